//! The model fitted to the input (docs/global-fit.md): the third stage
//! after labelling and initializing. Every input point (a scan's points,
//! or samples spread over a mesh's surface) is labelled with the solid
//! part whose surface is nearest, and left out where it cannot be trusted:
//! past a part's end (a cap's or a transition's), or within the junction
//! distance of another part (near an armpit, the crotch, a finger's root:
//! an arm touching the torso never feeds the torso). Each part is then
//! fitted to its points by one least squares per round
//! ([`crate::surface::fit::fit_part`]); the transitions, built after, take
//! the fitted parts' ends.

use super::{BodyDigit, BodyPart};
use crate::anatomy::{BodyGeometry, PartName};
use crate::geom::math::{Point3, Real};
use crate::spatial::distance::{sample_surface_on_triangles, MeshDistance};
use crate::spatial::point_grid::PointGrid;
use crate::surface::fit::{
    fit_part_from, project, Coverage, Foot, PartGrid, Surface, SurfaceFitOptions, SurfaceFitStats,
};
use crate::surface::part::Part;
use rayon::prelude::*;

/// Which inputs the parts are fitted to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FitMode {
    /// Scans only: their sections are slabs of noisy points in an
    /// occupancy image, and the fit takes them to the points. A mesh's
    /// sections are exact cuts already: there the fit gains little for
    /// several times the time (docs/global-fit.md).
    #[default]
    Scans,
    /// Meshes and scans.
    All,
    /// Neither: the parts as their sections give them.
    Off,
}

/// Options of the fit of the model to the input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlobalFitOptions {
    /// Which inputs are fitted. Default [`FitMode::Scans`].
    pub mode: FitMode,
    /// Rounds, smoothness, robust weights ([`SurfaceFitOptions`]; its
    /// `min_cutoff` is set from [`GlobalFitOptions::min_cutoff`]).
    pub surface: SurfaceFitOptions,
    /// Samples spread over a mesh's surface. Default 120 000.
    pub mesh_samples: usize,
    /// At most this many points per section of a part (a denser scan is
    /// thinned evenly). Default 400.
    pub points_per_section: usize,
    /// A point this near another part's surface (or inside it), as a
    /// fraction of the height, belongs to the junction, not to a part.
    /// Default 0.003 (5 mm on 1.7 m).
    pub junction: Real,
    /// A point this near its part's surface, as a fraction of the height,
    /// always takes part (the robust cutoff never drops it). Default
    /// 0.003.
    pub min_cutoff: Real,
    /// A section is added where a fitted part's points still lie farther
    /// than this (the 90th percentile over an interval between two
    /// sections), as a fraction of the height, and the part fitted again
    /// ([`SurfaceFitOptions::split`]); 0 adds none. Default 0.0015.
    pub split: Real,
    /// No section is added between two closer than twice this, as a
    /// fraction of the height. Default 0.005.
    pub min_gap: Real,
}

impl Default for GlobalFitOptions {
    fn default() -> Self {
        GlobalFitOptions {
            mode: FitMode::Scans,
            surface: SurfaceFitOptions::default(),
            mesh_samples: 120_000,
            points_per_section: 400,
            junction: 0.003,
            min_cutoff: 0.003,
            split: 0.0015,
            min_gap: 0.005,
        }
    }
}

/// What the fit did to one part, in millimetres.
#[derive(Clone, Debug, PartialEq)]
pub struct PartFit {
    /// The part's name as the model file writes it (`left_arm`,
    /// `left_arm_digit_1`).
    pub name: String,
    /// Points labelled with the part (after thinning), and those inside
    /// the robust cutoff in the last round.
    pub points: usize,
    pub used: usize,
    /// RMS residual of the points inside the first round's cutoff, before
    /// and after.
    pub rms_before_mm: Real,
    pub rms_after_mm: Real,
    /// RMS and largest distance from the fitted part's surface to the
    /// part's before the fit.
    pub moved_rms_mm: Real,
    pub moved_max_mm: Real,
    /// Rounds taken.
    pub rounds: usize,
    /// Sections added where the points still lay far after the rounds
    /// (and the part fitted again).
    pub sections_added: usize,
}

impl PartFit {
    fn of(name: String, s: &SurfaceFitStats, mm: Real) -> PartFit {
        PartFit {
            name,
            points: s.points,
            used: s.used,
            rms_before_mm: s.rms_before * mm,
            rms_after_mm: s.rms_after * mm,
            moved_rms_mm: s.moved_rms * mm,
            moved_max_mm: s.moved_max * mm,
            rounds: s.rounds,
            sections_added: s.added,
        }
    }
}

/// The input a model is fitted to: its points or mesh, the body's height
/// and how many millimetres make one of its units.
pub(super) struct FitInput<'a> {
    pub(super) geometry: BodyGeometry<'a>,
    pub(super) height: Real,
    pub(super) mm: Real,
}

/// The solids (parts, then digits) fitted to the input, those named by
/// `only` or all. Returns what the fit did to each.
pub(super) fn fit_to_input(
    parts: &mut [BodyPart],
    digits: &mut [BodyDigit],
    input: &FitInput<'_>,
    opts: &GlobalFitOptions,
    only: Option<PartName>,
) -> Vec<PartFit> {
    let height = input.height;
    let applies = match opts.mode {
        FitMode::All => true,
        FitMode::Scans => matches!(input.geometry, BodyGeometry::Cloud(_)),
        FitMode::Off => false,
    };
    if !applies {
        return Vec::new();
    }
    let solids: Vec<&Part> = parts
        .iter()
        .map(|p| &p.part)
        .chain(digits.iter().map(|d| &d.part))
        .collect();
    // As the model file names them: `left_arm`, `left_arm_digit_1`, ….
    let snake = |n: PartName| n.to_string().replace(' ', "_");
    let names: Vec<String> = parts
        .iter()
        .map(|p| snake(p.name))
        .chain(
            digits
                .iter()
                .zip(super::digits::digit_numbers(digits))
                .map(|(d, number)| format!("{}_digit_{number}", snake(d.hand))),
        )
        .collect();
    let owners: Vec<PartName> = parts
        .iter()
        .map(|p| p.name)
        .chain(digits.iter().map(|d| d.hand))
        .collect();
    // Labelling costs a projection a point: no more points than twice
    // what the parts will take.
    let sections: usize = solids.iter().map(|p| p.sections().len()).sum();
    let points = thinned(
        input_points(input.geometry, opts.mesh_samples),
        2 * opts.points_per_section * sections,
    );
    let chosen: Vec<usize> = (0..solids.len())
        .filter(|&i| only.is_none_or(|o| owners[i] == o && i < parts.len()))
        .collect();
    let labels = label(&solids, &points, height, opts, &chosen);
    let surface = SurfaceFitOptions {
        min_cutoff: opts.min_cutoff * height,
        coverage_reach: LABEL_REACH * height,
        split: opts.split * height,
        min_gap: opts.min_gap * height,
        ..opts.surface
    };
    let positions: Vec<Point3> = points.iter().map(|(p, _)| *p).collect();
    let grid = PointGrid::new(&positions, 0.01 * height);
    let fitted: Vec<(usize, Part, SurfaceFitStats)> = chosen
        .par_iter()
        .map(|&i| {
            let mine = |l: &Option<(usize, Foot)>| l.is_some_and(|(part, _)| part == i);
            let labelled = labels.iter().filter(|l| mine(l)).count();
            let cap = opts.points_per_section * solids[i].sections().len();
            // Each point kept or not by its own index, so one point
            // labelled otherwise changes nothing else.
            let share = cap as Real / labelled.max(1) as Real;
            // Their feet on the part, found in labelling, start the fit.
            let (taken, feet): (Vec<Point3>, Vec<Option<Foot>>) = labels
                .iter()
                .zip(&points)
                .enumerate()
                .filter(|&(k, (l, _))| mine(l) && kept(k, share))
                .map(|(_, (l, (p, _)))| (*p, l.map(|(_, f)| f)))
                .unzip();
            let weights = vec![1.0; taken.len()];
            // A point no part takes (a junction's, a hole's rim) holds
            // every part near it; one another part takes holds none.
            let allows = |k: usize| labels[k].is_none_or(|(part, _)| part == i);
            let cover = Coverage {
                grid: &grid,
                allows: &allows,
                reach: surface.coverage_reach,
            };
            let (part, stats) = fit_part_from(solids[i], &taken, feet, &weights, &cover, &surface);
            (i, part, stats)
        })
        .collect();
    let mut report = Vec::with_capacity(fitted.len());
    for (i, part, stats) in fitted {
        if i < parts.len() {
            parts[i].part = part;
        } else {
            digits[i - parts.len()].part = part;
        }
        report.push(PartFit::of(names[i].clone(), &stats, input.mm));
    }
    report
}

/// A scan's points, or samples spread evenly over a mesh's surface; each
/// with its surface's unit normal where known (a mesh's triangle's).
fn input_points(input: BodyGeometry<'_>, mesh_samples: usize) -> Vec<(Point3, Option<Point3>)> {
    match input {
        BodyGeometry::Cloud(c) => c.positions.iter().map(|&p| (p, None)).collect(),
        BodyGeometry::Mesh(m) => {
            let (points, on, _) = sample_surface_on_triangles(m, mesh_samples);
            points
                .into_iter()
                .zip(on)
                .map(|(p, t)| {
                    let [a, b, c] = m.triangle(t as usize);
                    (p, (b - a).cross(c - a).normalized())
                })
                .collect()
        }
    }
}

/// How far from a part's surface a point may lie and still be labelled
/// to it, and a surface sample be held to a point, as a fraction of the
/// body's height (34 mm on 1.7 m).
const LABEL_REACH: Real = 0.02;

/// Each point's part (an index into `solids`) and its foot there, or
/// `None` where no part may take it: nearest to no part within the reach,
/// within the junction distance of (or inside) another part, or (a mesh's
/// samples) on a surface turned more than 60° from the part's. A point
/// past its part's end (its foot `at_end`) holds the part's surface
/// ([`Coverage`]) but is not fitted: a cap's or a transition's. Only
/// points that may take part in fitting `chosen` (within twice the reach
/// of one's box) are labelled; the others are `None`.
fn label(
    solids: &[&Part],
    points: &[(Point3, Option<Point3>)],
    height: Real,
    opts: &GlobalFitOptions,
    chosen: &[usize],
) -> Vec<Option<(usize, Foot)>> {
    let grids: Vec<PartGrid> = solids.par_iter().map(|p| PartGrid::for_part(p)).collect();
    let surfaces: Vec<Option<Surface<'_>>> = solids.iter().map(|p| Surface::of(p)).collect();
    let trees: Vec<MeshDistance<'_>> = grids.iter().map(|g| MeshDistance::new(g.mesh())).collect();
    let reach = LABEL_REACH * height;
    let junction = opts.junction * height;
    let boxes: Vec<_> = grids
        .iter()
        .map(|g| {
            g.bounds().map(|b| {
                let r = Point3::new(reach, reach, reach);
                (b.min - r, b.max + r)
            })
        })
        .collect();
    // Within `pad` of part `i`'s box.
    let in_box = |i: usize, p: Point3, pad: Real| {
        boxes[i].is_some_and(|(lo, hi)| {
            let (lo, hi) = (
                lo - Point3::new(pad, pad, pad),
                hi + Point3::new(pad, pad, pad),
            );
            p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z
        })
    };
    points
        .par_iter()
        .map(|&(p, normal)| {
            // Twice the reach: the fit moves the part (by millimetres).
            let near_chosen = chosen.iter().any(|&i| in_box(i, p, reach));
            if !near_chosen {
                return None;
            }
            let feet: Vec<(usize, Foot)> = (0..solids.len())
                .filter(|&i| in_box(i, p, 0.0))
                .filter_map(|i| Some((i, project(surfaces[i].as_ref()?, &grids[i], &trees[i], p)?)))
                .collect();
            let &(best, foot) = feet
                .iter()
                .min_by(|a, b| a.1.signed.abs().total_cmp(&b.1.signed.abs()))?;
            if foot.signed.abs() > reach || p.distance(foot.point) > reach {
                return None;
            }
            if feet
                .iter()
                .any(|&(i, f)| i != best && !f.at_end && f.signed < junction)
            {
                return None;
            }
            if normal.is_some_and(|n| n.dot(foot.normal).abs() < 0.5) {
                return None;
            }
            Some((best, foot))
        })
        .collect()
}

/// Whether the point of index `k` is among a `share` of the points taken
/// evenly (a low-discrepancy sequence over the indices).
fn kept(k: usize, share: Real) -> bool {
    share >= 1.0 || (k as Real * 0.618_033_988_749_894_9).fract() < share
}

/// At most `cap` of `points`, taken evenly through their order.
fn thinned<T: Copy>(points: Vec<T>, cap: usize) -> Vec<T> {
    if points.len() <= cap || cap == 0 {
        return points;
    }
    let step = points.len() as Real / cap as Real;
    (0..cap)
        .map(|k| points[(k as Real * step) as usize])
        .collect()
}
