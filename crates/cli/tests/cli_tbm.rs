//! End-to-end: the compact model (`reconstruct -o body.tbm`, read by
//! `mesh` and `measure`; damaged files exit 2 naming the file) and the
//! rate-distortion options (`--target-rms`, `--max-parameters`), on the
//! built-in body.

use assert_cmd::Command;
use std::path::PathBuf;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("trigbody-tbm-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn trigbody() -> Command {
    Command::cargo_bin("trigbody").unwrap()
}

/// The number after `key` in the reconstruct printout.
fn number_after(stdout: &str, key: &str) -> f64 {
    let rest = &stdout[stdout
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in {stdout}"))..];
    rest[key.len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn a_compact_model_is_written_read_and_refused_when_damaged() {
    let d = dir("roundtrip");
    let out = trigbody()
        .current_dir(&d)
        .args(["reconstruct", "-o", "body.tbm"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("body.tbm:") && stdout.contains("bytes"),
        "{stdout}"
    );
    let bytes = std::fs::read(d.join("body.tbm")).unwrap();
    assert!(bytes.starts_with(b"TBM") && bytes.len() < 40_000);
    for args in [
        vec!["mesh", "body.tbm", "-o", "body.obj", "--skin", "outer"],
        vec!["measure", "body.tbm"],
    ] {
        let out = trigbody().current_dir(&d).args(&args).output().unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    std::fs::write(d.join("cut.tbm"), &bytes[..bytes.len() / 2]).unwrap();
    let mut flipped = bytes.clone();
    flipped[bytes.len() / 3] ^= 0x10;
    std::fs::write(d.join("flipped.tbm"), flipped).unwrap();
    for bad in ["cut.tbm", "flipped.tbm"] {
        for cmd in ["mesh", "measure"] {
            let mut args = vec![cmd, bad];
            if cmd == "mesh" {
                args.extend(["-o", "x.obj"]);
            }
            let out = trigbody().current_dir(&d).args(&args).output().unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
            assert!(
                stderr.contains(bad) && stderr.contains("corrupt"),
                "{stderr}"
            );
        }
    }
}

/// A file of the shared data beside the repository (`rel` below
/// `shared/data`), or `None` with a loud note that `what` is not checked.
fn shared_file(rel: &str, what: &str) -> Option<String> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data")
        .join(rel);
    if path.is_file() {
        Some(path.to_string_lossy().to_string())
    } else {
        eprintln!("NOTE: {} missing: {what} NOT checked", path.display());
        None
    }
}

/// `trigbody reconstruct ARGS` on the built-in body: its printout, after
/// checking that it succeeded.
fn reconstruct_ok(args: &[&str]) -> String {
    let out = trigbody().arg("reconstruct").args(args).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{args:?}: {stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

#[test]
fn a_parameter_budget_is_never_exceeded() {
    let stdout = reconstruct_ok(&["--max-parameters", "6000"]);
    let n = number_after(&stdout, "design parameters");
    assert!(n <= 6000.0 && n > 4000.0, "{n} parameters: {stdout}");
    let out = trigbody()
        .args(["reconstruct", "--max-parameters", "50"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("within 50 design parameters"));
}

/// `--target-rms 2.0` on the built-in body and mh_base lands within
/// 10 % below the target (1.97 and 1.98 mm; the search's stop is 5 %;
/// where the RMS jumps across the target between two trials the second
/// search, on the curve tolerances alone, finds a model in between).
#[test]
fn a_target_rms_is_met_within_ten_percent() {
    let stdout = reconstruct_ok(&["--target-rms", "2.0"]);
    let rms = number_after(&stdout, "distance         rms");
    assert!((1.8..=2.0).contains(&rms), "rms {rms}: {stdout}");
    let Some(base) = shared_file("bodies/mh_base.obj", "--target-rms on mh_base") else {
        return;
    };
    let stdout = reconstruct_ok(&[&base, "--target-rms", "2.0"]);
    let rms = number_after(&stdout, "distance         rms");
    assert!((1.8..=2.0).contains(&rms), "mh_base: rms {rms}: {stdout}");
}

/// A corpus body whose foot outlines, fitted at high orders on unevenly
/// spaced points, swung out between them at some trial settings: a leg
/// 3.6 m across, and the report's tessellation aborted asking for 8.9 GB.
/// Such curves are dropped (`loops_out`); every trial stays a body.
#[test]
fn a_target_search_never_builds_a_wild_part() {
    let Some(path) = shared_file("corpus/body_008.ply", "the wild-part search") else {
        return;
    };
    // Below the body's floor: the search runs to its finest trials, where
    // the orders are highest.
    let stdout = reconstruct_ok(&[&path, "--units", "mm", "--target-rms", "1.5"]);
    let line = rate_line(&stdout);
    let trials: Vec<f64> = line
        .split(';')
        .filter_map(|t| t.split(" / ").nth(1))
        .map(|r| r.trim_end_matches(" mm").trim().parse().unwrap())
        .collect();
    assert!(trials.len() >= 3, "{line}");
    for rms in trials {
        assert!(rms < 10.0, "a trial at {rms} mm: {line}");
    }
}

/// A corpus body whose arms press on its torso: finer tolerances leave its
/// RMS near 2.3 mm, the segmentation's error. A 2 mm target is reported
/// not met after the RMS stops changing, not after every step down to the
/// finest coarseness (eight trials, four at nearly one coarseness).
#[test]
fn an_unreachable_target_stops_where_the_rms_stops_falling() {
    let Some(path) = shared_file("corpus/body_022.ply", "the unreachable target") else {
        return;
    };
    let stdout = reconstruct_ok(&[&path, "--units", "m", "--target-rms", "2.0"]);
    let line = rate_line(&stdout);
    let trials = line.matches(" mm;").count();
    assert!((3..=4).contains(&trials), "{line}");
    assert!(stdout.contains("NOT met"), "{stdout}");
}

/// The rate search's line of trials in a reconstruction's printout.
fn rate_line(stdout: &str) -> &str {
    stdout
        .lines()
        .find(|l| l.starts_with("rate search"))
        .unwrap_or_else(|| panic!("{stdout}"))
}
