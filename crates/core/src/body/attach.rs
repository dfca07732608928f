//! Arms attached to the torso where no shoulder transition joins them.
//!
//! An arm whose shoulder transition was left out (or never planned: an
//! arm held out sideways) relies on the torso reaching into it. When the
//! arm's tube starts short of the torso (an upper arm pressed to the
//! trunk, whose cuts took in the trunk and were dropped), the two solids
//! do not meet and the closed skin comes out in pieces: a floating arm.
//! Such an arm gets its first section again, carried back along its axis
//! by steps of the section spacing until the copy's centre lies inside the
//! torso, and one step further so that the two solids overlap (as a
//! digit's first section is repeated inside the palm).

use super::*;
use crate::geom::math::Point2;
use crate::section::mesh::point_in_polygon;

/// Points around the torso's curve for the inside test.
const AROUND: usize = 64;

/// Whether `p` lies inside the torso `torso`: inside its curve at the
/// height of `p` along `up`, both projected across `up`.
fn inside_torso(torso: &Part, up: Vec3, p: Point3) -> bool {
    let Some(s) = torso.s_at_level(up, p.dot(up)) else {
        return false;
    };
    let e1 = up.any_perpendicular();
    let e2 = up.cross(e1);
    let flat = |q: Point3| Point2::new(q.dot(e1), q.dot(e2));
    let poly: Vec<Point2> = (0..AROUND)
        .map(|k| {
            let v = std::f64::consts::TAU * k as Real / AROUND as Real;
            flat(torso.point(s, v))
        })
        .collect();
    point_in_polygon(flat(p), &poly)
}

/// `arm` with its first section repeated back along its axis into
/// `torso` (module doc): steps of `step`, at most `reach` back. `None`
/// when its first section's centre already lies inside the torso, or no
/// step within `reach` gets there.
pub(super) fn carried_back(
    arm: &BodyPart,
    torso: &Part,
    up: Vec3,
    step: Real,
    reach: Real,
) -> Option<(BodyPart, Real)> {
    let part = &arm.part;
    let start = part.centre(0.0);
    if inside_torso(torso, up, start) || !(step > 0.0) {
        return None;
    }
    let back = (start - part.centre((0.5 * step).min(part.length()))).normalized()?;
    let steps = (reach / step).floor() as usize;
    let k = (1..=steps).find(|&k| inside_torso(torso, up, start + back * (k as Real * step)))?;
    let shift = back * ((k + 1) as Real * step);
    let mut first = part.sections().first()?.clone();
    first.frame.origin += shift;
    let mut curves = vec![first];
    curves.extend(part.sections().iter().cloned());
    let carried = Part::new(curves, part.options()).ok()?;
    let mut fits = arm.fits.clone();
    let at = fits.first()?.at - shift.norm() / part.length().max(Real::MIN_POSITIVE);
    fits.insert(0, SectionFit { at, ..fits[0] });
    Some((
        BodyPart {
            name: arm.name,
            part: carried,
            fits,
        },
        shift.norm(),
    ))
}

/// Each arm that no shoulder transition joins and whose tube starts
/// outside the torso, carried back into it ([`carried_back`],
/// at most [`ATTACH_REACH`] × `H`, by steps of the section spacing), with
/// a warning.
pub(super) fn attach_arms(
    parts: &mut [BodyPart],
    shoulders: Shoulders,
    (seg, opts): (&Segmentation, &ReconstructOptions),
    warnings: &mut Vec<String>,
) {
    let (up, h) = (seg.frame.up, seg.height);
    let step = opts.spacing * h;
    let Some(torso) = parts.iter().find(|p| p.name == PartName::Torso) else {
        return;
    };
    let torso = torso.part.clone();
    for (k, arm) in [PartName::LeftArm, PartName::RightArm]
        .into_iter()
        .enumerate()
    {
        if shoulders.side[k] {
            continue;
        }
        let Some(p) = parts.iter_mut().find(|p| p.name == arm) else {
            continue;
        };
        if let Some((carried, by)) = attach::carried_back(p, &torso, up, step, ATTACH_REACH * h) {
            *p = carried;
            warnings.push(format!(
                "{arm}: its tube started outside the torso; its first section is repeated {:.0} % of the height back along its axis, inside the torso",
                100.0 * by / h
            ));
        }
    }
}

/// How far back (fraction of `H`) an arm's first section may be carried
/// to reach the torso ([`attach_arms`]).
pub const ATTACH_REACH: Real = 0.15;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::trig::Frame;

    /// A circle of radius `r` about `centre` in the plane across `normal`.
    fn circle(centre: Point3, normal: Vec3, r: Real) -> TrigCurve {
        let n = normal.normalized().unwrap();
        let e1 = n.any_perpendicular();
        let frame = Frame {
            origin: centre,
            e1,
            e2: n.cross(e1),
        };
        TrigCurve {
            frame,
            a: vec![0.0, r, 0.0],
            b: vec![0.0, r, 0.0],
        }
    }

    /// A tube of circles of radius `r` from `from` to `to`.
    fn tube(from: Point3, to: Point3, r: Real, n: usize) -> Part {
        let d = to - from;
        let curves = (0..n)
            .map(|k| circle(from + d * (k as Real / (n - 1) as Real), d, r))
            .collect();
        Part::new(curves, &PartOptions::default()).unwrap()
    }

    fn arm_of(part: Part) -> BodyPart {
        let n = part.sections().len();
        BodyPart {
            name: PartName::LeftArm,
            part,
            fits: (0..n)
                .map(|k| SectionFit {
                    at: 0.2 + 0.1 * k as Real,
                    order: 1,
                    ea: 0.0,
                    em: 0.0,
                    met: true,
                    ellipse: None,
                })
                .collect(),
        }
    }

    #[test]
    fn an_arm_short_of_the_torso_is_carried_back_into_it() {
        let up = Vec3::new(0.0, 0.0, 1.0);
        // A torso of radius 0.15 up the z axis; an arm hanging beside it,
        // 0.1 out from its side, from 1.2 down to 0.7.
        let torso = tube(
            Point3::new(0.0, 0.0, 0.8),
            Point3::new(0.0, 0.0, 1.5),
            0.15,
            8,
        );
        let arm = arm_of(tube(
            Point3::new(0.25, 0.0, 1.2),
            Point3::new(0.25, 0.0, 0.7),
            0.04,
            6,
        ));
        assert!(!inside_torso(&torso, up, arm.part.centre(0.0)));
        // Tilted in towards the torso's axis, its axis reaches it.
        let tilted = arm_of(tube(
            Point3::new(0.25, 0.0, 1.2),
            Point3::new(0.45, 0.0, 0.7),
            0.04,
            6,
        ));
        let (carried, moved) = carried_back(&tilted, &torso, up, 0.02, 0.3).expect("carried");
        assert_eq!(carried.part.sections().len(), 7);
        assert_eq!(carried.fits.len(), 7);
        assert!(carried.fits[0].at < carried.fits[1].at);
        let first = carried.part.centre(0.0);
        assert!(inside_torso(&torso, up, first), "{first:?}");
        assert!(moved <= 0.3 + 0.02 && moved > 0.1, "{moved}");
        // The rest of the arm is as it was.
        let old = tilted.part.centre(tilted.part.length());
        let new = carried.part.centre(carried.part.length());
        assert!(old.distance(new) < 1e-9, "{old:?} {new:?}");
        // Hanging straight down, its axis never meets the torso: left alone.
        assert!(carried_back(&arm, &torso, up, 0.02, 0.3).is_none());
        // An arm starting inside the torso already is left alone.
        let inside = arm_of(tube(
            Point3::new(0.1, 0.0, 1.2),
            Point3::new(0.3, 0.0, 0.7),
            0.04,
            6,
        ));
        assert!(carried_back(&inside, &torso, up, 0.02, 0.3).is_none());
    }
}
