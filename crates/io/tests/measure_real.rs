//! Measurements of the project's real bodies (from `../shared/data`;
//! skipped with a note when that folder is absent): every girth from the
//! fitted curve agrees within 4 mm with the same girth measured directly on
//! the mesh section (same plane; convex-hull perimeter for tape girths), and
//! the curve stack's volume and surface area agree with the mesh's within
//! 1 % and 2 %. The library knows nothing of these bodies; the tolerance
//! assumes metres (the shared bodies' unit).

mod common;

use common::shared_data;
use std::time::Instant;
use trigbody_core::{measure_mesh, MeasureOptions, MeasurementKind};
use trigbody_io::{read_mesh, ReadOptions};

#[test]
fn girths_volume_and_area_agree_with_the_mesh_on_every_shared_body() {
    let Some(data) = shared_data() else { return };
    for name in ["mh_base.obj", "mh_male.obj", "mh_female.ply"] {
        let mesh = read_mesh(data.join("bodies").join(name), &ReadOptions::default()).unwrap();
        let t = Instant::now();
        let m = measure_mesh(&mesh, &MeasureOptions::default()).unwrap();
        eprintln!("{name}: measured in {:.2?}", t.elapsed());
        assert!(m.warnings.is_empty(), "{name}: {:?}", m.warnings);
        eprintln!(
            "{:<18} {:>9} {:>9} {:>7} {:>9} {:>9} {:>7}",
            "", "tape", "mesh", "diff", "perim", "mesh", "diff"
        );
        for x in &m.measurements {
            match &x.girth {
                Some(g) => {
                    eprintln!(
                        "{:<18} {:>9.1} {:>9.1} {:>7.2} {:>9.1} {:>9.1} {:>7.2}",
                        x.name,
                        1e3 * g.tape,
                        1e3 * g.mesh_tape,
                        1e3 * (g.tape - g.mesh_tape),
                        1e3 * g.perimeter,
                        1e3 * g.mesh_perimeter,
                        1e3 * (g.perimeter - g.mesh_perimeter)
                    );
                }
                None => eprintln!("{:<18} {:>9.1}", x.name, 1e3 * x.value),
            }
        }
        eprintln!(
            "volume {:.5} vs mesh {:.5} ({:+.3} %); area {:.4} vs mesh {:.4} ({:+.3} %); {} slice curves",
            m.volume.model,
            m.volume.mesh,
            100.0 * m.volume.relative_difference(),
            m.surface_area.model,
            m.surface_area.mesh,
            100.0 * m.surface_area.relative_difference(),
            m.slice_curves.len()
        );
        let girths = m
            .measurements
            .iter()
            .filter(|x| x.kind == MeasurementKind::Girth)
            .count();
        assert_eq!(girths, 12, "{name}");
        for x in &m.measurements {
            if let Some(g) = &x.girth {
                assert!(
                    (g.tape - g.mesh_tape).abs() <= 0.004,
                    "{name} {}: tape girth {} vs mesh {}",
                    x.name,
                    g.tape,
                    g.mesh_tape
                );
            }
        }
        assert!(m.volume.relative_difference().abs() <= 0.01, "{name}");
        assert!(m.surface_area.relative_difference().abs() <= 0.02, "{name}");
    }
}

/// Invariance: the male body turned (up along a skew axis), moved far from
/// the origin and with its vertex order reversed gives the same
/// measurements (girths within 2 mm, lengths within 3 mm, volume within
/// 0.1 %): nothing depends on coordinates or vertex order.
#[test]
fn measurements_do_not_depend_on_placement_or_vertex_order() {
    let Some(data) = shared_data() else { return };
    let mesh = read_mesh(
        data.join("bodies").join("mh_male.obj"),
        &ReadOptions::default(),
    )
    .unwrap();
    // Rotation: 90° about x (y up becomes z up), then 30° about z.
    let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
    let turn = |p: trigbody_core::Vec3| {
        let q = trigbody_core::Vec3::new(p.x, -p.z, p.y);
        trigbody_core::Vec3::new(c * q.x - s * q.y, s * q.x + c * q.y, q.z)
            + trigbody_core::Vec3::new(40.0, -25.0, 12.0)
    };
    let n = mesh.positions.len() as u32;
    let moved = trigbody_core::Mesh::new(
        mesh.positions.iter().rev().map(|&p| turn(p)).collect(),
        mesh.triangles
            .iter()
            .map(|t| t.map(|i| n - 1 - i))
            .collect(),
    )
    .unwrap();
    let opts = MeasureOptions::default();
    let a = measure_mesh(&mesh, &opts).unwrap();
    let b = measure_mesh(&moved, &opts).unwrap();
    for x in &a.measurements {
        let y = b.get(x.name).unwrap();
        let tol = if x.kind == MeasurementKind::Girth {
            0.002
        } else {
            0.003
        };
        assert!(
            (x.value - y.value).abs() <= tol,
            "{}: {} vs {} moved",
            x.name,
            x.value,
            y.value
        );
    }
    assert!((a.volume.model / b.volume.model - 1.0).abs() < 1e-3);
    assert!((a.surface_area.model / b.surface_area.model - 1.0).abs() < 5e-3);
}

/// The reconstructed body MODEL measured from its own curves
/// (`measure_body`), against the same girths measured directly on the input
/// mesh in the same planes (`compare_with_mesh`: convex-hull perimeter of the
/// mesh loop around the plane's origin), on every body in
/// `../shared/data/bodies`: girths within 4 mm, volume within 1 %, surface
/// area within 2 % (volumes +0.68 / +0.81 / +0.73 %, areas −1.34 / −1.40 /
/// −0.89 % on the base, male and female meshes with the arms' side
/// transitions; about 0.5 % of each volume is the mesh's mouth cavity,
/// which one curve per section fills: docs/measure.md).
#[test]
fn model_girths_volume_and_area_agree_with_the_input_mesh() {
    use trigbody_core::internals::measure::model::compare_with_mesh;
    use trigbody_core::BodyGeometry;
    use trigbody_core::{measure_body, ModelMeasureOptions};
    use trigbody_core::{reconstruct, ReconstructOptions};
    let Some(data) = shared_data() else { return };
    let mut names: Vec<_> = std::fs::read_dir(data.join("bodies"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| matches!(e, "obj" | "ply" | "stl"))
        })
        .collect();
    names.sort();
    assert!(!names.is_empty());
    let mut failures = Vec::new();
    // The target; prints the verdict.
    let mut judge = |body: &str, what: &str, miss: f64, target: f64| -> &'static str {
        if !(miss.abs() <= target) {
            failures.push(format!("{body} {what}: {miss:+.5} (target {target})"));
        }
        if miss.abs() <= target {
            "meets"
        } else {
            "MISSES"
        }
    };
    for path in &names {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let mesh = read_mesh(path, &ReadOptions::default()).unwrap();
        let (body, _) =
            reconstruct(BodyGeometry::Mesh(&mesh), &ReconstructOptions::default()).unwrap();
        let mut m = measure_body(&body, &ModelMeasureOptions::default()).unwrap();
        compare_with_mesh(&mut m, &mesh);
        eprintln!("{name}: model measured against the input mesh (mm)");
        eprintln!(
            "{:<18} {:>9} {:>9} {:>7} {:>9} {:>9}  4 mm",
            "", "model", "mesh", "diff", "perim", "mesh"
        );
        for x in &m.measurements {
            match &x.girth {
                Some(g) => {
                    let verdict = judge(&name, x.name, g.tape - g.mesh_tape, 0.004);
                    eprintln!(
                        "{:<18} {:>9.1} {:>9.1} {:>7.2} {:>9.1} {:>9.1}  {verdict}",
                        x.name,
                        1e3 * g.tape,
                        1e3 * g.mesh_tape,
                        1e3 * (g.tape - g.mesh_tape),
                        1e3 * g.perimeter,
                        1e3 * g.mesh_perimeter,
                    );
                }
                None => eprintln!("{:<18} {:>9.1}", x.name, 1e3 * x.value),
            }
        }
        let v = judge(&name, "volume", m.volume.relative_difference(), 0.01);
        let a = judge(
            &name,
            "surface area",
            m.surface_area.relative_difference(),
            0.02,
        );
        eprintln!(
            "volume {:.5} vs mesh {:.5} m³ ({:+.2} %, 1 %: {v}); area {:.4} vs mesh {:.4} m² ({:+.2} %, 2 %: {a})",
            m.volume.model,
            m.volume.mesh,
            100.0 * m.volume.relative_difference(),
            m.surface_area.model,
            m.surface_area.mesh,
            100.0 * m.surface_area.relative_difference(),
        );
        assert!(m.warnings.is_empty(), "{name}: {:?}", m.warnings);
        let girths = m
            .measurements
            .iter()
            .filter(|x| x.kind == MeasurementKind::Girth)
            .count();
        assert_eq!(girths, 12, "{name}");
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
