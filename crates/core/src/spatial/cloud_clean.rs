//! Input hygiene for a scanned point cloud: the floor or turntable under the
//! feet and the stray points and clumps a scanner records around a body are
//! taken out before the body is segmented.
//!
//! Everything is relative to the cloud's own extent `E` (the longest side of
//! the box holding the central 99.8 % of the points along each axis, so a
//! stray point far away does not set it):
//!
//! 1. **Floor.** For each candidate direction `n` (the up axis when given,
//!    else the three principal axes of the voxel-thinned cloud, both signs),
//!    the points' heights along `n` are binned (`E / 500` wide). A floor is
//!    a thin dense sheet at the low end: the fullest bin in the lowest 15 %
//!    of the heights, whose points cover, in the plane, an area of at least
//!    [`CleanOptions::min_floor_area`] × `E²` (counted in cells of the voxel
//!    size), and what lies above it reaches at least `E / 2` along `n` (a
//!    body stands on its floor; a flat side of it has no such reach). Its
//!    plane is refitted (least squares) to the points within a band around
//!    it that narrows to three robust deviations (at least two bins), which
//!    must stay under [`CleanOptions::max_floor_width`] × `E`; every
//!    point below the band's top is floor. The two soles of a body cover about 0.02 E²; a
//!    floor disc under the feet ten times that.
//! 2. **Strays.** The remaining points are put in voxels of side
//!    [`CleanOptions::voxel`] × `E`, 26-connected into components. The
//!    largest component is the body; another component is kept when it
//!    has at least [`CleanOptions::min_component`] of the largest's points
//!    or lies within three voxels of such a component (a part cut off by a
//!    scanner hole); the rest is dropped.
//!
//! The result says how many points went and why, and, when a floor was
//! found, its normal: the body's up direction.

use rayon::slice::ParallelSliceMut;
use std::borrow::Cow;

use crate::geom::linalg::principal;
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{central_extent, PointCloud};
use crate::geom::stats::{median, nth_smallest};
use crate::geom::union_find::root;

/// Options of [`clean_cloud`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CleanOptions {
    /// Remove a floor or turntable under the feet. Default true.
    pub remove_floor: bool,
    /// Remove stray points and small clumps. Default true.
    pub remove_strays: bool,
    /// The up direction, when known: only a floor normal to it is looked
    /// for. Default `None` (the principal axes are tried).
    pub up: Option<Vec3>,
    /// A floor covers at least this fraction of `E²`. Default 0.06.
    pub min_floor_area: Real,
    /// A floor's sheet is at most this thick (three robust deviations of
    /// its points from the plane, either side), as a fraction of `E`.
    /// Default 0.025: a scanned floor is a few millimetres thick (corpus:
    /// 0.004 E, the two-bin minimum), while a stretch of the body that a
    /// candidate's refit turns to is 0.05-0.4 E thick and can cover as much
    /// area as a floor.
    pub max_floor_width: Real,
    /// Voxel side for the components, as a fraction of `E`. Default 0.01.
    pub voxel: Real,
    /// A component other than the largest is kept when it has at least
    /// this fraction of the largest's points. Default 0.05.
    pub min_component: Real,
}

impl Default for CleanOptions {
    fn default() -> Self {
        CleanOptions {
            remove_floor: true,
            remove_strays: true,
            up: None,
            min_floor_area: 0.06,
            max_floor_width: 0.025,
            voxel: 0.01,
            min_component: 0.05,
        }
    }
}

/// What [`clean_cloud`] found and removed.
#[derive(Clone, Debug, PartialEq)]
pub struct CleanReport {
    /// Points on or below the floor.
    pub floor_points: usize,
    /// The floor's normal, pointing to the body, when a floor was found.
    pub floor_normal: Option<Vec3>,
    /// Points in components too small to be part of the body.
    pub stray_points: usize,
    /// Components dropped.
    pub stray_components: usize,
    /// Components kept (the body and pieces of it).
    pub kept_components: usize,
}

impl CleanReport {
    /// One line per removal, for a warning list.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if self.floor_points > 0 {
            w.push(format!(
                "removed a floor under the feet: {} points",
                self.floor_points
            ));
        }
        if self.stray_points > 0 {
            w.push(format!(
                "removed {} stray points in {} clumps away from the body",
                self.stray_points, self.stray_components
            ));
        }
        w
    }
}

/// The cloud without its floor and stray points (see the module doc), and
/// what was removed. Points keep their order; normals follow their points.
/// A cloud with nothing to remove is returned as it is, not copied.
pub fn clean_cloud<'c>(
    cloud: &'c PointCloud,
    opts: &CleanOptions,
) -> (Cow<'c, PointCloud>, CleanReport) {
    let mut report = CleanReport {
        floor_points: 0,
        floor_normal: None,
        stray_points: 0,
        stray_components: 0,
        kept_components: 0,
    };
    let pts = &cloud.positions;
    let Some(extent) = robust_extent(pts) else {
        return (Cow::Borrowed(cloud), report);
    };
    let mut keep = vec![true; pts.len()];
    let voxels = Voxels::new(pts, Vec3::ZERO, opts.voxel * extent);
    if opts.remove_floor {
        if let Some(floor) = find_floor(&voxels.centroids, extent, opts) {
            let top = floor.top(pts, extent);
            for (k, p) in keep.iter_mut().zip(pts) {
                if p.dot(floor.normal) < top {
                    *k = false;
                    report.floor_points += 1;
                }
            }
            report.floor_normal = Some(floor.normal);
        }
    }
    if opts.remove_strays {
        let comps = voxels.components(&keep);
        let largest = comps.sizes.iter().copied().max().unwrap_or(0);
        let min = ((opts.min_component * largest as Real).ceil() as usize).max(1);
        let big: Vec<bool> = comps.sizes.iter().map(|&s| s >= min).collect();
        // A small piece close to the body stays: a bit of it that a
        // scanner's gap cut off, not something in the room.
        let stays = voxels.near_big(&comps, &big, NEAR_BODY);
        for (k, &c) in keep.iter_mut().zip(&comps.of_point) {
            if *k && !stays[c as usize] {
                *k = false;
                report.stray_points += 1;
            }
        }
        let (kept, dropped) =
            comps
                .sizes
                .iter()
                .zip(&stays)
                .fold((0, 0), |(a, b), (&s, &k)| match (s, k) {
                    (0, _) => (a, b),
                    (_, true) => (a + 1, b),
                    _ => (a, b + 1),
                });
        report.kept_components = kept;
        report.stray_components = dropped;
    }
    if report.floor_points + report.stray_points == 0 {
        return (Cow::Borrowed(cloud), report);
    }
    let positions = pts
        .iter()
        .zip(&keep)
        .filter_map(|(p, &k)| k.then_some(*p))
        .collect();
    let normals = cloud.normals.as_ref().map(|ns| {
        ns.iter()
            .zip(&keep)
            .filter_map(|(n, &k)| k.then_some(*n))
            .collect()
    });
    (Cow::Owned(PointCloud { positions, normals }), report)
}

/// The longest side of the box holding the central 99.8 % of the finite
/// points along each axis; `None` for fewer than 10 points.
fn robust_extent(pts: &[Point3]) -> Option<Real> {
    if pts.iter().filter(|p| p.is_finite()).count() < 10 {
        return None;
    }
    central_extent(pts, 1000).filter(|&e| e > 0.0)
}

/// A floor plane found on the voxel centroids: `p · normal = level`, its
/// sheet `width` thick either side.
struct Floor {
    normal: Vec3,
    level: Real,
    width: Real,
    /// The covered area, as a fraction of `E²`.
    area: Real,
}

impl Floor {
    /// Points with `p · normal` below this are floor: three robust
    /// deviations of every point near the plane above it (at least two
    /// bins: the centroids average the scanner's noise away).
    fn top(&self, pts: &[Point3], extent: Real) -> Real {
        let bin = extent / 500.0;
        let reach = self.width.max(4.0 * bin);
        let near = near_plane(pts, self.normal, self.level, reach);
        let dev = robust_deviation(&near, self.normal, self.level);
        self.level + (3.0 * dev).max(2.0 * bin)
    }
}

fn find_floor(pts: &[Point3], extent: Real, opts: &CleanOptions) -> Option<Floor> {
    let cell = opts.voxel * extent;
    let candidates: Vec<Vec3> = match opts.up.and_then(|u| u.normalized()) {
        Some(u) => vec![u],
        None => principal_axes(pts)
            .into_iter()
            .flat_map(|a| [a, -a])
            .collect(),
    };
    let mut best: Option<Floor> = None;
    for n in candidates {
        let Some(f) = floor_along(pts, n, extent, cell) else {
            continue;
        };
        if f.width > opts.max_floor_width * extent {
            continue;
        }
        if f.area >= opts.min_floor_area && best.as_ref().is_none_or(|b| f.area > b.area) {
            best = Some(f);
        }
    }
    best
}

/// The floor normal to about `n`, refitted (see the module doc).
fn floor_along(pts: &[Point3], n: Vec3, extent: Real, cell: Real) -> Option<Floor> {
    let bin = extent / 500.0;
    let centre = low_band(pts, n, extent, bin)?;
    // Refit the plane to the points near it, the band then set to three
    // robust deviations (at least two bins): a candidate axis a few degrees
    // off the floor's normal holds a strip of the floor in its fullest bin,
    // and each refit turns the plane towards the floor's.
    let (mut normal, mut level, mut width) = (n, centre, 1.5 * bin);
    for _ in 0..8 {
        let band = near_plane(pts, normal, level, width);
        let (c, m) = plane_fit(&band)?;
        let m = if m.dot(n) < 0.0 { -m } else { m };
        if m.dot(n) < 0.9 {
            return None;
        }
        normal = m;
        level = c.dot(m);
        width = (3.0 * robust_deviation(&band, m, level)).max(2.0 * bin);
    }
    let sheet = near_plane(pts, normal, level, width);
    let top = level + width;
    // A body stands on its floor: what lies above it reaches along the
    // normal at least half the cloud's extent (a flat side does not).
    let mut above: Vec<Real> = pts
        .iter()
        .filter(|p| p.is_finite())
        .map(|p| p.dot(normal))
        .filter(|&h| h > top)
        .collect();
    if above.len() < 10 {
        return None;
    }
    let k = above.len() - 1 - above.len() / 1000;
    let reach = nth_smallest(&mut above, k)? - top;
    if reach < 0.5 * extent {
        return None;
    }
    let area = covered_area(&sheet, normal, cell) / (extent * extent);
    Some(Floor {
        normal,
        level,
        width,
        area,
    })
}

/// The finite points within `width` of the plane `p · n = level`.
fn near_plane(pts: &[Point3], n: Vec3, level: Real, width: Real) -> Vec<Point3> {
    pts.iter()
        .filter(|p| p.is_finite() && (p.dot(n) - level).abs() <= width)
        .copied()
        .collect()
}

/// The fullest bin of heights along `n` in the lowest 15 % of their range:
/// its centre height.
fn low_band(pts: &[Point3], n: Vec3, extent: Real, bin: Real) -> Option<Real> {
    let mut h: Vec<Real> = pts
        .iter()
        .filter(|p| p.is_finite())
        .map(|p| p.dot(n))
        .collect();
    if h.len() < 10 {
        return None;
    }
    let k = h.len() / 1000;
    let lo = nth_smallest(&mut h, k)?;
    let hi_k = h.len() - 1 - k;
    let hi = nth_smallest(&mut h, hi_k)?;
    let start = lo - 2.0 * bin;
    let span = (hi - lo).max(extent * 0.01);
    let bins = ((0.15 * span + 2.0 * bin) / bin).ceil() as usize + 1;
    let mut count = vec![0usize; bins];
    for &v in &h {
        let b = (v - start) / bin;
        if b >= 0.0 && (b as usize) < bins {
            count[b as usize] += 1;
        }
    }
    let (best, _) = count
        .iter()
        .enumerate()
        .max_by_key(|&(i, c)| (*c, usize::MAX - i))?;
    Some(start + (best as Real + 0.5) * bin)
}

/// The centroid and normal of the least-squares plane through `pts`.
fn plane_fit(pts: &[Point3]) -> Option<(Point3, Vec3)> {
    if pts.len() < 3 {
        return None;
    }
    let (c, vals, vecs) = principal(pts);
    let k = (0..3).min_by(|&a, &b| vals[a].total_cmp(&vals[b]))?;
    Some((c, vecs[k].normalized()?))
}

/// The median absolute distance of `pts` from the plane `p · n = c`,
/// scaled to a normal distribution's deviation (× 1.4826).
fn robust_deviation(pts: &[Point3], n: Vec3, c: Real) -> Real {
    let mut d: Vec<Real> = pts.iter().map(|p| (p.dot(n) - c).abs()).collect();
    median(&mut d).map_or(0.0, |m| 1.4826 * m)
}

/// The area of the cells of side `cell` that `pts` occupy in the plane
/// normal to `n`.
fn covered_area(pts: &[Point3], n: Vec3, cell: Real) -> Real {
    let e1 = n.any_perpendicular();
    let e2 = n.cross(e1);
    let mut cells = std::collections::HashSet::new();
    for p in pts {
        let key = (
            (p.dot(e1) / cell).floor() as i64,
            (p.dot(e2) / cell).floor() as i64,
        );
        cells.insert(key);
    }
    cells.len() as Real * cell * cell
}

/// The principal axes of the voxel centroids (so a densely scanned region
/// does not tilt them).
fn principal_axes(cents: &[Point3]) -> Vec<Vec3> {
    if cents.len() < 3 {
        return Vec::new();
    }
    let (_, _, vecs) = principal(cents);
    vecs.iter().filter_map(|v| v.normalized()).collect()
}

fn voxel_key(p: Point3, origin: Point3, cell: Real) -> [i64; 3] {
    let a = (p - origin).to_array();
    [
        (a[0] / cell).floor() as i64,
        (a[1] / cell).floor() as i64,
        (a[2] / cell).floor() as i64,
    ]
}

/// The 26-connected voxel component of each point (voxels of side `cell`
/// from `origin`; `u32::MAX` for a non-finite point), numbered in voxel key
/// order.
pub fn voxel_components(pts: &[Point3], origin: Point3, cell: Real) -> Vec<u32> {
    Voxels::new(pts, origin, cell)
        .components(&vec![true; pts.len()])
        .of_point
}

/// The finite points in voxels of one side, numbered in key order (so
/// nothing depends on the points' order).
struct Voxels {
    keys: Vec<[i64; 3]>,
    /// Each voxel's point centroid.
    centroids: Vec<Point3>,
    /// Each point's voxel (`u32::MAX` for a non-finite point).
    of_point: Vec<u32>,
}

/// Voxel components of the kept points.
struct Components {
    /// The component of each point (`u32::MAX` for points not kept).
    of_point: Vec<u32>,
    /// The component of each voxel (`u32::MAX` for voxels without a kept
    /// point).
    of_voxel: Vec<u32>,
    /// Kept points per component.
    sizes: Vec<usize>,
}

impl Voxels {
    fn new(pts: &[Point3], origin: Point3, cell: Real) -> Voxels {
        let mut order: Vec<([i64; 3], u32)> = pts
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_finite())
            .map(|(i, p)| (voxel_key(*p, origin, cell), i as u32))
            .collect();
        order.par_sort_unstable();
        let mut keys = Vec::new();
        let mut centroids = Vec::new();
        let mut of_point = vec![u32::MAX; pts.len()];
        for run in order.chunk_by(|a, b| a.0 == b.0) {
            let v = keys.len() as u32;
            keys.push(run[0].0);
            let mut sum = Vec3::ZERO;
            for &(_, i) in run {
                sum += pts[i as usize];
                of_point[i as usize] = v;
            }
            centroids.push(sum * (1.0 / run.len() as Real));
        }
        Voxels {
            keys,
            centroids,
            of_point,
        }
    }

    /// 26-connected components of the voxels holding a kept point.
    fn components(&self, keep: &[bool]) -> Components {
        let n = self.keys.len();
        let mut kept_voxel = vec![false; n];
        for (&v, &k) in self.of_point.iter().zip(keep) {
            if k && v != u32::MAX {
                kept_voxel[v as usize] = true;
            }
        }
        let mut parent: Vec<u32> = (0..n as u32).collect();
        for (i, k) in self.keys.iter().enumerate() {
            if !kept_voxel[i] {
                continue;
            }
            // Neighbours later in key order (the earlier ones link to this).
            for d in NEIGHBOURS_AFTER {
                let nk = [k[0] + d[0], k[1] + d[1], k[2] + d[2]];
                if let Ok(j) = self.keys.binary_search(&nk) {
                    if kept_voxel[j] {
                        let (a, b) = (root(&mut parent, i as u32), root(&mut parent, j as u32));
                        if a != b {
                            parent[a.max(b) as usize] = a.min(b);
                        }
                    }
                }
            }
        }
        let mut label = vec![u32::MAX; n];
        let mut next = 0u32;
        let mut voxel_comp = vec![u32::MAX; n];
        for i in 0..n {
            if !kept_voxel[i] {
                continue;
            }
            let r = root(&mut parent, i as u32) as usize;
            if label[r] == u32::MAX {
                label[r] = next;
                next += 1;
            }
            voxel_comp[i] = label[r];
        }
        let mut sizes = vec![0usize; next as usize];
        let of_point = self
            .of_point
            .iter()
            .zip(keep)
            .map(|(&v, &k)| {
                if k && v != u32::MAX {
                    let c = voxel_comp[v as usize];
                    sizes[c as usize] += 1;
                    c
                } else {
                    u32::MAX
                }
            })
            .collect();
        Components {
            of_point,
            of_voxel: voxel_comp,
            sizes,
        }
    }
}

impl Voxels {
    /// Per component: big, or with a voxel within `reach` voxels (in each
    /// axis) of a big component's voxel.
    fn near_big(&self, comps: &Components, big: &[bool], reach: i64) -> Vec<bool> {
        let mut near = big.to_vec();
        for (k, &c) in self.keys.iter().zip(&comps.of_voxel) {
            if c == u32::MAX || near[c as usize] {
                continue;
            }
            'search: for dx in -reach..=reach {
                for dy in -reach..=reach {
                    for dz in -reach..=reach {
                        let nk = [k[0] + dx, k[1] + dy, k[2] + dz];
                        if let Ok(j) = self.keys.binary_search(&nk) {
                            let o = comps.of_voxel[j];
                            if o != u32::MAX && big[o as usize] {
                                near[c as usize] = true;
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        near
    }
}

/// A small component within this many voxels of the body is kept.
const NEAR_BODY: i64 = 3;

/// The 13 of a voxel's 26 neighbours whose keys sort after its own.
const NEIGHBOURS_AFTER: [[i64; 3]; 13] = [
    [0, 0, 1],
    [0, 1, -1],
    [0, 1, 0],
    [0, 1, 1],
    [1, -1, -1],
    [1, -1, 0],
    [1, -1, 1],
    [1, 0, -1],
    [1, 0, 0],
    [1, 0, 1],
    [1, 1, -1],
    [1, 1, 0],
    [1, 1, 1],
];

#[cfg(test)]
mod tests {
    use super::*;

    /// A capsule-like column of points 1.7 tall on a disc, plus strays.
    fn column(with_floor: bool, strays: bool) -> PointCloud {
        let mut p = Vec::new();
        for i in 0..200 {
            let z = 0.01 + 1.7 * i as Real / 200.0;
            for j in 0..60 {
                let a = std::f64::consts::TAU * j as Real / 60.0;
                p.push(Vec3::new(0.15 * a.cos(), 0.1 * a.sin(), z));
            }
        }
        if with_floor {
            for i in -60..=60 {
                for j in -60..=60 {
                    let (x, y) = (i as Real * 0.01, j as Real * 0.01);
                    if x * x + y * y < 0.36 {
                        p.push(Vec3::new(x, y, 0.0));
                    }
                }
            }
        }
        if strays {
            p.push(Vec3::new(1.0, 1.0, 1.0));
            for k in 0..20 {
                p.push(Vec3::new(-0.8, 0.5 + 0.001 * k as Real, 1.2));
            }
        }
        PointCloud {
            positions: p,
            normals: None,
        }
    }

    #[test]
    fn a_floor_disc_is_found_and_removed_with_its_normal() {
        let c = column(true, false);
        let (out, r) = clean_cloud(&c, &CleanOptions::default());
        let n = r.floor_normal.expect("floor");
        assert!(n.dot(Vec3::new(0.0, 0.0, 1.0)) > 0.999, "{n:?}");
        assert!(out.positions.iter().all(|p| p.to_array()[2] > 0.009));
        assert_eq!(out.positions.len(), 200 * 60);
        assert!(r.floor_points > 1000);
    }

    #[test]
    fn a_body_without_floor_keeps_every_point() {
        let c = column(false, false);
        let (out, r) = clean_cloud(&c, &CleanOptions::default());
        assert_eq!(r.floor_normal, None);
        assert_eq!(*out, c);
    }

    #[test]
    fn strays_and_clumps_go_and_the_order_does_not_matter() {
        let c = column(false, true);
        let (out, r) = clean_cloud(&c, &CleanOptions::default());
        assert_eq!(r.stray_points, 21);
        assert_eq!(r.stray_components, 2);
        assert_eq!(out.positions.len(), 200 * 60);
        let mut rev = c.clone();
        rev.positions.reverse();
        let (out2, r2) = clean_cloud(&rev, &CleanOptions::default());
        assert_eq!(r2, r);
        assert_eq!(out2.positions.len(), out.positions.len());
    }

    #[test]
    fn a_given_up_axis_limits_the_floor_search() {
        let c = column(true, false);
        let opts = CleanOptions {
            up: Some(Vec3::new(1.0, 0.0, 0.0)),
            ..CleanOptions::default()
        };
        let (_, r) = clean_cloud(&c, &opts);
        assert_eq!(r.floor_points, 0);
    }

    #[test]
    fn a_floor_thicker_than_the_limit_is_not_a_floor() {
        let c = column(true, false);
        let opts = CleanOptions {
            max_floor_width: 1e-4,
            ..CleanOptions::default()
        };
        let (_, r) = clean_cloud(&c, &opts);
        assert_eq!(r.floor_normal, None);
        assert_eq!(r.floor_points, 0);
    }
}
