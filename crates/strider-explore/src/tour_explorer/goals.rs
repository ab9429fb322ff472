//! The goal set the tour is planned over, and the goal the robot has committed to.

use super::TourExplorer;
use crate::kernel::Body;
use crate::planner::{GoalKey, TourGoal, farthest_point_subsample};
use strider_core::Cell;

impl TourExplorer {
    /// The goal set pursued by the strategy.
    pub(super) fn goals(&self, body: &Body) -> Vec<TourGoal> {
        let mut goals: Vec<TourGoal> = self
            .spatial
            .iter()
            .map(|s| TourGoal {
                key: GoalKey::Spatial(s.cell),
                sites: vec![s.cell],
            })
            .collect();
        if self.behaviour.cost_goals {
            let map = body.map();
            let r = 2.0 * map.params().r_robot / map.cell_size();
            for (g, goal) in &self.cost_goals {
                let fresh = unsampled_sites(&goal.sites, *g, &self.sampled, r);
                if fresh.is_empty() {
                    continue;
                }
                goals.push(TourGoal {
                    key: GoalKey::Cost {
                        gait: *g,
                        class: goal.class.map_or(u32::MAX, |c| c.0),
                    },
                    sites: farthest_point_subsample(&fresh, self.params.max_sites_per_goal),
                });
            }
        }
        goals
    }

    /// The index in `goals` of the goal being pursued, if it is still a goal: the same key, or
    /// (goal keys drift as the map and models change) a spatial goal within c_radius of the
    /// pursued site, or a cost goal of the same gait that still lists the pursued site.
    pub(super) fn committed_goal(&self, body: &Body, goals: &[TourGoal]) -> Option<usize> {
        let (key, site) = self.current?;
        if let Some(i) = goals.iter().position(|g| g.key == key) {
            return Some(i);
        }
        match key {
            GoalKey::Spatial(_) => {
                let map = body.map();
                let r = map.params().c_radius / map.cell_size();
                goals
                    .iter()
                    .enumerate()
                    .filter(|(_, g)| matches!(g.key, GoalKey::Spatial(_)))
                    .map(|(i, g)| (i, g.sites[0].dist_cells(site)))
                    .filter(|&(_, d)| d <= r)
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(i, _)| i)
            }
            GoalKey::Cost { gait, .. } => goals.iter().position(|g| {
                matches!(g.key, GoalKey::Cost { gait: h, .. } if h == gait)
                    && g.sites.contains(&site)
            }),
        }
    }
}

/// The sites of a cost goal of gait `gait` that are farther than `r` cells from every site and
/// position where that gait already sampled (`sampled`: (gait, cell) pairs). A robot stuck
/// beside a site measures the cells it stands on, not the site, which stays a site of the goal
/// and would draw the robot back for ever; other gaits still sample there.
fn unsampled_sites(sites: &[Cell], gait: u8, sampled: &[(u8, Cell)], r: f64) -> Vec<Cell> {
    sites
        .iter()
        .copied()
        .filter(|s| {
            sampled
                .iter()
                .all(|&(h, c)| h != gait || c.dist_cells(*s) > r)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sites_where_the_same_gait_sampled_are_not_pursued_again() {
        let sites = [Cell::new(0, 0), Cell::new(10, 0), Cell::new(20, 0)];
        // Gait 1 sampled at (10, 0) while standing stuck at (3, 0).
        let sampled = [(1, Cell::new(10, 0)), (1, Cell::new(3, 0))];
        assert_eq!(
            unsampled_sites(&sites, 1, &sampled, 4.0),
            vec![Cell::new(20, 0)]
        );
        // A site 3 cells from where the robot stood, with a radius just below 3: pursued.
        assert_eq!(
            unsampled_sites(&sites, 1, &sampled, 2.9),
            vec![Cell::new(0, 0), Cell::new(20, 0)]
        );
        // Another gait's samples do not count.
        assert_eq!(unsampled_sites(&sites, 0, &sampled, 4.0), sites.to_vec());
        assert_eq!(unsampled_sites(&sites, 1, &[], 4.0), sites.to_vec());
    }
}
