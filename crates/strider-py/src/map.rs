//! `strider.ElevationMap`: the colored 2.5D elevation map on its own — fuse scans, read layers.

use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strider_core::{ColoredPoint, Point3, PointCloud};
use strider_explore::kernel::map_layers;
use strider_map::{ElevationMap as RustMap, MapParams};

use crate::errors::{msg, to_py};
use crate::layers::to_dict;

/// The colored 2.5D elevation map (Prágr22's map: fusion, passability).
///
/// `ElevationMap(params_json=None, scenario=None, world_seed=1)`: the map parameters of a
/// scenario, or the defaults, updated by `params` (a JSON object of map parameter names, e.g.
/// `{"cell_size": 0.1}`; unknown names are an error).
#[pyclass(module = "strider", unsendable, subclass)]
pub struct ElevationMap {
    pub(crate) map: RustMap,
    scans: u64,
}

fn pose_parts(pose: &[f64]) -> PyResult<(Point3, f64)> {
    let (x, y, z, yaw) = match *pose {
        [x, y, z] => (x, y, z, 0.0),
        [x, y, z, yaw] => (x, y, z, yaw),
        _ => {
            return Err(msg(format!(
                "pose: (x, y, z) or (x, y, z, yaw), got {} values",
                pose.len()
            )));
        }
    };
    if ![x, y, z, yaw].iter().all(|v| v.is_finite()) {
        return Err(msg("pose: every value must be finite"));
    }
    Ok((Point3::new(x, y, z), yaw))
}

#[pymethods]
impl ElevationMap {
    #[new]
    #[pyo3(signature = (params_json = None, scenario = None, world_seed = 1))]
    fn new(
        py: Python<'_>,
        params_json: Option<&str>,
        scenario: Option<&str>,
        world_seed: u64,
    ) -> PyResult<Self> {
        let base = match scenario {
            Some(s) => {
                py.detach(|| strider_experiments::trial::load(s, world_seed))
                    .map_err(to_py)?
                    .map
            }
            None => MapParams::default(),
        };
        let params = match params_json {
            None => base,
            Some(j) => {
                let mut v = serde_json::to_value(&base).map_err(|e| msg(e.to_string()))?;
                let over: serde_json::Value =
                    serde_json::from_str(j).map_err(|e| msg(format!("map params: {e}")))?;
                let (Some(o), Some(into)) = (over.as_object(), v.as_object_mut()) else {
                    return Err(msg("map params: expected a dict of parameter names"));
                };
                for (k, val) in o {
                    if !into.contains_key(k) {
                        return Err(msg(format!(
                            "map params: unknown parameter {k:?} (known: {})",
                            into.keys().cloned().collect::<Vec<_>>().join(", ")
                        )));
                    }
                    into.insert(k.clone(), val.clone());
                }
                serde_json::from_value(v).map_err(|e| msg(format!("map params: {e}")))?
            }
        };
        let map = RustMap::try_new(params).map_err(|e| msg(format!("map params: {e}")))?;
        Ok(Self { map, scans: 0 })
    }

    /// Fuses one scan: `points` (N × 3 float32, metres) with `colors` (N × 3 uint8) taken by a
    /// sensor at `pose` = (x, y, z) or (x, y, z, yaw). The points are in the sensor's frame
    /// (x forward, y left, z up), turned by yaw and moved to the pose, unless `world_frame` is
    /// true. Non-finite points are skipped and counted. Updates passability; returns the fusion
    /// counts as a dict.
    #[pyo3(signature = (points, colors, pose, world_frame = false))]
    fn fuse<'py>(
        &mut self,
        py: Python<'py>,
        points: PyReadonlyArray2<'py, f32>,
        colors: PyReadonlyArray2<'py, u8>,
        pose: Vec<f64>,
        world_frame: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (origin, yaw) = pose_parts(&pose)?;
        let (p, c) = (points.as_array(), colors.as_array());
        if points.shape()[1] != 3 || colors.shape() != points.shape() {
            return Err(msg(format!(
                "points {:?} and colors {:?}: both must be N × 3",
                points.shape(),
                colors.shape()
            )));
        }
        let (s, co) = (yaw.sin(), yaw.cos());
        let pts: Vec<ColoredPoint> = p
            .rows()
            .into_iter()
            .zip(c.rows())
            .map(|(p, c)| {
                let (x, y, z) = (p[0] as f64, p[1] as f64, p[2] as f64);
                let (wx, wy, wz) = if world_frame {
                    (x, y, z)
                } else {
                    (
                        origin.x + co * x - s * y,
                        origin.y + s * x + co * y,
                        origin.z + z,
                    )
                };
                ColoredPoint {
                    x: wx as f32,
                    y: wy as f32,
                    z: wz as f32,
                    rgb: [c[0], c[1], c[2]],
                }
            })
            .collect();
        self.scans += 1;
        let cloud = PointCloud::new(self.scans as f64, 0, origin, pts);
        let st = self.map.integrate(&cloud);
        let d = PyDict::new(py);
        d.set_item("fused_points", st.fused_points)?;
        d.set_item("skipped_non_finite", st.skipped_non_finite)?;
        d.set_item("skipped_out_of_range", st.skipped_out_of_range)?;
        d.set_item("cells_updated", st.cells_updated)?;
        Ok(d)
    }

    /// The map's layers over its known part: a dict of numpy arrays (see `strider.Report.layers`).
    fn layers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        to_dict(py, map_layers(&self.map), self.map.cell_size())
    }

    /// Observed cells.
    #[getter]
    fn observed_cells(&self) -> usize {
        self.map.observed_count()
    }

    /// The cell size, m.
    #[getter]
    fn cell_size(&self) -> f64 {
        self.map.cell_size()
    }
}
