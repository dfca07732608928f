//! The [`Report`]: how well and how compactly a [`Body`] fits its input.

use super::*;
use crate::cloud_surface::CloudSurface;
use crate::distance::{coherent_map, sample_surface_on_triangles};
use crate::joints::{estimate_joints, JointName};
use crate::skin::ClosedPieces;

/// Per-part numbers of the [`Report`].
#[derive(Clone, Debug, PartialEq)]
pub struct PartReport {
    /// The part (for a cavity: the part it lies in).
    pub name: PartName,
    /// True for a cavity ([`BodyCavity`]) of the part `name`.
    pub cavity: bool,
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

/// How well and how compactly the model fits its input.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The model's design parameters (method.md §7).
    pub design_parameters: usize,
    /// The input's vertex (mesh) or point (cloud) count; the polygon
    /// baseline is `3 × input_vertices`.
    pub input_vertices: usize,
    /// Symmetric distance: `rms = √((rms_in² + rms_out²)/2)`, `p95` and
    /// `max` the larger of the two directions'.
    pub distance_mm: DistanceMm,
    /// Input → model: input surface samples (mesh) or points (cloud) to
    /// the model's outer skin ([`crate::skin`]: the boundary of the union
    /// of its pieces, the triangles of a piece lying inside another one
    /// deeper than [`ReconstructOptions::skin_depth`] left out).
    pub input_to_model_mm: DistanceMm,
    /// Model → input: samples of the model's outer skin to the input's
    /// surface: the mesh, or the surface a cloud samples
    /// ([`crate::cloud_surface`]: the distance to a least-squares disk of
    /// the local point spacing's radius at the nearest scan point, at most
    /// the distance to that point; the distance to the nearest point alone
    /// has a floor of the point spacing, 1.9 mm RMS for a perfect model of
    /// a 200 000-point body scan). The samples are those
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
    /// escapes the input, [`crate::visibility`]: the inside of a modelled
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
    /// ([`crate::holes`]: the soles the body stood on, the crown, the
    /// crotch). Their distance measures the hole, not the model. 0 for a
    /// mesh.
    pub unobserved_samples: usize,
    /// Share of the pieces' tessellated area lying inside other pieces
    /// (not on the outer skin), left out of both directions.
    pub interior_area_share: Real,
    pub parts: Vec<PartReport>,
    /// Parts the segmentation found (feet included).
    pub parts_found: Vec<PartName>,
    /// Joint centres estimated from the segmentation
    /// ([`crate::joints::estimate_joints`]), in the input's coordinates.
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
    let parts = body.parts.iter().map(|p| (p.name, false, &p.part, &p.fits));
    let cavities = body
        .cavities
        .iter()
        .map(|c| (c.within, true, &c.part, &c.fits));
    parts
        .chain(cavities)
        .map(|(name, cavity, part, fits)| {
            let mut orders: Vec<usize> = fits.iter().map(|f| f.order).collect();
            orders.sort_unstable();
            let med = orders.get(orders.len() / 2).copied().unwrap_or(0);
            let fold = |f: &dyn Fn(&SectionFit) -> Real| fits.iter().map(f).fold(0.0, Real::max);
            PartReport {
                name,
                cavity,
                sections: fits.len(),
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

/// The pieces (without normals) one after another in one mesh and each
/// piece's range of triangles in it, as [`crate::skin::concatenate`]
/// makes them: the positions and the renumbered triangles copied side by
/// side on two cores (the report's surface is about 9 MB; most of the
/// time is the first touch of the fresh arrays' pages).
fn concatenate(pieces: &[Mesh]) -> (Mesh, Vec<std::ops::Range<usize>>) {
    let (positions, triangles) = crate::distance::join(
        || {
            let mut out = Vec::with_capacity(pieces.iter().map(|m| m.positions.len()).sum());
            for m in pieces {
                out.extend_from_slice(&m.positions);
            }
            out
        },
        || {
            let mut out = Vec::with_capacity(pieces.iter().map(|m| m.triangles.len()).sum());
            let mut base = 0u32;
            for m in pieces {
                out.extend(m.triangles.iter().map(|t| t.map(|v| v + base)));
                base += m.positions.len() as u32;
            }
            out
        },
    );
    let mut ranges = Vec::with_capacity(pieces.len());
    let mut start = 0;
    for m in pieces {
        ranges.push(start..start + m.triangles.len());
        start += m.triangles.len();
    }
    (
        Mesh {
            positions,
            normals: None,
            triangles,
        },
        ranges,
    )
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
    let (surface, pieces) = concatenate(&tessellated);
    drop(tessellated);
    // Model -> input (sampling the model included) while the model's
    // hierarchy is built, the pieces' open ends closed and the outer skin
    // found (three threads on the two cores): every sample's distance is
    // taken, those on interior triangles are left out once the outer skin
    // is known. The input mesh's ray-casting hierarchy (for the hidden
    // samples) is built on the first side too.
    // For a cloud, each sample's distance to the nearest scan point (for
    // the holes, below) and to the scan's surface ([`crate::cloud_surface`],
    // starting from that point; the spacing `√(A / N)` from all the
    // pieces' area `A`, the outer skin's not known yet, and the `N`
    // points), measured while the skin is found.
    let ((model_samples, out_all, on, area, input_samples, input_count, vis), skin, model_dist) =
        std::thread::scope(|scope| {
            let out = scope.spawn(|| {
                let (model_samples, on, area) =
                    sample_surface_on_triangles(&surface, opts.report_samples);
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
                        Some(crate::visibility::Visibility::new(m)),
                    ),
                    BodyGeometry::Cloud(c) => (
                        every_kth(&c.positions, opts.report_samples),
                        c.positions.len(),
                        None,
                    ),
                };
                (model_samples, d, on, area, samples, count, vis)
            });
            // A cavity's surface lies inside its part's solid and bounds
            // empty space there: it is on the outer skin (the boundary of
            // the parts' union less the cavities), and nothing is inside
            // it. Its pieces (the last ones) are nobody's to the skin.
            let solids = &pieces[..pieces.len() - model.cavities.len().min(pieces.len())];
            let closed = scope.spawn(|| ClosedPieces::new(&surface, solids));
            let model_dist = MeshDistance::new(&surface);
            let skin = match closed.join() {
                Ok(c) => c.outer(&model_dist, opts.skin_depth * model.height),
                Err(panic) => std::panic::resume_unwind(panic),
            };
            match out.join() {
                Ok(o) => (o, skin, model_dist),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        });
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
            crate::holes::over_holes(
                grid,
                &out_samples,
                &nearest_d,
                opts.coverage_mm / mm,
                crate::holes::RIM_RADIUS_SPACINGS * spacing,
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
    let ((av, a), (b, bv)) = crate::distance::join(
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
        design_parameters: model.design_parameters(),
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
        parts_found: seg.parts.iter().map(|p| p.name).collect(),
        joints: estimate_joints(seg),
        warnings,
    })
}

/// A uniform grid over a point cloud for nearest-point distances: cells of
/// side `cell`, hashed by integer coordinates; a query searches shells of
/// cells outward until the shell's inner distance exceeds the best found.
#[derive(Debug)]
pub struct PointGrid<'a> {
    /// The grid copies the points it indexes ([`PointGrid::new`]'s `points`
    /// stay borrowed for the API's sake).
    points: std::marker::PhantomData<&'a [Point3]>,
    cell: Real,
    origin: Point3,
    dims: [usize; 3],
    /// Start of each cell's run in `sorted` (prefix sums, length cells + 1).
    starts: Vec<u32>,
    /// The finite points cell by cell (a cell's points side by side in
    /// memory), as coordinate triples: a zeroed array of them is one the
    /// system zeroes page by page on first touch, so the cores that fill
    /// it share the touching ([`PointGrid::new`]).
    sorted: Vec<[Real; 3]>,
    /// The index in [`PointGrid::new`]'s `points` of each of `sorted`
    /// (a cloud's normals are looked up through it).
    order: Vec<u32>,
}

impl<'a> PointGrid<'a> {
    /// Builds the grid; `cell` is clamped so there are at most ~4M cells.
    pub fn new(points: &'a [Point3], cell: Real) -> PointGrid<'a> {
        let (lo, cell, dims) = crate::mesh::grid_layout(points, cell, 4.0e6);
        let n = dims[0] * dims[1] * dims[2];
        let mut grid = PointGrid {
            points: std::marker::PhantomData,
            cell,
            origin: lo,
            dims,
            starts: vec![0; n + 1],
            sorted: Vec::new(),
            order: Vec::new(),
        };
        // Each point's cell (`u32::MAX` for a point left out: the grid
        // has at most ~4M cells), over the cores. The grid's origin is the
        // finite points' minimum, so their offsets are at least 0 and
        // truncation is the floor of `coords` (without a call to `floor`
        // per coordinate).
        let mut keys = vec![0u32; points.len()];
        crate::distance::par_for_each_mut(&mut keys, 1 << 15, |i, key| {
            let p = points[i];
            *key = if p.is_finite() {
                let d = (p - grid.origin) / grid.cell;
                grid.key([d.x as i64, d.y as i64, d.z as i64]) as u32
            } else {
                u32::MAX
            };
        });
        for &k in keys.iter().filter(|&&k| k != u32::MAX) {
            grid.starts[k as usize + 1] += 1;
        }
        for i in 0..n {
            grid.starts[i + 1] += grid.starts[i];
        }
        // The points' indices cell by cell (in index order within a
        // cell), then the points gathered in that order over the cores:
        // the scatter moves 4-byte indices, the gather writes in
        // sequence.
        let mut fill = grid.starts.clone();
        let mut order = vec![0u32; grid.starts[n] as usize];
        for (i, &k) in keys.iter().enumerate() {
            if k != u32::MAX {
                order[fill[k as usize] as usize] = i as u32;
                fill[k as usize] += 1;
            }
        }
        grid.sorted = vec![[0.0; 3]; order.len()];
        crate::distance::par_for_each_mut(&mut grid.sorted, 1 << 15, |k, x| {
            *x = points[order[k] as usize].to_array();
        });
        grid.order = order;
        grid
    }

    fn coords(&self, p: Point3) -> [i64; 3] {
        let d = (p - self.origin) / self.cell;
        [d.x.floor() as i64, d.y.floor() as i64, d.z.floor() as i64]
    }

    fn key(&self, c: [i64; 3]) -> usize {
        let cl = |v: i64, n: usize| v.clamp(0, n as i64 - 1) as usize;
        (cl(c[2], self.dims[2]) * self.dims[1] + cl(c[1], self.dims[1])) * self.dims[0]
            + cl(c[0], self.dims[0])
    }

    /// Distance from `p` to the nearest point (infinite for an empty cloud).
    pub fn nearest(&self, p: Point3) -> Real {
        self.nearest_from(p, None).0
    }

    /// The distance from each of `points` to the nearest point, exactly as
    /// [`PointGrid::nearest`], faster: the points are visited in Morton
    /// order ([`coherent_map`]) and each search starts from the previous
    /// point's nearest point, whose distance bounds it (cells farther away
    /// are skipped).
    pub fn distances(&self, points: &[Point3]) -> Vec<Real> {
        self.nearest_indices(points)
            .into_iter()
            .map(|(d, _)| d)
            .collect()
    }

    /// The distance from `p` to the nearest point and that point's index
    /// in the grid's order, starting from the point of index `seed` (its
    /// distance bounds the search; it is the answer unless a point lies
    /// strictly closer). Squared distances are compared and the square
    /// root taken once (the same number: the root is monotone and
    /// correctly rounded).
    fn nearest_from(&self, p: Point3, seed: Option<u32>) -> (Real, Option<u32>) {
        if self.sorted.is_empty() || !p.is_finite() {
            return (Real::INFINITY, None);
        }
        let seed = seed.filter(|&i| (i as usize) < self.sorted.len());
        let (mut best2, mut best_i) = match seed {
            Some(i) => (
                (Vec3::from(self.sorted[i as usize]) - p).norm_squared(),
                Some(i),
            ),
            None => (Real::INFINITY, None),
        };
        let c = self.coords(p);
        let clamp = |v: i64, n: usize| v.clamp(0, n as i64 - 1);
        let cc = [
            clamp(c[0], self.dims[0]),
            clamp(c[1], self.dims[1]),
            clamp(c[2], self.dims[2]),
        ];
        // Distance from p to its projection q on the grid's box: for x in
        // the (convex) box, |p - x|² ≥ |p - q|² + |q - x|².
        let hi = self.origin
            + Vec3::new(
                self.dims[0] as Real * self.cell,
                self.dims[1] as Real * self.cell,
                self.dims[2] as Real * self.cell,
            );
        let q = Vec3::new(
            p.x.clamp(self.origin.x, hi.x),
            p.y.clamp(self.origin.y, hi.y),
            p.z.clamp(self.origin.z, hi.z),
        );
        let outside2 = (p - q).norm_squared();
        let maxr = *self.dims.iter().max().unwrap_or(&1) as i64;
        for r in 0..=maxr {
            // Every point in shell r is at least (r - 1) cells from q.
            let inner = ((r - 1).max(0) as Real) * self.cell;
            if best2.is_finite() && outside2 + inner * inner > best2 {
                break;
            }
            for dz in -r..=r {
                for dy in -r..=r {
                    for dx in -r..=r {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                            continue;
                        }
                        let q = [cc[0] + dx, cc[1] + dy, cc[2] + dz];
                        if (0..3).any(|i| q[i] < 0 || q[i] >= self.dims[i] as i64) {
                            continue;
                        }
                        // Skip a cell whose box is no nearer than the best.
                        let lo = self.origin
                            + Vec3::new(q[0] as Real, q[1] as Real, q[2] as Real) * self.cell;
                        let hi = lo + Vec3::new(self.cell, self.cell, self.cell);
                        let gap = Vec3::new(
                            (lo.x - p.x).max(0.0).max(p.x - hi.x),
                            (lo.y - p.y).max(0.0).max(p.y - hi.y),
                            (lo.z - p.z).max(0.0).max(p.z - hi.z),
                        );
                        if gap.norm_squared() >= best2 {
                            continue;
                        }
                        let k = self.key(q);
                        let (a, b) = (self.starts[k] as usize, self.starts[k + 1] as usize);
                        for (i, x) in (a..b).zip(&self.sorted[a..b]) {
                            let d2 = (Vec3::from(*x) - p).norm_squared();
                            if d2 < best2 {
                                best2 = d2;
                                best_i = Some(i as u32);
                            }
                        }
                    }
                }
            }
        }
        (best2.sqrt(), best_i)
    }

    /// The point nearest `p` (`None` for an empty cloud).
    pub fn nearest_point(&self, p: Point3) -> Option<Point3> {
        self.nearest_from(p, None)
            .1
            .map(|i| Vec3::from(self.sorted[i as usize]))
    }

    /// For each of `points`, the distance to the nearest point and that
    /// point's index in the grid's order (`None` for an empty cloud or a
    /// point that is not finite), as [`PointGrid::distances`] finds them
    /// (the same distances).
    pub(crate) fn nearest_indices(&self, points: &[Point3]) -> Vec<(Real, Option<u32>)> {
        coherent_map(points, |p, seed: &mut Option<u32>| {
            let (d, i) = self.nearest_from(p, *seed);
            *seed = i;
            (d, i)
        })
    }

    /// The point of index `i` in the grid's order (`i` below
    /// [`PointGrid::len`]).
    pub(crate) fn point(&self, i: u32) -> Point3 {
        Vec3::from(self.sorted[i as usize])
    }

    /// The index in [`PointGrid::new`]'s `points` of the point of index
    /// `i` in the grid's order.
    pub(crate) fn input_index(&self, i: u32) -> usize {
        self.order[i as usize] as usize
    }

    /// The number of points indexed (the finite ones).
    pub fn len(&self) -> usize {
        self.sorted.len()
    }

    /// True when no (finite) point is indexed.
    pub fn is_empty(&self) -> bool {
        self.sorted.is_empty()
    }

    /// The points within distance `r` of `p`.
    pub fn within(&self, p: Point3, r: Real) -> Vec<Point3> {
        let mut out = Vec::new();
        self.for_each_within(p, r, |_, q| out.push(q));
        out
    }

    /// `f(run, candidates)` for each run of `ids` (indices in the grid's
    /// order, ascending) lying in one cell, `candidates` the points within
    /// `r` of the run's bounding box (in the order
    /// [`PointGrid::for_each_within`] visits them): every point within `r`
    /// of a run's point is among them (its distance to the box is at most
    /// its distance to the point, in floating point too: the box's
    /// coordinate differences are no larger, rounding being monotone). The
    /// neighbourhoods of many points, each cell's surroundings gathered
    /// once for all its points. Indices past the grid's points are skipped;
    /// nothing is called for a radius that is not a finite number ≥ 0.
    pub(crate) fn for_each_cell_run(
        &self,
        ids: &[u32],
        r: Real,
        mut f: impl FnMut(&[u32], &[Point3]),
    ) {
        if !(r >= 0.0) || !r.is_finite() {
            return;
        }
        let n = self.sorted.len() as u32;
        let mut candidates = Vec::new();
        let mut rest = ids;
        while let Some(&first) = rest.first() {
            if first >= n {
                rest = &rest[1..];
                continue;
            }
            // The cell holding `first`: the last whose run starts at or
            // before it.
            let k = self.starts.partition_point(|&s| s <= first) - 1;
            let end = self.starts[k + 1];
            let (run, tail) = rest.split_at(rest.partition_point(|&i| i < end).max(1));
            rest = tail;
            let (lo, hi) = run.iter().fold(
                (
                    Vec3::new(Real::INFINITY, Real::INFINITY, Real::INFINITY),
                    Vec3::new(Real::NEG_INFINITY, Real::NEG_INFINITY, Real::NEG_INFINITY),
                ),
                |(lo, hi), &i| {
                    let q = Vec3::from(self.sorted[i as usize]);
                    (lo.min(q), hi.max(q))
                },
            );
            candidates.clear();
            let reach = Vec3::new(r, r, r);
            self.for_each_cell(lo - reach, hi + reach, |cell, span| {
                if span.is_empty() {
                    return;
                }
                // A cell whose box lies farther than r from the run's box
                // holds no candidate (the box distance bounds its points').
                let c_lo = self.origin
                    + Vec3::new(cell[0] as Real, cell[1] as Real, cell[2] as Real) * self.cell;
                let c_hi = c_lo + Vec3::new(self.cell, self.cell, self.cell);
                let apart = (c_lo - hi).max(lo - c_hi).max(Vec3::ZERO);
                if apart.norm_squared() > r * r * (1.0 + 1e-9) {
                    return;
                }
                for q in &self.sorted[span] {
                    let q = Vec3::from(*q);
                    let gap = (lo - q).max(q - hi).max(Vec3::ZERO);
                    if gap.norm_squared() <= r * r {
                        candidates.push(q);
                    }
                }
            });
            f(run, &candidates);
        }
    }

    /// `f(i, q)` for every point `q` (index `i` in the grid's order)
    /// within distance `r` of `p`, cell by cell.
    pub(crate) fn for_each_within(&self, p: Point3, r: Real, mut f: impl FnMut(u32, Point3)) {
        if self.sorted.is_empty() || !p.is_finite() || !(r >= 0.0) {
            return;
        }
        let reach = Vec3::new(r, r, r);
        self.for_each_cell(p - reach, p + reach, |_, span| {
            for (i, q) in span.clone().zip(&self.sorted[span]) {
                let q = Vec3::from(*q);
                if (q - p).norm_squared() <= r * r {
                    f(i as u32, q);
                }
            }
        });
    }

    /// `f(cell, points)` for every cell of the grid meeting the box
    /// `[lo, hi]` (clamped to the grid), in z, y, x order: its integer
    /// coordinates and the range of its points in the grid's order.
    fn for_each_cell(
        &self,
        lo: Point3,
        hi: Point3,
        mut f: impl FnMut([i64; 3], std::ops::Range<usize>),
    ) {
        let (a, b) = (self.coords(lo), self.coords(hi));
        let clamp = |v: i64, n: usize| v.clamp(0, n as i64 - 1);
        for z in clamp(a[2], self.dims[2])..=clamp(b[2], self.dims[2]) {
            for y in clamp(a[1], self.dims[1])..=clamp(b[1], self.dims[1]) {
                for x in clamp(a[0], self.dims[0])..=clamp(b[0], self.dims[0]) {
                    let k = self.key([x, y, z]);
                    f(
                        [x, y, z],
                        self.starts[k] as usize..self.starts[k + 1] as usize,
                    );
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two-core concatenation is the skin module's, array for array.
    #[test]
    fn concatenation_matches_the_skins() {
        let piece = |k: u32, n: u32| Mesh {
            positions: (0..n)
                .map(|i| Vec3::new(i as Real, k as Real, (i * k) as Real * 0.5))
                .collect(),
            normals: None,
            triangles: (0..n.saturating_sub(2))
                .map(|i| [i, (i + 1 + k) % n, (i + 2) % n])
                .collect(),
        };
        let pieces = vec![piece(1, 7), piece(2, 3), piece(3, 0), piece(4, 12)];
        let (mine, ranges) = concatenate(&pieces);
        let (skin, skin_ranges) = crate::skin::concatenate(&pieces);
        assert_eq!(mine, skin);
        assert_eq!(ranges, skin_ranges);
        assert_eq!(concatenate(&[]), crate::skin::concatenate(&[]));
    }

    #[test]
    fn grid_nearest_matches_brute_force() {
        let mut rng = crate::scanner::Rng::new(7);
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
