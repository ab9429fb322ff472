//! The transform tree of a log (/tf and /tf_static) and the rigid transforms it holds.

use crate::config::ReplayConfig;
use crate::ros2::{Quaternion, Transform, seconds_to_nanos};
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

/// The transform tree over the whole log, and what its errors say about it.
#[derive(Default)]
pub(super) struct TfBuffer {
    /// child → (stamp ns, parent, child-in-parent), sorted by stamp.
    dynamic: HashMap<String, Vec<(i64, String, Iso)>>,
    /// child → (parent, child-in-parent).
    statics: HashMap<String, (String, Iso)>,
    /// How far outside its stamps a dynamic transform is used, ns.
    tolerance_ns: i64,
    /// The frame transforms are looked up in, and whether it was left at its default.
    world: String,
    world_defaulted: bool,
    /// The topics of the transforms and the messages seen on the static one.
    topic: String,
    static_topic: String,
    static_messages: usize,
}

/// Most transforms (parent → child) an error lists.
const MAX_LISTED: usize = 24;

impl TfBuffer {
    /// An empty tree for the `world_frame`, topics and tolerance of `cfg`.
    pub(super) fn new(cfg: &ReplayConfig) -> Self {
        Self {
            tolerance_ns: seconds_to_nanos(cfg.tf.tolerance_s),
            world: cfg.world_frame.clone(),
            world_defaulted: cfg.world_frame_defaulted,
            topic: cfg.tf.topic.clone(),
            static_topic: cfg.tf.static_topic.clone(),
            ..Self::default()
        }
    }

    /// Counts a message on the static topic (whether or not it holds transforms).
    pub(super) fn note_static_message(&mut self) {
        self.static_messages += 1;
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

    /// The parent of `child` at `t` and `child` in it (interpolated between stamps); `None`
    /// when `child` has no parent at all.
    fn edge(&self, child: &str, t: i64) -> Result<Option<(String, Iso)>, String> {
        if let Some((p, iso)) = self.statics.get(child) {
            return Ok(Some((p.clone(), *iso)));
        }
        let Some(v) = self.dynamic.get(child).filter(|v| !v.is_empty()) else {
            return Ok(None);
        };
        let k = v.partition_point(|e| e.0 < t);
        if k < v.len() && v[k].0 == t {
            return Ok(Some((v[k].1.clone(), v[k].2)));
        }
        let tol = secs(self.tolerance_ns);
        if k == 0 {
            return if v[0].0 - t <= self.tolerance_ns {
                Ok(Some((v[0].1.clone(), v[0].2)))
            } else {
                Err(format!(
                    "frame {child:?} has no transform before {:.3} s (first at {:.3} s; \
                     [tf] tolerance_s = {tol})",
                    secs(t),
                    secs(v[0].0)
                ))
            };
        }
        if k == v.len() {
            let last = &v[k - 1];
            return if t - last.0 <= self.tolerance_ns {
                Ok(Some((last.1.clone(), last.2)))
            } else {
                Err(format!(
                    "frame {child:?} has no transform after {:.3} s (last at {:.3} s; \
                     [tf] tolerance_s = {tol})",
                    secs(t),
                    secs(last.0)
                ))
            };
        }
        let (a, b) = (&v[k - 1], &v[k]);
        if a.1 != b.1 {
            // The parent changed between the two stamps: no interpolation across trees.
            return Ok(Some((a.1.clone(), a.2)));
        }
        let f = (t - a.0) as f64 / (b.0 - a.0) as f64;
        Ok(Some((a.1.clone(), a.2.lerp(&b.2, f))))
    }

    /// `frame` expressed in the world frame at `t`: the chain of parents up to it. The error
    /// names both frames (and whether the world frame is the default), where the chain broke,
    /// the transforms the file has, and a missing or empty static topic.
    pub(super) fn lookup(&self, frame: &str, t: i64) -> Result<Iso, String> {
        let mut total = Iso::IDENTITY;
        let mut chain = vec![frame.to_string()];
        for _ in 0..64 {
            let f = chain.last().map_or(frame, String::as_str);
            if f == self.world {
                return Ok(total);
            }
            let (cause, root) = match self.edge(f, t) {
                Ok(Some((parent, e))) => {
                    total = if chain.len() == 1 {
                        e
                    } else {
                        e.compose(&total)
                    };
                    chain.push(parent);
                    continue;
                }
                Ok(None) if chain.len() == 1 => (
                    format!("frame {f:?} has no parent on {}", self.topics()),
                    Some(f),
                ),
                Ok(None) => (
                    format!(
                        "its chain {} ends at {f:?}, which has no parent",
                        chain.join(" → ")
                    ),
                    Some(f),
                ),
                Err(e) => (e, None),
            };
            return Err(self.explain(frame, t, &cause, root));
        }
        let shown: Vec<&str> = chain.iter().take(8).map(String::as_str).collect();
        let cause = format!(
            "its chain {} … does not reach it within 64 transforms",
            shown.join(" → ")
        );
        Err(self.explain(frame, t, &cause, None))
    }

    /// The transform topics, for messages.
    fn topics(&self) -> String {
        if self.static_topic.is_empty() {
            self.topic.clone()
        } else {
            format!("{} or {}", self.topic, self.static_topic)
        }
    }

    /// The error of looking up `frame` at `t`, for `cause`; `root` is the frame without a parent
    /// where the chain ended, if it did.
    fn explain(&self, frame: &str, t: i64, cause: &str, root: Option<&str>) -> String {
        let world = &self.world;
        let mut s = format!("no transform from frame {frame:?} to the world frame {world:?}");
        if self.world_defaulted {
            s += &format!(" (world_frame is not set; {world:?} is its default)");
        }
        s += &format!(" at {:.3} s: {cause}", secs(t));
        let edges = self.edges();
        let in_file = edges.iter().any(|(p, c, _)| p == world || c == world);
        if let Some(root) = root.filter(|r| !in_file && edges.iter().any(|(p, _, _)| p == r)) {
            s += &format!(
                "; the world frame {world:?} is in no transform of the file: set world_frame = \
                 {root:?} (the root of the tree) or the log's fixed frame"
            );
        }
        s += "; transforms in the file: ";
        if edges.is_empty() {
            s += "none";
        }
        for (k, (p, c, topic)) in edges.iter().enumerate() {
            if k == MAX_LISTED {
                s += &format!(", … ({} more)", edges.len() - MAX_LISTED);
                break;
            }
            s += &format!("{}{p} → {c} ({topic})", if k > 0 { ", " } else { "" });
        }
        if self.statics.is_empty() {
            s += &match (self.static_topic.as_str(), self.static_messages) {
                ("", _) => "; no static transforms ([tf] static_topic is empty)".to_string(),
                (topic, 0) => format!("; {topic} is missing (no message in the file)"),
                (topic, n) => format!("; {topic} is empty ({n} messages, no transform)"),
            };
        }
        s
    }

    /// Every (parent, child, topic) of the tree, sorted; a dynamic frame whose parent changed
    /// is listed once per parent.
    fn edges(&self) -> Vec<(String, String, String)> {
        let mut edges: Vec<(String, String, String)> = self
            .statics
            .iter()
            .map(|(c, (p, _))| (p.clone(), c.clone(), self.static_topic.clone()))
            .collect();
        for (c, v) in &self.dynamic {
            let mut parents: Vec<&String> = v.iter().map(|e| &e.1).collect();
            parents.sort();
            parents.dedup();
            for p in parents {
                edges.push((p.clone(), c.clone(), self.topic.clone()));
            }
        }
        edges.sort();
        edges
    }
}

/// Nanoseconds to seconds.
fn secs(ns: i64) -> f64 {
    ns as f64 * 1e-9
}
