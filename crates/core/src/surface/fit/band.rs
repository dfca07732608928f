//! The normal equations of a part's fit: a symmetric positive definite
//! band matrix (a point touches the four sections around its foot, the
//! smoothness three), factored by Cholesky with no fill outside the band.

use crate::geom::linalg::dot;
use crate::geom::math::Real;

/// A symmetric positive definite band matrix, its lower band stored by
/// rows (`bw` below the diagonal), factored in place by Cholesky.
pub(super) struct Band {
    n: usize,
    bw: usize,
    a: Vec<Real>,
    /// A consecutive row's values ([`Band::add_outer`]), copied out of its
    /// (index, value) pairs so that the inner loop runs over plain numbers.
    dense: Vec<Real>,
}

impl Band {
    pub(super) fn new(n: usize, bw: usize) -> Band {
        Band {
            n,
            bw,
            a: vec![0.0; n * (bw + 1)],
            dense: Vec::new(),
        }
    }

    #[inline]
    pub(super) fn at(&mut self, i: usize, j: usize) -> &mut Real {
        debug_assert!(j <= i && i - j <= self.bw);
        &mut self.a[i * (self.bw + 1) + self.bw + j - i]
    }

    #[inline]
    pub(super) fn get(&self, i: usize, j: usize) -> Real {
        self.a[i * (self.bw + 1) + self.bw + j - i]
    }

    /// Adds `w · r rᵀ` for a sparse row `r` (indices ascending). A row of
    /// consecutive indices (a point's: the sections around its foot, each
    /// with its coefficients in order) is added a stored row at a time.
    pub(super) fn add_outer(&mut self, row: &[(usize, Real)], w: Real) {
        let Some(&(i0, _)) = row.first() else {
            return;
        };
        let consecutive = row.iter().enumerate().all(|(k, &(i, _))| i == i0 + k);
        if !consecutive {
            for (p, &(i, ri)) in row.iter().enumerate() {
                for &(j, rj) in &row[..=p] {
                    *self.at(i, j) += w * ri * rj;
                }
            }
            return;
        }
        debug_assert!(row.len() <= self.bw + 1 && i0 + row.len() <= self.n);
        self.dense.clear();
        self.dense.extend(row.iter().map(|&(_, r)| r));
        for (p, &ri) in self.dense.iter().enumerate() {
            // Entries (i, i0) ..= (i, i) of the band, stored in order.
            let start = (i0 + p) * (self.bw + 1) + self.bw - p;
            let wi = w * ri;
            for (a, &rj) in self.a[start..=start + p].iter_mut().zip(&self.dense[..=p]) {
                *a += wi * rj;
            }
        }
    }

    /// Solves `A x = b` (`A` factored in place); `None` unless positive definite.
    pub(super) fn solve(mut self, mut b: Vec<Real>) -> Option<Vec<Real>> {
        let (n, bw) = (self.n, self.bw);
        let stride = bw + 1;
        // Row `i` holds columns `i - bw ..= i` at `i * stride ..`: the sums
        // over `k` below are dot products of two rows' stored runs.
        let run =
            |i: usize, k0: usize, k1: usize| i * stride + bw + k0 - i..i * stride + bw + k1 - i;
        for j in 0..n {
            let lo = j.saturating_sub(bw);
            let row_j = run(j, lo, j);
            let d = self.get(j, j) - dot(&self.a[row_j.clone()], &self.a[row_j]);
            if !(d > 0.0) {
                return None;
            }
            let d = d.sqrt();
            *self.at(j, j) = d;
            for i in j + 1..(j + bw + 1).min(n) {
                let k0 = i.saturating_sub(bw);
                let x = self.get(i, j) - dot(&self.a[run(i, k0, j)], &self.a[run(j, k0, j)]);
                *self.at(i, j) = x / d;
            }
        }
        for i in 0..n {
            let mut x = b[i];
            for k in i.saturating_sub(bw)..i {
                x -= self.get(i, k) * b[k];
            }
            b[i] = x / self.get(i, i);
        }
        for i in (0..n).rev() {
            let mut x = b[i];
            for k in i + 1..(i + bw + 1).min(n) {
                x -= self.get(k, i) * b[k];
            }
            b[i] = x / self.get(i, i);
        }
        Some(b)
    }
}
