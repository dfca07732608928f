//! Times [`segment`] on the shared bodies and scan (the issue-5 budget is
//! 0.5 s for the whole reconstruction of a 13k-vertex mesh or a 200k-point
//! scan; segmentation should take well under 100 ms of it).
//!
//! ```text
//! cargo run --release -p trigbody-io --example segment_timing [DATA_DIR] [RUNS]
//! ```
//!
//! `DATA_DIR` defaults to `$TRIGBODY_DATA`, else `../shared/data` beside the
//! repository. Prints the median and the fastest of `RUNS` (default 15)
//! runs per input, and each input's landmark heights as fractions of H.

use std::path::PathBuf;
use std::time::{Duration, Instant};
use trigbody_core::{segment, BodyGeometry, SegmentOptions, Segmentation};
use trigbody_io::{read_mesh, read_point_cloud, ReadOptions};

fn time(runs: usize, mut f: impl FnMut() -> Segmentation) -> (Duration, Duration, Segmentation) {
    let mut times = Vec::with_capacity(runs);
    let mut last = None;
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        let s = f();
        times.push(t.elapsed());
        last = Some(s);
    }
    times.sort();
    let s = last.expect("at least one run");
    (times[times.len() / 2], times[0], s)
}

fn report(name: &str, (median, best, s): (Duration, Duration, Segmentation)) {
    println!(
        "{name:<22} median {:>7.1} ms  best {:>7.1} ms  parts {}  warnings {}",
        median.as_secs_f64() * 1e3,
        best.as_secs_f64() * 1e3,
        s.parts.len(),
        s.warnings.len()
    );
    let line: Vec<String> = s
        .landmarks
        .iter()
        .map(|l| format!("{} {:.3}", l.kind, l.height_fraction))
        .collect();
    println!("    {}", line.join(", "));
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let data = args
        .next()
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("TRIGBODY_DATA").map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    let runs: usize = args.next().and_then(|r| r.parse().ok()).unwrap_or(15);
    let opts = SegmentOptions::default();
    for name in ["mh_base.obj", "mh_male.obj", "mh_female.ply"] {
        let mesh = read_mesh(data.join("bodies").join(name), &ReadOptions::default())?;
        report(
            name,
            time(runs, || {
                segment(BodyGeometry::Mesh(&mesh), &opts).expect("segmentation")
            }),
        );
    }
    let cloud = read_point_cloud(
        data.join("scans").join("mh_male_scan.ply"),
        &ReadOptions::default(),
    )?;
    report(
        "mh_male_scan.ply",
        time(runs, || {
            segment(BodyGeometry::Cloud(&cloud), &opts).expect("segmentation")
        }),
    );
    Ok(())
}
