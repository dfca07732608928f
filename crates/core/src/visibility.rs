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

use crate::math::{Point3, Real, Vec3};
use crate::mesh::{Aabb, Mesh};

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
}

/// A ray-casting hierarchy over a mesh (see the module doc).
#[derive(Debug)]
pub struct Visibility<'m> {
    mesh: &'m Mesh,
    nodes: Vec<Node>,
    order: Vec<usize>,
    eps: Real,
    directions: Vec<Vec3>,
}

fn tri_bounds(m: &Mesh, t: usize) -> Aabb {
    let [a, b, c] = m.triangle(t);
    Aabb {
        min: a.min(b).min(c),
        max: a.max(b).max(c),
    }
}

fn union(a: Aabb, b: Aabb) -> Aabb {
    Aabb {
        min: a.min.min(b.min),
        max: a.max.max(b.max),
    }
}

/// The parameter where the ray `o + t d` enters the box (0 from inside),
/// if it does for `t < t_max` (`inv` = componentwise `1/d`).
fn ray_box(b: &Aabb, o: Point3, inv: Vec3, t_max: Real) -> Option<Real> {
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
fn ray_triangle(o: Point3, d: Vec3, [a, b, c]: [Point3; 3]) -> Option<Real> {
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

impl<'m> Visibility<'m> {
    /// The hierarchy over `mesh`'s triangles.
    pub fn new(mesh: &'m Mesh) -> Visibility<'m> {
        let n = mesh.triangles.len();
        let bounds: Vec<Aabb> = (0..n).map(|t| tri_bounds(mesh, t)).collect();
        let mut order: Vec<usize> = (0..n).collect();
        let mut nodes = Vec::new();
        if n > 0 {
            build(&bounds, &mut order, 0, n, &mut nodes);
        }
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
            mesh,
            nodes,
            order,
            eps: 1e-6 * diag,
            directions,
        }
    }

    /// True when the ray from `o` along `d` hits a triangle at `t > ε`.
    fn blocked(&self, o: Point3, d: Vec3) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let inv = Vec3::new(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
        if ray_box(&self.nodes[0].bounds, o, inv, Real::INFINITY).is_none() {
            return false;
        }
        // Median splits keep the depth near log2(triangles / 4): a fixed
        // stack of 64 is far more than a mesh of 2^32 triangles needs.
        let mut stack = [0usize; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top]];
            if node.count > 0 {
                for &t in &self.order[node.start..node.start + node.count] {
                    if ray_triangle(o, d, self.mesh.triangle(t)).is_some_and(|h| h > self.eps) {
                        return true;
                    }
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
        false
    }

    /// True when no ray from `p` escapes (see the module doc).
    pub fn hidden(&self, p: Point3) -> bool {
        self.directions.iter().all(|&d| self.blocked(p, d))
    }
}

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
    index
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::uv_sphere;

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
    }
}
