//! GLB export, checked by an independent reader (the `gltf` crate).

use trigbody_core::{
    tessellate_part, CapKind, Frame, Part, PartOptions, TessellationOptions, TrigCurve, Vec3,
};
use trigbody_io::gltf::{glb_bytes, GltfError, NamedMesh};

fn capped_part(offset: Vec3, r: f64) -> trigbody_core::Mesh {
    let curves: Vec<TrigCurve> = (0..5)
        .map(|k| {
            let frame = Frame {
                origin: offset + Vec3::new(0.0, 0.0, 0.05 * k as f64),
                e1: Vec3::X,
                e2: Vec3::Y,
            };
            TrigCurve::new(
                frame,
                vec![0.0, r, 0.0, 0.01, 0.0],
                vec![0.0, 0.8 * r, 0.0, 0.0, 0.005],
            )
            .unwrap()
        })
        .collect();
    let opts = PartOptions {
        start_cap: CapKind::Flat,
        end_cap: CapKind::dome(),
        ..PartOptions::default()
    };
    let part = Part::new(curves, &opts).unwrap();
    tessellate_part(&part, &TessellationOptions::default()).unwrap()
}

#[test]
fn glb_loads_with_the_gltf_crate_and_bounds_are_right() {
    let a = capped_part(Vec3::new(0.1, 0.2, 0.3), 0.05);
    let b = capped_part(Vec3::new(-0.4, 1.0, 0.0), 0.03);
    let bytes = glb_bytes(&[
        NamedMesh {
            name: "leg_left",
            mesh: &a,
        },
        NamedMesh {
            name: "arm_right",
            mesh: &b,
        },
    ])
    .unwrap();
    assert_eq!(bytes.len() % 4, 0);
    // For checking with an external validator: TRIGBODY_GLB_OUT=path.glb.
    if let Ok(path) = std::env::var("TRIGBODY_GLB_OUT") {
        std::fs::write(path, &bytes).unwrap();
    }
    let gltf = gltf::Gltf::from_slice(&bytes).expect("the gltf crate reads our GLB");
    let blob = gltf.blob.as_deref().expect("binary chunk");
    let names: Vec<_> = gltf
        .nodes()
        .map(|n| n.name().unwrap_or("").to_string())
        .collect();
    assert_eq!(names, ["leg_left", "arm_right"]);
    for (mesh, src) in gltf.meshes().zip([&a, &b]) {
        let prim = mesh.primitives().next().unwrap();
        let pos = prim.get(&gltf::Semantic::Positions).unwrap();
        let bounds = pos.min().zip(pos.max()).expect("POSITION has min and max");
        let (min, max) = (bounds.0, bounds.1);
        let aabb = src.bounds().unwrap();
        for k in 0..3 {
            let lo = min[k].as_f64().unwrap();
            let hi = max[k].as_f64().unwrap();
            assert!(
                (lo - aabb.min[k]).abs() < 1e-6,
                "min {k}: {lo} vs {}",
                aabb.min[k]
            );
            assert!(
                (hi - aabb.max[k]).abs() < 1e-6,
                "max {k}: {hi} vs {}",
                aabb.max[k]
            );
        }
        let reader = prim.reader(|buffer| match buffer.source() {
            gltf::buffer::Source::Bin => Some(blob),
            _ => None,
        });
        let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        assert_eq!(positions.len(), src.positions.len());
        // The stored bounds are exactly those of the stored positions.
        for k in 0..3 {
            let lo = positions.iter().map(|p| p[k]).fold(f32::INFINITY, f32::min);
            let hi = positions
                .iter()
                .map(|p| p[k])
                .fold(f32::NEG_INFINITY, f32::max);
            assert_eq!(lo as f64, min[k].as_f64().unwrap());
            assert_eq!(hi as f64, max[k].as_f64().unwrap());
        }
        let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
        for n in &normals {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-6);
        }
        let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
        assert_eq!(indices.len(), 3 * src.triangles.len());
        assert_eq!(indices[..3], src.triangles[0]);
    }
}

#[test]
fn glb_rejects_nothing_and_bad_meshes() {
    assert!(matches!(glb_bytes(&[]), Err(GltfError::Empty)));
    let bad = trigbody_core::Mesh {
        positions: vec![Vec3::ZERO; 3],
        normals: None,
        triangles: vec![[0, 1, 5]],
    };
    let err = glb_bytes(&[NamedMesh {
        name: "broken",
        mesh: &bad,
    }])
    .unwrap_err();
    assert!(err.to_string().contains("broken"), "{err}");
}
