//! The baseline the paper improves on (Hyun et al. 2003/2005): a standard
//! ellipse `E(v) = (a cos v, b sin v)` in a rotated frame through the
//! centroid (method.md §4).
//!
//! The centre is the centroid of the points, the axes are the principal
//! directions of the points, and each point's parameter is its own best one
//! on the ellipse: alternate `v_i = atan2(w_i / b, u_i / a)` with the
//! least-squares semi-axes `a = Σ u_i cos v_i / Σ cos² v_i`,
//! `b = Σ w_i sin v_i / Σ sin² v_i` (u, w: the point's coordinates along the
//! axes) until they settle, so an exact ellipse scores zero error.

use crate::curve::lsq::FitErrors;
use crate::curve::trig::{Frame, TrigCurve};
use crate::geom::linalg::{scatter2, symmetric_eigen2};
use crate::geom::math::{Real, Vec2};
use crate::geom::tolerance::GEOMETRIC_EPS;

/// Iterations of the alternating fit at most.
const MAX_ITERATIONS: usize = 200;

/// A standard-ellipse fit of a loop, in the loop's plane coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EllipseFit {
    /// Unit direction of the first semi-axis `a` in plane coordinates.
    pub axis: Vec2,
    /// Semi-axis along `axis`.
    pub a: Real,
    /// Semi-axis along `axis` rotated by +90°.
    pub b: Real,
    /// The same relative errors as the trigonometric fit (paper Eq. 9-11).
    pub errors: FitErrors,
    /// Alternation steps until the semi-axes settled.
    pub iterations: usize,
}

impl EllipseFit {
    /// The ellipse as an order-1 [`TrigCurve`] in `frame` (whose origin is the
    /// centroid the points were taken relative to): with `d1 = axis`,
    /// `d2 = axis⊥`, `x(v) = a d1x cos v + b d2x sin v`,
    /// `y(v) = b d2y sin v + a d1y cos v`.
    pub fn to_curve(&self, frame: Frame) -> TrigCurve {
        let (d1, d2) = (self.axis, self.axis.perp());
        TrigCurve {
            frame,
            a: vec![0.0, self.a * d1.x, self.b * d2.x],
            b: vec![0.0, self.b * d2.y, self.a * d1.y],
        }
    }
}

/// The principal directions of 2D points (relative to their centroid): the
/// unit eigenvector of the largest eigenvalue of the covariance, and both
/// eigenvalues (largest first).
pub fn principal_axes(points: &[Vec2]) -> (Vec2, Real, Real) {
    let n = points.len().max(1) as Real;
    let (sxx, sxy, syy) = scatter2(points, Vec2::ZERO);
    symmetric_eigen2(sxx / n, sxy / n, syy / n)
}

/// Fits the standard ellipse to `points` given relative to their centroid.
/// Returns `None` for fewer than 3 points or a degenerate (zero-extent) set.
pub fn fit_ellipse(points: &[Vec2]) -> Option<EllipseFit> {
    if points.len() < 3 {
        return None;
    }
    let (d1, l1, l2) = principal_axes(points);
    if !(l2 > 0.0) || !l1.is_finite() {
        return None;
    }
    let d2 = d1.perp();
    let uw: Vec<Vec2> = points
        .iter()
        .map(|p| Vec2::new(p.dot(d1), p.dot(d2)))
        .collect();
    // For points spread evenly in v, mean u² = a²/2.
    let (mut a, mut b) = ((2.0 * l1).sqrt(), (2.0 * l2).sqrt());
    // The point's own parameter v = atan2(w/b, u/a) needs no trigonometry:
    // with ρ = √((u/a)² + (w/b)²), cos v = (u/a)/ρ and sin v = (w/b)/ρ.
    let cos_sin = |q: &Vec2, a: Real, b: Real| {
        let (x, y) = (q.x / a, q.y / b);
        let rho = (x * x + y * y).sqrt();
        if rho > 0.0 {
            (x / rho, y / rho)
        } else {
            (1.0, 0.0)
        }
    };
    let mut iterations = 0;
    while iterations < MAX_ITERATIONS {
        iterations += 1;
        let (mut uc, mut cc, mut ws, mut ss) = (0.0, 0.0, 0.0, 0.0);
        for q in &uw {
            let (c, s) = cos_sin(q, a, b);
            uc += q.x * c;
            cc += c * c;
            ws += q.y * s;
            ss += s * s;
        }
        if !(cc > 0.0 && ss > 0.0) {
            break;
        }
        let (na, nb) = (uc / cc, ws / ss);
        if !(na > 0.0 && nb > 0.0) {
            break;
        }
        let change = ((na - a) / a).abs().max(((nb - b) / b).abs());
        (a, b) = (na, nb);
        if change < 1e-13 {
            break;
        }
    }
    let n = uw.len() as Real;
    let floor = (l1.sqrt() * GEOMETRIC_EPS).max(Real::MIN_POSITIVE);
    let (mut sum_rel, mut max_rel, mut sum_sq, mut max_d) = (0.0, 0.0 as Real, 0.0, 0.0 as Real);
    for q in &uw {
        let (c, s) = cos_sin(q, a, b);
        let (dx, dy) = (a * c - q.x, b * s - q.y);
        let d = (dx * dx + dy * dy).sqrt();
        let rel = d / (q.x * q.x + q.y * q.y).sqrt().max(floor);
        sum_rel += rel;
        max_rel = max_rel.max(rel);
        sum_sq += d * d;
        max_d = max_d.max(d);
    }
    Some(EllipseFit {
        axis: d1,
        a,
        b,
        errors: FitErrors {
            ea: sum_rel / n,
            em: max_rel,
            rms: (sum_sq / n).sqrt(),
            max: max_d,
        },
        iterations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use std::f64::consts::TAU;

    #[test]
    fn exact_rotated_ellipse_has_zero_error() {
        for &(a, b, rot) in &[(0.2, 0.12, 0.3), (1.0, 0.3, -1.2), (5.0, 4.9, 2.0)] {
            let (s, c) = (rot as Real).sin_cos();
            let pts: Vec<Vec2> = (0..97)
                .map(|i| {
                    let v = TAU * i as Real / 97.0;
                    let (x, y) = (a * v.cos(), b * v.sin());
                    Vec2::new(c * x - s * y, s * x + c * y)
                })
                .collect();
            let e = fit_ellipse(&pts).unwrap();
            assert!(e.errors.ea < 1e-12 && e.errors.em < 1e-12, "{e:?}");
            assert_near!(e.a, a, 1e-12);
            assert_near!(e.b, b, 1e-12);
            let curve = e.to_curve(Frame::XY);
            for (i, p) in pts.iter().enumerate().step_by(7) {
                let _ = i;
                // Every input point lies on the curve form of the ellipse.
                let best = (0..2000)
                    .map(|k| (curve.plane_point(TAU * k as Real / 2000.0) - *p).norm())
                    .fold(Real::INFINITY, Real::min);
                assert!(best < 2e-3 * a);
            }
        }
    }

    #[test]
    fn degenerate_input_is_refused() {
        assert!(fit_ellipse(&[Vec2::ZERO; 2]).is_none());
        let line: Vec<Vec2> = (0..10).map(|i| Vec2::new(i as Real, 0.0)).collect();
        assert!(fit_ellipse(&line).is_none());
    }
}
