//! Times `reconstruct` step by step (the progress callback's steps) on the
//! built-in body's mesh, its 200 000-point virtual scan, or a file: the
//! median and fastest of RUNS runs, and the fastest time of each step.
//! Reading the input is not included (see `benches/reconstruct.rs` for
//! the end-to-end times).
//!
//! ```text
//! cargo run --release -p trigbody-io --example reconstruct_timing [mesh|scan|both|FILE] [RUNS]
//! ```
//!
//! `REPORT_EDGE` and `REPORT_SAMPLES` in the environment override the
//! report's tessellation edge (fraction of H) and sample count;
//! `SCAN_FRAMES` the frames a scan is reconstructed in.

use std::path::PathBuf;
use std::time::Instant;
use trigbody_core::BodyGeometry;
use trigbody_core::{reconstruct_with_progress, Progress, ReconstructOptions};
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_io::{read_geometry, read_mesh, Geometry, ReadOptions};

fn run(name: &str, body: BodyGeometry<'_>, runs: usize) {
    let mut opts = ReconstructOptions::default();
    // The report's statistics, to see how its numbers move with them.
    let env = |name: &str| std::env::var(name).ok();
    if let Some(e) = env("REPORT_EDGE").and_then(|v| v.parse().ok()) {
        opts.report_edge = e;
    }
    if let Some(n) = env("REPORT_SAMPLES").and_then(|v| v.parse().ok()) {
        opts.report_samples = n;
    }
    if let Some(n) = env("SCAN_FRAMES").and_then(|v| v.parse().ok()) {
        opts.scan_frames = n;
    }
    let mut totals = Vec::new();
    let mut best: Vec<(String, f64)> = Vec::new();
    for _ in 0..runs.max(1) {
        let t0 = Instant::now();
        let mut stages: Vec<(String, f64)> = Vec::new();
        let mut cb =
            |p: Progress<'_>| stages.push((p.stage.to_string(), t0.elapsed().as_secs_f64()));
        let (_, r) = reconstruct_with_progress(body, &opts, &mut cb).expect("reconstruct");
        let total = t0.elapsed().as_secs_f64();
        totals.push(total);
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
                "{name}: rms {:.3} p95 {:.3} max {:.2} mm, coverage {:.3} %, {} parameters",
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
    let runs: usize = args.next().and_then(|r| r.parse().ok()).unwrap_or(5);
    if !matches!(which.as_str(), "mesh" | "scan" | "both") {
        let g = read_geometry(&which, &ReadOptions::default()).expect("a readable input");
        match &g {
            Geometry::Mesh(m) => run(&which, BodyGeometry::Mesh(m), runs),
            Geometry::Points(c) => run(&which, BodyGeometry::Cloud(c), runs),
        }
        return;
    }
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&path, &ReadOptions::default()).expect("the built-in body");
    if which != "scan" {
        run("mesh", BodyGeometry::Mesh(&mesh), runs);
    }
    if which != "mesh" {
        let scan = virtual_scan(&mesh, &ScannerOptions::default())
            .expect("virtual scan")
            .cloud;
        run("virtual scan", BodyGeometry::Cloud(&scan), runs);
    }
}
