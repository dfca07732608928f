//! End-to-end tests of `trigbody fit` and `trigbody examples`: the real
//! binary on real files.

use assert_cmd::Command;
use serde_json::Value;
use std::f64::consts::TAU;
use std::path::PathBuf;

fn trigbody() -> Command {
    Command::cargo_bin("trigbody").unwrap()
}

/// A fresh scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn loops_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/loops")
}

fn fit_json(args: &[&str], stdin: &str) -> Value {
    let out = trigbody()
        .arg("fit")
        .args(args)
        .arg("--json")
        .write_stdin(stdin)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    serde_json::from_slice(&out).unwrap()
}

/// Evaluates the curve in a fit's JSON at v, from the file alone.
fn eval(j: &Value, v: f64) -> [f64; 3] {
    let a: Vec<f64> = serde_json::from_value(j["a"].clone()).unwrap();
    let b: Vec<f64> = serde_json::from_value(j["b"].clone()).unwrap();
    let vec = |k: &str| -> [f64; 3] { serde_json::from_value(j["frame"][k].clone()).unwrap() };
    let (o, e1, e2) = (vec("origin"), vec("e1"), vec("e2"));
    let (mut x, mut y) = (a[0], b[0]);
    for jj in 1..=a.len() / 2 {
        let (s, c) = (jj as f64 * v).sin_cos();
        x += a[2 * jj - 1] * c + a[2 * jj] * s;
        y += b[2 * jj - 1] * s + b[2 * jj] * c;
    }
    [0, 1, 2].map(|k| o[k] + x * e1[k] + y * e2[k])
}

#[test]
fn circle_through_the_cli_is_exact_and_evaluable_from_json() {
    let text: String = (0..50)
        .map(|i| {
            let t = TAU * i as f64 / 50.0;
            format!("{}, {}\n", 3.0 + 0.5 * t.cos(), 1.0 + 0.5 * t.sin())
        })
        .collect();
    let j = fit_json(&["--param", "chord"], &text);
    assert_eq!(j["order"], 1);
    assert!(j["ea"].as_f64().unwrap() < 1e-9 && j["em"].as_f64().unwrap() < 1e-9);
    assert_eq!(j["met"], true);
    assert_eq!(j["frame"]["e1"], serde_json::json!([1.0, 0.0, 0.0]));
    assert_eq!(j["frame"]["e2"], serde_json::json!([0.0, 1.0, 0.0]));
    for k in 0..20 {
        let p = eval(&j, TAU * k as f64 / 20.0);
        let r = ((p[0] - 3.0).powi(2) + (p[1] - 1.0).powi(2)).sqrt();
        assert!((r - 0.5).abs() < 1e-12, "radius {r}");
    }
    for key in [
        "orders_tried",
        "paper_order",
        "minimal_order",
        "normal",
        "b",
    ] {
        assert!(j.get(key).is_some(), "missing {key}");
    }
    assert!(j["ellipse"]["ea"].as_f64().unwrap() < 1e-9);
}

#[test]
fn symmetric_star_through_the_cli_is_exact_with_polar() {
    let r = |t: f64| 0.1 * (1.0 + 0.25 * (2.0 * t).cos() - 0.1 * (4.0 * t).cos());
    let text: String = (0..72)
        .map(|i| {
            let t = TAU * i as f64 / 72.0;
            format!("{} {}\n", r(t) * t.cos(), r(t) * t.sin())
        })
        .collect();
    let j = fit_json(&["--param", "polar", "--order", "5"], &text);
    assert!(j["ea"].as_f64().unwrap() < 1e-9, "{}", j["ea"]);
    assert!(j["em"].as_f64().unwrap() < 1e-9, "{}", j["em"]);
}

#[test]
fn real_loop_table_and_plots() {
    let dir = scratch("real_loop_table_and_plots");
    let file = loops_dir().join("torso_chest.xyz");
    for ext in ["svg", "png"] {
        let plot = dir.join(format!("torso.{ext}"));
        let out = trigbody()
            .arg("fit")
            .arg(&file)
            .arg("--plot")
            .arg(&plot)
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        let text = String::from_utf8(out).unwrap();
        assert!(
            text.contains("trig series") && text.contains("ellipse"),
            "{text}"
        );
        assert!(text.contains("order search"), "{text}");
        let bytes = std::fs::read(&plot).unwrap();
        assert!(bytes.len() > 1000);
    }
    let svg = std::fs::read_to_string(dir.join("torso.svg")).unwrap();
    assert!(svg.contains("ellipse") && svg.contains("trig J="));
}

#[test]
fn examples_command_is_the_readme_main_job() {
    let dir = scratch("examples_command");
    let out = trigbody()
        .current_dir(&dir)
        .args(["examples", "--plot", "examples.png"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let text = String::from_utf8(out).unwrap();
    for name in [
        "torso_chest",
        "neck",
        "thigh",
        "upper_arm",
        "calf",
        "torso_waist",
    ] {
        assert!(text.contains(name), "{text}");
    }
    assert!(dir.join("examples.png").exists());
    let json = trigbody()
        .current_dir(&dir)
        .args(["examples", "--json", "--plot", "e.svg"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let list: Vec<Value> = serde_json::from_slice(&json).unwrap();
    assert_eq!(list.len(), 6);
    for j in &list {
        assert_eq!(j["met"], true, "{}", j["name"]);
        assert_eq!(j["order"], j["minimal_order"]);
    }
}

/// Runs `trigbody fit` on `stdin` with `args`, expects exit 2 and a message
/// containing `needle`.
fn refused(args: &[&str], stdin: &str, needle: &str) {
    let out = trigbody()
        .arg("fit")
        .args(args)
        .write_stdin(stdin)
        .assert()
        .code(2)
        .get_output()
        .clone();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains(needle), "expected '{needle}' in: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_input_exits_2_with_a_clear_message() {
    refused(&[], "", "no points");
    refused(&[], "# only a comment\n", "no points");
    refused(&[], "1 2\n", "the same point");
    refused(&[], "1 2\n3 4\n", "only 2 distinct");
    refused(
        &["--order", "3"],
        "0 0\n1 0\n1.3 0.8\n0.5 1.4\n-0.3 0.8\n",
        "order 3 needs at least 7 distinct points",
    );
    refused(&[], "0 0\n1 nan\n1 1\n", "not finite");
    refused(&[], "0 0\n1 inf\n1 1\n", "not finite");
    refused(&[], "2 2\n2 2\n2 2\n2 2\n", "the same point");
    refused(&[], "0 0\n1 1\n2 2\n3 3\n", "on one line");
    refused(&[], "0 0\n1 0\nabc 1\n", "-:3: 'abc' is not a number");
    refused(&[], "0 0\n1 1\n1 0\n0 1\n", "crosses itself");
    let saddle: String = (0..40)
        .map(|i| {
            let t = TAU * i as f64 / 40.0;
            format!("{} {} {}\n", t.cos(), t.sin(), 0.5 * (2.0 * t).cos())
        })
        .collect();
    refused(&[], &saddle, "not planar");
    // With the flag it is a warning and a fit.
    let out = trigbody()
        .args(["fit", "--allow-non-planar"])
        .write_stdin(saddle)
        .assert()
        .success()
        .get_output()
        .clone();
    assert!(String::from_utf8(out.stderr).unwrap().contains("warning"));
    refused(&["--order", "0"], "0 0\n1 0\n0 1\n", "at least 1");
    refused(&["--order", "x"], "0 0\n1 0\n0 1\n", "'x'");
    refused(
        &["--plot", "out.jpg"],
        "0 0\n1 0\n0 1\n",
        "unknown picture format",
    );
    refused(
        &["--ea=-1"],
        "0 0\n1 0\n0 1\n",
        "invalid tolerance ea = -1: it must be a positive number",
    );
}

#[test]
fn missing_file_is_bad_input_naming_it() {
    let out = trigbody()
        .args(["fit", "/nonexistent/loop.txt"])
        .assert()
        .code(2)
        .get_output()
        .clone();
    assert!(String::from_utf8(out.stderr)
        .unwrap()
        .contains("/nonexistent/loop.txt"));
}

#[test]
fn refuses_to_write_the_plot_over_its_input() {
    let dir = scratch("refuses_overwrite");
    let input = dir.join("loop.svg");
    std::fs::write(&input, "0 0\n1 0\n1 1\n0 1\n0.5 1.2\n").unwrap();
    trigbody()
        .arg("fit")
        .arg(&input)
        .arg("--plot")
        .arg(&input)
        .assert()
        .code(2);
    assert_eq!(
        std::fs::read_to_string(&input).unwrap(),
        "0 0\n1 0\n1 1\n0 1\n0.5 1.2\n"
    );
}

#[test]
fn negative_reference_is_a_value() {
    let loops = loops_dir().join("thigh.xyz");
    trigbody()
        .arg("fit")
        .arg(&loops)
        .args(["--reference", "-1,0,0", "--normal", "0,-1,0"])
        .assert()
        .success();
}

#[test]
fn an_existing_plot_is_replaced_only_with_force() {
    let dir = scratch("plot_force");
    let plot = dir.join("thigh.svg");
    std::fs::write(&plot, "keep me").unwrap();
    let loops = loops_dir().join("thigh.xyz");
    let out = trigbody()
        .arg("fit")
        .arg(&loops)
        .arg("--plot")
        .arg(&plot)
        .assert()
        .code(2)
        .get_output()
        .clone();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("thigh.svg") && err.contains("--force"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&plot).unwrap(), "keep me");
    trigbody()
        .arg("fit")
        .arg(&loops)
        .arg("--plot")
        .arg(&plot)
        .arg("--force")
        .assert()
        .success();
    assert!(std::fs::read_to_string(&plot).unwrap().contains("<svg"));
}

/// `--noise`: a circle of radius 50 scattered by 1 (deterministic, mean
/// zero) is fitted at a low order with it and a high one without; a
/// negative noise is refused.
#[test]
fn noise_keeps_the_order_to_the_shape() {
    let text: String = (0..120)
        .map(|i| {
            let t = TAU * i as f64 / 120.0;
            // A fixed pseudo-random scatter in [-1.7, 1.7] (sd about 1).
            let e = 1.7 * ((i * 7919 % 97) as f64 / 48.0 - 1.0);
            let r = 50.0 + e;
            format!("{} {}\n", r * t.cos(), r * t.sin())
        })
        .collect();
    let plain = fit_json(&["--smoothing", "1e-5"], &text);
    let floored = fit_json(&["--smoothing", "1e-5", "--noise", "1"], &text);
    let (a, b) = (
        plain["order"].as_u64().unwrap(),
        floored["order"].as_u64().unwrap(),
    );
    assert!(a >= 10, "order {a} without --noise");
    assert!(b <= 3, "order {b} with --noise 1");
    refused(&["--noise", "-1"], &text, "--noise");
}
