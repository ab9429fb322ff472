//! What the unit tests of this crate share: maps on a given lattice and blocks of known cells.

use crate::map::ElevationMap;
use crate::params::MapParams;
use strider_core::{Cell, Rgb8};

/// An empty map with cells of `cell_size` metres in tiles of `tile_size` cells, the other
/// parameters default.
pub(crate) fn lattice_map(cell_size: f64, tile_size: u32) -> ElevationMap {
    ElevationMap::new(MapParams {
        cell_size,
        tile_size,
        ..MapParams::default()
    })
}

/// The cells of the `width × height` block whose lowest cell is `(i, j)`, row by row.
pub(crate) fn block(i: i32, j: i32, width: i32, height: i32) -> impl Iterator<Item = Cell> {
    (j..j + height).flat_map(move |j| (i..i + width).map(move |i| Cell::new(i, j)))
}

/// Sets `cells` observed at height `z(cell)` (variance 1e-4, default colour).
pub(crate) fn known(
    m: &mut ElevationMap,
    cells: impl IntoIterator<Item = Cell>,
    z: impl Fn(Cell) -> f32,
) {
    for c in cells {
        m.set_cell(c, z(c), 1e-4, Rgb8::default());
    }
}

/// Sets `cells` observed flat at height 0 and updates passability.
pub(crate) fn flat(m: &mut ElevationMap, cells: impl IntoIterator<Item = Cell>) {
    known(m, cells, |_| 0.0);
    m.update_passability();
}
