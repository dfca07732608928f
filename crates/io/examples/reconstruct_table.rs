//! Reconstructs the shared bodies, their virtual scans and the external
//! scan, and prints the issue-5 table (parts, distances, coverage, size).
//!
//! ```text
//! cargo run --release -p trigbody-io --example reconstruct_table [DATA_DIR]
//! ```

use std::path::PathBuf;
use std::time::Instant;
use trigbody_core::BodyGeometry;
use trigbody_core::{reconstruct, ReconstructOptions, Report};
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_io::{read_mesh, read_point_cloud, ReadOptions};

fn row(name: &str, r: &Report, secs: f64) {
    println!(
        "{name:<22} parts {:>2}/{:<2} rms {:>5.2} p95 {:>5.2} max {:>6.1} | in→m rms {:>5.2} p95 {:>5.2} | m→in rms {:>5.2} p95 {:>5.2} | cov {:>6.2}% | params {:>5} / {:>5} = {:>5.1}% | {:.2} s",
        r.parts.len(),
        r.parts_found.len(),
        r.distance_mm.rms,
        r.distance_mm.p95,
        r.distance_mm.max,
        r.input_to_model_mm.rms,
        r.input_to_model_mm.p95,
        r.model_to_input_mm.rms,
        r.model_to_input_mm.p95,
        100.0 * r.coverage,
        r.design_parameters,
        3 * r.input_vertices,
        100.0 * r.parameter_ratio(),
        secs
    );
    for p in &r.parts {
        println!(
            "    {:<10} sections {:>3} orders {:>2}/{:>2}/{:>2} met {:>3} worst ea {:.3} em {:.3} | ellipse {:.3} {:.3}",
            p.name.to_string(), p.sections, p.orders.0, p.orders.1, p.orders.2, p.met, p.worst_ea, p.worst_em, p.ellipse_worst_ea, p.ellipse_worst_em
        );
    }
    if std::env::var("SHOW_WARNINGS").is_ok() {
        for w in &r.warnings {
            println!("    warning: {w}");
        }
    }
}

fn main() {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("../shared/data"));
    let opts = ReconstructOptions::default();
    for body in ["mh_male.obj", "mh_base.obj", "mh_female.ply"] {
        let mesh = match read_mesh(dir.join("bodies").join(body), &ReadOptions::default()) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{body}: {e}");
                continue;
            }
        };
        let t = Instant::now();
        match reconstruct(BodyGeometry::Mesh(&mesh), &opts) {
            Ok((_, r)) => row(body, &r, t.elapsed().as_secs_f64()),
            Err(e) => println!("{body}: {e}"),
        }
        if std::env::var("MESH_ONLY").is_ok() {
            continue;
        }
        let scan = match virtual_scan(&mesh, &ScannerOptions::default()) {
            Ok(s) => s.cloud,
            Err(e) => {
                eprintln!("{body} scan: {e}");
                continue;
            }
        };
        let t = Instant::now();
        match reconstruct(BodyGeometry::Cloud(&scan), &opts) {
            Ok((_, r)) => row(
                &format!("{body} (virtual scan)"),
                &r,
                t.elapsed().as_secs_f64(),
            ),
            Err(e) => println!("{body} scan: {e}"),
        }
    }
    if std::env::var("MESH_ONLY").is_ok() {
        return;
    }
    match read_point_cloud(dir.join("scans/mh_male_scan.ply"), &ReadOptions::default()) {
        Ok(c) => {
            let t = Instant::now();
            match reconstruct(BodyGeometry::Cloud(&c), &opts) {
                Ok((_, r)) => row("mh_male_scan.ply", &r, t.elapsed().as_secs_f64()),
                Err(e) => println!("mh_male_scan.ply: {e}"),
            }
        }
        Err(e) => eprintln!("scan: {e}"),
    }
}
