//! Changes of the training set: insertion (one point or a block), removal, replacement and new
//! targets, each in O(n²), and the factorisation with its jitter ladder behind them.

use faer::Par;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use rayon::prelude::*;

use super::factor::dot;
use super::kernel::{k_of_r2, sq_dist};
use super::{Gp, GpError, JITTER_STEPS, PAR_MIN_N, check_point, check_y, scale_points};

impl Gp {
    /// Adds a training point in O(n²): one forward substitution extends L by a row and w by an
    /// entry. If the new pivot is not positive the jitter escalates and the factor is rebuilt
    /// (O(n³), rare); if that fails too, nothing changes and the error is returned.
    pub fn push(&mut self, x: &[f64], y: f64) -> Result<(), GpError> {
        self.check_dim(x)?;
        check_point(x, self.len())?;
        check_y(y, self.params.prior_mean, self.len())?;
        self.push_storage(x, y, 1.0)?;
        self.perm.push(self.len() - 1);
        Ok(())
    }

    /// Adds training points (`xs`: k × dim row-major, `ys`: k targets) in order, as k calls of
    /// [`Gp::push`] would, but with one blocked triangular solve V = L⁻¹K(X, X_new) for all of
    /// them (compute-bound, where k separate forward substitutions each stream L through
    /// memory) and a k × k Cholesky of the Schur complement for their own rows. A point whose
    /// pivot is not positive, and every later one, goes through [`Gp::push`] (jitter
    /// escalation). Atomic: on a bad point or length, or when even the jitter ladder cannot
    /// make a point fit, nothing changes (callers keep their own index of the points).
    pub fn extend(&mut self, xs: &[f64], ys: &[f64]) -> Result<(), GpError> {
        let (d, n, k) = (self.dim, self.len(), ys.len());
        if xs.len() != k * d {
            return Err(GpError::BadDimension(format!(
                "{} input values for {} targets of dimension {}",
                xs.len(),
                k,
                d
            )));
        }
        for (j, (x, &y)) in xs.chunks_exact(d).zip(ys).enumerate() {
            check_point(x, n + j)?;
            check_y(y, self.params.prior_mean, n + j)?;
        }
        if k == 0 {
            return Ok(());
        }
        let kind = self.params.kernel.kind;
        let s2 = self.params.kernel.signal_variance;
        let new_q = scale_points(xs, &self.inv_l);
        // V = L⁻¹ K(X, X_new), column-major n × k.
        let mut v = vec![0.0; n * k];
        if n > 0 {
            v.par_chunks_mut(n)
                .zip(new_q.par_chunks(d))
                .for_each(|(col, qj)| {
                    for (c, xi) in col.iter_mut().zip(self.xs.chunks_exact(d)) {
                        *c = k_of_r2(kind, s2, sq_dist(xi, qj));
                    }
                });
            let vm = faer::MatMut::from_column_major_slice_mut(&mut v, n, k);
            solve_lower_triangular_in_place(self.factor.view(), vm, Par::rayon(0));
        }
        // Rows of the new points, one at a time: row j = [V[:, j], L22[j, ..j]] and its pivot,
        // exactly the forward substitution a push would do.
        let sn2 = self.params.noise_variance;
        let min_pivot2 = self.min_pivot2();
        let mut l22: Vec<Vec<f64>> = Vec::with_capacity(k);
        for j in 0..k {
            let vj = &v[j * n..(j + 1) * n];
            let qj = &new_q[j * d..(j + 1) * d];
            let mut tail = Vec::with_capacity(j + 1);
            for (i, li) in l22.iter().enumerate() {
                let vi = &v[i * n..(i + 1) * n];
                let kij = k_of_r2(kind, s2, sq_dist(&new_q[i * d..(i + 1) * d], qj));
                let r = (kij - dot(vi, vj) - dot(&li[..i], &tail[..i])) / li[i];
                tail.push(r);
            }
            let pivot2 = s2 + sn2 + self.jitter - dot(vj, vj) - dot(&tail, &tail);
            if !(pivot2.is_finite() && pivot2 > min_pivot2) {
                // Commit the rows so far, then the rest one by one (jitter escalation). Rare:
                // the copy that keeps a failure atomic is affordable here.
                let saved = self.clone();
                self.commit_rows(&v, n, &l22, &xs[..j * d], &ys[..j], &new_q[..j * d]);
                for (x, &y) in xs[j * d..].chunks_exact(d).zip(&ys[j..]) {
                    if let Err(e) = self.push(x, y) {
                        *self = saved;
                        return Err(e);
                    }
                }
                return Ok(());
            }
            tail.push(pivot2.sqrt());
            l22.push(tail);
        }
        self.commit_rows(&v, n, &l22, xs, ys, &new_q);
        Ok(())
    }

    /// Appends the rows computed by [`Gp::extend`] (V's columns and L22's rows) with their
    /// points, extending w by forward substitution.
    fn commit_rows(
        &mut self,
        v: &[f64],
        n: usize,
        l22: &[Vec<f64>],
        xs: &[f64],
        ys: &[f64],
        new_q: &[f64],
    ) {
        let m = self.params.prior_mean;
        let mut row = Vec::with_capacity(n + l22.len());
        for (j, (lj, &y)) in l22.iter().zip(ys).enumerate() {
            row.clear();
            row.extend_from_slice(&v[j * n..(j + 1) * n]);
            row.extend_from_slice(&lj[..j]);
            let piv = lj[j];
            let wn = (y - m - dot(&row, &self.w)) / piv;
            self.factor.push_row(&row, piv);
            self.w.push(wn);
            self.y.push(y);
            self.psi.push(1.0);
            self.perm.push(self.len() - 1);
        }
        let k = l22.len();
        self.x.extend_from_slice(&xs[..k * self.dim]);
        self.xs.extend_from_slice(&new_q[..k * self.dim]);
    }

    /// Removes training point `i` in O(n²) (rank-1 update of the trailing block of L); the later
    /// indices shift down by one.
    pub fn remove(&mut self, i: usize) -> Result<(), GpError> {
        self.check_index(i)?;
        let p = self.perm.remove(i);
        for q in &mut self.perm {
            if *q > p {
                *q -= 1;
            }
        }
        self.remove_storage(p);
        Ok(())
    }

    /// Replaces training point `i` (same index afterwards). A change of `y` alone is
    /// [`Gp::set_y`]; otherwise a removal and an insertion, O(n²) together. On error nothing
    /// changes.
    pub fn replace(&mut self, i: usize, x: &[f64], y: f64) -> Result<(), GpError> {
        self.check_index(i)?;
        self.check_dim(x)?;
        check_point(x, i)?;
        check_y(y, self.params.prior_mean, i)?;
        if self.x(i) == x {
            return self.set_y(i, y);
        }
        let p = self.perm[i];
        let old_x = self.x(i).to_vec();
        let old_y = self.y[p];
        let psi = self.psi[p];
        for q in &mut self.perm {
            if *q > p {
                *q -= 1;
            }
        }
        self.remove_storage(p);
        let last = self.len();
        match self.push_storage(x, y, psi) {
            Ok(()) => {
                self.perm[i] = last;
                Ok(())
            }
            Err(e) => {
                // Put the old point back (it fitted before, with the same jitter).
                self.push_storage(&old_x, old_y, psi)?;
                self.perm[i] = last;
                Err(e)
            }
        }
    }

    /// Changes the target of training point `i`: L stays, w is re-solved from that row on
    /// (O((n − row)²), no kernel evaluations).
    pub fn set_y(&mut self, i: usize, y: f64) -> Result<(), GpError> {
        self.check_index(i)?;
        check_y(y, self.params.prior_mean, i)?;
        let p = self.perm[i];
        self.y[p] = y;
        self.resolve_w_from(p);
        Ok(())
    }

    /// Changes the targets of several training points at once: L stays, w is re-solved once
    /// from the lowest storage row touched (one O(n²) solve instead of one per point). Atomic:
    /// on an invalid index or target nothing changes.
    pub fn set_ys(&mut self, changes: &[(usize, f64)]) -> Result<(), GpError> {
        for &(i, y) in changes {
            self.check_index(i)?;
            check_y(y, self.params.prior_mean, i)?;
        }
        let mut lowest = usize::MAX;
        for &(i, y) in changes {
            let p = self.perm[i];
            self.y[p] = y;
            lowest = lowest.min(p);
        }
        if lowest != usize::MAX {
            self.resolve_w_from(lowest);
        }
        Ok(())
    }

    /// Builds and factorises K + (σ_n² + jitter) I for the stored points, trying the jitter
    /// ladder from step `from`. `self.factor.n` must already be the point count. On failure the
    /// jitter is left at the last value tried and the factor is garbage (callers restore).
    pub(super) fn refactor(&mut self, from: usize) -> Result<(), GpError> {
        let n = self.len();
        let s2 = self.params.kernel.signal_variance;
        let par = if n >= PAR_MIN_N {
            Par::rayon(0)
        } else {
            Par::Seq
        };
        for &step in &JITTER_STEPS[from..] {
            self.jitter = step * s2;
            self.fill_kernel_matrix();
            if self.factor.factorize(self.min_pivot2(), par) {
                self.resolve_w_from(0);
                return Ok(());
            }
        }
        Err(GpError::NotPositiveDefinite {
            jitter: self.jitter,
        })
    }

    /// Writes the lower triangle of K + σ_n² Ψ + jitter I into the factor, columns in parallel.
    fn fill_kernel_matrix(&mut self) {
        let n = self.len();
        let d = self.dim;
        let kind = self.params.kernel.kind;
        let s2 = self.params.kernel.signal_variance;
        let (sn2, jitter) = (self.params.noise_variance, self.jitter);
        let ld = self.factor.ld;
        let xs = &self.xs;
        let psi = &self.psi;
        self.factor.n = n;
        if n == 0 {
            return;
        }
        self.factor.data[..n * ld]
            .par_chunks_mut(ld)
            .enumerate()
            .for_each(|(j, col)| {
                let xj = &xs[j * d..(j + 1) * d];
                col[j] = s2 + sn2 * psi[j] + jitter;
                for (i, c) in col[j + 1..n].iter_mut().enumerate() {
                    let i = i + j + 1;
                    *c = k_of_r2(kind, s2, sq_dist(&xs[i * d..(i + 1) * d], xj));
                }
            });
    }

    /// w[p..] = L⁻¹(y − m) from row p on (rows before p are unchanged).
    fn resolve_w_from(&mut self, p: usize) {
        let n = self.len();
        let m = self.params.prior_mean;
        self.w.resize(n, 0.0);
        for k in p..n {
            self.w[k] = self.y[k] - m;
        }
        self.factor.forward_solve_from(&mut self.w, p);
    }

    /// Appends a (checked) point with noise multiplier `psi` as the last storage row; atomic on
    /// error.
    fn push_storage(&mut self, x: &[f64], y: f64, psi: f64) -> Result<(), GpError> {
        let n = self.len();
        let d = self.dim;
        let kind = self.params.kernel.kind;
        let s2 = self.params.kernel.signal_variance;
        let xq = scale_points(x, &self.inv_l);
        let mut row: Vec<f64> = self
            .xs
            .chunks_exact(d)
            .map(|xi| k_of_r2(kind, s2, sq_dist(xi, &xq)))
            .collect();
        self.factor.forward_solve_from(&mut row, 0);
        let pivot2 =
            self.params.kernel.signal_variance + self.params.noise_variance * psi + self.jitter
                - dot(&row, &row);
        if pivot2.is_finite() && pivot2 > self.min_pivot2() {
            let piv = pivot2.sqrt();
            let wn = (y - self.params.prior_mean - dot(&row, &self.w)) / piv;
            self.factor.push_row(&row, piv);
            self.x.extend_from_slice(x);
            self.xs.extend_from_slice(&xq);
            self.y.push(y);
            self.psi.push(psi);
            self.w.push(wn);
            return Ok(());
        }
        // Escalate the jitter and rebuild (rare): keep the old state to restore on failure.
        let saved = (self.factor.clone(), self.w.clone(), self.jitter);
        self.x.extend_from_slice(x);
        self.xs.extend_from_slice(&xq);
        self.y.push(y);
        self.psi.push(psi);
        self.factor.reserve_one();
        self.factor.n = n + 1;
        let from = JITTER_STEPS
            .iter()
            .position(|&s| s * s2 > self.jitter)
            .unwrap_or(JITTER_STEPS.len());
        match self.refactor(from) {
            Ok(()) => Ok(()),
            Err(e) => {
                self.x.truncate(n * d);
                self.xs.truncate(n * d);
                self.y.truncate(n);
                self.psi.truncate(n);
                (self.factor, self.w, self.jitter) = saved;
                Err(e)
            }
        }
    }

    fn remove_storage(&mut self, p: usize) {
        let d = self.dim;
        self.factor.remove(p);
        self.x.drain(p * d..(p + 1) * d);
        self.xs.drain(p * d..(p + 1) * d);
        self.y.remove(p);
        self.psi.remove(p);
        self.w.truncate(p);
        self.resolve_w_from(p);
    }
}
