//! A whole body model reconstructed from a mesh or a scanned point cloud
//! (issue 5, method.md §6-§8): [`reconstruct`] segments the input, cuts every
//! part across its own axis, fits each loop with the smallest order that
//! meets the tolerances, skins the parts, closes their free ends and
//! measures the result against the input ([`Report`]).
//!
//! # The pipeline
//!
//! 1. **Segmentation** ([`segment`]): the body's frame (up, front, left),
//!    landmarks and one smoothed axis per part.
//! 2. **Sections.** Each part is cut by planes perpendicular to its axis
//!    ([`cut_part`]), spaced [`ReconstructOptions::spacing`] × `H` apart
//!    (`H` the body's height), and each loop is fitted by [`fit_loop`] with
//!    the body's front as the reference direction (where `v = 0` lies) and
//!    the axis as the plane normal, so every section of a part starts at
//!    the front and runs the same way: no twist between sections. Scan
//!    loops use [`scan_fit_options`] (the smoothness penalty that bridges
//!    the scanner's holes, tolerances no lower than the scan's noise).
//! 3. **Parts and ends.**
//!    * Torso: crotch → neck, both ends open (the legs hang below its
//!      first section, the head sits on its last).
//!    * Head: neck → head top. Sections run while the loop stays at least
//!      [`ReconstructOptions::end_area_fraction`] of the part's largest
//!      loop beyond it, then a dome reaches the head top: its height
//!      `h = d / r`, `d` the distance from the last section's centre to the
//!      head top along the axis, `r = √(A/π)` the last loop's mean radius.
//!    * Arms: shoulder → hand tip, the same rule past the wrist, held
//!      against the wrist's loop on a mesh (past the palm a mesh's loop is
//!      the fingers' own outline: it runs on while they lie together and
//!      ends where one finger is cut alone) and against the largest (the
//!      palm with its thumb) on a scan (whose slab there merges fingers,
//!      thumb and gaps into blobs): a mitten-like dome to the hand tip.
//!      Where the fingers are apart (on a scan: apart past each level,
//!      [`crate::section::cloud::superlevel`]), the palm ends flat where
//!      they part and each finger is a digit of its own (`digits.rs`).
//!    * Legs with feet (shoe-like): crotch → ankle along the leg's axis,
//!      then straight down along `−up` to just above the floor, so the
//!      sections below the ankle are horizontal outlines of the whole foot
//!      (heel to toes), until the outline shrinks below
//!      [`ReconstructOptions::sole_area_fraction`] of the largest (where the
//!      sole curves up at heel and toes); a shallow dome from the last
//!      outline down to the foot's own bottom below its centre (the input's
//!      lowest points under that outline, never below the floor: a foot
//!      lifted by a bent knee ends above it) closes the sole (a flat cap
//!      there would stand off the sole). The segmentation's
//!      foot parts are reported as found and covered by the legs.
//!
//!    Sections whose loop cannot be cut or fitted are skipped with a
//!    warning; when two consecutive planes cross inside the curves (where a
//!    tilted axis turns), the later section is dropped.
//! 4. **Transitions** ([`crate::surface::transition`], method.md §6): each leg's
//!    first section joins its half of the torso's first curve (split at
//!    the crotch by the plane normal to the body's left axis, closed by a
//!    seam dipping to the crotch's level) through a Hermite surface with
//!    the parts' own end tangents, magnitudes fitted to the input; the two
//!    close the torso's bottom (flat cap instead if one cannot be built).
//!    Torso and head get one where their end sections are apart (on the
//!    shared bodies they share the neck's plane, so none is built).
//! 5. **Cavities** ([`BodyCavity`], `cavity.rs`): on a mesh, the loops
//!    nested in the head's horizontal loops (a modelled mouth's inside),
//!    followed level to level and skinned as a closed pocket: empty space
//!    inside the head, its surface facing into it.
//! 6. **Report**: design parameters (method.md §7, transitions included)
//!    against 3 × the input's vertices, and distances both ways in
//!    millimetres, coverage of the whole input and of its outer surface
//!    (see [`Report`]).
//!
//! Nothing here knows units, coordinates or vertex order: lengths are
//! fractions of `H`; [`ReconstructOptions::units`] only converts the
//! report's distances to millimetres.

use crate::anatomy::{BodyFrame, BodyGeometry, LandmarkKind, PartName};
use crate::curve::fit::{fit_loop, FitOptions, LoopFit};
use crate::curve::trig::TrigCurve;
use crate::geom::math::{mean_radius, Point3, Real, Vec3};
use crate::geom::mesh::{Mesh, PointCloud};
use crate::geom::rigid::Rigid;
use crate::section::cloud::scan_fit_options;
use crate::section::mesh::SectionLoop;
use crate::segment::{segment, Cutter, PartAxis, SegmentError, SegmentOptions, Segmentation};
use crate::spatial::cloud_clean::CleanOptions;
use crate::spatial::distance::{sample_surface, DistanceStats, MeshDistance};
use crate::spatial::point_grid::PointGrid;
use crate::surface::cap::{CapKind, DomeAxis};
use crate::surface::part::{Part, PartError, PartOptions};
use crate::surface::pieces::{tessellate_pieces, Piece};
use crate::surface::tessellate::{TessellateError, TessellationOptions};
use crate::surface::transition::{fit_magnitudes, Seam, SideCut, Transition, TransitionSpec};
use rayon::prelude::*;
use std::fmt;
use thiserror::Error;

mod attach;
mod cavity;
mod digits;
mod fit;
mod frames;
mod plan;
mod pose;
pub mod rate;
mod repeat;
mod report;
mod transitions;
mod validate;

pub use cavity::*;
pub use digits::*;
pub use fit::{FitMode, GlobalFitOptions, PartFit};
use plan::*;
pub use report::*;
pub use validate::{validate_input, InputError, HUMAN_EXTENT_M};

/// The unit of the input's coordinates (the report is in millimetres).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Units {
    /// Metres (the default: the built-in body's unit).
    #[default]
    Metres,
    /// Centimetres.
    Centimetres,
    /// Millimetres.
    Millimetres,
}

impl Units {
    /// Millimetres per input unit.
    pub fn to_mm(self) -> Real {
        match self {
            Units::Metres => 1000.0,
            Units::Centimetres => 10.0,
            Units::Millimetres => 1.0,
        }
    }
    /// The symbol written in model files: `m`, `cm`, `mm`.
    pub fn symbol(self) -> &'static str {
        match self {
            Units::Metres => "m",
            Units::Centimetres => "cm",
            Units::Millimetres => "mm",
        }
    }
    /// The unit of a symbol (`m`, `cm`, `mm`).
    pub fn from_symbol(s: &str) -> Option<Units> {
        match s {
            "m" => Some(Units::Metres),
            "cm" => Some(Units::Centimetres),
            "mm" => Some(Units::Millimetres),
            _ => None,
        }
    }
}

impl fmt::Display for Units {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// Options of [`reconstruct`]; lengths are fractions of the body's height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReconstructOptions {
    /// Segmentation (up and front axes, slices). Default: found from the data.
    pub segment: SegmentOptions,
    /// Fit tolerances and order choice (default E_a ≤ 1 %, E_M ≤ 5 %,
    /// automatic order).
    pub fit: FitOptions,
    /// Section spacing along a part's axis as a fraction of the height.
    /// Default 0.012 (about 2 cm on a 1.7 m body).
    pub spacing: Real,
    /// Section spacing below the ankle (the foot's outline changes fast
    /// there), as a fraction of the height. Default 0.004.
    pub foot_spacing: Real,
    /// Spacing of a digit's (a finger's) sections, as a fraction of the
    /// height: every this much of the levels [`DIGIT_SPACING`] apart the
    /// fingers are followed at. Default 0.008 (every second level: a
    /// finger is a smooth tube); the rate search scales it.
    pub digit_spacing: Real,
    /// A rounded end (head top, hand) ends its sections where the loop has
    /// shrunk below this fraction of the largest loop beyond the part's
    /// middle (head) or wrist (a scan's hand), or of the wrist's loop (a
    /// mesh's hand); a dome closes the rest. Default 0.5.
    pub end_area_fraction: Real,
    /// The foot's sections end where its outline shrinks below this fraction
    /// of its largest outline below the ankle (the sole curving up at the
    /// heel and toes, or a lifted foot's tilted sole, which the outlines
    /// follow down to the heel); a dome down to the foot's bottom closes
    /// it. Default 0.5.
    pub sole_area_fraction: Real,
    /// Height of the lowest foot section above the floor, as a fraction of
    /// the height. Default 0.002.
    pub sole_height: Real,
    /// Skinning of every part (caps are chosen by the pipeline).
    /// Default [`PartOptions::default`] (Catmull-Rom, twist aligned).
    pub part: PartOptions,
    /// The input's unit (the report converts to millimetres). Default metres.
    pub units: Units,
    /// Infer the unit instead (`units` is then not read): the one of m, cm
    /// and mm under which the input's extent is a human height
    /// ([`HUMAN_EXTENT_M`]); an error names the candidates when none or
    /// several are. Default false: a unit is a fact about the file, and a
    /// guess, even a checked one, should be asked for.
    pub infer_units: bool,
    /// Scan loops carry the scanner's noise (about 1 mm, several per cent of
    /// an arm's radius), which no order should reproduce: their tolerances
    /// are `E_a`, `E_M` times this factor, and no lower than the scan's
    /// measured noise gives ([`crate::curve::noise`]). Default 2 (1 gave
    /// the corpus scans 35 % more parameters for 0.04 mm nearer on average,
    /// well within what any small change moves a scan's result).
    pub scan_tolerance_factor: Real,
    /// A section is dropped when a quarter of its curve lies farther than
    /// this fraction of the height from the input (a wrongly joined scan
    /// loop). Default 0.006 (1 cm on 1.73 m).
    pub max_curve_offset: Real,
    /// Rounds of adaptive refinement (see `refine`). Default 3.
    pub refine_rounds: usize,
    /// A section is added where the surface strays farther than this
    /// fraction of the height from the input halfway between two sections.
    /// Default 0.003 (5.2 mm on 1.73 m; half of it adds parameters, not
    /// accuracy).
    pub refine_tolerance: Real,
    /// Sections are never added closer than this fraction of the height.
    /// Default 0.002.
    pub min_spacing: Real,
    /// After the refinement, a section is dropped where the surface
    /// skinned through the others passes its loop within this fraction of
    /// the height beyond its own fit's error (the 90th percentile of the
    /// loop's distances; `plan/prune.rs`); 0 keeps every section. Default
    /// 0.0003 (0.5 mm on 1.73 m: about 30 % fewer parameters for 0.01 mm
    /// more RMS on the corpus).
    pub prune_tolerance: Real,
    /// Points sampled on each surface for the distances. Default 60 000.
    pub report_samples: usize,
    /// Tessellation edge length for the measured model surface, as a
    /// fraction of the height. Default 0.003 (5 mm on 1.7 m).
    pub report_edge: Real,
    /// Coverage distance in millimetres: an input point is covered when the
    /// model passes within it. Default 5.
    pub coverage_mm: Real,
    /// The report measures the model's outer skin ([`crate::surface::skin`]): a
    /// triangle of one piece is left out when its centroid lies inside
    /// another piece deeper than this fraction of the height. Default
    /// 0.0003 (0.5 mm on 1.73 m: where two pieces' surfaces nearly
    /// coincide, both stay).
    pub skin_depth: Real,
    /// A scan's floor and stray points removed before segmentation
    /// ([`crate::spatial::cloud_clean`]; its `up` is taken from `segment.up`).
    pub clean: CleanOptions,
    /// A scan is reconstructed in this many frames (its own, then turned
    /// about its up axis in 15° steps) and the model nearest its input
    /// kept (`body/frames.rs`); 1 reconstructs it once. Meshes are
    /// reconstructed once, in their own frame. Default 3.
    pub scan_frames: usize,
    /// The parts fitted to every input point by least squares after they
    /// are built (`body/fit.rs`).
    pub global_fit: GlobalFitOptions,
}

impl Default for ReconstructOptions {
    fn default() -> Self {
        ReconstructOptions {
            segment: SegmentOptions::default(),
            fit: FitOptions::default(),
            spacing: 0.012,
            foot_spacing: 0.004,
            digit_spacing: 0.008,
            end_area_fraction: 0.5,
            sole_height: 0.002,
            sole_area_fraction: 0.5,
            part: PartOptions::default(),
            units: Units::Metres,
            infer_units: false,
            scan_tolerance_factor: 2.0,
            max_curve_offset: 0.006,
            refine_rounds: 3,
            refine_tolerance: 0.003,
            min_spacing: 0.002,
            prune_tolerance: 0.0003,
            report_samples: 60_000,
            report_edge: 0.003,
            coverage_mm: 5.0,
            skin_depth: 0.0003,
            clean: CleanOptions::default(),
            scan_frames: 3,
            global_fit: GlobalFitOptions::default(),
        }
    }
}

/// The largest [`ReconstructOptions::prune_tolerance`] (a twentieth of
/// the height: past it a part keeps little more than its ends).
pub const MAX_PRUNE_TOLERANCE: Real = 0.05;

/// The most frames [`ReconstructOptions::scan_frames`] allows: 6 frames
/// 15° apart span the 90° after which an axis-aligned grid repeats.
pub const MAX_SCAN_FRAMES: usize = 6;

/// What went wrong in [`reconstruct`].
#[derive(Debug, Error, PartialEq)]
pub enum ReconstructError {
    /// The input is not one human body in its unit, or is malformed.
    #[error("{0}")]
    Input(#[from] InputError),
    /// Segmentation failed: the message names what was not found.
    #[error("segmentation: {0}")]
    Segment(#[from] SegmentError),
    /// The segmentation's frame is not a frame (not finite, or up and
    /// front parallel).
    #[error("the body's frame is degenerate: {frame:?}")]
    Frame { frame: BodyFrame },
    /// A bad option value.
    #[error("bad option {name} = {value}: {why}")]
    BadOption {
        name: &'static str,
        value: Real,
        why: &'static str,
    },
    /// A part had fewer than two usable sections.
    #[error(
        "{part}: only {count} usable section(s) could be cut and fitted (at least 2 are needed)"
    )]
    TooFewSections { part: PartName, count: usize },
    /// Skinning a part failed.
    #[error("{part}: {source}")]
    Part {
        part: PartName,
        #[source]
        source: PartError,
    },
    /// A transition could not be rebuilt (moving a body).
    #[error("transition {from} -> {to}: {why}")]
    Transition {
        from: PartName,
        to: PartName,
        why: String,
    },
    /// Tessellating a part for the measurements failed.
    #[error("{part}: {source}")]
    Tessellate {
        part: PartName,
        #[source]
        source: TessellateError,
    },
}

/// The fit summary of one section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionFit {
    /// Arc-length fraction along the part's (possibly extended) axis.
    pub at: Real,
    pub order: usize,
    pub ea: Real,
    pub em: Real,
    /// True when the tolerances were met.
    pub met: bool,
    /// The ellipse baseline's `(E_a, E_M)` on the same loop.
    pub ellipse: Option<(Real, Real)>,
}

impl SectionFit {
    /// What the report says of a loop's fit at the axis fraction `at`.
    pub fn of(at: Real, fit: &LoopFit) -> SectionFit {
        SectionFit {
            at,
            order: fit.order,
            ea: fit.errors.ea,
            em: fit.errors.em,
            met: fit.met,
            ellipse: fit.ellipse.as_ref().map(|e| (e.errors.ea, e.errors.em)),
        }
    }
}

/// One reconstructed part.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyPart {
    pub name: PartName,
    pub part: Part,
    /// One entry per section of `part`, in order.
    pub fits: Vec<SectionFit>,
}

/// A transition surface between two parts of a body (see
/// [`crate::surface::transition`]): `u = 0` on `from`, `u = 1` on `to`.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyTransition {
    pub from: PartName,
    pub to: PartName,
    pub transition: Transition,
}

/// A reconstructed body: skinned parts with their caps and the transitions
/// between them, in the input's frame and units.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub units: Units,
    /// The body's frame from the segmentation.
    pub frame: BodyFrame,
    /// Soles to head top, in input units.
    pub height: Real,
    pub parts: Vec<BodyPart>,
    /// Transitions: each leg to its half of the torso's bottom (the two
    /// close the torso's bottom), and the torso to the head where their
    /// end sections do not coincide.
    pub transitions: Vec<BodyTransition>,
    /// The fingers of hands whose fingers are apart in the input
    /// ([`BodyDigit`]): solid parts overlapping the palm's end.
    pub digits: Vec<BodyDigit>,
    /// Pockets of skin inside parts (a modelled mouth, [`BodyCavity`]):
    /// empty space inside the body, their surfaces facing into it.
    pub cavities: Vec<BodyCavity>,
}

impl Body {
    /// Design parameters (method.md §7): every section's coefficients,
    /// origin and frame, plus one height per dome cap (and its fullness and
    /// axis when not the defaults), for the parts and the cavities, plus each
    /// transition's ([`Transition::design_parameters`]: two magnitudes, and
    /// a seam's point and normal).
    pub fn design_parameters(&self) -> usize {
        let with_caps = |part: &Part| {
            let o = part.options();
            part.design_parameters()
                + o.start_cap.design_parameters()
                + o.end_cap.design_parameters()
        };
        let parts: usize = self.solids().map(with_caps).sum();
        let cavities: usize = self.cavities.iter().map(|c| with_caps(&c.part)).sum();
        parts
            + cavities
            + self
                .transitions
                .iter()
                .map(|t| t.transition.design_parameters())
                .sum::<usize>()
    }

    /// The numbers the compact `.tbm` file stores for the same surfaces
    /// (docs/model-format.md): each part's (and cavity's) first section
    /// frame whole (9 numbers), every later one in 3 (its plane's tilt and
    /// offset from the previous section's; the rotation and shift within
    /// the plane go into the coefficients), the rest as counted by
    /// [`Body::design_parameters`].
    pub fn compact_numbers(&self) -> usize {
        let later_frames: usize = self
            .solids()
            .chain(self.cavities.iter().map(|c| &c.part))
            .map(|p| p.sections().len().saturating_sub(1))
            .sum();
        self.design_parameters() - 6 * later_frames
    }

    /// The solid parts' surfaces: the parts, then the digits.
    pub fn solids(&self) -> impl Iterator<Item = &Part> {
        let digits = self.digits.iter().map(|d| &d.part);
        self.parts.iter().map(|p| &p.part).chain(digits)
    }

    /// The part of a name.
    pub fn part(&self, name: PartName) -> Option<&BodyPart> {
        self.parts.iter().find(|p| p.name == name)
    }

    /// Tessellates every part, then every transition, every digit and every
    /// cavity into one mesh (in that order), the pieces taken by the cores as they come free.
    pub fn tessellate(&self, options: &TessellationOptions) -> Result<Mesh, ReconstructError> {
        Ok(crate::geom::mesh::concatenate(&self.tessellate_pieces(options)?).0)
    }

    /// Every part's tessellation, then every transition's, every digit's
    /// and every cavity's (the pieces of [`Body::tessellate`], one mesh each; a
    /// cavity's turned to face into the pocket), taken by the cores as
    /// they come free.
    pub fn tessellate_pieces(
        &self,
        options: &TessellationOptions,
    ) -> Result<Vec<Mesh>, ReconstructError> {
        // Each piece with the part it belongs to, for the error (a
        // transition's is its first part's; they do not fail).
        let (owners, pieces): (Vec<PartName>, Vec<Piece>) = self
            .parts
            .iter()
            .map(|p| (p.name, Piece::Part(&p.part)))
            .chain(
                self.transitions
                    .iter()
                    .map(|t| (t.from, Piece::Transition(&t.transition))),
            )
            .chain(self.digits.iter().map(|d| (d.hand, Piece::Part(&d.part))))
            .chain(
                self.cavities
                    .iter()
                    .map(|c| (c.within, Piece::Cavity(&c.part))),
            )
            .unzip();
        tessellate_pieces(&pieces, options).map_err(|(i, source)| ReconstructError::Tessellate {
            part: owners[i],
            source,
        })
    }
}

fn check_options(o: &ReconstructOptions) -> Result<(), ReconstructError> {
    let pos = |name: &'static str, v: Real| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(ReconstructError::BadOption {
                name,
                value: v,
                why: "must be a positive finite number",
            })
        }
    };
    pos("spacing", o.spacing)?;
    pos("foot_spacing", o.foot_spacing)?;
    pos("digit_spacing", o.digit_spacing)?;
    pos("end_area_fraction", o.end_area_fraction)?;
    pos("sole_height", o.sole_height)?;
    pos("sole_area_fraction", o.sole_area_fraction)?;
    pos("report_edge", o.report_edge)?;
    pos("refine_tolerance", o.refine_tolerance)?;
    pos("min_spacing", o.min_spacing)?;
    pos("scan_tolerance_factor", o.scan_tolerance_factor)?;
    pos("max_curve_offset", o.max_curve_offset)?;
    pos("coverage_mm", o.coverage_mm)?;
    pos("skin_depth", o.skin_depth)?;
    if !(o.prune_tolerance.is_finite() && (0.0..=MAX_PRUNE_TOLERANCE).contains(&o.prune_tolerance))
    {
        return Err(ReconstructError::BadOption {
            name: "prune_tolerance",
            value: o.prune_tolerance,
            why: "must be 0 (no pruning) to 0.05 of the height",
        });
    }
    if !(1..=MAX_SCAN_FRAMES).contains(&o.scan_frames) {
        return Err(ReconstructError::BadOption {
            name: "scan_frames",
            value: o.scan_frames as Real,
            why: "must be 1 to 6 (the frames lie 15° apart)",
        });
    }
    if o.spacing > 0.2 || o.foot_spacing > 0.2 {
        return Err(ReconstructError::BadOption {
            name: "spacing",
            value: o.spacing.max(o.foot_spacing),
            why: "must be at most 0.2 of the height",
        });
    }
    Ok(())
}

/// Reconstructs a body model from a mesh or a cloud and measures it (see
/// the module doc). Parts the segmentation did not find (an arm missing
/// from a scan) are left out with a warning; errors name what was not
/// found.
pub fn reconstruct(
    body: BodyGeometry<'_>,
    opts: &ReconstructOptions,
) -> Result<(Body, Report), ReconstructError> {
    reconstruct_with_progress(body, opts, &mut |_| {})
}

/// Where a long computation is, for a progress display: the step that
/// starts now and how many of `total` steps are done (`done == total`
/// once, at the end, with the stage `"done"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress<'a> {
    /// The step starting, e.g. `sections: torso`.
    pub stage: &'a str,
    pub done: usize,
    pub total: usize,
}

impl Progress<'_> {
    /// `done / total` in `[0, 1]`.
    pub fn fraction(&self) -> Real {
        if self.total == 0 {
            1.0
        } else {
            (self.done as Real / self.total as Real).min(1.0)
        }
    }
}

/// Steps [`reconstruct_with_progress`] reports: preparing, segmenting,
/// sections of six parts, skinning, refining six parts, transitions,
/// cavities, measuring.
const RECONSTRUCT_STEPS: usize = 18;

/// [`reconstruct`] calling `progress` as each step starts (preparing the
/// input, segmenting, each part's sections, skinning, each part's
/// refinement, transitions, measuring) and once at the end (see
/// [`Progress`]).
///
/// The input is reconstructed as a copy in its own frame and order
/// (`body/pose.rs`); the model and the report's joints are moved back.
pub fn reconstruct_with_progress(
    body: BodyGeometry<'_>,
    opts: &ReconstructOptions,
    report_progress: &mut dyn FnMut(Progress<'_>),
) -> Result<(Body, Report), ReconstructError> {
    check_options(opts)?;
    let opts = &checked_input(body, opts)?;
    reconstruct_checked(body, opts, report_progress)
}

/// `opts` with the unit of `body` as [`validate_input`] finds it (given,
/// or inferred), once `body` is checked: first, so that a body in the
/// wrong unit is told as such, not as a segmentation that found no head.
fn checked_input(
    body: BodyGeometry<'_>,
    opts: &ReconstructOptions,
) -> Result<ReconstructOptions, ReconstructError> {
    let given = (!opts.infer_units).then_some(opts.units);
    let units = validate_input(body, given)?;
    Ok(ReconstructOptions { units, ..*opts })
}

/// [`reconstruct_with_progress`] of an input [`checked_input`] passed,
/// at options [`check_options`] passed.
fn reconstruct_checked(
    body: BodyGeometry<'_>,
    opts: &ReconstructOptions,
    report_progress: &mut dyn FnMut(Progress<'_>),
) -> Result<(Body, Report), ReconstructError> {
    let mut done = 0;
    let mut progress = |stage: &str| {
        report_progress(Progress {
            stage,
            done: done.min(RECONSTRUCT_STEPS - 1),
            total: RECONSTRUCT_STEPS,
        });
        done += 1;
    };
    progress("preparing the input");
    // The input is moved into its own frame and order (`pose`).
    let own = Some(pose::own_frame(body, opts)?);
    let into = own.as_ref().map(|o| &o.1);
    let (prepared, own_opts) = pose::Prepared::in_own_frame(body, own.as_ref(), opts);
    let result = match prepared.geometry() {
        BodyGeometry::Cloud(cloud) if own_opts.scan_frames > 1 => {
            frames::best_of_frames(cloud, &own_opts, &mut progress)?.0
        }
        input => reconstruct_steps(input, &own_opts, &mut progress)?,
    };
    let (model, report) = finished(result, &prepared, into, opts)?;
    report_progress(Progress {
        stage: "done",
        done: RECONSTRUCT_STEPS,
        total: RECONSTRUCT_STEPS,
    });
    Ok((model, report))
}

/// A model of the input in its own frame (`into` took it there) made the
/// user's: the preparation's warnings first, each warning once, the model
/// and the joints moved back.
fn finished(
    (model, mut report): (Body, Report),
    prepared: &pose::Prepared<'_>,
    into: Option<&Rigid>,
    opts: &ReconstructOptions,
) -> Result<(Body, Report), ReconstructError> {
    let mut warnings = prepared.warnings(&mut report, opts.units);
    warnings.append(&mut report.warnings);
    // A part rebuilt after a dropped section says again what it dropped
    // before: each warning once, in order.
    let mut seen = std::collections::HashSet::new();
    warnings.retain(|w| seen.insert(w.clone()));
    report.warnings = warnings;
    match into {
        Some(into) => frames::turned_back((model, report), &into.inverse()),
        None => Ok((model, report)),
    }
}

fn reconstruct_steps(
    body: BodyGeometry<'_>,
    opts: &ReconstructOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<(Body, Report), ReconstructError> {
    let segmented = Segmented::of(body, opts, progress)?;
    build(&Groundwork::new(&segmented), opts, progress)
}

/// The input segmented (`seg0`), and with the legs continued to the
/// floor (`seg`): what every reconstruction of it shares whatever the
/// curve, pruning and refinement tolerances.
struct Segmented<'a> {
    body: BodyGeometry<'a>,
    seg0: Segmentation,
    seg: Segmentation,
}

impl<'a> Segmented<'a> {
    fn of(
        body: BodyGeometry<'a>,
        opts: &ReconstructOptions,
        progress: &mut dyn FnMut(&str),
    ) -> Result<Segmented<'a>, ReconstructError> {
        progress("segmenting");
        let seg0 = segment(body, &opts.segment)?;
        let seg = legs_to_floor(&seg0, opts);
        Ok(Segmented { body, seg0, seg })
    }
}

/// A segmented input with its cutter (whose slicers and grids are built
/// on first use) and its distance structure.
struct Groundwork<'a> {
    body: BodyGeometry<'a>,
    seg0: &'a Segmentation,
    seg: &'a Segmentation,
    cutter: Cutter<'a>,
    input: InputDistance<'a>,
}

impl<'a> Groundwork<'a> {
    fn new(s: &'a Segmented<'a>) -> Groundwork<'a> {
        let input = match s.body {
            BodyGeometry::Mesh(m) => InputDistance::Mesh(MeshDistance::new(m)),
            BodyGeometry::Cloud(c) => {
                InputDistance::Cloud(PointGrid::new(&c.positions, 0.01 * s.seg0.height))
            }
        };
        Groundwork {
            body: s.body,
            seg0: &s.seg0,
            seg: &s.seg,
            cutter: Cutter::new(s.body, &s.seg),
            input,
        }
    }
}

/// The model and its report from a segmented input (the steps after the
/// segmentation; see the module's notes).
fn build<'a>(
    g: &'a Groundwork<'a>,
    opts: &ReconstructOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<(Body, Report), ReconstructError> {
    let (body, seg0, seg, cutter, input) = (g.body, g.seg0, g.seg, &g.cutter, &g.input);
    let mut warnings = seg0.warnings.clone();
    if cutter.unseen_side().is_some() {
        warnings.push(
            "the scan was seen from one side only (its trunk has no points on one side): \
             the unseen sides are bridged from the seen ones"
                .to_string(),
        );
    }
    let h = seg0.height;
    let up = seg0.frame.up;
    let floor = seg0.frame.origin.dot(up);

    // Horizontal cuts at the crotch itself meet both legs or their merged
    // loop: the torso starts a little above it and the legs a little below.
    let crotch_level = landmark(seg, LandmarkKind::Crotch).map_or(floor + 0.47 * h, |c| c.dot(up));
    // Wider for scans: their slabs are a point spacing thick and the crotch
    // is a scanner hole, where a narrow margin mixes both thighs.
    let margin = match body {
        BodyGeometry::Mesh(_) => 0.6,
        BodyGeometry::Cloud(_) => 1.5,
    } * seg.slice_spacing;
    // The torso's sections, its loops above the armpits clipped as
    // `shoulders` says (see [`Shoulders`]).
    let torso_plan = |shoulders: Shoulders, warnings: &mut Vec<String>| {
        let axis = seg.part(PartName::Torso)?;
        let step = opts.spacing * h / axis.length();
        Some(Plan {
            name: PartName::Torso,
            cuts: cut_all(
                cutter,
                PartName::Torso,
                &fractions(
                    fraction_at_level(axis, up, crotch_level + margin, true),
                    1.0,
                    step,
                ),
                opts,
                shoulders,
                warnings,
            ),
            start_cap: CapKind::Open,
            end_cap: CapKind::Open,
            tip: None,
            end_unchecked: false,
            shoulders,
        })
    };
    let limbs = LimbPlans {
        cutter,
        seg,
        seg0,
        opts,
        floor,
        leg_top: crotch_level - margin,
    };
    let mut shoulders = Shoulders::of(seg);
    // The torso is planned after the arms are built: its loops stop at
    // their first sections. The other parts are planned and built over
    // the cores; their warnings and steps are told in order after.
    let (limb_parts, with_torso) = limbs.parts(&mut warnings);
    let (mut parts, mut digits) = build_limbs(&limbs, &limb_parts, input, &mut warnings, progress);
    if with_torso {
        shoulders = shoulders.with_arms(&parts);
        progress("sections: torso");
        let plan = torso_plan(shoulders, &mut warnings);
        progress("skinning and refining: torso");
        if let Some(plan) = plan {
            let torso = refine(cutter, plan, opts, input, &mut warnings)?;
            let k = parts
                .iter()
                .take_while(|p| p.name < PartName::Torso)
                .count();
            parts.insert(k, torso);
        }
    }
    let (gf, fit_input) = (
        &opts.global_fit,
        fit::FitInput {
            geometry: body,
            height: h,
            mm: opts.units.to_mm(),
        },
    );
    let mut fitted = fit::fit_to_input(&mut parts, &mut digits, &fit_input, gf, None);
    progress("transitions");
    // At most twice: an arm whose side transition fails or strays loses it,
    // and the torso is cut again to reach into that arm instead.
    let transitions = loop {
        let (transitions, poor) = transitions::assemble(
            &mut parts,
            seg,
            crotch_level,
            input,
            shoulders,
            opts.units.to_mm(),
            &mut warnings,
        );
        if poor.iter().all(Option::is_none) {
            break transitions;
        }
        for (k, arm) in [PartName::LeftArm, PartName::RightArm]
            .into_iter()
            .enumerate()
        {
            if let Some(why) = &poor[k] {
                shoulders.side[k] = false;
                warnings.push(format!(
                    "{arm}: the shoulder transition was left out ({why}); the torso reaches into the arm instead"
                ));
            }
        }
        if let Some(plan) = torso_plan(shoulders, &mut warnings) {
            let torso = refine(cutter, plan, opts, input, &mut warnings)?;
            if let Some(t) = parts.iter_mut().find(|p| p.name == PartName::Torso) {
                *t = torso;
            }
            let again =
                fit::fit_to_input(&mut parts, &mut [], &fit_input, gf, Some(PartName::Torso));
            for f in again {
                match fitted.iter_mut().find(|g| g.name == f.name) {
                    Some(g) => *g = f,
                    None => fitted.push(f),
                }
            }
        }
    };
    attach::attach_arms(&mut parts, shoulders, (seg0, opts), &mut warnings);
    attach::attach_digits(&parts, &mut digits, h, &mut warnings);
    progress("cavities");
    let cavities = head_cavities(cutter, &parts, input, opts, &mut warnings);
    let model = Body {
        units: opts.units,
        frame: seg.frame,
        height: h,
        parts,
        transitions,
        digits,
        cavities,
    };
    progress("measuring");
    let mut report = measure_with(body, &model, seg0, opts, warnings, input)?;
    report.fit = fitted;
    Ok((model, report))
}

/// Plans and builds the head, arms and legs over the cores (each arm's
/// digits after its palm: they reach back into it as built), then tells
/// their steps to `progress` and their warnings in order. A part that
/// cannot be built is left out with a warning.
fn build_limbs(
    limbs: &LimbPlans<'_, '_>,
    limb_parts: &[(PartName, &PartAxis)],
    input: &InputDistance<'_>,
    warnings: &mut Vec<String>,
    progress: &mut dyn FnMut(&str),
) -> (Vec<BodyPart>, Vec<BodyDigit>) {
    let (cutter, opts) = (limbs.cutter, limbs.opts);
    let built: Vec<_> = limb_parts
        .par_iter()
        .map(|&(name, axis)| {
            let (mut planning, mut building) = (Vec::new(), Vec::new());
            let (plan, split) = limbs.plan(name, axis, &mut planning);
            let part = refine(cutter, plan, opts, input, &mut building);
            let digits = match (&part, split) {
                (Ok(palm), Some(split)) => {
                    let last = palm.fits.last().map_or(split.palm_end, |f| f.at);
                    build_digits(cutter, name, &split, last, opts, &mut building)
                }
                _ => Vec::new(),
            };
            (name, planning, part, building, digits)
        })
        .collect();
    for (name, planning, ..) in &built {
        progress(&format!("sections: {name}"));
        warnings.extend(planning.iter().cloned());
    }
    progress("skinning");
    let (mut parts, mut digits) = (Vec::new(), Vec::new());
    for (name, _, part, building, hand) in built {
        progress(&format!("skinning and refining: {name}"));
        warnings.extend(building);
        match part {
            Ok(p) => {
                parts.push(p);
                digits.extend(hand);
            }
            Err(e) => warnings.push(format!("{name} left out: {e}")),
        }
    }
    (parts, digits)
}

/// The segmentation with the legs continued straight down to the floor
/// (shoe-like feet).
fn legs_to_floor(seg0: &Segmentation, opts: &ReconstructOptions) -> Segmentation {
    let (h, up) = (seg0.height, seg0.frame.up);
    let floor = seg0.frame.origin.dot(up);
    let mut seg = seg0.clone();
    for p in seg.parts.iter_mut() {
        if matches!(p.name, PartName::LeftLeg | PartName::RightLeg) {
            *p = extend_to_floor(
                p,
                up,
                floor,
                opts.sole_height * h,
                0.25 * opts.foot_spacing * h,
            );
        }
    }
    seg
}

/// The head's pockets of skin (a modelled mouth) over the run of its
/// sections (meshes only: `find_cavities`).
fn head_cavities(
    cutter: &Cutter<'_>,
    parts: &[BodyPart],
    input: &InputDistance<'_>,
    opts: &ReconstructOptions,
    warnings: &mut Vec<String>,
) -> Vec<BodyCavity> {
    let head_run = parts
        .iter()
        .find(|p| p.name == PartName::Head)
        .and_then(|h| Some((h.fits.first()?.at, h.fits.last()?.at)));
    match head_run {
        Some(run) => find_cavities(cutter, PartName::Head, run, input, opts, warnings),
        None => Vec::new(),
    }
}

/// Convenience for a cloud input.
pub fn reconstruct_cloud(
    cloud: &PointCloud,
    opts: &ReconstructOptions,
) -> Result<(Body, Report), ReconstructError> {
    reconstruct(BodyGeometry::Cloud(cloud), opts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_counts_every_step_and_ends_at_its_total() {
        let body = crate::geom::shapes::stick_body(1);
        let mut seen: Vec<(String, usize, usize)> = Vec::new();
        reconstruct_with_progress(
            BodyGeometry::Mesh(&body),
            &ReconstructOptions::default(),
            &mut |p| seen.push((p.stage.to_string(), p.done, p.total)),
        )
        .unwrap();
        // One report per step, counting up by one, then "done" at the
        // total (this body has no arms: their four steps are skipped).
        // A step added without raising the count would stall the bar
        // below its end: every step but "done" stays below the total.
        let (last, steps) = seen.split_last().unwrap();
        assert_eq!(steps.len(), RECONSTRUCT_STEPS - 4, "{seen:?}");
        for (k, (_, done, total)) in steps.iter().enumerate() {
            assert_eq!((*done, *total), (k, RECONSTRUCT_STEPS), "{seen:?}");
        }
        assert_eq!(
            last,
            &("done".to_string(), RECONSTRUCT_STEPS, RECONSTRUCT_STEPS)
        );
    }

    #[test]
    fn sphere_is_a_clear_error() {
        let m = crate::geom::shapes::uv_sphere(Vec3::ZERO, 1.0, 32, 16);
        let e = reconstruct(BodyGeometry::Mesh(&m), &ReconstructOptions::default()).unwrap_err();
        assert!(
            matches!(e, ReconstructError::Segment(SegmentError::NoUpAxis { .. })),
            "{e}"
        );
    }
}
