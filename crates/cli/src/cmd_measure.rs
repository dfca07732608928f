//! `trigbody measure MODEL.json|INPUT [--json] [--direct]`: stature, girths,
//! lengths, shoulder breadth, volume and surface area of a body — from a
//! model file's curves, or from the model reconstructed from an input mesh
//! or scan (each girth beside the same girth on the input mesh), or with
//! `--direct` from the fitted sections of a mesh itself.

use crate::body_input::{measurements, Measured};
use crate::exit::{bad, print};
use anyhow::Result;
use clap::Args;
use serde_json::{json, Value};
use std::path::PathBuf;
use trigbody_core::{Measurement, Measurements, Units};
use trigbody_io::{ReadOptions, UpAxis};

/// Flags of `trigbody measure`.
#[derive(Debug, Args)]
pub struct MeasureArgs {
    /// The body: a model file (.json, from `trigbody reconstruct`), or a
    /// mesh (.obj, .ply, .stl) or scan (.ply, .xyz points), reconstructed
    /// first.
    pub body: PathBuf,
    /// Print JSON: a list of measurements (name, kind, value, unit, and for
    /// girths the plane {origin, normal} they were taken in), plus volume
    /// and surface_area.
    #[arg(long)]
    pub json: bool,
    /// Measure a mesh directly from fitted curves of its own sections,
    /// without reconstructing a model.
    #[arg(long)]
    pub direct: bool,
    /// A mesh (.obj, .ply, .stl) to measure every girth on in the same plane,
    /// beside the model's (default: the input the model was reconstructed
    /// from, when it is a mesh).
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// The input's length unit (m, cm, mm, or auto to infer it from the
    /// body's extent), as printed: values are never converted, and a model
    /// file's own unit is used for it.
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
    let units = match args.unit.as_str() {
        "auto" => None,
        u => Some(
            Units::from_symbol(u)
                .ok_or_else(|| bad(format!("--unit {u}: must be m, cm, mm or auto")))?,
        ),
    };
    let b = measurements(&args.body, &read, args.direct, args.input.as_deref(), units)?;
    let unit = b.units.symbol().to_string();
    let m = &b.measurements;
    let input = args.body.display().to_string();
    for w in &m.warnings {
        crate::exit::diag(format_args!("trigbody: warning: {input}: {w}"));
    }
    if args.json {
        let mut text =
            serde_json::to_string_pretty(&measurements_json(m, &unit, &input, b.measured))?;
        text.push('\n');
        print(&text)
    } else {
        print(&table(m, &unit, b.measured))
    }
}

/// A number, or JSON null when it is not finite (nothing to compare with).
fn num(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

/// The JSON document of `measure --json`.
pub fn measurements_json(m: &Measurements, unit: &str, input: &str, measured: Measured) -> Value {
    let (volume_method, area_method) = match measured {
        Measured::Direct => (
            "midpoint rule over horizontal slabs of the fitted section curves' exact areas",
            "bands of triangles between the fitted curves of consecutive horizontal slices",
        ),
        _ => (
            "divergence theorem over each part's patches and caps (Gauss-Legendre in u, trapezoid in v), open ends closed by their sections' planar discs; parts summed",
            "integral of |t_v x t_u| over each part's patches and caps; parts summed",
        ),
    };
    json!({
        "input": input,
        "measured_on": measured.as_str(),
        "unit": unit,
        "measurements": m.measurements.iter().map(|x| measurement_json(x, unit)).collect::<Vec<_>>(),
        "volume": {
            "value": m.volume.model,
            "unit": format!("{unit}^3"),
            "input_mesh": num(m.volume.mesh),
            "method": volume_method,
        },
        "surface_area": {
            "value": m.surface_area.model,
            "unit": format!("{unit}^2"),
            "input_mesh": num(m.surface_area.mesh),
            "method": area_method,
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
        j["input_tape"] = num(g.mesh_tape);
        j["input_perimeter"] = num(g.mesh_perimeter);
    }
    j
}

/// The table of `measure`: values in mm when the unit is metres; the input
/// columns when there is an input mesh to compare with.
fn table(m: &Measurements, unit: &str, measured: Measured) -> String {
    let (scale, shown) = match unit {
        "m" => (1e3, "mm"),
        "cm" => (10.0, "mm"),
        _ => (1.0, unit),
    };
    let mut out = format!("measured on the {}\n", measured.as_str());
    out += &format!(
        "{:<18} {:<8} {:>10}   {:>10} {:>8}   ISO 7250-1\n",
        "measurement", "kind", shown, "input", "diff"
    );
    for x in &m.measurements {
        let (input, diff) = match &x.girth {
            Some(g) if g.mesh_tape.is_finite() => (
                format!("{:.1}", scale * g.mesh_tape),
                format!("{:+.1}", scale * (x.value - g.mesh_tape)),
            ),
            _ => (String::new(), String::new()),
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
    let compared = |c: &trigbody_core::internals::measure::mesh::Comparison, digits: usize| {
        if c.mesh.is_finite() {
            format!(
                " (input mesh {:.digits$}, {:+.2} %)",
                c.mesh,
                100.0 * c.relative_difference()
            )
        } else {
            String::new()
        }
    };
    out += &format!(
        "volume        {:.5} {unit}^3{}\n",
        m.volume.model,
        compared(&m.volume, 5)
    );
    out += &format!(
        "surface area  {:.4} {unit}^2{}\n",
        m.surface_area.model,
        compared(&m.surface_area, 4)
    );
    out
}
