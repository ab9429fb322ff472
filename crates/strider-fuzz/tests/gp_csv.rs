//! Fuzz target: the GP CSV reader and, on every accepted table small enough to fit, an exact GP
//! fit and prediction whose means and variances must be finite (variances ≥ 0).

use strider_fuzz::{CappedAlloc, Outcome, Text, config, fuzz};
use strider_learn::gp::{Gp, GpParams, Kernel, KernelKind};
use strider_learn::gp_csv::{Table, parse_bytes};

#[global_allocator]
static ALLOC: CappedAlloc = CappedAlloc::new();

const DICTIONARY: &[&str] = &["x", "y", "z", "roll", "cost", "NaN", "inf", "e", "E"];

const TWO_FEATURES: &str = "x1,x2,y\n0.0,0.0,1.0\n0.5,0.1,1.2\n1.0,0.4,1.9\n1.5,0.9,2.2\n";
const ONE_FEATURE: &str = "x,y\n-1,0.3\n0,0.1\n1,0.35\n2,1e-3\n3,-2.5e1\n";
const CRLF_SPACES: &str = "a , b , y\r\n 1 , 2 , 3 \r\n4,5,6\r\n";

/// Tables up to this many rows are fitted; larger ones only parse (a fit is O(n³)).
const FIT_ROWS: usize = 300;

fn check(input: &Text) -> Result<Outcome, String> {
    let table = match parse_bytes(&input.0) {
        Ok(t) => t,
        Err(e) => return Ok(Outcome::Rejected(e.to_string())),
    };
    if table.values.len() != table.rows * table.cols {
        return Err(format!(
            "{} values for {} rows × {} columns",
            table.values.len(),
            table.rows,
            table.cols
        ));
    }
    if let Some(v) = table.values.iter().find(|v| !v.is_finite()) {
        return Err(format!("an accepted table holds {v}"));
    }
    if table.cols < 2 || table.rows > FIT_ROWS {
        return Ok(Outcome::Accepted);
    }
    fit_and_predict(&table)
}

fn fit_and_predict(t: &Table) -> Result<Outcome, String> {
    let dim = t.cols - 1;
    let mut x = Vec::with_capacity(t.rows * dim);
    let mut y = Vec::with_capacity(t.rows);
    for row in t.values.chunks_exact(t.cols) {
        x.extend_from_slice(&row[..dim]);
        y.push(row[dim]);
    }
    let params = GpParams {
        kernel: Kernel {
            kind: KernelKind::SquaredExponential,
            lengthscales: vec![1.0],
            signal_variance: 1.0,
        },
        noise_variance: 0.01,
        prior_mean: 0.0,
    };
    let gp = match Gp::fit(dim, params, &x, &y) {
        Ok(gp) => gp,
        Err(e) => return Ok(Outcome::Rejected(e.to_string())),
    };
    let mut mean = vec![0.0; t.rows];
    let mut var = vec![0.0; t.rows];
    if let Err(e) = gp.predict_batch(&x, &mut mean, &mut var) {
        return Ok(Outcome::Rejected(e.to_string()));
    }
    let bad = mean
        .iter()
        .zip(&var)
        .position(|(m, v)| !(m.is_finite() && v.is_finite() && *v >= 0.0));
    match bad {
        Some(k) => Err(format!(
            "prediction {k}: mean {} variance {}",
            mean[k], var[k]
        )),
        None => Ok(Outcome::Accepted),
    }
}

#[test]
fn fuzz_gp_csv() {
    let seeds = [TWO_FEATURES, ONE_FEATURE, CRLF_SPACES]
        .iter()
        .map(|s| Text(s.as_bytes().to_vec()))
        .collect();
    fuzz(config!("gp_csv", 3000), &ALLOC, seeds, DICTIONARY, check);
}
