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
//!    the scanner's holes).
//! 3. **Parts and ends.**
//!    * Torso: crotch → neck, both ends open (the legs hang below its
//!      first section, the head sits on its last).
//!    * Head: neck → head top. Sections run while the loop stays at least
//!      [`ReconstructOptions::end_area_fraction`] of the part's largest
//!      loop beyond it, then a dome reaches the head top: its height
//!      `h = d / r`, `d` the distance from the last section's centre to the
//!      head top along the axis, `r = √(A/π)` the last loop's mean radius.
//!    * Arms: shoulder → hand tip, the same rule past the wrist (where the
//!      fingers split the hand's loop, its area drops): a mitten-like dome
//!      to the hand tip.
//!    * Legs with feet (shoe-like): crotch → ankle along the leg's axis,
//!      then straight down along `−up` to just above the floor, so the
//!      sections below the ankle are horizontal outlines of the whole foot
//!      (heel to toes), until the outline shrinks below
//!      [`ReconstructOptions::sole_area_fraction`] of the largest (where the
//!      sole curves up at heel and toes); a shallow dome from the last
//!      outline down to the floor below its centre closes the sole (a flat
//!      cap there left the sole 6-10 mm away: coverage 96.2 → 96.9 % on the
//!      male mesh). The segmentation's
//!      foot parts are reported as found and covered by the legs.
//!
//!    Sections whose loop cannot be cut or fitted are skipped with a
//!    warning; when two consecutive planes cross inside the curves (where a
//!    tilted axis turns), the later section is dropped.
//! 4. **Report**: design parameters (method.md §7) against 3 × the input's
//!    vertices, and distances both ways in millimetres (see [`Report`]).
//!
//! Nothing here knows units, coordinates or vertex order: lengths are
//! fractions of `H`; [`ReconstructOptions::units`] only converts the
//! report's distances to millimetres.

use crate::cap::CapKind;
use crate::curve::TrigCurve;
use crate::distance::{sample_surface, DistanceStats, MeshDistance};
use crate::fit::{fit_loop, FitOptions, LoopFit};
use crate::math::{Point3, Real, Vec3};
use crate::mesh::{Mesh, PointCloud};
use crate::part::{Part, PartError, PartOptions};
use crate::scan_section::scan_fit_options;
use crate::segment::{
    cut_part_along, segment, BodyFrame, BodyGeometry, LandmarkKind, PartAxis, PartName,
    SegmentError, SegmentOptions, Segmentation,
};
use crate::tessellate::{tessellate_part, TessellateError, TessellationOptions};
use std::fmt;
use thiserror::Error;

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
    /// A rounded end (head top, hand) ends its sections where the loop has
    /// shrunk below this fraction of the largest loop beyond the part's
    /// middle (head) or wrist (hand); a dome closes the rest. Default 0.5.
    pub end_area_fraction: Real,
    /// The foot's sections end where its outline shrinks below this fraction
    /// of its largest outline below the ankle (the sole curving up at the
    /// heel and toes); a flat cap closes it. Default 0.75.
    pub sole_area_fraction: Real,
    /// Height of the lowest foot section above the floor, as a fraction of
    /// the height. Default 0.002.
    pub sole_height: Real,
    /// Skinning of every part (caps are chosen by the pipeline).
    /// Default [`PartOptions::default`] (Catmull-Rom, twist aligned).
    pub part: PartOptions,
    /// The input's unit (the report converts to millimetres). Default metres.
    pub units: Units,
    /// Scan loops carry the scanner's noise (about 1 mm, several per cent of
    /// an arm's radius), which no order should reproduce: their tolerances
    /// are `E_a`, `E_M` times this factor. Default 2.
    pub scan_tolerance_factor: Real,
    /// A section is dropped when a quarter of its curve lies farther than
    /// this fraction of the height from the input (a wrongly joined scan
    /// loop). Default 0.006 (1 cm on 1.73 m).
    pub max_curve_offset: Real,
    /// Rounds of adaptive refinement (see [`refine`]). Default 3.
    pub refine_rounds: usize,
    /// A section is added where the surface strays farther than this
    /// fraction of the height from the input halfway between two sections.
    /// Default 0.003 (5.2 mm on 1.73 m; measured on the three meshes: 0.0015
    /// gave the same RMS within 0.05 mm with 6 % more parameters).
    pub refine_tolerance: Real,
    /// Sections are never added closer than this fraction of the height.
    /// Default 0.002.
    pub min_spacing: Real,
    /// Points sampled on each surface for the distances. Default 60 000.
    pub report_samples: usize,
    /// Tessellation edge length for the measured model surface, as a
    /// fraction of the height. Default 0.003 (5 mm on 1.7 m).
    pub report_edge: Real,
    /// Coverage distance in millimetres: an input point is covered when the
    /// model passes within it. Default 5.
    pub coverage_mm: Real,
}

impl Default for ReconstructOptions {
    fn default() -> Self {
        ReconstructOptions {
            segment: SegmentOptions::default(),
            fit: FitOptions::default(),
            spacing: 0.012,
            foot_spacing: 0.004,
            end_area_fraction: 0.5,
            sole_height: 0.002,
            sole_area_fraction: 0.75,
            part: PartOptions::default(),
            units: Units::Metres,
            scan_tolerance_factor: 2.0,
            max_curve_offset: 0.006,
            refine_rounds: 3,
            refine_tolerance: 0.003,
            min_spacing: 0.002,
            report_samples: 60_000,
            report_edge: 0.003,
            coverage_mm: 5.0,
        }
    }
}

/// What went wrong in [`reconstruct`].
#[derive(Debug, Error, PartialEq)]
pub enum ReconstructError {
    /// Segmentation failed: the message names what was not found.
    #[error("segmentation: {0}")]
    Segment(#[from] SegmentError),
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

/// One reconstructed part.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyPart {
    pub name: PartName,
    pub part: Part,
    /// One entry per section of `part`, in order.
    pub fits: Vec<SectionFit>,
}

/// A reconstructed body: skinned parts with their caps, in the input's
/// frame and units.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub units: Units,
    /// The body's frame from the segmentation.
    pub frame: BodyFrame,
    /// Soles to head top, in input units.
    pub height: Real,
    pub parts: Vec<BodyPart>,
}

impl Body {
    /// Design parameters (method.md §7): every section's coefficients,
    /// origin and frame, plus one height per dome cap.
    pub fn design_parameters(&self) -> usize {
        self.parts
            .iter()
            .map(|p| {
                let domes = [p.part.options().start_cap, p.part.options().end_cap]
                    .iter()
                    .filter(|c| matches!(c, CapKind::Dome { .. }))
                    .count();
                p.part.design_parameters() + domes
            })
            .sum()
    }

    /// The part of a name.
    pub fn part(&self, name: PartName) -> Option<&BodyPart> {
        self.parts.iter().find(|p| p.name == name)
    }

    /// Tessellates every part into one mesh (parts one after the other).
    pub fn tessellate(&self, options: &TessellationOptions) -> Result<Mesh, ReconstructError> {
        let mut out = Mesh::default();
        for p in &self.parts {
            let m = tessellate_part(&p.part, options).map_err(|source| {
                ReconstructError::Tessellate {
                    part: p.name,
                    source,
                }
            })?;
            append_mesh(&mut out, &m);
        }
        Ok(out)
    }
}

/// Appends `m` to `out` (indices shifted).
pub fn append_mesh(out: &mut Mesh, m: &Mesh) {
    let base = out.positions.len() as u32;
    out.positions.extend_from_slice(&m.positions);
    match (&mut out.normals, &m.normals) {
        (Some(n), Some(mn)) => n.extend_from_slice(mn),
        (n @ None, Some(mn)) if base == 0 => *n = Some(mn.clone()),
        (n, _) => *n = None,
    }
    out.triangles.extend(
        m.triangles
            .iter()
            .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
    );
}

/// Per-part numbers of the [`Report`].
#[derive(Clone, Debug, PartialEq)]
pub struct PartReport {
    pub name: PartName,
    pub sections: usize,
    /// Orders used: minimum, median, maximum.
    pub orders: (usize, usize, usize),
    /// Worst `E_a` and `E_M` over the part's sections.
    pub worst_ea: Real,
    pub worst_em: Real,
    /// Sections that met the tolerances.
    pub met: usize,
    /// The ellipse baseline's worst `E_a` and `E_M`.
    pub ellipse_worst_ea: Real,
    pub ellipse_worst_em: Real,
    pub design_parameters: usize,
}

/// Distance statistics in millimetres.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DistanceMm {
    pub rms: Real,
    pub p95: Real,
    pub max: Real,
}

impl DistanceMm {
    fn of(s: &DistanceStats, mm: Real) -> DistanceMm {
        DistanceMm {
            rms: s.rms * mm,
            p95: s.p95 * mm,
            max: s.max * mm,
        }
    }
}

/// How well and how compactly the model fits its input.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The model's design parameters (method.md §7).
    pub design_parameters: usize,
    /// The input's vertex (mesh) or point (cloud) count; the polygon
    /// baseline is `3 × input_vertices`.
    pub input_vertices: usize,
    /// Symmetric distance: `rms = √((rms_in² + rms_out²)/2)`, `p95` and
    /// `max` the larger of the two directions'.
    pub distance_mm: DistanceMm,
    /// Input → model: input surface samples (mesh) or points (cloud) to
    /// the model's surface.
    pub input_to_model_mm: DistanceMm,
    /// Model → input: model surface samples to the input's surface (mesh)
    /// or nearest input point (cloud).
    pub model_to_input_mm: DistanceMm,
    /// Share of input samples within [`ReconstructOptions::coverage_mm`]
    /// of the model.
    pub coverage: Real,
    pub parts: Vec<PartReport>,
    /// Parts the segmentation found (feet included).
    pub parts_found: Vec<PartName>,
    pub warnings: Vec<String>,
}

impl Report {
    /// `design_parameters / (3 × input_vertices)`.
    pub fn parameter_ratio(&self) -> Real {
        self.design_parameters as Real / (3 * self.input_vertices.max(1)) as Real
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
    pos("end_area_fraction", o.end_area_fraction)?;
    pos("sole_height", o.sole_height)?;
    pos("sole_area_fraction", o.sole_area_fraction)?;
    pos("report_edge", o.report_edge)?;
    pos("refine_tolerance", o.refine_tolerance)?;
    pos("min_spacing", o.min_spacing)?;
    pos("scan_tolerance_factor", o.scan_tolerance_factor)?;
    pos("max_curve_offset", o.max_curve_offset)?;
    pos("coverage_mm", o.coverage_mm)?;
    if o.spacing > 0.2 || o.foot_spacing > 0.2 {
        return Err(ReconstructError::BadOption {
            name: "spacing",
            value: o.spacing.max(o.foot_spacing),
            why: "must be at most 0.2 of the height",
        });
    }
    Ok(())
}

/// One cut-and-fitted section.
struct Cut {
    at: Real,
    fit: LoopFit,
    area: Real,
}

/// Cuts and fits `part` of `seg` at `at`.
fn cut_and_fit(
    body: BodyGeometry<'_>,
    seg: &Segmentation,
    name: PartName,
    at: Real,
    opts: &ReconstructOptions,
) -> Result<Cut, String> {
    // Torso, head and legs (with the feet) are cut across the body's up
    // axis: parallel planes never cross, and a horizontal cut below the
    // ankle is the foot's outline. Arms are cut across their own axis.
    let normal = match name {
        PartName::LeftArm | PartName::RightArm => None,
        _ => Some(seg.frame.up),
    };
    let cut = cut_part_along(body, seg, name, at, normal, true, &opts.segment)
        .map_err(|e| e.to_string())?;
    let base = FitOptions {
        reference: Some(seg.frame.front),
        normal: Some(cut.plane.normal),
        allow_non_planar: true,
        ..opts.fit
    };
    let fo = match body {
        BodyGeometry::Cloud(_) => scan_fit_options(&FitOptions {
            ea: base.ea * opts.scan_tolerance_factor,
            em: base.em * opts.scan_tolerance_factor,
            ..base
        }),
        BodyGeometry::Mesh(_) => base,
    };
    let fit = fit_loop(&cut.outline.points, &fo).map_err(|e| e.to_string())?;
    Ok(Cut {
        at,
        fit,
        area: cut.outline.area,
    })
}

/// Arc-length fraction of the axis point nearest `p`.
fn fraction_of(axis: &PartAxis, p: Point3) -> Real {
    let total = axis.length();
    if !(total > 0.0) {
        return 0.0;
    }
    let mut acc = 0.0;
    let mut best = (Real::INFINITY, 0.0);
    for (k, q) in axis.points.iter().enumerate() {
        if k > 0 {
            acc += axis.points[k - 1].distance(*q);
        }
        let d = q.distance(p);
        if d < best.0 {
            best = (d, acc / total);
        }
    }
    best.1
}

/// Evenly spaced fractions from `t0` to `t1` at most `step` apart (both
/// ends included).
fn fractions(t0: Real, t1: Real, step: Real) -> Vec<Real> {
    if !(t1 > t0) {
        return vec![t0];
    }
    let n = (((t1 - t0) / step).ceil() as usize).max(1);
    (0..=n)
        .map(|k| t0 + (t1 - t0) * k as Real / n as Real)
        .collect()
}

/// The sections of a part, plus the part's axis length.
struct Plan {
    name: PartName,
    cuts: Vec<Cut>,
    start_cap: CapKind,
    end_cap: CapKind,
    /// For a dome end: the tip the dome should reach.
    tip: Option<Point3>,
}

/// Cuts at every fraction, skipping (with a warning) those that fail.
fn cut_all(
    body: BodyGeometry<'_>,
    seg: &Segmentation,
    name: PartName,
    ts: &[Real],
    opts: &ReconstructOptions,
    warnings: &mut Vec<String>,
) -> Vec<Cut> {
    let mut out = Vec::with_capacity(ts.len());
    for &t in ts {
        match cut_and_fit(body, seg, name, t, opts) {
            Ok(c) => out.push(c),
            Err(e) => warnings.push(format!("{name}: section at {t:.3} skipped: {e}")),
        }
    }
    out
}

/// Sections up to a rounded end: evenly from `t0` while the loop keeps at
/// least `end_area_fraction` of the largest loop seen after `watch_from`.
fn cut_to_rounded_end(
    body: BodyGeometry<'_>,
    seg: &Segmentation,
    name: PartName,
    t0: Real,
    watch_from: Real,
    step: Real,
    opts: &ReconstructOptions,
    warnings: &mut Vec<String>,
) -> Vec<Cut> {
    let mut out: Vec<Cut> = Vec::new();
    let mut largest: Real = 0.0;
    let ts = fractions(t0, 1.0, step);
    for &t in &ts[..ts.len().saturating_sub(1)] {
        let c = match cut_and_fit(body, seg, name, t, opts) {
            Ok(c) => c,
            Err(e) => {
                if t >= watch_from {
                    break;
                }
                warnings.push(format!("{name}: section at {t:.3} skipped: {e}"));
                continue;
            }
        };
        if t >= watch_from {
            if largest > 0.0 && c.area < opts.end_area_fraction * largest {
                break;
            }
            largest = largest.max(c.area);
        }
        out.push(c);
    }
    out
}

/// The leg's axis continued from the ankle straight down to `floor + lift`
/// along `−up`, in steps of `step`.
fn extend_to_floor(axis: &PartAxis, up: Vec3, floor: Real, lift: Real, step: Real) -> PartAxis {
    let mut a = axis.clone();
    let Some(&last) = a.points.last() else {
        return a;
    };
    let r = a.radii.last().copied().unwrap_or(0.0);
    let drop = last.dot(up) - (floor + lift);
    if drop > step {
        let n = (drop / step).ceil() as usize;
        for k in 1..=n {
            a.points.push(last - up * (drop * k as Real / n as Real));
            a.radii.push(r);
        }
    }
    a
}

/// The first arc-length fraction where the axis reaches `level` along `up`
/// (going up when `rising`, down otherwise); 0 when it starts beyond it.
fn fraction_at_level(axis: &PartAxis, up: Vec3, level: Real, rising: bool) -> Real {
    let total = axis.length();
    if !(total > 0.0) {
        return 0.0;
    }
    let beyond = |p: &Point3| {
        if rising {
            p.dot(up) >= level
        } else {
            p.dot(up) <= level
        }
    };
    let mut acc = 0.0;
    for (k, p) in axis.points.iter().enumerate() {
        if k > 0 {
            acc += axis.points[k - 1].distance(*p);
        }
        if beyond(p) {
            return (acc / total).min(0.5);
        }
    }
    0.0
}

fn landmark(seg: &Segmentation, kind: LandmarkKind) -> Option<Point3> {
    seg.landmark(kind).map(|l| l.position)
}

/// Builds a part from its cuts, dropping a section whose plane crosses its
/// neighbour's inside the curves, and retrying.
fn build_part(
    plan: Plan,
    opts: &ReconstructOptions,
    scan: bool,
    warnings: &mut Vec<String>,
) -> Result<(BodyPart, Vec<Cut>), ReconstructError> {
    let Plan {
        name,
        mut cuts,
        start_cap,
        mut end_cap,
        tip,
    } = plan;
    let mut dome_retries = 0;
    loop {
        if cuts.len() < 2 {
            return Err(ReconstructError::TooFewSections {
                part: name,
                count: cuts.len(),
            });
        }
        if let (Some(tip), Some(last)) = (tip, cuts.last()) {
            // Dome height relative to the last loop's mean radius.
            let c = &last.fit.curve;
            let r = (c.area().abs() / std::f64::consts::PI).sqrt();
            let d = (tip - c.frame.origin)
                .dot(c.frame.e1.cross(c.frame.e2))
                .abs();
            if r > 0.0 && d > 0.0 {
                end_cap = CapKind::Dome {
                    relative_height: (d / r).clamp(0.02, 4.0),
                };
            }
        }
        let options = PartOptions {
            start_cap,
            end_cap,
            ..opts.part
        };
        let curves: Vec<TrigCurve> = cuts.iter().map(|c| c.fit.curve.clone()).collect();
        match Part::new(curves, &options) {
            Ok(part) => {
                // A dome must point at its tip: where the last sections
                // wobble (a scanned hand) the end tangent can point sideways
                // and the dome miss the tip by centimetres; drop the last
                // section and retry, at most three times. Scans only:
                // measured, the external scan's right hand went from 27 to
                // 4 mm RMS (body 8.0 -> 4.6 mm), while on meshes the rule
                // dropped good hand sections (male 3.1 -> 4.2 mm).
                let check = scan && dome_retries < 3;
                if let (true, Some(tip), Some(cap), Some(last)) =
                    (check, tip, part.end_cap(), cuts.last())
                {
                    let g = last.fit.curve.frame.origin;
                    let cos = (cap.apex - g)
                        .normalized()
                        .zip((tip - g).normalized())
                        .map_or(1.0, |(a, b)| a.dot(b));
                    if matches!(cap.kind, CapKind::Dome { .. })
                        && cuts.len() > 3
                        && cos < 30f64.to_radians().cos()
                    {
                        warnings.push(format!(
                            "{name}: section at {:.3} dropped (the end dome from it points {:.0} degrees away from the tip)",
                            last.at,
                            cos.clamp(-1.0, 1.0).acos().to_degrees()
                        ));
                        dome_retries += 1;
                        cuts.pop();
                        continue;
                    }
                }
                let fits = cuts
                    .iter()
                    .map(|c| SectionFit {
                        at: c.at,
                        order: c.fit.order,
                        ea: c.fit.errors.ea,
                        em: c.fit.errors.em,
                        met: c.fit.met,
                        ellipse: c.fit.ellipse.as_ref().map(|e| (e.errors.ea, e.errors.em)),
                    })
                    .collect();
                return Ok((BodyPart { name, part, fits }, cuts));
            }
            Err(PartError::CrossingPlanes { index, .. })
            | Err(PartError::CoincidentSections { index }) => {
                // Drop the later section of the pair (never the first).
                let k = (index + 1).min(cuts.len() - 1);
                warnings.push(format!(
                    "{name}: section at {:.3} dropped (its plane meets its neighbour's inside the curves)",
                    cuts[k].at
                ));
                cuts.remove(k);
            }
            Err(source) => return Err(ReconstructError::Part { part: name, source }),
        }
    }
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

/// [`reconstruct`] calling `progress` with the name of each step as it
/// starts (for a progress display).
pub fn reconstruct_with_progress(
    body: BodyGeometry<'_>,
    opts: &ReconstructOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<(Body, Report), ReconstructError> {
    check_options(opts)?;
    progress("segmenting");
    let seg0 = segment(body, &opts.segment)?;
    let mut warnings = seg0.warnings.clone();
    let h = seg0.height;
    let up = seg0.frame.up;
    let floor = seg0.frame.origin.dot(up);
    // Legs continue straight down to the floor (shoe-like feet).
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

    // Horizontal cuts at the crotch itself meet both legs or their merged
    // loop: the torso starts a little above it and the legs a little below.
    let crotch_level = landmark(&seg, LandmarkKind::Crotch).map_or(floor + 0.47 * h, |c| c.dot(up));
    // Measured: 0.6 slice spacings on meshes (coverage +0.4-0.5 % against
    // 1.5); scan slabs are a point spacing thick and the crotch is a
    // scanner hole, so at 0.6 the first leg loops of virtual scans mixed
    // both thighs (model -> input RMS 4.2 -> 7.2 mm): 1.5 there.
    let margin = match body {
        BodyGeometry::Mesh(_) => 0.6,
        BodyGeometry::Cloud(_) => 1.5,
    } * seg.slice_spacing;
    let mut plans = Vec::new();
    for name in [
        PartName::Torso,
        PartName::Head,
        PartName::LeftArm,
        PartName::RightArm,
        PartName::LeftLeg,
        PartName::RightLeg,
    ] {
        let Some(axis) = seg.part(name) else {
            warnings.push(format!("{name} not found: left out of the model"));
            continue;
        };
        progress(&format!("sections: {name}"));
        let len = axis.length();
        if !(len > 0.0) {
            warnings.push(format!("{name}: axis of zero length, left out"));
            continue;
        }
        let step = opts.spacing * h / len;
        let plan = match name {
            PartName::Torso => Plan {
                name,
                cuts: cut_all(
                    body,
                    &seg,
                    name,
                    &fractions(
                        fraction_at_level(axis, up, crotch_level + margin, true),
                        1.0,
                        step,
                    ),
                    opts,
                    &mut warnings,
                ),
                start_cap: CapKind::Open,
                end_cap: CapKind::Open,
                tip: None,
            },
            PartName::Head => Plan {
                name,
                cuts: cut_to_rounded_end(body, &seg, name, 0.0, 0.5, step, opts, &mut warnings),
                start_cap: CapKind::Open,
                end_cap: CapKind::dome(),
                tip: axis.points.last().copied(),
            },
            PartName::LeftArm | PartName::RightArm => {
                let wrist_kind = if name == PartName::LeftArm {
                    LandmarkKind::LeftWrist
                } else {
                    LandmarkKind::RightWrist
                };
                let wrist = landmark(&seg, wrist_kind)
                    .map(|w| fraction_of(axis, w))
                    .unwrap_or(0.8);
                let fine = (0.5 * step).max(0.25 * opts.foot_spacing * h / len);
                let mut cuts = cut_all(
                    body,
                    &seg,
                    name,
                    &fractions(0.0, wrist, step),
                    opts,
                    &mut warnings,
                );
                cuts.pop(); // the wrist itself starts the hand's run
                cuts.extend(cut_to_rounded_end(
                    body,
                    &seg,
                    name,
                    wrist,
                    wrist,
                    fine,
                    opts,
                    &mut warnings,
                ));
                Plan {
                    name,
                    cuts,
                    start_cap: CapKind::Open,
                    end_cap: CapKind::dome(),
                    tip: axis.points.last().copied(),
                }
            }
            _ => {
                // Legs: evenly to the ankle, finely below it to the sole.
                let ankle_kind = if name == PartName::LeftLeg {
                    LandmarkKind::LeftAnkle
                } else {
                    LandmarkKind::RightAnkle
                };
                let orig = seg0.part(name).map(PartAxis::length).unwrap_or(len);
                let ankle = landmark(&seg, ankle_kind)
                    .map(|a| fraction_of(axis, a))
                    .unwrap_or(orig / len)
                    .min(orig / len);
                let t0 = fraction_at_level(axis, up, crotch_level - margin, false);
                let upper = (ankle - 0.02 * h / len).max(t0);
                let mut cuts = cut_all(
                    body,
                    &seg,
                    name,
                    &fractions(t0, upper, step),
                    opts,
                    &mut warnings,
                );
                cuts.pop();
                // Below the ankle: horizontal outlines of the foot until
                // they shrink where the sole curves up (heel, toes).
                let foot = ReconstructOptions {
                    end_area_fraction: opts.sole_area_fraction,
                    ..*opts
                };
                cuts.extend(cut_to_rounded_end(
                    body,
                    &seg,
                    name,
                    upper,
                    ankle,
                    opts.foot_spacing * h / len,
                    &foot,
                    &mut warnings,
                ));
                // The sole: a shallow dome from the last outline down to
                // the floor below its centre.
                let sole = cuts.last().map(|c| {
                    let o = c.fit.curve.frame.origin;
                    o - up * (o.dot(up) - floor)
                });
                Plan {
                    name,
                    cuts,
                    start_cap: CapKind::Open,
                    end_cap: CapKind::Flat,
                    tip: sole,
                }
            }
        };
        plans.push(plan);
    }

    progress("skinning");
    let input = match body {
        BodyGeometry::Mesh(m) => InputDistance::Mesh(MeshDistance::new(m)),
        BodyGeometry::Cloud(c) => InputDistance::Cloud(PointGrid::new(&c.positions, 0.01 * h)),
    };
    let mut parts = Vec::new();
    for plan in plans {
        let name = plan.name;
        progress(&format!("skinning and refining: {name}"));
        match refine(body, &seg, plan, opts, &input, &mut warnings) {
            Ok(p) => parts.push(p),
            Err(e) if name != PartName::Torso => {
                warnings.push(format!("{name} left out: {e}"));
            }
            Err(e) => return Err(e),
        }
    }
    let model = Body {
        units: opts.units,
        frame: seg.frame,
        height: h,
        parts,
    };
    progress("measuring");
    let report = measure(body, &model, &seg0, opts, warnings)?;
    Ok((model, report))
}

/// Distances to the input: its surface (mesh) or its nearest point (cloud).
enum InputDistance<'a> {
    Mesh(MeshDistance<'a>),
    Cloud(PointGrid<'a>),
}

impl InputDistance<'_> {
    fn distance(&self, p: Point3) -> Real {
        match self {
            InputDistance::Mesh(m) => m.distance(p),
            InputDistance::Cloud(g) => g.nearest(p),
        }
    }
}

/// The 75th percentile of the distances from 64 points of a section's
/// curve to the input: a curve fitted to a wrongly joined loop (a scan
/// slab's arcs joined across a hole) has long stretches away from it.
fn curve_offset(c: &Cut, input: &InputDistance) -> Real {
    let mut d: Vec<Real> = c
        .fit
        .curve
        .sample(64)
        .iter()
        .map(|p| input.distance(*p))
        .collect();
    d.sort_by(Real::total_cmp);
    d[48]
}

/// The 90th percentile of the in-plane distances from the loop points of
/// `cut` to `curve` (sampled densely), both projected into the cut's plane
/// (a percentile, not the maximum: a scan loop's noise and stray points
/// must not call for sections everywhere).
fn stray(cut: &Cut, curve: &crate::curve::SpaceCurve) -> Real {
    let f = &cut.fit.curve.frame;
    let n = 256;
    let poly: Vec<(Real, Real)> = (0..n)
        .map(|i| {
            let p = curve.point(std::f64::consts::TAU * i as Real / n as Real) - f.origin;
            (p.dot(f.e1), p.dot(f.e2))
        })
        .collect();
    let mut all = Vec::with_capacity(cut.fit.plane_points.len());
    for q in &cut.fit.plane_points {
        let mut best = Real::INFINITY;
        for i in 0..n {
            let (ax, ay) = poly[i];
            let (bx, by) = poly[(i + 1) % n];
            let (dx, dy) = (bx - ax, by - ay);
            let l2 = dx * dx + dy * dy;
            let t = if l2 > 0.0 {
                (((q.x - ax) * dx + (q.y - ay) * dy) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (ex, ey) = (ax + t * dx - q.x, ay + t * dy - q.y);
            best = best.min((ex * ex + ey * ey).sqrt());
        }
        all.push(best);
    }
    if all.is_empty() {
        return 0.0;
    }
    all.sort_by(Real::total_cmp);
    all[(all.len() * 9 / 10).min(all.len() - 1)]
}

/// A fit far outside its tolerances (three times either): a loop the
/// section picked wrongly or a hole the fit could not bridge.
fn wild(c: &Cut, opts: &ReconstructOptions) -> bool {
    !c.fit.met
        && (c.fit.errors.ea > 3.0 * opts.fit.ea * opts.scan_tolerance_factor
            || c.fit.errors.em > 3.0 * opts.fit.em * opts.scan_tolerance_factor)
}

/// Drops sections whose loop is implausible: area outside `[½, 2]` times
/// the median of its (up to four) nearest neighbours' — a wrong loop
/// picked where a scan's slab broke up (armpits, fingers) — or a wild fit
/// (see [`wild`]).
fn drop_outliers(mut plan: Plan, opts: &ReconstructOptions, warnings: &mut Vec<String>) -> Plan {
    let n = plan.cuts.len();
    if n < 3 {
        return plan;
    }
    let keep: Vec<bool> = (0..n)
        .map(|i| {
            let mut near: Vec<Real> = (i.saturating_sub(2)..(i + 3).min(n))
                .filter(|&j| j != i)
                .map(|j| plan.cuts[j].area)
                .collect();
            near.sort_by(Real::total_cmp);
            let med = near[near.len() / 2];
            let a = plan.cuts[i].area;
            a >= 0.5 * med && a <= 2.0 * med && !wild(&plan.cuts[i], opts)
        })
        .collect();
    let name = plan.name;
    let mut k = 0;
    plan.cuts.retain(|c| {
        let ok = keep[k];
        k += 1;
        if !ok {
            warnings.push(format!(
                "{name}: section at {:.3} dropped (area {:.3e} unlike its neighbours', or E_a {:.3} / E_M {:.3} far beyond the tolerances)",
                c.at, c.area, c.fit.errors.ea, c.fit.errors.em
            ));
        }
        ok
    });
    plan
}

/// Adaptive spacing (method.md §8.6): builds the part, then between every
/// two consecutive sections cuts the input halfway and compares that loop
/// with the surface's curve halfway between the sections (patch parameter
/// `u = ½`, both in the new cut's plane). Where the surface strays more
/// than [`ReconstructOptions::refine_tolerance`] × `H` from the input (the
/// 90th percentile of the loop points' distances, see [`stray`]), the
/// new section is added; repeated for [`ReconstructOptions::refine_rounds`]
/// rounds, never closer than [`ReconstructOptions::min_spacing`] × `H`.
fn refine(
    body: BodyGeometry<'_>,
    seg: &Segmentation,
    mut plan: Plan,
    opts: &ReconstructOptions,
    input: &InputDistance,
    warnings: &mut Vec<String>,
) -> Result<BodyPart, ReconstructError> {
    let name = plan.name;
    let (start_cap, end_cap, tip) = (plan.start_cap, plan.end_cap, plan.tip);
    let far = opts.max_curve_offset * seg.height;
    plan.cuts.retain(|c| {
        let off = curve_offset(c, input);
        if off > far {
            warnings.push(format!(
                "{name}: section at {:.3} dropped (a quarter of its curve lies {:.1} mm or more from the input)",
                c.at,
                off * opts.units.to_mm()
            ));
        }
        off <= far
    });
    // One pass: a second one (for outliers among outliers) dropped real
    // sections of the base mesh's feet and hands (RMS 3.2 -> 4.6 mm).
    let plan = drop_outliers(plan, opts, warnings);
    let (mut built, mut cuts) =
        build_part(plan, opts, matches!(body, BodyGeometry::Cloud(_)), warnings)?;
    let len = seg.part(name).map_or(0.0, PartAxis::length);
    if !(len > 0.0) {
        return Ok(built);
    }
    let min_step = opts.min_spacing * seg.height / len;
    let tol = opts.refine_tolerance * seg.height;
    for _ in 0..opts.refine_rounds {
        let segments = built.part.segments();
        if segments.len() + 1 != cuts.len() {
            break; // only for the one-patch-per-interval schemes
        }
        let mut added = Vec::new();
        for i in 0..cuts.len() - 1 {
            let (t0, t1) = (cuts[i].at, cuts[i + 1].at);
            if t1 - t0 < 2.0 * min_step {
                continue;
            }
            let tm = 0.5 * (t0 + t1);
            let Ok(c) = cut_and_fit(body, seg, name, tm, opts) else {
                continue;
            };
            let (a0, a1) = (cuts[i].area, cuts[i + 1].area);
            let plausible =
                c.area >= 0.5 * a0.min(a1) && c.area <= 2.0 * a0.max(a1) && !wild(&c, opts);
            if plausible
                && curve_offset(&c, input) <= far
                && stray(&c, &segments[i].patch.curve_at(0.5)) > tol
            {
                added.push(c);
            }
        }
        if added.is_empty() {
            break;
        }
        let mut all: Vec<Cut> = cuts.into_iter().chain(added).collect();
        all.sort_by(|a, b| a.at.total_cmp(&b.at));
        let plan = Plan {
            name,
            cuts: all,
            start_cap,
            end_cap,
            tip,
        };
        (built, cuts) = build_part(plan, opts, matches!(body, BodyGeometry::Cloud(_)), warnings)?;
    }
    Ok(built)
}

/// The per-part numbers of a body.
pub fn part_reports(body: &Body) -> Vec<PartReport> {
    body.parts
        .iter()
        .map(|p| {
            let mut orders: Vec<usize> = p.fits.iter().map(|f| f.order).collect();
            orders.sort_unstable();
            let med = orders.get(orders.len() / 2).copied().unwrap_or(0);
            let fold = |f: &dyn Fn(&SectionFit) -> Real| p.fits.iter().map(f).fold(0.0, Real::max);
            PartReport {
                name: p.name,
                sections: p.fits.len(),
                orders: (
                    orders.first().copied().unwrap_or(0),
                    med,
                    orders.last().copied().unwrap_or(0),
                ),
                worst_ea: fold(&|f| f.ea),
                worst_em: fold(&|f| f.em),
                met: p.fits.iter().filter(|f| f.met).count(),
                ellipse_worst_ea: fold(&|f| f.ellipse.map_or(0.0, |e| e.0)),
                ellipse_worst_em: fold(&|f| f.ellipse.map_or(0.0, |e| e.1)),
                design_parameters: p.part.design_parameters(),
            }
        })
        .collect()
}

/// Deterministic subsample of at most `n` items (every k-th).
fn every_kth(points: &[Point3], n: usize) -> Vec<Point3> {
    let k = points.len().div_ceil(n.max(1)).max(1);
    points.iter().step_by(k).copied().collect()
}

/// Measures `model` against its input `body` (see [`Report`]).
pub fn measure(
    body: BodyGeometry<'_>,
    model: &Body,
    seg: &Segmentation,
    opts: &ReconstructOptions,
    warnings: Vec<String>,
) -> Result<Report, ReconstructError> {
    let mm = opts.units.to_mm();
    let tess = TessellationOptions {
        target_edge: Some(opts.report_edge * model.height),
        ..TessellationOptions::default()
    };
    let surface = model.tessellate(&tess)?;
    let model_dist = MeshDistance::new(&surface);
    let model_samples = sample_surface(&surface, opts.report_samples);
    let (input_samples, input_count, out_d) = match body {
        BodyGeometry::Mesh(m) => {
            let input = MeshDistance::new(m);
            let d: Vec<Real> = model_samples.iter().map(|p| input.distance(*p)).collect();
            (sample_surface(m, opts.report_samples), m.positions.len(), d)
        }
        BodyGeometry::Cloud(c) => {
            let grid = PointGrid::new(&c.positions, 0.01 * model.height);
            let d: Vec<Real> = model_samples.iter().map(|p| grid.nearest(*p)).collect();
            (
                every_kth(&c.positions, opts.report_samples),
                c.positions.len(),
                d,
            )
        }
    };
    let in_d: Vec<Real> = input_samples
        .iter()
        .map(|p| model_dist.distance(*p))
        .collect();
    let covered = in_d.iter().filter(|&&d| d * mm <= opts.coverage_mm).count();
    let a = DistanceMm::of(&DistanceStats::of(&in_d), mm);
    let b = DistanceMm::of(&DistanceStats::of(&out_d), mm);
    Ok(Report {
        design_parameters: model.design_parameters(),
        input_vertices: input_count,
        distance_mm: DistanceMm {
            rms: ((a.rms * a.rms + b.rms * b.rms) / 2.0).sqrt(),
            p95: a.p95.max(b.p95),
            max: a.max.max(b.max),
        },
        input_to_model_mm: a,
        model_to_input_mm: b,
        coverage: covered as Real / in_d.len().max(1) as Real,
        parts: part_reports(model),
        parts_found: seg.parts.iter().map(|p| p.name).collect(),
        warnings,
    })
}

/// A uniform grid over a point cloud for nearest-point distances: cells of
/// side `cell`, hashed by integer coordinates; a query searches shells of
/// cells outward until the shell's inner distance exceeds the best found.
#[derive(Debug)]
pub struct PointGrid<'a> {
    points: &'a [Point3],
    cell: Real,
    origin: Point3,
    dims: [usize; 3],
    /// Start of each cell's run in `order` (prefix sums, length cells + 1).
    starts: Vec<u32>,
    order: Vec<u32>,
}

impl<'a> PointGrid<'a> {
    /// Builds the grid; `cell` is clamped so there are at most ~4M cells.
    pub fn new(points: &'a [Point3], cell: Real) -> PointGrid<'a> {
        let fin = || points.iter().filter(|p| p.is_finite());
        let mut lo = Vec3::new(Real::INFINITY, Real::INFINITY, Real::INFINITY);
        let mut hi = -lo;
        for p in fin() {
            lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
            hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
        }
        if !(lo.x <= hi.x) {
            lo = Vec3::ZERO;
            hi = Vec3::ZERO;
        }
        let ext = hi - lo;
        let mut cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            1.0
        };
        let vol = (ext.x / cell + 1.0) * (ext.y / cell + 1.0) * (ext.z / cell + 1.0);
        if vol > 4.0e6 {
            cell *= (vol / 4.0e6).cbrt();
        }
        let dims = [
            (ext.x / cell) as usize + 1,
            (ext.y / cell) as usize + 1,
            (ext.z / cell) as usize + 1,
        ];
        let n = dims[0] * dims[1] * dims[2];
        let mut grid = PointGrid {
            points,
            cell,
            origin: lo,
            dims,
            starts: vec![0; n + 1],
            order: Vec::new(),
        };
        let keys: Vec<Option<usize>> = points
            .iter()
            .map(|p| p.is_finite().then(|| grid.key(grid.coords(*p))))
            .collect();
        for k in keys.iter().flatten() {
            grid.starts[k + 1] += 1;
        }
        for i in 0..n {
            grid.starts[i + 1] += grid.starts[i];
        }
        let mut fill = grid.starts.clone();
        grid.order = vec![0; grid.starts[n] as usize];
        for (i, k) in keys.iter().enumerate() {
            if let Some(k) = k {
                grid.order[fill[*k] as usize] = i as u32;
                fill[*k] += 1;
            }
        }
        grid
    }

    fn coords(&self, p: Point3) -> [i64; 3] {
        let d = (p - self.origin) / self.cell;
        [d.x.floor() as i64, d.y.floor() as i64, d.z.floor() as i64]
    }

    fn key(&self, c: [i64; 3]) -> usize {
        let cl = |v: i64, n: usize| v.clamp(0, n as i64 - 1) as usize;
        (cl(c[2], self.dims[2]) * self.dims[1] + cl(c[1], self.dims[1])) * self.dims[0]
            + cl(c[0], self.dims[0])
    }

    /// Distance from `p` to the nearest point (infinite for an empty cloud).
    pub fn nearest(&self, p: Point3) -> Real {
        if self.order.is_empty() || !p.is_finite() {
            return Real::INFINITY;
        }
        let c = self.coords(p);
        let clamp = |v: i64, n: usize| v.clamp(0, n as i64 - 1);
        let cc = [
            clamp(c[0], self.dims[0]),
            clamp(c[1], self.dims[1]),
            clamp(c[2], self.dims[2]),
        ];
        // Distance from p to its projection q on the grid's box: for x in
        // the (convex) box, |p - x|² ≥ |p - q|² + |q - x|².
        let hi = self.origin
            + Vec3::new(
                self.dims[0] as Real * self.cell,
                self.dims[1] as Real * self.cell,
                self.dims[2] as Real * self.cell,
            );
        let q = Vec3::new(
            p.x.clamp(self.origin.x, hi.x),
            p.y.clamp(self.origin.y, hi.y),
            p.z.clamp(self.origin.z, hi.z),
        );
        let outside2 = (p - q).norm_squared();
        let maxr = *self.dims.iter().max().unwrap_or(&1) as i64;
        let mut best = Real::INFINITY;
        for r in 0..=maxr {
            // Every point in shell r is at least (r - 1) cells from q.
            let inner = ((r - 1).max(0) as Real) * self.cell;
            if best.is_finite() && (outside2 + inner * inner).sqrt() > best {
                break;
            }
            for dz in -r..=r {
                for dy in -r..=r {
                    for dx in -r..=r {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                            continue;
                        }
                        let q = [cc[0] + dx, cc[1] + dy, cc[2] + dz];
                        if (0..3).any(|i| q[i] < 0 || q[i] >= self.dims[i] as i64) {
                            continue;
                        }
                        let k = self.key(q);
                        for &i in &self.order[self.starts[k] as usize..self.starts[k + 1] as usize]
                        {
                            best = best.min(self.points[i as usize].distance(p));
                        }
                    }
                }
            }
        }
        best
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
    fn grid_nearest_matches_brute_force() {
        let mut rng = crate::scanner::Rng::new(7);
        let pts: Vec<Point3> = (0..2000)
            .map(|_| Vec3::new(rng.uniform(), 2.0 * rng.uniform(), rng.uniform()))
            .collect();
        let grid = PointGrid::new(&pts, 0.05);
        for _ in 0..200 {
            let q = Vec3::new(
                3.0 * rng.uniform() - 1.0,
                3.0 * rng.uniform() - 0.5,
                rng.uniform(),
            );
            let brute = pts
                .iter()
                .map(|p| p.distance(q))
                .fold(Real::INFINITY, Real::min);
            assert!((grid.nearest(q) - brute).abs() < 1e-12, "{q:?}");
        }
    }

    #[test]
    fn sphere_is_a_clear_error() {
        let m = crate::shapes::uv_sphere(Vec3::ZERO, 1.0, 32, 16);
        let e = reconstruct(BodyGeometry::Mesh(&m), &ReconstructOptions::default()).unwrap_err();
        assert!(
            matches!(e, ReconstructError::Segment(SegmentError::NoUpAxis { .. })),
            "{e}"
        );
    }
}
