//! End-to-end tests of `trigbody sections` and `trigbody scan`: the real
//! binary on files written here (a cylinder of known radius).

use assert_cmd::Command;
use serde_json::Value;
use std::path::PathBuf;
use trigbody_core::internals::geom::shapes;
use trigbody_core::Vec3;
use trigbody_io::{write_mesh, WriteOptions};

fn trigbody() -> Command {
    Command::cargo_bin("trigbody").unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A closed cylinder of radius 0.1 around the y axis, 1 unit tall (y up,
/// as the files' convention is).
fn cylinder_obj(dir: &std::path::Path) -> PathBuf {
    let mut m = shapes::cylinder(Vec3::ZERO, 0.1, 1.0, 21, 256);
    for p in &mut m.positions {
        *p = Vec3::new(p.x, p.z, -p.y);
    }
    let path = dir.join("cylinder.obj");
    write_mesh(&path, &m, &WriteOptions::default()).unwrap();
    path
}

#[test]
fn sections_of_a_cylinder_are_circles_in_the_json() {
    let dir = scratch("sections_cylinder");
    let obj = cylinder_obj(&dir);
    let json = dir.join("s.json");
    trigbody()
        .args(["sections", obj.to_str().unwrap(), "--count", "5", "--json"])
        .arg(&json)
        .assert()
        .success();
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(doc["format"], "trigbody-sections");
    let levels = doc["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 5);
    for (k, level) in levels.iter().enumerate() {
        let offset = level["offset"].as_f64().unwrap();
        assert!((offset - (k as f64 + 0.5) / 5.0).abs() < 1e-12);
        let loops = level["loops"].as_array().unwrap();
        assert_eq!(loops.len(), 1);
        let l = &loops[0];
        let (a1, b1) = (l["a"][1].as_f64().unwrap(), l["b"][1].as_f64().unwrap());
        // |a1| = |b1| = r for a circle (sign depends on the start point)
        assert!(
            (a1.hypot(l["a"][2].as_f64().unwrap()) - 0.1).abs() < 1e-4,
            "{a1}"
        );
        assert!(
            (b1.hypot(l["b"][2].as_f64().unwrap()) - 0.1).abs() < 1e-4,
            "{b1}"
        );
        assert!((l["normal"][1].as_f64().unwrap() - 1.0).abs() < 1e-9);
        assert!(l["ellipse"]["ea"].as_f64().unwrap() < 1e-3);
        for key in ["origin", "e1", "e2", "order", "ea", "em", "orders_tried"] {
            assert!(l.get(key).is_some(), "loop lacks {key}");
        }
    }
}

#[test]
fn sections_plot_draws_every_level_and_the_outline() {
    let dir = scratch("sections_plot");
    let obj = cylinder_obj(&dir);
    for name in ["s.svg", "s.png"] {
        let plot = dir.join(name);
        trigbody()
            .args(["sections", obj.to_str().unwrap(), "--count", "4", "--plot"])
            .arg(&plot)
            .assert()
            .success();
        assert!(std::fs::metadata(&plot).unwrap().len() > 1000);
    }
    let svg = std::fs::read_to_string(dir.join("s.svg")).unwrap();
    // The overview, then one panel per level (4 ≤ --plot-levels).
    assert_eq!(
        svg.matches("offset ").count(),
        4,
        "one detail panel per level"
    );
    assert!(svg.contains("input (outline)") && svg.contains("ellipse"));
    trigbody()
        .args(["sections", obj.to_str().unwrap(), "--plot", "x.gif"])
        .assert()
        .code(2);
}

#[test]
fn scan_then_sections_of_the_scan() {
    let dir = scratch("scan_cylinder");
    let obj = cylinder_obj(&dir);
    let ply = dir.join("scan.ply");
    let out = trigbody()
        .args([
            "scan",
            obj.to_str().unwrap(),
            "--points",
            "40000",
            "--seed",
            "7",
            "-o",
        ])
        .arg(&ply)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    assert!(String::from_utf8_lossy(&out).contains("40000 points"));
    // same seed, same file
    let again = dir.join("again.ply");
    trigbody()
        .args([
            "scan",
            obj.to_str().unwrap(),
            "--points",
            "40000",
            "--seed",
            "7",
            "-o",
        ])
        .arg(&again)
        .assert()
        .success();
    assert_eq!(std::fs::read(&ply).unwrap(), std::fs::read(&again).unwrap());
    // writing over an existing file needs --overwrite
    trigbody()
        .args(["scan", obj.to_str().unwrap(), "--points", "1000", "-o"])
        .arg(&ply)
        .assert()
        .code(2);
    let json = dir.join("s.json");
    trigbody()
        .args([
            "sections",
            ply.to_str().unwrap(),
            "--from",
            "0.2",
            "--to",
            "0.8",
            "--step",
            "0.2",
            "--json",
        ])
        .arg(&json)
        .assert()
        .success();
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(doc["kind"], "scan");
    let levels = doc["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 3);
    for level in levels {
        let loops = level["loops"].as_array().unwrap();
        assert_eq!(loops.len(), 1);
        let a1 = loops[0]["a"][1]
            .as_f64()
            .unwrap()
            .hypot(loops[0]["a"][2].as_f64().unwrap());
        assert!((a1 - 0.1).abs() < 2e-3, "radius {a1}");
    }
}

#[test]
fn bad_input_exits_2_naming_the_problem() {
    let dir = scratch("sections_bad");
    let obj = cylinder_obj(&dir);
    let missing = dir.join("missing.obj");
    let out = trigbody()
        .args(["sections"])
        .arg(&missing)
        .assert()
        .code(2)
        .get_output()
        .stderr
        .clone();
    assert!(String::from_utf8_lossy(&out).contains("missing.obj"));
    let out = trigbody()
        .args([
            "sections",
            obj.to_str().unwrap(),
            "--from",
            "5",
            "--to",
            "6",
        ])
        .assert()
        .code(2)
        .get_output()
        .stderr
        .clone();
    assert!(String::from_utf8_lossy(&out).contains("outside the input"));
    trigbody()
        .args(["sections", obj.to_str().unwrap(), "--count", "0"])
        .assert()
        .code(2);
    trigbody()
        .args(["sections", obj.to_str().unwrap(), "--step=-0.1"])
        .assert()
        .code(2);
    trigbody()
        .args(["scan", obj.to_str().unwrap(), "--points", "0", "-o"])
        .arg(dir.join("x.ply"))
        .assert()
        .code(2);
}

/// Coordinates are often negative: `--from -0.5` and `--reference -1,0,0`
/// are values, not flags (a regression found by hand: clap took them for
/// options).
#[test]
fn negative_numbers_are_values() {
    let dir = scratch("sections_negative");
    let obj = cylinder_obj(&dir);
    trigbody()
        .args(["sections", obj.to_str().unwrap(), "--count", "2"])
        .args(["--from", "-0.5", "--to", "0.9", "--reference", "-1,0,0"])
        .assert()
        .success();
}
