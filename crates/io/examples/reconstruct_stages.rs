//! Wall time of each reconstruction stage on a mesh, three runs (a
//! diagnostic; the benchmark is `cargo bench -p trigbody-io --bench
//! reconstruct`).
//!
//! ```text
//! cargo run --release -p trigbody-io --example reconstruct_stages BODY.obj
//! ```

use std::time::Instant;
use trigbody_core::body::{reconstruct_with_progress, ReconstructOptions};
use trigbody_core::segment::BodyGeometry;
use trigbody_io::{read_geometry, Geometry, ReadOptions};

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: reconstruct_stages BODY");
        return;
    };
    let geometry = match read_geometry(&path, &ReadOptions::default()) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("{e}");
            return;
        }
    };
    let body = match &geometry {
        Geometry::Mesh(m) => BodyGeometry::Mesh(m),
        Geometry::Points(c) => BodyGeometry::Cloud(c),
    };
    for _ in 0..3 {
        let start = Instant::now();
        let mut stages: Vec<(String, f64)> = Vec::new();
        let mut current = (String::from("start"), Instant::now());
        let result = reconstruct_with_progress(body, &ReconstructOptions::default(), &mut |s| {
            // Per-part steps are summed under their step's name.
            let key = s.split(':').next().unwrap_or(s).to_string();
            let now = Instant::now();
            stages.push((current.0.clone(), (now - current.1).as_secs_f64()));
            current = (key, now);
        });
        if let Err(e) = result {
            eprintln!("{e}");
            return;
        }
        stages.push((current.0.clone(), current.1.elapsed().as_secs_f64()));
        let mut sums: Vec<(String, f64)> = Vec::new();
        for (k, v) in stages {
            match sums.iter_mut().find(|e| e.0 == k) {
                Some(e) => e.1 += v,
                None => sums.push((k, v)),
            }
        }
        let line: Vec<String> = sums
            .iter()
            .filter(|(k, _)| k != "start")
            .map(|(k, v)| format!("{k} {v:.3}"))
            .collect();
        println!(
            "total {:.3} s: {}",
            start.elapsed().as_secs_f64(),
            line.join(", ")
        );
    }
}
