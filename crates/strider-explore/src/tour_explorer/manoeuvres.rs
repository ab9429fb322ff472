//! The sampling manoeuvre at a reached cost goal (decision 24).

use super::{Sampling, TourExplorer};
use crate::kernel::{Actuators, Body, Manoeuvre};
use strider_core::{GaitId, Point2};

impl TourExplorer {
    /// Decision 24: enforce `gait` and walk straight ahead (or the most open direction when
    /// the heading is blocked) for Δt_sample over cells where the centre may be.
    pub(super) fn start_sampling(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        t: f64,
        gait: GaitId,
    ) {
        let Some(p) = body.pose() else { return };
        let d = body.map().cell_size();
        let v = self.params.gaits[gait.0 as usize].v_max;
        let len = (v * self.params.dt_sample).max(2.0 * d);
        let start = Point2::new(p.position.x, p.position.y);
        let mut best: Option<(usize, Vec<Point2>)> = None;
        for k in [0.0f64, 1.0, -1.0, 2.0, -2.0, 3.0, -3.0, 4.0] {
            let yaw = p.yaw + k * std::f64::consts::FRAC_PI_4;
            let (dx, dy) = (yaw.cos(), yaw.sin());
            let mut pts = vec![start];
            let steps = (len / (0.5 * d)).ceil() as usize;
            for s in 1..=steps {
                let q = Point2::new(
                    start.x + dx * s as f64 * 0.5 * d,
                    start.y + dy * s as f64 * 0.5 * d,
                );
                if !self.centre_may_be(body, q) {
                    break;
                }
                pts.push(q);
            }
            let n = pts.len();
            if n > steps / 2 {
                best = Some((n, pts));
                break;
            }
            if best.as_ref().is_none_or(|(bn, _)| n > *bn) {
                best = Some((n, pts));
            }
        }
        let Some((_, pts)) = best else { return };
        robot.follow(&pts);
        self.sampling = Some(Sampling {
            gait,
            walk: Manoeuvre {
                until: t + self.params.dt_sample,
            },
        });
    }

    /// True where the robot's centre may be: a finite cell of the latest planning grid (known,
    /// admissible, the footprint inside the exploration bounds), or before the first view an
    /// admissible map cell.
    fn centre_may_be(&self, body: &Body, q: Point2) -> bool {
        let map = body.map();
        match (&self.view, map.cell_at(q.x, q.y)) {
            (Some(v), Some(c)) => v.grid.is_admissible(c),
            _ => map.is_admissible_at(q.x, q.y),
        }
    }
}
