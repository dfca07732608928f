//! Closed triangle meshes of simple solids with known sections: a UV sphere,
//! a capped cylinder, a torus, and a crude "body" (trunk, two legs, two
//! arms and a head built from capped cylinders and a sphere). They serve as
//! exact references in tests and as synthetic input in benchmarks.
//!
//! Every mesh is closed and outward oriented (counter-clockwise triangles seen
//! from outside), with the axis of symmetry along `axis`-independent world +z
//! unless stated otherwise.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::Mesh;
use std::f64::consts::{PI, TAU};

/// A UV sphere of radius `r` about `center`: `stacks ≥ 2` rings of latitude
/// (poles included as single vertices) and `slices ≥ 3` meridians, poles on
/// the z axis.
pub fn uv_sphere(center: Point3, r: Real, stacks: usize, slices: usize) -> Mesh {
    let stacks = stacks.max(2);
    let slices = slices.max(3);
    let mut positions = vec![center + Vec3::new(0.0, 0.0, -r)];
    for i in 1..stacks {
        let phi = -PI / 2.0 + PI * i as Real / stacks as Real;
        for j in 0..slices {
            let th = TAU * j as Real / slices as Real;
            positions.push(
                center
                    + Vec3::new(
                        r * phi.cos() * th.cos(),
                        r * phi.cos() * th.sin(),
                        r * phi.sin(),
                    ),
            );
        }
    }
    positions.push(center + Vec3::new(0.0, 0.0, r));
    let top = (positions.len() - 1) as u32;
    let ring = |i: usize, j: usize| (1 + (i - 1) * slices + j % slices) as u32;
    let mut triangles = Vec::new();
    for j in 0..slices {
        triangles.push([0, ring(1, j + 1), ring(1, j)]);
        triangles.push([top, ring(stacks - 1, j), ring(stacks - 1, j + 1)]);
    }
    for i in 1..stacks - 1 {
        for j in 0..slices {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j + 1),
                ring(i + 1, j),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Mesh {
        positions,
        normals: None,
        triangles,
    }
}

/// A closed cylinder of radius `r` around the vertical line through `base`
/// (world z), from `base.z` to `base.z + height`, with `rings ≥ 2` rings of
/// `slices ≥ 3` vertices and flat caps (a centre vertex each).
pub fn cylinder(base: Point3, r: Real, height: Real, rings: usize, slices: usize) -> Mesh {
    let rings = rings.max(2);
    let slices = slices.max(3);
    let mut positions = Vec::with_capacity(rings * slices + 2);
    for i in 0..rings {
        let z = height * i as Real / (rings - 1) as Real;
        for j in 0..slices {
            let th = TAU * j as Real / slices as Real;
            positions.push(base + Vec3::new(r * th.cos(), r * th.sin(), z));
        }
    }
    let bottom = positions.len() as u32;
    positions.push(base);
    let top = positions.len() as u32;
    positions.push(base + Vec3::new(0.0, 0.0, height));
    let v = |i: usize, j: usize| (i * slices + j % slices) as u32;
    let mut triangles = Vec::new();
    for i in 0..rings - 1 {
        for j in 0..slices {
            let (a, b, c, d) = (v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    for j in 0..slices {
        triangles.push([bottom, v(0, j + 1), v(0, j)]);
        triangles.push([top, v(rings - 1, j), v(rings - 1, j + 1)]);
    }
    Mesh {
        positions,
        normals: None,
        triangles,
    }
}

/// The box `lo..hi`: its eight corners, twelve triangles facing out.
pub fn cuboid(lo: Point3, hi: Point3) -> Mesh {
    let corner = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    let triangles = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    Mesh {
        positions: (0..8).map(corner).collect(),
        normals: None,
        triangles,
    }
}

/// A torus around the z axis through `center`: major radius `big_r` (centre
/// of the tube), minor radius `r`, `n_major × n_minor` vertices.
pub fn torus(center: Point3, big_r: Real, r: Real, n_major: usize, n_minor: usize) -> Mesh {
    let (nm, nn) = (n_major.max(3), n_minor.max(3));
    let mut positions = Vec::with_capacity(nm * nn);
    for i in 0..nm {
        let u = TAU * i as Real / nm as Real;
        for j in 0..nn {
            let w = TAU * j as Real / nn as Real;
            let rr = big_r + r * w.cos();
            positions.push(center + Vec3::new(rr * u.cos(), rr * u.sin(), r * w.sin()));
        }
    }
    let v = |i: usize, j: usize| ((i % nm) * nn + j % nn) as u32;
    let mut triangles = Vec::new();
    for i in 0..nm {
        for j in 0..nn {
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Mesh {
        positions,
        normals: None,
        triangles,
    }
}

/// Concatenates meshes (no welding): the union of separate closed solids.
pub fn merge(meshes: &[Mesh]) -> Mesh {
    Mesh {
        normals: None,
        ..crate::geom::mesh::concatenate(meshes).0
    }
}

/// A crude standing "body" about 1.7 units tall along +z, facing +y, built
/// from separate closed solids (which overlap, as a body's parts do not):
/// two legs, a trunk, two vertical arms beside the trunk, a neck and a head.
/// `detail` scales the vertex count: about 3 300 `detail²` vertices
/// (detail 2 ≈ 13 000, like the MakeHuman bodies).
pub fn stick_body(detail: usize) -> Mesh {
    let d = detail.clamp(1, 16);
    let (rings, slices) = (12 * d, 48 * d);
    merge(&[
        cylinder(Vec3::new(-0.1, 0.0, 0.0), 0.07, 0.85, rings, slices),
        cylinder(Vec3::new(0.1, 0.0, 0.0), 0.07, 0.85, rings, slices),
        cylinder(Vec3::new(0.0, 0.0, 0.8), 0.16, 0.65, rings, slices),
        cylinder(Vec3::new(-0.23, 0.0, 0.75), 0.045, 0.65, rings, slices),
        cylinder(Vec3::new(0.23, 0.0, 0.75), 0.045, 0.65, rings, slices),
        cylinder(Vec3::new(0.0, 0.0, 1.42), 0.055, 0.08, rings / 4, slices),
        uv_sphere(Vec3::new(0.0, 0.0, 1.6), 0.11, 8 * d, slices),
    ])
}
