//! `trigbody plot-sections MODEL.json|INPUT -o OUT.svg|png`: the paper's
//! Figures 1-2 for any body — the model's sections at the measurement
//! levels (its trigonometric curves), with the input's section points and
//! their least-squares ellipse when an input mesh is known (the one
//! reconstructed, or `--input`), else the ellipse of the model's curve.

use crate::body_input::measurements;
use crate::cmd_fit::image_format;
use crate::exit::{bad, print};
use crate::output::write_file;
use crate::panels::{across, loops_panel, LoopDrawing};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use trigbody_core::internals::measure::model::model_ellipse;
use trigbody_io::{ReadOptions, UpAxis};
use trigbody_render::{plot_panels, PlotOptions};

/// The levels drawn, most telling first: torso, legs, arms, neck.
const LEVELS: [&str; 12] = [
    "chest",
    "waist",
    "hip",
    "thigh",
    "knee",
    "calf",
    "upper arm",
    "forearm",
    "neck",
    "elbow",
    "ankle",
    "wrist",
];

/// Flags of `trigbody plot-sections`.
#[derive(Debug, Args)]
pub struct PlotSectionsArgs {
    /// The body: a model file (.json, from `trigbody reconstruct`), or a mesh
    /// or scan, reconstructed first.
    pub body: PathBuf,
    /// A mesh whose sections in the same planes are drawn as points (default:
    /// the input the model was reconstructed from, when it is a mesh).
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// Draw the fitted sections of a mesh itself (no reconstruction).
    #[arg(long)]
    pub direct: bool,
    /// The picture to write (.svg or .png).
    #[arg(short, long)]
    pub output: PathBuf,
    /// How many levels to draw (1-12), in the order chest, waist, hip,
    /// thigh, knee, calf, upper arm, forearm, neck, elbow, ankle, wrist.
    #[arg(long, default_value_t = 9)]
    pub levels: usize,
    /// Panels per row.
    #[arg(long, default_value_t = 3, value_parser = crate::bounds::count_in(1usize, 12))]
    pub columns: usize,
    /// Size of one panel in pixels (below about 400 the legend covers the
    /// top of the loops).
    #[arg(long, default_value_t = 420, value_parser = crate::bounds::count_in(64u32, 4096))]
    pub panel_size: u32,
    /// The file's up axis (x, -x, y, -y, z, -z, or keep).
    #[arg(long, default_value = "keep")]
    pub up_axis: UpAxis,
    /// The unit of a mesh's or scan's coordinates (a model file carries
    /// its own); `auto` infers it from the body's extent.
    #[arg(long, value_enum, default_value_t = crate::cmd_reconstruct::UnitsFlag::M)]
    pub units: crate::cmd_reconstruct::UnitsFlag,
    /// Replace an existing output file (the input is never replaced).
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: PlotSectionsArgs) -> Result<()> {
    if !(1..=LEVELS.len()).contains(&args.levels) {
        return Err(bad(format!(
            "--levels: between 1 and {}, not {}",
            LEVELS.len(),
            args.levels
        )));
    }
    if args.columns == 0 {
        return Err(bad("--columns: at least 1"));
    }
    let format = image_format(&args.output)?;
    let read = ReadOptions {
        up_axis: args.up_axis,
        ..ReadOptions::default()
    };
    let b = measurements(
        &args.body,
        &read,
        args.direct,
        args.input.as_deref(),
        args.units.units(),
    )?;
    let m = &b.measurements;
    // Millimetres per unit: a model file's own, else the input's.
    let mm = b.units.to_mm();
    let mut panels = Vec::new();
    for name in LEVELS.iter().take(args.levels) {
        let Some((x, g)) = m.get(name).and_then(|x| x.girth.as_ref().map(|g| (x, g))) else {
            continue;
        };
        let (u, w) = across(g.plane.normal);
        let drawing = LoopDrawing {
            points: &g.outline,
            curve: &g.curve,
            ellipse: g.ellipse.clone().or_else(|| model_ellipse(g)),
        };
        let title = if g.mesh_tape.is_finite() {
            format!(
                "{}: {:.0} mm (input {:.0}), order {}",
                x.name,
                mm * x.value,
                mm * g.mesh_tape,
                g.curve.order()
            )
        } else {
            format!(
                "{}: {:.0} mm, order {}",
                x.name,
                mm * x.value,
                g.curve.order()
            )
        };
        panels.push(loops_panel(title, &[drawing], u, w));
    }
    if panels.is_empty() {
        return Err(bad(format!(
            "{}: no girth level could be measured",
            args.body.display()
        )));
    }
    let options = PlotOptions {
        panel_size: args.panel_size,
        columns: Some(args.columns),
        ..PlotOptions::default()
    };
    let bytes = plot_panels(&panels, format, &options)?;
    let mut inputs = vec![args.body.as_path()];
    inputs.extend(args.input.as_deref());
    write_file(&args.output, &bytes, &inputs, args.force)?;
    print(&format!(
        "{}: {} section(s)\n",
        args.output.display(),
        panels.len()
    ))
}
