//! `trigbody sections INPUT`: cut a mesh (plane sections) or a scan (slab
//! sections) with parallel planes and fit every loop.

use crate::cmd_fit::{image_format, parse_nonzero_vec3, FitFlags};
use crate::exit::{bad, print};
use crate::output::write_file;
use crate::panels::{across, loops_panel, LoopDrawing};
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use serde_json::{json, Value};
use std::path::PathBuf;
use trigbody_core::fit_loop;
use trigbody_core::internals::section::cloud::{scan_fit_options, CloudSlicer, ScanSectionOptions};
use trigbody_core::internals::section::mesh::{MeshSlicer, SectionOptions};
use trigbody_core::{FitOptions, LoopFit, Point3, Real, Vec2, Vec3};
use trigbody_io::fit_json::loop_fit_json;
use trigbody_io::{Geometry, ReadOptions};
use trigbody_render::{plot_panels, Curve2, Panel, PlotOptions};

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum AxisFlag {
    X,
    Y,
    Z,
}

impl AxisFlag {
    fn vector(self) -> Vec3 {
        match self {
            AxisFlag::X => Vec3::X,
            AxisFlag::Y => Vec3::Y,
            AxisFlag::Z => Vec3::Z,
        }
    }
}

/// Arguments of `trigbody sections`.
#[derive(Debug, Args)]
pub struct SectionsArgs {
    /// A mesh (OBJ, PLY, STL: plane sections) or a point cloud (PLY without
    /// faces, XYZ: slab sections).
    pub input: PathBuf,
    /// The axis the cutting planes are normal to (the files' up axis is y).
    #[arg(long, value_enum, default_value_t = AxisFlag::Y)]
    pub axis: AxisFlag,
    /// Number of evenly spaced planes between --from and --to (each at the
    /// middle of its share).
    #[arg(long, default_value_t = 20, conflicts_with = "step")]
    pub count: usize,
    /// Distance between planes instead of --count (the first half a step
    /// above --from).
    #[arg(long)]
    pub step: Option<Real>,
    /// Lowest offset along the axis (default: the input's lowest point).
    #[arg(long, allow_hyphen_values = true)]
    pub from: Option<Real>,
    /// Highest offset along the axis (default: the input's highest point).
    #[arg(long, allow_hyphen_values = true)]
    pub to: Option<Real>,
    /// Half-thickness of the slab for scans (default: the point spacing).
    #[arg(long, value_parser = crate::bounds::positive)]
    pub half_thickness: Option<Real>,
    /// Front direction x,y,z: v = 0 of every fitted curve lies along it.
    #[arg(long, value_parser = parse_nonzero_vec3, allow_hyphen_values = true)]
    pub reference: Option<Vec3>,
    #[command(flatten)]
    pub fit: FitFlags,
    /// Write every level and loop (frame, coefficients, errors) as JSON.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Draw all loops over the input's outline, and the points with the trig
    /// and ellipse fits of --plot-levels levels, to FILE.svg or FILE.png.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Replace an existing output file (the input is never replaced).
    #[arg(long)]
    pub force: bool,
    /// How many levels (spread evenly over those with loops) --plot draws in detail.
    #[arg(long, default_value_t = 8, value_parser = crate::bounds::count_in(1usize, 100))]
    pub plot_levels: usize,
}

/// A level's offset and its loops' points with their fits (for the plot).
type FittedLevel = (Real, Vec<(Vec<Point3>, LoopFit)>);

/// One loop of one level: its ordered points and where they came from.
struct CutLoop {
    points: Vec<Point3>,
    perimeter: Real,
    area: Real,
    note: String,
}

pub fn run(args: SectionsArgs) -> Result<()> {
    let name = args.input.display().to_string();
    crate::output::refuse_repeated_outputs(&[
        ("--json", args.json.as_deref()),
        ("--plot", args.plot.as_deref()),
    ])?;
    let geometry = crate::input_file::read_geometry(&args.input, &ReadOptions::default())?;
    let axis = args.axis.vector();
    if let Some(r) = args.reference {
        if r.cross(axis).norm() <= 1e-9 * r.norm() {
            return Err(bad(format!(
                "--reference {:?} is parallel to the cutting axis {:?}: it gives no direction in the planes",
                r.to_array(),
                args.axis
            )));
        }
    }
    let base = FitOptions {
        reference: args.reference,
        normal: Some(axis),
        ..args.fit.options()
    };
    // Cutters: one closure per input kind giving the loops at an offset.
    let mesh_slicer;
    let cloud_slicer;
    let scan_opts = ScanSectionOptions {
        half_thickness: args.half_thickness,
        reference: args.reference,
        ..Default::default()
    };
    let (range, is_scan) = match &geometry {
        Geometry::Mesh(m) => {
            let opts = SectionOptions {
                reference: args.reference,
                ..Default::default()
            };
            mesh_slicer =
                Some(MeshSlicer::new(m, axis, &opts).map_err(|e| bad(format!("{name}: {e}")))?);
            cloud_slicer = None;
            (mesh_slicer.as_ref().map(|s| s.range()), false)
        }
        Geometry::Points(p) => {
            cloud_slicer =
                Some(CloudSlicer::new(p, axis).map_err(|e| bad(format!("{name}: {e}")))?);
            mesh_slicer = None;
            (cloud_slicer.as_ref().map(|s| s.range()), true)
        }
    };
    let (lo, hi) = range.context("no slicer")?;
    let from = args.from.unwrap_or(lo);
    let to = args.to.unwrap_or(hi);
    if !(from.is_finite() && to.is_finite() && from < to) {
        return Err(bad(format!("--from {from} must be below --to {to}")));
    }
    if to < lo || from > hi {
        return Err(bad(format!(
            "{name}: --from {from} --to {to} lies outside the input, which spans [{lo}, {hi}] along {:?}",
            args.axis
        )));
    }
    let offsets = plane_offsets(&args, from, to)?;
    let fit_opts = match &cloud_slicer {
        Some(s) => scan_fit_options(&base, s.noise()),
        None => base,
    };

    let mut table = format!(
        "{name}: {} sections normal to {:?} from {from:.4} to {to:.4} ({})\n",
        offsets.len(),
        args.axis,
        if is_scan {
            "slabs of a point cloud"
        } else {
            "plane sections of a mesh"
        }
    );
    table += &format!(
        "  {:>10} {:>4} {:>6} {:>10} {:>10} {:>5} {:>9} {:>9} {:>9} {:>9}\n",
        "offset", "loop", "points", "perimeter", "area", "J", "E_a", "E_M", "ell. E_a", "ell. E_M"
    );
    let plot_format = match &args.plot {
        Some(p) => Some(image_format(p)?),
        None => None,
    };
    let Levels {
        rows,
        levels,
        fitted,
        cut,
        fits,
        first_error,
    } = fit_levels(
        &Cutters {
            mesh: mesh_slicer.as_ref(),
            cloud: cloud_slicer.as_ref(),
            scan: &scan_opts,
        },
        &name,
        &offsets,
        &fit_opts,
        plot_format.is_some(),
    );
    table += &rows;
    if cut == 0 {
        return Err(bad(format!(
            "{name}: no loop at any of the {} levels from {from} to {to}{}",
            offsets.len(),
            if is_scan {
                " (a thinner --half-thickness than the point spacing finds none)"
            } else {
                ""
            }
        )));
    }
    if fits == 0 {
        return Err(bad(format!(
            "none of the {cut} loops could be fitted; the first: {}",
            first_error.unwrap_or_default()
        )));
    }
    if let Some(path) = &args.json {
        let doc = json!({
            "format": "trigbody-sections",
            "version": 1,
            "input": name,
            "kind": if is_scan { "scan" } else { "mesh" },
            "axis": axis.to_array(),
            "levels": levels,
        });
        let text = serde_json::to_string_pretty(&doc).context("encoding JSON")? + "\n";
        write_file(path, text.as_bytes(), &[&args.input], args.force)?;
        table += &format!("JSON written to {}\n", path.display());
    }
    if let (Some(path), Some(format)) = (&args.plot, plot_format) {
        let outline = match &geometry {
            Geometry::Mesh(m) => &m.positions,
            Geometry::Points(p) => &p.positions,
        };
        let panels = section_panels(&name, outline, axis, &fitted, args.plot_levels);
        let bytes = plot_panels(&panels, format, &PlotOptions::default())?;
        write_file(path, &bytes, &[&args.input], args.force)?;
        table += &format!("plot written to {}\n", path.display());
    }
    print(&table)
}

/// The slicers of the input (one of them) and the scan slabs' options.
struct Cutters<'a> {
    mesh: Option<&'a MeshSlicer<'a>>,
    cloud: Option<&'a CloudSlicer<'a>>,
    scan: &'a ScanSectionOptions,
}

/// Every level's loops fitted: the table's rows, the JSON levels, the fits
/// kept for the plot, and the counts of loops cut and fitted with the first
/// fit error (nothing fitted is exit 2).
struct Levels {
    rows: String,
    levels: Vec<serde_json::Value>,
    fitted: Vec<FittedLevel>,
    cut: usize,
    fits: usize,
    first_error: Option<String>,
}

/// Cuts the input at each offset and fits every loop (see [`Levels`]).
fn fit_levels(
    cutters: &Cutters<'_>,
    name: &str,
    offsets: &[Real],
    fit_opts: &FitOptions,
    keep_fits: bool,
) -> Levels {
    let mut out = Levels {
        rows: String::new(),
        levels: Vec::new(),
        fitted: Vec::new(),
        cut: 0,
        fits: 0,
        first_error: None,
    };
    for &offset in offsets {
        let loops = loops_at(cutters.mesh, cutters.cloud, cutters.scan, name, offset);
        let mut json_loops = Vec::new();
        if loops.is_empty() {
            out.rows += &format!("  {offset:>10.4}    -      0   (no loop)\n");
        }
        out.cut += loops.len();
        for (i, l) in loops.iter().enumerate() {
            match fit_loop(&l.points, fit_opts) {
                Ok(fit) => {
                    out.fits += 1;
                    out.rows += &format!(
                        "  {offset:>10.4} {i:>4} {:>6} {:>10.4} {:>10.5} {:>5} {:>9} {:>9} {:>9} {:>9}{}\n",
                        l.points.len(),
                        l.perimeter,
                        l.area,
                        fit.order,
                        pct(fit.errors.ea),
                        pct(fit.errors.em),
                        fit.ellipse.map_or("-".into(), |e| pct(e.errors.ea)),
                        fit.ellipse.map_or("-".into(), |e| pct(e.errors.em)),
                        l.note
                    );
                    json_loops.push(loop_json(l, &fit));
                    if keep_fits {
                        match out.fitted.last_mut() {
                            Some((o, v)) if *o == offset => v.push((l.points.clone(), fit)),
                            _ => out.fitted.push((offset, vec![(l.points.clone(), fit)])),
                        }
                    }
                }
                Err(e) => {
                    let e = format!("{name}: loop {i} at offset {offset}: {e}");
                    crate::exit::diag(format_args!("trigbody: warning: {e}"));
                    out.first_error.get_or_insert(e);
                }
            }
        }
        out.levels
            .push(json!({ "offset": offset, "loops": json_loops }));
    }
    out
}

/// The offsets of the planes: `--step` apart, or `--count` of them, each
/// in the middle of its share of `[from, to]`.
fn plane_offsets(args: &SectionsArgs, from: Real, to: Real) -> Result<Vec<Real>> {
    Ok(match args.step {
        Some(step) if step.is_finite() && step > 0.0 => {
            let n = ((to - from) / step).floor() as usize;
            if n > 100_000 {
                return Err(bad(format!("--step {step} gives more than 100 000 planes")));
            }
            (0..n.max(1))
                .map(|k| from + (k as Real + 0.5) * step)
                .collect()
        }
        Some(step) => return Err(bad(format!("--step {step} must be a positive number"))),
        None if args.count == 0 || args.count > 100_000 => {
            return Err(bad(format!("--count {} must be in 1..=100000", args.count)))
        }
        None => (0..args.count)
            .map(|k| from + (k as Real + 0.5) * (to - from) / args.count as Real)
            .collect(),
    })
}

/// The loops at `offset` of whichever slicer there is (warnings for open
/// chains and failed cuts go to stderr).
fn loops_at(
    mesh_slicer: Option<&MeshSlicer>,
    cloud_slicer: Option<&CloudSlicer>,
    scan_opts: &ScanSectionOptions,
    name: &str,
    offset: Real,
) -> Vec<CutLoop> {
    if let Some(s) = mesh_slicer {
        match s.section_at(offset) {
            Ok(sec) => {
                for c in &sec.open_chains {
                    crate::exit::diag(format_args!(
                        "trigbody: warning: {name}: an open chain of {} points at offset {offset} (open or non-manifold surface)",
                        c.len()
                    ));
                }
                sec.loops
                    .into_iter()
                    .map(|l| CutLoop {
                        perimeter: l.perimeter,
                        area: l.area,
                        points: l.points,
                        note: String::new(),
                    })
                    .collect()
            }
            Err(e) => {
                crate::exit::diag(format_args!("trigbody: warning: {name}: {e}"));
                Vec::new()
            }
        }
    } else if let Some(s) = cloud_slicer {
        match s.section_at(offset, scan_opts) {
            Ok(sec) => sec
                .loops
                .into_iter()
                .map(|l| CutLoop {
                    perimeter: l.outline.perimeter,
                    area: l.outline.area,
                    note: if l.closed_ring {
                        String::new()
                    } else {
                        format!("  (gap {:.4} bridged)", l.max_gap)
                    },
                    points: l.outline.points,
                })
                .collect(),
            Err(e) => {
                crate::exit::diag(format_args!("trigbody: warning: {name}: {e}"));
                Vec::new()
            }
        }
    } else {
        Vec::new()
    }
}

fn pct(x: Real) -> String {
    format!("{:.3}%", 100.0 * x)
}

/// One loop in the JSON file: its plane frame at the top level (`origin`,
/// `e1`, `e2`, `normal`), everything [`loop_fit_json`] writes (order, the
/// paper's coefficients, errors, the ellipse baseline), and the cut loop's
/// own point count, perimeter and area.
fn loop_json(l: &CutLoop, fit: &LoopFit) -> Value {
    let f = &fit.curve.frame;
    let mut j = loop_fit_json(fit);
    j["origin"] = json!(f.origin.to_array());
    j["e1"] = json!(f.e1.to_array());
    j["e2"] = json!(f.e2.to_array());
    j["points"] = json!(l.points.len());
    j["perimeter"] = json!(l.perimeter);
    j["area"] = json!(l.area);
    j
}

/// The plot of `trigbody sections`: an overview with every loop over the
/// input's outline seen from the side, then up to `detail` levels with their
/// points, trig fits and ellipses in the cutting plane.
fn section_panels(
    name: &str,
    outline: &[Point3],
    axis: Vec3,
    fitted: &[FittedLevel],
    detail: usize,
) -> Vec<Panel> {
    let (u, w) = across(axis);
    let up = axis.normalized().unwrap_or(Vec3::Y);
    let side = |p: Point3| Vec2::new(p.dot(u), p.dot(up));
    let stride = outline.len().div_ceil(20_000).max(1);
    let mut overview = Panel {
        title: format!("{name}: {} levels", fitted.len()),
        points: outline.iter().step_by(stride).map(|p| side(*p)).collect(),
        points_label: "input (outline)".into(),
        faint_points: true,
        curves: Vec::new(),
    };
    for (k, (_, loops)) in fitted.iter().enumerate() {
        for (i, (_, fit)) in loops.iter().enumerate() {
            overview.curves.push(Curve2 {
                label: if k == 0 && i == 0 {
                    "trig curves".into()
                } else {
                    String::new()
                },
                points: fit.curve.sample(200).into_iter().map(side).collect(),
                color: (20, 150, 40),
                closed: true,
            });
        }
    }
    let mut panels = vec![overview];
    let n = fitted.len();
    let picks: Vec<usize> = if n <= detail {
        (0..n).collect()
    } else {
        (0..detail)
            .map(|k| (k * (n - 1)) / (detail - 1).max(1))
            .collect()
    };
    for k in picks {
        let (offset, loops) = &fitted[k];
        let drawings: Vec<LoopDrawing<'_>> = loops
            .iter()
            .map(|(points, fit)| LoopDrawing {
                points,
                curve: &fit.curve,
                ellipse: fit.ellipse_curve(),
            })
            .collect();
        let title = format!("offset {offset:.4}: {} loop(s)", loops.len());
        let panel = loops_panel(title, &drawings, u, w);
        panels.push(panel);
    }
    panels
}
