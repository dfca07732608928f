//! One behaviour behind every door: the same hostile inputs through
//! `trigbody reconstruct` and `trigbody batch` give the same status, the
//! same message and the same exit class, because the checks live in the
//! library (`trigbody_core::validate_input`), not in one command. The
//! Python package and the Dask example are held to the same table by
//! `crates/py/tests/test_doors.py`, which makes the same files.

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_trigbody");
/// The built-in body (metres), in the repository.
const BODY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/bodies/mh_male.obj");

/// The built-in body's vertices and triangles (1-based OBJ indices).
fn body() -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let text = std::fs::read_to_string(BODY).unwrap();
    let mut v = Vec::new();
    let mut f = Vec::new();
    for l in text.lines() {
        if let Some(rest) = l.strip_prefix("v ") {
            let c: Vec<f64> = rest
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect();
            v.push([c[0], c[1], c[2]]);
        } else if let Some(rest) = l.strip_prefix("f ") {
            let i: Vec<usize> = rest
                .split_whitespace()
                .map(|t| t.split('/').next().unwrap().parse().unwrap())
                .collect();
            for k in 1..i.len() - 1 {
                f.push([i[0], i[k], i[k + 1]]);
            }
        }
    }
    (v, f)
}

fn obj(v: &[[f64; 3]], f: &[[usize; 3]]) -> String {
    let mut s = String::new();
    for p in v {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in f {
        s += &format!("f {} {} {}\n", t[0], t[1], t[2]);
    }
    s
}

/// The triangles whose corners all pass `keep`, with only their vertices.
fn part_of(v: &[[f64; 3]], f: &[[usize; 3]], keep: impl Fn(&[f64; 3]) -> bool) -> String {
    let mut index = vec![0usize; v.len() + 1];
    let mut kept_v = Vec::new();
    let mut kept_f = Vec::new();
    for t in f.iter().filter(|t| t.iter().all(|&i| keep(&v[i - 1]))) {
        kept_f.push(t.map(|i| {
            if index[i] == 0 {
                kept_v.push(v[i - 1]);
                index[i] = kept_v.len();
            }
            index[i]
        }));
    }
    obj(&kept_v, &kept_f)
}

/// The hostile inputs of the issue (and a good body), written into `dir`:
/// name and the exit class `trigbody reconstruct` must give.
fn cases(dir: &Path) -> Vec<(&'static str, i32)> {
    let (v, f) = body();
    let scaled = |s: f64, dx: f64| -> Vec<[f64; 3]> {
        v.iter()
            .map(|p| [s * p[0] + dx, s * p[1], s * p[2]])
            .collect()
    };
    let mut two = scaled(1.0, 0.0);
    two.extend(scaled(1.0, 2.0));
    let n = v.len();
    let mut two_f = f.clone();
    two_f.extend(f.iter().map(|t| t.map(|i| i + n)));
    let mut nan = obj(&v, &f);
    nan = nan.replacen(&format!("v {} ", v[4][0]), "v nan ", 1);
    let ten: String = (0..10)
        .map(|i| format!("{} {} 0\n", 0.1 * i as f64, 0.17 * i as f64))
        .collect();
    let truncated = "ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\n\
                     property float y\nproperty float z\nend_header\n0 0 0\n0 1 0\n";
    let files: Vec<(&str, String, i32)> = vec![
        ("body.obj", obj(&v, &f), 0),
        ("body_in_mm.obj", obj(&scaled(1000.0, 0.0), &f), 2),
        ("body_1_7_mm.obj", obj(&scaled(0.001, 0.0), &f), 2),
        ("arm.obj", part_of(&v, &f, |p| p[0] > 0.25 && p[1] > 0.0), 2),
        ("nan_vertex.obj", nan, 2),
        ("two_bodies.obj", obj(&two, &two_f), 2),
        ("empty.obj", String::new(), 2),
        ("truncated.ply", truncated.to_string(), 2),
        ("ten_points.xyz", ten, 2),
    ];
    files
        .into_iter()
        .map(|(name, text, code)| {
            std::fs::write(dir.join(name), text).unwrap();
            (name, code)
        })
        .collect()
}

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("doors-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("in")).unwrap();
    dir
}

/// `trigbody reconstruct` on each case: its exit code and the message
/// after `trigbody: error: `.
fn reconstruct_door(dir: &Path, names: &[&str]) -> BTreeMap<String, (i32, String)> {
    names
        .iter()
        .map(|name| {
            let out = Command::new(BIN)
                .args(["reconstruct", &format!("in/{name}")])
                .current_dir(dir)
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            let error = stderr
                .lines()
                .find_map(|l| l.strip_prefix("trigbody: error: "))
                .unwrap_or("")
                .to_string();
            (name.to_string(), (out.status.code().unwrap(), error))
        })
        .collect()
}

/// `trigbody batch` over the folder: each row's exit class (0 for ok) and
/// error, from `summary.jsonl`.
fn batch_door(dir: &Path, extra: &[&str]) -> BTreeMap<String, (i32, String)> {
    let out = Command::new(BIN)
        .args(["batch", "in", "-o", "out", "--force"])
        .args(extra)
        .current_dir(dir)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.join("out/summary.jsonl")).unwrap();
    text.lines()
        .map(|l| {
            let row: Value = serde_json::from_str(l).unwrap();
            let input = row["input"].as_str().unwrap();
            let name = input.rsplit('/').next().unwrap().to_string();
            let error = row["error"].as_str().unwrap_or("").to_string();
            let code = match row["status"].as_str().unwrap() {
                "ok" => 0,
                _ if error.starts_with("internal error") => 1,
                _ => 2,
            };
            (name, (code, error))
        })
        .collect()
}

#[test]
fn reconstruct_and_batch_say_the_same_of_every_hostile_input() {
    let dir = scratch("table");
    let cases = cases(&dir.join("in"));
    let names: Vec<&str> = cases.iter().map(|c| c.0).collect();
    let cli = reconstruct_door(&dir, &names);
    for (name, code) in &cases {
        let (got, message) = &cli[*name];
        assert_eq!(got, code, "{name}: {message}");
        if *code != 0 {
            // Every refusal names the file.
            assert!(
                message.starts_with(&format!("in/{name}")),
                "{name}: {message}"
            );
        }
    }
    let expect = |name: &str, fragment: &str| {
        let m = &cli[name].1;
        assert!(m.contains(fragment), "{name}: expected {fragment:?} in {m}");
    };
    expect("body_in_mm.obj", "in mm it is 1.67 m tall");
    expect(
        "body_1_7_mm.obj",
        "no unit (m, cm, mm) makes it a human size",
    );
    expect("two_bodies.obj", "2 separate bodies");
    expect("nan_vertex.obj", "nan");
    let batch = batch_door(&dir, &[]);
    assert_eq!(batch.len(), cases.len(), "{batch:?}");
    for (name, _) in &cases {
        assert_eq!(
            batch[*name], cli[*name],
            "{name}: batch and reconstruct differ"
        );
    }
}

#[test]
fn units_auto_models_a_body_in_any_unit_and_says_which() {
    let dir = scratch("auto");
    let (v, f) = body();
    for (name, s) in [
        ("in_m.obj", 1.0),
        ("in_cm.obj", 100.0),
        ("in_mm.obj", 1000.0),
    ] {
        let scaled: Vec<[f64; 3]> = v.iter().map(|p| p.map(|c| c * s)).collect();
        std::fs::write(dir.join("in").join(name), obj(&scaled, &f)).unwrap();
    }
    std::fs::write(
        dir.join("in/tiny.obj"),
        obj(
            &v.iter().map(|p| p.map(|c| c * 1e-3)).collect::<Vec<_>>(),
            &f,
        ),
    )
    .unwrap();
    let batch = batch_door(&dir, &["--units", "auto"]);
    let rows: Vec<Value> = std::fs::read_to_string(dir.join("out/summary.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let units: BTreeMap<String, (String, f64)> = rows
        .iter()
        .map(|r| {
            let name = r["input"]
                .as_str()
                .unwrap()
                .rsplit('/')
                .next()
                .unwrap()
                .to_string();
            (
                name,
                (
                    r["units"].as_str().unwrap().to_string(),
                    r["rms_mm"].as_f64().unwrap_or(f64::NAN),
                ),
            )
        })
        .collect();
    assert_eq!(units["in_m.obj"].0, "m");
    assert_eq!(units["in_cm.obj"].0, "cm");
    assert_eq!(units["in_mm.obj"].0, "mm");
    // The same body in three units: the same model, to the distances' noise.
    let rms = units["in_m.obj"].1;
    for name in ["in_cm.obj", "in_mm.obj"] {
        assert!(
            (units[name].1 - rms).abs() < 0.01 * rms,
            "{name}: {:?} vs {rms}",
            units[name]
        );
    }
    let out = Command::new(BIN)
        .args(["reconstruct", "in/in_mm.obj", "--units", "auto"])
        .current_dir(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("input units: mm (inferred from the body's extent)"),
        "{stdout}"
    );
    let (code, error) = &batch["tiny.obj"];
    assert_eq!(*code, 2);
    assert!(
        error.contains("no unit (m, cm, mm) makes it a human size"),
        "{error}"
    );
    assert_eq!(units["tiny.obj"].0, "auto");
}

#[test]
fn a_manifest_gives_each_input_its_own_unit() {
    let dir = scratch("manifest");
    let (v, f) = body();
    let mm: Vec<[f64; 3]> = v.iter().map(|p| p.map(|c| c * 1000.0)).collect();
    std::fs::write(dir.join("in/a.obj"), obj(&v, &f)).unwrap();
    std::fs::write(dir.join("in/b.obj"), obj(&mm, &f)).unwrap();
    std::fs::write(
        dir.join("in/list.csv"),
        "path,units,note\na.obj,,metres\nb.obj,mm,\n",
    )
    .unwrap();
    let out = Command::new(BIN)
        .args(["batch", "--manifest", "in/list.csv", "-o", "out"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("out/summary.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    assert!(
        rows[0].contains("a.obj,ok,,m,") && rows[1].contains("b.obj,ok,,mm,"),
        "{csv}"
    );
    // A bad cell stops the run before any input is read, naming line and value.
    std::fs::write(
        dir.join("in/bad.csv"),
        "path,units\na.obj,m\nb.obj,inches\n",
    )
    .unwrap();
    let out = Command::new(BIN)
        .args(["batch", "--manifest", "in/bad.csv", "-o", "out2"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("in/bad.csv line 3: units 'inches' is not m, cm, mm or auto"),
        "{stderr}"
    );
    assert!(!dir.join("out2/summary.csv").exists());
}
