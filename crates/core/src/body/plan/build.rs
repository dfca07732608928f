//! Building each part from its cuts: its end (a dome that reaches the
//! tip, the end's sections and dome shape checked against the input), the
//! implausible sections dropped, and the adaptive refinement.

use super::*;
use crate::geom::parallel::parallel_map;
use crate::geom::stats::median;
use crate::geom::tolerance::ROUNDING_MARGIN;
use crate::surface::cap::{dome_cap, Cap, DomeAxis};
use crate::surface::part::Segment;

/// Builds a part from its cuts, dropping a section whose plane crosses its
/// neighbour's inside the curves, and retrying.
pub(in crate::body) fn build_part(
    plan: Plan,
    opts: &ReconstructOptions,
    scan: bool,
    end_check: Option<(&InputDistance, &[Point3], Real)>,
    warnings: &mut Vec<String>,
) -> Result<(BodyPart, Vec<Cut>), ReconstructError> {
    let Plan {
        name,
        mut cuts,
        start_cap,
        mut end_cap,
        tip,
        end_unchecked,
        shoulders: _,
    } = plan;
    let mut dome_retries = 0;
    let mut end_measured = false;
    let mut shape_chosen = false;
    let sole = matches!(name, PartName::LeftLeg | PartName::RightLeg);
    loop {
        if cuts.len() < 2 {
            return Err(ReconstructError::TooFewSections {
                part: name,
                count: cuts.len(),
            });
        }
        end_cap = dome_to_tip(&cuts, tip, end_cap);
        let options = PartOptions {
            start_cap,
            end_cap,
            ..opts.part
        };
        let curves: Vec<TrigCurve> = cuts.iter().map(|c| c.fit.curve.clone()).collect();
        match Part::new(curves, &options) {
            Ok(part) => {
                // A dome must point at its tip: where the last sections
                // wobble (a scanned hand) the end tangent can point sideways
                // and the dome miss the tip; drop the last section and
                // retry, at most three times. Scans only (on meshes it drops
                // good hand sections); not for the soles, whose dome is
                // shallow and whose outlines' centres shift heel to toe.
                let check = scan && !sole && dome_retries < 3;
                if let (true, Some(tip), Some(cap), Some(last)) =
                    (check, tip, part.end_cap(), cuts.last())
                {
                    let g = last.fit.curve.frame.origin;
                    let cos = (cap.apex - g)
                        .normalized()
                        .zip((tip - g).normalized())
                        .map_or(1.0, |(a, b)| a.dot(b));
                    // The last section's own normal may still point at
                    // the tip where the end tangent does not (the last
                    // centres drift with the thumb): then the dome goes
                    // along the normal and the section stays (once; the
                    // hand's dome shape is chosen later, `shaped_end`).
                    let normal = last.fit.curve.frame.e1.cross(last.fit.curve.frame.e2);
                    let along = (tip - g).normalized().map_or(0.0, |b| normal.dot(b).abs());
                    if let CapKind::Dome {
                        relative_height,
                        fullness,
                        axis: DomeAxis::Tangent,
                    } = end_cap
                    {
                        if cuts.len() > 3
                            && cos < 30f64.to_radians().cos()
                            && along >= 30f64.to_radians().cos()
                        {
                            end_cap = CapKind::Dome {
                                relative_height,
                                fullness,
                                axis: DomeAxis::Normal,
                            };
                            continue;
                        }
                    }
                    if matches!(cap.kind, CapKind::Dome { .. })
                        && cuts.len() > 3
                        && cos < 30f64.to_radians().cos()
                    {
                        warnings.push(format!(
                            "{name}: section at {:.3} dropped (the end dome from it points {:.0} degrees away from the tip)",
                            last.at,
                            cos.clamp(-1.0, 1.0).acos().to_degrees()
                        ));
                        dome_retries += 1;
                        cuts.pop();
                        continue;
                    }
                }
                // An estimated tip has no input around it to measure against.
                let measure = !(sole || end_measured || end_unchecked);
                if let (Some(check), true) = (end_check, measure) {
                    end_measured = true;
                    if let Some((k, before, after)) = better_end(&cuts, &part, tip, &options, check)
                    {
                        warnings.push(format!(
                            "{name}: last {k} section(s) from {:.3} dropped (the end strays {:.1} mm RMS from the input both ways with them, {:.1} mm without)",
                            cuts[cuts.len() - k].at,
                            before * opts.units.to_mm(),
                            after * opts.units.to_mm()
                        ));
                        cuts.truncate(cuts.len() - k);
                        continue;
                    }
                }
                // Then a hand dome's shape, on the kept sections.
                let hand = matches!(name, PartName::LeftArm | PartName::RightArm);
                if let (Some(check), true, false) = (end_check, hand, shape_chosen) {
                    shape_chosen = true;
                    if let (
                        Some((fullness, axis)),
                        CapKind::Dome {
                            relative_height, ..
                        },
                    ) = (shaped_end(&cuts, tip, &options, check), end_cap)
                    {
                        end_cap = CapKind::Dome {
                            relative_height,
                            fullness,
                            axis,
                        };
                        continue;
                    }
                }
                let fits = section_fits(&cuts);
                return Ok((BodyPart { name, part, fits }, cuts));
            }
            Err(PartError::CrossingPlanes { index, .. })
            | Err(PartError::CoincidentSections { index }) => {
                // Drop the later section of the pair (never the first).
                let k = (index + 1).min(cuts.len() - 1);
                let why = "its plane meets its neighbour's inside the curves";
                drop_cut(&mut cuts, k, name, why, warnings);
            }
            Err(PartError::MixedFrames {
                index,
                first_is_odd,
                ..
            }) if cuts.len() > 2 => {
                // The axis doubles back (a wobbly scanned joint): drop the
                // section facing against the run (maybe the first), not the part.
                let k = if first_is_odd { 0 } else { index };
                let why = "it faces against the part's run";
                drop_cut(&mut cuts, k, name, why, warnings);
            }
            Err(source) => return Err(ReconstructError::Part { part: name, source }),
        }
    }
}

/// Removes cut `k`, saying why in a warning.
fn drop_cut(cuts: &mut Vec<Cut>, k: usize, name: PartName, why: &str, warnings: &mut Vec<String>) {
    warnings.push(format!(
        "{name}: section at {:.3} dropped ({why})",
        cuts[k].at
    ));
    cuts.remove(k);
}

/// What the report says of each cut's fit.
fn section_fits(cuts: &[Cut]) -> Vec<SectionFit> {
    cuts.iter().map(|c| SectionFit::of(c.at, &c.fit)).collect()
}

/// A dome end (`tip` given) sized to reach the tip: its height is the
/// tip's distance from the last section's plane, relative to the last
/// loop's mean radius `√(A/π)` (clamped to `[0.02, 4]`), its fullness and
/// axis kept from `cap`; `cap` unchanged without a tip.
fn dome_to_tip(cuts: &[Cut], tip: Option<Point3>, cap: CapKind) -> CapKind {
    let (Some(tip), Some(last)) = (tip, cuts.last()) else {
        return cap;
    };
    match height_to_reach(&last.fit.curve, tip) {
        Some(relative_height) => {
            let (fullness, axis) = match cap {
                CapKind::Dome { fullness, axis, .. } => (fullness, axis),
                _ => (1.0, DomeAxis::Tangent),
            };
            CapKind::Dome {
                relative_height,
                fullness,
                axis,
            }
        }
        None => cap,
    }
}

/// The relative height of a dome on `c` that reaches the plane through
/// `tip` parallel to `c`'s: the distance `d` of `tip` from `c`'s plane over
/// `c`'s mean radius `r = √(A/π)`, clamped to `[0.02, 4]`; `None` unless
/// both are positive.
pub(in crate::body) fn height_to_reach(c: &TrigCurve, tip: Point3) -> Option<Real> {
    let r = mean_radius(c.area());
    let d = (tip - c.frame.origin)
        .dot(c.frame.e1.cross(c.frame.e2))
        .abs();
    (r > 0.0 && d > 0.0).then(|| (d / r).clamp(0.02, 4.0))
}

/// RMS distance to the input of the end dome's surface: 6 × 32 points at
/// `u = (i + ½)/6`, `v = 2πj/32` of the cap's patch (`u = 0` the last
/// section, `u = 1` the apex). `None` without a dome.
fn dome_error(part: &Part, input: &InputDistance) -> Option<Real> {
    Some(cap_error(part.end_cap()?, input))
}

/// [`dome_error`] of a cap.
fn cap_error(cap: &Cap, input: &InputDistance) -> Real {
    let pts: Vec<Point3> = (0..6)
        .flat_map(|i| curve_points(&cap.patch.curve_at((i as Real + 0.5) / 6.0), 32))
        .collect();
    let d = input.distances(&pts);
    (d.iter().map(|x| x * x).sum::<Real>() / d.len() as Real).sqrt()
}

/// A dome end that strays from the input (model → input RMS of its dome
/// above `tol`, the last of `end_check`) may come from a last section that
/// is not the hand's or the head's run: a loop where the fingers part,
/// whose shape and centre jump from its neighbour's, tilts the end
/// tangent, and the dome, which follows the tangent's harmonics over its
/// whole height, bulges into a paddle. Tries the part without its last 1-3
/// sections (at least four kept) and returns `(k, before, after)` for the
/// best when it strays under 0.7 times as much, or by `tol` less, both
/// ways ([`end_error`]).
/// The end is measured against the input both ways, so a good end is kept
/// (one way alone, model -> input, cuts fingertips off).
fn better_end(
    cuts: &[Cut],
    part: &Part,
    tip: Option<Point3>,
    options: &PartOptions,
    (input, points, tol): (&InputDistance, &[Point3], Real),
) -> Option<(usize, Real, Real)> {
    let tip = tip?;
    if !(dome_error(part, input)? > tol) {
        return None;
    }
    let n = cuts.len();
    let near = near_end(cuts, tip, points)?;
    // Each end built from the last ten sections at most: the last four
    // patches and the dome depend on the last five curves only (Catmull-Rom
    // takes one neighbour either side), and a short part is quick to build.
    let from = n.saturating_sub(10);
    let end = |k: usize| {
        let head = &cuts[from..n - k];
        let o = PartOptions {
            start_cap: CapKind::Open,
            end_cap: dome_to_tip(head, Some(tip), options.end_cap),
            ..*options
        };
        let curves: Vec<TrigCurve> = head.iter().map(|c| c.fit.curve.clone()).collect();
        Part::new(curves, &o)
            .ok()
            .and_then(|p| end_error(&p, input, &near))
    };
    // The four ends (0-3 sections dropped) over the cores.
    let ks: Vec<usize> = (0..=3usize.min(n.saturating_sub(4))).collect();
    let errors: Vec<Option<Real>> =
        parallel_map(&ks, 1, |run| run.iter().map(|&k| end(k)).collect());
    let before = errors[0].or_else(|| end_error(part, input, &near))?;
    let best = ks
        .iter()
        .zip(&errors)
        .skip(1)
        .filter_map(|(&k, e)| e.map(|e| (k, e)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let (k, after) = best?;
    (after < 0.7 * before || after < before - tol).then_some((k, before, after))
}

/// The input around a part's end: the points within the tip's distance
/// from the fourth section from the end (the last one every end
/// [`better_end`] tries keeps), at most 200 of them (every k-th).
fn near_end(cuts: &[Cut], tip: Point3, points: &[Point3]) -> Option<Vec<Point3>> {
    let reach = cuts
        .get(cuts.len().checked_sub(4)?)?
        .fit
        .curve
        .frame
        .origin
        .distance(tip);
    let near: Vec<Point3> = points
        .iter()
        .copied()
        .filter(|p| p.distance(tip) <= reach)
        .collect();
    Some(
        near.iter()
            .copied()
            .step_by(near.len().div_ceil(200).max(1))
            .collect(),
    )
}

/// The dome fullnesses [`shaped_end`] tries besides 1.
const DOME_FULLNESS: [Real; 2] = [1.5, 2.0];

/// The shape of a hand's dome (module doc of [`crate::surface::cap`]) that fits
/// the input best both ways ([`end_error`]): its fullness (wider across the
/// hand towards the tip) from 1 and [`DOME_FULLNESS`], and its axis (the
/// part's end tangent or the last section's normal), each end built from
/// the part's last ten sections; `None` when the plain dome (fullness 1
/// along the tangent) is best, or nothing could be measured.
///
/// A mitten over fingers spread in a fan: a dome that narrows like a
/// quarter circle leaves the outer fingertips bare (the male mesh: 455 of
/// 60 000 input samples uncovered at 0.55 H, most of them fingertips); and
/// where the last hand loops' centres drift with the thumb and fingers,
/// the end tangent tilts (the plain dome's apex can lie centimetres from
/// the hand tip). Hands only: a head's crown is round (and a scan's crown
/// unobserved), a sole's dome shallow.
fn shaped_end(
    cuts: &[Cut],
    tip: Option<Point3>,
    options: &PartOptions,
    (input, points, _): (&InputDistance, &[Point3], Real),
) -> Option<(Real, DomeAxis)> {
    let tip = tip?;
    let CapKind::Dome {
        relative_height, ..
    } = options.end_cap
    else {
        return None;
    };
    let near = near_end(cuts, tip, points)?;
    // One part (the caps do not change its patches), then each dome on
    // its last curve and end tangent, as `Part::new` builds it.
    let from = cuts.len().saturating_sub(10);
    let curves: Vec<TrigCurve> = cuts[from..].iter().map(|c| c.fit.curve.clone()).collect();
    let open = PartOptions {
        start_cap: CapKind::Open,
        end_cap: CapKind::Open,
        ..*options
    };
    let part = Part::new(curves, &open).ok()?;
    let (last, tangent) = (part.curves().last()?, part.end_tangent(false));
    let shapes: Vec<(Real, DomeAxis)> = [DomeAxis::Tangent, DomeAxis::Normal]
        .into_iter()
        .flat_map(|axis| {
            std::iter::once(1.0)
                .chain(DOME_FULLNESS)
                .map(move |f| (f, axis))
        })
        .collect();
    let errors: Vec<Option<Real>> = parallel_map(&shapes, 1, |run| {
        run.iter()
            .map(|&(fullness, axis)| {
                dome_cap(last, &tangent, relative_height, fullness, axis)
                    .ok()
                    .map(|cap| cap_end_error(part.segments(), &cap, input, &near))
            })
            .collect()
    });
    let plain = errors[0]?;
    let (shape, best) = shapes
        .iter()
        .zip(&errors)
        .skip(1)
        .filter_map(|(&s, e)| e.map(|e| (s, e)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    (best < plain).then_some(shape)
}

/// The end's error both ways: `√((d_out² + d_in²)/2)` with `d_out` the
/// dome's RMS distance to the input ([`dome_error`]) and `d_in` the RMS
/// distance of the input points `near` the end to the nearest of 6 × 32
/// points of each of the part's last four patches and its dome (a
/// shortened end that leaves the fingertips bare pays for it here).
fn end_error(part: &Part, input: &InputDistance, near: &[Point3]) -> Option<Real> {
    Some(cap_end_error(part.segments(), part.end_cap()?, input, near))
}

/// [`end_error`] of a part's patches `segments` closed by `cap`.
fn cap_end_error(segs: &[Segment], cap: &Cap, input: &InputDistance, near: &[Point3]) -> Real {
    let out = cap_error(cap, input);
    if near.is_empty() {
        return out;
    }
    let patches = segs[segs.len().saturating_sub(4)..]
        .iter()
        .map(|s| &s.patch)
        .chain(std::iter::once(&cap.patch));
    let mut samples = Vec::new();
    for patch in patches {
        for i in 0..6 {
            let u = (i as Real + 0.5) / 6.0;
            samples.extend(curve_points(&patch.curve_at(u), 32));
        }
    }
    let sum: Real = near
        .iter()
        .map(|p| {
            samples
                .iter()
                .map(|q| (*p - *q).norm_squared())
                .fold(Real::INFINITY, Real::min)
        })
        .sum();
    let inward = sum / near.len() as Real;
    (0.5 * (out * out + inward)).sqrt()
}

/// Distances to the input: its surface (mesh) or its nearest point (cloud).
pub(in crate::body) enum InputDistance<'a> {
    Mesh(MeshDistance<'a>),
    Cloud(PointGrid<'a>),
}

impl InputDistance<'_> {
    /// The distance of each point (see [`MeshDistance::distances`]).
    pub(in crate::body) fn distances(&self, points: &[Point3]) -> Vec<Real> {
        match self {
            InputDistance::Mesh(m) => m.distances(points),
            InputDistance::Cloud(g) => g.distances(points),
        }
    }
}

/// The 75th percentile of the distances from 64 points of a section's
/// curve to the input: a curve fitted to a wrongly joined loop (a scan
/// slab's arcs joined across a hole) has long stretches away from it.
/// The points of a torso loop's straight side that the arm's tube hides
/// ([`Clip::hides`], within `on_clip` of its plane) are left out: that
/// side runs through the arm's root by design. The rest of the side
/// counts: where it lies outside the tube (across the chest or through an
/// armpit) it would show as a wall. Where the loop was bridged across a
/// side the scanner did not see ([`Cut::bridge`]) the curve is judged
/// against the bridge.
pub(in crate::body) fn curve_offset(c: &Cut, input: &InputDistance, on_clip: Real) -> Real {
    let points: Vec<Point3> = c
        .fit
        .curve
        .sample(64)
        .into_iter()
        .filter(|&p| !c.clips.iter().any(|k| k.hides(p, on_clip)))
        .collect();
    let mut d = input.distances(&points);
    for (d, p) in d.iter_mut().zip(&points) {
        for q in &c.bridge {
            *d = d.min(p.distance(*q));
        }
    }
    d.sort_by(Real::total_cmp);
    d.get(d.len() * 3 / 4).copied().unwrap_or(0.0)
}

/// `n` points of a space curve at `v_i = 2π i/n`, all three series summed
/// over one table of harmonics per point (one `sin_cos` per point).
fn curve_points(curve: &crate::curve::trig::SpaceCurve, n: usize) -> Vec<Point3> {
    let order = curve.order();
    let (mut co, mut si) = (vec![0.0; order + 1], vec![0.0; order + 1]);
    let sum = |s: &crate::curve::series::Series, co: &[Real], si: &[Real]| {
        let c = &s.c;
        let mut acc = c.first().copied().unwrap_or(0.0);
        for j in 1..=s.order() {
            acc += c[2 * j - 1] * co[j] + c[2 * j] * si[j];
        }
        acc
    };
    (0..n)
        .map(|i| {
            crate::curve::series::harmonics(
                std::f64::consts::TAU * i as Real / n as Real,
                order,
                &mut co,
                &mut si,
            );
            Vec3::new(
                sum(&curve.x, &co, &si),
                sum(&curve.y, &co, &si),
                sum(&curve.z, &co, &si),
            )
        })
        .collect()
}

/// The 90th percentile of the in-plane distances from the loop points of
/// `cut` to `curve` (sampled densely), both projected into the cut's plane
/// (a percentile, not the maximum: a scan loop's noise and stray points
/// must not call for sections everywhere).
///
/// Each point's distance to the 256-gon is exact: the previous point's
/// nearest edge gives a first bound `d`, and an edge with midpoint `m` and
/// half-length `h` is only measured when `|q − m| < d + h` (every point of
/// the edge lies within `h` of `m`); the edges sorted by `m_x` limit the
/// candidates to `|m_x − q_x| ≤ d + h_max` by binary search.
pub(in crate::body) fn stray(cut: &Cut, curve: &crate::curve::trig::SpaceCurve) -> Real {
    stray_of(&cut.fit.curve.frame, &cut.fit.plane_points, curve)
}

/// [`stray`] of the points `points` of the plane of `f` (in its
/// coordinates).
pub(in crate::body) fn stray_of(
    f: &crate::curve::trig::Frame,
    points: &[crate::geom::math::Vec2],
    curve: &crate::curve::trig::SpaceCurve,
) -> Real {
    let n = 256;
    let poly: Vec<(Real, Real)> = curve_points(curve, n)
        .into_iter()
        .map(|p| {
            let p = p - f.origin;
            (p.dot(f.e1), p.dot(f.e2))
        })
        .collect();
    // Per edge: start, direction, squared length, midpoint, half-length.
    let edges: Vec<[Real; 8]> = (0..n)
        .map(|i| {
            let (ax, ay) = poly[i];
            let (bx, by) = poly[(i + 1) % n];
            let (dx, dy) = (bx - ax, by - ay);
            let l2 = dx * dx + dy * dy;
            let half = 0.5 * l2.sqrt();
            [ax, ay, dx, dy, l2, ax + 0.5 * dx, ay + 0.5 * dy, half]
        })
        .collect();
    let dist = |e: &[Real; 8], qx: Real, qy: Real| {
        let [ax, ay, dx, dy, l2, ..] = *e;
        let t = if l2 > 0.0 {
            (((qx - ax) * dx + (qy - ay) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (ex, ey) = (ax + t * dx - qx, ay + t * dy - qy);
        (ex * ex + ey * ey).sqrt()
    };
    // Edges by their midpoint's x: an edge closer than `d` has its
    // midpoint within `d + h_max` of the point in x.
    let mut by_x: Vec<usize> = (0..n).collect();
    by_x.sort_by(|&a, &b| edges[a][5].total_cmp(&edges[b][5]));
    let xs: Vec<Real> = by_x.iter().map(|&i| edges[i][5]).collect();
    let h_max = edges.iter().map(|e| e[7]).fold(0.0, Real::max);
    let mut all = Vec::with_capacity(points.len());
    let mut near = 0;
    for q in points {
        let mut best = dist(&edges[near], q.x, q.y);
        let window = (best + h_max) * (1.0 + ROUNDING_MARGIN);
        let lo = xs.partition_point(|&x| x < q.x - window);
        let hi = xs.partition_point(|&x| x <= q.x + window);
        for &i in &by_x[lo..hi] {
            let e = &edges[i];
            let (mx, my) = (e[5] - q.x, e[6] - q.y);
            let reach = best + e[7];
            if mx * mx + my * my >= reach * reach {
                continue;
            }
            let d = dist(e, q.x, q.y);
            if d < best {
                best = d;
                near = i;
            }
        }
        all.push(best);
    }
    if all.is_empty() {
        return 0.0;
    }
    all.sort_by(Real::total_cmp);
    all[(all.len() * 9 / 10).min(all.len() - 1)]
}

/// A fit far outside its tolerances (three times either): a loop the
/// section picked wrongly or a hole the fit could not bridge; or a curve
/// that loops out between its points ([`loops_out`]).
pub(in crate::body) fn wild(c: &Cut, opts: &ReconstructOptions) -> bool {
    let off = !c.fit.met
        && (c.fit.errors.ea > 3.0 * opts.fit.ea * opts.scan_tolerance_factor
            || c.fit.errors.em > 3.0 * opts.fit.em * opts.scan_tolerance_factor);
    off || loops_out(&c.fit)
}

/// How much farther from a loop's centroid than its farthest point a
/// fitted curve may reach ([`loops_out`]).
const LOOPS_OUT: Real = 1.5;

/// Whether the fitted curve reaches farther from the loop's centroid than
/// [`LOOPS_OUT`] times the loop's farthest point: a high order fitted to
/// points spaced unevenly (a foot outline's long straight edges) meets
/// E_a and E_M at the points and swings out between them (a 100 mm foot
/// outline with 181 mm coefficients made a leg's surface 3.6 m across).
fn loops_out(fit: &LoopFit) -> bool {
    let reach = fit
        .plane_points
        .iter()
        .map(|p| p.norm())
        .fold(0.0, Real::max);
    let n = (8 * fit.order).max(64);
    fit.curve
        .sample_plane(n)
        .iter()
        .any(|q| q.norm() > LOOPS_OUT * reach)
}

/// Drops sections whose loop is implausible: area outside `[½, 2]` times
/// the median of its (up to four) nearest neighbours' — a wrong loop
/// picked where a scan's slab broke up (armpits, fingers) — or a wild fit
/// (see [`wild`]).
pub(in crate::body) fn drop_outliers(
    mut plan: Plan,
    opts: &ReconstructOptions,
    warnings: &mut Vec<String>,
) -> Plan {
    let n = plan.cuts.len();
    if n < 3 {
        return plan;
    }
    let keep: Vec<bool> = (0..n)
        .map(|i| {
            let mut near: Vec<Real> = (i.saturating_sub(2)..(i + 3).min(n))
                .filter(|&j| j != i)
                .map(|j| plan.cuts[j].area)
                .collect();
            // At least two neighbours, as n >= 3.
            let med = median(&mut near).unwrap_or(Real::NAN);
            let a = plan.cuts[i].area;
            a >= 0.5 * med && a <= 2.0 * med && !wild(&plan.cuts[i], opts)
        })
        .collect();
    let name = plan.name;
    let mut k = 0;
    plan.cuts.retain(|c| {
        let ok = keep[k];
        k += 1;
        if !ok {
            warnings.push(format!(
                "{name}: section at {:.3} dropped (area {:.3e} unlike its neighbours', or E_a {:.3} / E_M {:.3} far beyond the tolerances)",
                c.at, c.area, c.fit.errors.ea, c.fit.errors.em
            ));
        }
        ok
    });
    plan
}

/// A halfway cut's loop area lies within this factor of the smaller of
/// its two neighbours' areas and its inverse of the larger's, or the cut
/// is not added: a loop that shrinks or grows by more than a third between
/// two sections a refinement apart is a wrong one (a scan's slab broken
/// under an armpit, a chain closed across a gap, a cut meeting a nearby
/// limb), and the sections' own test ([`drop_outliers`], ½ to 2 of the
/// median) lets such loops through.
pub(super) const HALFWAY_AREA: Real = 0.75;

/// Adaptive spacing (method.md §8.6): builds the part, then between every
/// two consecutive sections cuts the input halfway and compares that loop
/// with the surface's curve halfway between the sections (patch parameter
/// `u = ½`, both in the new cut's plane). Where the surface strays more
/// than [`ReconstructOptions::refine_tolerance`] × `H` from the input (the
/// 90th percentile of the loop points' distances, see [`stray`]), the
/// new section is added; repeated for [`ReconstructOptions::refine_rounds`]
/// rounds, never closer than [`ReconstructOptions::min_spacing`] × `H`.
pub(in crate::body) fn refine(
    cutter: &Cutter<'_>,
    mut plan: Plan,
    opts: &ReconstructOptions,
    input: &InputDistance,
    warnings: &mut Vec<String>,
) -> Result<BodyPart, ReconstructError> {
    let (body, seg) = (cutter.body(), cutter.segmentation());
    let name = plan.name;
    let (start_cap, tip, shoulders) = (plan.start_cap, plan.tip, plan.shoulders);
    let end_unchecked = plan.end_unchecked;
    let far = opts.max_curve_offset * seg.height;
    // How far a fitted curve may stray from its loop's straight side and
    // still be on it.
    let on_clip = 0.5 * far;
    plan.cuts.retain(|c| {
        let off = curve_offset(c, input, on_clip);
        if off > far {
            warnings.push(format!(
                "{name}: section at {:.3} dropped (a quarter of its curve lies {:.1} mm or more from the input)",
                c.at,
                off * opts.units.to_mm()
            ));
        }
        off <= far
    });
    // One pass: a second one (outliers among outliers) would drop real
    // sections of feet and hands.
    let plan = drop_outliers(plan, opts, warnings);
    let (mut built, mut cuts) = build_part(
        plan,
        opts,
        matches!(body, BodyGeometry::Cloud(_)),
        // The end is measured once, on the first build: the refinement
        // only adds sections between the kept ones.
        Some((input, body.positions(), opts.refine_tolerance * seg.height)),
        warnings,
    )?;
    // The end as chosen there (a dome's fullness).
    let end_cap = built.part.options().end_cap;
    let len = seg.part(name).map_or(0.0, PartAxis::length);
    if !(len > 0.0) {
        return Ok(built);
    }
    let min_step = opts.min_spacing * seg.height / len;
    let tol = opts.refine_tolerance * seg.height;
    // A halfway cut and its plausibility depend only on its interval's
    // two cuts, so an interval kept in a round (not split) is not cut
    // again the next round: its candidate (or its failure) is remembered,
    // and only the stray test, against the new skin, is repeated.
    let mut candidates: std::collections::HashMap<[u64; 4], Option<Cut>> =
        std::collections::HashMap::new();
    let key = |a: &Cut, b: &Cut| [a.at, b.at, a.area, b.area].map(Real::to_bits);
    for _ in 0..opts.refine_rounds {
        let segments = built.part.segments();
        if segments.len() + 1 != cuts.len() {
            break; // only for the one-patch-per-interval schemes
        }
        // The halfway cuts of one round are independent: split over the
        // cores.
        let fresh: Vec<usize> = (0..cuts.len() - 1)
            .filter(|&i| {
                let (t0, t1) = (cuts[i].at, cuts[i + 1].at);
                !(t1 - t0 < 2.0 * min_step)
                    && !candidates.contains_key(&key(&cuts[i], &cuts[i + 1]))
            })
            .collect();
        let found: Vec<Option<Cut>> = parallel_map(&fresh, 4, |run| {
            run.iter()
                .map(|&i| {
                    let (t0, t1) = (cuts[i].at, cuts[i + 1].at);
                    let c =
                        cut_and_fit(cutter, name, 0.5 * (t0 + t1), opts, shoulders, None).ok()?;
                    let (a0, a1) = (cuts[i].area, cuts[i + 1].area);
                    let plausible = c.area >= HALFWAY_AREA * a0.min(a1)
                        && c.area <= a0.max(a1) / HALFWAY_AREA
                        && !wild(&c, opts);
                    (plausible && curve_offset(&c, input, on_clip) <= far).then_some(c)
                })
                .collect()
        });
        for (&i, c) in fresh.iter().zip(found) {
            candidates.insert(key(&cuts[i], &cuts[i + 1]), c);
        }
        // The stray tests, in order, over the cores.
        let intervals: Vec<usize> = (0..cuts.len() - 1)
            .filter(|&i| {
                candidates
                    .get(&key(&cuts[i], &cuts[i + 1]))
                    .is_some_and(Option::is_some)
            })
            .collect();
        let split: Vec<bool> = parallel_map(&intervals, 4, |run| {
            run.iter()
                .map(|&i| {
                    let c = candidates[&key(&cuts[i], &cuts[i + 1])].as_ref();
                    c.is_some_and(|c| stray(c, &segments[i].patch.curve_at(0.5)) > tol)
                })
                .collect()
        });
        // A split interval never comes back (a cut now lies inside it).
        let added: Vec<Cut> = intervals
            .iter()
            .zip(split)
            .filter(|(_, s)| *s)
            .filter_map(|(&i, _)| candidates.remove(&key(&cuts[i], &cuts[i + 1])).flatten())
            .collect();
        if added.is_empty() {
            break;
        }
        let mut all: Vec<Cut> = cuts.into_iter().chain(added).collect();
        all.sort_by(|a, b| a.at.total_cmp(&b.at));
        let plan = Plan {
            name,
            cuts: all,
            start_cap,
            end_cap,
            tip,
            end_unchecked,
            shoulders,
        };
        (built, cuts) = build_part(
            plan,
            opts,
            matches!(body, BodyGeometry::Cloud(_)),
            None,
            warnings,
        )?;
    }
    let plan = Plan {
        name,
        cuts,
        start_cap,
        end_cap,
        tip,
        end_unchecked,
        shoulders,
    };
    let scan = matches!(body, BodyGeometry::Cloud(_));
    pruned(built, plan, opts, scan, seg.height, warnings)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::fit::fit_loop_2d;
    use crate::geom::math::Vec2;

    /// An ellipse's fit stays inside its points' reach; the same curve with
    /// a large 20th harmonic added swings out between them.
    #[test]
    fn a_curve_swinging_out_between_its_points_loops_out() {
        let pts: Vec<Vec2> = (0..64)
            .map(|k| {
                let t = std::f64::consts::TAU * k as Real / 64.0;
                Vec2::new(0.1 * t.cos(), 0.04 * t.sin())
            })
            .collect();
        let fit = fit_loop_2d(&pts, &FitOptions::default()).unwrap();
        assert!(!loops_out(&fit));
        let (mut a, mut b) = (fit.curve.a.clone(), fit.curve.b.clone());
        a.resize(41, 0.0);
        b.resize(41, 0.0);
        a[39] = 0.2;
        let curve = TrigCurve::new(fit.curve.frame, a, b).unwrap();
        let wild = LoopFit {
            curve,
            order: 20,
            ..fit
        };
        assert!(loops_out(&wild));
    }
}
