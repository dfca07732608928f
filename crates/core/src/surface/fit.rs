//! A part fitted to points by least squares (docs/global-fit.md).
//!
//! A Catmull-Rom part's surface is a fixed linear combination of its
//! section curves, `S(s, v) = Σ_m W_m(s) P_m(v)`, the weights `W_m` set by
//! the knots alone. With the knots, the sections' planes and each point's
//! foot `(s, v)` held, `S` is linear in the curves' coefficients, and so is
//! a point's residual along the surface normal. One round projects every
//! point on the part ([`PartGrid`], [`project`]), weighs its residual
//! (Huber, nothing past a cutoff), and solves one least squares for every
//! coefficient at once, with a smoothness term (second differences of the
//! sections' world coefficients along the part, so a hole is bridged by
//! its neighbours) and a small pull toward the current curves. The normal
//! matrix is block-banded (a point touches the four sections around its
//! foot): a band Cholesky solves it with no fill outside the band.

use super::part::{Part, PartError, Skinning};
use crate::curve::trig::TrigCurve;
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{Aabb, Mesh};
use crate::spatial::distance::MeshDistance;
use crate::spatial::point_grid::PointGrid;
use band::Band;
use moments::Moments;
use split::split_where_far;

mod band;
mod moments;
mod split;

/// Options of [`fit_part`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceFitOptions {
    /// Rounds of projection and solve. Default 3.
    pub rounds: usize,
    /// Weight of the second differences of the sections' coefficients
    /// along the part, relative to the data's weight per section. Default
    /// 0.05.
    pub smoothness: Real,
    /// Damping of each round: every coefficient is pulled toward its
    /// current value with this share of the weight the data and the
    /// smoothness give it. Default 0.1.
    pub pull: Real,
    /// The highest harmonic fitted; a curve's higher ones are kept as
    /// built. Default 12.
    pub max_order: usize,
    /// Weight of the pull toward the curves the fit started from (the
    /// squared distance between the curves), relative to the data's
    /// weight per section. Default 0.01.
    pub anchor: Real,
    /// Huber threshold, in robust standard deviations of the residuals.
    /// Default 1.345.
    pub huber: Real,
    /// Residuals past this many robust standard deviations weigh nothing.
    /// Default 4.
    pub cutoff: Real,
    /// The least cutoff, in the points' units: a point this near the
    /// surface always takes part. Default 0 (the caller sets a scale).
    pub min_cutoff: Real,
    /// Weight of the surface's own samples held to their nearest input
    /// points ([`Coverage`]), all of them together relative to all the
    /// points: 1 weighs the two halves of the distance alike. Default 1.
    pub coverage: Real,
    /// A surface sample farther than this from every point is not held
    /// (it bridges a hole), in the points' units. Default 0: none is
    /// held (the caller sets a scale).
    pub coverage_reach: Real,
    /// After the fit, a section is added halfway along every interval
    /// whose points still lie farther than this from the surface (their
    /// 90th percentile), and the part is fitted again: where the sections
    /// leave the fit too little to move (a gap where a section was
    /// dropped, a shoulder's quick change). In the points' units; 0 (the
    /// default) adds none.
    pub split: Real,
    /// No section is added between two closer than twice this (their
    /// centres' distance), in the points' units. Default 0.
    pub min_gap: Real,
}

impl Default for SurfaceFitOptions {
    fn default() -> Self {
        SurfaceFitOptions {
            rounds: 3,
            smoothness: 0.01,
            pull: 0.1,
            anchor: 0.01,
            max_order: 12,
            huber: 1.345,
            cutoff: 4.0,
            min_cutoff: 0.0,
            coverage: 1.0,
            coverage_reach: 0.0,
            split: 0.0,
            min_gap: 0.0,
        }
    }
}

/// What a fit did: the robust residuals before and after, and how far the
/// surface moved.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceFitStats {
    /// Points given, and those inside the cutoff in the last round.
    pub points: usize,
    pub used: usize,
    /// RMS of the residuals inside the first round's cutoff, before and
    /// after the fit (the same points).
    pub rms_before: Real,
    pub rms_after: Real,
    /// RMS and largest distance from the fitted surface to the first.
    pub moved_rms: Real,
    pub moved_max: Real,
    /// Rounds solved.
    pub rounds: usize,
    /// Sections added where the points still lay far
    /// ([`SurfaceFitOptions::split`]).
    pub added: usize,
}

/// A part's surface sampled on a grid of `(s, v)`, to find a point's foot.
#[derive(Clone, Debug)]
pub struct PartGrid {
    mesh: Mesh,
    params: Vec<[Real; 2]>,
}

impl PartGrid {
    /// The part sampled `per_segment` times along each segment and
    /// `around` times around.
    pub fn new(part: &Part, around: usize, per_segment: usize) -> PartGrid {
        let (around, per_segment) = (around.max(3), per_segment.max(1));
        let mut s_values: Vec<Real> = part
            .segments()
            .iter()
            .flat_map(|seg| {
                (0..per_segment)
                    .map(move |i| seg.s0 + seg.length() * i as Real / per_segment as Real)
            })
            .collect();
        s_values.push(part.length());
        let columns = around + 1;
        let mut positions = Vec::with_capacity(s_values.len() * columns);
        let mut params = Vec::with_capacity(positions.capacity());
        // Each section's curve at the columns' angles, once; a grid point
        // is their sum weighted by the sections' weights at its row.
        let weights = SectionWeights::of(part);
        let rings: Vec<Vec<Point3>> = match weights {
            Some(_) => part.curves().iter().map(|c| c.sample(around)).collect(),
            None => Vec::new(),
        };
        for &s in &s_values {
            let at = weights.as_ref().map(|w| w.at_with_derivative(s));
            for j in 0..columns {
                let v = std::f64::consts::TAU * j as Real / around as Real;
                positions.push(match at {
                    Some((w, count)) => w[..count]
                        .iter()
                        .fold(Vec3::ZERO, |acc, &(m, w, _)| acc + rings[m][j % around] * w),
                    None => part.point(s, v),
                });
                params.push([s, v]);
            }
        }
        let mut triangles = Vec::with_capacity(2 * (s_values.len() - 1) * around);
        for i in 0..s_values.len() - 1 {
            for j in 0..around {
                let a = (i * columns + j) as u32;
                let (b, c, d) = (a + 1, a + columns as u32 + 1, a + columns as u32);
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        PartGrid {
            mesh: Mesh {
                positions,
                normals: None,
                triangles,
            },
            params,
        }
    }

    /// The grid [`project`] starts from: 3 rows a segment, around it 8
    /// per harmonic of the highest order (at most 16) and 32 more.
    pub fn for_part(part: &Part) -> PartGrid {
        let around = highest_order(part).min(16) * 8 + 32;
        PartGrid::new(part, around, 3)
    }

    /// The grid's mesh (for a distance tree: `MeshDistance::new`).
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The box around the grid.
    pub fn bounds(&self) -> Option<Aabb> {
        self.mesh.bounds()
    }
}

/// The highest order among a part's curves.
fn highest_order(part: &Part) -> usize {
    part.curves()
        .iter()
        .map(TrigCurve::order)
        .max()
        .unwrap_or(1)
}

/// A point's nearest point on a part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Foot {
    pub s: Real,
    pub v: Real,
    pub point: Point3,
    /// The outward unit normal there (away from the part's centre line).
    pub normal: Vec3,
    /// The point's distance along `normal` (negative inside).
    pub signed: Real,
    /// The foot sits on an end of the part (the point lies past it).
    pub at_end: bool,
}

/// The foot of `p` on a part's `surface`: the nearest grid triangle
/// (`tree` over `grid`'s mesh), then Gauss-Newton steps on
/// `|S(s, v) - p|²`. `None` where the surface is degenerate there.
pub fn project(
    surface: &Surface<'_>,
    grid: &PartGrid,
    tree: &MeshDistance<'_>,
    p: Point3,
) -> Option<Foot> {
    let closest = tree.closest(p)?;
    let [ia, ib, ic] = grid.mesh.triangles[closest.triangle].map(|i| i as usize);
    let [a, b, c] = [ia, ib, ic].map(|i| grid.mesh.positions[i]);
    let [wa, wb, wc] = barycentric(closest.point, a, b, c);
    let param =
        |k: usize| wa * grid.params[ia][k] + wb * grid.params[ib][k] + wc * grid.params[ic][k];
    let (mut s, mut v) = (param(0), param(1));
    let length = surface.length();
    let mut e = surface.eval(s, v);
    for _ in 0..3 {
        let [point, ss, sv] = e;
        let d = p - point;
        let (m11, m12, m22) = (ss.dot(ss), ss.dot(sv), sv.dot(sv));
        let det = m11 * m22 - m12 * m12;
        if !(det > 1e-300) {
            break;
        }
        let (r1, r2) = (ss.dot(d), sv.dot(d));
        let (ds, dv) = ((m22 * r1 - m12 * r2) / det, (m11 * r2 - m12 * r1) / det);
        let next = s + ds;
        // Past an end: onto the end's rim, the step around it alone.
        let (ns, nv) = if next > 0.0 && next < length {
            (next, v + dv)
        } else {
            (next.clamp(0.0, length), v + r2 / m22)
        };
        let ne = surface.eval(ns, nv);
        // A step that leads away (past a fold of a strongly curved end,
        // where the linearisation is poor) is not taken.
        if (p - ne[0]).norm_squared() > d.norm_squared() {
            break;
        }
        (s, v, e) = (ns, nv, ne);
        // Converged: the step moved the foot by under 1e-6 of the part's
        // length (the next would move it by far less).
        if ds * ds * m11 + dv * dv * m22 <= (1e-6 * length).powi(2) {
            break;
        }
    }
    foot_at(surface, (s, v), e, p)
}

/// `p`'s foot taken at `(s, v)`, where the surface evaluates to `e`
/// (`[S, ∂S/∂s, ∂S/∂v]`): the outward normal there and `p`'s distance
/// along it. `None` where the surface is degenerate.
fn foot_at(surface: &Surface<'_>, (s, v): (Real, Real), e: [Vec3; 3], p: Point3) -> Option<Foot> {
    let [point, ss, sv] = e;
    // On an end, with the point beyond it along the part.
    let along = ss.dot(p - point);
    let length = surface.length();
    let rim = 1e-9 * length;
    let at_end = (s <= rim && along < 0.0) || (s >= length - rim && along > 0.0);
    let mut normal = ss.cross(sv).normalized()?;
    if normal.dot(point - surface.centre(s)) < 0.0 {
        normal = -normal;
    }
    Some(Foot {
        s,
        v: v.rem_euclid(std::f64::consts::TAU),
        point,
        normal,
        signed: (p - point).dot(normal),
        at_end,
    })
}

/// The input a part's surface is held to where it has no points of its
/// own (the model → input half of the distance: a mitten's skin across
/// the gaps between the fingers, a fold beside a junction): the input's
/// points and which of them may hold this part.
pub(crate) struct Coverage<'a> {
    pub grid: &'a PointGrid<'a>,
    /// Whether the input point of this index may hold the part (one
    /// labelled to another part does not: the torso's skin inside an arm).
    pub allows: &'a (dyn Fn(usize) -> bool + Sync),
    /// Surface farther than this from every input point bridges a hole
    /// and is left to the smoothness.
    pub reach: Real,
}

/// The part's surface samples (a grid of its parameters: 2 rows a
/// segment, 4 columns a harmonic up to 16 and 16 more) each with the
/// nearest input point that may hold it, as feet of those points taken at
/// the samples; and the number of samples.
fn coverage_feet(part: &Part, cover: &Coverage<'_>, gate: Real) -> (Vec<Foot>, usize) {
    let Some(surface) = Surface::of(part) else {
        return (Vec::new(), 0);
    };
    let grid = PartGrid::new(part, highest_order(part).min(16) * 4 + 16, 2);
    let nearest = cover.grid.nearest_indices(&grid.mesh.positions);
    let feet = grid
        .params
        .iter()
        .zip(nearest)
        .filter_map(|(&[s, v], (d, i))| {
            let near = d > gate && d <= cover.reach;
            let i = i.filter(|&i| near && (cover.allows)(cover.grid.input_index(i)))?;
            foot_at(&surface, (s, v), surface.eval(s, v), cover.grid.point(i))
        })
        .filter(|f| !f.at_end)
        .collect();
    (feet, grid.params.len())
}

/// A Catmull-Rom part's surface through its sections' weights: a point
/// and its derivatives with one sine and cosine (the harmonics by
/// recurrence), the same surface as [`Part::point`] to rounding.
#[derive(Clone, Debug)]
pub struct Surface<'a> {
    part: &'a Part,
    weights: SectionWeights,
    centres: Vec<Point3>,
    order: usize,
}

impl<'a> Surface<'a> {
    /// `None` unless the part is skinned by Catmull-Rom.
    pub fn of(part: &'a Part) -> Option<Surface<'a>> {
        let weights = SectionWeights::of(part)?;
        let centres = part
            .curves()
            .iter()
            .map(|c| {
                c.frame
                    .to_world(crate::geom::math::Vec2::new(c.a[0], c.b[0]))
            })
            .collect();
        let order = highest_order(part);
        Some(Surface {
            part,
            weights,
            centres,
            order,
        })
    }

    /// The part's length (its last knot).
    pub fn length(&self) -> Real {
        self.part.length()
    }

    /// The centre line at `s` (the sections' centres, weighted).
    pub fn centre(&self, s: Real) -> Point3 {
        let (w, count) = self.weights.at_with_derivative(s);
        w[..count]
            .iter()
            .fold(Vec3::ZERO, |acc, &(m, w, _)| acc + self.centres[m] * w)
    }

    /// `[S, ∂S/∂s, ∂S/∂v]` at `(s, v)`.
    pub fn eval(&self, s: Real, v: Real) -> [Vec3; 3] {
        let mut cs = [(1.0, 0.0); 64];
        let mut trig: Vec<(Real, Real)>;
        let table: &mut [(Real, Real)] = if self.order < 64 {
            &mut cs[..=self.order]
        } else {
            trig = vec![(1.0, 0.0); self.order + 1];
            &mut trig
        };
        let (s1, c1) = v.sin_cos();
        for j in 1..table.len() {
            let (c, s) = table[j - 1];
            table[j] = (c * c1 - s * s1, s * c1 + c * s1);
        }
        let (w, count) = self.weights.at_with_derivative(s);
        let mut out = [Vec3::ZERO; 3];
        for &(m, w, dw) in &w[..count] {
            let c = &self.part.curves()[m];
            let (mut x, mut y, mut dx, mut dy) = (c.a[0], c.b[0], 0.0, 0.0);
            for j in 1..=c.order() {
                let (cj, sj) = table[j];
                let (a1, a2, b1, b2) = (c.a[2 * j - 1], c.a[2 * j], c.b[2 * j - 1], c.b[2 * j]);
                let jf = j as Real;
                x += a1 * cj + a2 * sj;
                y += b1 * sj + b2 * cj;
                dx += jf * (a2 * cj - a1 * sj);
                dy += jf * (b1 * cj - b2 * sj);
            }
            let f = &c.frame;
            let point = f.origin + f.e1 * x + f.e2 * y;
            out[0] += point * w;
            out[1] += point * dw;
            out[2] += (f.e1 * dx + f.e2 * dy) * w;
        }
        out
    }
}

/// Barycentric coordinates of `p` (in the triangle's plane) in `abc`;
/// a degenerate triangle gives its first vertex.
fn barycentric(p: Point3, a: Point3, b: Point3, c: Point3) -> [Real; 3] {
    let (e0, e1, d) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
    let (d20, d21) = (d.dot(e0), d.dot(e1));
    let den = d00 * d11 - d01 * d01;
    if !(den > 0.0) {
        return [1.0, 0.0, 0.0];
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    [1.0 - v - w, v, w]
}

/// The part's surface as weights of its sections: each knot's tangent as
/// a combination of the sections (as `part::catmull_rom` builds it, the
/// fold rule decided on the centres), then a point's weights from the
/// Hermite basis of its segment.
#[derive(Clone, Debug)]
pub struct SectionWeights {
    knots: Vec<Real>,
    tangents: Vec<Vec<(usize, Real)>>,
}

impl SectionWeights {
    /// `None` unless the part is skinned by Catmull-Rom.
    pub fn of(part: &Part) -> Option<SectionWeights> {
        if part.options().skinning != Skinning::CatmullRom {
            return None;
        }
        let knots = part.knots().to_vec();
        let curves = part.curves();
        let n = curves.len();
        let h: Vec<Real> = knots.windows(2).map(|w| w[1] - w[0]).collect();
        let centres: Vec<Point3> = curves
            .iter()
            .map(|c| c.world_series().mean_point())
            .collect();
        // The chord k as weights, and its centres' motion.
        let chord = |k: usize| vec![(k + 1, 1.0 / h[k]), (k, -1.0 / h[k])];
        let motion = |k: usize| (centres[k + 1] - centres[k]) / h[k];
        let end = |k0: usize, k1: usize, q: Real, normal: Vec3| {
            // (1 + q) d_k0 - q d_k1 unless its centre motion folds back
            // against the chord's across the end plane.
            let t = motion(k0) * (1.0 + q) - motion(k1) * q;
            if t.dot(normal) * motion(k0).dot(normal) < 0.0 {
                chord(k0)
            } else {
                let mut w: Vec<(usize, Real)> = chord(k0)
                    .into_iter()
                    .map(|(m, c)| (m, c * (1.0 + q)))
                    .collect();
                w.extend(chord(k1).into_iter().map(|(m, c)| (m, -c * q)));
                w
            }
        };
        let tangents = (0..n)
            .map(|k| {
                if n == 2 {
                    chord(0)
                } else if k == 0 {
                    end(0, 1, h[0] / (h[0] + h[1]), curves[0].frame.normal())
                } else if k == n - 1 {
                    let q = h[n - 2] / (h[n - 3] + h[n - 2]);
                    end(n - 2, n - 3, q, curves[n - 1].frame.normal())
                } else {
                    let w = h[k - 1] + h[k];
                    let mut t: Vec<(usize, Real)> = chord(k - 1)
                        .into_iter()
                        .map(|(m, c)| (m, c * h[k] / w))
                        .collect();
                    t.extend(chord(k).into_iter().map(|(m, c)| (m, c * h[k - 1] / w)));
                    t
                }
            })
            .collect();
        Some(SectionWeights { knots, tangents })
    }

    /// The weights `W_m(s)` of the sections at `s` and their derivatives
    /// along `s`, as `(m, W_m, W_m')`, merged per section, in section
    /// order (at most four), and their count.
    pub fn at_with_derivative(&self, s: Real) -> ([(usize, Real, Real); 4], usize) {
        let segments = self.knots.len() - 1;
        let i = self.knots[1..]
            .partition_point(|&k| k < s)
            .min(segments - 1);
        let h = self.knots[i + 1] - self.knots[i];
        let t = (s - self.knots[i]) / h;
        let (t2, t3) = (t * t, t * t * t);
        let (h10, h11) = (t3 - 2.0 * t2 + t, t3 - t2);
        let (d10, d11) = ((3.0 * t2 - 4.0 * t + 1.0) / h, (3.0 * t2 - 2.0 * t) / h);
        let mut out = [(usize::MAX, 0.0, 0.0); 4];
        let mut count = 0;
        let mut add = |m: usize, w: Real, dw: Real| match out[..count].iter_mut().find(|e| e.0 == m)
        {
            Some(e) => {
                e.1 += w;
                e.2 += dw;
            }
            None if count < 4 => {
                out[count] = (m, w, dw);
                count += 1;
            }
            None => debug_assert!(false, "more than four sections at s = {s}"),
        };
        add(i, 2.0 * t3 - 3.0 * t2 + 1.0, (6.0 * t2 - 6.0 * t) / h);
        add(i + 1, -2.0 * t3 + 3.0 * t2, (-6.0 * t2 + 6.0 * t) / h);
        for &(m, c) in &self.tangents[i] {
            add(m, h10 * h * c, d10 * h * c);
        }
        for &(m, c) in &self.tangents[i + 1] {
            add(m, h11 * h * c, d11 * h * c);
        }
        out[..count].sort_by_key(|e| e.0);
        (out, count)
    }

    /// The weights `W_m(s)` of the sections at `s` (as `Part::locate`
    /// picks the segment), merged per section, in section order.
    pub fn at(&self, s: Real) -> Vec<(usize, Real)> {
        let (w, count) = self.at_with_derivative(s);
        w[..count].iter().map(|&(m, w, _)| (m, w)).collect()
    }
}

/// The unknowns: each curve's first `len[m]` coefficients of `a`, then
/// as many of `b`, curve after curve (harmonics up to the fit's order; a
/// curve's higher ones are kept as they are).
struct Layout {
    off: Vec<usize>,
    len: Vec<usize>,
}

impl Layout {
    fn new(curves: &[TrigCurve], max_order: usize) -> Layout {
        let len: Vec<usize> = curves
            .iter()
            .map(|c| 2 * c.order().min(max_order) + 1)
            .collect();
        let mut off = vec![0];
        for l in &len {
            off.push(off.last().copied().unwrap_or(0) + 2 * l);
        }
        Layout { off, len }
    }

    fn unknowns(&self) -> usize {
        self.off[self.off.len() - 1]
    }

    /// The index of `a[i]` (`b = false`) or `b[i]` of curve `m`.
    #[inline]
    fn at(&self, m: usize, b: bool, i: usize) -> usize {
        self.off[m] + if b { self.len[m] } else { 0 } + i
    }
}

/// A point's terms per section around its foot (the sections weighing
/// `weights` there): `(m, n·e1 W_m, n·e2 W_m)` for its normal `n`.
fn normal_terms(
    curves: &[TrigCurve],
    weights: &[(usize, Real, Real)],
    normal: Vec3,
    terms: &mut Vec<(usize, Real, Real)>,
) {
    terms.clear();
    terms.extend(weights.iter().map(|&(m, w, _)| {
        let f = &curves[m].frame;
        (m, normal.dot(f.e1) * w, normal.dot(f.e2) * w)
    }));
}

/// The row over the unknowns of a point's residual along its normal: its
/// `terms` over the bases at its angle (`basis(i, false)` the `a`
/// coefficients' `1, cos v, sin v, …`, `basis(i, true)` the `b`
/// coefficients' `1, sin v, cos v, …`).
fn data_row(
    layout: &Layout,
    terms: &[(usize, Real, Real)],
    basis: impl Fn(usize, bool) -> Real,
    row: &mut Vec<(usize, Real)>,
) {
    row.clear();
    for &(m, n1, n2) in terms {
        let len = layout.len[m];
        row.extend((0..len).map(|i| (layout.at(m, false, i), basis(i, false) * n1)));
        row.extend((0..len).map(|i| (layout.at(m, true, i), basis(i, true) * n2)));
    }
}

/// The second difference of the world coefficients at section `m`
/// (sections `m - 1`, `m`, `m + 1`, weighted for the knots' spacing), one
/// row per fitted harmonic coefficient and world axis: the row and its
/// current value. The shape, not the fit's motion, is kept smooth: the
/// slab sections' noise goes with it (smoothing the motion instead left
/// the corpus scans at 2.98-3.12 mm against 2.52).
fn smoothness_rows(
    curves: &[TrigCurve],
    layout: &Layout,
    knots: &[Real],
    m: usize,
    mut emit: impl FnMut(&[(usize, Real)], Real),
) {
    let (h0, h1) = (knots[m] - knots[m - 1], knots[m + 1] - knots[m]);
    let c = [2.0 * h1 / (h0 + h1), -2.0, 2.0 * h0 / (h0 + h1)];
    let order = (m - 1..=m + 1)
        .map(|k| (layout.len[k] - 1) / 2)
        .max()
        .unwrap_or(0);
    let mut row = Vec::with_capacity(12);
    for j in 0..=order {
        // (a index, b index) of the harmonic's world vector, constant first.
        let pairs: &[(usize, usize)] = if j == 0 {
            &[(0, 0)]
        } else {
            &[(2 * j - 1, 2 * j), (2 * j, 2 * j - 1)]
        };
        for &(ia, ib) in pairs {
            for axis in 0..3 {
                row.clear();
                let mut value = 0.0;
                for (q, &cq) in c.iter().enumerate() {
                    let k = m - 1 + q;
                    let curve = &curves[k];
                    if ia >= layout.len[k] {
                        continue;
                    }
                    let (e1, e2) = (
                        curve.frame.e1.to_array()[axis],
                        curve.frame.e2.to_array()[axis],
                    );
                    row.push((layout.at(k, false, ia), cq * e1));
                    row.push((layout.at(k, true, ib), cq * e2));
                    value += cq * (curve.a[ia] * e1 + curve.b[ib] * e2);
                    if j == 0 {
                        value += cq * curve.frame.origin.to_array()[axis];
                    }
                }
                row.sort_by_key(|&(i, _)| i);
                emit(&row, value);
            }
        }
    }
}

/// The robust scale of residuals: 1.4826 × their median absolute value.
fn robust_scale(residuals: impl Iterator<Item = Real>) -> Real {
    let mut r: Vec<Real> = residuals.map(Real::abs).collect();
    if r.is_empty() {
        return 0.0;
    }
    let mid = r.len() / 2;
    r.select_nth_unstable_by(mid, Real::total_cmp);
    1.4826 * r[mid]
}

/// Projects every point on `part` (none where it is not Catmull-Rom).
fn feet(part: &Part, points: &[Point3]) -> Vec<Option<Foot>> {
    let Some(surface) = Surface::of(part) else {
        return vec![None; points.len()];
    };
    let grid = PartGrid::for_part(part);
    let tree = MeshDistance::new(grid.mesh());
    points
        .iter()
        .map(|&p| project(&surface, &grid, &tree, p))
        .collect()
}

/// A round is undone when it leaves the points' RMS residual farther
/// than this share.
const WORSE: Real = 1e-3;

/// `part` fitted to `points` (each with a weight), the part's planes,
/// orders and caps kept. Points whose foot falls on an end weigh nothing.
/// A round that would leave the part invalid or farther from the points
/// (over the points inside the first round's cutoff) is not taken, and the
/// fit stops there.
pub fn fit_part(
    part: &Part,
    points: &[Point3],
    weights: &[Real],
    opts: &SurfaceFitOptions,
) -> (Part, SurfaceFitStats) {
    let grid = PointGrid::new(points, opts.coverage_reach.max(Real::MIN_POSITIVE));
    let allows = |i: usize| weights.get(i).is_some_and(|&w| w > 0.0);
    let cover = Coverage {
        grid: &grid,
        allows: &allows,
        reach: opts.coverage_reach,
    };
    fit_part_from(part, points, feet(part, points), weights, &cover, opts)
}

/// [`fit_part`] with the points' feet on `part` already found (as
/// [`project`] on [`PartGrid::for_part`] finds them: labelling did) and
/// the input its surface is held to.
pub(crate) fn fit_part_from(
    part: &Part,
    points: &[Point3],
    first_feet: Vec<Option<Foot>>,
    weights: &[Real],
    cover: &Coverage<'_>,
    opts: &SurfaceFitOptions,
) -> (Part, SurfaceFitStats) {
    let data = Fitting {
        points,
        weights,
        cover,
        opts,
    };
    let (mut fitted, mut stats, last_feet) = fit_rounds(part, first_feet, &data);
    if opts.split > 0.0 {
        let last_feet = last_feet.unwrap_or_else(|| feet(&fitted, points));
        if let Some(split) = split_where_far(&fitted, &last_feet, weights, opts) {
            let (refitted, again, _) = fit_rounds(&split, feet(&split, points), &data);
            stats = SurfaceFitStats {
                used: again.used,
                rms_after: again.rms_after,
                rounds: stats.rounds + again.rounds,
                added: refitted.sections().len() - part.sections().len(),
                ..stats
            };
            fitted = refitted;
        }
    }
    (stats.moved_rms, stats.moved_max) = displacement(part, &fitted);
    (fitted, stats)
}

/// What a part is fitted to: the points and their weights, the input its
/// skin is held to, and the options.
struct Fitting<'a> {
    points: &'a [Point3],
    weights: &'a [Real],
    cover: &'a Coverage<'a>,
    opts: &'a SurfaceFitOptions,
}

/// The rounds of projection and solve of [`fit_part_from`]: the part,
/// what they did (not how far it moved) and the points' feet on the part
/// where the last round found them.
fn fit_rounds(
    part: &Part,
    first_feet: Vec<Option<Foot>>,
    data: &Fitting<'_>,
) -> (Part, SurfaceFitStats, Option<Vec<Option<Foot>>>) {
    let Fitting {
        points,
        weights,
        cover,
        opts,
    } = *data;
    let mut last_feet = None;
    let mut first_feet = Some(first_feet);
    let mut stats = SurfaceFitStats {
        points: points.len(),
        ..SurfaceFitStats::default()
    };
    let mut current = part.clone();
    // The last step taken: the part it started from, its update and the
    // share of it taken.
    let mut step: Option<(Part, Vec<Real>, Real)> = None;
    let mut mask: Option<Vec<bool>> = None;
    let mut last_objective = Real::INFINITY;
    let mut gate: Option<Real> = None;
    let mut round = 0;
    loop {
        let feet = first_feet.take().unwrap_or_else(|| feet(&current, points));
        let usable =
            |i: usize| feet[i].filter(|f| !f.at_end && weights.get(i).is_some_and(|&w| w > 0.0));
        let sigma = robust_scale((0..points.len()).filter_map(|i| usable(i).map(|f| f.signed)));
        let cut = (opts.cutoff * sigma).max(opts.min_cutoff);
        let inside: Vec<bool> = (0..points.len())
            .map(|i| usable(i).is_some_and(|f| f.signed.abs() <= cut))
            .collect();
        let mask = mask.get_or_insert_with(|| inside.clone());
        let rms = rms_over(&feet, mask);
        // The skin held to the input where the points are farther than
        // the first round's Huber threshold: within it the points decide.
        let gate = *gate.get_or_insert(opts.huber * sigma);
        let (samples, grid_size) = if opts.coverage > 0.0 && cover.reach > 0.0 {
            coverage_feet(&current, cover, gate)
        } else {
            (Vec::new(), 0)
        };
        let sample_share = opts.coverage / grid_size.max(1) as Real;
        let objective = objective(&feet, mask, &samples, sample_share);
        // A step that leaves the points (and the skin held to them)
        // farther is taken again at half its length (the linearisation
        // held nearer), down to [`MIN_STEP`], else undone and the fit
        // stops; one that leaves them as near (converged, within
        // rounding) is kept, so no rounding in the input decides how many
        // rounds there are.
        if objective > last_objective * (1.0 + WORSE) {
            let Some((from, delta, share)) = step.take() else {
                last_feet = Some(feet);
                break;
            };
            let shorter = if share > MIN_STEP {
                scaled_step(&from, &delta, 0.5 * share, opts)
            } else {
                None
            };
            match shorter {
                Some((p, taken)) => {
                    current = p;
                    step = Some((from, delta, taken));
                    continue;
                }
                None => {
                    current = from;
                    stats.rounds -= 1;
                    break;
                }
            }
        }
        if round == 0 {
            stats.rms_before = rms;
        }
        (stats.rms_after, last_objective) = (rms, objective);
        stats.used = inside.iter().filter(|&&b| b).count();
        if round == opts.rounds {
            last_feet = Some(feet);
            break;
        }
        let round_data = Round {
            start: part.sections(),
            feet: &feet,
            inside: &inside,
            weights,
            samples: &samples,
            sample_share,
            huber: opts.huber * sigma,
        };
        let Some(delta) = round_data.solve(&current, opts) else {
            last_feet = Some(feet);
            break;
        };
        let Some((next, taken)) = scaled_step(&current, &delta, 1.0, opts) else {
            last_feet = Some(feet);
            break;
        };
        step = Some((std::mem::replace(&mut current, next), delta, taken));
        stats.rounds += 1;
        round += 1;
    }
    (current, stats, last_feet)
}

/// One round's data: the points' feet, which take part, their weights and
/// the Huber threshold.
struct Round<'a> {
    /// The sections the fit started from.
    start: &'a [TrigCurve],
    feet: &'a [Option<Foot>],
    inside: &'a [bool],
    weights: &'a [Real],
    /// The surface's samples held to the input ([`coverage_feet`]), each
    /// weighing this share of all the points' weight.
    samples: &'a [Foot],
    sample_share: Real,
    huber: Real,
}

impl Round<'_> {
    /// The update of one least squares to the curves' coefficients
    /// (`None` when the system is not positive definite).
    fn solve(&self, part: &Part, opts: &SurfaceFitOptions) -> Option<Vec<Real>> {
        let sw = SectionWeights::of(part)?;
        let curves = part.curves();
        let layout = Layout::new(curves, opts.max_order);
        let n = layout.unknowns();
        let mut band = Band::new(n, bandwidth(&sw, &layout.off, curves.len()));
        let mut rhs = vec![0.0; n];
        let mut moments = Moments::new(&layout);
        let (mut row, mut terms) = (Vec::new(), Vec::new());
        let mut total = 0.0;
        let mut add = |foot: &Foot, weight: Real| {
            let r = foot.signed;
            let huber = if r.abs() <= self.huber {
                1.0
            } else {
                self.huber / r.abs()
            };
            let w = weight * huber;
            let (weights, count) = sw.at_with_derivative(foot.s);
            normal_terms(curves, &weights[..count], foot.normal, &mut terms);
            moments.at_angle(foot.v);
            for &(m, n1, n2) in &terms {
                let (a, b) = (layout.at(m, false, 0), layout.at(m, true, 0));
                for i in 0..layout.len[m] {
                    rhs[a + i] += w * r * n1 * moments.basis(i, false);
                    rhs[b + i] += w * r * n2 * moments.basis(i, true);
                }
            }
            if !moments.add(&terms, w) {
                data_row(&layout, &terms, |i, b| moments.basis(i, b), &mut row);
                band.add_outer(&row, w);
            }
            w
        };
        for (i, foot) in self.feet.iter().enumerate() {
            if let Some(foot) = foot.filter(|_| self.inside[i]) {
                total += add(&foot, self.weights[i]);
            }
        }
        let sample_weight = self.sample_share * total;
        for foot in self.samples {
            add(foot, sample_weight);
        }
        moments.expand(&layout, &mut band);
        let per_section = total.max(1.0) / curves.len() as Real;
        // The curves the fit started from, in the current twist.
        let start: Vec<TrigCurve> = self
            .start
            .iter()
            .zip(part.twist())
            .map(|(c, &t)| c.shifted(t))
            .collect();
        let smooth = opts.smoothness * per_section;
        for m in 1..curves.len().saturating_sub(1) {
            smoothness_rows(curves, &layout, part.knots(), m, |row, value| {
                band.add_outer(row, smooth);
                for &(k, x) in row {
                    rhs[k] -= smooth * x * value;
                }
            });
        }
        // The anchor: every curve pulled toward the one the fit started
        // from (in the current twist), in proportion to the squared
        // distance between the two curves, so that what the points do
        // not decide (past an end, beside a junction, a section plane
        // along the surface: a sole) does not wander; the smoothness
        // still carries its neighbours' shape into it (holding such
        // sections harder left the corpus scans at 2.71 mm against 2.52).
        let anchor = opts.anchor * per_section;
        for (m, (c, start)) in curves.iter().zip(&start).enumerate() {
            for (b, now, then) in [(false, &c.a, &start.a), (true, &c.b, &start.b)] {
                for i in 0..layout.len[m] {
                    let share = if i == 0 { 1.0 } else { 0.5 };
                    let k = layout.at(m, b, i);
                    *band.at(k, k) += anchor * share;
                    rhs[k] += anchor * share * (then[i] - now[i]);
                }
            }
        }
        // Damping (Levenberg-Marquardt): each unknown also pulled toward
        // its current value in proportion to what the data say of it, so
        // that a round moves little where the points hardly decide.
        let floor = 1e-9 * per_section;
        for k in 0..n {
            let d = band.get(k, k);
            *band.at(k, k) += opts.pull * d + floor;
        }
        band.solve(rhs)
    }
}

/// The shortest share of a round's step tried ([`fit_part`]): a step
/// halved twice.
const MIN_STEP: Real = 0.25;

/// `part` moved by `share` of the round's update `delta` (its layout
/// rebuilt as the round built it), or by half as much while that leaves
/// the part invalid, down to [`MIN_STEP`]: the part and the share taken.
fn scaled_step(
    part: &Part,
    delta: &[Real],
    share: Real,
    opts: &SurfaceFitOptions,
) -> Option<(Part, Real)> {
    let layout = Layout::new(part.curves(), opts.max_order);
    let mut share = share;
    loop {
        let d: Vec<Real> = delta.iter().map(|x| x * share).collect();
        if let Ok(p) = updated(part, &layout, &d) {
            return Some((p, share));
        }
        if share <= MIN_STEP {
            return None;
        }
        share *= 0.5;
    }
}

/// The weighted mean square the fit lowers: the masked points' residuals
/// and the held skin's samples, each of those weighing `sample_share` of
/// all the points.
fn objective(feet: &[Option<Foot>], mask: &[bool], samples: &[Foot], sample_share: Real) -> Real {
    let (mut sum, mut count) = (0.0, 0usize);
    for (f, &m) in feet.iter().zip(mask) {
        if let (Some(f), true) = (f, m) {
            sum += f.signed * f.signed;
            count += 1;
        }
    }
    let held: Real = samples.iter().map(|f| f.signed * f.signed).sum();
    (sum + sample_share * count as Real * held) / count.max(1) as Real
}

fn rms_over(feet: &[Option<Foot>], mask: &[bool]) -> Real {
    let (mut sum, mut count) = (0.0, 0usize);
    for (f, &m) in feet.iter().zip(mask) {
        if let (Some(f), true) = (f, m) {
            sum += f.signed * f.signed;
            count += 1;
        }
    }
    if count == 0 {
        0.0
    } else {
        (sum / count as Real).sqrt()
    }
}

/// The band a point's or a smoothness row's unknowns span.
fn bandwidth(sw: &SectionWeights, off: &[usize], sections: usize) -> usize {
    let mut bw = 0;
    for i in 0..sections - 1 {
        let touched = sw.tangents[i]
            .iter()
            .chain(&sw.tangents[i + 1])
            .map(|&(m, _)| m)
            .chain([i, i + 1]);
        let (lo, hi) = touched.fold((usize::MAX, 0), |(lo, hi), m| (lo.min(m), hi.max(m)));
        bw = bw.max(off[hi + 1] - off[lo] - 1);
    }
    for m in 1..sections.saturating_sub(1) {
        bw = bw.max(off[m + 2] - off[m - 1] - 1);
    }
    bw
}

/// The part with its curves' coefficients moved by `delta`, rebuilt
/// through its sections (each curve's twist shift undone).
fn updated(part: &Part, layout: &Layout, delta: &[Real]) -> Result<Part, PartError> {
    let sections: Vec<TrigCurve> = part
        .curves()
        .iter()
        .zip(part.twist())
        .enumerate()
        .map(|(m, (c, &twist))| {
            let mut c = c.clone();
            for i in 0..layout.len[m] {
                c.a[i] += delta[layout.at(m, false, i)];
                c.b[i] += delta[layout.at(m, true, i)];
            }
            c.shifted(-twist)
        })
        .collect();
    Part::new(sections, part.options())
}

/// RMS and largest distance from `b`'s surface to `a`'s (samples of `b`
/// on a grid of its parameters, each to its foot on `a`).
fn displacement(a: &Part, b: &Part) -> (Real, Real) {
    if a == b {
        return (0.0, 0.0);
    }
    let samples: Vec<Point3> = PartGrid::new(b, 48, 2).mesh.positions;
    let (mut sum, mut max, mut count) = (0.0, 0.0, 0usize);
    for (p, foot) in samples.iter().zip(feet(a, &samples)) {
        let d = foot.map_or(0.0, |f| p.distance(f.point));
        sum += d * d;
        max = Real::max(max, d);
        count += 1;
    }
    ((sum / count.max(1) as Real).sqrt(), max)
}

#[cfg(test)]
mod tests;
