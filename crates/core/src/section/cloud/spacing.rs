//! The point spacing of a cloud (see the module doc of [`super`], 1).

use crate::geom::math::{Point3, Real};
use crate::geom::stats::median;

/// How many nearest neighbours [`estimate_spacing`] looks at.
const NEIGHBOURS: usize = 8;

/// A jump between the median distances to the k-th and the (k+1)-th
/// nearest neighbour larger than this says the points come in clusters of
/// k + 1 (two copies of a scan merged): on a uniform random sampling the
/// largest such ratio is 1.56 (k = 1), on the shared and corpus scans
/// at most 1.48.
const CLUSTER_JUMP: Real = 2.0;

/// Twice the median nearest-neighbour distance of up to 1000 evenly
/// chosen points (a sorted sweep along the height axis: neighbours are
/// searched outward in height until the height gap exceeds the 8th best
/// distance, at most 16384 steps each way). When the points come in
/// clusters of k + 1 (see [`CLUSTER_JUMP`]; two copies of a scan merged,
/// one jittered by less than the spacing), the middle of the nearest other
/// cluster's distances stands for the nearest neighbour: the cloud keeps
/// its spacing instead of taking the jitter's.
pub(super) fn estimate_spacing(points: &[Point3], order: &[u32], heights: &[Real]) -> Option<Real> {
    let n = order.len();
    if n < 2 {
        return None;
    }
    let samples = n.min(1000);
    // Each sample's nearest distances on its own, over the cores (in
    // order).
    let ss: Vec<usize> = (0..samples).collect();
    let near: Vec<Vec<Real>> = crate::geom::parallel::parallel_map(&ss, 64, |run| {
        run.iter()
            .map(|&s| nearest_in_sweep(points, order, heights, s * n / samples))
            .filter(|d| !d.is_empty())
            .collect()
    });
    let kth = |k: usize| {
        median(
            &mut near
                .iter()
                .filter_map(|d| d.get(k).copied())
                .collect::<Vec<_>>(),
        )
    };
    let medians: Vec<Real> = (0..NEIGHBOURS).map_while(kth).collect();
    // The last jump: the twins' own distances can jump too.
    let jump = (1..medians.len()).rfind(|&k| medians[k] > CLUSTER_JUMP * medians[k - 1]);
    // Clusters of k + 1 points: a point's k twins come first, then the
    // k + 1 points of the nearest other cluster.
    let first = match jump {
        None => medians.first().copied()?,
        Some(k) if 3 * k / 2 + 1 < medians.len() => {
            (medians[3 * k / 2] + medians[(3 * k).div_ceil(2)]) / 2.0
        }
        Some(k) => medians[k],
    };
    (first > 0.0).then_some(2.0 * first)
}

/// The distances from the point of sorted rank `i` to its nearest
/// [`NEIGHBOURS`] other points (of a different position) found by
/// [`estimate_spacing`]'s sweep, ascending; fewer when there are fewer.
fn nearest_in_sweep(points: &[Point3], order: &[u32], heights: &[Real], i: usize) -> Vec<Real> {
    let n = order.len();
    let p = points[order[i] as usize];
    // The best squared distances so far, ascending; `reach` is the root of
    // the last one once there are NEIGHBOURS of them.
    let mut best = [Real::INFINITY; NEIGHBOURS];
    let mut reach = Real::INFINITY;
    for dir in [-1isize, 1] {
        let mut j = i as isize + dir;
        let mut steps = 0;
        while j >= 0 && (j as usize) < n && steps < 16384 {
            let dh = (heights[j as usize] - heights[i]).abs();
            if dh >= reach {
                break;
            }
            let q = points[order[j as usize] as usize];
            let d2 = (p - q).norm_squared();
            if d2 > 0.0 && d2 < best[NEIGHBOURS - 1] {
                let mut at = NEIGHBOURS - 1;
                while at > 0 && best[at - 1] > d2 {
                    best[at] = best[at - 1];
                    at -= 1;
                }
                best[at] = d2;
                reach = best[NEIGHBOURS - 1].sqrt();
            }
            j += dir;
            steps += 1;
        }
    }
    best.iter()
        .take_while(|d| d.is_finite())
        .map(|d| d.sqrt())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::CloudSlicer;
    use crate::geom::math::{Point3, Vec3};
    use crate::geom::mesh::PointCloud;
    use crate::geom::rng::Rng;
    use std::f64::consts::TAU;

    /// Points on a cylinder of radius 0.1 around the z axis, 0.1 tall, with
    /// radial noise.
    fn cylinder(n: usize, rng: &mut Rng) -> Vec<Point3> {
        (0..n)
            .map(|_| {
                let a = TAU * rng.uniform();
                let r = 0.1 + 0.0005 * rng.gaussian();
                Vec3::new(r * a.cos(), r * a.sin(), -0.05 + 0.1 * rng.uniform())
            })
            .collect()
    }

    #[test]
    fn a_cloud_merged_with_jittered_copies_keeps_its_spacing() {
        let mut rng = Rng::new(11);
        let pts = cylinder(30_000, &mut rng);
        let spacing = |pts: Vec<Point3>| {
            let cloud = PointCloud::new(pts).unwrap();
            CloudSlicer::new(&cloud, Vec3::Z).unwrap().spacing()
        };
        let one = spacing(pts.clone());
        // Jitter as a share of the spacing (per coordinate): more copies
        // spread their twins' distances, and need less to be told apart.
        for (copies, jitter) in [(2, 0.1), (3, 0.1), (4, 0.05)] {
            let mut all = pts.clone();
            for _ in 1..copies {
                all.extend(pts.iter().map(|&p| {
                    let d = Vec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian());
                    p + d * (jitter * one)
                }));
            }
            let s = spacing(all);
            println!("{copies} copies: spacing {s:.6} against {one:.6}");
            assert!(
                (s / one - 1.0).abs() < 0.1,
                "{copies} copies: {s} against {one}"
            );
        }
        // Exact copies are no neighbours: the spacing is the same.
        assert_eq!(spacing([pts.clone(), pts.clone()].concat()), one);
        // Twice as many points of their own: the spacing shrinks by about √2.
        let denser = cylinder(60_000, &mut rng);
        let ratio = one / spacing(denser);
        assert!((1.25..1.6).contains(&ratio), "{ratio}");
    }
}
