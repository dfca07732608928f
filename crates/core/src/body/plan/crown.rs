//! A head whose crown the input lacks: scanners that see a body from a
//! ring of viewpoints often miss the top of the head, and the data ends
//! in an open rim. The crown is then estimated from the head's own shape
//! (its sections above the widest, taken as half an ellipsoid), not left
//! flat at the rim.

use super::*;

/// The depth of the input's top band that tells a rim from a crown, as a
/// fraction of the head's largest mean radius `R` (deep enough to hold a
/// whole rim where the up axis leans a little).
const TOP_BAND: Real = 0.25;
/// A top band with no points (but 1 %) within this distance (× `R`) of
/// its centroid, across the up axis, is a rim: a crown's band has points
/// near its middle, even a scanner's sparse one (under `0.35 R` on the
/// corpus scans, `0.53 R` on its one open rim).
const OPEN_TOP: Real = 0.45;
/// Sections within this distance (× `R`) below the rim see only part of
/// it and are dropped.
const RIM_SECTIONS: Real = 0.25;
/// The crown rises at most this far (× `R`) above the widest section.
const MAX_CROWN: Real = 2.0;
/// The head's points: above the widest cut, within this distance (× `R`)
/// of its centre across `up`.
const HEAD_REACH: Real = 1.5;
/// Points the top band needs to be judged.
const MIN_TOP_POINTS: usize = 8;

/// An estimated crown: keep the first `keep` cuts and close the head with
/// a dome to `tip`, `rise` above the input's highest point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::body) struct Crown {
    pub(in crate::body) keep: usize,
    pub(in crate::body) tip: Point3,
    pub(in crate::body) rise: Real,
    /// The mean distance of the top band's points from their centroid.
    pub(in crate::body) rim_radius: Real,
}

/// The crown of a head cut across `up` into `cuts` (neck to top), when the
/// input `points` end in an open rim; `None` when they close over the top
/// (or a hand raised above the head is the highest thing near it).
pub(in crate::body) fn unseen_crown(cuts: &[Cut], points: &[Point3], up: Vec3) -> Option<Crown> {
    let (widest, r_max) = cuts
        .iter()
        .enumerate()
        .map(|(i, c)| (i, mean_radius(c.area)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    if !(r_max > 0.0) {
        return None;
    }
    // Across the widest cut's centre: the last cuts may see part of a rim.
    let centre = cuts[widest].fit.curve.frame.origin;
    let level = |p: Point3| p.dot(up);
    let lateral = |p: Point3| {
        let d = p - centre;
        (d - up * d.dot(up)).norm()
    };
    let s_w = level(centre);
    let head: Vec<Point3> = points
        .iter()
        .copied()
        .filter(|&p| level(p) > s_w && lateral(p) <= HEAD_REACH * r_max)
        .collect();
    let top = head
        .iter()
        .map(|&p| level(p))
        .fold(Real::NEG_INFINITY, Real::max);
    let band: Vec<Point3> = head
        .iter()
        .copied()
        .filter(|&p| level(p) >= top - TOP_BAND * r_max)
        .collect();
    if band.len() < MIN_TOP_POINTS {
        return None;
    }
    let (hole, rim_radius) = hollow(&band, up);
    if hole < OPEN_TOP * r_max {
        return None;
    }
    // The sections through the rim's band see part of a ring.
    let keep = cuts
        .iter()
        .rposition(|c| level(c.fit.curve.frame.origin) < top - RIM_SECTIONS * r_max)?
        + 1;
    if keep < 4 {
        return None;
    }
    let b = half_height(&cuts[..keep], widest, r_max, up)
        .unwrap_or(r_max)
        .min(MAX_CROWN * r_max)
        .max(top - s_w);
    let base = cuts[keep - 1].fit.curve.frame.origin;
    let tip = base + up * (s_w + b - level(base));
    Some(Crown {
        keep,
        tip,
        rise: s_w + b - top,
        rim_radius,
    })
}

/// The empty middle of `points` across `up` (the distance from their
/// centroid within which 1 % of them lie) and their mean distance from it.
fn hollow(points: &[Point3], up: Vec3) -> (Real, Real) {
    let n = points.len() as Real;
    let c = points.iter().fold(Vec3::ZERO, |a, &p| a + p) / n;
    let mut d: Vec<Real> = points
        .iter()
        .map(|&p| {
            let d = p - c;
            (d - up * d.dot(up)).norm()
        })
        .collect();
    let mean = d.iter().sum::<Real>() / n;
    let hole = nth_smallest(&mut d, (points.len() / 100).max(2)).unwrap_or(0.0);
    (hole, mean)
}

/// The half-height `b` above the widest cut of the half ellipsoid
/// `r² = R²(1 − (s − s_w)²/b²)` through the cuts above it (least squares in
/// `b²`); `None` without a cut narrower than `R` above the widest.
fn half_height(cuts: &[Cut], widest: usize, r_max: Real, up: Vec3) -> Option<Real> {
    let s_w = cuts.get(widest)?.fit.curve.frame.origin.dot(up);
    let (mut xy, mut xx) = (0.0, 0.0);
    for c in &cuts[widest + 1..] {
        let x = 1.0 - (mean_radius(c.area) / r_max).powi(2);
        let y = (c.fit.curve.frame.origin.dot(up) - s_w).powi(2);
        if x > 0.0 && y > 0.0 {
            xy += x * y;
            xx += x * x;
        }
    }
    (xx > 0.0).then(|| (xy / xx).sqrt())
}
