//! `strider.CostModel`: the traversal cost model of one gait (strider-learn's
//! `GaitCostModel`, Prágr22's model with IGNG terrain classes) over a `strider.ElevationMap`.

use numpy::{IntoPyArray, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use strider_core::{Cell, CellRect, GaitId};
use strider_explore::kernel::map_layers;
use strider_learn::cost_model::{CostModelParams, GaitCostModel, Insertion, ModelUpdate};
use strider_learn::descriptor_field::DescriptorField;
use strider_map::ElevationMap as RustMap;
use strider_map::descriptors::TA_BINS;

use crate::errors::msg;
use crate::gp::{MeanVariance, gp_params, rows};
use crate::layers::grid;
use crate::map::ElevationMap;

/// The traversal cost model of one gait over an elevation map (Prágr22 Alg. 5–10).
///
/// `CostModel(map, gait=0, seed=1, lengthscale=0.4, signal_variance=1.0,
/// noise_variance=0.25, prior_mean=1.0, c_max=20.0)`; the other parameters are Prágr22
/// Table 3's. Descriptors are the 9-bin colour histograms ta(ν) of the map. `measure(x, y,
/// cost)` fuses a cost measured at a point when it is novel, `update()` relearns the regressor
/// and the terrain classes and returns the classes and goals, `costs()` and `classes()` are the
/// planning layers over `map.layers()`'s rectangle.
#[pyclass(name = "CostModel", module = "strider", unsendable)]
pub struct CostModel {
    map: Py<ElevationMap>,
    model: GaitCostModel,
    desc: DescriptorField,
    /// The map revision the descriptors follow.
    revision: u64,
}

impl CostModel {
    /// Brings the descriptors up to date with the map's changes since the last call.
    fn sync(&mut self, map: &RustMap) -> Option<CellRect> {
        self.desc.follow_color_histograms(map, &mut self.revision)
    }
}

fn update_dict<'py>(
    py: Python<'py>,
    u: &ModelUpdate,
    map: &RustMap,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let classes = PyList::empty(py);
    for c in &u.classes {
        let cd = PyDict::new(py);
        cd.set_item("id", c.id.0)?;
        cd.set_item("cells", c.cells)?;
        cd.set_item("learning_cells", c.learning_cells)?;
        cd.set_item("cost", c.cost)?;
        cd.set_item("variance", c.variance)?;
        classes.append(cd)?;
    }
    d.set_item("classes", classes)?;
    d.set_item("h_gt", u.h_gt)?;
    let centre = |c: &Cell| map.center(*c);
    let goals = PyList::empty(py);
    for g in &u.goals {
        let gd = PyDict::new(py);
        gd.set_item("class", g.class.map(|c| c.0))?;
        gd.set_item("information_gain", g.information_gain)?;
        let sites: Vec<(f64, f64)> = g.sites.iter().map(centre).map(|p| (p.x, p.y)).collect();
        gd.set_item("sites", sites)?;
        goals.append(gd)?;
    }
    d.set_item("goals", goals)?;
    d.set_item("pruned", u.pruned.iter().map(|c| c.0).collect::<Vec<_>>())?;
    Ok(d)
}

#[pymethods]
impl CostModel {
    #[new]
    #[pyo3(signature = (map, gait = 0, seed = 1, lengthscale = 0.4, signal_variance = 1.0, noise_variance = 0.25, prior_mean = 1.0, c_max = 20.0))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        map: Py<ElevationMap>,
        gait: u8,
        seed: u64,
        lengthscale: f64,
        signal_variance: f64,
        noise_variance: f64,
        prior_mean: f64,
        c_max: f64,
    ) -> PyResult<Self> {
        let gp = gp_params(
            "se",
            lengthscale,
            signal_variance,
            noise_variance,
            prior_mean,
        )?;
        let params = CostModelParams {
            c_max,
            ..CostModelParams::new(gp)
        };
        let model = GaitCostModel::new(GaitId(gait), TA_BINS, params, seed)
            .map_err(|e| msg(e.to_string()))?;
        Ok(Self {
            map,
            model,
            desc: DescriptorField::empty(CellRect::new(Cell::new(0, 0), 0, 0), TA_BINS),
            revision: 0,
        })
    }

    /// Fuses a cost measured at (x, y) (Alg. 5 `insertIfNovel`, into the cell and its 8
    /// neighbours); returns whether it was novel and stored.
    fn measure(&mut self, py: Python<'_>, x: f64, y: f64, cost: f64) -> PyResult<bool> {
        let map_ref = self.map.clone_ref(py);
        let m = map_ref.borrow(py);
        self.sync(&m.map);
        let Some(cell) = (x.is_finite() && y.is_finite())
            .then(|| m.map.cell_at(x, y))
            .flatten()
        else {
            return Err(msg(format!(
                "measure: ({x}, {y}) is not a point of the map"
            )));
        };
        match self.model.insert_measurement(cell, cost, &self.desc) {
            Ok(Insertion::Stored) => Ok(true),
            Ok(Insertion::NotNovel) => Ok(false),
            Err(e) => Err(msg(format!("measure: {e}"))),
        }
    }

    /// Alg. 6: relearns the regressor, adapts the terrain classes and finds the goals. Returns
    /// `{"classes": [{id, cells, learning_cells, cost, variance}], "h_gt", "goals": [{class,
    /// information_gain, sites: [(x, y)]}], "pruned"}`.
    fn update<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let map_ref = self.map.clone_ref(py);
        let m = map_ref.borrow(py);
        self.sync(&m.map);
        let u = self
            .model
            .update(&m.map, &self.desc)
            .map_err(|e| msg(e.to_string()))?;
        update_dict(py, &u, &m.map)
    }

    /// The planning cost of every cell of `map.layers()`'s rectangle (Prágr22 Eq. 18), float32.
    fn costs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let m = self.map.borrow(py);
        let rect = map_layers(&m.map).rect;
        let c = self.model.planning_costs(rect);
        grid(py, c, rect.height as usize, rect.width as usize)
    }

    /// The planning terrain class of every cell of `map.layers()`'s rectangle, int32, −1 where
    /// a cell has none.
    fn classes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let m = self.map.borrow(py);
        let rect = map_layers(&m.map).rect;
        let c: Vec<i32> = rect
            .cells()
            .map(|c| {
                self.model
                    .planning_class(c)
                    .map_or(-1, |t| i32::try_from(t.0).unwrap_or(i32::MAX))
            })
            .collect();
        grid(py, c, rect.height as usize, rect.width as usize)
    }

    /// The regressor's mean and latent variance at descriptors `D` (n × 9 histograms); the
    /// prior before the regressor exists.
    fn predict<'py>(
        &self,
        py: Python<'py>,
        d: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<MeanVariance<'py>> {
        let (xs, _, dim) = rows(&d, "D")?;
        if dim != TA_BINS {
            return Err(msg(format!("D has {dim} columns, descriptors {TA_BINS}")));
        }
        let (mean, var): (Vec<f64>, Vec<f64>) = self.model.predict_many(&xs).into_iter().unzip();
        Ok((mean.into_pyarray(py), var.into_pyarray(py)))
    }

    /// The number of cells with a measured cost.
    #[getter]
    fn measured_cells(&self) -> usize {
        self.model.measured_cells().len()
    }

    /// The size of the learning set (the regressor's training points).
    #[getter]
    fn learning_set(&self) -> usize {
        self.model.learning_set_len()
    }
}
