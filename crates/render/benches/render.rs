//! Rendering speed: a 1M-triangle torus at 1024 × 1024, one view, default
//! shading and 2 × 2 supersampling (target ≤ 0.3 s on two cores).

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use trigbody_render::{render_mesh, RenderOptions, View};

#[path = "../tests/common/shapes.rs"]
mod shapes;

fn bench_render(c: &mut Criterion) {
    // 1000 × 500 × 2 = 1 000 000 triangles, tilted so every part of the
    // rasterizer (steep and flat edges, both sides) is exercised.
    let torus = shapes::torus(1.0, 0.35, 1000, 500);
    assert_eq!(torus.triangles.len(), 1_000_000);
    let options = RenderOptions {
        views: vec![View {
            elevation_deg: 30.0,
            ..View::front()
        }],
        ..RenderOptions::default()
    };
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    group.bench_function("torus_1M_triangles_1024x1024", |b| {
        b.iter(|| render_mesh(black_box(&torus), &options).expect("renders"))
    });
    let single = RenderOptions {
        supersample: 1,
        ..options.clone()
    };
    group.bench_function("torus_1M_triangles_1024x1024_no_supersampling", |b| {
        b.iter(|| render_mesh(black_box(&torus), &single).expect("renders"))
    });
    group.finish();
}

criterion_group!(benches, bench_render);
criterion_main!(benches);
