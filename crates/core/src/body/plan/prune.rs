//! Pruning (issue 17's allocation of numbers to where the surface needs
//! them): a section the skinning of its neighbours reproduces is dropped.
//!
//! Removing section `k` changes the tangents at its two neighbours, so
//! the three segments from the second neighbour before it to the second
//! after it change, and nothing else. A trial rebuilds those segments
//! from the kept sections around `k` (three each side, so the tangents
//! of the segments' ends are the whole part's) and measures every section
//! already dropped in that span and `k` itself against the new surface:
//! the [`stray`] of its loop from the surface's curve where the centre
//! line crosses the loop's plane ([`Part::s_at_level`]), less
//! the stray from its own fitted curve (the fit's own error, a scan's
//! noise). A section goes when that excess stays within the tolerance for
//! all of them. Trials run over the cores; the lowest excesses are taken
//! first (in steps of a 32nd of the tolerance, then along the part, so
//! that a rounding does not change the choice), four kept sections apart
//! (their spans do not overlap), and the rounds repeat until nothing more
//! goes. The three sections at each end and the torso loops clipped at an
//! arm are never removed ([`keep_after_pruning`]).

use super::*;
use crate::geom::math::Vec2;
use crate::geom::parallel::parallel_map;

/// Kept sections each side of a trial: enough for the changed segments'
/// outer tangents to be the whole part's.
const REACH: usize = 3;

/// The most loop points a trial measures per loop.
const POINTS: usize = 96;

/// The sections at each end that set the part's end tangent (the
/// parabola's through the first or last three curves), along which its
/// cap or transition leaves it: they are never removed (a raised hand's
/// dome, its end tangent turned by a removal, overshot the fingertips by
/// 35 mm on body_010).
const END_TANGENT: usize = 3;

/// Which of `cuts` to keep: the three at each end always, a torso loop
/// clipped at an arm (where the arm's transition lands on the torso; the
/// far area at the armpits grows without them), and every other one
/// unless its removal (with the ones already removed) keeps every
/// removed loop within `tol` of the surface beyond its own fit's stray.
/// All kept for `tol ≤ 0`.
pub(in crate::body) fn keep_after_pruning(
    cuts: &[Cut],
    options: &PartOptions,
    tol: Real,
) -> Vec<bool> {
    let n = cuts.len();
    let mut kept = vec![true; n];
    if n < 3 || !(tol > 0.0) {
        return kept;
    }
    // Every loop's points, at most [`POINTS`] of them evenly by index: a
    // percentile needs no more, and the trials measure many loops.
    let points: Vec<Vec<Vec2>> = cuts
        .iter()
        .map(|c| {
            let p = &c.fit.plane_points;
            let step = p.len().div_ceil(POINTS).max(1);
            p.iter().step_by(step).copied().collect()
        })
        .collect();
    let own: Vec<Real> = (0..n)
        .map(|i| {
            let c = &cuts[i].fit.curve;
            stray_of(&c.frame, &points[i], &c.world_series())
        })
        .collect();
    let local = PartOptions {
        start_cap: CapKind::Open,
        end_cap: CapKind::Open,
        ..*options
    };
    let trials = Trials {
        cuts,
        points: &points,
        own: &own,
        options: &local,
    };
    // A trial's excess, with the span of cuts it depends on: kept until
    // a cut in that span is removed.
    let mut known: Vec<Option<(Real, usize, usize)>> = vec![None; n];
    loop {
        let live: Vec<usize> = (0..n).filter(|&i| kept[i]).collect();
        if live.len() < 3 {
            break;
        }
        let candidates: Vec<usize> = (END_TANGENT..live.len().saturating_sub(END_TANGENT))
            .filter(|&k| cuts[live[k]].clips.is_empty())
            .collect();
        let fresh: Vec<usize> = candidates
            .iter()
            .copied()
            .filter(|&k| known[live[k]].is_none())
            .collect();
        let found: Vec<Real> = parallel_map(&fresh, 4, |run| {
            run.iter()
                .map(|&k| trials.excess(&live, k, &kept))
                .collect()
        });
        for (&k, e) in fresh.iter().zip(found) {
            let span = (
                live[k.saturating_sub(REACH)],
                live[(k + REACH).min(live.len() - 1)],
            );
            known[live[k]] = Some((e, span.0, span.1));
        }
        let excess: Vec<Real> = candidates
            .iter()
            .map(|&k| known[live[k]].map_or(Real::INFINITY, |(e, ..)| e))
            .collect();
        let mut order: Vec<usize> = (0..candidates.len())
            .filter(|&j| excess[j] <= tol)
            .collect();
        // Lowest excess first, in steps of a 32nd of the tolerance and then
        // along the part: excesses a rounding apart (the same body turned)
        // choose the same sections.
        let step = |j: usize| (excess[j].max(0.0) * 32.0 / tol).floor() as u64;
        order.sort_by_key(|&j| (step(j), j));
        let mut taken: Vec<usize> = Vec::new();
        for j in order {
            let k = candidates[j];
            if taken.iter().all(|&t| t.abs_diff(k) > REACH) {
                taken.push(k);
            }
        }
        if taken.is_empty() {
            break;
        }
        for k in taken {
            let r = live[k];
            kept[r] = false;
            for slot in known.iter_mut() {
                if slot.is_some_and(|(_, lo, hi)| lo <= r && r <= hi) {
                    *slot = None;
                }
            }
        }
    }
    kept
}

/// The part `built` from `plan`'s cuts, without those the pruning drops
/// ([`keep_after_pruning`] at [`ReconstructOptions::prune_tolerance`] ×
/// `height`): rebuilt from the rest, or `built` itself when none goes.
pub(in crate::body) fn pruned(
    built: BodyPart,
    mut plan: Plan,
    opts: &ReconstructOptions,
    scan: bool,
    height: Real,
    warnings: &mut Vec<String>,
) -> Result<BodyPart, ReconstructError> {
    let keep = keep_after_pruning(&plan.cuts, &opts.part, opts.prune_tolerance * height);
    if keep.iter().all(|&k| k) {
        return Ok(built);
    }
    let mut k = 0;
    plan.cuts.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    Ok(build_part(plan, opts, scan, None, warnings)?.0)
}

struct Trials<'a> {
    cuts: &'a [Cut],
    points: &'a [Vec<Vec2>],
    own: &'a [Real],
    options: &'a PartOptions,
}

impl Trials<'_> {
    /// The largest excess stray, over `live[k]` and the removed cuts in
    /// the span its removal changes, of the surface without `live[k]`
    /// (infinite where that surface cannot be built).
    fn excess(&self, live: &[usize], k: usize, kept: &[bool]) -> Real {
        let lo = k.saturating_sub(REACH);
        let hi = (k + REACH).min(live.len() - 1);
        let local: Vec<usize> = (lo..=hi).filter(|&m| m != k).map(|m| live[m]).collect();
        let curves: Vec<TrigCurve> = local
            .iter()
            .map(|&i| self.cuts[i].fit.curve.clone())
            .collect();
        let Ok(part) = Part::new(curves, self.options) else {
            return Real::INFINITY;
        };
        // The changed span: from the second kept section before to the
        // second after.
        let (from, to) = (live[k.saturating_sub(2)], live[(k + 2).min(live.len() - 1)]);
        let mut worst: Real = 0.0;
        for r in from + 1..to {
            if kept[r] && r != live[k] {
                continue;
            }
            // The surface's curve where its centre line crosses the loop's
            // plane.
            let frame = &self.cuts[r].fit.curve.frame;
            let normal = frame.normal();
            let Some(s) = part.s_at_level(normal, frame.origin.dot(normal)) else {
                return Real::INFINITY;
            };
            let (m, u) = part.locate(s);
            let curve = part.segments()[m].patch.curve_at(u);
            let d = stray_of(frame, &self.points[r], &curve) - self.own[r];
            worst = worst.max(d);
        }
        worst
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::fit::fit_loop_2d;
    use crate::curve::trig::Frame;
    use crate::geom::math::Vec2;

    /// Sections of the surface of revolution of `radius` about z at the
    /// heights `zs` (64 points a loop,
    /// each curve fitted nearly exactly, in its own plane z = const).
    fn sections(zs: &[Real], radius: impl Fn(Real) -> Real) -> Vec<Cut> {
        zs.iter()
            .enumerate()
            .map(|(k, &z)| {
                let r = radius(z);
                let pts: Vec<Vec2> = (0..64)
                    .map(|i| {
                        let t = std::f64::consts::TAU * i as Real / 64.0;
                        Vec2::new(r * t.cos(), 0.7 * r * t.sin())
                    })
                    .collect();
                let tight = FitOptions {
                    ea: 1e-6,
                    em: 1e-5,
                    ..FitOptions::default()
                };
                let mut fit = fit_loop_2d(&pts, &tight).unwrap();
                let f = fit.curve.frame;
                let frame = Frame {
                    origin: f.origin + Vec3::new(0.0, 0.0, z),
                    ..f
                };
                fit.curve =
                    TrigCurve::new(frame, fit.curve.a.clone(), fit.curve.b.clone()).unwrap();
                Cut {
                    at: k as Real / (zs.len() - 1) as Real,
                    area: fit.curve.area().abs(),
                    fit,
                    clips: Vec::new(),
                    bridge: Vec::new(),
                }
            })
            .collect()
    }

    fn heights(n: usize, length: Real) -> Vec<Real> {
        (0..n)
            .map(|k| length * k as Real / (n - 1) as Real)
            .collect()
    }

    /// The 90th percentile of a removed loop's distances to the section of
    /// the part built from the kept cuts by the loop's plane `z = const`
    /// (found along every line `v = const` by bisection, 512 lines): an
    /// independent measure of what the pruning promised.
    fn worst_removed(cuts: &[Cut], keep: &[bool]) -> Real {
        let kept: Vec<TrigCurve> = cuts
            .iter()
            .zip(keep)
            .filter(|(_, &k)| k)
            .map(|(c, _)| c.fit.curve.clone())
            .collect();
        let part = Part::new(kept, &PartOptions::default()).unwrap();
        let mut worst: Real = 0.0;
        for (c, _) in cuts.iter().zip(keep).filter(|(_, &k)| !k) {
            let z = c.fit.curve.frame.origin.z;
            // The segment between the kept sections around the plane.
            let s = part
                .segments()
                .iter()
                .find(|s| {
                    let z0 = s.patch.curve_at(0.0).z.c[0];
                    let z1 = s.patch.curve_at(1.0).z.c[0];
                    (z0 - z) * (z1 - z) <= 0.0
                })
                .unwrap();
            let section: Vec<Vec2> = (0..512)
                .filter_map(|j| {
                    let v = std::f64::consts::TAU * j as Real / 512.0;
                    {
                        let h = |u: Real| s.patch.point(u, v).z - z;
                        let (mut a, mut b) = (0.0, 1.0);
                        if h(a) * h(b) > 0.0 {
                            return None;
                        }
                        for _ in 0..32 {
                            let m = 0.5 * (a + b);
                            if h(a) * h(m) <= 0.0 {
                                b = m;
                            } else {
                                a = m;
                            }
                        }
                        let p = s.patch.point(a, v);
                        Some(Vec2::new(p.x, p.y))
                    }
                })
                .collect();
            assert_eq!(section.len(), 512);
            let f = c.fit.curve.frame;
            let mut d: Vec<Real> = c
                .fit
                .plane_points
                .iter()
                .map(|q| {
                    let p = f.to_world(*q);
                    let p = Vec2::new(p.x, p.y);
                    (0..section.len())
                        .map(|i| {
                            let (a, b) = (section[i], section[(i + 1) % section.len()]);
                            let t = ((p - a).dot(b - a) / (b - a).dot(b - a)).clamp(0.0, 1.0);
                            (a + (b - a) * t - p).norm()
                        })
                        .fold(Real::INFINITY, Real::min)
                })
                .collect();
            d.sort_by(Real::total_cmp);
            worst = worst.max(d[d.len() * 9 / 10]);
        }
        worst
    }

    /// Circles along a straight axis loft to a cylinder whatever sections
    /// are kept: everything goes but the three at each end (they set the
    /// end tangents).
    #[test]
    fn a_cylinder_keeps_only_its_ends() {
        let cuts = sections(&heights(21, 0.5), |_| 0.1);
        let keep = keep_after_pruning(&cuts, &PartOptions::default(), 1e-6);
        let kept: Vec<usize> = (0..21).filter(|&i| keep[i]).collect();
        assert_eq!(kept, [0, 1, 2, 18, 19, 20], "{keep:?}");
        let w = worst_removed(&cuts, &keep);
        // Only the fits' own error (E_M 1e-5 of a 0.1 radius).
        assert!(w < 5e-6, "{w}");
    }

    /// A bulging surface keeps more sections at a tighter tolerance, and
    /// every removed loop lies within the tolerance of the kept sections'
    /// surface (measured in 3D on the rebuilt part).
    #[test]
    fn a_removed_loop_stays_within_the_tolerance() {
        let cuts = sections(&heights(41, 0.6), |z| 0.1 + 0.03 * (8.0 * z).sin());
        let mut last = cuts.len() + 1;
        for tol in [2e-4, 5e-4, 2e-3] {
            let keep = keep_after_pruning(&cuts, &PartOptions::default(), tol);
            let n = keep.iter().filter(|&&k| k).count();
            assert!(n <= last, "tol {tol}: {n} kept, {last} before");
            assert!(n > 6, "tol {tol}: the bulges need sections ({n} kept)");
            let worst = worst_removed(&cuts, &keep);
            // Allowed beyond the tolerance: the sagitta of the 256-gon the
            // pruning measures against (1e-5 on these loops).
            assert!(
                worst <= tol + 2e-5,
                "tol {tol}: a removed loop is {worst} off"
            );
            last = n;
        }
        assert!(last < 20, "a coarse tolerance keeps {last} of 41");
    }

    #[test]
    fn nothing_goes_without_a_tolerance() {
        let cuts = sections(&heights(6, 0.5), |_| 0.1);
        assert!(keep_after_pruning(&cuts, &PartOptions::default(), 0.0)
            .iter()
            .all(|&k| k));
    }
}
