//! Hot paths of the curve core on a 256-point loop: the fixed-order least
//! squares at the points' own parameters, the equally-spaced fast path, the
//! adaptive order search, and the ellipse baseline.

use criterion::{criterion_group, criterion_main, Criterion};
use std::f64::consts::TAU;
use std::hint::black_box;
use trigbody_core::fit_ellipse;
use trigbody_core::internals::curve::fit::{chord_params, search_order};
use trigbody_core::internals::curve::lsq::{fit_equally_spaced, LoopFitter};
use trigbody_core::{fit_loop_2d, FitOptions};
use trigbody_core::{Real, Vec2};

/// A torso-like loop (flattened, with a front dip and a back bulge) sampled
/// unevenly, 256 points, about its centroid.
fn torso_loop(n: usize) -> Vec<Vec2> {
    let pts: Vec<Vec2> = (0..n)
        .map(|i| {
            let s = i as Real / n as Real;
            let t = TAU * (s + 0.04 * (TAU * s).sin()); // uneven spacing
            let r = 1.0 + 0.12 * (2.0 * t).cos() - 0.05 * (4.0 * t).cos() + 0.03 * (3.0 * t).sin();
            Vec2::new(0.16 * r * t.cos(), 0.11 * r * t.sin())
        })
        .collect();
    let c = pts.iter().fold(Vec2::ZERO, |a, p| a + *p) / n as Real;
    pts.iter().map(|p| *p - c).collect()
}

fn bench_fit(c: &mut Criterion) {
    let q = torso_loop(256);
    let params = chord_params(&q, Vec2::new(1.0, 0.0));
    c.bench_function("fit J=8, 256 points at own parameters", |b| {
        b.iter(|| {
            let f = LoopFitter::new(black_box(&q), black_box(&params), None, 8, 0.0);
            black_box(f.coefficients(8))
        })
    });
    let even: Vec<Vec2> = (0..256)
        .map(|i| {
            let t = TAU * i as Real / 256.0;
            let r = 1.0 + 0.12 * (2.0 * t).cos() - 0.05 * (4.0 * t).cos();
            Vec2::new(0.16 * r * t.cos(), 0.11 * r * t.sin())
        })
        .collect();
    c.bench_function("fast path J=8, 256 equally spaced", |b| {
        b.iter(|| black_box(fit_equally_spaced(black_box(&even), 0.0, 8)))
    });
    let opts = FitOptions::default();
    c.bench_function("adaptive order search, 256 points", |b| {
        b.iter(|| black_box(search_order(black_box(&q), black_box(&params), None, &opts)))
    });
    c.bench_function("ellipse baseline, 256 points", |b| {
        b.iter(|| black_box(fit_ellipse(black_box(&q))))
    });
    c.bench_function(
        "whole fit_loop_2d (clean, orient, check, search, ellipse), 256 points",
        |b| b.iter(|| black_box(fit_loop_2d(black_box(&q), &opts))),
    );
}

criterion_group!(benches, bench_fit);
criterion_main!(benches);
