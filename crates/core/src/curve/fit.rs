//! Fitting a trigonometric curve to one ordered closed loop of points
//! (method.md §2-4): cleaning, plane and frame, orientation, start point,
//! parameter values, least squares, order choice and the ellipse baseline.
//!
//! ```
//! use trigbody_core::{fit_loop_2d, FitOptions, Vec2};
//! // 64 points on a circle of radius 2: order 1 fits it exactly.
//! let pts: Vec<Vec2> = (0..64)
//!     .map(|i| {
//!         let t = std::f64::consts::TAU * i as f64 / 64.0;
//!         Vec2::new(2.0 * t.cos(), 2.0 * t.sin())
//!     })
//!     .collect();
//! let fit = fit_loop_2d(&pts, &FitOptions::default()).unwrap();
//! assert_eq!(fit.order, 1);
//! assert!(fit.met && fit.errors.ea < 1e-12);
//! ```

use crate::curve::ellipse::{fit_ellipse, principal_axes, EllipseFit};
use crate::curve::lsq::{
    fit_equally_spaced, is_equally_spaced, Coefficients, FitErrors, LoopFitter,
};
use crate::curve::noise::noise_tolerances;
use crate::curve::order::{
    best_evaluated, minimal_order, paper_search, ErrorCache, OrderOptions, DEFAULT_MAX_ORDER,
};
use crate::curve::trig::{Frame, TrigCurve};
use crate::geom::linalg::symmetric_eigen3;
use crate::geom::math::{Point3, Real, Vec2, Vec3, DEFAULT_EA, DEFAULT_EM};
use crate::geom::tolerance::{DIRECTION_EPS, GEOMETRIC_EPS};
use std::f64::consts::TAU;
use thiserror::Error;

/// How the parameter value `v_i` of each point is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Parameterization {
    /// Normalized cumulative chord length `v_i = 2π s_i / L` from the start
    /// point (the default).
    #[default]
    Chord,
    /// The polar angle about the centroid, measured from the reference
    /// direction (exact for curves given as `r(θ)`; needs a loop that is
    /// star-shaped about its centroid).
    Polar,
}

/// How the points are weighted in the centroid and the least squares.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Weighting {
    /// Every point counts once (the paper's Eq. 4-5).
    Uniform,
    /// Each point weighs the arc length it stands for (half its two edges),
    /// so dense stretches of an unevenly sampled loop do not dominate the
    /// centroid or the least squares (the default: on the bundled real loops
    /// it needs 30 orders in all against 32 uniform, and the ellipse
    /// baseline's E_a drops 2-5× with the unbiased centroid).
    #[default]
    ArcLength,
}

/// Which order to fit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OrderChoice {
    /// The smallest order meeting the tolerances (the default).
    #[default]
    Auto,
    /// Exactly this order.
    Fixed(usize),
}

/// Options of [`fit_loop`] and [`fit_loop_2d`]; every field has a documented
/// default ([`FitOptions::default`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitOptions {
    /// Order choice (default [`OrderChoice::Auto`]).
    pub order: OrderChoice,
    /// Average relative error tolerance `E_a` (default 0.01).
    pub ea: Real,
    /// Maximum relative error tolerance `E_M` (default 0.05).
    pub em: Real,
    /// Highest order the automatic choice tries (default 32).
    pub max_order: usize,
    /// Parameterization (default chord length).
    pub param: Parameterization,
    /// Point weighting (default arc length).
    pub weighting: Weighting,
    /// The reference direction `r`: `v = 0` is where the ray from the
    /// centroid along `r` (projected into the plane) crosses the loop.
    /// Default: the loop's principal axis for 3D input, +x for 2D input.
    pub reference: Option<Vec3>,
    /// The direction the plane normal should point along (for body parts:
    /// up, or away from the torso); the loop is made counter-clockwise about
    /// it. Default: the normal that makes the input's own order
    /// counter-clockwise (3D input), +z (2D input).
    pub normal: Option<Vec3>,
    /// Largest out-of-plane distance of a 3D loop allowed, relative to its
    /// RMS radius (default 0.05).
    pub max_plane_deviation: Real,
    /// Fit a loop beyond `max_plane_deviation` anyway, with a warning
    /// (default false: it is an error).
    pub allow_non_planar: bool,
    /// Smoothness penalty `λ`: least squares plus `λ (Σ w) Σ_j j⁴ (α_j² + β_j²)`
    /// on the harmonics' amplitudes (a penalty on the curve's second
    /// derivative), which bridges gaps in scanned loops smoothly. Default 0.
    pub smoothing: Real,
    /// The points' scatter across the loop (a scanner's noise), in their
    /// units: the automatic order's tolerances are raised to what this
    /// noise alone gives ([`crate::curve::noise`]), so a scanned loop's
    /// order follows its shape and not its scatter. Default 0 (a mesh's
    /// section has none).
    pub noise: Real,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            order: OrderChoice::Auto,
            ea: DEFAULT_EA,
            em: DEFAULT_EM,
            max_order: DEFAULT_MAX_ORDER,
            param: Parameterization::Chord,
            weighting: Weighting::ArcLength,
            reference: None,
            normal: None,
            max_plane_deviation: 0.05,
            allow_non_planar: false,
            smoothing: 0.0,
            noise: 0.0,
        }
    }
}

/// Why a loop could not be fitted. Each message says what to fix.
#[derive(Debug, Error, PartialEq)]
pub enum FitError {
    #[error("no points: a loop needs at least 3 distinct points")]
    Empty,
    #[error("point {index} is not finite ({value:?}): remove or repair it")]
    NonFinite { index: usize, value: [Real; 3] },
    #[error("only {distinct} distinct point(s): a loop needs at least 3")]
    TooFewPoints { distinct: usize },
    #[error("order {order} needs at least {needed} distinct points (2J+1), but the loop has {distinct}; lower the order or give more points")]
    OrderTooHigh {
        order: usize,
        needed: usize,
        distinct: usize,
    },
    #[error("order must be at least 1")]
    ZeroOrder,
    #[error("all {count} points are the same point: there is no loop")]
    Coincident { count: usize },
    #[error("all points lie on one line: there is no loop to fit")]
    Collinear,
    #[error("the loop is not planar: a point lies {distance:e} from the best-fit plane, {relative:.3} of the loop's radius (allowed {allowed:.3}); cut a planar section or allow non-planar loops")]
    NotPlanar {
        distance: Real,
        relative: Real,
        allowed: Real,
    },
    #[error("the loop crosses itself: edge {first} (points {first}-{first_next}) crosses edge {second}; give the points in order along the loop")]
    SelfCrossing {
        first: usize,
        first_next: usize,
        second: usize,
    },
    #[error("the reference direction is parallel to the loop's normal, so it gives no direction in the plane")]
    BadReference,
    #[error("invalid tolerance {name} = {value}: it must be a positive number")]
    BadTolerance { name: &'static str, value: Real },
    #[error("the least-squares system is singular at order {order}: the points are too clustered for it")]
    Singular { order: usize },
}

/// A fitted loop: the curve, its errors, how the order was chosen, the
/// ellipse baseline, and the cleaned input it was fitted to.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopFit {
    /// The fitted curve (frame origin = the centroid, paper Eq. 4).
    pub curve: TrigCurve,
    /// The order of `curve`.
    pub order: usize,
    /// Errors of `curve` at the input points.
    pub errors: FitErrors,
    /// True when `errors` meet both tolerances.
    pub met: bool,
    /// The tolerances `(E_a, E_M)` the fit was judged against (the
    /// options', raised to what [`FitOptions::noise`] gives).
    pub tolerances: (Real, Real),
    /// The orders the paper's interpolation search tried, in order.
    pub orders_tried: Vec<usize>,
    /// The paper's search's pick (`None`: it found no order that meets).
    pub paper_order: Option<usize>,
    /// The exact smallest order that meets the tolerances, if any.
    pub minimal_order: Option<usize>,
    /// Errors of every order evaluated, ascending by order.
    pub errors_by_order: Vec<(usize, FitErrors)>,
    /// The standard-ellipse baseline on the same points.
    pub ellipse: Option<EllipseFit>,
    /// Largest distance of an input point from the fitted plane (0 for 2D).
    pub plane_deviation: Real,
    /// The cleaned points in plane coordinates relative to the centroid, in
    /// the (counter-clockwise) order they were fitted.
    pub plane_points: Vec<Vec2>,
    /// The parameter value of each of `plane_points`.
    pub params: Vec<Real>,
    /// Points dropped as consecutive duplicates or a repeated closing point.
    pub dropped: usize,
    /// True when the input ran clockwise and was reversed.
    pub reversed: bool,
    /// True when the coefficients came from the equally-spaced fast path.
    pub fast_path: bool,
    /// Things the user should know (tolerances not met, non-planar loop…).
    pub warnings: Vec<String>,
}

impl LoopFit {
    /// The ellipse baseline as an order-1 curve in the fit's frame.
    pub fn ellipse_curve(&self) -> Option<TrigCurve> {
        self.ellipse.map(|e| e.to_curve(self.curve.frame))
    }
}

/// The points lie on a line when their second principal variance is below
/// this fraction of the first (the loop has no area to fit).
const COLLINEAR_RATIO: Real = 1e-20;

/// Fits a loop of 3D points ordered along the loop (see the module docs).
pub fn fit_loop(points: &[Point3], opts: &FitOptions) -> Result<LoopFit, FitError> {
    check_options(opts)?;
    let (pts, dropped) = clean(points)?;
    let w = arc_weights(&pts, |p, q| (*p - *q).norm(), opts.weighting);
    let wsum: Real = w.iter().sum();
    let centroid = pts
        .iter()
        .zip(&w)
        .fold(Vec3::ZERO, |acc, (p, wi)| acc + *p * *wi)
        / wsum;
    // Plane: the smallest principal axis of the (weighted) covariance.
    let mut cov = [[0.0; 3]; 3];
    for (p, wi) in pts.iter().zip(&w) {
        let d = (*p - centroid).to_array();
        for r in 0..3 {
            for c in 0..3 {
                cov[r][c] += wi * d[r] * d[c] / wsum;
            }
        }
    }
    let (vals, vecs) = symmetric_eigen3(cov);
    if !(vals[0] > 0.0) {
        return Err(FitError::Coincident { count: pts.len() });
    }
    if !(vals[1] > COLLINEAR_RATIO * vals[0]) {
        return Err(FitError::Collinear);
    }
    let mut normal = vecs[2];
    let rms_radius = (vals[0] + vals[1] + vals[2].max(0.0)).sqrt();
    let deviation = pts
        .iter()
        .map(|p| (*p - centroid).dot(normal).abs())
        .fold(0.0, Real::max);
    let mut warnings = Vec::new();
    let relative = deviation / rms_radius;
    if relative > opts.max_plane_deviation {
        if opts.allow_non_planar {
            warnings.push(format!(
                "the loop is not planar: a point lies {deviation:.4e} from the plane ({:.1} % of its radius); it was projected",
                100.0 * relative
            ));
        } else {
            return Err(FitError::NotPlanar {
                distance: deviation,
                relative,
                allowed: opts.max_plane_deviation,
            });
        }
    }
    // Orient the normal: along the requested direction, else so that the
    // input's own order runs counter-clockwise (positive signed area
    // ½ Σ (p_i − c) × (p_{i+1} − c) · n).
    let flip = match opts.normal {
        Some(n) => normal.dot(n) < 0.0,
        None => {
            let n = pts.len();
            let area: Real = (0..n)
                .map(|i| {
                    (pts[i] - centroid)
                        .cross(pts[(i + 1) % n] - centroid)
                        .dot(normal)
                })
                .sum();
            area < 0.0
        }
    };
    if flip {
        normal = -normal;
    }
    let e1_guess = match opts.reference {
        Some(r) if (r - normal * r.dot(normal)).norm() <= DIRECTION_EPS * r.norm() => {
            return Err(FitError::BadReference)
        }
        Some(r) => r,
        None => vecs[0],
    };
    let frame = Frame::from_normal(centroid, normal, e1_guess).ok_or(FitError::BadReference)?;
    let q: Vec<Vec2> = pts.iter().map(|p| frame.to_plane(*p)).collect();
    let mut fit = fit_plane_points(frame, q, Vec2::new(1.0, 0.0), opts)?;
    fit.plane_deviation = deviation;
    fit.dropped = dropped;
    warnings.append(&mut fit.warnings);
    fit.warnings = warnings;
    Ok(fit)
}

/// Fits a loop of 2D points ordered along the loop. The series' x and y are
/// the input's own axes (`e1 = (1,0,0)`, `e2 = (0,1,0)`), the origin is the
/// centroid, and the loop is made counter-clockwise about +z.
pub fn fit_loop_2d(points: &[Vec2], opts: &FitOptions) -> Result<LoopFit, FitError> {
    check_options(opts)?;
    let p3: Vec<Point3> = points.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect();
    let (pts, dropped) = clean(&p3)?;
    let p2: Vec<Vec2> = pts.iter().map(|p| Vec2::new(p.x, p.y)).collect();
    let w = arc_weights(&p2, |p, q| (*p - *q).norm(), opts.weighting);
    let wsum: Real = w.iter().sum();
    let c = p2
        .iter()
        .zip(&w)
        .fold(Vec2::ZERO, |acc, (p, wi)| acc + *p * *wi)
        / wsum;
    let q: Vec<Vec2> = p2.iter().map(|p| *p - c).collect();
    let (_, l1, l2) = principal_axes(&q);
    if !(l1 > 0.0) {
        return Err(FitError::Coincident { count: pts.len() });
    }
    if !(l2 > COLLINEAR_RATIO * l1) {
        return Err(FitError::Collinear);
    }
    let ray = match opts.reference {
        Some(r) => Vec2::new(r.x, r.y)
            .normalized()
            .ok_or(FitError::BadReference)?,
        None => Vec2::new(1.0, 0.0),
    };
    let frame = Frame {
        origin: Vec3::new(c.x, c.y, 0.0),
        e1: Vec3::X,
        e2: Vec3::Y,
    };
    let mut fit = fit_plane_points(frame, q, ray, opts)?;
    fit.dropped = dropped;
    Ok(fit)
}

fn check_options(opts: &FitOptions) -> Result<(), FitError> {
    for (name, value) in [("ea", opts.ea), ("em", opts.em)] {
        if !(value > 0.0 && value.is_finite()) {
            return Err(FitError::BadTolerance { name, value });
        }
    }
    for (name, value) in [("smoothing", opts.smoothing), ("noise", opts.noise)] {
        if !(value >= 0.0 && value.is_finite()) {
            return Err(FitError::BadTolerance { name, value });
        }
    }
    if opts.order == OrderChoice::Fixed(0) {
        return Err(FitError::ZeroOrder);
    }
    Ok(())
}

/// Rejects empty and non-finite input; drops consecutive duplicates and a
/// repeated closing point. Returns the cleaned points and how many were
/// dropped.
fn clean(points: &[Point3]) -> Result<(Vec<Point3>, usize), FitError> {
    if points.is_empty() {
        return Err(FitError::Empty);
    }
    if let Some((index, p)) = points.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(FitError::NonFinite {
            index,
            value: p.to_array(),
        });
    }
    let mut out: Vec<Point3> = Vec::with_capacity(points.len());
    for p in points {
        if out.last() != Some(p) {
            out.push(*p);
        }
    }
    while out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    let dropped = points.len() - out.len();
    if out.len() == 1 {
        return Err(FitError::Coincident {
            count: points.len(),
        });
    }
    if out.len() < 3 {
        return Err(FitError::TooFewPoints {
            distinct: out.len(),
        });
    }
    Ok((out, dropped))
}

/// Per-point weights: all one, or the arc length each point stands for
/// (half of its two edges), scaled to mean one.
fn arc_weights<P>(pts: &[P], dist: impl Fn(&P, &P) -> Real, w: Weighting) -> Vec<Real> {
    let n = pts.len();
    match w {
        Weighting::Uniform => vec![1.0; n],
        Weighting::ArcLength => {
            let edge: Vec<Real> = (0..n).map(|i| dist(&pts[i], &pts[(i + 1) % n])).collect();
            let total: Real = edge.iter().sum();
            (0..n)
                .map(|i| 0.5 * (edge[i] + edge[(i + n - 1) % n]) * n as Real / total)
                .collect()
        }
    }
}

/// Twice the signed area... halved: the shoelace signed area of a polygon.
pub fn signed_area(q: &[Vec2]) -> Real {
    let n = q.len();
    0.5 * (0..n).map(|i| q[i].cross(q[(i + 1) % n])).sum::<Real>()
}

/// Finds a pair of non-adjacent edges of the closed polygon that cross, by a
/// sweep over the edges sorted by their smallest x.
pub fn find_self_crossing(q: &[Vec2]) -> Option<(usize, usize)> {
    let n = q.len();
    if n < 4 {
        return None;
    }
    let mut order: Vec<usize> = (0..n).collect();
    let lo = |i: usize| q[i].x.min(q[(i + 1) % n].x);
    let hi = |i: usize| q[i].x.max(q[(i + 1) % n].x);
    order.sort_by(|&a, &b| lo(a).total_cmp(&lo(b)));
    for (k, &i) in order.iter().enumerate() {
        let (a0, a1) = (q[i], q[(i + 1) % n]);
        let (ylo, yhi) = (a0.y.min(a1.y), a0.y.max(a1.y));
        for &j in &order[k + 1..] {
            if lo(j) > hi(i) {
                break;
            }
            if j == (i + 1) % n || i == (j + 1) % n {
                continue;
            }
            let (b0, b1) = (q[j], q[(j + 1) % n]);
            if b0.y.max(b1.y) < ylo || b0.y.min(b1.y) > yhi {
                continue;
            }
            if segments_cross(a0, a1, b0, b1) {
                return Some((i.min(j), i.max(j)));
            }
        }
    }
    None
}

/// Proper or touching intersection of segments `ab` and `cd`.
fn segments_cross(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
    let o = |p: Vec2, q: Vec2, r: Vec2| (q - p).cross(r - p);
    let (d1, d2, d3, d4) = (o(c, d, a), o(c, d, b), o(a, b, c), o(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: Vec2, q: Vec2, r: Vec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    (d1 == 0.0 && on(c, d, a))
        || (d2 == 0.0 && on(c, d, b))
        || (d3 == 0.0 && on(a, b, c))
        || (d4 == 0.0 && on(a, b, d))
}

/// Chord-length parameters `v_i = 2π (s_i − s_0) / L`, where `s_0` is the arc
/// position at which the ray from the origin along `ray` leaves the loop
/// (its farthest crossing), or the point farthest along `ray` when the ray
/// misses the loop.
pub fn chord_params(q: &[Vec2], ray: Vec2) -> Vec<Real> {
    let n = q.len();
    let mut s = vec![0.0; n];
    for i in 1..n {
        s[i] = s[i - 1] + (q[i] - q[i - 1]).norm();
    }
    let total = s[n - 1] + (q[0] - q[n - 1]).norm();
    // Farthest crossing of the ray {t·ray, t ≥ 0} with edge i → i+1.
    let mut best: Option<(Real, Real)> = None; // (t, arc position)
    for i in 0..n {
        let (a, b) = (q[i], q[(i + 1) % n]);
        let e = b - a;
        let denom = ray.cross(e);
        if denom == 0.0 {
            continue;
        }
        // a + u e = t ray  →  t = a×e / ray×e,  u = a×ray / ray×e
        let t = a.cross(e) / denom;
        let u = a.cross(ray) / denom;
        if t >= 0.0 && (0.0..1.0).contains(&u) && best.is_none_or(|(bt, _)| t > bt) {
            best = Some((t, s[i] + u * e.norm()));
        }
    }
    let s0 = match best {
        Some((_, pos)) => pos,
        None => {
            let k = (0..n)
                .max_by(|&i, &j| q[i].dot(ray).total_cmp(&q[j].dot(ray)))
                .unwrap_or(0);
            s[k]
        }
    };
    s.iter()
        .map(|&si| TAU * (si - s0).rem_euclid(total) / total)
        .collect()
}

/// Polar-angle parameters about the origin, measured from `ray`.
pub fn polar_params(q: &[Vec2], ray: Vec2) -> Vec<Real> {
    let perp = ray.perp();
    q.iter()
        .map(|p| p.dot(perp).atan2(p.dot(ray)).rem_euclid(TAU))
        .collect()
}

/// Errors of coefficients `c` at `points` with parameters `params` (the
/// slow, direct evaluation used by the fast path).
fn direct_errors(points: &[Vec2], params: &[Real], c: &Coefficients) -> FitErrors {
    let scale = points.iter().map(|p| p.norm()).fold(0.0, Real::max);
    let floor = (scale * GEOMETRIC_EPS).max(Real::MIN_POSITIVE);
    let (mut sum_rel, mut max_rel, mut sum_sq, mut max_d) = (0.0, 0.0 as Real, 0.0, 0.0 as Real);
    for (p, &v) in points.iter().zip(params) {
        let (s1, c1) = v.sin_cos();
        let (mut cj, mut sj) = (1.0, 0.0);
        let (mut x, mut y) = (c.a[0], c.b[0]);
        for j in 1..=c.order() {
            (cj, sj) = (cj * c1 - sj * s1, sj * c1 + cj * s1);
            x += c.a[2 * j - 1] * cj + c.a[2 * j] * sj;
            y += c.b[2 * j - 1] * sj + c.b[2 * j] * cj;
        }
        let d = (x - p.x).hypot(y - p.y);
        let rel = d / p.norm().max(floor);
        sum_rel += rel;
        max_rel = max_rel.max(rel);
        sum_sq += d * d;
        max_d = max_d.max(d);
    }
    let n = points.len() as Real;
    FitErrors {
        ea: sum_rel / n,
        em: max_rel,
        rms: (sum_sq / n).sqrt(),
        max: max_d,
    }
}

/// The outcome of [`search_order`]: the chosen fit and how it was chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct OrderSearch {
    /// The chosen order: the exact minimum meeting the tolerances, the best
    /// evaluated when none does, or the fixed order asked for.
    pub order: usize,
    pub coefficients: Coefficients,
    pub errors: FitErrors,
    pub met: bool,
    /// The paper's interpolation search: orders tried and its pick.
    pub orders_tried: Vec<usize>,
    pub paper_order: Option<usize>,
    /// The exact smallest order meeting the tolerances.
    pub minimal_order: Option<usize>,
    pub errors_by_order: Vec<(usize, FitErrors)>,
    /// True when the coefficients came from the equally-spaced fast path.
    pub fast_path: bool,
    /// The highest order that could be tried.
    pub limit: usize,
}

/// Fits points `q` (plane coordinates about their centroid) at parameters
/// `params` with optional weights, choosing the order as `opts` says, and
/// runs both order searches (method.md §3). `q` must hold at least 3
/// distinct points.
pub fn search_order(
    q: &[Vec2],
    params: &[Real],
    weights: Option<&[Real]>,
    opts: &FitOptions,
) -> Result<OrderSearch, FitError> {
    let distinct = q.len();
    if distinct < 3 {
        return Err(FitError::TooFewPoints { distinct });
    }
    let limit_by_points = (distinct - 1) / 2;
    let order_opts = OrderOptions {
        ea: opts.ea,
        em: opts.em,
        max_order: opts.max_order,
    };
    let limit = match opts.order {
        OrderChoice::Fixed(0) => return Err(FitError::ZeroOrder),
        OrderChoice::Fixed(j) => {
            if 2 * j + 1 > distinct {
                return Err(FitError::OrderTooHigh {
                    order: j,
                    needed: 2 * j + 1,
                    distinct,
                });
            }
            opts.max_order.max(j).min(limit_by_points)
        }
        OrderChoice::Auto => opts.max_order.min(limit_by_points).max(1),
    };
    // The fitter, rebuilt with the full capacity only when a search needs it.
    let build = |cap: usize| LoopFitter::new(q, params, weights, cap, opts.smoothing);
    let small = build(limit.min(INITIAL_CAPACITY));
    let large = std::cell::OnceCell::new();
    let fitter_for = |j: usize| -> &LoopFitter {
        if j <= small.capacity() {
            &small
        } else {
            large.get_or_init(|| build(limit))
        }
    };
    let mut cache = ErrorCache::new(|j: usize| fitter_for(j).fit(j).map(|(_, e)| e));
    let minimal = minimal_order(&mut cache, &order_opts, limit);
    let paper = paper_search(&mut cache, &order_opts, limit);
    let order = match opts.order {
        OrderChoice::Fixed(j) => j,
        OrderChoice::Auto => minimal
            .or_else(|| best_evaluated(&cache, &order_opts))
            .unwrap_or(1),
    };
    let errors_by_order = cache.evaluated();
    drop(cache);
    let fast_path = weights.is_none() && opts.smoothing == 0.0 && is_equally_spaced(params);
    let (coefficients, errors) = if fast_path {
        let c = fit_equally_spaced(q, params[0], order).ok_or(FitError::Singular { order })?;
        let e = direct_errors(q, params, &c);
        (c, e)
    } else {
        fitter_for(order)
            .fit(order)
            .ok_or(FitError::Singular { order })?
    };
    Ok(OrderSearch {
        order,
        met: errors.meets(opts.ea, opts.em),
        coefficients,
        errors,
        orders_tried: paper.tried,
        paper_order: paper.pick,
        minimal_order: minimal,
        errors_by_order,
        fast_path,
        limit,
    })
}

/// Fits points to a curve of order `order` in a given `frame` at given
/// parameters (no plane fit, no reordering): the least squares of paper
/// Eq. 5 exactly as stated. Points are projected into the frame's plane.
pub fn fit_in_frame(
    points: &[Point3],
    params: &[Real],
    frame: Frame,
    order: usize,
) -> Result<TrigCurve, FitError> {
    if points.len() != params.len() {
        return Err(FitError::TooFewPoints {
            distinct: points.len().min(params.len()),
        });
    }
    let (pts, _) = clean(points)?;
    if order == 0 {
        return Err(FitError::ZeroOrder);
    }
    if 2 * order + 1 > pts.len() {
        return Err(FitError::OrderTooHigh {
            order,
            needed: 2 * order + 1,
            distinct: pts.len(),
        });
    }
    let q: Vec<Vec2> = points.iter().map(|p| frame.to_plane(*p)).collect();
    let fitter = LoopFitter::new(&q, params, None, order, 0.0);
    let c = fitter
        .coefficients(order)
        .ok_or(FitError::Singular { order })?;
    Ok(TrigCurve {
        frame,
        a: c.a,
        b: c.b,
    })
}

/// The orders the fitter first prepares for (the paper's search starts at 10).
const INITIAL_CAPACITY: usize = 10;

/// The common back half of the fit: points already in plane coordinates
/// relative to the centroid.
fn fit_plane_points(
    frame: Frame,
    mut q: Vec<Vec2>,
    ray: Vec2,
    opts: &FitOptions,
) -> Result<LoopFit, FitError> {
    let mut warnings = Vec::new();
    let reversed = signed_area(&q) < 0.0;
    if reversed {
        q.reverse();
    }
    if let Some((first, second)) = find_self_crossing(&q) {
        return Err(FitError::SelfCrossing {
            first,
            first_next: (first + 1) % q.len(),
            second,
        });
    }
    let params = match opts.param {
        Parameterization::Chord => chord_params(&q, ray),
        Parameterization::Polar => {
            let p = polar_params(&q, ray);
            let n = p.len();
            let runs_backwards = (0..n).any(|i| {
                let d = p[(i + 1) % n] - p[i];
                d - TAU * (d / TAU).round() < 0.0
            });
            if runs_backwards {
                warnings.push(
                    "the loop is not star-shaped about its centroid: the polar angle runs backwards in places; the chord parameterization suits it better".to_string(),
                );
            }
            p
        }
    };
    // Arc-length weights that are all equal (evenly spaced points) are no
    // weights: the equally-spaced fast path then applies.
    let weights = match opts.weighting {
        Weighting::Uniform => None,
        Weighting::ArcLength => Some(arc_weights(&q, |p, r| (*p - *r).norm(), opts.weighting))
            .filter(|w| w.iter().any(|x| (x - 1.0).abs() > 1e-12)),
    };
    let floored;
    let opts = if opts.noise > 0.0 && opts.order == OrderChoice::Auto {
        let (ea, em) = noise_tolerances(&q, opts.noise, opts.ea, opts.em);
        floored = FitOptions { ea, em, ..*opts };
        &floored
    } else {
        opts
    };
    let search = search_order(&q, &params, weights.as_deref(), opts)?;
    let OrderSearch {
        order,
        coefficients: coeffs,
        errors,
        met,
        orders_tried,
        paper_order,
        minimal_order: minimal,
        errors_by_order,
        fast_path: equally_spaced,
        limit,
    } = search;
    if !met {
        let (ta, tm, ea, em) = (
            100.0 * opts.ea,
            100.0 * opts.em,
            100.0 * errors.ea,
            100.0 * errors.em,
        );
        warnings.push(match opts.order {
            OrderChoice::Fixed(_) => format!(
                "order {order} does not meet E_a ≤ {ta:.3} % and E_M ≤ {tm:.3} % (E_a = {ea:.3} %, E_M = {em:.3} %)"
            ),
            OrderChoice::Auto => format!(
                "no order up to {limit} meets E_a ≤ {ta:.3} % and E_M ≤ {tm:.3} %; order {order} gives E_a = {ea:.3} %, E_M = {em:.3} %"
            ),
        });
    }
    let ellipse = fit_ellipse(&q);
    let curve = TrigCurve {
        frame,
        a: coeffs.a,
        b: coeffs.b,
    };
    Ok(LoopFit {
        curve,
        order,
        errors,
        met,
        tolerances: (opts.ea, opts.em),
        orders_tried,
        paper_order,
        minimal_order: minimal,
        errors_by_order,
        ellipse,
        plane_deviation: 0.0,
        plane_points: q,
        params,
        dropped: 0,
        reversed,
        fast_path: equally_spaced,
        warnings,
    })
}
