//! Curves of a model's parts the measurements are taken on: mean points
//! and vector areas of closed space curves, a part's iso-curves and centre
//! line, and levels along a direction.

use crate::curve::series::{harmonics, Series};
use crate::curve::trig::{Frame, SpaceCurve};
use crate::geom::math::{Point3, Real, Vec2, Vec3};
use crate::surface::part::Part;
use crate::surface::patch::Patch;
use std::f64::consts::{PI, TAU};

/// The vector area `A⃗ = ½ ∮ C × C' dv` of a closed trigonometric curve
/// `C = c₀ + Σ_j (a_j cos jv + b_j sin jv)`: harmonics `j ≠ k` integrate to
/// zero against each other and `c₀` against `C'`, and
/// `(a cos jv + b sin jv) × j(b cos jv − a sin jv) = j a × b`, so
/// `A⃗ = π Σ_j j a_j × b_j`, exact in `O(J)`.
pub(super) fn vector_area(c: &SpaceCurve) -> Vec3 {
    let coef = |s: &Series, k: usize| s.c.get(k).copied().unwrap_or(0.0);
    let mut a = Vec3::ZERO;
    for j in 1..=c.x.order().max(c.y.order()).max(c.z.order()) {
        let (p, q) = (2 * j - 1, 2 * j);
        let cj = Vec3::new(coef(&c.x, p), coef(&c.y, p), coef(&c.z, p));
        let sj = Vec3::new(coef(&c.x, q), coef(&c.y, q), coef(&c.z, q));
        a += cj.cross(sj) * j as Real;
    }
    a * PI
}

/// The mean point of a patch's curve at `u = 0` (its `f_0`'s).
pub(super) fn start_mean(patch: &Patch) -> Point3 {
    patch.coefficients()[0].mean_point()
}

/// The mean point and vector area ([`vector_area`]) of a patch's curve at
/// `u = 1`, `Σ_m f_m`, without building it.
pub(super) fn end_mean_and_area(patch: &Patch) -> (Point3, Vec3) {
    let fs = patch.coefficients();
    let sum = |k: usize| {
        fs.iter().fold(Vec3::ZERO, |acc, f| {
            let c = |s: &Series| s.c.get(k).copied().unwrap_or(0.0);
            acc + Vec3::new(c(&f.x), c(&f.y), c(&f.z))
        })
    };
    let order = fs
        .iter()
        .map(|f| f.x.order().max(f.y.order()).max(f.z.order()))
        .max()
        .unwrap_or(0);
    let mut a = Vec3::ZERO;
    for j in 1..=order {
        a += sum(2 * j - 1).cross(sum(2 * j)) * j as Real;
    }
    (sum(0), a * PI)
}

/// The curve of `part` at axis parameter `s`.
pub(super) fn curve_at(part: &Part, s: Real) -> SpaceCurve {
    let (i, u) = part.locate(s);
    let patch = &part.segments()[i].patch;
    iso_curve(patch, u, 0, effective_order(patch))
}

/// `∂^k t/∂u^k (u, ·)` of a patch, truncated to `order` (the patch's
/// harmonics above its effective order are zero).
pub(super) fn iso_curve(patch: &Patch, u: Real, k: usize, order: usize) -> SpaceCurve {
    let n = 2 * order + 1;
    let (mut x, mut y, mut z) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for (m, f) in patch.coefficients().iter().enumerate() {
        if m < k {
            continue;
        }
        let falling: Real = (0..k).map(|i| (m - i) as Real).product();
        let w = falling * u.powi((m - k) as i32);
        for (dst, src) in [(&mut x, &f.x), (&mut y, &f.y), (&mut z, &f.z)] {
            for (d, c) in dst.iter_mut().zip(&src.c) {
                *d += w * c;
            }
        }
    }
    SpaceCurve {
        x: Series { c: x },
        y: Series { c: y },
        z: Series { c: z },
    }
}

/// The highest harmonic with a non-zero coefficient in any of the patch's
/// coefficient functions (patches are padded to their part's order).
pub(super) fn effective_order(patch: &Patch) -> usize {
    let mut order = 1;
    for f in patch.coefficients() {
        for sr in [&f.x, &f.y, &f.z] {
            for j in (order + 1..=sr.order()).rev() {
                if sr.c[2 * j - 1] != 0.0 || sr.c[2 * j] != 0.0 {
                    order = j;
                    break;
                }
            }
        }
    }
    order
}

/// `n` samples of a space curve (one harmonic table per sample for all
/// three coordinates).
pub(super) fn sample(c: &SpaceCurve, n: usize) -> Vec<Point3> {
    let order = c.order();
    let (mut cs, mut sn) = (vec![0.0; order + 1], vec![0.0; order + 1]);
    let at = |s: &Series, cs: &[Real], sn: &[Real]| {
        let mut acc = s.c[0];
        for j in 1..=s.order() {
            acc += s.c[2 * j - 1] * cs[j] + s.c[2 * j] * sn[j];
        }
        acc
    };
    (0..n)
        .map(|i| {
            harmonics(TAU * i as Real / n as Real, order, &mut cs, &mut sn);
            Vec3::new(at(&c.x, &cs, &sn), at(&c.y, &cs, &sn), at(&c.z, &cs, &sn))
        })
        .collect()
}

/// The samples of `c` in the plane of axes `(e1, e2)` about `o`, as a
/// polygon scaled about `c`'s mean point to `c`'s own area there
/// ([`vector_area`]): an inscribed polygon falls short by about
/// `(2π/n)²/6` of the area (0.6 % at 32), which an inside test near the
/// curve would count as outside every time.
pub(super) fn area_true_outline(
    c: &SpaceCurve,
    samples: &[Point3],
    o: Point3,
    e1: Vec3,
    e2: Vec3,
) -> Vec<Vec2> {
    let plane = |p: &Point3| Vec2::new((*p - o).dot(e1), (*p - o).dot(e2));
    let m = plane(&c.mean_point());
    let pts: Vec<Vec2> = samples.iter().map(plane).collect();
    let n = pts.len();
    let poly: Real = (0..n)
        .map(|i| (pts[i] - m).cross(pts[(i + 1) % n] - m))
        .sum::<Real>()
        / 2.0;
    let curve = vector_area(c).dot(e1.cross(e2));
    let k = if poly * curve > 0.0 {
        (curve / poly).sqrt()
    } else {
        1.0
    };
    pts.into_iter().map(|p| m + (p - m) * k).collect()
}

/// Two unit vectors across `n`, the first toward `toward` when possible.
pub(super) fn plane_axes(n: Vec3, toward: Vec3) -> (Vec3, Vec3) {
    Frame::from_normal(Vec3::ZERO, n, toward)
        .or_else(|| Frame::from_normal(Vec3::ZERO, n, Vec3::X))
        .or_else(|| Frame::from_normal(Vec3::ZERO, n, Vec3::Y))
        .map_or((Vec3::X, Vec3::Y), |f| (f.e1, f.e2))
}
