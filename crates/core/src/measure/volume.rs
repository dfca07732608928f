//! Volume and surface area of a model from its own surfaces (Gauss
//! quadrature over each patch, the divergence theorem for the volume), and
//! the volume and area an arm shares with the torso, subtracted once.

use crate::anatomy::PartName;
use crate::body::Body;
use crate::curve::series::{harmonics, Series};
use crate::curve::trig::SpaceCurve;
use crate::geom::math::{Point3, Real, Vec2, Vec3};
use crate::measure::part_curves::*;
use crate::section::mesh::point_in_polygon;
use crate::surface::part::Part;
use crate::surface::patch::Patch;
use std::f64::consts::TAU;

/// Volume, surface area and the extent along `up` of one part with its caps.
pub(super) struct PartIntegrals {
    pub(super) volume: Real,
    pub(super) area: Real,
    pub(super) low: Real,
    pub(super) high: Real,
}

/// Gauss-Legendre nodes and weights on `[0, 1]`.
pub(super) const GL2: [(Real, Real); 2] = [
    (0.211_324_865_405_187_1, 0.5),
    (0.788_675_134_594_812_9, 0.5),
];
pub(super) const GL6: [(Real, Real); 6] = [
    (0.033_765_242_898_423_99, 0.085_662_246_189_585_17),
    (0.169_395_306_766_867_73, 0.180_380_786_524_069_3),
    (0.380_690_406_958_401_5, 0.233_956_967_286_345_53),
    (0.619_309_593_041_598_5, 0.233_956_967_286_345_53),
    (0.830_604_693_233_132_3, 0.180_380_786_524_069_3),
    (0.966_234_757_101_576, 0.085_662_246_189_585_17),
];

/// `cos jv`, `sin jv` on `n` equally spaced `v`, also as rows
/// `[1, cos v, sin v, …, cos Jv, sin Jv]` in the series' coefficient layout.
pub(super) struct VTable {
    n: usize,
    order: usize,
    cos: Vec<Real>,
    sin: Vec<Real>,
    rows: Vec<Real>,
}

impl VTable {
    pub(super) fn new(n: usize, order: usize) -> VTable {
        let mut cos = vec![0.0; n * (order + 1)];
        let mut sin = vec![0.0; n * (order + 1)];
        let m = 2 * order + 1;
        let mut rows = vec![0.0; n * m];
        for i in 0..n {
            let r = i * (order + 1)..(i + 1) * (order + 1);
            let (c, s) = (&mut cos[r.clone()], &mut sin[r]);
            harmonics(TAU * i as Real / n as Real, order, c, s);
            let row = &mut rows[i * m..(i + 1) * m];
            row[0] = 1.0;
            for j in 1..=order {
                row[2 * j - 1] = c[j];
                row[2 * j] = s[j];
            }
        }
        VTable {
            n,
            order,
            cos,
            sin,
            rows,
        }
    }

    /// Nine series at sample `i`; `coef` holds their coefficients
    /// interleaved, `coef[9k + s]` the `k`-th of series `s` (one pass over
    /// the row, nine independent sums).
    #[inline]
    pub(super) fn eval9(&self, coef: &[Real], i: usize) -> [Real; 9] {
        let m = 2 * self.order + 1;
        let row = &self.rows[i * m..(i + 1) * m];
        let mut acc = [0.0; 9];
        for (&r, c) in row.iter().zip(coef.chunks_exact(9)) {
            for s in 0..9 {
                acc[s] += r * c[s];
            }
        }
        acc
    }

    /// Value of a series at sample `i`.
    #[inline]
    pub(super) fn value(&self, s: &Series, i: usize) -> Real {
        let base = i * (self.order + 1);
        let mut v = s.c[0];
        for j in 1..=s.order().min(self.order) {
            v += s.c[2 * j - 1] * self.cos[base + j] + s.c[2 * j] * self.sin[base + j];
        }
        v
    }

    pub(super) fn position(&self, c: &SpaceCurve, i: usize) -> Vec3 {
        Vec3::new(
            self.value(&c.x, i),
            self.value(&c.y, i),
            self.value(&c.z, i),
        )
    }

    /// Value and `d/dv` of a series at sample `i`.
    #[inline]
    pub(super) fn eval(&self, s: &Series, i: usize) -> (Real, Real) {
        let base = i * (self.order + 1);
        let (mut v, mut d) = (s.c[0], 0.0);
        for j in 1..=s.order().min(self.order) {
            let (c, sn) = (self.cos[base + j], self.sin[base + j]);
            let (p, q) = (s.c[2 * j - 1], s.c[2 * j]);
            v += p * c + q * sn;
            d += j as Real * (q * c - p * sn);
        }
        (v, d)
    }

    pub(super) fn point(&self, c: &SpaceCurve, i: usize) -> (Vec3, Vec3) {
        let (x, dx) = self.eval(&c.x, i);
        let (y, dy) = self.eval(&c.y, i);
        let (z, dz) = self.eval(&c.z, i);
        (Vec3::new(x, y, z), Vec3::new(dx, dy, dz))
    }
}

/// Tables by order, `2J + 6` samples each: the trapezoid rule is then
/// exact for the flux integrand's harmonics up to `2J + 5`, and those above
/// (products of the highest harmonics) are below the fit's own error.
#[derive(Default)]
pub(super) struct Tables(Vec<Option<VTable>>);

impl Tables {
    fn get(&mut self, order: usize) -> &VTable {
        if self.0.len() <= order {
            self.0.resize_with(order + 1, || None);
        }
        self.0[order].get_or_insert_with(|| VTable::new(2 * order + 6, order))
    }
}

/// Coordinate `s` (x, y, z) of a space curve.
fn du_of(c: &SpaceCurve, s: usize) -> &Series {
    match s {
        0 => &c.x,
        1 => &c.y,
        _ => &c.z,
    }
}

/// Flux `∬ (t − q)·(t_v × t_u) du dv`, area `∬ |t_v × t_u|` of a patch,
/// and the extent of its nodes along `up`.
pub(super) fn patch_integrals(
    patch: &Patch,
    tables: &mut Tables,
    nodes: &[(Real, Real)],
    q: Point3,
    up: Vec3,
    ext: &mut (Real, Real),
) -> (Real, Real) {
    let table = tables.get(effective_order(patch));
    let dv = TAU / table.n as Real;
    let (mut flux, mut area) = (0.0, 0.0);
    let order = table.order;
    let m = 2 * order + 1;
    // Interleaved coefficients of t, t_v and t_u at a node: d/dv turns
    // harmonic j's (cos, sin) coefficients (p, q) into (j q, −j p).
    let mut coef = vec![0.0; 9 * m];
    for &(u, w) in nodes {
        let c = iso_curve(patch, u, 0, order);
        let du = iso_curve(patch, u, 1, order);
        for (s, sr) in [&c.x, &c.y, &c.z].into_iter().enumerate() {
            coef[s] = sr.c[0];
            coef[3 + s] = 0.0;
            coef[6 + s] = du_of(&du, s).c[0];
            for j in 1..=order {
                let (p, q) = (sr.c[2 * j - 1], sr.c[2 * j]);
                let (a, b) = (9 * (2 * j - 1), 9 * (2 * j));
                coef[a + s] = p;
                coef[b + s] = q;
                coef[a + 3 + s] = j as Real * q;
                coef[b + 3 + s] = -(j as Real) * p;
                coef[a + 6 + s] = du_of(&du, s).c[2 * j - 1];
                coef[b + 6 + s] = du_of(&du, s).c[2 * j];
            }
        }
        for i in 0..table.n {
            let e = table.eval9(&coef, i);
            let p = Vec3::new(e[0], e[1], e[2]);
            let pv = Vec3::new(e[3], e[4], e[5]);
            let cr = pv.cross(Vec3::new(e[6], e[7], e[8]));
            flux += w * dv * (p - q).dot(cr);
            area += w * dv * cr.norm();
            let hgt = p.dot(up);
            ext.0 = ext.0.min(hgt);
            ext.1 = ext.1.max(hgt);
        }
    }
    (flux, area)
}

pub(super) fn part_integrals(part: &Part, up: Vec3, tables: &mut Tables) -> PartIntegrals {
    let curves = part.curves();
    let mut ext = (Real::INFINITY, Real::NEG_INFINITY);
    let (mut signed, mut area) = (0.0, 0.0);
    for seg in part.segments() {
        // The slab of this patch, closed by the cones from its end curves'
        // mean points, measured from its first curve's mean point `q`.
        let q = start_mean(&seg.patch);
        let (f, a) = patch_integrals(&seg.patch, tables, &GL2, q, up, &mut ext);
        let (mean, va) = end_mean_and_area(&seg.patch);
        signed += f + (mean - q).dot(va);
        area += a;
    }
    for c in [&curves[0], &curves[curves.len() - 1]] {
        let c = c.world_series();
        let t = tables.get(c.order());
        for i in 0..t.n {
            let hgt = t.point(&c, i).0.dot(up);
            ext.0 = ext.0.min(hgt);
            ext.1 = ext.1.max(hgt);
        }
    }
    let mut volume = (signed / 3.0).abs();
    for cap in [part.start_cap(), part.end_cap()].into_iter().flatten() {
        // From the rim's mean point the rim's cone is flat: no disc term.
        let q = start_mean(&cap.patch);
        let (f, a) = patch_integrals(&cap.patch, tables, &GL6, q, up, &mut ext);
        volume += (f / 3.0).abs();
        area += a;
        let hgt = cap.apex.dot(up);
        ext.0 = ext.0.min(hgt);
        ext.1 = ext.1.max(hgt);
    }
    PartIntegrals {
        volume,
        area,
        low: ext.0,
        high: ext.1,
    }
}

/// Volume and surface area of the model (sum over parts and transitions,
/// see the module doc, less each cavity's volume and plus its area), and
/// its extent `(low, high)` along `up`.
pub fn volume_area_extent(body: &Body) -> (Real, Real, (Real, Real)) {
    let up = body.frame.up;
    let mut out = (0.0, 0.0, (Real::INFINITY, Real::NEG_INFINITY));
    let mut tables = Tables::default();
    // A digit overlaps its palm by [`crate::body::DIGIT_OVERLAP`] levels:
    // counted whole (a few cm³ over a body's 70 000).
    for p in body.solids() {
        let r = part_integrals(p, up, &mut tables);
        out.0 += r.volume;
        out.1 += r.area;
        out.2 .0 = out.2 .0.min(r.low);
        out.2 .1 = out.2 .1.max(r.high);
    }
    for t in &body.transitions {
        let (v, a) = transition_integrals(t.transition.patch(), up, &mut tables, &mut out.2);
        out.0 += v;
        out.1 += a;
    }
    // A cavity is empty space inside its part: its volume is the body's
    // less, its surface (the pocket's lining) the body's too. It lies
    // inside the body, so the extent is the parts'.
    for c in &body.cavities {
        let r = part_integrals(&c.part, up, &mut tables);
        out.0 -= r.volume;
        out.1 += r.area;
    }
    out
}

/// Volume and area of a transition band (a leg's top to its half of the
/// torso's bottom): the band closed by the cones from its two boundary
/// curves' mean points, as a part's open ends are closed (module doc). The
/// band is one Hermite patch across the whole gap, so its `u` integral
/// takes 6 Gauss points (as caps do). The torso side's cone over a half
/// loop and its seam does not tile the torso's bottom cone exactly; the
/// difference is a thin sliver under the crotch.
pub(super) fn transition_integrals(
    patch: &Patch,
    up: Vec3,
    tables: &mut Tables,
    ext: &mut (Real, Real),
) -> (Real, Real) {
    let (c0, c1) = (patch.curve_at(0.0), patch.curve_at(1.0));
    let q = c0.mean_point();
    let (flux, area) = patch_integrals(patch, tables, &GL6, q, up, ext);
    let disc = |c: &SpaceCurve| (c.mean_point() - q).dot(vector_area(c));
    let ends = disc(&c1) - disc(&c0);
    (((flux + ends) / 3.0).abs(), area)
}

/// A torso's horizontal outlines at evenly spaced levels, for inside tests.
struct LevelTable {
    lo: Real,
    step: Real,
    /// Per level, the outline in `(front, left)` coordinates (empty where
    /// the torso has no curve at that level).
    outlines: Vec<Vec<Vec2>>,
    up: Vec3,
    front: Vec3,
    left: Vec3,
}

impl LevelTable {
    fn new(
        torso: &Part,
        up: Vec3,
        front: Vec3,
        left: Vec3,
        lo: Real,
        hi: Real,
        n: usize,
    ) -> LevelTable {
        let step = (hi - lo) / (n - 1).max(1) as Real;
        let outlines = (0..n)
            .map(|i| {
                let lv = lo + step * i as Real;
                torso.s_at_level(up, lv).map_or(Vec::new(), |s| {
                    let c = curve_at(torso, s);
                    area_true_outline(&c, &sample(&c, 32), Vec3::ZERO, front, left)
                })
            })
            .collect();
        LevelTable {
            lo,
            step,
            outlines,
            up,
            front,
            left,
        }
    }

    fn contains(&self, p: Point3) -> bool {
        let k = ((p.dot(self.up) - self.lo) / self.step).round();
        if !(k >= 0.0 && (k as usize) < self.outlines.len()) {
            return false;
        }
        let o = &self.outlines[k as usize];
        !o.is_empty() && point_in_polygon(Vec2::new(p.dot(self.front), p.dot(self.left)), o)
    }
}

/// One section of an arm across its axis, for inside tests.
struct ArmSlice {
    centre: Point3,
    axis: Vec3,
    e1: Vec3,
    e2: Vec3,
    outline: Vec<Vec2>,
}

/// Where an arm without a side transition starts inside the torso (its
/// first section inside the torso's shoulder loops), the overlap is
/// counted twice by the sums over parts. Its volume is
/// `∫ A_in(s) ds` over the arm's sections across its axis, `ds = 0.01 H`,
/// `A_in` the area of the section (a 10 × 10 grid over its box) inside the
/// torso's horizontal outline at the point's height; its surface is the
/// arm's quadrature nodes inside the torso plus the torso's nodes inside
/// the arm. Returns `(volume, area)` to subtract.
fn arm_torso_overlap(
    torso: &Part,
    arm: &Part,
    up: Vec3,
    front: Vec3,
    left: Vec3,
    h: Real,
) -> (Real, Real) {
    let ds = 0.01 * h;
    let count = ((0.35 * arm.length()) / ds).ceil() as usize;
    let mut slices = Vec::new();
    let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
    for k in 0..count {
        let s = (k as Real + 0.5) * ds;
        let c = curve_at(arm, s);
        let (i, u) = arm.locate(s);
        let d = arm.segments()[i].patch.u_derivative_curve(u, 1);
        let Some(axis) = d.mean_point().normalized() else {
            continue;
        };
        let (e1, e2) = plane_axes(axis, front);
        let centre = c.mean_point();
        let pts = sample(&c, 32);
        for p in &pts {
            lo = lo.min(p.dot(up));
            hi = hi.max(p.dot(up));
        }
        let outline = area_true_outline(&c, &pts, centre, e1, e2);
        slices.push(ArmSlice {
            centre,
            axis,
            e1,
            e2,
            outline,
        });
    }
    if slices.is_empty() {
        return (0.0, 0.0);
    }
    let table = LevelTable::new(torso, up, front, left, lo, hi, 48);
    // Volume.
    let g = 10;
    let mut volume = 0.0;
    for sl in &slices {
        let (mut a, mut b) = (
            Vec2::new(Real::INFINITY, Real::INFINITY),
            Vec2::new(Real::NEG_INFINITY, Real::NEG_INFINITY),
        );
        for q in &sl.outline {
            a = Vec2::new(a.x.min(q.x), a.y.min(q.y));
            b = Vec2::new(b.x.max(q.x), b.y.max(q.y));
        }
        let (dx, dy) = ((b.x - a.x) / g as Real, (b.y - a.y) / g as Real);
        let mut inside = 0usize;
        for i in 0..g {
            for j in 0..g {
                let q = Vec2::new(a.x + (i as Real + 0.5) * dx, a.y + (j as Real + 0.5) * dy);
                if point_in_polygon(q, &sl.outline)
                    && table.contains(sl.centre + sl.e1 * q.x + sl.e2 * q.y)
                {
                    inside += 1;
                }
            }
        }
        volume += inside as Real * dx * dy * ds;
    }
    // Surfaces: the arm's nodes inside the torso, the torso's inside the arm.
    let s_end = count as Real * ds;
    let inside_arm = |p: Point3| {
        let best = slices
            .iter()
            .min_by(|x, y| {
                x.axis
                    .dot(p - x.centre)
                    .abs()
                    .total_cmp(&y.axis.dot(p - y.centre).abs())
            })
            .filter(|sl| sl.axis.dot(p - sl.centre).abs() <= 0.5 * ds);
        best.is_some_and(|sl| {
            let r = p - sl.centre;
            point_in_polygon(Vec2::new(r.dot(sl.e1), r.dot(sl.e2)), &sl.outline)
        })
    };
    let mut tables = Tables::default();
    let area_arm = area_where(arm, &mut tables, |s0, _| s0 <= s_end, |p| table.contains(p));
    let in_band = near_levels(torso, up, lo - ds, hi + ds);
    let area_torso = area_where(torso, &mut tables, in_band, |p| {
        let lv = p.dot(up);
        lv >= lo && lv <= hi && inside_arm(p)
    });
    (volume, area_arm + area_torso)
}

/// Where an arm ends on the torso's side through a transition
/// ([`crate::surface::transition::SideCut`]), the torso's loops reach past the side
/// plane into the transition: that part of the torso's solid and skin is
/// counted twice by the sums over parts. Its volume is `∫ A(z) dz` over
/// the torso's horizontal curves between the lowest and highest points of
/// the transition's curve on the torso (48 levels, midpoint rule),
/// `A` the area of the curve's 64-gon (scaled to the curve's area) beyond
/// the plane's line; its surface the torso's quadrature nodes beyond the
/// plane. Returns `(volume, area)` to subtract. (The transition's own
/// surface dips into the torso at the armpit over 0.1-0.2 % of the body's
/// area, not subtracted.)
fn torso_beyond_side(
    torso: &Part,
    side: &crate::surface::transition::SideCut,
    end: &SpaceCurve,
    up: Vec3,
    front: Vec3,
    left: Vec3,
) -> (Real, Real) {
    let Some(n) = side.normal.normalized() else {
        return (0.0, 0.0);
    };
    // Only between the levels of the transition's curve on the torso (the
    // torso's hips may reach past the side plane too).
    let levels: Vec<Real> = sample(end, 128).iter().map(|p| p.dot(up)).collect();
    let lo = levels.iter().copied().fold(Real::INFINITY, Real::min);
    let hi = levels.iter().copied().fold(Real::NEG_INFINITY, Real::max);
    if !(hi > lo) {
        return (0.0, 0.0);
    }
    let beyond = |p: Point3| {
        let lv = p.dot(up);
        (p - side.point).dot(n) > 0.0 && lv >= lo && lv <= hi
    };
    let n2 = Vec2::new(n.dot(front), n.dot(left));
    let c = side.point.dot(front) * n2.x + side.point.dot(left) * n2.y;
    let steps = 48;
    let dz = (hi - lo) / steps as Real;
    let mut volume = 0.0;
    for k in 0..steps {
        let lv = lo + (k as Real + 0.5) * dz;
        let Some(s) = torso.s_at_level(up, lv) else {
            continue;
        };
        let curve = curve_at(torso, s);
        let pts = sample(&curve, 64);
        if !pts.iter().any(|&p| beyond(p)) {
            continue;
        }
        let outline = area_true_outline(&curve, &pts, Vec3::ZERO, front, left);
        volume += clipped_area(&outline, n2, c) * dz;
    }
    // Only the patches whose centres come within the band (the others'
    // nodes all fail `beyond`).
    let margin = 0.5 * (hi - lo);
    let in_band = near_levels(torso, up, lo - margin, hi + margin);
    let mut tables = Tables::default();
    let area = area_where(torso, &mut tables, in_band, beyond);
    (volume, area)
}

/// The area of a closed polygon on the side `q·n > c` of a line
/// (Sutherland–Hodgman against one half-plane, then the shoelace formula,
/// [`crate::curve::fit::signed_area`]).
fn clipped_area(poly: &[Vec2], n: Vec2, c: Real) -> Real {
    let m = poly.len();
    let mut kept: Vec<Vec2> = Vec::with_capacity(m + 2);
    for i in 0..m {
        let (a, b) = (poly[i], poly[(i + 1) % m]);
        let (fa, fb) = (a.x * n.x + a.y * n.y - c, b.x * n.x + b.y * n.y - c);
        if fa > 0.0 {
            kept.push(a);
        }
        if (fa > 0.0) != (fb > 0.0) {
            let w = fa / (fa - fb);
            kept.push(Vec2::new(a.x + (b.x - a.x) * w, a.y + (b.y - a.y) * w));
        }
    }
    crate::curve::fit::signed_area(&kept).abs()
}

/// Whether the patch `[s0, s1]` of `part` reaches the levels `[lo, hi]`
/// along `up` (by its end curves' centres): the `use_segment` of
/// [`area_where`] for a band of heights.
fn near_levels(part: &Part, up: Vec3, lo: Real, hi: Real) -> impl Fn(Real, Real) -> bool + '_ {
    move |s0, s1| {
        let (a, b) = (part.centre(s0).dot(up), part.centre(s1).dot(up));
        a.max(b) >= lo && a.min(b) <= hi
    }
}

/// `∬ |t_v × t_u|` over the part's patches `[s0, s1]` with
/// `use_segment(s0, s1)`, counting only nodes where `keep(point)`.
fn area_where(
    part: &Part,
    tables: &mut Tables,
    use_segment: impl Fn(Real, Real) -> bool,
    keep: impl Fn(Point3) -> bool,
) -> Real {
    let mut area = 0.0;
    for seg in part.segments().iter().filter(|s| use_segment(s.s0, s.s1)) {
        let order = effective_order(&seg.patch);
        let table = tables.get(order);
        let dv = TAU / table.n as Real;
        for &(u, w) in &GL2 {
            let c = iso_curve(&seg.patch, u, 0, order);
            let du = iso_curve(&seg.patch, u, 1, order);
            for i in 0..table.n {
                let (p, pv) = table.point(&c, i);
                if keep(p) {
                    area += w * dv * pv.cross(table.position(&du, i)).norm();
                }
            }
        }
    }
    area
}

/// The volume and area each arm shares with the torso, in arm order.
pub(super) fn arm_torso_overlaps(body: &Body, torso: &Part, h: Real) -> Vec<(Real, Real)> {
    let (up, front) = (body.frame.up, body.frame.front);
    [PartName::LeftArm, PartName::RightArm]
        .iter()
        .filter_map(|&a| body.part(a))
        .map(|a| {
            let side = body.transitions.iter().find_map(|t| {
                let side = t.transition.spec().side?;
                (t.from == a.name && t.to == PartName::Torso)
                    .then(|| (side, t.transition.curves()[2]))
            });
            match side {
                Some((side, end)) => {
                    torso_beyond_side(torso, &side, end, up, front, body.frame.left)
                }
                None => arm_torso_overlap(torso, &a.part, up, front, body.frame.left, h),
            }
        })
        .collect()
}
