//! Times `reconstruct` on the built-in body's mesh and its 200 000-point
//! virtual scan, stage by stage (the progress callback's steps).
//!
//! ```text
//! cargo run --release -p trigbody-io --example reconstruct_timing [mesh|scan|both] [RUNS]
//! ```

use std::path::PathBuf;
use std::time::Instant;
use trigbody_core::body::{reconstruct_with_progress, Progress, ReconstructOptions};
use trigbody_core::scanner::{virtual_scan, ScannerOptions};
use trigbody_core::segment::BodyGeometry;
use trigbody_io::{read_mesh, ReadOptions};

fn run(name: &str, body: BodyGeometry<'_>, runs: usize) {
    let mut opts = ReconstructOptions::default();
    if let Some(e) = std::env::var("REPORT_EDGE")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        opts.report_edge = e;
    }
    if let Some(n) = std::env::var("REPORT_SAMPLES")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        opts.report_samples = n;
    }
    let mut totals = Vec::new();
    let mut best: Vec<(String, f64)> = Vec::new();
    for _ in 0..runs.max(1) {
        let t0 = Instant::now();
        let mut stages: Vec<(String, f64)> = Vec::new();
        let mut cb =
            |p: Progress<'_>| stages.push((p.stage.to_string(), t0.elapsed().as_secs_f64()));
        let (model, r) = reconstruct_with_progress(body, &opts, &mut cb).expect("reconstruct");
        let total = t0.elapsed().as_secs_f64();
        if std::env::var_os("MEASURE").is_some() {
            use trigbody_core::distance::{sample_surface, MeshDistance};
            let t = Instant::now();
            let m = model
                .tessellate(&trigbody_core::TessellationOptions {
                    target_edge: Some(opts.report_edge * model.height),
                    ..Default::default()
                })
                .unwrap();
            let t_tess = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let d = MeshDistance::new(&m);
            let t_bvh = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let ms = sample_surface(&m, 60000);
            let t_samp = t.elapsed().as_secs_f64();
            let pts = match body {
                BodyGeometry::Mesh(i) => sample_surface(i, 60000),
                BodyGeometry::Cloud(c) => c.positions.iter().step_by(4).copied().collect(),
            };
            let t = Instant::now();
            let x = d.distances(&pts);
            let t_q = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let y: Vec<f64> = pts.iter().map(|p| d.distance(*p)).collect();
            let t_q1 = t.elapsed().as_secs_f64();
            assert_eq!(x, y);
            println!(
                "{} tris: tessellate {:.1} ms, BVH {:.1} ms, 60k samples {:.1} ms, {} queries {:.1} ms ({:.1} ms cold, 1 thread)",
                m.triangles.len(), 1e3 * t_tess, 1e3 * t_bvh, 1e3 * t_samp, pts.len(), 1e3 * t_q, 1e3 * t_q1
            );
            if let BodyGeometry::Cloud(c) = body {
                for f in [0.01, 0.007, 0.005, 0.0035] {
                    let t = Instant::now();
                    let g = trigbody_core::body::PointGrid::new(&c.positions, f * model.height);
                    let tb = t.elapsed().as_secs_f64();
                    let t = Instant::now();
                    let d = g.distances(&ms);
                    println!(
                        "grid {f}: build {:.1} ms, {} queries {:.1} ms (sum {})",
                        1e3 * tb,
                        ms.len(),
                        1e3 * t.elapsed().as_secs_f64(),
                        d.iter().sum::<f64>()
                    );
                }
            }
            drop(ms);
        }
        totals.push(total);
        stages.push(("end".into(), total));
        let times: Vec<(String, f64)> = stages
            .windows(2)
            .map(|w| (w[0].0.clone(), w[1].1 - w[0].1))
            .collect();
        if best.len() != times.len() {
            best = times;
        } else {
            for (b, t) in best.iter_mut().zip(times) {
                b.1 = b.1.min(t.1);
            }
        }
        if totals.len() == 1 {
            println!(
                "{name}: rms {:.3} p95 {:.3} max {:.2} cov {:.3} %, {} params",
                r.distance_mm.rms,
                r.distance_mm.p95,
                r.distance_mm.max,
                100.0 * r.coverage,
                r.design_parameters
            );
        }
    }
    totals.sort_by(f64::total_cmp);
    println!(
        "{name}: {} runs, median {:.3} s, fastest {:.3} s; fastest per step:",
        totals.len(),
        totals[totals.len() / 2],
        totals[0]
    );
    for (s, t) in &best {
        println!("    {s:<32} {:>7.1} ms", 1e3 * t);
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let which = args.next().unwrap_or_else(|| "both".into());
    let runs: usize = args.next().and_then(|r| r.parse().ok()).unwrap_or(1);
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&path, &ReadOptions::default()).expect("the built-in body");
    if which.contains('.') {
        let g = trigbody_io::read_geometry(&which, &ReadOptions::default()).expect("input");
        match &g {
            trigbody_io::Geometry::Mesh(m) => run(&which, BodyGeometry::Mesh(m), runs),
            trigbody_io::Geometry::Points(c) => run(&which, BodyGeometry::Cloud(c), runs),
        }
        return;
    }
    if which != "scan" {
        run("mesh", BodyGeometry::Mesh(&mesh), runs);
    }
    if which != "mesh" {
        let scan = virtual_scan(&mesh, &ScannerOptions::default())
            .expect("virtual scan")
            .cloud;
        run("scan", BodyGeometry::Cloud(&scan), runs);
    }
}
