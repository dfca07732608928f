//! Write then read gives the same geometry, for every format: exactly for
//! the f64 text formats and double PLY, within f32 precision for float PLY
//! and STL.

mod common;

use common::is_closed_and_oriented;
use proptest::prelude::*;
use trigbody_core::{Mesh, PointCloud, Vec3};
use trigbody_io::{
    obj, ply, read_bytes, read_geometry, stl, write_geometry, write_mesh, write_point_cloud, xyz,
    Format, Geometry, IoError, PlyPrecision, ReadOptions, WriteOptions,
};

/// An octahedron far from the origin with awkward coordinates and unit normals.
fn octahedron() -> Mesh {
    let c = Vec3::new(1234.5678, -0.1, 1e-7);
    let r = 0.123_456_789_012_345_67;
    let dirs = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let positions = dirs.iter().map(|d| c + *d * r).collect();
    let normals = Some(dirs.to_vec());
    let triangles = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    let m = Mesh {
        positions,
        normals,
        triangles,
    };
    m.validate().unwrap();
    assert!(is_closed_and_oriented(&m));
    m
}

fn read_mesh_bytes(data: &[u8], format: Format) -> Mesh {
    match read_bytes(data, format, &ReadOptions::default()).unwrap() {
        Geometry::Mesh(m) => m,
        Geometry::Points(_) => panic!("{format}: expected a mesh"),
    }
}

fn f32_close(a: Vec3, b: Vec3) -> bool {
    let scale = a.norm().max(b.norm()).max(1.0);
    (a - b).norm() <= 2.0 * f32::EPSILON as f64 * scale
}

#[test]
fn obj_mesh_is_exact() {
    let m = octahedron();
    let mut bytes = Vec::new();
    obj::write_mesh(&mut bytes, &m).unwrap();
    assert_eq!(read_mesh_bytes(&bytes, Format::Obj), m);
    let mut plain = m.clone();
    plain.normals = None;
    bytes.clear();
    obj::write_mesh(&mut bytes, &plain).unwrap();
    assert_eq!(read_mesh_bytes(&bytes, Format::Obj), plain);
}

#[test]
fn ply_double_is_exact_and_float_within_f32() {
    let m = octahedron();
    let mut bytes = Vec::new();
    let double = WriteOptions {
        ply_precision: PlyPrecision::Double,
        ..WriteOptions::default()
    };
    ply::write_mesh(&mut bytes, &m, &double).unwrap();
    assert_eq!(read_mesh_bytes(&bytes, Format::Ply), m);

    bytes.clear();
    ply::write_mesh(&mut bytes, &m, &WriteOptions::default()).unwrap();
    let back = read_mesh_bytes(&bytes, Format::Ply);
    assert_eq!(back.triangles, m.triangles);
    for (a, b) in m.positions.iter().zip(&back.positions) {
        assert!(f32_close(*a, *b), "{a:?} vs {b:?}");
    }
    for (a, b) in m.normals.unwrap().iter().zip(back.normals.unwrap().iter()) {
        assert!(f32_close(*a, *b));
    }
}

#[test]
fn stl_keeps_triangles_within_f32() {
    let m = octahedron();
    let mut bytes = Vec::new();
    stl::write_mesh(&mut bytes, &m).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * m.triangles.len());
    assert!(!bytes.starts_with(b"solid"));
    let back = read_mesh_bytes(&bytes, Format::Stl);
    assert_eq!(back.positions.len(), 6, "corners are merged again");
    assert_eq!(back.triangles.len(), m.triangles.len());
    assert!(is_closed_and_oriented(&back));
    for t in 0..m.triangles.len() {
        let (a, b) = (m.triangle(t), back.triangle(t));
        for k in 0..3 {
            assert!(f32_close(a[k], b[k]));
        }
    }
    // STL has no vertex normals; writing stored facet normals computed from
    // the corners.
    let n = |k: usize| f32::from_le_bytes(bytes[84 + 4 * k..88 + 4 * k].try_into().unwrap());
    let expected = Vec3::new(1.0, 1.0, 1.0).normalized().unwrap();
    assert!((Vec3::new(n(0).into(), n(1).into(), n(2).into()) - expected).norm() < 1e-6);
}

#[test]
fn point_clouds_are_exact_in_text_and_double_ply() {
    let m = octahedron();
    let cloud = PointCloud::from(m);
    let mut bytes = Vec::new();
    for delimiter in [xyz::Delimiter::Space, xyz::Delimiter::Comma] {
        bytes.clear();
        xyz::write_points(&mut bytes, &cloud, delimiter).unwrap();
        let back = read_bytes(&bytes, Format::Xyz, &ReadOptions::default()).unwrap();
        assert_eq!(back, Geometry::Points(cloud.clone()), "{delimiter:?}");
    }
    bytes.clear();
    obj::write_points(&mut bytes, &cloud).unwrap();
    let back = read_bytes(&bytes, Format::Obj, &ReadOptions::default()).unwrap();
    assert_eq!(back, Geometry::Points(cloud.clone()));
    bytes.clear();
    let double = WriteOptions {
        ply_precision: PlyPrecision::Double,
        ..WriteOptions::default()
    };
    ply::write_points(&mut bytes, &cloud, &double).unwrap();
    let back = read_bytes(&bytes, Format::Ply, &ReadOptions::default()).unwrap();
    assert_eq!(back, Geometry::Points(cloud));
}

#[test]
fn path_writers_never_overwrite_unless_told() {
    let dir = std::env::temp_dir().join(format!("trigbody-io-rt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let m = octahedron();
    let keep = WriteOptions::default();
    for name in ["a.obj", "a.PLY", "a.stl", "a.xyz", "a.csv", "a.txt"] {
        let path = dir.join(name);
        write_mesh(&path, &m, &keep).unwrap();
        let before = std::fs::read(&path).unwrap();
        let e = write_mesh(&path, &m, &keep).unwrap_err();
        assert!(matches!(e, IoError::AlreadyExists { .. }), "{name}: {e:?}");
        assert_eq!(std::fs::read(&path).unwrap(), before, "{name} was touched");
        let again = WriteOptions {
            overwrite: true,
            ..keep
        };
        write_mesh(&path, &m, &again).unwrap();
        let back = read_geometry(&path, &ReadOptions::default()).unwrap();
        assert_eq!(back.positions().len(), 6, "{name}");
        if matches!(name, "a.obj" | "a.xyz" | "a.csv" | "a.txt") {
            assert_eq!(back.positions(), &m.positions[..], "{name}");
        }
    }
    // Points cannot go to STL; nothing is created.
    let cloud = PointCloud::from(m.clone());
    let e = write_point_cloud(dir.join("p.stl"), &cloud, &keep).unwrap_err();
    assert!(matches!(e, IoError::WrongKind { .. }));
    assert!(!dir.join("p.stl").exists());
    // Invalid geometry is refused before a file is created.
    let mut bad = m;
    bad.positions[3].y = f64::NAN;
    let e = write_geometry(dir.join("bad.ply"), &Geometry::Mesh(bad), &keep).unwrap_err();
    assert!(matches!(e, IoError::InvalidGeometry { .. }), "{e:?}");
    assert!(!dir.join("bad.ply").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e6..1e6f64,
        any::<f64>().prop_filter("finite", |v| v.is_finite()),
    ]
}

fn cloud_strategy() -> impl Strategy<Value = PointCloud> {
    (1usize..40, any::<bool>()).prop_flat_map(|(n, with_normals)| {
        let p = prop::collection::vec((finite(), finite(), finite()), n);
        let q = prop::collection::vec((finite(), finite(), finite()), n);
        (p, q).prop_map(move |(p, q)| PointCloud {
            positions: p.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect(),
            normals: with_normals
                .then(|| q.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect()),
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn any_finite_cloud_round_trips_exactly(cloud in cloud_strategy()) {
        let double = WriteOptions { ply_precision: PlyPrecision::Double, ..WriteOptions::default() };
        for format in [Format::Obj, Format::Ply, Format::Xyz] {
            let mut bytes = Vec::new();
            trigbody_io::write_to(&mut bytes, &Geometry::Points(cloud.clone()), format, &double).unwrap();
            let back = read_bytes(&bytes, format, &ReadOptions::default()).unwrap();
            prop_assert_eq!(back, Geometry::Points(cloud.clone()), "{}", format);
        }
    }

    #[test]
    fn any_fan_of_triangles_round_trips(cloud in cloud_strategy(), seed in any::<u64>()) {
        prop_assume!(cloud.positions.len() >= 3);
        let n = cloud.positions.len() as u64;
        let mut s = seed | 1;
        let mut next = || { s ^= s << 13; s ^= s >> 7; s ^= s << 17; (s % n) as u32 };
        // Readers drop degenerate and repeated triangles: none are made.
        let mut seen = std::collections::HashSet::new();
        let triangles: Vec<[u32; 3]> = (0..n)
            .map(|_| [next(), next(), next()])
            .filter(|&[a, b, c]| a != b && b != c && a != c)
            .filter(|t| { let mut k = *t; k.sort_unstable(); seen.insert(k) })
            .collect();
        prop_assume!(!triangles.is_empty());
        let mesh = Mesh { positions: cloud.positions, normals: cloud.normals, triangles };
        for format in [Format::Obj, Format::Ply] {
            let mut bytes = Vec::new();
            let double = WriteOptions { ply_precision: PlyPrecision::Double, ..WriteOptions::default() };
            trigbody_io::write_to(&mut bytes, &Geometry::Mesh(mesh.clone()), format, &double).unwrap();
            let back = read_mesh_bytes(&bytes, format);
            if format == Format::Obj && mesh.normals.is_some() {
                // OBJ writes v//v corners: normals come back per vertex, the
                // same for vertices used by faces.
                prop_assert_eq!(&back.positions, &mesh.positions);
                prop_assert_eq!(&back.triangles, &mesh.triangles);
            } else {
                prop_assert_eq!(&back, &mesh, "{}", format);
            }
        }
    }
}
