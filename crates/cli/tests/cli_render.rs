//! End-to-end tests of `trigbody render`: the real binary on generated
//! mesh files.

use assert_cmd::Command;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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

/// A closed cylinder (radius 0.2, height 1, z up when `z_up`) as OBJ text
/// with quads on the side and fans on the caps.
fn cylinder_obj(z_up: bool) -> String {
    let n = 48;
    let mut text = String::from("# generated cylinder\n");
    for y in [0.0, 1.0] {
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            let (x, z) = (0.2 * a.cos(), 0.2 * a.sin());
            if z_up {
                writeln!(text, "v {x} {} {y}", -z).unwrap();
            } else {
                writeln!(text, "v {x} {y} {z}").unwrap();
            }
        }
    }
    for i in 0..n {
        let j = (i + 1) % n;
        // 1-based: bottom ring 1..=n, top ring n+1..=2n.
        writeln!(text, "f {} {} {} {}", i + 1, n + i + 1, n + j + 1, j + 1).unwrap();
    }
    let top: Vec<String> = (0..n).rev().map(|i| (n + i + 1).to_string()).collect();
    let bottom: Vec<String> = (0..n).map(|i| (i + 1).to_string()).collect();
    writeln!(text, "f {}", top.join(" ")).unwrap();
    writeln!(text, "f {}", bottom.join(" ")).unwrap();
    text
}

/// Width and height from a PNG's IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    (be(&bytes[16..20]), be(&bytes[20..24]))
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn renders_a_mesh_file_to_png() {
    let dir = scratch("render_ok");
    let mesh = write(&dir, "cylinder.obj", &cylinder_obj(false));
    let out = dir.join("pictures/cylinder.png");
    let output = trigbody()
        .args([
            "render",
            mesh.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["--size", "96", "--views", "front,side,back,30"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let stdout = String::from_utf8_lossy(&output);
    assert!(stdout.contains("4 view(s), 384×96 pixels"), "{stdout}");
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(png_size(&bytes), (384, 96));
}

#[test]
fn up_axis_flag_turns_a_z_up_file_upright() {
    // The same cylinder written z-up, read with `--up-axis z`, gives the
    // same picture as the y-up file.
    let dir = scratch("render_up");
    let render = |file: &str, text: &str, extra: &[&str]| {
        let mesh = write(&dir, file, text);
        let out = dir.join(format!("{file}.png"));
        trigbody()
            .args([
                "render",
                mesh.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args(["--size", "64", "--views", "front,side"])
            .args(extra)
            .assert()
            .success();
        std::fs::read(&out).unwrap()
    };
    let y_up = render("y.obj", &cylinder_obj(false), &[]);
    let z_up = render("z.obj", &cylinder_obj(true), &["--up-axis", "z"]);
    let z_unturned = render("z_keep.obj", &cylinder_obj(true), &[]);
    assert_eq!(png_size(&y_up), (128, 64));
    assert_eq!(y_up, z_up);
    assert_ne!(y_up, z_unturned);
}

/// Stderr must name `what`, and the exit code must be 2.
fn fails_with_bad_input(args: &[&str], what: &str) {
    let output = trigbody().args(args).output().unwrap();
    assert_eq!(output.status.code(), Some(2), "{args:?}");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains(what), "{args:?}: {stderr}");
}

#[test]
fn bad_input_exits_2_naming_the_file_or_value() {
    let dir = scratch("render_bad");
    let mesh = write(&dir, "cylinder.obj", &cylinder_obj(false));
    let mesh = mesh.to_str().unwrap();
    let out = dir.join("out.png");
    let out = out.to_str().unwrap();
    let missing = dir.join("missing.obj");
    fails_with_bad_input(
        &["render", missing.to_str().unwrap(), "-o", out],
        "missing.obj",
    );
    let nan = write(&dir, "nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
    fails_with_bad_input(&["render", nan.to_str().unwrap(), "-o", out], "nan.obj");
    let points = write(&dir, "points.xyz", "0 0 0\n1 0 0\n0 1 0\n");
    fails_with_bad_input(
        &["render", points.to_str().unwrap(), "-o", out],
        "points.xyz",
    );
    let model = write(&dir, "model.json", "{}");
    fails_with_bad_input(
        &["render", model.to_str().unwrap(), "-o", out],
        "model.json",
    );
    fails_with_bad_input(&["render", mesh, "-o", out, "--views", "top"], "top");
    fails_with_bad_input(
        &["render", mesh, "-o", out, "--size", "0"],
        "--size <SIZE>': must be a whole number in 16..=8192",
    );
    fails_with_bad_input(&["render", mesh, "-o", out, "--supersample", "9"], "9");
    fails_with_bad_input(&["render", mesh, "-o", "picture.jpg"], "picture.jpg");
    assert!(!Path::new(out).exists());
}

/// `--focus head` on the built-in body draws only the head (fewer
/// triangles than the whole body, every one above the neck); a box that
/// holds nothing, a box that is not one, and a cylinder with no body to
/// find regions on are refused with exit 2.
#[test]
fn focus_zooms_onto_a_region_or_a_box() {
    let dir = scratch("render_focus");
    let body = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/bodies/mh_male.obj");
    let out = dir.join("head.png");
    let stdout = trigbody()
        .args(["render", body, "-o", out.to_str().unwrap()])
        .args(["--size", "64", "--focus", "head"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let stdout = String::from_utf8_lossy(&stdout);
    let drawn: usize = stdout
        .split(": ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    let whole = trigbody_io::read_mesh(body, &Default::default()).unwrap();
    assert!(
        drawn > 1000 && drawn < whole.triangles.len() / 2,
        "{stdout}"
    );
    // The top fifth of the body's box.
    let b = whole.bounds().unwrap();
    let y0 = b.max.y - 0.2 * (b.max.y - b.min.y);
    let corners = format!(
        "--focus-box={},{y0},{},{},{},{}",
        b.min.x, b.min.z, b.max.x, b.max.y, b.max.z
    );
    let boxed = dir.join("box.png");
    trigbody()
        .args(["render", body, "-o", boxed.to_str().unwrap()])
        .args(["--size", "64", &corners])
        .assert()
        .success();
    let out = dir.join("bad.png");
    let out = out.to_str().unwrap();
    fails_with_bad_input(
        &["render", body, "-o", out, "--focus-box=5,5,5,6,6,6"],
        "no triangle lies in the box",
    );
    fails_with_bad_input(
        &["render", body, "-o", out, "--focus-box=1,1,1,0,0,0"],
        "is not a box",
    );
    let cylinder = write(&dir, "cylinder.obj", &cylinder_obj(false));
    fails_with_bad_input(
        &[
            "render",
            cylinder.to_str().unwrap(),
            "-o",
            out,
            "--focus",
            "feet",
        ],
        "--focus needs a body",
    );
}

/// `--focus` finds its regions with the up axis the user gave: a z-up copy
/// of the built-in body with `--up-axis z` draws its head; the y-up body
/// said to be x-up is no standing body, and is refused (exit 2) rather
/// than segmented along an axis the user did not give.
#[test]
fn focus_uses_the_up_axis_given() {
    let dir = scratch("render_focus_up");
    let body = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/bodies/mh_male.obj");
    let mesh = trigbody_io::read_mesh(body, &Default::default()).unwrap();
    let mut obj = String::new();
    for p in &mesh.positions {
        // (x, y, z) as a z-up file stores it: (x, -z, y).
        obj.push_str(&format!("v {} {} {}\n", p.x, -p.z, p.y));
    }
    for t in &mesh.triangles {
        obj.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    let z_up = write(&dir, "z_up.obj", &obj);
    let out = dir.join("head.png");
    trigbody()
        .args([
            "render",
            z_up.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["--size", "64", "--focus", "head", "--up-axis", "z"])
        .assert()
        .success();
    let out = dir.join("bad.png");
    fails_with_bad_input(
        &[
            "render",
            body,
            "-o",
            out.to_str().unwrap(),
            "--focus",
            "head",
            "--up-axis",
            "x",
        ],
        "--focus needs a body",
    );
}

/// The tool knows its own output: `--focus` on a model file finds the
/// regions on the model's closed skin (its overlapping pieces alone are
/// no body to segment), with no `--focus-from`.
#[test]
fn focus_works_on_a_model_file() {
    let dir = scratch("render_focus_model");
    let model = dir.join("m.json");
    trigbody()
        .args(["reconstruct", "-o", model.to_str().unwrap()])
        .assert()
        .success();
    let drawn = |region: &str| -> usize {
        let out = dir.join(format!("{region}.png"));
        let stdout = trigbody()
            .args([
                "render",
                model.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args(["--size", "64", "--focus", region])
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        let stdout = String::from_utf8_lossy(&stdout).to_string();
        stdout
            .split(": ")
            .nth(1)
            .and_then(|t| t.split(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{stdout}"))
    };
    let (head, feet) = (drawn("head"), drawn("feet"));
    assert!(head > 500 && feet > 500, "head {head}, feet {feet}");
}
