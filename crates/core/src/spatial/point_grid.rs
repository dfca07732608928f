//! A uniform grid over a point cloud for nearest-point queries.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::tolerance::ROUNDING_MARGIN;
use crate::spatial::distance::coherent_map;

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
        let (lo, cell, dims) = crate::geom::mesh::grid_layout(points, cell, 4.0e6);
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
        crate::geom::parallel::par_for_each_mut(&mut keys, 1 << 15, |i, key| {
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
        crate::geom::parallel::par_for_each_mut(&mut grid.sorted, 1 << 15, |k, x| {
            *x = points[order[k] as usize].to_array();
        });
        grid.order = order;
        grid
    }

    pub(crate) fn coords(&self, p: Point3) -> [i64; 3] {
        let d = (p - self.origin) / self.cell;
        [d.x.floor() as i64, d.y.floor() as i64, d.z.floor() as i64]
    }

    pub(crate) fn key(&self, c: [i64; 3]) -> usize {
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
                if apart.norm_squared() > r * r * (1.0 + ROUNDING_MARGIN) {
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
