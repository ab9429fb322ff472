//! The clustering of the observed values (Nardi19 §IV-B): the bandwidth, 1-D mean-shift, the
//! selection of the modes that become components, and the responsibilities of Eq. 5.

use rayon::prelude::*;

use super::{MixtureError, MixtureParams, check_finite};

/// Silverman's rule of thumb for a Gaussian kernel density, h = 1.06 · s · n^(−1/5) with s the
/// sample standard deviation; for constant data a tiny positive bandwidth relative to the
/// value (any bandwidth then gives one cluster).
pub fn silverman_bandwidth(values: &[f64]) -> f64 {
    let n = values.len().max(1) as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    let h = 1.06 * var.sqrt() * n.powf(-0.2);
    h.max(1e-9 * (1.0 + mean.abs()))
}

/// One mode found by [`mean_shift_1d`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode {
    /// The centroid C_i (a local maximum of the kernel density).
    pub centroid: f64,
    /// Observations nearer to this centroid than to any other.
    pub members: usize,
}

/// Mean-shift clustering of 1-D values (Nardi19 §IV-B, Fukunaga & Hostetler) with a Gaussian
/// kernel of bandwidth `h`: seeds are the means of the occupied bins of width h, each climbs to
/// its density mode by x ← Σ w_j y_j / Σ w_j, w_j = exp(−(y_j − x)²/2h²); modes within h of a
/// denser mode merge into it. Returns the modes in ascending order with their member counts
/// (each value counted at its nearest mode). Empty input: no modes.
pub fn mean_shift_1d(values: &[f64], h: f64) -> Result<Vec<Mode>, MixtureError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(MixtureError::BadParameter(format!(
            "mean-shift bandwidth {h} is not a positive finite number"
        )));
    }
    check_finite("a clustered value", values)?;
    if values.is_empty() {
        return Ok(Vec::new());
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    // Bin seeding: one seed per occupied bin (the mean of its values).
    let mut seeds = Vec::new();
    let mut k = 0;
    while k < sorted.len() {
        let bin = (sorted[k] / h).floor();
        let start = k;
        while k < sorted.len() && (sorted[k] / h).floor() == bin {
            k += 1;
        }
        seeds.push(sorted[start..k].iter().sum::<f64>() / (k - start) as f64);
    }
    let inv2h2 = 1.0 / (2.0 * h * h);
    let density = |x: f64| -> (f64, f64) {
        // Only values within 5h matter (exp(−12.5) ≈ 4e-6): a window of the sorted values.
        let lo = sorted.partition_point(|v| *v < x - 5.0 * h);
        let hi = sorted.partition_point(|v| *v <= x + 5.0 * h);
        let (mut sw, mut swy) = (0.0, 0.0);
        for &v in &sorted[lo..hi] {
            let w = (-(v - x) * (v - x) * inv2h2).exp();
            sw += w;
            swy += w * v;
        }
        (sw, swy)
    };
    let mut modes: Vec<(f64, f64)> = seeds
        .par_iter()
        .map(|&s| {
            let mut x = s;
            for _ in 0..500 {
                let (sw, swy) = density(x);
                if sw <= 0.0 {
                    break;
                }
                let nx = swy / sw;
                let done = (nx - x).abs() < 1e-6 * h;
                x = nx;
                if done {
                    break;
                }
            }
            (x, density(x).0)
        })
        .collect();
    // Densest first (ties: lower value), then suppress modes within h of a kept one.
    modes.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.total_cmp(&b.0)));
    let mut kept: Vec<f64> = Vec::new();
    for (x, _) in modes {
        if kept.iter().all(|c| (c - x).abs() >= h) {
            kept.push(x);
        }
    }
    kept.sort_by(f64::total_cmp);
    let mut members = vec![0usize; kept.len()];
    for &v in values {
        members[nearest(&kept, v)] += 1;
    }
    Ok(kept
        .into_iter()
        .zip(members)
        .map(|(centroid, members)| Mode { centroid, members })
        .collect())
}

/// Index of the centroid nearest to `v` (ties: the lower index).
pub(super) fn nearest(centroids: &[f64], v: f64) -> usize {
    let mut best = 0;
    for (i, c) in centroids.iter().enumerate() {
        if (c - v).abs() < (centroids[best] - v).abs() {
            best = i;
        }
    }
    best
}

/// Eq. 5 with decision 20: φ_i(y) = exp(−|y − C_i|/τ) / Σ_k exp(−|y − C_k|/τ) for every value
/// (row-major n × m, rows sum to 1). Computed relative to the nearest centroid, so it never
/// overflows or divides by zero.
pub fn responsibilities(y: &[f64], centroids: &[f64], tau: f64) -> Result<Vec<f64>, MixtureError> {
    if !(tau.is_finite() && tau > 0.0) {
        return Err(MixtureError::BadParameter(format!(
            "temperature {tau} is not a positive finite number"
        )));
    }
    if centroids.is_empty() {
        return Err(MixtureError::BadParameter("no centroids".into()));
    }
    check_finite("an observed value", y)?;
    check_finite("a centroid", centroids)?;
    let m = centroids.len();
    let mut out = vec![0.0; y.len() * m];
    for (row, &v) in out.chunks_exact_mut(m).zip(y) {
        let dmin = centroids
            .iter()
            .map(|c| (v - c).abs())
            .fold(f64::INFINITY, f64::min);
        let mut s = 0.0;
        for (r, c) in row.iter_mut().zip(centroids) {
            *r = (-((v - c).abs() - dmin) / tau).exp();
            s += *r;
        }
        for r in row.iter_mut() {
            *r /= s;
        }
    }
    Ok(out)
}

/// Keeps the modes with enough members (at least `min_cluster_size` and
/// `min_cluster_fraction` of the values), at most `max_components` of them (the most
/// populous), re-counting members after each drop; the centroids in ascending order. At least
/// one centroid always remains (the most populous mode).
pub(super) fn select_modes(modes: &[Mode], y: &[f64], params: &MixtureParams) -> Vec<f64> {
    let n = y.len();
    let need = params
        .min_cluster_size
        .max((params.min_cluster_fraction * n as f64).ceil() as usize);
    let mut cs: Vec<f64> = modes.iter().map(|m| m.centroid).collect();
    loop {
        let mut count = vec![0usize; cs.len()];
        for &v in y {
            count[nearest(&cs, v)] += 1;
        }
        // Drop the smallest offender (ties: the higher centroid) and recount.
        let too_many = cs.len() > params.max_components;
        let worst = (0..cs.len()).min_by(|&a, &b| count[a].cmp(&count[b]).then(b.cmp(&a)));
        match worst {
            Some(w) if cs.len() > 1 && (count[w] < need || too_many) => {
                cs.remove(w);
            }
            _ => break,
        }
    }
    cs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_shift_finds_separated_modes() {
        let mut y = Vec::new();
        for k in 0..30 {
            let e = (k as f64 * 0.37).sin() * 0.02;
            y.push(0.5 + e);
            y.push(2.5 + e);
            if k % 3 == 0 {
                y.push(4.0 + e);
            }
        }
        let modes = mean_shift_1d(&y, 0.2).unwrap();
        let cs: Vec<f64> = modes.iter().map(|m| m.centroid).collect();
        assert_eq!(cs.len(), 3, "{cs:?}");
        assert!((cs[0] - 0.5).abs() < 0.02 && (cs[1] - 2.5).abs() < 0.02);
        assert!((cs[2] - 4.0).abs() < 0.02);
        assert_eq!(modes.iter().map(|m| m.members).sum::<usize>(), y.len());
        assert_eq!(modes[2].members, 10);
    }

    #[test]
    fn mean_shift_rejects_bad_bandwidth_and_values() {
        assert!(mean_shift_1d(&[1.0], 0.0).is_err());
        assert!(mean_shift_1d(&[1.0], f64::NAN).is_err());
        assert!(mean_shift_1d(&[1.0, f64::INFINITY], 1.0).is_err());
        assert!(mean_shift_1d(&[], 1.0).unwrap().is_empty());
    }

    #[test]
    fn responsibilities_follow_eq5_with_the_minus_sign() {
        let phi = responsibilities(&[0.0, 1.0, 1e6], &[0.0, 1.0], 0.5).unwrap();
        // y = 0: exp(0) vs exp(−2).
        let e = (-2.0f64).exp();
        assert!((phi[0] - 1.0 / (1.0 + e)).abs() < 1e-12);
        assert!((phi[1] - e / (1.0 + e)).abs() < 1e-12);
        assert!((phi[2] - phi[1]).abs() < 1e-12 && (phi[3] - phi[0]).abs() < 1e-12);
        // Far away: finite and normalised, the nearer centroid wins.
        assert!(phi[4].is_finite() && phi[5] > phi[4]);
        assert!((phi[4] + phi[5] - 1.0).abs() < 1e-12);
        assert!(responsibilities(&[0.0], &[], 1.0).is_err());
        assert!(responsibilities(&[0.0], &[1.0], 0.0).is_err());
    }

    #[test]
    fn small_clusters_are_dropped() {
        let mut y = vec![1.0; 50];
        y.extend([5.0, 5.0]);
        let modes = mean_shift_1d(&y, 0.5).unwrap();
        assert_eq!(modes.len(), 2);
        let p = MixtureParams::default();
        assert_eq!(select_modes(&modes, &y, &p), vec![1.0]);
        let p = MixtureParams {
            min_cluster_size: 1,
            min_cluster_fraction: 0.0,
            ..MixtureParams::default()
        };
        assert_eq!(select_modes(&modes, &y, &p).len(), 2);
        let p = MixtureParams {
            max_components: 1,
            min_cluster_size: 1,
            min_cluster_fraction: 0.0,
            ..MixtureParams::default()
        };
        assert_eq!(select_modes(&modes, &y, &p), vec![1.0]);
    }
}
