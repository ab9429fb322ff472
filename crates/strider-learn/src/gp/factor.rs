//! The lower Cholesky factor L of K + (σ_n² + jitter) I, stored column-major with spare
//! capacity (leading dimension ld ≥ n) so that a new training point appends one row (O(n²))
//! without moving the others, and faer works on the buffer in place.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{
    LltRegularization, cholesky_in_place, cholesky_in_place_scratch,
};
use faer::{MatMut, MatRef, Par};

/// Column-major lower-triangular n×n matrix inside an ld×ld buffer; L[i][j] = `data[j * ld + i]`
/// for i ≥ j. Entries above the diagonal are unspecified.
#[derive(Clone, Debug, Default)]
pub(crate) struct Factor {
    pub n: usize,
    pub ld: usize,
    pub data: Vec<f64>,
}

impl Factor {
    /// An empty factor with room for `cap` rows and columns.
    pub fn with_capacity(cap: usize) -> Factor {
        Factor {
            n: 0,
            ld: cap,
            data: vec![0.0; cap * cap],
        }
    }

    /// L[i][j].
    #[cfg(test)]
    #[inline]
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.data[j * self.ld + i]
    }

    /// Column j from the diagonal down: L[j..n][j].
    #[inline]
    pub fn col_below(&self, j: usize) -> &[f64] {
        &self.data[j * self.ld + j..j * self.ld + self.n]
    }

    #[inline]
    pub fn diag(&self, i: usize) -> f64 {
        self.data[i * self.ld + i]
    }

    fn len(&self) -> usize {
        if self.n == 0 {
            0
        } else {
            (self.n - 1) * self.ld + self.n
        }
    }

    /// A faer view of L (column-major, column stride ld).
    pub fn view(&self) -> MatRef<'_, f64> {
        let len = self.len();
        MatRef::from_column_major_slice_with_stride(&self.data[..len], self.n, self.n, self.ld)
    }

    fn view_mut(&mut self) -> MatMut<'_, f64> {
        let len = self.len();
        MatMut::from_column_major_slice_with_stride_mut(
            &mut self.data[..len],
            self.n,
            self.n,
            self.ld,
        )
    }

    /// Makes room for at least one more row and column (grows by a quarter, at least 32).
    pub fn reserve_one(&mut self) {
        if self.n < self.ld {
            return;
        }
        let new_ld = self.ld + (self.ld / 4).max(32);
        let mut data = vec![0.0; new_ld * new_ld];
        for j in 0..self.n {
            data[j * new_ld + j..j * new_ld + self.n].copy_from_slice(self.col_below(j));
        }
        self.data = data;
        self.ld = new_ld;
    }

    /// Factorises in place (blocked faer Cholesky on the lower triangle, which the caller has
    /// filled with K + (σ_n² + jitter) I). False if a pivot² is not above `min_pivot2`.
    pub fn factorize(&mut self, min_pivot2: f64, par: Par) -> bool {
        let n = self.n;
        let mut buf = MemBuffer::new(cholesky_in_place_scratch::<f64>(n, par, Default::default()));
        let ok = cholesky_in_place(
            self.view_mut(),
            LltRegularization::default(),
            par,
            MemStack::new(&mut buf),
            Default::default(),
        )
        .is_ok();
        ok && (0..n).all(|i| {
            let d = self.diag(i);
            d.is_finite() && d * d > min_pivot2
        })
    }

    /// Solves L[..m, ..m] v = b in place, m = b.len() ≤ n, column by column (contiguous axpys).
    /// `b[..start]` must already be solved; the rows from `start` on hold the right-hand side.
    /// The solve streams the whole of L through memory once, so at large n it is bound by memory
    /// bandwidth (measured: splitting the updates over two rayon tasks made it slower here).
    pub fn forward_solve_from(&self, b: &mut [f64], start: usize) {
        let m = b.len();
        debug_assert!(m <= self.n);
        // Contributions of the solved head to the tail.
        if start > 0 && start < m {
            let (head, tail) = b.split_at_mut(start);
            self.update_rows(tail, start, head, 0);
        }
        let mut j0 = start;
        while j0 < m {
            let j1 = (j0 + SOLVE_BLOCK).min(m);
            // Solve the diagonal block.
            for j in j0..j1 {
                let col = &self.data[j * self.ld + j..j * self.ld + j1];
                let v = b[j] / col[0];
                b[j] = v;
                axpy(&mut b[j + 1..j1], -v, &col[1..]);
            }
            // Update the rows below with the block's columns.
            if j1 < m {
                let (head, tail) = b.split_at_mut(j1);
                self.update_rows(tail, j1, &head[j0..j1], j0);
            }
            j0 = j1;
        }
    }

    /// tail[r] −= Σ_k L[row0 + r][col0 + k] · v[k] (column axpys).
    fn update_rows(&self, tail: &mut [f64], row0: usize, v: &[f64], col0: usize) {
        let rows = tail.len();
        for (k, &vk) in v.iter().enumerate() {
            let base = (col0 + k) * self.ld + row0;
            axpy(tail, -vk, &self.data[base..base + rows]);
        }
    }

    /// Appends row and column n: `row` holds L⁻¹k for the new point (length n), `diag` the pivot.
    pub fn push_row(&mut self, row: &[f64], diag: f64) {
        self.reserve_one();
        let n = self.n;
        let ld = self.ld;
        for (j, v) in row.iter().enumerate() {
            self.data[j * ld + n] = *v;
        }
        self.data[n * ld + n] = diag;
        self.n += 1;
    }

    /// Deletes row and column p: the trailing block L₃₃ becomes the factor of
    /// L₃₃L₃₃ᵀ + l₃₂l₃₂ᵀ (a rank-1 update, always stable), then rows and columns after p move up
    /// and left by one.
    pub fn remove(&mut self, p: usize) {
        let n = self.n;
        let ld = self.ld;
        debug_assert!(p < n);
        let mut x: Vec<f64> = self.data[p * ld + p + 1..p * ld + n].to_vec();
        // Rank-1 update of L[p+1.., p+1..] with x, column by column (in place).
        for (kk, k) in (p + 1..n).enumerate() {
            let col = &mut self.data[k * ld + k..k * ld + n];
            let d = col[0];
            let xk = x[kk];
            let r = d.hypot(xk);
            let c = r / d;
            let s = xk / d;
            col[0] = r;
            let xt = &mut x[kk + 1..];
            for (l, xv) in col[1..].iter_mut().zip(xt.iter_mut()) {
                let new = (*l + s * *xv) / c;
                *xv = c * *xv - s * new;
                *l = new;
            }
        }
        // Columns j < p: drop entry p (rows p+1..n move up).
        for j in 0..p {
            let base = j * ld;
            self.data.copy_within(base + p + 1..base + n, base + p);
        }
        // Columns j > p move left, dropping entry p.
        for j in p + 1..n {
            let src = j * ld;
            let dst = (j - 1) * ld;
            // rows j..n of column j → rows j-1..n-1 of column j-1
            self.data.copy_within(src + j..src + n, dst + j - 1);
        }
        self.n -= 1;
    }
}

/// Columns per block of a forward solve.
const SOLVE_BLOCK: usize = 128;

/// y += a · x (vectorises).
#[inline]
pub(crate) fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    for (yv, xv) in y.iter_mut().zip(x) {
        *yv += a * xv;
    }
}

/// Dot product with eight accumulators (vectorises; fixed order, so deterministic).
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 8];
    let chunks = n / 8;
    for c in 0..chunks {
        let (pa, pb) = (&a[c * 8..c * 8 + 8], &b[c * 8..c * 8 + 8]);
        for k in 0..8 {
            acc[k] += pa[k] * pb[k];
        }
    }
    let mut s = ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
    for k in chunks * 8..n {
        s += a[k] * b[k];
    }
    s
}
