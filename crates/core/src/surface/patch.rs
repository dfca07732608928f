//! Surface patches through cross-section curves (paper Eq. 13-18,
//! method.md §5).
//!
//! A patch is a polynomial in `u` whose coefficients are closed space curves
//! (trigonometric series in `v`), one per world coordinate:
//!
//! ```text
//! t(u, v) = Σ_{m=0..N-1} u^m f_m(v)          (paper Eq. 13)
//! ```
//!
//! Interpolating `K` curves `c_k` at parameters `u_k` gives the rows
//! `Σ_m u_k^m f_m = c_k` (Eq. 14-15). Boundary conditions add rows for the
//! `u`-derivatives at `u = 0` or `u = 1` (Eq. 17-18; second derivatives for
//! curvature continuity):
//!
//! ```text
//! ∂t/∂u   (0, v) = f_1(v)                    ∂t/∂u   (1, v) = Σ_m m f_m(v)
//! ∂²t/∂u² (0, v) = 2 f_2(v)                  ∂²t/∂u² (1, v) = Σ_m m(m-1) f_m(v)
//! ```
//!
//! Every row is the same linear combination of the unknown functions for
//! every coordinate and every Fourier coefficient, so one LU factorization of
//! the `N × N` matrix (`N = K +` number of conditions) solves the whole patch
//! (Eq. 16): `F = R⁻¹ C`, applied coefficient-wise.

use crate::curve::series::Series;
use crate::curve::trig::SpaceCurve;
use crate::geom::linalg::Lu;
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::tolerance::PIVOT_EPS;
use thiserror::Error;

/// What is wrong with the input of a patch.
#[derive(Debug, Error, PartialEq)]
pub enum PatchError {
    #[error("a patch needs at least 2 curves, got {count}")]
    TooFewCurves { count: usize },
    #[error("{what}: coefficient {coordinate}[{index}] is not finite ({value})")]
    NonFinite {
        what: String,
        coordinate: char,
        index: usize,
        value: Real,
    },
    #[error("{params} parameter values for {curves} curves: give one per curve")]
    ParameterCount { params: usize, curves: usize },
    #[error("curve parameters must be finite and strictly increasing; u[{index}] = {value}")]
    BadParameters { index: usize, value: Real },
    #[error("the {size}×{size} patch system is singular: the parameters and boundary conditions do not determine a patch (e.g. a curve at u = 0 together with a second-derivative condition and too few curves)")]
    Singular { size: usize },
}

/// Boundary derivatives imposed on a patch (paper Eq. 17-18). Each is a space
/// curve: the derivative `∂t/∂u` (or `∂²t/∂u²`) along the whole boundary, in
/// the patch's own `u` (scale a neighbour's derivative by the ratio of the
/// parameter lengths before passing it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EndConditions {
    /// `∂t/∂u` at `u = 0` (tangent continuity with a patch before this one).
    pub start_tangent: Option<SpaceCurve>,
    /// `∂²t/∂u²` at `u = 0` (curvature continuity).
    pub start_curvature: Option<SpaceCurve>,
    /// `∂t/∂u` at `u = 1`.
    pub end_tangent: Option<SpaceCurve>,
    /// `∂²t/∂u²` at `u = 1`.
    pub end_curvature: Option<SpaceCurve>,
}

impl EndConditions {
    /// No conditions: a plain interpolating patch (Eq. 14-16).
    pub const NONE: EndConditions = EndConditions {
        start_tangent: None,
        start_curvature: None,
        end_tangent: None,
        end_curvature: None,
    };

    fn count(&self) -> usize {
        [
            &self.start_tangent,
            &self.start_curvature,
            &self.end_tangent,
            &self.end_curvature,
        ]
        .iter()
        .filter(|c| c.is_some())
        .count()
    }
}

/// A surface `t(u, v) = Σ_m u^m f_m(v)` with trigonometric coefficient
/// curves `f_m` of one common order (paper Eq. 13). `u ∈ [0, 1]` runs across
/// the curves, `v ∈ [0, 2π)` around them.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// The coefficient functions `f_0 … f_{N-1}`, all of order [`Patch::order`].
    f: Vec<SpaceCurve>,
}

/// The coefficients of a space curve as one flat vector `[x…, y…, z…]`
/// written at `order` (the form in which curves are combined linearly).
pub(crate) fn flatten(c: &SpaceCurve, order: usize) -> Vec<Real> {
    let n = 2 * order + 1;
    let mut out = Vec::with_capacity(3 * n);
    for s in [&c.x, &c.y, &c.z] {
        let start = out.len();
        out.extend_from_slice(&s.c[..s.c.len().min(n)]);
        out.resize(start + n, 0.0);
    }
    out
}

/// The inverse of [`flatten`].
pub(crate) fn unflatten(v: &[Real], order: usize) -> SpaceCurve {
    let n = 2 * order + 1;
    SpaceCurve {
        x: Series { c: v[..n].to_vec() },
        y: Series {
            c: v[n..2 * n].to_vec(),
        },
        z: Series {
            c: v[2 * n..3 * n].to_vec(),
        },
    }
}

/// `Σ_i w_i v_i` of flat coefficient vectors of equal length.
pub(crate) fn combine(terms: &[(Real, &[Real])]) -> Vec<Real> {
    let len = terms.first().map_or(0, |t| t.1.len());
    let mut out = vec![0.0; len];
    for (w, v) in terms {
        if *w != 0.0 {
            for (o, x) in out.iter_mut().zip(v.iter()) {
                *o += w * x;
            }
        }
    }
    out
}

/// Rejects a curve with a non-finite coefficient, naming it.
pub(crate) fn check_finite(c: &SpaceCurve, what: impl Fn() -> String) -> Result<(), PatchError> {
    for (coordinate, s) in [('x', &c.x), ('y', &c.y), ('z', &c.z)] {
        if let Some((index, &value)) = s.c.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(PatchError::NonFinite {
                what: what(),
                coordinate,
                index,
                value,
            });
        }
    }
    Ok(())
}

/// `d^k/du^k u^m` at `u`: `m!/(m-k)! u^{m-k}` (zero for `k > m`).
#[inline]
fn power_derivative(u: Real, m: usize, k: usize) -> Real {
    if k > m {
        return 0.0;
    }
    let mut f = 1.0;
    for i in 0..k {
        f *= (m - i) as Real;
    }
    f * u.powi((m - k) as i32)
}

impl Patch {
    /// The patch through `curves` (paper Eq. 14-16) with optional boundary
    /// derivative conditions (Eq. 17-18).
    ///
    /// `params` are the curves' `u` values (finite, strictly increasing; they
    /// need not span `[0, 1]`, though the end conditions always act at
    /// `u = 0` and `u = 1`); `None` means evenly spaced `u_k = k/(K-1)`.
    /// Curves of different orders are padded to the largest.
    pub fn interpolate(
        curves: &[SpaceCurve],
        params: Option<&[Real]>,
        ends: &EndConditions,
    ) -> Result<Patch, PatchError> {
        let k = curves.len();
        if k < 2 {
            return Err(PatchError::TooFewCurves { count: k });
        }
        for (i, c) in curves.iter().enumerate() {
            check_finite(c, || format!("curve {i}"))?;
        }
        let conditions: [(&Option<SpaceCurve>, &str, Real, usize); 4] = [
            (&ends.start_tangent, "start tangent", 0.0, 1),
            (&ends.start_curvature, "start curvature", 0.0, 2),
            (&ends.end_tangent, "end tangent", 1.0, 1),
            (&ends.end_curvature, "end curvature", 1.0, 2),
        ];
        for (c, name, _, _) in &conditions {
            if let Some(c) = c {
                check_finite(c, || name.to_string())?;
            }
        }
        let default_params: Vec<Real>;
        let u = match params {
            Some(p) => {
                if p.len() != k {
                    return Err(PatchError::ParameterCount {
                        params: p.len(),
                        curves: k,
                    });
                }
                for (i, &x) in p.iter().enumerate() {
                    if !x.is_finite() || (i > 0 && x <= p[i - 1]) {
                        return Err(PatchError::BadParameters { index: i, value: x });
                    }
                }
                p
            }
            None => {
                default_params = (0..k).map(|i| i as Real / (k - 1) as Real).collect();
                &default_params
            }
        };
        let n = k + ends.count();
        let order = curves
            .iter()
            .chain(conditions.iter().filter_map(|c| c.0.as_ref()))
            .map(SpaceCurve::order)
            .max()
            .unwrap_or(1);

        // Rows: R[r][m] = d^k u^m / du^k at the row's u; right-hand sides C.
        let mut r = Vec::with_capacity(n * n);
        let mut rhs: Vec<Vec<Real>> = Vec::with_capacity(n);
        for (c, &uk) in curves.iter().zip(u) {
            r.extend((0..n).map(|m| power_derivative(uk, m, 0)));
            rhs.push(flatten(c, order));
        }
        for (c, _, at, deriv) in conditions {
            if let Some(c) = c {
                r.extend((0..n).map(|m| power_derivative(at, m, deriv)));
                rhs.push(flatten(c, order));
            }
        }
        // Below the pivot tolerance the curves' parameters (or the conditions)
        // do not determine the patch.
        let lu = Lu::factor(&r, n, PIVOT_EPS).ok_or(PatchError::Singular { size: n })?;
        // F = R⁻¹ C: one inverse, then each f_m is a combination of the rows.
        let inv = lu.inverse();
        if inv.iter().any(|x| !x.is_finite()) {
            return Err(PatchError::Singular { size: n });
        }
        let f = (0..n)
            .map(|m| {
                let terms: Vec<(Real, &[Real])> = (0..n)
                    .map(|row| (inv[m * n + row], rhs[row].as_slice()))
                    .collect();
                unflatten(&combine(&terms), order)
            })
            .collect();
        Ok(Patch { f })
    }

    /// The cubic Hermite patch from curve `p0` with `∂t/∂u = t0` at `u = 0` to
    /// `p1` with `∂t/∂u = t1` at `u = 1`, in power form:
    /// `f_0 = p0, f_1 = t0, f_2 = 3(p1-p0) - 2t0 - t1, f_3 = 2(p0-p1) + t0 + t1`.
    pub fn hermite(
        p0: &SpaceCurve,
        t0: &SpaceCurve,
        p1: &SpaceCurve,
        t1: &SpaceCurve,
    ) -> Result<Patch, PatchError> {
        for (c, name) in [(p0, "p0"), (t0, "t0"), (p1, "p1"), (t1, "t1")] {
            check_finite(c, || name.to_string())?;
        }
        let order = [p0, t0, p1, t1]
            .iter()
            .map(|c| c.order())
            .max()
            .unwrap_or(1);
        let [p0, t0, p1, t1] = [p0, t0, p1, t1].map(|c| flatten(c, order));
        let f = [
            p0.clone(),
            t0.clone(),
            combine(&[(3.0, &p1), (-3.0, &p0), (-2.0, &t0), (-1.0, &t1)]),
            combine(&[(2.0, &p0), (-2.0, &p1), (1.0, &t0), (1.0, &t1)]),
        ];
        Ok(Patch {
            f: f.iter().map(|v| unflatten(v, order)).collect(),
        })
    }

    /// A patch from its coefficient functions `f_m` directly (padded to a
    /// common order). At least one function, all finite.
    pub fn from_coefficients(f: Vec<SpaceCurve>) -> Result<Patch, PatchError> {
        if f.is_empty() {
            return Err(PatchError::TooFewCurves { count: 0 });
        }
        for (i, c) in f.iter().enumerate() {
            check_finite(c, || format!("coefficient function f_{i}"))?;
        }
        let order = f.iter().map(SpaceCurve::order).max().unwrap_or(1);
        Ok(Patch {
            f: f.iter().map(|c| c.with_order(order)).collect(),
        })
    }

    /// The coefficient functions `f_m`.
    pub fn coefficients(&self) -> &[SpaceCurve] {
        &self.f
    }

    /// The polynomial degree in `u` (`N - 1`).
    pub fn degree(&self) -> usize {
        self.f.len() - 1
    }

    /// The trigonometric order in `v` (common to every `f_m`).
    pub fn order(&self) -> usize {
        self.f[0].order()
    }

    /// The iso-curve `∂^k t/∂u^k (u, ·)` as a space curve (k = 0: the curve
    /// of the patch at `u`). Exact: a combination of the `f_m`.
    pub fn u_derivative_curve(&self, u: Real, k: usize) -> SpaceCurve {
        let order = self.order();
        let flat: Vec<Vec<Real>> = self.f.iter().map(|c| flatten(c, order)).collect();
        let terms: Vec<(Real, &[Real])> = flat
            .iter()
            .enumerate()
            .map(|(m, v)| (power_derivative(u, m, k), v.as_slice()))
            .collect();
        unflatten(&combine(&terms), order)
    }

    /// The curve of the patch at `u`, `t(u, ·)`.
    pub fn curve_at(&self, u: Real) -> SpaceCurve {
        self.u_derivative_curve(u, 0)
    }

    /// The mixed partial derivative `∂^{ku+kv} t / ∂u^{ku} ∂v^{kv}` at `(u, v)`.
    pub fn derivative(&self, u: Real, v: Real, ku: usize, kv: u32) -> Vec3 {
        let mut acc = Vec3::ZERO;
        for (m, c) in self.f.iter().enumerate().skip(ku) {
            acc += c.derivative(v, kv) * power_derivative(u, m, ku);
        }
        acc
    }

    /// The point `t(u, v)`.
    pub fn point(&self, u: Real, v: Real) -> Point3 {
        self.derivative(u, v, 0, 0)
    }

    /// `∂t/∂u` at `(u, v)`.
    pub fn du(&self, u: Real, v: Real) -> Vec3 {
        self.derivative(u, v, 1, 0)
    }

    /// `∂t/∂v` at `(u, v)`.
    pub fn dv(&self, u: Real, v: Real) -> Vec3 {
        self.derivative(u, v, 0, 1)
    }

    /// The point, `∂t/∂u` and `∂t/∂v` at every `(us[j], vs[i])`, row by
    /// row (`out[j * vs.len() + i]`). The coefficient curves are evaluated
    /// once per `v` (they do not depend on `u`) and combined for each `u`
    /// by the same sums in the same order as [`Patch::point`],
    /// [`Patch::du`] and [`Patch::dv`]: the same numbers, at a fraction of
    /// the trigonometric work.
    pub fn grid(&self, us: &[Real], vs: &[Real]) -> Vec<[Vec3; 3]> {
        let terms = self.f.len();
        // Per v: f_m(v) and f_m'(v) for every m.
        let columns: Vec<(Vec<Vec3>, Vec<Vec3>)> = vs
            .iter()
            .map(|&v| {
                (
                    self.f.iter().map(|c| c.derivative(v, 0)).collect(),
                    self.f.iter().map(|c| c.derivative(v, 1)).collect(),
                )
            })
            .collect();
        let mut out = Vec::with_capacity(us.len() * vs.len());
        for &u in us {
            let w0: Vec<Real> = (0..terms).map(|m| power_derivative(u, m, 0)).collect();
            let w1: Vec<Real> = (0..terms).map(|m| power_derivative(u, m, 1)).collect();
            for (f0, f1) in &columns {
                let (mut p, mut du, mut dv) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
                for m in 0..terms {
                    p += f0[m] * w0[m];
                }
                for m in 1..terms {
                    du += f0[m] * w1[m];
                }
                for m in 0..terms {
                    dv += f1[m] * w0[m];
                }
                out.push([p, du, dv]);
            }
        }
        out
    }

    /// The unit normal `∂t/∂v × ∂t/∂u / |…|`: it points outward when the
    /// curves run counter-clockwise about the direction of increasing `u`
    /// (the convention of method.md §2). `None` where the surface is
    /// degenerate (e.g. the apex of a cap).
    pub fn normal(&self, u: Real, v: Real) -> Option<Vec3> {
        self.dv(u, v).cross(self.du(u, v)).normalized()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_vec_near;
    use crate::curve::trig::{Frame, TrigCurve};
    use crate::geom::math::Vec3;

    fn curve(z: Real, seed: Real, order: usize) -> SpaceCurve {
        let frame = Frame::from_normal(
            Vec3::new(0.1 * seed, -0.05 * seed, z),
            Vec3::new(0.1 * seed.sin(), 0.05, 1.0),
            Vec3::X,
        )
        .unwrap();
        let mut a = vec![0.0; 2 * order + 1];
        let mut b = a.clone();
        a[1] = 0.2 + 0.02 * seed;
        b[1] = 0.15 - 0.01 * seed;
        for j in 2..=order {
            a[2 * j - 1] = 0.01 * (seed + j as Real).sin();
            a[2 * j] = 0.008 * (seed * j as Real).cos();
            b[2 * j - 1] = -0.006 * (seed - j as Real).sin();
            b[2 * j] = 0.004 * (seed + 2.0 * j as Real).cos();
        }
        TrigCurve::new(frame, a, b).unwrap().world_series()
    }

    #[test]
    fn passes_through_every_curve() {
        let curves: Vec<SpaceCurve> = (0..5)
            .map(|k| curve(0.1 * k as Real, k as Real, 2 + k))
            .collect();
        let p = Patch::interpolate(&curves, None, &EndConditions::NONE).unwrap();
        assert_eq!(p.degree(), 4);
        assert_eq!(p.order(), 6);
        for (k, c) in curves.iter().enumerate() {
            let u = k as Real / 4.0;
            for i in 0..37 {
                let v = i as Real * 0.17;
                assert_vec_near!(p.point(u, v), c.point(v), 1e-9);
            }
        }
    }

    #[test]
    fn uneven_parameters_and_all_conditions_hold() {
        let curves: Vec<SpaceCurve> = (0..3)
            .map(|k| curve(0.1 * k as Real, k as Real, 3))
            .collect();
        let ends = EndConditions {
            start_tangent: Some(curve(1.0, 7.0, 2)),
            start_curvature: Some(curve(-0.5, 3.0, 4)),
            end_tangent: Some(curve(0.7, 2.0, 1)),
            end_curvature: Some(curve(0.2, 5.0, 3)),
        };
        let u = [0.0, 0.3, 1.0];
        let p = Patch::interpolate(&curves, Some(&u), &ends).unwrap();
        assert_eq!(p.degree(), 6);
        for i in 0..23 {
            let v = i as Real * 0.29;
            for (k, c) in curves.iter().enumerate() {
                assert_vec_near!(p.point(u[k], v), c.point(v), 1e-9);
            }
            let e = &ends;
            assert!(
                (p.derivative(0.0, v, 1, 0) - e.start_tangent.as_ref().unwrap().point(v)).norm()
                    < 1e-9
            );
            assert!(
                (p.derivative(0.0, v, 2, 0) - e.start_curvature.as_ref().unwrap().point(v)).norm()
                    < 1e-9
            );
            assert!(
                (p.derivative(1.0, v, 1, 0) - e.end_tangent.as_ref().unwrap().point(v)).norm()
                    < 1e-9
            );
            assert!(
                (p.derivative(1.0, v, 2, 0) - e.end_curvature.as_ref().unwrap().point(v)).norm()
                    < 1e-9
            );
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let curves: Vec<SpaceCurve> = (0..4)
            .map(|k| curve(0.1 * k as Real, k as Real, 3))
            .collect();
        let p = Patch::interpolate(&curves, None, &EndConditions::NONE).unwrap();
        let h = 1e-6;
        for &(u, v) in &[(0.2, 0.3), (0.7, 4.0), (0.5, 2.2)] {
            let fu = (p.point(u + h, v) - p.point(u - h, v)) / (2.0 * h);
            let fv = (p.point(u, v + h) - p.point(u, v - h)) / (2.0 * h);
            assert_vec_near!(fu, p.du(u, v), 1e-7);
            assert_vec_near!(fv, p.dv(u, v), 1e-7);
            let fuu = (p.du(u + h, v) - p.du(u - h, v)) / (2.0 * h);
            let fuv = (p.du(u, v + h) - p.du(u, v - h)) / (2.0 * h);
            assert_vec_near!(fuu, p.derivative(u, v, 2, 0), 1e-6);
            assert_vec_near!(fuv, p.derivative(u, v, 1, 1), 1e-6);
            let c = p.u_derivative_curve(u, 1);
            assert_vec_near!(c.point(v), p.du(u, v), 1e-12);
        }
    }

    /// The grid evaluation gives exactly the pointwise numbers.
    #[test]
    fn grid_is_the_pointwise_evaluation() {
        let (p0, t0, p1, t1) = (
            curve(0.0, 1.0, 2),
            curve(1.0, 2.0, 3),
            curve(0.3, 3.0, 2),
            curve(0.5, 4.0, 1),
        );
        let p = Patch::hermite(&p0, &t0, &p1, &t1).unwrap();
        let us: Vec<Real> = (0..=7).map(|j| j as Real / 7.0).collect();
        let vs: Vec<Real> = (0..11).map(|i| i as Real * 0.57).collect();
        let g = p.grid(&us, &vs);
        assert_eq!(g.len(), us.len() * vs.len());
        for (j, &u) in us.iter().enumerate() {
            for (i, &v) in vs.iter().enumerate() {
                assert_eq!(g[j * vs.len() + i], [p.point(u, v), p.du(u, v), p.dv(u, v)]);
            }
        }
    }

    #[test]
    fn hermite_matches_its_ends() {
        let (p0, t0, p1, t1) = (
            curve(0.0, 1.0, 2),
            curve(1.0, 2.0, 3),
            curve(0.3, 3.0, 2),
            curve(0.5, 4.0, 1),
        );
        let p = Patch::hermite(&p0, &t0, &p1, &t1).unwrap();
        for i in 0..20 {
            let v = i as Real * 0.3;
            assert_vec_near!(p.point(0.0, v), p0.point(v), 1e-12);
            assert_vec_near!(p.point(1.0, v), p1.point(v), 1e-12);
            assert_vec_near!(p.du(0.0, v), t0.point(v), 1e-12);
            assert_vec_near!(p.du(1.0, v), t1.point(v), 1e-12);
        }
    }

    #[test]
    fn rejects_bad_input() {
        let c = curve(0.0, 1.0, 2);
        assert_eq!(
            Patch::interpolate(std::slice::from_ref(&c), None, &EndConditions::NONE),
            Err(PatchError::TooFewCurves { count: 1 })
        );
        let mut bad = c.clone();
        bad.y.c[2] = Real::NAN;
        assert!(matches!(
            Patch::interpolate(&[c.clone(), bad], None, &EndConditions::NONE),
            Err(PatchError::NonFinite {
                coordinate: 'y',
                index: 2,
                ..
            })
        ));
        assert!(matches!(
            Patch::interpolate(
                &[c.clone(), c.clone()],
                Some(&[0.5, 0.5]),
                &EndConditions::NONE
            ),
            Err(PatchError::BadParameters { index: 1, .. })
        ));
        assert!(matches!(
            Patch::interpolate(
                &[c.clone(), c.clone(), c.clone()],
                Some(&[0.0, 1.0]),
                &EndConditions::NONE
            ),
            Err(PatchError::ParameterCount {
                params: 2,
                curves: 3
            })
        ));
        // Curves at u = ±1/2 and a tangent condition at u = 0: the rows
        // [1, -½, ¼], [1, ½, ¼], [0, 1, 0] are dependent (a parabola symmetric
        // about 0 cannot have its slope there chosen).
        let ends = EndConditions {
            start_tangent: Some(c.clone()),
            ..EndConditions::NONE
        };
        assert_eq!(
            Patch::interpolate(&[c.clone(), c.clone()], Some(&[-0.5, 0.5]), &ends),
            Err(PatchError::Singular { size: 3 })
        );
    }
}
