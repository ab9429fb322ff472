//! The ground truth a soak judges a mission against: where the robot's centre may be, and
//! where commanded waypoints, goals and tour sites may lie.
//!
//! The rule is the simulator's own (`strider_sim::motion`): the centre may enter a cell whose
//! elevation is within the robot's `max_step_m` of the ground it stands on, or a cell whose
//! terrain it is strong enough to push through (then it keeps standing on the ground it came
//! from); never a cell outside the world or over a hole. A cell is admissible when that rule
//! lets the robot reach it from the start; a pose is admissible when its cell is, and its cell
//! is within a step of the ground the body stands on (or pushable).
//!
//! Separately, and only counted, never a violation: whether the centre stands in a cell the
//! map's own rule on the true elevation calls inadmissible (an obstacle within the footprint
//! radius, [`strider_scenario::World::gt_admissible`]). The simulator lets the robot graze
//! obstacles; the planner's inflation is meant to keep it from doing so, and the count shows
//! how well it does.

use std::collections::VecDeque;

use strider_core::{Cell, CellRect, Point2, Point3, Pose2};
use strider_scenario::{Bounds, Scenario};
use strider_sim::Heightfield;

/// Grounds a pushable cell may carry before the fill treats it as carrying any (a cell
/// entered from that many different elevations is a pathological world; the fill then only
/// gets more permissive).
const MAX_GROUNDS: usize = 16;

/// Elevations this close are the same ground, m.
const SAME_GROUND_M: f64 = 1e-9;

/// The ground truth of one scenario's world for one robot.
pub struct Judge {
    hf: Heightfield,
    rect: CellRect,
    terrain: Vec<u8>,
    /// Terrain indices the robot can push through.
    pushable: [bool; 256],
    max_step: f64,
    /// Cells the simulator's rule lets the robot reach from the start.
    reachable: Vec<bool>,
    /// The map's admissibility on the true elevation (counted only, see the module docs).
    clear: Vec<bool>,
    world: Bounds,
    /// The exploration bounds grown by one map cell.
    goals: Bounds,
    gaits: usize,
}

impl Judge {
    /// The judge of `sc`'s world and robot.
    pub fn new(sc: &Scenario) -> anyhow::Result<Self> {
        let w = &sc.world;
        let hf = Heightfield::from_world(w)?;
        let mut pushable = [false; 256];
        for t in &w.terrains {
            pushable[t.index as usize] = t
                .push_force_n
                .is_some_and(|f| f <= sc.robot.max_push_force_n);
        }
        let m = sc.map.cell_size;
        let mut judge = Self {
            rect: w.rect,
            terrain: w.terrain.clone(),
            pushable,
            max_step: sc.robot.max_step_m,
            reachable: Vec::new(),
            clear: w.gt_admissible(sc.map.rho_obstacle, sc.map.r_robot),
            world: w.extent(),
            goals: Bounds {
                min: Point2::new(sc.bounds.min.x - m, sc.bounds.min.y - m),
                max: Point2::new(sc.bounds.max.x + m, sc.bounds.max.y + m),
            },
            gaits: sc.robot.gaits.len(),
            hf,
        };
        judge.reachable = judge.fill(sc.start.position());
        Ok(judge)
    }

    /// Cells reachable from `start` under the simulator's rule: 8-connected (a superset of
    /// the cells a straight move crosses), each entered within a step of the ground the robot
    /// stands on, or pushed through carrying that ground.
    fn fill(&self, start: Point2) -> Vec<bool> {
        let n = self.rect.len();
        let mut reached = vec![false; n];
        // Per pushable cell, the grounds it was entered with (`None`: any).
        let mut carried: Vec<Option<Vec<f64>>> = vec![Some(Vec::new()); n];
        let Some((k0, z0)) = self.cell_at(start) else {
            return reached;
        };
        reached[k0] = true;
        let mut queue = VecDeque::from([(k0, z0)]);
        while let Some((k, ground)) = queue.pop_front() {
            for c in self.rect.cell(k).neighbours8() {
                let (Some(j), Some(z)) = (self.rect.index(c), self.hf.cell_elevation(c)) else {
                    continue;
                };
                if (z - ground).abs() <= self.max_step {
                    if !reached[j] {
                        reached[j] = true;
                        queue.push_back((j, z));
                    }
                } else if self.pushable[self.terrain[j] as usize] {
                    let Some(grounds) = carried[j].as_mut() else {
                        continue;
                    };
                    if grounds.iter().any(|g| (g - ground).abs() <= SAME_GROUND_M) {
                        continue;
                    }
                    reached[j] = true;
                    if grounds.len() >= MAX_GROUNDS {
                        carried[j] = None;
                        for c in self.rect.cell(j).neighbours8() {
                            if let (Some(i), Some(z)) =
                                (self.rect.index(c), self.hf.cell_elevation(c))
                                && !reached[i]
                            {
                                reached[i] = true;
                                queue.push_back((i, z));
                            }
                        }
                    } else {
                        grounds.push(ground);
                        queue.push_back((j, ground));
                    }
                }
            }
        }
        reached
    }

    /// The layer index and elevation of the cell under `p`, if it is a world cell.
    fn cell_at(&self, p: Point2) -> Option<(usize, f64)> {
        let c = Cell::containing(p.x, p.y, self.hf.resolution())?;
        Some((self.rect.index(c)?, self.hf.cell_elevation(c)?))
    }

    /// `Err` with what is wrong when the true pose `p`, on ground of elevation `ground` (the
    /// body's), is not admissible.
    pub fn pose(&self, p: Pose2, ground: f64) -> Result<(), String> {
        let at = || format!("centre ({:.3}, {:.3}) m", p.x, p.y);
        if !(p.x.is_finite() && p.y.is_finite() && p.yaw.is_finite() && ground.is_finite()) {
            return Err(format!(
                "pose ({}, {}, {}) on ground {ground} is not finite",
                p.x, p.y, p.yaw
            ));
        }
        let Some((k, z)) = self.cell_at(p.position()) else {
            return Err(format!("{} is outside the world or over a hole", at()));
        };
        let c = self.rect.cell(k);
        if !self.reachable[k] {
            return Err(format!(
                "{} in cell ({}, {}) at z {z:.3} m, which the simulator's step rule never lets the robot reach from the start (inside a wall or obstacle)",
                at(),
                c.i,
                c.j
            ));
        }
        let step = (z - ground).abs();
        if step > self.max_step + SAME_GROUND_M && !self.pushable[self.terrain[k] as usize] {
            return Err(format!(
                "{} in cell ({}, {}) at z {z:.3} m, {step:.3} m from the ground the body stands on ({ground:.3} m; max step {} m)",
                at(),
                c.i,
                c.j,
                self.max_step
            ));
        }
        Ok(())
    }

    /// Whether the centre at `p` stands in a cell the map's rule on the true elevation calls
    /// admissible (counted, never a violation: see the module docs).
    pub fn clear_of_obstacles(&self, p: Point2) -> bool {
        self.cell_at(p).is_some_and(|(k, _)| self.clear[k])
    }

    /// `Err` when commanded waypoint `p` is not finite or outside the world.
    pub fn waypoint(&self, p: Point2) -> Result<(), String> {
        if p.is_finite() && self.world.contains(p) {
            return Ok(());
        }
        Err(format!(
            "waypoint ({}, {}) m commanded outside the world {}",
            p.x,
            p.y,
            show(&self.world)
        ))
    }

    /// `Err` when goal or tour site `p` of `what` is not finite or outside the exploration
    /// bounds (grown by one map cell).
    pub fn site(&self, what: &str, p: Point3) -> Result<(), String> {
        let q = Point2::new(p.x, p.y);
        if q.is_finite() && p.z.is_finite() && self.goals.contains(q) {
            return Ok(());
        }
        Err(format!(
            "{what} site ({}, {}, {}) m outside the exploration bounds {} (grown by one map cell)",
            p.x,
            p.y,
            p.z,
            show(&self.goals)
        ))
    }

    /// The robot's number of gaits.
    pub fn gaits(&self) -> usize {
        self.gaits
    }

    /// The world's extent.
    pub fn world(&self) -> Bounds {
        self.world
    }
}

fn show(b: &Bounds) -> String {
    format!(
        "x {:.2}..{:.2}, y {:.2}..{:.2}",
        b.min.x, b.max.x, b.min.y, b.max.y
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// courtyard-small with a 1 m wall two cells wide across its middle column of cells (x
    /// from 3.0 to 3.1 m), except for a gap at the bottom; returns the scenario and a point
    /// inside the wall.
    fn walled() -> (Scenario, Point2) {
        let mut sc = Scenario::from_name_or_file("courtyard-small", 1).unwrap();
        let w = &mut sc.world;
        let d = w.resolution;
        w.elevation.fill(0.0);
        let mut inside = None;
        for k in 0..w.rect.len() {
            let p = w.cell_center(k);
            if (3.0..3.1).contains(&p.x) && p.y > 1.0 {
                w.elevation[k] = 1.0;
                inside.get_or_insert(p);
            }
        }
        sc.start = Pose2::new(1.0 + d / 2.0, 2.0 + d / 2.0, 0.0);
        (sc, inside.unwrap())
    }

    #[test]
    fn a_pose_inside_a_wall_is_a_violation() {
        let (sc, wall) = walled();
        let j = Judge::new(&sc).unwrap();
        let ground = 0.0;
        assert_eq!(j.pose(sc.start, ground), Ok(()));
        // In the wall: not reachable from the start, and a 1 m step.
        let e = j.pose(Pose2::new(wall.x, wall.y, 0.0), ground).unwrap_err();
        assert!(e.contains("never lets the robot reach"), "{e}");
        // On top of the wall, standing on it: still not reachable.
        let e = j.pose(Pose2::new(wall.x, wall.y, 0.0), 1.0).unwrap_err();
        assert!(e.contains("inside a wall"), "{e}");
        // Beyond the wall, through the gap: reachable.
        assert_eq!(j.pose(Pose2::new(4.0, 0.5, 0.0), ground), Ok(()));
        // A reachable cell judged from ground the body cannot stand on.
        let e = j.pose(Pose2::new(4.0, 0.5, 0.0), 0.5).unwrap_err();
        assert!(e.contains("from the ground the body stands on"), "{e}");
        // Outside the world, and not a number.
        let e = j.pose(Pose2::new(-1.0, 0.5, 0.0), ground).unwrap_err();
        assert!(e.contains("outside the world"), "{e}");
        let e = j.pose(Pose2::new(f64::NAN, 0.5, 0.0), ground).unwrap_err();
        assert!(e.contains("not finite"), "{e}");
    }

    #[test]
    fn a_wall_without_a_gap_closes_off_the_far_side() {
        let (mut sc, _) = walled();
        let w = &mut sc.world;
        for k in 0..w.rect.len() {
            let p = w.cell_center(k);
            if (3.0..3.1).contains(&p.x) {
                w.elevation[k] = 1.0;
            }
        }
        let j = Judge::new(&sc).unwrap();
        let e = j.pose(Pose2::new(4.0, 0.5, 0.0), 0.0).unwrap_err();
        assert!(e.contains("never lets the robot reach"), "{e}");
        // Unless the wall is a curtain the robot can push through.
        let curtain = 200;
        for k in 0..sc.world.rect.len() {
            if sc.world.elevation[k] == 1.0 {
                sc.world.terrain[k] = curtain;
            }
        }
        let mut t = sc.world.terrains[0].clone();
        t.index = curtain;
        t.push_force_n = Some(0.0);
        sc.world.terrains.push(t);
        let j = Judge::new(&sc).unwrap();
        assert_eq!(j.pose(Pose2::new(4.0, 0.5, 0.0), 0.0), Ok(()));
        let inside = Pose2::new(3.05, 0.5, 0.0);
        assert_eq!(j.pose(inside, 0.0), Ok(()));
    }

    #[test]
    fn waypoints_and_sites_must_lie_in_the_world_and_the_bounds() {
        let (sc, wall) = walled();
        let j = Judge::new(&sc).unwrap();
        assert!(j.waypoint(wall).is_ok());
        assert!(j.waypoint(Point2::new(100.0, 0.0)).is_err());
        assert!(j.waypoint(Point2::new(f64::NAN, 0.0)).is_err());
        let b = sc.bounds;
        let mid = Point3::new((b.min.x + b.max.x) / 2.0, (b.min.y + b.max.y) / 2.0, 0.0);
        assert!(j.site("tour", mid).is_ok());
        let far = Point3::new(b.max.x + 1.0, mid.y, 0.0);
        assert!(j.site("tour", far).unwrap_err().contains("tour site"));
        assert!(j.site("goal", Point3::new(mid.x, mid.y, f64::NAN)).is_err());
    }
}
