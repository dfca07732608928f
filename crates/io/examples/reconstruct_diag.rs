//! Where a reconstruction misses: uncovered input by height, and each
//! part's model → input distances (a diagnostic for tuning).
//!
//! ```text
//! cargo run --release -p trigbody-io --example reconstruct_diag BODY
//! ```

use trigbody_core::internals::spatial::distance::{sample_surface, DistanceStats, MeshDistance};
use trigbody_core::internals::spatial::point_grid::PointGrid;
use trigbody_core::BodyGeometry;
use trigbody_core::{reconstruct, ReconstructOptions};
use trigbody_core::{tessellate_part, TessellationOptions};
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_io::{read_geometry, Geometry, ReadOptions};

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: reconstruct_diag BODY");
        return;
    };
    let geometry = match read_geometry(&path, &ReadOptions::default()) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{e}");
            return;
        }
    };
    let scan = std::env::var("SCAN").is_ok();
    let (mesh, cloud) = match geometry {
        Geometry::Mesh(m) => {
            let c = if scan {
                virtual_scan(&m, &ScannerOptions::default())
                    .ok()
                    .map(|s| s.cloud)
            } else {
                None
            };
            (m, c)
        }
        Geometry::Points(c) => (trigbody_core::Mesh::default(), Some(c)),
    };
    let opts = ReconstructOptions::default();
    let input_geo = match &cloud {
        Some(c) => BodyGeometry::Cloud(c),
        None => BodyGeometry::Mesh(&mesh),
    };
    let (body, _) = match reconstruct(input_geo, &opts) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("{e}");
            return;
        }
    };
    let tess = TessellationOptions {
        target_edge: Some(0.003 * body.height),
        ..TessellationOptions::default()
    };
    let Ok(surface) = body.tessellate(&tess) else {
        return;
    };
    let md = MeshDistance::new(&surface);
    let up = body.frame.up;
    let left = body.frame.left;
    let floor = body.frame.origin.dot(up);
    let samples = match &cloud {
        Some(c) => c.positions.iter().step_by(4).copied().collect(),
        None => sample_surface(&mesh, 60_000),
    };
    let mut bins = vec![(0usize, 0usize); 20];
    let mut lat = vec![(0usize, 0usize); 20];
    for p in &samples {
        let f = ((p.dot(up) - floor) / body.height * 20.0).clamp(0.0, 19.0) as usize;
        let l = (((*p - body.frame.origin).dot(left) / body.height + 0.5) * 20.0).clamp(0.0, 19.0)
            as usize;
        let far = md.distance(*p) > 0.005;
        bins[f].0 += 1;
        lat[l].0 += 1;
        if far {
            bins[f].1 += 1;
            lat[l].1 += 1;
        }
    }
    for (k, (n, u)) in bins.iter().enumerate().rev() {
        println!(
            "height {:.2}: {:>6} samples, {:>5} uncovered",
            k as f64 / 20.0,
            n,
            u
        );
    }
    for (k, (n, u)) in lat.iter().enumerate() {
        println!(
            "left {:+.2}: {:>6} samples, {:>5} uncovered",
            k as f64 / 20.0 - 0.5,
            n,
            u
        );
    }
    if std::env::var("SECTIONS").is_ok() {
        for p in &body.parts {
            println!("{}", p.name);
            for (c, f) in p.part.curves().iter().zip(&p.fits) {
                println!(
                    "   h {:.3} area {:.5} J {} em {:.3}",
                    (c.frame.origin.dot(up) - floor) / body.height,
                    c.area().abs(),
                    f.order,
                    f.em
                );
            }
        }
    }
    let input = MeshDistance::new(&mesh);
    let grid = cloud
        .as_ref()
        .map(|c| PointGrid::new(&c.positions, 0.01 * body.height));
    for p in &body.parts {
        let Ok(m) = tessellate_part(&p.part, &tess) else {
            continue;
        };
        let pts = sample_surface(&m, 10_000);
        let d: Vec<f64> = pts
            .iter()
            .map(|q| {
                grid.as_ref()
                    .map_or_else(|| input.distance(*q), |g| g.nearest(*q))
                    * 1000.0
            })
            .collect();
        let mut hb = vec![(0usize, 0.0f64); 40];
        for (q, dd) in pts.iter().zip(&d) {
            let f = ((q.dot(up) - floor) / body.height * 40.0).clamp(0.0, 39.0) as usize;
            hb[f].0 += 1;
            hb[f].1 = hb[f].1.max(*dd);
        }
        let line: Vec<String> = hb
            .iter()
            .enumerate()
            .filter(|(_, b)| b.0 > 0)
            .map(|(k, b)| format!("{:.3}:{:.0}", k as f64 / 40.0, b.1))
            .collect();
        println!("   max by height: {}", line.join(" "));
        let s = DistanceStats::of(&d);
        println!(
            "{:<10} model→input rms {:.2} p95 {:.2} max {:.1}",
            p.name.to_string(),
            s.rms,
            s.p95,
            s.max
        );
    }
}
