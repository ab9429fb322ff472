//! The transform tree of a log (/tf and /tf_static) and the rigid transforms it holds.

use crate::ros2::{Quaternion, Transform};
use std::collections::HashMap;

/// A rigid transform p' = q·p + t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Iso {
    pub(super) q: Quaternion,
    pub(super) t: [f64; 3],
}

impl Iso {
    pub(super) const IDENTITY: Iso = Iso {
        q: Quaternion::IDENTITY,
        t: [0.0; 3],
    };

    /// The transform of a message; `None` when it is not finite or its rotation is zero.
    pub(super) fn from_msg(tr: &Transform) -> Option<Iso> {
        let v = tr.translation;
        (v.x.is_finite() && v.y.is_finite() && v.z.is_finite())
            .then_some(())
            .and(tr.rotation.normalized())
            .map(|q| Iso {
                q,
                t: [v.x, v.y, v.z],
            })
    }

    /// `self ∘ o`: first `o`, then `self`.
    pub(super) fn compose(&self, o: &Iso) -> Iso {
        let r = self.q.rotate(o.t);
        Iso {
            q: self.q.product(o.q),
            t: [r[0] + self.t[0], r[1] + self.t[1], r[2] + self.t[2]],
        }
    }

    /// `p` transformed.
    pub(super) fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let r = self.q.rotate(p);
        [r[0] + self.t[0], r[1] + self.t[1], r[2] + self.t[2]]
    }

    /// Interpolation at fraction `a` from `self` to `o` (translation linear, rotation nlerp
    /// along the shorter arc: the stamps of a tf stream are close together).
    fn lerp(&self, o: &Iso, a: f64) -> Iso {
        let mut q2 = o.q;
        let dot = self.q.x * q2.x + self.q.y * q2.y + self.q.z * q2.z + self.q.w * q2.w;
        if dot < 0.0 {
            q2 = Quaternion {
                x: -q2.x,
                y: -q2.y,
                z: -q2.z,
                w: -q2.w,
            };
        }
        let l = |x: f64, y: f64| x + (y - x) * a;
        let q = Quaternion {
            x: l(self.q.x, q2.x),
            y: l(self.q.y, q2.y),
            z: l(self.q.z, q2.z),
            w: l(self.q.w, q2.w),
        }
        .normalized()
        .unwrap_or(self.q);
        Iso {
            q,
            t: [
                l(self.t[0], o.t[0]),
                l(self.t[1], o.t[1]),
                l(self.t[2], o.t[2]),
            ],
        }
    }
}

/// The transform tree over the whole log.
#[derive(Default)]
pub(super) struct TfBuffer {
    /// child → (stamp ns, parent, child-in-parent), sorted by stamp.
    dynamic: HashMap<String, Vec<(i64, String, Iso)>>,
    /// child → (parent, child-in-parent).
    statics: HashMap<String, (String, Iso)>,
    /// How far outside its stamps a dynamic transform is used, ns.
    tolerance_ns: i64,
}

impl TfBuffer {
    /// An empty tree whose dynamic transforms are used up to `tolerance_ns` outside their
    /// stamps.
    pub(super) fn new(tolerance_ns: i64) -> Self {
        Self {
            tolerance_ns,
            ..Self::default()
        }
    }

    /// Adds the static transform of `child` in `parent`.
    pub(super) fn add_static(&mut self, child: String, parent: String, iso: Iso) {
        self.statics.insert(child, (parent, iso));
    }

    /// Adds the transform of `child` in `parent` at `ns`.
    pub(super) fn add(&mut self, child: String, ns: i64, parent: String, iso: Iso) {
        self.dynamic
            .entry(child)
            .or_default()
            .push((ns, parent, iso));
    }

    /// Orders each frame's transforms by stamp (ties in the order added), once all are in.
    pub(super) fn sort(&mut self) {
        for v in self.dynamic.values_mut() {
            v.sort_by_key(|e| e.0);
        }
    }

    /// The parent of `child` at `t` and `child` in it (interpolated between stamps).
    fn edge(&self, child: &str, t: i64) -> Result<(String, Iso), String> {
        if let Some((p, iso)) = self.statics.get(child) {
            return Ok((p.clone(), *iso));
        }
        let Some(v) = self.dynamic.get(child).filter(|v| !v.is_empty()) else {
            return Err(format!("no transform of frame {child:?}"));
        };
        let k = v.partition_point(|e| e.0 < t);
        if k < v.len() && v[k].0 == t {
            return Ok((v[k].1.clone(), v[k].2));
        }
        let secs = |ns: i64| ns as f64 * 1e-9;
        if k == 0 {
            return if v[0].0 - t <= self.tolerance_ns {
                Ok((v[0].1.clone(), v[0].2))
            } else {
                Err(format!(
                    "frame {child:?} has no transform before {:.3} s (first at {:.3} s)",
                    secs(t),
                    secs(v[0].0)
                ))
            };
        }
        if k == v.len() {
            let last = &v[k - 1];
            return if t - last.0 <= self.tolerance_ns {
                Ok((last.1.clone(), last.2))
            } else {
                Err(format!(
                    "frame {child:?} has no transform after {:.3} s (last at {:.3} s)",
                    secs(t),
                    secs(last.0)
                ))
            };
        }
        let (a, b) = (&v[k - 1], &v[k]);
        if a.1 != b.1 {
            // The parent changed between the two stamps: no interpolation across trees.
            return Ok((a.1.clone(), a.2));
        }
        let f = (t - a.0) as f64 / (b.0 - a.0) as f64;
        Ok((a.1.clone(), a.2.lerp(&b.2, f)))
    }

    /// `frame` expressed in `world` at `t`: the chain of parents up to `world`.
    pub(super) fn lookup(&self, frame: &str, world: &str, t: i64) -> Result<Iso, String> {
        let mut total = Iso::IDENTITY;
        let mut f = frame.to_string();
        let mut first = true;
        for _ in 0..64 {
            if f == world {
                return Ok(total);
            }
            let (parent, e) = self.edge(&f, t)?;
            total = if first { e } else { e.compose(&total) };
            first = false;
            f = parent;
        }
        Err(format!(
            "frame {frame:?}: no chain to {world:?} within 64 transforms"
        ))
    }
}
