//! End-to-end: `trigbody corpus` on one body of each pose class of the
//! shared development corpus (`../shared/data/corpus`), and one scan of
//! each kind of clutter, judged against the truth meshes.
//!
//! The limits are regression guards at the level reached now, not the
//! pose-robustness issue's targets (which are not met yet: see
//! docs/corpus.md): a pose class that stops reconstructing, loses a part or
//! drifts off its truth fails here. Without the shared data the test says
//! so loudly and checks only the command's handling of a bad folder.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn corpus() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/corpus");
    if d.join("manifest.json").is_file() {
        Some(d)
    } else {
        eprintln!(
            "NOTE: {} not found: the corpus pose-class checks are SKIPPED",
            d.display()
        );
        None
    }
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("trigbody-corpus-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs `trigbody corpus DIR ARGS --out OUT`, checks that it succeeded
/// and returns its results.csv.
fn run_corpus(dir: &Path, out: &Path, args: &[&str]) -> String {
    let run = Command::cargo_bin("trigbody")
        .unwrap()
        .arg("corpus")
        .arg(dir)
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    std::fs::read_to_string(out.join("results.csv")).unwrap()
}

/// (input, pose class, RMS limit mm, wrists checked; ankles always are,
/// within 30 mm) — meshes 1.2-3.3 mm now, scans 3.3-6.5 mm (100 000
/// samples; the test takes 30 000).
const CASES: [(&str, &str, f64, bool); 25] = [
    ("body_019", "a", 2.4, true),
    ("body_012", "close", 2.7, true),
    ("body_026", "wide", 2.1, true),
    ("body_000", "t", 2.4, true),
    ("body_020", "raised", 2.4, true),
    ("body_024", "mixed", 2.5, true),
    // Arms the slice graph does not separate, found on the surface: an arm
    // lifted over the shoulder, both raised beside the head, one across
    // the body.
    ("body_030", "wide", 3.0, true),
    ("body_006", "raised", 2.1, true),
    ("body_023", "mixed", 2.8, true),
    // Arms raised above the shoulders: the trunk path must go up the neck,
    // not along a raised arm whose horizontal loops are larger.
    ("body_032", "raised", 2.0, true),
    // Forearms bent forward or up, which slices end at the elbow: the hand
    // is followed on the surface, from a hanging arm and from a raised one.
    ("body_007", "close", 2.8, true),
    ("body_008", "raised", 3.3, true),
    // Arms held out part way and raised: the torso's loops stop at each
    // arm's first built section, not at its axis' shoulder end (a flange
    // over the shoulder: 4.4 and 6.6 mm).
    ("body_005", "wide", 2.1, true),
    ("body_001", "raised", 4.2, true),
    // A heavy body whose arms run out in the torso's loops below the
    // armpit: those loops end on the arm's first section too, as the
    // ones above do (a flange across the armpit: 4.0 mm). Its right arm's
    // first cuts, past a gap where the arm's planes meet nothing, cut
    // the shoulder lengthwise: dropped (a bulge over the deltoid: 1.75).
    ("body_015", "a", 1.7, true),
    // A bent knee lifts one foot off the floor: its sole dome must stop at
    // the foot, not at the floor (3.5 mm with the floor's). Every sole dome
    // goes down along the outline's normal (1.7 mm along the end tangent).
    ("body_037", "a", 2.0, true),
    // A lifted foot's tilted sole: its outlines go on down to the heel
    // until they shrink to half the largest (2.7 mm when they stopped at
    // three quarters).
    ("body_039", "raised", 2.1, true),
    // Feet tilted toes down: below the ankle the outlines run ahead of the
    // line down from it, and low cuts meet the toes as loops of their own.
    // Each outline is taken inside the one before, the toes' hull where no
    // loop holds most of the area (2.38 and 4.82 mm when the loop nearest
    // that line, a stray fragment, ended the run above the toes).
    ("body_004", "wide", 2.0, true),
    // Lips parted: a head cut through the slit followed the mouth's pocket
    // (a C between O's) and the head's surface cut into the face (1.72 mm,
    // far area 0.66 %); the pocket is bridged.
    ("body_018", "a", 1.8, true),
    ("body_004_scan", "wide", 4.5, true),
    // A floor and stray points, arms close, thighs close under the
    // crotch: a leg's slab leaves the other leg's side out (3.29 mm when
    // its loop held both thighs, folded across the crotch).
    ("body_003_scan", "close", 3.15, true),
    // A floor and stray points, T-pose.
    ("body_000_scan", "t", 5.3, true),
    // A missed head top.
    ("body_009_scan", "a", 7.5, true),
    // Raised arms in a scan: the head kept between them (46 mm without
    // it), the bent forearms followed on the cloud's surface graph (21 mm
    // without, a wrist 0.26 m off), the torso's top sections kept though
    // their straight sides run through the arms' roots (6.3 mm dropped).
    ("body_010_scan", "raised", 5.2, true),
    // Arms out wide in a scan, the hands found on the surface graph.
    ("body_005_scan", "wide", 4.5, true),
];

#[test]
fn one_body_of_each_pose_class_stays_reconstructed() {
    let Some(dir) = corpus() else {
        return;
    };
    let out = out_dir("poses");
    let names: Vec<&str> = CASES.iter().map(|c| c.0).collect();
    let only = names.join(",");
    let args = ["--only", &only, "--samples", "30000", "--pictures", "1"];
    let csv = run_corpus(&dir, &out, &args);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), CASES.len(), "{csv}");
    for (name, pose, limit, wrists) in CASES {
        let row = rows
            .iter()
            .find(|r| r[0] == name)
            .unwrap_or_else(|| panic!("{name}: {csv}"));
        assert_eq!(row[col("pose")], pose, "{name}");
        assert_ne!(row[col("status")], "failed", "{name} ({pose}): {csv}");
        assert_eq!(row[col("parts")], "8", "{name} ({pose}): a part was lost");
        let rms: f64 = row[col("rms_mm")].parse().unwrap();
        assert!(rms <= limit, "{name} ({pose}): rms {rms} mm > {limit}");
        let joints = ["left_wrist_mm", "right_wrist_mm"]
            .into_iter()
            .filter(|_| wrists)
            .chain(["left_ankle_mm", "right_ankle_mm"]);
        for joint in joints {
            let e: f64 = row[col(joint)].parse().unwrap();
            assert!(e <= 30.0, "{name} ({pose}): {joint} {e} mm off the truth");
        }
    }
    // Shoulders and hips over the meshes: the socket and the hip's offsets
    // (segment::joints) put their medians at 13-17 mm; on the upper arm's
    // line nearest the Drillis-Contini acromion they were 23 and 21 mm.
    for kind in ["shoulder", "hip"] {
        let mut errs: Vec<f64> = rows
            .iter()
            .filter(|r| !r[0].ends_with("_scan"))
            .flat_map(|r| ["left", "right"].map(|s| r[col(&format!("{s}_{kind}_mm"))]))
            .map(|e| e.parse().unwrap())
            .collect();
        errs.sort_by(f64::total_cmp);
        let median = errs[errs.len() / 2];
        assert!(median <= 20.0, "{kind}s: median {median} mm off the truth");
    }
    // Meshes whose far area (model farther than 10 mm from the truth) lay
    // mostly on a hand's paddle: a mesh hand's sections run on past the
    // palm while the fingers lie together (body_037: 0.53 % when they
    // stopped at half the palm with its thumb). body_005's fingers are
    // apart: its run takes their loops inside the palm's outline, a mitten
    // (0.62 % when the loop round the axis was one finger, the run ended
    // at the knuckles and a dome ballooned). body_000, 004 and 018: a head
    // cut through parted lips (0.57-0.66 % before the mouth's pocket was
    // bridged). The target.
    for name in [
        "body_032", "body_037", "body_005", "body_000", "body_004", "body_018",
    ] {
        let row = rows.iter().find(|r| r[0] == name).unwrap();
        let far: f64 = row[col("model_far")].parse().unwrap();
        assert!(far <= 0.005, "{name}: far area {far} over 0.5 %");
    }
    let md = std::fs::read_to_string(out.join("results.md")).unwrap();
    assert!(md.contains("| body_020 | raised |"), "{md}");
    assert!(std::fs::read_dir(&out).unwrap().any(|e| e
        .unwrap()
        .file_name()
        .to_string_lossy()
        .starts_with("worst-1-")));
    // The results are not replaced without --force.
    let again = Command::cargo_bin("trigbody")
        .unwrap()
        .arg("corpus")
        .arg(&dir)
        .args(["--only", "body_019", "--pictures", "0", "--samples", "2000"])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(again.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&again.stderr).contains("already exists"));
}

#[test]
fn a_folder_without_a_manifest_is_a_usage_error() {
    let out = out_dir("nomanifest");
    std::fs::create_dir_all(&out).unwrap();
    let run = Command::cargo_bin("trigbody")
        .unwrap()
        .arg("corpus")
        .arg(&out)
        .arg("--out")
        .arg(out.join("res"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("manifest.json"));
}

/// `--turn-deg` and `--shift-mm` move each input its own way and its model
/// back: a mesh and a scan (each built in its own frame) are judged as
/// given (the same parts, parameters and verdict; distances within the
/// sampler's noise), and bad probe values are usage errors.
#[test]
fn a_turned_and_moved_mesh_or_scan_is_judged_as_given() {
    let bad = |args: &[&str]| {
        let out = out_dir("badprobe");
        let run = Command::cargo_bin("trigbody")
            .unwrap()
            .arg("corpus")
            .arg(&out)
            .args(args)
            .output()
            .unwrap();
        assert_eq!(run.status.code(), Some(2), "{args:?}");
        String::from_utf8_lossy(&run.stderr).into_owned()
    };
    assert!(bad(&["--turn-deg", "NaN"]).contains("--turn-deg"));
    assert!(bad(&["--shift-mm=-1"]).contains("--shift-mm -1"));
    let Some(dir) = corpus() else {
        return;
    };
    let rms = |only: &str, extra: &[&str]| {
        let out = out_dir(&format!("probe{}", extra.len()));
        // The outer skin: body_033's closed skin turned and turned back
        // differs (1.08 against 1.06 mm RMS, 0.08 against 0.05 % far: the
        // closed skin's boolean, not the judging, a known defect).
        let mut args = vec![
            "--only",
            only,
            "--pictures",
            "0",
            "--samples",
            "20000",
            "--skin",
            "outer",
        ];
        args.extend_from_slice(extra);
        let csv = run_corpus(&dir, &out, &args);
        let md = std::fs::read_to_string(out.join("results.md")).unwrap();
        let turned = extra.contains(&"--turn-deg");
        assert_eq!(md.starts_with("Every input turned"), turned, "{md}");
        // Every column but the time, row by row.
        let header: Vec<String> = csv
            .lines()
            .next()
            .unwrap()
            .split(',')
            .map(String::from)
            .collect();
        let rows: Vec<Vec<String>> = csv
            .lines()
            .skip(1)
            .map(|row| {
                row.split(',')
                    .zip(&header)
                    .filter(|(_, h)| h.as_str() != "seconds")
                    .map(|(v, _)| v.to_string())
                    .collect()
            })
            .collect();
        assert_eq!(rows.len(), only.split(',').count(), "{csv}");
        rows
    };
    let same = |a: Vec<Vec<String>>, b: Vec<Vec<String>>| {
        for (x, y) in a.iter().zip(&b) {
            same_row(x, y);
        }
    };
    // A scan's images turned on a coordinate's last digits (every corpus
    // scan's model moved, by up to 5 mm); body_004_scan is one of the ten
    // now built alike.
    let both = "body_033,body_004_scan";
    let given = rms(both, &[]);
    let probed = rms(
        both,
        &["--turn-deg", "40", "--shift-mm", "300", "--seed", "7"],
    );
    same(given, probed);
    // The manifest's up axis turns with the input.
    let up = rms("body_033", &["--given-up"]);
    let up_probed = rms(
        "body_033",
        &["--given-up", "--turn-deg", "40", "--seed", "7"],
    );
    same(up, up_probed);
}

/// The position of `p95_mm` in a corpus row (after `input`, `pose`,
/// `topology`, `scan`, `status`, `parts` and `rms_mm`).
const P95_COLUMN: usize = 7;

/// Two corpus rows equal: words and counts exactly, numbers within the
/// sampler's noise. A model turned and turned back differs from the
/// other in its last bits; where that moves one skin triangle across the
/// inside test, every later area sample moves, and the distances change
/// in their fourth digit (body_033: 1.3819 against 1.3815 mm). A scan's
/// fit to its points labels each point with its nearest part: a point on
/// a tie or a junction's bound goes either way under rounding, so a
/// scan's numbers agree within 0.5 % (body_004_scan: RMS 1.5556 against
/// 1.5545 mm), the bar for a turned scan, and its shares within a
/// tenth of a percentage point (far 0.95 against 1.00 %). Its p95, a
/// quantile, within 1.5 %: a scan's fingers are digits of few points
/// each, and a point on a link's bound moves a fingertip (body_004_scan:
/// 2.2840 against 2.2608 mm).
fn same_row(a: &[String], b: &[String]) {
    assert_eq!(a.len(), b.len());
    let scan = a.get(3).is_some_and(|s| s == "true");
    let (relative, absolute) = if scan { (5e-3, 1e-3) } else { (2e-3, 1e-4) };
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        let relative = if scan && i == P95_COLUMN {
            1.5e-2
        } else {
            relative
        };
        match (x.parse::<f64>(), y.parse::<f64>()) {
            (Ok(p), Ok(q)) if x.contains('.') => assert!(
                (p - q).abs() <= relative * p.abs().max(q.abs()) + absolute,
                "{a:?}\n{b:?}"
            ),
            _ => assert_eq!(x, y, "{a:?}\n{b:?}"),
        }
    }
}

/// A raised-arm scan turned 30° (seed 6): a loop of the head's run held
/// the raised arm beside it, and ending the run there (before the run's
/// watched end) lost the head (26 mm RMS); the head is kept (5.9 mm).
#[test]
fn a_turned_raised_arm_scan_keeps_its_head() {
    let Some(dir) = corpus() else {
        return;
    };
    let args = ["--only", "body_001_scan", "--turn-deg", "30", "--seed", "6"];
    let args = [&args[..], &["--pictures", "0", "--samples", "20000"]].concat();
    let csv = run_corpus(&dir, &out_dir("turned-raised"), &args);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rms: f64 = row[col("rms_mm")].parse().unwrap();
    assert_eq!(row[col("parts")], "8", "{csv}");
    assert!(rms < 8.0, "{csv}");
}

/// body_027's upper arms lie pressed to the torso. Given its exact up axis
/// (`--given-up`), the left arm's first built section faces the body's
/// front, and the torso's loops stopped at that section's plane left
/// nothing of the torso above the waist: every section there was skipped
/// and the model was 15.9 mm from the truth. A plane that leaves nothing
/// now leaves the loop whole beside that arm (9.1 mm; 4.8 mm with the up
/// axis found from the data, where the upper arms are missing too).
#[test]
fn a_given_up_axis_keeps_the_torso_beside_pressed_arms() {
    let Some(dir) = corpus() else {
        return;
    };
    let args = ["--only", "body_027", "--given-up", "--pictures", "0"];
    let csv = run_corpus(
        &dir,
        &out_dir("given-up-027"),
        &[&args[..], &["--samples", "20000"]].concat(),
    );
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rms: f64 = row[col("rms_mm")].parse().unwrap();
    assert!(rms < 11.0, "{csv}");
}
