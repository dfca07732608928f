//! Open arcs (step 4 of the module docs of [`super`]): joining the pieces
//! of one loop broken by scanner holes, and ordering by angle.

use super::grid::Grid;
use super::representatives;
use crate::geom::math::{Point2, Point3, Real, Vec2};
use crate::geom::tolerance::PIVOT_EPS;

/// Angular bins of [`merge_arcs`]' coverage measure (5° each).
const COVERAGE_BINS: usize = 72;

/// Joins open arcs that are pieces of one loop broken by scanner holes.
///
/// A set of arcs (two, or the fewest more when no pair qualifies) is joined when,
/// about the centre `c` of the circle fitted to all of them: (1) each pair
/// occupies disjoint angular ranges (overlap at most 15 % of the smaller's
/// 5° bins, or its two end bins); (2) together they cover at least 10° more
/// than any one covers about its own centre (arcs of one loop complete each
/// other; separate parts seen from between them cover less than each does
/// on its own), or, with a fragment at most 10° wide among them, no less
/// and every hole short (below);
/// (3) in angular order each arc is one run (a set of `k` arcs has `k`
/// junctions) and at every junction the radii agree within 25 % (a loop is
/// continuous across a hole; a nearby part, e.g. an arm in the shadow it
/// casts on the torso, lies at a different radius). The best set (largest
/// gain) is joined first, until no set qualifies.
///
/// Larger sets are needed where a loop is broken more than once: a pair of
/// its arcs has one junction across the others' place, where the radii of
/// an elongated loop (a torso at the shoulders, 2.7 : 1) legitimately
/// differ by far more than 25 %. The fewest arcs that qualify are joined
/// first (sets of every size, so whether a loop is joined does not turn on
/// how many pieces the cells' phase broke it into).
///
/// Each arc is given as (a sample of its points for the decision, all its
/// points); the joined point lists are returned.
pub(super) fn merge_arcs(
    mut groups: Vec<(Vec<usize>, Vec<usize>)>,
    pts: &[Point2],
) -> Vec<Vec<usize>> {
    let own = |g: &[usize]| {
        let c = arc_centre(g, pts);
        coverage(g.iter().map(|&m| pts[m] - c))
            .iter()
            .filter(|&&x| x)
            .count()
    };
    let mut covered: Vec<usize> = groups.iter().map(|g| own(&g.0)).collect();
    loop {
        let n = groups.len();
        let best_of = |sets: Vec<Vec<usize>>| {
            sets.into_iter()
                .filter_map(|set| {
                    let floor = set.iter().map(|&i| covered[i]).max().unwrap_or(0);
                    let arcs: Vec<&[usize]> = set.iter().map(|&i| groups[i].0.as_slice()).collect();
                    merge_gain(&arcs, floor, pts).map(|gain| (set, gain))
                })
                // the first of equal gains, as a strict `>` scan would keep
                .rev()
                .max_by_key(|(_, gain)| *gain)
        };
        let pairs = (0..n).flat_map(|i| (i + 1..n).map(move |j| vec![i, j]));
        let mut best = best_of(pairs.collect());
        if n <= MAX_SET_ARCS {
            for size in 3..=n {
                if best.is_some() {
                    break;
                }
                best = best_of(subsets(n, size));
            }
        }
        let Some((set, _)) = best else {
            return groups.into_iter().map(|g| g.1).collect();
        };
        // Highest index first, so the lower indices stay valid.
        let (first, rest) = set.split_first().expect("a set holds two arcs or more");
        for &j in rest.iter().rev() {
            let b = groups.swap_remove(j);
            covered.swap_remove(j);
            groups[*first].0.extend(b.0);
            groups[*first].1.extend(b.1);
        }
        covered[*first] = own(&groups[*first].0);
    }
}

/// An arc covering at most this many bins about the joint centre is a
/// fragment (see [`merge_gain`]).
const FRAGMENT_BINS: usize = 2;

/// Bins two arcs may share whatever their size: the bins of their ends
/// where they meet across a hole narrower than a bin.
const SHARED_END_BINS: Real = 2.0;

/// Sets of three or more arcs are tried only among at most this many
/// arcs (at most 219 sets; a slab of a body has a handful).
const MAX_SET_ARCS: usize = 8;

/// The `size`-element subsets of `0..n`, each ascending, in
/// lexicographic order.
fn subsets(n: usize, size: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut set: Vec<usize> = (0..size).collect();
    if size == 0 || size > n {
        return out;
    }
    loop {
        out.push(set.clone());
        // The last index that can still move right.
        let Some(i) = (0..size).rev().find(|&i| set[i] < n - size + i) else {
            return out;
        };
        set[i] += 1;
        for j in i + 1..size {
            set[j] = set[j - 1] + 1;
        }
    }
}

/// The centre used to order an arc: its fitted circle's centre, or its
/// centroid when the fit fails or lands far away.
fn arc_centre(members: &[usize], pts: &[Point2]) -> Vec2 {
    let n = members.len().max(1) as Real;
    let mean = members.iter().fold(Vec2::ZERO, |s, &m| s + pts[m]) / n;
    let rms = (members
        .iter()
        .map(|&m| (pts[m] - mean).norm_squared())
        .sum::<Real>()
        / n)
        .sqrt();
    circle_centre(members.iter().map(|&m| pts[m] - mean))
        .map(|c| c + mean)
        .filter(|c| (*c - mean).norm() < 3.0 * rms)
        .unwrap_or(mean)
}

/// `atan2(y, x)` to within 1e-5 rad (a degree-9 odd polynomial for the
/// arctangent on [0, 1] and octant folding): angles here only bin and
/// order points, and the library call is a large part of a slab's cost.
fn fast_atan2(y: Real, x: Real) -> Real {
    use std::f64::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = if ax > ay { (ay, ax) } else { (ax, ay) };
    if hi == 0.0 {
        return 0.0;
    }
    let t = lo / hi;
    let t2 = t * t;
    let mut a = t
        * (0.999_866_0
            + t2 * (-0.330_299_5 + t2 * (0.180_141_0 + t2 * (-0.085_133_0 + t2 * 0.020_835_1))));
    if ay > ax {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 {
        -a
    } else {
        a
    }
}

fn angle_bin(angle: Real) -> usize {
    let a = angle.rem_euclid(std::f64::consts::TAU);
    ((a / std::f64::consts::TAU * COVERAGE_BINS as Real) as usize).min(COVERAGE_BINS - 1)
}

/// Which 5° bins the offsets `d` (from a centre) fall in.
fn coverage(offsets: impl Iterator<Item = Vec2>) -> [bool; COVERAGE_BINS] {
    let mut bins = [false; COVERAGE_BINS];
    for d in offsets {
        bins[angle_bin(fast_atan2(d.y, d.x))] = true;
    }
    bins
}

/// The number of bins joining `arcs` adds beyond `floor` (the largest of
/// their own coverages), or `None` when they should not be joined (see
/// [`merge_arcs`]).
fn merge_gain(arcs: &[&[usize]], floor: usize, pts: &[Point2]) -> Option<usize> {
    let union: Vec<usize> = arcs.iter().flat_map(|a| a.iter().copied()).collect();
    let c = arc_centre(&union, pts);
    // (angle, radius, arc) about the joint centre.
    let mut polar: Vec<(Real, Real, usize)> = arcs
        .iter()
        .enumerate()
        .flat_map(|(which, a)| {
            a.iter().map(move |&m| {
                let d = pts[m] - c;
                (fast_atan2(d.y, d.x), d.norm_squared().sqrt(), which)
            })
        })
        .collect();
    let mut bins = vec![[false; COVERAGE_BINS]; arcs.len()];
    for &(angle, _, which) in &polar {
        bins[which][angle_bin(angle)] = true;
    }
    let count = |b: &[bool; COVERAGE_BINS]| b.iter().filter(|&&x| x).count();
    for x in 0..arcs.len() {
        for y in x + 1..arcs.len() {
            let overlap = bins[x]
                .iter()
                .zip(&bins[y])
                .filter(|(p, q)| **p && **q)
                .count();
            let smaller = count(&bins[x]).min(count(&bins[y])) as Real;
            if overlap as Real > (0.15 * smaller).max(SHARED_END_BINS) {
                return None;
            }
        }
    }
    let merged = (0..COVERAGE_BINS)
        .filter(|&k| bins.iter().any(|b| b[k]))
        .count();
    // A fragment a bin or two wide may add nothing to a loop nearly whole:
    // it joins on its radii and short holes alone, as a larger set does.
    let fragment = bins.iter().map(count).min().unwrap_or(0) <= FRAGMENT_BINS;
    let gain = merged.checked_sub(floor + if fragment { 0 } else { 2 })?;
    // Radii at the junctions, in angular order about c.
    polar.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
    let n = polar.len();
    let junctions: Vec<usize> = (0..n)
        .filter(|&k| polar[k].2 != polar[(k + 1) % n].2)
        .collect();
    if junctions.len() != arcs.len() {
        return None;
    }
    for &k in &junctions {
        let side = |from: isize, dir: isize| {
            let mut r: Vec<Real> = (0..5)
                .map(|s| polar[(from + dir * s).rem_euclid(n as isize) as usize].1)
                .collect();
            r.sort_by(Real::total_cmp);
            r[2]
        };
        let (r0, r1) = (side(k as isize, -1), side(k as isize + 1, 1));
        if (r0 - r1).abs() > 0.25 * r0.max(r1) {
            return None;
        }
    }
    if arcs.len() > 2 || fragment {
        // A loop broken more than once by small holes, or a fragment in
        // one: every hole short against the loop (a torso arc joined to an
        // arm's leaves a wide one).
        let at = |k: usize| {
            let (a, r, _) = polar[k % n];
            Vec2::new(r * a.cos(), r * a.sin())
        };
        let perimeter: Real = (0..n).map(|k| (at(k + 1) - at(k)).norm()).sum();
        if junctions
            .iter()
            .any(|&k| (at(k + 1) - at(k)).norm() > MAX_SET_GAP * perimeter)
        {
            return None;
        }
    }
    Some(gain)
}

/// The widest hole, as a fraction of the loop's perimeter, that a join of
/// three or more arcs may bridge.
const MAX_SET_GAP: Real = 0.02;

/// Orders by angle about the centre of the algebraic circle fit (falling
/// back to the centroid), one bin per cell of arc at the mean radius.
pub(super) fn order_by_angle(grid: &Grid, members: &[usize], pts: &[Point2]) -> Option<Vec<usize>> {
    let n = members.len() as Real;
    let centre = arc_centre(members, pts);
    let radius = members
        .iter()
        .map(|&m| (pts[m] - centre).norm())
        .sum::<Real>()
        / n;
    let bins = ((std::f64::consts::TAU * radius / grid.cell).round() as usize).max(8);
    let keys: Vec<(u32, usize)> = members
        .iter()
        .map(|&m| {
            let d = pts[m] - centre;
            let a = fast_atan2(d.y, d.x).rem_euclid(std::f64::consts::TAU);
            (
                ((a / std::f64::consts::TAU * bins as Real) as usize).min(bins - 1) as u32,
                m,
            )
        })
        .collect();
    let reps = representatives(keys, pts, grid.cell);
    (reps.len() >= 3).then_some(reps)
}

/// Kåsa's algebraic circle fit: least squares of
/// `x² + y² + D x + E y + F = 0`, centre `(−D/2, −E/2)`.
fn circle_centre(points: impl Iterator<Item = Vec2>) -> Option<Vec2> {
    let mut m = [[0.0; 3]; 3];
    let mut r = [0.0; 3];
    for p in points {
        let row = [p.x, p.y, 1.0];
        let z = -(p.x * p.x + p.y * p.y);
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += row[i] * row[j];
            }
            r[i] += row[i] * z;
        }
    }
    let flat: Vec<Real> = m.iter().flatten().copied().collect();
    let lu = crate::geom::linalg::Lu::factor(&flat, 3, PIVOT_EPS)?;
    let s = lu.solve(&r);
    let c = Vec2::new(-s[0] / 2.0, -s[1] / 2.0);
    c.is_finite().then_some(c)
}

/// A loop's gaps wider than `min_gap` that `unseen` accepts (given the
/// gap's two ends; between consecutive points, the last to the first
/// included) filled with points of the cubic Hermite
/// curve from the gap's start to its end, leaving and arriving along the
/// loop's directions there (each taken over `reach` of the loop) with the
/// gap's length as their magnitude, `step` apart. The loop with the fills
/// in place is returned, and the fills alone.
///
/// A side the scanner did not see (one camera's cloud has no back) is
/// closed the way the seen sides head, not by whatever a series fitted to
/// the seen arc does past its ends (a high order swings out by several
/// centimetres over a third of a loop).
pub fn bridge_gaps(
    points: &[Point3],
    min_gap: Real,
    reach: Real,
    step: Real,
    unseen: &dyn Fn(Point3, Point3) -> bool,
) -> (Vec<Point3>, Vec<Point3>) {
    let n = points.len();
    if n < 4 || !(step > 0.0) {
        return (points.to_vec(), Vec::new());
    }
    // The loop's direction at `i`, over `reach` backward (`back`) or
    // forward of it.
    let direction = |i: usize, back: bool| {
        let mut k = i;
        for _ in 1..n {
            let next = if back { (k + n - 1) % n } else { (k + 1) % n };
            k = next;
            if points[k].distance(points[i]) >= reach {
                break;
            }
        }
        let d = if back {
            points[i] - points[k]
        } else {
            points[k] - points[i]
        };
        d.normalized()
    };
    let (mut out, mut fills) = (Vec::with_capacity(n), Vec::new());
    for i in 0..n {
        let (p0, p1) = (points[i], points[(i + 1) % n]);
        out.push(p0);
        let chord = p1.distance(p0);
        if !(chord > min_gap) || !unseen(p0, p1) {
            continue;
        }
        let (Some(t0), Some(t1)) = (direction(i, true), direction((i + 1) % n, false)) else {
            continue;
        };
        let (t0, t1) = (t0 * chord, t1 * chord);
        let count = (chord / step).ceil() as usize;
        for k in 1..count {
            let t = k as Real / count as Real;
            let (t2, t3) = (t * t, t * t * t);
            let p = p0 * (2.0 * t3 - 3.0 * t2 + 1.0)
                + t0 * (t3 - 2.0 * t2 + t)
                + p1 * (-2.0 * t3 + 3.0 * t2)
                + t1 * (t3 - t2);
            out.push(p);
            fills.push(p);
        }
    }
    (out, fills)
}

/// The horizontal direction a cloud was not seen from, when it was seen
/// from one side only (one depth camera: no back), else `None`.
///
/// `slabs`: horizontal slabs through the trunk, each a set of points in
/// its plane. About the slab's centroid its points fill the 5° bins of
/// [`coverage`]; a slab with an empty run of at least 60°
/// votes for the middle of that run. The cloud is one-sided when at
/// least 70 % of the slabs vote and their votes agree (the mean of the
/// unit votes at least 0.8 long). A scanner all around leaves holes
/// (armpits, the crotch), not a side of the trunk.
pub fn unseen_side(slabs: &[Vec<Point2>]) -> Option<Vec2> {
    let mut votes = Vec::new();
    for pts in slabs.iter().filter(|p| p.len() >= 12) {
        let c = pts.iter().fold(Vec2::ZERO, |a, &p| a + p) * (1.0 / pts.len() as Real);
        let full = coverage(pts.iter().map(|&p| p - c));
        // The longest cyclic run of empty bins.
        let Some(start) = (0..COVERAGE_BINS).find(|&k| full[k]) else {
            continue;
        };
        let (mut best, mut run) = ((0, 0), 0);
        for k in 1..=COVERAGE_BINS {
            let b = (start + k) % COVERAGE_BINS;
            if full[b] {
                run = 0;
            } else {
                run += 1;
                if run > best.1 {
                    best = (b, run);
                }
            }
        }
        if best.1 * 6 >= COVERAGE_BINS {
            let mid = best.0 as Real + 0.5 - 0.5 * best.1 as Real;
            let a = mid / COVERAGE_BINS as Real * std::f64::consts::TAU;
            votes.push(Vec2::new(a.cos(), a.sin()));
        }
    }
    let voted = slabs.iter().filter(|p| p.len() >= 12).count();
    if voted == 0 || (votes.len() as Real) < 0.7 * voted as Real {
        return None;
    }
    let mean = votes.iter().fold(Vec2::ZERO, |a, &v| a + v) * (1.0 / votes.len() as Real);
    if mean.norm() >= 0.8 {
        mean.normalized()
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    #[test]
    fn fast_atan2_is_accurate() {
        for k in 0..10_000 {
            let a = -PI + TAU * k as Real / 10_000.0;
            for r in [1e-6, 1.0, 1e6] {
                let (y, x) = (r * a.sin(), r * a.cos());
                let d = (fast_atan2(y, x) - y.atan2(x) + PI).rem_euclid(TAU) - PI;
                assert!(d.abs() < 2e-5, "{a}: {d}");
            }
        }
        assert_eq!(fast_atan2(0.0, 0.0), 0.0);
    }

    fn circle(r: Real, from: Real, to: Real, n: usize) -> Vec<Point3> {
        (0..n)
            .map(|k| {
                let a = from + (to - from) * k as Real / (n - 1) as Real;
                Point3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect()
    }

    #[test]
    fn a_third_of_a_circle_unseen_is_bridged_near_the_circle() {
        use std::f64::consts::PI;
        let arc = circle(0.1, 0.0, 4.0 * PI / 3.0, 120);
        let step = arc[0].distance(arc[1]);
        let (all, fills) = bridge_gaps(&arc, 0.02, 0.01, step, &|_, _| true);
        assert_eq!(all.len(), arc.len() + fills.len());
        // The gap is the chord of 120°: 0.173 long, a point every `step`.
        assert!(fills.len() >= 40, "{}", fills.len());
        for p in &fills {
            let r = p.norm();
            assert!((r - 0.1).abs() < 0.012, "{r}");
            assert!(p.y < 0.0, "{p:?}");
        }
        // Gaps the caller does not call unseen, and narrower ones, stay.
        assert!(bridge_gaps(&arc, 0.02, 0.01, step, &|_, _| false)
            .1
            .is_empty());
        assert!(bridge_gaps(&arc, 0.2, 0.01, step, &|_, _| true)
            .1
            .is_empty());
    }

    fn slab(r: Real, skip: impl Fn(Real) -> bool) -> Vec<Point2> {
        (0..360)
            .map(|k| (k as Real).to_radians())
            .filter(|&a| !skip(a))
            .map(|a| Point2::new(1.5 * r * a.cos(), r * a.sin()))
            .collect()
    }

    #[test]
    fn a_trunk_seen_from_one_side_is_told_from_one_with_holes() {
        use std::f64::consts::PI;
        // The back (about −y) missing over 120° at every level.
        let back = |a: Real| (a - 1.5 * PI).abs() < PI / 3.0;
        let one_sided: Vec<Vec<Point2>> = (0..10).map(|_| slab(0.12, back)).collect();
        let side = unseen_side(&one_sided).unwrap();
        assert!(side.dot(Vec2::new(0.0, -1.0)) > 0.99, "{side:?}");
        // All round with 20° holes (an armpit's, the crotch's): not one-sided.
        let holes: Vec<Vec<Point2>> = (0..10)
            .map(|k| slab(0.12, |a| (a - k as Real * 0.6).abs() < 0.17))
            .collect();
        assert_eq!(unseen_side(&holes), None);
        // Wide gaps facing every way: a cloud with holes, not one camera's.
        let scattered: Vec<Vec<Point2>> = (0..10)
            .map(|k| slab(0.12, |a| (a - k as Real * 0.63).abs() < PI / 3.0))
            .collect();
        assert_eq!(unseen_side(&scattered), None);
    }
}
