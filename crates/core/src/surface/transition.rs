//! Transition surfaces between parts (method.md §6): a cubic Hermite
//! surface in `u`, coefficient-wise in `v`, from a boundary curve on one
//! part to a boundary curve on another, with both boundary tangents.
//!
//! ```text
//! t(u, v) = H₀(u) p₀(v) + H₁(u) m₀ τ₀(v) + H₂(u) p₁(v) + H₃(u) m₁ τ₁(v)
//! H₀ = 2u³ − 3u² + 1,  H₁ = u³ − 2u² + u,  H₂ = −2u³ + 3u²,  H₃ = u³ − u²
//! ```
//!
//! `p₀` is the end curve of the part the transition starts from (a limb:
//! its first section, twist-aligned as skinned), `τ₀` that part's
//! `∂t/∂s` there pointing out of it, `p₁`/`τ₁` the curve and the tangent on
//! the other part pointing into it. `m₀`, `m₁` (model units) are the
//! magnitudes: the shape controls. At `u = 0` the surface is `p₀` and
//! `∂t/∂u = m₀ τ₀`, parallel to the part's own `∂t/∂s`, so position and
//! tangent direction are continuous across the join (and the same at
//! `u = 1`): the transition keeps G1 continuity with both parts.
//!
//! **Boundary on the torso.** For the neck `p₁` is the head's own end
//! section. For an arm it is a curve on the torso's side ([`SideCut`],
//! [`side_cut_loop`]): the torso's surface cut by a plane (vertical
//! through the armpit), with `τ₁` the surface's own direction across the
//! curve, and both tangents scaled by the local gap ([`gap_scaled`]). For
//! a leg it is the leg's half of the torso's
//! bottom curve ([`Seam`]): the torso's first curve is split by the plane
//! through the crotch point `K` normal to the body's left axis; the half on
//! the leg's side is closed by a seam across the plane that dips from the
//! two crossings down to `K`'s level (a parabola in the plane), so the two
//! legs' transitions share the seam and together close the torso's bottom.
//! The half-loop is resampled at equal chord length, fitted by its discrete
//! Fourier series of order [`TransitionSpec::order`] (exact least squares
//! on equally spaced samples), oriented like `p₀` and phase-aligned to it
//! ([`best_phase_shift`]); `τ₁` is the torso's `∂t/∂s` at the same samples
//! (its mean along the seam), fitted the same way.
//!
//! **Magnitudes** ([`fit_magnitudes`]): both are chosen on the grid
//! `λ d`, `λ ∈ {⅛, ¼, ½, ¾, 1, 1½, 2, 3}`, `d` the distance between the
//! boundary curves' centres, minimizing the mean squared distance from the
//! surface (8 × 32 samples strictly between the curves) to the input
//! there.
//!
//! **Design parameters** (method.md §7): the two magnitudes, plus 6 for a
//! seam or a side cut (its point and plane normal); everything else is
//! derived from the parts.

use crate::curve::series::Series;
use crate::curve::trig::SpaceCurve;
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::Mesh;
use crate::geom::tolerance::ROUNDING_MARGIN;
use crate::surface::part::{best_phase_shift, Part};
use crate::surface::patch::{Patch, PatchError};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;
use thiserror::Error;

/// Samples of the half-loop (and its tangents) before the Fourier fit.
const HALF_LOOP_SAMPLES: usize = 512;
/// The magnitude grid, as multiples of the distance between the centres.
pub const MAGNITUDE_GRID: [Real; 8] = [0.125, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0];

/// Why a transition could not be built.
#[derive(Debug, Error, PartialEq)]
pub enum TransitionError {
    #[error("the magnitudes must be finite and positive, got {0} and {1}")]
    BadMagnitudes(Real, Real),
    #[error("the seam plane does not split the end curve in two (it crosses it {0} times)")]
    SeamMisses(usize),
    #[error("the seam's normal has no direction")]
    BadSeam,
    #[error("the side plane does not cut the part's surface in a closed curve around its point")]
    SideCutMisses,
    #[error("the side plane's normal has no direction")]
    BadSideCut,
    #[error("the half-loop order must be between 1 and 64, got {0}")]
    BadOrder(usize),
    #[error(transparent)]
    Patch(#[from] PatchError),
}

/// Splits the end curve on the `to` part: the boundary is the half of the
/// curve on the side `normal` points to, closed by a seam through the
/// plane `(point, normal)` dipping to `point`'s level along `up`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Seam {
    /// A point of the plane; the seam's lowest point is at its level (the
    /// crotch).
    pub point: Point3,
    /// The plane's normal, pointing to the kept half.
    pub normal: Vec3,
    /// The direction the seam dips against (the body's up).
    pub up: Vec3,
}

/// Cuts the `to` part's surface with a plane: the boundary on a part's
/// side (an arm's transition ends on the torso's shoulder), see
/// [`side_cut_loop`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SideCut {
    /// A point of the plane inside the wanted curve (where the arm's axis
    /// meets the plane).
    pub point: Point3,
    /// The plane's normal, pointing out of the `to` part towards the
    /// `from` part.
    pub normal: Vec3,
}

/// Everything that defines a transition besides the two parts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TransitionSpec {
    /// Which end of the `from` part: its first section (`true`) or last.
    pub from_start: bool,
    /// Which end of the `to` part.
    pub to_start: bool,
    /// `m₀`, `m₁` in model units.
    pub magnitudes: [Real; 2],
    /// Split the `to` end curve (a leg's half of the torso's bottom).
    pub seam: Option<Seam>,
    /// End on the `to` part's side instead of an end of it: its surface
    /// cut by a plane (an arm on the torso's shoulder); `to_start` is then
    /// not used. Both tangents are then scaled by the local gap between
    /// the boundary curves ([`gap_scaled`]).
    pub side: Option<SideCut>,
    /// Fourier order of a seam half-loop or a side curve and their
    /// tangents.
    pub order: usize,
}

/// A transition surface (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Transition {
    spec: TransitionSpec,
    p0: SpaceCurve,
    t0: SpaceCurve,
    p1: SpaceCurve,
    t1: SpaceCurve,
    patch: Patch,
}

fn scale(c: &SpaceCurve, f: Real) -> SpaceCurve {
    let s = |x: &Series| Series {
        c: x.c.iter().map(|a| a * f).collect(),
    };
    SpaceCurve {
        x: s(&c.x),
        y: s(&c.y),
        z: s(&c.z),
    }
}

/// The boundary of `part` at one end: its (twist-aligned) curve and `∂t/∂s`
/// pointing out of the part (`outward`) or into it.
fn part_end(part: &Part, start: bool, outward: bool) -> (SpaceCurve, SpaceCurve) {
    let curves = part.curves();
    let c = if start {
        &curves[0]
    } else {
        &curves[curves.len() - 1]
    };
    let t = part.end_tangent(start);
    (c.world_series(), if outward { t } else { scale(&t, -1.0) })
}

/// The discrete Fourier series of order `order` of equally spaced samples.
fn dft(values: &[Real], order: usize) -> Series {
    let m = values.len();
    if m == 0 {
        return Series::zeros(order);
    }
    let n = m as Real;
    // cos, sin of 2π k / n once: the term (j, i) is entry j i mod n.
    let table: Vec<(Real, Real)> = (0..m)
        .map(|k| {
            let (s, c) = (TAU * k as Real / n).sin_cos();
            (c, s)
        })
        .collect();
    let mut c = vec![0.0; 2 * order + 1];
    c[0] = values.iter().sum::<Real>() / n;
    for j in 1..=order {
        let (mut a, mut b) = (0.0, 0.0);
        let mut k = 0;
        for x in values {
            let (co, s) = table[k];
            a += x * co;
            b += x * s;
            k = (k + j) % m;
        }
        c[2 * j - 1] = 2.0 * a / n;
        c[2 * j] = 2.0 * b / n;
    }
    Series { c }
}

fn fit_space(points: &[Point3], order: usize) -> SpaceCurve {
    let col = |f: fn(&Point3) -> Real| points.iter().map(f).collect::<Vec<_>>();
    SpaceCurve {
        x: dft(&col(|p| p.x), order),
        y: dft(&col(|p| p.y), order),
        z: dft(&col(|p| p.z), order),
    }
}

/// Twice the signed area of a closed polygon projected on the plane
/// normal to `up` (positive: counter-clockwise seen from `up`).
fn signed_area(points: &[Point3], up: Vec3) -> Real {
    let n = points.len();
    (0..n)
        .map(|i| points[i].cross(points[(i + 1) % n]).dot(up))
        .sum()
}

/// The half-loop boundary and its tangent field (see [`Seam`] and the
/// module doc), oriented like `reference` and phase-aligned to it.
pub fn seam_half_loop(
    curve: &SpaceCurve,
    tangent: &SpaceCurve,
    seam: &Seam,
    order: usize,
    reference: &SpaceCurve,
) -> Result<(SpaceCurve, SpaceCurve), TransitionError> {
    if !(1..=64).contains(&order) {
        return Err(TransitionError::BadOrder(order));
    }
    let normal = seam.normal.normalized().ok_or(TransitionError::BadSeam)?;
    let up = seam.up.normalized().ok_or(TransitionError::BadSeam)?;
    let m = HALF_LOOP_SAMPLES;
    let pts: Vec<Point3> = (0..m)
        .map(|i| curve.point(TAU * i as Real / m as Real))
        .collect();
    let tans: Vec<Vec3> = (0..m)
        .map(|i| tangent.point(TAU * i as Real / m as Real))
        .collect();
    let side: Vec<Real> = pts.iter().map(|p| (*p - seam.point).dot(normal)).collect();
    // The crossings: i where sample i is outside the kept half and i+1 in.
    let ups: Vec<usize> = (0..m)
        .filter(|&i| side[i] <= 0.0 && side[(i + 1) % m] > 0.0)
        .collect();
    let downs: Vec<usize> = (0..m)
        .filter(|&i| side[i] > 0.0 && side[(i + 1) % m] <= 0.0)
        .collect();
    if ups.len() != 1 || downs.len() != 1 {
        return Err(TransitionError::SeamMisses(ups.len() + downs.len()));
    }
    let cross = |i: usize| {
        let j = (i + 1) % m;
        let w = side[i] / (side[i] - side[j]);
        (
            pts[i] + (pts[j] - pts[i]) * w,
            tans[i] + (tans[j] - tans[i]) * w,
        )
    };
    let (enter, _) = cross(ups[0]);
    let (leave, _) = cross(downs[0]);
    let axis = tangent.mean_point().normalized().unwrap_or(up);
    // The kept arc, from where it enters the half to where it leaves.
    let mut poly: Vec<(Point3, Vec3)> = vec![(enter, axis)];
    let mut i = (ups[0] + 1) % m;
    while side[i] > 0.0 {
        poly.push((pts[i], tans[i]));
        i = (i + 1) % m;
    }
    poly.push((leave, axis));
    // The seam from `leave` back to `enter`, dipping to the seam point's
    // level (never rising above the chord).
    let chord = leave.distance(enter);
    let spacing = poly
        .windows(2)
        .map(|w| w[0].0.distance(w[1].0))
        .sum::<Real>()
        / (poly.len() - 1).max(1) as Real;
    let steps = ((chord / spacing.max(Real::MIN_POSITIVE)).ceil() as usize).clamp(2, m);
    let mid = (leave + enter) * 0.5;
    let dip = (seam.point.dot(up) - mid.dot(up)).min(0.0);
    for k in 1..steps {
        let s = k as Real / steps as Real;
        let p = leave + (enter - leave) * s + up * (4.0 * s * (1.0 - s) * dip);
        poly.push((p, axis));
    }
    fit_closed(&poly, up, order, reference).ok_or(TransitionError::SeamMisses(0))
}

/// A closed polygon of points with tangents, resampled at equal chord
/// length ([`HALF_LOOP_SAMPLES`]), oriented about `up` like `reference`,
/// fitted by its discrete Fourier series of order `order` and
/// phase-aligned to `reference`. `None` for a polygon of no length.
fn fit_closed(
    poly: &[(Point3, Vec3)],
    up: Vec3,
    order: usize,
    reference: &SpaceCurve,
) -> Option<(SpaceCurve, SpaceCurve)> {
    let m = HALF_LOOP_SAMPLES;
    let n = poly.len();
    let mut acc = vec![0.0; n + 1];
    for k in 0..n {
        acc[k + 1] = acc[k] + poly[k].0.distance(poly[(k + 1) % n].0);
    }
    let total = acc[n];
    if !(total > 0.0) {
        return None;
    }
    let mut rp = Vec::with_capacity(m);
    let mut rt = Vec::with_capacity(m);
    let mut k = 0;
    for i in 0..m {
        let s = total * i as Real / m as Real;
        while acc[k + 1] < s {
            k += 1;
        }
        let len = acc[k + 1] - acc[k];
        let w = if len > 0.0 { (s - acc[k]) / len } else { 0.0 };
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        rp.push(a.0 + (b.0 - a.0) * w);
        rt.push(a.1 + (b.1 - a.1) * w);
    }
    let ref_pts: Vec<Point3> = (0..m)
        .map(|i| reference.point(TAU * i as Real / m as Real))
        .collect();
    if (signed_area(&rp, up) > 0.0) != (signed_area(&ref_pts, up) > 0.0) {
        rp.reverse();
        rt.reverse();
    }
    let p = fit_space(&rp, order);
    let t = fit_space(&rt, order);
    let phi = best_phase_shift(reference, &p);
    Some((p.shifted(phi), t.shifted(phi)))
}

/// Rows of the part's surface per unit of its parameter length, and
/// samples around, for [`side_cut_loop`]'s contouring.
const SIDE_ROWS: usize = 300;
const SIDE_AROUND: usize = 128;

/// The boundary on a part's side ([`SideCut`]): the part's surface
/// `t(s, v)` cut by the plane `(x − q)·n = 0`, as the zero contour of
/// `f(s, v) = (t(s, v) − q)·n` on a grid of `SIDE_ROWS` rows along the
/// part (only the patches that come near the plane) by `SIDE_AROUND`
/// columns (marching squares, periodic in `v`; a saddle cell is split by
/// the sign of its mean). Of the closed contours, the smallest one whose
/// projection on the plane encloses `q` is the curve. Its tangent field
/// is the surface's direction across the curve, `τ = (t_s × t_v) × c'`
/// (`c'` the contour's direction), unit, pointing into the part (against
/// `n`): the transition leaves the part along its own surface (G1). Both
/// are fitted like a seam's half-loop (`fit_closed`).
pub fn side_cut_loop(
    part: &Part,
    cut: &SideCut,
    order: usize,
    reference: &SpaceCurve,
) -> Result<(SpaceCurve, SpaceCurve), TransitionError> {
    if !(1..=64).contains(&order) {
        return Err(TransitionError::BadOrder(order));
    }
    let n = cut.normal.normalized().ok_or(TransitionError::BadSideCut)?;
    if !cut.point.is_finite() {
        return Err(TransitionError::BadSideCut);
    }
    let q = cut.point;
    let segs = part.segments();
    let total = part.length();
    if segs.is_empty() || !(total > 0.0) {
        return Err(TransitionError::SideCutMisses);
    }
    // Patches that come near the plane: an end curve within a hundredth of
    // the part's length of it, or on its far side (a patch between two
    // curves further off does not bulge across).
    let reach = 0.01 * total;
    let near =
        |c: &SpaceCurve| (0..32).any(|i| (c.point(TAU * i as Real / 32.0) - q).dot(n) > -reach);
    let close: Vec<usize> = (0..segs.len())
        .filter(|&i| near(&segs[i].patch.curve_at(0.0)) || near(&segs[i].patch.curve_at(1.0)))
        .collect();
    let (Some(&first), Some(&last)) = (close.first(), close.last()) else {
        return Err(TransitionError::SideCutMisses);
    };
    // Rows: (segment, u) with the points and f-values around.
    let cols = SIDE_AROUND;
    let mut rows: Vec<(usize, Real)> = Vec::new();
    for (i, seg) in segs.iter().enumerate().take(last + 1).skip(first) {
        let k = ((seg.length() / total * SIDE_ROWS as Real).ceil() as usize).max(1);
        let from = if i == first { 0 } else { 1 };
        for j in from..=k {
            rows.push((i, j as Real / k as Real));
        }
    }
    // cos(k v_j), sin(k v_j) once for every column, then each row's points
    // as sums over its coefficients.
    let top = segs[first..=last]
        .iter()
        .map(|s| s.patch.order())
        .max()
        .unwrap_or(0);
    let mut cos = vec![0.0; cols * (top + 1)];
    let mut sin = vec![0.0; cols * (top + 1)];
    for j in 0..cols {
        let v = TAU * j as Real / cols as Real;
        let o = j * (top + 1);
        crate::curve::series::harmonics(v, top, &mut cos[o..o + top + 1], &mut sin[o..o + top + 1]);
    }
    let eval = |c: &[Real], o: usize| {
        let mut acc = c.first().copied().unwrap_or(0.0);
        for k in 1..=((c.len() - 1) / 2).min(top) {
            acc += c[2 * k - 1] * cos[o + k] + c[2 * k] * sin[o + k];
        }
        acc
    };
    let mut pts: Vec<Point3> = Vec::with_capacity(rows.len() * cols);
    for &(i, u) in &rows {
        let c = segs[i].patch.curve_at(u);
        pts.extend((0..cols).map(|j| {
            let o = j * (top + 1);
            Vec3::new(eval(&c.x.c, o), eval(&c.y.c, o), eval(&c.z.c, o))
        }));
    }
    let f: Vec<Real> = pts.iter().map(|p| (*p - q).dot(n)).collect();
    let (links, points) = plane_crossings(rows.len(), cols, &pts, &f);
    let chain = innermost_contour(&links, &points, q, n).ok_or(TransitionError::SideCutMisses)?;
    // Tangents across the curve, from the surface's derivatives there.
    let len = chain.len();
    let poly: Vec<(Point3, Vec3)> = (0..len)
        .map(|k| {
            let (p, rr, jj) = points[&chain[k]];
            let r0 = (rr.floor() as usize).min(rows.len() - 1);
            let r1 = (r0 + 1).min(rows.len() - 1);
            let w = rr - r0 as Real;
            let (i0, u0) = rows[r0];
            let (i1, u1) = rows[r1];
            let (i, u) = if i0 == i1 {
                (i0, u0 + (u1 - u0) * w)
            } else if w < 0.5 {
                (i0, u0)
            } else {
                (i1, u1)
            };
            let v = TAU * jj / cols as Real;
            let du = segs[i].patch.derivative(u, v, 1, 0);
            let dv = segs[i].patch.derivative(u, v, 0, 1);
            let along = points[&chain[(k + 1) % len]].0 - points[&chain[(k + len - 1) % len]].0;
            let t = du
                .cross(dv)
                .cross(along)
                .normalized()
                .map(|t| if t.dot(n) > 0.0 { -t } else { t })
                .unwrap_or(-n);
            (p, t)
        })
        .collect();
    fit_closed(&poly, n, order, reference).ok_or(TransitionError::SideCutMisses)
}

/// Where the grid's edges cross the plane, by edge id: the point
/// and its grid parameters (row, column).
type Crossings = std::collections::HashMap<usize, (Point3, Real, Real)>;

/// Links between crossing ids, both ways.
type Links = std::collections::HashMap<usize, Vec<usize>>;

/// Marching squares on a grid of `rows × cols` points `pts` (closed
/// around the columns) with plane offsets `f`: the crossings of the
/// plane `f = 0` with the grid's edges and the links between them within
/// each cell.
fn plane_crossings(rows: usize, cols: usize, pts: &[Point3], f: &[Real]) -> (Links, Crossings) {
    let at = |r: usize, j: usize| r * cols + j % cols;
    // Edge ids: 2 (r cols + j) for the edge (r, j)-(r, j+1), +1 for
    // (r, j)-(r+1, j). A crossing: its point and its grid parameters.
    let crossing = |a: usize, b: usize| -> Option<(Point3, Real)> {
        let (fa, fb) = (f[a], f[b]);
        ((fa > 0.0) != (fb > 0.0)).then(|| {
            let w = fa / (fa - fb);
            (pts[a] + (pts[b] - pts[a]) * w, w)
        })
    };
    let mut links: Links = Default::default();
    let mut points: Crossings = Default::default();
    for r in 0..rows.saturating_sub(1) {
        for j in 0..cols {
            // Corners c0 (r, j), c1 (r, j+1), c2 (r+1, j+1), c3 (r+1, j).
            let c = [at(r, j), at(r, j + 1), at(r + 1, j + 1), at(r + 1, j)];
            let edges = [
                (2 * at(r, j), c[0], c[1]),
                (2 * at(r, j + 1) + 1, c[1], c[2]),
                (2 * at(r + 1, j), c[3], c[2]),
                (2 * at(r, j) + 1, c[0], c[3]),
            ];
            let mut hit: Vec<usize> = Vec::with_capacity(4);
            for (k, &(id, a, b)) in edges.iter().enumerate() {
                if let Some((p, w)) = crossing(a, b) {
                    // Grid parameters of the crossing: row and column.
                    let (rr, jj) = match k {
                        0 => (r as Real, j as Real + w),
                        1 => (r as Real + w, (j + 1) as Real),
                        2 => ((r + 1) as Real, j as Real + w),
                        _ => (r as Real + w, j as Real),
                    };
                    points.insert(id, (p, rr, jj));
                    hit.push(id);
                }
            }
            let pairs: Vec<(usize, usize)> = match hit.len() {
                2 => vec![(hit[0], hit[1])],
                4 => {
                    let mean = c.iter().map(|&i| f[i]).sum::<Real>() / 4.0;
                    if (mean > 0.0) == (f[c[0]] > 0.0) {
                        vec![(hit[0], hit[1]), (hit[2], hit[3])]
                    } else {
                        vec![(hit[0], hit[3]), (hit[1], hit[2])]
                    }
                }
                _ => Vec::new(),
            };
            for (a, b) in pairs {
                links.entry(a).or_default().push(b);
                links.entry(b).or_default().push(a);
            }
        }
    }
    (links, points)
}

/// Chains the links into closed contours and returns the smallest around
/// the plane's point `q` (normal `n`), as crossing ids in order.
fn innermost_contour(links: &Links, points: &Crossings, q: Point3, n: Vec3) -> Option<Vec<usize>> {
    let e1 = n.any_perpendicular();
    let e2 = n.cross(e1);
    let flat = |p: Point3| crate::geom::math::Vec2::new((p - q).dot(e1), (p - q).dot(e2));
    let mut seen: std::collections::HashSet<usize> = Default::default();
    let mut best: Option<(Real, Vec<usize>)> = None;
    let mut starts: Vec<usize> = links.keys().copied().collect();
    starts.sort_unstable();
    for start in starts {
        if seen.contains(&start) {
            continue;
        }
        let mut chain = vec![start];
        seen.insert(start);
        let mut prev = usize::MAX;
        let mut cur = start;
        let closed = loop {
            let next = links[&cur]
                .iter()
                .copied()
                .find(|&x| x != prev && !seen.contains(&x));
            match next {
                Some(x) => {
                    seen.insert(x);
                    chain.push(x);
                    prev = cur;
                    cur = x;
                }
                None => {
                    break links[&cur].len() == 2 && links[&cur].contains(&start) && chain.len() > 2
                }
            }
        };
        if !closed {
            continue;
        }
        let poly: Vec<crate::geom::math::Vec2> =
            chain.iter().map(|id| flat(points[id].0)).collect();
        if !crate::section::mesh::point_in_polygon(crate::geom::math::Vec2::new(0.0, 0.0), &poly) {
            continue;
        }
        let area = crate::curve::fit::signed_area(&poly).abs();
        if best.as_ref().is_none_or(|(a, _)| area < *a) {
            best = Some((area, chain));
        }
    }
    best.map(|(_, chain)| chain)
}

/// A tangent field rescaled to the local gap between the boundary curves:
/// `τ(v) |p₁(v) − p₀(v)| / (|τ(v)| d)`, `d` the distance between their
/// centres, fitted at `order` (equally spaced samples, exact least
/// squares). A side transition's gap runs from nothing at the armpit to
/// a hand's breadth over the shoulder: magnitudes `λ d` of the plain
/// tangents (as long over the armpit as over the shoulder) looped there.
pub fn gap_scaled(t: &SpaceCurve, p0: &SpaceCurve, p1: &SpaceCurve, order: usize) -> SpaceCurve {
    scaled_by_gaps(t, &relative_gaps(p0, p1), order)
}

/// `|p₁(v) − p₀(v)| / d` at [`HALF_LOOP_SAMPLES`] equally spaced `v`, `d`
/// the distance between the curves' centres ([`gap_scaled`]; computed
/// once for both tangents of a transition).
fn relative_gaps(p0: &SpaceCurve, p1: &SpaceCurve) -> Vec<Real> {
    let d = p0
        .mean_point()
        .distance(p1.mean_point())
        .max(Real::MIN_POSITIVE);
    let m = HALF_LOOP_SAMPLES;
    (0..m)
        .map(|i| {
            let v = TAU * i as Real / m as Real;
            p1.point(v).distance(p0.point(v)) / d
        })
        .collect()
}

/// The unit tangent field times `gaps` (at equally spaced `v`), fitted at
/// `order`.
fn scaled_by_gaps(t: &SpaceCurve, gaps: &[Real], order: usize) -> SpaceCurve {
    let m = gaps.len();
    let scaled: Vec<Point3> = gaps
        .iter()
        .enumerate()
        .map(|(i, &g)| {
            let tv = t.point(TAU * i as Real / m as Real);
            tv.normalized().map_or(Vec3::ZERO, |u| u * g)
        })
        .collect();
    fit_space(&scaled, order)
}

impl Transition {
    /// The Hermite transition from `p0` (tangent `m0 t0`) to `p1` (tangent
    /// `m1 t1`); `t0`, `t1` point the way `u` increases.
    pub fn hermite(
        p0: SpaceCurve,
        t0: SpaceCurve,
        p1: SpaceCurve,
        t1: SpaceCurve,
        spec: TransitionSpec,
    ) -> Result<Transition, TransitionError> {
        let [m0, m1] = spec.magnitudes;
        if !(m0.is_finite() && m0 > 0.0 && m1.is_finite() && m1 > 0.0) {
            return Err(TransitionError::BadMagnitudes(m0, m1));
        }
        let patch = Patch::hermite(&p0, &scale(&t0, m0), &p1, &scale(&t1, m1))?;
        Ok(Transition {
            spec,
            p0,
            t0,
            p1,
            t1,
            patch,
        })
    }

    /// The boundary curves and tangents of a transition from `from` to `to`
    /// (the magnitudes of `spec` are not used).
    pub fn boundaries(
        from: &Part,
        to: &Part,
        spec: &TransitionSpec,
    ) -> Result<[SpaceCurve; 4], TransitionError> {
        let (p0, t0) = part_end(from, spec.from_start, true);
        if let Some(side) = &spec.side {
            let (p1, t1) = side_cut_loop(to, side, spec.order, &p0)?;
            let gaps = relative_gaps(&p0, &p1);
            let t0 = scaled_by_gaps(&t0, &gaps, spec.order);
            let t1 = scaled_by_gaps(&t1, &gaps, spec.order);
            return Ok([p0, t0, p1, t1]);
        }
        // Into `to`: against its outward end tangent.
        let (c1, t1) = part_end(to, spec.to_start, false);
        let (p1, t1) = match &spec.seam {
            Some(seam) => seam_half_loop(&c1, &t1, seam, spec.order, &p0)?,
            None => {
                let phi = best_phase_shift(&p0, &c1);
                (c1.shifted(phi), t1.shifted(phi))
            }
        };
        Ok([p0, t0, p1, t1])
    }

    /// The transition from an end of `from` to an end of `to` (see
    /// [`TransitionSpec`]): what a model file rebuilds.
    pub fn between(
        from: &Part,
        to: &Part,
        spec: TransitionSpec,
    ) -> Result<Transition, TransitionError> {
        let [p0, t0, p1, t1] = Transition::boundaries(from, to, &spec)?;
        Transition::hermite(p0, t0, p1, t1, spec)
    }

    pub fn spec(&self) -> &TransitionSpec {
        &self.spec
    }
    /// The surface: `u = 0` on the `from` part, `u = 1` on the `to` part.
    pub fn patch(&self) -> &Patch {
        &self.patch
    }
    /// `(p₀, τ₀, p₁, τ₁)` (tangents before the magnitudes).
    pub fn curves(&self) -> [&SpaceCurve; 4] {
        [&self.p0, &self.t0, &self.p1, &self.t1]
    }
    /// Design parameters: the two magnitudes, plus 6 for a seam (point and
    /// normal; its `up` is the body's frame, not counted) or a side cut
    /// (point and normal).
    pub fn design_parameters(&self) -> usize {
        2 + if self.spec.seam.is_some() { 6 } else { 0 }
            + if self.spec.side.is_some() { 6 } else { 0 }
    }

    /// A grid mesh of the surface: `around` samples in `v`, `along`
    /// intervals in `u`, triangles oriented so that their normals point
    /// away from the centre line of the surface (outward for a tube).
    pub fn tessellate(&self, around: usize, along: usize) -> Mesh {
        let (around, along) = (around.max(3), along.max(1));
        let mut positions = Vec::with_capacity(around * (along + 1));
        let mut normals = Vec::with_capacity(around * (along + 1));
        let mut outward = 0.0;
        // Points and derivatives on the whole grid at once (the same
        // numbers as `point` and `normal` one by one).
        let us: Vec<Real> = (0..=along).map(|j| j as Real / along as Real).collect();
        let vs: Vec<Real> = (0..around)
            .map(|i| TAU * i as Real / around as Real)
            .collect();
        let grid = self.patch.grid(&us, &vs);
        for (j, &u) in us.iter().enumerate() {
            let c = self.patch.curve_at(u);
            let g = c.mean_point();
            for &[p, du, dv] in &grid[j * around..(j + 1) * around] {
                let n = dv.cross(du).normalized().unwrap_or(Vec3::ZERO);
                outward += (p - g).dot(n);
                positions.push(p);
                normals.push(n);
            }
        }
        let flip = outward < 0.0;
        if flip {
            for n in normals.iter_mut() {
                *n = -*n;
            }
        }
        let mut triangles = Vec::with_capacity(2 * around * along);
        for j in 0..along {
            for i in 0..around {
                let a = (j * around + i) as u32;
                let b = (j * around + (i + 1) % around) as u32;
                let c = a + around as u32;
                let d = b + around as u32;
                // dv × du outward: (a, b, d) runs along v then u.
                if flip {
                    triangles.push([a, d, b]);
                    triangles.push([a, c, d]);
                } else {
                    triangles.push([a, b, d]);
                    triangles.push([a, d, c]);
                }
            }
        }
        Mesh {
            positions,
            normals: Some(normals),
            triangles,
        }
    }

    /// Tessellated as the parts are with `options`: edges of about
    /// `target_edge` when it is set, else `around × along`.
    pub fn tessellate_with(
        &self,
        options: &crate::surface::tessellate::TessellationOptions,
    ) -> Mesh {
        match options.target_edge {
            Some(e) => self.tessellate_edge(e),
            None => self.tessellate(options.around, options.along),
        }
    }

    /// [`Transition::tessellate`] with grid edges of about `edge` (model
    /// units) along both directions.
    pub fn tessellate_edge(&self, edge: Real) -> Mesh {
        let samples = 64;
        let perimeter = |c: &SpaceCurve| {
            let p: Vec<Point3> = (0..=samples)
                .map(|i| c.point(TAU * i as Real / samples as Real))
                .collect();
            p.windows(2).map(|w| w[0].distance(w[1])).sum::<Real>()
        };
        let around_len = perimeter(&self.p0).max(perimeter(&self.p1));
        let us: Vec<Real> = (0..=samples).map(|k| k as Real / samples as Real).collect();
        let vs: Vec<Real> = (0..16).map(|i| TAU * i as Real / 16.0).collect();
        let grid = self.patch.grid(&us, &vs);
        let along_len = (0..16)
            .map(|i| {
                (0..samples)
                    .map(|k| grid[k * 16 + i][0].distance(grid[(k + 1) * 16 + i][0]))
                    .sum::<Real>()
            })
            .fold(0.0, Real::max);
        let steps = |l: Real| ((l / edge).ceil() as usize).clamp(1, 4096);
        self.tessellate(steps(around_len).max(8), steps(along_len))
    }
}

/// Chooses the magnitudes on [`MAGNITUDE_GRID`] × `d` (`d` the distance
/// between the boundary curves' centres) minimizing the mean squared
/// distance from 8 × 32 surface points strictly between the curves, over
/// the whole grid (coordinate descent stalls in the diagonal valleys where
/// one magnitude makes up for the other); the first candidate of least
/// score in the grid's order wins. `distances` maps a batch of points to
/// their distances from the input.
///
/// The search is exact but prunes: every candidate's middle row of points
/// is measured first (one batch), then the candidates are visited in
/// order of that row's sum, each adding its other rows (middle out) until
/// the partial sum exceeds the best full sum so far by more than a
/// rounding margin ([`ROUNDING_MARGIN`]; the rounding of 256 non-negative
/// terms is below `256 ε`), so it cannot win. A candidate measured in
/// full is scored by its sum in row order, as without pruning.
pub fn fit_magnitudes(
    curves: &[SpaceCurve; 4],
    distances: &dyn Fn(&[Point3]) -> Vec<Real>,
) -> Result<[Real; 2], TransitionError> {
    const ROWS: usize = 8;
    const AROUND: usize = 32;
    // Rows (j = 1..=8 at u = j / 9) middle out.
    const VISIT: [usize; ROWS] = [4, 5, 3, 6, 2, 7, 1, 8];
    let [p0, t0, p1, t1] = curves;
    let d = p0.mean_point().distance(p1.mean_point());
    if !(d > 0.0) {
        return Err(TransitionError::BadMagnitudes(d, d));
    }
    let grid: Vec<[Real; 2]> = MAGNITUDE_GRID
        .iter()
        .flat_map(|&a| MAGNITUDE_GRID.iter().map(move |&b| [a, b]))
        .collect();
    let patches = grid
        .iter()
        .map(|&[a, b]| Patch::hermite(p0, &scale(t0, a * d), p1, &scale(t1, b * d)))
        .collect::<Result<Vec<Patch>, PatchError>>()?;
    let row = |patch: &Patch, j: usize| -> Vec<Point3> {
        let c = patch.curve_at(j as Real / (ROWS + 1) as Real);
        (0..AROUND)
            .map(|i| c.point(TAU * i as Real / AROUND as Real))
            .collect()
    };
    // rows[k][j - 1]: candidate k's squared distances of row j, once
    // measured.
    let mut rows: Vec<Vec<Option<Vec<Real>>>> = vec![vec![None; ROWS]; grid.len()];
    let first: Vec<Point3> = patches.iter().flat_map(|p| row(p, VISIT[0])).collect();
    for (k, e) in distances(&first).chunks(AROUND).enumerate() {
        rows[k][VISIT[0] - 1] = Some(e.iter().map(|e| e.powi(2)).collect());
    }
    let row_sum = |r: &[Real]| r.iter().fold(0.0, |s: Real, e| s + e);
    let mut visit: Vec<(Real, usize)> = rows
        .iter()
        .enumerate()
        .map(|(k, r)| (r[VISIT[0] - 1].as_deref().map_or(0.0, row_sum), k))
        .collect();
    visit.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    // (full sum, candidate)
    let mut best: Option<(Real, usize)> = None;
    for &(partial0, k) in &visit {
        let mut partial = partial0;
        let mut pruned = false;
        for &j in &VISIT[1..] {
            if best.is_some_and(|(b, _)| partial > b * (1.0 + ROUNDING_MARGIN)) {
                pruned = true;
                break;
            }
            let e: Vec<Real> = distances(&row(&patches[k], j))
                .iter()
                .map(|e| e.powi(2))
                .collect();
            partial += row_sum(&e);
            rows[k][j - 1] = Some(e);
        }
        if pruned || best.is_some_and(|(b, _)| partial > b * (1.0 + ROUNDING_MARGIN)) {
            continue;
        }
        // All rows measured: the sum in row order.
        let mut sum = 0.0;
        for r in &rows[k] {
            for &e in r.as_deref().unwrap_or(&[]) {
                sum += e;
            }
        }
        if sum < Real::INFINITY && best.is_none_or(|(b, bk)| sum < b || (sum == b && k < bk)) {
            best = Some((sum, k));
        }
    }
    Ok(best.map_or([d, d], |(_, k)| [grid[k][0] * d, grid[k][1] * d]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_vec_near;
    use crate::curve::trig::{Frame, TrigCurve};
    use crate::surface::part::PartOptions;

    fn circle(z: Real, r: Real) -> TrigCurve {
        let frame = Frame {
            origin: Vec3::new(0.0, 0.0, z),
            e1: Vec3::X,
            e2: Vec3::Y,
        };
        TrigCurve::circle(frame, r, 3)
    }

    fn cylinder(z0: Real, z1: Real, r: Real) -> Part {
        let curves = (0..4)
            .map(|k| circle(z0 + (z1 - z0) * k as Real / 3.0, r))
            .collect();
        Part::new(curves, &PartOptions::default()).unwrap()
    }

    fn spec(m0: Real, m1: Real) -> TransitionSpec {
        TransitionSpec {
            from_start: false,
            to_start: true,
            magnitudes: [m0, m1],
            seam: None,
            side: None,
            order: 8,
        }
    }

    /// A transition between two coaxial circles of different radii, with
    /// the parts' own tangents: position and tangent direction match both
    /// parts at the joins to 1e-9.
    #[test]
    fn coaxial_circles_join_with_g1_continuity() {
        let a = cylinder(0.0, 0.3, 0.1);
        let b = {
            // A cone widening from 0.15 to 0.2 above the gap.
            let curves = (0..4)
                .map(|k| circle(0.5 + 0.1 * k as Real, 0.15 + 0.05 * k as Real / 3.0))
                .collect();
            Part::new(curves, &PartOptions::default()).unwrap()
        };
        let t = Transition::between(&a, &b, spec(0.17, 0.23)).unwrap();
        let p = t.patch();
        for i in 0..32 {
            let v = TAU * i as Real / 32.0;
            // Positions.
            let end_a = a.point(a.length(), v);
            let start_b = b.point(0.0, v);
            assert!(p.point(0.0, v).distance(end_a) < 1e-9);
            assert!(p.point(1.0, v).distance(start_b) < 1e-9);
            // Tangent directions along the parts' axes.
            let da = a.derivative(a.length(), v, 1, 0).normalized().unwrap();
            let db = b.derivative(0.0, v, 1, 0).normalized().unwrap();
            let d0 = p.du(0.0, v).normalized().unwrap();
            let d1 = p.du(1.0, v).normalized().unwrap();
            assert!(d0.distance(da) < 1e-9, "{d0:?} vs {da:?}");
            assert!(d1.distance(db) < 1e-9, "{d1:?} vs {db:?}");
            // Across v too (the surface's tangent plane): ∂/∂v agrees.
            assert!(p.dv(0.0, v).distance(a.derivative(a.length(), v, 0, 1)) < 1e-9);
            assert!(p.dv(1.0, v).distance(b.derivative(0.0, v, 0, 1)) < 1e-9);
        }
    }

    /// Two pieces of one cylinder with a gap: the transition with both
    /// magnitudes equal to the gap is the cylinder itself.
    #[test]
    fn cylinder_to_cylinder_reproduces_the_cylinder() {
        let (r, gap) = (0.1, 0.2);
        let a = cylinder(0.0, 0.3, r);
        let b = cylinder(0.3 + gap, 0.8, r);
        let t = Transition::between(&a, &b, spec(gap, gap)).unwrap();
        for j in 0..=10 {
            let u = j as Real / 10.0;
            for i in 0..24 {
                let v = TAU * i as Real / 24.0;
                let q = t.patch().point(u, v);
                assert!(((q.x * q.x + q.y * q.y).sqrt() - r).abs() < 1e-12);
                assert!((q.z - (0.3 + gap * u)).abs() < 1e-12);
            }
        }
        // The mesh: a grid, normals pointing away from the axis.
        let mesh = t.tessellate(16, 4);
        assert_eq!(mesh.triangles.len(), 2 * 16 * 4);
        let normals = mesh.normals.as_ref().unwrap();
        for (p, n) in mesh.positions.iter().zip(normals) {
            assert!(Vec3::new(p.x, p.y, 0.0).dot(*n) > 0.0);
        }
        for tri in &mesh.triangles {
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(Vec3::new(a.x, a.y, 0.0).dot(n) > 0.0);
        }
        assert!(Transition::between(&a, &b, spec(0.0, 1.0)).is_err());
    }

    /// The magnitude search recovers the magnitudes of a known transition
    /// (a bulge between two circles with flaring tangents) from distances
    /// to that surface alone.
    #[test]
    fn magnitudes_are_recovered_from_the_surface() {
        let p0 = circle(0.0, 0.1).world_series();
        let p1 = circle(1.0, 0.1).world_series();
        // Tangents flaring outward at the start and inward at the end.
        let flare = |radial: Real| {
            let mut t = scale(&p0, radial);
            t.x.c[0] = 0.0;
            t.y.c[0] = 0.0;
            t.z.c = vec![1.0, 0.0, 0.0];
            t
        };
        let (t0, t1) = (flare(1.0), flare(-1.0));
        let truth = Transition::hermite(
            p0.clone(),
            t0.clone(),
            p1.clone(),
            t1.clone(),
            spec(0.5, 1.5),
        )
        .unwrap();
        // Radius of the true surface at height z (z(u) is monotone here).
        let radius_at = |z: Real| {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if truth.patch().point(mid, 0.0).z < z {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let q = truth.patch().point(0.5 * (lo + hi), 0.0);
            (q.x * q.x + q.y * q.y).sqrt()
        };
        let dist = |p: Point3| ((p.x * p.x + p.y * p.y).sqrt() - radius_at(p.z)).abs();
        let batch = |pts: &[Point3]| pts.iter().map(|&p| dist(p)).collect();
        let m = fit_magnitudes(&[p0, t0, p1, t1], &batch).unwrap();
        assert!(
            (m[0] - 0.5).abs() < 1e-12 && (m[1] - 1.5).abs() < 1e-12,
            "{m:?}"
        );
    }

    /// The pruned search picks exactly the candidate a plain scan of the
    /// whole grid in order picks (first least mean square), for targets
    /// with their best anywhere on the grid, ties and flat distances.
    #[test]
    fn pruned_magnitude_search_matches_the_full_scan() {
        let p0 = circle(0.0, 0.1).world_series();
        let p1 = circle(1.0, 0.15).world_series();
        let flare = |radial: Real| {
            let mut t = scale(&p0, radial);
            t.x.c[0] = 0.0;
            t.y.c[0] = 0.0;
            t.z.c = vec![1.0, 0.0, 0.0];
            t
        };
        let curves = [p0.clone(), flare(0.7), p1.clone(), flare(-0.4)];
        let full = |dist: &dyn Fn(Point3) -> Real| {
            let [p0, t0, p1, t1] = &curves;
            let d = p0.mean_point().distance(p1.mean_point());
            let mut best = (Real::INFINITY, [d, d]);
            for a in MAGNITUDE_GRID {
                for b in MAGNITUDE_GRID {
                    let patch =
                        Patch::hermite(p0, &scale(t0, a * d), p1, &scale(t1, b * d)).unwrap();
                    let mut sum = 0.0;
                    for j in 1..=8 {
                        let c = patch.curve_at(j as Real / 9.0);
                        for i in 0..32 {
                            sum += dist(c.point(TAU * i as Real / 32.0)).powi(2);
                        }
                    }
                    let score = sum / 256.0;
                    if score < best.0 {
                        best = (score, [a * d, b * d]);
                    }
                }
            }
            best.1
        };
        let targets: Vec<Box<dyn Fn(Point3) -> Real>> = vec![
            // Cylinders of several radii, a cone, a wavy tube, a plane,
            // a constant (every candidate ties: the first wins).
            Box::new(|p: Point3| ((p.x * p.x + p.y * p.y).sqrt() - 0.12).abs()),
            Box::new(|p: Point3| ((p.x * p.x + p.y * p.y).sqrt() - 0.3).abs()),
            Box::new(|p: Point3| ((p.x * p.x + p.y * p.y).sqrt() - 0.05 - 0.2 * p.z).abs()),
            Box::new(|p: Point3| {
                ((p.x * p.x + p.y * p.y).sqrt() - 0.1 - 0.05 * (9.0 * p.z).sin()).abs()
            }),
            Box::new(|p: Point3| (p.x - 0.02).abs()),
            Box::new(|_| 0.25),
        ];
        for (n, dist) in targets.iter().enumerate() {
            let batch = |pts: &[Point3]| pts.iter().map(|&p| dist(p)).collect();
            let m = fit_magnitudes(&curves, &batch).unwrap();
            assert_eq!(m, full(dist.as_ref()), "target {n}");
        }
    }

    /// A seam splits a wide ellipse into halves that meet on the seam,
    /// each running the reference's way round.
    #[test]
    fn seam_halves_share_the_seam() {
        let frame = Frame {
            origin: Vec3::new(0.0, 0.0, 1.0),
            e1: Vec3::X,
            e2: Vec3::Y,
        };
        let mut wide = TrigCurve::circle(frame, 0.1, 2);
        wide.a[1] = 0.2; // x semi-axis 0.2, y 0.1
        let c = wide.world_series();
        let tangent = SpaceCurve {
            x: Series::constant(0.0),
            y: Series::constant(0.0),
            z: Series::constant(1.0),
        };
        let leg = |x: Real| {
            let f = Frame {
                origin: Vec3::new(x, 0.0, 0.9),
                e1: Vec3::X,
                e2: Vec3::Y,
            };
            TrigCurve::circle(f, 0.08, 3).world_series()
        };
        let seam = |s: Real| Seam {
            point: Vec3::new(0.0, 0.0, 0.95),
            normal: Vec3::X * s,
            up: Vec3::Z,
        };
        let (l, _) = seam_half_loop(&c, &tangent, &seam(1.0), 12, &leg(0.1)).unwrap();
        let (r, _) = seam_half_loop(&c, &tangent, &seam(-1.0), 12, &leg(-0.1)).unwrap();
        // Each half lies on its side (up to the Fourier fit's ripple).
        for i in 0..64 {
            let v = TAU * i as Real / 64.0;
            assert!(l.point(v).x > -0.01 && r.point(v).x < 0.01);
            // The seam dips to z = 0.95 at most.
            assert!(l.point(v).z > 0.94 && l.point(v).z < 1.01);
        }
        // Crossing twice is required.
        let away = Seam {
            point: Vec3::new(1.0, 0.0, 0.95),
            ..seam(1.0)
        };
        assert!(seam_half_loop(&c, &tangent, &away, 12, &leg(0.1)).is_err());
    }

    /// A cylinder (radius 0.5 along z) cut across its axis at z = 1.3: the
    /// side curve is the circle there, running the way the reference runs
    /// about the plane's normal, and the tangent across it is the axis
    /// direction into the part (against the normal). A plane past the
    /// part, or a point outside the curve, finds no side curve.
    #[test]
    fn a_side_cut_across_a_cylinder_is_its_circle() {
        let part = cylinder(0.0, 3.0, 0.5);
        let reference = circle(5.0, 0.4).world_series();
        let z = Vec3::new(0.0, 0.0, 1.0);
        let cut = SideCut {
            point: Point3::new(0.1, -0.05, 1.3),
            normal: z,
        };
        let (p, t) = side_cut_loop(&part, &cut, 8, &reference).unwrap();
        let turn = |c: &SpaceCurve| {
            (0..64)
                .map(|i| {
                    let v = TAU * i as Real / 64.0;
                    (c.point(v) - c.mean_point())
                        .cross(c.derivative(v, 1))
                        .dot(z)
                })
                .sum::<Real>()
        };
        assert!(turn(&p) > 0.0 && turn(&reference) > 0.0);
        for i in 0..64 {
            let v = TAU * i as Real / 64.0;
            let q = p.point(v);
            assert!((q.z - 1.3).abs() < 1e-9, "{q:?}");
            // The contour's polygon has 128 corners on the circle: its
            // chords sag by r (1 − cos(π/128)) = 1.5e-4.
            let r = (q.x * q.x + q.y * q.y).sqrt();
            assert!((r - 0.5).abs() < 2e-4, "{r}");
            assert!((t.point(v) + z).norm() < 1e-9, "{:?}", t.point(v));
        }
        for miss in [
            SideCut {
                point: Point3::new(0.0, 0.0, 4.0),
                normal: z,
            },
            SideCut {
                point: Point3::new(2.0, 0.0, 1.3),
                normal: z,
            },
        ] {
            assert_eq!(
                side_cut_loop(&part, &miss, 8, &reference).unwrap_err(),
                TransitionError::SideCutMisses
            );
        }
        let flat = SideCut {
            point: cut.point,
            normal: Vec3::ZERO,
        };
        assert_eq!(
            side_cut_loop(&part, &flat, 8, &reference).unwrap_err(),
            TransitionError::BadSideCut
        );
    }

    /// Two unit circles 2 apart: the gap equals the centres' distance
    /// everywhere, so a constant tangent comes out as its unit vector.
    #[test]
    fn gap_scaled_tangents_follow_the_local_gap() {
        let p0 = circle(0.0, 1.0).world_series();
        let p1 = circle(2.0, 1.0).world_series();
        let t = SpaceCurve {
            x: Series { c: vec![0.0] },
            y: Series { c: vec![0.0] },
            z: Series { c: vec![3.0] },
        };
        let g = gap_scaled(&t, &p0, &p1, 4);
        for i in 0..16 {
            let v = TAU * i as Real / 16.0;
            assert_vec_near!(g.point(v), Vec3::new(0.0, 0.0, 1.0), 1e-12);
        }
        // A circle of radius 2 at the far end: the gap grows where the
        // curves part (√(4 + 1) at v where both radii point the same way).
        let wide = circle(2.0, 2.0).world_series();
        let g = gap_scaled(&t, &p0, &wide, 8);
        let gap = p0.point(0.0).distance(wide.point(0.0));
        assert!(
            (g.point(0.0).z - gap / 2.0).abs() < 1e-9,
            "{:?}",
            g.point(0.0)
        );
    }
}
