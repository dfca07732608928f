//! A body part: an ordered list of cross-section curves along an axis,
//! skinned into a chain of [`Patch`]es with tangent continuity at every
//! interior join (method.md §5), optionally closed by [`Cap`]s.
//!
//! The surface is parametrized by `s`, the cumulative distance between the
//! curves' mean points (so uneven section spacing is respected), and `v`.
//! Section `k` sits at knot `s_k`; segment `i` covers `[s_i, s_{i+1}]` (or a
//! run of several sections for the paper's patches) with its own
//! `u = (s - s_start) / L`, so `∂t/∂s = (1/L) ∂t/∂u`.
//!
//! Four skinning schemes ([`Skinning`]), all producing polynomial patches:
//!
//! * **Catmull-Rom** (default; see "Which scheme" below): a C1
//!   piecewise cubic Hermite through the curves' coefficient vectors, the
//!   tangent at each curve the derivative of the parabola through it and its
//!   two neighbours at their actual spacing (the non-uniform Catmull-Rom /
//!   Bessel tangent `T_k = (h_k D_{k-1} + h_{k-1} D_k)/(h_{k-1} + h_k)`,
//!   `D_k = (C_{k+1} - C_k)/h_k`).
//! * **Natural spline**: the C2 cubic spline through the coefficient vectors
//!   with zero second derivative at both ends.
//! * **Paper, chained**: patches of `K` curves (Eq. 13-16), each after the
//!   first taking the previous patch's end tangent as an Eq. 17 condition
//!   (and its second derivative when curvature continuity is asked).
//! * **Paper, unchained**: the same patches without the condition (only C0
//!   across joins).
//!
//! **Twist.** Before skinning, each curve's parameter is shifted by the `φ`
//! minimizing `∫ |C_{k+1}(v+φ) - C_k(v)|² dv` (see [`best_phase_shift`]).
//!
//! **Which scheme.** On legs and torsos (`docs/skinning.md`) Catmull-Rom,
//! the natural spline and the unchained paper patches are about as close
//! to the input; the chained paper patches are worse, because the Eq. 17
//! condition carries each patch's end slope, polynomial wiggles included,
//! into the next. Catmull-Rom is the default for its locality; the paper's
//! scheme is kept as an option.
//!
//! ```
//! use trigbody_core::{tessellate_part, CapKind, Frame, Part, PartOptions, TessellationOptions, TrigCurve, Vec3};
//! // Five equal circles 5 cm apart, closed flat at both ends: a cylinder.
//! let curves: Vec<TrigCurve> = (0..5)
//!     .map(|k| {
//!         let frame = Frame { origin: Vec3::new(0.0, 0.0, 0.05 * k as f64), e1: Vec3::X, e2: Vec3::Y };
//!         TrigCurve::circle(frame, 0.1, 2)
//!     })
//!     .collect();
//! let options = PartOptions { start_cap: CapKind::Flat, end_cap: CapKind::Flat, ..PartOptions::default() };
//! let part = Part::new(curves, &options)?;
//! assert!((part.length() - 0.2).abs() < 1e-12);
//! let mesh = tessellate_part(&part, &TessellationOptions::default())?;
//! let exact = std::f64::consts::PI * 0.01 * 0.2;
//! assert!((mesh.signed_volume() - exact).abs() < 0.005 * exact);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::curve::trig::{CurveError, SpaceCurve, TrigCurve};
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::rigid::Rigid;
use crate::geom::tolerance::GEOMETRIC_EPS;
use crate::surface::cap::{dome_cap, flat_cap, Cap, CapError, CapKind};
use crate::surface::patch::{combine, flatten, unflatten, EndConditions, Patch, PatchError};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};
use thiserror::Error;

/// How the curves of a part are joined into a surface (see the module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Skinning {
    /// C1 piecewise cubic Hermite with chord-length-aware Catmull-Rom tangents.
    #[default]
    CatmullRom,
    /// C2 natural cubic spline.
    NaturalSpline,
    /// The paper's patches of `K` curves chained by Eq. 17 (C1; C2 with
    /// `curvature_continuity`).
    PaperChained,
    /// The paper's patches of `K` curves without the chaining condition (C0).
    PaperUnchained,
}

impl Skinning {
    /// All schemes, for comparisons.
    pub const ALL: [Skinning; 4] = [
        Skinning::CatmullRom,
        Skinning::NaturalSpline,
        Skinning::PaperChained,
        Skinning::PaperUnchained,
    ];
    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Skinning::CatmullRom => "catmull-rom",
            Skinning::NaturalSpline => "natural-spline",
            Skinning::PaperChained => "paper-chained",
            Skinning::PaperUnchained => "paper-unchained",
        }
    }
    /// The inverse of [`Skinning::name`].
    pub fn from_name(name: &str) -> Option<Skinning> {
        Skinning::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// The default number of curves per patch for the paper's schemes: 4 (cubic
/// patches; higher degrees oscillate, see the measurements in the crate docs).
pub const DEFAULT_CURVES_PER_PATCH: usize = 4;

/// Options of [`Part::new`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartOptions {
    /// The skinning scheme. Default [`Skinning::CatmullRom`].
    pub skinning: Skinning,
    /// Curves per patch `K ≥ 2` for the paper's schemes (a long part is split
    /// into as many patches as needed, never one high-degree polynomial).
    /// Default [`DEFAULT_CURVES_PER_PATCH`].
    pub curves_per_patch: usize,
    /// Chained paper patches also match the second derivative (Eq. 17 with
    /// second derivatives). Default false.
    pub curvature_continuity: bool,
    /// Shift each curve's parameter to minimize twist. Default true.
    pub align_twist: bool,
    /// How the first curve's end is closed. Default open.
    pub start_cap: CapKind,
    /// How the last curve's end is closed. Default open.
    pub end_cap: CapKind,
}

impl Default for PartOptions {
    fn default() -> Self {
        PartOptions {
            skinning: Skinning::default(),
            curves_per_patch: DEFAULT_CURVES_PER_PATCH,
            curvature_continuity: false,
            align_twist: true,
            start_cap: CapKind::Open,
            end_cap: CapKind::Open,
        }
    }
}

/// What is wrong with the sections of a part.
#[derive(Debug, Error, PartialEq)]
pub enum PartError {
    #[error("a part needs at least 2 sections, got {count}")]
    TooFewSections { count: usize },
    #[error("section {index}: {source}")]
    Curve {
        index: usize,
        #[source]
        source: CurveError,
    },
    #[error("curves per patch must be at least 2, got {0}")]
    CurvesPerPatch(usize),
    #[error("sections {index} and {} have the same centre: the part has no length there", index + 1)]
    CoincidentSections { index: usize },
    #[error("section {index}'s plane normal points {}the part's axis while section 0's points {}it: orient all section frames alike", if *.flipped { "against " } else { "along " }, if *.flipped { "along " } else { "against " })]
    MixedFrames {
        index: usize,
        flipped: bool,
        /// Most sections face against section 0: it is the odd one.
        first_is_odd: bool,
    },
    #[error("section {index} runs {} about the axis, unlike section 0: give all curves the same direction", if *.clockwise { "clockwise" } else { "counter-clockwise" })]
    MixedOrientation { index: usize, clockwise: bool },
    #[error("the planes of sections {index} and {} cross inside the curves (a point of one curve lies beyond the other's plane by {depth:.3e}): the part would fold over itself", index + 1)]
    CrossingPlanes { index: usize, depth: Real },
    #[error("segment {segment}: {source}")]
    Patch {
        segment: usize,
        #[source]
        source: PatchError,
    },
    #[error("{} cap: {source}", if *.start { "start" } else { "end" })]
    Cap {
        start: bool,
        #[source]
        source: CapError,
    },
}

/// One piece of the part's surface: a patch over the axis interval `[s0, s1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    pub patch: Patch,
    pub s0: Real,
    pub s1: Real,
}

impl Segment {
    /// The parameter length `L = s1 - s0`.
    #[inline]
    pub fn length(&self) -> Real {
        self.s1 - self.s0
    }
}

/// A skinned part (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    sections: Vec<TrigCurve>,
    curves: Vec<TrigCurve>,
    twist: Vec<Real>,
    knots: Vec<Real>,
    segments: Vec<Segment>,
    start_cap: Option<Cap>,
    end_cap: Option<Cap>,
    options: PartOptions,
    clockwise: bool,
}

fn scaled(c: &SpaceCurve, f: Real) -> SpaceCurve {
    let s = |x: &crate::curve::series::Series| crate::curve::series::Series {
        c: x.c.iter().map(|a| a * f).collect(),
    };
    SpaceCurve {
        x: s(&c.x),
        y: s(&c.y),
        z: s(&c.z),
    }
}

/// The parameter shift `φ` that best aligns `curve` to `reference`: it
/// maximizes `⟨C_ref, C(·+φ)⟩`, equivalently minimizes
/// `∫ |C(v+φ) - C_ref(v)|² dv`. With `C`'s j-th harmonic `(a, b)` and the
/// reference's `(p, q)` per coordinate, the inner product is the
/// trigonometric polynomial `Σ_j A_j cos jφ + B_j sin jφ` with
/// `A_j = Σ (p a + q b)`, `B_j = Σ (p b - q a)`: sampled densely (16J, at
/// least 64 samples), then the best sample refined by Newton's method. Near
/// ties (local maxima within 1 % of `Σ_j |(A_j, B_j)|` of the best, as for
/// curves dominated by an even harmonic) go to the shift nearest zero, so
/// the sections' own start points decide. Returns `φ ∈ (-π, π]`;
/// `curve.shifted(φ)` is the aligned curve.
pub fn best_phase_shift(reference: &SpaceCurve, curve: &SpaceCurve) -> Real {
    let order = reference.order().min(curve.order());
    let mut ab = vec![(0.0, 0.0); order + 1];
    for (p, c) in [
        (&reference.x, &curve.x),
        (&reference.y, &curve.y),
        (&reference.z, &curve.z),
    ] {
        for j in 1..=order.min(p.order()).min(c.order()) {
            let (pa, pb, a, b) = (p.c[2 * j - 1], p.c[2 * j], c.c[2 * j - 1], c.c[2 * j]);
            ab[j].0 += pa * a + pb * b;
            ab[j].1 += pa * b - pb * a;
        }
    }
    let g = |phi: Real, k: u32| -> Real {
        (1..=order)
            .map(|j| {
                let (s, co) = (j as Real * phi).sin_cos();
                let (a, b) = ab[j];
                let f = (j as Real).powi(k as i32);
                f * match k % 4 {
                    0 => a * co + b * s,
                    1 => -a * s + b * co,
                    2 => -a * co - b * s,
                    _ => a * s - b * co,
                }
            })
            .sum()
    };
    let n = (16 * order).max(64);
    let step = TAU / n as Real;
    // The samples: `g(φ_i, 0)` with each `sin_cos(j φ_i)` read from a
    // table kept per `n` (the same numbers and sums; the sampling is most
    // of the work, and a reconstruction aligns thousands of curve pairs
    // of a few orders).
    let values: Vec<Real> = match phase_table(n) {
        Some(table) => (0..n)
            .map(|i| {
                let row = &table[i * (n / 16)..];
                (1..=order)
                    .map(|j| {
                        let (s, co) = row[j - 1];
                        let (a, b) = ab[j];
                        a * co + b * s
                    })
                    .sum()
            })
            .collect(),
        None => (0..n).map(|i| g(i as Real * step, 0)).collect(),
    };
    let top = values.iter().copied().fold(Real::NEG_INFINITY, Real::max);
    // Among the sampled local maxima within 1 % of the oscillation's
    // amplitude of the best, take the one nearest φ = 0: a nearly symmetric
    // curve (an ellipse) has two almost equal maxima half a turn apart, and
    // the sections' own start points (consistent by construction) decide.
    let amplitude: Real = ab.iter().map(|(a, b)| a.hypot(*b)).sum();
    let wrapped = |i: usize| {
        let phi = i as Real * step;
        if phi > PI {
            phi - TAU
        } else {
            phi
        }
    };
    let start = (0..n)
        .filter(|&i| {
            let (prev, next) = (values[(i + n - 1) % n], values[(i + 1) % n]);
            values[i] >= prev && values[i] >= next && values[i] >= top - 0.01 * amplitude
        })
        .min_by(|&a, &b| wrapped(a).abs().total_cmp(&wrapped(b).abs()))
        .unwrap_or(0);
    let mut phi = wrapped(start);
    for _ in 0..30 {
        let (d1, d2) = (g(phi, 1), g(phi, 2));
        if d2.is_nan() || d2 >= 0.0 {
            break;
        }
        let delta = (-d1 / d2).clamp(-step, step);
        phi += delta;
        if delta.abs() < 1e-15 {
            break;
        }
    }
    let mut phi = phi.rem_euclid(TAU);
    if phi > PI {
        phi -= TAU;
    }
    phi
}

/// `sin_cos(j · φ_i)` for the phase samples `φ_i = i · (2π / n)`, `i < n`,
/// `j = 1..=n/16` (row `i` at `i · n/16`), computed as
/// [`best_phase_shift`] computes them, once per `n` for the process
/// (`None` past 2^18 entries: computed in place then).
fn phase_table(n: usize) -> Option<std::sync::Arc<Vec<(Real, Real)>>> {
    use std::collections::HashMap;
    use std::sync::{Arc, Mutex, OnceLock};
    type Tables = Mutex<HashMap<usize, Arc<Vec<(Real, Real)>>>>;
    static TABLES: OnceLock<Tables> = OnceLock::new();
    let per = n / 16;
    if n.saturating_mul(per) > 1 << 18 {
        return None;
    }
    let tables = TABLES.get_or_init(Tables::default);
    // A poisoned lock only means another thread panicked while filling
    // the map: the tables in it are whole.
    let mut map = tables.lock().unwrap_or_else(|e| e.into_inner());
    let table = map.entry(n).or_insert_with(|| {
        let step = TAU / n as Real;
        let rows = (0..n).flat_map(|i| {
            let phi = i as Real * step;
            (1..=per).map(move |j| {
                let (s, co) = (j as Real * phi).sin_cos();
                (s, co)
            })
        });
        Arc::new(rows.collect())
    });
    Some(Arc::clone(table))
}

/// Splits `n` intervals into groups of at most `k - 1`, as evenly as possible:
/// returns the section index where each group starts, and `n` at the end.
fn patch_breaks(intervals: usize, curves_per_patch: usize) -> Vec<usize> {
    let per = curves_per_patch - 1;
    let groups = intervals.div_ceil(per);
    let (base, extra) = (intervals / groups, intervals % groups);
    let mut breaks = vec![0];
    let mut at = 0;
    for g in 0..groups {
        at += base + usize::from(g < extra);
        breaks.push(at);
    }
    breaks
}

impl Part {
    /// The part moved by `m`: skinned again through its moved sections
    /// with its options, as a model file rebuilds it (so a moved model
    /// written and read back is the same model).
    pub fn moved(&self, m: &Rigid) -> Result<Part, PartError> {
        let sections = self.sections.iter().map(|c| c.moved(m)).collect();
        Part::new(sections, &self.options)
    }

    /// Skins `curves` (ordered along the part) with `options`.
    ///
    /// The sections are checked first: every curve valid, consecutive centres
    /// distinct, every plane normal on the same side of the axis and every
    /// curve running the same way about it, and no two consecutive planes
    /// crossing within the curves (each curve lies strictly on its own side
    /// of the neighbouring plane).
    pub fn new(curves: Vec<TrigCurve>, options: &PartOptions) -> Result<Part, PartError> {
        let n = curves.len();
        if n < 2 {
            return Err(PartError::TooFewSections { count: n });
        }
        if options.curves_per_patch < 2 {
            return Err(PartError::CurvesPerPatch(options.curves_per_patch));
        }
        for (index, c) in curves.iter().enumerate() {
            c.validate()
                .map_err(|source| PartError::Curve { index, source })?;
        }
        let world: Vec<SpaceCurve> = curves.iter().map(TrigCurve::world_series).collect();
        let centres: Vec<Point3> = world.iter().map(SpaceCurve::mean_point).collect();
        let scale = centres.iter().map(|c| c.norm()).fold(0.0, Real::max).max(
            curves
                .iter()
                .map(|c| c.a[1].abs() + c.b[1].abs())
                .fold(0.0, Real::max),
        );
        let mut knots = vec![0.0];
        for k in 0..n - 1 {
            let d = centres[k + 1].distance(centres[k]);
            if d.is_nan() || d <= GEOMETRIC_EPS * scale.max(Real::MIN_POSITIVE) {
                return Err(PartError::CoincidentSections { index: k });
            }
            knots.push(knots[k] + d);
        }
        // Plane normals and directions of travel, all relative to the axis.
        let direction = |k: usize| {
            if k + 1 < n {
                centres[k + 1] - centres[k]
            } else {
                centres[k] - centres[k - 1]
            }
        };
        let along = |k: usize| curves[k].frame.normal().dot(direction(k)) > 0.0;
        let first_along = along(0);
        let first_ccw = (curves[0].area() > 0.0) == first_along;
        for k in 1..n {
            if along(k) != first_along {
                let against = (1..n).filter(|&j| along(j) != first_along).count();
                return Err(PartError::MixedFrames {
                    index: k,
                    flipped: first_along,
                    first_is_odd: 2 * against > n - 1,
                });
            }
            if ((curves[k].area() > 0.0) == along(k)) != first_ccw {
                return Err(PartError::MixedOrientation {
                    index: k,
                    clockwise: first_ccw,
                });
            }
        }
        let sign = if first_along { 1.0 } else { -1.0 };
        for k in 0..n - 1 {
            let samples = 8 * curves[k].order().max(curves[k + 1].order()) + 64;
            // Heights of curve k+1 above plane k and of curve k below plane k+1.
            let above = curves[k + 1]
                .sample(samples)
                .iter()
                .map(|p| sign * curves[k].frame.height(*p))
                .fold(Real::INFINITY, Real::min);
            let below = curves[k]
                .sample(samples)
                .iter()
                .map(|p| -sign * curves[k + 1].frame.height(*p))
                .fold(Real::INFINITY, Real::min);
            let depth = above.min(below);
            if depth.is_nan() || depth <= 0.0 {
                return Err(PartError::CrossingPlanes {
                    index: k,
                    depth: -depth,
                });
            }
        }

        // Twist alignment.
        let sections = curves.clone();
        let mut curves = curves;
        let mut world = world;
        let mut twist = vec![0.0; n];
        if options.align_twist {
            for k in 1..n {
                let phi = best_phase_shift(&world[k - 1], &world[k]);
                if phi != 0.0 {
                    twist[k] = phi;
                    curves[k] = curves[k].shifted(phi);
                    world[k] = curves[k].world_series();
                }
            }
        }

        let segments = match options.skinning {
            Skinning::CatmullRom => {
                let ends = [&curves[0], &curves[n - 1]].map(|c| c.frame.normal());
                catmull_rom(&world, &knots, ends)?
            }
            Skinning::NaturalSpline => natural_spline(&world, &knots)?,
            Skinning::PaperChained => paper(&world, &knots, options, true)?,
            Skinning::PaperUnchained => paper(&world, &knots, options, false)?,
        };
        let mut part = Part {
            sections,
            curves,
            twist,
            knots,
            segments,
            start_cap: None,
            end_cap: None,
            options: *options,
            clockwise: !first_ccw,
        };
        part.start_cap = part.make_cap(true)?;
        part.end_cap = part.make_cap(false)?;
        Ok(part)
    }

    fn make_cap(&self, start: bool) -> Result<Option<Cap>, PartError> {
        let kind = if start {
            self.options.start_cap
        } else {
            self.options.end_cap
        };
        let curve = if start {
            &self.curves[0]
        } else {
            &self.curves[self.curves.len() - 1]
        };
        let cap = match kind {
            CapKind::Open => return Ok(None),
            CapKind::Flat => flat_cap(curve),
            CapKind::Dome {
                relative_height,
                fullness,
                axis,
            } => {
                let t = self.end_tangent(start);
                dome_cap(curve, &t, relative_height, fullness, axis)
            }
        };
        cap.map(Some)
            .map_err(|source| PartError::Cap { start, source })
    }

    /// `∂t/∂s` at an end as a curve, pointing out of the part.
    pub fn end_tangent(&self, start: bool) -> SpaceCurve {
        if start {
            let s = &self.segments[0];
            scaled(&s.patch.u_derivative_curve(0.0, 1), -1.0 / s.length())
        } else {
            let s = &self.segments[self.segments.len() - 1];
            scaled(&s.patch.u_derivative_curve(1.0, 1), 1.0 / s.length())
        }
    }

    /// The sections exactly as given to [`Part::new`] (what a model file
    /// stores: rebuilding from them with the same options gives this part).
    pub fn sections(&self) -> &[TrigCurve] {
        &self.sections
    }
    /// The sections after twist alignment (each passes exactly through the
    /// surface at its knot).
    pub fn curves(&self) -> &[TrigCurve] {
        &self.curves
    }
    /// The parameter shift applied to each section by twist alignment.
    pub fn twist(&self) -> &[Real] {
        &self.twist
    }
    /// The axis parameter `s_k` of each section (cumulative centre distance).
    pub fn knots(&self) -> &[Real] {
        &self.knots
    }
    /// The patches of the surface, in order along the axis.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }
    pub fn start_cap(&self) -> Option<&Cap> {
        self.start_cap.as_ref()
    }
    pub fn end_cap(&self) -> Option<&Cap> {
        self.end_cap.as_ref()
    }
    pub fn options(&self) -> &PartOptions {
        &self.options
    }
    /// True when the curves run clockwise about the axis (first to last
    /// section): the patches' `∂v × ∂u` normals then point inward, and the
    /// tessellator flips them.
    pub fn is_clockwise(&self) -> bool {
        self.clockwise
    }
    /// The total parameter length (the axis length through the centres).
    pub fn length(&self) -> Real {
        self.knots[self.knots.len() - 1]
    }

    /// The centre (mean point) of the part's curve at `s`: `Σ_m f_m,0 u^m`
    /// (no series built).
    pub fn centre(&self, s: Real) -> Point3 {
        let (i, u) = self.locate(s);
        let mut acc = Vec3::ZERO;
        let mut um = 1.0;
        for f in self.segments[i].patch.coefficients() {
            acc += f.mean_point() * um;
            um *= u;
        }
        acc
    }

    /// The `s` where the centre line's height along `dir` is `level`, by the
    /// Illinois variant of regula falsi (the centre line of a part cut
    /// across `dir` is monotone in height; converges superlinearly, to
    /// 1e-12 of the part's length). `None` when the level is outside the
    /// part.
    pub fn s_at_level(&self, dir: Vec3, level: Real) -> Option<Real> {
        let l = self.length();
        let h = |s: Real| self.centre(s).dot(dir) - level;
        let (mut a, mut b) = (0.0, l);
        let (mut fa, mut fb) = (h(a), h(b));
        if fa * fb > 0.0 || !(fa.is_finite() && fb.is_finite()) {
            return None;
        }
        let mut side = 0;
        for _ in 0..60 {
            if fa == fb {
                break;
            }
            let c = (a * fb - b * fa) / (fb - fa);
            let fc = h(c);
            if fc == 0.0 || (b - a).abs() <= 1e-12 * l {
                return Some(c);
            }
            if (fc > 0.0) == (fb > 0.0) {
                b = c;
                fb = fc;
                if side == -1 {
                    fa *= 0.5;
                }
                side = -1;
            } else {
                a = c;
                fa = fc;
                if side == 1 {
                    fb *= 0.5;
                }
                side = 1;
            }
            if fc.abs() <= 1e-13 * l {
                return Some(c);
            }
        }
        Some(0.5 * (a + b))
    }

    /// The segment containing `s` (clamped to the part) and the local `u`.
    pub fn locate(&self, s: Real) -> (usize, Real) {
        let i = self
            .segments
            .partition_point(|seg| seg.s1 < s)
            .min(self.segments.len() - 1);
        let seg = &self.segments[i];
        (i, (s - seg.s0) / seg.length())
    }

    /// `∂^{ks+kv} t / ∂s^{ks} ∂v^{kv}` at `(s, v)`; at a join, from the
    /// segment that ends there.
    pub fn derivative(&self, s: Real, v: Real, ks: usize, kv: u32) -> Vec3 {
        let (i, u) = self.locate(s);
        let seg = &self.segments[i];
        seg.patch.derivative(u, v, ks, kv) / seg.length().powi(ks as i32)
    }

    /// The point at `(s, v)`.
    pub fn point(&self, s: Real, v: Real) -> Point3 {
        self.derivative(s, v, 0, 0)
    }

    /// The number of design parameters: every section's (coefficients,
    /// origin, frame) plus the options (method.md §7: patches are derived).
    pub fn design_parameters(&self) -> usize {
        self.curves.iter().map(TrigCurve::design_parameters).sum()
    }
}

fn common_order(world: &[SpaceCurve]) -> usize {
    world.iter().map(SpaceCurve::order).max().unwrap_or(1)
}

fn patch_err(segment: usize) -> impl Fn(PatchError) -> PartError {
    move |source| PartError::Patch { segment, source }
}

/// Cubic Hermite segments with the non-uniform Catmull-Rom (Bessel) tangents.
/// An end's tangent (the derivative of the parabola through the last three
/// curves) is the last chord's instead where the two cross the end curve's
/// plane (normal `ends`: first, last) in opposite directions: with uneven knots (a foot's
/// outlines, whose centres shift from heel to toe) the parabola can turn
/// back through the end plane, and the skin and its end cap fold back
/// into the part.
fn catmull_rom(
    world: &[SpaceCurve],
    knots: &[Real],
    ends: [Vec3; 2],
) -> Result<Vec<Segment>, PartError> {
    let order = common_order(world);
    let p: Vec<Vec<Real>> = world.iter().map(|c| flatten(c, order)).collect();
    let n = p.len();
    let h: Vec<Real> = knots.windows(2).map(|w| w[1] - w[0]).collect();
    let d: Vec<Vec<Real>> = (0..n - 1)
        .map(|k| combine(&[(1.0 / h[k], &p[k + 1]), (-1.0 / h[k], &p[k])]))
        .collect();
    let tangents: Vec<Vec<Real>> = (0..n)
        .map(|k| {
            if n == 2 {
                d[0].clone()
            } else if k == 0 {
                // Derivative at s_0 of the parabola through curves 0, 1, 2.
                let q = h[0] / (h[0] + h[1]);
                let t = combine(&[(1.0 + q, &d[0]), (-q, &d[1])]);
                unless_folding(t, &d[0], ends[0], order)
            } else if k == n - 1 {
                let q = h[n - 2] / (h[n - 3] + h[n - 2]);
                let t = combine(&[(1.0 + q, &d[n - 2]), (-q, &d[n - 3])]);
                unless_folding(t, &d[n - 2], ends[1], order)
            } else {
                let w = h[k - 1] + h[k];
                combine(&[(h[k] / w, &d[k - 1]), (h[k - 1] / w, &d[k])])
            }
        })
        .collect();
    (0..n - 1)
        .map(|k| {
            let t0 = unflatten(&combine(&[(h[k], &tangents[k])]), order);
            let t1 = unflatten(&combine(&[(h[k], &tangents[k + 1])]), order);
            let patch = Patch::hermite(&world[k], &t0, &world[k + 1], &t1).map_err(patch_err(k))?;
            Ok(Segment {
                patch,
                s0: knots[k],
                s1: knots[k + 1],
            })
        })
        .collect()
}

/// `tangent` (flattened coefficients), or `chord` where their mean
/// motions (the constant coefficients) cross the plane with `normal` in
/// opposite directions.
fn unless_folding(tangent: Vec<Real>, chord: &[Real], normal: Vec3, order: usize) -> Vec<Real> {
    let n = 2 * order + 1;
    let along = |v: &[Real]| Vec3::new(v[0], v[n], v[2 * n]).dot(normal);
    if along(&tangent) * along(chord) < 0.0 {
        chord.to_vec()
    } else {
        tangent
    }
}

/// The natural cubic spline (C2, zero second derivative at both ends) through
/// the coefficient vectors: the tridiagonal system
/// `h_{k-1} M_{k-1} + 2(h_{k-1}+h_k) M_k + h_k M_{k+1} = 6(D_k - D_{k-1})`
/// for the second derivatives `M_k`, solved once for all coefficients.
fn natural_spline(world: &[SpaceCurve], knots: &[Real]) -> Result<Vec<Segment>, PartError> {
    let order = common_order(world);
    let p: Vec<Vec<Real>> = world.iter().map(|c| flatten(c, order)).collect();
    let n = p.len();
    let len = p[0].len();
    let h: Vec<Real> = knots.windows(2).map(|w| w[1] - w[0]).collect();
    let d: Vec<Vec<Real>> = (0..n - 1)
        .map(|k| combine(&[(1.0 / h[k], &p[k + 1]), (-1.0 / h[k], &p[k])]))
        .collect();
    let mut m = vec![vec![0.0; len]; n];
    if n > 2 {
        // Thomas algorithm on the interior unknowns 1..n-1.
        let inner = n - 2;
        let mut diag = vec![0.0; inner];
        let mut upper = vec![0.0; inner];
        let mut rhs: Vec<Vec<Real>> = vec![Vec::new(); inner];
        for i in 0..inner {
            let k = i + 1;
            diag[i] = 2.0 * (h[k - 1] + h[k]);
            upper[i] = h[k];
            rhs[i] = combine(&[(6.0, &d[k]), (-6.0, &d[k - 1])]);
            if i > 0 {
                let w = h[k - 1] / diag[i - 1];
                diag[i] -= w * upper[i - 1];
                let prev = rhs[i - 1].clone();
                rhs[i] = combine(&[(1.0, &rhs[i]), (-w, &prev)]);
            }
        }
        for i in (0..inner).rev() {
            let next = if i + 1 < inner {
                combine(&[(upper[i], &m[i + 2])])
            } else {
                vec![0.0; len]
            };
            m[i + 1] = combine(&[(1.0 / diag[i], &rhs[i]), (-1.0 / diag[i], &next)]);
        }
    }
    (0..n - 1)
        .map(|k| {
            let hh = h[k] * h[k];
            let f = [
                p[k].clone(),
                combine(&[
                    (1.0, &p[k + 1]),
                    (-1.0, &p[k]),
                    (-hh / 3.0, &m[k]),
                    (-hh / 6.0, &m[k + 1]),
                ]),
                combine(&[(hh / 2.0, &m[k])]),
                combine(&[(hh / 6.0, &m[k + 1]), (-hh / 6.0, &m[k])]),
            ];
            let patch = Patch::from_coefficients(f.iter().map(|v| unflatten(v, order)).collect())
                .map_err(patch_err(k))?;
            Ok(Segment {
                patch,
                s0: knots[k],
                s1: knots[k + 1],
            })
        })
        .collect()
}

/// The paper's patches of up to `K` curves (Eq. 13-16), optionally chained by
/// Eq. 17 (the previous patch's end derivatives, rescaled to this patch's
/// parameter length, as start conditions).
fn paper(
    world: &[SpaceCurve],
    knots: &[Real],
    options: &PartOptions,
    chained: bool,
) -> Result<Vec<Segment>, PartError> {
    let breaks = patch_breaks(world.len() - 1, options.curves_per_patch);
    let mut segments: Vec<Segment> = Vec::with_capacity(breaks.len() - 1);
    for (i, w) in breaks.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let (s0, s1) = (knots[a], knots[b]);
        let len = s1 - s0;
        let params: Vec<Real> = knots[a..=b].iter().map(|s| (s - s0) / len).collect();
        let mut ends = EndConditions::NONE;
        if let (true, Some(prev)) = (chained, segments.last()) {
            let ratio = len / prev.length();
            ends.start_tangent = Some(scaled(&prev.patch.u_derivative_curve(1.0, 1), ratio));
            if options.curvature_continuity {
                ends.start_curvature = Some(scaled(
                    &prev.patch.u_derivative_curve(1.0, 2),
                    ratio * ratio,
                ));
            }
        }
        let patch =
            Patch::interpolate(&world[a..=b], Some(&params), &ends).map_err(patch_err(i))?;
        segments.push(Segment { patch, s0, s1 });
    }
    Ok(segments)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::trig::Frame;
    use crate::{assert_near, assert_vec_near};

    /// Sections of a wavy tube along +z at uneven spacing.
    fn wavy(n: usize, order: usize) -> Vec<TrigCurve> {
        (0..n)
            .map(|k| {
                let z = 0.03 * k as Real + 0.004 * (k as Real * 1.3).sin();
                let frame = Frame {
                    origin: Vec3::new(0.01 * (z * 9.0).sin(), 0.005 * z, z),
                    e1: Vec3::X,
                    e2: Vec3::Y,
                };
                let mut a = vec![0.0; 2 * order + 1];
                let mut b = a.clone();
                a[1] = 0.06 + 0.01 * (z * 7.0).sin();
                b[1] = 0.05 + 0.01 * (z * 5.0).cos();
                for j in 2..=order {
                    a[2 * j - 1] = 0.004 * (z * 3.0 + j as Real).sin();
                    b[2 * j] = 0.003 * (z * 4.0 - j as Real).cos();
                }
                TrigCurve::new(frame, a, b).unwrap()
            })
            .collect()
    }

    fn options(skinning: Skinning, k: usize, c2: bool) -> PartOptions {
        PartOptions {
            skinning,
            curves_per_patch: k,
            curvature_continuity: c2,
            ..PartOptions::default()
        }
    }

    #[test]
    fn every_scheme_interpolates_and_is_c1() {
        let curves = wavy(11, 4);
        for skinning in Skinning::ALL {
            for k in [2, 3, 4, 5] {
                let c2 = skinning == Skinning::PaperChained && k > 2;
                let part = Part::new(curves.clone(), &options(skinning, k, c2)).unwrap();
                for (c, &s) in part.curves().iter().zip(part.knots()) {
                    for i in 0..29 {
                        let v = i as Real * 0.22;
                        assert!(
                            (part.point(s, v) - c.point(v)).norm() < 1e-9,
                            "{skinning:?} K={k}"
                        );
                    }
                }
                // Derivative continuity across every join.
                let segs = part.segments();
                for w in segs.windows(2) {
                    let (a, b) = (&w[0], &w[1]);
                    for i in 0..29 {
                        let v = i as Real * 0.22;
                        let jump = |ks: usize| {
                            (a.patch.derivative(1.0, v, ks, 0) / a.length().powi(ks as i32)
                                - b.patch.derivative(0.0, v, ks, 0) / b.length().powi(ks as i32))
                            .norm()
                        };
                        assert!(jump(0) < 1e-9);
                        if skinning != Skinning::PaperUnchained {
                            assert!(jump(1) < 1e-9, "{skinning:?} K={k}: {}", jump(1));
                        }
                        if skinning == Skinning::NaturalSpline || c2 {
                            // In the next patch's u units (∂²t/∂u² = L² ∂²t/∂s²).
                            let j2 = jump(2) * b.length().powi(2);
                            assert!(j2 < 1e-9, "{skinning:?} K={k}: {j2}");
                        }
                    }
                }
            }
        }
    }

    /// Three level circles going down, the last a short step down and a
    /// long one sideways (a foot's outlines from heel to toe): the
    /// parabola's end derivative would rise back through the last plane
    /// (z +0.46 per unit); the skin leaves along the last chord instead,
    /// and its dome points down. Both ends, either way round.
    #[test]
    fn an_end_tangent_never_turns_back_through_the_end_plane() {
        let circle = |x: Real, z: Real| {
            let frame = Frame {
                origin: Vec3::new(x, 0.0, z),
                e1: Vec3::Y,
                e2: Vec3::X,
            };
            TrigCurve::new(frame, vec![0.0, 0.05, 0.0], vec![0.0, 0.05, 0.0]).unwrap()
        };
        let down = vec![circle(0.0, 0.0), circle(0.0, -0.01), circle(0.03, -0.015)];
        let opts = PartOptions {
            end_cap: CapKind::dome(),
            ..PartOptions::default()
        };
        let part = Part::new(down.clone(), &opts).unwrap();
        let t = part.end_tangent(false);
        let chord = Vec3::new(0.03, 0.0, -0.005).normalized().unwrap();
        assert_vec_near!(t.mean_point(), chord, 1e-12);
        assert!(part.end_cap().unwrap().apex.z < -0.015);
        // Reversed, the same at the start.
        let up: Vec<TrigCurve> = down.into_iter().rev().collect();
        let part = Part::new(up, &opts).unwrap();
        let t = part.end_tangent(true);
        assert_vec_near!(t.mean_point(), chord, 1e-12);
    }

    #[test]
    fn long_parts_are_chains_of_low_degree() {
        // 50 sections of a smooth tube: no patch above degree K-1 (+1 for the
        // chaining condition) and the surface between sections stays close to
        // the smooth tube it samples.
        let curves = wavy(50, 3);
        for skinning in Skinning::ALL {
            let part = Part::new(curves.clone(), &options(skinning, 4, false)).unwrap();
            for seg in part.segments() {
                assert!(
                    seg.patch.degree() <= 4,
                    "{skinning:?}: degree {}",
                    seg.patch.degree()
                );
            }
            // Mid-interval radius within 0.2 mm of the neighbours' average.
            let k = part.knots();
            for i in 0..k.len() - 1 {
                let s = 0.5 * (k[i] + k[i + 1]);
                let p = part.point(s, 0.0);
                let q = 0.5 * (part.curves()[i].point(0.0) + part.curves()[i + 1].point(0.0));
                assert!(p.distance(q) < 2e-3, "{skinning:?} {i}: {}", p.distance(q));
            }
        }
    }

    /// The cached phase samples are bit for bit the ones computed in
    /// place, from any thread; tables too large are not kept.
    #[test]
    fn phase_table_is_the_direct_sin_cos() {
        for n in [64, 80, 320] {
            let step = TAU / n as Real;
            let check = move || {
                let t = phase_table(n).unwrap();
                assert_eq!(t.len(), n * (n / 16));
                for i in 0..n {
                    for j in 1..=n / 16 {
                        let direct = (j as Real * (i as Real * step)).sin_cos();
                        let got = t[i * (n / 16) + j - 1];
                        assert_eq!(got.0.to_bits(), direct.0.to_bits());
                        assert_eq!(got.1.to_bits(), direct.1.to_bits());
                    }
                }
            };
            check();
            std::thread::spawn(check).join().unwrap();
        }
        assert!(phase_table(1 << 12).is_none());
    }

    #[test]
    fn phase_shift_recovers_a_planted_rotation() {
        let c = wavy(2, 5)[0].world_series();
        for phi0 in [0.3, -2.0, 3.0, 1e-3] {
            let moved = c.shifted(phi0);
            let phi = best_phase_shift(&c, &moved);
            assert_near!(phi, -phi0, 1e-10);
        }
    }

    #[test]
    fn near_ties_keep_the_start_points() {
        // Curves dominated by the second harmonic look almost the same half
        // a turn later: the two maxima of the alignment differ by a faint
        // first harmonic (here favouring the far one). The shift nearest
        // zero is kept, so the sections' own start points decide.
        let c = TrigCurve::new(
            Frame::XY,
            vec![0.0, 0.001, 0.0, 0.1, 0.0],
            vec![0.0, 0.001, 0.0, 0.0, 0.1],
        )
        .unwrap();
        let d = TrigCurve::new(
            Frame::XY,
            vec![0.0, -0.0012, 0.0, 0.1, 0.0],
            vec![0.0, -0.0012, 0.0, 0.0, 0.1],
        )
        .unwrap()
        .shifted(0.05);
        let phi = best_phase_shift(&c.world_series(), &d.world_series());
        assert_near!(phi, -0.05, 1e-3);
    }

    #[test]
    fn twist_is_aligned() {
        let mut curves = wavy(5, 3);
        curves[2] = curves[2].shifted(0.7);
        curves[3] = curves[3].shifted(0.7);
        curves[4] = curves[4].shifted(-1.1);
        let part = Part::new(curves, &PartOptions::default()).unwrap();
        let t = part.twist();
        assert_near!(t[2], -0.7, 0.05);
        assert_near!(t[3], -0.7, 0.05);
        assert_near!(t[4], 1.1, 0.05);
    }

    #[test]
    fn bad_sections_are_rejected() {
        let curves = wavy(4, 2);
        assert_eq!(
            Part::new(curves[..1].to_vec(), &PartOptions::default()),
            Err(PartError::TooFewSections { count: 1 })
        );
        // Crossing with consistent normals: tilt by 60° about x.
        let mut crossing = curves.clone();
        crossing[1].frame =
            Frame::from_normal(crossing[1].frame.origin, Vec3::new(0.0, 0.87, 0.5), Vec3::X)
                .unwrap();
        assert!(matches!(
            Part::new(crossing, &PartOptions::default()),
            Err(PartError::CrossingPlanes { index: 0, .. })
        ));
        // A flipped frame (normal against the axis).
        let mut flipped = curves.clone();
        flipped[3].frame.e2 = flipped[3].frame.e2 * -1.0;
        assert!(matches!(
            Part::new(flipped, &PartOptions::default()),
            Err(PartError::MixedFrames { index: 3, .. })
        ));
        // A curve running the other way.
        let mut reversed = curves.clone();
        for x in reversed[1].b.iter_mut() {
            *x = -*x;
        }
        assert!(matches!(
            Part::new(reversed, &PartOptions::default()),
            Err(PartError::MixedOrientation { index: 1, .. })
        ));
        let mut nan = curves.clone();
        nan[2].a[1] = Real::NAN;
        assert!(matches!(
            Part::new(nan, &PartOptions::default()),
            Err(PartError::Curve { index: 2, .. })
        ));
        let mut same = curves;
        same[1] = same[0].clone();
        assert!(matches!(
            Part::new(same, &PartOptions::default()),
            Err(PartError::CoincidentSections { index: 0 })
                | Err(PartError::CrossingPlanes { index: 0, .. })
        ));
    }

    #[test]
    fn breaks_are_balanced() {
        let b = patch_breaks(49, 4);
        assert_eq!(b.first(), Some(&0));
        assert_eq!(b.last(), Some(&49));
        assert!(b.windows(2).all(|w| (2..=3).contains(&(w[1] - w[0]))));
        assert_eq!(patch_breaks(1, 4), vec![0, 1]);
        assert_eq!(patch_breaks(6, 4), vec![0, 3, 6]);
    }

    proptest::proptest! {
        /// Random sections (orders 1-6, uneven spacing, random phases):
        /// every scheme interpolates them and is C1 (C0 for the unchained one).
        #[test]
        fn random_sections_interpolate_and_join_smoothly(
            seed in proptest::collection::vec(-1.0f64..1.0, 40),
            k in 2usize..6,
        ) {
            let n = 3 + (seed[0].abs() * 6.0) as usize;
            let mut z = 0.0;
            let curves: Vec<TrigCurve> = (0..n)
                .map(|i| {
                    z += 0.02 + 0.02 * seed[i + 1].abs();
                    let order = 1 + ((seed[i + 2].abs() * 6.0) as usize).min(5);
                    let mut a = vec![0.0; 2 * order + 1];
                    let mut b = a.clone();
                    a[1] = 0.06 + 0.01 * seed[i + 3];
                    b[1] = 0.05 + 0.01 * seed[i + 4];
                    for j in 2..=order {
                        a[2 * j - 1] = 0.004 * seed[(i + j) % 40] / j as Real;
                        b[2 * j] = 0.004 * seed[(i + 2 * j) % 40] / j as Real;
                    }
                    let frame = Frame { origin: Vec3::new(0.01 * seed[i + 5], 0.0, z), e1: Vec3::X, e2: Vec3::Y };
                    TrigCurve::new(frame, a, b).unwrap().shifted(3.0 * seed[i + 6])
                })
                .collect();
            for skinning in Skinning::ALL {
                let part = Part::new(curves.clone(), &options(skinning, k, false)).unwrap();
                for (c, &s) in part.curves().iter().zip(part.knots()) {
                    for i in 0..13 {
                        let v = i as Real * 0.5;
                        proptest::prop_assert!((part.point(s, v) - c.point(v)).norm() < 1e-9);
                    }
                }
                for w in part.segments().windows(2) {
                    for i in 0..13 {
                        let v = i as Real * 0.5;
                        let d = (w[0].patch.du(1.0, v) / w[0].length() - w[1].patch.du(0.0, v) / w[1].length()).norm();
                        if skinning != Skinning::PaperUnchained {
                            proptest::prop_assert!(d < 1e-9, "{:?}: {}", skinning, d);
                        }
                    }
                }
            }
        }
    }
}
