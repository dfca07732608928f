//! `trigbody fit [FILE|-]`: fit one loop and report it.

use crate::exit::{bad, print};
use crate::output::write_file;
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use std::io::Read;
use std::path::{Path, PathBuf};
use trigbody_core::{fit_loop, fit_loop_2d};
use trigbody_core::{
    FitOptions, LoopFit, OrderChoice, Parameterization, Real, Vec2, Vec3, Weighting,
};
use trigbody_io::fit_json::loop_fit_json;
use trigbody_io::loop_text::{read_loop, LoopPoints};
use trigbody_render::{plot_panels, Curve2, ImageFormat, Panel, PlotOptions};

/// Flags of the curve fit, shared by every command that fits loops. Each maps
/// one to one onto a field of [`FitOptions`].
#[derive(Debug, Clone, Args)]
pub struct FitFlags {
    /// Order J of the series, or `auto` for the smallest that meets the tolerances.
    #[arg(long, default_value = "auto", value_parser = parse_order)]
    pub order: OrderChoice,
    /// Average relative error tolerance E_a (paper Eq. 12).
    #[arg(long, default_value_t = 0.01, value_parser = crate::bounds::tolerance_ea)]
    pub ea: Real,
    /// Maximum relative error tolerance E_M (paper Eq. 12).
    #[arg(long, default_value_t = 0.05, value_parser = crate::bounds::tolerance_em)]
    pub em: Real,
    /// Highest order `auto` may choose.
    #[arg(long, default_value_t = trigbody_core::internals::curve::order::DEFAULT_MAX_ORDER,
          value_parser = crate::bounds::count_in(1usize, MAX_ORDER))]
    pub max_order: usize,
    /// Parameter values of the points: chord length or polar angle.
    #[arg(long, value_enum, default_value_t = ParamFlag::Chord)]
    pub param: ParamFlag,
    /// Point weights: the arc length each point stands for, or uniform (the paper's).
    #[arg(long, value_enum, default_value_t = WeightFlag::Arc)]
    pub weighting: WeightFlag,
    /// Smoothness penalty on high harmonics (0 = plain least squares).
    #[arg(long, default_value_t = 0.0, value_parser = crate::bounds::non_negative, allow_hyphen_values = true)]
    pub smoothing: Real,
    /// The points' scatter (standard deviation, in their units): `auto`
    /// stops at the order that follows the shape, not the scatter (0 =
    /// none; `sections` on a scan uses the scan's measured noise)
    #[arg(long, default_value_t = 0.0, value_parser = crate::bounds::non_negative, allow_hyphen_values = true)]
    pub noise: Real,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ParamFlag {
    Chord,
    Polar,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum WeightFlag {
    Uniform,
    Arc,
}

/// The highest order `--order` and `--max-order` accept (a loop of order
/// J needs 2J + 1 points; no body section has 20 000).
pub const MAX_ORDER: usize = 10_000;

fn parse_order(s: &str) -> Result<OrderChoice, String> {
    if s.eq_ignore_ascii_case("auto") {
        return Ok(OrderChoice::Auto);
    }
    match s.parse::<usize>() {
        Ok(0) => Err("the order must be at least 1".into()),
        Ok(j) if j > MAX_ORDER => Err(format!("the order must be at most {MAX_ORDER}")),
        Ok(j) => Ok(OrderChoice::Fixed(j)),
        Err(_) => Err(format!(
            "'{s}' is neither a positive whole number nor 'auto'"
        )),
    }
}

/// A direction x,y,z: three finite numbers, not all zero.
pub fn parse_nonzero_vec3(s: &str) -> Result<Vec3, String> {
    let v = parse_vec3(s)?;
    if v.norm() > 0.0 {
        Ok(v)
    } else {
        Err(format!(
            "'{s}' is the zero vector, which gives no direction"
        ))
    }
}

pub fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<Real> = s
        .split(',')
        .map(|t| t.trim().parse::<Real>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}' is not three numbers x,y,z"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("'{s}' is not three finite numbers x,y,z")),
    }
}

impl FitFlags {
    /// The fit options these flags describe.
    pub fn options(&self) -> FitOptions {
        FitOptions {
            order: self.order,
            ea: self.ea,
            em: self.em,
            max_order: self.max_order,
            param: match self.param {
                ParamFlag::Chord => Parameterization::Chord,
                ParamFlag::Polar => Parameterization::Polar,
            },
            weighting: match self.weighting {
                WeightFlag::Uniform => Weighting::Uniform,
                WeightFlag::Arc => Weighting::ArcLength,
            },
            smoothing: self.smoothing,
            noise: self.noise,
            ..FitOptions::default()
        }
    }
}

/// Arguments of `trigbody fit`.
#[derive(Debug, Args)]
pub struct FitArgs {
    /// The loop: lines of `x y` or `x y z` (commas or whitespace, `#` comments);
    /// `-` or nothing reads standard input.
    pub file: Option<PathBuf>,
    #[command(flatten)]
    pub fit: FitFlags,
    /// The reference direction x,y,z: v = 0 where the ray from the centroid along it crosses the loop.
    #[arg(long, value_parser = parse_nonzero_vec3, allow_hyphen_values = true)]
    pub reference: Option<Vec3>,
    /// The direction the loop's normal should point along, x,y,z (3D loops).
    #[arg(long, value_parser = parse_nonzero_vec3, allow_hyphen_values = true)]
    pub normal: Option<Vec3>,
    /// Fit a 3D loop that is far from planar anyway (projected, with a warning).
    #[arg(long)]
    pub allow_non_planar: bool,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Draw the points, the trig curve and the ellipse to FILE.svg or FILE.png.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Replace an existing output file (the input is never replaced).
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: FitArgs) -> Result<()> {
    let (points, name) = match args.file.as_deref() {
        None => (read_stdin()?, "-".to_string()),
        Some(p) if p == Path::new("-") => (read_stdin()?, "-".to_string()),
        Some(p) => {
            let f = std::fs::File::open(p).map_err(|e| bad(format!("{}: {e}", p.display())))?;
            (
                read_loop(f, &p.display().to_string()).map_err(bad)?,
                p.display().to_string(),
            )
        }
    };
    let plot_format = match &args.plot {
        Some(p) => Some(image_format(p)?),
        None => None,
    };
    let mut opts = args.fit.options();
    opts.reference = args.reference;
    opts.normal = args.normal;
    opts.allow_non_planar = args.allow_non_planar;
    let fit = fit_points(&points, &opts).map_err(|e| bad(format!("{name}: {e}")))?;
    for w in &fit.warnings {
        crate::exit::diag(format_args!("trigbody: warning: {name}: {w}"));
    }
    let mut out = if args.json {
        serde_json::to_string_pretty(&loop_fit_json(&fit)).context("encoding JSON")? + "\n"
    } else {
        fit_table(&name, &points, &fit)
    };
    if let (Some(path), Some(format)) = (&args.plot, plot_format) {
        let panel = fit_panel(&name, &points, &fit);
        let bytes = plot_panels(&[panel], format, &PlotOptions::default())?;
        write_file(path, &bytes, args.file.as_deref().as_slice(), args.force)?;
        if !args.json {
            out += &format!("plot written to {}\n", path.display());
        }
    }
    print(&out)
}

fn read_stdin() -> Result<LoopPoints> {
    let mut buf = Vec::new();
    std::io::stdin()
        .read_to_end(&mut buf)
        .context("reading standard input")?;
    read_loop(&buf[..], "-").map_err(bad)
}

/// Fits 2D or 3D points.
pub fn fit_points(
    points: &LoopPoints,
    opts: &FitOptions,
) -> Result<LoopFit, trigbody_core::FitError> {
    match points {
        LoopPoints::Planar(p) => fit_loop_2d(p, opts),
        LoopPoints::Spatial(p) => fit_loop(p, opts),
    }
}

/// The image format of an output path, or a bad-input error naming it.
pub fn image_format(path: &Path) -> Result<ImageFormat> {
    let ext = crate::output::output_extension(path, "svg");
    ImageFormat::from_path(&Path::new("plot").with_extension(ext)).ok_or_else(|| {
        bad(format!(
            "{}: unknown picture format; use a .svg or .png file name",
            path.display()
        ))
    })
}

fn pct(x: Real) -> String {
    if x < 1e-4 {
        format!("{:.2e} %", 100.0 * x)
    } else {
        format!("{:.3} %", 100.0 * x)
    }
}

/// The human-readable report of one fit.
pub fn fit_table(name: &str, points: &LoopPoints, fit: &LoopFit) -> String {
    let dim = match points {
        LoopPoints::Planar(_) => "2D",
        LoopPoints::Spatial(_) => "3D",
    };
    let mut s = format!(
        "{name}: {} points ({dim}), {} dropped as duplicates{}\n",
        fit.plane_points.len(),
        fit.dropped,
        if fit.reversed {
            ", reversed to run counter-clockwise"
        } else {
            ""
        }
    );
    if dim == "3D" {
        s += &format!(
            "  plane: normal {:?}, largest out-of-plane distance {:.3e}\n",
            round3(fit.curve.frame.normal()),
            fit.plane_deviation
        );
    }
    s += &format!(
        "  {:<14} {:>6} {:>12} {:>12} {:>12}  {}\n",
        "", "order", "E_a", "E_M", "rms dist", "meets"
    );
    s += &format!(
        "  {:<14} {:>6} {:>12} {:>12} {:>12.4e}  {}\n",
        "trig series",
        fit.order,
        pct(fit.errors.ea),
        pct(fit.errors.em),
        fit.errors.rms,
        if fit.met { "yes" } else { "no" }
    );
    if let Some(e) = &fit.ellipse {
        s += &format!(
            "  {:<14} {:>6} {:>12} {:>12} {:>12.4e}  {}\n",
            "ellipse",
            1,
            pct(e.errors.ea),
            pct(e.errors.em),
            e.errors.rms,
            if e.errors.meets(fit.tolerances.0, fit.tolerances.1) {
                "yes"
            } else {
                "no"
            }
        );
    }
    let tried: Vec<String> = fit.orders_tried.iter().map(|j| j.to_string()).collect();
    s += &format!(
        "  order search: paper's interpolation tried J = {} → {}; exact minimum {}\n",
        tried.join(", "),
        fit.paper_order.map_or("none met".into(), |j| j.to_string()),
        fit.minimal_order
            .map_or("none met".into(), |j| j.to_string()),
    );
    s += &format!(
        "  design parameters: {} (2×{} coefficients + origin + frame); perimeter {:.6}, area {:.6}\n",
        fit.curve.design_parameters(),
        fit.curve.a.len(),
        fit.curve.perimeter(),
        fit.curve.area()
    );
    s
}

fn round3(v: Vec3) -> [Real; 3] {
    v.to_array().map(|x| (x * 1000.0).round() / 1000.0)
}

/// A plot panel of one fit: the points, the trig curve and the ellipse, in
/// the input's own coordinates for 2D loops and in plane coordinates about
/// the centroid for 3D loops.
pub fn fit_panel(name: &str, points: &LoopPoints, fit: &LoopFit) -> Panel {
    let offset = match points {
        LoopPoints::Planar(_) => Vec2::new(fit.curve.frame.origin.x, fit.curve.frame.origin.y),
        LoopPoints::Spatial(_) => Vec2::ZERO,
    };
    let shift = |v: Vec<Vec2>| v.into_iter().map(|p| p + offset).collect::<Vec<_>>();
    let mut curves = vec![Curve2 {
        label: format!(
            "trig J={}: E_a {}, E_M {}",
            fit.order,
            pct(fit.errors.ea),
            pct(fit.errors.em)
        ),
        points: shift(fit.curve.sample_plane(400)),
        color: (20, 150, 40),
        closed: true,
    }];
    if let (Some(e), Some(c)) = (&fit.ellipse, fit.ellipse_curve()) {
        curves.push(Curve2 {
            label: format!(
                "ellipse: E_a {}, E_M {}",
                pct(e.errors.ea),
                pct(e.errors.em)
            ),
            points: shift(c.sample_plane(400)),
            color: (30, 60, 220),
            closed: true,
        });
    }
    Panel {
        title: name.to_string(),
        points: shift(fit.plane_points.clone()),
        points_label: format!("input ({} points)", fit.plane_points.len()),
        faint_points: false,
        curves,
    }
}
