//! Pockets of a section loop behind a mouth, bridged.
//!
//! Where a surface folds in through a slit into a pocket (the lips of a
//! mesh that models the mouth's inside), a plane cut can follow the fold:
//! the loop runs in through the slit, round the pocket and out again, a
//! C where its neighbours are an O (a plane along a tilted head's lips
//! meets them 40 mm apart). A trigonometric curve follows the C and the
//! surface skinned through it cuts through the head; no scanner sees into
//! the pocket. [`bridge_inlets`] replaces each such excursion by the
//! straight segment across its mouth.
//!
//! An **inlet** is a run of the loop from point `i` to point `j` which
//! turns *into* the loop: closed by the chord `j → i` it encloses a
//! region (the pocket) in the sense opposite to the loop's, so cutting it
//! off adds the pocket to the loop. Of the two runs between `i` and `j`
//! at most one can (their signed areas add up to the loop's); a pocket's
//! lining can be half the loop or more. It is bridged when the pocket
//! holds at least [`MIN_POCKET`] times the chord squared (deeper than
//! wide: not a concave stretch of the outline, the notch under a chin)
//! and a given share of the loop's area, and at most the loop's area
//! (not inside the part: a slit between a limb's loop and the trunk it
//! wraps). Its mouth is then at most `√(area / MIN_POCKET)` wide, which
//! bounds the pairs searched. A protrusion (an ear, a thumb) turns the
//! loop's way and stays. The largest pockets are taken first; one inside
//! or overlapping a pocket already taken is skipped.

use crate::geom::math::{Point2, Real};
use crate::section::mesh::{push_between, SectionLoop};
use std::collections::HashMap;

/// An inlet's pocket holds at least this many times its mouth's width
/// squared: a V notch six times deeper than wide, a slot three.
pub const MIN_POCKET: Real = 3.0;

/// `section` with every inlet whose pocket holds at least `min_share` of
/// the loop's area (and the module doc's other bounds) replaced by its
/// mouth's segment, and how many were bridged. The loop itself (cloned)
/// when it has none.
pub fn bridge_inlets(section: &SectionLoop, min_share: Real) -> (SectionLoop, usize) {
    let n = section.points.len();
    let mouth = (section.area / MIN_POCKET).sqrt();
    if n < 4 || !(mouth > 0.0) {
        return (section.clone(), 0);
    }
    let plane = section.plane_points();
    let inlets = inlets(&plane, mouth, min_share);
    if inlets.is_empty() {
        return (section.clone(), 0);
    }
    let mut cut = vec![false; n];
    for &(i, j) in &inlets {
        run(i, j, n)
            .filter(|&k| k != i && k != j)
            .for_each(|k| cut[k] = true);
    }
    let step = section.median_edge();
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        if cut[k] {
            continue;
        }
        let a = section.points[k];
        out.push(a);
        // The mouth: from here to the inlet's far end, at the loop's
        // median spacing.
        if let Some(&(_, j)) = inlets.iter().find(|(i, _)| *i == k) {
            push_between(&mut out, a, section.points[j], step);
        }
    }
    let (e1, e2) = (section.frame.e1, section.frame.e2);
    match SectionLoop::from_points(out, e1, e2) {
        Some(l) => (l, inlets.len()),
        None => (section.clone(), 0),
    }
}

/// The inlets `(i, j)` of the polygon `p` (module doc; either turning
/// sense) whose mouths are at most `mouth` wide: the run from `i` forward
/// to `j`, both kept, wrapping past the end.
fn inlets(p: &[Point2], mouth: Real, min_share: Real) -> Vec<(usize, usize)> {
    let n = p.len();
    // Prefix shoelace sums over the doubled index range,
    // so a run wrapping past the end is one difference.
    let at = |k: usize| p[k % n];
    let mut cross = vec![0.0; 2 * n + 1];
    for k in 0..2 * n {
        let (a, b) = (at(k), at(k + 1));
        cross[k + 1] = cross[k] + (a.x * b.y - a.y * b.x);
    }
    // The loop's own turning sense (its plane axes may be either way).
    let orientation = cross[n].signum();
    let area = 0.5 * cross[n].abs();
    let key = |q: Point2| ((q.x / mouth).floor() as i64, (q.y / mouth).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (k, &q) in p.iter().enumerate() {
        grid.entry(key(q)).or_default().push(k);
    }
    let mut found: Vec<(Real, usize, usize)> = Vec::new();
    for (i, &a) in p.iter().enumerate() {
        let (cx, cy) = key(a);
        for dx in -1..=1 {
            for dy in -1..=1 {
                let Some(cell) = grid.get(&(cx + dx, cy + dy)) else {
                    continue;
                };
                for &j in cell {
                    let chord = (p[j] - a).norm();
                    if j == i || chord > mouth {
                        continue;
                    }
                    // The run from i forward to j, closed by the chord.
                    let end = if j > i { j } else { j + n };
                    let b = p[j];
                    let twice_area = cross[end] - cross[i] + (b.x * a.y - b.y * a.x);
                    let pocket = -0.5 * twice_area * orientation;
                    let deep = pocket >= MIN_POCKET * chord * chord;
                    if pocket > 0.0 && deep && (min_share * area..=area).contains(&pocket) {
                        found.push((pocket, i, j));
                    }
                }
            }
        }
    }
    found.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
    let mut taken = vec![false; n];
    let mut out = Vec::new();
    for (_, i, j) in found {
        // The run's points, ends included, must all be free.
        if run(i, j, n).any(|k| taken[k]) {
            continue;
        }
        run(i, j, n).for_each(|k| taken[k] = true);
        out.push((i, j));
    }
    out
}

/// The indices of the run from `i` forward to `j` (both included) round a
/// loop of `n` points.
fn run(i: usize, j: usize, n: usize) -> impl Iterator<Item = usize> {
    let len = (j + n - i) % n;
    (0..=len).map(move |s| (i + s) % n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::math::{Point3, Vec3};

    fn section(points: &[(Real, Real)]) -> SectionLoop {
        let pts = points
            .iter()
            .map(|&(x, y)| Point3::new(x, y, 0.0))
            .collect();
        SectionLoop::from_points(pts, Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)).unwrap()
    }

    /// A 100 × 100 square with a slit `gap` wide going `depth` in from the
    /// middle of its top side and a 40 × 30 chamber at its bottom (a mouth
    /// and its pocket), counter-clockwise.
    fn mouth(gap: Real, depth: Real) -> Vec<(Real, Real)> {
        let (l, r) = (50.0 - gap / 2.0, 50.0 + gap / 2.0);
        let bottom = 100.0 - depth;
        vec![
            (0.0, 0.0),
            (100.0, 0.0),
            (100.0, 100.0),
            (r, 100.0),
            (r, bottom + 30.0),
            (70.0, bottom + 30.0),
            (70.0, bottom),
            (30.0, bottom),
            (30.0, bottom + 30.0),
            (l, bottom + 30.0),
            (l, 100.0),
            (0.0, 100.0),
        ]
    }

    #[test]
    fn a_mouth_through_a_slit_is_closed_over() {
        // The pocket, 2 × 50 + 40 × 30 = 1300, is 15 % of the loop's 8700.
        let s = section(&mouth(2.0, 80.0));
        let (b, count) = bridge_inlets(&s, 0.1);
        assert_eq!(count, 1);
        assert!((b.area - 10_000.0).abs() < 1e-9, "{}", b.area);
        let on_square = |p: &Point3| p.x == 0.0 || p.x == 100.0 || p.y == 0.0 || p.y == 100.0;
        assert!(b.points.iter().all(on_square));
        // A mouth 12 wide: 1800 is still 12.5 times 12².
        assert_eq!(bridge_inlets(&section(&mouth(12.0, 80.0)), 0.1).1, 1);
    }

    #[test]
    fn a_pocket_under_the_share_stays() {
        let s = section(&mouth(2.0, 80.0));
        assert_eq!(bridge_inlets(&s, 0.14).1, 1);
        assert_eq!(bridge_inlets(&s, 0.16).1, 0);
        // A slot 3 wide and 20 deep (the gap between two toes): 0.6 %.
        let slot = [
            (0.0, 0.0),
            (100.0, 0.0),
            (100.0, 100.0),
            (51.5, 100.0),
            (51.5, 80.0),
            (48.5, 80.0),
            (48.5, 100.0),
            (0.0, 100.0),
        ];
        assert_eq!(bridge_inlets(&section(&slot), 0.1).1, 0);
        assert_eq!(bridge_inlets(&section(&slot), 0.0).1, 1);
    }

    #[test]
    fn a_protrusion_a_wide_notch_or_a_convex_loop_stays() {
        // An ear-like flap standing out of the square's top.
        let flap = [
            (0.0, 0.0),
            (100.0, 0.0),
            (100.0, 100.0),
            (51.0, 100.0),
            (51.0, 150.0),
            (70.0, 150.0),
            (70.0, 180.0),
            (30.0, 180.0),
            (30.0, 150.0),
            (49.0, 150.0),
            (49.0, 100.0),
            (0.0, 100.0),
        ];
        let s = section(&flap);
        let (b, count) = bridge_inlets(&s, 0.0);
        assert_eq!(count, 0);
        assert_eq!(b, s);
        // A V notch 40 wide and 60 deep, 12 % of the loop: 1200 < 3 × 40².
        let notch = [
            (0.0, 0.0),
            (100.0, 0.0),
            (100.0, 100.0),
            (70.0, 100.0),
            (50.0, 40.0),
            (30.0, 100.0),
            (0.0, 100.0),
        ];
        assert_eq!(bridge_inlets(&section(&notch), 0.1).1, 0);
        let circle: Vec<(Real, Real)> = (0..200)
            .map(|k| {
                let t = k as Real / 200.0 * std::f64::consts::TAU;
                (50.0 * t.cos(), 50.0 * t.sin())
            })
            .collect();
        assert_eq!(bridge_inlets(&section(&circle), 0.0).1, 0);
    }

    #[test]
    fn an_inlet_across_the_first_point_is_found() {
        // The slit's run wraps past the polygon's start.
        let mut pts = mouth(2.0, 80.0);
        pts.rotate_left(6);
        let (b, count) = bridge_inlets(&section(&pts), 0.1);
        assert_eq!(count, 1);
        assert!((b.area - 10_000.0).abs() < 1e-9);
    }
}
