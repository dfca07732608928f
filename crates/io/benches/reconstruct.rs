//! End-to-end reconstruction of the built-in body (`data/bodies/mh_male.obj`,
//! 13 380 vertices) from its mesh and from its 200 000-point virtual scan:
//! segmentation, sections, fits, refinement, skinning and the report's
//! measurements. Reading the files is not included (see `read.rs`).
//!
//! `cargo bench -p trigbody-io --bench reconstruct`

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::PathBuf;
use trigbody_core::body::{reconstruct, ReconstructOptions};
use trigbody_core::scanner::{virtual_scan, ScannerOptions};
use trigbody_core::segment::BodyGeometry;
use trigbody_io::{read_mesh, ReadOptions};

fn bench(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&path, &ReadOptions::default()).expect("the built-in body");
    let scan = virtual_scan(&mesh, &ScannerOptions::default())
        .expect("virtual scan")
        .cloud;
    let opts = ReconstructOptions::default();
    let mut g = c.benchmark_group("reconstruct");
    g.sample_size(10);
    g.bench_function("built-in body mesh", |b| {
        b.iter(|| reconstruct(black_box(BodyGeometry::Mesh(&mesh)), &opts).expect("mesh"))
    });
    g.bench_function("built-in body virtual scan 200k", |b| {
        b.iter(|| reconstruct(black_box(BodyGeometry::Cloud(&scan)), &opts).expect("scan"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
