//! Self-intersections of a triangle mesh: every pair of triangles whose
//! boxes overlap (found by descending a box hierarchy against itself) is
//! tested edge by edge against the other triangle.
//!
//! Two triangles that do not lie in one plane intersect exactly when an
//! edge of one crosses the other, so each pair's six edge–triangle tests
//! decide it; crossings within a relative `1e-9` of an edge's ends or of the
//! other triangle's boundary count as touching, not crossing (coplanar
//! overlaps are not detected). Triangles sharing an edge are neighbours;
//! triangles sharing one vertex intersect only where they meet away from
//! it.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{Aabb, Mesh};

const EPS: Real = 1e-9;

/// The boxes of `m`'s triangles.
pub(crate) fn triangle_boxes(m: &Mesh) -> Vec<Aabb> {
    (0..m.triangles.len())
        .map(|t| {
            let [a, b, c] = m.triangle(t);
            Aabb {
                min: a.min(b).min(c),
                max: a.max(b).max(c),
            }
        })
        .collect()
}

/// The number of intersecting pairs of `m`'s triangles (see the module doc).
pub fn intersecting_pairs(m: &Mesh) -> usize {
    intersecting_pair_list(m).len()
}

/// The intersecting pairs of `m`'s triangles (see the module doc), in the
/// hierarchy's order.
pub fn intersecting_pair_list(m: &Mesh) -> Vec<(u32, u32)> {
    let tree = Tree::new(&triangle_boxes(m));
    let mut pairs = Vec::new();
    tree.overlapping_pairs(&mut pairs);
    let crossing = |chunk: &[(u32, u32)]| -> Vec<(u32, u32)> {
        chunk
            .iter()
            .copied()
            .filter(|&(s, t)| pair_intersects(m, s as usize, t as usize))
            .collect()
    };
    let chunks: Vec<&[(u32, u32)]> = pairs.chunks(4096).collect();
    crate::geom::parallel::each_on_cores(&chunks, |c| crossing(c))
        .into_iter()
        .flatten()
        .collect()
}

/// Whether triangles `s` and `t` of `m` intersect (module doc).
fn pair_intersects(m: &Mesh, s: usize, t: usize) -> bool {
    pair_intersects_within(m, s, t, EPS)
}

/// Whether triangles `s` and `t` of `m` intersect, crossings within a
/// relative `eps` of a boundary counting as touching (a negative `eps`
/// counts near misses as crossings: a conservative test).
pub(crate) fn pair_intersects_within(m: &Mesh, s: usize, t: usize, eps: Real) -> bool {
    let (ts, tt) = (m.triangles[s], m.triangles[t]);
    let shared: Vec<u32> = ts.iter().copied().filter(|v| tt.contains(v)).collect();
    if shared.len() >= 2 {
        return false;
    }
    let (ps, pt) = (m.triangle(s), m.triangle(t));
    let crosses = |tri_a: [u32; 3], pa: [Point3; 3], pb: [Point3; 3]| {
        (0..3).any(|k| {
            let (i, j) = (k, (k + 1) % 3);
            // From a shared vertex, only a crossing away from it counts
            // (the edge is run from that vertex, the start excluded).
            let (from, to) = if shared.first() == Some(&tri_a[j]) {
                (pa[j], pa[i])
            } else {
                (pa[i], pa[j])
            };
            segment_crosses(from, to, pb, eps)
        })
    };
    crosses(ts, ps, pt) || crosses(tt, pt, ps)
}

/// Whether the segment `p → q` crosses triangle `tri` strictly inside
/// both (module doc's tolerance).
fn segment_crosses(p: Point3, q: Point3, [a, b, c]: [Point3; 3], eps: Real) -> bool {
    let d = q - p;
    let (e1, e2) = (b - a, c - a);
    let h = d.cross(e2);
    let det = e1.dot(h);
    let scale = e1.norm() * e2.norm() * d.norm();
    if !(det.abs() > EPS * scale) {
        return false;
    }
    let s = p - a;
    let u = s.dot(h) / det;
    let qv = s.cross(e1);
    let v = d.dot(qv) / det;
    let t = e2.dot(qv) / det;
    u > eps && v > eps && u + v < 1.0 - eps && t > eps && t < 1.0 - eps
}

/// Where the ray `o + s d`, `s > 0`, crosses triangle `[a, b, c]`: `Some(s)`,
/// or `None` when it misses; `Err(())` when it passes within a relative
/// `1e-9` of the triangle's boundary or its plane contains the ray, where
/// the crossing is undecided.
pub(crate) fn ray_crosses(o: Point3, d: Vec3, [a, b, c]: [Point3; 3]) -> Result<Option<Real>, ()> {
    let (e1, e2) = (b - a, c - a);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if !(det.abs() > EPS * e1.norm() * e2.norm() * d.norm()) {
        // Parallel: a miss unless the ray lies in the plane.
        let n = e1.cross(e2);
        return if (o - a).dot(n).abs() > EPS * n.norm() * (o - a).norm().max(e1.norm()) {
            Ok(None)
        } else {
            Err(())
        };
    }
    let s = o - a;
    let u = s.dot(h) / det;
    let qv = s.cross(e1);
    let v = d.dot(qv) / det;
    let t = e2.dot(qv) / det;
    let inside = u > EPS && v > EPS && u + v < 1.0 - EPS;
    let outside = u < -EPS || v < -EPS || u + v > 1.0 + EPS;
    if outside || t < -EPS {
        Ok(None)
    } else if inside && t > EPS {
        Ok(Some(t))
    } else {
        Err(())
    }
}

/// A box hierarchy over boxes: nodes with two children or a run of
/// leaves' indices.
pub(crate) struct Tree {
    nodes: Vec<Node>,
    order: Vec<u32>,
    boxes: Vec<Aabb>,
}

struct Node {
    bounds: Aabb,
    /// Children (`left`, `left + 1`) or, for a leaf, `order[start..end]`.
    kind: Kind,
}

enum Kind {
    Inner(usize, usize),
    Leaf(usize, usize),
}

impl Tree {
    pub(crate) fn new(boxes: &[Aabb]) -> Tree {
        let mut tree = Tree {
            nodes: Vec::new(),
            order: (0..boxes.len() as u32).collect(),
            boxes: boxes.to_vec(),
        };
        if !boxes.is_empty() {
            tree.build(0, boxes.len());
        }
        tree
    }

    /// Builds the node over `order[start..end]`, returning its index.
    fn build(&mut self, start: usize, end: usize) -> usize {
        let bounds = self.order[start..end]
            .iter()
            .map(|&i| self.boxes[i as usize])
            .reduce(|a, b| Aabb {
                min: a.min.min(b.min),
                max: a.max.max(b.max),
            })
            .unwrap_or(Aabb {
                min: Point3::ZERO,
                max: Point3::ZERO,
            });
        let index = self.nodes.len();
        self.nodes.push(Node {
            bounds,
            kind: Kind::Leaf(start, end),
        });
        if end - start <= 8 {
            return index;
        }
        let size = bounds.size();
        let axis = if size.x >= size.y && size.x >= size.z {
            0
        } else if size.y >= size.z {
            1
        } else {
            2
        };
        let key = |b: &Aabb| {
            let c = b.center();
            [c.x, c.y, c.z][axis]
        };
        let mid = (start + end) / 2;
        let boxes = &self.boxes;
        self.order[start..end].select_nth_unstable_by(mid - start, |&i, &j| {
            key(&boxes[i as usize]).total_cmp(&key(&boxes[j as usize]))
        });
        let left = self.build(start, mid);
        let right = self.build(mid, end);
        self.nodes[index].kind = Kind::Inner(left, right);
        index
    }

    /// Every pair `(i, j)`, `i < j`, of boxes that overlap.
    pub(crate) fn overlapping_pairs(&self, out: &mut Vec<(u32, u32)>) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![(0usize, 0usize)];
        while let Some((a, b)) = stack.pop() {
            let (na, nb) = (&self.nodes[a], &self.nodes[b]);
            if !na.bounds.overlaps(&nb.bounds) {
                continue;
            }
            match (&na.kind, &nb.kind) {
                (Kind::Leaf(s0, e0), Kind::Leaf(s1, e1)) => {
                    for x in *s0..*e0 {
                        let from = if a == b { x + 1 } else { *s1 };
                        for y in from..*e1 {
                            let (i, j) = (self.order[x], self.order[y]);
                            if self.boxes[i as usize].overlaps(&self.boxes[j as usize]) {
                                out.push((i.min(j), i.max(j)));
                            }
                        }
                    }
                }
                (Kind::Inner(l, r), _) if a == b => {
                    stack.extend([(*l, *l), (*r, *r), (*l, *r)]);
                }
                (Kind::Inner(l, r), Kind::Leaf(..)) => stack.extend([(*l, b), (*r, b)]),
                (Kind::Leaf(..), Kind::Inner(l, r)) => stack.extend([(a, *l), (a, *r)]),
                (Kind::Inner(l0, r0), Kind::Inner(l1, r1)) => {
                    stack.extend([(*l0, *l1), (*l0, *r1), (*r0, *l1), (*r0, *r1)]);
                }
            }
        }
    }
}

impl Tree {
    /// Calls `f` with every box the ray `o + s d`, `s >= 0`, may pass
    /// through (a slab test per node, slightly widened).
    pub(crate) fn along_ray(&self, o: Point3, d: Vec3, mut f: impl FnMut(usize)) {
        if self.nodes.is_empty() {
            return;
        }
        let hits = |b: &Aabb| {
            let (mut lo, mut hi) = (0.0 as Real, Real::INFINITY);
            for (o, d, min, max) in [
                (o.x, d.x, b.min.x, b.max.x),
                (o.y, d.y, b.min.y, b.max.y),
                (o.z, d.z, b.min.z, b.max.z),
            ] {
                let pad = 1e-9 * (max - min).abs().max(1e-12);
                let (min, max) = (min - pad, max + pad);
                if d == 0.0 {
                    if o < min || o > max {
                        return false;
                    }
                    continue;
                }
                let (a, b) = ((min - o) / d, (max - o) / d);
                lo = lo.max(a.min(b));
                hi = hi.min(a.max(b));
            }
            lo <= hi
        };
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            if !hits(&node.bounds) {
                continue;
            }
            match node.kind {
                Kind::Inner(l, r) => stack.extend([l, r]),
                Kind::Leaf(s, e) => {
                    for &i in &self.order[s..e] {
                        if hits(&self.boxes[i as usize]) {
                            f(i as usize);
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::math::Vec3;

    fn tris(ts: &[[Point3; 3]]) -> Mesh {
        Mesh {
            positions: ts.iter().flatten().copied().collect(),
            normals: None,
            triangles: (0..ts.len() as u32)
                .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
                .collect(),
        }
    }

    #[test]
    fn crossing_and_apart_triangles() {
        let p = |x, y, z| Vec3::new(x, y, z);
        let flat = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
        let through = [p(0.2, 0.2, -1.0), p(0.3, 0.2, 1.0), p(0.2, 0.3, 1.0)];
        let above = [p(0.2, 0.2, 0.5), p(0.3, 0.2, 1.0), p(0.2, 0.3, 1.0)];
        assert_eq!(intersecting_pairs(&tris(&[flat, through])), 1);
        assert_eq!(intersecting_pairs(&tris(&[flat, above])), 0);
        // A closed box (shared vertices, neighbours everywhere) has none.
        let cube = crate::geom::shapes::cylinder(Vec3::new(0.0, 0.0, 0.0), 1.0, 2.0, 6, 24);
        assert_eq!(intersecting_pairs(&cube), 0);
        // Many triangles: the hierarchy finds the one crossing pair.
        let mut many: Vec<[Point3; 3]> = (0..200)
            .map(|k| {
                let x = 3.0 * k as Real;
                [p(x, 5.0, 0.0), p(x + 1.0, 5.0, 0.0), p(x, 6.0, 0.0)]
            })
            .collect();
        many.push(flat);
        many.push(through);
        assert_eq!(intersecting_pairs(&tris(&many)), 1);
    }
}
