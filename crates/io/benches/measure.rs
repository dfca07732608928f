//! Measurement speed on the shared male body (skipped with a note when
//! `../shared/data` is absent): the closed-form part — perimeter and tape
//! girth of the 12 girth curves and the volume `h Σ A` of the ~660 slice
//! curves, i.e. all measurements of a model whose curves exist — and, for
//! reference, the whole `measure_mesh` (segmentation, sections, fits).
//! And all measurements of the reconstructed body MODEL from its own curves
//! (`measure_body`: landmarks, searches, 12 girth sections, lengths,
//! volume and surface area), with its volume-and-area pass alone.
//!
//! `cargo bench -p trigbody-io --bench measure` (`-- model` for the model's)

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::PathBuf;
use trigbody_core::internals::measure::mesh::girths_and_volume;
use trigbody_core::internals::measure::volume::volume_area_extent;
use trigbody_core::BodyGeometry;
use trigbody_core::{measure_body, ModelMeasureOptions};
use trigbody_core::{measure_mesh, MeasureOptions};
use trigbody_core::{reconstruct, ReconstructOptions};
use trigbody_io::{read_mesh, ReadOptions};

fn bench(c: &mut Criterion) {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/bodies/mh_male.obj");
    if !path.is_file() {
        eprintln!("note: {} not found; skipping", path.display());
        return;
    }
    let Ok(mesh) = read_mesh(&path, &ReadOptions::default()) else {
        eprintln!("note: {} unreadable; skipping", path.display());
        return;
    };
    match reconstruct(BodyGeometry::Mesh(&mesh), &ReconstructOptions::default()) {
        Ok((body, _)) => {
            let mo = ModelMeasureOptions::default();
            c.bench_function("model: all measurements of the mh_male model", |b| {
                b.iter(|| measure_body(black_box(&body), &mo))
            });
            c.bench_function("model: volume and surface area only", |b| {
                b.iter(|| volume_area_extent(black_box(&body)))
            });
        }
        Err(e) => eprintln!("note: reconstructing failed ({e}); model benches skipped"),
    }
    let opts = MeasureOptions::default();
    let Ok(m) = measure_mesh(&mesh, &opts) else {
        eprintln!("note: measuring failed; skipping");
        return;
    };
    let girths: Vec<_> = m
        .measurements
        .iter()
        .filter_map(|x| x.girth.as_ref().map(|g| &g.curve))
        .collect();
    c.bench_function("measure: 12 girths + volume from curves", |b| {
        b.iter(|| {
            girths_and_volume(
                black_box(&girths),
                black_box(&m.slice_curves),
                m.slice_spacing,
                opts.perimeter_accuracy,
            )
        })
    });
    c.bench_function("measure: 12 girths only", |b| {
        b.iter(|| girths_and_volume(black_box(&girths), &[], 1.0, opts.perimeter_accuracy))
    });
    c.bench_function("measure: volume only", |b| {
        b.iter(|| girths_and_volume(&[], black_box(&m.slice_curves), 1.0, 1e-8))
    });
    let mut group = c.benchmark_group("measure_mesh");
    group.sample_size(10);
    group.bench_function("mh_male.obj: segment, cut, fit, measure", |b| {
        b.iter(|| measure_mesh(black_box(&mesh), &opts))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
