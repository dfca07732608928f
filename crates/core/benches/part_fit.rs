//! The global fit's unit of work: one part fitted to its points (the
//! projection of every point, the least squares, the skin held where the
//! points are far), on a torso-sized tube of 24 sections of order 10 and
//! 12 000 points of a bumpier tube with a millimetre of noise.

use criterion::{criterion_group, criterion_main, Criterion};
use std::f64::consts::TAU;
use std::hint::black_box;
use trigbody_core::internals::curve::trig::{Frame, TrigCurve};
use trigbody_core::internals::surface::fit::{fit_part, SurfaceFitOptions};
use trigbody_core::internals::surface::part::{Part, PartOptions};
use trigbody_core::{Point3, Real, Vec3};

/// A tube along y of 24 sections 0.025 apart, flattened like a torso;
/// `bump` adds a third and a fifth harmonic that change along it.
fn tube(bump: Real) -> Part {
    let curves = (0..24)
        .map(|k| {
            let y = 0.025 * k as Real;
            let frame = Frame::from_normal(Point3::new(0.0, y, 0.0), Vec3::Y, Vec3::X).unwrap();
            let mut c = TrigCurve::circle(frame, 0.14, 10);
            c.b[2] *= 0.7;
            c.a[5] = bump * (3.0 * y).sin();
            c.b[9] = bump * 0.5 * (5.0 * y).cos();
            c
        })
        .collect();
    Part::new(curves, &PartOptions::default()).unwrap()
}

/// `n` points on `part` inside its ends, each moved along y by up to
/// half a millimetre and outward by up to one (a low-discrepancy walk,
/// no generator needed).
fn points(part: &Part, n: usize) -> Vec<Point3> {
    let l = part.length();
    (0..n)
        .map(|i| {
            let (a, b, c) = (
                (i as Real * 0.618_033_988_75).fract(),
                (i as Real * 0.754_877_666_25).fract(),
                (i as Real * 0.569_840_290_99).fract(),
            );
            let p = part.point(l * (0.02 + 0.96 * a), TAU * b);
            let out = Vec3::new(p.x, 0.0, p.z).normalized().unwrap_or(Vec3::X);
            p + out * (0.001 * (c - 0.5)) + Vec3::Y * (0.0005 * (a - 0.5))
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let truth = tube(0.012);
    let start = tube(0.0);
    let pts = points(&truth, 12_000);
    let weights = vec![1.0; pts.len()];
    let opts = SurfaceFitOptions {
        min_cutoff: 0.005,
        coverage_reach: 0.03,
        ..SurfaceFitOptions::default()
    };
    let mut g = c.benchmark_group("part fit");
    g.sample_size(20);
    g.bench_function("tube of 24 sections J=10, 12 000 points, 3 rounds", |b| {
        b.iter(|| black_box(fit_part(black_box(&start), &pts, &weights, &opts)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
