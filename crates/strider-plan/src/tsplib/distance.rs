//! TSPLIB's distance functions of coordinates, exactly as the library defines them.

use super::header::WeightType;

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
            (RRR * (0.5 * ((1.0 + q1) * q2 - (1.0 - q1) * q3)).acos() + 1.0) as i64
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

/// The full matrix of `kind` distances between the first `n` of `coords` (row-major, zero
/// diagonal).
pub(super) fn coordinate_matrix(kind: WeightType, coords: &[(f64, f64)], n: usize) -> Vec<i64> {
    let mut m = vec![0i64; n * n];
    for i in 0..n {
        for j in 0..n {
            if i != j {
                m[i * n + j] = coord_distance(kind, coords[i], coords[j]);
            }
        }
    }
    m
}
