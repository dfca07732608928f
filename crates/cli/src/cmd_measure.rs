//! `trigbody measure MODEL.json|INPUT [--json]`: stature, girths, lengths,
//! shoulder breadth, volume and surface area of a body.

use crate::body_input::measurements;
use crate::exit::print;
use anyhow::Result;
use clap::Args;
use serde_json::{json, Value};
use std::path::PathBuf;
use trigbody_core::measure::{MeasureOptions, Measurement, Measurements};
use trigbody_io::{ReadOptions, UpAxis};

/// Flags of `trigbody measure`.
#[derive(Debug, Args)]
pub struct MeasureArgs {
    /// The body: a closed mesh (.obj, .ply, .stl). Model files (.json) are
    /// measured once whole-body models exist (`trigbody reconstruct`).
    pub input: PathBuf,
    /// Print JSON: a list of measurements (name, kind, value, unit, and for
    /// girths the plane {origin, normal} they were taken in), plus volume
    /// and surface_area.
    #[arg(long)]
    pub json: bool,
    /// The input's length unit, as printed (values are never converted).
    #[arg(long, default_value = "m")]
    pub unit: String,
    /// The file's up axis (x, -x, y, -y, z, -z, or keep); measurements find
    /// the body's own up axis either way.
    #[arg(long, default_value = "keep")]
    pub up_axis: UpAxis,
}

pub fn run(args: MeasureArgs) -> Result<()> {
    let read = ReadOptions {
        up_axis: args.up_axis,
        ..ReadOptions::default()
    };
    let m = measurements(&args.input, &read, &MeasureOptions::default())?;
    if args.json {
        let mut text = serde_json::to_string_pretty(&measurements_json(
            &m,
            &args.unit,
            &args.input.display().to_string(),
        ))?;
        text.push('\n');
        print(&text)
    } else {
        print(&table(&m, &args.unit))
    }
}

/// The JSON document of `measure --json`.
pub fn measurements_json(m: &Measurements, unit: &str, input: &str) -> Value {
    json!({
        "input": input,
        "unit": unit,
        "measurements": m.measurements.iter().map(|x| measurement_json(x, unit)).collect::<Vec<_>>(),
        "volume": {
            "value": m.volume.model,
            "unit": format!("{unit}^3"),
            "input_mesh": m.volume.mesh,
            "method": "midpoint rule over horizontal slabs of the fitted section curves' exact areas",
        },
        "surface_area": {
            "value": m.surface_area.model,
            "unit": format!("{unit}^2"),
            "input_mesh": m.surface_area.mesh,
            "method": "bands of triangles between the fitted curves of consecutive horizontal slices",
        },
        "warnings": m.warnings,
    })
}

fn measurement_json(x: &Measurement, unit: &str) -> Value {
    let mut j = json!({
        "name": x.name,
        "kind": x.kind.as_str(),
        "value": x.value,
        "unit": unit,
        "iso_7250_1": x.iso,
        "definition": x.definition,
    });
    if let Some(g) = &x.girth {
        j["plane"] = json!({
            "origin": g.plane.origin.to_array(),
            "normal": g.plane.normal.to_array(),
        });
        j["curve_perimeter"] = json!(g.perimeter);
        j["curve_order"] = json!(g.curve.order());
        j["input_tape"] = json!(g.mesh_tape);
        j["input_perimeter"] = json!(g.mesh_perimeter);
    }
    j
}

/// The table of `measure`: values in mm when the unit is metres.
fn table(m: &Measurements, unit: &str) -> String {
    let (scale, shown) = if unit == "m" {
        (1e3, "mm")
    } else {
        (1.0, unit)
    };
    let mut out = format!(
        "{:<18} {:<8} {:>10}   {:>10} {:>8}   ISO 7250-1\n",
        "measurement", "kind", shown, "input", "diff"
    );
    for x in &m.measurements {
        let (input, diff) = match &x.girth {
            Some(g) => (
                format!("{:.1}", scale * g.mesh_tape),
                format!("{:+.1}", scale * (x.value - g.mesh_tape)),
            ),
            None => (String::new(), String::new()),
        };
        out += &format!(
            "{:<18} {:<8} {:>10.1}   {:>10} {:>8}   {}\n",
            x.name,
            x.kind.as_str(),
            scale * x.value,
            input,
            diff,
            x.iso.unwrap_or("-")
        );
    }
    out += &format!(
        "volume        {:.5} {unit}^3 (input mesh {:.5}, {:+.2} %)\n",
        m.volume.model,
        m.volume.mesh,
        100.0 * m.volume.relative_difference()
    );
    out += &format!(
        "surface area  {:.4} {unit}^2 (input mesh {:.4}, {:+.2} %)\n",
        m.surface_area.model,
        m.surface_area.mesh,
        100.0 * m.surface_area.relative_difference()
    );
    for w in &m.warnings {
        out += &format!("warning: {w}\n");
    }
    out
}
