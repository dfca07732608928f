//! The point spacing of a cloud (see the module doc of [`super`], 1).

use crate::geom::linalg::{principal, Cholesky};
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

/// The spacing is at least this many times the cloud's noise across its
/// surface ([`local_noise`]): an occupancy cell finer than the noisy
/// shell's thickness sees the shell as specks. A scan merged with a copy
/// of itself jittered by 1 mm has twins 1.4 mm apart and a spacing of
/// 2.5 mm by its neighbours, where its slab images need about 3.1 mm (the
/// segmentation lost an arm or the head); the corpus scans' noise is under
/// a third of their spacing, so this acts only on a cloud noisier
/// than its sampling.
const NOISE_CELLS: Real = 3.0;

/// How many neighbours [`local_noise`] fits its quadric to.
const NOISE_NEIGHBOURS: usize = 24;

/// Twice the median nearest-neighbour distance of up to 1000 evenly
/// chosen points (a sorted sweep along the height axis: neighbours are
/// searched outward in height until the height gap exceeds the 8th best
/// distance, at most 16384 steps each way). When the points come in
/// clusters of k + 1 (see [`CLUSTER_JUMP`]; two copies of a scan merged,
/// one jittered by less than the spacing), the middle of the nearest other
/// cluster's distances stands for the nearest neighbour: the cloud keeps
/// its spacing instead of taking the jitter's. At least [`NOISE_CELLS`]
/// times the median [`local_noise`] of the same points. Returns the
/// spacing and that noise.
pub(super) fn estimate_spacing(
    points: &[Point3],
    order: &[u32],
    heights: &[Real],
) -> Option<(Real, Real)> {
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
    let mut noise: Vec<Real> = crate::geom::parallel::parallel_map(&ss, 64, |run| {
        run.iter()
            .filter_map(|&s| {
                let i = s * n / samples;
                let around: Vec<Point3> =
                    neighbours_in_sweep(points, order, heights, i, NOISE_NEIGHBOURS)
                        .into_iter()
                        .map(|b| b.1)
                        .collect();
                local_noise(points[order[i] as usize], &around)
            })
            .collect()
    });
    let noise = median(&mut noise).unwrap_or(0.0);
    (first > 0.0).then_some(((2.0 * first).max(NOISE_CELLS * noise), noise))
}

/// The `k` points nearest the point of sorted rank `i` (of a different
/// position) with their squared distances, ascending: a sweep along the
/// sorted heights, outward until the height gap reaches the `k`-th best
/// distance, at most 16384 steps each way.
fn neighbours_in_sweep(
    points: &[Point3],
    order: &[u32],
    heights: &[Real],
    i: usize,
    k: usize,
) -> Vec<(Real, Point3)> {
    let n = order.len();
    let p = points[order[i] as usize];
    let mut best: Vec<(Real, Point3)> = Vec::with_capacity(k + 1);
    let mut reach = Real::INFINITY;
    for dir in [-1isize, 1] {
        let mut j = i as isize + dir;
        let mut steps = 0;
        while j >= 0 && (j as usize) < n && steps < 16384 {
            if (heights[j as usize] - heights[i]).abs() >= reach {
                break;
            }
            let q = points[order[j as usize] as usize];
            let d2 = (p - q).norm_squared();
            if d2 > 0.0 && (best.len() < k || d2 < best[k - 1].0) {
                let at = best.partition_point(|b| b.0 <= d2);
                best.insert(at, (d2, q));
                best.truncate(k);
                if best.len() == k {
                    reach = best[k - 1].0.sqrt();
                }
            }
            j += dir;
            steps += 1;
        }
    }
    best
}

/// The noise of the surface at `p`: the root mean square residual of the
/// quadric height field `w = a u² + b uv + c v² + d u + e v + f` fitted to
/// `p` and `around` in their principal frame (`w` along the least
/// variance), corrected for the six fitted numbers. A quadric, not a
/// plane: over a few spacings a limb's curvature is as large as a
/// scanner's noise, and a plane fitted to so few noisy points tilts to
/// follow them. `None` for fewer than ten points or a degenerate fit.
fn local_noise(p: Point3, around: &[Point3]) -> Option<Real> {
    let mut pts = vec![p];
    pts.extend_from_slice(around);
    if pts.len() < 10 {
        return None;
    }
    let (c, _, axes) = principal(&pts);
    // Across-plane coordinates scaled to about one, for the conditioning.
    let r = pts.iter().map(|&q| (q - c).norm()).fold(0.0, Real::max);
    if !(r > 0.0) {
        return None;
    }
    let row = |q: Point3| {
        let d = q - c;
        let (u, v) = (d.dot(axes[0]) / r, d.dot(axes[1]) / r);
        ([u * u, u * v, v * v, u, v, 1.0], d.dot(axes[2]))
    };
    let (mut ata, mut atb) = ([0.0; 36], [0.0; 6]);
    for &q in &pts {
        let (a, w) = row(q);
        for r in 0..6 {
            atb[r] += a[r] * w;
            for k in 0..6 {
                ata[r * 6 + k] += a[r] * a[k];
            }
        }
    }
    let x = Cholesky::factor(&ata, 6, 1e-12)?.solve_leading(&atb, 6);
    let sum: Real = pts
        .iter()
        .map(|&q| {
            let (a, w) = row(q);
            let fit: Real = a.iter().zip(&x).map(|(ai, xi)| ai * xi).sum();
            (w - fit).powi(2)
        })
        .sum();
    Some((sum / (pts.len() - 6) as Real).sqrt())
}

/// The distances from the point of sorted rank `i` to its nearest
/// [`NEIGHBOURS`] other points (see [`neighbours_in_sweep`]), ascending;
/// fewer when there are fewer.
fn nearest_in_sweep(points: &[Point3], order: &[u32], heights: &[Real], i: usize) -> Vec<Real> {
    neighbours_in_sweep(points, order, heights, i, NEIGHBOURS)
        .iter()
        .map(|b| b.0.sqrt())
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

    /// 25 points on 8 × 8 mm of a limb (a cylinder of radius 4 cm): without
    /// noise the quadric takes the curvature (a plane would leave 0.2 mm);
    /// with 1 mm of noise along the normal it measures about 1 mm.
    #[test]
    fn local_noise_measures_the_noise_not_the_curvature() {
        let mut rng = Rng::new(3);
        for sigma in [0.0, 0.001] {
            let mut found = Vec::new();
            for _ in 0..200 {
                let patch: Vec<Point3> = (0..25)
                    .map(|_| {
                        let a = 0.2 * (rng.uniform() - 0.5);
                        let r = 0.04 + sigma * rng.gaussian();
                        Vec3::new(r * a.cos(), r * a.sin(), 0.008 * (rng.uniform() - 0.5))
                    })
                    .collect();
                found.extend(super::local_noise(patch[0], &patch[1..]));
            }
            let noise = crate::geom::stats::median(&mut found).unwrap();
            println!("sigma {sigma}: noise {noise:.6}");
            if sigma == 0.0 {
                assert!(noise < 1e-5, "{noise}");
            } else {
                assert!((noise / sigma - 1.0).abs() < 0.3, "{noise}");
            }
        }
    }
}
