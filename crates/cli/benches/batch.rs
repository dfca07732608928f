//! `trigbody batch` on corpus meshes (`../shared/data/corpus`, or
//! `TRIGBODY_DATA`), one job: the time per iteration over three bodies,
//! reading, reconstructing and writing the model and report included, so
//! bodies per second per core = 3 / (time per iteration).
//!
//! `cargo bench -p trigbody --bench batch`

use criterion::{criterion_group, criterion_main, Criterion};
use std::path::PathBuf;

/// Metres, y up, A pose and wide stance: meshes the reconstruction takes.
const BODIES: [&str; 3] = ["body_002.ply", "body_005.ply", "body_015.ply"];

fn bench(c: &mut Criterion) {
    let data = std::env::var_os("TRIGBODY_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    let inputs: Vec<String> = BODIES
        .iter()
        .map(|b| data.join("corpus").join(b).display().to_string())
        .collect();
    if !inputs.iter().all(|p| std::path::Path::new(p).is_file()) {
        eprintln!(
            "NOTE: the corpus is not at {}; SKIPPING the batch benchmark",
            data.display()
        );
        return;
    }
    let out = std::env::temp_dir().join(format!("trigbody-bench-batch-{}", std::process::id()));
    let mut args = vec!["trigbody".to_string(), "batch".to_string()];
    args.extend(inputs);
    args.extend(["-o", &out.display().to_string(), "--jobs", "1", "--force"].map(String::from));
    let mut g = c.benchmark_group("batch");
    g.sample_size(10);
    g.bench_function("3 corpus meshes, 1 job", |b| {
        b.iter(|| assert_eq!(trigbody::run(args.clone()), 0))
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&out);
}

criterion_group!(benches, bench);
criterion_main!(benches);
