//! Sections added where a fitted part's points still lie far: the
//! interval's own surface curve, flattened into a plane halfway between
//! its neighbours', for the fit to move.

use super::{Foot, SurfaceFitOptions};
use crate::curve::trig::{standard_to_paper_b, Frame, SpaceCurve, TrigCurve};
use crate::geom::math::{Real, Vec3};
use crate::surface::part::Part;

/// Points an interval needs before its residual may add a section.
const SPLIT_POINTS: usize = 20;

/// `part` with a section added halfway along every interval whose points
/// (their feet there, off the ends, weighted) lie farther than
/// [`SurfaceFitOptions::split`] from it at the 90th percentile, and whose
/// two sections are more than twice [`SurfaceFitOptions::min_gap`] apart.
/// The new section is the surface's own curve there, flattened into the
/// plane halfway between its neighbours'. `None` when none is added (or
/// the part would not be valid with them).
pub(super) fn split_where_far(
    part: &Part,
    feet: &[Option<Foot>],
    weights: &[Real],
    opts: &SurfaceFitOptions,
) -> Option<Part> {
    let segments = part.segments();
    let curves = part.curves();
    if segments.len() + 1 != curves.len() {
        return None; // one patch per interval only
    }
    let mut residuals: Vec<Vec<Real>> = vec![Vec::new(); segments.len()];
    for (foot, &w) in feet.iter().zip(weights) {
        if let Some(f) = foot.filter(|f| !f.at_end && w > 0.0) {
            residuals[part.locate(f.s).0].push(f.signed.abs());
        }
    }
    let mut sections: Vec<TrigCurve> = Vec::with_capacity(2 * curves.len());
    let mut added = 0;
    for (i, section) in part.sections().iter().enumerate() {
        sections.push(section.clone());
        let Some(r) = residuals.get_mut(i) else {
            continue;
        };
        // A segment's length is its two centres' distance (the knots).
        if r.len() < SPLIT_POINTS || segments[i].length() <= 2.0 * opts.min_gap {
            continue;
        }
        let k = (0.9 * (r.len() - 1) as Real).round() as usize;
        let (_, &mut p90, _) = r.select_nth_unstable_by(k, Real::total_cmp);
        if p90 <= opts.split {
            continue;
        }
        if let Some(c) =
            halfway_section(&segments[i].patch.curve_at(0.5), &curves[i], &curves[i + 1])
        {
            sections.push(c);
            added += 1;
        }
    }
    if added == 0 {
        return None;
    }
    Part::new(sections, part.options()).ok()
}

/// The space curve `c` flattened into the plane through its centre whose
/// normal and first axis are halfway between `a`'s and `b`'s.
pub(super) fn halfway_section(c: &SpaceCurve, a: &TrigCurve, b: &TrigCurve) -> Option<TrigCurve> {
    let origin = c.mean_point();
    let frame = Frame::from_normal(
        origin,
        a.frame.normal() + b.frame.normal(),
        a.frame.e1 + b.frame.e1,
    )?;
    let c = c.with_order(c.order());
    let along = |e: Vec3| -> Vec<Real> {
        let mut out: Vec<Real> = (0..c.x.c.len())
            .map(|k| Vec3::new(c.x.c[k], c.y.c[k], c.z.c[k]).dot(e))
            .collect();
        out[0] -= origin.dot(e);
        out
    };
    let (x, y) = (along(frame.e1), along(frame.e2));
    TrigCurve::new(frame, x, standard_to_paper_b(&y)).ok()
}
