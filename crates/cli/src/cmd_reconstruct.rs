//! `trigbody reconstruct [INPUT] [-o MODEL.json] [--mesh OUT] [--report R.json]`:
//! a body model from a mesh or a scan (the built-in body without INPUT),
//! with a report of its size and its distance to the input.

use crate::cmd_fit::parse_vec3;
use crate::exit::{bad, print};
use crate::output::{refuse_input, write_file};
use crate::progress::ProgressBar;
use anyhow::Result;
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use trigbody_core::body::{reconstruct_with_progress, Progress, ReconstructOptions, Report, Units};
use trigbody_core::segment::BodyGeometry;
use trigbody_core::{Real, TessellationOptions, Vec3};
use trigbody_io::body_file::{model_of_body, part_file_name, report_json, report_part_names};
use trigbody_io::gltf::{glb_bytes, NamedMesh};
use trigbody_io::model::{merge_pieces, skin_pieces, write_model};
use trigbody_io::{
    read_bytes, read_geometry, write_mesh, Format, Geometry, ReadOptions, WriteOptions,
};

/// The built-in body (CC0 MakeHuman average young male, metres; see
/// `data/bodies/README.md`).
const BUILT_IN_BODY: &[u8] = include_bytes!("../../../data/bodies/mh_male.obj");

/// Units of the input's coordinates.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum UnitsFlag {
    M,
    Cm,
    Mm,
}

/// Arguments of `trigbody reconstruct`.
#[derive(Debug, Args)]
pub struct ReconstructArgs {
    /// A body mesh (.obj, .ply, .stl) or scan (.ply points, .xyz); without
    /// it, the built-in body.
    pub input: Option<PathBuf>,
    /// The model file to write (JSON, model format version 5).
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
    /// The up direction: x, y, z, -x, -y, -z or a vector x,y,z (default: found from the data).
    #[arg(long, value_parser = parse_direction, allow_hyphen_values = true)]
    pub up_axis: Option<Vec3>,
    /// The direction the body faces (same forms; default: found from the feet).
    #[arg(long, value_parser = parse_direction, allow_hyphen_values = true)]
    pub front: Option<Vec3>,
    /// The unit of the input's coordinates (distances are reported in mm).
    #[arg(long, value_enum, default_value_t = UnitsFlag::M)]
    pub units: UnitsFlag,
    /// Section spacing along each part, as a fraction of the body's height.
    #[arg(long, default_value_t = ReconstructOptions::default().spacing)]
    pub spacing: Real,
    /// Average relative error tolerance E_a of every section.
    #[arg(long, default_value_t = trigbody_core::math::DEFAULT_EA)]
    pub ea: Real,
    /// Maximum relative error tolerance E_M of every section.
    #[arg(long, default_value_t = trigbody_core::math::DEFAULT_EM)]
    pub em: Real,
    /// Replace existing output files.
    #[arg(long)]
    pub force: bool,
}

/// `x`, `-y`, ... or `x,y,z`.
fn parse_direction(s: &str) -> Result<Vec3, String> {
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
    t.push_str(&format!(
        "design parameters {} vs 3 x {} input vertices = {} ({:.1} %)\n",
        r.design_parameters,
        r.input_vertices,
        3 * r.input_vertices,
        100.0 * r.parameter_ratio()
    ));
    let d = |name: &str, x: &trigbody_core::body::DistanceMm| {
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

pub fn run(args: ReconstructArgs) -> Result<()> {
    let started = std::time::Instant::now();
    let mut bar = ProgressBar::new("reconstructing");
    bar.update(Progress {
        stage: "reading the input",
        done: 0,
        total: 1,
    });
    let (name, geometry) = match &args.input {
        Some(path) => (
            path.display().to_string(),
            read_geometry(path, &ReadOptions::default()).map_err(bad)?,
        ),
        None => (
            "built-in body (mh_male.obj)".to_string(),
            read_bytes(BUILT_IN_BODY, Format::Obj, &ReadOptions::default())?,
        ),
    };
    let mut options = ReconstructOptions {
        units: match args.units {
            UnitsFlag::M => Units::Metres,
            UnitsFlag::Cm => Units::Centimetres,
            UnitsFlag::Mm => Units::Millimetres,
        },
        spacing: args.spacing,
        ..ReconstructOptions::default()
    };
    options.segment.up = args.up_axis;
    options.segment.front = args.front;
    options.fit.ea = args.ea;
    options.fit.em = args.em;
    let body = match &geometry {
        Geometry::Mesh(m) => BodyGeometry::Mesh(m),
        Geometry::Points(c) => BodyGeometry::Cloud(c),
    };
    let result = reconstruct_with_progress(body, &options, &mut |p| bar.update(p));
    bar.finish();
    let (model, report) = result.map_err(|e| bad(format!("{name}: {e}")))?;
    let inputs: Vec<&std::path::Path> = args.input.as_deref().into_iter().collect();
    for w in &report.warnings {
        eprintln!("trigbody: warning: {name}: {w}");
    }
    if let Some(path) = &args.output {
        let mut bytes = Vec::new();
        write_model(&mut bytes, &model_of_body(&model))?;
        write_file(path, &bytes, &inputs, args.force)?;
    }
    if let Some(path) = &args.report {
        let mut bytes = serde_json::to_vec_pretty(&report_json(&report))?;
        bytes.push(b'\n');
        write_file(path, &bytes, &inputs, args.force)?;
    }
    if let Some(path) = &args.mesh {
        let tess = TessellationOptions {
            target_edge: Some(0.004 * model.height),
            ..TessellationOptions::default()
        };
        let file_model = model_of_body(&model);
        let pieces = file_model
            .tessellate_pieces(&tess)
            .map_err(|e| bad(format!("{name}: {e}")))?;
        let pieces = skin_pieces(&file_model, pieces, args.skin.into())
            .map_err(|e| bad(format!("{name}: {e}")))?;
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .unwrap_or_default();
        if ext == "glb" {
            let named: Vec<NamedMesh> = pieces
                .iter()
                .map(|(name, mesh)| NamedMesh { name, mesh })
                .collect();
            write_file(path, &glb_bytes(&named)?, &inputs, args.force)?;
        } else if matches!(
            Format::from_path(path),
            Some(Format::Obj | Format::Ply | Format::Stl)
        ) {
            let all = merge_pieces(&pieces);
            let wo = WriteOptions {
                overwrite: args.force,
                ..WriteOptions::default()
            };
            refuse_input(path, &inputs)?;
            write_mesh(path, &all, &wo).map_err(bad)?;
        } else {
            return Err(bad(format!(
                "{}: unknown mesh format; use a .glb, .obj, .ply or .stl file name",
                path.display()
            )));
        }
    }
    print(&format!(
        "{name}: {} parts, reconstructed in {:.2} s\n{}",
        model.parts.len(),
        started.elapsed().as_secs_f64(),
        table(&report)
    ))
}
