//! Joint centres estimated from a segmentation: where a skeleton's
//! shoulders, elbows, wrists, hips, knees and ankles lie inside the body.
//!
//! Wrists are the segmentation's own landmarks (the centres of the
//! narrowest cuts across the forearm), the shoulder the start of the arm's
//! axis (where its cuts merge with the trunk). The narrowest cut of the
//! leg lies above the malleoli; the ankle joint is lower, where the foot
//! begins: walking down the shank's line from that cut in horizontal
//! sections, the first whose length along the foot exceeds the shank's
//! by [`FOOT_BEGINS`] ([`ankle_joint`]). Elbow, hip and knee have no
//! girth minimum to find; they are placed on the limbs' axes by the
//! segment lengths of the standard anthropometric tables (Drillis and
//! Contini 1966, as fractions of the stature `H`): upper arm 0.186, forearm
//! 0.146, thigh 0.245, shank 0.246, and the hip joint 0.04 `H` above the
//! crotch (trochanter 0.53 `H`, crotch about 0.48 `H`) on the line of the
//! thigh's axis. Arc length along the axis follows a bent
//! limb, so the estimates do not assume a pose.

use crate::anatomy::{BodyGeometry, LandmarkKind, PartName};
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
        // The humeral head lies about an arm radius inside the shoulder
        // from where the arm's cuts stop being separate.
        let r = axis.radii.first().copied().unwrap_or(0.0);
        out.push((names[0], start - tangent * r));
        let wrist_at = arc_of_nearest(axis, wrist);
        let t = wrist_at * UPPER_ARM / (UPPER_ARM + FOREARM);
        if let Some(e) = point_at_arc(axis, t) {
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
        // The thigh's axis below the crotch (where the legs' loops are
        // apart), continued up to the hip joint's height.
        let (Some(p1), Some(p2), Some(crotch)) = (
            point_at_arc(axis, 0.06 * h),
            point_at_arc(axis, 0.16 * h),
            lm(L::Crotch),
        ) else {
            continue;
        };
        let up = seg.frame.up;
        let Some(dir) = (p1 - p2).normalized().filter(|d| d.dot(up) > 0.1) else {
            continue;
        };
        let rise = (crotch.dot(up) + HIP_ABOVE_CROTCH * h - p1.dot(up)) / dir.dot(up);
        out.push((names[0], p1 + dir * rise));
        // The ankle joint lies on the shank's line below the axis's end.
        let ankle_at = arc_of_nearest(axis, narrowest) + narrowest.distance(ankle);
        // Hip to knee is THIGH of THIGH + SHANK; the axis starts
        // HIP_ABOVE_CROTCH below the hip.
        let total = ankle_at + HIP_ABOVE_CROTCH * h;
        let t = (total * THIGH / (THIGH + SHANK) - HIP_ABOVE_CROTCH * h).max(0.0);
        if let Some(k) = point_at_arc(axis, t) {
            out.push((names[1], k));
        }
        out.push((names[2], ankle));
    }
    out.sort_by_key(|(n, _)| *n);
    out
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
