//! The regions a close look tells apart, from a segmentation's landmarks:
//! the head is above the plane through the neck landmark normal to the
//! neck → head-top direction; a hand is past the plane through its wrist
//! normal to the wrist → hand-tip direction and within 1.5 × that distance
//! of the wrist; the feet are below the higher ankle along `up`; hands come
//! first, then feet, then head. The measurements compare the model with
//! its input region by region (`measure::regions`); the report counts each
//! region's design parameters.

use crate::anatomy::LandmarkKind;
use crate::geom::math::{Point3, Real, Vec3};
use crate::segment::Segmentation;

/// The regions a close look tells apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Region {
    Head,
    Hands,
    Feet,
    Rest,
}

impl Region {
    /// All regions, in report order.
    pub const ALL: [Region; 4] = [Region::Head, Region::Hands, Region::Feet, Region::Rest];

    /// The region's name in a table.
    pub fn name(self) -> &'static str {
        match self {
            Region::Head => "head",
            Region::Hands => "hands",
            Region::Feet => "feet",
            Region::Rest => "rest",
        }
    }
}

/// The planes that bound the regions (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Regions {
    /// Neck point and the unit direction to the head top.
    head: Option<(Point3, Vec3)>,
    /// Per hand: wrist, unit direction to the tip, reach (1.5 × distance).
    hands: Vec<(Point3, Vec3, Real)>,
    /// The higher ankle's height along `up`.
    feet: Option<Real>,
    up: Vec3,
}

impl Regions {
    /// The regions of a segmented body (a landmark not found: that region
    /// is empty).
    pub fn new(seg: &Segmentation) -> Regions {
        let at = |k: LandmarkKind| seg.landmark(k).map(|l| l.position);
        let towards = |from: Point3, to: Point3| (to - from).normalized().map(|d| (from, d));
        let head = at(LandmarkKind::Neck)
            .zip(at(LandmarkKind::HeadTop))
            .and_then(|(n, t)| towards(n, t));
        let hands = [
            (LandmarkKind::LeftWrist, LandmarkKind::LeftHandTip),
            (LandmarkKind::RightWrist, LandmarkKind::RightHandTip),
        ]
        .iter()
        .filter_map(|&(w, t)| {
            let (w, t) = (at(w)?, at(t)?);
            let (_, d) = towards(w, t)?;
            Some((w, d, 1.5 * w.distance(t)))
        })
        .collect();
        let up = seg.frame.up;
        let feet = [LandmarkKind::LeftAnkle, LandmarkKind::RightAnkle]
            .iter()
            .filter_map(|&k| at(k))
            .map(|p| p.dot(up))
            .reduce(Real::max);
        Regions {
            head,
            hands,
            feet,
            up,
        }
    }

    /// The region of a point.
    pub fn of(&self, p: Point3) -> Region {
        if self
            .hands
            .iter()
            .any(|&(w, d, reach)| (p - w).dot(d) > 0.0 && p.distance(w) < reach)
        {
            Region::Hands
        } else if self.feet.is_some_and(|h| p.dot(self.up) < h) {
            Region::Feet
        } else if self.head.is_some_and(|(n, d)| (p - n).dot(d) > 0.0) {
            Region::Head
        } else {
            Region::Rest
        }
    }
}
