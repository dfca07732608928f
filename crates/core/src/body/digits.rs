//! Digits: the fingers of a hand held apart, each a part of its own.
//!
//! Past the knuckles a cut across the hand's axis meets each finger held
//! apart as a loop of its own; a mitten's skin spans the gaps between them
//! (far from the input) and rounds the fingertips into one dome.
//!
//! 1. **Levels.** From the wrist to the hand's tip every
//!    [`DIGIT_SPACING`] × `H` along the arm's axis, every loop near the
//!    axis point of the plane across the hand's direction (wrist to tip:
//!    the planes are parallel, so that no two cross inside a finger where
//!    the axis bends; [`Cutter::loops_at`]). A scan's slab image joins
//!    fingers a few point spacings apart, so a cloud's levels split each
//!    slab by the points past it: linked within [`DIGIT_LINK_SPACINGS`]
//!    point spacings, they fall into one component per finger
//!    ([`crate::section::cloud::superlevel`]), and each component's share
//!    of the slab is cut alone.
//! 2. **Runs.** A loop continues the run whose loop at the level before
//!    contains its centroid, or whose centroid it contains (the nearest
//!    such run); a cloud's loop, the run whose last loop's component holds
//!    it (across a level where a finger's slab had too few points). A run
//!    continued by two or more loops ends there (it splits) and each of
//!    those loops starts a run of its own, its child.
//! 3. **Digits.** A run descended from the wrist's loop that ends without
//!    splitting, with at least [`MIN_DIGIT_SECTIONS`] loops, none over
//!    [`MAX_DIGIT_SHARE`] of the hand's largest loop (the palm's) and one
//!    at least [`MIN_DIGIT_SHARE`] of it. A hand
//!    with at least [`MIN_DIGITS`] digits is split; otherwise its fingers
//!    touch and the hand stays a mitten, with a warning.
//! 4. **Parts.** The palm's run ends at the level before its last digit
//!    starts, closed flat (the fingers that leave earlier overlap it).
//!    Each digit is skinned through its loops every
//!    [`ReconstructOptions::digit_spacing`] (and its last), its first loop repeated
//!    [`DIGIT_OVERLAP`] levels back inside the palm (so that its open start
//!    lies within the palm's solid and the union has no seam), and closed
//!    by a dome reaching where its loops vanish (bisected,
//!    [`crate::body::END_BISECTIONS`] halvings; a cloud's, where its
//!    component's points end, from its last loop of at least
//!    [`DIGIT_END_SHARE`] of its median loop's area). Its sections lie across the hand's
//!    direction, not each finger's own: spread fingers are cut a little
//!    obliquely, curled ones end where the cuts leave them.

use super::*;
use crate::body::cavity::{continues, dome_reaching, vanishing};
use crate::geom::stats::median;
use crate::section::cloud::superlevel::{superlevel_loops, Region, NO_COMPONENT};
use crate::section::cloud::ScanSectionOptions;

/// Spacing of the levels across the hand, as a fraction of the body's
/// height: 0.004 (7 mm on 1.73 m, 6-12 sections over a finger).
pub const DIGIT_SPACING: Real = 0.004;

/// Fewest loops of a digit's run (a thumb crossed by two cuts on its way
/// out of the plane is left in the palm's outline).
pub const MIN_DIGIT_SECTIONS: usize = 3;

/// A digit's loops are at most this share of the hand's largest loop (a
/// finger's is 5-12 % of the palm's; two fingers together up to 25 %).
pub const MAX_DIGIT_SHARE: Real = 0.3;

/// A digit's largest loop is at least this share of the hand's largest:
/// a sliver (a ring, a nail's edge, a stray fold of a scanned mesh) is
/// not a finger (a thumb's tip is 3 %).
pub const MIN_DIGIT_SHARE: Real = 0.01;

/// Fewest digits of a split hand: four fingers apart, or three with two
/// touching.
pub const MIN_DIGITS: usize = 3;

/// The highest order of a digit's section.
pub const MAX_DIGIT_ORDER: usize = 3;

/// How many levels back inside the palm a digit's first loop is repeated.
pub const DIGIT_OVERLAP: Real = 1.5;

/// A finger or thumb of a hand: a part of its own, overlapping the palm's
/// end.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyDigit {
    /// The arm whose hand it belongs to.
    pub hand: PartName,
    pub part: Part,
    /// One entry per section of `part`, in order.
    pub fits: Vec<SectionFit>,
}

/// Each digit's number on its hand, from 1 in the order given (as the
/// model file names them: `left_arm_digit_1`, …).
pub(super) fn digit_numbers(digits: &[BodyDigit]) -> Vec<usize> {
    (0..digits.len())
        .map(|k| {
            digits[..k]
                .iter()
                .filter(|e| e.hand == digits[k].hand)
                .count()
                + 1
        })
        .collect()
}

/// A hand split into its palm and the runs of its digits.
pub(super) struct HandSplit {
    /// The axis fraction of the palm's last level.
    pub(super) palm_end: Real,
    /// The levels' spacing (axis fraction).
    step: Real,
    /// The levels' planes' normal: the hand's direction.
    normal: Vec3,
    /// Each digit's loops with their axis fractions.
    digits: Vec<Vec<(Real, SectionLoop)>>,
    /// Each digit's tip height along `normal` where a cloud's points end
    /// (`None`: found from its loops).
    tips: Vec<Option<Real>>,
}

/// A loop of a level across the hand; a cloud's with the height its
/// points reach along the hand's direction and its component at each
/// level ([`crate::section::cloud::superlevel::LevelLoop`]).
type Cut = (SectionLoop, Option<(Real, Vec<u32>)>);

/// Whether `next` continues a run whose last loop is `last` at level
/// `j`: a cloud's lies in the same component there (past a level where
/// a finger's slab had too few points, too), a mesh's contains its
/// centroid or the other way round.
fn joins((j, last): &(usize, Cut), next: &Cut) -> bool {
    match (&last.1, &next.1) {
        (Some((_, a)), Some((_, b))) => a[*j] != NO_COMPONENT && a[*j] == b[*j],
        _ => continues(&last.0, &next.0),
    }
}

/// A run of loops from level to level.
struct Run {
    loops: Vec<(usize, Cut)>,
    parent: Option<usize>,
    split: bool,
}

/// The runs of `levels` (see the module doc, step 2); run 0 starts at the
/// largest loop of level 0 round `centre`, else the nearest to it.
fn runs_of(levels: Vec<Vec<Cut>>, centre: Point3) -> Vec<Run> {
    let mut runs: Vec<Run> = Vec::new();
    let mut alive: Vec<usize> = Vec::new();
    for (k, loops) in levels.into_iter().enumerate() {
        let mut loops = loops;
        if k == 0 {
            // The largest loop round the centre (not a cap's disc inside
            // it), else the nearest.
            let key = |l: &Cut| match l.0.contains(centre) {
                true => (0, -l.0.area),
                false => (1, l.0.centroid.distance(centre)),
            };
            loops.sort_by(|a, b| {
                let (ka, kb) = (key(a), key(b));
                ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
            });
        }
        // Each loop's run: the nearest alive run it continues.
        let owner: Vec<Option<usize>> = loops
            .iter()
            .map(|l| {
                alive
                    .iter()
                    .copied()
                    .filter(|&r| joins(runs[r].loops.last().expect("runs hold loops"), l))
                    .min_by(|&a, &b| {
                        let d = |r: usize| {
                            runs[r]
                                .loops
                                .last()
                                .map_or(Real::MAX, |(_, p)| p.0.centroid.distance(l.0.centroid))
                        };
                        d(a).total_cmp(&d(b))
                    })
            })
            .collect();
        let mut next = Vec::new();
        for (l, o) in loops.into_iter().zip(&owner) {
            let children = o.map_or(0, |r| owner.iter().filter(|x| **x == Some(r)).count());
            match o {
                Some(r) if children == 1 => {
                    runs[*r].loops.push((k, l));
                    next.push(*r);
                }
                _ => {
                    if let Some(r) = o {
                        runs[*r].split = true;
                    }
                    runs.push(Run {
                        loops: vec![(k, l)],
                        parent: *o,
                        split: false,
                    });
                    next.push(runs.len() - 1);
                }
            }
        }
        alive = next;
    }
    runs
}

/// Whether run `r` descends from run 0 (the wrist's).
fn from_wrist(runs: &[Run], mut r: usize) -> bool {
    loop {
        if r == 0 {
            return true;
        }
        match runs[r].parent {
            Some(p) => r = p,
            None => return false,
        }
    }
}

/// Splits `arm`'s hand, from the axis fraction `wrist` on, into its palm
/// and digits (module doc); `Err` says why the hand stays a mitten.
pub(super) fn split_hand(
    cutter: &Cutter<'_>,
    arm: PartName,
    wrist: Real,
    opts: &ReconstructOptions,
) -> Result<HandSplit, String> {
    let seg = cutter.segmentation();
    let axis = seg.part(arm).ok_or("no arm")?;
    let len = axis.length();
    if !(len > 0.0) || !(wrist < 1.0) {
        return Err("no hand past the wrist".into());
    }
    let step = DIGIT_SPACING * seg.height / len;
    let ts = fractions(wrist, 1.0, step);
    let no_hand = || "no hand past the wrist".to_string();
    let centre = axis.point_and_tangent(wrist).ok_or_else(no_hand)?.0;
    let tip = *axis.points.last().ok_or_else(no_hand)?;
    let normal = (tip - centre).normalized().ok_or_else(no_hand)?;
    let levels: Vec<Vec<Cut>> = match cutter.body() {
        BodyGeometry::Mesh(_) => {
            let loops_at = |t: Real| {
                cutter
                    .loops_at(arm, t, Some(normal), &opts.segment)
                    .map(|(_, l)| l.into_iter().map(|l| (l, None)).collect())
                    .unwrap_or_default()
            };
            crate::geom::parallel::parallel_map(&ts, 4, |run| {
                run.iter().map(|&t| loops_at(t)).collect()
            })
        }
        BodyGeometry::Cloud(c) => cloud_levels(cutter, c, (arm, &ts), (centre, normal), opts)
            .ok_or("the cloud's point spacing is unknown")?,
    };
    let runs = runs_of(levels, centre);
    let hand: Vec<usize> = (0..runs.len()).filter(|&r| from_wrist(&runs, r)).collect();
    let largest = hand
        .iter()
        .flat_map(|&r| runs[r].loops.iter().map(|(_, l)| l.0.area))
        .fold(0.0, Real::max);
    let digits: Vec<&Run> = hand
        .iter()
        .map(|&r| &runs[r])
        .filter(|r| {
            let areas = || r.loops.iter().map(|(_, l)| l.0.area);
            !r.split
                && r.loops.len() >= MIN_DIGIT_SECTIONS
                && areas().all(|a| a <= MAX_DIGIT_SHARE * largest)
                && areas().any(|a| a >= MIN_DIGIT_SHARE * largest)
        })
        .collect();
    if digits.len() < MIN_DIGITS {
        return Err(format!(
            "{} finger(s) apart in the input, {MIN_DIGITS} needed",
            digits.len()
        ));
    }
    let last_start = digits.iter().map(|r| r.loops[0].0).max().unwrap_or(0);
    if last_start == 0 {
        return Err("the fingers part at the wrist".into());
    }
    let tips = digits
        .iter()
        .map(|r| r.loops.last().and_then(|(_, l)| l.1.as_ref().map(|c| c.0)))
        .collect();
    let digits = digits
        .into_iter()
        .map(|run| {
            run.loops[..kept_loops(&run.loops)]
                .iter()
                .map(|(k, l)| (ts[*k], l.0.clone()))
                .collect()
        })
        .collect();
    Ok(HandSplit {
        palm_end: ts[last_start - 1],
        step,
        normal,
        digits,
        tips,
    })
}

/// How many of a run's loops a digit is skinned through: a cloud's
/// without its last loops under [`DIGIT_END_SHARE`] of the run's median
/// area (a fingertip's slab of a few scattered points gives a small loop
/// whose harmonics tangle; its dome reaches the tip from the loop before),
/// keeping [`MIN_DIGIT_SECTIONS`]; a mesh's all (its tip is found from
/// its last loop).
fn kept_loops(loops: &[(usize, Cut)]) -> usize {
    let mut areas: Vec<Real> = loops.iter().map(|(_, l)| l.0.area).collect();
    let cloud = loops.iter().all(|(_, l)| l.1.is_some());
    let Some(median) = median(&mut areas).filter(|_| cloud) else {
        return loops.len();
    };
    let mut n = loops.len();
    while n > MIN_DIGIT_SECTIONS && loops[n - 1].1 .0.area < DIGIT_END_SHARE * median {
        n -= 1;
    }
    n
}

/// A cloud's digit ends before its loops fall under this share of its
/// median loop's area ([`kept_loops`]).
pub const DIGIT_END_SHARE: Real = 0.25;

/// How far apart, in point spacings, two points of a cloud's hand may lie
/// and still be one finger's ([`superlevel_loops`]' link): across a
/// scanner's thin stretches of a finger, not across the gap to the next.
pub const DIGIT_LINK_SPACINGS: Real = 1.75;

/// The fewest points of a cloud's loop across a finger (the slab's
/// default asks for 12).
pub const DIGIT_SLAB_POINTS: usize = 5;

/// A cloud's loops at the axis fractions `ts` of `arm`'s hand, across
/// `normal` (module doc, step 1): the cloud's points near the hand's line
/// from `centre` along `normal`, each level's slab split by what lies past
/// it ([`superlevel_loops`]), so that fingers a slab's closing would join
/// are loops of their own. `None` when the cloud's spacing is unknown.
fn cloud_levels(
    cutter: &Cutter<'_>,
    cloud: &PointCloud,
    (arm, ts): (PartName, &[Real]),
    (centre, normal): (Point3, Vec3),
    opts: &ReconstructOptions,
) -> Option<Vec<Vec<Cut>>> {
    let seg = cutter.segmentation();
    let axis = seg.part(arm)?;
    // A finger's slab holds few points (its sides facing the next
    // finger are seldom seen).
    let so = ScanSectionOptions {
        min_slab_points: DIGIT_SLAB_POINTS,
        min_component_points: DIGIT_SLAB_POINTS,
        ..cutter.slab_options(&opts.segment)?
    };
    let (t, g) = (so.half_thickness?, so.cell_size?);
    let spacing = seg.point_spacing.unwrap_or(g);
    let offsets: Vec<Real> = ts
        .iter()
        .map(|&f| {
            axis.point_and_tangent(f)
                .map_or(Real::NAN, |(p, _)| p.dot(normal))
        })
        .collect();
    // The points the levels' cuts see: within the cuts' radius of the
    // hand's line, from the wrist's slab on.
    let radius = 3.0 * axis.max_radius().max(seg.height * 0.02);
    let ids: Vec<u32> = (0..cloud.positions.len() as u32)
        .filter(|&i| {
            let d = cloud.positions[i as usize] - centre;
            let along = d.dot(normal);
            along >= -t && (d - normal * along).norm() <= radius
        })
        .collect();
    let region = Region {
        positions: &cloud.positions,
        ids: &ids,
        axis: normal,
    };
    let levels = superlevel_loops(&region, &offsets, DIGIT_LINK_SPACINGS * spacing, g, &so);
    Some(
        levels
            .into_iter()
            .map(|l| {
                l.into_iter()
                    .map(|l| (l.outline, Some((l.reach, l.component))))
                    .collect()
            })
            .collect(),
    )
}

/// The digits of `split` (`arm`'s hand), each reaching back
/// [`DIGIT_OVERLAP`] levels past `palm_last` (the axis fraction of the
/// built palm's last section: a section there can have been dropped) or
/// its own first loop, whichever is further back; a digit that cannot be
/// built is left out with a warning.
pub(super) fn build_digits(
    cutter: &Cutter<'_>,
    arm: PartName,
    split: &HandSplit,
    palm_last: Real,
    opts: &ReconstructOptions,
    warnings: &mut Vec<String>,
) -> Vec<BodyDigit> {
    let mut out = Vec::with_capacity(split.digits.len());
    for k in 0..split.digits.len() {
        match build_digit(cutter, arm, k, split, palm_last, opts) {
            Ok(d) => out.push(d),
            Err(e) => warnings.push(format!("{arm}: digit {} left out: {e}", k + 1)),
        }
    }
    out
}

/// The axis fraction past `end` (a digit's last loop, at `at`) where its
/// loops vanish: bisected between `at` and the next level of `split`.
fn tip_fraction(
    cutter: &Cutter<'_>,
    arm: PartName,
    split: &HandSplit,
    (at, end): (Real, &SectionLoop),
    opts: &ReconstructOptions,
) -> Real {
    vanishing(at, (at + split.step).min(1.0), |t| {
        cutter
            .loops_at(arm, t, Some(split.normal), &opts.segment)
            .map(|(_, loops)| loops.iter().any(|l| continues(end, l)))
            .unwrap_or(false)
    })
}

/// Digit `digit` of `split` from its loops (axis fraction, loop), starting
/// inside the palm whose last section lies at `palm_last` (module doc,
/// step 4).
fn build_digit(
    cutter: &Cutter<'_>,
    arm: PartName,
    digit: usize,
    split: &HandSplit,
    palm_last: Real,
    opts: &ReconstructOptions,
) -> Result<BodyDigit, String> {
    let (run, step, normal) = (&split.digits[digit], split.step, split.normal);
    let len = cutter.segmentation().part(arm).ok_or("no arm")?.length();
    let n = run.len();
    let fo = FitOptions {
        reference: Some(cutter.segmentation().frame.front),
        normal: Some(normal),
        allow_non_planar: true,
        max_order: opts.fit.max_order.min(MAX_DIGIT_ORDER),
        ..opts.fit
    };
    // Every `digit_spacing` of the run and its last loop.
    let stride = ((opts.digit_spacing / DIGIT_SPACING).round() as usize).max(1);
    let mut fits = Vec::with_capacity(n / stride + 2);
    let mut curves = Vec::with_capacity(n / stride + 2);
    for (k, (at, outline)) in run.iter().enumerate() {
        if k % stride == 0 || k + 1 == n {
            let fit = plan::fit_untangled(&outline.with_edge_midpoints(), &fo)?;
            fits.push(SectionFit::of(*at, &fit));
            curves.push(fit.curve);
        }
    }
    // The first curve again inside the palm: back along the digit's own
    // run (its centroids' mean step over its first loops, whose part
    // along the planes' normal is one level), so that a thumb leaving the
    // palm sideways starts inside the palm, not beside it.
    let (first_at, first) = (run[0].0, &run[0].1);
    let start = (first_at - DIGIT_OVERLAP * step).min(palm_last - DIGIT_OVERLAP * step);
    let k = n.min(3) - 1;
    let drift = (run[k].1.centroid - first.centroid) * (1.0 / k.max(1) as Real);
    let per_level = match drift.dot(normal) {
        along if k > 0 && along > 0.0 => drift * (step * len / along),
        _ => normal * (step * len),
    };
    let mut inside = curves[0].clone();
    inside.frame.origin -= per_level * ((first_at - start) / step);
    curves.insert(0, inside);
    fits.insert(
        0,
        SectionFit {
            at: start,
            ..fits[0]
        },
    );
    // The dome reaches where the last loop's run vanishes.
    let (last_at, last) = (run[n - 1].0, &run[n - 1].1);
    let tip = match split.tips[digit] {
        Some(h) => last.centroid + normal * (h - last.centroid.dot(normal)),
        None => {
            let tip_at = tip_fraction(cutter, arm, split, (last_at, last), opts);
            last.centroid + normal * ((tip_at - last_at) * len)
        }
    };
    let options = PartOptions {
        start_cap: CapKind::Open,
        end_cap: dome_reaching(curves.last().ok_or("no sections")?, tip),
        ..opts.part
    };
    let part = Part::new(curves, &options).map_err(|e| e.to_string())?;
    Ok(BodyDigit {
        hand: arm,
        part,
        fits,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::shapes::{cylinder, merge};

    /// The left hand's split from the wrist at 0, with default options.
    fn split_of(cutter: &Cutter<'_>) -> Result<HandSplit, String> {
        split_hand(
            cutter,
            PartName::LeftArm,
            0.0,
            &ReconstructOptions::default(),
        )
    }

    /// A hand hanging along −z: a palm (a cylinder of radius 45 mm from
    /// 0.75 to 0.9 up) and `fingers` fingers of radius `r` from 0.62 up to
    /// 0.78 (inside the palm's end), 4 mm apart at their sides; with the
    /// arm's axis down its middle from 0.9 to the fingertips.
    fn hand(fingers: usize, r: Real) -> (Mesh, Segmentation) {
        let mut pieces = vec![cylinder(Vec3::new(0.0, 0.0, 0.75), 0.045, 0.15, 16, 64)];
        for k in 0..fingers {
            let dx = (k as Real - 0.5 * (fingers - 1) as Real) * (2.0 * r + 0.004);
            pieces.push(cylinder(Vec3::new(dx, 0.0, 0.62), r, 0.16, 12, 32));
        }
        let n = 57;
        let axis = PartAxis {
            name: PartName::LeftArm,
            points: (0..n)
                .map(|i| Vec3::new(0.0, 0.0, 0.9 - 0.28 * i as Real / (n - 1) as Real))
                .collect(),
            radii: vec![0.045; n],
            start: LandmarkKind::LeftArmpit,
            end: LandmarkKind::LeftHandTip,
        };
        (
            merge(&pieces),
            Segmentation::z_up(1.7, Vec::new(), vec![axis]),
        )
    }

    /// A digit's surface at the default tessellation.
    fn tessellated(d: &BodyDigit) -> Mesh {
        crate::surface::tessellate::tessellate_part(&d.part, &TessellationOptions::default())
            .unwrap()
    }

    /// The left hand's split and its digits, with default options: four.
    fn four_digits(cutter: &Cutter<'_>) -> (HandSplit, Vec<BodyDigit>) {
        let opts = ReconstructOptions::default();
        let split = split_hand(cutter, PartName::LeftArm, 0.0, &opts).unwrap();
        assert_eq!(split.digits.len(), 4);
        let mut warnings = Vec::new();
        let arm = PartName::LeftArm;
        let digits = build_digits(cutter, arm, &split, split.palm_end, &opts, &mut warnings);
        assert_eq!(digits.len(), 4, "{warnings:?}");
        (split, digits)
    }

    #[test]
    fn fingers_apart_are_digits_that_follow_them() {
        let (mesh, seg) = hand(4, 0.009);
        let (split, digits) = four_digits(&Cutter::new(BodyGeometry::Mesh(&mesh), &seg));
        // The palm ends a level (7 mm) before the fingers' first loops
        // (here inside it, where they start).
        let palm_end = 0.9 - 0.28 * split.palm_end;
        assert!(palm_end > 0.775 && palm_end < 0.79, "{palm_end}");
        let mut centres = Vec::new();
        for d in &digits {
            let m = tessellated(d);
            let c = m
                .positions
                .iter()
                .filter(|p| p.z > 0.64)
                .fold((Vec3::new(0.0, 0.0, 0.0), 0.0), |(a, n), &p| {
                    (a + p, n + 1.0)
                });
            let c = c.0 * (1.0 / c.1);
            // On its finger's side (9 mm from its line), from inside the
            // palm to the fingertip, which its dome reaches.
            for p in m.positions.iter().filter(|p| p.z > 0.635 && p.z < 0.76) {
                let off = Vec3::new(p.x - c.x, p.y - c.y, 0.0).norm();
                assert!((off - 0.009).abs() < 0.001, "{p:?} {off}");
            }
            let (lo, hi) = m
                .positions
                .iter()
                .fold((Real::MAX, Real::MIN), |(lo, hi), p| {
                    (lo.min(p.z), hi.max(p.z))
                });
            assert!((lo - 0.62).abs() < 0.003, "tip at {lo}");
            assert!(hi > palm_end, "{hi} starts below the palm's end {palm_end}");
            centres.push(c.x);
        }
        centres.sort_by(Real::total_cmp);
        for (k, x) in centres.iter().enumerate() {
            let want = (k as Real - 1.5) * 0.022;
            assert!((x - want).abs() < 0.001, "{x} {want}");
        }
    }

    #[test]
    fn a_sliver_beside_the_fingers_is_not_a_digit() {
        // A 2 mm strand hanging in front of the fingers, inside the palm
        // at its top (0.1 % of the palm's loop).
        let (mesh, seg) = hand(4, 0.009);
        let mesh = merge(&[
            mesh,
            cylinder(Vec3::new(0.0, 0.03, 0.64), 0.002, 0.14, 12, 16),
        ]);
        let cutter = Cutter::new(BodyGeometry::Mesh(&mesh), &seg);
        let split = split_of(&cutter).unwrap();
        assert_eq!(split.digits.len(), 4);
    }

    /// Points spread by area over `mesh`, about 1 mm apart.
    fn scan_of(mesh: &Mesh) -> PointCloud {
        PointCloud {
            positions: crate::spatial::distance::sample_surface(mesh, 120_000),
            normals: None,
        }
    }

    #[test]
    fn fingers_together_leave_a_mitten() {
        // The fingers as one block (as fingers pressed together cut).
        let (mesh, seg) = hand(1, 0.035);
        let cutter = Cutter::new(BodyGeometry::Mesh(&mesh), &seg);
        let why = split_of(&cutter).err().unwrap();
        assert!(why.contains("finger(s) apart"), "{why}");
        let cloud = scan_of(&mesh);
        let cutter = Cutter::new(BodyGeometry::Cloud(&cloud), &seg);
        let why = split_of(&cutter).err().unwrap();
        assert!(why.contains("finger(s) apart"), "{why}");
    }

    #[test]
    fn a_scan_s_fingers_apart_are_digits_to_their_tips() {
        // 4 mm apart: a slab image's closing (two cells of a spacing or
        // more each way) joins them; the points past each level do not.
        let (mesh, seg) = hand(4, 0.009);
        let cloud = scan_of(&mesh);
        let (_, digits) = four_digits(&Cutter::new(BodyGeometry::Cloud(&cloud), &seg));
        let mut centres = Vec::new();
        for d in &digits {
            let m = tessellated(d);
            let lo = m.positions.iter().map(|p| p.z).fold(Real::MAX, Real::min);
            assert!((lo - 0.62).abs() < 0.003, "tip at {lo}");
            let mid: Vec<&Point3> = m
                .positions
                .iter()
                .filter(|p| (p.z - 0.7).abs() < 0.01)
                .collect();
            centres.push(mid.iter().map(|p| p.x).sum::<Real>() / mid.len() as Real);
        }
        centres.sort_by(Real::total_cmp);
        for (k, x) in centres.iter().enumerate() {
            let want = (k as Real - 1.5) * 0.022;
            assert!((x - want).abs() < 0.002, "{x} {want}");
        }
    }
}
