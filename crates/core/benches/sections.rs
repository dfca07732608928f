//! 80 plane sections of a ~13k-vertex body mesh and 80 slab sections of a
//! 200k-point virtual scan of it.
//!
//! The mesh is a synthetic "stick body" (`shapes::stick_body(2)`, ≈ 13 000
//! vertices, 1.7 units tall); set `TRIGBODY_BENCH_OBJ` to a triangulated
//! or quad OBJ file to use a real body instead (read here with a minimal
//! `v`/`f` parser, so the core crate needs no I/O dependency).
//!
//! `cargo bench -p trigbody-core --bench sections`

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use trigbody_core::internals::geom::shapes;
use trigbody_core::internals::section::cloud::{CloudSlicer, ScanSectionOptions};
use trigbody_core::internals::section::mesh::{MeshSlicer, SectionOptions};
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_core::{Mesh, Vec3};

/// `v x y z` and `f a b c ...` lines only (fan-triangulated, 1-based,
/// `a/b/c` forms accepted); `None` on anything unexpected.
fn read_obj(path: &str) -> Option<Mesh> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut m = Mesh::default();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it.take(3).map(|x| x.parse().ok()).collect::<Option<_>>()?;
                m.positions
                    .push(Vec3::new(*c.first()?, *c.get(1)?, *c.get(2)?));
            }
            Some("f") => {
                let idx: Vec<u32> = it
                    .map(|w| w.split('/').next()?.parse::<u32>().ok()?.checked_sub(1))
                    .collect::<Option<_>>()?;
                for k in 1..idx.len().saturating_sub(1) {
                    m.triangles.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    m.validate().ok()?;
    Some(m)
}

fn body() -> (Mesh, Vec3, String) {
    if let Ok(path) = std::env::var("TRIGBODY_BENCH_OBJ") {
        if let Some(m) = read_obj(&path) {
            // the up axis is the direction of largest extent
            let s = m.bounds().map(|b| b.size()).unwrap_or(Vec3::Y);
            let up = if s.y >= s.x && s.y >= s.z {
                Vec3::Y
            } else if s.z >= s.x {
                Vec3::Z
            } else {
                Vec3::X
            };
            return (m, up, path);
        }
        eprintln!("could not read {path}; using the synthetic body");
    }
    (
        shapes::stick_body(2),
        Vec3::Z,
        "synthetic stick body".into(),
    )
}

fn bench(c: &mut Criterion) {
    let (mesh, up, what) = body();
    eprintln!(
        "{what}: {} vertices, {} triangles",
        mesh.positions.len(),
        mesh.triangles.len()
    );
    let opts = SectionOptions::default();
    c.bench_function("80 mesh sections (slicer built each run)", |b| {
        b.iter(|| {
            let slicer = MeshSlicer::new(black_box(&mesh), up, &opts).unwrap();
            black_box(slicer.sections_evenly(80))
        })
    });
    let scan = virtual_scan(&mesh, &ScannerOptions::default()).unwrap();
    let cloud = scan.cloud;
    eprintln!("virtual scan: {} points", cloud.positions.len());
    let sopts = ScanSectionOptions::default();
    let slicer = CloudSlicer::new(&cloud, up).unwrap();
    let (lo, hi) = slicer.range();
    c.bench_function(
        "80 slab sections of a 200k-point scan (cloud sorted once)",
        |b| {
            b.iter(|| {
                let step = (hi - lo) / 80.0;
                let n: usize = (0..80)
                    .filter_map(|k| slicer.section_at(lo + (k as f64 + 0.5) * step, &sopts).ok())
                    .map(|s| s.loops.len())
                    .sum();
                black_box(n)
            })
        },
    );
    c.bench_function(
        "sorting a 200k-point scan and estimating its spacing",
        |b| b.iter(|| black_box(CloudSlicer::new(black_box(&cloud), up).unwrap().spacing())),
    );
    c.bench_function(
        "80 slab sections of a 200k-point scan (sorting included)",
        |b| {
            b.iter(|| {
                let slicer = CloudSlicer::new(black_box(&cloud), up).unwrap();
                let (lo, hi) = slicer.range();
                let step = (hi - lo) / 80.0;
                let n: usize = (0..80)
                    .filter_map(|k| slicer.section_at(lo + (k as f64 + 0.5) * step, &sopts).ok())
                    .map(|s| s.loops.len())
                    .sum();
                black_box(n)
            })
        },
    );
    let mut g = c.benchmark_group("virtual scan");
    g.sample_size(10);
    g.bench_function("200k points, 24 views", |b| {
        b.iter(|| black_box(virtual_scan(&mesh, &ScannerOptions::default()).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
