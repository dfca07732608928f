//! Tessellating a part to about one million triangles.
//!
//! `cargo bench -p trigbody-core --bench tessellate`; the vertex rate is
//! printed by criterion as throughput (elements = vertices).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use trigbody_core::{
    tessellate_part, tessellate_part_into, CapKind, Frame, Part, PartOptions, TessellationOptions,
    TrigCurve, Vec3,
};

/// 21 sections of order 10 along a gently curved axis, capped at both ends.
fn part() -> Part {
    let curves: Vec<TrigCurve> = (0..21)
        .map(|k| {
            let t = k as f64 / 20.0;
            let frame = Frame::from_normal(
                Vec3::new(0.02 * (3.0 * t).sin(), 0.0, 0.8 * t),
                Vec3::Z,
                Vec3::X,
            )
            .expect("valid frame");
            let mut a = vec![0.0; 21];
            let mut b = vec![0.0; 21];
            a[1] = 0.06 + 0.02 * (5.0 * t).sin();
            b[1] = 0.05 + 0.01 * (4.0 * t).cos();
            for j in 2..=10 {
                a[2 * j - 1] = 0.003 / j as f64 * (t * j as f64).cos();
                b[2 * j] = 0.002 / j as f64 * (t + j as f64).sin();
            }
            TrigCurve::new(frame, a, b).expect("valid curve")
        })
        .collect();
    let opts = PartOptions {
        start_cap: CapKind::Flat,
        end_cap: CapKind::dome(),
        ..PartOptions::default()
    };
    Part::new(curves, &opts).expect("valid part")
}

fn bench(c: &mut Criterion) {
    let part = part();
    let opts = TessellationOptions {
        around: 1000,
        along: 25,
        cap_rings: 10,
        target_edge: None,
    };
    let mesh = tessellate_part(&part, &opts).expect("tessellation");
    let vertices = mesh.positions.len() as u64;
    eprintln!("{} vertices, {} triangles", vertices, mesh.triangles.len());
    let mut group = c.benchmark_group("tessellate");
    group.throughput(Throughput::Elements(vertices));
    group.sample_size(20);
    group.bench_function("part_1M_triangles", |b| {
        b.iter(|| tessellate_part(black_box(&part), black_box(&opts)).expect("tessellation"))
    });
    let mut reused = mesh.clone();
    group.bench_function("part_1M_triangles_reused_buffers", |b| {
        b.iter(|| {
            tessellate_part_into(black_box(&part), black_box(&opts), &mut reused)
                .expect("tessellation")
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
