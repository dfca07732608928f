//! Body measurements from cross-section curves: stature, girths, lengths,
//! breadth, volume and surface area (issue 6).
//!
//! A trigonometric section curve `P(v) = (x(v), y(v))`, `v ∈ [0, 2π)`, gives
//! its girth in closed form up to one quadrature: the perimeter
//! `L = ∫₀^{2π} |P'(v)| dv` ([`TrigCurve::perimeter`]), and a tape measure's
//! reading, which bridges concave stretches, is the perimeter of the curve's
//! convex hull ([`tape_girth`]). Areas are exact: `A = ½ ∮ (x y' − y x') dv
//! = π Σ_j j (a_j d_j − b_j c_j)` ([`TrigCurve::area`]).
//!
//! # Where each measurement is taken
//!
//! Every plane is placed from the [`Segmentation`]'s landmarks and part axes,
//! by fractions of lengths found on the body, never by coordinates. `H` is
//! the stature; heights are along the body's up axis above the soles.
//! Torso girths are taken in horizontal planes (normal = up); limb girths in
//! planes perpendicular to the limb's axis at an arc-length fraction `t` of
//! the part (0 at the proximal end). ISO 7250-1 names are given where the
//! standard has the measurement; our landmarks are geometric stand-ins for
//! the palpated ones of the standard (see [`GIRTHS`] and [`Measurement`]):
//!
//! | name | ISO 7250-1 | plane |
//! | --- | --- | --- |
//! | neck | neck circumference | horizontal at the neck landmark (the smallest horizontal convex-hull girth between armpits and head) |
//! | chest | chest circumference | horizontal, `chest_below_armpit · H` below the higher armpit |
//! | waist | waist circumference | horizontal, the smallest torso tape girth between 35 % and 85 % of the way from crotch to chest level (the natural waist) |
//! | hip | hip circumference | horizontal, the largest torso tape girth between `hip_search_start · H` above the crotch and the waist (the buttocks) |
//! | thigh | thigh circumference | ⟂ leg axis at `t = 0.1` (just below the gluteal fold) |
//! | knee | knee circumference | ⟂ leg axis at `t = 0.45` (mid-patella) |
//! | calf | calf circumference | ⟂ leg axis, largest equivalent radius for `t ∈ [0.55, 0.85]` |
//! | ankle | ankle circumference | ⟂ leg axis, smallest equivalent radius for `t ∈ [0.85, 0.97]` (above the malleoli) |
//!
//! Leg fractions `t` run over the leg axis from its first point
//! `leg_start_below_crotch · H` below the crotch (the axis's first stretch
//! runs from the crotch on the midline to the thigh's centre) to the ankle.
//! A limb cut whose loop is larger than `max_loop_area_ratio` times the
//! part's own slice area there (the other thigh or the trunk was caught)
//! moves distally by 2 % of the part until it is the limb's own loop.
//! | upper arm | upper arm circumference | ⟂ arm axis at 28 % of shoulder→wrist (midway shoulder-elbow) |
//! | elbow | elbow circumference | ⟂ arm axis at 56 % of shoulder→wrist |
//! | forearm | forearm circumference | ⟂ arm axis, largest equivalent radius between 62 % and 80 % of shoulder→wrist |
//! | wrist | wrist circumference | ⟂ arm axis at the wrist landmark (the arm's girth minimum) |
//!
//! Lengths: **stature** (ISO: stature) is the body's extent along up;
//! **crotch height / inseam** (ISO: crotch height) is the crotch landmark's
//! height above the soles; **arm length** is the arc length of the arm axis
//! from the shoulder landmark to the wrist landmark (ISO has shoulder-elbow
//! and forearm-hand lengths; ours is their sum up to the wrist, measured
//! along the axis); **shoulder breadth** (ISO: biacromial breadth) is the
//! straight distance between the two shoulder landmarks (the arm axes'
//! upper ends, about 2 % H above the armpits: a stand-in for the acromia).
//!
//! Limbs are measured on the body's left side when it is found, else the
//! right.
//!
//! # Volume and surface area
//!
//! The body is cut by `volume_levels` horizontal planes at the centres of
//! equal slabs of thickness `h`; every loop is fitted with a curve. The
//! volume is the midpoint rule `V = h Σ_k Σ_i A(C_{k,i})` on the curves' exact
//! areas. The surface area is that of the stack of curves: between
//! consecutive levels, loops that match one-to-one (centroids within half
//! the smaller equivalent radius, areas within a factor 0.7) are joined by a
//! band of triangles between `M` samples of each curve, evenly spaced by
//! arc length (start points aligned by the cyclic shift of least squared
//! distance). Where the topology changes (crotch, armpits, fingers: a loop
//! without a match, or one within reach of a matched pair) the perimeters
//! of the unjoined loops are added as walls of half a slab and the
//! difference of their areas as a horizontal cap. Without the reach rule
//! the trunk's band at the armpit spanned to the shoulders (+4 % area). Both are compared with the input mesh's own
//! [`Mesh::signed_volume`] and [`Mesh::surface_area`].

use crate::anatomy::{BodyGeometry, LandmarkKind, PartName};
use crate::curve::fit::{fit_loop, FitError, FitOptions};
use crate::curve::trig::TrigCurve;
use crate::geom::holes::close_holes;
use crate::geom::math::{mean_radius, Point3, Real, Vec3};
use crate::geom::mesh::Mesh;
use crate::geom::tolerance::SIZING_ACCURACY;
use crate::section::girth::{polygon_perimeter, polygon_tape_girth, tape_girth};
use crate::section::mesh::{MeshSlicer, Plane, SectionError, SectionLoop};
use crate::segment::{cut_part, segment, PartAxis, SegmentError, SegmentOptions, Segmentation};
use thiserror::Error;

/// Options of [`measure_mesh`]; every field has a documented default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasureOptions {
    /// Segmentation options (default [`SegmentOptions::default`]).
    pub segment: SegmentOptions,
    /// Fit options for each girth's loop. Default: [`FitOptions::default`]
    /// with `ea = 0.002`, `em = 0.01` (a 2 mm average error on a 1 m girth
    /// would show in the girth; tighter tolerances cost higher orders).
    pub fit: FitOptions,
    /// Fit options for the volume/area slices. Default: the defaults of
    /// [`FitOptions`] with `allow_non_planar` (loops are planar anyway).
    pub slice_fit: FitOptions,
    /// Chest plane below the higher armpit, as a fraction of `H`.
    /// Default 0.025 (≈ 4 cm: the mesosternale level).
    pub chest_below_armpit: Real,
    /// Lowest hip plane above the crotch, as a fraction of `H`. Default 0.02.
    pub hip_search_start: Real,
    /// Relative accuracy of the curve perimeters (the trapezoid rule's
    /// doubling stops when two estimates agree to it). Default 1e-6: 1 µm
    /// on a 1 m girth. The curve's own default, 1e-10, doubles up to 2^16
    /// samples on curves with tight bends.
    pub perimeter_accuracy: Real,
    /// Planes tried in each waist/hip search. Default 32.
    pub search_levels: usize,
    /// Horizontal slabs for volume and surface area. Default 300
    /// (≈ 6 mm on a 1.75 m body; the midpoint rule's error falls as `h²`).
    pub volume_levels: usize,
    /// Samples per curve for the surface bands. Default 512: a band's
    /// triangles skew by up to half a sample spacing, which must stay well
    /// under the slab thickness.
    pub band_samples: usize,
    /// A section polygon is resampled to at least this many points evenly
    /// spaced by arc length before it is fitted. Default 256: a coarse
    /// mesh cuts a wrist in ~30 points, and an order-15 fit through 30
    /// points oscillates between them; the dense polygon pins the curve
    /// to the straight edges.
    pub fit_samples: usize,
    /// The legs are measured from the first axis point this far below the
    /// crotch (fraction of `H`); the axis's first stretch runs from the
    /// crotch on the midline to the thigh's centre. Default 0.03.
    pub leg_start_below_crotch: Real,
    /// A limb cut whose loop is more than this many times the area of the
    /// part's slices there (`π r²`) has caught a neighbour (the other
    /// thigh, the trunk); the plane moves distally by 2 % of the part until
    /// it does not. Default 1.6.
    pub max_loop_area_ratio: Real,
}

impl Default for MeasureOptions {
    fn default() -> Self {
        MeasureOptions {
            segment: SegmentOptions::default(),
            fit: FitOptions {
                ea: 0.002,
                em: 0.01,
                ..FitOptions::default()
            },
            slice_fit: FitOptions {
                allow_non_planar: true,
                ..FitOptions::default()
            },
            chest_below_armpit: 0.025,
            hip_search_start: 0.02,
            perimeter_accuracy: SIZING_ACCURACY,
            search_levels: 32,
            volume_levels: 300,
            band_samples: 512,
            fit_samples: 256,
            leg_start_below_crotch: 0.03,
            max_loop_area_ratio: 1.6,
        }
    }
}

/// What went wrong in [`measure_mesh`]. Each message says what was missing.
#[derive(Debug, Error, PartialEq)]
pub enum MeasureError {
    #[error("bad option {name}: {why}")]
    BadOption {
        name: &'static str,
        why: &'static str,
    },
    #[error("segmentation failed: {0}")]
    Segment(#[from] SegmentError),
    #[error("section failed: {0}")]
    Section(#[from] SectionError),
    #[error("{measurement}: the landmark {landmark} was not found on this body")]
    MissingLandmark {
        measurement: &'static str,
        landmark: LandmarkKind,
    },
    #[error("{measurement}: the part {part} was not found on this body")]
    MissingPart {
        measurement: &'static str,
        part: PartName,
    },
    #[error("the model has no parts (or no extent) to measure")]
    NoParts,
    #[error("{measurement}: the plane meets no loop of the body")]
    EmptySection { measurement: &'static str },
    #[error("{measurement}: fitting its section failed: {source}")]
    Fit {
        measurement: &'static str,
        source: FitError,
    },
}

/// What a measurement is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeasurementKind {
    /// A tape girth around a section (closed curve).
    Girth,
    /// A height above the soles.
    Height,
    /// A length along the body.
    Length,
    /// A straight distance across the body.
    Breadth,
}

impl MeasurementKind {
    /// The lower-case name used in tables and JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            MeasurementKind::Girth => "girth",
            MeasurementKind::Height => "height",
            MeasurementKind::Length => "length",
            MeasurementKind::Breadth => "breadth",
        }
    }
}

/// A girth's section, curve and the same girth measured on the input.
#[derive(Clone, Debug, PartialEq)]
pub struct Girth {
    /// The plane the girth is taken in.
    pub plane: Plane,
    /// The fitted curve of the section loop.
    pub curve: TrigCurve,
    /// The least-squares ellipse of the same loop (the paper's baseline),
    /// when it could be fitted (for a model: of the input's loop, once
    /// compared with one; see the model's measurement).
    pub ellipse: Option<TrigCurve>,
    /// The input's section loop (mesh polygon); empty for a model measured
    /// without an input.
    pub outline: Vec<Point3>,
    /// The curve's perimeter `∫|P'(v)| dv`.
    pub perimeter: Real,
    /// The curve's tape girth (convex-hull perimeter): the girth's value.
    pub tape: Real,
    /// The perimeter of the input's section polygon (NaN when there is no
    /// input to compare with).
    pub mesh_perimeter: Real,
    /// The convex-hull perimeter of the input's section polygon (NaN when
    /// there is no input).
    pub mesh_tape: Real,
}

/// One measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// Short name (`"waist"`, `"stature"`).
    pub name: &'static str,
    pub kind: MeasurementKind,
    /// In the input's length unit.
    pub value: Real,
    /// The ISO 7250-1 name, where the standard has the measurement.
    pub iso: Option<&'static str>,
    /// How it is taken, in words.
    pub definition: &'static str,
    /// For girths: the plane, the curve and the direct mesh measurement.
    pub girth: Option<Girth>,
}

/// Volume or surface area of the curve model and of the input mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// From the section curves (or the body model's surfaces).
    pub model: Real,
    /// From the input mesh itself (NaN when there is none).
    pub mesh: Real,
}

impl Comparison {
    /// `model / mesh − 1`.
    pub fn relative_difference(&self) -> Real {
        self.model / self.mesh - 1.0
    }
}

/// Everything [`measure_mesh`] finds.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurements {
    pub measurements: Vec<Measurement>,
    pub volume: Comparison,
    pub surface_area: Comparison,
    /// The fitted curves of the horizontal slices (volume, surface area),
    /// bottom to top; loops that could not be fitted are left out (their
    /// polygons still count).
    pub slice_curves: Vec<TrigCurve>,
    /// The slab thickness `h` of the slices.
    pub slice_spacing: Real,
    /// Measurements that could not be taken (a missing arm), in words.
    pub warnings: Vec<String>,
}

impl Measurements {
    /// The measurement of a name.
    pub fn get(&self, name: &str) -> Option<&Measurement> {
        self.measurements.iter().find(|m| m.name == name)
    }
}

/// Where a limb girth's plane goes along its part axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LimbPlace {
    /// At this arc-length fraction of the part.
    At(Real),
    /// Where the equivalent radius is largest in this fraction range.
    Largest(Real, Real),
    /// Where the equivalent radius is smallest in this fraction range.
    Smallest(Real, Real),
    /// At the landmark (projected on the axis).
    Landmark,
}

/// A girth's definition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GirthDefinition {
    pub name: &'static str,
    pub iso: Option<&'static str>,
    pub definition: &'static str,
    pub place: GirthPlace,
}

/// Where a girth's plane goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GirthPlace {
    /// Horizontal, on the torso: chest, waist, hip.
    Torso(TorsoLevel),
    /// Perpendicular to the head/neck axis at the neck landmark.
    Neck,
    /// Perpendicular to the leg axis.
    Leg(LimbPlace),
    /// Perpendicular to the arm axis; fractions are of the shoulder→wrist
    /// arc length.
    Arm(LimbPlace),
}

/// The torso levels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TorsoLevel {
    Chest,
    Waist,
    Hip,
}

/// The girths, in the order they are reported.
pub const GIRTHS: [GirthDefinition; 12] = [
    GirthDefinition {
        name: "neck",
        iso: Some("neck circumference"),
        definition: "horizontal at the neck landmark (the smallest horizontal convex-hull girth between the armpits and the head)",
        place: GirthPlace::Neck,
    },
    GirthDefinition {
        name: "chest",
        iso: Some("chest circumference"),
        definition: "horizontal, 0.025 H below the higher armpit (mesosternale level), torso loop only",
        place: GirthPlace::Torso(TorsoLevel::Chest),
    },
    GirthDefinition {
        name: "waist",
        iso: Some("waist circumference"),
        definition: "horizontal, the smallest torso tape girth between 35 % and 85 % of the way from the crotch to the chest level (natural waist)",
        place: GirthPlace::Torso(TorsoLevel::Waist),
    },
    GirthDefinition {
        name: "hip",
        iso: Some("hip circumference"),
        definition: "horizontal, the largest torso tape girth from 0.02 H above the crotch up to the waist (over the buttocks)",
        place: GirthPlace::Torso(TorsoLevel::Hip),
    },
    GirthDefinition {
        name: "thigh",
        iso: Some("thigh circumference"),
        definition: "perpendicular to the leg axis at 10 % of its length from 0.03 H below the crotch to the ankle (just below the gluteal fold); moved down while the loop holds both thighs",
        place: GirthPlace::Leg(LimbPlace::At(0.1)),
    },
    GirthDefinition {
        name: "knee",
        iso: Some("knee circumference"),
        definition: "perpendicular to the leg axis at 45 % of its length (0.03 H below the crotch to the ankle)",
        place: GirthPlace::Leg(LimbPlace::At(0.45)),
    },
    GirthDefinition {
        name: "calf",
        iso: Some("calf circumference"),
        definition: "perpendicular to the leg axis where its equivalent radius is largest between 55 % and 85 % of its length",
        place: GirthPlace::Leg(LimbPlace::Largest(0.55, 0.85)),
    },
    GirthDefinition {
        name: "ankle",
        iso: Some("ankle circumference"),
        definition: "perpendicular to the leg axis where its equivalent radius is smallest between 85 % and 97 % of its length (above the malleoli)",
        place: GirthPlace::Leg(LimbPlace::Smallest(0.85, 0.97)),
    },
    GirthDefinition {
        name: "upper arm",
        iso: Some("upper arm circumference"),
        definition: "perpendicular to the arm axis at 28 % of the shoulder→wrist length (midway shoulder-elbow)",
        place: GirthPlace::Arm(LimbPlace::At(0.28)),
    },
    GirthDefinition {
        name: "elbow",
        iso: Some("elbow circumference"),
        definition: "perpendicular to the arm axis at 56 % of the shoulder→wrist length",
        place: GirthPlace::Arm(LimbPlace::At(0.56)),
    },
    GirthDefinition {
        name: "forearm",
        iso: Some("forearm circumference"),
        definition: "perpendicular to the arm axis where its equivalent radius is largest between 62 % and 80 % of the shoulder→wrist length",
        place: GirthPlace::Arm(LimbPlace::Largest(0.62, 0.8)),
    },
    GirthDefinition {
        name: "wrist",
        iso: Some("wrist circumference"),
        definition: "perpendicular to the arm axis at the wrist landmark (the forearm's smallest convex-hull girth)",
        place: GirthPlace::Arm(LimbPlace::Landmark),
    },
];

/// Measures a body given as a closed surface mesh: segments it, takes every
/// girth of [`GIRTHS`] from fitted section curves (with the same girth on
/// the mesh section alongside), the lengths, and volume and surface area
/// of the stack of horizontal section curves. See the module docs for the
/// definitions.
///
/// This is the one place an input becomes measurements; a reconstructed
/// body model will plug in here by supplying its curves instead of fitting
/// sections of the mesh.
pub fn measure_mesh(mesh: &Mesh, opts: &MeasureOptions) -> Result<Measurements, MeasureError> {
    if opts.volume_levels < 8 {
        return Err(MeasureError::BadOption {
            name: "volume_levels",
            why: "at least 8 slabs are needed",
        });
    }
    if opts.band_samples < 8 {
        return Err(MeasureError::BadOption {
            name: "band_samples",
            why: "at least 8 samples per curve are needed",
        });
    }
    if opts.search_levels < 2 {
        return Err(MeasureError::BadOption {
            name: "search_levels",
            why: "at least 2 levels are needed",
        });
    }
    if !(opts.chest_below_armpit.is_finite() && opts.hip_search_start.is_finite()) {
        return Err(MeasureError::BadOption {
            name: "chest_below_armpit / hip_search_start",
            why: "must be finite",
        });
    }
    // Girths through a hole are open chains and an open mesh has no volume:
    // its holes are closed first.
    let closed = close_holes(mesh);
    let mut warnings = Vec::new();
    if let Some((_, holes)) = &closed {
        warnings.push(format!(
            "closed {} hole(s) in the mesh ({:.2} % of its area added); girths and volume are of the closed mesh",
            holes.holes,
            100.0 * holes.area_share
        ));
    }
    let mesh = closed.as_ref().map_or(mesh, |c| &c.0);
    let seg = segment(BodyGeometry::Mesh(mesh), &opts.segment)?;
    let up = seg.frame.up;
    let floor = seg.frame.origin.dot(up);
    let h = seg.height;
    let slicer = MeshSlicer::new(mesh, up, &opts.segment.section)?;
    let mut measurements = Vec::new();

    measurements.push(Measurement {
        name: "stature",
        kind: MeasurementKind::Height,
        value: h,
        iso: Some("stature (body height)"),
        definition: "extent of the body along its up axis, soles to head top",
        girth: None,
    });

    // Chest, waist and hip need the crotch and an armpit; without them the
    // other measurements are still taken, with a warning.
    let torso = match TorsoLevels::find(&seg, &slicer, opts) {
        Ok(t) => Some(t),
        Err(e @ (MeasureError::MissingPart { .. } | MeasureError::MissingLandmark { .. })) => {
            warnings.push(format!("chest, waist, hip: {e}"));
            None
        }
        Err(e) => return Err(e),
    };
    for def in GIRTHS.iter() {
        let result = match (def.place, &torso) {
            (GirthPlace::Torso(_), None) => continue,
            (_, torso) => girth_at(mesh, &seg, &slicer, torso.as_ref(), def, opts),
        };
        match result {
            Ok(g) => measurements.push(Measurement {
                name: def.name,
                kind: MeasurementKind::Girth,
                value: g.tape,
                iso: def.iso,
                definition: def.definition,
                girth: Some(g),
            }),
            Err(e @ (MeasureError::MissingPart { .. } | MeasureError::MissingLandmark { .. })) => {
                warnings.push(e.to_string())
            }
            Err(e) => return Err(e),
        }
    }

    match seg.landmark(LandmarkKind::Crotch) {
        Some(c) => measurements.push(Measurement {
            name: "inseam",
            kind: MeasurementKind::Height,
            value: c.position.dot(up) - floor,
            iso: Some("crotch height"),
            definition: "height of the crotch landmark (where the legs join) above the soles",
            girth: None,
        }),
        None => warnings.push("inseam: no crotch landmark".into()),
    }
    match arm_side(&seg) {
        Some((arm, shoulder, wrist)) => {
            let (a, b) = (axis_fraction(arm, shoulder), axis_fraction(arm, wrist));
            measurements.push(Measurement {
                name: "arm length",
                kind: MeasurementKind::Length,
                value: (b - a).abs() * arm.length(),
                iso: Some("shoulder-elbow length + forearm length (to the wrist)"),
                definition:
                    "arc length of the arm axis from the shoulder landmark to the wrist landmark",
                girth: None,
            });
        }
        None => warnings.push("arm length: no arm with shoulder and wrist landmarks".into()),
    }
    match (
        seg.landmark(LandmarkKind::LeftShoulder),
        seg.landmark(LandmarkKind::RightShoulder),
    ) {
        (Some(l), Some(r)) => measurements.push(Measurement {
            name: "shoulder breadth",
            kind: MeasurementKind::Breadth,
            value: l.position.distance(r.position),
            iso: Some("biacromial breadth"),
            definition:
                "straight distance between the two shoulder landmarks (upper ends of the arm axes)",
            girth: None,
        }),
        _ => warnings.push("shoulder breadth: both shoulders are needed".into()),
    }

    let stack = slice_stack(&slicer, opts)?;
    Ok(Measurements {
        measurements,
        volume: Comparison {
            model: stack.volume,
            mesh: mesh.signed_volume().abs(),
        },
        surface_area: Comparison {
            model: stack.area,
            mesh: mesh.surface_area(),
        },
        slice_curves: stack.curves,
        slice_spacing: stack.spacing,
        warnings,
    })
}

/// The closed-form part of the measurements, given the curves: each girth
/// curve's perimeter `∫|P'(v)| dv` and tape girth (convex-hull perimeter),
/// and the volume `h Σ A(C)` of slice curves `h` apart. This is what a
/// body model's measurements cost once its curves exist (the benchmark
/// `measure` times it).
pub fn girths_and_volume(
    girth_curves: &[&TrigCurve],
    slice_curves: &[TrigCurve],
    spacing: Real,
    perimeter_accuracy: Real,
) -> (Vec<(Real, Real)>, Real) {
    let girths = girth_curves
        .iter()
        .map(|c| (c.perimeter_with_accuracy(perimeter_accuracy), tape_girth(c)))
        .collect();
    let volume = spacing * slice_curves.iter().map(TrigCurve::area).sum::<Real>();
    (girths, volume)
}

/// The chest, waist and hip planes' heights (absolute, along up).
struct TorsoLevels {
    chest: Real,
    waist: Real,
    hip: Real,
}

impl TorsoLevels {
    fn find(
        seg: &Segmentation,
        slicer: &MeshSlicer<'_>,
        opts: &MeasureOptions,
    ) -> Result<TorsoLevels, MeasureError> {
        let up = seg.frame.up;
        let h = seg.height;
        let torso = seg.part(PartName::Torso).ok_or(MeasureError::MissingPart {
            measurement: "chest",
            part: PartName::Torso,
        })?;
        let crotch = seg
            .landmark(LandmarkKind::Crotch)
            .ok_or(MeasureError::MissingLandmark {
                measurement: "hip",
                landmark: LandmarkKind::Crotch,
            })?
            .position
            .dot(up);
        let armpit = [LandmarkKind::LeftArmpit, LandmarkKind::RightArmpit]
            .iter()
            .filter_map(|&k| seg.landmark(k))
            .map(|l| l.position.dot(up))
            .fold(Real::NEG_INFINITY, Real::max);
        if !armpit.is_finite() {
            return Err(MeasureError::MissingLandmark {
                measurement: "chest",
                landmark: LandmarkKind::LeftArmpit,
            });
        }
        let chest = armpit - opts.chest_below_armpit * h;
        let n = opts.search_levels;
        let tape_at = |level: Real| -> Option<Real> {
            let s = slicer.section_at(level).ok()?;
            let k = s.select(torso_point(torso, up, level))?;
            Some(polygon_tape_girth(&s.loops[k].plane_points()))
        };
        let search = |lo: Real, hi: Real, largest: bool| -> Real {
            let mut best = (0.5 * (lo + hi), if largest { 0.0 } else { Real::MAX });
            for i in 0..n {
                let level = lo + (hi - lo) * i as Real / (n - 1) as Real;
                if let Some(g) = tape_at(level) {
                    if (largest && g > best.1) || (!largest && g < best.1) {
                        best = (level, g);
                    }
                }
            }
            best.0
        };
        let waist = search(
            crotch + 0.35 * (chest - crotch),
            crotch + 0.85 * (chest - crotch),
            false,
        );
        let hip = search(crotch + opts.hip_search_start * h, waist, true);
        Ok(TorsoLevels { chest, waist, hip })
    }
}

/// The torso axis point at absolute height `level` (linear interpolation
/// along up; the ends are held).
fn torso_point(torso: &PartAxis, up: Vec3, level: Real) -> Point3 {
    let pts = &torso.points;
    let Some(first) = pts.first() else {
        return up * level;
    };
    let mut best = *first;
    for w in pts.windows(2) {
        let (a, b) = (w[0].dot(up), w[1].dot(up));
        if (a - level) * (b - level) <= 0.0 && a != b {
            let u = (level - a) / (b - a);
            return w[0] + (w[1] - w[0]) * u;
        }
        if (w[1].dot(up) - level).abs() < (best.dot(up) - level).abs() {
            best = w[1];
        }
    }
    best + up * (level - best.dot(up))
}

/// The arc-length fraction of the axis point nearest to `p`.
fn axis_fraction(axis: &PartAxis, p: Point3) -> Real {
    let total = axis.length();
    if total <= 0.0 {
        return 0.0;
    }
    let mut acc = 0.0;
    let mut best = (Real::MAX, 0.0);
    for w in axis.points.windows(2) {
        let d = w[1] - w[0];
        let len = d.norm();
        let u = if len > 0.0 {
            ((p - w[0]).dot(d) / (len * len)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = w[0] + d * u;
        let dist = q.distance(p);
        if dist < best.0 {
            best = (dist, acc + u * len);
        }
        acc += len;
    }
    best.1 / total
}

/// The measured arm (left when found) with its shoulder and wrist.
fn arm_side(seg: &Segmentation) -> Option<(&PartAxis, Point3, Point3)> {
    [
        (
            PartName::LeftArm,
            LandmarkKind::LeftShoulder,
            LandmarkKind::LeftWrist,
        ),
        (
            PartName::RightArm,
            LandmarkKind::RightShoulder,
            LandmarkKind::RightWrist,
        ),
    ]
    .iter()
    .find_map(|&(p, s, w)| {
        Some((
            seg.part(p)?,
            seg.landmark(s)?.position,
            seg.landmark(w)?.position,
        ))
    })
}

/// The axis fraction of a [`LimbPlace`] within `[lo, hi]` of the axis.
fn limb_fraction(axis: &PartAxis, place: LimbPlace, lo: Real, hi: Real, landmark: Real) -> Real {
    let span = |f: Real| lo + f * (hi - lo);
    let extreme = |a: Real, b: Real, largest: bool| -> Real {
        let n = axis.points.len();
        let total = axis.length();
        let mut acc = 0.0;
        let mut best: Option<(Real, Real)> = None;
        for k in 0..n {
            if k > 0 {
                acc += axis.points[k].distance(axis.points[k - 1]);
            }
            let t = if total > 0.0 { acc / total } else { 0.0 };
            let Some(&r) = axis.radii.get(k) else { break };
            if t < span(a) || t > span(b) {
                continue;
            }
            let better = match best {
                None => true,
                Some((_, br)) => (largest && r > br) || (!largest && r < br),
            };
            if better {
                best = Some((t, r));
            }
        }
        best.map_or(span(0.5 * (a + b)), |b| b.0)
    };
    match place {
        LimbPlace::At(f) => span(f),
        LimbPlace::Largest(a, b) => extreme(a, b, true),
        LimbPlace::Smallest(a, b) => extreme(a, b, false),
        LimbPlace::Landmark => landmark,
    }
}

fn girth_at(
    mesh: &Mesh,
    seg: &Segmentation,
    slicer: &MeshSlicer<'_>,
    torso: Option<&TorsoLevels>,
    def: &GirthDefinition,
    opts: &MeasureOptions,
) -> Result<Girth, MeasureError> {
    let name = def.name;
    let up = seg.frame.up;
    let body = BodyGeometry::Mesh(mesh);
    let missing_part = |part| MeasureError::MissingPart {
        measurement: name,
        part,
    };
    let (plane, outline): (Plane, SectionLoop) = match def.place {
        GirthPlace::Torso(level) => {
            let axis = seg
                .part(PartName::Torso)
                .ok_or(missing_part(PartName::Torso))?;
            let torso = torso.ok_or(MeasureError::MissingPart {
                measurement: name,
                part: PartName::Torso,
            })?;
            let offset = match level {
                TorsoLevel::Chest => torso.chest,
                TorsoLevel::Waist => torso.waist,
                TorsoLevel::Hip => torso.hip,
            };
            let origin = torso_point(axis, up, offset);
            let s = slicer.section_at(offset)?;
            let k = s
                .select(origin)
                .ok_or(MeasureError::EmptySection { measurement: name })?;
            (Plane::new(origin, up)?, s.loops[k].clone())
        }
        GirthPlace::Neck => {
            let neck = seg
                .landmark(LandmarkKind::Neck)
                .ok_or(MeasureError::MissingLandmark {
                    measurement: name,
                    landmark: LandmarkKind::Neck,
                })?;
            let offset = neck.position.dot(up);
            let s = slicer.section_at(offset)?;
            let k = s
                .select(neck.position)
                .ok_or(MeasureError::EmptySection { measurement: name })?;
            (Plane::new(neck.position, up)?, s.loops[k].clone())
        }
        GirthPlace::Leg(place) => {
            let (part, axis) = [PartName::LeftLeg, PartName::RightLeg]
                .iter()
                .find_map(|&p| seg.part(p).map(|a| (p, a)))
                .ok_or(missing_part(PartName::LeftLeg))?;
            let lo = leg_start(axis, up, opts.leg_start_below_crotch * seg.height);
            let t = limb_fraction(axis, place, lo, 1.0, 1.0);
            own_loop_cut(body, seg, part, axis, t, opts)?
        }
        GirthPlace::Arm(place) => {
            let (axis, shoulder, wrist) = arm_side(seg).ok_or(missing_part(PartName::LeftArm))?;
            let part = axis.name;
            let lo = axis_fraction(axis, shoulder);
            let hi = axis_fraction(axis, wrist);
            let t = limb_fraction(axis, place, lo, hi, hi);
            own_loop_cut(body, seg, part, axis, t, opts)?
        }
    };
    let fit_opts = FitOptions {
        normal: Some(plane.normal),
        allow_non_planar: true,
        ..opts.fit
    };
    let dense = crate::section::mesh::resample_closed(
        &outline.points,
        opts.fit_samples.max(outline.points.len()),
    );
    let fit = fit_loop(&dense, &fit_opts).map_err(|source| MeasureError::Fit {
        measurement: name,
        source,
    })?;
    let poly = outline.plane_points();
    Ok(Girth {
        plane,
        perimeter: fit.curve.perimeter_with_accuracy(opts.perimeter_accuracy),
        tape: tape_girth(&fit.curve),
        ellipse: fit.ellipse_curve(),
        curve: fit.curve,
        mesh_perimeter: polygon_perimeter(&poly),
        mesh_tape: polygon_tape_girth(&poly),
        outline: outline.points,
    })
}

/// The horizontal stack of fitted curves: volume and surface area.
struct SliceStack {
    volume: Real,
    area: Real,
    curves: Vec<TrigCurve>,
    spacing: Real,
}

/// One fitted slice loop: its curve's samples, area and centroid.
struct SliceCurve {
    samples: Vec<Point3>,
    area: Real,
    perimeter: Real,
    centroid: Point3,
    radius: Real,
    /// The largest distance of a sample from the centroid.
    reach: Real,
}

fn slice_stack(slicer: &MeshSlicer<'_>, opts: &MeasureOptions) -> Result<SliceStack, MeasureError> {
    let (lo, hi) = slicer.range();
    let n = opts.volume_levels;
    let dh = (hi - lo) / n as Real;
    let m = opts.band_samples;
    let mut levels: Vec<Vec<SliceCurve>> = Vec::with_capacity(n);
    let mut curves = Vec::new();
    for k in 0..n {
        let s = slicer.section_at(lo + (k as Real + 0.5) * dh)?;
        let mut here = Vec::new();
        for (li, l) in s.loops.iter().enumerate() {
            // Even-odd rule: a loop inside an odd number of others bounds a
            // hole (a cavity of the surface), its area counts negative.
            let depth = s
                .loops
                .iter()
                .enumerate()
                .filter(|&(lj, o)| lj != li && l.points.first().is_some_and(|&p| o.contains(p)))
                .count();
            let sign = if depth % 2 == 1 { -1.0 } else { 1.0 };
            let dense = crate::section::mesh::resample_closed(
                &l.points,
                opts.fit_samples.max(l.points.len()),
            );
            let fit = fit_loop(
                &dense,
                &FitOptions {
                    normal: Some(slicer.axis()),
                    ..opts.slice_fit
                },
            );
            // A loop too small or degenerate to fit is measured as its
            // polygon (a fingertip grazed by the plane).
            let (samples, area, perimeter, centroid) = match fit {
                // Samples evenly spaced by arc length: rings of two levels
                // then correspond by arc fraction. Equal steps of `v` do
                // not: the parameter's speed differs between fits, and the
                // band's triangles shear along the ring (adding area).
                Ok(f) => {
                    let out = (
                        crate::section::mesh::resample_closed(&f.curve.sample(4 * m), m),
                        f.curve.area(),
                        f.curve.perimeter(),
                        f.curve.area_centroid().unwrap_or(l.centroid),
                    );
                    curves.push(f.curve);
                    out
                }
                Err(_) => (
                    crate::section::mesh::resample_closed(&l.points, m),
                    l.area,
                    l.perimeter,
                    l.centroid,
                ),
            };
            let reach = samples
                .iter()
                .map(|p| p.distance(centroid))
                .fold(0.0, Real::max);
            here.push(SliceCurve {
                samples,
                area: sign * area,
                perimeter,
                centroid,
                radius: mean_radius(area),
                reach,
            });
        }
        levels.push(here);
    }
    let volume: Real = levels.iter().flatten().map(|c| c.area).sum::<Real>() * dh;
    // Ends: the first and last levels are capped, with half-slab walls.
    let mut area = 0.0;
    for end in [levels.first(), levels.last()].into_iter().flatten() {
        for c in end {
            area += c.area + 0.5 * dh * c.perimeter;
        }
    }
    for w in levels.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        let parent_of = |c: &SliceCurve, others: &[SliceCurve]| -> Option<usize> {
            others
                .iter()
                .enumerate()
                .map(|(i, o)| (i, o.centroid.distance(c.centroid)))
                .filter(|&(i, d)| {
                    let o = &others[i];
                    let ratio = o.area.abs() / c.area.abs();
                    d < 0.5 * o.radius.min(c.radius) && (0.7..=1.0 / 0.7).contains(&ratio)
                })
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .map(|(i, _)| i)
        };
        let down: Vec<Option<usize>> = b.iter().map(|c| parent_of(c, a)).collect();
        let up: Vec<Option<usize>> = a.iter().map(|c| parent_of(c, b)).collect();
        // A pair is joined by a band when each is the other's match and no
        // loop left unmatched on either side lies within reach of the pair
        // (an arm merging into the trunk at the armpit).
        let mut pairs: Vec<(usize, usize)> = (0..b.len())
            .filter_map(|j| {
                let i = down[j]?;
                (up[i] == Some(j) && down.iter().filter(|&&d| d == Some(i)).count() == 1)
                    .then_some((i, j))
            })
            .collect();
        let matched_a: Vec<bool> = (0..a.len())
            .map(|i| pairs.iter().any(|p| p.0 == i))
            .collect();
        let matched_b: Vec<bool> = (0..b.len())
            .map(|j| pairs.iter().any(|p| p.1 == j))
            .collect();
        pairs.retain(|&(i, j)| {
            let near = |c: &SliceCurve| {
                c.centroid.distance(a[i].centroid) < a[i].reach + c.radius
                    || c.centroid.distance(b[j].centroid) < b[j].reach + c.radius
            };
            !(a.iter().zip(&matched_a).any(|(c, &m)| !m && near(c))
                || b.iter().zip(&matched_b).any(|(c, &m)| !m && near(c)))
        });
        let mut free = (0.0, 0.0);
        for (i, c) in a.iter().enumerate() {
            if !pairs.iter().any(|p| p.0 == i) {
                area += 0.5 * dh * c.perimeter;
                free.0 += c.area;
            }
        }
        for (j, c) in b.iter().enumerate() {
            if !pairs.iter().any(|p| p.1 == j) {
                area += 0.5 * dh * c.perimeter;
                free.1 += c.area;
            }
        }
        for &(i, j) in &pairs {
            area += band_area(&a[i].samples, &b[j].samples);
        }
        // Flat area where the topology changes: the difference between the
        // areas not joined by bands on either side.
        area += (free.0 - free.1).abs();
    }
    Ok(SliceStack {
        volume,
        area,
        curves,
        spacing: dh,
    })
}

/// The area of the band of triangles between two closed sample rings of
/// the same length, the second shifted cyclically to lie closest to the
/// first (least summed squared distance).
fn band_area(a: &[Point3], b: &[Point3]) -> Real {
    let m = a.len();
    if m == 0 || b.len() != m {
        return 0.0;
    }
    // Every shift, scored on 64 of the samples (enough to place a ring).
    let stride = (m / 64).max(1);
    let shift = (0..m)
        .map(|s| {
            let d: Real = (0..m)
                .step_by(stride)
                .map(|i| (a[i] - b[(i + s) % m]).norm_squared())
                .sum();
            (s, d)
        })
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map_or(0, |x| x.0);
    let tri = |p: Point3, q: Point3, r: Point3| 0.5 * (q - p).cross(r - p).norm();
    (0..m)
        .map(|i| {
            let (a0, a1) = (a[i], a[(i + 1) % m]);
            let (b0, b1) = (b[(i + shift) % m], b[(i + 1 + shift) % m]);
            tri(a0, a1, b1) + tri(a0, b1, b0)
        })
        .sum()
}

/// The arc-length fraction of the first leg axis point at least `below`
/// under the axis's start (the crotch).
fn leg_start(axis: &PartAxis, up: Vec3, below: Real) -> Real {
    let Some(first) = axis.points.first() else {
        return 0.0;
    };
    let top = first.dot(up);
    let total = axis.length();
    let mut acc = 0.0;
    for k in 1..axis.points.len() {
        acc += axis.points[k].distance(axis.points[k - 1]);
        if top - axis.points[k].dot(up) >= below {
            return if total > 0.0 { acc / total } else { 0.0 };
        }
    }
    0.0
}

/// The equivalent radius of the part's slices nearest to fraction `t`.
fn radius_at(axis: &PartAxis, t: Real) -> Option<Real> {
    let total = axis.length();
    let mut acc = 0.0;
    let mut best: Option<(Real, Real)> = None;
    for k in 0..axis.points.len() {
        if k > 0 {
            acc += axis.points[k].distance(axis.points[k - 1]);
        }
        let tk = if total > 0.0 { acc / total } else { 0.0 };
        let r = *axis.radii.get(k)?;
        if best.is_none_or(|(d, _)| (tk - t).abs() < d) {
            best = Some(((tk - t).abs(), r));
        }
    }
    best.map(|b| b.1)
}

/// Cuts a limb at `t`; when the loop is larger than
/// `max_loop_area_ratio · π r(t)²` (a neighbour was caught), moves the
/// plane distally by 0.02 up to ten times.
fn own_loop_cut(
    body: BodyGeometry<'_>,
    seg: &Segmentation,
    part: PartName,
    axis: &PartAxis,
    t: Real,
    opts: &MeasureOptions,
) -> Result<(Plane, SectionLoop), MeasureError> {
    let mut t = t;
    let mut cut = cut_part(body, seg, part, t, &opts.segment)?;
    for _ in 0..10 {
        let own = radius_at(axis, t)
            .map(|r| std::f64::consts::PI * r * r * opts.max_loop_area_ratio)
            .is_none_or(|limit| cut.outline.area <= limit);
        if own || t >= 0.98 {
            break;
        }
        t += 0.02;
        cut = cut_part(body, seg, part, t, &opts.segment)?;
    }
    Ok((cut.plane, cut.outline))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::shapes;
    use crate::section::mesh::SectionOptions;
    use std::f64::consts::PI;

    #[test]
    fn a_sphere_stack_has_the_sphere_volume_and_area() {
        let sphere = shapes::uv_sphere(Vec3::new(3.0, -2.0, 5.0), 0.5, 96, 192);
        let slicer = MeshSlicer::new(
            &sphere,
            Vec3::new(0.3, 1.0, 0.2),
            &SectionOptions::default(),
        )
        .unwrap();
        let s = slice_stack(&slicer, &MeasureOptions::default()).unwrap();
        let (v, a) = (sphere.signed_volume().abs(), sphere.surface_area());
        eprintln!(
            "stack {} {} mesh {v} {a} exact {} {}",
            s.volume,
            s.area,
            4.0 / 3.0 * PI * 0.125,
            PI
        );
        assert!((s.volume / v - 1.0).abs() < 2e-3);
        assert!((s.area / a - 1.0).abs() < 5e-3);
    }
}

#[cfg(test)]
mod stick_body_tests {
    use super::*;
    use crate::geom::shapes;

    /// The synthetic stick body (overlapping cylinders, arms against the
    /// trunk: no armpits): the torso girths are reported missing with a
    /// warning, the volume of the stack still matches the mesh's, and
    /// nothing panics.
    #[test]
    fn a_body_without_armpits_is_measured_with_warnings() {
        let body = shapes::stick_body(2);
        let m = match measure_mesh(&body, &MeasureOptions::default()) {
            Ok(m) => m,
            // A body the segmentation rejects is a typed error, not a panic.
            Err(e) => {
                assert!(matches!(e, MeasureError::Segment(_)), "{e}");
                return;
            }
        };
        assert!(m.get("chest").is_none());
        assert!(!m.warnings.is_empty());
        assert!(m.get("stature").is_some());
    }

    #[test]
    fn bad_options_are_typed_errors() {
        let body = shapes::stick_body(1);
        let opts = MeasureOptions {
            volume_levels: 2,
            ..MeasureOptions::default()
        };
        assert!(matches!(
            measure_mesh(&body, &opts),
            Err(MeasureError::BadOption {
                name: "volume_levels",
                ..
            })
        ));
    }
}
