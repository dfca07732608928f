//! Plane sections of triangle meshes: the closed loops where a plane cuts a
//! surface (method.md §8.2, "mesh: chained segments").
//!
//! # The construction
//!
//! For a plane with unit normal `n` at offset `c` (the points `p` with
//! `p·n = c`), every vertex gets a height `h_i = p_i·n − c`. A vertex is
//! *above* when `h_i ≥ 0` and *below* otherwise. Counting a vertex exactly on
//! the plane as above is the same as moving the plane an infinitesimal step
//! along `−n`: every edge then either crosses or does not, with no
//! ambiguous cases, and the loops close. (A face lying in the plane is above
//! it; the plane through the top face of a cube cuts its sides just below
//! the top and yields the square, the plane through its bottom face yields
//! nothing.)
//!
//! An edge `(i, j)` with one end above and one below crosses at
//!
//! ```text
//! t = h_i / (h_i − h_j),     x = p_i + t (p_j − p_i)
//! ```
//!
//! computed once per mesh edge, keyed by the sorted vertex pair (so two
//! triangles sharing the edge share the point exactly). A triangle with
//! mixed sides has exactly two crossing edges and contributes one segment
//! between their points. Segments are chained through the shared edge
//! points; on a closed manifold surface every crossing edge belongs to two
//! segments and the chains are closed loops. Where a surface is open or
//! non-manifold, chains end at edges with one (or more than two) segments;
//! chains whose ends lie within a tolerance are stitched, the rest are
//! reported as open chains, never a panic.
//!
//! Each loop is oriented counter-clockwise about `n`: in plane coordinates
//! `(x, y) = ((p−o)·e1, (p−o)·e2)` with `e1 × e2 = n`, its signed area
//!
//! ```text
//! A = ½ Σ_k (x_k y_{k+1} − x_{k+1} y_k)
//! ```
//!
//! is positive.
//!
//! # Many parallel planes
//!
//! [`MeshSlicer`] precomputes the vertex heights along the axis once and
//! sorts the triangles by their lowest height, so a plane only visits the
//! triangles whose height interval contains it (a binary search bounds the
//! candidates; the few unusually tall triangles are kept in a short list
//! that every plane checks).

use crate::curve::trig::Frame;
use crate::geom::math::{Point2, Point3, Real, Vec2, Vec3};
use crate::geom::mesh::{Mesh, MeshError};
use crate::geom::stats::{median, nth_smallest};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A multiplicative hash for edge keys (two vertex indices): the default
/// SipHash is several times slower and its DoS resistance is not needed.
#[derive(Default)]
struct EdgeHasher(u64);

impl Hasher for EdgeHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(b)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }
    fn write_u32(&mut self, v: u32) {
        self.0 = (self.0.rotate_left(32) ^ u64::from(v)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

type EdgeMap = HashMap<(u32, u32), u32, BuildHasherDefault<EdgeHasher>>;
use thiserror::Error;

/// A plane through `origin` with unit normal `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub origin: Point3,
    /// Unit length.
    pub normal: Vec3,
}

impl Plane {
    /// A plane from a point on it and a normal (normalised here). Errors when
    /// the normal is zero or anything is not finite.
    pub fn new(origin: Point3, normal: Vec3) -> Result<Plane, SectionError> {
        match normal.normalized() {
            Some(n) if origin.is_finite() => Ok(Plane { origin, normal: n }),
            _ => Err(SectionError::BadPlane {
                origin: origin.to_array(),
                normal: normal.to_array(),
            }),
        }
    }

    /// The offset `c = origin·n`: the plane is `{p : p·n = c}`.
    #[inline]
    pub fn offset(&self) -> Real {
        self.origin.dot(self.normal)
    }

    /// Signed distance of `p` along the normal.
    #[inline]
    pub fn height(&self, p: Point3) -> Real {
        (p - self.origin).dot(self.normal)
    }
}

/// What went wrong while sectioning.
#[derive(Debug, Error, PartialEq)]
pub enum SectionError {
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    #[error("the plane is not valid: origin {origin:?}, normal {normal:?} (the normal must be finite and non-zero)")]
    BadPlane {
        origin: [Real; 3],
        normal: [Real; 3],
    },
    #[error("the plane at offset {offset} along {axis:?} misses the mesh, which spans [{min}, {max}] along that axis")]
    Missed {
        offset: Real,
        axis: [Real; 3],
        min: Real,
        max: Real,
    },
    #[error("the section offset {0} is not finite")]
    NonFiniteOffset(Real),
    #[error("the mesh's triangles are all degenerate (zero extent along every axis)")]
    Degenerate,
}

/// Options of [`section_mesh`] and [`MeshSlicer`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionOptions {
    /// Open chains whose ends lie closer than this fraction of the mesh's
    /// bounding-box diagonal are joined (cracks between unwelded duplicate
    /// vertices, small non-manifold spots). Default `1e-5`
    /// (17 µm on a 1.7 m body).
    pub stitch_tolerance: Real,
    /// Loops whose area is below this fraction of the squared bounding-box
    /// diagonal are dropped as degenerate (a plane touching a vertex or an
    /// edge). Default `1e-12`.
    pub min_relative_area: Real,
    /// Direction of the in-plane axis `e1` of every loop frame (projected
    /// into the plane); `None` uses a fixed perpendicular of the normal
    /// ([`Vec3::any_perpendicular`]). Pass the body's front direction to get
    /// frames that agree with the fit's reference.
    pub reference: Option<Vec3>,
}

impl Default for SectionOptions {
    fn default() -> Self {
        SectionOptions {
            stitch_tolerance: 1e-5,
            min_relative_area: 1e-12,
            reference: None,
        }
    }
}

/// One closed section loop, counter-clockwise about the plane normal.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionLoop {
    /// The loop's points in order (the closing segment from the last back to
    /// the first is implied; the first point is not repeated).
    pub points: Vec<Point3>,
    /// The plane frame: `origin` is the area centroid, `e1 × e2` is the
    /// plane normal.
    pub frame: Frame,
    /// Enclosed area (positive).
    pub area: Real,
    /// Length of the closed polygon.
    pub perimeter: Real,
    /// Area centroid (the centroid of the enclosed region, in the plane).
    pub centroid: Point3,
}

impl SectionLoop {
    /// A loop from ordered points in a plane with axes `e1`, `e2`
    /// (`e1 × e2` the normal): reoriented counter-clockwise, with area,
    /// perimeter and centroid. `None` when it encloses no area.
    pub(crate) fn from_points(mut points: Vec<Point3>, e1: Vec3, e2: Vec3) -> Option<SectionLoop> {
        let first = *points.first()?;
        let plane: Vec<Point2> = points
            .iter()
            .map(|&p| {
                let d = p - first;
                Vec2::new(d.dot(e1), d.dot(e2))
            })
            .collect();
        let (area, c) = polygon_area_centroid(&plane)?;
        if area < 0.0 {
            points.reverse();
        }
        let centroid = first + e1 * c.x + e2 * c.y;
        let perimeter = closed_length(&points);
        Some(SectionLoop {
            points,
            frame: Frame {
                origin: centroid,
                e1,
                e2,
            },
            area: area.abs(),
            perimeter,
            centroid,
        })
    }

    /// The loop in its own plane coordinates (relative to the centroid).
    pub fn plane_points(&self) -> Vec<Point2> {
        self.points
            .iter()
            .map(|&p| self.frame.to_plane(p))
            .collect()
    }

    /// The loop's points with each edge's midpoint after its first point
    /// (the closing edge's last): `2n` points in the loop's order, for a
    /// fit to the polygon's edges as well as its corners.
    pub fn with_edge_midpoints(&self) -> Vec<Point3> {
        let n = self.points.len();
        let mut out = Vec::with_capacity(2 * n);
        for (i, &a) in self.points.iter().enumerate() {
            out.push(a);
            if n > 1 {
                out.push((a + self.points[(i + 1) % n]) * 0.5);
            }
        }
        out
    }

    /// The median length of the polygon's edges (closing edge included),
    /// at least the smallest positive number: the spacing a new straight
    /// side gets ([`push_between`]).
    pub fn median_edge(&self) -> Real {
        let n = self.points.len();
        let mut edges: Vec<Real> = (0..n)
            .map(|i| self.points[i].distance(self.points[(i + 1) % n]))
            .collect();
        median(&mut edges).unwrap_or(0.0).max(Real::MIN_POSITIVE)
    }

    /// True when `p` (projected into the plane) lies inside the loop
    /// (even-odd rule).
    pub fn contains(&self, p: Point3) -> bool {
        point_in_polygon(self.frame.to_plane(p), &self.plane_points())
    }

    /// Distance in the plane from the projection of `p` to the loop polygon.
    pub fn distance(&self, p: Point3) -> Real {
        distance_to_polygon(self.frame.to_plane(p), &self.plane_points())
    }

    /// The part of the loop on the side `(p − origin)·normal ≤ 0` of a
    /// clipping plane (Sutherland–Hodgman against one half-space), closed
    /// along the plane's line in the section: where a loop runs out into a
    /// neighbouring part (a horizontal torso cut through arms held out
    /// sideways), the part keeps its own piece with a straight side. The
    /// new side gets points at the loop's median edge length, so a fit sees
    /// it as densely as the rest. `None` when nothing (or no area) is left;
    /// the loop itself when it lies wholly on the kept side.
    pub fn clipped(&self, origin: Point3, normal: Vec3) -> Option<SectionLoop> {
        let side: Vec<Real> = self
            .points
            .iter()
            .map(|&p| (p - origin).dot(normal))
            .collect();
        if side.iter().all(|&s| s <= 0.0) {
            return Some(self.clone());
        }
        let n = self.points.len();
        let step = self.median_edge();
        let mut out: Vec<Point3> = Vec::with_capacity(n + 16);
        // The point where the kept polygon last left the half-space.
        let mut exit: Option<Point3> = None;
        for i in 0..n {
            let (a, b) = (self.points[i], self.points[(i + 1) % n]);
            let (sa, sb) = (side[i], side[(i + 1) % n]);
            if sa <= 0.0 {
                out.push(a);
            }
            if (sa <= 0.0) != (sb <= 0.0) {
                let x = a + (b - a) * (sa / (sa - sb));
                if sa <= 0.0 {
                    out.push(x);
                    exit = Some(x);
                } else {
                    // Entering again: fill the straight side from the exit.
                    if let Some(e) = exit.take() {
                        push_between(&mut out, e, x, step);
                    }
                    out.push(x);
                }
            }
        }
        if let (Some(e), Some(&first)) = (exit, out.first()) {
            // The polygon started outside: the side closes onto the first point.
            push_between(&mut out, e, first, step);
        }
        SectionLoop::from_points(out, self.frame.e1, self.frame.e2)
    }
}

/// `m` points evenly spaced by arc length along a closed polygon.
pub fn resample_closed(points: &[Point3], m: usize) -> Vec<Point3> {
    let n = points.len();
    let total: Real = (0..n)
        .map(|i| points[i].distance(points[(i + 1) % n]))
        .sum();
    if n == 0 || total <= 0.0 {
        return points.to_vec();
    }
    let mut out = Vec::with_capacity(m);
    let (mut i, mut acc) = (0usize, 0.0);
    for k in 0..m {
        let target = total * k as Real / m as Real;
        while i < n {
            let d = points[i].distance(points[(i + 1) % n]);
            if acc + d >= target {
                let u = if d > 0.0 { (target - acc) / d } else { 0.0 };
                out.push(points[i] + (points[(i + 1) % n] - points[i]) * u);
                break;
            }
            acc += d;
            i += 1;
        }
    }
    out
}

/// Points strictly between `a` and `b`, about `step` apart.
pub(crate) fn push_between(out: &mut Vec<Point3>, a: Point3, b: Point3, step: Real) {
    let k = (a.distance(b) / step).floor() as usize;
    for j in 1..k {
        out.push(a + (b - a) * (j as Real / k as Real));
    }
}

/// All loops of one plane section.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    pub plane: Plane,
    /// Closed loops, each counter-clockwise about the plane normal, in a
    /// deterministic order (by the mesh edges they start on).
    pub loops: Vec<SectionLoop>,
    /// Chains that could not be closed (open or non-manifold surface), each
    /// in order along the chain.
    pub open_chains: Vec<Vec<Point3>>,
}

impl Section {
    /// The index of the loop to use for `p`: the innermost (smallest) loop
    /// enclosing `p` projected into the plane, else the loop nearest to it.
    /// `None` only when there are no loops.
    pub fn select(&self, p: Point3) -> Option<usize> {
        select_loop(&self.loops, p)
    }
}

pub(crate) fn select_loop(loops: &[SectionLoop], p: Point3) -> Option<usize> {
    let inside = loops
        .iter()
        .enumerate()
        .filter(|(_, l)| l.contains(p))
        .min_by(|a, b| a.1.area.total_cmp(&b.1.area))
        .map(|(i, _)| i);
    inside.or_else(|| {
        loops
            .iter()
            .enumerate()
            .map(|(i, l)| (i, l.distance(p)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    })
}

/// The section of `mesh` by `plane`. For many parallel planes build a
/// [`MeshSlicer`] once instead.
///
/// ```
/// use trigbody_core::internals::geom::shapes;
/// use trigbody_core::internals::section::mesh::{section_mesh, Plane, SectionOptions};
/// use trigbody_core::Vec3;
/// let sphere = shapes::uv_sphere(Vec3::ZERO, 1.0, 64, 128);
/// let plane = Plane::new(Vec3::new(0.0, 0.0, 0.5), Vec3::Z).unwrap();
/// let s = section_mesh(&sphere, &plane, &SectionOptions::default()).unwrap();
/// assert_eq!(s.loops.len(), 1);
/// // a circle of radius sqrt(1 - 0.25), inscribed polygon: slightly less
/// let r = (0.75f64).sqrt();
/// assert!((s.loops[0].perimeter / (std::f64::consts::TAU * r) - 1.0).abs() < 2e-3);
/// ```
pub fn section_mesh(
    mesh: &Mesh,
    plane: &Plane,
    opts: &SectionOptions,
) -> Result<Section, SectionError> {
    let slicer = MeshSlicer::new(mesh, plane.normal, opts)?;
    let mut s = slicer.section_at(plane.offset())?;
    s.plane = *plane;
    Ok(s)
}

/// Precomputed heights and triangle order of a mesh along one axis, for
/// cutting it with many planes normal to that axis.
#[derive(Debug)]
pub struct MeshSlicer<'m> {
    mesh: &'m Mesh,
    axis: Vec3,
    e1: Vec3,
    e2: Vec3,
    opts: SectionOptions,
    /// Vertex heights `p·axis`.
    heights: Vec<Real>,
    /// "Short" triangles sorted by their lowest vertex height.
    sorted: Vec<u32>,
    sorted_min: Vec<Real>,
    /// Largest height span among the short triangles.
    short_span: Real,
    /// Triangles taller than `short_span` (checked by every plane).
    tall: Vec<u32>,
    min: Real,
    max: Real,
    diagonal: Real,
}

impl<'m> MeshSlicer<'m> {
    /// Validates `mesh` and prepares it for sections normal to `axis`
    /// (normalised here).
    pub fn new(
        mesh: &'m Mesh,
        axis: Vec3,
        opts: &SectionOptions,
    ) -> Result<MeshSlicer<'m>, SectionError> {
        mesh.validate()?;
        let axis = axis.normalized().ok_or(SectionError::BadPlane {
            origin: [0.0; 3],
            normal: axis.to_array(),
        })?;
        let bounds = mesh
            .bounds()
            .ok_or(SectionError::Mesh(MeshError::NoVertices))?;
        let diagonal = bounds.diagonal();
        if diagonal.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(SectionError::Degenerate);
        }
        let (e1, e2) = plane_axes(axis, opts.reference);
        let heights: Vec<Real> = mesh.positions.iter().map(|p| p.dot(axis)).collect();
        let tri_range = |t: &[u32; 3]| {
            let h = [
                heights[t[0] as usize],
                heights[t[1] as usize],
                heights[t[2] as usize],
            ];
            (h[0].min(h[1]).min(h[2]), h[0].max(h[1]).max(h[2]))
        };
        // Split off unusually tall triangles: a span above 8 times the 90th
        // percentile span would make every plane scan a long candidate range.
        let mut spans: Vec<Real> = mesh
            .triangles
            .iter()
            .map(|t| {
                let (lo, hi) = tri_range(t);
                hi - lo
            })
            .collect();
        let k = ((spans.len() * 9) / 10).min(spans.len().saturating_sub(1));
        let p90 = nth_smallest(&mut spans, k).unwrap_or(0.0);
        let limit = 8.0 * p90;
        let mut short: Vec<(Real, u32)> = Vec::with_capacity(mesh.triangles.len());
        let mut tall = Vec::new();
        let mut short_span: Real = 0.0;
        for (i, t) in mesh.triangles.iter().enumerate() {
            let (lo, hi) = tri_range(t);
            if hi - lo > limit {
                tall.push(i as u32);
            } else {
                short_span = short_span.max(hi - lo);
                short.push((lo, i as u32));
            }
        }
        short.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let (min, max) = heights
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), &h| {
                (lo.min(h), hi.max(h))
            });
        Ok(MeshSlicer {
            mesh,
            axis,
            e1,
            e2,
            opts: *opts,
            heights,
            sorted_min: short.iter().map(|s| s.0).collect(),
            sorted: short.iter().map(|s| s.1).collect(),
            short_span,
            tall,
            min,
            max,
            diagonal,
        })
    }

    /// The unit axis (the normal of every plane).
    pub fn axis(&self) -> Vec3 {
        self.axis
    }

    /// The range `[min, max]` of vertex heights `p·axis`.
    pub fn range(&self) -> (Real, Real) {
        (self.min, self.max)
    }

    /// The section by the plane `{p : p·axis = offset}`.
    pub fn section_at(&self, offset: Real) -> Result<Section, SectionError> {
        if !offset.is_finite() {
            return Err(SectionError::NonFiniteOffset(offset));
        }
        let missed = || SectionError::Missed {
            offset,
            axis: self.axis.to_array(),
            min: self.min,
            max: self.max,
        };
        if offset < self.min || offset > self.max {
            return Err(missed());
        }
        let plane = Plane {
            origin: self.axis * offset,
            normal: self.axis,
        };
        // Candidates: short triangles with min ≤ offset and
        // min ≥ offset − short_span, plus the tall ones.
        let hi = self.sorted_min.partition_point(|&m| m <= offset);
        let lo = self.sorted_min[..hi].partition_point(|&m| m < offset - self.short_span);
        let candidates = self.sorted[lo..hi].iter().chain(self.tall.iter());

        let h = |v: u32| self.heights[v as usize] - offset;
        let mut node_of = EdgeMap::default();
        let mut nodes: Vec<Point3> = Vec::new();
        let mut segments: Vec<[u32; 2]> = Vec::new();
        let mut node = |a: u32, b: u32, nodes: &mut Vec<Point3>| -> u32 {
            let key = if a < b { (a, b) } else { (b, a) };
            *node_of.entry(key).or_insert_with(|| {
                let (ha, hb) = (h(key.0), h(key.1));
                let pa = self.mesh.positions[key.0 as usize];
                let pb = self.mesh.positions[key.1 as usize];
                // A vertex on the plane is its own crossing point, exactly
                // (so the crossings of all its edges coincide).
                nodes.push(if ha == 0.0 {
                    pa
                } else if hb == 0.0 {
                    pb
                } else {
                    pa + (pb - pa) * (ha / (ha - hb))
                });
                (nodes.len() - 1) as u32
            })
        };
        for &ti in candidates {
            let t = self.mesh.triangles[ti as usize];
            let above = [h(t[0]) >= 0.0, h(t[1]) >= 0.0, h(t[2]) >= 0.0];
            if above[0] == above[1] && above[1] == above[2] {
                continue;
            }
            let mut ends = [0u32; 2];
            let mut k = 0;
            for e in 0..3 {
                let (a, b) = (e, (e + 1) % 3);
                if above[a] != above[b] {
                    ends[k] = node(t[a], t[b], &mut nodes);
                    k += 1;
                }
            }
            segments.push(ends);
        }
        if segments.is_empty() {
            return Err(missed());
        }
        let (closed, open) = chain_segments(nodes.len(), &segments);
        let to_points = |ids: &[u32]| dedup_points(ids.iter().map(|&i| nodes[i as usize]));
        let mut loops_pts: Vec<Vec<Point3>> = closed
            .iter()
            .map(|c| {
                let mut p = to_points(c);
                while p.len() > 1 && p.first() == p.last() {
                    p.pop();
                }
                p
            })
            .collect();
        let open_pts: Vec<Vec<Point3>> = open.iter().map(|c| to_points(c)).collect();
        let (stitched, open_chains) = stitch(open_pts, self.opts.stitch_tolerance * self.diagonal);
        loops_pts.extend(stitched);

        let min_area = self.opts.min_relative_area * self.diagonal * self.diagonal;
        let loops = loops_pts
            .into_iter()
            .filter(|p| p.len() >= 3)
            .filter_map(|p| SectionLoop::from_points(p, self.e1, self.e2))
            .filter(|l| l.area > min_area)
            .collect();
        Ok(Section {
            plane,
            loops,
            open_chains,
        })
    }

    /// Sections at `count ≥ 1` evenly spaced offsets strictly inside the
    /// height range: `min + (k + ½)(max − min)/count`. Planes that miss
    /// (possible only for degenerate meshes) are skipped.
    pub fn sections_evenly(&self, count: usize) -> Vec<Section> {
        let step = (self.max - self.min) / count.max(1) as Real;
        (0..count)
            .filter_map(|k| self.section_at(self.min + (k as Real + 0.5) * step).ok())
            .collect()
    }
}

/// In-plane axes `(e1, e2)` with `e1 × e2 = n`; `e1` along `reference`
/// projected into the plane when that is possible.
pub(crate) fn plane_axes(n: Vec3, reference: Option<Vec3>) -> (Vec3, Vec3) {
    let e1 = reference
        .and_then(|r| (r - n * r.dot(n)).normalized())
        .unwrap_or_else(|| n.any_perpendicular());
    (e1, n.cross(e1))
}

/// Chains segments (pairs of node ids) through shared nodes. Returns the
/// closed cycles and the open chains (which start and end at nodes that do
/// not have exactly two segments). Deterministic: walks start from the
/// lowest-numbered unused segment.
fn chain_segments(node_count: usize, segments: &[[u32; 2]]) -> (Vec<Vec<u32>>, Vec<Vec<u32>>) {
    // Node → incident segments in compressed rows.
    let mut start = vec![0u32; node_count + 1];
    for s in segments {
        start[s[0] as usize + 1] += 1;
        start[s[1] as usize + 1] += 1;
    }
    for i in 0..node_count {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut incident = vec![0u32; start[node_count] as usize];
    for (si, s) in segments.iter().enumerate() {
        for &n in s {
            incident[fill[n as usize] as usize] = si as u32;
            fill[n as usize] += 1;
        }
    }
    let degree = |n: u32| start[n as usize + 1] - start[n as usize];
    let mut used = vec![false; segments.len()];
    // Walk from `from` along segment `seg`, until a node of degree ≠ 2 or a
    // node without unused segments.
    let walk = |from: u32, seg: usize, used: &mut Vec<bool>| -> Vec<u32> {
        let mut chain = vec![from];
        let (mut at, mut seg) = (from, seg);
        loop {
            used[seg] = true;
            let s = segments[seg];
            let next = if s[0] == at { s[1] } else { s[0] };
            chain.push(next);
            at = next;
            if degree(at) != 2 {
                break;
            }
            let range = start[at as usize] as usize..start[at as usize + 1] as usize;
            match incident[range].iter().find(|&&x| !used[x as usize]) {
                Some(&x) => seg = x as usize,
                None => break,
            }
        }
        chain
    };
    let mut open = Vec::new();
    for n in 0..node_count as u32 {
        if degree(n) == 2 {
            continue;
        }
        for k in start[n as usize]..start[n as usize + 1] {
            let seg = incident[k as usize] as usize;
            if !used[seg] {
                open.push(walk(n, seg, &mut used));
            }
        }
    }
    let mut closed = Vec::new();
    for seg in 0..segments.len() {
        if !used[seg] {
            let mut c = walk(segments[seg][0], seg, &mut used);
            if c.len() > 1 && c.first() == c.last() {
                c.pop();
                closed.push(c);
            } else {
                open.push(c);
            }
        }
    }
    (closed, open)
}

/// Points without consecutive exact duplicates: several edges through a
/// vertex on the plane all cross at that vertex.
fn dedup_points(points: impl Iterator<Item = Point3>) -> Vec<Point3> {
    let mut out: Vec<Point3> = Vec::new();
    for p in points {
        if out.last() != Some(&p) {
            out.push(p);
        }
    }
    out
}

/// Joins open chains whose ends are within `tol`: a chain whose end meets
/// its own start is closed; otherwise the nearest other chain end (within
/// `tol`) is appended (reversed if needed). Returns the closed loops and the
/// chains that stay open.
fn stitch(mut chains: Vec<Vec<Point3>>, tol: Real) -> (Vec<Vec<Point3>>, Vec<Vec<Point3>>) {
    let mut closed = Vec::new();
    let mut open = Vec::new();
    while let Some(mut c) = chains.pop() {
        while let (Some(&first), Some(&last)) = (c.first(), c.last()) {
            if c.len() > 2 && first.distance(last) <= tol {
                if first == last {
                    c.pop();
                }
                closed.push(std::mem::take(&mut c));
                break;
            }
            // Nearest end of another chain to our last point.
            let best = chains
                .iter()
                .enumerate()
                .flat_map(|(i, o)| {
                    let a = o.first().map(|p| (i, false, p.distance(last)));
                    let b = o.last().map(|p| (i, true, p.distance(last)));
                    a.into_iter().chain(b)
                })
                .filter(|x| x.2 <= tol)
                .min_by(|x, y| x.2.total_cmp(&y.2));
            match best {
                Some((i, reversed, _)) => {
                    let mut o = chains.swap_remove(i);
                    if reversed {
                        o.reverse();
                    }
                    let skip = usize::from(o.first() == c.last());
                    c.extend(o.into_iter().skip(skip));
                }
                None => {
                    open.push(std::mem::take(&mut c));
                    break;
                }
            }
        }
    }
    closed.reverse();
    open.reverse();
    (closed, open)
}

/// Signed area and area centroid of a closed polygon (shoelace formula):
///
/// ```text
/// A  = ½ Σ (x_k y_{k+1} − x_{k+1} y_k)
/// Cx = Σ (x_k + x_{k+1})(x_k y_{k+1} − x_{k+1} y_k) / (6A)
/// ```
///
/// `None` when the area is zero or not finite.
pub fn polygon_area_centroid(p: &[Point2]) -> Option<(Real, Point2)> {
    if p.len() < 3 {
        return None;
    }
    // Relative to the first point, for accuracy far from the origin.
    let o = p[0];
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..p.len() {
        let (u, w) = (p[k] - o, p[(k + 1) % p.len()] - o);
        let cr = u.cross(w);
        a2 += cr;
        cx += (u.x + w.x) * cr;
        cy += (u.y + w.y) * cr;
    }
    if a2 == 0.0 || !a2.is_finite() {
        return None;
    }
    Some((0.5 * a2, o + Vec2::new(cx, cy) / (3.0 * a2)))
}

/// Length of a closed polyline (including the closing segment).
pub fn closed_length(p: &[Point3]) -> Real {
    if p.len() < 2 {
        return 0.0;
    }
    (0..p.len())
        .map(|k| p[k].distance(p[(k + 1) % p.len()]))
        .sum()
}

/// Even-odd point-in-polygon test.
pub fn point_in_polygon(q: Point2, poly: &[Point2]) -> bool {
    let mut inside = false;
    let n = poly.len();
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        if (a.y > q.y) != (b.y > q.y) {
            let x = a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if q.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Distance from `q` to a closed polygon's edges.
pub fn distance_to_polygon(q: Point2, poly: &[Point2]) -> Real {
    let n = poly.len();
    (0..n)
        .map(|k| distance_to_segment(q, poly[k], poly[(k + 1) % n]))
        .fold(Real::INFINITY, Real::min)
}

/// The parameter `t ∈ [0, 1]` of the point of segment `[a, b]` nearest to
/// `q` (that point is `a + t (b − a)`; 0 for a degenerate segment).
pub fn segment_parameter(q: Point2, a: Point2, b: Point2) -> Real {
    let ab = b - a;
    let l2 = ab.norm_squared();
    if l2 > 0.0 {
        ((q - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Distance from `q` to the segment `[a, b]`.
pub fn distance_to_segment(q: Point2, a: Point2, b: Point2) -> Real {
    let t = segment_parameter(q, a, b);
    (a + (b - a) * t - q).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_loop(half: Real, n_side: usize) -> SectionLoop {
        let mut pts = Vec::new();
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        for k in 0..4 {
            let (x0, y0) = corners[k];
            let (x1, y1) = corners[(k + 1) % 4];
            for j in 0..n_side {
                let t = j as Real / n_side as Real;
                pts.push(Vec3::new(
                    half * (x0 + (x1 - x0) * t),
                    half * (y0 + (y1 - y0) * t),
                    0.5,
                ));
            }
        }
        SectionLoop::from_points(pts, Vec3::X, Vec3::Y).unwrap()
    }

    #[test]
    fn edge_midpoints_follow_each_corner() {
        let sq = SectionLoop::from_points(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 2.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
            ],
            Vec3::X,
            Vec3::Y,
        )
        .unwrap();
        let m = sq.with_edge_midpoints();
        assert_eq!(m.len(), 8);
        for (k, &p) in sq.points.iter().enumerate() {
            assert_eq!(m[2 * k], p);
            let next = sq.points[(k + 1) % 4];
            assert_eq!(m[2 * k + 1], (p + next) * 0.5);
        }
        // The polygon is unchanged: same area through the doubled points.
        let again = SectionLoop::from_points(m, Vec3::X, Vec3::Y).unwrap();
        assert!((again.area - sq.area).abs() < 1e-12);
    }

    #[test]
    fn clipping_a_square_keeps_the_exact_rectangle() {
        let sq = square_loop(1.0, 8);
        // Keep x <= 0.5: a 1.5 x 2 rectangle.
        let c = sq.clipped(Vec3::new(0.5, 0.0, 0.0), Vec3::X).unwrap();
        assert!((c.area - 3.0).abs() < 1e-12, "{}", c.area);
        assert!((c.perimeter - 7.0).abs() < 1e-12, "{}", c.perimeter);
        assert!(c
            .points
            .iter()
            .all(|p| p.x <= 0.5 + 1e-12 && (p.z - 0.5).abs() < 1e-15));
        // The new side is sampled like the rest (edge 0.25): no gap longer.
        let n = c.points.len();
        let longest = (0..n)
            .map(|i| c.points[i].distance(c.points[(i + 1) % n]))
            .fold(0.0, Real::max);
        assert!(longest <= 0.25 + 1e-12, "{longest}");
        // Whole loop on the kept side: unchanged; nothing kept: None.
        assert_eq!(sq.clipped(Vec3::new(2.0, 0.0, 0.0), Vec3::X).unwrap(), sq);
        assert!(sq.clipped(Vec3::new(-2.0, 0.0, 0.0), Vec3::X).is_none());
    }

    #[test]
    fn clipping_starts_anywhere_on_the_loop() {
        let sq = square_loop(1.0, 8);
        for roll in 0..sq.points.len() {
            let mut pts = sq.points.clone();
            pts.rotate_left(roll);
            let l = SectionLoop::from_points(pts, Vec3::X, Vec3::Y).unwrap();
            // A slanted plane: keep x + y <= 1 (the square minus a corner
            // triangle of legs 1: area 4 - 0.5).
            let c = l
                .clipped(Vec3::new(0.5, 0.5, 0.0), Vec3::new(1.0, 1.0, 0.0))
                .unwrap();
            assert!((c.area - 3.5).abs() < 1e-12, "roll {roll}: {}", c.area);
        }
    }
    use crate::assert_near;
    use crate::geom::shapes;
    use std::f64::consts::{PI, TAU};

    fn opts() -> SectionOptions {
        SectionOptions::default()
    }

    fn is_ccw(l: &SectionLoop, n: Vec3) -> bool {
        let pts: Vec<Point2> = l
            .points
            .iter()
            .map(|&p| Vec2::new(p.dot(l.frame.e1), p.dot(l.frame.e2)))
            .collect();
        l.frame.e1.cross(l.frame.e2).dot(n) > 0.999
            && polygon_area_centroid(&pts).is_some_and(|(a, _)| a > 0.0)
    }

    /// A regular polygon with `n` sides inscribed in a circle of radius r has
    /// perimeter 2 n r sin(π/n) and area ½ n r² sin(2π/n).
    #[test]
    fn cylinder_sections_are_inscribed_polygons_at_any_height() {
        let (r, n) = (0.3, 40);
        let m = shapes::cylinder(Vec3::new(1.0, -2.0, 0.5), r, 2.0, 7, n);
        let slicer = MeshSlicer::new(&m, Vec3::Z, &opts()).unwrap();
        for z in [0.51, 0.8, 0.5 + 2.0 / 6.0, 1.7, 2.49] {
            let s = slicer.section_at(z).unwrap();
            assert_eq!(s.loops.len(), 1, "z = {z}");
            assert!(s.open_chains.is_empty());
            let l = &s.loops[0];
            assert!(is_ccw(l, Vec3::Z));
            assert_near!(
                l.perimeter,
                2.0 * n as Real * r * (PI / n as Real).sin(),
                1e-12
            );
            assert_near!(
                l.area,
                0.5 * n as Real * r * r * (TAU / n as Real).sin(),
                1e-12
            );
            assert_near!(l.centroid.distance(Vec3::new(1.0, -2.0, z)), 0.0, 1e-12);
            for p in &l.points {
                assert_near!(p.z, z, 1e-12);
            }
        }
    }

    #[test]
    fn sphere_sections_are_circles_of_known_radius() {
        let m = shapes::uv_sphere(Vec3::new(0.2, 0.1, -0.3), 1.0, 180, 360);
        let slicer = MeshSlicer::new(&m, Vec3::Z, &opts()).unwrap();
        for z in [-0.9, -0.5, 0.0, 0.33, 0.95] {
            let s = slicer.section_at(z - 0.3).unwrap();
            assert_eq!(s.loops.len(), 1);
            let l = &s.loops[0];
            let r = (1.0 - z * z).sqrt();
            // chordal error of the faceted sphere is ~ (π/180)²/8 relative
            assert_near!(l.perimeter / (TAU * r), 1.0, 5e-4);
            for p in &l.points {
                let d = Vec2::new(p.x - 0.2, p.y - 0.1).norm();
                assert!(d <= r + 1e-9 && d >= r * (1.0 - 5e-4), "{d} vs {r}");
            }
        }
    }

    #[test]
    fn oblique_sections_and_ccw_about_any_normal() {
        let m = shapes::uv_sphere(Vec3::ZERO, 1.0, 60, 120);
        for n in [
            Vec3::new(1.0, 1.0, 0.3),
            Vec3::new(0.0, -1.0, 0.0),
            -Vec3::Z,
        ] {
            let plane = Plane::new(Vec3::ZERO, n).unwrap();
            let s = section_mesh(&m, &plane, &opts()).unwrap();
            assert_eq!(s.loops.len(), 1);
            assert!(is_ccw(&s.loops[0], plane.normal));
            assert_near!(s.loops[0].area / PI, 1.0, 3e-3);
            assert_near!(s.loops[0].centroid.norm(), 0.0, 1e-9);
        }
    }

    /// Planes exactly through a ring of vertices: the vertices count as
    /// above, the loop passes through them, closed and not duplicated.
    #[test]
    fn plane_exactly_through_vertices() {
        let n = 24;
        let m = shapes::cylinder(Vec3::ZERO, 1.0, 3.0, 4, n);
        let slicer = MeshSlicer::new(&m, Vec3::Z, &opts()).unwrap();
        let s = slicer.section_at(1.0).unwrap();
        assert_eq!(s.loops.len(), 1);
        assert!(s.open_chains.is_empty());
        assert_eq!(s.loops[0].points.len(), n);
        assert_near!(
            s.loops[0].perimeter,
            2.0 * n as Real * (PI / n as Real).sin(),
            1e-12
        );
        // through a single vertex of a sphere's equator (oblique plane)
        let sph = shapes::uv_sphere(Vec3::ZERO, 1.0, 10, 12);
        let v = sph.positions[5];
        let plane = Plane::new(v, Vec3::new(0.3, -0.2, 1.0)).unwrap();
        let s = section_mesh(&sph, &plane, &opts()).unwrap();
        assert_eq!(s.loops.len(), 1);
        assert!(s.loops[0].points.contains(&v));
    }

    /// Planes through coplanar faces: the top cap of a cylinder (cut just
    /// below: the full polygon) and the bottom cap (nothing: a clear error).
    #[test]
    fn plane_through_coplanar_faces() {
        let n = 16;
        let m = shapes::cylinder(Vec3::ZERO, 1.0, 2.0, 3, n);
        let slicer = MeshSlicer::new(&m, Vec3::Z, &opts()).unwrap();
        let top = slicer.section_at(2.0).unwrap();
        assert_eq!(top.loops.len(), 1);
        assert_eq!(top.loops[0].points.len(), n);
        assert!(matches!(
            slicer.section_at(0.0),
            Err(SectionError::Missed { .. })
        ));
        // a vertical plane through the flat caps' centres and two rim vertices
        let s = section_mesh(&m, &Plane::new(Vec3::ZERO, Vec3::Y).unwrap(), &opts()).unwrap();
        assert_eq!(s.loops.len(), 1);
        assert_near!(s.loops[0].area, 4.0, 1e-12);
    }

    #[test]
    fn two_cylinders_and_torus_give_two_loops() {
        let m = shapes::merge(&[
            shapes::cylinder(Vec3::new(-1.0, 0.0, 0.0), 0.4, 1.0, 5, 32),
            shapes::cylinder(Vec3::new(1.0, 0.0, 0.0), 0.4, 1.0, 5, 32),
        ]);
        let s = section_mesh(
            &m,
            &Plane::new(Vec3::new(0.0, 0.0, 0.3), Vec3::Z).unwrap(),
            &opts(),
        )
        .unwrap();
        assert_eq!(s.loops.len(), 2);
        assert!(s.loops.iter().all(|l| is_ccw(l, Vec3::Z)));
        let right = s.select(Vec3::new(1.1, 0.0, 5.0)).unwrap();
        assert!(s.loops[right].centroid.x > 0.9);
        let near_left = s.select(Vec3::new(-3.0, 0.0, 0.0)).unwrap();
        assert!(s.loops[near_left].centroid.x < -0.9);

        // A torus cut through its axis: two discs; cut across it: two
        // concentric circles, both counter-clockwise, the innermost enclosing
        // loop is selected for a point in the hole.
        let t = shapes::torus(Vec3::ZERO, 2.0, 0.5, 96, 48);
        let s = section_mesh(&t, &Plane::new(Vec3::ZERO, Vec3::X).unwrap(), &opts()).unwrap();
        assert_eq!(s.loops.len(), 2);
        for l in &s.loops {
            assert_near!(l.area / (PI * 0.25), 1.0, 5e-3);
        }
        let s = section_mesh(
            &t,
            &Plane::new(Vec3::new(0.0, 0.0, 0.1), Vec3::Z).unwrap(),
            &opts(),
        )
        .unwrap();
        assert_eq!(s.loops.len(), 2);
        assert!(s.loops.iter().all(|l| is_ccw(l, Vec3::Z)));
        let i = s.select(Vec3::new(0.1, 0.0, 0.0)).unwrap();
        assert!(s.loops[i].area < PI * 2.0 * 2.0);
    }

    #[test]
    fn open_surfaces_give_open_chains_and_cracks_are_stitched() {
        // An open tube (caps removed), cut at the ends of its rings: closed.
        let mut m = shapes::cylinder(Vec3::ZERO, 1.0, 1.0, 3, 12);
        let caps = 2 * 12;
        m.triangles.truncate(m.triangles.len() - caps);
        let s = section_mesh(
            &m,
            &Plane::new(Vec3::new(0.0, 0.0, 0.3), Vec3::Z).unwrap(),
            &opts(),
        )
        .unwrap();
        assert_eq!(s.loops.len(), 1);
        // Remove one wall quad: an open chain, no panic.
        let mut cut = m.clone();
        cut.triangles.drain(0..2);
        let s = section_mesh(
            &cut,
            &Plane::new(Vec3::new(0.0, 0.0, 0.3), Vec3::Z).unwrap(),
            &opts(),
        )
        .unwrap();
        assert!(s.loops.is_empty());
        assert_eq!(s.open_chains.len(), 1);
        // 12 vertical and 12 diagonal crossing edges, one quad's two gone
        assert_eq!(s.open_chains[0].len(), 23);
        // Unweld the seam (duplicate the vertices of column 0): the chain
        // ends coincide and are stitched into a loop.
        let mut unwelded = m.clone();
        let n0 = unwelded.positions.len() as u32;
        let col0: Vec<u32> = (0..3).map(|i| i * 12).collect();
        for &v in &col0 {
            unwelded.positions.push(unwelded.positions[v as usize]);
        }
        for t in unwelded.triangles.iter_mut().take(2 * 12 * 2) {
            // triangles of the last column (j = 11) refer to column 0 as j+1
            let in_last_col = t.iter().any(|&v| v % 12 == 11);
            if in_last_col {
                for v in t.iter_mut() {
                    if let Some(k) = col0.iter().position(|&c| c == *v) {
                        *v = n0 + k as u32;
                    }
                }
            }
        }
        let s = section_mesh(
            &unwelded,
            &Plane::new(Vec3::new(0.0, 0.0, 0.3), Vec3::Z).unwrap(),
            &opts(),
        )
        .unwrap();
        assert_eq!(s.loops.len(), 1, "open: {:?}", s.open_chains.len());
        assert!(s.open_chains.is_empty());
        assert_eq!(s.loops[0].points.len(), 24);
    }

    #[test]
    fn bad_input_is_a_typed_error() {
        let m = shapes::uv_sphere(Vec3::ZERO, 1.0, 8, 8);
        let err = section_mesh(
            &m,
            &Plane::new(Vec3::new(0.0, 0.0, 2.0), Vec3::Z).unwrap(),
            &opts(),
        )
        .unwrap_err();
        assert!(matches!(err, SectionError::Missed { .. }));
        assert!(err.to_string().contains("misses the mesh"));
        assert!(Plane::new(Vec3::ZERO, Vec3::ZERO).is_err());
        assert!(Plane::new(Vec3::new(f64::NAN, 0.0, 0.0), Vec3::Z).is_err());
        assert_eq!(
            section_mesh(
                &Mesh::default(),
                &Plane::new(Vec3::ZERO, Vec3::Z).unwrap(),
                &opts()
            ),
            Err(SectionError::Mesh(MeshError::NoVertices))
        );
        let flat = Mesh {
            positions: vec![Vec3::ZERO; 3],
            normals: None,
            triangles: vec![[0, 1, 2]],
        };
        assert_eq!(
            section_mesh(&flat, &Plane::new(Vec3::ZERO, Vec3::Z).unwrap(), &opts()),
            Err(SectionError::Degenerate)
        );
        let slicer = MeshSlicer::new(&m, Vec3::Z, &opts()).unwrap();
        assert!(matches!(
            slicer.section_at(f64::NAN),
            Err(SectionError::NonFiniteOffset(_))
        ));
    }

    /// Far from the origin and rotated, the same section.
    #[test]
    fn invariant_under_rigid_motion() {
        let m = shapes::torus(Vec3::ZERO, 2.0, 0.5, 48, 24);
        let base = section_mesh(
            &m,
            &Plane::new(Vec3::new(0.0, 0.0, 0.2), Vec3::Z).unwrap(),
            &opts(),
        )
        .unwrap();
        let shift = Vec3::new(1e5, -3e4, 7e3);
        let (c, s) = (0.6, 0.8);
        let rot = |p: Vec3| Vec3::new(c * p.x - s * p.z, p.y, s * p.x + c * p.z);
        let mut moved = m.clone();
        for p in &mut moved.positions {
            *p = rot(*p) + shift;
        }
        let plane = Plane::new(rot(Vec3::new(0.0, 0.0, 0.2)) + shift, rot(Vec3::Z)).unwrap();
        let s2 = section_mesh(&moved, &plane, &opts()).unwrap();
        assert_eq!(s2.loops.len(), base.loops.len());
        let mut a: Vec<Real> = base.loops.iter().map(|l| l.area).collect();
        let mut b: Vec<Real> = s2.loops.iter().map(|l| l.area).collect();
        a.sort_by(Real::total_cmp);
        b.sort_by(Real::total_cmp);
        for (x, y) in a.iter().zip(&b) {
            assert_near!(*x, *y, 1e-6);
        }
    }

    #[test]
    fn stick_body_has_expected_loop_counts() {
        let m = shapes::stick_body(1);
        let slicer = MeshSlicer::new(&m, Vec3::Z, &opts()).unwrap();
        assert_eq!(slicer.section_at(0.4).unwrap().loops.len(), 2);
        assert_eq!(slicer.section_at(1.1).unwrap().loops.len(), 3);
        assert_eq!(slicer.section_at(1.6).unwrap().loops.len(), 1);
        let all = slicer.sections_evenly(80);
        assert_eq!(all.len(), 80);
        assert!(all
            .iter()
            .all(|s| !s.loops.is_empty() && s.open_chains.is_empty()));
    }
}
