//! `trigbody examples`: fit the bundled real cross-sections, compare each
//! with the ellipse baseline, and draw them all.

use crate::cmd_fit::{fit_panel, fit_points, image_format, FitFlags};
use crate::exit::print;
use crate::output::write_file;
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use trigbody_io::fit_json::loop_fit_json;
use trigbody_io::loop_text::parse_loop;
use trigbody_render::{plot_panels, PlotOptions};

/// The bundled loops: (name, text), cut from the MakeHuman average male body
/// (CC0) by `data/loops/cut_loops.py`.
pub const EXAMPLE_LOOPS: [(&str, &str); 6] = [
    (
        "torso_chest",
        include_str!("../../../data/loops/torso_chest.xyz"),
    ),
    (
        "torso_waist",
        include_str!("../../../data/loops/torso_waist.xyz"),
    ),
    ("neck", include_str!("../../../data/loops/neck.xyz")),
    (
        "upper_arm",
        include_str!("../../../data/loops/upper_arm.xyz"),
    ),
    ("thigh", include_str!("../../../data/loops/thigh.xyz")),
    ("calf", include_str!("../../../data/loops/calf.xyz")),
];

/// Arguments of `trigbody examples`.
#[derive(Debug, Args)]
pub struct ExamplesArgs {
    #[command(flatten)]
    pub fit: FitFlags,
    /// Also draw all fits to FILE (SVG or PNG).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Print a JSON list of the fits instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Replace an existing output file (the input is never replaced).
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: ExamplesArgs) -> Result<()> {
    let format = args.plot.as_deref().map(image_format).transpose()?;
    let opts = args.fit.options();
    let mut panels = Vec::new();
    let mut json = Vec::new();
    let mut out = String::new();
    if !args.json {
        out += &format!(
            "{:<12} {:>6} | {:>9} {:>9} {:>5} | {:>9} {:>9} {:>5} | {:>6} {:>8}\n",
            "loop", "points", "trig E_a", "E_M", "J", "ell. E_a", "E_M", "meets", "paper", "params"
        );
    }
    for (name, text) in EXAMPLE_LOOPS {
        let points = parse_loop(text, name).with_context(|| format!("bundled loop {name}"))?;
        let fit =
            fit_points(&points, &opts).with_context(|| format!("fitting bundled loop {name}"))?;
        if args.json {
            let mut j = loop_fit_json(&fit);
            j["name"] = serde_json::Value::from(name);
            json.push(j);
        } else {
            let (ea, em, meets) = fit.ellipse.map_or((f64::NAN, f64::NAN, false), |e| {
                (e.errors.ea, e.errors.em, e.errors.meets(opts.ea, opts.em))
            });
            out += &format!(
                "{:<12} {:>6} | {:>8.3}% {:>8.3}% {:>5} | {:>8.3}% {:>8.3}% {:>5} | {:>6} {:>8}\n",
                name,
                fit.plane_points.len(),
                100.0 * fit.errors.ea,
                100.0 * fit.errors.em,
                if fit.met {
                    fit.order.to_string()
                } else {
                    format!("{}!", fit.order)
                },
                100.0 * ea,
                100.0 * em,
                if meets { "yes" } else { "no" },
                fit.paper_order.map_or("-".to_string(), |j| j.to_string()),
                fit.curve.design_parameters(),
            );
        }
        panels.push(fit_panel(name, &points, &fit));
    }
    if args.json {
        out += &serde_json::to_string_pretty(&json)?;
        out.push('\n');
    } else {
        out += &format!(
            "tolerances: E_a ≤ {:.2} %, E_M ≤ {:.2} %; J is the smallest order meeting both ('!' = none did), 'paper' the paper's interpolation pick; the ellipse is the Hyun et al. baseline\n",
            100.0 * opts.ea,
            100.0 * opts.em
        );
    }
    let plot_opts = PlotOptions {
        title: Some("Real cross-sections: trigonometric series vs. ellipse".to_string()),
        ..PlotOptions::default()
    };
    if let (Some(path), Some(format)) = (&args.plot, format) {
        let bytes = plot_panels(&panels, format, &plot_opts)?;
        write_file(path, &bytes, &[], args.force)?;
        if !args.json {
            out += &format!("plot written to {}\n", path.display());
        }
    }
    print(&out)
}
