//! End-to-end tests of `trigbody measure`, `plot-sections` and
//! `render --compare`: the real binary. The shared bodies (`../shared/data`)
//! are used when present and skipped with a note otherwise.

use assert_cmd::Command;
use serde_json::Value;
use std::path::PathBuf;

fn trigbody() -> Command {
    Command::cargo_bin("trigbody").unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn male_body() -> Option<PathBuf> {
    let base = std::env::var_os("TRIGBODY_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    let p = base.join("bodies/mh_male.obj");
    if p.is_file() {
        Some(p)
    } else {
        eprintln!("note: {} not found; skipping", p.display());
        None
    }
}

fn exit_code(cmd: &mut Command) -> (i32, String) {
    let out = cmd.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn measure_json_lists_every_measurement_with_girth_planes() {
    let Some(body) = male_body() else { return };
    let out = trigbody()
        .args(["measure", "--json"])
        .arg(&body)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    let list = j["measurements"].as_array().unwrap();
    let names: Vec<&str> = list.iter().map(|m| m["name"].as_str().unwrap()).collect();
    for want in [
        "stature",
        "neck",
        "chest",
        "waist",
        "hip",
        "thigh",
        "knee",
        "calf",
        "ankle",
        "upper arm",
        "elbow",
        "forearm",
        "wrist",
        "inseam",
        "arm length",
        "shoulder breadth",
    ] {
        assert!(names.contains(&want), "{want} missing from {names:?}");
    }
    for m in list {
        assert!(m["value"].as_f64().unwrap() > 0.0);
        assert_eq!(m["unit"], "m");
        let kind = m["kind"].as_str().unwrap();
        assert!(["girth", "height", "length", "breadth"].contains(&kind));
        if kind == "girth" {
            let origin = m["plane"]["origin"].as_array().unwrap();
            let normal: Vec<f64> = m["plane"]["normal"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert_eq!(origin.len(), 3);
            let len = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!((len - 1.0).abs() < 1e-9);
            let diff = m["value"].as_f64().unwrap() - m["input_tape"].as_f64().unwrap();
            assert!(diff.abs() <= 0.004, "{}: {diff}", m["name"]);
        }
    }
    for key in ["volume", "surface_area"] {
        assert!(j[key]["value"].as_f64().unwrap() > 0.0);
        assert!(j[key]["input_mesh"].as_f64().unwrap() > 0.0);
    }
}

#[test]
fn plot_sections_and_render_compare_write_pictures() {
    let Some(body) = male_body() else { return };
    let dir = scratch("plot_sections");
    let svg = dir.join("sections.svg");
    trigbody()
        .arg("plot-sections")
        .arg(&body)
        .arg("-o")
        .arg(&svg)
        .args(["--levels", "3"])
        .assert()
        .success();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("chest") && text.contains("hip"));
    let png = dir.join("compare.png");
    trigbody()
        .arg("render")
        .arg(&body)
        .arg("--compare")
        .arg(&body)
        .arg("-o")
        .arg(&png)
        .args(["--size", "128"])
        .assert()
        .success();
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
}

#[test]
fn bad_inputs_exit_2_with_a_message() {
    let dir = scratch("measure_bad");
    let model = dir.join("model.json");
    std::fs::write(&model, "{}").unwrap();
    let (code, err) = exit_code(trigbody().arg("measure").arg(&model));
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("model.json"), "{err}");
    let (code, err) = exit_code(trigbody().arg("measure").arg(dir.join("missing.obj")));
    assert_eq!(code, 2, "{err}");
    let cloud = dir.join("cloud.xyz");
    std::fs::write(&cloud, "0 0 0\n1 0 0\n0 1 0\n0 0 1\n").unwrap();
    let (code, err) = exit_code(trigbody().arg("measure").arg(&cloud));
    assert_eq!(code, 2, "{err}");
    // What `reconstruct` says of the same file.
    assert!(err.contains("cloud.xyz: segmentation: no up axis"), "{err}");
    let junk = dir.join("junk.obj");
    std::fs::write(&junk, "v 0 0 nan\nf 1 1 1\n").unwrap();
    let (code, err) = exit_code(trigbody().arg("measure").arg(&junk));
    assert_eq!(code, 2, "{err}");
    let (code, err) = exit_code(
        trigbody()
            .arg("plot-sections")
            .arg(&junk)
            .args(["-o", "x.svg", "--levels", "0"]),
    );
    assert_eq!(code, 2, "{err}");
    let (code, err) = exit_code(
        trigbody()
            .arg("plot-sections")
            .arg(&junk)
            .args(["-o", "x.gif"]),
    );
    assert_eq!(code, 2, "{err}");
    let (code, err) = exit_code(
        trigbody()
            .arg("render")
            .arg(&model)
            .args(["-o"])
            .arg(dir.join("m.png")),
    );
    assert_eq!(code, 2, "{err}");
}

/// A body model written by `trigbody reconstruct` from the built-in body,
/// once per test binary.
fn built_in_model() -> PathBuf {
    static MODEL: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    MODEL
        .get_or_init(|| {
            let dir = scratch("built_in_model");
            let model = dir.join("male.json");
            trigbody()
                .arg("reconstruct")
                .arg("-o")
                .arg(&model)
                .assert()
                .success();
            model
        })
        .clone()
}

#[test]
fn measure_a_model_file_from_its_curves() {
    let model = built_in_model();
    let out = trigbody()
        .args(["measure", "--json"])
        .arg(&model)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["measured_on"], "model file");
    assert_eq!(j["unit"], "m");
    let list = j["measurements"].as_array().unwrap();
    assert_eq!(list.len(), 16, "{list:?}");
    let get = |name: &str| {
        list.iter()
            .find(|m| m["name"] == name)
            .unwrap_or_else(|| panic!("{name} missing"))
    };
    // A 1.73 m adult: plausible values, girths ordered as on any body.
    let stature = get("stature")["value"].as_f64().unwrap();
    assert!((1.6..1.9).contains(&stature), "{stature}");
    let g = |name: &str| get(name)["value"].as_f64().unwrap();
    assert!(g("wrist") < g("forearm") && g("forearm") < g("upper arm"));
    assert!(g("ankle") < g("calf") && g("calf") < g("thigh") && g("thigh") < g("hip"));
    assert!(g("neck") < g("waist") && g("waist") < g("chest"));
    for m in list.iter().filter(|m| m["kind"] == "girth") {
        let n: Vec<f64> = m["plane"]["normal"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert!((n.iter().map(|x| x * x).sum::<f64>().sqrt() - 1.0).abs() < 1e-9);
        // No input mesh to compare with: null, not a number.
        assert!(m["input_tape"].is_null());
    }
    let v = j["volume"]["value"].as_f64().unwrap();
    let a = j["surface_area"]["value"].as_f64().unwrap();
    assert!(
        (0.04..0.09).contains(&v) && (1.4..2.2).contains(&a),
        "{v} {a}"
    );
    assert!(j["volume"]["input_mesh"].is_null());
    // The table: every measurement, no input column values.
    let out = trigbody().arg("measure").arg(&model).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("measured on the model file") && text.contains("shoulder breadth"));
}

#[test]
fn render_and_plot_sections_draw_a_model_file() {
    let model = built_in_model();
    let dir = scratch("model_pictures");
    let png = dir.join("model.png");
    trigbody()
        .arg("render")
        .arg(&model)
        .arg("-o")
        .arg(&png)
        .args(["--size", "96", "--views", "front,side"])
        .assert()
        .success();
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let w = u32::from_be_bytes([bytes[16], bytes[17], bytes[18], bytes[19]]);
    assert_eq!(w, 2 * 96);
    let svg = dir.join("sections.svg");
    trigbody()
        .arg("plot-sections")
        .arg(&model)
        .arg("-o")
        .arg(&svg)
        .args(["--levels", "4"])
        .assert()
        .success();
    let text = std::fs::read_to_string(&svg).unwrap();
    for want in ["chest", "waist", "hip", "thigh", "trig series", "ellipse"] {
        assert!(text.contains(want), "{want} missing from the SVG");
    }
}

#[test]
fn a_model_compared_with_its_input_mesh() {
    let Some(body) = male_body() else { return };
    let model = built_in_model();
    let out = trigbody()
        .args(["measure", "--json"])
        .arg(&model)
        .arg("--input")
        .arg(&body)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    for m in j["measurements"].as_array().unwrap() {
        if m["kind"] == "girth" {
            let d = m["value"].as_f64().unwrap() - m["input_tape"].as_f64().unwrap();
            assert!(d.abs() <= 0.004, "{}: {d}", m["name"]);
        }
    }
    let dir = scratch("model_compare");
    let png = dir.join("compare.png");
    trigbody()
        .arg("render")
        .arg(&model)
        .arg("--compare")
        .arg(&body)
        .arg("-o")
        .arg(&png)
        .args(["--size", "96", "--views", "front"])
        .assert()
        .success();
    let svg = dir.join("sections.svg");
    trigbody()
        .arg("plot-sections")
        .arg(&model)
        .arg("--input")
        .arg(&body)
        .arg("-o")
        .arg(&svg)
        .args(["--levels", "2"])
        .assert()
        .success();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.contains("section points") && text.contains("(input"),
        "input points and girth"
    );
}

#[test]
fn bad_model_files_exit_2_naming_the_file() {
    let dir = scratch("model_bad");
    // No parts.
    let empty = dir.join("no_parts.json");
    std::fs::write(
        &empty,
        r#"{"format": "trigbody-model", "version": 2, "units": "m",
            "body": {"frame": {"up": [0, 1, 0], "front": [0, 0, 1], "left": [1, 0, 0],
                               "origin": [0, 0, 0]}, "height": 1.7},
            "parts": [], "transitions": []}"#,
    )
    .unwrap();
    // Truncated: the first half of a real model file.
    let text = std::fs::read_to_string(built_in_model()).unwrap();
    let truncated = dir.join("truncated.json");
    std::fs::write(&truncated, &text[..text.len() / 2]).unwrap();
    for file in [&empty, &truncated] {
        let name = file.file_name().unwrap().to_str().unwrap();
        for cmd in ["measure", "plot-sections", "render"] {
            let mut c = trigbody();
            c.arg(cmd).arg(file);
            if cmd != "measure" {
                c.arg("-o").arg(dir.join(format!("{cmd}.png")));
            }
            let (code, err) = exit_code(&mut c);
            assert_eq!(code, 2, "{cmd} {name}: {err}");
            assert!(err.contains(name), "{cmd} {name}: {err}");
        }
    }
    // A loft's model (parts, no body frame) is drawn but not measured.
    let loft = dir.join("loft.json");
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    doc.as_object_mut().unwrap().remove("body");
    std::fs::write(&loft, serde_json::to_string(&doc).unwrap()).unwrap();
    let (code, err) = exit_code(trigbody().arg("measure").arg(&loft));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("loft.json") && err.contains("reconstruct"),
        "{err}"
    );
    // --direct is for meshes.
    let (code, err) = exit_code(
        trigbody()
            .args(["measure", "--direct"])
            .arg(built_in_model()),
    );
    assert_eq!(code, 2, "{err}");
}
