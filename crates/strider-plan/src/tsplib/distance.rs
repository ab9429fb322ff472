//! TSPLIB's distance functions of coordinates, exactly as the library defines them.

use super::TsplibError;
use super::header::WeightType;
use crate::gtsp::MAX_TOUR_COST;

/// TSPLIB `nint`.
fn nint(x: f64) -> i64 {
    (x + 0.5).floor() as i64
}

/// Geographic latitude/longitude in radians from TSPLIB's `DDD.MM` format.
fn geo_radians(x: f64) -> f64 {
    // TSPLIB's truncated value, not std::f64::consts::PI.
    #[allow(clippy::approx_constant)]
    const PI: f64 = 3.141592;
    let deg = x.trunc();
    let min = x - deg;
    PI * (deg + 5.0 * min / 3.0) / 180.0
}

fn coord_distance(kind: WeightType, a: (f64, f64), b: (f64, f64)) -> i64 {
    let dx = a.0 - b.0;
    let dy = a.1 - b.1;
    match kind {
        WeightType::Euc2d => nint((dx * dx + dy * dy).sqrt()),
        WeightType::Ceil2d => (dx * dx + dy * dy).sqrt().ceil() as i64,
        WeightType::Att => {
            let r = ((dx * dx + dy * dy) / 10.0).sqrt();
            let t = nint(r);
            if (t as f64) < r { t + 1 } else { t }
        }
        WeightType::Geo => {
            const RRR: f64 = 6378.388;
            let (lat_i, lon_i) = (geo_radians(a.0), geo_radians(a.1));
            let (lat_j, lon_j) = (geo_radians(b.0), geo_radians(b.1));
            let q1 = (lon_i - lon_j).cos();
            let q2 = (lat_i - lat_j).cos();
            let q3 = (lat_i + lat_j).cos();
            // Rounding can push the cosine just outside [-1, 1], where acos is NaN.
            let cos = (0.5 * ((1.0 + q1) * q2 - (1.0 - q1) * q3)).clamp(-1.0, 1.0);
            (RRR * cos.acos() + 1.0) as i64
        }
        WeightType::Explicit => unreachable!("explicit weights have no coordinates"),
    }
}

/// TSPLIB distance between two points for `EDGE_WEIGHT_TYPE` `kind`
/// (`"EUC_2D"`, `"CEIL_2D"`, `"ATT"`, `"GEO"`). Returns `None` for other kinds.
pub fn tsplib_distance(kind: &str, a: (f64, f64), b: (f64, f64)) -> Option<i64> {
    match WeightType::from_name(kind)? {
        WeightType::Explicit => None,
        k => Some(coord_distance(k, a, b)),
    }
}

/// An upper bound of every `kind` distance between points of `coords`, from their bounding
/// box (+inf when the box is too wide for `f64`).
fn distance_bound(kind: WeightType, coords: &[(f64, f64)]) -> f64 {
    let (mut lo, mut hi) = (
        (f64::INFINITY, f64::INFINITY),
        (f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for &(x, y) in coords {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    let diagonal = (hi.0 - lo.0).hypot(hi.1 - lo.1);
    match kind {
        // Half the earth's circumference at TSPLIB's radius, plus the +1 of its formula.
        WeightType::Geo => 6378.388 * std::f64::consts::PI + 1.0,
        WeightType::Att => (diagonal / 10f64.sqrt()).ceil() + 1.0,
        _ => diagonal.ceil() + 1.0,
    }
}

/// The full matrix of `kind` distances between the first `n` of `coords` (row-major, zero
/// diagonal). Refused when the coordinates are so far apart that a tour of `n` vertices could
/// cost more than [`MAX_TOUR_COST`].
pub(super) fn coordinate_matrix(
    kind: WeightType,
    coords: &[(f64, f64)],
    n: usize,
) -> Result<Vec<i64>, TsplibError> {
    let bound = distance_bound(kind, &coords[..n]);
    let worst = bound * n as f64;
    if worst.is_nan() || worst > MAX_TOUR_COST as f64 {
        return Err(TsplibError::CostTooLarge {
            what: format!(
                "{} distances between these coordinates reach {bound:.3e} (across their \
                 bounding box)",
                kind.name()
            ),
            n,
            limit: MAX_TOUR_COST,
        });
    }
    let mut m = vec![0i64; n * n];
    for i in 0..n {
        for j in 0..n {
            if i != j {
                m[i * n + j] = coord_distance(kind, coords[i], coords[j]);
            }
        }
    }
    Ok(m)
}
