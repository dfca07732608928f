//! Distances between points and triangle meshes: a bounding-volume hierarchy
//! over the triangles with exact closest-point queries, and the symmetric
//! distance statistics used to judge a model against its input.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{tri_bounds, union, Aabb, Mesh};
use crate::geom::parallel::{par_for_each_mut, parallel_map};
use crate::spatial::morton::{morton_sort, morton_sort_by};

/// Triangles per leaf of the hierarchy.
const LEAF_SIZE: usize = 8;

/// A node of [`MeshDistance`]'s hierarchy: 32 bytes, so two siblings
/// (stored side by side) fill one 64-byte cache line. Its box is stored
/// in single precision rounded outward ([`Node::boxed`]): it holds the
/// exact box of its triangles, so a query that prunes by it prunes no
/// triangle the exact box would keep (it may visit a node more, never
/// one less), and every distance is still computed in double precision
/// from the triangles.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: [f32; 3],
    hi: [f32; 3],
    /// Leaf: first triangle index in `order`, count. Inner: left child index
    /// (right child is `left + 1`), count 0.
    start: u32,
    count: u32,
}

/// The largest `f32` at most `x` (`x` finite or infinite).
fn f32_down(x: Real) -> f32 {
    let f = x as f32;
    if (f as Real) <= x {
        f
    } else if f == 0.0 {
        -f32::from_bits(1)
    } else if f > 0.0 {
        f32::from_bits(f.to_bits() - 1)
    } else {
        f32::from_bits(f.to_bits() + 1)
    }
}

/// The smallest `f32` at least `x`.
fn f32_up(x: Real) -> f32 {
    -f32_down(-x)
}

impl Node {
    /// The node's box in double precision (the stored one, exactly).
    #[inline]
    fn bounds(&self) -> Aabb {
        let v = |a: [f32; 3]| Vec3::new(a[0] as Real, a[1] as Real, a[2] as Real);
        Aabb {
            min: v(self.lo),
            max: v(self.hi),
        }
    }

    /// The smallest single-precision box holding `b`.
    fn boxed(&mut self, b: &Aabb) {
        self.lo = [f32_down(b.min.x), f32_down(b.min.y), f32_down(b.min.z)];
        self.hi = [f32_up(b.max.x), f32_up(b.max.y), f32_up(b.max.z)];
    }

    /// Squared distance from `p` to the box (0 inside), as
    /// [`box_distance_sq`] of [`Node::bounds`].
    #[inline]
    fn distance_sq(&self, p: Point3) -> Real {
        box_distance_sq(&self.bounds(), p)
    }
}

/// A bounding-volume hierarchy over a mesh's triangles for nearest-point
/// queries: `closest(p)` returns the point of the surface nearest to `p`.
#[derive(Debug)]
pub struct MeshDistance<'m> {
    mesh: &'m Mesh,
    nodes: Vec<Node>,
    order: Vec<u32>,
}

/// The nearest surface point to a query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    pub point: Point3,
    pub distance: Real,
    pub triangle: usize,
}

/// Squared distance from `p` to the box (0 inside).
#[inline]
fn box_distance_sq(b: &Aabb, p: Point3) -> Real {
    let d = Vec3::new(
        (b.min.x - p.x).max(0.0).max(p.x - b.max.x),
        (b.min.y - p.y).max(0.0).max(p.y - b.max.y),
        (b.min.z - p.z).max(0.0).max(p.z - b.max.z),
    );
    d.norm_squared()
}

/// The point of triangle `abc` closest to `p` (Voronoi-region walk over the
/// vertices, edges and face; exact for non-degenerate and degenerate
/// triangles alike).
pub fn closest_point_on_triangle(p: Point3, a: Point3, b: Point3, c: Point3) -> Point3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let denom = d1 - d3;
        return if denom > 0.0 {
            a + ab * (d1 / denom)
        } else {
            a
        };
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let denom = d2 - d6;
        return if denom > 0.0 {
            a + ac * (d2 / denom)
        } else {
            a
        };
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let denom = (d4 - d3) + (d5 - d6);
        return if denom > 0.0 {
            b + (c - b) * ((d4 - d3) / denom)
        } else {
            b
        };
    }
    let sum = va + vb + vc;
    if !(sum > 0.0) || !sum.is_finite() {
        // Degenerate (zero-area) triangle: the nearest of its three edges.
        let seg = |u: Point3, v: Point3| {
            let e = v - u;
            let l = e.norm_squared();
            let t = if l > 0.0 {
                ((p - u).dot(e) / l).clamp(0.0, 1.0)
            } else {
                0.0
            };
            u + e * t
        };
        let cands = [seg(a, b), seg(b, c), seg(c, a)];
        return cands
            .into_iter()
            .min_by(|x, y| (*x - p).norm_squared().total_cmp(&(*y - p).norm_squared()))
            .unwrap_or(a);
    }
    let (v, w) = (vb / sum, vc / sum);
    a + ab * v + ac * w
}

impl<'m> MeshDistance<'m> {
    /// Builds the hierarchy over the triangles sorted along a Morton
    /// (Z-order) curve of their box centres, quantized to 1024 steps per
    /// axis of the centres' bounding box: each node's triangles are a run
    /// of that order, split where the highest bit in which the run's first
    /// and last codes differ changes (halves of the node's box along the
    /// axis of that bit), in the middle where the codes are equal; boxes
    /// are filled bottom-up. Linear passes and one radix sort, cheaper than
    /// a median search per node. The mesh should be valid
    /// ([`Mesh::validate`]); an empty mesh gives a hierarchy whose queries
    /// return `None`.
    pub fn new(mesh: &'m Mesh) -> MeshDistance<'m> {
        let n = mesh.triangles.len();
        let (order, codes) = morton_sort_by(n, |t| tri_bounds(mesh, t).center());
        let mut nodes: Vec<Node> = Vec::with_capacity(2 * n / LEAF_SIZE + 1);
        if n > 0 {
            let empty = Node {
                lo: [0.0; 3],
                hi: [0.0; 3],
                start: 0,
                count: 0,
            };
            nodes.push(empty);
            // (node index, start, end) to split.
            let mut stack = vec![(0usize, 0usize, n)];
            while let Some((ni, s, e)) = stack.pop() {
                if e - s <= LEAF_SIZE {
                    nodes[ni].start = s as u32;
                    nodes[ni].count = (e - s) as u32;
                    continue;
                }
                let diff = codes[s] ^ codes[e - 1];
                let mid = if diff == 0 {
                    (s + e) / 2
                } else {
                    let bit = 1u32 << (31 - diff.leading_zeros());
                    s + codes[s..e].partition_point(|&c| c & bit == 0)
                };
                let left = nodes.len();
                nodes.push(empty);
                nodes.push(empty);
                nodes[ni].start = left as u32;
                nodes[ni].count = 0;
                stack.push((left, s, mid));
                stack.push((left + 1, mid, e));
            }
            // Boxes bottom-up, rounded outward: the leaves' from their
            // triangles (over the cores), then, children coming after
            // their parents, each inner node's the union of its
            // children's.
            par_for_each_mut(&mut nodes, 4096, |_, node| {
                if node.count > 0 {
                    let s = node.start as usize;
                    let b = order[s..s + node.count as usize]
                        .iter()
                        .map(|&t| tri_bounds(mesh, t as usize))
                        .reduce(union)
                        .unwrap_or(Aabb {
                            min: Vec3::ZERO,
                            max: Vec3::ZERO,
                        });
                    node.boxed(&b);
                }
            });
            for ni in (0..nodes.len()).rev() {
                let node = nodes[ni];
                if node.count == 0 {
                    let l = node.start as usize;
                    let b = union(nodes[l].bounds(), nodes[l + 1].bounds());
                    nodes[ni].boxed(&b);
                }
            }
        }
        MeshDistance { mesh, nodes, order }
    }

    /// The mesh the hierarchy is over.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// The distance from each of `points` to the surface (infinite for an
    /// empty mesh), exactly as [`MeshDistance::distance`], faster: the
    /// points are visited in Morton order ([`coherent_map`]) and each search
    /// starts from the previous point's nearest triangle, whose distance
    /// (usually the answer or close to it) prunes the hierarchy from the
    /// root.
    pub fn distances(&self, points: &[Point3]) -> Vec<Real> {
        self.distances_where(points, Real::INFINITY, |_| true, |_| true)
    }

    /// [`MeshDistance::distances`] to the triangles `t` with `triangle(t)`
    /// only, closer than `max_distance` (infinite where there is none; a
    /// bound makes far queries cheap), searching only the nodes `n` with
    /// `node(n)`: `node` must hold for every node with such a triangle
    /// below it (e.g. a bit of [`MeshDistance::node_labels`]); where it
    /// holds for others it only prunes less.
    pub fn distances_where(
        &self,
        points: &[Point3],
        max_distance: Real,
        node: impl Fn(usize) -> bool + Sync,
        triangle: impl Fn(usize) -> bool + Sync,
    ) -> Vec<Real> {
        let max_sq = max_distance * max_distance;
        // The state a query leaves for the next: its nearest triangle
        // (the next one's seed) and the search stack (allocated once a run).
        type State = (Option<usize>, Vec<(u32, Real)>);
        coherent_map(points, |p, (seed, stack): &mut State| {
            let c = match *seed {
                Some(t) => self.closest_from(p, t, max_sq, &node, &triangle, stack),
                None => self.search(p, max_sq, None, &node, &triangle, stack),
            };
            *seed = c.map(|c| c.triangle);
            c.map_or(Real::INFINITY, |c| c.distance)
        })
    }

    /// The surface point nearest to `p`, or `None` for an empty mesh.
    pub fn closest(&self, p: Point3) -> Option<Closest> {
        self.closest_within(p, Real::INFINITY)
    }

    /// The nearest surface point closer than `max_distance`, if any.
    pub fn closest_within(&self, p: Point3, max_distance: Real) -> Option<Closest> {
        let all = |_| true;
        let mut stack = Vec::new();
        self.search(p, max_distance * max_distance, None, &all, &all, &mut stack)
    }

    /// For every node of the hierarchy, the bitwise or of `label(t)` over
    /// the triangles `t` below it (indexed as the `node` arguments of the
    /// `_where` queries): with triangles selected by a bit of their label,
    /// `node(n) = labels[n] & bit != 0` skips the subtrees without any.
    pub fn node_labels(&self, label: impl Fn(usize) -> u64) -> Vec<u64> {
        let mut labels = vec![0u64; self.nodes.len()];
        // Children come after their parents: bottom-up.
        for ni in (0..self.nodes.len()).rev() {
            let node = self.nodes[ni];
            let s = node.start as usize;
            labels[ni] = if node.count > 0 {
                self.order[s..s + node.count as usize]
                    .iter()
                    .fold(0, |a, &t| a | label(t as usize))
            } else {
                labels[s] | labels[s + 1]
            };
        }
        labels
    }

    /// How many triangles `t` with `triangle(t)` the segment `o + s d`,
    /// `0 < s < length` (a ray for an infinite length), crosses
    /// (Möller-Trumbore; a ray through an edge or a vertex may count a
    /// crossing twice or not at all), searching only the nodes `n` with
    /// `node(n)` (as in [`MeshDistance::distances_where`]).
    pub fn ray_crossings_where(
        &self,
        o: Point3,
        d: Vec3,
        length: Real,
        node: impl Fn(usize) -> bool,
        triangle: impl Fn(usize) -> bool,
    ) -> usize {
        use crate::spatial::visibility::{ray_box, ray_triangle};
        let inv = Vec3::new(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
        let mut crossings = 0;
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        while let Some(ni) = stack.pop() {
            let n = &self.nodes[ni as usize];
            if !node(ni as usize) || ray_box(&n.bounds(), o, inv, length).is_none() {
                continue;
            }
            let s = n.start as usize;
            if n.count > 0 {
                crossings += self.order[s..s + n.count as usize]
                    .iter()
                    .filter(|&&t| {
                        triangle(t as usize)
                            && ray_triangle(o, d, self.mesh.triangle(t as usize))
                                .is_some_and(|h| h > 0.0 && h < length)
                    })
                    .count();
            } else {
                stack.push(n.start);
                stack.push(n.start + 1);
            }
        }
        crossings
    }

    /// Calls `visit` with the box of every leaf of the hierarchy that meets
    /// `region`, searching only the nodes `n` with `node(n)` (a leaf's box
    /// holds all its triangles, selected or not).
    pub fn leaves_where(
        &self,
        region: &Aabb,
        node: impl Fn(usize) -> bool,
        mut visit: impl FnMut(&Aabb),
    ) {
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        while let Some(ni) = stack.pop() {
            let n = &self.nodes[ni as usize];
            let bounds = n.bounds();
            if !node(ni as usize) || !bounds.overlaps(region) {
                continue;
            }
            if n.count > 0 {
                visit(&bounds);
            } else {
                stack.push(n.start);
                stack.push(n.start + 1);
            }
        }
    }

    /// The nearest selected surface point closer than `√max_sq`, starting
    /// from triangle `seed` (selected): its distance bounds the search, and
    /// it is the answer unless a selected triangle lies strictly closer (so
    /// the distance is exactly an unseeded search's).
    fn closest_from(
        &self,
        p: Point3,
        seed: usize,
        max_sq: Real,
        node: &impl Fn(usize) -> bool,
        triangle: &impl Fn(usize) -> bool,
        stack: &mut Vec<(u32, Real)>,
    ) -> Option<Closest> {
        let [a, b, c] = self.mesh.triangle(seed);
        let q = closest_point_on_triangle(p, a, b, c);
        let d = (q - p).norm_squared();
        if d < max_sq {
            self.search(p, d, Some((q, seed)), node, triangle, stack)
        } else {
            self.search(p, max_sq, None, node, triangle, stack)
        }
    }

    /// Depth-first search for the nearest triangle `t` with `triangle(t)`
    /// closer than `√best_sq` (else `best`), nearer child first; a node `n`
    /// is entered only while `node(n)` holds and its box is closer than the
    /// best so far. `stack` is the search's stack (emptied first; passed in
    /// so that a run of queries allocates it once).
    fn search(
        &self,
        p: Point3,
        mut best_sq: Real,
        mut best: Option<(Point3, usize)>,
        node_ok: &impl Fn(usize) -> bool,
        triangle_ok: &impl Fn(usize) -> bool,
        stack: &mut Vec<(u32, Real)>,
    ) -> Option<Closest> {
        if self.nodes.is_empty() || !node_ok(0) {
            return best.map(|(point, triangle)| Closest {
                point,
                distance: best_sq.sqrt(),
                triangle,
            });
        }
        stack.clear();
        stack.push((0, self.nodes[0].distance_sq(p)));
        while let Some((ni, dn)) = stack.pop() {
            if dn >= best_sq {
                continue;
            }
            let node = &self.nodes[ni as usize];
            if node.count > 0 {
                let s = node.start as usize;
                for &t in &self.order[s..s + node.count as usize] {
                    if !triangle_ok(t as usize) {
                        continue;
                    }
                    let [a, b, c] = self.mesh.triangle(t as usize);
                    let q = closest_point_on_triangle(p, a, b, c);
                    let d = (q - p).norm_squared();
                    if d < best_sq {
                        best_sq = d;
                        best = Some((q, t as usize));
                    }
                }
            } else {
                let (l, r) = (node.start, node.start + 1);
                let box_sq = |c: u32| {
                    if node_ok(c as usize) {
                        self.nodes[c as usize].distance_sq(p)
                    } else {
                        Real::INFINITY
                    }
                };
                let (dl, dr) = (box_sq(l), box_sq(r));
                // Visit the nearer child first (pushed last).
                let (near, far) = if dl <= dr {
                    ((l, dl), (r, dr))
                } else {
                    ((r, dr), (l, dl))
                };
                if far.1 < best_sq {
                    stack.push(far);
                }
                if near.1 < best_sq {
                    stack.push(near);
                }
            }
        }
        best.map(|(point, triangle)| Closest {
            point,
            distance: best_sq.sqrt(),
            triangle,
        })
    }

    /// The distance from `p` to the surface (infinite for an empty mesh).
    pub fn distance(&self, p: Point3) -> Real {
        self.closest(p).map_or(Real::INFINITY, |c| c.distance)
    }
}

/// Summary statistics of a set of distances.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DistanceStats {
    pub count: usize,
    pub rms: Real,
    pub mean: Real,
    /// 95th percentile.
    pub p95: Real,
    pub max: Real,
}

impl DistanceStats {
    /// Statistics of `d` (empty gives all zeros).
    pub fn of(d: &[Real]) -> DistanceStats {
        if d.is_empty() {
            return DistanceStats::default();
        }
        let n = d.len() as Real;
        // The k-th smallest by a selection, not a sort (the same element
        // in the same total order; linear time).
        let mut work = d.to_vec();
        let k = ((0.95 * (d.len() - 1) as Real).round() as usize).min(d.len() - 1);
        let (_, &mut p95, above) = work.select_nth_unstable_by(k, Real::total_cmp);
        let max = above
            .iter()
            .copied()
            .fold(p95, |m, x| if x.total_cmp(&m).is_gt() { x } else { m });
        DistanceStats {
            count: d.len(),
            rms: (d.iter().map(|x| x * x).sum::<Real>() / n).sqrt(),
            mean: d.iter().sum::<Real>() / n,
            p95,
            max,
        }
    }
}

/// Points spread over a mesh's surface in proportion to area,
/// deterministically: each triangle gets `round(count · area / total)`
/// points on a fixed barycentric pattern (at least its centroid when
/// `count` ≥ triangles). Good for densely sampling a surface to compare it
/// with another.
pub fn sample_surface(mesh: &Mesh, count: usize) -> Vec<Point3> {
    sample_surface_on_triangles(mesh, count).0
}

/// [`sample_surface`]'s points, for each the triangle it lies on, and the
/// mesh's area.
pub fn sample_surface_on_triangles(mesh: &Mesh, count: usize) -> (Vec<Point3>, Vec<u32>, Real) {
    let areas: Vec<Real> = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.triangle(t);
            (b - a).cross(c - a).norm() * 0.5
        })
        .collect();
    let total: Real = areas.iter().sum();
    if !(total > 0.0) {
        return (Vec::new(), Vec::new(), total);
    }
    let mut out = Vec::with_capacity(count + mesh.triangles.len());
    let mut on = Vec::with_capacity(count + mesh.triangles.len());
    let mut carry = 0.0;
    for (t, area) in areas.iter().enumerate() {
        carry += count as Real * area / total;
        let k = carry.floor() as usize;
        carry -= k as Real;
        let [a, b, c] = mesh.triangle(t);
        // A low-discrepancy pattern in the triangle (reflected 2D Kronecker
        // sequence, golden-ratio based).
        for i in 0..k {
            let (mut u, mut v) = (
                (0.5 + i as Real * 0.754_877_666_246_692_7).fract(),
                (0.5 + i as Real * 0.569_840_290_998_053_2).fract(),
            );
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            out.push(a + (b - a) * u + (c - a) * v);
            on.push(t as u32);
        }
    }
    (out, on, total)
}

/// Distances of `points` to the surface of `target`, one per point (see
/// [`MeshDistance::distances`]).
pub fn distances_to(target: &MeshDistance, points: &[Point3]) -> Vec<Real> {
    target.distances(points)
}

/// `query(p, state)` for every point, the points visited in Morton order
/// (sorted along a Z-order curve, so consecutive points are near each
/// other; fewer than 4096 points keep their order) with a `state` per run (starting from `S::default()`) that a
/// query leaves for the next: e.g. the previous point's nearest element, a
/// first guess that bounds the next search. Runs are split over the cores
/// ([`parallel_map`], at least 4096 points each); the answers come back in
/// the order of `points`. With `query` exact whatever the state, the
/// answers are exactly those of querying each point alone.
pub fn coherent_map<S: Default, R: Copy + Default + Send>(
    points: &[Point3],
    query: impl Fn(Point3, &mut S) -> R + Sync,
) -> Vec<R> {
    // A few points (a curve's samples) keep their order: sorting would
    // cost more than it saves.
    let order: Vec<u32> = if points.len() < 4096 {
        (0..points.len() as u32).collect()
    } else {
        morton_sort(points).0
    };
    let answers = parallel_map(&order, 4096, |run| {
        let mut state = S::default();
        run.iter()
            .map(|&i| query(points[i as usize], &mut state))
            .collect()
    });
    let mut out = vec![R::default(); points.len()];
    for (&i, d) in order.iter().zip(answers) {
        out[i as usize] = d;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::assert_vec_near;

    fn brute(mesh: &Mesh, p: Point3) -> Real {
        (0..mesh.triangles.len())
            .map(|t| {
                let [a, b, c] = mesh.triangle(t);
                (closest_point_on_triangle(p, a, b, c) - p).norm()
            })
            .fold(Real::INFINITY, Real::min)
    }

    fn sphere(n: usize) -> Mesh {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for i in 0..=n {
            let th = std::f64::consts::PI * i as Real / n as Real;
            for j in 0..2 * n {
                let ph = std::f64::consts::PI * j as Real / n as Real;
                positions.push(Vec3::new(
                    th.sin() * ph.cos(),
                    th.cos(),
                    th.sin() * ph.sin(),
                ));
            }
        }
        let idx = |i: usize, j: usize| (i * 2 * n + j % (2 * n)) as u32;
        for i in 0..n {
            for j in 0..2 * n {
                triangles.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
                triangles.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
            }
        }
        Mesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert_eq!(
            closest_point_on_triangle(Vec3::new(-1., -1., 0.), a, b, c),
            a
        );
        let f = closest_point_on_triangle(Vec3::new(0.2, 0.2, 5.0), a, b, c);
        assert_vec_near!(f, Vec3::new(0.2, 0.2, 0.0), 1e-15);
        let e = closest_point_on_triangle(Vec3::new(0.5, -3.0, 1.0), a, b, c);
        assert_vec_near!(e, Vec3::new(0.5, 0.0, 0.0), 1e-15);
        let h = closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, b, c);
        assert_vec_near!(h, Vec3::new(0.5, 0.5, 0.0), 1e-15);
        // Degenerate triangle: a segment.
        let d = closest_point_on_triangle(Vec3::new(0.5, 1.0, 0.0), a, b, b);
        assert_vec_near!(d, Vec3::new(0.5, 0.0, 0.0), 1e-15);
    }

    /// The selective queries agree with brute force over the selected
    /// triangles: distances (bounded or not), ray crossings, leaves.
    #[test]
    fn selected_queries_match_brute_force() {
        let m = sphere(12);
        let bvh = MeshDistance::new(&m);
        // Select the triangles of the upper half by a label bit.
        let upper = |t: usize| m.triangle(t).iter().all(|p| p.z > 0.0);
        let labels = bvh.node_labels(|t| if upper(t) { 2 } else { 1 });
        let node = |n: usize| labels[n] & 2 != 0;
        let points: Vec<Point3> = (0..300)
            .map(|i| {
                let t = i as Real * 0.37;
                Vec3::new(t.cos(), t.sin(), (t * 0.13).sin()) * (0.1 + (i % 9) as Real * 0.2)
            })
            .collect();
        let brute_upper = |p: Point3| {
            (0..m.triangles.len())
                .filter(|&t| upper(t))
                .map(|t| {
                    let [a, b, c] = m.triangle(t);
                    (closest_point_on_triangle(p, a, b, c) - p).norm()
                })
                .fold(Real::INFINITY, Real::min)
        };
        let all = bvh.distances_where(&points, Real::INFINITY, node, upper);
        let near = bvh.distances_where(&points, 0.3, node, upper);
        for (i, &p) in points.iter().enumerate() {
            let b = brute_upper(p);
            assert_near!(all[i], b, 1e-14);
            if b < 0.3 {
                assert_near!(near[i], b, 1e-14);
            } else {
                assert!(near[i].is_infinite());
            }
            // A ray from inside the sphere crosses the upper half once
            // going up and not at all going down (away from the equator).
            if p.norm() < 0.9 && p.z > 0.05 {
                assert_eq!(
                    bvh.ray_crossings_where(
                        p,
                        Vec3::new(0.01, 0.02, 1.0),
                        Real::INFINITY,
                        node,
                        upper
                    ),
                    1
                );
                assert_eq!(
                    bvh.ray_crossings_where(
                        p,
                        Vec3::new(0.01, 0.02, -1.0),
                        Real::INFINITY,
                        node,
                        upper
                    ),
                    0
                );
                // A segment that stops inside crosses nothing.
                let short = (0.99 - p.norm()).max(0.0) * 0.5;
                assert_eq!(
                    bvh.ray_crossings_where(p, Vec3::new(0.0, 0.0, 1.0), short, node, upper),
                    0
                );
            }
        }
        // Every selected triangle's box lies in a visited leaf box.
        let region = Aabb {
            min: Vec3::new(-0.2, -0.2, 0.5),
            max: Vec3::new(0.2, 0.2, 2.0),
        };
        let mut leaves = Vec::new();
        bvh.leaves_where(&region, node, |b| leaves.push(*b));
        for t in (0..m.triangles.len()).filter(|&t| upper(t) && tri_bounds(&m, t).overlaps(&region))
        {
            let b = tri_bounds(&m, t);
            assert!(leaves
                .iter()
                .any(|l| l.min.min(b.min) == l.min && l.max.max(b.max) == l.max));
        }
        assert!(!leaves.is_empty());
    }

    /// The single-precision node boxes hold the exact ones: outward
    /// rounding gives the nearest `f32` on the right side.
    #[test]
    fn outward_rounding_brackets_the_value() {
        for x in [
            0.0,
            0.1,
            -0.1,
            1.0,
            1.0 + 1e-12,
            -1.7e-3,
            1e-42,
            -1e-42,
            3e38,
            1e39,
            -1e39,
        ] {
            let (lo, hi) = (f32_down(x), f32_up(x));
            assert!((lo as Real) <= x && (hi as Real) >= x, "{x}");
            // The nearest on its side: the next f32 up from `lo` passes x.
            let next_up = |f: f32| {
                if f == 0.0 {
                    f32::from_bits(1)
                } else if f > 0.0 {
                    f32::from_bits(f.to_bits() + 1)
                } else {
                    f32::from_bits(f.to_bits() - 1)
                }
            };
            assert!((next_up(lo) as Real) > x, "{x}");
            assert_eq!(f32_up(x), -f32_down(-x));
            if x == (x as f32) as Real {
                assert_eq!((lo as Real, hi as Real), (x, x));
            }
        }
        let m = sphere(12);
        let bvh = MeshDistance::new(&m);
        for n in &bvh.nodes {
            let b = n.bounds();
            if n.count > 0 {
                let s = n.start as usize;
                for &t in &bvh.order[s..s + n.count as usize] {
                    let tb = tri_bounds(&m, t as usize);
                    assert!(union(b, tb).min == b.min && union(b, tb).max == b.max);
                }
            }
        }
    }

    #[test]
    fn hierarchy_matches_brute_force() {
        let m = sphere(12);
        let bvh = MeshDistance::new(&m);
        for i in 0..200 {
            let t = i as Real * 0.7;
            let p = Vec3::new(1.7 * t.sin(), 1.3 * (0.3 * t).cos(), 0.9 * (1.1 * t).sin())
                * (0.2 + (i % 7) as Real * 0.3);
            assert_near!(bvh.distance(p), brute(&m, p), 1e-14);
        }
    }

    #[test]
    fn batched_distances_are_the_single_queries() {
        let m = sphere(24);
        let bvh = MeshDistance::new(&m);
        // 10 000 points in no order, inside, on and outside the sphere.
        let pts: Vec<Point3> = (0..10_000)
            .map(|i| {
                let t = i as Real * 0.618_033_988_749_895;
                Vec3::new(t.sin(), (1.7 * t).cos(), (2.3 * t).sin()) * (0.2 + 1.6 * t.fract())
            })
            .collect();
        let single: Vec<Real> = pts.iter().map(|p| bvh.distance(*p)).collect();
        assert_eq!(bvh.distances(&pts), single);
        assert!(bvh.distances(&[]).is_empty());
    }

    #[test]
    fn surface_samples_lie_on_the_surface_and_cover_it() {
        let m = sphere(16);
        let s = sample_surface(&m, 5000);
        assert!((s.len() as i64 - 5000).abs() <= 1);
        let bvh = MeshDistance::new(&m);
        assert!(s.iter().all(|p| bvh.distance(*p) < 1e-12));
        // Roughly even: each octant holds about an eighth.
        let octant = s
            .iter()
            .filter(|p| p.x > 0.0 && p.y > 0.0 && p.z > 0.0)
            .count();
        assert!((octant as Real / s.len() as Real - 0.125).abs() < 0.01);
    }

    #[test]
    fn stats_of_known_values() {
        let d: Vec<Real> = (0..=100).map(|i| i as Real).collect();
        let s = DistanceStats::of(&d);
        assert_eq!(s.max, 100.0);
        assert_eq!(s.p95, 95.0);
        assert_near!(s.mean, 50.0, 1e-12);
        assert_eq!(DistanceStats::of(&[]).count, 0);
        let empty = Mesh::default();
        assert!(MeshDistance::new(&empty).closest(Vec3::ZERO).is_none());
    }
}
