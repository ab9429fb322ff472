//! Terrain appearance descriptors computed on the map.
//!
//! * ta(ν), Prágr22 §4.2 (decision 6): relative counts of the cell colours, each mapped to the
//!   nearest of nine prototypes in CIELAB, over the known cells of the disc of radius r_hist;
//!   no descriptor when fewer than half the disc's cells are known.
//! * The Prágr23 8-bin histogram: the same over the first eight prototypes.
//! * Lab (a, b) of a cell.
//! * The 5-D shape + appearance descriptor of Prágr19 Eq. 10 (decision 7): eigenvalues
//!   λ1 ≤ λ2 ≤ λ3 of the covariance of the (x, y, z) cell centres within δ_desc give
//!   s1 = λ1/λ3, s2 = (λ2 − λ1)/λ3, s3 = (λ3 − λ2)/λ3 (unstructured / planar / linear), followed
//!   by the mean Lab a and b of those cells divided by 128 and clamped to [−1, 1]. λ3 ≈ 0 gives
//!   (0, 0, 1). The same half-known rule applies.
//!
//! Bulk functions fill a dense [`Raster`] over a rectangle in parallel (rows with rayon); the
//! single-cell functions are the bulk ones on a 1 × 1 rectangle, so both share one code path.

use crate::map::ElevationMap;
use crate::passability::disc_reach;
use crate::rect;
use nalgebra::{Matrix3, SymmetricEigen};
use rayon::prelude::*;
use strider_core::color::{PrototypeQuantizer, rgb_to_lab};
use strider_core::grid::disc_offsets;
use strider_core::{Cell, CellRect, Rgb8};

/// Bins of ta(ν) (Prágr22, nine prototypes).
pub const TA_BINS: usize = 9;
/// Bins of the Prágr23 histogram (first eight prototypes).
pub const C4_BINS: usize = 8;

/// λ3 below this (m²) counts as zero: a degenerate neighbourhood (decision 7).
const LAMBDA_EPS: f64 = 1e-12;

/// A dense row-major layer of values over a rectangle.
#[derive(Clone, Debug, PartialEq)]
pub struct Raster<T> {
    /// The cells covered.
    pub rect: CellRect,
    /// One value per cell of `rect`, row-major.
    pub values: Vec<T>,
}

impl<T> Raster<T> {
    /// The value at `c`, `None` outside the rectangle.
    pub fn get(&self, c: Cell) -> Option<&T> {
        self.rect.index(c).map(|k| &self.values[k])
    }
}

/// The map's known cells over a rectangle, prepared for descriptor computation.
struct View {
    rect: CellRect,
    elev: Vec<f32>,
    color: Vec<Option<strider_core::Rgb8>>,
}

impl View {
    fn new(map: &ElevationMap, out: CellRect, r: f64) -> Self {
        let rect = rect::expand(out, disc_reach(r, map.cell_size()));
        Self {
            rect,
            elev: map.elevation_raster(rect),
            color: map.color_raster(rect),
        }
    }
}

/// Fills a raster over `out` by calling `f(cell, view-index of the cell, disc)` in parallel.
fn fill<T: Send + Clone>(
    out: CellRect,
    view: &View,
    disc: &[(i32, i32)],
    f: impl Fn(Cell, &View, &[isize]) -> T + Sync,
) -> Raster<T> {
    let w = view.rect.width as isize;
    let disc_k: Vec<isize> = disc
        .iter()
        .map(|&(di, dj)| dj as isize * w + di as isize)
        .collect();
    let values: Vec<T> = (0..out.len())
        .into_par_iter()
        .map(|k| f(out.cell(k), view, &disc_k))
        .collect();
    Raster { rect: out, values }
}

/// Bin counts of one disc: per bin, and the known cells.
#[derive(Clone, Copy)]
struct DiscCounts<const N: usize> {
    bins: [u32; N],
    known: u32,
}

impl<const N: usize> DiscCounts<N> {
    #[inline]
    fn add(&mut self, b: u8) {
        if b != u8::MAX {
            self.bins[b as usize] += 1;
            self.known += 1;
        }
    }

    #[inline]
    fn remove(&mut self, b: u8) {
        if b != u8::MAX {
            self.bins[b as usize] -= 1;
            self.known -= 1;
        }
    }

    /// The relative histogram, `None` under the half-known rule.
    fn histogram(&self, disc_len: usize) -> Option<[f32; N]> {
        let known = self.known as usize;
        if known == 0 || 2 * known < disc_len {
            return None;
        }
        Some(std::array::from_fn(|b| self.bins[b] as f32 / known as f32))
    }
}

/// The histograms of every cell of `out`, one row per parallel task. Along a row the disc's
/// counts slide: each step removes the leftmost cell of each of its 2R + 1 row spans and adds
/// the cell past the rightmost, 2(2R + 1) updates instead of the disc's π R² (81 → 22 for
/// r_hist = 5 cells). This runs for the whole known map at every learning update.
fn histograms<const N: usize>(
    map: &ElevationMap,
    out: CellRect,
    r: f64,
) -> Raster<Option<[f32; N]>> {
    let vrect = rect::expand(out, disc_reach(r, map.cell_size()));
    let bins = colour_bins(map, vrect, &PrototypeQuantizer::new(N));
    let disc = disc_offsets(r, map.cell_size());
    // The disc as row spans dj ↦ [−a, a] (it is symmetric and convex along rows).
    let reach = disc.iter().map(|&(_, dj)| dj.abs()).max().unwrap_or(0);
    let mut half = vec![-1i32; 2 * reach as usize + 1];
    for &(di, dj) in &disc {
        let a = &mut half[(dj + reach) as usize];
        *a = (*a).max(di);
    }
    let vw = vrect.width as isize;
    let (ow, oh) = (out.width as usize, out.height as usize);
    let mut values = vec![None; out.len()];
    if ow == 0 {
        return Raster { rect: out, values };
    }
    values.par_chunks_mut(ow).zip(0..oh).for_each(|(row, j)| {
        let first = out.cell(j * ow);
        let base = vrect.index(first).unwrap_or(0) as isize;
        let at = |i: isize, dj: i32| bins[(base + dj as isize * vw + i) as usize];
        let mut counts = DiscCounts::<N> {
            bins: [0; N],
            known: 0,
        };
        for &(di, dj) in &disc {
            counts.add(at(di as isize, dj));
        }
        row[0] = counts.histogram(disc.len());
        for i in 1..ow as isize {
            for (s, &a) in half.iter().enumerate() {
                let dj = s as i32 - reach;
                if a >= 0 {
                    counts.remove(at(i - 1 - a as isize, dj));
                    counts.add(at(i + a as isize, dj));
                }
            }
            row[i as usize] = counts.histogram(disc.len());
        }
    });
    Raster { rect: out, values }
}

/// The prototype bin of every cell of `rect`, `u8::MAX` where unobserved. Neighbouring cells
/// often share a colour (a surface, or the one colour given to a laser's points), so each
/// block remembers its last colour and skips the Lab conversion for a repeat.
fn colour_bins(map: &ElevationMap, rect: CellRect, q: &PrototypeQuantizer) -> Vec<u8> {
    let colours = map.color_raster(rect);
    let mut bins = vec![u8::MAX; colours.len()];
    bins.par_chunks_mut(4096)
        .zip(colours.par_chunks(4096))
        .for_each(|(bins, colours)| {
            let mut last: Option<(Rgb8, u8)> = None;
            for (b, c) in bins.iter_mut().zip(colours) {
                let Some(c) = *c else { continue };
                *b = match last {
                    Some((lc, lb)) if lc == c => lb,
                    _ => {
                        let nb = q.nearest(c) as u8;
                        last = Some((c, nb));
                        nb
                    }
                };
            }
        });
    bins
}

/// ta(ν) (Prágr22 §4.2) for every cell of `rect`: 9-bin relative colour histogram within r_hist.
pub fn color_histograms(
    map: &ElevationMap,
    rect: CellRect,
    r_hist: f64,
) -> Raster<Option<[f32; TA_BINS]>> {
    histograms::<TA_BINS>(map, rect, r_hist)
}

/// How far, in cells, a histogram of radius `r_hist` reaches: a change of one cell can change
/// the histograms of the cells up to this many cells away (in rows or columns).
pub fn histogram_reach(r_hist: f64, d: f64) -> u32 {
    disc_reach(r_hist, d)
}

/// The Prágr23 8-bin colour histogram for every cell of `rect`.
pub fn c4_histograms(
    map: &ElevationMap,
    rect: CellRect,
    r_hist: f64,
) -> Raster<Option<[f32; C4_BINS]>> {
    histograms::<C4_BINS>(map, rect, r_hist)
}

/// ta(ν) of one cell; `None` when fewer than half the disc's cells are known.
pub fn color_histogram(map: &ElevationMap, c: Cell, r_hist: f64) -> Option<[f32; TA_BINS]> {
    color_histograms(map, CellRect::new(c, 1, 1), r_hist).values[0]
}

/// The Prágr23 8-bin histogram of one cell.
pub fn c4_histogram(map: &ElevationMap, c: Cell, r_hist: f64) -> Option<[f32; C4_BINS]> {
    c4_histograms(map, CellRect::new(c, 1, 1), r_hist).values[0]
}

/// CIELAB (a, b) of a cell's colour, `None` when unobserved.
pub fn lab_ab(map: &ElevationMap, c: Cell) -> Option<[f32; 2]> {
    map.color(c).map(|rgb| {
        let lab = rgb_to_lab(rgb);
        [lab.a, lab.b]
    })
}

/// The 5-D descriptor of Prágr19 Eq. 10 (decision 7) for every cell of `rect`, neighbourhood
/// radius `delta_desc`.
pub fn shape_lab_descriptors(
    map: &ElevationMap,
    rect: CellRect,
    delta_desc: f64,
) -> Raster<Option<[f32; 5]>> {
    let d = map.cell_size();
    let view = View::new(map, rect, delta_desc);
    let ab = lab_ab_of(&view);
    let disc = disc_offsets(delta_desc, d);
    fill(rect, &view, &disc, |c, v, disc_k| {
        shape_lab_in_view(c, v, &ab, &disc, disc_k, d)
    })
}

/// The 5-D descriptor of each of `cells` (any order, any spread): one view over their bounding
/// rectangle, each cell's colour converted to Lab once, only the given cells evaluated (in
/// parallel). Much cheaper than [`shape_lab_descriptor`] per cell when the cells are many.
pub fn shape_lab_descriptors_at(
    map: &ElevationMap,
    cells: &[Cell],
    delta_desc: f64,
) -> Vec<Option<[f32; 5]>> {
    let Some(first) = cells.first() else {
        return Vec::new();
    };
    let (mut lo, mut hi) = (*first, *first);
    for c in cells {
        lo = Cell::new(lo.i.min(c.i), lo.j.min(c.j));
        hi = Cell::new(hi.i.max(c.i), hi.j.max(c.j));
    }
    let out = CellRect::new(lo, (hi.i - lo.i + 1) as u32, (hi.j - lo.j + 1) as u32);
    let d = map.cell_size();
    let view = View::new(map, out, delta_desc);
    let ab = lab_ab_of(&view);
    let disc = disc_offsets(delta_desc, d);
    let w = view.rect.width as isize;
    let disc_k: Vec<isize> = disc
        .iter()
        .map(|&(di, dj)| dj as isize * w + di as isize)
        .collect();
    cells
        .par_iter()
        .map(|&c| shape_lab_in_view(c, &view, &ab, &disc, &disc_k, d))
        .collect()
}

/// Lab (a, b) of every cell of a view ([0, 0] where unknown).
fn lab_ab_of(view: &View) -> Vec<[f32; 2]> {
    view.color
        .iter()
        .map(|c| {
            c.map_or([0.0; 2], |c| {
                let l = rgb_to_lab(c);
                [l.a, l.b]
            })
        })
        .collect()
}

/// Eq. 10 for cell `c` of a view (decision 7).
fn shape_lab_in_view(
    c: Cell,
    v: &View,
    ab: &[[f32; 2]],
    disc: &[(i32, i32)],
    disc_k: &[isize],
    d: f64,
) -> Option<[f32; 5]> {
    let centre = v.rect.index(c).unwrap_or(0) as isize;
    let mut n = 0usize;
    let mut s = [0.0f64; 3];
    let mut ss = [[0.0f64; 3]; 3];
    let (mut sa, mut sb) = (0.0f64, 0.0f64);
    let mut z_ref = f64::NAN;
    for (&o, &(di, dj)) in disc_k.iter().zip(disc) {
        let k = (centre + o) as usize;
        let e = v.elev[k];
        if e.is_nan() {
            continue;
        }
        if z_ref.is_nan() {
            z_ref = e as f64; // shift for numerical stability; covariance is unchanged
        }
        let p = [di as f64 * d, dj as f64 * d, e as f64 - z_ref];
        for a in 0..3 {
            s[a] += p[a];
            for b in 0..3 {
                ss[a][b] += p[a] * p[b];
            }
        }
        sa += ab[k][0] as f64;
        sb += ab[k][1] as f64;
        n += 1;
    }
    if n == 0 || 2 * n < disc_k.len() {
        return None;
    }
    let nf = n as f64;
    let cov = Matrix3::from_fn(|a, b| ss[a][b] / nf - s[a] * s[b] / (nf * nf));
    let mut lambda: Vec<f64> = SymmetricEigen::new(cov)
        .eigenvalues
        .iter()
        .map(|&l| l.max(0.0))
        .collect();
    lambda.sort_by(f64::total_cmp);
    let (l1, l2, l3) = (lambda[0], lambda[1], lambda[2]);
    let shape = if l3 <= LAMBDA_EPS {
        [0.0, 0.0, 1.0]
    } else {
        [l1 / l3, (l2 - l1) / l3, (l3 - l2) / l3] // Eq. 10
    };
    let scale = |x: f64| (x / nf / 128.0).clamp(-1.0, 1.0) as f32;
    Some([
        shape[0] as f32,
        shape[1] as f32,
        shape[2] as f32,
        scale(sa),
        scale(sb),
    ])
}

/// The 5-D descriptor of one cell; `None` when fewer than half the neighbourhood is known.
pub fn shape_lab_descriptor(map: &ElevationMap, c: Cell, delta_desc: f64) -> Option<[f32; 5]> {
    shape_lab_descriptors(map, CellRect::new(c, 1, 1), delta_desc).values[0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::lattice_map;
    use approx::assert_abs_diff_eq;
    use strider_core::Rgb8;
    use strider_core::color::COLOR_PROTOTYPES;

    fn map() -> ElevationMap {
        lattice_map(0.1, 4)
    }

    #[test]
    fn histogram_relative_counts_and_half_rule() {
        let mut m = map();
        let red = COLOR_PROTOTYPES[3].1;
        let white = COLOR_PROTOTYPES[0].1;
        let magenta = COLOR_PROTOTYPES[8].1;
        // Disc of radius 0.1 = 5 cells: centre red, two white, one magenta, one unknown.
        m.set_cell(Cell::new(0, 0), 0.0, 1e-4, red);
        m.set_cell(Cell::new(1, 0), 0.0, 1e-4, white);
        m.set_cell(Cell::new(0, 1), 0.0, 1e-4, Rgb8::new(235, 238, 242));
        m.set_cell(Cell::new(-1, 0), 0.0, 1e-4, magenta);
        let h = color_histogram(&m, Cell::new(0, 0), 0.1).unwrap();
        let mut want = [0.0f32; 9];
        want[3] = 0.25;
        want[0] = 0.5;
        want[8] = 0.25;
        assert_eq!(h, want);
        // The Prágr23 histogram has no magenta: it goes to the nearest of the first eight prototypes.
        let h8 = c4_histogram(&m, Cell::new(0, 0), 0.1).unwrap();
        assert_abs_diff_eq!(h8.iter().sum::<f32>(), 1.0);
        assert_eq!(h8[0], 0.5);
        // (2, 0): disc holds (1,0), (2,0)?, (3,0)?, (2,±1)? → only 1 of 5 known.
        assert_eq!(color_histogram(&m, Cell::new(2, 0), 0.1), None);
        // Exactly half is not enough for 5 cells (2.5): 2 known → None; 3 → Some.
        m.set_cell(Cell::new(1, 1), 0.0, 1e-4, red);
        assert!(color_histogram(&m, Cell::new(1, 1), 0.1).is_some());
        let raster = color_histograms(&m, CellRect::new(Cell::new(-1, -1), 3, 3), 0.1);
        assert_eq!(raster.get(Cell::new(0, 0)).unwrap().unwrap(), want);
    }

    #[test]
    fn lab_of_a_cell() {
        let mut m = map();
        m.set_cell(Cell::new(0, 0), 0.0, 1e-4, Rgb8::new(255, 0, 0));
        let ab = lab_ab(&m, Cell::new(0, 0)).unwrap();
        assert_abs_diff_eq!(ab[0], 80.09, epsilon = 0.05);
        assert_abs_diff_eq!(ab[1], 67.20, epsilon = 0.05);
        assert_eq!(lab_ab(&m, Cell::new(1, 0)), None);
    }

    fn ramp(slope: f32, rgb: Rgb8) -> ElevationMap {
        let mut m = map();
        for j in -4..=4 {
            for i in -4..=4 {
                let x = (i as f32 + 0.5) * 0.1;
                m.set_cell(Cell::new(i, j), 1.0 + slope * x, 1e-4, rgb);
            }
        }
        m
    }

    #[test]
    fn sliding_histograms_equal_one_disc_at_a_time() {
        // A 1 × 1 rectangle counts its disc directly; a wide one slides the counts along rows.
        let mut m = map();
        let mut x = 12345u32;
        for j in -9..=9 {
            for i in -12..=12 {
                x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                if x >> 29 == 0 {
                    continue; // holes, an eighth of the cells
                }
                let c = x.to_le_bytes();
                m.set_cell(Cell::new(i, j), 0.0, 1e-4, Rgb8::new(c[1], c[2], c[3]));
            }
        }
        for r in [0.0, 0.1, 0.25, 0.33] {
            let rect = CellRect::new(Cell::new(-14, -11), 29, 23);
            let bulk = color_histograms(&m, rect, r);
            let c4 = c4_histograms(&m, rect, r);
            for (k, c) in rect.cells().enumerate() {
                assert_eq!(bulk.values[k], color_histogram(&m, c, r), "r {r} {c:?}");
                assert_eq!(c4.values[k], c4_histogram(&m, c, r), "r {r} {c:?}");
            }
            assert!(bulk.values.iter().any(Option::is_some));
            assert!(bulk.values.iter().any(Option::is_none));
        }
    }

    #[test]
    fn descriptors_at_scattered_cells_equal_one_by_one() {
        let mut m = map();
        for j in -6..=6 {
            for i in -6..=6 {
                if (i + 2 * j) % 5 == 0 {
                    continue; // holes
                }
                let z = 0.02 * ((i * i + j) % 7) as f32;
                m.set_cell(
                    Cell::new(i, j),
                    z,
                    1e-4,
                    Rgb8::new(
                        (40 + 13 * i.unsigned_abs()) as u8,
                        120,
                        (60 + 9 * j.unsigned_abs()) as u8,
                    ),
                );
            }
        }
        let cells = [
            Cell::new(3, -2),
            Cell::new(-5, 5),
            Cell::new(0, 0),
            Cell::new(6, 6),
            Cell::new(9, 9), // unknown surroundings
        ];
        let batch = shape_lab_descriptors_at(&m, &cells, 0.25);
        for (c, b) in cells.iter().zip(&batch) {
            assert_eq!(*b, shape_lab_descriptor(&m, *c, 0.25), "{c:?}");
        }
        assert!(batch[4].is_none() && batch[2].is_some());
        assert!(shape_lab_descriptors_at(&m, &[], 0.25).is_empty());
    }

    #[test]
    fn shape_descriptor_flat_ramp_and_degenerate() {
        let gray = Rgb8::new(128, 128, 128);
        // Flat patch: λ = (0, v, v) → planar (0, 1, 0); gray has a = b ≈ 0.
        let m = ramp(0.0, gray);
        let f = shape_lab_descriptor(&m, Cell::new(0, 0), 0.2).unwrap();
        for (x, w) in f.iter().zip([0.0, 1.0, 0.0, 0.0, 0.0]) {
            assert_abs_diff_eq!(*x, w, epsilon = 1e-4);
        }
        // Ramp z = s·x on a symmetric disc: covariance [[v,0,sv],[0,v,0],[sv,0,s²v]] has
        // eigenvalues 0, v, v(1+s²) → (0, 1/(1+s²), s²/(1+s²)).
        let s = 2.0f32;
        let red = Rgb8::new(255, 0, 0);
        let m = ramp(s, red);
        let f = shape_lab_descriptor(&m, Cell::new(0, 0), 0.2).unwrap();
        assert_abs_diff_eq!(f[0], 0.0, epsilon = 1e-4);
        assert_abs_diff_eq!(f[1], 1.0 / (1.0 + s * s), epsilon = 1e-4);
        assert_abs_diff_eq!(f[2], s * s / (1.0 + s * s), epsilon = 1e-4);
        let lab = rgb_to_lab(red);
        assert_abs_diff_eq!(f[3], lab.a / 128.0, epsilon = 1e-4);
        assert_abs_diff_eq!(f[4], lab.b / 128.0, epsilon = 1e-4);
        // δ_desc smaller than a cell: a single point, λ3 = 0 → (0, 0, 1).
        let f = shape_lab_descriptor(&m, Cell::new(0, 0), 0.01).unwrap();
        assert_eq!(&f[..3], &[0.0, 0.0, 1.0]);
        // Unknown neighbourhood → None.
        assert_eq!(shape_lab_descriptor(&m, Cell::new(40, 0), 0.2), None);
    }
}
