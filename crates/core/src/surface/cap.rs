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
//!   `∂t/∂u = -(π/2) φ D(v)`, where `T = ∂t/∂s` is the part's tangent at its
//!   end (so the cap meets the part with tangent continuity), `a` the unit
//!   mean of `T` (the part's axis there), `h` the dome height,
//!   `λ = (π/2) h`, and `D(v) = p cos v + q sin v` the first harmonic of
//!   `C - g` projected perpendicular to `a`. Near the apex
//!   `t ≈ A + (1-u)(π/2) D(v)`: polar coordinates in the plane spanned by
//!   `p` and `q`, so the dome has one tangent plane (normal `a`) at the apex
//!   instead of a cone point. The factors π/2 make a cylinder's dome close to
//!   a quarter circle in profile (a hemisphere when `h` is the radius).
//!   The **fullness** `φ` (1 by default) keeps the dome's sections wider
//!   towards the apex along the major axis of the first harmonic's
//!   ellipse (the apex tangent is `-(π/2) D_φ(v)`, `D_φ` being `D` with
//!   that semi-axis scaled by `φ`, the other kept): on a cylinder of radius
//!   `r` the profile along that axis is `ρ(u) = r (h₀₀(u) − φ (π/2) h₁₁(u))`
//!   (`h₀₀ = 2u³ − 3u² + 1`, `h₁₁ = u³ − u²`) at the same heights, so at
//!   `u = 0.7` (0.88 `h` up) `ρ = 0.45 r` for `φ = 1` and `0.68 r` for
//!   `φ = 2`; `ρ` stays within 0.04 % of `r` before it falls for `φ ≤ 2`.
//!   A mitten over fingers spread in a fan needs the wider end, and a flat
//!   hand's thickness does not. The **axis** `a` is the mean of `T` by
//!   default ([`DomeAxis::Tangent`]); with [`DomeAxis::Normal`] it is the
//!   end curve's plane normal (on `T`'s side), the apex straight above the
//!   curve's centre: where the last sections' centres drift sideways (a
//!   hand whose last loops shift with the thumb and fingers) the tangent's
//!   mean tilts by tens of degrees and the dome points past the fingers.

use crate::curve::series::Series;
use crate::curve::trig::{SpaceCurve, TrigCurve};
use crate::geom::math::{mean_radius, Point3, Real, Vec3};
use crate::surface::patch::{Patch, PatchError};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;
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
    /// hemisphere); `fullness` `φ` (1, the default, is left out of files)
    /// widens its sections towards the apex (module doc).
    Dome {
        relative_height: Real,
        #[serde(default = "unit", skip_serializing_if = "is_unit")]
        fullness: Real,
        #[serde(default, skip_serializing_if = "DomeAxis::is_tangent")]
        axis: DomeAxis,
    },
}

/// Which way a dome rises from its end curve (module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DomeAxis {
    /// Along the mean of the part's end tangent (the default, left out of
    /// files).
    #[default]
    Tangent,
    /// Along the end curve's plane normal, on the tangent's side.
    Normal,
}

impl DomeAxis {
    fn is_tangent(&self) -> bool {
        *self == DomeAxis::Tangent
    }
}

fn unit() -> Real {
    1.0
}

fn is_unit(x: &Real) -> bool {
    *x == 1.0
}

/// The default relative dome height: 1 (a hemisphere-like tip).
pub const DEFAULT_DOME_HEIGHT: Real = 1.0;

impl CapKind {
    /// The numbers a model file stores for the cap (method.md §7): none for
    /// an open or flat end; a dome's height, and its fullness and axis
    /// when not the defaults (the fields a file leaves out otherwise).
    pub fn design_parameters(&self) -> usize {
        match self {
            CapKind::Open | CapKind::Flat => 0,
            CapKind::Dome { fullness, axis, .. } => {
                1 + usize::from(!is_unit(fullness)) + usize::from(!axis.is_tangent())
            }
        }
    }

    /// A dome of the default height.
    pub fn dome() -> CapKind {
        CapKind::Dome {
            relative_height: DEFAULT_DOME_HEIGHT,
            fullness: 1.0,
            axis: DomeAxis::Tangent,
        }
    }
}

/// What prevents building a cap.
#[derive(Debug, Error, PartialEq)]
pub enum CapError {
    #[error("the dome height must be finite and positive, got {0}")]
    BadHeight(Real),
    #[error("the dome fullness must be finite and positive, got {0}")]
    BadFullness(Real),
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
    curve
        .area_centroid()
        .unwrap_or_else(|| curve.world_series().mean_point())
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

/// The first harmonic `D(v) = p cos v + q sin v` (an ellipse) with its
/// major semi-axis `M = D(v*)`, `tan 2v* = 2 p·q / (|p|² − |q|²)`, scaled
/// by `fullness` and its minor one kept: `p + (φ − 1)(p·M̂) M̂`, and the
/// same for `q`. A flat hand's dome widens across the fingers' fan and
/// keeps its thickness.
fn widened(p: Vec3, q: Vec3, fullness: Real) -> (Vec3, Vec3) {
    if fullness == 1.0 {
        return (p, q);
    }
    let v = 0.5 * (2.0 * p.dot(q)).atan2(p.dot(p) - q.dot(q));
    let Some(major) = (p * v.cos() + q * v.sin()).normalized() else {
        return (p, q);
    };
    let k = fullness - 1.0;
    (
        p + major * (k * p.dot(major)),
        q + major * (k * q.dot(major)),
    )
}

/// The dome cap of `curve` (see the module doc). `tangent` is the part's
/// `∂t/∂s` at this end, pointing out of the part (negate it at the start).
pub fn dome_cap(
    curve: &TrigCurve,
    tangent: &SpaceCurve,
    relative_height: Real,
    fullness: Real,
    axis: DomeAxis,
) -> Result<Cap, CapError> {
    if !(relative_height.is_finite() && relative_height > 0.0) {
        return Err(CapError::BadHeight(relative_height));
    }
    if !(fullness.is_finite() && fullness > 0.0) {
        return Err(CapError::BadFullness(fullness));
    }
    let c = curve.world_series();
    let g = centre(curve);
    let kind = CapKind::Dome {
        relative_height,
        fullness,
        axis,
    };
    let mean = tangent.mean_point().normalized().ok_or(CapError::NoAxis)?;
    let axis = match axis {
        DomeAxis::Tangent => mean,
        DomeAxis::Normal => {
            let n = curve.frame.normal();
            if n.dot(mean) < 0.0 {
                -n
            } else {
                n
            }
        }
    };
    // Mean radius from the area; the RMS distance to the centre when flat.
    let mut radius = mean_radius(curve.area());
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
    let (p, q) = widened(first(1), first(2), fullness);
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
    Ok(Cap { kind, patch, apex })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_vec_near;
    use crate::curve::trig::Frame;

    fn unit_axis_tangent(order: usize) -> SpaceCurve {
        constant_curve(Vec3::Z, order)
    }

    #[test]
    fn flat_cap_spans_the_disc() {
        let c = TrigCurve::circle(Frame::XY, 0.5, 3);
        let cap = flat_cap(&c).unwrap();
        for i in 0..20 {
            let v = i as Real * 0.31;
            assert_vec_near!(cap.patch.point(0.0, v), c.point(v), 1e-15);
            assert!(cap.patch.point(1.0, v).norm() < 1e-15);
            let p = cap.patch.point(0.4, v);
            crate::assert_near!(p.norm(), 0.3, 1e-14);
            // Outward for an end cap of a part running along +z.
            assert_vec_near!(cap.patch.normal(0.4, v).unwrap(), Vec3::Z, 1e-12);
        }
    }

    #[test]
    fn dome_on_a_cylinder_is_nearly_a_hemisphere_and_smooth() {
        let r = 0.2;
        let c = TrigCurve::circle(Frame::XY, r, 2);
        let cap = dome_cap(&c, &unit_axis_tangent(2), 1.0, 1.0, DomeAxis::Tangent).unwrap();
        assert_vec_near!(cap.apex, Vec3::new(0.0, 0.0, r), 1e-14);
        for i in 0..24 {
            let v = i as Real * 0.26;
            // Tangent continuity with the cylinder at u = 0.
            let du = cap.patch.du(0.0, v).normalized().unwrap();
            assert_vec_near!(du, Vec3::Z, 1e-14);
            // The profile stays within 3 % of the sphere.
            for k in 0..=10 {
                let p = cap.patch.point(k as Real / 10.0, v);
                assert!((p.norm() - r).abs() < 0.03 * r, "{}", p.norm());
            }
            // Normals approach the axis at the apex (one tangent plane).
            let n = cap.patch.normal(1.0 - 1e-6, v).unwrap();
            assert_vec_near!(n, Vec3::Z, 1e-4);
        }
        assert_eq!(
            dome_cap(&c, &unit_axis_tangent(2), -1.0, 1.0, DomeAxis::Tangent),
            Err(CapError::BadHeight(-1.0))
        );
    }

    #[test]
    fn a_fuller_dome_widens_along_its_major_axis_to_the_same_apex() {
        // An elliptic end, semi-axes 0.2 (x) and 0.1 (y), like a flat hand.
        let c = TrigCurve::new(Frame::XY, vec![0.0, 0.2, 0.0], vec![0.0, 0.1, 0.0]).unwrap();
        let t = unit_axis_tangent(2);
        let plain = dome_cap(&c, &t, 2.0, 1.0, DomeAxis::Tangent).unwrap();
        let full = dome_cap(&c, &t, 2.0, 2.0, DomeAxis::Tangent).unwrap();
        assert_vec_near!(plain.apex, full.apex, 1e-15);
        for k in 0..=20 {
            let u = k as Real / 20.0;
            // The same heights (the axial part does not depend on φ).
            for v in [0.0, 0.3, FRAC_PI_2] {
                crate::assert_near!(plain.patch.point(u, v).z, full.patch.point(u, v).z, 1e-14);
            }
            // The profile of the module doc along the major axis,
            // ρ = a (h00 − φ (π/2) h11); the minor axis as without φ.
            let (h00, h11) = (2.0 * u.powi(3) - 3.0 * u * u + 1.0, u.powi(3) - u * u);
            for (cap, phi) in [(&plain, 1.0), (&full, 2.0)] {
                let p = cap.patch.point(u, 0.0);
                crate::assert_near!(p.x, 0.2 * (h00 - phi * FRAC_PI_2 * h11), 1e-14);
                crate::assert_near!(p.y, 0.0, 1e-14);
                let q = cap.patch.point(u, FRAC_PI_2);
                crate::assert_near!(q.y, 0.1 * (h00 - FRAC_PI_2 * h11), 1e-14);
                crate::assert_near!(q.x, 0.0, 1e-14);
            }
            // Never past the end's width by more than 0.04 %.
            assert!(full.patch.point(u, 0.0).x <= 1.0004 * 0.2);
        }
        crate::assert_near!(full.patch.point(0.7, 0.0).x / 0.2, 0.678, 1e-3);
        crate::assert_near!(plain.patch.point(0.7, 0.0).x / 0.2, 0.447, 1e-3);
        // A fullness of 1 is the plain dome, coefficient for coefficient.
        assert_eq!(
            dome_cap(&c, &t, 2.0, 1.0, DomeAxis::Tangent).unwrap(),
            plain
        );
        assert!(matches!(
            dome_cap(&c, &t, 1.0, Real::NAN, DomeAxis::Tangent),
            Err(CapError::BadFullness(x)) if x.is_nan()
        ));
        assert_eq!(
            dome_cap(&c, &t, 1.0, 0.0, DomeAxis::Tangent).map(|_| ()),
            Err(CapError::BadFullness(0.0))
        );
    }

    #[test]
    fn a_cap_counts_the_numbers_its_file_stores() {
        let dome = |fullness, axis| CapKind::Dome {
            relative_height: 1.2,
            fullness,
            axis,
        };
        assert_eq!(CapKind::Open.design_parameters(), 0);
        assert_eq!(CapKind::Flat.design_parameters(), 0);
        assert_eq!(CapKind::dome().design_parameters(), 1);
        assert_eq!(dome(1.5, DomeAxis::Tangent).design_parameters(), 2);
        assert_eq!(dome(1.0, DomeAxis::Normal).design_parameters(), 2);
        assert_eq!(dome(2.0, DomeAxis::Normal).design_parameters(), 3);
    }

    #[test]
    fn a_dome_along_the_normal_rises_above_the_centre_whatever_the_tangent() {
        let c = TrigCurve::circle(Frame::XY, 0.1, 2);
        // A tangent tilted 45 degrees in x.
        let t = constant_curve(Vec3::new(1.0, 0.0, 1.0), 2);
        let along = dome_cap(&c, &t, 1.5, 1.0, DomeAxis::Normal).unwrap();
        assert_vec_near!(along.apex, Vec3::new(0.0, 0.0, 0.15), 1e-14);
        let tilted = dome_cap(&c, &t, 1.5, 1.0, DomeAxis::Tangent).unwrap();
        let s = 0.15 / 2f64.sqrt();
        assert_vec_near!(tilted.apex, Vec3::new(s, 0.0, s), 1e-14);
        // Both leave the curve along the part's tangent (C1 at u = 0).
        for cap in [&along, &tilted] {
            for i in 0..8 {
                let v = i as Real * 0.8;
                assert_vec_near!(cap.patch.point(0.0, v), c.point(v), 1e-15);
                let du = cap.patch.du(0.0, v).normalized().unwrap();
                assert_vec_near!(du, Vec3::new(1.0, 0.0, 1.0).normalized().unwrap(), 1e-14);
            }
        }
        // A normal against the tangent is turned to the tangent's side.
        let down = constant_curve(Vec3::new(0.0, 0.0, -1.0), 2);
        let below = dome_cap(&c, &down, 1.0, 1.0, DomeAxis::Normal).unwrap();
        assert_vec_near!(below.apex, Vec3::new(0.0, 0.0, -0.1), 1e-14);
    }
}
