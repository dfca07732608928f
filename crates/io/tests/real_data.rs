//! The project's real bodies and scan (from `../shared/data`; skipped with a
//! note when that folder is not beside the repository).

mod common;

use common::{is_closed_and_oriented, shared_data};
use trigbody_core::Mesh;
use trigbody_io::{read_geometry, read_mesh, Geometry, ReadOptions};

fn check_body(mesh: &Mesh, name: &str, height: f64, triangles: usize) {
    assert_eq!(mesh.positions.len(), 13380, "{name}");
    assert_eq!(mesh.triangles.len(), triangles, "{name}");
    assert!(is_closed_and_oriented(mesh), "{name} is not closed");
    let b = mesh.bounds().unwrap();
    let h = b.size().y;
    assert!(
        (h - height).abs() < 0.01,
        "{name}: height {h}, expected {height}"
    );
    assert!(
        (b.min.y + 0.82).abs() < 0.03,
        "{name}: feet at y = {}",
        b.min.y
    );
    // Outward orientation: positive volume of a plausible body (40–120 L).
    let v = mesh.signed_volume();
    assert!((0.04..0.12).contains(&v), "{name}: volume {v} m³");
}

#[test]
fn makehuman_bodies() {
    let Some(data) = shared_data() else { return };
    let o = ReadOptions::default();
    for (name, height) in [("mh_base.obj", 1.67), ("mh_male.obj", 1.73)] {
        let m = read_mesh(data.join("bodies").join(name), &o).unwrap();
        check_body(&m, name, height, 2 * 13378);
    }
    let m = read_mesh(data.join("bodies/mh_female.ply"), &o).unwrap();
    check_body(&m, "mh_female.ply", 1.59, 26756);
}

#[test]
fn simulated_scan() {
    let Some(data) = shared_data() else { return };
    let g = read_geometry(data.join("scans/mh_male_scan.ply"), &ReadOptions::default()).unwrap();
    let Geometry::Points(p) = g else {
        panic!("the scan has no faces")
    };
    assert_eq!(p.positions.len(), 200_000);
    let normals = p.normals.as_ref().expect("the scan has normals");
    assert_eq!(normals.len(), 200_000);
    let unit = normals
        .iter()
        .filter(|n| (n.norm() - 1.0).abs() < 1e-3)
        .count();
    assert!(unit > 199_000, "{unit} unit normals");
    let b = p.bounds().unwrap();
    assert!(
        (b.size().y - 1.73).abs() < 0.03,
        "scan height {}",
        b.size().y
    );
    assert!((b.min.y + 0.82).abs() < 0.05, "scan feet at {}", b.min.y);
}

#[test]
fn z_up_and_millimetres_give_the_same_body() {
    let Some(data) = shared_data() else { return };
    let path = data.join("bodies/mh_female.ply");
    let plain = read_mesh(&path, &ReadOptions::default()).unwrap();
    // Write the body z-up in millimetres, read it back with options.
    let mut zup = plain.clone();
    for p in &mut zup.positions {
        *p = trigbody_core::Vec3::new(p.x, -p.z, p.y) * 1000.0;
    }
    let mut bytes = Vec::new();
    trigbody_io::ply::write_mesh(
        &mut bytes,
        &zup,
        &trigbody_io::WriteOptions {
            ply_precision: trigbody_io::PlyPrecision::Double,
            ..Default::default()
        },
    )
    .unwrap();
    let options = ReadOptions {
        scale: 0.001,
        up_axis: trigbody_io::UpAxis::PlusZ,
    };
    let Geometry::Mesh(back) = trigbody_io::ply::read(bytes.as_slice(), &options).unwrap() else {
        panic!("mesh expected")
    };
    for (a, b) in plain.positions.iter().zip(&back.positions) {
        assert!((*a - *b).norm() < 1e-12);
    }
    assert_eq!(plain.triangles, back.triangles);
}
