//! Cutting, fitting, refining and skinning each part (pipeline steps 2-3):
//! the cuts here, the part built from them in [`build`].

use super::*;
use crate::geom::parallel::parallel_map;
use crate::geom::stats::{median, nth_smallest};
use crate::section::cloud::bridge_gaps;
use crate::section::mesh::point_in_polygon;

mod build;
mod crown;
mod limbs;
mod prune;
pub(super) use build::*;
pub(super) use crown::*;
pub(super) use limbs::*;
pub(super) use prune::*;

/// One cut-and-fitted section.
pub(super) struct Cut {
    pub(super) at: Real,
    pub(super) fit: LoopFit,
    pub(super) area: Real,
    /// Where a torso loop was clipped at an arm's first section
    /// ([`torso_without_arms`]).
    pub(super) clips: Vec<Clip>,
    /// Points a scan's loop was bridged with across a side the scanner
    /// did not see ([`bridge_gaps`]): the curve is fitted to them there.
    pub(super) bridge: Vec<Point3>,
}

/// A plane a torso loop was clipped at, just inside an arm's first
/// section: the loop's straight side there lies inside the arm's tube
/// where it is within the tube's radius of the arm's axis, and is hidden
/// by design; the rest of it is skin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Clip {
    /// A point of the plane and its normal (pointing along the arm).
    pub(super) origin: Point3,
    pub(super) normal: Vec3,
    /// The arm's axis point at its first section, and that section's
    /// mean radius `√(A/π)`.
    pub(super) centre: Point3,
    pub(super) radius: Real,
}

impl Clip {
    /// Whether `p` lies on the plane (within `tol`) inside the arm's tube.
    pub(super) fn hides(&self, p: Point3, tol: Real) -> bool {
        let r = p - self.centre;
        let across = r - self.normal * r.dot(self.normal);
        (p - self.origin).dot(self.normal).abs() < tol && across.norm() <= self.radius
    }
}

/// Cuts and fits `part` at `at` (through the cutter's shared slicers): the
/// loop around the axis point, or with `within` the loops whose centroids
/// it accepts ([`Cutter::cut_within`]).
pub(super) fn cut_and_fit(
    cutter: &Cutter<'_>,
    name: PartName,
    at: Real,
    opts: &ReconstructOptions,
    shoulders: Shoulders,
    within: Option<&dyn Fn(Point3) -> bool>,
) -> Result<Cut, String> {
    let (body, seg) = (cutter.body(), cutter.segmentation());
    // Torso, head and legs (with the feet) are cut across the body's up
    // axis: parallel planes never cross, and a horizontal cut below the
    // ankle is the foot's outline. Arms are cut across their own axis.
    let normal = match name {
        PartName::LeftArm | PartName::RightArm => None,
        _ => Some(seg.frame.up),
    };
    let mut cut = match within {
        Some(within) => cutter.cut_within(name, at, normal, within, &opts.segment),
        None => cutter.cut(name, at, normal, true, &opts.segment),
    }
    .map_err(|e| e.to_string())?;
    // A scan's unseen sides are bridged before the torso's loops are
    // clipped at the arms: a clip's straight side is no gap.
    let mut bridge = Vec::new();
    if let Some(side) = cutter.unseen_side() {
        let (points, fills) = bridged(&cut.outline, side, seg.height);
        if !fills.is_empty() {
            let f = cut.outline.frame;
            if let Some(outline) = SectionLoop::from_points(points, f.e1, f.e2) {
                (cut.outline, bridge) = (outline, fills);
            }
        }
    }
    let mut clips = Vec::new();
    if name == PartName::Torso {
        cut.outline = torso_without_arms(seg, cut.outline, shoulders, &mut clips)
            .ok_or_else(|| "nothing of the torso is left beside the arms".to_string())?;
    }
    let base = FitOptions {
        reference: Some(seg.frame.front),
        normal: Some(cut.plane.normal),
        allow_non_planar: true,
        ..opts.fit
    };
    let fo = match body {
        BodyGeometry::Cloud(_) => scan_fit_options(
            &FitOptions {
                ea: base.ea * opts.scan_tolerance_factor,
                em: base.em * opts.scan_tolerance_factor,
                ..base
            },
            seg.point_noise.unwrap_or(0.0),
        ),
        BodyGeometry::Mesh(_) => base,
    };
    // A mesh's section is a polygon whose edges lie on the surface: the
    // curve is fitted to its corners and its edges' midpoints. Through the
    // corners alone a curve bulges past every chord (each arc holds its
    // edge's sagitta), and the volume comes out over the 1 % issue 6
    // allows; more points per edge would shorten the tape girths, which
    // rest on the corners, for little volume. A cloud's outline is a
    // contour of occupied cells, not surface: its corners only.
    let points: std::borrow::Cow<'_, [Point3]> = match body {
        BodyGeometry::Mesh(_) => cut.outline.with_edge_midpoints().into(),
        BodyGeometry::Cloud(_) => (&cut.outline.points[..]).into(),
    };
    let mut fit = fit_untangled(&points, &fo)?;
    // Tape girths are taken below the armpits (chest, waist, hip).
    if name == PartName::Torso
        && matches!(body, BodyGeometry::Mesh(_))
        && cut.plane.origin.dot(seg.frame.up) < seg.armpit_level()
    {
        fit = with_tape_girth(fit, &cut.outline, &points, &fo, TORSO_TAPE_TOLERANCE);
    }
    Ok(Cut {
        at,
        fit,
        area: cut.outline.area,
        clips,
        bridge,
    })
}

/// A scan's loop gap wider than this fraction of the height and facing
/// the side the scanner did not see is bridged by [`bridge_gaps`].
const UNSEEN_GAP: Real = 0.02;

/// A one-sided scan's loop with its gaps that face `side` (the gap's
/// middle lies within 60° of `side` from the loop's centroid, in its
/// plane) bridged, and the bridge.
fn bridged(outline: &SectionLoop, side: Vec3, height: Real) -> (Vec<Point3>, Vec<Point3>) {
    let points = &outline.points;
    let mut steps: Vec<Real> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    let step = median(&mut steps).unwrap_or(0.0);
    let normal = outline.frame.e1.cross(outline.frame.e2);
    let faces = |p0: Point3, p1: Point3| {
        let out = (p0 + p1) * 0.5 - outline.centroid;
        let (out, side) = (
            out - normal * out.dot(normal),
            side - normal * side.dot(normal),
        );
        match (out.normalized(), side.normalized()) {
            (Some(o), Some(s)) => o.dot(s) >= 0.5,
            _ => false,
        }
    };
    let gap = UNSEEN_GAP * height;
    bridge_gaps(points, gap, 0.5 * gap, step, &faces)
}

/// The largest relative difference between a torso section's tape girth
/// (the perimeter of the fitted curve's convex hull) and its loop's that
/// the order choice accepts on a mesh (see [`with_tape_girth`]): 4 mm on a
/// 1 m girth, the agreement issue 6 asks of girths.
pub(super) const TORSO_TAPE_TOLERANCE: Real = 0.004;

/// Raises the order of a torso section's fit until its tape girth (the
/// perimeter of the convex hull of 256 points of the curve) is within
/// `tolerance` of the loop's own tape girth, or the order limit is reached
/// (then the best of the orders tried is kept). Chest, waist and hip
/// girths are tape girths of torso sections (issue 6): a curve meeting
/// E_a and E_M can still round off the peaks a tape spans (a chest's
/// breasts), and its girth then falls short. Only the torso
/// below the armpits (where tape girths are taken) is checked, and only on
/// meshes: a scan's loop is noisy, and its hull follows the noise outward.
fn with_tape_girth(
    fit: LoopFit,
    outline: &SectionLoop,
    points: &[Point3],
    fo: &FitOptions,
    tolerance: Real,
) -> LoopFit {
    use crate::section::girth::polygon_tape_girth;
    let target = polygon_tape_girth(&outline.plane_points());
    if !(target > 0.0) {
        return fit;
    }
    let miss =
        |f: &LoopFit| (polygon_tape_girth(&f.curve.sample_plane(256)) - target).abs() / target;
    let mut best = (miss(&fit), fit);
    let limit = fo.max_order.min(points.len().saturating_sub(1) / 2);
    let mut order = best.1.order;
    while best.0 > tolerance && order < limit {
        order += 1;
        let fixed = FitOptions {
            order: crate::curve::fit::OrderChoice::Fixed(order),
            ..*fo
        };
        let Ok(f) = fit_loop(points, &fixed) else {
            break;
        };
        let m = miss(&f);
        if m < best.0 {
            best = (m, f);
        }
    }
    best.1
}

/// A torso loop runs out along an arm (arms held out sideways, where a
/// horizontal cut meets the arm lengthwise) when it encloses (in its
/// plane) a point of the arm's axis lying more than a quarter of the
/// arm's length (and one arm diameter) beyond the arm's boundary plane
/// (through the armpit, normal to the arm's direction armpit → wrist).
/// Such a loop is clipped at the arm's first built section (below), as
/// every loop above the armpit is, so that loops below and above the
/// armpit end on the same plane: the boundary plane lies short of the
/// first section wherever the arm's first cuts were skipped, and the
/// loops that stopped there stepped out past the ones that did not (a
/// flange across the armpit). Only where the arm ends on the torso's side
/// through a transition is a loop running out clipped at the boundary
/// plane.
///
/// A hanging arm's axis never projects into a torso loop, but above the
/// armpit a horizontal cut still meets the arm's root obliquely and runs a
/// long way down it (far wider than the chest below): the skin between the
/// two would stand out as a thin flange past the arm. Above the armpit the loop is
/// therefore clipped:
///
/// * where the arm ends on the torso's side through a transition
///   (`shoulders`, [`hanging_shoulder`]): at the side plane, vertical
///   through the armpit with normal `n` (the horizontal part of the arm's
///   start direction), moved `δ(h) = SIDE_OVERLAP · min(1, h / SIDE_RAMP)`
///   past it (`h` the height above the armpit, fractions of `H`; from
///   [`SIDE_BELOW`] below the armpit, at the plane itself): the half
///   space `(p − a − δ H n)·n > 0` is left out. The transition starts on
///   the torso's surface in the side plane itself and covers the straight
///   side;
/// * otherwise (an arm held out part way or raised, or one whose
///   transition strayed from the input): at the plane of the arm's first
///   built section (`p₀`, the axis point at [`Shoulders::start`]; normal
///   `t₀`, the axis tangent there without its forward or backward part,
///   [`coronal_outward`]) moved [`SHOULDER_OVERLAP`] into the arm,
///   `(p − p₀ − δ H t₀)·t₀ > 0` left out: the arm's own sections model
///   what lies past its first one, and the torso's straight side sits
///   inside the arm's tube. Each such clip that changes the loop is added
///   to `clips` ([`Clip`]).
pub(super) fn torso_without_arms(
    seg: &Segmentation,
    outline: SectionLoop,
    shoulders: Shoulders,
    clips: &mut Vec<Clip>,
) -> Option<SectionLoop> {
    let mut out = outline;
    for (arm, armpit, wrist) in [
        (
            PartName::LeftArm,
            LandmarkKind::LeftArmpit,
            LandmarkKind::LeftWrist,
        ),
        (
            PartName::RightArm,
            LandmarkKind::RightArmpit,
            LandmarkKind::RightWrist,
        ),
    ] {
        let (Some(axis), Some(a)) = (seg.part(arm), landmark(seg, armpit)) else {
            continue;
        };
        let far = landmark(seg, wrist).or_else(|| axis.points.last().copied());
        let Some(d) = far.and_then(|w| (w - a).normalized()) else {
            continue;
        };
        let r = median(&mut axis.radii.clone()).unwrap_or(0.0);
        // A shoulder's own loops hold the upper arm's first decimetre, and
        // clipping them costs accuracy; a loop along the arm reaches much
        // further.
        let reach = (2.0 * r).max(0.25 * axis.length());
        let step = (axis.points.len() / 24).max(1);
        // The loop projected once, not once per axis point (`contains`).
        let poly = out.plane_points();
        let runs_out = axis
            .points
            .iter()
            .step_by(step)
            .any(|&p| (p - a).dot(d) > reach && point_in_polygon(out.frame.to_plane(p), &poly));
        let level = (out.frame.origin - a).dot(seg.frame.up) / seg.height;
        let side =
            hanging_shoulder(seg, arm).filter(|_| shoulders.side_of(arm) && level >= -SIDE_BELOW);
        if runs_out && side.is_some() {
            out = out.clipped(a, d)?;
        } else if let Some(sh) = side {
            // The arm's transition ends on the torso's shoulder, cut by
            // the side plane (vertical, through the armpit): the loop
            // reaches SIDE_OVERLAP past it, ramped up from nothing at the
            // armpit over SIDE_RAMP of height (and no further than the
            // plane just below the armpit).
            let reach = SIDE_OVERLAP * (level / SIDE_RAMP).clamp(0.0, 1.0);
            out = out.clipped(sh.armpit + sh.normal * (reach * seg.height), sh.normal)?;
        } else if level >= 0.0 || runs_out {
            // No side transition: the torso's loop stops where the arm's
            // tube starts (its first built section), reaching
            // SHOULDER_OVERLAP into it so that the straight side lies
            // inside the tube. (Below the armpit, unless the loop runs
            // out along it, the arm is a loop of its own.)
            if let Some((p0, t)) = axis.point_and_tangent(shoulders.start_of(arm)) {
                let t0 = coronal_outward(seg, arm, t);
                let origin = p0 + t0 * (SHOULDER_OVERLAP * seg.height);
                // A plane that leaves nothing of the loop does not part an
                // arm from the trunk (an arm whose first section faces
                // the front): the loop stays whole beside that arm.
                let Some(kept) = out.clipped(origin, t0) else {
                    continue;
                };
                if out.points.iter().any(|&p| (p - origin).dot(t0) > 0.0) {
                    clips.push(Clip {
                        origin,
                        normal: t0,
                        centre: p0,
                        // A first section cut across the chest (an arm
                        // starting forward) is no measure of the tube.
                        radius: shoulders.radius_of(arm).min(1.5 * r),
                    });
                }
                out = kept;
            }
        }
    }
    Some(out)
}

/// The normal of the plane a torso loop stops at beside `arm`: the arm's
/// direction `t` at its first section without its forward or backward
/// part, where that still points out of the torso on the arm's side (else
/// `t` itself: an arm starting across the chest). An arm whose start leans
/// forward or back would otherwise have the plane slice the chest's front
/// or the back off the torso's loops.
pub(super) fn coronal_outward(seg: &Segmentation, arm: PartName, t: Vec3) -> Vec3 {
    let (front, left) = (seg.frame.front, seg.frame.left);
    let out = if arm == PartName::LeftArm {
        left
    } else {
        -left
    };
    (t - front * t.dot(front))
        .normalized()
        .filter(|c| c.dot(out) > 0.0)
        .unwrap_or(t)
}

/// How far past the shoulder's side plane (vertical, through the armpit)
/// a torso loop above a hanging arm's armpit reaches (fraction of the
/// height), from [`SIDE_RAMP`] above the armpit (less below it, in
/// proportion). Too close, the torso's straight side shows above a
/// transition that sags over the shoulder; from 0.01 on the results hardly
/// move.
pub(super) const SIDE_OVERLAP: Real = 0.015;

/// Height above the armpit (fraction of the height) over which a torso
/// loop's reach past the side plane grows from nothing to
/// [`SIDE_OVERLAP`]. Without it the loop just above the armpit reached past
/// the plane and the one just below not at all: the skin stepped between
/// them and a line ran across chest and back.
pub(super) const SIDE_RAMP: Real = 0.02;

/// How far below a side arm's armpit (fraction of the height) the torso's
/// loops are clipped at the side plane itself. A scan's armpit landmark
/// is a slab's height: a torso loop just below it can still hold part of
/// the arm. The trunk lies inside the plane just below the armpit (the
/// plane passes through it).
pub(super) const SIDE_BELOW: Real = 0.005;

/// Which hanging arms end on the torso's side through a transition (left,
/// right; [`hanging_shoulder`]). The torso's loops above such an arm's
/// armpit stop just past the side plane ([`torso_without_arms`]); above
/// another arm's, just inside the arm's first section.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Shoulders {
    pub(super) side: [bool; 2],
    /// Each arm's first built section (left, right): the fraction along
    /// its axis where its tube starts, known once the arm is built (the
    /// torso is built after the arms). A torso loop that reaches into the
    /// arm stops just past it (`None`: the axis' shoulder end).
    pub(super) start: [Option<Real>; 2],
    /// The mean radius `√(A/π)` of each arm's first built section (0
    /// while unknown).
    pub(super) radius: [Real; 2],
}

impl Shoulders {
    /// Every hanging arm on the side.
    pub(super) fn of(seg: &Segmentation) -> Shoulders {
        Shoulders {
            side: [PartName::LeftArm, PartName::RightArm]
                .map(|a| hanging_shoulder(seg, a).is_some()),
            start: [None; 2],
            radius: [0.0; 2],
        }
    }

    /// The shoulders with each built arm's first section (`parts`: the
    /// parts built so far; see [`Shoulders::start`]).
    pub(super) fn with_arms(mut self, parts: &[BodyPart]) -> Shoulders {
        for part in parts {
            let Some(k) = arm_slot(part.name) else {
                continue;
            };
            self.start[k] = part.fits.first().map(|f| f.at);
            if let Some(c) = part.part.sections().first() {
                self.radius[k] = mean_radius(c.area());
            }
        }
        self
    }

    /// Where `arm`'s tube starts (see [`Shoulders::start`]).
    pub(super) fn start_of(self, arm: PartName) -> Real {
        arm_slot(arm).and_then(|k| self.start[k]).unwrap_or(0.0)
    }

    /// The mean radius of `arm`'s first built section (see
    /// [`Shoulders::radius`]).
    pub(super) fn radius_of(self, arm: PartName) -> Real {
        arm_slot(arm).map_or(0.0, |k| self.radius[k])
    }

    /// Whether `arm` ends on the torso's side.
    pub(super) fn side_of(self, arm: PartName) -> bool {
        arm_slot(arm).is_some_and(|k| self.side[k])
    }
}

/// The slot of an arm in the [`Shoulders`] pairs (left, right); `None`
/// for another part.
fn arm_slot(arm: PartName) -> Option<usize> {
    match arm {
        PartName::LeftArm => Some(0),
        PartName::RightArm => Some(1),
        _ => None,
    }
}

/// An arm within [`HANGING`] of straight down at its shoulder end.
pub(super) struct HangingShoulder {
    /// The arm's armpit landmark.
    pub(super) armpit: Point3,
    /// The horizontal part of the arm's start direction, unit: the side
    /// plane's normal, pointing out of the torso.
    pub(super) normal: Vec3,
    /// The arm axis' shoulder end and its direction there (toward the
    /// hand).
    pub(super) start: Point3,
    pub(super) direction: Vec3,
}

/// The cosine of the largest angle from straight down (about 66°) of an
/// arm that hangs (its transition ends on the torso's side,
/// [`HangingShoulder`]): arms of a wide body lie between 60° and 66° and
/// take transitions; a T-pose's arms (about 90°) are held out.
pub(super) const HANGING: Real = 0.4;

/// The shoulder of a hanging arm (`None` for another part, an arm held
/// out, or one whose armpit was not found).
pub(super) fn hanging_shoulder(seg: &Segmentation, arm: PartName) -> Option<HangingShoulder> {
    let kind = match arm {
        PartName::LeftArm => LandmarkKind::LeftArmpit,
        PartName::RightArm => LandmarkKind::RightArmpit,
        _ => return None,
    };
    let armpit = landmark(seg, kind)?;
    let (start, direction) = seg.part(arm)?.point_and_tangent(0.0)?;
    let up = seg.frame.up;
    if !(direction.dot(up) < -HANGING) {
        return None;
    }
    let normal = (direction - up * direction.dot(up)).normalized()?;
    Some(HangingShoulder {
        armpit,
        normal,
        start,
        direction,
    })
}

/// How far past an arm's first section a torso loop above the armpit
/// reaches (fraction of the height; the clip of [`torso_without_arms`]
/// for an arm without a side transition). At 0 the straight side is the
/// arm's first section itself, skin of both pieces; from 0.04 the clip
/// misses the loops; 0.015 keeps the torso's flange off the arm.
pub(super) const SHOULDER_OVERLAP: Real = 0.015;

/// [`fit_loop`], untangling a loop that crosses itself: where edges `i`
/// and `j` cross, the shorter run of points between them (a small twist of
/// the outline, e.g. where a mesh's toes touch) is dropped and the fit
/// retried, at most 8 times.
pub(super) fn fit_untangled(points: &[Point3], fo: &FitOptions) -> Result<LoopFit, String> {
    // The fit reports crossing edges in its cleaned list (consecutive
    // duplicates and a repeated closing point dropped): clean alike.
    let mut pts: Vec<Point3> = Vec::with_capacity(points.len());
    for p in points {
        if pts.last() != Some(p) {
            pts.push(*p);
        }
    }
    while pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    let mut tries = 0;
    loop {
        match fit_loop(&pts, fo) {
            Err(crate::curve::fit::FitError::SelfCrossing { first, second, .. })
                if tries < 8 && pts.len() > 8 =>
            {
                let n = pts.len();
                let (i, j) = (first.min(second), first.max(second).min(n - 1));
                pts = if j - i <= n / 2 {
                    pts[..=i].iter().chain(&pts[j + 1..]).copied().collect()
                } else {
                    pts[i + 1..=j].to_vec()
                };
                tries += 1;
            }
            other => return other.map_err(|e| e.to_string()),
        }
    }
}

/// Arc-length fraction of the axis point nearest `p`.
pub(super) fn fraction_of(axis: &PartAxis, p: Point3) -> Real {
    let total = axis.length();
    if !(total > 0.0) {
        return 0.0;
    }
    let mut acc = 0.0;
    let mut best = (Real::INFINITY, 0.0);
    for (k, q) in axis.points.iter().enumerate() {
        if k > 0 {
            acc += axis.points[k - 1].distance(*q);
        }
        let d = q.distance(p);
        if d < best.0 {
            best = (d, acc / total);
        }
    }
    best.1
}

/// Evenly spaced fractions from `t0` to `t1` at most `step` apart (both
/// ends included).
pub(super) fn fractions(t0: Real, t1: Real, step: Real) -> Vec<Real> {
    if !(t1 > t0) {
        return vec![t0];
    }
    let n = (((t1 - t0) / step).ceil() as usize).max(1);
    (0..=n)
        .map(|k| t0 + (t1 - t0) * k as Real / n as Real)
        .collect()
}

/// The sections of a part, plus the part's axis length.
pub(super) struct Plan {
    pub(super) name: PartName,
    pub(super) cuts: Vec<Cut>,
    pub(super) start_cap: CapKind,
    pub(super) end_cap: CapKind,
    /// For a dome end: the tip the dome should reach.
    pub(super) tip: Option<Point3>,
    /// Whether the end is left unchecked against the input: its tip is an
    /// estimate beyond it (an unseen crown), or it is a palm's flat end
    /// inside its fingers' parts.
    pub(super) end_unchecked: bool,
    /// How the torso meets the arms (torso only).
    pub(super) shoulders: Shoulders,
}

/// Cuts at every fraction, skipping (with a warning) those that fail.
pub(super) fn cut_all(
    cutter: &Cutter<'_>,
    name: PartName,
    ts: &[Real],
    opts: &ReconstructOptions,
    shoulders: Shoulders,
    warnings: &mut Vec<String>,
) -> Vec<Cut> {
    // Independent cuts: split over the cores, results in order.
    let cuts = parallel_map(ts, 4, |run| {
        run.iter()
            .map(|&t| cut_and_fit(cutter, name, t, opts, shoulders, None))
            .collect()
    });
    let mut out = Vec::with_capacity(ts.len());
    for (&t, cut) in ts.iter().zip(cuts) {
        match cut {
            Ok(c) => out.push(c),
            Err(e) => warnings.push(format!("{name}: section at {t:.3} skipped: {e}")),
        }
    }
    out
}

/// A rounded end's run of sections (head top, hand, foot): evenly from
/// `t0` in steps of `step` (axis fractions) up to `until` (the part's end
/// itself never); from `watch_from` on the run ends where the loop shrinks
/// below `end_area_fraction` of the area it is held `against`, or no
/// longer [`follows`] the loop before.
#[derive(Clone, Copy, Debug)]
pub(super) struct RoundedEnd {
    pub(super) t0: Real,
    /// The last fraction cut (1: to the part's end; a palm whose fingers
    /// are digits stops where they part).
    pub(super) until: Real,
    pub(super) watch_from: Real,
    pub(super) step: Real,
    pub(super) against: EndArea,
    /// Whether each loop after the first is made of the plane's loops
    /// inside the one before ([`Cutter::cut_within`]) rather than the one
    /// round the axis.
    pub(super) within_last: bool,
}

/// What a rounded end's loops are held against.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum EndArea {
    /// The largest loop seen from `watch_from` on (a head's widest, a
    /// foot's largest outline, a scan's palm with its thumb).
    Largest,
    /// The first loop from `watch_from` on (a mesh's wrist): past the
    /// palm a mesh's loop is the fingers' own outline, which runs on while
    /// they lie together and ends where one finger is cut alone.
    First,
}

/// Sections up to a rounded end ([`RoundedEnd`]).
pub(super) fn cut_to_rounded_end(
    cutter: &Cutter<'_>,
    name: PartName,
    run: RoundedEnd,
    opts: &ReconstructOptions,
    warnings: &mut Vec<String>,
) -> Vec<Cut> {
    let mut out: Vec<Cut> = Vec::new();
    let RoundedEnd {
        t0,
        until,
        watch_from,
        step,
        against,
        within_last,
    } = run;
    let mut reference: Real = 0.0;
    let mut failed = 0;
    let ts = fractions(t0, 1.0, step);
    let ts = &ts[..ts.len().saturating_sub(1)];
    let ts = &ts[..ts.iter().take_while(|&&t| t <= until).count()];
    // Cut a few planes ahead over the cores, then walk them in order: the
    // cuts past the end (at most one batch) are made and dropped.
    let batch = rayon::current_num_threads().clamp(1, 8);
    for chunk in ts.chunks(batch) {
        // A run that takes each loop inside the last one cuts in order once
        // it has a first loop; the loop round the axis, its fallback, is
        // cut only when needed.
        let ahead = !within_last || out.is_empty();
        let around = |t: Real| cut_and_fit(cutter, name, t, opts, Shoulders::default(), None);
        let cuts: Vec<Option<Result<Cut, String>>> = if ahead {
            parallel_map(chunk, 1, |run| {
                run.iter().map(|&t| Some(around(t))).collect()
            })
        } else {
            chunk.iter().map(|_| None).collect()
        };
        for (&t, c) in chunk.iter().zip(cuts) {
            let c = match out.last().filter(|_| within_last) {
                Some(prev) => following(cutter, name, t, opts, prev)
                    .or_else(|_| c.unwrap_or_else(|| around(t))),
                None => c.unwrap_or_else(|| around(t)),
            };
            let c = match c {
                Ok(c) => c,
                Err(e) => {
                    // Past `watch_from` a failed cut usually means the part
                    // has ended, but a single one may be a flaw of the input
                    // (a foot outline crossing itself where the toes touch,
                    // on the female mesh: its soles were left 1-2 cm
                    // uncovered): skip one, stop at the second in a row.
                    if t >= watch_from {
                        failed += 1;
                        if failed >= 2 {
                            return out;
                        }
                    }
                    warnings.push(format!("{name}: section at {t:.3} skipped: {e}"));
                    continue;
                }
            };
            failed = 0;
            if t >= watch_from {
                let shrunk = reference > 0.0 && c.area < opts.end_area_fraction * reference;
                if shrunk || out.last().is_some_and(|p| !follows(p, &c)) {
                    return out;
                }
                if against == EndArea::Largest || reference == 0.0 {
                    reference = reference.max(c.area);
                }
            }
            out.push(c);
        }
    }
    out
}

/// Whether the torso's axis `torso` pierces `cut`'s plane inside its
/// fitted curve: the loop holds the trunk, not only an arm (a raised arm's
/// first cuts across its own axis can run through the chest and shoulder).
pub(super) fn holds_axis(cut: &Cut, torso: &PartAxis) -> bool {
    let c = &cut.fit.curve;
    let outline = c.sample_plane(96);
    torso.points.windows(2).any(|w| {
        let (h0, h1) = (c.frame.height(w[0]), c.frame.height(w[1]));
        if h0 * h1 > 0.0 || h0 == h1 {
            return false;
        }
        let q = w[0] + (w[1] - w[0]) * (h0 / (h0 - h1));
        point_in_polygon(c.frame.to_plane(q), &outline)
    })
}

/// Whether `cut`'s loop is larger than the median of the next two loops'
/// by more than a third (the band [`build::HALFWAY_AREA`] allows between
/// neighbours): an arm's first loop that takes in some of the trunk.
pub(super) fn takes_in_trunk(cut: &Cut, next: &[Cut]) -> bool {
    let mut areas: Vec<Real> = next.iter().take(2).map(|c| c.area).collect();
    median(&mut areas).is_some_and(|m| cut.area * build::HALFWAY_AREA > m)
}

/// A test of whether a point, seen along `c`'s normal, lies inside it.
fn inside_curve(c: &TrigCurve) -> impl Fn(Point3) -> bool + '_ {
    let outline = c.sample_plane(96);
    move |p| point_in_polygon(c.frame.to_plane(p), &outline)
}

/// The cut at `t` made of the loops centred inside `prev`'s curve
/// ([`Cutter::cut_within`]).
fn following(
    cutter: &Cutter<'_>,
    name: PartName,
    t: Real,
    opts: &ReconstructOptions,
    prev: &Cut,
) -> Result<Cut, String> {
    let within = inside_curve(&prev.fit.curve);
    cut_and_fit(cutter, name, t, opts, Shoulders::default(), Some(&within))
}

/// Whether `next` continues the part `prev` belongs to: its centre lies
/// within twice `prev`'s mean radius `√(A/π)` of `prev`'s centre (a
/// hand's loops shift by about a radius where the thumb leaves them).
/// Where a foot's outlines end, the cut's nearest loop can be the other
/// foot or another part touching this one.
pub(super) fn follows(prev: &Cut, next: &Cut) -> bool {
    let r = mean_radius(prev.area);
    let (a, b) = (prev.fit.curve.frame.origin, next.fit.curve.frame.origin);
    a.distance(b) <= 2.0 * r
}

/// The leg's axis continued from the ankle straight down to `floor + lift`
/// along `−up`, in steps of `step`.
pub(super) fn extend_to_floor(
    axis: &PartAxis,
    up: Vec3,
    floor: Real,
    lift: Real,
    step: Real,
) -> PartAxis {
    let mut a = axis.clone();
    let Some(&last) = a.points.last() else {
        return a;
    };
    let r = a.radii.last().copied().unwrap_or(0.0);
    let drop = last.dot(up) - (floor + lift);
    if drop > step {
        let n = (drop / step).ceil() as usize;
        for k in 1..=n {
            a.points.push(last - up * (drop * k as Real / n as Real));
            a.radii.push(r);
        }
    }
    a
}

/// The level along `up` of a foot's bottom under its last outline `c` (a
/// horizontal curve): the lowest hundredth of the input's points below
/// `c`'s plane whose projection falls inside it (a stray point or two
/// does not count), never below `floor`; `floor` when none falls inside.
pub(super) fn sole_level(body: BodyGeometry<'_>, c: &TrigCurve, up: Vec3, floor: Real) -> Real {
    let outline = c.sample_plane(96);
    let top = c.frame.origin.dot(up);
    let mut below: Vec<Real> = body
        .positions()
        .iter()
        .filter(|p| p.dot(up) < top)
        .filter(|p| point_in_polygon(c.frame.to_plane(**p), &outline))
        .map(|p| p.dot(up))
        .collect();
    let k = below.len() / 100;
    nth_smallest(&mut below, k).map_or(floor, |b| b.max(floor))
}

/// The first arc-length fraction where the axis reaches `level` along `up`
/// (going up when `rising`, down otherwise); 0 when it starts beyond it.
pub(super) fn fraction_at_level(axis: &PartAxis, up: Vec3, level: Real, rising: bool) -> Real {
    let total = axis.length();
    if !(total > 0.0) {
        return 0.0;
    }
    let beyond = |p: &Point3| {
        if rising {
            p.dot(up) >= level
        } else {
            p.dot(up) <= level
        }
    };
    let mut acc = 0.0;
    for (k, p) in axis.points.iter().enumerate() {
        if k > 0 {
            acc += axis.points[k - 1].distance(*p);
        }
        if beyond(p) {
            return (acc / total).min(0.5);
        }
    }
    0.0
}

pub(super) fn landmark(seg: &Segmentation, kind: LandmarkKind) -> Option<Point3> {
    seg.landmark(kind).map(|l| l.position)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::trig::Frame;
    use crate::section::girth::polygon_tape_girth;
    use crate::{assert_near, assert_vec_near};

    /// A body `h` high (up = z, left = x) whose only part is a left arm
    /// 0.5 long from `p0` along `t0`, with its armpit and wrist.
    fn one_arm(h: Real, p0: Point3, t0: Vec3, armpit: Point3) -> Segmentation {
        let landmark = |kind, position: Point3| crate::anatomy::Landmark {
            kind,
            position,
            height_fraction: position.z / h,
            confidence: 1.0,
            how: "test",
        };
        Segmentation::z_up(
            h,
            vec![
                landmark(LandmarkKind::LeftArmpit, armpit),
                landmark(LandmarkKind::LeftWrist, p0 + t0 * 0.5),
            ],
            vec![PartAxis {
                name: PartName::LeftArm,
                points: (0..=50).map(|i| p0 + t0 * (0.01 * i as Real)).collect(),
                radii: vec![0.045; 51],
                start: LandmarkKind::LeftShoulder,
                end: LandmarkKind::LeftHandTip,
            }],
        )
    }

    /// A body 1.7 high (up = z, left = x) with a left arm hanging at 45°
    /// from a shoulder end at (0.2, 0, 1.3), its armpit at 1.27: a torso
    /// loop above the armpit that runs out to ±0.26 loses what lies past
    /// the arm's first section moved `SHOULDER_OVERLAP · H` into the arm
    /// (its straight side on that plane) when the arm has no side
    /// transition, and what lies past the side plane through the armpit
    /// when it has; the right side (no arm found) and a loop below the
    /// armpit are left alone.
    #[test]
    fn a_torso_loop_above_the_armpit_stops_inside_the_hanging_arm() {
        let h = 1.7;
        let p0 = Point3::new(0.2, 0.0, 1.3);
        let t0 = Vec3::new(1.0, 0.0, -1.0).normalized().unwrap();
        let seg = one_arm(h, p0, t0, Point3::new(0.18, 0.0, 1.27));
        let stadium = |z: Real, half: Real| {
            let points: Vec<Point3> = (0..400)
                .map(|i| {
                    let t = std::f64::consts::TAU * i as Real / 400.0;
                    Point3::new(half * t.cos(), 0.1 * t.sin(), z)
                })
                .collect();
            SectionLoop::from_points(points, Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0))
                .unwrap()
        };
        let extent = |l: &SectionLoop| {
            let xs = l.points.iter().map(|p| p.x);
            (
                xs.clone().fold(Real::INFINITY, Real::min),
                xs.fold(Real::NEG_INFINITY, Real::max),
            )
        };
        // Above the armpit: the plane (p − p₀ − δ t₀)·t₀ = 0 meets z = 1.29
        // at x = 0.2 + δ √2 + (1.29 − 1.3) (45°: one to one).
        let overlap = Shoulders::default();
        let above =
            torso_without_arms(&seg, stadium(1.29, 0.26), overlap, &mut Vec::new()).unwrap();
        let origin = p0 + t0 * (SHOULDER_OVERLAP * h);
        let (lo, hi) = extent(&above);
        let x = 0.2 + SHOULDER_OVERLAP * h * std::f64::consts::SQRT_2 - 0.01;
        assert!((hi - x).abs() < 1e-12, "{hi} vs {x}");
        assert!((lo + 0.26).abs() < 1e-12, "{lo}");
        assert!(above.points.iter().all(|&p| (p - origin).dot(t0) <= 1e-12));
        // Below the armpit the arm is a loop of its own: nothing to clip.
        let below = stadium(1.25, 0.26);
        assert_eq!(
            torso_without_arms(&seg, below.clone(), overlap, &mut Vec::new()).unwrap(),
            below
        );
        // With the arm's transition on the torso's side: the loop stops
        // past the vertical plane through the armpit (x = 0.18), by
        // SIDE_OVERLAP · H ramped over SIDE_RAMP · H above the armpit.
        let side = Shoulders::of(&seg);
        assert_eq!(side.side, [true, false]);
        let above = torso_without_arms(&seg, stadium(1.29, 0.26), side, &mut Vec::new()).unwrap();
        let (lo, hi) = extent(&above);
        let reach = SIDE_OVERLAP * h * ((0.02 / h) / SIDE_RAMP).min(1.0);
        assert!((hi - (0.18 + reach)).abs() < 1e-12, "{hi}");
        assert!((lo + 0.26).abs() < 1e-12, "{lo}");
        assert_eq!(
            torso_without_arms(&seg, below.clone(), side, &mut Vec::new()).unwrap(),
            below
        );
        // Just below the armpit (within SIDE_BELOW), a loop still holding
        // part of the arm stops at the side plane itself; without the side
        // transition it is left alone.
        let just_below = stadium(1.268, 0.26);
        let (_, hi) =
            extent(&torso_without_arms(&seg, just_below.clone(), side, &mut Vec::new()).unwrap());
        assert!((hi - 0.18).abs() < 1e-12, "{hi}");
        assert_eq!(
            torso_without_arms(&seg, just_below.clone(), overlap, &mut Vec::new()).unwrap(),
            just_below
        );
    }

    /// A left arm held out nearly level (no side transition) whose first
    /// built section lies a fifth along its axis: torso loops above the
    /// armpit and below it that run out along the arm both stop just past
    /// that section (not at the boundary plane through the armpit, which
    /// lies short of it), and say so in `clips`; the straight side is
    /// hidden within the tube's radius of the arm's axis only.
    #[test]
    fn a_torso_loop_along_a_held_out_arm_stops_at_its_first_section() {
        let h = 1.7;
        let p0 = Point3::new(0.2, 0.0, 1.3);
        let t0 = Vec3::new(1.0, 0.0, -0.1).normalized().unwrap();
        let armpit = Point3::new(0.18, 0.0, 1.27);
        let seg = one_arm(h, p0, t0, armpit);
        let slab = |z: Real| {
            let points: Vec<Point3> = (0..400)
                .map(|i| {
                    let t = std::f64::consts::TAU * i as Real / 400.0;
                    Point3::new(0.6 * t.cos(), 0.1 * t.sin(), z)
                })
                .collect();
            SectionLoop::from_points(points, Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0))
                .unwrap()
        };
        let shoulders = Shoulders {
            side: [false; 2],
            start: [Some(0.2), None],
            radius: [0.05, 0.0],
        };
        assert!(hanging_shoulder(&seg, PartName::LeftArm).is_none());
        let centre = p0 + t0 * (0.2 * 0.5);
        let first = centre + t0 * (SHOULDER_OVERLAP * h);
        for z in [1.29, 1.25] {
            let mut clips = Vec::new();
            let clipped = torso_without_arms(&seg, slab(z), shoulders, &mut clips).unwrap();
            let past = clipped.points.iter().map(|&p| (p - first).dot(t0));
            let reach = past.fold(Real::NEG_INFINITY, Real::max);
            assert!(reach <= 1e-12 && reach > -1e-3, "{z}: {reach}");
            assert_eq!(clips.len(), 1);
            let clip = clips[0];
            assert_vec_near!(clip.origin, first, 1e-12);
            assert_vec_near!(clip.centre, centre, 1e-12);
            // The radius is the first section's, at most 1.5 times the
            // arm's median (0.045 here).
            assert_near!(clip.radius, 0.05, 1e-15);
            // On the plane: hidden near the axis, not 0.06 away from it or
            // off the plane.
            let across = Vec3::new(0.0, 1.0, 0.0);
            assert!(clip.hides(first + across * 0.04, 1e-3));
            assert!(!clip.hides(first + across * 0.06, 1e-3));
            assert!(!clip.hides(first + across * 0.01 + t0 * 0.002, 1e-3));
        }
        // A loop that does not reach the plane is not clipped there.
        let mut clips = Vec::new();
        let narrow = SectionLoop::from_points(
            (0..400)
                .map(|i| {
                    let t = std::f64::consts::TAU * i as Real / 400.0;
                    Point3::new(0.1 * t.cos(), 0.1 * t.sin(), 1.29)
                })
                .collect(),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap();
        let kept = torso_without_arms(&seg, narrow.clone(), shoulders, &mut clips).unwrap();
        assert_eq!(kept, narrow);
        assert!(clips.is_empty());
    }

    /// The plane beside an arm leaning forward at its start is turned to
    /// face sideways (up = z, front = -y, left = x); an arm starting
    /// straight forward or across the chest keeps its own direction.
    #[test]
    fn the_plane_beside_an_arm_faces_sideways() {
        let seg = Segmentation::z_up(1.7, Vec::new(), Vec::new());
        let unit = |x: Real, y: Real, z: Real| Vec3::new(x, y, z).normalized().unwrap();
        let leaning = unit(1.0, -0.5, 0.5);
        let n = coronal_outward(&seg, PartName::LeftArm, leaning);
        assert_vec_near!(n, unit(1.0, 0.0, 0.5), 1e-15);
        let forward = unit(0.0, -1.0, 0.0);
        assert_eq!(coronal_outward(&seg, PartName::LeftArm, forward), forward);
        let across = unit(1.0, -0.3, 0.0);
        assert_eq!(coronal_outward(&seg, PartName::RightArm, across), across);
        let right = unit(-1.0, 0.4, 0.2);
        assert_vec_near!(
            coronal_outward(&seg, PartName::RightArm, right),
            unit(-1.0, 0.0, 0.2),
            1e-15
        );
    }

    /// A cut fitted to the ellipse of semi-axes 0.05 (x) and 0.1 (y)
    /// centred at `(x, 0, 0.02)` in the plane `z = 0.02`.
    fn elliptic_cut(x: Real, at: Real) -> Cut {
        let points: Vec<Point3> = (0..64)
            .map(|i| {
                let t = std::f64::consts::TAU * i as Real / 64.0;
                Point3::new(x + 0.05 * t.cos(), 0.1 * t.sin(), 0.02)
            })
            .collect();
        let fit = fit_loop(&points, &FitOptions::default()).unwrap();
        let area = fit.curve.area().abs();
        Cut {
            at,
            fit,
            area,
            clips: Vec::new(),
            bridge: Vec::new(),
        }
    }

    /// A foot outline's successor lies within two mean radii of it; the
    /// other foot, 0.25 away, does not continue it.
    #[test]
    fn the_other_foot_does_not_continue_a_foot() {
        let cut = |x: Real| elliptic_cut(x, 0.9);
        // Mean radius √(0.05 · 0.1) ≈ 0.0707.
        let foot = cut(0.0);
        assert!(follows(&foot, &cut(0.03)));
        assert!(follows(&foot, &cut(0.14)));
        assert!(!follows(&foot, &cut(0.25)));
    }

    /// An arm's cut holds the torso's axis where the axis pierces its
    /// plane inside the loop; not beside the loop, nor where the axis ends
    /// below the plane.
    #[test]
    fn a_loop_round_the_torso_s_axis_holds_it() {
        let cut = |x: Real| elliptic_cut(x, 0.0);
        let torso = |top: Real| PartAxis {
            name: PartName::Torso,
            points: (0..=10)
                .map(|i| Point3::new(0.01, 0.0, -1.0 + (top + 1.0) * i as Real / 10.0))
                .collect(),
            radii: vec![0.15; 11],
            start: LandmarkKind::Crotch,
            end: LandmarkKind::Neck,
        };
        assert!(holds_axis(&cut(0.0), &torso(1.0)));
        assert!(!holds_axis(&cut(0.25), &torso(1.0)));
        assert!(!holds_axis(&cut(0.0), &torso(0.0)));
    }

    /// A foot lifted 3 cm off the floor: its sole is its own lowest points
    /// (a lone stray point below them does not count), not the floor; the
    /// floor when nothing lies under the outline, and never below it.
    #[test]
    fn a_lifted_foot_keeps_its_own_sole() {
        let up = Vec3::new(0.0, 1.0, 0.0);
        let frame =
            Frame::from_normal(Point3::new(0.0, 0.10, 0.0), up, Vec3::new(0.0, 0.0, 1.0)).unwrap();
        let outline = TrigCurve::circle(frame, 0.05, 4);
        // A column of points from y = 0.03 up to 0.15 inside the outline,
        // and points beside it down to the floor at 0.
        let mut pts = Vec::new();
        for i in 0..=60 {
            let y = 0.03 + 0.002 * i as Real;
            for k in 0..12 {
                let a = k as Real * std::f64::consts::TAU / 12.0;
                pts.push(Point3::new(0.03 * a.cos(), y, 0.03 * a.sin()));
                pts.push(Point3::new(0.2 + 0.03 * a.cos(), y - 0.03, 0.03 * a.sin()));
            }
        }
        pts.push(Point3::new(0.0, 0.01, 0.0)); // a stray point under the foot
        let cloud = PointCloud::new(pts).unwrap();
        let body = BodyGeometry::Cloud(&cloud);
        let level = sole_level(body, &outline, up, 0.0);
        assert!((level - 0.03).abs() < 1e-12, "{level}");
        assert_eq!(sole_level(body, &outline, up, 0.05), 0.05);
        let away = TrigCurve::circle(
            Frame::from_normal(Point3::new(1.0, 0.1, 0.0), up, Vec3::new(0.0, 0.0, 1.0)).unwrap(),
            0.05,
            4,
        );
        assert_eq!(sole_level(body, &away, up, -0.01), -0.01);
    }

    /// A loop with two narrow bumps (a bust seen from above): the fit at
    /// the order E_a and E_M allow rounds the bumps off and its tape girth
    /// falls short; [`with_tape_girth`] raises the order until the tape
    /// girth is within the tolerance, and leaves a loop that already meets
    /// it alone.
    #[test]
    fn the_tape_girth_check_raises_the_order_until_the_tape_agrees() {
        let bump = |t: Real, c: Real| (t - c).cos().max(0.0).powi(150);
        let points: Vec<Point3> = (0..400)
            .map(|i| {
                let t = std::f64::consts::TAU * i as Real / 400.0;
                let r = 0.12 * (1.0 + 0.3 * bump(t, 1.3) + 0.3 * bump(t, 1.85));
                Vec3::new(1.6 * r * t.cos(), r * t.sin(), 0.0)
            })
            .collect();
        let outline = SectionLoop::from_points(points.clone(), Vec3::X, Vec3::Y).unwrap();
        let fo = FitOptions {
            normal: Some(Vec3::Z),
            ..FitOptions::default()
        };
        let fit = fit_loop(&points, &fo).unwrap();
        let target = polygon_tape_girth(&outline.plane_points());
        let miss =
            |f: &LoopFit| (polygon_tape_girth(&f.curve.sample_plane(256)) - target).abs() / target;
        assert!(
            miss(&fit) > 0.004,
            "the plain fit's tape miss {}",
            miss(&fit)
        );
        let order = fit.order;
        let raised = with_tape_girth(fit, &outline, &points, &fo, 0.004);
        assert!(raised.order > order);
        assert!(miss(&raised) <= 0.004, "{}", miss(&raised));
        // Already within: unchanged.
        let again = with_tape_girth(raised.clone(), &outline, &points, &fo, 0.004);
        assert_eq!(again.order, raised.order);
    }
}
