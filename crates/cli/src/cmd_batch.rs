//! `trigbody batch INPUTS… -o OUTDIR`: reconstructs every body of a dataset
//! in parallel and writes, per input, `OUTDIR/NAME.json` (the model),
//! `OUTDIR/NAME.report.json` (the report) and with `--mesh EXT`
//! `OUTDIR/NAME.EXT`, where NAME is the input's file stem; then
//! `OUTDIR/summary.jsonl` and `OUTDIR/summary.csv`, one row per input.
//!
//! * An input is a file, a folder (its mesh and scan files, not recursive)
//!   or a glob pattern (`*`, `?`, `[…]`, `**` for any depth); or each row
//!   of a `--manifest` CSV, with options of its own (`batch_manifest.rs`).
//! * Each input is checked by the library before it is modelled (its unit,
//!   one body): a row fails with the message `reconstruct` gives.
//! * A failing input (unreadable, no body, a panic) is a row with its error,
//!   never the end of the run. Exit 0 when every input is done, 2 when some
//!   failed on bad input, 1 when one failed internally.
//! * `--resume` skips an input whose outputs all exist (each is written to
//!   a temporary file and renamed, so one that exists is complete) and
//!   replaces the leftovers of an input that stopped half way.

use crate::batch_manifest::{read_manifest, Overrides};
use crate::cmd_mesh::SkinFlag;
use crate::cmd_reconstruct::{write_outputs, BodyFlags, Outputs};
use crate::exit::{bad, code_of, print};
use crate::progress::ProgressBar;
use anyhow::Result;
use clap::{Args, ValueEnum};
use serde::Serialize;
use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;
use trigbody_core::{reconstruct, Progress, ReconstructOptions};
use trigbody_io::{read_geometry, Format, ReadOptions};

/// The mesh `--mesh` writes beside each model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MeshExt {
    Glb,
    Obj,
    Ply,
    Stl,
}

/// Arguments of `trigbody batch`.
#[derive(Debug, Args)]
pub struct BatchArgs {
    /// Meshes (.obj, .ply, .stl) and scans (.ply points, .xyz): files,
    /// folders (their mesh and scan files) or glob patterns ("scans/**/*.ply").
    #[arg(required_unless_present = "manifest", value_name = "INPUTS")]
    pub inputs: Vec<String>,
    /// A CSV of the inputs with options of their own: columns `path`
    /// (relative to the manifest's folder) and optionally `units` (m, cm,
    /// mm, auto), `up` and `front`; an empty cell takes the command line's.
    #[arg(long, value_name = "CSV", conflicts_with = "inputs")]
    pub manifest: Option<PathBuf>,
    /// The folder to write into (created when missing).
    #[arg(short, long, value_name = "OUTDIR")]
    pub output: PathBuf,
    /// Also write each model's mesh, in this format.
    #[arg(long, value_enum)]
    pub mesh: Option<MeshExt>,
    /// The surface `--mesh` writes: every piece whole, or the outer skin.
    #[arg(long, value_enum, default_value_t = SkinFlag::Whole)]
    pub skin: SkinFlag,
    /// Bodies reconstructed at once (default: the cores available).
    #[arg(short, long)]
    pub jobs: Option<usize>,
    /// Skip inputs whose outputs are all there.
    #[arg(long)]
    pub resume: bool,
    /// Replace existing outputs.
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub body: BodyFlags,
}

/// One input's row of the summary.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub input: String,
    /// `ok`, `failed` or `skipped` (done by an earlier run, `--resume`).
    pub status: &'static str,
    pub error: Option<String>,
    /// Exit code class of the failure: 2 bad input, 1 internal.
    #[serde(skip)]
    pub code: u8,
    /// The unit used: given, or inferred (`--units auto`); what was asked
    /// for when the input failed before its unit was known.
    pub units: String,
    pub seconds: Option<f64>,
    pub parts: Option<usize>,
    pub design_parameters: Option<u64>,
    pub input_vertices: Option<u64>,
    pub parameter_ratio: Option<f64>,
    pub rms_mm: Option<f64>,
    pub p95_mm: Option<f64>,
    pub max_mm: Option<f64>,
    pub coverage: Option<f64>,
    pub visible_coverage: Option<f64>,
    pub model: String,
    pub report: String,
    pub mesh: Option<String>,
}

/// The output files of one input.
#[derive(Debug, Clone)]
struct Job {
    input: PathBuf,
    /// Options of this input's own (`--manifest`).
    overrides: Overrides,
    model: PathBuf,
    report: PathBuf,
    mesh: Option<PathBuf>,
}

impl Job {
    fn done(&self) -> bool {
        self.model.is_file()
            && self.report.is_file()
            && self.mesh.as_ref().is_none_or(|m| m.is_file())
    }
}

/// Whether `path` is a file batch reads from a folder: a mesh or scan
/// format, not a hidden file.
fn is_input_file(path: &Path) -> bool {
    let hidden = path
        .file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with('.'));
    path.is_file() && !hidden && Format::from_path(path).is_some()
}

/// The input files named by `inputs`, sorted and without repeats, less
/// the summaries batch writes in `outdir` (a CSV reads as points). A name
/// that is neither a file, a folder nor a pattern matching something is
/// kept: its row says why it cannot be read.
pub fn expand_inputs(inputs: &[String], outdir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for s in inputs {
        let path = Path::new(s);
        if path.is_dir() {
            let entries =
                std::fs::read_dir(path).map_err(|e| bad(format!("{}: {e}", path.display())))?;
            for entry in entries {
                let p = entry
                    .map_err(|e| bad(format!("{}: {e}", path.display())))?
                    .path();
                if is_input_file(&p) {
                    files.push(p);
                }
            }
        } else if !path.exists() && s.contains(['*', '?', '[']) {
            let matches = glob::glob(s).map_err(|e| bad(format!("{s}: not a pattern: {e}")))?;
            let before = files.len();
            for m in matches {
                let p = m.map_err(|e| bad(format!("{s}: {e}")))?;
                if is_input_file(&p) {
                    files.push(p);
                }
            }
            if files.len() == before {
                return Err(bad(format!("{s}: no mesh or scan file matches")));
            }
        } else {
            files.push(path.to_path_buf());
        }
    }
    let summaries: Vec<PathBuf> = ["summary.csv", "summary.jsonl"]
        .iter()
        .filter_map(|n| outdir.join(n).canonicalize().ok())
        .collect();
    files.retain(|f| !f.canonicalize().is_ok_and(|c| summaries.contains(&c)));
    files.sort();
    files.dedup();
    Ok(files)
}

/// The jobs of `files` in `outdir`; two inputs whose outputs would share a
/// name (the same stem in two folders or formats) are refused.
fn jobs(
    files: Vec<(PathBuf, Overrides)>,
    outdir: &Path,
    mesh: Option<MeshExt>,
) -> Result<Vec<Job>> {
    let mut owner: HashMap<PathBuf, PathBuf> = HashMap::new();
    let mut jobs = Vec::with_capacity(files.len());
    for (input, overrides) in files {
        let stem = input
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "body".to_string());
        let ext = mesh.map(|m| m.to_possible_value().map(|v| v.get_name().to_string()));
        let job = Job {
            model: outdir.join(format!("{stem}.json")),
            report: outdir.join(format!("{stem}.report.json")),
            mesh: ext.flatten().map(|e| outdir.join(format!("{stem}.{e}"))),
            input,
            overrides,
        };
        for out in [Some(&job.model), Some(&job.report), job.mesh.as_ref()]
            .into_iter()
            .flatten()
        {
            if let Some(other) = owner.insert(out.clone(), job.input.clone()) {
                return Err(bad(format!(
                    "{} and {} would both write {}; give inputs with distinct file names",
                    other.display(),
                    job.input.display(),
                    out.display()
                )));
            }
        }
        jobs.push(job);
    }
    Ok(jobs)
}

fn number(v: &Value, path: &[&str]) -> Option<f64> {
    path.iter().try_fold(v, |v, k| v.get(k))?.as_f64()
}

/// A row from a report's JSON (as written by `write_outputs`).
fn fill_from_report(row: &mut Row, report: &Value) {
    let int = |k: &str| report.get(k).and_then(Value::as_u64);
    row.parts = report
        .get("parts")
        .and_then(Value::as_array)
        .map(|p| p.len());
    row.design_parameters = int("design_parameters");
    row.input_vertices = int("input_vertices");
    row.parameter_ratio = number(report, &["parameter_ratio"]);
    row.rms_mm = number(report, &["distance_mm", "rms"]);
    row.p95_mm = number(report, &["distance_mm", "p95"]);
    row.max_mm = number(report, &["distance_mm", "max"]);
    row.coverage = number(report, &["coverage"]);
    row.visible_coverage = number(report, &["visible_coverage"]);
    if let Some(u) = report.get("units").and_then(Value::as_str) {
        row.units = u.to_string();
    }
}

fn empty_row(job: &Job, units: &str, status: &'static str) -> Row {
    Row {
        input: job.input.display().to_string(),
        status,
        error: None,
        code: 0,
        units: units.to_string(),
        seconds: None,
        parts: None,
        design_parameters: None,
        input_vertices: None,
        parameter_ratio: None,
        rms_mm: None,
        p95_mm: None,
        max_mm: None,
        coverage: None,
        visible_coverage: None,
        model: job.model.display().to_string(),
        report: job.report.display().to_string(),
        mesh: job.mesh.as_ref().map(|m| m.display().to_string()),
    }
}

/// Reads, reconstructs and writes one input.
fn process(job: &Job, options: &ReconstructOptions, args: &BatchArgs) -> Result<Value> {
    let name = job.input.display().to_string();
    let geometry = read_geometry(&job.input, &ReadOptions::default()).map_err(bad)?;
    let body = geometry.body();
    let (model, report) = reconstruct(body, options).map_err(|e| bad(format!("{name}: {e}")))?;
    let outputs = Outputs {
        model: Some(&job.model),
        report: Some(&job.report),
        mesh: job.mesh.as_deref(),
        skin: args.skin,
        // `--resume` reaches here only for an input not complete: what is
        // there is the leftover of an interrupted run.
        force: args.force || args.resume,
        quantum_mm: None,
    };
    write_outputs(&name, &model, &report, &outputs, &[&job.input])?;
    Ok(trigbody_io::body_file::report_json(&report))
}

/// The row of one input, its failure (an error or a panic) included.
fn run_one(job: &Job, options: &ReconstructOptions, args: &BatchArgs) -> Row {
    let options = &job.overrides.apply(options);
    let units = match options.infer_units {
        true => "auto",
        false => options.units.symbol(),
    };
    if args.resume && job.done() {
        let mut row = empty_row(job, units, "skipped");
        if let Some(report) = std::fs::read(&job.report)
            .ok()
            .and_then(|b| serde_json::from_slice::<Value>(&b).ok())
        {
            fill_from_report(&mut row, &report);
        }
        return row;
    }
    let started = Instant::now();
    let result =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| process(job, options, args)));
    let mut row = empty_row(job, units, "ok");
    row.seconds = Some(started.elapsed().as_secs_f64());
    match result {
        Ok(Ok(report)) => fill_from_report(&mut row, &report),
        Ok(Err(e)) => {
            row.status = "failed";
            row.error = Some(format!("{e:#}"));
            row.code = code_of(&e);
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown".to_string());
            row.status = "failed";
            row.error = Some(format!("internal error (a panic: {what})"));
            row.code = 1;
        }
    }
    row
}

/// A CSV field, quoted when it needs to be.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The columns of `summary.csv`, in order (the fields of [`Row`]).
const COLUMNS: [&str; 17] = [
    "input",
    "status",
    "error",
    "units",
    "seconds",
    "parts",
    "design_parameters",
    "input_vertices",
    "parameter_ratio",
    "rms_mm",
    "p95_mm",
    "max_mm",
    "coverage",
    "visible_coverage",
    "model",
    "report",
    "mesh",
];

/// The summary as CSV: a header, then one line per row (empty fields for
/// what a row does not have).
pub fn summary_csv(rows: &[Row]) -> String {
    let columns = &COLUMNS;
    let mut out = columns.join(",") + "\n";
    for row in rows {
        let fields = serde_json::to_value(row).unwrap_or_default();
        let cells: Vec<String> = columns
            .iter()
            .map(|k| match fields.get(k) {
                None | Some(Value::Null) => String::new(),
                Some(Value::String(s)) => csv_field(s),
                Some(other) => other.to_string(),
            })
            .collect();
        out += &(cells.join(",") + "\n");
    }
    out
}

/// The progress line's step: failures so far, the time left, the input.
fn stage(done: usize, total: usize, failed: usize, started: Instant, last: &str) -> String {
    let eta = match done {
        0 => "ETA -".to_string(),
        _ => {
            let per = started.elapsed().as_secs_f64() / done as f64;
            format!("ETA {:.0} s", per * (total - done) as f64)
        }
    };
    format!("{failed} failed  {eta}  {last}")
}

pub fn run(args: BatchArgs) -> Result<()> {
    let jobs_n = match args.jobs {
        Some(0) => return Err(bad("--jobs must be at least 1")),
        Some(n) => n,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let files = match &args.manifest {
        Some(m) => read_manifest(m)?,
        None => expand_inputs(&args.inputs, &args.output)?
            .into_iter()
            .map(|f| (f, Overrides::default()))
            .collect(),
    };
    let jobs = jobs(files, &args.output, args.mesh)?;
    std::fs::create_dir_all(&args.output)
        .map_err(|e| bad(format!("{}: {e}", args.output.display())))?;
    let options = args.body.options();
    let total = jobs.len();
    let started = Instant::now();
    let next = AtomicUsize::new(0);
    let rows: Mutex<Vec<Option<Row>>> = Mutex::new(vec![None; total]);
    let bar = Mutex::new((ProgressBar::new("batch"), 0usize, 0usize));
    std::thread::scope(|s| {
        for _ in 0..jobs_n.min(total) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(job) = jobs.get(i) else { break };
                let row = run_one(job, &options, &args);
                let mut b = bar.lock().unwrap_or_else(|e| e.into_inner());
                b.1 += 1;
                b.2 += usize::from(row.status == "failed");
                let line = stage(b.1, total, b.2, started, &row.input);
                let done = b.1;
                b.0.update(Progress {
                    stage: &line,
                    done,
                    total,
                });
                rows.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(row);
            });
        }
    });
    bar.into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .0
        .finish();
    let rows: Vec<Row> = rows
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .flatten()
        .collect();
    write_summary(&args.output, &rows)?;
    let mut text = String::new();
    for r in &rows {
        match (&r.error, r.seconds) {
            // Most errors name the input already.
            (Some(e), _) if e.starts_with(&r.input) => text += &format!("failed   {e}\n"),
            (Some(e), _) => text += &format!("failed   {}: {e}\n", r.input),
            (None, Some(t)) => {
                text += &format!(
                    "ok       {} in {t:.2} s, rms {:.2} mm\n",
                    r.input,
                    r.rms_mm.unwrap_or(f64::NAN)
                )
            }
            (None, None) => text += &format!("skipped  {} (done before)\n", r.input),
        }
    }
    let failed: Vec<&Row> = rows.iter().filter(|r| r.status == "failed").collect();
    let skipped = rows.iter().filter(|r| r.status == "skipped").count();
    text += &format!(
        "{} inputs: {} done, {skipped} skipped, {} failed, in {:.1} s on {jobs_n} jobs; summary in {}\n",
        rows.len(),
        rows.len() - skipped - failed.len(),
        failed.len(),
        started.elapsed().as_secs_f64(),
        args.output.join("summary.csv").display()
    );
    print(&text)?;
    match failed.iter().map(|r| r.code).max() {
        None => Ok(()),
        Some(code) => {
            let msg = format!("{} of {} inputs failed", failed.len(), rows.len());
            if code == 2 {
                Err(bad(msg))
            } else {
                Err(anyhow::anyhow!(msg))
            }
        }
    }
}

/// Writes `summary.jsonl` and `summary.csv` in `outdir` (the run's own
/// files: replaced by every run).
fn write_summary(outdir: &Path, rows: &[Row]) -> Result<()> {
    let mut jsonl = String::new();
    for r in rows {
        jsonl += &serde_json::to_string(r)?;
        jsonl.push('\n');
    }
    for (name, text) in [("summary.jsonl", jsonl), ("summary.csv", summary_csv(rows))] {
        crate::output::write_file(&outdir.join(name), text.as_bytes(), &[], true)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_quotes_what_needs_it() {
        assert_eq!(csv_field("a.ply"), "a.ply");
        assert_eq!(csv_field("x: 1, 2"), "\"x: 1, 2\"");
        assert_eq!(csv_field("say \"no\""), "\"say \"\"no\"\"\"");
    }

    #[test]
    fn csv_has_every_field_of_a_row() {
        let job = Job {
            input: PathBuf::from("a, b.ply"),
            model: PathBuf::from("o/a.json"),
            report: PathBuf::from("o/a.report.json"),
            mesh: None,
            overrides: Overrides::default(),
        };
        let row = empty_row(&job, "m", "ok");
        let Value::Object(fields) = serde_json::to_value(&row).unwrap() else {
            panic!("a row is an object")
        };
        let mut keys: Vec<&str> = fields.keys().map(|k| k.as_str()).collect();
        let mut columns = COLUMNS.to_vec();
        keys.sort();
        columns.sort();
        assert_eq!(keys, columns);
        let csv = summary_csv(&[row]);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[0].split(',').count(), COLUMNS.len());
        assert!(lines[1].starts_with("\"a, b.ply\",ok,,m,"), "{}", lines[1]);
    }

    #[test]
    fn same_stem_twice_is_refused() {
        let files = vec![
            (PathBuf::from("a/body.obj"), Overrides::default()),
            (PathBuf::from("b/body.ply"), Overrides::default()),
        ];
        let e = jobs(files, Path::new("out"), None).unwrap_err();
        assert_eq!(code_of(&e), 2);
        assert!(e.to_string().contains("would both write"), "{e}");
    }

    #[test]
    fn a_folder_gives_its_meshes_and_scans_not_the_summaries() {
        let d = std::env::temp_dir().join(format!("trigbody-batch-expand-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        for f in [
            "b.obj",
            "a.xyz",
            "summary.csv",
            "notes.md",
            ".hidden.ply",
            "m.json",
        ] {
            std::fs::write(d.join(f), "").unwrap();
        }
        let got = expand_inputs(&[d.display().to_string()], &d).unwrap();
        let names: Vec<_> = got
            .iter()
            .map(|p| p.file_name().unwrap().to_owned())
            .collect();
        assert_eq!(names, ["a.xyz", "b.obj"]);
        // Elsewhere, a summary.csv is an input like any other.
        let got = expand_inputs(&[d.display().to_string()], Path::new("other")).unwrap();
        assert_eq!(got.len(), 3);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn eta_follows_the_rate() {
        let t = Instant::now() - std::time::Duration::from_secs(10);
        let s = stage(5, 10, 1, t, "x.ply");
        assert!(s.starts_with("1 failed  ETA 10 s"), "{s}");
        assert!(stage(0, 10, 0, Instant::now(), "").contains("ETA -"));
    }
}
