//! `trigbody reconstruct [INPUT] [-o MODEL.json] [--mesh OUT] [--report R.json]`:
//! a body model from a mesh or a scan (the built-in body without INPUT),
//! with a report of its size and its distance to the input.

use crate::cmd_fit::parse_vec3;
use crate::exit::{bad, print};
use crate::output::{output_extension, refuse_input, refuse_repeated_outputs, write_file};
use crate::progress::ProgressBar;
use anyhow::Result;
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};
use trigbody_core::internals::body::rate::{reconstruct_for, Goal, RateOptions, RateOutcome};
use trigbody_core::FitMode;
use trigbody_core::{reconstruct_with_progress, Body, Progress, ReconstructOptions, Report, Units};
use trigbody_core::{Real, TessellationOptions, Vec3};
use trigbody_io::body_file::{model_of_body, part_file_name, report_json, report_part_names};
use trigbody_io::gltf::{glb_bytes, NamedMesh};
use trigbody_io::model::{merge_pieces, skin_pieces, write_model};
use trigbody_io::tbm::{encode_tbm, TbmOptions};
use trigbody_io::{read_bytes, write_mesh_as, Format, ReadOptions, WriteOptions};

/// The built-in body (CC0 MakeHuman average young male, metres; see
/// `data/bodies/README.md`).
const BUILT_IN_BODY: &[u8] = include_bytes!("../../../data/bodies/mh_male.obj");

/// Units of the input's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum UnitsFlag {
    M,
    Cm,
    Mm,
    /// The one of m, cm and mm that makes the input a human height
    /// (0.4-2.6 m); refused, naming the candidates, when none or several do.
    Auto,
}

impl UnitsFlag {
    /// The library's unit, `None` for `auto`.
    pub fn units(self) -> Option<Units> {
        match self {
            UnitsFlag::M => Some(Units::Metres),
            UnitsFlag::Cm => Some(Units::Centimetres),
            UnitsFlag::Mm => Some(Units::Millimetres),
            UnitsFlag::Auto => None,
        }
    }
}

/// Which inputs the parts are fitted to, point by point, after they are
/// built.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FitFlag {
    /// Scans (their slab sections carry the scanner's noise); a mesh's
    /// sections are exact cuts already.
    Auto,
    /// Meshes and scans.
    Global,
    /// Neither: the parts as their sections give them.
    None,
}

impl FitFlag {
    /// The library's mode for the flag.
    pub fn mode(self) -> FitMode {
        match self {
            FitFlag::Auto => FitMode::Scans,
            FitFlag::Global => FitMode::All,
            FitFlag::None => FitMode::Off,
        }
    }
}

/// Arguments of `trigbody reconstruct`.
#[derive(Debug, Args)]
pub struct ReconstructArgs {
    /// A body mesh (.obj, .ply, .stl) or scan (.ply points, .xyz); without
    /// it, the built-in body.
    pub input: Option<PathBuf>,
    /// The model file to write: JSON (model format version 5), or the
    /// compact binary model for a `.tbm` name (docs/model-format.md).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// A mesh of the model's surface: .glb, .obj, .ply, .stl (one closed
    /// surface by default; with --skin whole or outer, a .glb has one node
    /// per part).
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// The surface `--mesh` writes: one closed surface (the union of the
    /// pieces), every piece whole, or only the model's outer skin (each
    /// piece's triangles inside another piece left out).
    #[arg(long, value_enum, default_value_t = crate::cmd_mesh::SkinFlag::Closed)]
    pub skin: crate::cmd_mesh::SkinFlag,
    /// The report as JSON.
    #[arg(long)]
    pub report: Option<PathBuf>,
    #[command(flatten)]
    pub body: BodyFlags,
    /// Choose the spacing and tolerances (--spacing, --ea, --em scaled
    /// together, then --ea, --em alone) for the smallest model within this
    /// symmetric RMS distance to the input, in mm: a search over
    /// reconstructions (docs/compactness.md).
    #[arg(long, conflicts_with = "max_parameters")]
    pub target_rms: Option<Real>,
    /// The same for the most accurate model of at most N design parameters.
    #[arg(long)]
    pub max_parameters: Option<usize>,
    /// Quantization step in mm of a `.tbm` model file's coefficients and
    /// planes (default 0.00002 × the body's height, 0.035 mm on 1.73 m).
    #[arg(long)]
    pub quantum: Option<Real>,
    /// Replace existing output files.
    #[arg(long)]
    pub force: bool,
}

/// The flags that say how to read and reconstruct a body, shared by
/// `reconstruct` and `batch`.
#[derive(Debug, Clone, Args)]
pub struct BodyFlags {
    /// The up direction: x, y, z, -x, -y, -z or a vector x,y,z (default: found from the data).
    #[arg(long, value_parser = parse_direction, allow_hyphen_values = true)]
    pub up_axis: Option<Vec3>,
    /// The direction the body faces (same forms; default: found from the feet).
    #[arg(long, value_parser = parse_direction, allow_hyphen_values = true)]
    pub front: Option<Vec3>,
    /// The unit of the input's coordinates (distances are reported in mm);
    /// `auto` infers it from the body's extent and the report says which.
    #[arg(long, value_enum, default_value_t = UnitsFlag::M)]
    pub units: UnitsFlag,
    /// Section spacing along each part, as a fraction of the body's height.
    #[arg(long, default_value_t = ReconstructOptions::default().spacing,
          value_parser = crate::bounds::real_in(0.002, 0.2))]
    pub spacing: Real,
    /// Section spacing along a finger (a mesh hand whose fingers are
    /// apart: each finger is a part of its own), as a fraction of the
    /// body's height.
    #[arg(long, default_value_t = ReconstructOptions::default().digit_spacing,
          value_parser = crate::bounds::real_in(0.004, 0.2))]
    pub digit_spacing: Real,
    /// Drop a section where the surface skinned through the others passes
    /// its loop within this fraction of the body's height (beyond the
    /// section's own fit); 0 keeps every section.
    #[arg(long, default_value_t = ReconstructOptions::default().prune_tolerance,
          value_parser = crate::bounds::real_in(0.0, trigbody_core::MAX_PRUNE_TOLERANCE))]
    pub prune: Real,
    /// A scan is reconstructed in this many frames (its own, then turned
    /// about its up axis in 15° steps) and the model nearest the scan
    /// kept; 1 reconstructs it once (faster). Meshes are reconstructed once.
    #[arg(long, default_value_t = ReconstructOptions::default().scan_frames,
          value_parser = crate::bounds::count_in(1usize, trigbody_core::MAX_SCAN_FRAMES))]
    pub scan_frames: usize,
    /// Fit every part to the input's points by least squares after it is
    /// built: scans (`auto`), meshes too (`global`) or neither (`none`).
    #[arg(long, value_enum, default_value_t = FitFlag::Auto)]
    pub fit: FitFlag,
    /// Average relative error tolerance E_a of every section.
    #[arg(long, default_value_t = trigbody_core::internals::geom::math::DEFAULT_EA, value_parser = crate::bounds::tolerance_ea)]
    pub ea: Real,
    /// Maximum relative error tolerance E_M of every section.
    #[arg(long, default_value_t = trigbody_core::internals::geom::math::DEFAULT_EM, value_parser = crate::bounds::tolerance_em)]
    pub em: Real,
}

impl BodyFlags {
    /// The reconstruction options these flags describe (the rest default).
    pub fn options(&self) -> ReconstructOptions {
        let mut options = ReconstructOptions {
            units: self.units.units().unwrap_or_default(),
            infer_units: self.units == UnitsFlag::Auto,
            spacing: self.spacing,
            digit_spacing: self.digit_spacing,
            prune_tolerance: self.prune,
            scan_frames: self.scan_frames,
            ..ReconstructOptions::default()
        };
        options.segment.up = self.up_axis;
        options.segment.front = self.front;
        options.fit.ea = self.ea;
        options.fit.em = self.em;
        options.global_fit.mode = self.fit.mode();
        options
    }
}

/// `x`, `-y`, ... or `x,y,z`.
pub fn parse_direction(s: &str) -> Result<Vec3, String> {
    let v = match s.trim().to_ascii_lowercase().as_str() {
        "x" | "+x" => Vec3::X,
        "y" | "+y" => Vec3::Y,
        "z" | "+z" => Vec3::Z,
        "-x" => -Vec3::X,
        "-y" => -Vec3::Y,
        "-z" => -Vec3::Z,
        _ => parse_vec3(s)?,
    };
    v.normalized()
        .ok_or_else(|| format!("'{s}' is not a direction (zero length)"))
}

fn table(r: &Report) -> String {
    let mut t = String::new();
    t.push_str("part        sections  orders min/med/max   worst E_a  worst E_M  met | ellipse E_a  E_M     | params\n");
    for (p, name) in r.parts.iter().zip(report_part_names(r)) {
        t.push_str(&format!(
            "{:<11} {:>8}  {:>6}/{:>3}/{:>3}     {:>8.3}%  {:>8.3}%  {:>3} | {:>9.2}%  {:>7.2}% | {:>6}\n",
            name,
            p.sections,
            p.orders.0,
            p.orders.1,
            p.orders.2,
            100.0 * p.worst_ea,
            100.0 * p.worst_em,
            p.met,
            100.0 * p.ellipse_worst_ea,
            100.0 * p.ellipse_worst_em,
            p.design_parameters
        ));
    }
    let found: Vec<&str> = r.parts_found.iter().map(|p| part_file_name(*p)).collect();
    t.push_str(&format!("parts found: {}\n", found.join(", ")));
    let how = if r.units_inferred {
        "inferred from the body's extent"
    } else {
        "given"
    };
    t.push_str(&format!("input units: {} ({how})\n", r.units.symbol()));
    t.push_str(&format!(
        "design parameters {} ({} numbers in a .tbm file) vs 3 x {} input vertices = {} ({:.1} %)\n",
        r.design_parameters,
        r.compact_numbers,
        r.input_vertices,
        3 * r.input_vertices,
        100.0 * r.parameter_ratio()
    ));
    let by = r.region_parameters;
    t.push_str(&format!(
        "  by region: head {}, hands {}, feet {}, rest {}\n",
        by.head, by.hands, by.feet, by.rest
    ));
    if !r.fit.is_empty() {
        t.push_str("fitted to the input: points used, residual rms before -> after, curves moved rms / max, sections added\n");
        for f in &r.fit {
            t.push_str(&format!(
                "  {:<18} {:>6}  {:>5.2} -> {:>5.2} mm  {:>5.2} / {:>5.2} mm  {:>3}\n",
                f.name,
                f.used,
                f.rms_before_mm,
                f.rms_after_mm,
                f.moved_rms_mm,
                f.moved_max_mm,
                f.sections_added
            ));
        }
    }
    let d = |name: &str, x: &trigbody_core::internals::body::DistanceMm| {
        format!(
            "{name:<16} rms {:>6.2} mm  p95 {:>6.2} mm  max {:>7.2} mm\n",
            x.rms, x.p95, x.max
        )
    };
    t.push_str(&format!(
        "distances to and from the model's outer skin ({:.1} % of its pieces' area lies inside other pieces)\n",
        100.0 * r.interior_area_share
    ));
    t.push_str(&d("distance", &r.distance_mm));
    t.push_str(&d("  input->model", &r.input_to_model_mm));
    t.push_str(&d("  model->input", &r.model_to_input_mm));
    t.push_str(&format!(
        "coverage {:.2} % of the input within 5 mm of the model\n",
        100.0 * r.coverage,
    ));
    t.push_str(&format!(
        "on the surface the input shows: coverage {:.2} %, rms {:.2} mm, p95 {:.2} mm ({} input samples hidden inside it, {} model samples over a scan's holes left out)\n",
        100.0 * r.visible_coverage,
        r.visible_rms_mm,
        r.visible_p95_mm,
        r.hidden_samples,
        r.unobserved_samples
    ));
    t
}

fn search_lines(out: &RateOutcome, goal: Goal) -> String {
    let mut t = String::from(
        "rate search (coarseness c: E_a, E_M, the pruning tolerance and the digits' spacing x c; then E_a, E_M x f):",
    );
    // A trial's settings: `c 2.130`, or `c 2.130 f 1.20` in the second search.
    let at = |c: f64, f: f64| {
        if f == 1.0 {
            format!("c {c:.3}")
        } else {
            format!("c {c:.3} f {f:.2}")
        }
    };
    for trial in &out.trials {
        let name = at(trial.coarseness, trial.tolerance);
        match (trial.design_parameters, trial.rms_mm) {
            (Some(n), Some(r)) => t.push_str(&format!(" {name}: {n} / {r:.2} mm;")),
            _ => t.push_str(&format!(" {name}: failed;")),
        }
    }
    let what = match goal {
        Goal::TargetRms(mm) => format!("rms <= {mm} mm"),
        Goal::MaxParameters(n) => format!("<= {n} parameters"),
    };
    let chosen = at(out.coarseness, out.tolerance);
    if out.met {
        t.push_str(&format!("\nchose {chosen} ({what})\n"));
    } else {
        t.push_str(&format!(
            "\n{what} NOT met: the most accurate model tried ({chosen})\n"
        ));
    }
    t
}

pub fn run(args: ReconstructArgs) -> Result<()> {
    let started = std::time::Instant::now();
    refuse_repeated_outputs(&[
        ("-o", args.output.as_deref()),
        ("--report", args.report.as_deref()),
        ("--mesh", args.mesh.as_deref()),
    ])?;
    let mut bar = ProgressBar::new("reconstructing");
    bar.update(Progress {
        stage: "reading the input",
        done: 0,
        total: 1,
    });
    let (name, geometry) = match &args.input {
        Some(path) => (
            path.display().to_string(),
            crate::input_file::read_geometry(path, &ReadOptions::default())?,
        ),
        None => (
            "built-in body (mh_male.obj)".to_string(),
            read_bytes(BUILT_IN_BODY, Format::Obj, &ReadOptions::default())?,
        ),
    };
    if let Some(q) = args.quantum {
        if !(q.is_finite() && q > 0.0) {
            return Err(bad(format!(
                "--quantum {q}: must be a positive number of mm"
            )));
        }
    }
    let options = args.body.options();
    let body = geometry.body();
    let goal = match (args.target_rms, args.max_parameters) {
        (Some(t), _) => Some(Goal::TargetRms(t)),
        (None, Some(n)) => Some(Goal::MaxParameters(n)),
        (None, None) => None,
    };
    let mut search = String::new();
    let (model, report) = match goal {
        None => {
            let result = reconstruct_with_progress(body, &options, &mut |p| bar.update(p));
            bar.finish();
            result.map_err(|e| bad(format!("{name}: {e}")))?
        }
        Some(goal) => {
            let mut k = 0;
            let result = reconstruct_for(body, &options, goal, &RateOptions::default(), |_| {
                k += 1;
                bar.update(Progress {
                    stage: "rate search",
                    done: k,
                    total: RateOptions::default().steps + 2,
                })
            });
            bar.finish();
            let out = result.map_err(|e| bad(format!("{name}: {e}")))?;
            search = search_lines(&out, goal);
            (out.body, out.report)
        }
    };
    let inputs: Vec<&std::path::Path> = args.input.as_deref().into_iter().collect();
    for w in &report.warnings {
        crate::exit::diag(format_args!("trigbody: warning: {name}: {w}"));
    }
    let outputs = Outputs {
        model: args.output.as_deref(),
        report: args.report.as_deref(),
        mesh: args.mesh.as_deref(),
        skin: args.skin,
        force: args.force,
        quantum_mm: args.quantum,
    };
    let tbm_line = write_outputs(&name, &model, &report, &outputs, &inputs)?;
    print(&format!(
        "{name}: {} parts, reconstructed in {:.2} s\n{search}{}{tbm_line}",
        model.parts.len(),
        started.elapsed().as_secs_f64(),
        table(&report)
    ))
}

/// The pieces `--mesh` writes for `model`: tessellated at edges of 0.004 ×
/// its height, then the `skin` kept.
pub fn mesh_pieces(
    model: &Body,
    skin: trigbody_io::model::Skin,
) -> std::result::Result<Vec<(String, trigbody_core::Mesh)>, String> {
    let tess = TessellationOptions {
        target_edge: Some(0.004 * model.height),
        ..TessellationOptions::default()
    };
    let file_model = model_of_body(model);
    let pieces = file_model
        .tessellate_pieces(&tess)
        .map_err(|e| e.to_string())?;
    skin_pieces(&file_model, pieces, skin).map_err(|e| e.to_string())
}

/// Where a reconstruction's results go (each `None` is not written).
#[derive(Debug, Clone, Copy)]
pub struct Outputs<'a> {
    pub model: Option<&'a Path>,
    pub report: Option<&'a Path>,
    pub mesh: Option<&'a Path>,
    pub skin: crate::cmd_mesh::SkinFlag,
    pub force: bool,
    /// The quantization step of a `.tbm` model file, in mm (None: its default).
    pub quantum_mm: Option<Real>,
}

/// Writes the model file, the report (JSON) and the mesh (by its
/// extension: .glb one node per piece, .obj/.ply/.stl merged) under the
/// output policy of [`write_file`]; `name` names the input in errors.
pub fn write_outputs(
    name: &str,
    model: &Body,
    report: &Report,
    outputs: &Outputs,
    inputs: &[&Path],
) -> Result<String> {
    let mut tbm_line = String::new();
    if let Some(path) = &outputs.model {
        let compact = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("tbm"));
        let bytes = if compact {
            let mm = model.units.to_mm();
            let tbm = TbmOptions {
                step: outputs.quantum_mm.map(|q| q / mm),
                ..TbmOptions::default()
            };
            let (bytes, s) = encode_tbm(&model_of_body(model), &tbm).map_err(bad)?;
            tbm_line = format!(
                "{}: {} bytes, {} section numbers, step {:.4} mm, curve points within {:.3} mm (bound; measured {:.3} mm)\n",
                path.display(),
                s.bytes,
                s.section_numbers,
                s.step * mm,
                s.bound * mm,
                s.max_error * mm
            );
            bytes
        } else {
            let mut bytes = Vec::new();
            write_model(&mut bytes, &model_of_body(model))?;
            bytes
        };
        write_file(path, &bytes, inputs, outputs.force)?;
    }
    if let Some(path) = &outputs.report {
        let mut bytes = serde_json::to_vec_pretty(&report_json(report))?;
        bytes.push(b'\n');
        write_file(path, &bytes, inputs, outputs.force)?;
    }
    if let Some(path) = &outputs.mesh {
        let pieces =
            mesh_pieces(model, outputs.skin.into()).map_err(|e| bad(format!("{name}: {e}")))?;
        let ext = output_extension(path, "glb");
        let format = Format::from_path(&std::path::Path::new("mesh").with_extension(&ext));
        if ext == "glb" {
            let named: Vec<NamedMesh> = pieces
                .iter()
                .map(|(name, mesh)| NamedMesh { name, mesh })
                .collect();
            write_file(path, &glb_bytes(&named)?, inputs, outputs.force)?;
        } else if let Some(format @ (Format::Obj | Format::Ply | Format::Stl)) = format {
            let all = merge_pieces(&pieces);
            let wo = WriteOptions {
                overwrite: outputs.force,
                ..WriteOptions::default()
            };
            refuse_input(path, inputs)?;
            write_mesh_as(path, &all, format, &wo).map_err(bad)?;
        } else {
            return Err(bad(format!(
                "{}: unknown mesh format; use a .glb, .obj, .ply or .stl file name",
                path.display()
            )));
        }
    }
    Ok(tbm_line)
}
