//! Small dense linear algebra: the few factorizations the core needs, on
//! row-major `Vec<Real>` matrices. Sizes here are tiny (a (2J+1)² Gram matrix,
//! a K×K skinning system), so plain loops beat a general library.

use crate::geom::math::{Point2, Point3, Real, Vec2, Vec3};

/// `Σ a_i b_i` over two equal slices, with four partial sums (a fixed
/// order, so results are reproducible, and independent lanes, so it
/// vectorizes; one running sum does not).
#[inline]
pub fn dot(a: &[Real], b: &[Real]) -> Real {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: Real = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// A lower-triangular Cholesky factor `L` of a symmetric positive definite
/// matrix `A = L Lᵀ`, stored row-major `n × n`.
///
/// The factor of a leading principal block of `A` is the leading block of
/// `L`: this is what lets one factorization serve every fit order.
#[derive(Clone, Debug)]
pub struct Cholesky {
    pub n: usize,
    pub l: Vec<Real>,
}

impl Cholesky {
    /// Factors the row-major `n × n` symmetric matrix `a` (only its lower
    /// triangle is read). Returns `None` when a pivot is not positive relative
    /// to the matrix's scale (`rel_pivot_tol · max diagonal`): the matrix is
    /// singular or too ill-conditioned for the normal equations.
    pub fn factor(a: &[Real], n: usize, rel_pivot_tol: Real) -> Option<Cholesky> {
        let (ch, rank) = Cholesky::factor_partial(a, n, rel_pivot_tol);
        (rank == n).then_some(ch)
    }

    /// Factors as far as the pivots allow: the factor of the largest leading
    /// block of `a` whose pivots all exceed `rel_pivot_tol · max diagonal`,
    /// and that block's size (the rank the data support, 0 when none).
    /// Only the first `rank` rows and columns of the returned factor are valid.
    pub fn factor_partial(a: &[Real], n: usize, rel_pivot_tol: Real) -> (Cholesky, usize) {
        let scale = (0..n).map(|i| a[i * n + i]).fold(0.0, Real::max);
        let mut l = vec![0.0; n * n];
        if !(scale > 0.0) || !scale.is_finite() {
            return (Cholesky { n, l }, 0);
        }
        for j in 0..n {
            let mut d = a[j * n + j];
            for k in 0..j {
                d -= l[j * n + k] * l[j * n + k];
            }
            if !(d > rel_pivot_tol * scale) {
                return (Cholesky { n, l }, j);
            }
            let d = d.sqrt();
            l[j * n + j] = d;
            for i in j + 1..n {
                let mut s = a[i * n + j];
                for k in 0..j {
                    s -= l[i * n + k] * l[j * n + k];
                }
                l[i * n + j] = s / d;
            }
        }
        (Cholesky { n, l }, n)
    }

    /// Solves `L z = r` for the leading `m` unknowns (m ≤ n).
    pub fn forward(&self, r: &[Real], m: usize) -> Vec<Real> {
        let n = self.n;
        let mut z = vec![0.0; m];
        for i in 0..m {
            let mut s = r[i];
            for k in 0..i {
                s -= self.l[i * n + k] * z[k];
            }
            z[i] = s / self.l[i * n + i];
        }
        z
    }

    /// Solves `L_mᵀ x = z` where `L_m` is the leading `m × m` block.
    pub fn backward(&self, z: &[Real], m: usize) -> Vec<Real> {
        let n = self.n;
        let mut x = z[..m].to_vec();
        for i in (0..m).rev() {
            let mut s = x[i];
            for k in i + 1..m {
                s -= self.l[k * n + i] * x[k];
            }
            x[i] = s / self.l[i * n + i];
        }
        x
    }

    /// Solves `A_m x = r` with the leading `m × m` block of `A`.
    pub fn solve_leading(&self, r: &[Real], m: usize) -> Vec<Real> {
        self.backward(&self.forward(r, m), m)
    }
}

/// An LU factorization with partial pivoting of a square row-major matrix,
/// `P A = L U` (used for the K×K skinning systems).
#[derive(Clone, Debug)]
pub struct Lu {
    pub n: usize,
    lu: Vec<Real>,
    perm: Vec<usize>,
}

impl Lu {
    /// Factors `a` (`n × n`, row-major). `None` when a pivot vanishes
    /// relative to the largest entry (`rel_tol`).
    pub fn factor(a: &[Real], n: usize, rel_tol: Real) -> Option<Lu> {
        let mut lu = a.to_vec();
        let mut perm: Vec<usize> = (0..n).collect();
        let scale = lu.iter().fold(0.0 as Real, |m, x| m.max(x.abs()));
        if !(scale > 0.0) || !scale.is_finite() {
            return None;
        }
        for k in 0..n {
            let p = (k..n)
                .max_by(|&i, &j| lu[i * n + k].abs().total_cmp(&lu[j * n + k].abs()))
                .unwrap_or(k);
            if !(lu[p * n + k].abs() > rel_tol * scale) {
                return None;
            }
            if p != k {
                for j in 0..n {
                    lu.swap(k * n + j, p * n + j);
                }
                perm.swap(k, p);
            }
            for i in k + 1..n {
                let f = lu[i * n + k] / lu[k * n + k];
                lu[i * n + k] = f;
                for j in k + 1..n {
                    lu[i * n + j] -= f * lu[k * n + j];
                }
            }
        }
        Some(Lu { n, lu, perm })
    }

    /// Solves `A x = r`.
    pub fn solve(&self, r: &[Real]) -> Vec<Real> {
        let n = self.n;
        let mut x: Vec<Real> = self.perm.iter().map(|&p| r[p]).collect();
        for i in 0..n {
            for k in 0..i {
                x[i] -= self.lu[i * n + k] * x[k];
            }
        }
        for i in (0..n).rev() {
            for k in i + 1..n {
                x[i] -= self.lu[i * n + k] * x[k];
            }
            x[i] /= self.lu[i * n + i];
        }
        x
    }

    /// The inverse matrix (row-major), for applying the same solve to many
    /// coefficient vectors as one small matrix product.
    pub fn inverse(&self) -> Vec<Real> {
        let n = self.n;
        let mut inv = vec![0.0; n * n];
        for j in 0..n {
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            let col = self.solve(&e);
            for i in 0..n {
                inv[i * n + j] = col[i];
            }
        }
        inv
    }
}

/// The centroid of `pts` (not empty) and the eigenvalues (descending) and
/// unit eigenvectors of their scatter matrix: principal components.
pub fn principal(pts: &[Point3]) -> (Point3, [Real; 3], [Vec3; 3]) {
    let c = pts.iter().fold(Vec3::ZERO, |a, &p| a + p) * (1.0 / pts.len() as Real);
    let (vals, vecs) = symmetric_eigen3(scatter(pts, c));
    (c, vals, vecs)
}

/// The scatter matrix `Σ (p − c)(p − c)ᵀ` of `pts` about `c`.
pub fn scatter(pts: &[Point3], c: Point3) -> [[Real; 3]; 3] {
    let mut m = [[0.0; 3]; 3];
    for p in pts {
        let d = (*p - c).to_array();
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += d[i] * d[j];
            }
        }
    }
    m
}

/// The 2D scatter `(Σ dx², Σ dx dy, Σ dy²)` of `pts` about `c`, `d = p − c`.
pub fn scatter2(pts: &[Point2], c: Point2) -> (Real, Real, Real) {
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for p in pts {
        let d = *p - c;
        xx += d.x * d.x;
        xy += d.x * d.y;
        yy += d.y * d.y;
    }
    (xx, xy, yy)
}

/// The symmetric 2×2 matrix `[[xx, xy], [xy, yy]]`'s unit eigenvector of
/// the larger eigenvalue, then both eigenvalues, larger first (the smaller
/// at least 0, as for a scatter).
pub fn symmetric_eigen2(xx: Real, xy: Real, yy: Real) -> (Vec2, Real, Real) {
    let mean = 0.5 * (xx + yy);
    let dev = (0.5 * (xx - yy)).hypot(xy);
    let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
    (
        Vec2::new(angle.cos(), angle.sin()),
        mean + dev,
        (mean - dev).max(0.0),
    )
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations:
/// eigenvalues in descending order with their unit eigenvectors.
pub fn symmetric_eigen3(m: [[Real; 3]; 3]) -> ([Real; 3], [Vec3; 3]) {
    let mut a = m;
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..64 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-30 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let mut idx = [0, 1, 2];
    idx.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let vals = idx.map(|i| a[i][i]);
    let vecs = idx.map(|i| Vec3::new(v[0][i], v[1][i], v[2][i]));
    (vals, vecs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    fn spd(n: usize) -> Vec<Real> {
        // A = Mᵀ M + n I with a fixed M.
        let m: Vec<Real> = (0..n * n)
            .map(|k| ((k * 7 + 3) % 11) as Real / 11.0 - 0.4)
            .collect();
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] = (0..n).map(|k| m[k * n + i] * m[k * n + j]).sum::<Real>()
                    + if i == j { n as Real } else { 0.0 };
            }
        }
        a
    }

    #[test]
    fn cholesky_solves_and_nests() {
        let n = 7;
        let a = spd(n);
        let ch = Cholesky::factor(&a, n, 1e-14).unwrap();
        let r: Vec<Real> = (0..n).map(|i| i as Real - 2.0).collect();
        for m in 1..=n {
            let x = ch.solve_leading(&r, m);
            for i in 0..m {
                let s: Real = (0..m).map(|j| a[i * n + j] * x[j]).sum();
                assert_near!(s, r[i], 1e-12);
            }
        }
    }

    #[test]
    fn cholesky_rejects_singular() {
        let a = vec![1.0, 1.0, 1.0, 1.0];
        assert!(Cholesky::factor(&a, 2, 1e-12).is_none());
    }

    #[test]
    fn eigen3_diagonalizes() {
        let m = [[4.0, 1.0, -0.5], [1.0, 3.0, 0.25], [-0.5, 0.25, 1.0]];
        let (vals, vecs) = symmetric_eigen3(m);
        assert!(vals[0] >= vals[1] && vals[1] >= vals[2]);
        for (l, v) in vals.iter().zip(vecs) {
            for i in 0..3 {
                let mv = m[i][0] * v.x + m[i][1] * v.y + m[i][2] * v.z;
                assert_near!(mv, l * v[i], 1e-12);
            }
            assert_near!(v.norm(), 1.0, 1e-12);
        }
    }

    #[test]
    fn lu_solves_vandermonde() {
        let n = 5;
        let a: Vec<Real> = (0..n)
            .flat_map(|k| {
                let u = k as Real / (n - 1) as Real;
                (0..n).map(move |m| u.powi(m as i32))
            })
            .collect();
        let lu = Lu::factor(&a, n, 1e-14).unwrap();
        let r = vec![1.0, -2.0, 0.5, 3.0, 0.0];
        let x = lu.solve(&r);
        for i in 0..n {
            let s: Real = (0..n).map(|j| a[i * n + j] * x[j]).sum();
            assert_near!(s, r[i], 1e-12);
        }
        let inv = lu.inverse();
        for i in 0..n {
            for j in 0..n {
                let s: Real = (0..n).map(|k| a[i * n + k] * inv[k * n + j]).sum();
                assert_near!(s, if i == j { 1.0 } else { 0.0 }, 1e-11);
            }
        }
        assert!(Lu::factor(&[1.0, 2.0, 2.0, 4.0], 2, 1e-12).is_none());
    }
}
