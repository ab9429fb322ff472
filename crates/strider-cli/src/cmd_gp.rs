//! `strider gp predict`: exact GP regression on CSV files (fixed hyperparameters), with in-process
//! timings for side-by-side benchmarks (`bench/gp_vs_sklearn.py`).

use std::fs;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde_json::json;
use strider_learn::gp::{Gp, GpParams, Kernel, KernelKind};

use crate::args::PredictArgs;

/// Options of `strider gp predict`.
struct PredictOptions<'a> {
    /// Training CSV: header, then rows of features followed by y.
    pub train: &'a Path,
    /// Query CSV: header, then rows of features.
    pub query: &'a Path,
    /// Kernel name: se, exp, matern32, matern52.
    pub kernel: &'a str,
    /// Isotropic lengthscale.
    pub lengthscale: f64,
    /// Signal variance σ_s².
    pub signal_variance: f64,
    /// Noise variance σ_n².
    pub noise_variance: f64,
    /// Prior mean.
    pub prior_mean: f64,
    /// Output CSV `mean,variance` (latent variance).
    pub out: &'a Path,
    /// Optional timing JSON.
    pub timing_json: Option<&'a Path>,
}

/// Parses a kernel name.
fn parse_kernel(s: &str) -> Result<KernelKind> {
    Ok(match s {
        "se" => KernelKind::SquaredExponential,
        "exp" => KernelKind::Exponential,
        "matern32" => KernelKind::Matern32,
        "matern52" => KernelKind::Matern52,
        _ => bail!("unknown --kernel {s:?}: use se, exp, matern32 or matern52"),
    })
}

/// A numeric CSV: the column count of its header and the values, row-major.
struct Table {
    cols: usize,
    rows: usize,
    values: Vec<f64>,
}

/// Reads a CSV with a header line and finite numbers in every field; errors name the file and
/// the line.
fn read_table(path: &Path) -> Result<Table> {
    let text =
        fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut lines = text.lines().enumerate();
    let cols = loop {
        match lines.next() {
            Some((_, l)) if l.trim().is_empty() => continue,
            Some((_, l)) => break l.split(',').count(),
            None => bail!("{}: empty file (a header line is expected)", path.display()),
        }
    };
    let mut values = Vec::new();
    let mut rows = 0;
    for (ln, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let mut count = 0;
        for field in line.split(',') {
            count += 1;
            if count > cols {
                break;
            }
            let f = field.trim();
            let v: f64 = f.parse().map_err(|_| {
                anyhow::anyhow!(
                    "{}: line {}: field {count} {f:?} is not a number",
                    path.display(),
                    ln + 1
                )
            })?;
            if !v.is_finite() {
                bail!(
                    "{}: line {}: field {count} is {f} (finite numbers only)",
                    path.display(),
                    ln + 1
                );
            }
            values.push(v);
        }
        let total = line.split(',').count();
        if total != cols {
            bail!(
                "{}: line {}: {total} columns, the header has {cols}",
                path.display(),
                ln + 1
            );
        }
        rows += 1;
    }
    Ok(Table { cols, rows, values })
}

/// Runs `strider gp predict`.
pub fn predict(a: &PredictArgs) -> Result<()> {
    predict_with(&PredictOptions {
        train: &a.train,
        query: &a.query,
        kernel: &a.kernel,
        lengthscale: a.lengthscale,
        signal_variance: a.signal_variance,
        noise_variance: a.noise_variance,
        prior_mean: a.prior_mean,
        out: &a.out,
        timing_json: a.timing_json.as_deref(),
    })
}

fn predict_with(o: &PredictOptions) -> Result<()> {
    let kind = parse_kernel(o.kernel)?;
    let train = read_table(o.train)?;
    let query = read_table(o.query)?;
    if train.cols < 2 {
        bail!(
            "{}: at least one feature column and the y column are needed",
            o.train.display()
        );
    }
    let dim = train.cols - 1;
    if query.cols != dim {
        bail!(
            "{}: {} feature columns, but the training file {} has {dim}",
            o.query.display(),
            query.cols,
            o.train.display()
        );
    }
    let mut x = Vec::with_capacity(train.rows * dim);
    let mut y = Vec::with_capacity(train.rows);
    for row in train.values.chunks_exact(train.cols) {
        x.extend_from_slice(&row[..dim]);
        y.push(row[dim]);
    }
    let params = GpParams {
        kernel: Kernel {
            kind,
            lengthscales: vec![o.lengthscale],
            signal_variance: o.signal_variance,
        },
        noise_variance: o.noise_variance,
        prior_mean: o.prior_mean,
    };
    let t0 = Instant::now();
    let gp = Gp::fit(dim, params, &x, &y)
        .with_context(|| format!("{}: cannot fit the GP", o.train.display()))?;
    let fit_s = t0.elapsed().as_secs_f64();
    let mut mean = vec![0.0; query.rows];
    let mut var = vec![0.0; query.rows];
    let t1 = Instant::now();
    gp.predict_batch(&query.values, &mut mean, &mut var)
        .with_context(|| format!("{}: cannot predict", o.query.display()))?;
    let predict_s = t1.elapsed().as_secs_f64();
    let mut out = String::with_capacity(query.rows * 50 + 16);
    out.push_str("mean,variance\n");
    for (m, v) in mean.iter().zip(&var) {
        // `{:e}` prints the shortest representation that round-trips: full precision.
        out.push_str(&format!("{m:e},{v:e}\n"));
    }
    fs::write(o.out, out).with_context(|| format!("cannot write {}", o.out.display()))?;
    if let Some(t) = o.timing_json {
        let j = json!({
            "n_train": train.rows,
            "n_query": query.rows,
            "fit_s": fit_s,
            "predict_s": predict_s,
        });
        fs::write(t, format!("{j}\n")).with_context(|| format!("cannot write {}", t.display()))?;
    }
    Ok(())
}
