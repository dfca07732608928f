//! Closing a mesh's holes: where a scanner saw nothing (a head's crown,
//! the soles, an armpit) or a part was cut away, a mesh has rims of edges
//! that only one triangle uses. Horizontal and part sections through a
//! hole give open chains, which no step can use, so a body with a hole in
//! its shoulder loses everything above the hole. [`close_holes`] fans each
//! rim from its centroid, with the orientation of the triangles around it.
//!
//! Vertices at the same position are one vertex here (an unwelded seam is
//! no hole), and an edge shared by three or more triangles is no rim.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::Mesh;
use std::collections::HashMap;

/// What [`close_holes`] closed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ClosedHoles {
    /// Rims closed.
    pub holes: usize,
    /// Their total length.
    pub rim_length: Real,
    /// The area added, as a fraction of the mesh's own.
    pub area_share: Real,
}

/// `mesh` with every hole closed by a fan of triangles from its rim's
/// centroid, and what was closed; `None` when it has no hole. Rims that do
/// not run round consistently (a non-manifold spot) are left open.
pub fn close_holes(mesh: &Mesh) -> Option<(Mesh, ClosedHoles)> {
    let id = canonical_ids(&mesh.positions);
    let mut uses: HashMap<(u32, u32), (u32, [u32; 2])> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (id[t[k] as usize], id[t[(k + 1) % 3] as usize]);
            if a == b {
                continue;
            }
            let e = uses.entry((a.min(b), a.max(b))).or_insert((0, [a, b]));
            e.0 += 1;
        }
    }
    // Round each rim against its triangle's edge: a → b there is b → a here.
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for &(count, [a, b]) in uses.values() {
        if count == 1 {
            next.entry(b).or_default().push(a);
        }
    }
    if next.is_empty() {
        return None;
    }
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let (mut positions, mut normals) = (mesh.positions.clone(), mesh.normals.clone());
    let mut triangles = mesh.triangles.clone();
    let mut closed = ClosedHoles::default();
    let mut added = 0.0;
    for s in starts {
        while let Some(rim) = walk_rim(&mut next, s) {
            let c = rim
                .iter()
                .fold(Vec3::ZERO, |a, &v| a + mesh.positions[v as usize])
                / rim.len() as Real;
            let ci = positions.len() as u32;
            positions.push(c);
            if let Some(n) = normals.as_mut() {
                let sum = rim.iter().fold(Vec3::ZERO, |a, &v| a + n[v as usize]);
                n.push(sum.normalized().unwrap_or(Vec3::ZERO));
            }
            for (k, &v) in rim.iter().enumerate() {
                let w = rim[(k + 1) % rim.len()];
                let (p, q) = (mesh.positions[v as usize], mesh.positions[w as usize]);
                closed.rim_length += p.distance(q);
                added += 0.5 * (p - c).cross(q - c).norm();
                triangles.push([v, w, ci]);
            }
            closed.holes += 1;
        }
    }
    if closed.holes == 0 {
        return None;
    }
    closed.area_share = added / mesh.surface_area().max(Real::MIN_POSITIVE);
    let out = Mesh {
        positions,
        normals,
        triangles,
    };
    Some((out, closed))
}

/// Per vertex the first vertex at its exact position.
fn canonical_ids(positions: &[Point3]) -> Vec<u32> {
    let mut first: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
    positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // +0.0 and -0.0 are the same place.
            let key = p.to_array().map(|c| (c + 0.0).to_bits());
            *first.entry(key).or_insert(i as u32)
        })
        .collect()
}

/// One rim through `start` (its vertices in order), taking its edges out
/// of `next`; `None` when no rim edge leaves `start` or the walk does not
/// come back to it (those edges are dropped).
fn walk_rim(next: &mut HashMap<u32, Vec<u32>>, start: u32) -> Option<Vec<u32>> {
    let mut rim = vec![start];
    let mut at = start;
    loop {
        let to = next.get_mut(&at)?.pop()?;
        if to == start {
            return (rim.len() >= 3).then_some(rim);
        }
        if rim.len() > next.len() + 1 {
            return None;
        }
        rim.push(to);
        at = to;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::shapes::uv_sphere;

    #[test]
    fn a_closed_mesh_has_no_hole() {
        assert!(close_holes(&uv_sphere(Vec3::ZERO, 1.0, 12, 24)).is_none());
    }

    #[test]
    fn a_sphere_without_its_cap_is_closed_again_with_the_same_orientation() {
        let sphere = uv_sphere(Vec3::ZERO, 1.0, 16, 32);
        let mut open = sphere.clone();
        // Drop every triangle with a corner above z = 0.8.
        open.triangles
            .retain(|t| t.iter().all(|&v| sphere.positions[v as usize].z <= 0.8));
        let (closed, what) = close_holes(&open).expect("a hole");
        assert_eq!(what.holes, 1);
        // Closed: every edge in exactly two triangles, each way once.
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        let id = canonical_ids(&closed.positions);
        for t in &closed.triangles {
            for k in 0..3 {
                let (a, b) = (id[t[k] as usize], id[t[(k + 1) % 3] as usize]);
                if a != b {
                    *edges.entry((a, b)).or_default() += 1;
                }
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge {a}-{b}");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {b}-{a} unmatched");
        }
        // Outward like the sphere: the volume is positive and close to the
        // sphere's less its flattened cap.
        let v = closed.signed_volume();
        let top = open
            .triangles
            .iter()
            .flatten()
            .map(|&v| sphere.positions[v as usize].z)
            .fold(Real::MIN, Real::max);
        let h = 1.0 - top;
        let cap = std::f64::consts::PI * h * h * (3.0 - h) / 3.0;
        let full = sphere.signed_volume();
        assert!(
            v > 0.0 && (v - (full - cap)).abs() < 0.02 * full,
            "{v} vs {}",
            full - cap
        );
        // The fan is the rim's flat polygon: a disc of radius √(1 − top²).
        let disc = std::f64::consts::PI * (1.0 - top * top);
        let share = disc / open.surface_area();
        assert!(
            (what.area_share / share - 1.0).abs() < 0.03,
            "{} vs {share}",
            what.area_share
        );
        assert!(
            (what.rim_length / (std::f64::consts::TAU * (1.0 - top * top).sqrt()) - 1.0).abs()
                < 0.01
        );
    }

    #[test]
    fn an_unwelded_seam_is_no_hole() {
        let sphere = uv_sphere(Vec3::ZERO, 1.0, 8, 16);
        // Give every triangle its own three vertices.
        let positions: Vec<Point3> = sphere
            .triangles
            .iter()
            .flat_map(|t| t.map(|v| sphere.positions[v as usize]))
            .collect();
        let triangles = (0..sphere.triangles.len() as u32)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        let soup = Mesh::new(positions, triangles).unwrap();
        assert!(close_holes(&soup).is_none());
    }
}
