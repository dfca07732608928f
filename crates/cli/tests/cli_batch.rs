//! End-to-end tests of `trigbody batch` (the real binary) over the shared
//! bodies, the shared scan and two corpus bodies (`../shared/data`, or
//! `TRIGBODY_DATA`), with an unreadable file among them.

use assert_cmd::Command;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn trigbody() -> Command {
    Command::cargo_bin("trigbody").unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn shared_data() -> Option<PathBuf> {
    let base = std::env::var_os("TRIGBODY_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    if base.join("corpus/manifest.json").is_file() {
        Some(base)
    } else {
        eprintln!(
            "note: the shared data is not at {}; SKIPPING the batch tests on real bodies",
            base.display()
        );
        None
    }
}

fn lines(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn batch_does_every_good_input_reports_the_bad_one_and_resumes() {
    let Some(data) = shared_data() else { return };
    let d = scratch("batch-shared");
    let inputs = d.join("in");
    std::fs::create_dir_all(&inputs).unwrap();
    for f in [
        "bodies/mh_base.obj",
        "bodies/mh_male.obj",
        "bodies/mh_female.ply",
    ] {
        let p = data.join(f);
        std::fs::copy(&p, inputs.join(p.file_name().unwrap())).unwrap();
    }
    // Not a PLY file at all: a header that ends early.
    std::fs::write(
        inputs.join("broken.ply"),
        "ply\nformat ascii 1.0\nelement vert",
    )
    .unwrap();
    let corpus = data.join("corpus/body_00[25].ply");
    let scan = data.join("scans/mh_male_scan.ply");
    let out = d.join("out");
    let run = |extra: &[&str]| {
        let mut cmd = trigbody();
        cmd.arg("batch")
            .arg(&inputs)
            .arg(corpus.to_str().unwrap())
            .arg(&scan)
            .arg("-o")
            .arg(&out)
            .args(["--jobs", "2"])
            .args(extra);
        cmd.output().unwrap()
    };
    let first = run(&[]);
    let stderr = String::from_utf8_lossy(&first.stderr);
    assert_eq!(first.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("1 of 7 inputs failed"), "{stderr}");
    let rows = lines(&out.join("summary.jsonl"));
    assert_eq!(rows.len(), 7);
    for r in &rows {
        let input = r["input"].as_str().unwrap();
        if input.ends_with("broken.ply") {
            assert_eq!(r["status"], "failed");
            assert!(r["error"].as_str().unwrap().contains("PLY"), "{r}");
            continue;
        }
        assert_eq!(r["status"], "ok", "{r}");
        assert!(r["rms_mm"].as_f64().unwrap() > 0.0, "{r}");
        assert!(Path::new(r["model"].as_str().unwrap()).is_file());
        let report: Value =
            serde_json::from_slice(&std::fs::read(r["report"].as_str().unwrap()).unwrap()).unwrap();
        assert_eq!(report["distance_mm"]["rms"], r["rms_mm"]);
    }
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), 8, "{csv}");
    assert!(csv.starts_with("input,status,error,"), "{csv}");

    // The model is the one `reconstruct` writes for the same input.
    let single = d.join("single.json");
    trigbody()
        .arg("reconstruct")
        .arg(inputs.join("mh_male.obj"))
        .arg("-o")
        .arg(&single)
        .assert()
        .success();
    assert_eq!(
        std::fs::read(&single).unwrap(),
        std::fs::read(out.join("mh_male.json")).unwrap()
    );

    // Again without --resume: the outputs are there, so every input fails
    // at once (nothing is overwritten); with --resume nothing is redone.
    let stamp = |p: &str| std::fs::metadata(out.join(p)).unwrap().modified().unwrap();
    let before = stamp("body_002.json");
    let again = run(&[]);
    assert_eq!(again.status.code(), Some(2));
    let rows = lines(&out.join("summary.jsonl"));
    assert!(rows.iter().all(|r| r["status"] == "failed"));
    let resumed = run(&["--resume"]);
    assert_eq!(resumed.status.code(), Some(2));
    let rows = lines(&out.join("summary.jsonl"));
    let skipped = rows.iter().filter(|r| r["status"] == "skipped").count();
    assert_eq!(skipped, 6, "{rows:?}");
    assert!(rows
        .iter()
        .filter(|r| r["status"] == "skipped")
        .all(|r| r["design_parameters"].as_u64().unwrap() > 0));
    assert_eq!(stamp("body_002.json"), before);
}

#[test]
fn bad_usage_exits_2_before_any_work() {
    let d = scratch("batch-usage");
    let out = trigbody()
        .args(["batch", "nothing/here/*.ply", "-o"])
        .arg(d.join("o"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no mesh or scan file matches"));
    let out = trigbody()
        .args(["batch", "x.obj", "--jobs", "0", "-o"])
        .arg(d.join("o"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--jobs"));
}
