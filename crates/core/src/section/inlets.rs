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
//!
//! An [`InletRule`] may also take smaller, shallower pockets whose mouth
//! opens towards a given direction ([`Facing`]: a head's eye sockets open
//! to the front, the folds at its ears sideways or back). The pockets
//! bridged are returned too, each its lining closed by its mouth: the
//! caller may line them (a head's cavities).

use crate::geom::math::{Point2, Real, Vec2, Vec3};
use crate::section::mesh::{push_between, SectionLoop};
use std::collections::HashMap;

/// An inlet's pocket holds at least this many times its mouth's width
/// squared: a V notch six times deeper than wide, a slot three.
pub const MIN_POCKET: Real = 3.0;

/// Which pockets [`bridge_inlets`] bridges besides the module doc's
/// bounds: those holding at least `min_share` of the loop's area, and,
/// when `facing` is given, also those holding at least its `min_share`
/// whose mouth faces its direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InletRule {
    pub min_share: Real,
    pub facing: Option<Facing>,
}

/// Smaller pockets bridged where their mouth opens towards `dir` (within
/// [`FACING_COS`]: the direction from the pocket's centroid to its mouth's
/// middle, in the loop's plane): at least `min_share` of the loop, and
/// `min_pocket` (instead of [`MIN_POCKET`]) times the mouth's width
/// squared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facing {
    pub dir: Vec3,
    pub min_share: Real,
    pub min_pocket: Real,
}

/// A mouth faces a direction within 45°.
pub const FACING_COS: Real = std::f64::consts::FRAC_1_SQRT_2;

/// `section` with every inlet whose pocket `rule` takes (and the module
/// doc's other bounds) replaced by its mouth's segment, and the pockets
/// bridged (each its run of the loop, closed by the mouth). The loop
/// itself (cloned) when it has none.
pub fn bridge_inlets(section: &SectionLoop, rule: &InletRule) -> (SectionLoop, Vec<SectionLoop>) {
    let n = section.points.len();
    let depth = rule
        .facing
        .map_or(MIN_POCKET, |f| f.min_pocket.min(MIN_POCKET));
    let mouth = (section.area / depth).sqrt();
    if n < 4 || !(mouth > 0.0) {
        return (section.clone(), Vec::new());
    }
    let plane = section.plane_points();
    // The facing direction in the loop's plane, when it has one there.
    let facing = rule.facing.and_then(|f| {
        let (e1, e2) = (section.frame.e1, section.frame.e2);
        let d = Vec2::new(f.dir.dot(e1), f.dir.dot(e2));
        (d.norm() > 0.5 * f.dir.norm()).then(|| (d / d.norm(), f.min_share, f.min_pocket))
    });
    let shares = Shares {
        min_share: rule.min_share,
        facing,
    };
    let inlets = inlets(&plane, mouth, &shares);
    if inlets.is_empty() {
        return (section.clone(), Vec::new());
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
    let Some(bridged) = SectionLoop::from_points(out, e1, e2) else {
        return (section.clone(), Vec::new());
    };
    let pockets = inlets
        .iter()
        .filter_map(|&(i, j)| {
            let lining: Vec<_> = run(i, j, n).map(|k| section.points[k]).collect();
            SectionLoop::from_points(lining, e1, e2)
        })
        .collect();
    (bridged, pockets)
}

/// [`InletRule`] in a loop's plane: the facing direction a unit vector.
struct Shares {
    min_share: Real,
    /// The direction, its share and its depth ratio.
    facing: Option<(Vec2, Real, Real)>,
}

/// The inlets `(i, j)` of the polygon `p` (module doc; either turning
/// sense) whose mouths are at most `mouth` wide: the run from `i` forward
/// to `j`, both kept, wrapping past the end.
fn inlets(p: &[Point2], mouth: Real, shares: &Shares) -> Vec<(usize, usize)> {
    let n = p.len();
    // Prefix shoelace sums (and the first moments the centroid needs) over
    // the doubled index range, so a run wrapping past the end is one
    // difference.
    let at = |k: usize| p[k % n];
    let mut cross = vec![0.0; 2 * n + 1];
    let mut moment = vec![Vec2::ZERO; 2 * n + 1];
    for k in 0..2 * n {
        let (a, b) = (at(k), at(k + 1));
        let c = a.x * b.y - a.y * b.x;
        cross[k + 1] = cross[k] + c;
        moment[k + 1] = moment[k] + (a + b) * c;
    }
    let min_share = shares
        .facing
        .map_or(shares.min_share, |f| f.1.min(shares.min_share));
    let min_pocket = shares.facing.map_or(MIN_POCKET, |f| f.2.min(MIN_POCKET));
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
                    let closing = b.x * a.y - b.y * a.x;
                    let twice_area = cross[end] - cross[i] + closing;
                    let pocket = -0.5 * twice_area * orientation;
                    let squared = chord * chord;
                    let deep = pocket >= min_pocket * squared;
                    if !(pocket > 0.0 && deep && (min_share * area..=area).contains(&pocket)) {
                        continue;
                    }
                    let taken = (pocket >= shares.min_share * area
                        && pocket >= MIN_POCKET * squared)
                        || shares.facing.is_some_and(|(dir, share, depth)| {
                            // From the pocket's centroid to its mouth.
                            let centroid =
                                (moment[end] - moment[i] + (b + a) * closing) / (3.0 * twice_area);
                            let out = (a + b) * 0.5 - centroid;
                            pocket >= share * area
                                && pocket >= depth * squared
                                && out.dot(dir) >= FACING_COS * out.norm()
                        });
                    if taken {
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

    /// Pockets holding at least `min_share` of the loop, whichever way
    /// they open.
    fn share(min_share: Real) -> InletRule {
        InletRule {
            min_share,
            facing: None,
        }
    }

    fn section(points: &[(Real, Real)]) -> SectionLoop {
        let pts = points
            .iter()
            .map(|&(x, y)| Point3::new(x, y, 0.0))
            .collect();
        SectionLoop::from_points(pts, Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)).unwrap()
    }

    /// A 100 × 100 square with a slit `gap` wide going `neck` in from the
    /// middle of its top side into a `width` × `height` chamber (a mouth
    /// and its pocket), counter-clockwise.
    fn slit(gap: Real, neck: Real, width: Real, height: Real) -> Vec<(Real, Real)> {
        let (l, r) = (50.0 - gap / 2.0, 50.0 + gap / 2.0);
        let (cl, cr) = (50.0 - width / 2.0, 50.0 + width / 2.0);
        let (top, bottom) = (100.0 - neck, 100.0 - neck - height);
        vec![
            (0.0, 0.0),
            (100.0, 0.0),
            (100.0, 100.0),
            (r, 100.0),
            (r, top),
            (cr, top),
            (cr, bottom),
            (cl, bottom),
            (cl, top),
            (l, top),
            (l, 100.0),
            (0.0, 100.0),
        ]
    }

    /// [`slit`] `depth` deep to the bottom of a 40 × 30 chamber.
    fn mouth(gap: Real, depth: Real) -> Vec<(Real, Real)> {
        slit(gap, depth - 30.0, 40.0, 30.0)
    }

    #[test]
    fn a_mouth_through_a_slit_is_closed_over() {
        // The pocket, 2 × 50 + 40 × 30 = 1300, is 15 % of the loop's 8700.
        let s = section(&mouth(2.0, 80.0));
        let (b, pockets) = bridge_inlets(&s, &share(0.1));
        assert_eq!(pockets.len(), 1);
        assert!((b.area - 10_000.0).abs() < 1e-9, "{}", b.area);
        // The pocket: its lining closed by the mouth.
        assert!(
            (pockets[0].area - 1300.0).abs() < 1e-9,
            "{}",
            pockets[0].area
        );
        let on_square = |p: &Point3| p.x == 0.0 || p.x == 100.0 || p.y == 0.0 || p.y == 100.0;
        assert!(b.points.iter().all(on_square));
        // A mouth 12 wide: 1800 is still 12.5 times 12².
        assert_eq!(
            bridge_inlets(&section(&mouth(12.0, 80.0)), &share(0.1))
                .1
                .len(),
            1
        );
    }

    #[test]
    fn a_pocket_under_the_share_stays() {
        let s = section(&mouth(2.0, 80.0));
        assert_eq!(bridge_inlets(&s, &share(0.14)).1.len(), 1);
        assert_eq!(bridge_inlets(&s, &share(0.16)).1.len(), 0);
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
        assert_eq!(bridge_inlets(&section(&slot), &share(0.1)).1.len(), 0);
        assert_eq!(bridge_inlets(&section(&slot), &share(0.0)).1.len(), 1);
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
        let (b, pockets) = bridge_inlets(&s, &share(0.0));
        assert_eq!(pockets.len(), 0);
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
        assert_eq!(bridge_inlets(&section(&notch), &share(0.1)).1.len(), 0);
        let circle: Vec<(Real, Real)> = (0..200)
            .map(|k| {
                let t = k as Real / 200.0 * std::f64::consts::TAU;
                (50.0 * t.cos(), 50.0 * t.sin())
            })
            .collect();
        assert_eq!(bridge_inlets(&section(&circle), &share(0.0)).1.len(), 0);
    }

    /// An eye socket: a slit 2 wide and 10 deep in the top side into a
    /// 16 × 14 chamber, 2.5 % of the loop. Under the plain share it stays;
    /// with a facing rule it is bridged when the rule's direction is the
    /// way the slit opens (+y, or within 45° of it), not across or against.
    #[test]
    fn a_small_pocket_is_bridged_only_where_it_faces_the_rule() {
        let eye = slit(2.0, 10.0, 16.0, 14.0);
        let s = section(&eye);
        assert_eq!(bridge_inlets(&s, &share(0.1)).1.len(), 0);
        let facing = |x: Real, y: Real| InletRule {
            min_share: 0.1,
            facing: Some(Facing {
                dir: Vec3::new(x, y, 0.0),
                min_share: 0.005,
                min_pocket: MIN_POCKET,
            }),
        };
        let (b, pockets) = bridge_inlets(&s, &facing(0.0, 1.0));
        assert_eq!(pockets.len(), 1);
        assert!((b.area - 10_000.0).abs() < 1e-9, "{}", b.area);
        assert_eq!(bridge_inlets(&s, &facing(0.6, 1.0)).1.len(), 1);
        assert_eq!(bridge_inlets(&s, &facing(1.0, 0.0)).1.len(), 0);
        assert_eq!(bridge_inlets(&s, &facing(0.0, -1.0)).1.len(), 0);
        // A direction along the plane's normal says nothing here.
        let normal = InletRule {
            min_share: 0.1,
            facing: Some(Facing {
                dir: Vec3::new(0.0, 0.1, 1.0),
                min_share: 0.005,
                min_pocket: MIN_POCKET,
            }),
        };
        assert_eq!(bridge_inlets(&s, &normal).1.len(), 0);
        // Where the lids part widest: a 12 wide mouth 4 deep over a
        // 16 × 10 cup, 208 = 1.4 times its width squared. A facing rule's
        // own depth ratio takes it; the plain one (3) does not.
        let cup = slit(12.0, 4.0, 16.0, 10.0);
        let s = section(&cup);
        let with_depth = |min_pocket: Real| InletRule {
            min_share: 0.1,
            facing: Some(Facing {
                dir: Vec3::new(0.0, 1.0, 0.0),
                min_share: 0.005,
                min_pocket,
            }),
        };
        assert_eq!(bridge_inlets(&s, &with_depth(MIN_POCKET)).1.len(), 0);
        assert_eq!(bridge_inlets(&s, &with_depth(1.0)).1.len(), 1);
    }

    #[test]
    fn an_inlet_across_the_first_point_is_found() {
        // The slit's run wraps past the polygon's start.
        let mut pts = mouth(2.0, 80.0);
        pts.rotate_left(6);
        let (b, pockets) = bridge_inlets(&section(&pts), &share(0.1));
        assert_eq!(pockets.len(), 1);
        assert!((b.area - 10_000.0).abs() < 1e-9);
    }
}
