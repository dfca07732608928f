//! Joint centres estimated from a segmentation: where a skeleton's
//! shoulders, elbows, wrists, hips, knees and ankles lie inside the body.
//!
//! Wrists are the segmentation's own landmarks (the centres of the
//! narrowest cuts across the forearm). The narrowest cut of the leg lies
//! above the malleoli; the ankle joint is lower, where the foot begins:
//! walking down the shank's line from that cut in horizontal sections,
//! the first whose length along the foot exceeds the shank's by
//! `FOOT_BEGINS` (`ankle_joint`). A bent elbow or knee is where the
//! straight lines of its two segments cross (`bend_corner`): the
//! axis's smoothing cuts the corner, the lines do not. A straight limb
//! has no corner to find; its joint is placed by the segment lengths of
//! the standard anthropometric tables (Drillis and Contini 1966, as
//! fractions of the stature `H`: upper arm 0.186, forearm 0.146, thigh
//! 0.245, shank 0.246; trochanter height 0.530): the elbow by arc
//! length along the arm's axis, the knee at the shank's share of the
//! rise from the body's own ankle joint to the hip's height. The
//! shoulder is where the upper arm's line passes a socket placed from
//! the soles and the neck (`shoulder_joint`); the hip on the thigh's
//! axis line continued up to 0.04 `H` above the crotch, in the trunk's
//! coronal plane, then a little outward and back. Where the tables do
//! not say, the offsets are the means of the development corpus's rig
//! joints over its 40 bodies (docs/corpus.md, Joints; a fit on half the
//! bodies predicts the other half as well).

use crate::anatomy::{BodyGeometry, LandmarkKind, PartName};
use crate::geom::linalg::principal;
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::stats::median;
use crate::section::cloud::{CloudSlicer, ScanSectionOptions};
use crate::section::mesh::{MeshSlicer, SectionLoop, SectionOptions};
use crate::segment::{PartAxis, Segmentation};

/// A joint of the body's skeleton.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum JointName {
    LeftShoulder,
    RightShoulder,
    LeftElbow,
    RightElbow,
    LeftWrist,
    RightWrist,
    LeftHip,
    RightHip,
    LeftKnee,
    RightKnee,
    LeftAnkle,
    RightAnkle,
}

impl JointName {
    /// The snake-case name (`left_elbow`), as body-scan datasets spell it.
    pub fn as_str(self) -> &'static str {
        match self {
            JointName::LeftShoulder => "left_shoulder",
            JointName::RightShoulder => "right_shoulder",
            JointName::LeftElbow => "left_elbow",
            JointName::RightElbow => "right_elbow",
            JointName::LeftWrist => "left_wrist",
            JointName::RightWrist => "right_wrist",
            JointName::LeftHip => "left_hip",
            JointName::RightHip => "right_hip",
            JointName::LeftKnee => "left_knee",
            JointName::RightKnee => "right_knee",
            JointName::LeftAnkle => "left_ankle",
            JointName::RightAnkle => "right_ankle",
        }
    }
}

impl std::fmt::Display for JointName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Upper arm and forearm lengths as fractions of the stature.
const UPPER_ARM: Real = 0.186;
const FOREARM: Real = 0.146;
/// Thigh and shank lengths as fractions of the stature.
const THIGH: Real = 0.245;
const SHANK: Real = 0.246;
/// Hip joint centre above the crotch, as a fraction of the stature.
const HIP_ABOVE_CROTCH: Real = 0.04;
/// The femoral head lies this far (fractions of the stature) outward of
/// the thigh's line continued up and behind the trunk's coronal plane
/// (the rig joints of the development corpus: 0.0070 `H` (sd 0.0048)
/// and 0.0070 `H` (sd 0.0051) over its 40 bodies).
const HIP_OUTWARD: Real = 0.0070;
const HIP_BEHIND: Real = 0.0070;
/// The shoulder joint's standard socket: its height above the soles and
/// below the neck's narrowest cut, its offset outward from the neck's
/// centre and in front of it (fractions of the stature; the development
/// corpus's rig joints, means over its 40 bodies, sd 0.010, 0.010, 0.007
/// and 0.010 `H`: their height sits 0.02 `H` under the acromion of
/// Drillis and Contini, 1966, and their breadth 0.205 `H` inside its
/// biacromial 0.259 `H`, as a ball joint's centre does).
const SHOULDER_HEIGHT: Real = 0.797;
const SHOULDER_BELOW_NECK: Real = 0.070;
const SHOULDER_OUTWARD: Real = 0.1025;
const SHOULDER_FRONT: Real = -0.0064;
/// How far the shoulder joint moves from the upper arm's line toward
/// the socket: σ_line² / (σ_line² + σ_socket²), the line passing the
/// rig joints at 14 mm median, the socket 17-20 mm per axis.
const SOCKET_WEIGHT: Real = 0.35;
/// The upper arm's line is fitted over this much of the arm's axis from
/// its start, as a fraction of the stature (less than the upper arm).
const UPPER_ARM_LINE: Real = 0.08;
/// Greater trochanter (hip joint) height above the soles, as a fraction of
/// the stature.
const HIP_HEIGHT: Real = 0.530;
/// A limb segment's straight line is fitted over its axis from
/// `LINE_FROM` to `LINE_TO` (fractions of the stature) away from the
/// joint at its far end: the middle of a segment, clear of both joints.
const LINE_FROM: Real = 0.02;
const LINE_TO: Real = 0.10;
/// The span of the leg's axis below the crotch (fractions of the
/// stature) whose line is continued up to the hip: the thigh's lower
/// half, clear of the knee about 0.25 `H` down.
const THIGH_LINE: (Real, Real) = (0.10, 0.18);
/// The smallest bend (degrees) whose corner is located.
const MIN_BEND: Real = 25.0;
/// A horizontal section this many times longer along the foot than the
/// shank's has reached the foot (the ankle joint's level).
const FOOT_BEGINS: Real = 1.25;

/// Every joint the segmentation's parts give, in [`JointName`] order;
/// `body` is the segmented input (for the ankles' sections).
pub fn estimate_joints(body: BodyGeometry<'_>, seg: &Segmentation) -> Vec<(JointName, Point3)> {
    let mut out = Vec::new();
    let h = seg.height;
    let lm = |k: LandmarkKind| {
        seg.landmarks
            .iter()
            .find(|l| l.kind == k)
            .map(|l| l.position)
    };
    use JointName as J;
    use LandmarkKind as L;
    let arms = [
        (
            PartName::LeftArm,
            L::LeftWrist,
            [J::LeftShoulder, J::LeftElbow, J::LeftWrist],
        ),
        (
            PartName::RightArm,
            L::RightWrist,
            [J::RightShoulder, J::RightElbow, J::RightWrist],
        ),
    ];
    for (part, wrist_kind, names) in arms {
        let (Some(axis), Some(wrist)) = (seg.part(part), lm(wrist_kind)) else {
            continue;
        };
        let (Some(start), Some((_, tangent))) =
            (axis.points.first().copied(), axis.point_and_tangent(0.0))
        else {
            continue;
        };
        let outward = if part == PartName::LeftArm {
            seg.frame.left
        } else {
            -seg.frame.left
        };
        // Without a torso: the humeral head about an arm radius inside
        // the shoulder from where the arm's cuts stop being separate.
        let shoulder = shoulder_joint(seg, axis, outward)
            .unwrap_or_else(|| start - tangent * axis.radii.first().copied().unwrap_or(0.0));
        out.push((names[0], shoulder));
        let wrist_at = arc_of_nearest(axis, wrist);
        let corner = bend_corner(
            axis,
            (LINE_FROM * h, LINE_TO * h),
            (wrist_at - LINE_TO * h, wrist_at - LINE_FROM * h),
        );
        let t = wrist_at * UPPER_ARM / (UPPER_ARM + FOREARM);
        if let Some(e) = corner.or_else(|| point_at_arc(axis, t)) {
            out.push((names[1], e));
        }
        out.push((names[2], wrist));
    }
    let legs = [
        (
            PartName::LeftLeg,
            PartName::LeftFoot,
            L::LeftAnkle,
            [J::LeftHip, J::LeftKnee, J::LeftAnkle],
        ),
        (
            PartName::RightLeg,
            PartName::RightFoot,
            L::RightAnkle,
            [J::RightHip, J::RightKnee, J::RightAnkle],
        ),
    ];
    let sections = HorizontalSections::new(body, seg);
    for (part, foot, ankle_kind, names) in legs {
        let (Some(axis), Some(narrowest)) = (seg.part(part), lm(ankle_kind)) else {
            continue;
        };
        let along_foot = seg
            .part(foot)
            .and_then(|f| Some(*f.points.last()? - *f.points.first()?))
            .unwrap_or(seg.frame.front);
        let ankle = sections
            .as_ref()
            .and_then(|s| ankle_joint(s, seg, axis, narrowest, along_foot))
            .unwrap_or(narrowest);
        // The thigh's axis line over its lower half below the crotch
        // (where the legs' loops are apart and the inner thighs and the
        // buttock's fold no longer pull their centroids), continued up to
        // the hip joint's height, in the trunk's coronal plane
        // ([`in_coronal_plane`]).
        let (Some((p1, along, _)), Some(crotch)) = (
            axis_line(axis, THIGH_LINE.0 * h, THIGH_LINE.1 * h),
            lm(L::Crotch),
        ) else {
            continue;
        };
        let up = seg.frame.up;
        let dir = -along;
        if dir.dot(up) <= 0.1 {
            continue;
        }
        let rise = (crotch.dot(up) + HIP_ABOVE_CROTCH * h - p1.dot(up)) / dir.dot(up);
        let outward = if part == PartName::LeftLeg {
            seg.frame.left
        } else {
            -seg.frame.left
        };
        let hip = in_coronal_plane(seg, p1 + dir * rise)
            + (outward * HIP_OUTWARD - seg.frame.front * HIP_BEHIND) * h;
        out.push((names[0], hip));
        // The ankle joint lies on the shank's line below the axis's end.
        let ankle_at = arc_of_nearest(axis, narrowest) + narrowest.distance(ankle);
        // A bent knee where the thigh's and the shank's lines cross; a
        // straight one where the shank's share of the rise from the ankle
        // to the hip's standard height is reached along the axis.
        let corner = bend_corner(
            axis,
            (0.06 * h, 0.16 * h),
            (ankle_at - LINE_TO * h, ankle_at - LINE_FROM * h),
        );
        let hip_level = seg.frame.origin.dot(up) + HIP_HEIGHT * h;
        let level = ankle.dot(up) + (hip_level - ankle.dot(up)) * SHANK / (THIGH + SHANK);
        let knee = corner.or_else(|| axis.point_at_level(up, level));
        // Hip to knee is THIGH of THIGH + SHANK; the axis starts
        // HIP_ABOVE_CROTCH below the hip.
        let total = ankle_at + HIP_ABOVE_CROTCH * h;
        let t = (total * THIGH / (THIGH + SHANK) - HIP_ABOVE_CROTCH * h).max(0.0);
        if let Some(k) = knee.or_else(|| point_at_arc(axis, t)) {
            out.push((names[1], k));
        }
        out.push((names[2], ankle));
    }
    out.sort_by_key(|(n, _)| *n);
    out
}

/// The shoulder joint (the humeral head's centre): near the line of the
/// upper arm (the arm's axis over its first [`UPPER_ARM_LINE`] `H`), at
/// the socket's place along it. The socket lies [`SHOULDER_OUTWARD`] `H`
/// out from the neck's centre and [`SHOULDER_FRONT`] `H` in front of it,
/// at the mean of two heights: [`SHOULDER_HEIGHT`] `H` above the soles
/// and [`SHOULDER_BELOW_NECK`] `H` below the neck (the trunk's axis
/// stands in for a neck not found). The point of the line nearest the
/// socket then moves [`SOCKET_WEIGHT`] of the way to it: the line
/// follows the arm in any pose but says nothing of where along it the
/// joint is; the socket says both, less sharply. `outward` is the body's
/// side of this arm. `None` without a trunk or an upper arm to fit.
fn shoulder_joint(seg: &Segmentation, axis: &PartAxis, outward: Vec3) -> Option<Point3> {
    let (up, front, h) = (seg.frame.up, seg.frame.front, seg.height);
    let (on_line, dir, _) = axis_line(axis, 0.0, UPPER_ARM_LINE * h)?;
    let from_soles = seg.frame.origin.dot(up) + SHOULDER_HEIGHT * h;
    let neck = seg.landmark(LandmarkKind::Neck).map(|l| l.position);
    let (centre, level) = match neck {
        Some(n) => (n, 0.5 * (from_soles + n.dot(up) - SHOULDER_BELOW_NECK * h)),
        None => (trunk_at_level(seg, from_soles)?, from_soles),
    };
    let socket = centre
        + up * (level - centre.dot(up))
        + outward * (SHOULDER_OUTWARD * h)
        + front * (SHOULDER_FRONT * h);
    let nearest = on_line + dir * (socket - on_line).dot(dir);
    Some(nearest + (socket - nearest) * SOCKET_WEIGHT)
}

/// `p` moved along the body's front onto the coronal plane through the
/// trunk's axis at its height: the acetabula lie about mid-depth in the
/// pelvis, wherever the thighs point. `p` itself without a trunk.
fn in_coronal_plane(seg: &Segmentation, p: Point3) -> Point3 {
    let front = seg.frame.front;
    trunk_at_level(seg, p.dot(seg.frame.up)).map_or(p, |c| p + front * (c - p).dot(front))
}

/// The trunk's axis point nearest in height to `level`; `None` without a
/// trunk.
fn trunk_at_level(seg: &Segmentation, level: Real) -> Option<Point3> {
    let up = seg.frame.up;
    let torso = seg.part(PartName::Torso)?;
    torso
        .points
        .iter()
        .min_by(|a, b| {
            (a.dot(up) - level)
                .abs()
                .total_cmp(&(b.dot(up) - level).abs())
        })
        .copied()
}

/// The straight line through the axis points at arc lengths `from..=to`
/// (their centroid and principal direction, pointing along the axis)
/// and the median radius there. `None` for fewer than three points.
fn axis_line(axis: &PartAxis, from: Real, to: Real) -> Option<(Point3, Vec3, Real)> {
    let mut acc = 0.0;
    let mut picked = Vec::new();
    let mut radii = Vec::new();
    for (i, p) in axis.points.iter().enumerate() {
        if i > 0 {
            acc += p.distance(axis.points[i - 1]);
        }
        if (from..=to).contains(&acc) {
            picked.push(*p);
            radii.extend(axis.radii.get(i).copied());
        }
    }
    if picked.len() < 3 {
        return None;
    }
    let (c, _, vectors) = principal(&picked);
    let mut dir = vectors[0].normalized()?;
    if dir.dot(picked[picked.len() - 1] - picked[0]) < 0.0 {
        dir = -dir;
    }
    Some((c, dir, median(&mut radii).unwrap_or(0.0)))
}

/// Horizontal sections of the input.
enum HorizontalSections<'a> {
    Mesh(MeshSlicer<'a>),
    Cloud(CloudSlicer<'a>, ScanSectionOptions),
}

impl<'a> HorizontalSections<'a> {
    fn new(body: BodyGeometry<'a>, seg: &Segmentation) -> Option<HorizontalSections<'a>> {
        let up = seg.frame.up;
        Some(match body {
            BodyGeometry::Mesh(m) => {
                HorizontalSections::Mesh(MeshSlicer::new(m, up, &SectionOptions::default()).ok()?)
            }
            BodyGeometry::Cloud(c) => HorizontalSections::Cloud(
                CloudSlicer::new(c, up).ok()?,
                ScanSectionOptions {
                    half_thickness: seg.point_spacing,
                    cell_size: seg.point_spacing,
                    reference: Some(seg.frame.front),
                    ..ScanSectionOptions::default()
                },
            ),
        })
    }

    /// The loops at `offset` along up.
    fn loops(&self, offset: Real) -> Vec<SectionLoop> {
        match self {
            HorizontalSections::Mesh(s) => {
                s.section_at(offset).map(|s| s.loops).unwrap_or_default()
            }
            HorizontalSections::Cloud(s, o) => s
                .section_at(offset, o)
                .map(|s| s.loops.into_iter().map(|l| l.outline).collect())
                .unwrap_or_default(),
        }
    }
}

/// The ankle joint below the leg's narrowest cut `narrowest` (the end of
/// its `axis`): on the shank's line (the axis's last 0.08 `H`), in
/// horizontal sections every 0.005 `H` downward, the first loop around
/// the line whose length along `along_foot` is [`FOOT_BEGINS`] times the
/// shank's (the median over the 0.03 `H` above the narrowest cut). `None`
/// when the sections do not show it.
fn ankle_joint(
    sections: &HorizontalSections<'_>,
    seg: &Segmentation,
    axis: &PartAxis,
    narrowest: Point3,
    along_foot: Vec3,
) -> Option<Point3> {
    let (up, h) = (seg.frame.up, seg.height);
    let foot = (along_foot - up * along_foot.dot(up)).normalized()?;
    let total = axis.length();
    let upper = point_at_arc(axis, total - 0.08 * h)?;
    let shank = (upper - narrowest)
        .normalized()
        .filter(|d| d.dot(up) > 0.5)?;
    let floor = seg.frame.origin.dot(up);
    // The shank's line at height `level` along up.
    let on_line = |level: Real| narrowest + shank * ((level - narrowest.dot(up)) / shank.dot(up));
    let length_at = |level: Real| -> Option<Real> {
        let c = on_line(level);
        let loops = sections.loops(level);
        let near = loops
            .iter()
            .min_by(|a, b| a.centroid.distance(c).total_cmp(&b.centroid.distance(c)))?;
        let (lo, hi) = near
            .points
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.dot(foot)), hi.max(p.dot(foot)))
            });
        (hi > lo && near.centroid.distance(c) < 0.05 * h).then_some(hi - lo)
    };
    let top = narrowest.dot(up);
    let mut above: Vec<Real> = (0..=6)
        .filter_map(|k| length_at(top + 0.005 * h * k as Real))
        .collect();
    if above.len() < 3 {
        return None;
    }
    let shank_length = median(&mut above)?;
    let mut level = top - 0.005 * h;
    while level > floor + 0.01 * h {
        if length_at(level)? >= FOOT_BEGINS * shank_length {
            return Some(on_line(level));
        }
        level -= 0.005 * h;
    }
    None
}

/// Where a bent limb's two segments meet: the crossing (the midpoint of
/// the closest approach) of the straight lines through its axis at arc
/// lengths `upper` and `lower`, when they bend by at least [`MIN_BEND`]
/// and pass within the limb's radius of each other. A corner cut by the
/// axis's smoothing is restored; a straighter limb has no well-posed
/// crossing (it moves by `r / tan θ` for an `r` of noise), so `None`.
fn bend_corner(axis: &PartAxis, upper: (Real, Real), lower: (Real, Real)) -> Option<Point3> {
    let (p1, d1, r1) = axis_line(axis, upper.0, upper.1)?;
    let (p2, d2, _) = axis_line(axis, lower.0, lower.1)?;
    let cos = d1.dot(d2);
    if cos > MIN_BEND.to_radians().cos() {
        return None;
    }
    // Closest points p1 + d1 s, p2 + d2 t of the two lines (unit d1, d2).
    let w = p1 - p2;
    let den = 1.0 - cos * cos;
    let s = (cos * d2.dot(w) - d1.dot(w)) / den;
    let t = (d2.dot(w) - cos * d1.dot(w)) / den;
    let (a, b) = (p1 + d1 * s, p2 + d2 * t);
    (a.distance(b) <= r1).then_some((a + b) * 0.5)
}

/// The arc length along `axis` of its point nearest to `p`.
fn arc_of_nearest(axis: &PartAxis, p: Point3) -> Real {
    let (mut best, mut best_at, mut acc) = (Real::INFINITY, 0.0, 0.0);
    for w in axis.points.windows(2) {
        let d = w[1] - w[0];
        let len = d.norm();
        let u = if len > 0.0 {
            ((p - w[0]).dot(d) / (len * len)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dist = (w[0] + d * u).distance(p);
        if dist < best {
            (best, best_at) = (dist, acc + u * len);
        }
        acc += len;
    }
    best_at
}

/// The point at arc length `s` along `axis` (clamped to its ends).
fn point_at_arc(axis: &PartAxis, s: Real) -> Option<Point3> {
    let total = axis.length();
    if !(total > 0.0) {
        return axis.points.first().copied();
    }
    axis.point_and_tangent(s / total).map(|(p, _)| p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::math::Vec3;

    fn axis(points: Vec<Point3>) -> PartAxis {
        let n = points.len();
        PartAxis {
            name: PartName::LeftArm,
            points,
            radii: vec![0.04; n],
            start: LandmarkKind::LeftShoulder,
            end: LandmarkKind::LeftHandTip,
        }
    }

    /// An axis along `a` to `corner`, then along `b`, sampled every
    /// `step`, its corner cut by a chord between the points `cut` away.
    fn bent(corner: Point3, a: Vec3, b: Vec3, cut: Real, step: Real) -> PartAxis {
        let n = (1.0 / step) as usize;
        let mut points: Vec<Point3> = (0..=n)
            .map(|i| corner - a * (1.0 - i as Real * step))
            .filter(|p| p.distance(corner) >= cut)
            .collect();
        points.extend(
            (1..=n)
                .map(|i| corner + b * (i as Real * step))
                .filter(|p| p.distance(corner) >= cut),
        );
        axis(points)
    }

    #[test]
    fn a_bent_limb_s_cut_corner_is_restored() {
        let corner = Vec3::new(0.3, -0.2, 1.1);
        let a = Vec3::new(1.0, 0.0, 0.0);
        for deg in [30.0_f64, 60.0, 90.0, 120.0] {
            let (s, c) = deg.to_radians().sin_cos();
            let b = Vec3::new(c, s * 0.6, s * 0.8);
            let limb = bent(corner, a, b, 0.1, 0.01);
            let k = bend_corner(&limb, (0.1, 0.6), (1.2, 1.7)).unwrap();
            assert!(k.distance(corner) < 1e-9, "{deg}: {k:?}");
        }
    }

    #[test]
    fn a_straight_or_skew_limb_has_no_corner() {
        let corner = Vec3::new(0.0, 0.0, 1.0);
        let a = Vec3::new(0.0, 0.0, -1.0);
        let (s, c) = 10.0_f64.to_radians().sin_cos();
        let slight = bent(corner, a, Vec3::new(s, 0.0, -c), 0.0, 0.01);
        assert!(bend_corner(&slight, (0.1, 0.6), (1.2, 1.7)).is_none());
        // Two lines bent by 90° but passing 0.5 apart (radius 0.04).
        let mut points: Vec<Point3> = (0..=50)
            .map(|i| Vec3::new(i as Real * 0.02, 0.0, 0.0))
            .collect();
        points.extend((1..=50).map(|i| Vec3::new(1.0, i as Real * 0.02, 0.5)));
        assert!(bend_corner(&axis(points), (0.1, 0.6), (1.5, 2.0)).is_none());
    }

    #[test]
    fn the_level_is_found_along_a_slanted_axis() {
        let a = axis(vec![
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.2, 0.0, 0.5),
            Vec3::new(0.2, 0.1, 0.0),
        ]);
        let up = Vec3::new(0.0, 0.0, 1.0);
        let p = a.point_at_level(up, 0.75).unwrap();
        assert!(p.distance(Vec3::new(0.1, 0.0, 0.75)) < 1e-12, "{p:?}");
        let p = a.point_at_level(up, 0.25).unwrap();
        assert!(p.distance(Vec3::new(0.2, 0.05, 0.25)) < 1e-12, "{p:?}");
        assert!(a.point_at_level(up, 1.5).is_none());
    }

    /// A z-up trunk from 0.9 to 1.4 and its neck landmark.
    fn trunk(h: Real, neck: Point3) -> Segmentation {
        Segmentation::z_up(
            h,
            vec![crate::anatomy::Landmark {
                kind: LandmarkKind::Neck,
                position: neck,
                height_fraction: neck.z / h,
                confidence: 1.0,
                how: "test",
            }],
            vec![PartAxis {
                name: PartName::Torso,
                points: (0..=20)
                    .map(|i| Vec3::new(0.0, 0.0, 0.9 + 0.025 * i as Real))
                    .collect(),
                radii: vec![0.15; 21],
                start: LandmarkKind::Crotch,
                end: LandmarkKind::Neck,
            }],
        )
    }

    #[test]
    fn a_shoulder_lies_between_the_arm_s_line_and_the_socket() {
        let h = 1.8;
        let neck = Vec3::new(0.01, 0.02, 1.55);
        let seg = trunk(h, neck);
        let level = 0.5 * (SHOULDER_HEIGHT * h + neck.z - SHOULDER_BELOW_NECK * h);
        let socket = Vec3::new(
            neck.x + SHOULDER_OUTWARD * h,
            neck.y - SHOULDER_FRONT * h,
            level,
        );
        // An arm held out level, 2 cm in front of the socket and 3 cm
        // above it: along its line at the socket's lateral offset, then
        // SOCKET_WEIGHT of the way to the socket.
        let arm = axis(
            (0..=60)
                .map(|i| Vec3::new(0.05 + 0.01 * i as Real, socket.y - 0.02, level + 0.03))
                .collect(),
        );
        let s = shoulder_joint(&seg, &arm, seg.frame.left).unwrap();
        let on_line = Vec3::new(socket.x, socket.y - 0.02, level + 0.03);
        let want = on_line + (socket - on_line) * SOCKET_WEIGHT;
        assert!(s.distance(want) < 1e-9, "{s:?} {want:?}");
        // The same arm hanging down through the socket: the socket.
        let hanging = axis(
            (0..=60)
                .map(|i| Vec3::new(socket.x, socket.y, level + 0.1 - 0.01 * i as Real))
                .collect(),
        );
        let s = shoulder_joint(&seg, &hanging, seg.frame.left).unwrap();
        assert!(s.distance(socket) < 1e-9, "{s:?} {socket:?}");
        // The right arm mirrors it.
        let right = axis(
            (0..=60)
                .map(|i| {
                    Vec3::new(
                        2.0 * neck.x - socket.x,
                        socket.y,
                        level + 0.1 - 0.01 * i as Real,
                    )
                })
                .collect(),
        );
        let s = shoulder_joint(&seg, &right, -seg.frame.left).unwrap();
        let want = Vec3::new(2.0 * neck.x - socket.x, socket.y, level);
        assert!(s.distance(want) < 1e-9, "{s:?} {want:?}");
        // A hip in front of the trunk's axis moves back onto its plane,
        // keeping its height and side.
        let hip = in_coronal_plane(&seg, Vec3::new(0.1, -0.07, 0.95));
        assert!(hip.distance(Vec3::new(0.1, 0.0, 0.95)) < 1e-12, "{hip:?}");
    }

    #[test]
    fn arc_positions_follow_a_bent_axis() {
        let a = axis(vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ]);
        assert!((arc_of_nearest(&a, Vec3::new(1.2, 0.5, 0.0)) - 1.5).abs() < 1e-12);
        let p = point_at_arc(&a, 1.25).unwrap();
        assert!(p.distance(Vec3::new(1.0, 0.25, 0.0)) < 1e-12, "{p:?}");
        assert!(
            point_at_arc(&a, 9.0)
                .unwrap()
                .distance(Vec3::new(1.0, 1.0, 0.0))
                < 1e-12
        );
    }
}
