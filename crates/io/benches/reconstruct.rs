//! End-to-end reconstruction of the built-in body (`data/bodies/mh_male.obj`,
//! 13 380 vertices) from its mesh and from its 200 000-point virtual scan,
//! each **including reading the input file** (the OBJ; a binary PLY of the
//! virtual scan written once to the temporary directory): segmentation,
//! sections, fits, refinement, skinning and the report's measurements.
//! The budget is 0.5 s for each on a 2-core machine. The
//! `segment` entries time the first step alone and the `report` entries
//! the last one, `clean` the scan's hygiene before it (`measure`: the model's tessellation, its outer skin and
//! the distances both ways; unlike inside `reconstruct` it also builds
//! the input's distance structure), both from memory.
//!
//! The `rate` entry times a rate-distortion reconstruction of the mesh
//! (`reconstruct --target-rms 2.0`: the search's trials, each a whole
//! reconstruction with its report; issue 17's budget is 1 s).
//!
//! `cargo bench -p trigbody-io --bench reconstruct`
//! (`cargo run --release -p trigbody-io --example reconstruct_timing`
//! prints the time of every step).

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::PathBuf;
use trigbody_core::internals::body::measure;
use trigbody_core::internals::body::rate::{reconstruct_for, Goal, RateOptions};
use trigbody_core::{clean_cloud, reconstruct, CleanOptions, ReconstructOptions};
use trigbody_core::{segment, BodyGeometry, SegmentOptions};
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_io::{read_geometry, read_mesh, write_point_cloud, ReadOptions, WriteOptions};

fn run(path: &PathBuf, opts: &ReconstructOptions) -> usize {
    let geometry = read_geometry(path, &ReadOptions::default()).expect("readable input");
    let body = geometry.body();
    let (model, report) = reconstruct(black_box(body), opts).expect("reconstructed");
    model.parts.len() + report.design_parameters
}

fn bench(c: &mut Criterion) {
    let mesh_path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&mesh_path, &ReadOptions::default()).expect("the built-in body");
    let scan = virtual_scan(&mesh, &ScannerOptions::default())
        .expect("virtual scan")
        .cloud;
    let scan_path = std::env::temp_dir().join(format!(
        "trigbody-bench-virtual-scan-{}.ply",
        std::process::id()
    ));
    let wo = WriteOptions {
        overwrite: true,
        ..WriteOptions::default()
    };
    write_point_cloud(&scan_path, &scan, &wo).expect("temporary PLY");
    let opts = ReconstructOptions::default();
    let mut g = c.benchmark_group("reconstruct");
    g.sample_size(10);
    g.bench_function("built-in body mesh, read + reconstruct", |b| {
        b.iter(|| run(&mesh_path, &opts))
    });
    g.bench_function(
        "built-in body virtual scan 200k, read PLY + reconstruct",
        |b| b.iter(|| run(&scan_path, &opts)),
    );
    g.bench_function("rate: built-in body mesh, --target-rms 2.0", |b| {
        b.iter(|| {
            let out = reconstruct_for(
                black_box(BodyGeometry::Mesh(&mesh)),
                &opts,
                Goal::TargetRms(2.0),
                &RateOptions::default(),
                |_| {},
            )
            .expect("a model");
            out.report.design_parameters
        })
    });
    let so = SegmentOptions::default();
    g.bench_function("segment mesh", |b| {
        b.iter(|| segment(black_box(BodyGeometry::Mesh(&mesh)), &so).expect("mesh"))
    });
    g.bench_function("clean virtual scan 200k (floor and strays)", |b| {
        b.iter(|| clean_cloud(black_box(&scan), &CleanOptions::default()))
    });
    g.bench_function("segment virtual scan 200k", |b| {
        b.iter(|| segment(black_box(BodyGeometry::Cloud(&scan)), &so).expect("scan"))
    });
    for (name, body) in [
        ("report mesh", BodyGeometry::Mesh(&mesh)),
        ("report virtual scan 200k", BodyGeometry::Cloud(&scan)),
    ] {
        let (model, first) = reconstruct(body, &opts).expect("reconstructed");
        let seg = segment(body, &opts.segment).expect("segmented");
        g.bench_function(name, |b| {
            b.iter(|| {
                measure(black_box(body), &model, &seg, &opts, first.warnings.clone())
                    .expect("measured")
            })
        });
    }
    g.finish();
    let _ = std::fs::remove_file(&scan_path);
}

criterion_group!(benches, bench);
criterion_main!(benches);
