//! `trigbody corpus`: reconstructs every body of a folder described by a
//! `manifest.json`, and judges each model's written closed skin (the default mesh) against the
//! ground truth (the body's mesh; for a scan, the mesh it was made from)
//! both ways, and its joint centres against the manifest's.
//!
//! The manifest is `{"bodies": [{"name", "file", "units", "up", "pose",
//! "topology", "landmarks": {"left_elbow": [x, y, z], ...}, "scan":
//! {"file"}?}]}`, landmarks in the file's own coordinates and units.

use crate::exit::bad;
use crate::output::write_file;
use anyhow::{Context, Result};
use clap::Args;
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use trigbody_core::internals::geom::rng::Rng;
use trigbody_core::internals::spatial::distance::{DistanceStats, MeshDistance};
use trigbody_core::{
    compare_surfaces, compare_surfaces_seen, reconstruct, CompareOptions, Mesh, ReconstructOptions,
    Rigid, SurfaceComparison, Units, Vec3,
};
use trigbody_io::model::{merge_pieces, Skin};
use trigbody_io::{read_geometry, Geometry, ReadOptions};
use trigbody_render::{render_mesh_values, RenderOptions, VertexValues, View};

#[derive(Debug, Args)]
pub struct CorpusArgs {
    /// The corpus folder (holding manifest.json and the files it names).
    pub dir: PathBuf,
    /// Where the table (results.md, results.csv) and the pictures of the
    /// worst inputs go.
    #[arg(short, long, default_value = "corpus-results")]
    pub out: PathBuf,
    /// Only these bodies (names from the manifest, comma-separated; a
    /// scan is `NAME_scan`).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// Meshes only, or scans only.
    #[arg(long, value_enum, default_value_t = Kinds::All)]
    pub kinds: Kinds,
    /// Pass the manifest's up axis to the reconstruction (default: found
    /// from the data, as a user without it would run it).
    #[arg(long)]
    pub given_up: bool,
    /// Frames each scan is reconstructed in, the model nearest the scan
    /// kept (as `reconstruct --scan-frames`).
    #[arg(long, default_value_t = ReconstructOptions::default().scan_frames,
          value_parser = crate::bounds::count_in(1usize, trigbody_core::MAX_SCAN_FRAMES))]
    pub scan_frames: usize,
    /// As `reconstruct --fit`.
    #[arg(long, value_enum, default_value_t = crate::cmd_reconstruct::FitFlag::Auto)]
    pub fit: crate::cmd_reconstruct::FitFlag,
    /// As `reconstruct --prune`.
    #[arg(long, default_value_t = ReconstructOptions::default().prune_tolerance,
          value_parser = crate::bounds::real_in(0.0, trigbody_core::MAX_PRUNE_TOLERANCE))]
    pub prune: f64,
    /// Samples on each surface for the distances.
    #[arg(long, default_value_t = 100_000)]
    pub samples: usize,
    /// Pictures of this many worst inputs (by symmetric RMS).
    #[arg(long, default_value_t = 5)]
    pub pictures: usize,
    /// The skin judged: the closed skin `reconstruct --mesh` writes by
    /// default, or the outer skin (each piece's triangles inside another
    /// left out; `whole` is every piece as tessellated).
    #[arg(long, value_enum, default_value_t = crate::cmd_mesh::SkinFlag::Closed)]
    pub skin: crate::cmd_mesh::SkinFlag,
    /// Move every input by this many millimetres (in a direction drawn
    /// from `--seed` and the input's name) and its model back before
    /// judging: a probe of how stable a reconstruction is under a change
    /// that should change nothing.
    #[arg(long, default_value_t = 0.0)]
    pub shift_mm: f64,
    /// Turn every input by this many degrees about an axis drawn from
    /// `--seed` and its name (with `--shift-mm`, then moved), its model
    /// turned back before judging.
    #[arg(long, default_value_t = 0.0)]
    pub turn_deg: f64,
    /// The seed of `--shift-mm`'s and `--turn-deg`'s directions.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Replace existing result files.
    #[arg(long)]
    pub force: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Kinds {
    All,
    Meshes,
    Scans,
}

/// One input to run: a body's mesh or its scan.
struct Case {
    name: String,
    input: PathBuf,
    truth: PathBuf,
    scan: bool,
    pose: String,
    topology: String,
    units: Units,
    up: Option<Vec3>,
    landmarks: Vec<(String, Vec3)>,
}

/// One input's outcome.
struct Outcome {
    case: Case,
    result: std::result::Result<Judged, String>,
    /// The reconstruction's wall time (what `reconstruct` without `--mesh`
    /// takes); for a failure, the time until it failed.
    seconds: f64,
}

struct Judged {
    cmp: SurfaceComparison,
    parameters: usize,
    parts: usize,
    /// Joint name, error in mm (None: not found).
    joints: Vec<(String, Option<f64>)>,
    up: Vec3,
    front: Vec3,
    /// The reconstruction's wall time (not the reading, skin or judging).
    seconds: f64,
}

pub fn run(args: CorpusArgs) -> Result<()> {
    if !(args.shift_mm.is_finite() && args.shift_mm >= 0.0) {
        return Err(bad(format!(
            "--shift-mm {}: must be a finite number of millimetres, 0 or more",
            args.shift_mm
        )));
    }
    if !(args.turn_deg.is_finite() && args.turn_deg.abs() <= 360.0) {
        return Err(bad(format!(
            "--turn-deg {}: must be a finite angle within ±360 degrees",
            args.turn_deg
        )));
    }
    let manifest_path = args.dir.join("manifest.json");
    let text = std::fs::read_to_string(&manifest_path)
        .map_err(|e| bad(format!("{}: {e}", manifest_path.display())))?;
    let manifest: Value = serde_json::from_str(&text)
        .map_err(|e| bad(format!("{}: {e}", manifest_path.display())))?;
    let cases =
        cases(&manifest, &args).map_err(|e| bad(format!("{}: {e}", manifest_path.display())))?;
    if cases.is_empty() {
        return Err(bad(format!(
            "{}: no body matches the selection",
            manifest_path.display()
        )));
    }
    let mut outcomes = Vec::new();
    // The worst skins so far (symmetric RMS, outcome, skin), for pictures:
    // only as many as are drawn are kept.
    let mut worst: Vec<(f64, usize, Mesh)> = Vec::new();
    for (k, case) in cases.into_iter().enumerate() {
        let started = std::time::Instant::now();
        let judged = judge(&case, &args);
        let seconds = match &judged {
            Ok((j, _)) => j.seconds,
            Err(_) => started.elapsed().as_secs_f64(),
        };
        let result = judged.map(|(j, skin)| {
            if args.pictures > 0 {
                worst.push((j.cmp.symmetric_rms, k, skin));
                worst.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
                worst.truncate(args.pictures);
            }
            j
        });
        let o = Outcome {
            case,
            result,
            seconds,
        };
        crate::exit::diag(format_args!("[{}] {}", k + 1, row_text(&o)));
        outcomes.push(o);
    }
    let mut md = markdown(&outcomes);
    if args.turn_deg != 0.0 || args.shift_mm != 0.0 {
        md.insert_str(
            0,
            &format!(
                "Every input turned {}° and moved {} mm (--seed {}: its own axis and direction), its model turned back before judging.\n\n",
                args.turn_deg, args.shift_mm, args.seed
            ),
        );
    }
    write_file(&args.out.join("results.md"), md.as_bytes(), &[], args.force)?;
    write_file(
        &args.out.join("results.csv"),
        csv(&outcomes).as_bytes(),
        &[],
        args.force,
    )?;
    pictures(&outcomes, &worst, &args)?;
    print!("{}", summary(&outcomes));
    Ok(())
}

fn cases(manifest: &Value, args: &CorpusArgs) -> std::result::Result<Vec<Case>, String> {
    let bodies = manifest["bodies"].as_array().ok_or("no \"bodies\" array")?;
    let mut out = Vec::new();
    for b in bodies {
        let name = b["name"].as_str().ok_or("a body without a \"name\"")?;
        let file = b["file"]
            .as_str()
            .ok_or_else(|| format!("{name}: no \"file\""))?;
        let units = b["units"]
            .as_str()
            .and_then(Units::from_symbol)
            .ok_or_else(|| format!("{name}: \"units\" must be m, cm or mm"))?;
        let up = vec3(&b["up"]).ok_or_else(|| format!("{name}: \"up\" must be [x, y, z]"))?;
        let mut landmarks = Vec::new();
        if let Some(map) = b["landmarks"].as_object() {
            for (k, v) in map {
                let p = vec3(v).ok_or_else(|| format!("{name}: landmark {k} must be [x, y, z]"))?;
                landmarks.push((k.clone(), p));
            }
        }
        let truth = args.dir.join(file);
        let base = Case {
            name: name.to_string(),
            input: truth.clone(),
            truth,
            scan: false,
            pose: b["pose"].as_str().unwrap_or("").to_string(),
            topology: b["topology"].as_str().unwrap_or("").to_string(),
            units,
            up: args.given_up.then_some(up),
            landmarks,
        };
        let scan = b["scan"]["file"].as_str().map(|f| Case {
            name: format!("{name}_scan"),
            input: args.dir.join(f),
            scan: true,
            truth: base.truth.clone(),
            pose: base.pose.clone(),
            topology: base.topology.clone(),
            landmarks: base.landmarks.clone(),
            ..base
        });
        let chosen = |c: &Case| {
            (args.only.is_empty() || args.only.contains(&c.name))
                && match args.kinds {
                    Kinds::All => true,
                    Kinds::Meshes => !c.scan,
                    Kinds::Scans => c.scan,
                }
        };
        if chosen(&base) {
            out.push(base);
        }
        if let Some(s) = scan.filter(|s| chosen(s)) {
            out.push(s);
        }
    }
    Ok(out)
}

fn vec3(v: &Value) -> Option<Vec3> {
    let a = v.as_array()?;
    if a.len() != 3 {
        return None;
    }
    let x: Vec<f64> = a.iter().filter_map(|c| c.as_f64()).collect();
    (x.len() == 3).then(|| Vec3::new(x[0], x[1], x[2]))
}

/// Reconstructs one input and judges the mesh a user gets (its closed skin).
/// The judgement and the skin it judged.
fn judge(case: &Case, args: &CorpusArgs) -> std::result::Result<(Judged, Mesh), String> {
    let read = |p: &Path| read_geometry(p, &ReadOptions::default()).map_err(|e| format!("{e:#}"));
    let geometry = read(&case.input)?;
    let truth = match read(&case.truth)? {
        Geometry::Mesh(m) => m,
        Geometry::Points(_) => {
            return Err(format!("{}: the truth is not a mesh", case.truth.display()))
        }
    };
    let mut options = ReconstructOptions {
        units: case.units,
        scan_frames: args.scan_frames,
        prune_tolerance: args.prune,
        ..ReconstructOptions::default()
    };
    let seen = match &geometry {
        Geometry::Points(c) => Some(c.positions.clone()),
        Geometry::Mesh(_) => None,
    };
    let shift = probe_motion(&case.name, args, case.units);
    // The manifest's up (--given-up) turns with the input.
    options.segment.up = case.up.map(|u| shift.map_or(u, |t| t.vector(u)));
    options.global_fit.mode = args.fit.mode();
    let geometry = match (geometry, &shift) {
        (g, None) => g,
        (Geometry::Mesh(m), Some(t)) => Geometry::Mesh(t.mesh(&m)),
        (Geometry::Points(c), Some(t)) => Geometry::Points(t.cloud(&c)),
    };
    let body = geometry.body();
    let started = std::time::Instant::now();
    let (mut model, mut report) = reconstruct(body, &options).map_err(|e| e.to_string())?;
    let seconds = started.elapsed().as_secs_f64();
    if let Some(t) = shift {
        let back = t.inverse();
        model = model.moved(&back).map_err(|e| e.to_string())?;
        for (_, p) in report.joints.iter_mut() {
            *p = back.point(*p);
        }
    }
    let skin = user_mesh(&model, args.skin)?;
    let mm = case.units.to_mm();
    let compare = CompareOptions {
        samples: args.samples,
        near: 5.0 / mm,
        far: 10.0 / mm,
    };
    // A scan's model is judged on the truth its scanner saw: truth within
    // 5 mm of a scan point (the points as read, before any probe motion).
    let cmp = match &seen {
        Some(points) => compare_surfaces_seen(&truth, &skin, points, SEEN_MM / mm, &compare),
        None => compare_surfaces(&truth, &skin, &compare),
    };
    let cmp = in_mm(cmp, mm);
    let joints = JOINTS
        .iter()
        .map(|&j| {
            let truth = case.landmarks.iter().find(|(n, _)| n == j).map(|(_, p)| *p);
            let found = report
                .joints
                .iter()
                .find(|(n, _)| n.as_str() == j)
                .map(|(_, p)| *p);
            let err = match (truth, found) {
                (Some(t), Some(f)) => Some(t.distance(f) * mm),
                _ => None,
            };
            (j.to_string(), err)
        })
        .collect();
    let judged = Judged {
        cmp,
        parameters: report.design_parameters,
        parts: report.parts_found.len(),
        joints,
        up: model.frame.up,
        front: model.frame.front,
        seconds,
    };
    Ok((judged, skin))
}

/// The joints checked against the manifest.
const JOINTS: [&str; 12] = [
    "left_shoulder",
    "right_shoulder",
    "left_elbow",
    "right_elbow",
    "left_wrist",
    "right_wrist",
    "left_hip",
    "right_hip",
    "left_knee",
    "right_knee",
    "left_ankle",
    "right_ankle",
];

/// A scan's truth counts where a scan point lies within this (mm).
const SEEN_MM: f64 = 5.0;

/// Joint errors above this (mm) fail.
const JOINT_LIMIT_MM: f64 = 30.0;

/// The motion `--turn-deg` and `--shift-mm` ask of one input (`None` for
/// neither): the axis and direction drawn from the seed and the input's
/// name, so every input moves its own way and a run can be repeated.
fn probe_motion(name: &str, args: &CorpusArgs, units: Units) -> Option<Rigid> {
    if args.shift_mm == 0.0 && args.turn_deg == 0.0 {
        return None;
    }
    // FNV-1a of the name, mixed with the seed.
    let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    let mut rng = Rng::new(hash ^ args.seed);
    let mut unit = || Vec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()).normalized();
    let (k, d) = (unit()?, unit()?);
    // Rodrigues for R^T, the turn by `-turn_deg` about `k`: the rows of
    // the turn R are R^T e_i, and `into_axes` moves its origin to zero, so
    // the origin `-R^T t` ends at the shift `t`.
    let (sn, cs) = args.turn_deg.to_radians().sin_cos();
    let inverse = |v: Vec3| v * cs - k.cross(v) * sn + k * (k.dot(v) * (1.0 - cs));
    let to = d * (args.shift_mm / units.to_mm());
    Rigid::into_axes(-inverse(to), inverse(Vec3::X), inverse(Vec3::Y))
}

/// The skin `reconstruct --mesh M --skin S` writes (by default the one
/// closed skin, the mesh a user gets).
fn user_mesh(
    model: &trigbody_core::Body,
    skin: crate::cmd_mesh::SkinFlag,
) -> std::result::Result<Mesh, String> {
    Ok(merge_pieces(&crate::cmd_reconstruct::mesh_pieces(
        model,
        Skin::from(skin),
    )?))
}

fn in_mm(c: SurfaceComparison, mm: f64) -> SurfaceComparison {
    let s = |d: DistanceStats| DistanceStats {
        rms: d.rms * mm,
        mean: d.mean * mm,
        p95: d.p95 * mm,
        max: d.max * mm,
        ..d
    };
    SurfaceComparison {
        truth_to_model: s(c.truth_to_model),
        model_to_truth: s(c.model_to_truth),
        symmetric_rms: c.symmetric_rms * mm,
        p95: c.p95 * mm,
        ..c
    }
}

/// The targets: (rms, p95, truth near, model near, model far).
fn targets(scan: bool) -> (f64, f64, f64, f64, f64) {
    if scan {
        (2.5, 5.0, 0.97, 0.97, 0.01)
    } else {
        (2.5, 6.0, 0.98, 0.98, 0.005)
    }
}

fn worst_joint(j: &Judged) -> Option<(String, f64)> {
    j.joints
        .iter()
        .filter_map(|(n, e)| e.map(|e| (n.clone(), e)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// Which targets one outcome misses (empty: all met).
fn misses(o: &Outcome) -> Vec<&'static str> {
    let Ok(j) = &o.result else {
        return vec!["failed"];
    };
    let (rms, p95, tn, mn, far) = targets(o.case.scan);
    let c = &j.cmp;
    let mut m = Vec::new();
    if j.parts < 8 {
        m.push("parts");
    }
    if c.symmetric_rms > rms {
        m.push("rms");
    }
    if c.p95 > p95 {
        m.push("p95");
    }
    if c.truth_near < tn {
        m.push("input covered");
    }
    if c.model_near < mn {
        m.push("model near");
    }
    if c.model_far > far {
        m.push("far area");
    }
    if j.joints
        .iter()
        .any(|(_, e)| e.is_none_or(|e| e > JOINT_LIMIT_MM))
    {
        m.push("joints");
    }
    m
}

fn row_text(o: &Outcome) -> String {
    match &o.result {
        Ok(j) => {
            let (wn, we) = worst_joint(j).unwrap_or(("-".into(), f64::NAN));
            format!(
                "{} ({}, {}): rms {:.2} mm, p95 {:.2} mm, input covered {:.1} %, model near {:.1} %, far {:.2} %{}, worst joint {wn} {we:.0} mm, {:.1} s{}",
                o.case.name,
                o.case.pose,
                o.case.topology,
                j.cmp.symmetric_rms,
                j.cmp.p95,
                100.0 * j.cmp.truth_near,
                100.0 * j.cmp.model_near,
                100.0 * j.cmp.model_far,
                if o.case.scan {
                    format!(", unseen truth {:.1} %", 100.0 * j.cmp.truth_unseen)
                } else {
                    String::new()
                },
                o.seconds,
                match misses(o).as_slice() {
                    [] => String::new(),
                    m => format!("; misses: {}", m.join(", ")),
                }
            )
        }
        Err(e) => format!("{} ({}): FAILED: {e}", o.case.name, o.case.pose),
    }
}

fn markdown(outcomes: &[Outcome]) -> String {
    let mut s = String::new();
    s.push_str(&summary(outcomes));
    s.push_str("\n| input | pose | topology | parts | rms mm | p95 mm | input covered % | model near % | far % | unseen % | worst joint (mm) | params | s | misses |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for o in outcomes {
        match &o.result {
            Ok(j) => {
                let (wn, we) = worst_joint(j).unwrap_or(("-".into(), f64::NAN));
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {:.2} | {:.2} | {:.1} | {:.1} | {:.2} | {:.1} | {wn} {we:.0} | {} | {:.1} | {} |",
                    o.case.name,
                    o.case.pose,
                    o.case.topology,
                    j.parts,
                    j.cmp.symmetric_rms,
                    j.cmp.p95,
                    100.0 * j.cmp.truth_near,
                    100.0 * j.cmp.model_near,
                    100.0 * j.cmp.model_far,
                    100.0 * j.cmp.truth_unseen,
                    j.parameters,
                    o.seconds,
                    misses(o).join(", ")
                );
            }
            Err(e) => {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | - | - | - | - | - | - | - | - | - | {:.1} | failed: {} |",
                    o.case.name,
                    o.case.pose,
                    o.case.topology,
                    o.seconds,
                    e.replace('|', "/")
                );
            }
        }
    }
    s
}

fn csv(outcomes: &[Outcome]) -> String {
    let mut s = String::from("input,pose,topology,scan,status,parts,rms_mm,p95_mm,input_covered,model_near,model_far,unseen_truth,design_parameters,seconds");
    for j in JOINTS {
        let _ = write!(s, ",{j}_mm");
    }
    s.push_str(",error\n");
    for o in outcomes {
        let c = &o.case;
        let _ = write!(s, "{},{},{},{}", c.name, c.pose, c.topology, c.scan);
        match &o.result {
            Ok(j) => {
                let _ = write!(
                    s,
                    ",{},{},{:.4},{:.4},{:.5},{:.5},{:.5},{:.5},{},{:.3}",
                    if misses(o).is_empty() { "pass" } else { "miss" },
                    j.parts,
                    j.cmp.symmetric_rms,
                    j.cmp.p95,
                    j.cmp.truth_near,
                    j.cmp.model_near,
                    j.cmp.model_far,
                    j.cmp.truth_unseen,
                    j.parameters,
                    o.seconds
                );
                for (_, e) in &j.joints {
                    match e {
                        Some(e) => {
                            let _ = write!(s, ",{e:.1}");
                        }
                        None => s.push(','),
                    }
                }
                s.push_str(",\n");
            }
            Err(e) => {
                let _ = write!(s, ",failed,,,,,,,,,{:.3}", o.seconds);
                s.push_str(&",".repeat(JOINTS.len()));
                let _ = writeln!(s, ",\"{}\"", e.replace('"', "'"));
            }
        }
    }
    s
}

/// The median (NaN for none: a column with nothing measured).
fn median(v: Vec<f64>) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        crate::cmd_render::percentile(&v, 0.5)
    }
}

fn summary(outcomes: &[Outcome]) -> String {
    let mut s = String::new();
    for (label, scan) in [("meshes", false), ("scans", true)] {
        let of: Vec<&Outcome> = outcomes.iter().filter(|o| o.case.scan == scan).collect();
        if of.is_empty() {
            continue;
        }
        let ok: Vec<&Judged> = of.iter().filter_map(|o| o.result.as_ref().ok()).collect();
        let pass = of.iter().filter(|o| misses(o).is_empty()).count();
        let joints_ok = ok
            .iter()
            .filter(|j| {
                j.joints
                    .iter()
                    .all(|(_, e)| e.is_some_and(|e| e <= JOINT_LIMIT_MM))
            })
            .count();
        let _ = writeln!(
            s,
            "{label}: {pass} of {} meet every target; {} reconstructed, {} failed; median rms {:.2} mm, median p95 {:.2} mm; all joints within {JOINT_LIMIT_MM:.0} mm on {joints_ok}",
            of.len(),
            ok.len(),
            of.len() - ok.len(),
            median(ok.iter().map(|j| j.cmp.symmetric_rms).collect()),
            median(ok.iter().map(|j| j.cmp.p95).collect()),
        );
        let per_joint: Vec<String> = JOINTS
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let errs: Vec<f64> = ok.iter().filter_map(|j| j.joints[k].1).collect();
                format!("{name} {:.0}", median(errs))
            })
            .collect();
        let _ = writeln!(s, "  median joint errors (mm): {}", per_joint.join(", "));
    }
    s
}

/// The worst inputs' closed skins (`worst`, worst first) coloured by their
/// distance to the truth, front, side and back, one picture each.
fn pictures(outcomes: &[Outcome], worst: &[(f64, usize, Mesh)], args: &CorpusArgs) -> Result<()> {
    for (k, (_, index, skin)) in worst.iter().enumerate() {
        let o = &outcomes[*index];
        let Ok(j) = &o.result else { continue };
        let truth = trigbody_io::read_mesh(&o.case.truth, &ReadOptions::default()).map_err(bad)?;
        let mm = o.case.units.to_mm();
        let skin_mm: Vec<f64> = MeshDistance::new(&truth)
            .distances(&skin.positions)
            .into_iter()
            .map(|d| d * mm)
            .collect();
        let options = RenderOptions {
            width: 512,
            height: 512,
            views: vec![View::front(), View::side(), View::back()],
            up: j.up,
            front: j.front,
            ..RenderOptions::default()
        };
        let values = VertexValues::new(&skin_mm, (0.0, 20.0), "distance to the truth (mm)");
        let render = render_mesh_values(skin, &values, &options)
            .with_context(|| format!("rendering {}", o.case.name))?;
        let png = render.image.to_png()?;
        let path = args
            .out
            .join(format!("worst-{}-{}.png", k + 1, o.case.name));
        write_file(&path, &png, &[], args.force)?;
    }
    Ok(())
}
