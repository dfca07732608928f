//! The rims of a scan's holes: where a scanner saw nothing (the soles a
//! body stands on, the crown seen at grazing angles, the armpits), a model
//! closes the surface, and its distance to the nearest scan point measures
//! the hole's size, not the model's error.
//!
//! A scan point `q` lies on a **rim** when the scan points around it (within
//! a radius `R`, `q` excluded), projected into their own least-squares
//! plane through `q` (normal = the eigenvector of the smallest eigenvalue
//! of their covariance about `q`), leave an angular gap wider than
//! [`RIM_GAP`] (120°) about `q`. Inside a sampled surface the neighbours
//! surround `q`: at `R` = 4 point spacings about 50 of them, and for
//! `n` random directions the chance of a gap over a third of the circle is
//! about `n (2/3)^(n−1)`, 1e-7 (at 3 spacings, 28 neighbours, 5e-4). On a
//! hole's rim they lie on
//! one side (a gap near 180°), at a hole's corner more. Fewer than [`MIN_NEIGHBOURS`] neighbours (a stray point,
//! a hole's ragged edge) also count as a rim.
//!
//! The report (the reconstruction's `Report`) uses it for a point-cloud input:
//! a model sample farther than the coverage distance from every scan point
//! whose nearest scan point lies on a rim is *over a hole*, and the
//! observed-surface numbers leave it out (the plain numbers keep it).

use crate::geom::linalg::{scatter, symmetric_eigen3};
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::parallel::parallel_map;
use crate::spatial::point_grid::PointGrid;
use std::collections::HashMap;

/// The widest angular gap (radians) between neighbours about a point that
/// is not on a rim: 120°.
pub const RIM_GAP: Real = 2.0 * std::f64::consts::FRAC_PI_3;

/// Fewer neighbours than this within the radius: a rim.
pub const MIN_NEIGHBOURS: usize = 6;

/// The test radius in point spacings (see the module doc).
pub const RIM_RADIUS_SPACINGS: Real = 4.0;

/// True when `q` lies on the rim of a hole of the surface that its
/// `neighbours` (the scan points within the test radius of `q`, `q` itself
/// excluded or not: points at `q` are skipped) sample (see the module doc).
pub fn on_rim(q: Point3, neighbours: &[Point3]) -> bool {
    let offsets: Vec<_> = neighbours
        .iter()
        .map(|p| *p - q)
        .filter(|d| d.norm_squared() > 0.0)
        .collect();
    if offsets.len() < MIN_NEIGHBOURS {
        return true;
    }
    let (_, vectors) = symmetric_eigen3(scatter(&offsets, Vec3::ZERO));
    let (e1, e2) = (vectors[0], vectors[1]);
    let mut angles: Vec<Real> = offsets.iter().map(|d| d.dot(e2).atan2(d.dot(e1))).collect();
    angles.sort_by(Real::total_cmp);
    let n = angles.len();
    let widest = (0..n)
        .map(|i| {
            if i + 1 < n {
                angles[i + 1] - angles[i]
            } else {
                angles[0] + std::f64::consts::TAU - angles[i]
            }
        })
        .fold(0.0, Real::max);
    widest > RIM_GAP
}

/// Which of `samples` (a model's, at distances `d` from the cloud that
/// `grid` indexes) lie over a hole of the scan: farther than `far` from
/// every scan point, with the nearest scan point on a rim ([`on_rim`],
/// neighbours within `radius`). Samples within `far` are never over a
/// hole. The far samples are tested on the cores, each run remembering the
/// verdict of the nearest points it has met (neighbouring samples share
/// them).
pub fn over_holes(
    grid: &PointGrid<'_>,
    samples: &[Point3],
    d: &[Real],
    far: Real,
    radius: Real,
) -> Vec<bool> {
    let far_ones: Vec<usize> = (0..samples.len().min(d.len()))
        .filter(|&i| d[i] > far)
        .collect();
    let verdicts = parallel_map(&far_ones, 64, |run| {
        let mut seen: HashMap<[u64; 3], bool> = HashMap::new();
        run.iter()
            .map(|&i| {
                let Some(q) = grid.nearest_point(samples[i]) else {
                    return false;
                };
                *seen
                    .entry(q.to_array().map(Real::to_bits))
                    .or_insert_with(|| on_rim(q, &grid.within(q, radius)))
            })
            .collect()
    });
    let mut over = vec![false; samples.len()];
    for (&i, v) in far_ones.iter().zip(verdicts) {
        over[i] = v;
    }
    over
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::math::Vec3;
    use crate::geom::rng::Rng;

    /// The tilted plane's orthonormal axes `(a, b)` and normal.
    fn axes() -> (Vec3, Vec3, Vec3) {
        let (c, s) = (0.5f64.cos(), 0.5f64.sin());
        let (a, b) = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, c, s));
        (a, b, a.cross(b))
    }

    /// Points of a tilted plane patch `|u|, |v| ≤ 1` (spacing ~0.05, noise
    /// σ = 0.005) without the part `u > cut` (the hole).
    fn patch(cut: Real, rng: &mut Rng) -> Vec<Point3> {
        let (a, b, n) = axes();
        let mut out = Vec::new();
        for _ in 0..1600 {
            let (u, v) = (2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0);
            let noise = 0.005 * rng.gaussian();
            if u <= cut {
                out.push(a * u + b * v + n * noise);
            }
        }
        out
    }

    fn near(points: &[Point3], q: Point3, r: Real) -> Vec<Point3> {
        points
            .iter()
            .copied()
            .filter(|p| p.distance(q) <= r)
            .collect()
    }

    /// Inside a sampled patch no point is on a rim; along the edge of the
    /// half that was cut away every point is; a lone point is.
    #[test]
    fn rims_are_where_the_samples_stop() {
        let mut rng = Rng::new(7);
        let pts = patch(0.0, &mut rng);
        let (a, b, _) = axes();
        let r = 0.2; // 4 spacings
        let (mut inside, mut edge) = (0, 0);
        for q in &pts {
            let (u, v) = (q.dot(a), q.dot(b));
            // away from the patch's other edges
            if v.abs() > 0.6 || u < -0.6 {
                continue;
            }
            let rim = on_rim(*q, &near(&pts, *q, r));
            if u < -0.3 && u > -0.5 {
                assert!(!rim, "inside point {q:?} called a rim");
                inside += 1;
            }
            if u > -0.01 {
                assert!(rim, "edge point {q:?} not called a rim");
                edge += 1;
            }
        }
        assert!(inside > 50 && edge > 3, "{inside} {edge}");
        assert!(on_rim(
            Vec3::new(5.0, 5.0, 5.0),
            &near(&pts, Vec3::new(5.0, 5.0, 5.0), r)
        ));
    }

    /// Samples over the cut-away half of a patch, beyond `far`, are over a
    /// hole; samples off the sampled half's face by as much are not (the
    /// nearest point is inside the patch, not on its rim); near samples
    /// never are.
    #[test]
    fn samples_beyond_a_rim_are_over_the_hole() {
        let mut rng = Rng::new(9);
        let pts = patch(0.0, &mut rng);
        let (a, b, n) = axes();
        let grid = PointGrid::new(&pts, 0.1);
        let samples = [
            a * 0.5 + b * 0.1,             // over the hole, 0.5 from the rim
            a * -0.5 + b * 0.1 + n * 0.3,  // off the face by 0.3
            a * -0.5 + b * 0.1 + n * 0.01, // near
        ];
        let d: Vec<Real> = samples.iter().map(|s| grid.nearest(*s)).collect();
        assert_eq!(
            over_holes(&grid, &samples, &d, 0.1, 0.2),
            vec![true, false, false]
        );
    }

    /// A closed sphere sampled all over (spacing √(4π/4000) ≈ 0.056, radius
    /// 4 spacings, as the report uses) has no rim, curved as it is.
    #[test]
    fn a_closed_sphere_has_no_rim() {
        let mut rng = Rng::new(3);
        let pts: Vec<Point3> = (0..4000)
            .map(|_| {
                Vec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian())
                    .normalized()
                    .unwrap()
            })
            .collect();
        let rims = pts
            .iter()
            .step_by(10)
            .filter(|q| on_rim(**q, &near(&pts, **q, 0.22)))
            .count();
        assert_eq!(rims, 0);
    }
}
