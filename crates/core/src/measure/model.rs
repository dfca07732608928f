//! Measurements of a reconstructed body model ([`Body`]) from its own
//! curves (issue 6): stature, twelve girths, inseam, arm length, shoulder
//! breadth, volume and surface area — no mesh involved. [`compare_with_mesh`]
//! then measures the same girths directly on an input mesh, in the same
//! planes, so every number can be checked.
//!
//! # The model's surface
//!
//! A part is a chain of patches `t(u, v) = Σ_m f_m(v) u^m` over axis
//! intervals `[s_i, s_{i+1}]`; the curve of a part at any axis parameter `s`
//! is a trigonometric series `C_s(v)` ([`crate::surface::patch::Patch::curve_at`]). Torso,
//! head and legs are cut by horizontal planes, so their `C_s` are planar and
//! horizontal; arms are cut across their own axis.
//!
//! # A girth in a plane
//!
//! For a plane `(o, n)` crossing a part, the model's section is the closed
//! curve `Q(v) = t(s(v), v)` with `n·(t(s(v), v) − o) = 0`, solved for each
//! `v` by Newton's method in `s` from the `s` where the part's centre line
//! crosses the plane (`f'(s) = n·∂t/∂s`). Where the plane is one of the
//! part's own iso-planes (a horizontal girth on the torso) `s(v)` is
//! constant and `Q = C_s` exactly. `Q` is sampled at
//! [`ModelMeasureOptions::section_samples`] values of `v` and turned into a
//! trigonometric series in the plane by the discrete Fourier transform
//! (exact for `C_s`, whose order is below half the sample count). The
//! girth's perimeter is `∫|Q'(v)| dv` by adaptive quadrature
//! ([`TrigCurve::perimeter_with_accuracy`]); the **tape girth**, the value
//! reported, is the perimeter of the convex hull of `M =`
//! [`ModelMeasureOptions::tape_samples`] samples (a tape bridges concave
//! stretches; the chords of a smooth convex arc fall short by a relative
//! `(π/M)²/6`, 2.5e-5 at 256: 25 µm on a 1 m girth).
//!
//! # Landmarks, from the model itself
//!
//! `up` is the body frame's up axis; heights are along it. `H` is the
//! stature: the extent of the model's surface (parts and caps) along `up`.
//!
//! * **Crotch**: halfway between the torso's first section (it starts just
//!   above the crotch) and the higher of the legs' first sections (they
//!   start just below it).
//! * **Armpit**: the lowest point of each arm's first section (the shoulder
//!   cut across the arm axis); the higher of the two.
//! * **Shoulders**: the centres of the arms' first sections.
//! * **Wrist**: on the arm's centre line between 45 % and 97 % of its length,
//!   the smallest tape girth of those followed distally by a girth at least
//!   15 % larger (the hand): the narrowing between forearm and palm.
//! * **Ankle**: on the leg, the smallest equivalent radius `√(A/π)` between
//!   0.035 H and 0.15 H above the soles.
//!
//! Limb girth planes are perpendicular to the limb's axis: the chord of its
//! centre line over ±[`ModelMeasureOptions::axis_window`] · H about the
//! place, kept between the limb's start and its wrist or ankle. Torso and
//! neck girths are horizontal. The definitions are in [`MODEL_GIRTHS`].
//!
//! # Volume and surface area
//!
//! Each part with its caps, its open ends closed by the planar discs of its
//! end sections, is a closed surface; by the divergence theorem its volume
//! is `V = (1/3) ∮ (P − q)·N dA`. On a patch `N dA = (t_v × t_u) du dv`
//! (outward for curves running counter-clockwise about the axis; the sign
//! is fixed by taking `|V|`), and the cone from a point `q` over a closed
//! curve `C` with mean point `o` contributes `(o − q)·A⃗`, with
//! `A⃗ = ½ ∮ C × C' dv = π Σ_j j a_j × b_j` the curve's vector area
//! (`C = c₀ + Σ_j a_j cos jv + b_j sin jv`; exact, see `vector_area`). Each
//! patch is a slab closed by the cones from its two end curves' mean
//! points, which its neighbours share, so the slabs tile the part; each
//! slab is taken about its own first curve's mean point, where that cone
//! vanishes. About the part's first curve instead, the quadrature's error
//! in `∮ N dA` is multiplied by the distance from there: the legs' volumes
//! came out 3.6e-4 (base), 2.0e-3 (male) and 5.8e-3 (female) over those of
//! their fine tessellations, now within 7e-5 (the `volume_diag` example). A
//! dome or flat cap adds the volume between it and its rim's disc, taken
//! about the rim's mean point. The `u` integrals use 2-point
//! Gauss-Legendre per patch (6 for caps), the `v` integrals the trapezoid
//! rule at `2J + 6` points, `J` the patch's effective order (the
//! trapezoid rule is exact for trigonometric integrands of order below
//! the sample count). With the 6-point rule swapped in for the parts'
//! patches the three shared bodies' models' volumes moved by at most
//! 6e-6; the area is +5.1e-4 relative to it on the male model (3 points:
//! −3.8e-4, at 1.5 times the cost).
//! The surface area is `∬ |t_v × t_u|` over the same nodes, open ends not
//! counted (they are joins).
//!
//! Parts and the transition bands between them (each closed the same way
//! by its two boundary curves' cones, 6 Gauss points in `u`) are summed,
//! then the overlaps are removed: where an arm ends on the torso's side
//! through a transition, the torso's reach past the side plane, inside the
//! transition (see `torso_beyond_side`); where an arm without one starts
//! inside the torso's shoulder loops, the overlap (see
//! `arm_torso_overlap`): its volume by the arm's cross-section area
//! inside the torso, its surface by inside tests of the quadrature nodes.
//! The outlines of those inside tests are 32-gons scaled to their curves'
//! areas (an inscribed 32-gon is 0.6 % short, and the overlap lies along
//! the torso's outline). Where the two skins nearly coincide (the top of
//! the shoulder) the inside tests split that skin between the parts at
//! random: the union's area is right on average but varies a little with
//! the slice settings. The gap
//! at the crotch between the torso's first section and the legs' counts
//! as it is (open).

use crate::anatomy::PartName;
use crate::body::Body;
use crate::curve::ellipse::fit_ellipse;
use crate::curve::series::{harmonics, Series};
use crate::curve::trig::{Frame, SpaceCurve, TrigCurve};
use crate::geom::math::{mean_radius, Point3, Real, Vec2, Vec3};
use crate::geom::mesh::Mesh;
use crate::geom::tolerance::{ROUNDING_MARGIN, SIZING_ACCURACY};
use crate::measure::mesh::{
    Comparison, Girth, MeasureError, Measurement, MeasurementKind, Measurements,
};
use crate::measure::part_curves::*;
use crate::measure::volume::{arm_torso_overlaps, volume_area_extent, VTable};
use crate::section::girth::{polygon_perimeter, polygon_tape_girth};
use crate::section::mesh::{polygon_area_centroid, section_mesh, Plane, SectionOptions};
use crate::surface::part::Part;
use std::f64::consts::TAU;

/// Options of [`measure_body`]; lengths are fractions of the stature `H`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelMeasureOptions {
    /// The chest plane lies this far below the higher armpit. Default 0.025.
    pub chest_below_armpit: Real,
    /// The hip search starts this far above the crotch. Default 0.02.
    pub hip_search_start: Real,
    /// Leg fractions run from this far below the crotch to the ankle.
    /// Default 0.03.
    pub leg_start_below_crotch: Real,
    /// Levels tried by each search (waist, hip, neck, calf, ankle, forearm;
    /// twice as many for the wrist). Default 24.
    pub search_levels: usize,
    /// Samples of a girth's section `Q(v)` (its series has order below half
    /// of this). Default 64.
    pub section_samples: usize,
    /// Samples of a girth curve whose convex hull gives the tape girth.
    /// Default 256 (chords short by a relative 2.5e-5 on a smooth convex
    /// arc: 25 µm on a 1 m girth).
    pub tape_samples: usize,
    /// Relative accuracy of the perimeter quadrature. Default 1e-6.
    pub perimeter_accuracy: Real,
    /// Half-width of the centre-line chord giving a limb's axis. Default 0.03.
    pub axis_window: Real,
}

impl Default for ModelMeasureOptions {
    fn default() -> Self {
        ModelMeasureOptions {
            chest_below_armpit: 0.025,
            hip_search_start: 0.02,
            leg_start_below_crotch: 0.03,
            search_levels: 24,
            section_samples: 64,
            tape_samples: 256,
            perimeter_accuracy: SIZING_ACCURACY,
            axis_window: 0.03,
        }
    }
}

/// A girth's name, ISO 7250-1 name and definition on the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelGirthDefinition {
    pub name: &'static str,
    pub iso: &'static str,
    pub definition: &'static str,
}

const fn def(
    name: &'static str,
    iso: &'static str,
    definition: &'static str,
) -> ModelGirthDefinition {
    ModelGirthDefinition {
        name,
        iso,
        definition,
    }
}

/// The girths of a model, in the order they are reported.
pub const MODEL_GIRTHS: [ModelGirthDefinition; 12] = [
    def("neck", "neck circumference", "horizontal, the smallest tape girth of the trunk from 0.03 H below to 0.06 H above the head's first section"),
    def("chest", "chest circumference", "horizontal on the torso, 0.025 H below the higher armpit (lowest point of an arm's first section)"),
    def("waist", "waist circumference", "horizontal, the smallest torso tape girth between 35 % and 85 % of the way from the crotch to the chest level"),
    def("hip", "hip circumference", "horizontal, the largest torso tape girth from 0.02 H above the crotch up to the waist"),
    def("thigh", "thigh circumference", "perpendicular to the leg axis at 10 % of the leg from 0.03 H below the crotch to the ankle"),
    def("knee", "knee circumference", "perpendicular to the leg axis at 45 % of the leg"),
    def("calf", "calf circumference", "perpendicular to the leg axis where the equivalent radius is largest between 55 % and 85 % of the leg"),
    def("ankle", "ankle circumference", "perpendicular to the leg axis at the ankle (the smallest equivalent radius from 0.035 H to 0.15 H above the soles)"),
    def("upper arm", "upper arm circumference", "perpendicular to the arm axis at 28 % of shoulder→wrist"),
    def("elbow", "elbow circumference", "perpendicular to the arm axis at 56 % of shoulder→wrist"),
    def("forearm", "forearm circumference", "perpendicular to the arm axis where the equivalent radius is largest between 62 % and 80 % of shoulder→wrist"),
    def("wrist", "wrist circumference", "perpendicular to the arm axis at the wrist (the narrowing between forearm and hand)"),
];

/// The search proxy of a curve projected across `n`: the tape girth of 32
/// samples (short by a relative `(π/32)²/6 ≈ 0.16 %` on a smooth convex
/// curve, about the same at every level searched, so the place found is
/// hardly moved), and the equivalent radius of their polygon.
fn proxies(c: &SpaceCurve, n: Vec3, toward: Vec3) -> (Real, Real) {
    let (e1, e2) = plane_axes(n, toward);
    let p: Vec<Vec2> = sample(c, 32)
        .into_iter()
        .map(|q| Vec2::new(q.dot(e1), q.dot(e2)))
        .collect();
    let area = 0.5
        * (0..p.len())
            .map(|i| p[i].cross(p[(i + 1) % p.len()]))
            .sum::<Real>();
    (polygon_tape_girth(&p), mean_radius(area))
}

/// The equivalent radius `√(|A⃗·n|/π)` of a space curve across `n`, exact
/// from its coefficients: with `C(v) = c_0 + Σ_j (A_j cos jv + B_j sin jv)`
/// the vector area `½ ∮ C × C' dv` is `π Σ_j j A_j × B_j`.
fn equivalent_radius(c: &SpaceCurve, n: Vec3) -> Real {
    let mut a = Vec3::ZERO;
    for j in 1..=c.order() {
        let at = |s: &Series, k: usize| s.c.get(k).copied().unwrap_or(0.0);
        let cj = Vec3::new(
            at(&c.x, 2 * j - 1),
            at(&c.y, 2 * j - 1),
            at(&c.z, 2 * j - 1),
        );
        let sj = Vec3::new(at(&c.x, 2 * j), at(&c.y, 2 * j), at(&c.z, 2 * j));
        a += cj.cross(sj) * j as Real;
    }
    mean_radius(a.dot(n))
}

/// The section of `part` by `plane` (see the module doc), as `n` points, or
/// `None` when Newton's method leaves the part. Each patch met is
/// evaluated once at the `n` values of `v` (its `f_m(v_i)`), after which
/// `t(u, v_i) = Σ_m f_m(v_i) u^m` is a polynomial in `u`.
fn exact_section(part: &Part, plane: &Plane, s0: Real, n: usize, tol: Real) -> Option<Vec<Point3>> {
    let l = part.length();
    let segs = part.segments();
    let mut cache: Vec<Option<Vec<Vec<Vec3>>>> = vec![None; segs.len()];
    let mut out = Vec::with_capacity(n);
    let mut s_prev = s0;
    for i in 0..n {
        let mut s = s_prev;
        let mut done = false;
        for _ in 0..30 {
            let (k, u) = part.locate(s);
            let seg = &segs[k];
            let f = cache[k].get_or_insert_with(|| {
                let table = VTable::new(n, effective_order(&seg.patch));
                (0..n)
                    .map(|q| {
                        seg.patch
                            .coefficients()
                            .iter()
                            .map(|c| table.point(c, q).0)
                            .collect()
                    })
                    .collect()
            });
            let fm = &f[i];
            let (mut p, mut dp) = (Vec3::ZERO, Vec3::ZERO);
            let mut um = 1.0;
            for (m, c) in fm.iter().enumerate() {
                if m > 0 {
                    dp += *c * (m as Real * um);
                    um *= u;
                }
                p += *c * um;
            }
            let height = plane.height(p);
            if height.abs() <= tol {
                out.push(p);
                done = true;
                break;
            }
            let df = plane.normal.dot(dp) / seg.length();
            if !(df.abs() > 0.0) {
                return None;
            }
            let next = s - height / df;
            if !next.is_finite()
                || next < -ROUNDING_MARGIN * l
                || next > l * (1.0 + ROUNDING_MARGIN)
            {
                return None;
            }
            s = next.clamp(0.0, l);
        }
        if !done {
            return None;
        }
        s_prev = s;
    }
    Some(out)
}

/// The trigonometric series through `n` points equally spaced in `v`, in
/// `frame`'s plane coordinates (paper layout, Eq. 3), by the DFT; harmonics
/// below `1e-9` of the largest are trimmed from the end.
fn series_through(points: &[Point3], frame: Frame, max_order: usize) -> TrigCurve {
    let n = points.len();
    let order = max_order.min((n - 1) / 2).max(1);
    let q: Vec<Vec2> = points.iter().map(|p| frame.to_plane(*p)).collect();
    let mut a = vec![0.0; 2 * order + 1];
    let mut b = vec![0.0; 2 * order + 1];
    let (mut cs, mut sn) = (vec![0.0; order + 1], vec![0.0; order + 1]);
    for (i, p) in q.iter().enumerate() {
        harmonics(TAU * i as Real / n as Real, order, &mut cs, &mut sn);
        a[0] += p.x;
        b[0] += p.y;
        for j in 1..=order {
            a[2 * j - 1] += p.x * cs[j];
            a[2 * j] += p.x * sn[j];
            b[2 * j - 1] += p.y * sn[j];
            b[2 * j] += p.y * cs[j];
        }
    }
    let (w0, w) = (1.0 / n as Real, 2.0 / n as Real);
    a[0] *= w0;
    b[0] *= w0;
    for k in 1..a.len() {
        a[k] *= w;
        b[k] *= w;
    }
    let scale = a
        .iter()
        .chain(&b)
        .skip(1)
        .fold(0.0, |m: Real, x| m.max(x.abs()));
    let mut keep = order;
    while keep > 1
        && [a[2 * keep - 1], a[2 * keep], b[2 * keep - 1], b[2 * keep]]
            .iter()
            .all(|x| x.abs() <= 1e-9 * scale)
    {
        keep -= 1;
    }
    a.truncate(2 * keep + 1);
    b.truncate(2 * keep + 1);
    TrigCurve { frame, a, b }
}

/// The least-squares ellipse of a closed loop of points as a curve in
/// `frame`'s plane: the loop is resampled at 256 points evenly spaced by
/// arc length (so dense stretches do not pull the fit) and taken relative
/// to its area centroid.
pub fn ellipse_of(points: &[Point3], frame: Frame) -> Option<TrigCurve> {
    let q: Vec<Vec2> = points.iter().map(|p| frame.to_plane(*p)).collect();
    let n = q.len();
    if n < 3 {
        return None;
    }
    let total = polygon_perimeter(&q);
    if !(total > 0.0) {
        return None;
    }
    let m = 256;
    let mut even = Vec::with_capacity(m);
    let (mut k, mut walked) = (0, 0.0);
    for i in 0..m {
        let target = total * i as Real / m as Real;
        loop {
            let len = (q[(k + 1) % n] - q[k]).norm();
            if walked + len >= target || k + 1 >= n {
                let t = if len > 0.0 {
                    ((target - walked) / len).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                even.push(q[k] + (q[(k + 1) % n] - q[k]) * t);
                break;
            }
            walked += len;
            k += 1;
        }
    }
    let (_, c) = polygon_area_centroid(&q)?;
    let rel: Vec<Vec2> = even.iter().map(|p| *p - c).collect();
    let e = fit_ellipse(&rel)?;
    Some(e.to_curve(Frame {
        origin: frame.to_world(c),
        ..frame
    }))
}

/// The least-squares ellipse of a girth's own curve (for drawing a model
/// without an input): see [`ellipse_of`].
pub fn model_ellipse(g: &Girth) -> Option<TrigCurve> {
    ellipse_of(&g.curve.sample(256), g.curve.frame)
}

/// The model's girth of `part` in the plane through the centre line at
/// `s0` with normal `normal`.
fn girth_in_plane(
    part: &Part,
    s0: Real,
    normal: Vec3,
    front: Vec3,
    h: Real,
    name: &'static str,
    opts: &ModelMeasureOptions,
) -> Result<Girth, MeasureError> {
    let origin = part.centre(s0);
    let plane = Plane::new(origin, normal)?;
    let points = exact_section(part, &plane, s0, opts.section_samples, 1e-10 * h)
        .ok_or(MeasureError::EmptySection { measurement: name })?;
    let frame = Frame::from_normal(origin, plane.normal, front)
        .or_else(|| Frame::from_normal(origin, plane.normal, Vec3::X))
        .or_else(|| Frame::from_normal(origin, plane.normal, Vec3::Y))
        .ok_or(MeasureError::EmptySection { measurement: name })?;
    let (k, _) = part.locate(s0);
    let order = (2 * effective_order(&part.segments()[k].patch)).clamp(8, 32);
    let curve = series_through(&points, frame, order);
    let tape = polygon_tape_girth(&curve.sample_plane(opts.tape_samples));
    Ok(Girth {
        plane,
        perimeter: curve.perimeter_with_accuracy(opts.perimeter_accuracy),
        tape,
        // Drawn, not measured: `compare_with_mesh` fits it to the input's
        // loop, `model_ellipse` to the curve (kept out of the timed path).
        ellipse: None,
        curve,
        outline: Vec::new(),
        mesh_perimeter: Real::NAN,
        mesh_tape: Real::NAN,
    })
}

/// The place of a search among `levels` evenly spaced values of `[lo, hi]`
/// maximizing (or minimizing) `f`; `None` when `f` is nowhere defined.
fn search(
    lo: Real,
    hi: Real,
    n: usize,
    largest: bool,
    f: impl Fn(Real) -> Option<Real>,
) -> Option<Real> {
    let mut best: Option<(Real, Real)> = None;
    for i in 0..n {
        let x = lo + (hi - lo) * i as Real / (n - 1).max(1) as Real;
        if let Some(g) = f(x) {
            if best.is_none_or(|(_, b)| if largest { g > b } else { g < b }) {
                best = Some((x, g));
            }
        }
    }
    best.map(|b| b.0)
}

/// The unit axis of a limb at `s`: the chord of its centre line over
/// `[s − w, s + w]` clamped to `[lo, hi]`.
fn limb_axis(part: &Part, s: Real, w: Real, lo: Real, hi: Real) -> Option<Vec3> {
    let (a, b) = ((s - w).max(lo), (s + w).min(hi));
    let (a, b) = if b - a < 0.25 * w {
        ((b - w).max(0.0), (a + w).min(part.length()))
    } else {
        (a, b)
    };
    (part.centre(b) - part.centre(a)).normalized()
}

fn check(opts: &ModelMeasureOptions) -> Result<(), MeasureError> {
    let finite = [
        opts.chest_below_armpit,
        opts.hip_search_start,
        opts.leg_start_below_crotch,
        opts.axis_window,
    ];
    if finite.iter().any(|x| !x.is_finite()) || !(opts.axis_window > 0.0) {
        return Err(MeasureError::BadOption {
            name: "chest_below_armpit / hip_search_start / leg_start_below_crotch / axis_window",
            why: "must be finite (axis_window positive)",
        });
    }
    if opts.search_levels < 2 {
        return Err(MeasureError::BadOption {
            name: "search_levels",
            why: "at least 2 levels are needed",
        });
    }
    if opts.section_samples < 16 || opts.tape_samples < 16 {
        return Err(MeasureError::BadOption {
            name: "section_samples / tape_samples",
            why: "at least 16 samples are needed",
        });
    }
    if !(opts.perimeter_accuracy > 0.0 && opts.perimeter_accuracy < 1.0) {
        return Err(MeasureError::BadOption {
            name: "perimeter_accuracy",
            why: "must be in (0, 1)",
        });
    }
    Ok(())
}

/// Measures a reconstructed body from its own curves (see the module doc).
/// Measurements whose part is missing (an arm left out of a scan) become
/// warnings; a body without a torso is an error. Volume and surface area
/// carry `NaN` for the mesh until [`compare_with_mesh`] fills them.
pub fn measure_body(body: &Body, opts: &ModelMeasureOptions) -> Result<Measurements, MeasureError> {
    check(opts)?;
    if body.parts.is_empty() {
        return Err(MeasureError::NoParts);
    }
    let (mut volume, mut area, (low, high)) = volume_area_extent(body);
    let h = high - low;
    if !(h > 0.0) {
        return Err(MeasureError::NoParts);
    }
    let torso = body
        .part(PartName::Torso)
        .map(|p| &p.part)
        .ok_or(MeasureError::MissingPart {
            measurement: "chest",
            part: PartName::Torso,
        })?;
    // The arm–torso overlaps (a quarter of the work) beside the landmarks
    // and girths; subtracted in arm order.
    let (overlaps, (m, warnings)) = rayon::join(
        || arm_torso_overlaps(body, torso, h),
        || {
            let levels = Levels::new(body, opts, torso, low, h);
            levels.measurements()
        },
    );
    for (v, s) in overlaps {
        volume -= v;
        area -= s;
    }
    Ok(Measurements {
        measurements: m,
        volume: Comparison {
            model: volume,
            mesh: Real::NAN,
        },
        surface_area: Comparison {
            model: area,
            mesh: Real::NAN,
        },
        slice_curves: Vec::new(),
        slice_spacing: 0.0,
        warnings,
    })
}

/// A girth's index in [`MODEL_GIRTHS`] and the girth, or why it is missing.
type IndexedGirth = (usize, Result<Girth, MeasureError>);

/// The body and the landmark levels [`measure_body`]'s girths are found
/// from (levels along `up`; `h` the stature, `low` the soles).
struct Levels<'a> {
    body: &'a Body,
    opts: &'a ModelMeasureOptions,
    torso: &'a Part,
    head: Option<&'a Part>,
    up: Vec3,
    front: Vec3,
    low: Real,
    h: Real,
    torso_bottom: Real,
    torso_top: Real,
    crotch: Real,
    /// The highest arm's lowest first-section point (`-inf` without arms).
    armpit: Real,
}

impl<'a> Levels<'a> {
    fn new(
        body: &'a Body,
        opts: &'a ModelMeasureOptions,
        torso: &'a Part,
        low: Real,
        h: Real,
    ) -> Levels<'a> {
        let up = body.frame.up;
        let level = |p: Point3| p.dot(up);
        let first_level = |p: &Part| level(p.curves()[0].world_series().mean_point());
        let torso_bottom = first_level(torso);
        let leg_tops: Vec<Real> = [PartName::LeftLeg, PartName::RightLeg]
            .iter()
            .filter_map(|&p| body.part(p))
            .map(|p| first_level(&p.part))
            .collect();
        let crotch = if leg_tops.is_empty() {
            torso_bottom
        } else {
            0.5 * (torso_bottom + leg_tops.iter().fold(Real::NEG_INFINITY, |a, &b| a.max(b)))
        };
        let armpit = [PartName::LeftArm, PartName::RightArm]
            .iter()
            .filter_map(|&p| body.part(p))
            .map(|p| {
                p.part.curves()[0]
                    .sample(64)
                    .iter()
                    .map(|q| level(*q))
                    .fold(Real::INFINITY, Real::min)
            })
            .fold(Real::NEG_INFINITY, Real::max);
        Levels {
            body,
            opts,
            torso,
            head: body.part(PartName::Head).map(|p| &p.part),
            up,
            front: body.frame.front,
            low,
            h,
            torso_bottom,
            torso_top: level(torso.centre(torso.length())),
            crotch,
            armpit,
        }
    }

    /// The level of `p`'s first section's mean point.
    fn first_level(&self, p: &Part) -> Real {
        p.curves()[0].world_series().mean_point().dot(self.up)
    }

    /// Every measurement, in the report's order, and the warnings.
    fn measurements(&self) -> (Vec<Measurement>, Vec<String>) {
        let mut warnings = Vec::new();
        let mut m = vec![Measurement {
            name: "stature",
            kind: MeasurementKind::Height,
            value: self.h,
            iso: Some("stature (body height)"),
            definition: "extent of the model's surface along its up axis, soles to head top",
            girth: None,
        }];
        let mut girths = self.trunk_girths(&mut warnings);
        let leg = [PartName::LeftLeg, PartName::RightLeg]
            .iter()
            .find_map(|&p| self.body.part(p).map(|b| &b.part));
        let arm = [PartName::LeftArm, PartName::RightArm]
            .iter()
            .find_map(|&p| self.body.part(p).map(|b| &b.part));
        match leg {
            Some(lg) => self.leg_girths(lg, &mut girths, &mut warnings),
            None => warnings.push("thigh, knee, calf, ankle, inseam: no leg".into()),
        }
        let arm_length = match arm {
            Some(a) => Some(self.arm_girths(a, &mut girths, &mut warnings)),
            None => {
                warnings.push(
                    "upper arm, elbow, forearm, wrist, arm length, shoulder breadth: no arm".into(),
                );
                None
            }
        };
        girths.sort_by_key(|g| g.0);
        for (i, g) in girths {
            let d = &MODEL_GIRTHS[i];
            match g {
                Ok(g) => m.push(Measurement {
                    name: d.name,
                    kind: MeasurementKind::Girth,
                    value: g.tape,
                    iso: Some(d.iso),
                    definition: d.definition,
                    girth: Some(g),
                }),
                Err(e) => warnings.push(format!("{}: {e}", d.name)),
            }
        }
        self.push_lengths(leg.is_some(), arm_length, &mut m, &mut warnings);
        (m, warnings)
    }

    /// A horizontal level on the trunk: the torso, or the head above it.
    fn trunk(&self, lv: Real) -> Option<(&'a Part, Real)> {
        if lv <= self.torso_top {
            self.torso.s_at_level(self.up, lv).map(|s| (self.torso, s))
        } else {
            self.head
                .and_then(|hd| hd.s_at_level(self.up, lv).map(|s| (hd, s)))
        }
    }

    /// The tape proxy of the trunk's horizontal section at `lv`.
    fn trunk_tape(&self, lv: Real) -> Option<Real> {
        self.trunk(lv)
            .map(|(p, s)| proxies(&curve_at(p, s), self.up, self.front).0)
    }

    /// Girth `i` of [`MODEL_GIRTHS`] in the trunk's horizontal plane at `lv`.
    fn horizontal(&self, i: usize, lv: Option<Real>) -> Result<Girth, MeasureError> {
        let name = MODEL_GIRTHS[i].name;
        let lv = lv.ok_or(MeasureError::EmptySection { measurement: name })?;
        let (p, s) = self
            .trunk(lv)
            .ok_or(MeasureError::EmptySection { measurement: name })?;
        self.girth(p, s, self.up, name)
    }

    /// The model's girth of `part` in the plane through the centre line at
    /// `s` with normal `normal`.
    fn girth(
        &self,
        part: &Part,
        s: Real,
        normal: Vec3,
        name: &'static str,
    ) -> Result<Girth, MeasureError> {
        girth_in_plane(part, s, normal, self.front, self.h, name, self.opts)
    }

    /// Neck, chest, waist and hip.
    fn trunk_girths(&self, warnings: &mut Vec<String>) -> Vec<IndexedGirth> {
        let (h, n, crotch) = (self.h, self.opts.search_levels, self.crotch);
        let tape = |lv: Real| self.trunk_tape(lv);
        let mut girths = Vec::new();
        // Neck: around the head's first section.
        let neck = match self.head {
            Some(hd) => {
                let base = self.first_level(hd);
                self.horizontal(0, search(base - 0.03 * h, base + 0.06 * h, n, false, tape))
            }
            None => Err(MeasureError::MissingPart {
                measurement: "neck",
                part: PartName::Head,
            }),
        };
        girths.push((0, neck));
        if self.armpit.is_finite() {
            let chest = self.armpit - self.opts.chest_below_armpit * h;
            girths.push((1, self.horizontal(1, Some(chest))));
            let waist = search(
                crotch + 0.35 * (chest - crotch),
                crotch + 0.85 * (chest - crotch),
                n,
                false,
                tape,
            );
            girths.push((2, self.horizontal(2, waist)));
            let hip = waist.and_then(|w| {
                search(
                    (crotch + self.opts.hip_search_start * h).max(self.torso_bottom),
                    w,
                    n,
                    true,
                    tape,
                )
            });
            girths.push((3, self.horizontal(3, hip)));
        } else {
            warnings.push("chest, waist, hip: no arm, so no armpit level".to_string());
        }
        girths
    }

    /// Thigh, knee, calf and ankle of the leg `lg`.
    fn leg_girths(&self, lg: &Part, girths: &mut Vec<IndexedGirth>, warnings: &mut Vec<String>) {
        let (h, n, up) = (self.h, self.opts.search_levels, self.up);
        let w = self.opts.axis_window * h;
        let floor = self.low;
        let ankle_lo = lg.s_at_level(up, floor + 0.15 * h);
        let ankle_hi = lg.s_at_level(up, floor + 0.035 * h);
        let top = lg
            .s_at_level(up, self.crotch - self.opts.leg_start_below_crotch * h)
            .unwrap_or(0.0);
        let radius = |s: Real| {
            let ax = limb_axis(lg, s, w, 0.0, lg.length())?;
            Some(equivalent_radius(&curve_at(lg, s), ax))
        };
        let Some((a, b)) = ankle_lo.zip(ankle_hi) else {
            warnings.push("thigh, knee, calf, ankle: the leg does not reach the ankle".into());
            return;
        };
        let ankle = search(a, b, n, false, radius).unwrap_or(b);
        let at = |t: Real| top + t * (ankle - top);
        let calf = search(at(0.55), at(0.85), n, true, radius).unwrap_or(at(0.7));
        for (i, s) in [(4, at(0.1)), (5, at(0.45)), (6, calf), (7, ankle)] {
            let name = MODEL_GIRTHS[i].name;
            let g = limb_axis(lg, s, w, top, ankle)
                .ok_or(MeasureError::EmptySection { measurement: name })
                .and_then(|ax| self.girth(lg, s, ax, name));
            girths.push((i, g));
        }
    }

    /// Upper arm, elbow, forearm and wrist of the arm `a`; returns the arm
    /// length (to the wrist).
    fn arm_girths(
        &self,
        a: &Part,
        girths: &mut Vec<IndexedGirth>,
        warnings: &mut Vec<String>,
    ) -> Real {
        let n = self.opts.search_levels;
        let w = self.opts.axis_window * self.h;
        let l = a.length();
        let tape = |s: Real| {
            let ax = limb_axis(a, s, w, 0.0, l)?;
            Some(proxies(&curve_at(a, s), ax, self.front))
        };
        // Wrist: the smallest girth followed distally by one 15 % larger.
        let levels: Vec<(Real, Real, Real)> = (0..2 * n)
            .filter_map(|i| {
                let s = l * (0.45 + 0.52 * i as Real / (2 * n - 1) as Real);
                tape(s).map(|(t, r)| (s, t, r))
            })
            .collect();
        let mut wrist = None::<(Real, Real)>;
        for (k, &(s, t, _)) in levels.iter().enumerate() {
            let beyond = levels[k..].iter().map(|x| x.1).fold(0.0, Real::max);
            if beyond >= 1.15 * t && wrist.is_none_or(|(_, b)| t < b) {
                wrist = Some((s, t));
            }
        }
        let wrist = match wrist {
            Some((s, _)) => s,
            None => {
                warnings.push(
                    "wrist: no hand wider than the wrist found; the arm's narrowest place is used"
                        .into(),
                );
                levels
                    .iter()
                    .min_by(|x, y| x.1.total_cmp(&y.1))
                    .map_or(0.75 * l, |x| x.0)
            }
        };
        let at = |t: Real| t * wrist;
        let forearm = search(at(0.62), at(0.8), n, true, |s| {
            let ax = limb_axis(a, s, w, 0.0, l)?;
            Some(equivalent_radius(&curve_at(a, s), ax))
        })
        .unwrap_or(at(0.7));
        for (i, s) in [(8, at(0.28)), (9, at(0.56)), (10, forearm), (11, wrist)] {
            let name = MODEL_GIRTHS[i].name;
            let g = limb_axis(a, s, w, 0.0, wrist)
                .ok_or(MeasureError::EmptySection { measurement: name })
                .and_then(|ax| self.girth(a, s, ax, name));
            girths.push((i, g));
        }
        wrist
    }

    /// Inseam, arm length and shoulder breadth.
    fn push_lengths(
        &self,
        has_leg: bool,
        arm_length: Option<Real>,
        m: &mut Vec<Measurement>,
        warnings: &mut Vec<String>,
    ) {
        if has_leg {
            m.push(Measurement {
                name: "inseam",
                kind: MeasurementKind::Height,
                value: self.crotch - self.low,
                iso: Some("crotch height"),
                definition: "height above the soles of the crotch: halfway between the torso's first section and the legs' first sections",
                girth: None,
            });
        }
        if let Some(len) = arm_length {
            m.push(Measurement {
                name: "arm length",
                kind: MeasurementKind::Length,
                value: len,
                iso: Some("shoulder-elbow length + forearm length (to the wrist)"),
                definition: "arc length of the arm's centre line from its first section (shoulder) to the wrist",
                girth: None,
            });
        }
        match (
            self.body.part(PartName::LeftArm),
            self.body.part(PartName::RightArm),
        ) {
            (Some(l), Some(r)) => m.push(Measurement {
                name: "shoulder breadth",
                kind: MeasurementKind::Breadth,
                value: l.part.centre(0.0).distance(r.part.centre(0.0)),
                iso: Some("biacromial breadth"),
                definition: "straight distance between the centres of the two arms' first sections (the shoulder cuts)",
                girth: None,
            }),
            _ => warnings.push("shoulder breadth: both arms are needed".into()),
        }
    }
}

/// Measures every girth of `m` directly on `mesh` in the same plane (the
/// loop around the plane's origin: its polygon perimeter and convex-hull
/// perimeter, its points as the girth's outline, its ellipse), and the
/// mesh's volume and surface area. A plane that misses the mesh leaves
/// `NaN` with a warning.
pub fn compare_with_mesh(m: &mut Measurements, mesh: &Mesh) {
    for x in m.measurements.iter_mut() {
        let Some(g) = x.girth.as_mut() else { continue };
        match section_mesh(mesh, &g.plane, &SectionOptions::default()) {
            Ok(s) => match s.select(g.plane.origin) {
                Some(k) => {
                    let poly = s.loops[k].plane_points();
                    g.mesh_perimeter = polygon_perimeter(&poly);
                    g.mesh_tape = polygon_tape_girth(&poly);
                    g.outline = s.loops[k].points.clone();
                    if let Some(e) = ellipse_of(&g.outline, g.curve.frame) {
                        g.ellipse = Some(e);
                    }
                }
                None => m
                    .warnings
                    .push(format!("{}: the input has no loop in this plane", x.name)),
            },
            Err(e) => m.warnings.push(format!("{}: input section: {e}", x.name)),
        }
    }
    m.volume.mesh = mesh.signed_volume().abs();
    m.surface_area.mesh = mesh.surface_area();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::anatomy::BodyFrame;
    use crate::body::{BodyPart, Units};
    use crate::measure::volume::{part_integrals, transition_integrals, Tables, GL6};
    use crate::surface::cap::CapKind;
    use crate::surface::part::PartOptions;
    use std::f64::consts::PI;

    /// A vertical cylinder of radius `r` from height 0 to `len` (y up),
    /// closed by flat caps, as the torso of a body.
    fn cylinder_body(r: Real, len: Real) -> Body {
        let curves: Vec<TrigCurve> = (0..6)
            .map(|k| {
                let frame = Frame {
                    origin: Vec3::new(0.3, len * k as Real / 5.0, -0.2),
                    e1: Vec3::Z,
                    e2: Vec3::X,
                };
                TrigCurve::circle(frame, r, 3)
            })
            .collect();
        let options = PartOptions {
            start_cap: CapKind::Flat,
            end_cap: CapKind::Flat,
            ..PartOptions::default()
        };
        Body {
            units: Units::Metres,
            transitions: Vec::new(),
            digits: Vec::new(),
            cavities: Vec::new(),
            frame: BodyFrame {
                up: Vec3::Y,
                front: Vec3::Z,
                left: Vec3::X,
                origin: Vec3::new(0.3, 0.0, -0.2),
            },
            height: len,
            parts: vec![BodyPart {
                name: PartName::Torso,
                part: Part::new(curves, &options).unwrap(),
                fits: Vec::new(),
            }],
        }
    }

    /// A transition between two coaxial cylinders of one radius, with the
    /// gap as both magnitudes, is the missing piece of cylinder: its band
    /// volume is `π r² gap` and its area `2π r gap`.
    #[test]
    fn a_cylinder_to_cylinder_transition_has_the_gap_s_volume_and_area() {
        use crate::surface::transition::{Transition, TransitionSpec};
        let (r, gap) = (0.12, 0.2);
        let cyl = |y0: Real, y1: Real| {
            let curves: Vec<TrigCurve> = (0..4)
                .map(|k| {
                    let frame = Frame {
                        origin: Vec3::new(0.1, y0 + (y1 - y0) * k as Real / 3.0, 0.3),
                        e1: Vec3::Z,
                        e2: Vec3::X,
                    };
                    TrigCurve::circle(frame, r, 3)
                })
                .collect();
            Part::new(curves, &PartOptions::default()).unwrap()
        };
        let (a, b) = (cyl(0.0, 0.3), cyl(0.3 + gap, 0.8));
        let spec = TransitionSpec {
            from_start: false,
            to_start: true,
            magnitudes: [gap, gap],
            seam: None,
            side: None,
            order: 8,
        };
        let t = Transition::between(&a, &b, spec).unwrap();
        let mut ext = (Real::INFINITY, Real::NEG_INFINITY);
        let (v, area) = transition_integrals(t.patch(), Vec3::Y, &mut Tables::default(), &mut ext);
        assert!((v / (PI * r * r * gap) - 1.0).abs() < 1e-9, "{v}");
        assert!((area / (TAU * r * gap) - 1.0).abs() < 1e-9, "{area}");
    }

    /// An ellipse of semi-axes 0.3 and 0.2 in the plane `x + y + z = 1`
    /// (plus `0.01 cos 3v` along the first axis: a harmonic with no sine
    /// partner changes the shape, not the area): its vector area is
    /// `π a b n`, and its area-true 32-gon encloses `π a b`.
    #[test]
    fn vector_area_and_area_true_outline_of_a_tilted_ellipse() {
        let n = Vec3::new(1.0, 1.0, 1.0).normalized().unwrap();
        let e1 = Vec3::new(1.0, -1.0, 0.0).normalized().unwrap();
        let e2 = n.cross(e1);
        let (a, b, o) = (0.3, 0.2, Vec3::new(0.2, 0.5, 0.3));
        let coord = |k: usize| {
            let mut c = vec![0.0; 7];
            c[0] = o[k];
            c[1] = a * e1[k];
            c[2] = b * e2[k];
            c[5] = 0.01 * e1[k];
            Series { c }
        };
        let c = SpaceCurve {
            x: coord(0),
            y: coord(1),
            z: coord(2),
        };
        let va = vector_area(&c);
        assert!((va - n * (PI * a * b)).norm() < 1e-12, "{va:?}");
        let poly = area_true_outline(&c, &sample(&c, 32), Vec3::ZERO, e1, e2);
        let m = poly.len();
        let area: Real = (0..m)
            .map(|i| poly[i].cross(poly[(i + 1) % m]))
            .sum::<Real>()
            / 2.0;
        assert!((area - PI * a * b).abs() < 1e-12, "{area}");
    }

    /// A part of horizontal circles (y up), 2.2 m long, straight for 1.7 m
    /// and then running out sideways and widening (as a leg into its
    /// foot): its volume by Cavalieri, `Σ ∫ A(u) y'(u) du` over the
    /// patches with `A(u)` the exact area of the horizontal iso-curve
    /// (exact: 6-point Gauss-Legendre on a polynomial of degree ≤ 11),
    /// against the divergence theorem's sum, within 5e-6 (measured
    /// 2.1e-6). Measured from the part's first curve instead of each
    /// patch's own, the 2-point quadrature's error is multiplied by the
    /// distance: 2.3e-5.
    #[test]
    fn a_part_running_out_sideways_has_its_slab_volume() {
        let curves: Vec<TrigCurve> = (0..23)
            .map(|k| {
                let frame = Frame {
                    origin: Vec3::new(
                        0.03 * (k as Real - 17.0).max(0.0).powi(2),
                        0.1 * k as Real,
                        0.0,
                    ),
                    e1: Vec3::Z,
                    e2: Vec3::X,
                };
                TrigCurve::circle(frame, 0.15 + 0.03 * (k as Real - 17.0).max(0.0), 3)
            })
            .collect();
        let part = Part::new(curves, &PartOptions::default()).unwrap();
        let mut tables = Tables::default();
        let got = part_integrals(&part, Vec3::Y, &mut tables).volume;
        let mut exact = 0.0;
        for seg in part.segments() {
            let order = effective_order(&seg.patch);
            assert!(seg.patch.coefficients().len() <= 5);
            for &(u, w) in &GL6 {
                let c = iso_curve(&seg.patch, u, 0, order);
                let dy = iso_curve(&seg.patch, u, 1, order).y.c[0];
                let a = vector_area(&c).y;
                exact += w * a.abs() * dy;
            }
        }
        assert!((got / exact - 1.0).abs() < 5e-6, "{got} vs {exact}");
    }

    #[test]
    fn a_capped_cylinder_has_its_exact_volume_area_and_extent() {
        let (r, len) = (0.15, 0.9);
        let (v, a, (lo, hi)) = volume_area_extent(&cylinder_body(r, len));
        assert!((v / (PI * r * r * len) - 1.0).abs() < 1e-9, "{v}");
        let exact = TAU * r * len + 2.0 * PI * r * r;
        assert!((a / exact - 1.0).abs() < 1e-6, "{a} vs {exact}");
        assert!(lo.abs() < 1e-12 && (hi - len).abs() < 1e-12, "{lo} {hi}");
    }

    #[test]
    fn a_cavity_takes_its_volume_from_the_body_and_adds_its_area() {
        // A capped cylinder of radius 0.05 and height 0.3 inside the
        // cylinder body, as its torso's cavity.
        let (r, len) = (0.15, 0.9);
        let mut body = cylinder_body(r, len);
        let (v0, a0, ext0) = volume_area_extent(&body);
        let (rc, lc) = (0.05, 0.3);
        let inner = cylinder_body(rc, lc).parts.remove(0).part;
        let moved: Vec<TrigCurve> = inner
            .sections()
            .iter()
            .map(|c| {
                let mut c = c.clone();
                c.frame.origin += Vec3::new(0.02, 0.3, 0.01);
                c
            })
            .collect();
        let part = Part::new(moved, inner.options()).unwrap();
        body.cavities.push(crate::body::BodyCavity {
            within: PartName::Torso,
            part,
            fits: Vec::new(),
        });
        let (v, a, ext) = volume_area_extent(&body);
        let cavity_volume = PI * rc * rc * lc;
        let cavity_area = TAU * rc * lc + 2.0 * PI * rc * rc;
        assert!(((v0 - v) / cavity_volume - 1.0).abs() < 1e-9, "{v0} {v}");
        assert!(((a - a0) / cavity_area - 1.0).abs() < 1e-6, "{a0} {a}");
        assert_eq!(ext, ext0);
        assert!(body.design_parameters() > cylinder_body(r, len).design_parameters());
    }

    #[test]
    fn girths_of_a_cylinder_are_its_circle_and_tilted_ellipse() {
        let (r, len) = (0.15, 0.9);
        let body = cylinder_body(r, len);
        let part = &body.parts[0].part;
        let opts = ModelMeasureOptions::default();
        let s = part.s_at_level(Vec3::Y, 0.4).unwrap();
        let g = girth_in_plane(part, s, Vec3::Y, Vec3::Z, len, "waist", &opts).unwrap();
        assert!((g.perimeter - TAU * r).abs() < 1e-9, "{}", g.perimeter);
        assert!((g.tape / (TAU * r) - 1.0).abs() < 3e-5, "{}", g.tape);
        // A plane tilted by 30°: an ellipse with semi-axes r and r / cos 30°.
        let t = 30f64.to_radians();
        let n = Vec3::new(t.sin(), t.cos(), 0.0);
        let g = girth_in_plane(part, s, n, Vec3::Z, len, "tilted", &opts).unwrap();
        let (a, b) = (r / t.cos(), r);
        let h = ((a - b) / (a + b)).powi(2);
        let ramanujan = PI * (a + b) * (1.0 + 3.0 * h / (10.0 + (4.0 - 3.0 * h).sqrt()));
        assert!(
            (g.perimeter / ramanujan - 1.0).abs() < 1e-6,
            "{} vs {ramanujan}",
            g.perimeter
        );
        for p in g.curve.sample(32) {
            assert!(g.plane.height(p).abs() < 1e-9);
            let radial = Vec3::new(p.x - 0.3, 0.0, p.z + 0.2).norm();
            assert!((radial - r).abs() < 1e-6, "{radial}");
        }
    }

    #[test]
    fn a_body_without_parts_or_with_bad_options_is_a_typed_error() {
        let mut body = cylinder_body(0.1, 1.0);
        body.parts.clear();
        assert_eq!(
            measure_body(&body, &ModelMeasureOptions::default()),
            Err(MeasureError::NoParts)
        );
        let body = cylinder_body(0.1, 1.0);
        let bad = ModelMeasureOptions {
            search_levels: 1,
            ..ModelMeasureOptions::default()
        };
        assert!(matches!(
            measure_body(&body, &bad),
            Err(MeasureError::BadOption { .. })
        ));
        // A torso alone: stature and volume, every other measurement a warning.
        let m = measure_body(&body, &ModelMeasureOptions::default()).unwrap();
        assert!((m.get("stature").unwrap().value - 1.0).abs() < 1e-9);
        assert!(m.get("chest").is_none() && !m.warnings.is_empty());
    }
}
