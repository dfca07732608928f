//! `trigbody loft SECTIONS.json [--select X,Y,Z] -o PART.json`: skin
//! cross-section curves into a part and write it as a model file.

use crate::cmd_fit::parse_vec3;
use crate::exit::bad;
use anyhow::Result;
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use trigbody_core::internals::surface::part::DEFAULT_CURVES_PER_PATCH;
use trigbody_core::{CapKind, Part, PartOptions, Point3, Real, Skinning, TrigCurve, Vec3};
use trigbody_io::model::{read_curve_levels, write_model, Model, ModelPart};

/// Skinning schemes, one to one with [`Skinning`].
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum SkinningFlag {
    /// C1 cubic Hermite with chord-length-aware Catmull-Rom tangents (default, measured best).
    CatmullRom,
    /// C2 natural cubic spline.
    NaturalSpline,
    /// The paper's patches of K curves chained by Eq. 17.
    PaperChained,
    /// The paper's patches of K curves without the chaining condition (C0).
    PaperUnchained,
}

/// How an end is closed.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum CapFlag {
    Open,
    Flat,
    Dome,
}

/// Arguments of `trigbody loft`.
#[derive(Debug, Args)]
pub struct LoftArgs {
    /// The curves: `{"curves": [{frame, a, b}, ...]}` in order along the part,
    /// or `{"sections": [{"curves": [...]}, ...]}` with several loops per level
    /// (then --select picks one per level).
    pub sections: PathBuf,
    /// A point x,y,z in the part: the curve whose centre is nearest to it,
    /// and from there up and down the levels the curve nearest to the last
    /// pick, until the branch ends (the centre jumps by more than the mean
    /// radius or the area changes by more than a factor 2: a crotch, an
    /// armpit).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub select: Option<Vec3>,
    /// The model file to write (one part).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The part's name (default: the output's file stem).
    #[arg(long)]
    pub name: Option<String>,
    /// The skinning scheme.
    #[arg(long, value_enum, default_value_t = SkinningFlag::CatmullRom)]
    pub skinning: SkinningFlag,
    /// Curves per patch for the paper's schemes.
    #[arg(long, default_value_t = DEFAULT_CURVES_PER_PATCH)]
    pub curves_per_patch: usize,
    /// Chained paper patches also match second derivatives.
    #[arg(long)]
    pub curvature_continuity: bool,
    /// Keep the curves' parameters as given (no twist alignment).
    #[arg(long)]
    pub no_align_twist: bool,
    /// How the first curve's end is closed.
    #[arg(long, value_enum, default_value_t = CapFlag::Open)]
    pub start_cap: CapFlag,
    /// How the last curve's end is closed.
    #[arg(long, value_enum, default_value_t = CapFlag::Open)]
    pub end_cap: CapFlag,
    /// Dome height relative to the end curve's mean radius.
    #[arg(long, default_value_t = trigbody_core::internals::surface::cap::DEFAULT_DOME_HEIGHT)]
    pub dome_height: Real,
    /// The unit of the coordinates, recorded in the model file.
    #[arg(long, default_value = "m")]
    pub units: String,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
}

fn centre(c: &TrigCurve) -> Point3 {
    let w = c.world_series();
    Vec3::new(w.x.c[0], w.y.c[0], w.z.c[0])
}

fn mean_radius(c: &TrigCurve) -> Real {
    (c.area().abs() / std::f64::consts::PI).sqrt()
}

/// True when `next` continues the branch of `prev`: its centre moves by less
/// than `prev`'s mean radius and its area is within a factor 2 (a merge or a
/// split, such as the crotch, ends the branch).
fn continues(prev: &TrigCurve, next: &TrigCurve) -> bool {
    let ratio = next.area().abs() / prev.area().abs();
    centre(next).distance(centre(prev)) < mean_radius(prev) && (0.5..=2.0).contains(&ratio)
}

/// One curve per level. Without a selection every level must hold exactly
/// one curve. With one, the part is the branch through the curve whose
/// centre is nearest to the point: from there up and down the levels, the
/// curve nearest to the previous pick, as long as it continues the branch
/// (see [`continues`]).
fn choose(levels: Vec<Vec<TrigCurve>>, select: Option<Vec3>, file: &str) -> Result<Vec<TrigCurve>> {
    let Some(point) = select else {
        return levels
            .into_iter()
            .enumerate()
            .filter(|(_, l)| !l.is_empty())
            .map(|(i, mut level)| match level.len() {
                1 => Ok(level.remove(0)),
                n => Err(bad(format!(
                    "{file}: level {i} has {n} curves; choose the part with --select x,y,z"
                ))),
            })
            .collect();
    };
    let seed = levels
        .iter()
        .enumerate()
        .flat_map(|(i, l)| {
            l.iter()
                .enumerate()
                .map(move |(k, c)| (i, k, centre(c).distance(point)))
        })
        .min_by(|a, b| a.2.total_cmp(&b.2))
        .ok_or_else(|| bad(format!("{file}: no curves")))?;
    let nearest = |level: &[TrigCurve], prev: &TrigCurve| -> Option<TrigCurve> {
        level
            .iter()
            .min_by(|a, b| {
                centre(a)
                    .distance(centre(prev))
                    .total_cmp(&centre(b).distance(centre(prev)))
            })
            .filter(|c| continues(prev, c))
            .cloned()
    };
    let first = levels[seed.0][seed.1].clone();
    let mut below = Vec::new();
    let mut prev = first.clone();
    for level in levels[..seed.0].iter().rev() {
        match nearest(level, &prev) {
            Some(c) => {
                prev = c.clone();
                below.push(c);
            }
            None => break,
        }
    }
    below.reverse();
    below.push(first.clone());
    let mut prev = first;
    for level in &levels[seed.0 + 1..] {
        match nearest(level, &prev) {
            Some(c) => {
                prev = c.clone();
                below.push(c);
            }
            None => break,
        }
    }
    Ok(below)
}

pub fn run(args: LoftArgs) -> Result<()> {
    let file = args.sections.display().to_string();
    let reader = std::fs::File::open(&args.sections).map_err(|e| bad(format!("{file}: {e}")))?;
    let levels = read_curve_levels(std::io::BufReader::new(reader), &file)
        .map_err(|e| bad(format!("{file}: {e}")))?;
    let curves = choose(levels, args.select, &file)?;
    let cap = |c: CapFlag| match c {
        CapFlag::Open => CapKind::Open,
        CapFlag::Flat => CapKind::Flat,
        CapFlag::Dome => CapKind::Dome {
            relative_height: args.dome_height,
            fullness: 1.0,
            axis: trigbody_core::DomeAxis::Tangent,
        },
    };
    let options = PartOptions {
        skinning: match args.skinning {
            SkinningFlag::CatmullRom => Skinning::CatmullRom,
            SkinningFlag::NaturalSpline => Skinning::NaturalSpline,
            SkinningFlag::PaperChained => Skinning::PaperChained,
            SkinningFlag::PaperUnchained => Skinning::PaperUnchained,
        },
        curves_per_patch: args.curves_per_patch,
        curvature_continuity: args.curvature_continuity,
        align_twist: !args.no_align_twist,
        start_cap: cap(args.start_cap),
        end_cap: cap(args.end_cap),
    };
    let count = curves.len();
    let part = Part::new(curves, &options).map_err(|e| bad(format!("{file}: {e}")))?;
    let name = args.name.clone().unwrap_or_else(|| {
        args.output
            .file_stem()
            .map_or("part".to_string(), |s| s.to_string_lossy().into_owned())
    });
    let model = Model {
        units: args.units.clone(),
        body: None,
        parts: vec![ModelPart {
            name,
            part,
            cavity_of: None,
        }],
        transitions: Vec::new(),
    };
    let mut bytes = Vec::new();
    write_model(&mut bytes, &model)?;
    crate::output::write_file(&args.output, &bytes, &[&args.sections], args.force)?;
    let part = &model.parts[0].part;
    let twist = part
        .twist()
        .iter()
        .map(|t| t.abs().to_degrees())
        .fold(0.0, Real::max);
    crate::exit::print(&format!(
        "{}: {count} curves, {} patches, length {:.4} {}, {} design parameters, skinning {}, largest twist correction {twist:.1}°\n",
        args.output.display(),
        part.segments().len(),
        part.length(),
        model.units,
        part.design_parameters(),
        options.skinning.name()
    ))?;
    Ok(())
}
