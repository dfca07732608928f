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
use trigbody_core::measure::{measure_mesh, MeasureOptions, MeasurementKind};
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
