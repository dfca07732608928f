//! The transitions that join the parts (method.md §6,
//! [`crate::surface::transition`]): each leg to its half of the torso's
//! bottom, each hanging arm to the torso's shoulder, the torso to the head.

use super::*;

/// Builds the transitions (method.md §6, [`crate::surface::transition`]): each leg's
/// first section to its half of the torso's first curve, split at the
/// crotch by the plane normal to the body's left axis (the two legs'
/// transitions close the torso's bottom); each arm on the torso's side
/// (`shoulders`) from its first section to the torso's surface cut by the
/// side plane (vertical through the armpit, [`SideCut`]); and the torso's
/// last section to the head's first where they are apart. Magnitudes are
/// fitted to the input ([`fit_magnitudes`]). When a leg's transition
/// cannot be built the torso's bottom gets a flat cap instead, with a
/// warning. Returns the transitions and, per arm (left, right), why its
/// side transition was left out, if it was (it could not be built, or it
/// strayed further from the input than [`ARM_TRANSITION_LIMIT`]; the
/// caller then rebuilds the torso to reach into that arm instead).
pub(super) fn assemble(
    parts: &mut [BodyPart],
    seg: &Segmentation,
    crotch_level: Real,
    input: &InputDistance,
    shoulders: Shoulders,
    mm_per_unit: Real,
    warnings: &mut Vec<String>,
) -> (Vec<BodyTransition>, [Option<String>; 2]) {
    let mut out = Vec::new();
    let mut poor: [Option<String>; 2] = [None, None];
    let Some(ti) = parts.iter().position(|p| p.name == PartName::Torso) else {
        return (out, poor);
    };
    let distance = |points: &[Point3]| input.distances(points);
    let build = |from: usize, spec: TransitionSpec, parts: &[BodyPart]| {
        let (f, t) = (&parts[from].part, &parts[ti].part);
        Transition::boundaries(f, t, &spec)
            .and_then(|c| {
                let magnitudes = fit_magnitudes(&c, &distance)?;
                let [p0, t0, p1, t1] = c;
                Transition::hermite(p0, t0, p1, t1, TransitionSpec { magnitudes, ..spec })
            })
            .map(|transition| BodyTransition {
                from: parts[from].name,
                to: parts[ti].name,
                transition,
            })
    };
    // Transitions from several parts over the cores, results in order; a
    // side transition with its RMS distance to the input.
    let build_all = |specs: &[(usize, TransitionSpec)], parts: &[BodyPart]| {
        crate::geom::parallel::parallel_map(specs, 1, |run| {
            run.iter()
                .map(|&(from, spec)| {
                    let built = build(from, spec, parts);
                    let rms = match (&built, spec.side) {
                        (Ok(t), Some(_)) => transition_rms(&t.transition, input),
                        _ => 0.0,
                    };
                    (built, rms)
                })
                .collect()
        })
    };
    // Legs: the seam through the crotch (its level; horizontally midway
    // between the legs' first centres).
    let leg_specs = leg_transition_specs(parts, ti, seg, crotch_level);
    let mut closed = leg_specs.len() == 2;
    // Hanging arms: the arm's first section to the torso's shoulder, cut
    // by the vertical plane through the armpit (the torso's loops above
    // the armpit stop just past it, `torso_without_arms`).
    let arms = arm_transition_specs(parts, seg, shoulders);
    // A side arm left out of the model, or whose axis line never meets its
    // side plane, has no transition either: the torso must reach into it
    // instead.
    for (k, arm) in [PartName::LeftArm, PartName::RightArm]
        .into_iter()
        .enumerate()
    {
        if shoulders.side_of(arm) && !arms.iter().any(|&(i, _)| parts[i].name == arm) {
            poor[k] = Some("no arm, or its axis misses the side plane".to_string());
        }
    }
    // The legs' and the arms' transitions together over the cores (a
    // flat cap on the torso's bottom does not move its shoulder).
    let all: Vec<(usize, TransitionSpec)> = leg_specs.iter().chain(&arms).copied().collect();
    let mut results = build_all(&all, parts).into_iter();
    for &(li, _) in &leg_specs {
        match results.next().map(|r| r.0) {
            Some(Ok(t)) => out.push(t),
            Some(Err(e)) => {
                warnings.push(format!(
                    "{}: no transition to the torso ({e})",
                    parts[li].name
                ));
                closed = false;
            }
            None => closed = false,
        }
    }
    if !closed {
        close_bottom_flat(&mut parts[ti], warnings);
    }
    let limit = ARM_TRANSITION_LIMIT * seg.height;
    for (&(ai, _), (result, rms)) in arms.iter().zip(results) {
        let k = usize::from(parts[ai].name == PartName::RightArm);
        match result {
            Ok(t) if rms <= limit => out.push(t),
            Ok(_) => {
                poor[k] = Some(format!(
                    "it lay {:.1} mm RMS from the input, over {:.1} mm",
                    rms * mm_per_unit,
                    limit * mm_per_unit
                ))
            }
            Err(e) => poor[k] = Some(e.to_string()),
        }
    }
    // Neck: torso's last section to the head's first, where apart.
    if let Some(t) = neck_transition(parts, ti, seg, input, warnings) {
        out.push(t);
    }
    (out, poor)
}

/// The legs' transitions to the torso (part `ti`): both or none, each
/// ending on the seam through the crotch (at its level, horizontally midway
/// between the legs' first centres).
fn leg_transition_specs(
    parts: &[BodyPart],
    ti: usize,
    seg: &Segmentation,
    crotch_level: Real,
) -> Vec<(usize, TransitionSpec)> {
    let legs: Vec<usize> = parts
        .iter()
        .enumerate()
        .filter(|(_, p)| matches!(p.name, PartName::LeftLeg | PartName::RightLeg))
        .map(|(i, _)| i)
        .collect();
    let leg_centre = |i: usize| parts[i].part.curves()[0].frame.origin;
    let mut leg_specs: Vec<(usize, TransitionSpec)> = Vec::new();
    let up = seg.frame.up;
    if legs.len() == 2 {
        let mid = (leg_centre(legs[0]) + leg_centre(legs[1])) * 0.5;
        let point = mid + up * (crotch_level - mid.dot(up));
        let torso_order = parts[ti].part.curves()[0].order();
        leg_specs = legs
            .iter()
            .map(|&li| {
                let side = (leg_centre(li) - point).dot(seg.frame.left);
                let spec = TransitionSpec {
                    from_start: true,
                    to_start: true,
                    magnitudes: [1.0, 1.0],
                    seam: Some(Seam {
                        point,
                        normal: seg.frame.left * side.signum(),
                        up,
                    }),
                    side: None,
                    order: torso_order.clamp(6, 16),
                };
                (li, spec)
            })
            .collect();
    }
    leg_specs
}

/// The hanging arms' transitions: the arm's first section to the torso's
/// shoulder, cut by the vertical plane through the armpit (the torso's
/// loops above the armpit stop just past it, `torso_without_arms`).
fn arm_transition_specs(
    parts: &[BodyPart],
    seg: &Segmentation,
    shoulders: Shoulders,
) -> Vec<(usize, TransitionSpec)> {
    parts
        .iter()
        .enumerate()
        .filter_map(|(ai, p)| {
            let sh = hanging_shoulder(seg, p.name).filter(|_| shoulders.side_of(p.name))?;
            let along = sh.direction.dot(sh.normal);
            if along.abs() < 1e-6 {
                return None;
            }
            // Where the arm's axis line meets the plane.
            let lambda = (sh.armpit - sh.start).dot(sh.normal) / along;
            // The contour's Fourier order: higher than the arm's curves, so
            // that the transition's end follows the torso's surface.
            let order = 32;
            Some((
                ai,
                TransitionSpec {
                    from_start: true,
                    to_start: false,
                    magnitudes: [1.0, 1.0],
                    seam: None,
                    side: Some(SideCut {
                        point: sh.start + sh.direction * lambda,
                        normal: sh.normal,
                    }),
                    order,
                },
            ))
        })
        .collect()
}

/// Closes the torso's bottom flat (no leg transitions close it).
fn close_bottom_flat(torso: &mut BodyPart, warnings: &mut Vec<String>) {
    let options = PartOptions {
        start_cap: CapKind::Flat,
        ..*torso.part.options()
    };
    match Part::new(torso.part.sections().to_vec(), &options) {
        Ok(p) => {
            torso.part = p;
            warnings.push("torso: bottom closed flat (no leg transitions)".to_string());
        }
        Err(e) => warnings.push(format!("torso: bottom left open ({e})")),
    }
}

/// The neck's transition from the torso (part `ti`, its last section) to
/// the head's first section, where they are apart.
fn neck_transition(
    parts: &[BodyPart],
    ti: usize,
    seg: &Segmentation,
    input: &InputDistance,
    warnings: &mut Vec<String>,
) -> Option<BodyTransition> {
    let hi = parts.iter().position(|p| p.name == PartName::Head)?;
    let distance = |points: &[Point3]| input.distances(points);
    let a = parts[ti].part.curves().last().map(|c| c.frame.origin);
    let b = parts[hi].part.curves()[0].frame.origin;
    if !a.is_some_and(|a| a.distance(b) > NECK_GAP * seg.height) {
        return None;
    }
    let spec = TransitionSpec {
        from_start: false,
        to_start: true,
        magnitudes: [1.0, 1.0],
        seam: None,
        side: None,
        order: 1,
    };
    // From the torso (u = 0) to the head.
    let (f, t) = (&parts[ti].part, &parts[hi].part);
    match Transition::boundaries(f, t, &spec).and_then(|c| {
        let magnitudes = fit_magnitudes(&c, &distance)?;
        let [p0, t0, p1, t1] = c;
        Transition::hermite(p0, t0, p1, t1, TransitionSpec { magnitudes, ..spec })
    }) {
        Ok(transition) => Some(BodyTransition {
            from: PartName::Torso,
            to: PartName::Head,
            transition,
        }),
        Err(e) => {
            warnings.push(format!("head: no transition to the torso ({e})"));
            None
        }
    }
}

/// The root mean square of the distances from a transition's surface to
/// the input: 15 rows strictly between its curves × 64 points around.
fn transition_rms(t: &Transition, input: &InputDistance) -> Real {
    let patch = t.patch();
    let points: Vec<Point3> = (1..16)
        .flat_map(|j| {
            let c = patch.curve_at(j as Real / 16.0);
            (0..64).map(move |i| c.point(std::f64::consts::TAU * i as Real / 64.0))
        })
        .collect();
    let d = input.distances(&points);
    (d.iter().map(|x| x * x).sum::<Real>() / d.len().max(1) as Real).sqrt()
}

/// The largest RMS distance (fraction of the height, [`transition_rms`])
/// from an arm's side transition to the input that is kept: good
/// transitions lie well under it, ones folded over the shoulders (arms
/// whose first sections are poor) far over it.
const ARM_TRANSITION_LIMIT: Real = 0.003;

/// The torso's last and the head's first section closer than this
/// fraction of the height share their plane: no neck transition.
const NECK_GAP: Real = 0.001;
