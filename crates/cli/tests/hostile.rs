//! The hostile-input suite (issue 19): every case a hostile user tried,
//! and more, each with its expected exit code and a fragment of its
//! message. Every run is the real binary under a 20 s watchdog: a hang is a
//! failure, and so is a panic or an abort (no exit code). Hostile files are
//! made in a scratch directory at test time; nothing large is committed.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_trigbody");
/// The built-in body (metres), in the repository.
const BODY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/bodies/mh_male.obj");
const LIMIT: Duration = Duration::from_secs(20);

struct Outcome {
    code: i32,
    stderr: String,
    elapsed: Duration,
}

/// Runs the binary in `dir` with a watchdog.
fn run(dir: &Path, args: &[&str]) -> Outcome {
    let started = Instant::now();
    let mut child = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the trigbody binary");
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut stderr, &mut s);
        s
    });
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?}: still running after {LIMIT:?} (a hang)");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = reader.join().unwrap();
    let code = status
        .code()
        .unwrap_or_else(|| panic!("{args:?}: killed by a signal (a crash): {stderr}"));
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    Outcome {
        code,
        stderr,
        elapsed: started.elapsed(),
    }
}

/// One case: `args` must exit with `code` and say `fragment` on stderr.
fn case(dir: &Path, args: &[&str], code: i32, fragment: &str) -> Outcome {
    let out = run(dir, args);
    assert_eq!(out.code, code, "{args:?}: {}", out.stderr);
    assert!(
        out.stderr.contains(fragment),
        "{args:?}: expected {fragment:?} in: {}",
        out.stderr
    );
    out
}

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("hostile-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The built-in body with every vertex scaled by `s` (and moved by `dx` in x).
fn scaled_body(s: f64, dx: f64) -> String {
    placed_body(s, dx, 0.0)
}

/// The built-in body scaled by `s` and moved by `dx` in x and `dy` in y.
fn placed_body(s: f64, dx: f64, dy: f64) -> String {
    let text = std::fs::read_to_string(BODY).unwrap();
    text.lines()
        .map(|l| match l.strip_prefix("v ") {
            Some(rest) => {
                let c: Vec<f64> = rest
                    .split_whitespace()
                    .map(|t| t.parse().unwrap())
                    .collect();
                format!("v {} {} {}\n", s * c[0] + dx, s * c[1] + dy, s * c[2])
            }
            None => format!("{l}\n"),
        })
        .collect()
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    std::fs::write(dir.join(name), text).unwrap();
    name.to_string()
}

#[test]
fn resource_bounds_are_exit_2_naming_the_option_and_its_range() {
    let d = scratch("bounds");
    case(&d, &["reconstruct", "-o", "m.json"], 0, "");
    let mut n = 0;
    let mut c = |args: &[&str], frag: &str| {
        case(&d, args, 2, frag);
        n += 1;
    };
    c(
        &["scan", BODY, "-o", "s.ply", "--points", "10000000000"],
        "'--points <POINTS>': must be a whole number in 1..=20000000",
    );
    c(
        &["scan", BODY, "-o", "s.ply", "--points", "100000000"],
        "1..=20000000",
    );
    c(
        &["scan", BODY, "-o", "s.ply", "--azimuths", "1000000"],
        "--azimuths",
    );
    c(
        &["scan", BODY, "-o", "s.ply", "--heights", "0"],
        "--heights",
    );
    c(
        &["reconstruct", "--spacing", "1e-6"],
        "'--spacing <SPACING>': must be a number in [0.002, 0.2]",
    );
    c(&["reconstruct", "--spacing", "NaN"], "--spacing");
    c(
        &["reconstruct", "--digit-spacing", "0.001"],
        "'--digit-spacing <DIGIT_SPACING>': must be a number in [0.004, 0.2]",
    );
    c(
        &["reconstruct", "--scan-frames", "0"],
        "'--scan-frames <SCAN_FRAMES>': must be a whole number in 1..=6",
    );
    c(&["reconstruct", "--scan-frames", "7"], "1..=6");
    c(
        &["plot-sections", BODY, "--panel-size", "0", "-o", "p.png"],
        "--panel-size <PANEL_SIZE>': must be a whole number in 64..=4096",
    );
    c(
        &["plot-sections", BODY, "--panel-size", "0", "-o", "p.svg"],
        "--panel-size",
    );
    c(
        &["plot-sections", BODY, "--columns", "0", "-o", "p.svg"],
        "--columns",
    );
    c(
        &["render", BODY, "-o", "r.png", "--size", "100000"],
        "--size",
    );
    c(
        &["mesh", "m.json", "-o", "m.obj", "--edge", "1e-7"],
        "--edge 0.0000001: must be at least",
    );
    c(
        &["mesh", "m.json", "-o", "m.obj", "--around", "100000000"],
        "--around",
    );
    c(
        &["mesh", "m.json", "-o", "m.obj", "--along", "0"],
        "--along",
    );
    assert!(!d.join("s.ply").exists() && !d.join("p.png").exists() && !d.join("m.obj").exists());
    assert_eq!(n, 16);
    // Nor a hidden temporary: only the model file is there.
    let names: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["m.json"]);
}

#[test]
fn sections_validates_its_options_as_fit_does() {
    let d = scratch("sections");
    let loop_text = write(&d, "loop.txt", "0 0\n1 0\n1.3 0.8\n0.5 1.4\n-0.3 0.8\n");
    for (flags, frag) in [
        (
            &["--half-thickness", "0"][..],
            "--half-thickness <HALF_THICKNESS>': must be a finite number above 0",
        ),
        (
            &["--order", "1000000000"][..],
            "the order must be at most 10000",
        ),
        (
            &["--ea", "0", "--em", "0"][..],
            "'--ea <EA>': invalid tolerance ea = 0: it must be a positive number",
        ),
        (&["--reference", "0,0,0"][..], "is the zero vector"),
        (
            &["--smoothing", "-5"][..],
            "'--smoothing <SMOOTHING>': must be a finite number, 0 or above",
        ),
        (&["--max-order", "0"][..], "--max-order"),
    ] {
        let mut args = vec!["sections", BODY];
        args.extend_from_slice(flags);
        case(&d, &args, 2, frag);
        if !flags.contains(&"--half-thickness") {
            let mut fit = vec!["fit", &loop_text];
            fit.extend_from_slice(flags);
            case(&d, &fit, 2, frag);
        }
    }
    // What only the data can refuse: nothing done is no success.
    case(&d, &["sections", BODY, "--order", "5000"], 2, "none of the");
    case(
        &d,
        &["sections", BODY, "--reference", "0,1,0"],
        2,
        "parallel to the cutting axis",
    );
    case(
        &d,
        &["sections", BODY, "--from", "5", "--to", "6"],
        2,
        "outside the input",
    );
    case(&d, &["sections", BODY, "--count", "0"], 2, "--count");
    case(
        &d,
        &["sections", BODY, "--step", "1e-9"],
        2,
        "more than 100 000 planes",
    );
}

#[test]
fn hostile_meshes_end_quickly_with_a_clear_answer() {
    let d = scratch("meshes");
    // 100 000 copies of one triangle.
    let copies = write(
        &d,
        "copies.obj",
        &format!("v 0 0 0\nv 1 0 0\nv 0 1 0\n{}", "f 1 2 3\n".repeat(100_000)),
    );
    for cmd in ["sections", "reconstruct", "measure"] {
        let out = run(&d, &[cmd, &copies]);
        assert_eq!(out.code, 2, "{cmd}: {}", out.stderr);
        assert!(
            out.stderr.contains("99999 duplicate"),
            "{cmd}: {}",
            out.stderr
        );
        // Measured 0.05 s (it was past 60 s).
        assert!(out.elapsed < Duration::from_secs(5), "{:?}", out.elapsed);
    }
    // The body with 100 000 copies of its first face: the copies are
    // dropped with a warning and the body is the body.
    let body = std::fs::read_to_string(BODY).unwrap();
    let first = body.lines().find(|l| l.starts_with("f ")).unwrap();
    let padded = write(
        &d,
        "padded.obj",
        &format!("{body}{}", format!("{first}\n").repeat(100_000)),
    );
    let out = case(&d, &["reconstruct", &padded], 0, "duplicate triangle(s)");
    assert!(out.elapsed < Duration::from_secs(15), "{:?}", out.elapsed);
    case(&d, &["measure", &padded], 0, "duplicate triangle(s)");
    // One face line with 5.1 million indices.
    let big = write(
        &d,
        "bigface.obj",
        &format!(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf {}\n",
            "1 2 3 ".repeat(1_700_000)
        ),
    );
    for cmd in ["sections", "reconstruct", "measure"] {
        let out = case(
            &d,
            &[cmd, &big],
            2,
            "bigface.obj: OBJ file, line 4: a face has 65537 corners, more than the 65536 allowed",
        );
        // Measured 0.05-0.09 s and 16 MB (it was past 60 s and 1.4 GB).
        assert!(out.elapsed < Duration::from_secs(5), "{:?}", out.elapsed);
    }
    // Only degenerate faces.
    let flat = write(
        &d,
        "flat.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\nf 2 3 3\n",
    );
    case(
        &d,
        &["reconstruct", &flat],
        2,
        "every one of its 2 triangles is degenerate or a duplicate",
    );
    // A PLY face list claiming 4 billion indices.
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n".to_vec();
    ply.extend_from_slice(&[0; 36]);
    ply.extend_from_slice(&u32::MAX.to_le_bytes());
    std::fs::write(d.join("list.ply"), ply).unwrap();
    case(&d, &["sections", "list.ply"], 2, "face 0 (byte");
    // More malformed input.
    case(
        &d,
        &[
            "reconstruct",
            &write(&d, "nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        ],
        2,
        "nan.obj",
    );
    case(
        &d,
        &["reconstruct", &write(&d, "empty.obj", "")],
        2,
        "empty",
    );
    case(
        &d,
        &["reconstruct", &write(&d, "body.dae", "x")],
        2,
        "unknown file extension",
    );
    case(&d, &["reconstruct", "missing.obj"], 2, "missing.obj");
    std::fs::create_dir_all(d.join("dir.obj")).unwrap();
    case(&d, &["reconstruct", "dir.obj"], 2, "not a regular file");
    let bad_index = write(&d, "index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n");
    case(&d, &["sections", &bad_index], 2, "line 4");
}

#[cfg(unix)]
#[test]
fn a_fifo_as_input_is_refused_without_blocking() {
    let d = scratch("fifo");
    let made = Command::new("mkfifo").arg(d.join("pipe.obj")).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("mkfifo unavailable: FIFO case skipped");
        return;
    }
    for cmd in ["sections", "reconstruct", "measure", "scan"] {
        let mut args = vec![cmd, "pipe.obj"];
        if cmd == "scan" {
            args.extend(["-o", "s.ply"]);
        }
        case(&d, &args, 2, "pipe.obj: not a regular file");
    }
}

#[test]
fn implausible_units_and_sizes_are_refused_with_the_unit_that_fits() {
    let d = scratch("units");
    let mm = write(&d, "mm.obj", &scaled_body(1000.0, 0.0));
    let told = "which in m is 1.6692e3 m: not a human body's height (0.4-2.6 m); in mm it is \
                1.67 m tall: give that unit, or auto to infer it";
    case(&d, &["reconstruct", &mm], 2, told);
    // The rate search checks its input too (it once reused the
    // segmentation without it: a 1 669 m body at 1 917 mm RMS, exit 0).
    case(&d, &["reconstruct", &mm, "--target-rms", "2000"], 2, told);
    case(&d, &["measure", &mm], 2, told);
    case(&d, &["plot-sections", &mm, "-o", "p.svg"], 2, told);
    case(
        &d,
        &["plot-sections", &mm, "-o", "p.svg", "--units", "mm"],
        0,
        "",
    );
    case(&d, &["reconstruct", &mm, "--units", "mm"], 0, "");
    case(
        &d,
        &["reconstruct", &mm, "--units", "auto", "--report", "r.json"],
        0,
        "",
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("r.json")).unwrap()).unwrap();
    assert_eq!(
        (report["units"].as_str(), report["units_inferred"].as_bool()),
        (Some("mm"), Some(true))
    );
    case(&d, &["measure", &mm, "--unit", "auto"], 0, "");
    case(
        &d,
        &["measure", &mm, "--unit", "inch"],
        2,
        "--unit inch: must be m, cm, mm or auto",
    );
    case(
        &d,
        &["reconstruct", BODY, "--units", "mm"],
        2,
        "in m it is 1.67 m tall",
    );
    case(
        &d,
        &["reconstruct", BODY, "--units", "cm"],
        2,
        "in m it is 1.67 m tall",
    );
    let huge = write(&d, "huge.obj", &scaled_body(1e20, 0.0));
    case(
        &d,
        &["reconstruct", &huge],
        2,
        "no unit (m, cm, mm) makes it a human size",
    );
    let tiny = write(&d, "tiny.obj", &scaled_body(1e-9, 0.0));
    case(
        &d,
        &["measure", &tiny, "--direct"],
        2,
        "no unit (m, cm, mm)",
    );
}

/// The built-in body and a second copy of it in one OBJ file.
fn two_bodies(one: &str, second: &str) -> String {
    let verts = one.lines().filter(|l| l.starts_with("v ")).count();
    let mut text = one.to_string();
    text.push_str(
        &second
            .lines()
            .filter(|l| l.starts_with("v "))
            .map(|l| format!("{l}\n"))
            .collect::<String>(),
    );
    for l in second.lines().filter(|l| l.starts_with("f ")) {
        let shifted: Vec<String> = l[2..]
            .split_whitespace()
            .map(|c| {
                let mut parts = c.split('/');
                let v: usize = parts.next().unwrap().parse().unwrap();
                std::iter::once((v + verts).to_string())
                    .chain(parts.map(String::from))
                    .collect::<Vec<_>>()
                    .join("/")
            })
            .collect();
        text.push_str(&format!("f {}\n", shifted.join(" ")));
    }
    text
}

#[test]
fn two_people_in_one_file_are_refused() {
    let d = scratch("two");
    let one = scaled_body(1.0, 0.0);
    let text = two_bodies(&one, &scaled_body(1.0, 2.0));
    let two = write(&d, "two.obj", &text);
    case(
        &d,
        &["reconstruct", &two],
        2,
        "the input holds 2 separate bodies (connected pieces 1.73 m, 1.73 m across)",
    );
    case(&d, &["measure", &two], 2, "2 separate bodies");
    // Their virtual scan: two clouds.
    case(
        &d,
        &["scan", &two, "-o", "two.ply", "--points", "60000"],
        0,
        "",
    );
    case(&d, &["reconstruct", "two.ply"], 2, "2 separate bodies");
    // The second 1 m to the side and on a 0.3 m step: their arms reach
    // past each other's side 10 cm apart, so their boxes overlap (one
    // body at 337 mm RMS, exit 0, when pieces were merged by boxes).
    let step = placed_body(1.0, 1.0, 0.3);
    let stepped = write(&d, "step.obj", &two_bodies(&one, &step));
    let args = ["reconstruct", &stepped, "--up-axis", "y", "-o", "s.json"];
    case(&d, &args, 2, "2 separate bodies");
}

#[test]
fn model_files_with_absurd_values_are_refused() {
    let d = scratch("model");
    case(&d, &["reconstruct", "-o", "m.json"], 0, "");
    let text = std::fs::read_to_string(d.join("m.json")).unwrap();
    let model: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut dome = model.clone();
    dome["parts"][1]["caps"]["end"]["relative_height"] = serde_json::json!(1e300);
    let dome = write(&d, "dome.json", &dome.to_string());
    case(
        &d,
        &["mesh", &dome, "-o", "d.obj"],
        2,
        "dome relative_height 1e300 must lie in (0, 100]",
    );
    case(&d, &["measure", &dome], 2, "relative_height");
    let mut far = model.clone();
    far["parts"][0]["sections"][0]["frame"]["origin"][0] = serde_json::json!(1e200);
    let far = write(&d, "far.json", &far.to_string());
    case(
        &d,
        &["mesh", &far, "-o", "f.obj"],
        2,
        "not a finite number of magnitude at most 1e9",
    );
    let mut fat = model;
    fat["parts"][0]["sections"][0]["a"][0] = serde_json::json!(-3e12);
    let fat = write(&d, "fat.json", &fat.to_string());
    case(&d, &["render", &fat, "-o", "f.png"], 2, "-3000000000000");
    assert!(!d.join("d.obj").exists() && !d.join("f.obj").exists());
}

#[test]
fn outputs_never_replace_inputs_or_each_other() {
    let d = scratch("files");
    std::fs::copy(BODY, d.join("in.obj")).unwrap();
    let original = std::fs::read(d.join("in.obj")).unwrap();
    case(&d, &["reconstruct", "-o", "m.json"], 0, "");
    let cases: [(&[&str], &str); 4] = [
        (
            &["reconstruct", "in.obj", "--mesh", "link.obj", "--force"],
            "link.obj",
        ),
        (
            &[
                "scan", "in.obj", "-o", "link.ply", "--force", "--points", "1000",
            ],
            "link.ply",
        ),
        (
            &["reconstruct", "in.obj", "-o", "link.json", "--force"],
            "link.json",
        ),
        (
            &["sections", "in.obj", "--json", "link.json", "--force"],
            "link.json",
        ),
    ];
    for (args, link) in cases {
        let _ = std::fs::remove_file(d.join(link));
        std::fs::hard_link(d.join("in.obj"), d.join(link)).unwrap();
        case(
            &d,
            args,
            2,
            &format!("{link}: refusing to write over the input file"),
        );
        assert_eq!(std::fs::read(d.join("in.obj")).unwrap(), original);
    }
    // `mesh`'s input is a model file: a mesh name linked to it.
    std::fs::hard_link(d.join("m.json"), d.join("m_link.obj")).unwrap();
    let model = std::fs::read(d.join("m.json")).unwrap();
    case(
        &d,
        &["mesh", "m.json", "-o", "m_link.obj", "--force"],
        2,
        "m_link.obj: refusing to write over the input file",
    );
    assert_eq!(std::fs::read(d.join("m.json")).unwrap(), model);
    // A run that fails with --force leaves the file it was to replace.
    std::fs::write(d.join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    for (args, keep) in [
        (
            &["reconstruct", "bad.obj", "-o", "keep.json", "--force"][..],
            "keep.json",
        ),
        (
            &[
                "mesh", "m.json", "-o", "keep.obj", "--force", "--edge", "1e-7",
            ][..],
            "keep.obj",
        ),
        (
            &[
                "scan", "bad.obj", "-o", "keep.ply", "--force", "--points", "0",
            ][..],
            "keep.ply",
        ),
        (
            &[
                "render", "bad.obj", "-o", "keep.png", "--force", "--size", "1",
            ][..],
            "keep.png",
        ),
    ] {
        std::fs::write(d.join(keep), b"KEEP").unwrap();
        case(&d, args, 2, "");
        assert_eq!(std::fs::read(d.join(keep)).unwrap(), b"KEEP", "{args:?}");
    }
    std::fs::hard_link(d.join("m.json"), d.join("m_link.json")).unwrap();
    case(
        &d,
        &["mesh", "m_link.json", "-o", "m.json", "--force"],
        2,
        "unknown mesh format",
    );
    case(
        &d,
        &["render", "m.json", "-o", "./m.json", "--force"],
        2,
        "",
    );
    case(
        &d,
        &[
            "reconstruct",
            "-o",
            "a.json",
            "--report",
            "a.json",
            "--force",
        ],
        2,
        "-o a.json and --report a.json name the same file",
    );
    case(
        &d,
        &["reconstruct", "-o", "b.json", "--report", "./b.json"],
        2,
        "name the same file",
    );
    case(
        &d,
        &["sections", "in.obj", "--json", "s.svg", "--plot", "s.svg"],
        2,
        "name the same file",
    );
    assert!(!d.join("a.json").exists() && !d.join("b.json").exists());
    // Devices are written in place, named without an extension.
    for args in [
        &["mesh", "m.json", "-o", "/dev/null"][..],
        &["scan", "in.obj", "-o", "/dev/null", "--points", "1000"][..],
        &[
            "reconstruct",
            "--mesh",
            "/dev/null",
            "-o",
            "/dev/null",
            "--report",
            "/dev/null",
        ][..],
        &["render", "m.json", "-o", "/dev/null", "--size", "64"][..],
        &["plot-sections", "m.json", "-o", "/dev/null"][..],
    ] {
        case(&d, args, 0, "");
    }
    // A write that fails (a full device) is exit 2 naming it.
    if Path::new("/dev/full").exists() {
        case(&d, &["mesh", "m.json", "-o", "/dev/full"], 2, "/dev/full");
    }
    // A target that cannot be replaced (a directory) survives with --force,
    // and no temporary is left.
    std::fs::create_dir_all(d.join("taken.obj")).unwrap();
    let before = std::fs::read_dir(&d).unwrap().count();
    case(
        &d,
        &["mesh", "m.json", "-o", "taken.obj", "--force"],
        2,
        "taken.obj",
    );
    assert!(d.join("taken.obj").is_dir());
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), before);
}

/// A writer killed at any moment leaves the old file whole (with --force)
/// or no file (without): never a partial file under the target's name.
#[cfg(unix)]
#[test]
fn a_killed_writer_leaves_the_old_file_or_none() {
    let d = scratch("killed");
    case(&d, &["reconstruct", "--mesh", "full.ply"], 0, "");
    let full = std::fs::metadata(d.join("full.ply")).unwrap().len();
    for (k, delay_ms) in [150u64, 400, 700, 1000, 1300, 1600].into_iter().enumerate() {
        let force = k % 2 == 0;
        let target = d.join("out.ply");
        let _ = std::fs::remove_file(&target);
        if force {
            std::fs::write(&target, b"OLD").unwrap();
        }
        let mut args = vec!["reconstruct", "--mesh", "out.ply"];
        if force {
            args.push("--force");
        }
        let mut child = Command::new(BIN)
            .args(&args)
            .current_dir(&d)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        let _ = child.kill();
        let _ = child.wait();
        match std::fs::read(&target) {
            Ok(bytes) => assert!(
                bytes == b"OLD" || bytes.len() as u64 == full,
                "killed after {delay_ms} ms: a file of {} bytes (full: {full})",
                bytes.len()
            ),
            Err(_) => assert!(!force, "killed after {delay_ms} ms: the old file is gone"),
        }
        // Whatever a kill leaves is hidden beside the target.
        for e in std::fs::read_dir(&d).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(
                name == "full.ply" || name == "out.ply" || name.starts_with(".out.ply.trigbody-"),
                "{name}"
            );
        }
    }
}

/// Parts of a body are no body: a model's parts are dropped, the rest
/// tessellated (outer skin) and given back to `reconstruct`.
#[test]
fn a_single_limb_or_a_torso_without_head_is_refused() {
    let d = scratch("parts");
    case(&d, &["reconstruct", "-o", "m.json"], 0, "");
    let text = std::fs::read_to_string(d.join("m.json")).unwrap();
    let model: serde_json::Value = serde_json::from_str(&text).unwrap();
    let keep = |names: &[&str], file: &str| {
        let mut m = model.clone();
        let parts: Vec<serde_json::Value> = m["parts"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| {
                // A part with its hand's digits.
                let name = p["name"].as_str().unwrap();
                names.contains(&name)
                    || name
                        .split_once("_digit_")
                        .is_some_and(|(arm, _)| names.contains(&arm))
            })
            .cloned()
            .collect();
        let transitions: Vec<serde_json::Value> = m["transitions"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|t| {
                names.contains(&t["from"].as_str().unwrap())
                    && names.contains(&t["to"].as_str().unwrap())
            })
            .cloned()
            .collect();
        m["parts"] = serde_json::Value::Array(parts);
        m["transitions"] = serde_json::Value::Array(transitions);
        if names.len() == 1 {
            m["parts"][0]["caps"]["start"] = serde_json::json!({ "kind": "flat" });
        }
        write(&d, file, &m.to_string());
        let obj = file.replace(".json", ".obj");
        case(&d, &["mesh", file, "-o", &obj, "--skin", "outer"], 0, "");
        obj
    };
    let arm = keep(&["left_arm"], "arm.json");
    case(&d, &["reconstruct", &arm], 2, "not a standing body");
    case(&d, &["measure", &arm], 2, "not a standing body");
    let headless = keep(
        &["torso", "left_arm", "right_arm", "left_leg", "right_leg"],
        "headless.json",
    );
    case(&d, &["reconstruct", &headless], 2, "not a standing body");
}

/// Sends `signal` (a name such as "INT") to process `pid`.
#[cfg(unix)]
fn signal(pid: u32, signal: &str) {
    let sent = Command::new("kill")
        .args(["-s", signal, &pid.to_string()])
        .status()
        .expect("kill");
    assert!(sent.success(), "kill -s {signal} {pid}");
}

/// Whether this process ignores signal `number` (Linux; a child inherits it).
#[cfg(unix)]
fn ignored(number: u32) -> bool {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find_map(|l| l.strip_prefix("SigIgn:"))?;
            u64::from_str_radix(line.trim(), 16).ok()
        })
        .is_some_and(|mask| mask >> (number - 1) & 1 == 1)
}

/// The hidden temporaries beside `out.xyz`.
#[cfg(unix)]
fn hidden(d: &Path) -> usize {
    std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".out.xyz.trigbody-"))
        .count()
}

/// Runs `scan` to `out.xyz` and, once its temporary shows, stops it
/// (SIGSTOP), sends `signal` if the temporary is still there and lets it
/// go on: the exit status and whether the signal landed mid-write.
#[cfg(unix)]
fn signalled_scan(
    d: &Path,
    signal_name: &str,
    force: bool,
    ignore: bool,
) -> (std::process::ExitStatus, bool) {
    let mut args = vec!["scan", BODY, "-o", "out.xyz"];
    if force {
        args.push("--force");
    }
    // `trap '' SIG` then exec: started with the signal ignored, as under
    // `nohup` or in a shell's background job.
    let trap = format!("trap '' {signal_name}; exec \"$0\" \"$@\"");
    let mut command = if ignore {
        let mut c = Command::new("sh");
        c.args(["-c", &trap, BIN]);
        c
    } else {
        Command::new(BIN)
    };
    let started = Instant::now();
    let mut child = command
        .args(&args)
        .current_dir(d)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut live = false;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if !live && hidden(d) == 1 {
            signal(child.id(), "STOP");
            // Still there once stopped: the signal lands mid-write.
            live = hidden(d) == 1;
            if live {
                signal(child.id(), signal_name);
            }
            signal(child.id(), "CONT");
        }
        assert!(started.elapsed() < LIMIT, "SIG{signal_name}: a hang");
        std::thread::sleep(Duration::from_micros(200));
    };
    (status, live)
}

/// SIGINT, SIGTERM and SIGHUP in the middle of a write: the process ends
/// by the signal (a shell's 130, 143, 129), its temporary is removed and
/// an existing target is byte for byte the old file; a signal ignored at
/// the start stays ignored and the write completes. The run is stopped as
/// soon as its temporary shows, so the signal lands while the temporary
/// is live; a run that finished before that is checked too and tried
/// again.
#[cfg(unix)]
#[test]
fn a_signal_mid_write_leaves_the_old_file_and_no_temporary() {
    use std::os::unix::process::ExitStatusExt;
    let d = scratch("signals");
    let target = d.join("out.xyz");
    let mut whole: Option<Vec<u8>> = None;
    let cases = [
        ("INT", 2, true, true),
        ("INT", 2, true, false),
        ("TERM", 15, false, false),
        ("HUP", 1, true, false),
    ];
    for (name, number, force, ignore) in cases {
        let ignore_inherited = ignored(number);
        let mut caught = false;
        for _attempt in 0..3 {
            let _ = std::fs::remove_file(&target);
            if force {
                std::fs::write(&target, b"OLD").unwrap();
            }
            let (status, live) = signalled_scan(&d, name, force, ignore);
            assert_eq!(hidden(&d), 0, "SIG{name}: a temporary was left");
            let now = std::fs::read(&target).ok();
            match (status.signal(), status.code()) {
                (Some(s), _) if s == number as i32 => {
                    assert!(!ignore && !ignore_inherited, "SIG{name} was ignored");
                    // A signal just after the rename finds the new file.
                    let old: Option<&[u8]> = force.then_some(b"OLD");
                    assert!(
                        now.as_deref() == old || now == whole,
                        "SIG{name}: the target was changed ({:?} bytes)",
                        now.map(|b| b.len())
                    );
                    caught |= live;
                }
                // Finished: before the signal, or with it ignored.
                (None, Some(0)) => {
                    let now = now.expect("the finished scan");
                    let lines = now.iter().filter(|&&b| b == b'\n').count();
                    assert_eq!(lines, 200_000, "SIG{name}: finished");
                    assert!(whole.is_none() || Some(&now) == whole.as_ref());
                    whole = Some(now);
                    caught |= live && (ignore || ignore_inherited);
                }
                other => panic!("SIG{name}: ended by {other:?}"),
            }
            if caught {
                break;
            }
        }
        assert!(caught, "SIG{name}: never sent mid-write");
    }
}

/// Normal deviates from a fixed seed (xorshift64, Box-Muller).
fn gaussians(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    move || (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos()
}

/// The report's RMS distance (mm) and design parameters; every part found
/// (the six of the body; the digits of a hand whose fingers are apart
/// come besides).
fn rms_and_parameters(report: &Path) -> (f64, u64) {
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(report).unwrap()).unwrap();
    let parts = r["parts"].as_array().expect("parts");
    let body = parts
        .iter()
        .filter(|p| !p["name"].as_str().unwrap_or("").contains("_digit_"))
        .count();
    assert_eq!(body, 6, "{report:?}");
    (
        r["distance_mm"]["rms"].as_f64().unwrap(),
        r["design_parameters"].as_u64().unwrap(),
    )
}

/// A scan made twice as dense by merging it with a copy of itself jittered
/// by 0.5 mm (each coordinate) is the same body, not "not a standing
/// body": the point spacing is not taken from the twins.
#[test]
fn a_scan_merged_with_a_jittered_copy_is_the_same_body() {
    let d = scratch("dense");
    case(&d, &["scan", BODY, "-o", "one.xyz"], 0, "");
    let text = std::fs::read_to_string(d.join("one.xyz")).unwrap();
    let mut g = gaussians(19);
    let mut twice = text.clone();
    for line in text.lines() {
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        let p: Vec<String> = (0..3).map(|k| (v[k] + 0.0005 * g()).to_string()).collect();
        twice.push_str(&format!(
            "{} {} {} {} {} {}\n",
            p[0], p[1], p[2], v[3], v[4], v[5]
        ));
    }
    write(&d, "twice.xyz", &twice);
    // One frame each: the points are what is tested, and 400 000 of them
    // in three frames come near the watchdog beside the other tests.
    case(
        &d,
        &[
            "reconstruct",
            "one.xyz",
            "--report",
            "one.json",
            "--scan-frames",
            "1",
        ],
        0,
        "",
    );
    let out = case(
        &d,
        &[
            "reconstruct",
            "twice.xyz",
            "--report",
            "twice.json",
            "--scan-frames",
            "1",
        ],
        0,
        "",
    );
    let (rms, params) = rms_and_parameters(&d.join("one.json"));
    let (rms2, params2) = rms_and_parameters(&d.join("twice.json"));
    println!(
        "one: rms {rms:.2} mm, {params} parameters; twice: rms {rms2:.2} mm, {params2} ({:?})",
        out.elapsed
    );
    assert!(rms2 < 1.25 * rms, "rms {rms2} against {rms}");
    assert!(
        (params2 as f64 / params as f64 - 1.0).abs() < 0.2,
        "{params2} parameters against {params}"
    );
}

/// A mesh with its left arm deleted is a partial model whose head is still
/// a head: the hole at the shoulder is closed (a warning says so), so the
/// trunk's horizontal sections run on up to the neck.
#[test]
fn a_mesh_without_its_left_arm_keeps_its_head() {
    let d = scratch("armless");
    let armless = armless_body(&d);
    case(
        &d,
        &["reconstruct", &armless, "-o", "m.json"],
        0,
        "closed 1 hole(s) in the mesh",
    );
    let m: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("m.json")).unwrap()).unwrap();
    let head = m["parts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "head")
        .expect("a head");
    let start = head["sections"][0]["frame"]["origin"][1].as_f64().unwrap();
    let dome = head["caps"]["end"]["relative_height"].as_f64().unwrap();
    assert!(start > 0.6, "the head starts at {start} m");
    assert!(dome < 1.0, "a dome of {dome} radii");
}

/// A standard error that cannot be written (full, as /dev/full is) does not
/// stop the work: the model is written and the run succeeds.
#[cfg(target_os = "linux")]
#[test]
fn a_full_stderr_does_not_stop_a_reconstruction() {
    let d = scratch("fullstderr");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    // The armless body warns (a hole closed, an arm missing).
    let armless = armless_body(&d);
    let status = Command::new(BIN)
        .current_dir(&d)
        .args(["reconstruct", &armless, "-o", "m.json"])
        .stdout(std::process::Stdio::null())
        .stderr(full)
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(0));
    let m: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("m.json")).unwrap()).unwrap();
    assert!(m["parts"].as_array().is_some_and(|p| !p.is_empty()));
}

/// The built-in body with its left arm deleted (faces with a corner at
/// x > 0.22 m above y = 0), written to `armless.obj` in `d`.
fn armless_body(d: &Path) -> String {
    let body = std::fs::read_to_string(BODY).unwrap();
    let v: Vec<[f64; 3]> = body
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|r| {
            let c: Vec<f64> = r.split_whitespace().map(|t| t.parse().unwrap()).collect();
            [c[0], c[1], c[2]]
        })
        .collect();
    // The left arm: faces with a corner at x > 0.22 m above y = 0.
    let on_arm = |l: &str| {
        l.split_whitespace().skip(1).any(|c| {
            let i: usize = c.split('/').next().unwrap().parse().unwrap();
            v[i - 1][0] > 0.22 && v[i - 1][1] > 0.0
        })
    };
    let text: String = body
        .lines()
        .filter(|l| !(l.starts_with("f ") && on_arm(l)))
        .map(|l| format!("{l}\n"))
        .collect();
    write(d, "armless.obj", &text)
}
