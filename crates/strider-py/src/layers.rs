//! Map and model layers as numpy arrays. Each layer is a `(rows, cols)` array in the layers'
//! own row-major order (row 0 the lowest y, column 0 the lowest x), handed over without a copy
//! (numpy takes the vector); `origin` is the world position of the lower-left corner of cell
//! (0, 0) and `cell_size` the edge of a cell, so cell (r, c) covers
//! `origin + cell_size * (c, r)` to `origin + cell_size * (c + 1, r + 1)`.

use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strider_core::snapshot::{Layers, Quantity};

/// `v` (rows × cols, row-major) as a 2-D numpy array, moved, not copied.
pub fn grid<'py, T: numpy::Element>(
    py: Python<'py>,
    v: Vec<T>,
    rows: usize,
    cols: usize,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(v.into_pyarray(py).reshape([rows, cols])?.into_any())
}

/// The layers as a dict of numpy arrays with `cell_size` and `origin`; model layers under
/// `models` by name.
pub fn to_dict<'py>(py: Python<'py>, l: Layers, cell_size: f64) -> PyResult<Bound<'py, PyDict>> {
    let (rows, cols) = (l.rect.height as usize, l.rect.width as usize);
    let d = PyDict::new(py);
    d.set_item("cell_size", cell_size)?;
    d.set_item(
        "origin",
        (
            l.rect.min.i as f64 * cell_size,
            l.rect.min.j as f64 * cell_size,
        ),
    )?;
    d.set_item("elevation", grid(py, l.elevation, rows, cols)?)?;
    d.set_item(
        "elevation_variance",
        grid(py, l.elevation_variance, rows, cols)?,
    )?;
    let colour: Vec<u8> = l.color.into_iter().flatten().collect();
    d.set_item(
        "color",
        colour.into_pyarray(py).reshape([rows, cols, 3])?.into_any(),
    )?;
    d.set_item("observed", grid(py, l.observed, rows, cols)?)?;
    d.set_item("passability", grid(py, l.passability, rows, cols)?)?;
    let models = PyDict::new(py);
    for m in l.models {
        let md = PyDict::new(py);
        md.set_item("quantity", quantity_name(&m.quantity))?;
        md.set_item("gait", m.gait.map(|g| g.0))?;
        md.set_item("cost", grid(py, m.cost, rows, cols)?)?;
        md.set_item("variance", grid(py, m.variance, rows, cols)?)?;
        md.set_item("measured", grid(py, m.measured, rows, cols)?)?;
        if let Some(classes) = m.classes {
            md.set_item("classes", grid(py, classes, rows, cols)?)?;
        }
        models.set_item(m.name, md)?;
    }
    d.set_item("models", models)?;
    Ok(d)
}

fn quantity_name(q: &Quantity) -> &'static str {
    match q {
        Quantity::InverseVelocity { .. } => "inverse_velocity",
        Quantity::RollVariance => "roll_variance",
        Quantity::PushForce => "push_force",
    }
}
