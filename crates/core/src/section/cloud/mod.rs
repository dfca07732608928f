//! Slab sections of point clouds: ordered closed loops from the scan points
//! near a plane (method.md §8.2, "scan: the slab's points as an occupancy
//! image, closed morphologically, then components and contours").
//!
//! # The construction
//!
//! 1. **Scale.** The cloud's point spacing `s ≈ ρ^{-1/2}` (`ρ` points per
//!    unit area) is estimated once as twice the median nearest-neighbour
//!    distance of a sample of points, passing over a point's near twins
//!    when the points come in clusters (a scan merged with a jittered copy
//!    of itself), and at least three times the cloud's noise across its
//!    surface (a quadric fitted to each sampled point's 24 neighbours), so
//!    a cloud noisier than its sampling gets cells no finer than its shell
//!    is thick. Every length default below is a multiple of `s`, so
//!    nothing assumes metres.
//! 2. **Slab.** The points with `|p·n − c| ≤ t` (default `t = s`) are
//!    projected into the plane. The points are sorted by height once, so
//!    each slab is a contiguous range found by binary search.
//! 3. **Occupancy image** with cells of size `g` (default `g = s`),
//!    **closed** morphologically (dilation then erosion by a square of
//!    radius `r` cells, default 2) to bridge the gaps between neighbouring
//!    points, then split into **8-connected components**: one per body part
//!    in the slice. Components with few points are dropped as outliers.
//! 4. **Ordering** of each component's points along its loop:
//!    * a component that encloses empty cells (a closed ring) or that is a
//!      solid blob (a slab grazing the surface, e.g. the top of the head)
//!      is traced: the outer boundary of the component with its enclosed
//!      cells filled is followed cell edge by cell edge (region on the
//!      left), smoothed (moving average of five corners), and each point
//!      gets its arc position along it: the nearest point on the boundary
//!      segments around the boundary vertex that a breadth-first
//!      propagation over the filled cells assigned to its cell. Of a blob
//!      only the points within 1.5 cells of the boundary are kept (its
//!      outline);
//!    * a thin component that does not close (a ring broken by a scanner
//!      hole) is an arc. Arcs that are pieces of one loop (disjoint angular
//!      ranges that complete each other, radii continuous across the gaps:
//!      see `merge_arcs`) are joined first. Each arc or joined group is
//!      ordered by angle about the centre of the circle fitted to its points
//!      (algebraic least squares, `x² + y² + Dx + Ey + F = 0`), which stays
//!      near the true centre when an arc is missing.
//! 5. **What is fitted.** The points are grouped into bins along the loop
//!    (one bin per boundary vertex, i.e. per cell; or per angular step of
//!    one cell at the loop's mean radius); in each bin points farther than
//!    three cells from the bin's median are rejected as outliers, and the
//!    **real scan point nearest to the mean of the rest** represents the bin.
//!    The loop handed to the curve fit is these representatives in order,
//!    projected into the section plane: real points, one per cell of loop
//!    length, so dense stretches do not outweigh sparse ones and the noise
//!    of the kept point is the scanner's (their indices in the cloud are
//!    kept too).
//!
//! Holes: where the scanner saw nothing the loop simply has no points; the
//! chord across the gap gets its share of the curve parameter (chord-length
//! parameterization), and the fit bridges it. With a smoothness penalty
//! ([`crate::curve::fit::FitOptions::smoothing`], see [`scan_fit_options`]) the
//! bridge is the smoothest curve through the data on either side instead of
//! whatever the highest harmonics do there. [`ScanLoop::max_gap`] reports
//! the widest gap bridged.

use crate::curve::fit::FitOptions;
use crate::geom::math::{Point2, Point3, Real, Vec2, Vec3};
use crate::geom::mesh::{MeshError, PointCloud};
use crate::geom::stats::median;
use crate::section::mesh::{plane_axes, select_loop, Plane, SectionLoop};
use thiserror::Error;

mod arcs;
mod contour;
pub(crate) mod grid;
mod spacing;
pub(crate) mod superlevel;

pub use arcs::{bridge_gaps, unseen_side};
use arcs::{merge_arcs, order_by_angle};
use contour::{order_component, Ordering};
use grid::{Grid, NONE};
use spacing::estimate_spacing;

/// The smoothness penalty [`scan_fit_options`] sets by default, `λ = 1e-5`
/// (the penalty is scale-free: both terms are squared lengths).
///
/// Without it a curve fitted across a hole in a scanned loop runs away
/// from the surface; a larger penalty holds it closer over holes but
/// rounds off the high orders of loops without one, hence the small value.
pub const DEFAULT_SCAN_SMOOTHING: Real = 1e-5;

/// Fit options for a scanned loop: `base` with the smoothness penalty
/// switched on (when `base` has none), so gaps are bridged smoothly, and
/// the cloud's `noise` ([`CloudSlicer::noise`]) as the points' scatter, so
/// no order follows it (when `base` gives none).
pub fn scan_fit_options(base: &FitOptions, noise: Real) -> FitOptions {
    FitOptions {
        noise: if base.noise > 0.0 { base.noise } else { noise },
        smoothing: if base.smoothing > 0.0 {
            base.smoothing
        } else {
            DEFAULT_SCAN_SMOOTHING
        },
        ..*base
    }
}

/// What went wrong in a slab section.
#[derive(Debug, Error, PartialEq)]
pub enum ScanSectionError {
    #[error("invalid point cloud: {0}")]
    Cloud(#[from] MeshError),
    #[error("the axis {0:?} is not a finite non-zero vector")]
    BadAxis([Real; 3]),
    #[error("the cloud has no extent (all points coincide)")]
    Degenerate,
    #[error("bad option {name} = {value}: {why}")]
    BadOption {
        name: &'static str,
        value: Real,
        why: &'static str,
    },
    #[error("the slab at offset {offset} (half-thickness {half_thickness}) holds {found} points; at least {needed} are needed (the cloud spans [{min}, {max}] along the axis)")]
    TooFewPoints {
        offset: Real,
        half_thickness: Real,
        found: usize,
        needed: usize,
        min: Real,
        max: Real,
    },
    #[error("the section offset {0} is not finite")]
    NonFiniteOffset(Real),
}

/// Options of [`CloudSlicer::section_at`]. Lengths in the cloud's units;
/// `None` picks a multiple of the estimated point spacing `s`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScanSectionOptions {
    /// Half-thickness `t` of the slab. Default `s` (≈ 3 mm for 200 000
    /// points on a body).
    pub half_thickness: Option<Real>,
    /// Occupancy cell size `g`. Default `s`.
    pub cell_size: Option<Real>,
    /// Radius of the morphological closing, in cells. Default 2.
    pub closing_radius: usize,
    /// Components with fewer points are dropped as outliers. Default 12.
    pub min_component_points: usize,
    /// A slab with fewer points is an error. Default 12.
    pub min_slab_points: usize,
    /// Largest image, in cells (the cell size grows to fit). Default 4 000 000.
    pub max_cells: usize,
    /// Direction of the in-plane axis `e1` of the loop frames; `None` as in
    /// [`crate::section::mesh::SectionOptions::reference`].
    pub reference: Option<Vec3>,
    /// When the cloud has normals, move each slab point within its tangent
    /// plane onto the section plane (see [`onto_plane`]) instead of straight
    /// along the axis. Default true.
    pub use_normals: bool,
}

impl Default for ScanSectionOptions {
    fn default() -> Self {
        ScanSectionOptions {
            half_thickness: None,
            cell_size: None,
            closing_radius: 2,
            min_component_points: 12,
            min_slab_points: 12,
            max_cells: 4_000_000,
            reference: None,
            use_normals: true,
        }
    }
}

/// One ordered loop of a slab section.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanLoop {
    /// The representatives in order, projected into the section plane
    /// (what the curve fit gets: real scan points moved at most the slab's
    /// half-thickness along the normal), with area, perimeter (of the
    /// polygon through them, gaps closed by chords), centroid and frame;
    /// counter-clockwise about the plane normal.
    pub outline: SectionLoop,
    /// Index in the cloud of each point of `outline.points` (the
    /// unprojected scan point).
    pub scan_indices: Vec<usize>,
    /// Slab points in this component.
    pub raw_points: usize,
    /// True when the occupancy ring closed (no gap wider than the closing
    /// bridges); false when the loop was ordered by angle across a gap.
    pub closed_ring: bool,
    /// The longest distance between consecutive representatives (the
    /// widest gap the fit must bridge).
    pub max_gap: Real,
}

/// All loops of one slab.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanSection {
    pub plane: Plane,
    pub loops: Vec<ScanLoop>,
    /// Points in the slab.
    pub slab_points: usize,
    pub half_thickness: Real,
    pub cell_size: Real,
}

impl ScanSection {
    /// The loop to use for `p`: the innermost loop enclosing its
    /// projection, else the nearest (as [`crate::section::mesh::Section::select`]).
    pub fn select(&self, p: Point3) -> Option<usize> {
        let outlines: Vec<SectionLoop> = self.loops.iter().map(|l| l.outline.clone()).collect();
        select_loop(&outlines, p)
    }
}

/// A point cloud sorted by height along an axis, for slab sections.
#[derive(Debug)]
pub struct CloudSlicer<'c> {
    cloud: &'c PointCloud,
    axis: Vec3,
    /// Point indices sorted by height.
    order: Vec<u32>,
    /// Heights in sorted order.
    heights: Vec<Real>,
    spacing: Real,
    noise: Real,
}

impl<'c> CloudSlicer<'c> {
    /// Validates the cloud, sorts it by height along `axis` and estimates
    /// the point spacing.
    pub fn new(cloud: &'c PointCloud, axis: Vec3) -> Result<CloudSlicer<'c>, ScanSectionError> {
        cloud.validate()?;
        let axis = axis
            .normalized()
            .ok_or(ScanSectionError::BadAxis(axis.to_array()))?;
        // Sorted by height, ties by index: a radix sort of plain integers
        // (see [`height_key`], [`sort_keyed`]).
        let mut keyed = keyed_heights(&cloud.positions, axis);
        sort_keyed(&mut keyed);
        let (order, heights) = sorted_heights(&keyed, &cloud.positions, axis);
        let (spacing, noise) = estimate_spacing(&cloud.positions, &order, &heights)
            .ok_or(ScanSectionError::Degenerate)?;
        Ok(CloudSlicer {
            cloud,
            axis,
            order,
            heights,
            spacing,
            noise,
        })
    }

    /// The point indices sorted by height (ties by index) and their
    /// heights.
    pub(crate) fn into_sorted(self) -> (Vec<u32>, Vec<Real>) {
        (self.order, self.heights)
    }

    /// The estimated point spacing `s ≈ ρ^{-1/2}` (see the module doc, 1).
    pub fn spacing(&self) -> Real {
        self.spacing
    }

    /// The estimated scatter of the points across the surface (the median
    /// over sampled points of a local quadric's residual; see the module
    /// doc, 1), in the cloud's units.
    pub fn noise(&self) -> Real {
        self.noise
    }

    /// The unit axis.
    pub fn axis(&self) -> Vec3 {
        self.axis
    }

    /// The range of heights `p·axis`.
    pub fn range(&self) -> (Real, Real) {
        (
            self.heights.first().copied().unwrap_or(0.0),
            self.heights.last().copied().unwrap_or(0.0),
        )
    }

    /// The slab section at `{p : p·axis = offset}`.
    pub fn section_at(
        &self,
        offset: Real,
        opts: &ScanSectionOptions,
    ) -> Result<ScanSection, ScanSectionError> {
        if !offset.is_finite() {
            return Err(ScanSectionError::NonFiniteOffset(offset));
        }
        let t = check_len("half_thickness", opts.half_thickness, self.spacing)?;
        let g = check_len("cell_size", opts.cell_size, self.spacing)?;
        let lo = self.heights.partition_point(|&h| h < offset - t);
        let hi = self.heights.partition_point(|&h| h <= offset + t);
        let (min, max) = self.range();
        let needed = opts.min_slab_points.max(3);
        if hi - lo < needed {
            return Err(ScanSectionError::TooFewPoints {
                offset,
                half_thickness: t,
                found: hi - lo,
                needed,
                min,
                max,
            });
        }
        let normals = self.cloud.normals.as_deref().filter(|_| opts.use_normals);
        let slab = Slab {
            positions: &self.cloud.positions,
            normals,
            axis: self.axis,
            offset,
            ids: &self.order[lo..hi],
            half_thickness: t,
        };
        Ok(section_of_slab(&slab, g, opts))
    }
}

/// A slab of a cloud: the points `ids` of `positions` within
/// `half_thickness` of the plane `{p : p·axis = offset}`.
pub(crate) struct Slab<'a> {
    pub positions: &'a [Point3],
    /// The cloud's normals, when used (see [`onto_plane`]).
    pub normals: Option<&'a [Vec3]>,
    /// A unit vector.
    pub axis: Vec3,
    pub offset: Real,
    /// Sorted by height, at least [`ScanSectionOptions::min_slab_points`].
    pub ids: &'a [u32],
    pub half_thickness: Real,
}

/// The section of `slab` with occupancy cells of size `g`: steps 3-5 of
/// the module doc. Shared by [`CloudSlicer::section_at`] and the body
/// cutter (`segment::Cutter`), which finds its slabs without sorting the
/// cloud for every plane.
pub(crate) fn section_of_slab(
    slab: &Slab<'_>,
    mut g: Real,
    opts: &ScanSectionOptions,
) -> ScanSection {
    let &Slab {
        positions,
        normals,
        axis,
        offset,
        ids,
        half_thickness: t,
    } = slab;
    let (e1, e2) = plane_axes(axis, opts.reference);
    let origin = axis * offset;
    let pts: Vec<Point2> = ids
        .iter()
        .map(|&i| {
            let p = positions[i as usize];
            let p = match normals {
                Some(ns) => onto_plane(p, ns[i as usize], axis, offset),
                None => p,
            };
            let d = p - origin;
            Vec2::new(d.dot(e1), d.dot(e2))
        })
        .collect();
    // Image bounds with a margin for the closing.
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (
        Real::INFINITY,
        Real::NEG_INFINITY,
        Real::INFINITY,
        Real::NEG_INFINITY,
    );
    for p in &pts {
        xmin = xmin.min(p.x);
        xmax = xmax.max(p.x);
        ymin = ymin.min(p.y);
        ymax = ymax.max(p.y);
    }
    let r = opts.closing_radius;
    let margin = r + 2;
    loop {
        let w = ((xmax - xmin) / g).floor() as usize + 2 + 2 * margin;
        let h = ((ymax - ymin) / g).floor() as usize + 2 + 2 * margin;
        if w.saturating_mul(h) <= opts.max_cells.max(64) {
            break;
        }
        g *= 1.5;
    }
    let grid = Grid::below(
        Vec2::new(xmin, ymin),
        margin,
        g,
        ((xmax - xmin) / g).floor() as usize + 2 + 2 * margin,
        ((ymax - ymin) / g).floor() as usize + 2 + 2 * margin,
    );
    let cell_of: Vec<usize> = pts.iter().map(|&p| grid.cell(p)).collect();
    let mut occupied = vec![false; grid.w * grid.h];
    for &c in &cell_of {
        occupied[c] = true;
    }
    let closed = grid.close(&occupied, r);
    let (labels, ncomp) = grid.components(&closed);
    // Points of each component.
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); ncomp];
    for (k, &c) in cell_of.iter().enumerate() {
        let l = labels[c];
        if l != NONE {
            members[l as usize].push(k);
        }
    }
    let mut ordered: Vec<(Vec<usize>, bool, usize)> = Vec::new();
    let mut arcs: Vec<(Vec<usize>, Vec<usize>)> = Vec::new();
    for (comp, m) in members.iter().enumerate() {
        if m.len() < opts.min_component_points.max(3) {
            continue;
        }
        match order_component(&grid, &labels, comp as u32, m, &pts, &cell_of) {
            Ordering::Done(Some((reps, closed))) => ordered.push((reps, closed, m.len())),
            Ordering::Done(None) => {}
            Ordering::Arc => {
                // one point per occupied cell stands for the arc while
                // deciding which arcs to join
                let mut sample: Vec<usize> = m.clone();
                sample.sort_unstable_by_key(|&k| (cell_of[k], k));
                sample.dedup_by_key(|k| cell_of[*k]);
                arcs.push((sample, m.clone()));
            }
        }
    }
    for group in merge_arcs(arcs, &pts) {
        if let Some(reps) = order_by_angle(&grid, &group, &pts) {
            ordered.push((reps, false, group.len()));
        }
    }
    let mut loops = Vec::new();
    for (mut reps, closed_ring, raw) in ordered {
        untangle(&mut reps, &pts);
        let planar: Vec<Point3> = reps
            .iter()
            .map(|&k| origin + e1 * pts[k].x + e2 * pts[k].y)
            .collect();
        let mut indices: Vec<usize> = reps.iter().map(|&k| ids[k] as usize).collect();
        let max_gap = (0..planar.len())
            .map(|i| planar[i].distance(planar[(i + 1) % planar.len()]))
            .fold(0.0, Real::max);
        let first = planar[0];
        let Some(outline) = SectionLoop::from_points(planar, e1, e2) else {
            continue;
        };
        if outline.points.first() != Some(&first) {
            indices.reverse();
        }
        loops.push(ScanLoop {
            outline,
            scan_indices: indices,
            raw_points: raw,
            closed_ring,
            max_gap,
        });
    }
    ScanSection {
        plane: Plane {
            origin,
            normal: axis,
        },
        loops,
        slab_points: ids.len(),
        half_thickness: t,
        cell_size: g,
    }
}

/// `(height_key(h), i)` for every point `i` at height `h = p·axis`.
pub(crate) fn keyed_heights(points: &[Point3], axis: Vec3) -> Vec<(u64, u32)> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| (height_key(p.dot(axis)), i as u32))
        .collect()
}

/// The indices of sorted [`keyed_heights`] and the points' heights in
/// that order, the two gathered side by side on two cores (most of the
/// time is the first touch of the fresh arrays' pages).
pub(crate) fn sorted_heights(
    keyed: &[(u64, u32)],
    points: &[Point3],
    axis: Vec3,
) -> (Vec<u32>, Vec<Real>) {
    crate::geom::parallel::join(
        || keyed.iter().map(|k| k.1).collect(),
        || {
            keyed
                .iter()
                .map(|k| points[k.1 as usize].dot(axis))
                .collect()
        },
    )
}

/// Sorts `(key, index)` pairs as `sort_unstable` on the pairs would (by
/// key, ties by index; pairs built in index order end up ordered by key,
/// ties by index), in linear time: a stable LSD radix sort on the keys'
/// high 32 bits (8-bit digits, every digit counted in one pass, a digit
/// all keys share skipped), then each run of keys sharing those bits
/// sorted as pairs (for heights, runs of points within about a
/// millionth of the height of each other: mostly single points). A few
/// passes over 200 000 heights instead of a comparison sort, and half the
/// passes of a radix sort on all 64 bits.
pub(crate) fn sort_keyed(keyed: &mut Vec<(u64, u32)>) {
    let mut counts = vec![[0usize; 257]; 4];
    for k in keyed.iter() {
        for (d, count) in counts.iter_mut().enumerate() {
            count[((k.0 >> (32 + 8 * d)) & 0xff) as usize + 1] += 1;
        }
    }
    let mut scratch = Vec::new();
    for (d, count) in counts.iter_mut().enumerate() {
        if count.contains(&keyed.len()) {
            continue; // every key has this digit
        }
        if scratch.len() != keyed.len() {
            scratch = vec![(0u64, 0u32); keyed.len()];
        }
        for b in 0..256 {
            count[b + 1] += count[b];
        }
        let shift = 32 + 8 * d;
        for k in keyed.iter() {
            let b = ((k.0 >> shift) & 0xff) as usize;
            scratch[count[b]] = *k;
            count[b] += 1;
        }
        std::mem::swap(keyed, &mut scratch);
    }
    let mut i = 0;
    while i < keyed.len() {
        let high = keyed[i].0 >> 32;
        let mut j = i + 1;
        while j < keyed.len() && keyed[j].0 >> 32 == high {
            j += 1;
        }
        if j - i > 1 {
            keyed[i..j].sort_unstable();
        }
        i = j;
    }
}

/// The IEEE total-order bits of a height: a monotone map to `u64`, so
/// `(height_key(h), index)` pairs sort by height, ties by index, as plain
/// integers.
pub(crate) fn height_key(h: Real) -> u64 {
    let b = h.to_bits() as i64;
    (b ^ ((((b >> 63) as u64) >> 1) as i64)) as u64 ^ (1 << 63)
}

/// Removes self-crossings of the ordered loop (local zigzags where bins
/// along a grazing stretch hold points from both sides of the slab) by
/// 2-opt moves: when edges `i` and `j > i` cross, the points `i+1..=j` are
/// reversed, which shortens the loop, so the repair ends. At most `n` moves;
/// what remains is left for the fit to report.
fn untangle(reps: &mut [usize], pts: &[Point2]) {
    let mut q: Vec<Vec2> = reps.iter().map(|&k| pts[k]).collect();
    for _ in 0..reps.len() {
        let Some((i, j)) = crate::curve::fit::find_self_crossing(&q) else {
            return;
        };
        if j <= i + 1 || j >= q.len() {
            return;
        }
        q[i + 1..=j].reverse();
        reps[i + 1..=j].reverse();
    }
}

/// Smallest `|g|²` at which [`onto_plane`] moves a point: `|g| = 0.2`, a
/// surface normal about 11.5° off the axis.
const MIN_TANGENT_SLOPE2: Real = 0.04;

/// Moves `p` (height `h = p·a − c` above the plane `{x : x·a = c}`) within
/// its tangent plane (normal `n`) onto the section plane:
///
/// ```text
/// g = a − n (n·a)          (the axis projected into the tangent plane)
/// p' = p − h g / |g|²      (so that p'·a = c, and p' − p ⟂ n)
/// ```
///
/// On an inclined surface, projecting straight along the axis shifts a
/// point by `h tan θ` sideways (θ the surface's inclination); where the slab
/// sees the surface only on one side of the plane (occlusion, grazing
/// views) that shift does not average out and biases the loop. For a unit
/// axis `|g|` is the sine of the angle between the normal and the axis, and
/// the move is `h / |g|` long: surfaces whose normal lies within about
/// 11.5° of the axis (`|g|² < 0.04`), where the move would grow without
/// bound, and invalid normals are projected straight.
pub fn onto_plane(p: Point3, n: Vec3, a: Vec3, c: Real) -> Point3 {
    let Some(n) = n.normalized() else {
        return p;
    };
    let g = a - n * n.dot(a);
    let g2 = g.norm_squared();
    if g2 < MIN_TANGENT_SLOPE2 {
        return p;
    }
    p - g * ((p.dot(a) - c) / g2)
}

fn check_len(name: &'static str, v: Option<Real>, default: Real) -> Result<Real, ScanSectionError> {
    match v {
        None => Ok(default),
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        Some(x) => Err(ScanSectionError::BadOption {
            name,
            value: x,
            why: "must be finite and positive",
        }),
    }
}

/// Groups `(bin, point)` pairs by bin (in bin order), rejects points more
/// than three cells from the bin's coordinate-wise median, and returns per
/// bin the real point nearest to the mean of the rest.
/// Distances to a cell's mean within this fraction of the cell's area are
/// a tie ([`representatives`]).
const TIE: Real = 1e-9;

fn representatives(mut keys: Vec<(u32, usize)>, pts: &[Point2], cell: Real) -> Vec<usize> {
    keys.sort_unstable();
    let mut reps = Vec::new();
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    for group in keys.chunk_by(|a, b| a.0 == b.0) {
        xs.clear();
        ys.clear();
        xs.extend(group.iter().map(|g| pts[g.1].x));
        ys.extend(group.iter().map(|g| pts[g.1].y));
        let (Some(mx), Some(my)) = (median(&mut xs), median(&mut ys)) else {
            continue;
        };
        let med = Vec2::new(mx, my);
        let kept: Vec<usize> = group
            .iter()
            .map(|g| g.1)
            .filter(|&m| (pts[m] - med).norm_squared() <= 9.0 * cell * cell)
            .collect();
        if !kept.is_empty() {
            let mean = kept.iter().fold(Vec2::ZERO, |s, &m| s + pts[m]) / kept.len() as Real;
            let d = |m: usize| (pts[m] - mean).norm_squared();
            let nearest = kept.iter().map(|&m| d(m)).fold(Real::INFINITY, Real::min);
            // Two points of a cell lie symmetrically about their mean: a
            // tie that rounding (a file's last digit) would break. Ties
            // within TIE of the cell's area go to the first point.
            if let Some(&best) = kept.iter().find(|&&m| d(m) <= nearest + TIE * cell * cell) {
                reps.push(best);
            }
        }
    }
    reps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radix_sort_is_the_pair_sort() {
        let mut rng = crate::geom::rng::Rng::new(3);
        // The radix sort gives the order of the pair sort.
        let check = |mut keyed: Vec<(u64, u32)>| {
            let mut expected = keyed.clone();
            expected.sort_unstable();
            sort_keyed(&mut keyed);
            assert_eq!(keyed, expected);
        };
        let keyed: Vec<(u64, u32)> = (0..5000)
            .map(|i| {
                // Heights with repeats and both signs.
                let h = ((rng.uniform() - 0.5) * 40.0).round() * 0.05;
                (height_key(h), i)
            })
            .collect();
        check(keyed);
        // Keys sharing their high 32 bits (heights a millionth of a
        // millimetre apart), in no index order.
        let keyed: Vec<(u64, u32)> = (0..3000u32)
            .map(|i| {
                let h = 1.0 + ((i * 7919) % 37) as Real * 1e-12 - (i % 3) as Real;
                (height_key(h), i.wrapping_mul(2_654_435_761) % 3001)
            })
            .collect();
        check(keyed);
        // A body's heights, repeats, both signs and high-bit ties among
        // them, in no index order.
        let keyed: Vec<(u64, u32)> = (0..90_000u32)
            .map(|i| {
                let h = match i % 4 {
                    0 => (rng.uniform() - 0.45) * 1.8,
                    1 => ((rng.uniform() - 0.5) * 40.0).round() * 0.05,
                    2 => 0.5 + ((i * 7919) % 37) as Real * 1e-12,
                    _ => -(rng.uniform() * 1e-3),
                };
                (height_key(h), i.wrapping_mul(2_654_435_761) % 90_001)
            })
            .collect();
        check(keyed);
    }
    use crate::assert_near;
    use crate::geom::rng::Rng;
    use std::f64::consts::{PI, TAU};

    /// Points on the lateral surface of a vertical cylinder (axis z through
    /// `c`), angles in `[a0, a1)`, heights in `[-0.05, 0.05]`, radial noise
    /// σ = `noise`.
    fn cylinder_cloud(
        c: Vec2,
        r: Real,
        a0: Real,
        a1: Real,
        n: usize,
        noise: Real,
        rng: &mut Rng,
    ) -> Vec<Point3> {
        (0..n)
            .map(|_| {
                let a = a0 + (a1 - a0) * rng.uniform();
                let rr = r + noise * rng.gaussian();
                Vec3::new(
                    c.x + rr * a.cos(),
                    c.y + rr * a.sin(),
                    -0.05 + 0.1 * rng.uniform(),
                )
            })
            .collect()
    }

    fn angles_increase(l: &ScanLoop, c: Vec2) -> bool {
        let a: Vec<Real> = l
            .outline
            .points
            .iter()
            .map(|p| (p.y - c.y).atan2(p.x - c.x))
            .collect();
        let steps: Vec<Real> = (0..a.len())
            .map(|i| (a[(i + 1) % a.len()] - a[i]).rem_euclid(TAU))
            .collect();
        // every step is forward (less than π) and they add up to one turn
        steps.iter().all(|&s| s < PI) && (steps.iter().sum::<Real>() - TAU).abs() < 1e-9
    }

    #[test]
    fn noisy_ring_gives_one_closed_ccw_loop_of_real_points() {
        let mut rng = Rng::new(5);
        let c = Vec2::new(0.3, -0.2);
        let pts = cylinder_cloud(c, 0.1, 0.0, TAU, 30_000, 0.001, &mut rng);
        let cloud = PointCloud::new(pts.clone()).unwrap();
        let slicer = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
        // 30 000 points on 0.063 m²: ρ^{-1/2} ≈ 1.45 mm
        assert!(
            slicer.spacing() > 0.0008 && slicer.spacing() < 0.003,
            "{}",
            slicer.spacing()
        );
        let s = slicer
            .section_at(0.0, &ScanSectionOptions::default())
            .unwrap();
        assert_eq!(s.loops.len(), 1);
        let l = &s.loops[0];
        assert!(l.closed_ring);
        assert!(angles_increase(l, c));
        for p in &l.outline.points {
            assert!(pts.iter().any(|q| q.x == p.x && q.y == p.y));
            assert!(p.z.abs() <= s.half_thickness);
            assert_near!((Vec2::new(p.x, p.y) - c).norm(), 0.1, 0.005);
        }
        assert_near!(l.outline.area, PI * 0.01, 3e-4);
        assert!(l.max_gap < 4.0 * s.cell_size);
    }

    /// A scanner's points where its rays meet a ring: four views, each
    /// with its rays on a lattice twice as fine as the cells (two points a
    /// cell, symmetric about their mean, and every other one on a cell's
    /// edge when the edges start at the first point). The section of the
    /// cloud moved by a nanometre, or written to twelve decimals and read
    /// back, is the section moved: rounding broke those ties and edges,
    /// and the outlines differed by 2 % of their length.
    #[test]
    fn a_lattice_scan_moved_by_a_rounding_gives_the_same_section() {
        let s = 0.003;
        let mut rng = Rng::new(11);
        let mut pts = Vec::new();
        for k in -66..=66 {
            let a = k as Real * s / 2.0;
            let depth = (0.1 * 0.1 - a * a).sqrt();
            for side in [-1.0, 1.0] {
                let d = side * depth + 0.0005 * rng.gaussian();
                let z = 0.004 * (rng.uniform() - 0.5);
                pts.push(Vec3::new(0.4 + a, -0.2 + d, z));
                pts.push(Vec3::new(0.4 + d, -0.2 + a, z));
            }
        }
        let opts = ScanSectionOptions {
            cell_size: Some(s),
            half_thickness: Some(0.003),
            ..ScanSectionOptions::default()
        };
        let section = |shift: Vec3, round: bool| {
            let moved: Vec<Point3> = pts
                .iter()
                .map(|&p| {
                    let q = p + shift;
                    let r = |c: Real| {
                        if round {
                            format!("{c:.12}").parse().unwrap()
                        } else {
                            c
                        }
                    };
                    Vec3::new(r(q.x), r(q.y), r(q.z))
                })
                .collect();
            let cloud = PointCloud::new(moved).unwrap();
            let slicer = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
            let sec = slicer.section_at(0.0, &opts).unwrap();
            sec.loops
                .iter()
                .map(|l| {
                    l.outline
                        .points
                        .iter()
                        .map(|&p| p - shift)
                        .collect::<Vec<_>>()
                })
                .collect::<Vec<_>>()
        };
        let given = section(Vec3::ZERO, false);
        assert_eq!(given.len(), 1);
        for (shift, round) in [(Vec3::new(1e-9, -1e-9, 0.0), false), (Vec3::ZERO, true)] {
            let other = section(shift, round);
            assert_eq!(other.len(), given.len());
            assert_eq!(other[0].len(), given[0].len(), "{shift:?} {round}");
            for (a, b) in given[0].iter().zip(&other[0]) {
                assert!((*a - *b).norm() < 1e-9, "{a:?} {b:?}");
            }
        }
    }

    /// A quarter of the ring unseen: ordered by angle across the gap, the
    /// gap reported, and the curve fit bridges it.
    #[test]
    fn ring_with_a_quarter_missing_is_ordered_and_bridged() {
        let mut rng = Rng::new(6);
        let c = Vec2::new(0.0, 0.0);
        let pts = cylinder_cloud(c, 0.1, 0.0, 1.5 * PI, 25_000, 0.001, &mut rng);
        let cloud = PointCloud::new(pts).unwrap();
        let slicer = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
        let s = slicer
            .section_at(0.0, &ScanSectionOptions::default())
            .unwrap();
        assert_eq!(s.loops.len(), 1);
        let l = &s.loops[0];
        assert!(!l.closed_ring);
        assert!(angles_increase(l, c));
        // the chord across the missing quarter, √2 r
        assert_near!(l.max_gap, 0.1 * 2f64.sqrt(), 0.01);
        for smoothing in [0.0, DEFAULT_SCAN_SMOOTHING] {
            let opts = crate::curve::fit::FitOptions {
                smoothing,
                ..Default::default()
            };
            let fit = crate::curve::fit::fit_loop(&l.outline.points, &opts).unwrap();
            // the fitted curve's points in the gap stay near the circle
            let worst = fit
                .curve
                .sample(720)
                .iter()
                .map(|p| ((Vec2::new(p.x, p.y)).norm() - 0.1).abs())
                .fold(0.0, Real::max);
            if smoothing > 0.0 {
                assert!(worst < 0.01, "smoothed fit strays {worst} from the circle");
            }
        }
    }

    #[test]
    fn two_parts_give_two_loops_and_selection_works() {
        let mut rng = Rng::new(7);
        let mut pts = cylinder_cloud(
            Vec2::new(-0.1, 0.0),
            0.06,
            0.0,
            TAU,
            15_000,
            0.001,
            &mut rng,
        );
        pts.extend(cylinder_cloud(
            Vec2::new(0.1, 0.0),
            0.06,
            0.0,
            TAU,
            15_000,
            0.001,
            &mut rng,
        ));
        let cloud = PointCloud::new(pts).unwrap();
        let slicer = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
        let s = slicer
            .section_at(0.01, &ScanSectionOptions::default())
            .unwrap();
        assert_eq!(s.loops.len(), 2);
        let i = s.select(Vec3::new(0.1, 0.0, 0.0)).unwrap();
        assert!(s.loops[i].outline.centroid.x > 0.09);
    }

    /// A non-star-shaped closed outline (an L), ordered along its contour.
    #[test]
    fn non_star_shaped_loop_is_ordered_along_the_contour() {
        // The L: (0,0) → (0.2,0) → (0.2,0.05) → (0.05,0.05) → (0.05,0.2) → (0,0.2)
        let corners = [
            Vec2::new(0.0, 0.0),
            Vec2::new(0.2, 0.0),
            Vec2::new(0.2, 0.05),
            Vec2::new(0.05, 0.05),
            Vec2::new(0.05, 0.2),
            Vec2::new(0.0, 0.2),
        ];
        let lens: Vec<Real> = (0..6)
            .map(|i| (corners[(i + 1) % 6] - corners[i]).norm())
            .collect();
        let total: Real = lens.iter().sum();
        let mut rng = Rng::new(8);
        let pts: Vec<Point3> = (0..20_000)
            .map(|_| {
                let mut s = rng.uniform() * total;
                let mut i = 0;
                while s > lens[i] && i < 5 {
                    s -= lens[i];
                    i += 1;
                }
                let q = corners[i] + (corners[(i + 1) % 6] - corners[i]) * (s / lens[i]);
                Vec3::new(
                    q.x + 0.0005 * rng.gaussian(),
                    q.y + 0.0005 * rng.gaussian(),
                    -0.05 + 0.1 * rng.uniform(),
                )
            })
            .collect();
        let cloud = PointCloud::new(pts).unwrap();
        let slicer = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
        let s = slicer
            .section_at(0.0, &ScanSectionOptions::default())
            .unwrap();
        assert_eq!(s.loops.len(), 1);
        let l = &s.loops[0];
        assert!(l.closed_ring);
        // area of the L: 0.2·0.05 + 0.05·0.15 = 0.0175
        assert_near!(l.outline.area, 0.0175, 0.0015);
        // ordered: the polygon through the representatives is about as long
        // as the L (a shuffled order would be many times longer)
        assert_near!(l.outline.perimeter / total, 1.0, 0.1);
    }

    #[test]
    fn solid_blob_is_traced_around_its_outside() {
        let mut rng = Rng::new(9);
        let pts: Vec<Point3> = (0..20_000)
            .map(|_| {
                let r = 0.05 * rng.uniform().sqrt();
                let a = TAU * rng.uniform();
                Vec3::new(r * a.cos(), r * a.sin(), 0.004 * rng.uniform())
            })
            .collect();
        let cloud = PointCloud::new(pts).unwrap();
        let slicer = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
        let s = slicer
            .section_at(
                0.002,
                &ScanSectionOptions {
                    half_thickness: Some(0.003),
                    ..Default::default()
                },
            )
            .unwrap();
        assert_eq!(s.loops.len(), 1);
        assert!(angles_increase(&s.loops[0], Vec2::ZERO));
        assert_near!(s.loops[0].outline.area / (PI * 0.0025), 1.0, 0.15);
    }

    /// An elongated loop (a torso at the shoulders, 2.7 : 1) broken by
    /// three holes, two of them close together on one side: no pair of its
    /// three arcs qualifies (each pair has a junction across the third
    /// arc's place, where the radii differ by far more than 25 %), the
    /// three together do, and the loop comes out whole. So at every cell
    /// size from the points' spacing (0.84 mm) to 1.3 mm: the cells' phase
    /// along the ring breaks it at sparse places too (up to five arcs,
    /// fragments of a few cells), and those are joined as well.
    #[test]
    fn an_elongated_ring_broken_three_times_is_joined() {
        let mut rng = Rng::new(5);
        let (a, b) = (0.27, 0.10);
        // Holes of 0.06 rad (≥ 6 mm, several cells) at these parameters.
        let holes = [0.0, 0.9, 1.6];
        let mut pts = Vec::new();
        while pts.len() < 60_000 {
            let t = TAU * rng.uniform();
            if holes.iter().any(|h| (t - h).abs() < 0.03) {
                continue;
            }
            let r = 1.0 + 0.002 * rng.gaussian();
            pts.push(Vec3::new(
                a * r * t.cos(),
                b * r * t.sin(),
                -0.01 + 0.02 * rng.uniform(),
            ));
        }
        let cloud = PointCloud::new(pts).unwrap();
        let slicer = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
        for cell in std::iter::once(None).chain((0..11).map(|k| Some(0.0008 + 0.00005 * k as Real)))
        {
            let opts = ScanSectionOptions {
                cell_size: cell,
                ..ScanSectionOptions::default()
            };
            let s = slicer.section_at(0.0, &opts).unwrap();
            assert_eq!(
                s.loops.len(),
                1,
                "{cell:?}: {:?}",
                s.loops.iter().map(|l| l.raw_points).collect::<Vec<_>>()
            );
            assert_near!(s.loops[0].outline.area.abs() / (PI * a * b), 1.0, 0.03);
            assert!(angles_increase(&s.loops[0], Vec2::ZERO));
        }
    }

    /// A ring broken into two arcs by two holes is joined into one loop;
    /// two separate parts each missing their inner side (legs whose inner
    /// thighs are unseen) stay two loops, and so does a torso with an arm
    /// in its shadow.
    #[test]
    fn broken_rings_are_joined_and_separate_parts_are_not() {
        let mut rng = Rng::new(11);
        let mut pts = cylinder_cloud(
            Vec2::ZERO,
            0.1,
            0.2,
            0.2 + 0.4 * TAU,
            12_000,
            0.001,
            &mut rng,
        );
        pts.extend(cylinder_cloud(
            Vec2::ZERO,
            0.1,
            0.2 + 0.55 * TAU,
            0.2 + 0.9 * TAU,
            10_000,
            0.001,
            &mut rng,
        ));
        let cloud = PointCloud::new(pts).unwrap();
        let s = CloudSlicer::new(&cloud, Vec3::Z)
            .unwrap()
            .section_at(0.0, &ScanSectionOptions::default())
            .unwrap();
        assert_eq!(s.loops.len(), 1);
        assert!(angles_increase(&s.loops[0], Vec2::ZERO));

        // legs: C-shapes open toward each other
        let mut pts = cylinder_cloud(
            Vec2::new(-0.1, 0.0),
            0.07,
            0.25 * PI,
            1.75 * PI,
            12_000,
            0.001,
            &mut rng,
        );
        pts.extend(cylinder_cloud(
            Vec2::new(0.1, 0.0),
            0.07,
            -0.75 * PI,
            0.75 * PI,
            12_000,
            0.001,
            &mut rng,
        ));
        let cloud = PointCloud::new(pts).unwrap();
        let s = CloudSlicer::new(&cloud, Vec3::Z)
            .unwrap()
            .section_at(0.0, &ScanSectionOptions::default())
            .unwrap();
        assert_eq!(s.loops.len(), 2);

        // torso with a hole facing an arm
        let mut pts = cylinder_cloud(
            Vec2::ZERO,
            0.15,
            -0.8 * PI,
            0.8 * PI,
            20_000,
            0.001,
            &mut rng,
        );
        pts.extend(cylinder_cloud(
            Vec2::new(-0.22, 0.0),
            0.04,
            0.0,
            TAU,
            6_000,
            0.001,
            &mut rng,
        ));
        let cloud = PointCloud::new(pts).unwrap();
        let s = CloudSlicer::new(&cloud, Vec3::Z)
            .unwrap()
            .section_at(0.0, &ScanSectionOptions::default())
            .unwrap();
        assert_eq!(s.loops.len(), 2);
    }

    /// A point on an inclined plane moved within it lands on the section
    /// plane and stays on the surface.
    #[test]
    fn onto_plane_stays_on_the_surface() {
        let n = Vec3::new(1.0, 0.0, -1.0).normalized().unwrap(); // 45° wall
        let p = Vec3::new(0.3, 0.2, 0.3 + 0.004); // on the wall x − z = −0.004
        let q = onto_plane(p, n, Vec3::Z, 0.3);
        assert_near!(q.z, 0.3, 1e-15);
        assert_near!((q - p).dot(n), 0.0, 1e-15);
        assert_near!(q.y, 0.2, 1e-15);
        // nearly horizontal surfaces are projected straight
        let flat = Vec3::new(0.1, 0.0, 1.0);
        assert_eq!(onto_plane(p, flat, Vec3::Z, 0.3), p);
    }

    /// A loop with a local zigzag is untangled into a simple polygon.
    #[test]
    fn zigzags_are_untangled() {
        let mut pts: Vec<Point2> = (0..40)
            .map(|k| {
                let a = TAU * k as Real / 40.0;
                Vec2::new(a.cos(), a.sin())
            })
            .collect();
        pts.swap(10, 11);
        pts.swap(25, 27);
        let mut reps: Vec<usize> = (0..40).collect();
        assert!(crate::curve::fit::find_self_crossing(&pts).is_some());
        untangle(&mut reps, &pts);
        let q: Vec<Point2> = reps.iter().map(|&k| pts[k]).collect();
        assert!(crate::curve::fit::find_self_crossing(&q).is_none());
        let mut sorted = reps.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..40).collect::<Vec<_>>());
    }

    #[test]
    fn bad_input_is_a_typed_error() {
        let mut rng = Rng::new(10);
        let pts = cylinder_cloud(Vec2::ZERO, 0.1, 0.0, TAU, 2000, 0.001, &mut rng);
        let cloud = PointCloud::new(pts).unwrap();
        let slicer = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
        let err = slicer
            .section_at(1.0, &ScanSectionOptions::default())
            .unwrap_err();
        assert!(matches!(
            err,
            ScanSectionError::TooFewPoints { found: 0, .. }
        ));
        assert!(err.to_string().contains("holds 0 points"));
        assert!(matches!(
            slicer.section_at(f64::NAN, &ScanSectionOptions::default()),
            Err(ScanSectionError::NonFiniteOffset(_))
        ));
        assert!(matches!(
            slicer.section_at(
                0.0,
                &ScanSectionOptions {
                    cell_size: Some(-1.0),
                    ..Default::default()
                }
            ),
            Err(ScanSectionError::BadOption {
                name: "cell_size",
                ..
            })
        ));
        assert!(matches!(
            CloudSlicer::new(&cloud, Vec3::ZERO),
            Err(ScanSectionError::BadAxis(_))
        ));
        assert!(matches!(
            CloudSlicer::new(&PointCloud::default(), Vec3::Z),
            Err(ScanSectionError::Cloud(MeshError::NoVertices))
        ));
        let same = PointCloud::new(vec![Vec3::ZERO; 10]).unwrap();
        assert!(matches!(
            CloudSlicer::new(&same, Vec3::Z),
            Err(ScanSectionError::Degenerate)
        ));
    }
}
