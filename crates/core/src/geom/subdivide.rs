//! One step of Loop subdivision (Loop 1987): every triangle split in four,
//! the new edge points and the old vertices moved by Loop's masks (Warren's
//! weights `β = 3/16` at valence 3, `3/(8n)` above). Boundary edges (in one
//! triangle) get their midpoint and boundary vertices stay put, so an open
//! mesh keeps its rims. A smooth copy of a mesh: the floor its own
//! smoothness sets for a smooth model's distance and normal errors.

use crate::geom::math::{Real, Vec3};
use crate::geom::mesh::Mesh;
use std::collections::HashMap;

/// `m` subdivided once (see the module doc; normals are not carried).
pub fn loop_subdivide(m: &Mesh) -> Mesh {
    let nv = m.positions.len();
    // Each undirected edge: its new vertex index and its opposite corners.
    let mut edges: HashMap<(u32, u32), (u32, Vec<u32>)> = HashMap::new();
    let mut positions = m.positions.clone();
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let key = (a.min(b), a.max(b));
            let next = (nv + edges.len()) as u32;
            edges.entry(key).or_insert((next, Vec::new())).1.push(c);
        }
    }
    positions.resize(nv + edges.len(), Vec3::ZERO);
    // Neighbours of each old vertex, and whether it is on a boundary.
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); nv];
    let mut boundary = vec![false; nv];
    for (&(a, b), (index, opposite)) in &edges {
        let (pa, pb) = (m.positions[a as usize], m.positions[b as usize]);
        positions[*index as usize] = if opposite.len() == 2 {
            let (c, d) = (
                m.positions[opposite[0] as usize],
                m.positions[opposite[1] as usize],
            );
            (pa + pb) * (3.0 / 8.0) + (c + d) * (1.0 / 8.0)
        } else {
            boundary[a as usize] = true;
            boundary[b as usize] = true;
            (pa + pb) * 0.5
        };
        neighbours[a as usize].push(b);
        neighbours[b as usize].push(a);
    }
    for v in 0..nv {
        // In index order: the sum does not depend on the map's order.
        neighbours[v].sort_unstable();
        let n = neighbours[v].len();
        if boundary[v] || n < 3 {
            continue;
        }
        let beta: Real = if n == 3 {
            3.0 / 16.0
        } else {
            3.0 / (8.0 * n as Real)
        };
        let sum = neighbours[v]
            .iter()
            .fold(Vec3::ZERO, |s, &w| s + m.positions[w as usize]);
        positions[v] = m.positions[v] * (1.0 - n as Real * beta) + sum * beta;
    }
    let mid = |a: u32, b: u32| edges[&(a.min(b), a.max(b))].0;
    let mut triangles = Vec::with_capacity(4 * m.triangles.len());
    for &[a, b, c] in &m.triangles {
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Mesh {
        positions,
        normals: None,
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere's subdivision has four times the triangles, stays closed,
    /// and its vertices move towards the centre by little (Loop shrinks a
    /// convex surface).
    #[test]
    fn sphere_subdivides_smoothly() {
        let s = crate::geom::shapes::uv_sphere(Vec3::ZERO, 1.0, 16, 32);
        let d = loop_subdivide(&s);
        assert_eq!(d.triangles.len(), 4 * s.triangles.len());
        let v0 = s.signed_volume();
        let v1 = d.signed_volume();
        assert!(v1 > 0.97 * v0 && v1 < 1.0 * v0 + 1e-9, "{v0} {v1}");
        for p in &d.positions {
            let r = p.norm();
            assert!(r > 0.97 && r < 1.0 + 1e-9, "{r}");
        }
    }

    /// A flat open square stays flat and keeps its rim.
    #[test]
    fn open_plane_keeps_its_rim() {
        let m = Mesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: None,
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let d = loop_subdivide(&m);
        assert_eq!(d.triangles.len(), 8);
        assert!(d.positions.iter().all(|p| p.z == 0.0));
        assert_eq!(&d.positions[..4], &m.positions[..]);
        assert!((d.surface_area() - 1.0).abs() < 1e-12);
    }
}
