//! Small files written to look like other programs' output.

mod common;

use common::{fixture, is_closed_and_oriented};
use trigbody_core::{assert_near, Mesh, Vec3};
use trigbody_io::{read_geometry, read_mesh, read_point_cloud, Geometry, ReadOptions};

fn mesh(name: &str) -> Mesh {
    read_mesh(fixture(name), &ReadOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn assert_unit_cube(name: &str, m: &Mesh) {
    assert_eq!(m.positions.len(), 8, "{name}");
    assert_eq!(m.triangles.len(), 12, "{name}");
    assert!(is_closed_and_oriented(m), "{name} is not closed");
    assert_near!(m.signed_volume(), 1.0, 1e-12);
    assert_near!(m.surface_area(), 6.0, 1e-12);
}

#[test]
fn ascii_ply_with_colours_and_quads() {
    let m = mesh("cube_ascii.ply");
    assert_unit_cube("cube_ascii.ply", &m);
    assert!(m.normals.is_none());
}

#[test]
fn binary_little_endian_ply_with_normals_colours_and_extra_element() {
    let m = mesh("cube_binary_le.ply");
    assert_unit_cube("cube_binary_le.ply", &m);
    let n = m.normals.as_ref().expect("normals");
    let expected = (Vec3::new(-0.5, -0.5, -0.5)).normalized().unwrap();
    assert!((n[0] - expected).norm() < 1e-6);
}

#[test]
fn binary_big_endian_ply_with_doubles_quads_crlf_header_and_edges() {
    let m = mesh("cube_binary_be.ply");
    assert_unit_cube("cube_binary_be.ply", &m);
    assert_eq!(m.positions[6], Vec3::new(1.0, 1.0, 1.0));
}

#[test]
fn ply_without_faces_is_a_point_cloud() {
    let g = read_geometry(fixture("points_binary_le.ply"), &ReadOptions::default()).unwrap();
    let Geometry::Points(p) = g else {
        panic!("expected points")
    };
    assert_eq!(p.positions.len(), 8);
    assert_eq!(p.normals.as_ref().map(Vec::len), Some(8));
    // read_mesh refuses it with a clear error.
    let e = read_mesh(fixture("points_binary_le.ply"), &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("no faces"), "{e}");
}

#[test]
fn obj_from_blender_with_uvs_normals_quads_groups_and_materials() {
    let m = mesh("cube_blender.obj");
    assert_unit_cube("cube_blender.obj", &m);
    // Each corner of the cube has three face normals: their mean.
    let n = m.normals.as_ref().expect("normals");
    let expected = Vec3::new(-1.0, -1.0, -1.0).normalized().unwrap();
    assert!((n[0] - expected).norm() < 1e-12, "{:?}", n[0]);
}

#[test]
fn obj_with_relative_indices_and_crlf() {
    let m = mesh("tetra_relative.obj");
    assert_eq!(m.positions.len(), 4);
    assert_eq!(
        m.triangles,
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    );
    assert!(is_closed_and_oriented(&m));
    assert_near!(m.signed_volume(), 1.0 / 6.0, 1e-15);
    // Not every corner names a normal: no normals.
    assert!(m.normals.is_none());
}

#[test]
fn ascii_stl_corners_are_merged() {
    assert_unit_cube("cube_ascii.stl", &mesh("cube_ascii.stl"));
}

#[test]
fn binary_stl_whose_header_begins_with_solid() {
    assert_unit_cube(
        "cube_binary_solid_header.stl",
        &mesh("cube_binary_solid_header.stl"),
    );
}

#[test]
fn csv_with_header_maps_columns_by_name() {
    let p = read_point_cloud(fixture("points_header.csv"), &ReadOptions::default()).unwrap();
    assert_eq!(p.positions.len(), 4);
    assert_eq!(p.positions[2], Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(
        p.normals.as_ref().unwrap()[1],
        Vec3::new(0.577, -0.577, -0.577)
    );
}

#[test]
fn cloudcompare_header_puts_normals_after_colours() {
    let p = read_point_cloud(fixture("points_cloudcompare.txt"), &ReadOptions::default()).unwrap();
    assert_eq!(p.positions[1], Vec3::new(-0.5, 0.25, 1.75));
    assert_eq!(p.normals.as_ref().unwrap()[1], Vec3::new(0.0, 1.0, 0.0));
}

#[test]
fn xyz_with_comments_tabs_and_millimetres() {
    let options = ReadOptions {
        scale: 0.001,
        ..ReadOptions::default()
    };
    let p = read_point_cloud(fixture("points.xyz"), &options).unwrap();
    assert_eq!(p.positions.len(), 3);
    assert!(p.normals.is_none());
    assert!((p.positions[0] - Vec3::new(0.0105, 0.02025, 0.030)).norm() < 1e-15);
    assert!((p.positions[1] - Vec3::new(-0.010, 0.025, 0.003)).norm() < 1e-15);
}

#[test]
fn extension_is_case_insensitive() {
    let dir = std::env::temp_dir().join(format!("trigbody-io-ext-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("CUBE.PLY");
    std::fs::copy(fixture("cube_ascii.ply"), &path).unwrap();
    assert_unit_cube(
        "CUBE.PLY",
        &read_mesh(&path, &ReadOptions::default()).unwrap(),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn xyz_rgb_columns_are_not_taken_for_normals() {
    let g = trigbody_io::read_bytes(
        b"0.1 0.2 0.3 255 128 0\n0.4 0.5 0.6 10 20 30\n",
        trigbody_io::Format::Xyz,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(g.positions().len(), 2);
    assert!(g.normals().is_none());
    let g = trigbody_io::read_bytes(
        b"0.1 0.2 0.3 0 0 1\n",
        trigbody_io::Format::Xyz,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(g.normals(), Some(&[Vec3::Z][..]));
}

#[test]
fn obj_continuation_lines_and_backslash_in_comments() {
    let text = "# saved to C:\\models\\\nv 0 0 0\nv 1 0 \\\n 0\nv 0 1 0\nf 1 \\\n2 3\n";
    let g = trigbody_io::read_bytes(
        text.as_bytes(),
        trigbody_io::Format::Obj,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(g.positions().len(), 3);
    assert_eq!(g.positions()[1], Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(g.triangles(), &[[0, 1, 2]]);
}

#[test]
fn binary_stl_with_a_zero_count_from_a_streaming_writer() {
    let mut d = vec![b' '; 80];
    d.extend_from_slice(&0u32.to_le_bytes());
    for t in [
        [0f32, 0., 0., 1., 0., 0., 0., 1., 0.],
        [0., 0., 0., 0., 1., 0., 0., 0., 1.],
    ] {
        d.extend_from_slice(&[0; 12]);
        for c in t {
            d.extend_from_slice(&c.to_le_bytes());
        }
        d.extend_from_slice(&[0; 2]);
    }
    let g = trigbody_io::read_bytes(&d, trigbody_io::Format::Stl, &ReadOptions::default()).unwrap();
    assert_eq!(g.triangles().len(), 2);
    assert_eq!(g.positions().len(), 4);
}

#[test]
fn ascii_ply_unused_integer_columns_may_hold_decimals() {
    let d = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty int x\nproperty int y\nproperty int z\nproperty uchar red\nproperty list uchar int tex\nend_header\n1 2 3 255.0 2 0.5 1.5\n";
    let g = trigbody_io::read_bytes(d, trigbody_io::Format::Ply, &ReadOptions::default()).unwrap();
    assert_eq!(g.positions(), &[Vec3::new(1.0, 2.0, 3.0)]);
}
