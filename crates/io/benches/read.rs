//! Reading speed. Self-contained: the inputs are generated in memory (a
//! 200 000-point binary PLY scan with normals, like the shared
//! `mh_male_scan.ply`, and a 13 380-vertex quad OBJ like the MakeHuman
//! bodies); the shared files are benchmarked too when they are beside the
//! repository.
//!
//! `cargo bench -p trigbody-io --bench read`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use std::path::PathBuf;
use trigbody_core::{PointCloud, Vec3};
use trigbody_io::{read_bytes, Format, ReadOptions};

/// A deterministic cloud of `n` points on a unit sphere with normals.
fn sphere_cloud(n: usize) -> PointCloud {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let positions: Vec<Vec3> = (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            let t = golden * i as f64;
            Vec3::new(r * t.cos(), y, r * t.sin())
        })
        .collect();
    PointCloud {
        normals: Some(positions.clone()),
        positions,
    }
}

fn scan_ply() -> Vec<u8> {
    let mut bytes = Vec::new();
    trigbody_io::ply::write_points(&mut bytes, &sphere_cloud(200_000), &Default::default())
        .expect("in-memory write");
    bytes
}

/// A closed 115 × 116 quad grid on a torus: 13 340 vertices, quads.
fn torus_obj() -> Vec<u8> {
    use std::fmt::Write;
    let (nu, nv) = (115usize, 116usize);
    let mut s = String::new();
    for i in 0..nu {
        for j in 0..nv {
            let (u, v) = (
                i as f64 / nu as f64 * std::f64::consts::TAU,
                j as f64 / nv as f64 * std::f64::consts::TAU,
            );
            let r = 0.5 + 0.2 * v.cos();
            writeln!(
                s,
                "v {:.5} {:.5} {:.5}",
                r * u.cos(),
                0.2 * v.sin(),
                r * u.sin()
            )
            .unwrap();
        }
    }
    for i in 0..nu {
        for j in 0..nv {
            let k = |a: usize, b: usize| (a % nu) * nv + (b % nv) + 1;
            writeln!(
                s,
                "f {} {} {} {}",
                k(i, j),
                k(i, j + 1),
                k(i + 1, j + 1),
                k(i + 1, j)
            )
            .unwrap();
        }
    }
    s.into_bytes()
}

fn shared(path: &str) -> Option<Vec<u8>> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data")
        .join(path);
    std::fs::read(p).ok()
}

fn bench(c: &mut Criterion) {
    let options = ReadOptions::default();
    let mut group = c.benchmark_group("read");
    let mut inputs = vec![
        ("ply_binary_200k_points", Format::Ply, scan_ply()),
        ("obj_13k_quads", Format::Obj, torus_obj()),
    ];
    if let Some(d) = shared("scans/mh_male_scan.ply") {
        inputs.push(("shared_mh_male_scan_ply", Format::Ply, d));
    }
    if let Some(d) = shared("bodies/mh_male.obj") {
        inputs.push(("shared_mh_male_obj", Format::Obj, d));
    }
    if let Some(d) = shared("bodies/mh_female.ply") {
        inputs.push(("shared_mh_female_ply", Format::Ply, d));
    }
    for (name, format, data) in &inputs {
        group.throughput(Throughput::Bytes(data.len() as u64));
        group.bench_function(*name, |b| {
            b.iter(|| read_bytes(black_box(data), *format, &options).expect("valid input"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
