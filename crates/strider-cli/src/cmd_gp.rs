//! `strider gp predict`: exact GP regression on CSV files (fixed hyperparameters), with in-process
//! timings for side-by-side benchmarks (`bench/gp_vs_sklearn.py`).

use std::fs;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde_json::json;
use strider_learn::gp::{Gp, GpParams, Kernel, KernelKind};
use strider_learn::gp_csv::{self, CsvError, MAX_TRAIN_ROWS, Table};

use crate::args::PredictArgs;
use crate::ranges::{check_non_negative, check_positive, show};

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

/// Reads a CSV table; errors name the file.
fn read_table(path: &Path) -> Result<Table> {
    gp_csv::read(path).map_err(|e| match e {
        CsvError::Io { .. } | CsvError::FileTooLarge { .. } => anyhow::Error::new(e),
        e => anyhow::Error::new(e).context(path.display().to_string()),
    })
}

/// Checks the hyperparameter flags, naming the flag of a bad value.
fn check_hyperparameters(o: &PredictOptions) -> Result<()> {
    let flag = |name: &str, v: f64, check: fn(f64) -> Result<f64, String>| {
        check(v).map_err(|e| anyhow::anyhow!("--{name} {}: {e}", show(v)))
    };
    flag("lengthscale", o.lengthscale, check_positive)?;
    flag("signal-variance", o.signal_variance, check_positive)?;
    flag("noise-variance", o.noise_variance, check_non_negative)?;
    if !o.prior_mean.is_finite() {
        bail!(
            "--prior-mean {}: must be a finite number",
            show(o.prior_mean)
        );
    }
    Ok(())
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
    check_hyperparameters(o)?;
    let train = read_table(o.train)?;
    if train.rows > MAX_TRAIN_ROWS {
        bail!(
            "{}: {} training rows, more than an exact GP fit takes ({MAX_TRAIN_ROWS}, \
             MAX_TRAIN_ROWS: an n × n factor and O(n³) time): subsample the training data",
            o.train.display(),
            train.rows
        );
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn options<'a>(train: &'a Path, query: &'a Path, out: &'a Path) -> PredictOptions<'a> {
        PredictOptions {
            train,
            query,
            kernel: "se",
            lengthscale: 0.4,
            signal_variance: 1.0,
            noise_variance: 0.25,
            prior_mean: 0.0,
            out,
            timing_json: None,
        }
    }

    #[test]
    fn training_sets_beyond_the_exact_fit_limit_are_refused_before_fitting() {
        let dir = std::env::temp_dir().join(format!("strider-gp-rows-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let (train, query, out) = (dir.join("t.csv"), dir.join("q.csv"), dir.join("o.csv"));
        let rows: String = (0..=MAX_TRAIN_ROWS).map(|i| format!("{i},1\n")).collect();
        fs::write(&train, format!("x,y\n{rows}")).unwrap();
        fs::write(&query, "x\n0.5\n").unwrap();
        let e = format!(
            "{:#}",
            predict_with(&options(&train, &query, &out)).unwrap_err()
        );
        assert!(
            e.ends_with(
                "t.csv: 10001 training rows, more than an exact GP fit takes (10000, \
                 MAX_TRAIN_ROWS: an n × n factor and O(n³) time): subsample the training data"
            ),
            "{e}"
        );
        assert!(!out.exists());
        let _ = fs::remove_dir_all(dir);
    }

    #[test]
    fn hyperparameters_out_of_range_name_the_flag() {
        let p = Path::new("unused.csv");
        let mut o = options(p, p, p);
        o.lengthscale = -1.0;
        assert_eq!(
            check_hyperparameters(&o).unwrap_err().to_string(),
            "--lengthscale -1: must be a finite number > 0"
        );
        o.lengthscale = 1.0;
        o.signal_variance = f64::NAN;
        assert_eq!(
            check_hyperparameters(&o).unwrap_err().to_string(),
            "--signal-variance NaN: must be a finite number > 0"
        );
        o.signal_variance = 1.0;
        o.noise_variance = -0.5;
        assert_eq!(
            check_hyperparameters(&o).unwrap_err().to_string(),
            "--noise-variance -0.5: must be a finite number ≥ 0"
        );
        o.noise_variance = 0.0;
        o.prior_mean = f64::INFINITY;
        assert_eq!(
            check_hyperparameters(&o).unwrap_err().to_string(),
            "--prior-mean inf: must be a finite number"
        );
    }
}
