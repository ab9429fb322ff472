//! The time-ordered track of recent poses: path length, gait constancy and the nearest pose over
//! a window, each in O(log n).

use strider_core::geom::Point3;
use strider_core::msg::{GaitId, PoseStamped};

use super::common::SkipCounts;
use super::ring::Ring;

/// One pose as kept by the pose tracks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct TrackPose {
    pub(super) stamp: f64,
    pub(super) position: Point3,
    pub(super) gait: GaitId,
    /// Horizontal path length from the track's first pose ever to this one, m: the length over
    /// any interval is a difference of two interpolated values instead of a sum over the window.
    arc: f64,
    /// Count of gait changes before this pose: the gait is constant between two poses exactly
    /// when their counts are equal.
    run: u64,
}

fn pose_is_finite(p: &PoseStamped) -> bool {
    p.stamp.is_finite()
        && p.position.x.is_finite()
        && p.position.y.is_finite()
        && p.position.z.is_finite()
}

/// A fixed-capacity, time-ordered track of recent poses.
#[derive(Clone, Debug)]
pub(super) struct PoseTrack {
    pub(super) ring: Ring<TrackPose>,
    /// Stamp tolerance, seconds (a quarter of the nominal sample period).
    pub(super) tol: f64,
}

impl PoseTrack {
    pub(super) fn new(capacity: usize, tol: f64) -> Self {
        Self {
            ring: Ring::new(capacity),
            tol,
        }
    }

    /// Accepts a pose (after validation); updates `skips`. Returns false when skipped.
    pub(super) fn push(
        &mut self,
        pose: &PoseStamped,
        gait: GaitId,
        skips: &mut SkipCounts,
    ) -> bool {
        if !pose_is_finite(pose) {
            skips.non_finite += 1;
            return false;
        }
        if let Some(last) = self.ring.back()
            && pose.stamp <= last.stamp
        {
            skips.out_of_order += 1;
            return false;
        }
        let (arc, run) = match self.ring.back() {
            Some(last) => (
                last.arc + last.position.xy().dist(pose.position.xy()),
                last.run + u64::from(last.gait != gait),
            ),
            None => (0.0, 0),
        };
        if self.ring.push_back(TrackPose {
            stamp: pose.stamp,
            position: pose.position,
            gait,
            arc,
            run,
        }) {
            skips.overrun += 1;
        }
        true
    }

    /// Drops old poses, keeping the newest pose at or before `t` (so the track still covers `t`).
    pub(super) fn retain_covering(&mut self, t: f64) {
        while self.ring.len() >= 2 && self.ring.get(1).is_some_and(|p| p.stamp <= t) {
            self.ring.pop_front();
        }
    }

    /// True when the track covers `[t0, t1]` up to the tolerance.
    pub(super) fn covers(&self, t0: f64, t1: f64) -> bool {
        match (self.ring.front(), self.ring.back()) {
            (Some(a), Some(b)) => a.stamp <= t0 + self.tol && b.stamp >= t1 - self.tol,
            _ => false,
        }
    }

    /// Horizontal path length over `[t0, t1]` along the poses, interpolating linearly inside the
    /// end segments. `None` when the track does not cover the interval.
    pub(super) fn path_length(&self, t0: f64, t1: f64) -> Option<f64> {
        if t1 < t0 || !self.covers(t0, t1) {
            return None;
        }
        Some((self.arc_at(t1) - self.arc_at(t0)).max(0.0))
    }

    /// The cumulative path length at time `t`, interpolated linearly inside its segment and
    /// clamped to the track's ends. The track must not be empty.
    pub(super) fn arc_at(&self, t: f64) -> f64 {
        let n = self.ring.len();
        let k = self.ring.partition_point(|p| p.stamp <= t);
        match (
            k.checked_sub(1).and_then(|i| self.ring.get(i)),
            self.ring.get(k),
        ) {
            (Some(q), Some(p)) => {
                let frac = ((t - q.stamp) / (p.stamp - q.stamp)).clamp(0.0, 1.0);
                q.arc + (p.arc - q.arc) * frac
            }
            (Some(q), None) => q.arc,
            (None, Some(p)) => p.arc,
            (None, None) => {
                debug_assert_eq!(n, 0);
                0.0
            }
        }
    }

    /// The gait when every pose bracketing `[t0, t1]` has the same one, else `None`. A pose
    /// matters when it lies inside the interval or is the last one before `t0` or the first one
    /// after `t1`.
    pub(super) fn constant_gait(&self, t0: f64, t1: f64) -> Option<GaitId> {
        let n = self.ring.len();
        if n == 0 {
            return None;
        }
        // First relevant: the last pose at or before t0 (poses before it are followed by one
        // at or before t0); last relevant: the first pose at or after t1.
        let first = self
            .ring
            .partition_point(|p| p.stamp <= t0)
            .saturating_sub(1);
        let last = self.ring.partition_point(|p| p.stamp < t1).min(n - 1);
        if first > last {
            return None;
        }
        let (a, b) = (self.ring.get(first)?, self.ring.get(last)?);
        (a.run == b.run).then_some(a.gait)
    }

    /// The pose whose stamp is nearest `t` (the earlier one on a tie); `None` when that pose is
    /// farther than one tolerance outside the track.
    pub(super) fn nearest(&self, t: f64) -> Option<TrackPose> {
        if !self.covers(t, t) {
            return None;
        }
        // Stamps increase, so the nearest pose is the last one before t or the first at/after.
        let k = self.ring.partition_point(|p| p.stamp < t);
        match (
            k.checked_sub(1).and_then(|i| self.ring.get(i)),
            self.ring.get(k),
        ) {
            (Some(a), Some(b)) => Some(if t - a.stamp <= b.stamp - t { a } else { b }),
            (a, b) => a.or(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The window queries by definition, O(n) scans over every pose (the reference the O(log n)
    /// queries are checked against).
    fn brute_path_length(t: &PoseTrack, t0: f64, t1: f64) -> f64 {
        let v: Vec<TrackPose> = t.ring.iter().collect();
        v.windows(2)
            .map(|w| {
                let (q, p) = (w[0], w[1]);
                let (a, b) = (t0.max(q.stamp), t1.min(p.stamp));
                if b > a {
                    q.position.xy().dist(p.position.xy()) * ((b - a) / (p.stamp - q.stamp)).min(1.0)
                } else {
                    0.0
                }
            })
            .sum()
    }

    fn brute_constant_gait(t: &PoseTrack, t0: f64, t1: f64) -> Option<GaitId> {
        let v: Vec<TrackPose> = t.ring.iter().collect();
        let mut gait = None;
        for (i, p) in v.iter().enumerate() {
            let next = v.get(i + 1).map_or(f64::INFINITY, |q| q.stamp);
            let prev = if i == 0 {
                f64::NEG_INFINITY
            } else {
                v[i - 1].stamp
            };
            if (p.stamp >= t0 || next > t0) && (p.stamp <= t1 || prev < t1) {
                match gait {
                    None => gait = Some(p.gait),
                    Some(g) if g != p.gait => return None,
                    Some(_) => {}
                }
            }
        }
        gait
    }

    fn brute_nearest(t: &PoseTrack, at: f64) -> Option<f64> {
        let mut best: Option<(f64, f64)> = None;
        for p in t.ring.iter() {
            let d = (p.stamp - at).abs();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, p.stamp));
            }
        }
        best.map(|(_, s)| s)
    }

    proptest::proptest! {
        /// Cumulative arc length, gait-run counts and binary search give what the window scans
        /// give, for wrapped rings, gait changes and intervals reaching past the track's ends.
        #[test]
        fn window_queries_match_scans(
            steps in proptest::collection::vec((0.01f64..0.2, -0.3f64..0.3, -0.3f64..0.3, 0u8..3), 2..60),
            cap in 3usize..40,
            q in proptest::collection::vec((-0.5f64..1.5, 0.0f64..1.0), 1..12),
        ) {
            let mut t = PoseTrack::new(cap, 1e-3);
            let mut sk = SkipCounts::default();
            let (mut stamp, mut x, mut y) = (0.0, 0.0, 0.0);
            for &(dt, dx, dy, g) in &steps {
                stamp += dt;
                x += dx;
                y += dy;
                let p = PoseStamped {
                    stamp,
                    position: Point3::new(x, y, 0.0),
                    ..Default::default()
                };
                t.push(&p, GaitId(g / 2), &mut sk);
            }
            let (lo, hi) = (t.ring.front().unwrap().stamp, t.ring.back().unwrap().stamp);
            for &(a, w) in &q {
                let t0 = lo + a * (hi - lo);
                let t1 = t0 + w * (hi - lo);
                if let Some(len) = t.path_length(t0, t1) {
                    proptest::prop_assert!((len - brute_path_length(&t, t0, t1)).abs() < 1e-9);
                }
                proptest::prop_assert_eq!(t.constant_gait(t0, t1), brute_constant_gait(&t, t0, t1));
                if let Some(p) = t.nearest(t0) {
                    proptest::prop_assert_eq!(Some(p.stamp), brute_nearest(&t, t0));
                }
            }
        }
    }

    #[test]
    fn path_length_interpolates_end_segments() {
        let mut t = PoseTrack::new(8, 0.01);
        let mut sk = SkipCounts::default();
        for k in 0..4 {
            let p = PoseStamped {
                stamp: k as f64,
                position: Point3::new(k as f64, 0.0, 0.0),
                ..Default::default()
            };
            assert!(t.push(&p, GaitId(0), &mut sk));
        }
        assert!((t.path_length(0.5, 2.25).unwrap() - 1.75).abs() < 1e-12);
        assert!(t.path_length(-1.0, 2.0).is_none());
    }
}
