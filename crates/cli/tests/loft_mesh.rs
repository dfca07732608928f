//! End-to-end: `trigbody loft` and `trigbody mesh` on small hand-written
//! curve files (the real binary, via assert_cmd).

use assert_cmd::Command;
use std::path::PathBuf;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("trigbody-loft-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A curve JSON object: an ellipse-like loop in the plane z = `z`, centred
/// at (`x`, 0, z).
fn curve(x: f64, z: f64, r: f64) -> String {
    format!(
        r#"{{"frame": {{"origin": [{x}, 0.0, {z}], "e1": [1, 0, 0], "e2": [0, 1, 0]}},
            "a": [0, {r}, 0, 0.004, 0.001], "b": [0, {}, 0, 0, 0.002]}}"#,
        0.8 * r
    )
}

fn curves_file(d: &std::path::Path, name: &str, curves: &[String]) -> PathBuf {
    let p = d.join(name);
    std::fs::write(&p, format!("{{\"curves\": [{}]}}", curves.join(","))).unwrap();
    p
}

fn tube(n: usize) -> Vec<String> {
    (0..n)
        .map(|k| curve(0.0, 0.03 * k as f64, 0.05 + 0.005 * (k as f64).sin()))
        .collect()
}

fn trigbody() -> Command {
    Command::cargo_bin("trigbody").unwrap()
}

#[test]
fn loft_then_mesh_to_every_format() {
    let d = dir("formats");
    let input = curves_file(&d, "curves.json", &tube(6));
    let part = d.join("leg.json");
    trigbody()
        .args([
            "loft",
            input.to_str().unwrap(),
            "-o",
            part.to_str().unwrap(),
        ])
        .args(["--start-cap", "flat", "--end-cap", "dome"])
        .assert()
        .success();
    let text = std::fs::read_to_string(&part).unwrap();
    assert!(text.contains("\"format\": \"trigbody-model\""));
    assert!(text.contains("\"name\": \"leg\""));
    for ext in ["glb", "obj", "ply", "stl"] {
        let out = d.join(format!("leg.{ext}"));
        trigbody()
            .args(["mesh", part.to_str().unwrap(), "-o", out.to_str().unwrap()])
            .args(["--around", "48", "--along", "6"])
            .assert()
            .success();
        let bytes = std::fs::read(&out).unwrap();
        assert!(bytes.len() > 1000, "{ext}");
        if ext == "glb" {
            assert_eq!(&bytes[..4], b"glTF");
            assert_eq!(bytes.len() % 4, 0);
        }
    }
}

#[test]
fn outputs_are_not_overwritten_without_force() {
    let d = dir("force");
    let input = curves_file(&d, "c.json", &tube(4));
    let part = d.join("p.json");
    let loft = |force: bool| {
        let mut c = trigbody();
        c.args([
            "loft",
            input.to_str().unwrap(),
            "-o",
            part.to_str().unwrap(),
        ]);
        if force {
            c.arg("--force");
        }
        c.assert()
    };
    loft(false).success();
    let out = loft(false).code(2);
    let err = String::from_utf8_lossy(&out.get_output().stderr).to_string();
    assert!(
        err.contains("already exists") && err.contains("--force"),
        "{err}"
    );
    loft(true).success();
}

fn stderr_of(args: &[&str]) -> (i32, String) {
    let out = trigbody().args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

#[test]
fn bad_input_exits_2_naming_the_problem() {
    let d = dir("bad");
    let out = d.join("o.json");
    let o = out.to_str().unwrap();
    // One section.
    let one = curves_file(&d, "one.json", &tube(1));
    let (code, err) = stderr_of(&["loft", one.to_str().unwrap(), "-o", o]);
    assert_eq!(code, 2);
    assert!(
        err.contains("one.json") && err.contains("at least 2"),
        "{err}"
    );
    // Crossing planes: the middle curve's plane tilted 60° about x.
    let mut curves = tube(3);
    curves[1] = r#"{"frame": {"origin": [0, 0, 0.03], "e1": [1, 0, 0], "e2": [0, 0.5, -0.8660254037844386]},
        "a": [0, 0.05, 0], "b": [0, 0.04, 0]}"#
        .to_string();
    let crossing = curves_file(&d, "crossing.json", &curves);
    let (code, err) = stderr_of(&["loft", crossing.to_str().unwrap(), "-o", o]);
    assert_eq!(code, 2);
    assert!(err.contains("cross"), "{err}");
    // A null (NaN on the way out) coefficient.
    let mut curves = tube(3);
    curves[2] = curves[2].replacen("0.004", "null", 1);
    let nan = curves_file(&d, "nan.json", &curves);
    let (code, err) = stderr_of(&["loft", nan.to_str().unwrap(), "-o", o]);
    assert_eq!(code, 2);
    assert!(err.contains("section 2") && err.contains("a[3]"), "{err}");
    // A missing frame.
    let mut curves = tube(3);
    curves[1] = r#"{"a": [0, 0.05, 0], "b": [0, 0.04, 0]}"#.to_string();
    let missing = curves_file(&d, "missing.json", &curves);
    let (code, err) = stderr_of(&["loft", missing.to_str().unwrap(), "-o", o]);
    assert_eq!(code, 2);
    assert!(err.contains("frame"), "{err}");
    // A model of an unknown version.
    let input = curves_file(&d, "ok.json", &tube(3));
    trigbody()
        .args(["loft", input.to_str().unwrap(), "-o", o])
        .assert()
        .success();
    let v9 = d.join("v9.json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    doc["version"] = 9.into();
    std::fs::write(&v9, doc.to_string()).unwrap();
    let glb = d.join("v9.glb");
    let (code, err) = stderr_of(&["mesh", v9.to_str().unwrap(), "-o", glb.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("v9.json") && err.contains("version 9"),
        "{err}"
    );
    assert!(!glb.exists());
}

#[test]
fn select_picks_one_loop_per_level() {
    let d = dir("select");
    // Two tubes side by side, both cut at every level.
    let levels: Vec<String> = (0..5)
        .map(|k| {
            let z = 0.03 * k as f64;
            format!(
                "{{\"curves\": [{}, {}]}}",
                curve(-0.1, z, 0.04),
                curve(0.1 + 0.002 * k as f64, z, 0.05)
            )
        })
        .collect();
    let input = d.join("levels.json");
    std::fs::write(&input, format!("{{\"sections\": [{}]}}", levels.join(","))).unwrap();
    let part = d.join("right.json");
    let (code, err) = stderr_of(&[
        "loft",
        input.to_str().unwrap(),
        "-o",
        part.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--select"), "{err}");
    trigbody()
        .args([
            "loft",
            input.to_str().unwrap(),
            "-o",
            part.to_str().unwrap(),
        ])
        .args(["--select", "0.1,0,0"])
        .assert()
        .success();
    let text = std::fs::read_to_string(&part).unwrap();
    assert!(
        text.contains("0.108"),
        "the right tube's last curve is used"
    );
    assert!(!text.contains("-0.1"), "the left tube is not");
}

/// The modelling path on a real body, when the shared data is beside the
/// repository: `sections` → `loft --select` (the left leg) → `mesh`.
#[test]
fn sections_then_loft_then_mesh_on_a_real_body() {
    let body =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/bodies/mh_male.obj");
    if !body.is_file() {
        eprintln!("note: {} not found; skipped", body.display());
        return;
    }
    let d = dir("real");
    let sections = d.join("s.json");
    // The body stands on y = -0.82 (metres, +y up): its legs end at the
    // crotch near y = -0.05.
    trigbody()
        .args(["sections", body.to_str().unwrap(), "--step", "0.03"])
        .args(["--from=-0.76", "--to=-0.05", "--reference", "0,0,1"])
        .args(["--json", sections.to_str().unwrap()])
        .assert()
        .success();
    let part = d.join("leg_left.json");
    let (code, err) = stderr_of(&[
        "loft",
        sections.to_str().unwrap(),
        "-o",
        part.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--select"), "{err}");
    let out = trigbody()
        .args([
            "loft",
            sections.to_str().unwrap(),
            "-o",
            part.to_str().unwrap(),
        ])
        .args(["--select=0.1,-0.4,0", "--start-cap", "dome"])
        .output()
        .unwrap();
    assert!(out.status.success());
    // The left leg only, from the ankle to the crotch: about 23 curves.
    let text = String::from_utf8_lossy(&out.stdout);
    let count: usize = text
        .split(": ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert!((18..=24).contains(&count), "{text}");
    let glb = d.join("leg.glb");
    trigbody()
        .args(["mesh", part.to_str().unwrap(), "-o", glb.to_str().unwrap()])
        .assert()
        .success();
    let bytes = std::fs::read(&glb).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    let text = std::fs::read_to_string(&part).unwrap();
    assert!(text.contains("\"name\": \"leg_left\""));
}

/// `--select` follows one branch and stops where branches merge: two legs
/// below, one trunk above.
#[test]
fn select_stops_where_branches_merge() {
    let d = dir("branches");
    let levels: Vec<String> = (0..6)
        .map(|k| {
            let z = 0.03 * k as f64;
            if k < 3 {
                format!(
                    "{{\"curves\": [{}, {}]}}",
                    curve(-0.1, z, 0.05),
                    curve(0.1, z, 0.05)
                )
            } else {
                format!("{{\"curves\": [{}]}}", curve(0.0, z, 0.16))
            }
        })
        .collect();
    let input = d.join("levels.json");
    std::fs::write(&input, format!("{{\"sections\": [{}]}}", levels.join(","))).unwrap();
    for (select, count) in [("0.1,0,0.03", 3), ("0,0,0.12", 3)] {
        let part = d.join("part.json");
        let out = trigbody()
            .args([
                "loft",
                input.to_str().unwrap(),
                "-o",
                part.to_str().unwrap(),
                "--force",
            ])
            .arg(format!("--select={select}"))
            .output()
            .unwrap();
        assert!(out.status.success());
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            text.contains(&format!(": {count} curves")),
            "{select}: {text}"
        );
    }
}
