//! The body's vocabulary shared by segmentation, reconstruction and
//! measurement: the input geometry, the body's frame, its landmarks and
//! its parts.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{Mesh, PointCloud};
use crate::geom::rigid::Rigid;
use std::fmt;

/// The geometry to segment: a surface or a cloud of scanned points.
#[derive(Clone, Copy, Debug)]
pub enum BodyGeometry<'a> {
    Mesh(&'a Mesh),
    Cloud(&'a PointCloud),
}

impl BodyGeometry<'_> {
    /// The vertices or points.
    pub fn positions(&self) -> &[Point3] {
        match self {
            BodyGeometry::Mesh(m) => &m.positions,
            BodyGeometry::Cloud(c) => &c.positions,
        }
    }
}

/// A mesh or a cloud held by value (a copy moved, ordered or cut down),
/// seen as a [`BodyGeometry`].
#[derive(Clone, Debug)]
pub(crate) enum OwnedGeometry {
    Mesh(Mesh),
    Cloud(PointCloud),
}

impl OwnedGeometry {
    pub(crate) fn geometry(&self) -> BodyGeometry<'_> {
        match self {
            OwnedGeometry::Mesh(m) => BodyGeometry::Mesh(m),
            OwnedGeometry::Cloud(c) => BodyGeometry::Cloud(c),
        }
    }
}

/// The body's own frame: orthonormal, right-handed (`left = up × front`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyFrame {
    pub up: Vec3,
    pub front: Vec3,
    pub left: Vec3,
    /// The point on the floor (the soles' plane) below the crotch.
    pub origin: Point3,
}

impl BodyFrame {
    /// The frame moved by `m`.
    pub fn moved(&self, m: &Rigid) -> BodyFrame {
        BodyFrame {
            up: m.vector(self.up),
            front: m.vector(self.front),
            left: m.vector(self.left),
            origin: m.point(self.origin),
        }
    }

    /// The motion into the body's own coordinates: the origin to zero,
    /// `left` to +x, `up` to +y, `front` to +z (`None` for a degenerate
    /// frame).
    pub fn into_own_axes(&self) -> Option<Rigid> {
        Rigid::into_axes(self.origin, self.left, self.up)
    }
}

/// The named places the segmentation finds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LandmarkKind {
    HeadTop,
    Neck,
    LeftArmpit,
    RightArmpit,
    Crotch,
    LeftWrist,
    RightWrist,
    LeftHandTip,
    RightHandTip,
    LeftAnkle,
    RightAnkle,
    LeftSole,
    RightSole,
    LeftHeel,
    RightHeel,
    LeftToe,
    RightToe,
    LeftShoulder,
    RightShoulder,
}

impl fmt::Display for LandmarkKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self, f)
    }
}

/// A landmark: where, how high, and how it was found.
#[derive(Clone, Debug, PartialEq)]
pub struct Landmark {
    pub kind: LandmarkKind,
    pub position: Point3,
    /// Height above the soles along `up`, as a fraction of `H`.
    pub height_fraction: Real,
    /// 0..1: how clear the evidence was (1: a graph junction or an end;
    /// for girth minima, the relative depth of the minimum).
    pub confidence: Real,
    /// How it was found, in words.
    pub how: &'static str,
}

/// The parts of a body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PartName {
    Torso,
    Head,
    LeftArm,
    RightArm,
    LeftLeg,
    RightLeg,
    LeftFoot,
    RightFoot,
}

impl PartName {
    /// Every part, in the order the segmentation reports them.
    pub const ALL: [PartName; 8] = [
        PartName::Torso,
        PartName::Head,
        PartName::LeftArm,
        PartName::RightArm,
        PartName::LeftLeg,
        PartName::RightLeg,
        PartName::LeftFoot,
        PartName::RightFoot,
    ];
}

impl fmt::Display for PartName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            PartName::Torso => "torso",
            PartName::Head => "head",
            PartName::LeftArm => "left arm",
            PartName::RightArm => "right arm",
            PartName::LeftLeg => "left leg",
            PartName::RightLeg => "right leg",
            PartName::LeftFoot => "left foot",
            PartName::RightFoot => "right foot",
        };
        f.write_str(s)
    }
}
