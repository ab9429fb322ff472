//! Tiled layers (decision 1): square tiles of `tile_size²` cells allocated on first touch in a
//! hash map keyed by tile index, so a layer grows in any direction (negative coordinates
//! included) without copying and an unexplored world costs nothing.
//!
//! Each map layer (elevation, variance, colour, …) is its own [`TiledLayer`], a separate array per
//! concept as in grid_map, not a fat cell struct. Bulk algorithms read a rectangle into a dense
//! raster with [`TiledLayer::read_rect`] (one hash lookup per tile, row copies inside) and write
//! results back with [`TiledLayer::write_rect`].

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use strider_core::{Cell, CellRect};

/// Index of a tile: tile `(ti, tj)` covers cells `[ti·s, (ti+1)·s) × [tj·s, (tj+1)·s)` for tile
/// size `s`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TileKey {
    /// Tile row (y) index. First, so that the derived order is row-major.
    pub tj: i32,
    /// Tile column (x) index.
    pub ti: i32,
}

/// A fast, non-cryptographic hasher for tile keys (FxHash-style multiply-rotate).
#[derive(Clone, Copy, Default)]
pub struct TileHasher(u64);

impl TileHasher {
    #[inline]
    fn add(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

impl Hasher for TileHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.add(b as u64);
        }
    }
    #[inline]
    fn write_i32(&mut self, v: i32) {
        self.add(v as u32 as u64);
    }
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
}

type TileMap<T> = HashMap<TileKey, Box<[T]>, BuildHasherDefault<TileHasher>>;

/// One layer of per-cell values stored in lazily allocated square tiles.
#[derive(Clone, Debug)]
pub struct TiledLayer<T: Copy + Default> {
    tile_size: u32,
    tiles: TileMap<T>,
}

impl<T: Copy + Default> TiledLayer<T> {
    /// An empty layer with tiles of `tile_size × tile_size` cells (at least 1).
    pub fn new(tile_size: u32) -> Self {
        Self {
            tile_size: tile_size.max(1),
            tiles: TileMap::default(),
        }
    }

    /// Tile edge length in cells.
    pub fn tile_size(&self) -> u32 {
        self.tile_size
    }

    /// Number of allocated tiles.
    pub fn tile_count(&self) -> usize {
        self.tiles.len()
    }

    /// True when no tile is allocated.
    pub fn is_empty(&self) -> bool {
        self.tiles.is_empty()
    }

    /// Drops every tile.
    pub fn clear(&mut self) {
        self.tiles.clear();
    }

    /// The tile holding `c` and the row-major index of `c` inside it.
    #[inline]
    pub fn locate(&self, c: Cell) -> (TileKey, usize) {
        let s = self.tile_size as i32;
        let key = TileKey {
            ti: c.i.div_euclid(s),
            tj: c.j.div_euclid(s),
        };
        let k = c.j.rem_euclid(s) as usize * s as usize + c.i.rem_euclid(s) as usize;
        (key, k)
    }

    /// The cells a tile covers.
    pub fn tile_rect(&self, key: TileKey) -> CellRect {
        let s = self.tile_size as i32;
        CellRect::new(
            Cell::new(key.ti * s, key.tj * s),
            self.tile_size,
            self.tile_size,
        )
    }

    /// The value at `c`, `None` when its tile is not allocated.
    #[inline]
    pub fn get(&self, c: Cell) -> Option<T> {
        let (key, k) = self.locate(c);
        self.tiles.get(&key).map(|t| t[k])
    }

    /// The value at `c`, `T::default()` when its tile is not allocated.
    #[inline]
    pub fn value(&self, c: Cell) -> T {
        self.get(c).unwrap_or_default()
    }

    /// The value at world point `(x, y)` for cell size `d`; `None` for non-finite input or an
    /// unallocated tile.
    pub fn get_world(&self, x: f64, y: f64, d: f64) -> Option<T> {
        Cell::containing(x, y, d).and_then(|c| self.get(c))
    }

    /// Mutable access to the value at `c`, `None` when its tile is not allocated.
    #[inline]
    pub fn get_mut(&mut self, c: Cell) -> Option<&mut T> {
        let (key, k) = self.locate(c);
        self.tiles.get_mut(&key).map(|t| &mut t[k])
    }

    /// Mutable access to the value at `c`, allocating its tile (filled with defaults) if needed.
    #[inline]
    pub fn get_or_insert(&mut self, c: Cell) -> &mut T {
        let (key, k) = self.locate(c);
        &mut self.tile_or_insert(key)[k]
    }

    /// Sets the value at `c`, allocating its tile if needed.
    #[inline]
    pub fn set(&mut self, c: Cell, v: T) {
        *self.get_or_insert(c) = v;
    }

    /// The cells of a tile in row-major order, `None` when not allocated.
    pub fn tile(&self, key: TileKey) -> Option<&[T]> {
        self.tiles.get(&key).map(|t| &t[..])
    }

    /// Mutable cells of a tile, `None` when not allocated.
    pub fn tile_mut(&mut self, key: TileKey) -> Option<&mut [T]> {
        self.tiles.get_mut(&key).map(|t| &mut t[..])
    }

    /// Mutable cells of a tile, allocating it (filled with defaults) if needed.
    pub fn tile_or_insert(&mut self, key: TileKey) -> &mut [T] {
        let n = self.tile_size as usize * self.tile_size as usize;
        self.tiles
            .entry(key)
            .or_insert_with(|| vec![T::default(); n].into_boxed_slice())
    }

    /// Keys of the allocated tiles in row-major order (deterministic).
    pub fn tile_keys(&self) -> Vec<TileKey> {
        let mut keys: Vec<TileKey> = self.tiles.keys().copied().collect();
        keys.sort_unstable();
        keys
    }

    /// The allocated tiles with their keys, in row-major tile order.
    pub fn tiles(&self) -> impl Iterator<Item = (TileKey, &[T])> + '_ {
        self.tile_keys()
            .into_iter()
            .map(move |k| (k, &self.tiles[&k][..]))
    }

    /// Every cell of every allocated tile with its value, tile by tile in row-major tile order.
    pub fn cells(&self) -> impl Iterator<Item = (Cell, T)> + '_ {
        self.tiles().flat_map(move |(key, data)| {
            let r = self.tile_rect(key);
            data.iter().enumerate().map(move |(k, &v)| (r.cell(k), v))
        })
    }

    /// The bounding rectangle of the allocated tiles, `None` when empty.
    pub fn bounds(&self) -> Option<CellRect> {
        self.tiles
            .keys()
            .map(|&k| self.tile_rect(k))
            .reduce(crate::rect::union)
    }

    /// Tile keys overlapping `rect`, row-major.
    fn keys_over(&self, rect: CellRect) -> impl Iterator<Item = TileKey> + use<T> {
        let s = self.tile_size as i32;
        let (i1, j1) = crate::rect::max_corner(rect);
        let (ti0, tj0) = (rect.min.i.div_euclid(s), rect.min.j.div_euclid(s));
        let (ti1, tj1) = (i1.div_euclid(s), j1.div_euclid(s));
        let empty = rect.is_empty();
        (tj0..=tj1)
            .flat_map(move |tj| (ti0..=ti1).map(move |ti| TileKey { ti, tj }))
            .filter(move |_| !empty)
    }

    /// Reads `rect` into a dense row-major raster (`out` is cleared and resized);
    /// unallocated cells read as `T::default()`.
    pub fn read_rect(&self, rect: CellRect, out: &mut Vec<T>) {
        out.clear();
        out.resize(rect.len(), T::default());
        self.for_each_overlap(rect, |tile, tile_off, out_off, n, _| {
            if let Some(t) = self.tiles.get(&tile) {
                out[out_off..out_off + n].copy_from_slice(&t[tile_off..tile_off + n]);
            }
        });
    }

    /// Writes a dense row-major raster over `rect` into the layer. A tile is allocated only when
    /// it would receive a non-default value, so writing "nothing" costs no memory.
    pub fn write_rect(&mut self, rect: CellRect, data: &[T])
    where
        T: PartialEq,
    {
        assert_eq!(data.len(), rect.len(), "raster size");
        let mut runs: Vec<(TileKey, usize, usize, usize)> = Vec::new();
        self.for_each_overlap(rect, |tile, tile_off, src_off, n, _| {
            runs.push((tile, tile_off, src_off, n));
        });
        let d = T::default();
        let mut k = 0;
        while k < runs.len() {
            let key = runs[k].0;
            let mut end = k;
            while end < runs.len() && runs[end].0 == key {
                end += 1;
            }
            let needed = self.tiles.contains_key(&key)
                || runs[k..end]
                    .iter()
                    .any(|&(_, _, s, n)| data[s..s + n].iter().any(|v| *v != d));
            if needed {
                let t = self.tile_or_insert(key);
                for &(_, toff, soff, n) in &runs[k..end] {
                    t[toff..toff + n].copy_from_slice(&data[soff..soff + n]);
                }
            }
            k = end;
        }
    }

    /// Calls `f(tile, offset in tile, offset in rect raster, run length, row)` for every row run
    /// of `rect` inside each overlapping tile, grouped by tile.
    fn for_each_overlap(
        &self,
        rect: CellRect,
        mut f: impl FnMut(TileKey, usize, usize, usize, usize),
    ) {
        let s = self.tile_size as i32;
        for key in self.keys_over(rect) {
            let Some(ov) = crate::rect::intersection(rect, self.tile_rect(key)) else {
                continue;
            };
            for row in 0..ov.height as i32 {
                let j = ov.min.j + row;
                let tile_off = ((j - key.tj * s) * s + (ov.min.i - key.ti * s)) as usize;
                let out_off = ((j - rect.min.j) as usize) * rect.width as usize
                    + (ov.min.i - rect.min.i) as usize;
                f(key, tile_off, out_off, ov.width as usize, row as usize);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grows_in_negative_coordinates() {
        let mut l: TiledLayer<f32> = TiledLayer::new(4);
        l.set(Cell::new(-1, -1), 1.0);
        l.set(Cell::new(-5, 3), 2.0);
        l.set(Cell::new(9, -9), 3.0);
        assert_eq!(l.get(Cell::new(-1, -1)), Some(1.0));
        assert_eq!(l.get(Cell::new(-5, 3)), Some(2.0));
        assert_eq!(l.get(Cell::new(9, -9)), Some(3.0));
        assert_eq!(l.get(Cell::new(-2, -1)), Some(0.0));
        assert_eq!(l.get(Cell::new(100, 100)), None);
        assert_eq!(l.tile_count(), 3);
        assert_eq!(l.bounds(), Some(CellRect::new(Cell::new(-8, -12), 20, 16)));
        // World queries: cell (-1, -1) covers [-0.1, 0) with d = 0.1.
        assert_eq!(l.get_world(-0.05, -0.01, 0.1), Some(1.0));
        let nonzero: Vec<(Cell, f32)> = l.cells().filter(|&(_, v)| v != 0.0).collect();
        assert_eq!(nonzero.len(), 3);
        assert_eq!(nonzero[0], (Cell::new(9, -9), 3.0), "row-major tile order");
    }

    #[test]
    fn read_write_rect_round_trip() {
        let mut l: TiledLayer<u16> = TiledLayer::new(3);
        let rect = CellRect::new(Cell::new(-4, -2), 7, 5);
        let data: Vec<u16> = (1..=rect.len() as u16).collect();
        l.write_rect(rect, &data);
        for (k, c) in rect.cells().enumerate() {
            assert_eq!(l.get(c), Some(data[k]));
        }
        let mut out = Vec::new();
        let bigger = crate::rect::expand(rect, 2);
        l.read_rect(bigger, &mut out);
        for (k, c) in bigger.cells().enumerate() {
            assert_eq!(out[k], l.value(c));
        }
        // Writing defaults allocates nothing.
        let mut e: TiledLayer<u16> = TiledLayer::new(3);
        e.write_rect(rect, &vec![0; rect.len()]);
        assert!(e.is_empty());
    }
}
