//! Cost of one O(n²) insertion into an n = 2000 GP in d = 9 (target ≤ 2 ms), cold and warm,
//! next to a full O(n³) refit of the same 2000 points.
//!
//! ```sh
//! cargo bench -p strider-learn --bench gp_update
//! ```

use divan::Bencher;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_learn::gp::{Gp, GpParams};

const N: usize = 2000;
const D: usize = 9;

fn main() {
    divan::main();
}

/// Points on the 9-simplex (normalised uniforms), like colour-histogram descriptors.
fn data(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut x = Vec::with_capacity(n * D);
    let mut y = Vec::with_capacity(n);
    for _ in 0..n {
        let p: Vec<f64> = (0..D)
            .map(|_| -rng.random_range(1e-12..1.0f64).ln())
            .collect();
        let s: f64 = p.iter().sum();
        x.extend(p.iter().map(|v| v / s));
        y.push((6.0 * x[x.len() - D]).sin() + rng.random_range(-0.5..0.5));
    }
    (x, y)
}

/// One `push` onto a GP holding 1999 points (so the model has n = 2000 afterwards).
#[divan::bench(sample_count = 30, sample_size = 1)]
fn push_at_2000(bencher: Bencher) {
    let (x, y) = data(N);
    let base = Gp::fit(D, GpParams::default(), &x[..(N - 1) * D], &y[..N - 1]).unwrap();
    let last = &x[(N - 1) * D..];
    bencher
        .with_inputs(|| base.clone())
        .bench_local_refs(|gp| gp.push(last, y[N - 1]).unwrap());
}

/// One `push` (to n = 2000) and the removal of that last point (O(n): no trailing block) on one
/// model, as in a run where updates keep the factor warm in the last-level cache; the cold
/// variant above first clones the model (40 MB), which evicts it.
#[divan::bench(sample_count = 30, sample_size = 10)]
fn push_then_remove_last_at_2000(bencher: Bencher) {
    let (x, y) = data(N);
    let mut gp = Gp::fit(D, GpParams::default(), &x[..(N - 1) * D], &y[..N - 1]).unwrap();
    let last = &x[(N - 1) * D..];
    bencher.bench_local(|| {
        gp.push(last, y[N - 1]).unwrap();
        gp.remove(N - 1).unwrap();
    });
}

/// A batch `fit` of 2000 points.
#[divan::bench(sample_count = 10, sample_size = 1)]
fn fit_2000(bencher: Bencher) {
    let (x, y) = data(N);
    bencher.bench(|| Gp::fit(D, GpParams::default(), &x, &y).unwrap());
}
