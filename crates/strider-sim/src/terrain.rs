//! The terrain table resolved for fast lookup: per terrain index and gait, how the robot fares.

use strider_scenario::{GaitResponse, RobotProfile, World};

/// Terrain properties resolved per layer index (0–255) and gait index.
///
/// A terrain index without an entry in the world's table, and a gait a terrain does not list,
/// get [`GaitResponse::default`] (full speed, no roll, no power), no vibration and rigidity.
#[derive(Clone, Debug)]
pub struct TerrainTable {
    gaits: usize,
    /// `[terrain * gaits + gait]`.
    responses: Vec<GaitResponse>,
    vibration: Vec<f64>,
    push_force: Vec<Option<f64>>,
}

impl TerrainTable {
    /// Resolves `world`'s terrain table for `robot`'s gaits (by gait name).
    pub fn new(world: &World, robot: &RobotProfile) -> Self {
        let gaits = robot.gaits.len();
        let mut responses = vec![GaitResponse::default(); 256 * gaits];
        let mut vibration = vec![0.0; 256];
        let mut push_force = vec![None; 256];
        for t in &world.terrains {
            let k = t.index as usize;
            vibration[k] = t.vibration;
            push_force[k] = t.push_force_n;
            for (g, spec) in robot.gaits.iter().enumerate() {
                if let Some(r) = t.gaits.get(&spec.name) {
                    responses[k * gaits + g] = r.clone();
                }
            }
        }
        Self {
            gaits,
            responses,
            vibration,
            push_force,
        }
    }

    /// How gait `gait` fares on terrain `terrain`.
    #[inline]
    pub fn response(&self, terrain: u8, gait: usize) -> &GaitResponse {
        &self.responses[terrain as usize * self.gaits + gait.min(self.gaits.saturating_sub(1))]
    }

    /// Vertical-acceleration RMS on terrain `terrain`, m/s².
    #[inline]
    pub fn vibration(&self, terrain: u8) -> f64 {
        self.vibration[terrain as usize]
    }

    /// Force to push through terrain `terrain`, newtons; `None` when rigid.
    #[inline]
    pub fn push_force(&self, terrain: u8) -> Option<f64> {
        self.push_force[terrain as usize]
    }
}
