//! Which points of a mesh's surface can be seen from outside it: the
//! input's *outer* surface, as opposed to geometry it models inside itself
//! (the inside of a mouth, an ear canal), which no outer skin can reach.
//!
//! A point is **hidden** when none of [`RAY_DIRECTIONS`] rays from it,
//! spread evenly over the whole sphere (a Fibonacci lattice, so the test
//! needs no surface normal and ignores the triangles' orientation), leaves
//! the mesh's bounding box without hitting a triangle farther than a tiny
//! offset `ε` (`1e-6` of the box diagonal, so the point's own triangle is
//! not hit). A point on the outer skin sees half the sphere; a point in a
//! closed cavity sees nothing; a point in a deep, narrow crease may be
//! hidden too (it is practically invisible to any scanner).
//!
//! Rays are cast through a bounding-volume hierarchy (median splits on the
//! longest axis, leaves of at most 4 triangles; slab test for boxes,
//! nearer child first, any hit ends the ray; Möller-Trumbore for
//! triangles).

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{tri_bounds, union};
use crate::geom::mesh::{Aabb, Mesh};

/// Rays per point.
pub const RAY_DIRECTIONS: usize = 64;

#[derive(Debug)]
struct Node {
    bounds: Aabb,
    /// Leaf: `start..start + count` in `order`; inner: children `left`,
    /// `left + 1`… stored as indices.
    start: usize,
    count: usize,
    left: usize,
    right: usize,
    /// The parent's index (the root's own).
    parent: usize,
}

/// A ray-casting hierarchy over a mesh (see the module doc).
#[derive(Debug)]
pub struct Visibility {
    nodes: Vec<Node>,
    /// The triangles' corners in the leaves' order (`start..start + count`
    /// of a leaf index this).
    tris: Vec<[Point3; 3]>,
    eps: Real,
    directions: Vec<Vec3>,
}

/// The parameter where the ray `o + t d` enters the box (0 from inside),
/// if it does for `t < t_max` (`inv` = componentwise `1/d`).
pub(crate) fn ray_box(b: &Aabb, o: Point3, inv: Vec3, t_max: Real) -> Option<Real> {
    let (mut t0, mut t1) = (0.0, t_max);
    for (lo, hi, o, inv) in [
        (b.min.x, b.max.x, o.x, inv.x),
        (b.min.y, b.max.y, o.y, inv.y),
        (b.min.z, b.max.z, o.z, inv.z),
    ] {
        if !inv.is_finite() {
            // Parallel to this slab: inside it or never.
            if o < lo || o > hi {
                return None;
            }
            continue;
        }
        let (a, c) = ((lo - o) * inv, (hi - o) * inv);
        let (near, far) = if a < c { (a, c) } else { (c, a) };
        if near > t0 {
            t0 = near;
        }
        if far < t1 {
            t1 = far;
        }
        if t0 > t1 {
            return None;
        }
    }
    Some(t0)
}

/// Möller-Trumbore: the ray parameter of the hit with triangle `abc`.
pub(crate) fn ray_triangle(o: Point3, d: Vec3, [a, b, c]: [Point3; 3]) -> Option<Real> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(e2.dot(q) * inv)
}

impl Visibility {
    /// The hierarchy over `mesh`'s triangles.
    pub fn new(mesh: &Mesh) -> Visibility {
        let n = mesh.triangles.len();
        let bounds: Vec<Aabb> = (0..n).map(|t| tri_bounds(mesh, t)).collect();
        let mut order: Vec<usize> = (0..n).collect();
        let mut nodes = Vec::new();
        if n > 0 {
            build(&bounds, &mut order, 0, n, &mut nodes);
        }
        let tris = order.iter().map(|&t| mesh.triangle(t)).collect();
        let diag = mesh.bounds().map_or(1.0, |b| b.diagonal());
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let directions = (0..RAY_DIRECTIONS)
            .map(|i| {
                let z = 1.0 - (2.0 * i as Real + 1.0) / RAY_DIRECTIONS as Real;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = golden * i as Real;
                Vec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect();
        Visibility {
            nodes,
            tris,
            eps: 1e-6 * diag,
            directions,
        }
    }

    /// True when the ray from `o` along `d` hits triangle `k` (an index
    /// into `tris`) at `t > ε`.
    fn hits(&self, o: Point3, d: Vec3, k: usize) -> bool {
        ray_triangle(o, d, self.tris[k]).is_some_and(|h| h > self.eps)
    }

    /// The leaf, under node `root`, holding a triangle the ray from `o`
    /// along `d` hits at `t > ε`, if any.
    fn blocker(&self, o: Point3, d: Vec3, root: usize) -> Option<usize> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = Vec3::new(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
        ray_box(&self.nodes[root].bounds, o, inv, Real::INFINITY)?;
        // Median splits keep the depth near log2(triangles / 4): a fixed
        // stack of 64 is far more than a mesh of 2^32 triangles needs.
        let mut stack = [0usize; 64];
        stack[0] = root;
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let index = stack[top];
            let node = &self.nodes[index];
            if node.count > 0 {
                if (node.start..node.start + node.count).any(|k| self.hits(o, d, k)) {
                    return Some(index);
                }
            } else {
                // Nearer child on top: a hidden point's rays meet the
                // cavity's walls, close by, first.
                let hit = |c: usize| ray_box(&self.nodes[c].bounds, o, inv, Real::INFINITY);
                match (hit(node.left), hit(node.right)) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b {
                            (node.left, node.right)
                        } else {
                            (node.right, node.left)
                        };
                        stack[top] = far;
                        stack[top + 1] = near;
                        top += 2;
                    }
                    (Some(_), None) => {
                        stack[top] = node.left;
                        top += 1;
                    }
                    (None, Some(_)) => {
                        stack[top] = node.right;
                        top += 1;
                    }
                    (None, None) => {}
                }
            }
        }
        None
    }

    /// True when no ray from `p` escapes (see the module doc).
    pub fn hidden(&self, p: Point3) -> bool {
        self.escape(p, 0, &mut Blockers::default()).is_none()
    }

    /// The index of a direction whose ray from `p` escapes, trying the
    /// directions from `first` on (cyclically), or `None` when `p` is
    /// hidden. Each direction's ray first searches the subtree (about
    /// `4 · 2^CACHE_LEVELS` triangles: the blocking leaf's ancestor
    /// [`CACHE_LEVELS`] up) that blocked that direction last (`cache`): any
    /// hit blocks the ray, so a nearby point's blocking wall settles most
    /// rays of a hidden point without a search from the root. The answer
    /// does not depend on `first` or `cache`; only the work does: one
    /// escaping ray ends the test, so starting from the direction that let
    /// a nearby point out usually costs one ray.
    pub fn escape(&self, p: Point3, first: usize, cache: &mut Blockers) -> Option<usize> {
        let n = self.directions.len();
        cache.0.resize(n, None);
        (0..n).map(|i| (first + i) % n).find(|&i| {
            let d = self.directions[i];
            if cache.0[i].is_some_and(|node| self.blocker(p, d, node as usize).is_some()) {
                return false;
            }
            match self.blocker(p, d, 0) {
                Some(mut leaf) => {
                    for _ in 0..CACHE_LEVELS {
                        leaf = self.nodes[leaf].parent;
                    }
                    cache.0[i] = Some(leaf as u32);
                    false
                }
                None => true,
            }
        })
    }

    /// [`Visibility::hidden`] for every point, over the cores. The points
    /// are visited in Morton order (neighbours one after another), in
    /// blocks of [`BLOCK`] dealt to the cores in turn (hidden points
    /// gather in a few places: dealing spreads them); each core starts
    /// every point's rays from the direction that let its previous point
    /// out, and each ray from the triangle that blocked that direction for
    /// a previous point ([`Visibility::escape`]).
    pub fn hidden_all(&self, points: &[Point3]) -> Vec<bool> {
        let order = crate::spatial::morton::morton_sort(points).0;
        let blocks: Vec<&[u32]> = order.chunks(BLOCK).collect();
        let cores = rayon::current_num_threads().min(blocks.len()).max(1);
        let run = |core: usize| {
            let (mut first, mut cache) = (0, Blockers::default());
            let mut out = Vec::new();
            for block in blocks.iter().skip(core).step_by(cores) {
                for &i in *block {
                    let p = points[i as usize];
                    let hidden = match self.escape(p, first, &mut cache) {
                        Some(k) => {
                            first = k;
                            false
                        }
                        None => true,
                    };
                    out.push((i, hidden));
                }
            }
            out
        };
        let answers: Vec<Vec<(u32, bool)>> = if cores == 1 {
            vec![run(0)]
        } else {
            use rayon::prelude::*;
            (0..cores).into_par_iter().map(run).collect()
        };
        let mut hidden = vec![false; points.len()];
        for (i, h) in answers.into_iter().flatten() {
            hidden[i as usize] = h;
        }
        hidden
    }
}

/// Points per block in [`Visibility::hidden_all`].
const BLOCK: usize = 32;

/// How far above the blocking leaf [`Visibility::escape`]'s cache points.
const CACHE_LEVELS: usize = 3;

/// Per direction, the subtree that blocked its last ray (see
/// [`Visibility::escape`]).
#[derive(Clone, Debug, Default)]
pub struct Blockers(Vec<Option<u32>>);

fn build(
    bounds: &[Aabb],
    order: &mut [usize],
    start: usize,
    end: usize,
    nodes: &mut Vec<Node>,
) -> usize {
    let b = order[start..end]
        .iter()
        .map(|&t| bounds[t])
        .reduce(union)
        .unwrap_or(Aabb {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        });
    let index = nodes.len();
    nodes.push(Node {
        bounds: b,
        start,
        count: end - start,
        left: 0,
        right: 0,
        parent: index,
    });
    if end - start <= 4 {
        return index;
    }
    let centre = |t: usize| (bounds[t].min + bounds[t].max) * 0.5;
    let size = b.max - b.min;
    let axis = if size.x >= size.y && size.x >= size.z {
        0
    } else if size.y >= size.z {
        1
    } else {
        2
    };
    let key = |t: &usize| centre(*t).to_array()[axis];
    let mid = (start + end) / 2;
    order[start..end].select_nth_unstable_by(mid - start, |a, b| key(a).total_cmp(&key(b)));
    let left = build(bounds, order, start, mid, nodes);
    let right = build(bounds, order, mid, end, nodes);
    nodes[index].count = 0;
    nodes[index].left = left;
    nodes[index].right = right;
    nodes[left].parent = index;
    nodes[right].parent = index;
    index
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::shapes::uv_sphere;

    /// A point outside or on a sphere sees out; points inside the closed
    /// sphere do not.
    #[test]
    fn enclosed_points_are_hidden_and_outer_ones_are_not() {
        let m = uv_sphere(Vec3::ZERO, 1.0, 32, 16);
        let v = Visibility::new(&m);
        assert!(v.hidden(Vec3::ZERO));
        assert!(v.hidden(Vec3::new(0.3, -0.2, 0.1)));
        assert!(!v.hidden(Vec3::new(2.0, 0.0, 0.0)));
        // A vertex of the sphere itself: on the outer surface.
        assert!(!v.hidden(m.positions[40]));
        // Empty mesh: nothing hides anything.
        let e = Mesh::default();
        assert!(!Visibility::new(&e).hidden(Vec3::ZERO));
        // The batch (warm-started, over the cores) agrees with single
        // tests, whatever direction each point starts from.
        let pts: Vec<Point3> = (0..300)
            .map(|i| {
                let t = i as Real * 0.37;
                Vec3::new(t.cos(), t.sin(), (t * 0.13).sin()) * (0.2 + (i % 7) as Real * 0.25)
            })
            .collect();
        let single: Vec<bool> = pts.iter().map(|&p| v.hidden(p)).collect();
        assert_eq!(v.hidden_all(&pts), single);
        assert!(single.iter().any(|&h| h) && single.iter().any(|&h| !h));
        for (k, &p) in pts.iter().enumerate().take(40) {
            assert_eq!(
                v.escape(p, k % RAY_DIRECTIONS, &mut Blockers::default())
                    .is_none(),
                single[k]
            );
        }
    }
}
