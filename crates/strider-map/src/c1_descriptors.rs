//! The Prágr18 descriptor family (Prágr18 §III-A) on the colored 2.5D map, for the learner
//! benchmark: a colour part (RGB or Lab, of the cell itself — "Point" — or the mean within
//! r_color = 0.2 m — "Mean" — or none) joined with a geometric part (height, shape, orientation,
//! all three — "Set" — or none), after the 13-feature set of the paper's reference \[24\] less its
//! distance and reflectance features.
//!
//! On a 2.5D grid the "points" are the known cell centres (x, y, z); the neighbourhood of the
//! geometric features is the disc of r_geom = 0.3 m. Features, scaled to be of order one:
//!
//! * **RGB**: (r, g, b) / 255. **Lab**: (L/100, a/128, b/128).
//! * **Height** (4, in decimetres): the cell's elevation above the global ground plane z = 0 (the
//!   map frame; Prágr18 fits a global ground plane), its elevation minus the neighbourhood
//!   mean, the neighbourhood's standard deviation and its range max − min.
//! * **Shape** (4): with λ1 ≤ λ2 ≤ λ3 the eigenvalues of the covariance of the neighbourhood's
//!   (x, y, z): λ1/λ3, (λ2 − λ1)/λ3, (λ3 − λ2)/λ3 (Prágr19 Eq. 10) and the change of curvature
//!   λ1/(λ1 + λ2 + λ3).
//! * **Orientation** (3): the unit normal (n_x, n_y, n_z), n_z ≥ 0, of the plane fitted to the
//!   k = 5 known cells nearest to the cell (itself included).
//!
//! # Degenerate input (decision 7)
//! * λ3 ≈ 0 (a single point, or a perfectly flat tiny patch): shape (0, 0, 1, 0), as decision 7
//!   sets the Prágr19 descriptor's (0, 0, 1).
//! * Fewer than three known cells for the normal, or a normal that is not unique (collinear
//!   cells): (0, 0, 1).
//! * Geometric features need at least half the r_geom disc known (the half-known rule of
//!   decisions 6–7); otherwise that part is missing.
//! * Missing colour: the "Point" colour of a cell without colour falls back to the neighbourhood
//!   mean; the "Mean" uses the coloured cells only; with no coloured cell within r_color the
//!   colour part is missing.
//!
//! A descriptor with a missing part is `None`: the benchmark skips (and counts) that sample.

use nalgebra::{Matrix3, SymmetricEigen};
use strider_core::Cell;
use strider_core::color::rgb_to_lab;
use strider_core::grid::disc_offsets;

use crate::map::ElevationMap;

/// λ3 below this (m²) counts as zero (decision 7).
const LAMBDA_EPS: f64 = 1e-12;

/// The colour part of a Prágr18 descriptor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorFeature {
    /// No colour.
    None,
    /// RGB of the cell ("RGB-P").
    RgbPoint,
    /// Mean RGB within r_color ("RGB-M").
    RgbMean,
    /// Lab of the cell ("Lab-P").
    LabPoint,
    /// Mean Lab within r_color ("Lab-M").
    LabMean,
}

impl ColorFeature {
    /// All five, in the naming order of Prágr18's table.
    pub const ALL: [ColorFeature; 5] = [
        ColorFeature::RgbPoint,
        ColorFeature::RgbMean,
        ColorFeature::LabPoint,
        ColorFeature::LabMean,
        ColorFeature::None,
    ];

    /// Prágr18's label: RGB-P, RGB-M, Lab-P, Lab-M, None.
    pub fn label(self) -> &'static str {
        match self {
            ColorFeature::None => "None",
            ColorFeature::RgbPoint => "RGB-P",
            ColorFeature::RgbMean => "RGB-M",
            ColorFeature::LabPoint => "Lab-P",
            ColorFeature::LabMean => "Lab-M",
        }
    }
}

/// The geometric part of a Prágr18 descriptor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GeomFeature {
    /// No geometry.
    None,
    /// The 4 height features.
    Height,
    /// The 4 shape features.
    Shape,
    /// The 3 orientation features.
    Orientation,
    /// All 11 ("Set").
    Set,
}

impl GeomFeature {
    /// All five, in the naming order of Prágr18's table.
    pub const ALL: [GeomFeature; 5] = [
        GeomFeature::Height,
        GeomFeature::Shape,
        GeomFeature::Orientation,
        GeomFeature::Set,
        GeomFeature::None,
    ];

    /// Prágr18's label: Height, Shape, Ori, Set, None.
    pub fn label(self) -> &'static str {
        match self {
            GeomFeature::None => "None",
            GeomFeature::Height => "Height",
            GeomFeature::Shape => "Shape",
            GeomFeature::Orientation => "Ori",
            GeomFeature::Set => "Set",
        }
    }
}

/// Neighbourhood radii of the Prágr18 features.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct C1Params {
    /// Radius of the colour mean, metres (Prágr18: 0.2).
    pub r_color: f64,
    /// Radius of the geometric neighbourhood, metres (Prágr18: 0.3).
    pub r_geom: f64,
}

impl Default for C1Params {
    fn default() -> Self {
        C1Params {
            r_color: 0.2,
            r_geom: 0.3,
        }
    }
}

/// Every Prágr18 feature of one cell; a part is `None` when it cannot be computed (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct C1Features {
    /// RGB of the cell (or the mean when the cell has no colour).
    pub rgb_point: Option<[f64; 3]>,
    /// Mean RGB within r_color.
    pub rgb_mean: Option<[f64; 3]>,
    /// Lab of the cell (or the mean).
    pub lab_point: Option<[f64; 3]>,
    /// Mean Lab within r_color.
    pub lab_mean: Option<[f64; 3]>,
    /// Height features.
    pub height: Option<[f64; 4]>,
    /// Shape features.
    pub shape: Option<[f64; 4]>,
    /// Orientation features.
    pub orientation: Option<[f64; 3]>,
}

impl C1Features {
    /// The descriptor (colour part, then geometric part); `None` when a requested part is
    /// missing or both parts are `None` (an empty descriptor).
    pub fn descriptor(&self, color: ColorFeature, geom: GeomFeature) -> Option<Vec<f64>> {
        let mut d = Vec::new();
        match color {
            ColorFeature::None => {}
            ColorFeature::RgbPoint => d.extend(self.rgb_point?),
            ColorFeature::RgbMean => d.extend(self.rgb_mean?),
            ColorFeature::LabPoint => d.extend(self.lab_point?),
            ColorFeature::LabMean => d.extend(self.lab_mean?),
        }
        match geom {
            GeomFeature::None => {}
            GeomFeature::Height => d.extend(self.height?),
            GeomFeature::Shape => d.extend(self.shape?),
            GeomFeature::Orientation => d.extend(self.orientation?),
            GeomFeature::Set => {
                d.extend(self.height?);
                d.extend(self.shape?);
                d.extend(self.orientation?);
            }
        }
        (!d.is_empty()).then_some(d)
    }
}

fn rgb01(c: strider_core::Rgb8) -> [f64; 3] {
    c.0.map(|v| v as f64 / 255.0)
}

fn lab01(c: strider_core::Rgb8) -> [f64; 3] {
    let l = rgb_to_lab(c);
    [l.l as f64 / 100.0, l.a as f64 / 128.0, l.b as f64 / 128.0]
}

/// Sorted eigenvalues and the eigenvector of the smallest of a 3 × 3 covariance.
fn eigen(cov: Matrix3<f64>) -> ([f64; 3], [f64; 3]) {
    let e = SymmetricEigen::new(cov);
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    let l = idx.map(|i| e.eigenvalues[i].max(0.0));
    let v = e.eigenvectors.column(idx[0]);
    (l, [v[0], v[1], v[2]])
}

/// Covariance of points given as offsets (x, y, z).
fn covariance(pts: &[[f64; 3]]) -> Matrix3<f64> {
    let n = pts.len() as f64;
    let mut m = [0.0; 3];
    for p in pts {
        for a in 0..3 {
            m[a] += p[a] / n;
        }
    }
    Matrix3::from_fn(|a, b| {
        pts.iter()
            .map(|p| (p[a] - m[a]) * (p[b] - m[b]))
            .sum::<f64>()
            / n
    })
}

/// Every Prágr18 feature of cell `c` of `map`.
pub fn c1_features(map: &ElevationMap, c: Cell, params: &C1Params) -> C1Features {
    let d = map.cell_size();
    let mut f = C1Features::default();
    // Colour.
    let disc_c = disc_offsets(params.r_color, d);
    let (mut srgb, mut slab, mut nc) = ([0.0; 3], [0.0; 3], 0usize);
    for &(di, dj) in &disc_c {
        if let Some(col) = map.color(Cell::new(c.i + di, c.j + dj)) {
            let (r, l) = (rgb01(col), lab01(col));
            for k in 0..3 {
                srgb[k] += r[k];
                slab[k] += l[k];
            }
            nc += 1;
        }
    }
    if nc > 0 {
        let n = nc as f64;
        f.rgb_mean = Some(srgb.map(|v| v / n));
        f.lab_mean = Some(slab.map(|v| v / n));
    }
    match map.color(c) {
        Some(col) => {
            f.rgb_point = Some(rgb01(col));
            f.lab_point = Some(lab01(col));
        }
        None => {
            f.rgb_point = f.rgb_mean;
            f.lab_point = f.lab_mean;
        }
    }
    // Geometry: the known cells of the r_geom disc.
    let Some(zc) = map.elevation(c).map(f64::from).filter(|z| z.is_finite()) else {
        return f;
    };
    let disc_g = disc_offsets(params.r_geom, d);
    let pts: Vec<[f64; 3]> = disc_g
        .iter()
        .filter_map(|&(di, dj)| {
            map.elevation(Cell::new(c.i + di, c.j + dj))
                .map(f64::from)
                .filter(|z| z.is_finite())
                .map(|z| [di as f64 * d, dj as f64 * d, z - zc])
        })
        .collect();
    if pts.is_empty() || 2 * pts.len() < disc_g.len() {
        return f;
    }
    let n = pts.len() as f64;
    let zs: Vec<f64> = pts.iter().map(|p| p[2] + zc).collect();
    let zmean = zs.iter().sum::<f64>() / n;
    let zstd = (zs.iter().map(|z| (z - zmean).powi(2)).sum::<f64>() / n).sqrt();
    let (zmin, zmax) = zs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &z| {
            (a.min(z), b.max(z))
        });
    f.height = Some([zc, zc - zmean, zstd, zmax - zmin].map(|v| 10.0 * v));
    let (l, _) = eigen(covariance(&pts));
    let [l1, l2, l3] = l;
    f.shape = Some(if l3 <= LAMBDA_EPS {
        [0.0, 0.0, 1.0, 0.0]
    } else {
        [l1 / l3, (l2 - l1) / l3, (l3 - l2) / l3, l1 / (l1 + l2 + l3)]
    });
    // Orientation: the plane through the 5 nearest known cells (3 × 3 window, nearest first).
    let mut near: Vec<(i32, [f64; 3])> = Vec::new();
    for dj in -1..=1 {
        for di in -1..=1 {
            if let Some(z) = map
                .elevation(Cell::new(c.i + di, c.j + dj))
                .map(f64::from)
                .filter(|z| z.is_finite())
            {
                near.push((di * di + dj * dj, [di as f64 * d, dj as f64 * d, z - zc]));
            }
        }
    }
    near.sort_by_key(|p| p.0);
    let near: Vec<[f64; 3]> = near.iter().take(5).map(|p| p.1).collect();
    let mut normal = [0.0, 0.0, 1.0];
    if near.len() >= 3 {
        let (l, v) = eigen(covariance(&near));
        // A unique normal needs the two larger eigenvalues apart from the smallest.
        if l[1] > 1e-9 * l[2].max(LAMBDA_EPS) && l[1] > LAMBDA_EPS {
            let s = if v[2] < 0.0 { -1.0 } else { 1.0 };
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if len > 0.0 && len.is_finite() {
                normal = v.map(|x| s * x / len);
            }
        }
    }
    f.orientation = Some(normal);
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::lattice_map;
    use strider_core::Rgb8;

    fn map() -> ElevationMap {
        lattice_map(0.05, 16)
    }

    #[test]
    fn flat_patch_ramp_and_degenerate_cases() {
        let mut m = map();
        let gray = Rgb8::new(128, 128, 128);
        for j in -10..=10 {
            for i in -10..=10 {
                m.set_cell(Cell::new(i, j), 0.0, 1e-4, gray);
            }
        }
        let f = c1_features(&m, Cell::new(0, 0), &C1Params::default());
        // Flat: λ1 = 0, λ2 = λ3 (a disc) → planar; normal up; heights 0.
        let s = f.shape.unwrap();
        assert!(s[0].abs() < 1e-9 && (s[1] - 1.0).abs() < 1e-6 && s[2].abs() < 1e-6);
        assert_eq!(f.orientation.unwrap(), [0.0, 0.0, 1.0]);
        assert_eq!(f.height.unwrap(), [0.0; 4]);
        assert!((f.rgb_point.unwrap()[0] - 128.0 / 255.0).abs() < 1e-12);
        let (p, q) = (f.rgb_point.unwrap(), f.rgb_mean.unwrap());
        assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-12));
        // Every combination of a known cell exists, except None × None.
        for c in ColorFeature::ALL {
            for g in GeomFeature::ALL {
                let d = f.descriptor(c, g);
                assert_eq!(
                    d.is_some(),
                    !(c == ColorFeature::None && g == GeomFeature::None)
                );
                assert!(d.unwrap_or_default().iter().all(|v| v.is_finite()));
            }
        }
        assert_eq!(
            f.descriptor(ColorFeature::LabMean, GeomFeature::Set)
                .unwrap()
                .len(),
            14
        );
        // A ramp z = 0.5 x: the normal tilts against +x.
        let mut r = map();
        for j in -10..=10 {
            for i in -10..=10 {
                r.set_cell(Cell::new(i, j), 0.5 * 0.05 * i as f32, 1e-4, gray);
            }
        }
        let n = c1_features(&r, Cell::new(0, 0), &C1Params::default())
            .orientation
            .unwrap();
        let want = [-0.5 / 1.25f64.sqrt(), 0.0, 1.0 / 1.25f64.sqrt()];
        for k in 0..3 {
            assert!((n[k] - want[k]).abs() < 1e-6, "{n:?}");
        }
        // A lone cell: λ3 = 0 would be degenerate but the half-known rule removes geometry;
        // its colour is there.
        let mut lone = map();
        lone.set_cell(Cell::new(0, 0), 0.1, 1e-4, gray);
        let f = c1_features(&lone, Cell::new(0, 0), &C1Params::default());
        assert!(f.shape.is_none() && f.height.is_none() && f.rgb_point.is_some());
        // With r_geom below a cell the disc is the cell alone: λ3 = 0 → (0, 0, 1, 0).
        let f = c1_features(
            &lone,
            Cell::new(0, 0),
            &C1Params {
                r_color: 0.2,
                r_geom: 0.01,
            },
        );
        assert_eq!(f.shape.unwrap(), [0.0, 0.0, 1.0, 0.0]);
        assert_eq!(f.orientation.unwrap(), [0.0, 0.0, 1.0]);
        // Unknown cell: nothing.
        let f = c1_features(&lone, Cell::new(50, 50), &C1Params::default());
        assert_eq!(f, C1Features::default());
        assert_eq!(
            f.descriptor(ColorFeature::RgbPoint, GeomFeature::None),
            None
        );
    }
}
