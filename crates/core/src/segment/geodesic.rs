//! Arms found on the body's own surface, whatever the pose: distances along
//! the surface from the crotch are largest at the hands, feet and head top
//! (an arm touching or crossing the torso, or raised above the head, is
//! still a separate sheet of a mesh), and level sets of the distance from
//! a hand are rings around the arm up to where they spread over the
//! shoulder. A mesh's surface is its edges; a cloud's, a graph of the
//! cubes its points fill ([`cloud_graph`]: an arm closer to the torso than
//! a cube joins it there). The segmentation joins its sliced arms with
//! these ([`super::arms`]): alone where the slices find no arm, else to
//! follow a bent forearm out to the hand.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::Mesh;
use crate::geom::stats::median;
use std::borrow::Cow;
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::OnceLock;

/// Where the body is, for [`Surface::new`]. Lengths in the input's units.
pub(super) struct BodyQuery {
    pub crotch: Point3,
    /// The top of the trunk path (the head's last loop).
    pub head: Point3,
    pub up: Vec3,
    /// The floor's height along `up` and the body's height `H`.
    pub floor: Real,
    pub extent: Real,
}

/// An arm found on the surface.
pub(super) struct SurfaceArm {
    /// Ring centroids and radii from the shoulder end out to the hand.
    pub axis: Vec<(Point3, Real)>,
    /// The shoulder end of the rings.
    pub armpit: Point3,
    /// The hand's extremity.
    pub tip: Point3,
}

/// Ring width of the level sets along an arm, a fraction of `H` (at least
/// the mesh's median edge, so a coarse mesh's rings are not empty).
const BAND: Real = 0.01;
/// A ring wider than this many times the arm's median ring has reached
/// the shoulder.
const SHOULDER_WIDE: Real = 1.6;
/// How far past a wide ring (fraction of `H`) the rings must stay as wide
/// for it to be the shoulder's.
const SHOULDER_STAYS: Real = 0.05;
/// The cube side (fraction of `H`) of a cloud's surface graph: a few
/// scanner spacings, well under an arm's width.
const CLOUD_CELL: Real = 0.006;
/// Most cubes of a cloud's dense grid (the cube grows beyond).
const CLOUD_CUBES: Real = 8.0e6;
/// Extremities closer than this (fraction of `H`) are one (a hand's
/// fingertips, a foot's toes).
const EXTREMITY_GAP: Real = 0.12;

/// The mesh's edges as a symmetric adjacency list with lengths.
struct SurfaceGraph {
    start: Vec<usize>,
    next: Vec<(u32, Real)>,
    /// The median edge length.
    median_edge: Real,
}

impl SurfaceGraph {
    fn new(m: &Mesh) -> SurfaceGraph {
        let n = m.positions.len();
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(6 * m.triangles.len());
        for t in &m.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a != b && (a as usize) < n && (b as usize) < n {
                    edges.push((a, b));
                    edges.push((b, a));
                }
            }
        }
        SurfaceGraph::of_edges(edges, &m.positions)
    }

    /// The graph of directed `edges` (both directions given) between
    /// `pos`, with lengths; duplicates merged.
    fn of_edges(mut edges: Vec<(u32, u32)>, pos: &[Point3]) -> SurfaceGraph {
        let n = pos.len();
        edges.sort_unstable();
        edges.dedup();
        let mut start = vec![0usize; n + 1];
        for &(a, _) in &edges {
            start[a as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let next: Vec<(u32, Real)> = edges
            .iter()
            .map(|&(a, b)| (b, pos[a as usize].distance(pos[b as usize])))
            .collect();
        let median_edge = median(&mut next.iter().map(|e| e.1).collect::<Vec<_>>()).unwrap_or(0.0);
        SurfaceGraph {
            start,
            next,
            median_edge,
        }
    }

    /// Dijkstra from `source` (infinite where it does not reach).
    fn distances(&self, source: u32) -> Vec<Real> {
        let n = self.start.len() - 1;
        let mut d = vec![Real::INFINITY; n];
        let mut heap = BinaryHeap::new();
        d[source as usize] = 0.0;
        heap.push(Queued(0.0, source));
        while let Some(Queued(du, u)) = heap.pop() {
            if du > d[u as usize] {
                continue;
            }
            for &(v, w) in &self.next[self.start[u as usize]..self.start[u as usize + 1]] {
                let dv = du + w;
                if dv < d[v as usize] {
                    d[v as usize] = dv;
                    heap.push(Queued(dv, v));
                }
            }
        }
        d
    }

    fn neighbours(&self, v: usize) -> impl Iterator<Item = usize> + '_ {
        self.next[self.start[v]..self.start[v + 1]]
            .iter()
            .map(|e| e.0 as usize)
    }
}

/// A min-heap entry (distance, vertex), ties by vertex.
#[derive(PartialEq)]
struct Queued(Real, u32);
impl Eq for Queued {}
impl Ord for Queued {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then_with(|| o.1.cmp(&self.1))
    }
}
impl PartialOrd for Queued {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// The vertices' shares of the surface: a third of each incident
/// triangle's area.
fn vertex_areas(m: &Mesh) -> Vec<Real> {
    let mut a = vec![0.0; m.positions.len()];
    for t in &m.triangles {
        let [p, q, r] = t.map(|i| m.positions[i as usize]);
        let third = (q - p).cross(r - p).norm() / 6.0;
        for &i in t {
            a[i as usize] += third;
        }
    }
    a
}

/// The local maxima of `d` (no neighbour farther), farthest first, each at
/// least `gap` from every one kept before it.
fn extremities(g: &SurfaceGraph, d: &[Real], pos: &[Point3], gap: Real) -> Vec<usize> {
    let mut maxima: Vec<usize> = (0..d.len())
        .filter(|&v| d[v].is_finite() && g.neighbours(v).all(|u| d[u] <= d[v]))
        .collect();
    maxima.sort_by(|&a, &b| d[b].total_cmp(&d[a]).then(a.cmp(&b)));
    let mut kept: Vec<usize> = Vec::new();
    for v in maxima {
        if kept.iter().all(|&k| pos[k].distance(pos[v]) >= gap) {
            kept.push(v);
        }
    }
    kept
}

/// The arm whose hand is vertex `tip`: rings of the distance from it, up
/// to the first ring wider than [`SHOULDER_WIDE`] times the median ring.
/// Centroids and radii from the shoulder end out to the hand.
fn arm_from_tip(
    g: &SurfaceGraph,
    pos: &[Point3],
    areas: &[Real],
    tip: usize,
    extent: Real,
) -> Option<Vec<(Point3, Real)>> {
    let d = g.distances(tip as u32);
    let band = (BAND * extent).max(g.median_edge);
    let count = (0.6 * extent / band).ceil() as usize;
    let mut sums = vec![(Vec3::ZERO, 0.0); count];
    for (v, &dv) in d.iter().enumerate() {
        let k = (dv / band) as usize;
        if dv.is_finite() && k < count {
            sums[k].0 += pos[v] * areas[v];
            sums[k].1 += areas[v];
        }
    }
    let centroid: Vec<Option<Point3>> = sums
        .iter()
        .map(|&(s, w)| (w > 0.0).then(|| s / w))
        .collect();
    let mut spread = vec![(0.0, 0.0); count];
    for (v, &dv) in d.iter().enumerate() {
        let k = (dv / band) as usize;
        if let Some(c) = centroid.get(k).copied().flatten() {
            spread[k].0 += pos[v].distance(c) * areas[v];
            spread[k].1 += areas[v];
        }
    }
    let rings: Vec<Option<(Point3, Real)>> = (0..count)
        .map(|k| centroid[k].map(|c| (c, spread[k].0 / spread[k].1)))
        .collect();
    // Past the hand (0.15 H), the first ring wider than the median of the
    // rings since the hand's middle, and the rings over the next
    // [`SHOULDER_STAYS`] as wide (their median), is the shoulder: a bent
    // elbow's ring is as wide, but the upper arm's rings after it are not.
    let past_hand = (0.15 * extent / band).ceil() as usize;
    let stays = (SHOULDER_STAYS * extent / band).ceil() as usize;
    let mut end = None;
    let widths =
        |r: &[Option<(Point3, Real)>]| -> Vec<Real> { r.iter().flatten().map(|x| x.1).collect() };
    for k in past_hand..count {
        let Some((_, r)) = rings[k] else { continue };
        let mut before = widths(&rings[past_hand / 2..k]);
        if before.len() < 3 {
            continue;
        }
        let Some(wide) = median(&mut before).map(|m| SHOULDER_WIDE * m) else {
            continue;
        };
        let mut after = widths(&rings[k + 1..(k + 1 + stays).min(count)]);
        if r > wide && median(&mut after).is_none_or(|m| m > wide) {
            end = Some(k);
            break;
        }
    }
    let end = end?;
    let axis: Vec<(Point3, Real)> = rings[..end].iter().rev().flatten().copied().collect();
    (axis.len() >= 5).then_some(axis)
}

/// A cloud's surface graph: the centroids of its points in cubes of side
/// `cell`, each linked to those of the 26 cubes around it (limbs farther
/// apart than a cube stay apart) and weighing its point count; the cubes
/// are laid from the cloud's lowest corner, so a moved cloud gives the same
/// graph. `None` for no points or a cell that is not a positive length.
fn cloud_graph(points: &[Point3], cell: Real) -> Option<(Vec<Point3>, SurfaceGraph, Vec<Real>)> {
    if !(cell > 0.0 && cell.is_finite()) || points.is_empty() {
        return None;
    }
    // A dense grid of cubes (grown when the cloud spans too many).
    let (lo, cell, [nx, ny, nz]) = crate::geom::mesh::grid_layout(points, cell, CLOUD_CUBES);
    let index = |p: Point3| {
        let [x, y, z] = crate::geom::mesh::grid_cell(p, lo, cell, [nx, ny, nz]);
        (z * ny + y) * nx + x
    };
    const NONE: u32 = u32::MAX;
    let mut slot = vec![NONE; nx * ny * nz];
    let mut cubes: Vec<(usize, Vec3, usize)> = Vec::new();
    for p in points.iter().filter(|p| p.is_finite()) {
        let c = index(*p);
        if slot[c] == NONE {
            slot[c] = cubes.len() as u32;
            cubes.push((c, Vec3::ZERO, 0));
        }
        let cube = &mut cubes[slot[c] as usize];
        cube.1 += *p;
        cube.2 += 1;
    }
    // Numbered in grid order, whatever the points' order.
    cubes.sort_unstable_by_key(|c| c.0);
    for (k, c) in cubes.iter().enumerate() {
        slot[c.0] = k as u32;
    }
    let pos: Vec<Point3> = cubes.iter().map(|c| c.1 / c.2 as Real).collect();
    let weights: Vec<Real> = cubes.iter().map(|c| c.2 as Real).collect();
    let mut edges = Vec::new();
    for (a, &(c, _, _)) in cubes.iter().enumerate() {
        let (x, y, z) = (c % nx, (c / nx) % ny, c / (nx * ny));
        for dz in z.saturating_sub(1)..(z + 2).min(nz) {
            for dy in y.saturating_sub(1)..(y + 2).min(ny) {
                for dx in x.saturating_sub(1)..(x + 2).min(nx) {
                    let b = slot[(dz * ny + dy) * nx + dx];
                    if b != NONE && b as usize != a {
                        edges.push((a as u32, b));
                    }
                }
            }
        }
    }
    let g = SurfaceGraph::of_edges(edges, &pos);
    Some((pos, g, weights))
}

/// Ring centroids and radii along an arm, shoulder end first.
type Rings = Vec<(Point3, Real)>;

/// A body's surface walked from the crotch: what both sides' arm searches
/// share, built once.
pub(super) struct Surface<'m> {
    /// The graph's vertices: a mesh's own, or a cloud's voxel centroids.
    pos: Cow<'m, [Point3]>,
    g: SurfaceGraph,
    areas: Vec<Real>,
    q: BodyQuery,
    /// The hand candidates, farthest from the crotch first (not a foot, not
    /// the head top on the trunk's line, far enough along the surface to
    /// be a hand), each with its arm's rings once asked for.
    hands: Vec<(usize, OnceLock<Option<Rings>>)>,
}

impl<'m> Surface<'m> {
    /// A mesh's surface: its edges.
    pub(super) fn new(m: &'m Mesh, q: BodyQuery) -> Option<Surface<'m>> {
        let g = SurfaceGraph::new(m);
        Surface::walk(Cow::Borrowed(&m.positions), g, vertex_areas(m), q)
    }

    /// A cloud's surface: [`cloud_graph`] with cubes of side
    /// [`CLOUD_CELL`] × `H`.
    pub(super) fn of_cloud(points: &[Point3], q: BodyQuery) -> Option<Surface<'static>> {
        let (pos, g, areas) = cloud_graph(points, CLOUD_CELL * q.extent)?;
        Surface::walk(Cow::Owned(pos), g, areas, q)
    }

    fn walk(
        pos: Cow<'m, [Point3]>,
        g: SurfaceGraph,
        areas: Vec<Real>,
        q: BodyQuery,
    ) -> Option<Surface<'m>> {
        // The nearest vertex on an edge (a loose vertex reaches nothing).
        let crotch = (0..pos.len())
            .filter(|&v| g.neighbours(v).next().is_some())
            .min_by(|&a, &b| {
                pos[a]
                    .distance(q.crotch)
                    .total_cmp(&pos[b].distance(q.crotch))
            })?;
        let from_crotch = g.distances(crotch as u32);
        let across = |v: Vec3| v - q.up * v.dot(q.up);
        let hfrac = |p: Point3| (p.dot(q.up) - q.floor) / q.extent;
        let hands = extremities(&g, &from_crotch, &pos, EXTREMITY_GAP * q.extent)
            .into_iter()
            .filter(|&v| hfrac(pos[v]) > 0.15)
            .filter(|&v| across(pos[v] - q.head).norm() > 0.07 * q.extent)
            .filter(|&v| from_crotch[v] > 0.45 * q.extent)
            .take(6)
            .map(|v| (v, OnceLock::new()))
            .collect();
        Some(Surface {
            pos,
            areas,
            g,
            q,
            hands,
        })
    }

    /// The arm on `side` (the body's left or right, a unit vector): the
    /// first hand candidate whose arm ends on that side.
    pub(super) fn find_arm(&self, side: Vec3) -> Option<SurfaceArm> {
        let (q, pos) = (&self.q, &self.pos);
        let across = |v: Vec3| v - q.up * v.dot(q.up);
        self.hands.iter().find_map(|(v, rings)| {
            let axis = rings
                .get_or_init(|| arm_from_tip(&self.g, &self.pos, &self.areas, *v, q.extent))
                .as_ref()?;
            let armpit = axis[0].0;
            // The shoulder end must lie on the side asked for, above the
            // crotch, and the arm must be longer than a hand.
            let on_side = across(armpit - q.crotch).dot(side) > 0.03 * q.extent;
            let above = armpit.dot(q.up) > q.crotch.dot(q.up) + 0.1 * q.extent;
            let long = armpit.distance(pos[*v]) > 0.2 * q.extent;
            (on_side && above && long).then(|| SurfaceArm {
                axis: axis.clone(),
                armpit,
                tip: pos[*v],
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::shapes;

    #[test]
    fn surface_distances_follow_the_edges() {
        // A 3 × 3 vertex square of side 2 with one diagonal per cell.
        let mut positions = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                positions.push(Vec3::new(i as Real, j as Real, 0.0));
            }
        }
        let mut triangles = Vec::new();
        for j in 0..2u32 {
            for i in 0..2u32 {
                let a = j * 3 + i;
                triangles.push([a, a + 1, a + 4]);
                triangles.push([a, a + 4, a + 3]);
            }
        }
        let m = Mesh {
            positions,
            normals: None,
            triangles,
        };
        let g = SurfaceGraph::new(&m);
        let d = g.distances(0);
        assert!((d[8] - 2.0 * 2f64.sqrt()).abs() < 1e-12, "{}", d[8]);
        assert!((d[2] - 2.0).abs() < 1e-12);
        assert!((d[5] - (1.0 + 2f64.sqrt())).abs() < 1e-12);
        assert_eq!(extremities(&g, &d, &m.positions, 0.5), vec![8]);
        let a: Real = vertex_areas(&m).iter().sum();
        assert!((a - 4.0).abs() < 1e-12);
    }

    /// A tube of radius 0.05 from its bottom cap's centre; above `flare`
    /// its radius grows to three times (a shoulder) when `flare < 1`.
    fn tube(flare: Real) -> (Mesh, usize) {
        let mut m = shapes::cylinder(Vec3::ZERO, 0.05, 1.0, 81, 32);
        for p in &mut m.positions {
            if p.z > flare {
                let s = 1.0 + 2.0 * ((p.z - flare) / 0.05).min(1.0);
                *p = Vec3::new(p.x * s, p.y * s, p.z);
            }
        }
        let tip = m.positions.len() - 2;
        (m, tip)
    }

    #[test]
    fn an_arm_ends_where_its_rings_widen() {
        let (m, tip) = tube(1.0);
        let g = SurfaceGraph::new(&m);
        assert!(arm_from_tip(&g, &m.positions, &vertex_areas(&m), tip, 1.0).is_none());
        let (m, tip) = tube(0.4);
        let g = SurfaceGraph::new(&m);
        let axis = arm_from_tip(&g, &m.positions, &vertex_areas(&m), tip, 1.0).unwrap();
        // From the shoulder end to the hand, on the tube's line, the rings
        // the tube's radius.
        let top = axis[0].0;
        assert!(top.z > 0.3 && top.z < 0.45, "{top:?}");
        assert!(axis.last().unwrap().0.z < 0.05);
        for (c, r) in &axis[..axis.len() - 2] {
            assert!(c.x.hypot(c.y) < 1e-3, "{c:?}");
            assert!((r - 0.05).abs() < 0.01 || c.z > 0.35, "{c:?} {r}");
        }
    }

    #[test]
    fn a_bent_elbow_s_wide_ring_is_not_the_shoulder() {
        // A forearm (radius 0.05) to 0.15, an elbow's wide ring (0.09) to
        // 0.165, a thicker upper arm (0.06) to 0.3, then the shoulder
        // spreading (to 0.15 over 0.05).
        let mut m = shapes::cylinder(Vec3::ZERO, 0.05, 1.0, 201, 32);
        for p in &mut m.positions {
            let s = match p.z {
                z if z < 0.15 => 1.0,
                z if z < 0.165 => 1.8,
                z if z < 0.3 => 1.2,
                z => 1.2 + 1.8 * ((z - 0.3) / 0.05).min(1.0),
            };
            *p = Vec3::new(p.x * s, p.y * s, p.z);
        }
        let tip = m.positions.len() - 2;
        let g = SurfaceGraph::new(&m);
        let axis = arm_from_tip(&g, &m.positions, &vertex_areas(&m), tip, 1.0).unwrap();
        let top = axis[0].0;
        assert!(top.z > 0.25 && top.z < 0.35, "{top:?}");
    }

    #[test]
    fn a_clouds_arm_ends_where_its_rings_widen() {
        // The flared tube's surface sampled densely, as a scan would.
        let m = shapes::cylinder(Vec3::ZERO, 0.05, 1.0, 401, 96);
        let flare = 0.4;
        let mut points: Vec<Point3> = m
            .positions
            .iter()
            .map(|p| {
                let s = 1.0 + 2.0 * ((p.z - flare).max(0.0) / 0.05).min(1.0);
                Vec3::new(p.x * s, p.y * s, p.z)
            })
            .collect();
        // The bottom cap, seen by the scanner too.
        for i in 0..16 {
            for j in 0..96 {
                let (r, t) = (
                    0.05 * i as Real / 16.0,
                    j as Real / 96.0 * std::f64::consts::TAU,
                );
                points.push(Vec3::new(r * t.cos(), r * t.sin(), 0.0));
            }
        }
        let (pos, g, w) = cloud_graph(&points, 0.01).unwrap();
        assert!(cloud_graph(&points, 0.0).is_none());
        assert!(cloud_graph(&points, Real::NAN).is_none());
        // The cube at the bottom cap's centre is the hand.
        let tip = (0..pos.len())
            .min_by(|&a, &b| pos[a].norm().total_cmp(&pos[b].norm()))
            .unwrap();
        let d = g.distances(tip as u32);
        // Along the tube the graph's distance is the length, up to the
        // cubes' zigzag.
        let far = (0..pos.len())
            .filter(|&v| pos[v].z > 0.3 && pos[v].z < 0.31)
            .map(|v| d[v])
            .fold(Real::INFINITY, Real::min);
        assert!(far > 0.29 && far < 0.36, "{far}");
        let axis = arm_from_tip(&g, &pos, &w, tip, 1.0).unwrap();
        let top = axis[0].0;
        assert!(top.z > 0.3 && top.z < 0.45, "{top:?}");
        // Near the tube's line (the cubes' diagonal steps bend the
        // rings a little) and of its radius below the flare.
        for (c, r) in axis.iter().filter(|(c, _)| c.z > 0.05 && c.z < 0.35) {
            assert!(c.x.hypot(c.y) < 0.01, "{c:?}");
            assert!((r - 0.05).abs() < 0.012, "{c:?} {r}");
        }
    }
}
