//! Scalar trigonometric (Fourier) series of one variable, in the standard
//! layout used for world-space coordinates and surface coefficient functions:
//!
//! ```text
//! s(v) = c[0] + Σ_{j=1..J} ( c[2j-1] cos jv + c[2j] sin jv )
//! ```
//!
//! This is exactly the paper's layout for `x` (the `a` coefficients, Eq. 3).
//! The paper's `y` layout swaps sin and cos; `TrigCurve` converts.

use crate::geom::math::Real;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// A real trigonometric series of order `J` with `2J+1` coefficients
/// `[c0, cos 1v, sin 1v, cos 2v, sin 2v, …]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Series {
    pub c: Vec<Real>,
}

/// `cos(j v)` and `sin(j v)` for `j = 0..=order`, by the angle-addition
/// recurrence (one `sin_cos` call; error grows like `j · ε`).
#[inline]
pub fn harmonics(v: Real, order: usize, cos: &mut [Real], sin: &mut [Real]) {
    let (s1, c1) = v.sin_cos();
    cos[0] = 1.0;
    sin[0] = 0.0;
    for j in 1..=order {
        cos[j] = cos[j - 1] * c1 - sin[j - 1] * s1;
        sin[j] = sin[j - 1] * c1 + cos[j - 1] * s1;
    }
}

impl Series {
    /// The zero series of order `order`.
    pub fn zeros(order: usize) -> Series {
        Series {
            c: vec![0.0; 2 * order + 1],
        }
    }

    /// A constant series (order 0).
    pub fn constant(value: Real) -> Series {
        Series { c: vec![value] }
    }

    /// The order `J` (the highest harmonic).
    #[inline]
    pub fn order(&self) -> usize {
        self.c.len() / 2
    }

    /// The `k`-th derivative at `v`: d^k/dv^k of each harmonic multiplies its
    /// amplitude by `j^k` and advances its phase by `k·π/2`.
    pub fn eval_derivative(&self, v: Real, k: u32) -> Real {
        let mut acc = if k == 0 { self.c[0] } else { 0.0 };
        let (s1, c1) = v.sin_cos();
        let (mut cj, mut sj) = (1.0, 0.0);
        for j in 1..=self.order() {
            (cj, sj) = (cj * c1 - sj * s1, sj * c1 + cj * s1);
            let (a, b) = (self.c[2 * j - 1], self.c[2 * j]);
            let f = (j as Real).powi(k as i32);
            // d^k/dv^k of (a cos jv + b sin jv), by k mod 4.
            let term = match k % 4 {
                0 => a * cj + b * sj,
                1 => -a * sj + b * cj,
                2 => -a * cj - b * sj,
                _ => a * sj - b * cj,
            };
            acc += f * term;
        }
        acc
    }

    /// The value at `v`.
    #[inline]
    pub fn eval(&self, v: Real) -> Real {
        self.eval_derivative(v, 0)
    }

    /// The same function with `order` harmonics: zero-padded when raising,
    /// truncated (the least-squares best lower-order series) when lowering.
    pub fn with_order(&self, order: usize) -> Series {
        let mut c = self.c.clone();
        c.resize(2 * order + 1, 0.0);
        Series { c }
    }

    /// The series of `s(v + phi)`: each harmonic rotates by `j·phi`.
    pub fn shifted(&self, phi: Real) -> Series {
        let mut c = self.c.clone();
        for j in 1..=self.order() {
            let (s, co) = (j as Real * phi).sin_cos();
            let (a, b) = (self.c[2 * j - 1], self.c[2 * j]);
            c[2 * j - 1] = a * co + b * s;
            c[2 * j] = -a * s + b * co;
        }
        Series { c }
    }

    /// The mean value over a period, `c[0]`.
    #[inline]
    pub fn mean(&self) -> Real {
        self.c[0]
    }

    /// `(1/2π) ∫ s(v) t(v) dv` over a period, exact from the coefficients
    /// (Parseval): `c0 d0 + ½ Σ (c_{2j-1} d_{2j-1} + c_{2j} d_{2j})`.
    pub fn inner_mean(&self, other: &Series) -> Real {
        let n = self.c.len().min(other.c.len());
        let tail: Real = (1..n).map(|k| self.c[k] * other.c[k]).sum();
        self.c[0] * other.c[0] + 0.5 * tail
    }

    /// Samples at `n` equally spaced parameters `v_i = 2π i / n`.
    pub fn sample(&self, n: usize) -> Vec<Real> {
        (0..n)
            .map(|i| self.eval(TAU * i as Real / n as Real))
            .collect()
    }

    /// True when every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        self.c.iter().all(|x| x.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    fn example() -> Series {
        Series {
            c: vec![0.3, 1.0, -0.5, 0.25, 0.125, -0.2, 0.05],
        }
    }

    fn direct(s: &Series, v: Real) -> Real {
        let mut acc = s.c[0];
        for j in 1..=s.order() {
            acc += s.c[2 * j - 1] * (j as Real * v).cos() + s.c[2 * j] * (j as Real * v).sin();
        }
        acc
    }

    #[test]
    fn eval_matches_direct_sum() {
        let s = example();
        for i in 0..50 {
            let v = i as Real * 0.37 - 3.0;
            assert_near!(s.eval(v), direct(&s, v), 1e-13);
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let s = example();
        let h = 1e-5;
        for k in 0..4 {
            for i in 0..20 {
                let v = i as Real * 0.31;
                let fd = (s.eval_derivative(v + h, k) - s.eval_derivative(v - h, k)) / (2.0 * h);
                assert_near!(s.eval_derivative(v, k + 1), fd, 1e-7);
            }
        }
    }

    #[test]
    fn shift_is_a_phase_rotation() {
        let s = example();
        let phi = 0.713;
        let t = s.shifted(phi);
        for i in 0..30 {
            let v = i as Real * 0.21;
            assert_near!(t.eval(v), s.eval(v + phi), 1e-13);
        }
    }

    #[test]
    fn padding_keeps_the_function() {
        let s = example();
        let p = s.with_order(9);
        assert_eq!(p.order(), 9);
        for i in 0..30 {
            let v = i as Real * 0.21;
            assert_near!(p.eval(v), s.eval(v), 1e-15);
        }
    }

    #[test]
    fn parseval_matches_quadrature() {
        let (s, t) = (example(), example().shifted(1.0));
        let n = 64;
        let q: Real = (0..n)
            .map(|i| {
                let v = TAU * i as Real / n as Real;
                s.eval(v) * t.eval(v)
            })
            .sum::<Real>()
            / n as Real;
        assert_near!(s.inner_mean(&t), q, 1e-14);
    }

    #[test]
    fn harmonics_recurrence_is_accurate() {
        let (mut c, mut s) = (vec![0.0; 41], vec![0.0; 41]);
        harmonics(2.345, 40, &mut c, &mut s);
        for j in 0..=40 {
            assert_near!(c[j], (j as Real * 2.345).cos(), 1e-13);
            assert_near!(s[j], (j as Real * 2.345).sin(), 1e-13);
        }
    }
}
