//! The [`Report`]: how well and how compactly a [`Body`] fits its input.

use super::*;
use crate::segment::joints::{estimate_joints, JointName};
use crate::segment::regions::{Region, Regions};
use crate::spatial::cloud_surface::CloudSurface;
use crate::spatial::distance::sample_surface_on_triangles;
use crate::surface::skin::ClosedPieces;

/// Per-part numbers of the [`Report`].
#[derive(Clone, Debug, PartialEq)]
pub struct PartReport {
    /// The part (for a cavity: the part it lies in).
    pub name: PartName,
    /// True for a cavity ([`BodyCavity`]) of the part `name`.
    pub cavity: bool,
    /// True for a digit ([`BodyDigit`]) of the arm `name`'s hand.
    pub digit: bool,
    /// The part's sections in the model (the fit's added ones too; the
    /// orders and E_a/E_M are those of the sections cut from the input).
    pub sections: usize,
    /// Orders used: minimum, median, maximum.
    pub orders: (usize, usize, usize),
    /// Worst `E_a` and `E_M` over the part's sections.
    pub worst_ea: Real,
    pub worst_em: Real,
    /// Sections that met the tolerances.
    pub met: usize,
    /// The ellipse baseline's worst `E_a` and `E_M`.
    pub ellipse_worst_ea: Real,
    pub ellipse_worst_em: Real,
    pub design_parameters: usize,
}

/// Distance statistics in millimetres.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DistanceMm {
    pub rms: Real,
    pub p95: Real,
    pub max: Real,
}

impl DistanceMm {
    fn of(s: &DistanceStats, mm: Real) -> DistanceMm {
        DistanceMm {
            rms: s.rms * mm,
            p95: s.p95 * mm,
            max: s.max * mm,
        }
    }
}

/// A model's design parameters by region (`segment::regions`: the head
/// above the neck, the hands past the wrists, the feet below the ankles,
/// the rest): each section counted in the region of its mean point, a
/// part's end cap with its end section, a cavity by its sections, the
/// transitions with the rest. They add up to [`Body::design_parameters`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegionParameters {
    pub head: usize,
    pub hands: usize,
    pub feet: usize,
    pub rest: usize,
}

impl RegionParameters {
    /// The parameters of `body` in `regions` (in the same frame).
    pub fn of(body: &Body, regions: &Regions) -> RegionParameters {
        let mut out = RegionParameters::default();
        for part in body.solids().chain(body.cavities.iter().map(|c| &c.part)) {
            let (curves, o) = (part.curves(), part.options());
            for (k, c) in curves.iter().enumerate() {
                let caps = if k == 0 {
                    o.start_cap.design_parameters()
                } else {
                    0
                } + if k + 1 == curves.len() {
                    o.end_cap.design_parameters()
                } else {
                    0
                };
                *out.at(regions.of(c.world_series().mean_point())) += c.design_parameters() + caps;
            }
        }
        out.rest += body
            .transitions
            .iter()
            .map(|t| t.transition.design_parameters())
            .sum::<usize>();
        out
    }

    fn at(&mut self, region: Region) -> &mut usize {
        match region {
            Region::Head => &mut self.head,
            Region::Hands => &mut self.hands,
            Region::Feet => &mut self.feet,
            Region::Rest => &mut self.rest,
        }
    }

    /// The sum over the regions.
    pub fn total(&self) -> usize {
        self.head + self.hands + self.feet + self.rest
    }
}

/// How well and how compactly the model fits its input.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The input's unit: the one given, or the one inferred from its
    /// extent ([`ReconstructOptions::infer_units`]).
    pub units: super::Units,
    /// Whether [`Report::units`] was inferred rather than given.
    pub units_inferred: bool,
    /// The model's design parameters (method.md §7).
    pub design_parameters: usize,
    /// The numbers its compact `.tbm` file stores ([`Body::compact_numbers`]).
    pub compact_numbers: usize,
    /// The design parameters by region: head, hands, feet and the rest.
    pub region_parameters: RegionParameters,
    /// The input's vertex (mesh) or point (cloud) count; the polygon
    /// baseline is `3 × input_vertices`.
    pub input_vertices: usize,
    /// Symmetric distance: `rms = √((rms_in² + rms_out²)/2)`, `p95` and
    /// `max` the larger of the two directions'.
    pub distance_mm: DistanceMm,
    /// Input → model: input surface samples (mesh) or points (cloud) to
    /// the model's outer skin ([`crate::surface::skin`]: the boundary of the union
    /// of its pieces, the triangles of a piece lying inside another one
    /// deeper than [`ReconstructOptions::skin_depth`] left out).
    pub input_to_model_mm: DistanceMm,
    /// Model → input: samples of the model's outer skin to the input's
    /// surface: the mesh, or the surface a cloud samples
    /// ([`crate::spatial::cloud_surface`]: the distance to a least-squares disk of
    /// the local point spacing's radius at the nearest scan point, at most
    /// the distance to that point; the distance to the nearest point alone
    /// has a floor of the point spacing, even for a perfect model). The
    /// samples are those
    /// [`ReconstructOptions::report_samples`] spread over all the pieces'
    /// tessellation that lie on the outer skin (as dense, fewer by
    /// [`Report::interior_area_share`]).
    pub model_to_input_mm: DistanceMm,
    /// Share of input samples within [`ReconstructOptions::coverage_mm`]
    /// of the model.
    pub coverage: Real,
    /// Coverage of the input's outer surface: the share of input samples
    /// within [`ReconstructOptions::coverage_mm`] among those not hidden
    /// inside the input (a farther sample is hidden when no ray from it
    /// escapes the input, [`crate::spatial::visibility`]: the inside of a modelled
    /// mouth). Equal to `coverage` for a cloud (a scanner saw every point).
    pub visible_coverage: Real,
    /// Input samples farther than the coverage distance and hidden.
    pub hidden_samples: usize,
    /// The symmetric RMS (mm) on the surface the input shows: for a mesh
    /// the hidden input samples left out of input → model (what the outer
    /// skin achieves on the input's outer surface); for a cloud the model
    /// samples over the scan's holes left out of model → input
    /// ([`Report::unobserved_samples`]).
    pub visible_rms_mm: Real,
    /// The symmetric 95th percentile (mm) with the same samples left out
    /// as [`Report::visible_rms_mm`].
    pub visible_p95_mm: Real,
    /// For a cloud, the model samples over the scan's holes: farther than
    /// the coverage distance from every scan point (the nearest-point
    /// distance), with the nearest scan point on a hole's rim
    /// ([`crate::section::holes`]: the soles the body stood on, the crown, the
    /// crotch). Their distance measures the hole, not the model. 0 for a
    /// mesh.
    pub unobserved_samples: usize,
    /// Share of the pieces' tessellated area lying inside other pieces
    /// (not on the outer skin), left out of both directions.
    pub interior_area_share: Real,
    pub parts: Vec<PartReport>,
    /// What the fit to the input did to each part (`body/fit.rs`): the
    /// residuals before and after and how far it moved the part; empty
    /// when the fit is off.
    pub fit: Vec<super::PartFit>,
    /// Parts the segmentation found (feet included).
    pub parts_found: Vec<PartName>,
    /// Joint centres estimated from the segmentation
    /// ([`crate::segment::joints::estimate_joints`]), in the input's coordinates.
    pub joints: Vec<(JointName, Point3)>,
    pub warnings: Vec<String>,
}

impl Report {
    /// `design_parameters / (3 × input_vertices)`.
    pub fn parameter_ratio(&self) -> Real {
        self.design_parameters as Real / (3 * self.input_vertices.max(1)) as Real
    }
}

/// The per-part numbers of a body.
pub fn part_reports(body: &Body) -> Vec<PartReport> {
    let parts = body
        .parts
        .iter()
        .map(|p| (p.name, false, false, &p.part, &p.fits));
    let digits = body
        .digits
        .iter()
        .map(|d| (d.hand, false, true, &d.part, &d.fits));
    let cavities = body
        .cavities
        .iter()
        .map(|c| (c.within, true, false, &c.part, &c.fits));
    parts
        .chain(digits)
        .chain(cavities)
        .map(|(name, cavity, digit, part, fits)| {
            let mut orders: Vec<usize> = fits.iter().map(|f| f.order).collect();
            orders.sort_unstable();
            let med = orders.get(orders.len() / 2).copied().unwrap_or(0);
            let fold = |f: &dyn Fn(&SectionFit) -> Real| fits.iter().map(f).fold(0.0, Real::max);
            PartReport {
                name,
                cavity,
                digit,
                sections: part.sections().len(),
                orders: (
                    orders.first().copied().unwrap_or(0),
                    med,
                    orders.last().copied().unwrap_or(0),
                ),
                worst_ea: fold(&|f| f.ea),
                worst_em: fold(&|f| f.em),
                met: fits.iter().filter(|f| f.met).count(),
                ellipse_worst_ea: fold(&|f| f.ellipse.map_or(0.0, |e| e.0)),
                ellipse_worst_em: fold(&|f| f.ellipse.map_or(0.0, |e| e.1)),
                design_parameters: part.design_parameters(),
            }
        })
        .collect()
}

/// The distances whose flag is not set (the samples a shown-surface
/// number keeps).
fn unflagged(d: &[Real], flags: &[bool]) -> Vec<Real> {
    d.iter()
        .zip(flags)
        .filter(|(_, f)| !**f)
        .map(|(d, _)| *d)
        .collect()
}

/// Deterministic subsample of at most `n` items (every k-th).
fn every_kth(points: &[Point3], n: usize) -> Vec<Point3> {
    let k = points.len().div_ceil(n.max(1)).max(1);
    points.iter().step_by(k).copied().collect()
}

/// Measures `model` against its input `body` (see [`Report`]).
pub fn measure(
    body: BodyGeometry<'_>,
    model: &Body,
    seg: &Segmentation,
    opts: &ReconstructOptions,
    warnings: Vec<String>,
) -> Result<Report, ReconstructError> {
    let input = match body {
        BodyGeometry::Mesh(m) => InputDistance::Mesh(MeshDistance::new(m)),
        BodyGeometry::Cloud(c) => {
            InputDistance::Cloud(PointGrid::new(&c.positions, 0.01 * model.height))
        }
    };
    measure_with(body, model, seg, opts, warnings, &input)
}

/// The report's samples of both surfaces ([`sample_both_ways`]).
struct Samples {
    /// Samples of the model's concatenated pieces.
    model: Vec<Point3>,
    /// Each model sample's distance to the input: to the nearest point and
    /// to the surface the points sample for a cloud, the distance twice
    /// for a mesh.
    distances: Vec<(Real, Real)>,
    /// Each model sample's triangle.
    on: Vec<u32>,
    /// The pieces' area.
    area: Real,
    /// Samples of the input (a mesh's surface, every k-th point of a cloud).
    input: Vec<Point3>,
    /// The input's vertex or point count.
    input_count: usize,
    /// A mesh input's ray-casting hierarchy (for the hidden samples).
    visibility: Option<crate::spatial::visibility::Visibility>,
}

/// Samples the model's `surface` and measures their distances to the input,
/// and samples the input.
fn sample_both_ways(
    body: BodyGeometry<'_>,
    input: &InputDistance,
    surface: &Mesh,
    opts: &ReconstructOptions,
) -> Samples {
    let (model_samples, on, area) = sample_surface_on_triangles(surface, opts.report_samples);
    let d: Vec<(Real, Real)> = match (body, input) {
        (BodyGeometry::Cloud(c), InputDistance::Cloud(grid)) => {
            let nearest = grid.nearest_indices(&model_samples);
            let spacing = (area / c.positions.len().max(1) as Real).sqrt();
            let surface = CloudSurface::new(grid, c.normals.as_deref(), spacing)
                .distances_from(&model_samples, &nearest);
            nearest.iter().map(|n| n.0).zip(surface).collect()
        }
        _ => input
            .distances(&model_samples)
            .into_iter()
            .map(|d| (d, d))
            .collect(),
    };
    let (samples, count, vis) = match body {
        BodyGeometry::Mesh(m) => (
            sample_surface(m, opts.report_samples),
            m.positions.len(),
            Some(crate::spatial::visibility::Visibility::new(m)),
        ),
        BodyGeometry::Cloud(c) => (
            every_kth(&c.positions, opts.report_samples),
            c.positions.len(),
            None,
        ),
    };
    Samples {
        model: model_samples,
        distances: d,
        on,
        area,
        input: samples,
        input_count: count,
        visibility: vis,
    }
}

/// [`measure`] with the input's distance structure already built (the
/// refinement's).
pub(super) fn measure_with(
    body: BodyGeometry<'_>,
    model: &Body,
    seg: &Segmentation,
    opts: &ReconstructOptions,
    warnings: Vec<String>,
    input: &InputDistance,
) -> Result<Report, ReconstructError> {
    let mm = opts.units.to_mm();
    let tess = TessellationOptions {
        target_edge: Some(opts.report_edge * model.height),
        ..TessellationOptions::default()
    };
    // The pieces one after another: the outer skin is found on the same
    // hierarchy that measures the input's distances to it. No measurement
    // uses the normals: they are not copied (4.6 MB for the built-in body).
    let mut tessellated = model.tessellate_pieces(&tess)?;
    for piece in &mut tessellated {
        piece.normals = None;
    }
    let (surface, pieces) = crate::geom::mesh::concatenate(&tessellated);
    drop(tessellated);
    // Model -> input (sampling the model included) while the model's
    // hierarchy is built, the pieces' open ends closed and the outer skin
    // found (three threads on the two cores): every sample's distance is
    // taken, those on interior triangles are left out once the outer skin
    // is known. The input mesh's ray-casting hierarchy (for the hidden
    // samples) is built on the first side too.
    // For a cloud, each sample's distance to the nearest scan point (for
    // the holes, below) and to the scan's surface ([`crate::spatial::cloud_surface`],
    // starting from that point; the spacing `√(A / N)` from all the
    // pieces' area `A`, the outer skin's not known yet, and the `N`
    // points), measured while the skin is found.
    let (samples, (skin, model_dist)) = rayon::join(
        || sample_both_ways(body, input, &surface, opts),
        || {
            // A cavity's surface lies inside its part's solid and bounds
            // empty space there: it is on the outer skin (the boundary of
            // the parts' union less the cavities), and nothing is inside
            // it. Its pieces (the last ones) are nobody's to the skin.
            let solids = &pieces[..pieces.len() - model.cavities.len().min(pieces.len())];
            let (closed, model_dist) = rayon::join(
                || ClosedPieces::new(&surface, solids),
                || MeshDistance::new(&surface),
            );
            let skin = closed.outer(&model_dist, opts.skin_depth * model.height);
            (skin, model_dist)
        },
    );
    let Samples {
        model: model_samples,
        distances: out_all,
        on,
        area,
        input: input_samples,
        input_count,
        visibility: vis,
    } = samples;
    let (out_both, out_samples): (Vec<(Real, Real)>, Vec<Point3>) = out_all
        .iter()
        .zip(&on)
        .zip(&model_samples)
        .filter(|((_, &t), _)| skin.outer[t as usize])
        .map(|((d, _), p)| (*d, *p))
        .unzip();
    let (nearest_d, out_d): (Vec<Real>, Vec<Real>) = out_both.into_iter().unzip();
    // A cloud's holes (found from the nearest-point distances): the rim
    // test's radius is 4 point spacings, the spacing `√(A / N)` from the
    // outer skin's area `A` and the `N` points.
    let over_hole = match (body, input) {
        (BodyGeometry::Cloud(c), InputDistance::Cloud(grid)) if !c.positions.is_empty() => {
            let spacing = ((area - skin.dropped_area).max(0.0) / c.positions.len() as Real).sqrt();
            crate::section::holes::over_holes(
                grid,
                &out_samples,
                &nearest_d,
                opts.coverage_mm / mm,
                crate::section::holes::RIM_RADIUS_SPACINGS * spacing,
            )
        }
        _ => vec![false; out_d.len()],
    };
    let unobserved = over_hole.iter().filter(|&&o| o).count();
    let observed_out = unflagged(&out_d, &over_hole);
    let in_d =
        model_dist.distances_where(&input_samples, Real::INFINITY, |_| true, |t| skin.outer[t]);
    let covered = in_d.iter().filter(|&&d| d * mm <= opts.coverage_mm).count();
    // Only the uncovered samples are tested (over the cores).
    let mut hidden_flags = vec![false; in_d.len()];
    if let Some(vis) = &vis {
        let far: Vec<usize> = (0..in_d.len())
            .filter(|&i| in_d[i] * mm > opts.coverage_mm)
            .collect();
        let points: Vec<Point3> = far.iter().map(|&i| input_samples[i]).collect();
        for (&i, h) in far.iter().zip(vis.hidden_all(&points)) {
            hidden_flags[i] = h;
        }
    }
    let hidden = hidden_flags.iter().filter(|&&h| h).count();
    let visible_in = unflagged(&in_d, &hidden_flags);
    // The two directions' statistics side by side (each a copy and a
    // selection over tens of thousands of distances).
    let ((av, a), (b, bv)) = crate::geom::parallel::join(
        || {
            (
                DistanceMm::of(&DistanceStats::of(&visible_in), mm),
                DistanceMm::of(&DistanceStats::of(&in_d), mm),
            )
        },
        || {
            (
                DistanceMm::of(&DistanceStats::of(&out_d), mm),
                DistanceMm::of(&DistanceStats::of(&observed_out), mm),
            )
        },
    );
    Ok(Report {
        units: opts.units,
        units_inferred: opts.infer_units,
        design_parameters: model.design_parameters(),
        compact_numbers: model.compact_numbers(),
        region_parameters: RegionParameters::of(model, &Regions::new(seg)),
        input_vertices: input_count,
        distance_mm: DistanceMm {
            rms: ((a.rms * a.rms + b.rms * b.rms) / 2.0).sqrt(),
            p95: a.p95.max(b.p95),
            max: a.max.max(b.max),
        },
        input_to_model_mm: a,
        model_to_input_mm: b,
        coverage: covered as Real / in_d.len().max(1) as Real,
        visible_coverage: covered as Real / (in_d.len() - hidden).max(1) as Real,
        hidden_samples: hidden,
        visible_rms_mm: ((av.rms * av.rms + bv.rms * bv.rms) / 2.0).sqrt(),
        visible_p95_mm: av.p95.max(bv.p95),
        unobserved_samples: unobserved,
        interior_area_share: if area > 0.0 {
            skin.dropped_area / area
        } else {
            0.0
        },
        parts: part_reports(model),
        fit: Vec::new(),
        parts_found: seg.parts.iter().map(|p| p.name).collect(),
        joints: estimate_joints(body, seg),
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_nearest_matches_brute_force() {
        let mut rng = crate::geom::rng::Rng::new(7);
        let pts: Vec<Point3> = (0..2000)
            .map(|_| Vec3::new(rng.uniform(), 2.0 * rng.uniform(), rng.uniform()))
            .collect();
        let grid = PointGrid::new(&pts, 0.05);
        for _ in 0..200 {
            let q = Vec3::new(
                3.0 * rng.uniform() - 1.0,
                3.0 * rng.uniform() - 0.5,
                rng.uniform(),
            );
            let brute = pts
                .iter()
                .map(|p| p.distance(q))
                .fold(Real::INFINITY, Real::min);
            assert!((grid.nearest(q) - brute).abs() < 1e-12, "{q:?}");
        }
        let queries: Vec<Point3> = (0..9000)
            .map(|_| {
                Vec3::new(
                    3.0 * rng.uniform() - 1.0,
                    3.0 * rng.uniform() - 0.5,
                    rng.uniform(),
                )
            })
            .collect();
        let single: Vec<Real> = queries.iter().map(|q| grid.nearest(*q)).collect();
        assert_eq!(grid.distances(&queries), single);
        // The nearest points' indices: the same distances, the indexed
        // point at that distance.
        let indexed = grid.nearest_indices(&queries);
        for ((q, d), (e, i)) in queries.iter().zip(&single).zip(&indexed) {
            assert_eq!(d, e);
            assert_eq!(grid.point(i.unwrap()).distance(*q), *d);
            assert_eq!(pts[grid.input_index(i.unwrap())], grid.point(i.unwrap()));
        }
        // Neighbourhoods cell by cell: each run lies in one cell and its
        // candidates are exactly the points within r of the run's box, in
        // the order `for_each_within` visits them.
        let mut ids: Vec<u32> = indexed.iter().filter_map(|(_, i)| *i).collect();
        ids.sort_unstable();
        ids.dedup();
        let mut seen = Vec::new();
        grid.for_each_cell_run(&ids, 0.07, |run, candidates| {
            seen.extend_from_slice(run);
            let cell = |i: u32| grid.key(grid.coords(grid.point(i)));
            assert!(run.iter().all(|&i| cell(i) == cell(run[0])));
            for &i in run {
                let mut near = Vec::new();
                grid.for_each_within(grid.point(i), 0.07, |_, x| near.push(x));
                let kept: Vec<Point3> = candidates
                    .iter()
                    .copied()
                    .filter(|x| (*x - grid.point(i)).norm_squared() <= 0.07 * 0.07)
                    .collect();
                assert_eq!(kept, near);
            }
        });
        assert_eq!(seen, ids);
        // The nearest point itself, and the points within a radius.
        for q in queries.iter().take(200) {
            let p = grid.nearest_point(*q).unwrap();
            assert_eq!(p.distance(*q), grid.nearest(*q));
            for r in [0.0, 0.03, 0.12] {
                let mut got: Vec<[u64; 3]> = grid
                    .within(*q, r)
                    .iter()
                    .map(|p| p.to_array().map(Real::to_bits))
                    .collect();
                let mut want: Vec<[u64; 3]> = pts
                    .iter()
                    .filter(|p| p.distance(*q) <= r)
                    .map(|p| p.to_array().map(Real::to_bits))
                    .collect();
                got.sort_unstable();
                want.sort_unstable();
                assert_eq!(got, want, "{q:?} {r}");
            }
        }
    }
}
