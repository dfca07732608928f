//! Closing the open ends of a part (method.md §5, §8: head top, finger
//! tips, toes, soles, cuts).
//!
//! Both caps are [`Patch`]es that start at the part's end curve (`u = 0`) and
//! collapse to one point, the apex, at `u = 1`:
//!
//! * **Flat**: `t(u, v) = (1-u) C(v) + u g`, the plane region of the end curve
//!   `C` swept to its area centroid `g` (a sole, a cut).
//! * **Dome**: the cubic Hermite patch (in `u`, coefficient-wise) from `C`
//!   with `∂t/∂u = λ T(v)` to the apex `A = g + h a` with
//!   `∂t/∂u = -(π/2) D(v)`, where `T = ∂t/∂s` is the part's tangent at its
//!   end (so the cap meets the part with tangent continuity), `a` the unit
//!   mean of `T` (the part's axis there), `h` the dome height,
//!   `λ = (π/2) h`, and `D(v) = p cos v + q sin v` the first harmonic of
//!   `C - g` projected perpendicular to `a`. Near the apex
//!   `t ≈ A + (1-u)(π/2) D(v)`: polar coordinates in the plane spanned by
//!   `p` and `q`, so the dome has one tangent plane (normal `a`) at the apex
//!   instead of a cone point. The factors π/2 make a cylinder's dome close to
//!   a quarter circle in profile (a hemisphere when `h` is the radius).

use crate::curve::{SpaceCurve, TrigCurve};
use crate::math::{Point3, Real, Vec3};
use crate::patch::{Patch, PatchError};
use crate::series::Series;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};
use thiserror::Error;

/// How an end of a part is closed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum CapKind {
    /// Left open (the default: the end joins another part by a transition).
    #[default]
    Open,
    /// A planar cap from the end curve to its area centroid.
    Flat,
    /// A smooth dome; its height is `relative_height` times the end curve's
    /// mean radius `sqrt(|area| / π)` ([`DEFAULT_DOME_HEIGHT`] = 1: about a
    /// hemisphere).
    Dome { relative_height: Real },
}

/// The default relative dome height: 1 (a hemisphere-like tip).
pub const DEFAULT_DOME_HEIGHT: Real = 1.0;

impl CapKind {
    /// A dome of the default height.
    pub fn dome() -> CapKind {
        CapKind::Dome {
            relative_height: DEFAULT_DOME_HEIGHT,
        }
    }
}

/// What prevents building a cap.
#[derive(Debug, Error, PartialEq)]
pub enum CapError {
    #[error("the dome height must be finite and positive, got {0}")]
    BadHeight(Real),
    #[error("the end curve encloses no area and has no extent: nothing to cap")]
    DegenerateCurve,
    #[error("the part's end tangent has no direction to put a dome on")]
    NoAxis,
    #[error(transparent)]
    Patch(#[from] PatchError),
}

/// A closed end: a patch from the end curve (`u = 0`) to the apex (`u = 1`).
#[derive(Clone, Debug, PartialEq)]
pub struct Cap {
    pub kind: CapKind,
    pub patch: Patch,
    /// The point where the patch collapses (`t(1, v)` for every `v`).
    pub apex: Point3,
}

fn constant_curve(p: Point3, order: usize) -> SpaceCurve {
    let c = |x: Real| {
        let mut s = Series::zeros(order);
        s.c[0] = x;
        s
    };
    SpaceCurve {
        x: c(p.x),
        y: c(p.y),
        z: c(p.z),
    }
}

/// The centre of the end curve: its area centroid, or the mean point when it
/// encloses no area.
fn centre(curve: &TrigCurve) -> Point3 {
    let w = curve.world_series();
    curve
        .area_centroid()
        .unwrap_or_else(|| Vec3::new(w.x.c[0], w.y.c[0], w.z.c[0]))
}

/// The flat cap `t(u, v) = (1-u) C(v) + u g` of `curve`.
pub fn flat_cap(curve: &TrigCurve) -> Result<Cap, CapError> {
    let c = curve.world_series();
    let g = centre(curve);
    let f1 = SpaceCurve {
        x: Series {
            c: c.x
                .c
                .iter()
                .enumerate()
                .map(|(i, x)| if i == 0 { g.x - x } else { -x })
                .collect(),
        },
        y: Series {
            c: c.y
                .c
                .iter()
                .enumerate()
                .map(|(i, x)| if i == 0 { g.y - x } else { -x })
                .collect(),
        },
        z: Series {
            c: c.z
                .c
                .iter()
                .enumerate()
                .map(|(i, x)| if i == 0 { g.z - x } else { -x })
                .collect(),
        },
    };
    Ok(Cap {
        kind: CapKind::Flat,
        patch: Patch::from_coefficients(vec![c, f1])?,
        apex: g,
    })
}

/// The dome cap of `curve` (see the module doc). `tangent` is the part's
/// `∂t/∂s` at this end, pointing out of the part (negate it at the start).
pub fn dome_cap(
    curve: &TrigCurve,
    tangent: &SpaceCurve,
    relative_height: Real,
) -> Result<Cap, CapError> {
    if !(relative_height.is_finite() && relative_height > 0.0) {
        return Err(CapError::BadHeight(relative_height));
    }
    let c = curve.world_series();
    let g = centre(curve);
    let axis = Vec3::new(tangent.x.c[0], tangent.y.c[0], tangent.z.c[0])
        .normalized()
        .ok_or(CapError::NoAxis)?;
    // Mean radius from the area; the RMS distance to the centre when flat.
    let mut radius = (curve.area().abs() / PI).sqrt();
    if radius.is_nan() || radius <= 0.0 {
        let n = 64;
        radius = (curve
            .sample(n)
            .iter()
            .map(|p| p.distance(g).powi(2))
            .sum::<Real>()
            / n as Real)
            .sqrt();
    }
    if !(radius.is_finite() && radius > 0.0) {
        return Err(CapError::DegenerateCurve);
    }
    let h = relative_height * radius;
    let apex = g + axis * h;
    let order = c.order().max(tangent.order());
    // First harmonic of C - g, perpendicular to the axis.
    let first = |k: usize| {
        let v = Vec3::new(
            c.x.c.get(k).copied().unwrap_or(0.0),
            c.y.c.get(k).copied().unwrap_or(0.0),
            c.z.c.get(k).copied().unwrap_or(0.0),
        );
        v - axis * v.dot(axis)
    };
    let (p, q) = (first(1), first(2));
    let mut d = SpaceCurve {
        x: Series::zeros(order),
        y: Series::zeros(order),
        z: Series::zeros(order),
    };
    for (s, (pp, qq)) in
        [&mut d.x, &mut d.y, &mut d.z]
            .into_iter()
            .zip([(p.x, q.x), (p.y, q.y), (p.z, q.z)])
    {
        s.c[1] = -FRAC_PI_2 * pp;
        s.c[2] = -FRAC_PI_2 * qq;
    }
    let lambda = FRAC_PI_2 * h;
    let t0 = SpaceCurve {
        x: Series {
            c: tangent.x.c.iter().map(|x| x * lambda).collect(),
        },
        y: Series {
            c: tangent.y.c.iter().map(|x| x * lambda).collect(),
        },
        z: Series {
            c: tangent.z.c.iter().map(|x| x * lambda).collect(),
        },
    };
    let patch = Patch::hermite(&c, &t0, &constant_curve(apex, order), &d)?;
    Ok(Cap {
        kind: CapKind::Dome { relative_height },
        patch,
        apex,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::Frame;

    fn unit_axis_tangent(order: usize) -> SpaceCurve {
        constant_curve(Vec3::Z, order)
    }

    #[test]
    fn flat_cap_spans_the_disc() {
        let c = TrigCurve::circle(Frame::XY, 0.5, 3);
        let cap = flat_cap(&c).unwrap();
        for i in 0..20 {
            let v = i as Real * 0.31;
            assert!((cap.patch.point(0.0, v) - c.point(v)).norm() < 1e-15);
            assert!(cap.patch.point(1.0, v).norm() < 1e-15);
            let p = cap.patch.point(0.4, v);
            crate::assert_near!(p.norm(), 0.3, 1e-14);
            // Outward for an end cap of a part running along +z.
            assert!((cap.patch.normal(0.4, v).unwrap() - Vec3::Z).norm() < 1e-12);
        }
    }

    #[test]
    fn dome_on_a_cylinder_is_nearly_a_hemisphere_and_smooth() {
        let r = 0.2;
        let c = TrigCurve::circle(Frame::XY, r, 2);
        let cap = dome_cap(&c, &unit_axis_tangent(2), 1.0).unwrap();
        assert!((cap.apex - Vec3::new(0.0, 0.0, r)).norm() < 1e-14);
        for i in 0..24 {
            let v = i as Real * 0.26;
            // Tangent continuity with the cylinder at u = 0.
            let du = cap.patch.du(0.0, v).normalized().unwrap();
            assert!((du - Vec3::Z).norm() < 1e-14);
            // The profile stays within 3 % of the sphere.
            for k in 0..=10 {
                let p = cap.patch.point(k as Real / 10.0, v);
                assert!((p.norm() - r).abs() < 0.03 * r, "{}", p.norm());
            }
            // Normals approach the axis at the apex (one tangent plane).
            let n = cap.patch.normal(1.0 - 1e-6, v).unwrap();
            assert!((n - Vec3::Z).norm() < 1e-4);
        }
        assert_eq!(
            dome_cap(&c, &unit_axis_tangent(2), -1.0),
            Err(CapError::BadHeight(-1.0))
        );
    }
}
