//! The scenario builder: what every built-in world shares, so that a built-in only states what
//! is special about it.
//!
//! A built-in names itself, its floor ([`Frame`]), its robot, map and simulator parameters, its
//! strategy sections and its [`TerrainTable`], then hands [`ScenarioBuilder::generate`] one
//! attempt at a layout: paint a [`Canvas`], finish it into a world, place start and tours and
//! check the layout's promises. The builder repeats attempts (each drawing on from the same
//! random stream) until one succeeds, and assembles the [`Scenario`]: bounds inset by the
//! robot's radius, the start facing +x, the default elevation encoding.

use rand::{SeedableRng, rngs::ChaCha8Rng};
use strider_core::{Point2, Pose2};
use strider_map::MapParams;

use super::canvas::Canvas;
use super::strategy;
use super::terrains::TerrainTable;
use crate::error::ScenarioError;
use crate::model::{Bounds, RobotProfile, Scenario, SimParams, Tour, World};

/// Layouts a generator may draw before giving up.
const MAX_ATTEMPTS: usize = 200;

/// A built-in world's floor: `[0, width] × [0, height]` metres at cell size `res`, painted with
/// terrain `base` before anything else.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    width: f64,
    height: f64,
    res: f64,
    base: u8,
}

impl Frame {
    /// `width × height` metres at cell size `res`, all terrain `base`.
    pub const fn new(width: f64, height: f64, res: f64, base: u8) -> Self {
        Self {
            width,
            height,
            res,
            base,
        }
    }
}

/// What one successful attempt produced: the world, the start position and the tours.
pub(crate) struct Layout {
    pub world: World,
    pub start: Point2,
    pub tours: Vec<Tour>,
}

/// A benchmark tour.
pub(crate) fn tour(name: &str, waypoints: Vec<Point2>, closed: bool) -> Tour {
    Tour {
        name: name.into(),
        waypoints,
        closed,
    }
}

/// One attempt at a layout: the random stream and what the attempt may read of the scenario.
pub(crate) struct Attempt<'a> {
    /// The world's random stream (shared by all attempts).
    pub rng: &'a mut ChaCha8Rng,
    /// The world seed.
    pub seed: u64,
    /// The scenario's map parameters.
    pub map: &'a MapParams,
    /// The scenario's exploration bounds.
    pub bounds: Bounds,
    frame: Frame,
    terrains: &'a TerrainTable,
}

impl Attempt<'_> {
    /// A fresh canvas of the floor, all base terrain.
    pub fn canvas(&self) -> Canvas {
        let f = self.frame;
        Canvas::new(f.width, f.height, f.res, f.base)
    }

    /// Colours and textures `canvas` into the world (draws from the stream).
    pub fn finish(&mut self, canvas: &Canvas) -> World {
        canvas.finish(self.terrains, self.rng)
    }

    /// Ground-truth admissibility of `world` for the scenario's robot and map parameters.
    pub fn admissible(&self, world: &World) -> Vec<bool> {
        world.gt_admissible(self.map.rho_obstacle, self.map.r_robot)
    }
}

/// A built-in scenario under construction.
pub(crate) struct ScenarioBuilder {
    name: String,
    description: String,
    seed: u64,
    rng: ChaCha8Rng,
    frame: Frame,
    robot: RobotProfile,
    map: MapParams,
    sim: SimParams,
    strategy: toml::Table,
    terrains: TerrainTable,
    time_limit_s: f64,
}

impl ScenarioBuilder {
    /// Scenario `name` for world seed `seed` on `frame` with `robot`. Until set otherwise: map
    /// parameters at their defaults but for the cell size (the frame's) and the robot radius
    /// (the robot's footprint), default simulator parameters, no strategy sections, an hour of
    /// mission time.
    pub fn new(
        name: &str,
        description: &str,
        seed: u64,
        frame: Frame,
        robot: RobotProfile,
    ) -> Self {
        let map = MapParams {
            cell_size: frame.res,
            r_robot: robot.footprint_radius,
            ..MapParams::default()
        };
        Self {
            name: name.into(),
            description: description.into(),
            seed,
            rng: ChaCha8Rng::seed_from_u64(seed),
            frame,
            robot,
            map,
            sim: SimParams::default(),
            strategy: toml::Table::new(),
            terrains: TerrainTable::new(),
            time_limit_s: 3600.0,
        }
    }

    /// The robot.
    pub fn robot(&self) -> &RobotProfile {
        &self.robot
    }

    /// The world's random stream, for draws made before the first attempt.
    pub fn rng(&mut self) -> &mut ChaCha8Rng {
        &mut self.rng
    }

    /// Map parameters: `f` gets the defaults described at [`Self::new`].
    pub fn map(mut self, f: impl FnOnce(MapParams) -> MapParams) -> Self {
        self.map = f(self.map);
        self
    }

    /// Simulator parameters.
    pub fn sim(mut self, sim: SimParams) -> Self {
        self.sim = sim;
        self
    }

    /// The parameter sections: `params` for each strategy (or command) in `names`.
    pub fn strategy(mut self, names: &[&str], params: toml::Table) -> Self {
        self.strategy = strategy::sections(names, &params);
        self
    }

    /// The terrain table.
    pub fn terrains(mut self, terrains: TerrainTable) -> Self {
        self.terrains = terrains;
        self
    }

    /// Mission time limit, simulated seconds.
    pub fn time_limit(mut self, seconds: f64) -> Self {
        self.time_limit_s = seconds;
        self
    }

    /// Draws layouts with `attempt` until one succeeds (at most [`MAX_ATTEMPTS`]) and builds
    /// the scenario around it; `failure` says what no attempt found.
    pub fn generate(
        mut self,
        failure: &str,
        mut attempt: impl FnMut(&mut Attempt<'_>) -> Option<Layout>,
    ) -> Result<Scenario, ScenarioError> {
        let r = self.map.r_robot;
        let bounds = Bounds {
            min: Point2::new(r, r),
            max: Point2::new(self.frame.width - r, self.frame.height - r),
        };
        for _ in 0..MAX_ATTEMPTS {
            let mut a = Attempt {
                rng: &mut self.rng,
                seed: self.seed,
                map: &self.map,
                bounds,
                frame: self.frame,
                terrains: &self.terrains,
            };
            if let Some(layout) = attempt(&mut a) {
                return Ok(self.scenario(layout, bounds));
            }
        }
        Err(ScenarioError::Generate {
            name: self.name,
            seed: self.seed,
            message: failure.into(),
        })
    }

    fn scenario(self, layout: Layout, bounds: Bounds) -> Scenario {
        Scenario {
            name: self.name,
            description: self.description,
            world_seed: self.seed,
            world: layout.world,
            robot: self.robot,
            map: self.map,
            sim: self.sim,
            strategy: self.strategy,
            start: Pose2::new(layout.start.x, layout.start.y, 0.0),
            bounds,
            tours: layout.tours,
            time_limit_s: self.time_limit_s,
            elevation_encoding: Default::default(),
        }
    }
}
