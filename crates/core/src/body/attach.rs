//! Limbs attached to their parents where nothing else joins them.
//!
//! An arm whose shoulder transition was left out (or never planned: an
//! arm held out sideways) relies on the torso reaching into it. When the
//! arm's tube starts short of the torso (an upper arm pressed to the
//! trunk, whose cuts took in the trunk and were dropped), the two solids
//! do not meet and the closed skin comes out in pieces: a floating arm.
//! Such an arm gets its first section again, carried back along its axis
//! by steps of the section spacing until the copy's centre lies inside the
//! torso, and one step further so that the two solids overlap. A digit
//! whose first section (already repeated back inside the palm as built)
//! still lies outside its hand, a thumb leaving the palm sideways, is
//! carried back into the hand the same way; where its own tube leads back
//! beside the palm (a scan's finger cut obliquely), back and towards the
//! hand's centre line.

use super::*;
use crate::geom::math::Point2;
use crate::section::mesh::point_in_polygon;

/// Points around a part's curve for the inside test.
const AROUND: usize = 64;

/// Whether `p` lies inside `part`: inside its curve at the height of `p`
/// along `up` (the part's centre line rising along it), both projected
/// across `up`.
fn inside_at_level(part: &Part, up: Vec3, p: Point3) -> bool {
    part.s_at_level(up, p.dot(up))
        .is_some_and(|s| inside_across(part, s, up, p))
}

/// Whether `p`, seen along `dir`, lies inside `part`'s curve at `s`.
fn inside_across(part: &Part, s: Real, dir: Vec3, p: Point3) -> bool {
    let e1 = dir.any_perpendicular();
    let e2 = dir.cross(e1);
    let flat = |q: Point3| Point2::new(q.dot(e1), q.dot(e2));
    let poly: Vec<Point2> = (0..AROUND)
        .map(|k| {
            let v = std::f64::consts::TAU * k as Real / AROUND as Real;
            flat(part.point(s, v))
        })
        .collect();
    point_in_polygon(flat(p), &poly)
}

/// The centre line's parameter of `part` nearest `p`: the nearest of
/// [`AROUND`] + 1 samples, refined between its neighbours.
fn nearest_on_centre(part: &Part, p: Point3) -> Option<Real> {
    let l = part.length();
    if !(l > 0.0) {
        return None;
    }
    let at = |k: usize| l * k as Real / AROUND as Real;
    let near = |s: Real| part.centre(s).distance(p);
    let k = (0..=AROUND).min_by(|&a, &b| near(at(a)).total_cmp(&near(at(b))))?;
    // Golden-section search between the neighbouring samples.
    let (mut a, mut b) = (at(k.saturating_sub(1)), at((k + 1).min(AROUND)));
    for _ in 0..40 {
        let (c, d) = (b - 0.618 * (b - a), a + 0.618 * (b - a));
        if near(c) < near(d) {
            b = d;
        } else {
            a = c;
        }
    }
    Some(0.5 * (a + b))
}

/// Whether `p` lies inside `part`'s tube: inside its curve at the centre
/// line's point nearest `p`, both projected across the centre line there
/// (a palm's flat, tilted end seen along the hand's direction can be a
/// sliver that nothing lies inside).
fn inside_tube(part: &Part, p: Point3) -> bool {
    let Some(s) = nearest_on_centre(part, p) else {
        return false;
    };
    let (l, h) = (part.length(), 1e-3 * part.length());
    (part.centre((s + h).min(l)) - part.centre((s - h).max(0.0)))
        .normalized()
        .is_some_and(|t| inside_across(part, s, t, p))
}

/// `part` (its section fits `fits`) with its first section repeated back
/// along its axis (or along `towards`, a unit vector, when given) until
/// its centre lies `inside` the part it joins (module doc): steps of
/// `step`, at most `reach` back; with how far it was carried. `None` when its first section's centre already lies
/// inside, or no step within `reach` gets there.
pub(super) fn carried_back(
    (part, fits): (&Part, &[SectionFit]),
    inside: &dyn Fn(Point3) -> bool,
    (step, reach): (Real, Real),
    towards: Option<Vec3>,
) -> Option<(Part, Vec<SectionFit>, Real)> {
    let start = part.centre(0.0);
    if inside(start) || !(step > 0.0) {
        return None;
    }
    let back = match towards {
        Some(d) => d,
        None => (start - part.centre((0.5 * step).min(part.length()))).normalized()?,
    };
    let steps = (reach / step).floor() as usize;
    let k = (1..=steps).find(|&k| inside(start + back * (k as Real * step)))?;
    let shift = back * ((k + 1) as Real * step);
    let mut first = part.sections().first()?.clone();
    first.frame.origin += shift;
    let mut curves = vec![first];
    curves.extend(part.sections().iter().cloned());
    let carried = Part::new(curves, part.options()).ok()?;
    let mut fits = fits.to_vec();
    let at = fits.first()?.at - shift.norm() / part.length().max(Real::MIN_POSITIVE);
    fits.insert(0, SectionFit { at, ..fits[0] });
    Some((carried, fits, shift.norm()))
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
    let h = seg.height;
    let (step, reach) = (opts.spacing * h, ATTACH_REACH * h);
    let Some(torso) = parts.iter().find(|p| p.name == PartName::Torso) else {
        return;
    };
    let torso = torso.part.clone();
    let up = seg.frame.up;
    let inside = |q: Point3| inside_at_level(&torso, up, q);
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
        if let Some((part, fits, by)) =
            carried_back((&p.part, &p.fits), &inside, (step, reach), None)
        {
            (p.part, p.fits) = (part, fits);
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

/// Each digit whose first section's centre lies outside its hand (at its
/// level along the hand's direction at its end, and across the hand's
/// centre line nearest it), carried back into it ([`carried_back`]:
/// along the digit's tube, else straight to the hand's centre line; at
/// most [`DIGIT_REACH`] × `H`, by steps of [`DIGIT_SPACING`] × `H`),
/// with a warning: a thumb that leaves the palm sideways can start beside
/// it.
pub(super) fn attach_digits(
    parts: &[BodyPart],
    digits: &mut [BodyDigit],
    h: Real,
    warnings: &mut Vec<String>,
) {
    let (step, reach) = (DIGIT_SPACING * h, DIGIT_REACH * h);
    let numbers = super::digits::digit_numbers(digits);
    for (d, k) in digits.iter_mut().zip(numbers) {
        let Some(hand) = parts.iter().find(|p| p.name == d.hand) else {
            continue;
        };
        let l = hand.part.length();
        let end = hand.part.centre(l);
        let Some(along) = (end - hand.part.centre((l - DIGIT_REACH * h).max(0.0))).normalized()
        else {
            continue;
        };
        let inside =
            |q: Point3| inside_at_level(&hand.part, along, q) || inside_tube(&hand.part, q);
        // Back along its own tube, else (a finger cut obliquely, whose
        // tube leads back beside the palm) halfway between that and
        // straight to the hand's centre line (so that the copy is not in
        // its first section's plane).
        let start = d.part.centre(0.0);
        let back = start - d.part.centre((0.5 * step).min(d.part.length()));
        let to_hand = nearest_on_centre(&hand.part, start).and_then(|s| {
            let towards = (hand.part.centre(s) - start).normalized()?;
            (towards + back.normalized()?).normalized()
        });
        let (digit, span) = ((&d.part, &d.fits[..]), (step, reach));
        let carried = carried_back(digit, &inside, span, None)
            .or_else(|| carried_back(digit, &inside, span, Some(to_hand?)));
        if let Some((part, fits, by)) = carried {
            (d.part, d.fits) = (part, fits);
            warnings.push(format!(
                "{}: digit {k}: its tube started outside the hand; its first section is repeated {:.1} % of the height back along it, inside the hand",
                d.hand,
                100.0 * by / h
            ));
        }
    }
}

/// How far back (fraction of `H`) a digit's first section may be carried
/// to reach its hand ([`attach_digits`]): about a finger's length.
pub const DIGIT_REACH: Real = 0.05;

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
        assert!(!inside_at_level(&torso, up, arm.part.centre(0.0)));
        // Tilted in towards the torso's axis, its axis reaches it.
        let tilted = arm_of(tube(
            Point3::new(0.25, 0.0, 1.2),
            Point3::new(0.45, 0.0, 0.7),
            0.04,
            6,
        ));
        let (carried, fits, moved) = carried_back(
            (&tilted.part, &tilted.fits),
            &|q| inside_at_level(&torso, up, q),
            (0.02, 0.3),
            None,
        )
        .expect("carried");
        assert_eq!(carried.sections().len(), 7);
        assert_eq!(fits.len(), 7);
        assert!(fits[0].at < fits[1].at);
        let first = carried.centre(0.0);
        let in_torso = |q: Point3| inside_at_level(&torso, up, q);
        assert!(in_torso(first), "{first:?}");
        assert!(moved <= 0.3 + 0.02 && moved > 0.1, "{moved}");
        // The rest of the arm is as it was.
        let old = tilted.part.centre(tilted.part.length());
        let new = carried.centre(carried.length());
        assert!(old.distance(new) < 1e-9, "{old:?} {new:?}");
        // Hanging straight down, its axis never meets the torso: left alone.
        assert!(carried_back((&arm.part, &arm.fits), &in_torso, (0.02, 0.3), None).is_none());
        // An arm starting inside the torso already is left alone.
        let inside = arm_of(tube(
            Point3::new(0.1, 0.0, 1.2),
            Point3::new(0.3, 0.0, 0.7),
            0.04,
            6,
        ));
        let inside = (&inside.part, &inside.fits[..]);
        assert!(carried_back(inside, &in_torso, (0.02, 0.3), None).is_none());
    }

    /// A digit hanging beside its palm, parallel to it: back along its
    /// own tube it never enters the palm; it is carried back and towards
    /// the palm's centre line instead, into the palm.
    #[test]
    fn a_digit_beside_its_palm_is_carried_to_it() {
        let palm = arm_of(tube(
            Point3::new(0.0, 0.0, 1.0),
            Point3::new(0.0, 0.0, 0.8),
            0.04,
            5,
        ));
        let finger = tube(
            Point3::new(0.07, 0.0, 0.82),
            Point3::new(0.07, 0.0, 0.74),
            0.008,
            4,
        );
        let fits = arm_of(finger.clone()).fits;
        let mut digits = vec![BodyDigit {
            hand: PartName::LeftArm,
            part: finger,
            fits,
        }];
        let mut warnings = Vec::new();
        attach_digits(std::slice::from_ref(&palm), &mut digits, 1.7, &mut warnings);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        let first = digits[0].part.centre(0.0);
        assert!(inside_tube(&palm.part, first), "{first:?}");
        assert!(first.x < 0.04 && first.z > 0.82, "{first:?}");
    }
}
