//! Least-squares fitting of a planar trigonometric curve at given parameter
//! values (paper Eq. 5-8, method.md §2.3), for every order at once.
//!
//! With the basis `φ = [1, cos v, sin v, …, cos Jv, sin Jv]` and weights `w_i`,
//! the normal equations are `G c = Bᵀ W x` with the Gram matrix
//! `G[k][l] = Σ_i w_i φ_k(v_i) φ_l(v_i)`. The product-to-sum identities
//! (`cos jv cos kv = ½[cos (j−k)v + cos (j+k)v]`, …) give every entry of `G`
//! from the weighted moments `C_m = Σ w_i cos m v_i`, `S_m = Σ w_i sin m v_i`
//! for `m ≤ 2J`, so building `G` costs O(I·J) instead of O(I·J²).
//!
//! The x and y series use the same functions (the paper's `y` layout only
//! swaps each sin/cos pair), so one factorization of `G` serves both. The
//! Cholesky factor of a leading block of `G` is the leading block of the
//! factor: one factorization serves every order `J ≤ J_cap`.
//!
//! When the parameters are equally spaced over a full period with equal
//! weights, `G` is diagonal (`I` and `I/2`) and the coefficients are a
//! discrete Fourier transform: [`fit_equally_spaced`] computes them directly.

use crate::curve::trig::standard_to_paper_b;
use crate::geom::linalg::{dot, Cholesky};
use crate::geom::math::{Real, Vec2};
use crate::geom::tolerance::GEOMETRIC_EPS;
use std::f64::consts::TAU;

/// Relative pivot tolerance of the normal equations: an order whose Gram
/// block has a pivot below this fraction of the largest diagonal entry is
/// considered unsupported by the data (too few or too clustered points).
pub const PIVOT_TOLERANCE: Real = 1e-11;

/// Coefficients `(a, b)` of one fit, in the paper's layout.
#[derive(Clone, Debug, PartialEq)]
pub struct Coefficients {
    pub a: Vec<Real>,
    pub b: Vec<Real>,
}

impl Coefficients {
    /// The order `J`.
    pub fn order(&self) -> usize {
        self.a.len() / 2
    }
}

/// The relative errors of a fit (paper Eq. 9-11):
/// `E_a = (1/I) Σ d_i / d̄_i`, `E_M = max_i d_i / d̄_i`, with
/// `d_i = |fitted(v_i) − p_i|` and `d̄_i = |p_i − centroid|`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FitErrors {
    pub ea: Real,
    pub em: Real,
    /// Root-mean-square distance `sqrt(Σ d_i² / I)`, in input units.
    pub rms: Real,
    /// Largest distance `max d_i`, in input units.
    pub max: Real,
}

impl FitErrors {
    /// True when both tolerances are met.
    pub fn meets(&self, ea: Real, em: Real) -> bool {
        self.ea <= ea && self.em <= em
    }
}

/// A least-squares fitter for one loop at fixed parameters, ready to produce
/// the fit of every order up to its capacity.
///
/// Tables are stored structure-of-arrays (one row of all points per
/// harmonic) so that the inner loops run over points and vectorize.
#[derive(Debug)]
pub struct LoopFitter<'a> {
    params: &'a [Real],
    /// Point coordinates relative to the centroid (the frame's origin).
    px: Vec<Real>,
    py: Vec<Real>,
    /// The highest order the tables were built for.
    cap: usize,
    /// `cos(j v_i)` at `[(j-1)·n + i]` and `sin(j v_i)` likewise, j = 1..=cap.
    cos_table: Vec<Real>,
    sin_table: Vec<Real>,
    chol: Cholesky,
    /// The number of leading basis functions the factorization supports.
    rank: usize,
    /// Bᵀ W x and Bᵀ W y in standard layout, length 2·cap+1.
    rhs_x: Vec<Real>,
    rhs_y: Vec<Real>,
    /// L⁻¹ Bᵀ W x and L⁻¹ Bᵀ W y (forward solves, nested in the order).
    z_x: Vec<Real>,
    z_y: Vec<Real>,
    /// 1 / |p_i − centroid|, with the distance floored away from zero.
    inv_dbar: Vec<Real>,
}

impl<'a> LoopFitter<'a> {
    /// Prepares fits up to order `cap` for `points` (relative to the
    /// centroid) at parameters `params`, with optional `weights` (default all
    /// one) and a smoothing penalty `smoothing · (Σ w) · Σ_j j⁴ (α_j² + β_j²)`
    /// on the harmonics (zero for none).
    pub fn new(
        points: &[Vec2],
        params: &'a [Real],
        weights: Option<&[Real]>,
        cap: usize,
        smoothing: Real,
    ) -> LoopFitter<'a> {
        let n = points.len();
        let dim = 2 * cap + 1;
        let px: Vec<Real> = points.iter().map(|p| p.x).collect();
        let py: Vec<Real> = points.iter().map(|p| p.y).collect();
        let w: Vec<Real> = match weights {
            Some(w) => w.to_vec(),
            None => vec![1.0; n],
        };
        let wx: Vec<Real> = px.iter().zip(&w).map(|(x, w)| x * w).collect();
        let wy: Vec<Real> = py.iter().zip(&w).map(|(y, w)| y * w).collect();
        let (mut s1, mut c1) = (vec![0.0; n], vec![0.0; n]);
        for (i, v) in params.iter().enumerate() {
            (s1[i], c1[i]) = v.sin_cos();
        }
        // Weighted moments C_m, S_m for m = 0..=2cap, and the right-hand sides.
        let mut cm = vec![0.0; 2 * cap + 1];
        let mut sm = vec![0.0; 2 * cap + 1];
        let mut rhs_x = vec![0.0; dim];
        let mut rhs_y = vec![0.0; dim];
        let mut cos_table = vec![0.0; n * cap];
        let mut sin_table = vec![0.0; n * cap];
        cm[0] = w.iter().sum();
        rhs_x[0] = wx.iter().sum();
        rhs_y[0] = wy.iter().sum();
        let (mut c, mut s) = (c1.clone(), s1.clone());
        for m in 1..=2 * cap {
            if m > 1 {
                for i in 0..n {
                    let (cc, ss) = (c[i] * c1[i] - s[i] * s1[i], s[i] * c1[i] + c[i] * s1[i]);
                    c[i] = cc;
                    s[i] = ss;
                }
            }
            cm[m] = dot(&w, &c);
            sm[m] = dot(&w, &s);
            if m <= cap {
                cos_table[(m - 1) * n..m * n].copy_from_slice(&c);
                sin_table[(m - 1) * n..m * n].copy_from_slice(&s);
                rhs_x[2 * m - 1] = dot(&wx, &c);
                rhs_x[2 * m] = dot(&wx, &s);
                rhs_y[2 * m - 1] = dot(&wy, &c);
                rhs_y[2 * m] = dot(&wy, &s);
            }
        }
        let gram = gram_from_moments(&cm, &sm, cap, smoothing * cm[0]);
        let (chol, rank) = Cholesky::factor_partial(&gram, dim, PIVOT_TOLERANCE);
        let z_x = chol.forward(&rhs_x, rank);
        let z_y = chol.forward(&rhs_y, rank);
        let dist: Vec<Real> = px
            .iter()
            .zip(&py)
            .map(|(x, y)| (x * x + y * y).sqrt())
            .collect();
        let scale = dist.iter().copied().fold(0.0, Real::max);
        let floor = (scale * GEOMETRIC_EPS).max(Real::MIN_POSITIVE);
        let inv_dbar = dist.iter().map(|d| 1.0 / d.max(floor)).collect();
        LoopFitter {
            params,
            px,
            py,
            cap,
            cos_table,
            sin_table,
            chol,
            rank,
            rhs_x,
            rhs_y,
            z_x,
            z_y,
            inv_dbar,
        }
    }

    /// The highest order the data support (`2J+1` independent basis
    /// functions at these parameters), at most the capacity.
    pub fn max_supported_order(&self) -> usize {
        if self.rank == 0 {
            0
        } else {
            ((self.rank - 1) / 2).min(self.cap)
        }
    }

    /// The capacity the tables were built for.
    pub fn capacity(&self) -> usize {
        self.cap
    }

    /// The least-squares coefficients of order `order`, or `None` when the
    /// order exceeds [`Self::max_supported_order`].
    pub fn coefficients(&self, order: usize) -> Option<Coefficients> {
        if order > self.max_supported_order() {
            return None;
        }
        let m = 2 * order + 1;
        let cx = self.chol.backward(&self.z_x, m);
        let cy = self.chol.backward(&self.z_y, m);
        Some(Coefficients {
            a: cx,
            b: standard_to_paper_b(&cy),
        })
    }

    /// The errors of a fit with coefficients `c` (order ≤ capacity) at this
    /// loop's own points and parameters.
    pub fn errors(&self, c: &Coefficients) -> FitErrors {
        let order = c.order().min(self.cap);
        let n = self.px.len();
        let mut fx = vec![c.a[0]; n];
        let mut fy = vec![c.b[0]; n];
        for j in 1..=order {
            let (ac, as_) = (c.a[2 * j - 1], c.a[2 * j]);
            let (bs, bc) = (c.b[2 * j - 1], c.b[2 * j]);
            let tc = &self.cos_table[(j - 1) * n..j * n];
            let ts = &self.sin_table[(j - 1) * n..j * n];
            for i in 0..n {
                fx[i] += ac * tc[i] + as_ * ts[i];
                fy[i] += bs * ts[i] + bc * tc[i];
            }
        }
        let (mut sum_rel, mut max_rel, mut sum_sq, mut max_sq) =
            (0.0, 0.0 as Real, 0.0, 0.0 as Real);
        for i in 0..n {
            let (dx, dy) = (fx[i] - self.px[i], fy[i] - self.py[i]);
            let d2 = dx * dx + dy * dy;
            let rel = d2.sqrt() * self.inv_dbar[i];
            sum_rel += rel;
            max_rel = max_rel.max(rel);
            sum_sq += d2;
            max_sq = max_sq.max(d2);
        }
        FitErrors {
            ea: sum_rel / n as Real,
            em: max_rel,
            rms: (sum_sq / n as Real).sqrt(),
            max: max_sq.sqrt(),
        }
    }

    /// The fit of order `order` and its errors.
    pub fn fit(&self, order: usize) -> Option<(Coefficients, FitErrors)> {
        let c = self.coefficients(order)?;
        let e = self.errors(&c);
        Some((c, e))
    }

    /// The parameters the fitter was built for.
    pub fn params(&self) -> &[Real] {
        self.params
    }

    /// `Bᵀ W x` and `Bᵀ W y` (standard layout), for diagnostics and tests.
    pub fn right_hand_sides(&self) -> (&[Real], &[Real]) {
        (&self.rhs_x, &self.rhs_y)
    }
}

/// The Gram matrix `G` (row-major, `(2cap+1)²`) of the basis
/// `[1, cos v, sin v, …]` from the weighted moments, plus the smoothing
/// penalty `penalty · j⁴` on the diagonal of harmonic `j`.
fn gram_from_moments(cm: &[Real], sm: &[Real], cap: usize, penalty: Real) -> Vec<Real> {
    let dim = 2 * cap + 1;
    let mut g = vec![0.0; dim * dim];
    // Moments for negative index: C_{-m} = C_m, S_{-m} = −S_m.
    let c = |m: isize| cm[m.unsigned_abs()];
    let s = |m: isize| {
        if m >= 0 {
            sm[m as usize]
        } else {
            -sm[m.unsigned_abs()]
        }
    };
    g[0] = cm[0];
    for j in 1..=cap {
        let ji = j as isize;
        g[2 * j - 1] = c(ji); // ⟨1, cos jv⟩
        g[2 * j] = s(ji); // ⟨1, sin jv⟩
        g[(2 * j - 1) * dim] = c(ji);
        g[(2 * j) * dim] = s(ji);
        for k in 1..=cap {
            let ki = k as isize;
            let (d, p) = (ji - ki, ji + ki);
            let (r, q) = (2 * j - 1, 2 * k - 1);
            g[r * dim + q] = 0.5 * (c(d) + c(p)); // cos jv cos kv
            g[r * dim + q + 1] = 0.5 * (s(p) - s(d)); // cos jv sin kv
            g[(r + 1) * dim + q] = 0.5 * (s(p) + s(d)); // sin jv cos kv
            g[(r + 1) * dim + q + 1] = 0.5 * (c(d) - c(p)); // sin jv sin kv
        }
        let pen = penalty * (j as Real).powi(4);
        g[(2 * j - 1) * dim + 2 * j - 1] += pen;
        g[(2 * j) * dim + 2 * j] += pen;
    }
    g
}

/// True when `params` are equally spaced over one full period,
/// `v_i = v_0 + 2π i / I` (mod 2π) to within `1e-12`.
pub fn is_equally_spaced(params: &[Real]) -> bool {
    let n = params.len();
    if n < 3 {
        return false;
    }
    let step = TAU / n as Real;
    params.iter().enumerate().all(|(i, &v)| {
        let d = (v - params[0] - step * i as Real).rem_euclid(TAU);
        d.min(TAU - d) <= 1e-12
    })
}

/// The fast path: coefficients of order `order` for points at equally spaced
/// parameters `v_i = v0 + 2π i / I` with equal weights (requires
/// `I ≥ 2·order + 1`). The basis is orthogonal on such points, so
/// `a0 = mean x`, `a_{2j-1} = (2/I) Σ x_i cos j v_i`, `a_{2j} = (2/I) Σ x_i sin j v_i`
/// (and likewise for y): a discrete Fourier transform, O(I·J).
pub fn fit_equally_spaced(points: &[Vec2], v0: Real, order: usize) -> Option<Coefficients> {
    let n = points.len();
    if n < 2 * order + 1 {
        return None;
    }
    let dim = 2 * order + 1;
    let mut cx = vec![0.0; dim];
    let mut cy = vec![0.0; dim];
    // Twiddles cos(2πk/n), sin(2πk/n): by rotation, re-anchored on an exact
    // sin_cos every 32 steps so rounding cannot accumulate.
    let step = TAU / n as Real;
    let (ds, dc) = step.sin_cos();
    let (mut tc, mut ts) = (vec![0.0; n], vec![0.0; n]);
    for k in 0..n {
        if k % 32 == 0 {
            (ts[k], tc[k]) = (step * k as Real).sin_cos();
        } else {
            tc[k] = tc[k - 1] * dc - ts[k - 1] * ds;
            ts[k] = ts[k - 1] * dc + tc[k - 1] * ds;
        }
    }
    cx[0] = points.iter().map(|p| p.x).sum();
    cy[0] = points.iter().map(|p| p.y).sum();
    for j in 1..=order {
        // Σ p_i cos(2π j i / n) and Σ p_i sin(2π j i / n): the twiddle of
        // j·i mod n, walked by adding j.
        // Two interleaved sets of sums (even and odd points) halve the
        // dependency chains; they are added in a fixed order.
        let mut acc = [0.0; 8];
        let (mut k, jj) = (0usize, j % n);
        let mut pairs = points.chunks_exact(2);
        for pair in &mut pairs {
            let k2 = if k + jj >= n { k + jj - n } else { k + jj };
            let (c, s, c2, s2) = (tc[k], ts[k], tc[k2], ts[k2]);
            acc[0] += pair[0].x * c;
            acc[1] += pair[0].x * s;
            acc[2] += pair[0].y * c;
            acc[3] += pair[0].y * s;
            acc[4] += pair[1].x * c2;
            acc[5] += pair[1].x * s2;
            acc[6] += pair[1].y * c2;
            acc[7] += pair[1].y * s2;
            k = if k2 + jj >= n { k2 + jj - n } else { k2 + jj };
        }
        if let [p] = pairs.remainder() {
            acc[0] += p.x * tc[k];
            acc[1] += p.x * ts[k];
            acc[2] += p.y * tc[k];
            acc[3] += p.y * ts[k];
        }
        let (xc, xs, yc, ys) = (
            acc[0] + acc[4],
            acc[1] + acc[5],
            acc[2] + acc[6],
            acc[3] + acc[7],
        );
        // Then the phase of the first parameter: j v_i = j v0 + 2π j i / n.
        let (s0, c0) = (j as Real * v0).sin_cos();
        cx[2 * j - 1] = c0 * xc - s0 * xs;
        cx[2 * j] = s0 * xc + c0 * xs;
        cy[2 * j - 1] = c0 * yc - s0 * ys;
        cy[2 * j] = s0 * yc + c0 * ys;
    }
    let inv = 1.0 / n as Real;
    cx[0] *= inv;
    cy[0] *= inv;
    for k in 1..dim {
        cx[k] *= 2.0 * inv;
        cy[k] *= 2.0 * inv;
    }
    Some(Coefficients {
        a: cx,
        b: standard_to_paper_b(&cy),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// A deterministic pseudo-random stream in [-1, 1).
    fn stream(seed: u64) -> impl FnMut() -> Real {
        let mut s = seed;
        move || {
            s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 11) as Real / (1u64 << 52) as Real - 1.0
        }
    }

    fn eval(c: &Coefficients, v: Real) -> Vec2 {
        let mut p = Vec2::new(c.a[0], c.b[0]);
        for j in 1..=c.order() {
            let (s, co) = (j as Real * v).sin_cos();
            p.x += c.a[2 * j - 1] * co + c.a[2 * j] * s;
            p.y += c.b[2 * j - 1] * s + c.b[2 * j] * co;
        }
        p
    }

    #[test]
    fn gram_from_moments_matches_direct_products() {
        let mut r = stream(3);
        let n = 40;
        let params: Vec<Real> = (0..n).map(|_| (r() + 1.0) * 3.0).collect();
        let weights: Vec<Real> = (0..n).map(|_| 1.5 + r()).collect();
        let cap = 4;
        let dim = 2 * cap + 1;
        let mut cm = vec![0.0; 2 * cap + 1];
        let mut sm = vec![0.0; 2 * cap + 1];
        for (v, w) in params.iter().zip(&weights) {
            for m in 0..=2 * cap {
                cm[m] += w * (m as Real * v).cos();
                sm[m] += w * (m as Real * v).sin();
            }
        }
        let g = gram_from_moments(&cm, &sm, cap, 0.0);
        let phi = |k: usize, v: Real| {
            if k == 0 {
                1.0
            } else if k % 2 == 1 {
                (k.div_ceil(2) as Real * v).cos()
            } else {
                ((k / 2) as Real * v).sin()
            }
        };
        for k in 0..dim {
            for l in 0..dim {
                let direct: Real = params
                    .iter()
                    .zip(&weights)
                    .map(|(&v, w)| w * phi(k, v) * phi(l, v))
                    .sum();
                assert_near!(g[k * dim + l], direct, 1e-12);
            }
        }
    }

    #[test]
    fn planted_series_is_recovered_at_its_parameters() {
        let mut r = stream(11);
        for order in 1..=12 {
            let planted = Coefficients {
                a: (0..2 * order + 1).map(|_| r()).collect(),
                b: (0..2 * order + 1).map(|_| r()).collect(),
            };
            let n = 4 * order + 7;
            let mut params: Vec<Real> =
                (0..n).map(|_| (r() + 1.0) * std::f64::consts::PI).collect();
            params.sort_by(Real::total_cmp);
            let pts: Vec<Vec2> = params.iter().map(|&v| eval(&planted, v)).collect();
            for fit_order in [order, order + 1] {
                let f = LoopFitter::new(&pts, &params, None, fit_order, 0.0);
                let Some(c) = f.coefficients(fit_order) else {
                    continue;
                };
                for k in 0..2 * order + 1 {
                    assert_near!(c.a[k], planted.a[k], 1e-9);
                    assert_near!(c.b[k], planted.b[k], 1e-9);
                }
                for k in 2 * order + 1..c.a.len() {
                    assert_near!(c.a[k], 0.0, 1e-9);
                }
            }
        }
    }

    #[test]
    fn fast_path_agrees_with_normal_equations() {
        let mut r = stream(5);
        let n = 256;
        let v0 = 0.37;
        let params: Vec<Real> = (0..n).map(|i| v0 + TAU * i as Real / n as Real).collect();
        let pts: Vec<Vec2> = params
            .iter()
            .map(|&v| Vec2::new(v.cos() + 0.1 * r(), 0.6 * v.sin() + 0.1 * r()))
            .collect();
        assert!(is_equally_spaced(&params));
        let f = LoopFitter::new(&pts, &params, None, 8, 0.0);
        for order in 1..=8 {
            let slow = f.coefficients(order).unwrap();
            let fast = fit_equally_spaced(&pts, v0, order).unwrap();
            for k in 0..2 * order + 1 {
                assert_near!(fast.a[k], slow.a[k], 1e-10);
                assert_near!(fast.b[k], slow.b[k], 1e-10);
            }
        }
    }

    #[test]
    fn too_few_points_limit_the_order() {
        let params: Vec<Real> = (0..7).map(|i| TAU * i as Real / 7.0).collect();
        let pts: Vec<Vec2> = params
            .iter()
            .map(|&v| Vec2::new(v.cos(), v.sin()))
            .collect();
        let f = LoopFitter::new(&pts, &params, None, 6, 0.0);
        assert_eq!(f.max_supported_order(), 3);
        assert!(f.coefficients(4).is_none());
        assert!(!is_equally_spaced(&params[..5]));
    }

    #[test]
    fn errors_of_exact_fit_vanish() {
        let params: Vec<Real> = (0..50).map(|i| 0.1 + 0.12 * i as Real).collect();
        let pts: Vec<Vec2> = params
            .iter()
            .map(|&v| Vec2::new(2.0 * v.cos(), v.sin()))
            .collect();
        let f = LoopFitter::new(&pts, &params, None, 3, 0.0);
        let (_, e) = f.fit(2).unwrap();
        assert!(e.ea < 1e-13 && e.em < 1e-13, "{e:?}");
    }
}
