//! Cavities: pockets of skin inside a part.
//!
//! A mesh from a modelling tool often models the inside of the mouth: the
//! skin turns in at the lips and lines a pocket inside the head (on the
//! shared MakeHuman bodies, well up from the throat). Where the lips close
//! over it, a horizontal section cuts the pocket as a loop of its own,
//! nested inside the head's loop; only the lips' slit (a couple of
//! millimetres of height) joins the two. A closed-loop model of the head
//! alone leaves the whole pocket out, and with it some coverage and most
//! of the input → model error.
//!
//! # The cavity surface
//!
//! 1. **Levels.** The part (the head) is cut across the body's up axis
//!    every [`CAVITY_SPACING`] × `H` over the run of its sections
//!    ([`Cutter::cut_nested`]): the part's loop and the loops nested in it,
//!    and the pockets bridged off the part's loop where they open through
//!    a slit (parted lips, parted eyelids: `section::inlets`), each its
//!    lining closed by the slit. Nested loops under [`MIN_LOOP_SHARE`] of
//!    the part's loop are slivers and left out.
//! 2. **Runs.** A nested loop continues the run whose last loop (one or two
//!    levels below: the lips' slit may hide one level) contains its
//!    centroid, or whose last centroid it contains (the nearest such run);
//!    otherwise it starts a run.
//! 3. **Cavities.** A run whose largest loop is at least
//!    [`MIN_CAVITY_SHARE`] of the part's loop at its level, with at least
//!    [`MIN_SECTIONS`] loops (a shorter run, an eye socket 10-20 mm tall,
//!    is cut again between levels half and a quarter as far apart,
//!    [`REFINEMENTS`]), is a cavity: its loops are fitted like the part's (the adaptive
//!    order search, the body's front as the reference direction) and
//!    skinned as a part; a section whose curve passes farther than
//!    [`ReconstructOptions::refine_tolerance`] × `H` from the input (a
//!    small loop pinched in two, fitted at a high order, swings between
//!    its points) is left out. Its ends are where its loops vanish, found by
//!    bisecting between its end level and the next ([`END_BISECTIONS`]
//!    halvings), and closed by domes along the up axis reaching those
//!    levels.
//!
//! The cavity's surface bounds empty space inside the body: the body's
//! solid is the union of the parts and transitions less the cavities'
//! solids. Its outward side (away from the body's solid) faces into the
//! pocket, opposite to a part's ([`Body::tessellate_pieces`] flips it);
//! its volume is subtracted from the body's and its area added
//! (the model's measurement).
//!
//! Only meshes have cavities: a scanner does not see inside a closed
//! pocket, and a cloud slab's nested outlines are not surface. A loop
//! nested in a nested loop (a tongue or teeth left inside the mouth)
//! bounds solid, not a pocket, and is left out; a closed shell left
//! inside the head's solid itself (an eyeball behind closed lids) cuts as
//! a nested loop like a pocket's and is taken for one: its surface is the
//! input's either way, only the volume's sign differs (an eyeball's 7
//! cm³).

use super::*;
use plan::fractions;

/// Spacing of the levels searched for cavities and of a cavity's sections,
/// as a fraction of the body's height: 0.006 (10 mm on 1.73 m, 6-9
/// sections over a mouth). Finer spends parameters for no accuracy;
/// coarser lets the lining stray from the mouth.
pub const CAVITY_SPACING: Real = 0.006;

/// A nested loop smaller than this share of its part's loop is a sliver,
/// not a pocket's section.
pub const MIN_LOOP_SHARE: Real = 0.002;

/// A run whose largest loop is under this share of its part's loop at that
/// level is left out: the head's own threshold for a pocket opening to the
/// front (an eye socket is 2.5 % of the head's loop, a mouth 10-40 %).
pub const MIN_CAVITY_SHARE: Real = crate::segment::MIN_FACING_POCKET_SHARE;

/// Fewest sections of a cavity.
pub const MIN_SECTIONS: usize = 3;

/// Halvings of the interval past each end level where the cavity's loops
/// vanish (the dome's reach is found to `CAVITY_SPACING / 2^n`).
pub const END_BISECTIONS: usize = 3;

/// A pocket of skin inside a part (see the reconstruction's cavities): its
/// surface is skinned through its sections and closed by domes at both
/// ends.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyCavity {
    /// The part it lies in.
    pub within: PartName,
    /// Its surface; the solid it encloses is empty space (the body's solid
    /// is the parts' less the cavities').
    pub part: Part,
    /// One entry per section of `part`, in order.
    pub fits: Vec<SectionFit>,
}

/// One nested loop at one level.
struct Found {
    at: Real,
    level: usize,
    outline: SectionLoop,
    /// The part's loop's area at that level.
    host_area: Real,
}

/// Halvings of the level spacing tried for a run shorter than
/// [`MIN_SECTIONS`].
pub const REFINEMENTS: usize = 2;

/// `run` with the loops continuing it at the levels `step` before its
/// first, between its levels `2 step` apart, and `step` after its last
/// (`nested` cuts a level), in order.
fn refined(run: Vec<Found>, step: Real, nested: &dyn Fn(Real) -> Vec<Found>) -> Vec<Found> {
    let mut levels: Vec<Real> = vec![run[0].at - step, run[run.len() - 1].at + step];
    levels.extend(
        run.windows(2)
            .filter(|w| w[1].at - w[0].at > 1.5 * step)
            .map(|w| 0.5 * (w[0].at + w[1].at)),
    );
    let mut out = run;
    for t in levels {
        let near = |f: &Found| (f.at - t).abs();
        let Some(closest) = out.iter().min_by(|a, b| near(a).total_cmp(&near(b))) else {
            continue;
        };
        let take = nested(t)
            .into_iter()
            .filter(|f| continues(&closest.outline, &f.outline))
            .max_by(|a, b| a.outline.area.total_cmp(&b.outline.area));
        if let Some(f) = take {
            out.push(f);
        }
    }
    out.sort_by(|a, b| a.at.total_cmp(&b.at));
    out
}

/// Does `l` continue the run whose last loop is `last`?
pub(super) fn continues(last: &SectionLoop, l: &SectionLoop) -> bool {
    last.contains(l.centroid) || l.contains(last.centroid)
}

/// The cavities of `within` (a part cut across `up`) between the axis
/// fractions `t0` and `t1`; warnings for those that could not be built.
pub(super) fn find_cavities(
    cutter: &Cutter<'_>,
    within: PartName,
    (t0, t1): (Real, Real),
    input: &InputDistance,
    opts: &ReconstructOptions,
    warnings: &mut Vec<String>,
) -> Vec<BodyCavity> {
    let seg = cutter.segmentation();
    if !matches!(cutter.body(), BodyGeometry::Mesh(_)) {
        return Vec::new();
    }
    let Some(axis) = seg.part(within) else {
        return Vec::new();
    };
    let len = axis.length();
    if !(len > 0.0) || !(t1 > t0) {
        return Vec::new();
    }
    let up = seg.frame.up;
    let step = CAVITY_SPACING * seg.height / len;
    let ts = fractions(t0, t1, step);
    let nested = |t: Real| -> Vec<Found> {
        cutter
            .cut_nested(within, t, Some(up), &opts.segment)
            .map(|(cut, nested)| {
                let host = cut.outline.area;
                nested
                    .into_iter()
                    .filter(|l| l.area >= MIN_LOOP_SHARE * host)
                    .map(|outline| Found {
                        at: t,
                        level: 0,
                        outline,
                        host_area: host,
                    })
                    .collect()
            })
            .unwrap_or_default()
    };
    let levels =
        crate::geom::parallel::parallel_map(&ts, 4, |run| run.iter().map(|&t| nested(t)).collect());
    // Runs of nested loops from level to level.
    let mut runs: Vec<Vec<Found>> = Vec::new();
    for (k, found) in levels.into_iter().enumerate() {
        let mut taken = vec![false; runs.len()];
        for mut f in found {
            f.level = k;
            let best = runs
                .iter()
                .enumerate()
                .filter(|(i, r)| {
                    let last = &r[r.len() - 1];
                    !taken[*i] && last.level + 2 >= k && continues(&last.outline, &f.outline)
                })
                .min_by(|a, b| {
                    let d = |r: &Vec<Found>| {
                        r[r.len() - 1].outline.centroid.distance(f.outline.centroid)
                    };
                    d(a.1).total_cmp(&d(b.1))
                })
                .map(|(i, _)| i);
            match best {
                Some(i) => {
                    taken[i] = true;
                    runs[i].push(f);
                }
                None => {
                    taken.push(true);
                    runs.push(vec![f]);
                }
            }
        }
    }
    let mut out = Vec::new();
    for run in runs {
        let largest = run
            .iter()
            .map(|f| f.outline.area / f.host_area)
            .fold(0.0, Real::max);
        if largest < MIN_CAVITY_SHARE {
            continue;
        }
        // A short pocket (an eye socket, 10-20 mm tall) between levels
        // finer until it has its sections.
        let (mut run, mut run_step) = (run, step);
        for _ in 0..REFINEMENTS {
            if run.len() >= MIN_SECTIONS {
                break;
            }
            run_step *= 0.5;
            run = refined(run, run_step, &nested);
        }
        if run.len() < MIN_SECTIONS {
            continue;
        }
        match build_cavity(cutter, within, &run, run_step, input, opts) {
            Ok(c) => out.push(c),
            Err(e) => warnings.push(format!(
                "{within}: the cavity at {:.3}-{:.3} was left out: {e}",
                run[0].at,
                run[run.len() - 1].at
            )),
        }
    }
    out
}

/// Where a run of loops vanishes between the axis fractions `inside` (a
/// level with its loop: `present`) and `outside` (one without): bisected
/// [`END_BISECTIONS`] times, the middle of the last interval.
pub(super) fn vanishing(
    mut inside: Real,
    mut outside: Real,
    present: impl Fn(Real) -> bool,
) -> Real {
    for _ in 0..END_BISECTIONS {
        let mid = 0.5 * (inside + outside);
        if present(mid) {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    0.5 * (inside + outside)
}

/// The level (axis fraction) past the end loop `end` (at `at`) where the
/// cavity's loops vanish: bisected between `at` and `at + dir × step`.
fn end_fraction(
    cutter: &Cutter<'_>,
    within: PartName,
    end: &SectionLoop,
    at: Real,
    dir: Real,
    step: Real,
    opts: &ReconstructOptions,
) -> Real {
    let up = cutter.segmentation().frame.up;
    vanishing(at, at + dir * step, |t| {
        cutter
            .cut_nested(within, t, Some(up), &opts.segment)
            .map(|(_, nested)| nested.iter().any(|l| continues(end, l)))
            .unwrap_or(false)
    })
}

/// A dome from `curve` along its plane's normal reaching the plane through
/// `tip` parallel to it (the lowest dome, 0.02 radii, where `tip` lies in
/// `curve`'s own plane).
pub(super) fn dome_reaching(curve: &TrigCurve, tip: Point3) -> CapKind {
    CapKind::Dome {
        relative_height: plan::height_to_reach(curve, tip).unwrap_or(0.02),
        fullness: 1.0,
        axis: crate::surface::cap::DomeAxis::Normal,
    }
}

fn build_cavity(
    cutter: &Cutter<'_>,
    within: PartName,
    run: &[Found],
    step: Real,
    input: &InputDistance,
    opts: &ReconstructOptions,
) -> Result<BodyCavity, String> {
    let seg = cutter.segmentation();
    let axis = seg.part(within).ok_or("no axis")?;
    let fo = FitOptions {
        reference: Some(seg.frame.front),
        normal: Some(seg.frame.up),
        allow_non_planar: true,
        ..opts.fit
    };
    let mut curves = Vec::with_capacity(run.len());
    let mut fits = Vec::with_capacity(run.len());
    let limit = opts.refine_tolerance * seg.height;
    for f in run {
        let fit = plan::fit_untangled(&f.outline.with_edge_midpoints(), &fo)?;
        // A fit that meets the tolerances at the loop's points can still
        // swing away between them (a small loop pinched in two, at a high
        // order): such a section is left out.
        let off = input
            .distances(&fit.curve.sample(64))
            .into_iter()
            .fold(0.0, Real::max);
        if off > limit {
            continue;
        }
        fits.push(SectionFit::of(f.at, &fit));
        curves.push(fit.curve);
    }
    if curves.len() < 2 {
        return Err(format!(
            "{} of its {} sections stray from the input",
            run.len() - curves.len(),
            run.len()
        ));
    }
    let (first, last) = (&run[0], &run[run.len() - 1]);
    let lo = end_fraction(cutter, within, &first.outline, first.at, -1.0, step, opts);
    let hi = end_fraction(cutter, within, &last.outline, last.at, 1.0, step, opts);
    let at_level = |t: Real| axis.point_and_tangent(t).map(|(p, _)| p);
    let (Some(bottom), Some(top)) = (at_level(lo), at_level(hi)) else {
        return Err("its ends lie off the part's axis".to_string());
    };
    let options = PartOptions {
        start_cap: dome_reaching(&curves[0], bottom),
        end_cap: dome_reaching(&curves[curves.len() - 1], top),
        ..opts.part
    };
    let part = Part::new(curves, &options).map_err(|e| e.to_string())?;
    Ok(BodyCavity { within, part, fits })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::shapes::{merge, stick_body, uv_sphere};

    /// The stick body with a hollow inside its head: a sphere of radius
    /// `r` turned inside out (a pocket of skin, as a mouth's lining), with
    /// a small solid sphere inside it (a tongue).
    fn hollow_head(r: Real) -> Mesh {
        let centre = Vec3::new(0.0, 0.0, 1.6);
        let mut pocket = uv_sphere(centre, r, 24, 64);
        pocket.flip_orientation();
        let tongue = uv_sphere(centre - Vec3::new(0.0, 0.0, 0.3 * r), 0.3 * r, 12, 32);
        merge(&[stick_body(1), pocket, tongue])
    }

    #[test]
    fn a_hollow_head_has_one_cavity_that_lines_it() {
        let r = 0.05;
        let mesh = hollow_head(r);
        let (body, report) =
            reconstruct(BodyGeometry::Mesh(&mesh), &ReconstructOptions::default()).unwrap();
        assert!(!report.warnings.iter().any(|w| w.contains("cavity")));
        // One cavity (the tongue inside it is solid, not a second one).
        assert_eq!(body.cavities.len(), 1, "{:?}", report.warnings);
        let c = &body.cavities[0];
        assert_eq!(c.within, PartName::Head);
        assert!(c.fits.len() >= MIN_SECTIONS, "{}", c.fits.len());
        // Its surface lies on the sphere, and its domes reach the poles.
        let m =
            crate::surface::tessellate::tessellate_part(&c.part, &TessellationOptions::default())
                .unwrap();
        let centre = Vec3::new(0.0, 0.0, 1.6);
        for p in &m.positions {
            let off = (p.distance(centre) - r).abs();
            assert!(off < 0.1 * r, "{p:?}: {off}");
        }
        let (lo, hi) = m
            .positions
            .iter()
            .fold((1e9, -1e9), |(lo, hi): (Real, Real), p| {
                (lo.min(p.z), hi.max(p.z))
            });
        assert!((lo - (1.6 - r)).abs() < 0.15 * r, "{lo}");
        assert!((hi - (1.6 + r)).abs() < 0.15 * r, "{hi}");
        // Its volume is the sphere's within 2 %, and the
        // tessellation turned inside out encloses it negatively.
        let v = crate::measure::volume::volume_area_extent(&Body {
            digits: Vec::new(),
            cavities: Vec::new(),
            transitions: Vec::new(),
            parts: vec![BodyPart {
                name: PartName::Head,
                part: c.part.clone(),
                fits: Vec::new(),
            }],
            ..body.clone()
        })
        .0;
        let sphere = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        assert!((v / sphere - 1.0).abs() < 0.02, "{v} vs {sphere}");
        let pieces = body
            .tessellate_pieces(&TessellationOptions::default())
            .unwrap();
        let inside_out = pieces.last().unwrap().signed_volume();
        assert!((inside_out / sphere + 1.0).abs() < 0.02, "{inside_out}");
        // Every point of the pocket's lining is near the cavity (the way
        // back: its poles and its equator alike).
        let lining = MeshDistance::new(&m);
        for p in uv_sphere(centre, r, 12, 24).positions {
            let d = lining.distance(p);
            assert!(d < 0.1 * r, "{p:?}: {d}");
        }
    }

    #[test]
    fn a_cloud_and_a_solid_head_have_none() {
        let body = stick_body(1);
        let (b, _) =
            reconstruct(BodyGeometry::Mesh(&body), &ReconstructOptions::default()).unwrap();
        assert!(b.cavities.is_empty());
        // A scanner sees no pocket inside a head, and a cloud's nested
        // slab outlines are not surface: none is looked for.
        let cloud = crate::spatial::scanner::virtual_scan(
            &hollow_head(0.05),
            &crate::spatial::scanner::ScannerOptions::default(),
        )
        .unwrap()
        .cloud;
        let (b, _) =
            reconstruct(BodyGeometry::Cloud(&cloud), &ReconstructOptions::default()).unwrap();
        assert!(b.cavities.is_empty());
    }
}
