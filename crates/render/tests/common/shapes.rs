//! Meshes of known shapes for the renderer's tests and benchmark: closed,
//! watertight (shared vertices), triangles counter-clockwise from outside.

#![allow(dead_code)]

use std::f64::consts::TAU;
use trigbody_core::{Mesh, Point3, Real, Vec3};

/// Makes the triangles face outwards (positive signed volume).
fn outward(mut mesh: Mesh) -> Mesh {
    if mesh.signed_volume() < 0.0 {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    mesh
}

/// A cylinder of radius `r` along +y from `y = 0` to `y = h`, with flat caps:
/// `segments` around (a vertex at angle 0, on +x), one ring per end and a
/// centre vertex per cap.
pub fn capped_cylinder(r: Real, h: Real, segments: u32) -> Mesh {
    let n = segments;
    let mut positions: Vec<Point3> = Vec::new();
    for y in [0.0, h] {
        for i in 0..n {
            let a = TAU * i as Real / n as Real;
            positions.push(Vec3::new(r * a.cos(), y, r * a.sin()));
        }
    }
    let bottom_centre = positions.len() as u32;
    positions.push(Vec3::new(0.0, 0.0, 0.0));
    positions.push(Vec3::new(0.0, h, 0.0));
    let top_centre = bottom_centre + 1;
    let mut triangles = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        let (b0, b1, t0, t1) = (i, j, n + i, n + j);
        triangles.push([b0, t0, b1]);
        triangles.push([b1, t0, t1]);
        triangles.push([top_centre, t1, t0]);
        triangles.push([bottom_centre, b0, b1]);
    }
    outward(Mesh::new(positions, triangles).expect("valid cylinder"))
}

/// A UV sphere of radius `r` about `centre`: `rings` bands of latitude,
/// `segments` around, one vertex at each pole; exact vertex normals.
pub fn uv_sphere(centre: Point3, r: Real, rings: u32, segments: u32) -> Mesh {
    let mut positions = vec![centre + Vec3::new(0.0, r, 0.0)];
    for k in 1..rings {
        let polar = std::f64::consts::PI * k as Real / rings as Real;
        for i in 0..segments {
            let a = TAU * i as Real / segments as Real;
            let d = Vec3::new(polar.sin() * a.cos(), polar.cos(), polar.sin() * a.sin());
            positions.push(centre + d * r);
        }
    }
    positions.push(centre - Vec3::new(0.0, r, 0.0));
    let south = positions.len() as u32 - 1;
    let ring = |k: u32, i: u32| 1 + (k - 1) * segments + i % segments;
    let mut triangles = Vec::new();
    for i in 0..segments {
        triangles.push([0, ring(1, i + 1), ring(1, i)]);
        triangles.push([south, ring(rings - 1, i), ring(rings - 1, i + 1)]);
    }
    for k in 1..rings - 1 {
        for i in 0..segments {
            let (a, b, c, d) = (
                ring(k, i),
                ring(k, i + 1),
                ring(k + 1, i),
                ring(k + 1, i + 1),
            );
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    let mut mesh = outward(Mesh::new(positions, triangles).expect("valid sphere"));
    mesh.normals = Some(
        mesh.positions
            .iter()
            .map(|p| (*p - centre) * (1.0 / r))
            .collect(),
    );
    mesh
}

/// A torus about the y axis (major radius `big`, tube radius `small`) with
/// `2 · around · tube` triangles.
pub fn torus(big: Real, small: Real, around: u32, tube: u32) -> Mesh {
    let mut positions = Vec::with_capacity((around * tube) as usize);
    for i in 0..around {
        let u = TAU * i as Real / around as Real;
        for j in 0..tube {
            let v = TAU * j as Real / tube as Real;
            let rho = big + small * v.cos();
            positions.push(Vec3::new(rho * u.cos(), small * v.sin(), rho * u.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % around) * tube + j % tube;
    let mut triangles = Vec::with_capacity((2 * around * tube) as usize);
    for i in 0..around {
        for j in 0..tube {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i, j + 1), id(i + 1, j + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    outward(Mesh::new(positions, triangles).expect("valid torus"))
}
