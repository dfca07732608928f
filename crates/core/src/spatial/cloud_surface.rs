//! The distance from a point to the **surface a point cloud samples**, not
//! to the cloud's nearest point.
//!
//! A scan of spacing `s` puts a point of a perfectly measured surface up to
//! `s/√2` from the nearest scan point of a square grid (`s·√(1/6)` RMS),
//! and `s/√π` ≈ 0.56 `s` RMS from the nearest of uniformly random points
//! of the same density (`P(d₀ > x) = e^{−πx²/s²}`): the nearest-point
//! distance has a floor set by the sampling, not by the surface.
//! Metrology tools model the cloud locally instead (a least-squares plane
//! about the nearest point); so does this module, with the plane bounded
//! where the points stop.
//!
//! # The surfel of a scan point
//!
//! For the cloud point `q` nearest a query `p`:
//!
//! * **Neighbours** `N`: the cloud points within `R = FIT_RADIUS_SPACINGS ·
//!   s` of `q` (`s` the cloud's mean spacing, given by the caller), `q`
//!   included; when fewer than [`MIN_FIT_POINTS`], those within `2R`. (A
//!   part thinner than `R`, an ear's rim, puts both its sides in the
//!   neighbourhood; filtering them by normal costs a cache miss per
//!   neighbour for no real gain.)
//! * **Plane**: through the neighbours' centroid `c` (`k` points), with
//!   normal `n` = `q`'s own normal when the cloud has one (finite, non-zero),
//!   else the eigenvector of the smallest eigenvalue `λ₃` of their
//!   covariance `C = 1/k Σ (x − c)(x − c)ᵀ` (the least-squares plane),
//!   required to be a plane: `λ₂ ≥ PLANARITY · λ₃`.
//! * **Radius** `r`: the local spacing `√(A/k)`, with `A` the area the
//!   neighbours cover estimated from their spread in the plane:
//!   `A = 4π √det C₂`, `C₂` the covariance's 2×2 block on two unit
//!   vectors across `n`. For points spread uniformly over an ellipse of
//!   semi-axes `a`, `b` (`C₂ = diag(a²/4, b²/4)`) that is its area `πab`
//!   exactly; over a half disk (a point on a hole's rim) it is 1.66 `R²`
//!   for 1.57 `R²`, so a rim point's `r` is 3 % larger than inside. The
//!   disk of radius `r` about each point covers the plane for a square grid
//!   (covering radius `s/√2`) and, for random points, all but the
//!   `e^{−π}` ≈ 4 % of the plane farther than `s` from every point.
//! * **Surfel**: the disk of radius `r` in that plane about `q`'s projection
//!   `q' = q − ((q − c)·n) n`.
//!
//! The distance from `p` to the surface is its distance to that disk,
//! at most the distance `d₀ = |p − q|` to the point itself (the surface
//! passes through its points, up to their noise):
//!
//! ```text
//! d = min(d₀, √(d_n² + max(0, d_t − r)²)),   d_n = (p − c)·n,
//!                                            d_t = |(p − q) − ((p − q)·n) n|.
//! ```
//!
//! What it measures:
//!
//! * on a plane sampled without noise `c` and `n` are exact and `d_t ≤ r`
//!   wherever the disks cover: `d = 0` (the unit tests' square grid);
//! * noise `σ` along the normal enters through the centroid, `σ/√k`, not
//!   `σ` (the nearest point carries all of it);
//! * a surface of curvature radius `ρ` puts the centroid `R²/(4ρ)` or so
//!   inside it (the mean sagitta over the disk), at most `R²/(2ρ)`;
//! * **over a hole** (the model closes a surface the scanner did not see)
//!   `q` is on the hole's rim and `d_t` is the distance to it. With
//!   `d₀ = √(((p − q)·n)² + d_t²)` and `e = |(q − c)·n|` the point's own
//!   offset from its plane (its noise), the triangle inequality gives
//!   `d₀ − r − e ≤ d ≤ d₀`: the distance to the surface never falls below
//!   the distance to the nearest point by more than a disk's radius, so
//!   over a hole it stays the hole's size minus `r`, never the distance to
//!   an extended plane;
//! * at a **sharp feature** (a toe's tip, the nose) the neighbours wrap
//!   round it and their plane through the centroid lies off both sides:
//!   there the bound `d ≤ d₀` holds the nearest-point distance (without it
//!   such samples would come out above it).
//!
//! Fallbacks, never a panic: no finite point or a query that is not finite
//! gives `∞` (as [`PointGrid::nearest`]); a point with fewer than
//! [`MIN_FIT_POINTS`] neighbours within `2R`, no plane (collinear or
//! scattered neighbours without normals) or a spacing that is not a
//! positive finite number gives the nearest-point distance.
//!
//! Cost: [`CloudSurface::distances`] finds each query's nearest point once
//! (the grid's Morton-ordered, seeded search) and builds one surfel per
//! distinct nearest point, in the grid's cell order over the cores, the
//! neighbours of a cell's points picked out of one gathering of that
//! cell's surroundings (`PointGrid::for_each_cell_run`): nearly one surfel
//! per sample on a dense scan.

use crate::geom::linalg::symmetric_eigen3;
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::parallel::parallel_map;
use crate::spatial::point_grid::PointGrid;

/// The neighbours' radius `R` in point spacings: about `π·2.5²` ≈ 20
/// neighbours on average. Larger radii average the noise over more points
/// (`σ/√k`) but put the centroid deeper inside a curved surface
/// (`R²/(4ρ)`); 2.5 is the best against a known surface
/// (`crates/io/tests/cloud_surface_real.rs`), with or without scan normals.
pub const FIT_RADIUS_SPACINGS: Real = 2.5;

/// Fewer neighbours (the point included) than this within `R` and `2R`:
/// no surfel, the nearest-point distance.
pub const MIN_FIT_POINTS: usize = 6;

/// Without normals, the neighbours make a plane when their in-plane
/// spread is at least this many times their spread across it
/// (`λ₂ ≥ PLANARITY · λ₃`).
pub const PLANARITY: Real = 2.0;

/// A scan point's disk of the surface (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surfel {
    /// The scan point `q`.
    pub point: Point3,
    /// The neighbours' centroid `c`, a point of the local plane.
    pub centre: Point3,
    /// The plane's unit normal `n` (its sign is not meaningful).
    pub normal: Vec3,
    /// The disk's radius `r`, the local spacing.
    pub radius: Real,
}

impl Surfel {
    /// The distance from `p` to the disk: `√(d_n² + max(0, d_t − r)²)`
    /// (without the module doc's bound by the distance to the point).
    pub fn distance(&self, p: Point3) -> Real {
        let dn = (p - self.centre).dot(self.normal);
        let v = p - self.point;
        let dt = (v - self.normal * v.dot(self.normal)).norm();
        let out = (dt - self.radius).max(0.0);
        (dn * dn + out * out).sqrt()
    }
}

/// Distances to the surface a cloud samples (see the module doc).
#[derive(Debug)]
pub struct CloudSurface<'g, 'a> {
    grid: &'g PointGrid<'a>,
    normals: Option<&'g [Vec3]>,
    /// `R` (not finite when the spacing was not a positive number).
    radius: Real,
}

/// Sums of the neighbours' offsets `d` from `q` and of their outer
/// products `d dᵀ` (its upper triangle: xx, xy, xz, yy, yz, zz).
#[derive(Default)]
struct Moments {
    count: Real,
    sum: [Real; 3],
    outer: [Real; 6],
}

impl Moments {
    #[inline]
    fn add(&mut self, d: Vec3) {
        self.count += 1.0;
        self.sum[0] += d.x;
        self.sum[1] += d.y;
        self.sum[2] += d.z;
        self.outer[0] += d.x * d.x;
        self.outer[1] += d.x * d.y;
        self.outer[2] += d.x * d.z;
        self.outer[3] += d.y * d.y;
        self.outer[4] += d.y * d.z;
        self.outer[5] += d.z * d.z;
    }

    /// The covariance about the mean, `1/k Σ d dᵀ − μ μᵀ`, and the mean
    /// offset `μ`.
    fn covariance(&self) -> ([[Real; 3]; 3], Vec3) {
        let k = self.count;
        let mu = [self.sum[0] / k, self.sum[1] / k, self.sum[2] / k];
        let o = &self.outer;
        let full = [[o[0], o[1], o[2]], [o[1], o[3], o[4]], [o[2], o[4], o[5]]];
        let mut cov = [[0.0; 3]; 3];
        for (i, row) in cov.iter_mut().enumerate() {
            for (j, c) in row.iter_mut().enumerate() {
                *c = full[i][j] / k - mu[i] * mu[j];
            }
        }
        (cov, Vec3::from(mu))
    }
}

impl<'g, 'a> CloudSurface<'g, 'a> {
    /// The surface of the cloud `grid` indexes. `normals`: the cloud's,
    /// one per point of the slice the grid was built from (a point whose
    /// normal is missing, not finite or zero gets its plane's); `spacing`:
    /// the cloud's mean point spacing (e.g. `√(A/N)` for `N` points over an
    /// area `A`).
    pub fn new(
        grid: &'g PointGrid<'a>,
        normals: Option<&'g [Vec3]>,
        spacing: Real,
    ) -> CloudSurface<'g, 'a> {
        let radius = if spacing > 0.0 && spacing.is_finite() {
            FIT_RADIUS_SPACINGS * spacing
        } else {
            Real::NAN
        };
        CloudSurface {
            grid,
            normals,
            radius,
        }
    }

    /// The cloud's unit normal at the point of grid index `i`, when it has
    /// a usable one.
    fn normal(&self, i: u32) -> Option<Vec3> {
        let n = *self.normals?.get(self.grid.input_index(i))?;
        if n.is_finite() {
            n.normalized()
        } else {
            None
        }
    }

    /// The surfel of the cloud point nearest `p` (`None`: no point, or
    /// see the module doc's fallbacks).
    pub fn surfel_near(&self, p: Point3) -> Option<Surfel> {
        self.surfel(self.grid.nearest_indices(&[p])[0].1?)
    }

    /// The surfel of the point of index `i` in the grid's order (`None`:
    /// see the module doc's fallbacks).
    pub(crate) fn surfel(&self, i: u32) -> Option<Surfel> {
        if i as usize >= self.grid.len() || !self.radius.is_finite() {
            return None;
        }
        let q = self.grid.point(i);
        let mut m = Moments::default();
        self.grid
            .for_each_within(q, self.radius, |_, x| m.add(x - q));
        self.fit(i, m)
    }

    /// The surfels of `ids` (indices in the grid's order, ascending; all
    /// below [`PointGrid::len`]), exactly [`CloudSurface::surfel`] of each:
    /// the neighbours are gathered cell by cell
    /// ([`PointGrid::for_each_cell_run`]) and visited in the same order.
    fn surfels(&self, ids: &[u32]) -> Vec<Option<Surfel>> {
        let mut out = Vec::with_capacity(ids.len());
        let r2 = self.radius * self.radius;
        // The neighbours' places among the candidates, written without a
        // branch (each candidate's slot is kept when it is a neighbour),
        // then their moments in the candidates' order.
        let mut near: Vec<u32> = Vec::new();
        self.grid
            .for_each_cell_run(ids, self.radius, |run, candidates| {
                near.resize(candidates.len() + 1, 0);
                for &i in run {
                    let q = self.grid.point(i);
                    let mut n = 0;
                    for (k, &x) in candidates.iter().enumerate() {
                        near[n] = k as u32;
                        n += usize::from((x - q).norm_squared() <= r2);
                    }
                    let mut m = Moments::default();
                    for &k in &near[..n] {
                        m.add(candidates[k as usize] - q);
                    }
                    out.push(self.fit(i, m));
                }
            });
        out.resize(ids.len(), None);
        out
    }

    /// The surfel of the point of grid index `i` from the moments of its
    /// neighbours within `R` (those within `2R` when they are too few).
    fn fit(&self, i: u32, mut m: Moments) -> Option<Surfel> {
        let q = self.grid.point(i);
        let enough = MIN_FIT_POINTS as Real;
        if m.count < enough {
            m = Moments::default();
            self.grid
                .for_each_within(q, 2.0 * self.radius, |_, x| m.add(x - q));
        }
        if m.count < enough {
            return None;
        }
        let (cov, mean) = m.covariance();
        let normal = match self.normal(i) {
            Some(n) => n,
            None => {
                let (values, vectors) = symmetric_eigen3(cov);
                if !(values[1] >= PLANARITY * values[2].max(0.0)) {
                    return None;
                }
                vectors[2]
            }
        };
        let e1 = normal.any_perpendicular();
        let e2 = normal.cross(e1);
        let quad = |a: Vec3, b: Vec3| {
            let (a, b) = (a.to_array(), b.to_array());
            (0..3)
                .map(|i| (0..3).map(|j| a[i] * cov[i][j] * b[j]).sum::<Real>())
                .sum::<Real>()
        };
        let det = quad(e1, e1) * quad(e2, e2) - quad(e1, e2).powi(2);
        let area = 4.0 * std::f64::consts::PI * det.sqrt();
        if !(area > 0.0) || !area.is_finite() {
            return None;
        }
        Some(Surfel {
            point: q,
            centre: q + mean,
            normal,
            radius: (area / m.count).sqrt(),
        })
    }

    /// The distance from `p` to the surface (see the module doc).
    pub fn distance(&self, p: Point3) -> Real {
        let near = self.grid.nearest_indices(&[p]);
        self.distances_from(&[p], &near)[0]
    }

    /// The distance from each of `points` to the surface, exactly
    /// [`CloudSurface::distance`] of each.
    pub fn distances(&self, points: &[Point3]) -> Vec<Real> {
        let near = self.grid.nearest_indices(points);
        self.distances_from(points, &near)
    }

    /// [`CloudSurface::distances`] with each point's nearest-point distance
    /// and index already found ([`PointGrid::nearest_indices`]'s answer
    /// for `points`): one surfel per distinct nearest point, built in the
    /// grid's order (neighbouring points one after another) over the
    /// cores.
    pub(crate) fn distances_from(
        &self,
        points: &[Point3],
        nearest: &[(Real, Option<u32>)],
    ) -> Vec<Real> {
        let n = self.grid.len();
        let mut slot = vec![u32::MAX; n];
        for &(_, i) in nearest {
            if let Some(i) = i.filter(|&i| (i as usize) < n) {
                slot[i as usize] = 0;
            }
        }
        let ids: Vec<u32> = (0..n as u32).filter(|&i| slot[i as usize] == 0).collect();
        for (k, &i) in ids.iter().enumerate() {
            slot[i as usize] = k as u32;
        }
        let surfels = if self.radius.is_finite() {
            parallel_map(&ids, 256, |run| self.surfels(run))
        } else {
            Vec::new()
        };
        points
            .iter()
            .zip(nearest)
            .map(|(p, &(d, i))| {
                let s = i
                    .and_then(|i| slot.get(i as usize))
                    .and_then(|&k| surfels.get(k as usize).copied().flatten());
                s.map_or(d, |s| s.distance(*p).min(d))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::rng::Rng;

    /// A tilted plane's orthonormal axes `(a, b)`, its normal and origin.
    fn plane() -> (Vec3, Vec3, Vec3, Point3) {
        let (c, s) = (0.5f64.cos(), 0.5f64.sin());
        let (a, b) = (Vec3::new(c, 0.0, s), Vec3::new(0.0, 1.0, 0.0));
        (a, b, a.cross(b), Vec3::new(0.3, -0.2, 0.7))
    }

    /// The square grid `origin + s (i a + j b)`, `|i|, |j| ≤ m`, without
    /// the points nearer the origin than `hole`.
    fn grid_cloud(s: Real, m: i32, hole: Real) -> Vec<Point3> {
        let (a, b, _, o) = plane();
        let mut out = Vec::new();
        for i in -m..=m {
            for j in -m..=m {
                let (u, v) = (i as Real * s, j as Real * s);
                if (u * u + v * v).sqrt() >= hole {
                    out.push(o + a * u + b * v);
                }
            }
        }
        out
    }

    fn rms(d: &[Real]) -> Real {
        (d.iter().map(|d| d * d).sum::<Real>() / d.len() as Real).sqrt()
    }

    /// `n` Fibonacci points on the unit sphere about `centre`, and their
    /// (exact) normals.
    fn fibonacci(n: usize, centre: Point3) -> (Vec<Point3>, Vec<Vec3>) {
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let normals: Vec<Vec3> = (0..n)
            .map(|i| {
                let z = 1.0 - (2.0 * i as Real + 1.0) / n as Real;
                let rho = (1.0 - z * z).sqrt();
                let phi = golden * i as Real;
                Vec3::new(rho * phi.cos(), rho * phi.sin(), z)
            })
            .collect();
        (normals.iter().map(|u| centre + *u).collect(), normals)
    }

    fn random_unit(rng: &mut Rng) -> Vec3 {
        loop {
            let v = Vec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian());
            if let Some(u) = v.normalized() {
                return u;
            }
        }
    }

    /// A plane sampled on an exact square grid of spacing `s`: the
    /// nearest-point distance of points on the plane has the sampling's
    /// floor, RMS `s·√(1/6)` (`E[x² + y²]` over a cell, `x, y` uniform on
    /// `±s/2`); the distance to the surface is 0 (rounding: < 1e-9), the
    /// surfels' radii the spacing. (The neighbours' radius 2.5 `s` falls
    /// between the grid's distances √5 and √8: no neighbour is left to
    /// rounding.)
    #[test]
    fn a_grid_on_a_plane_measures_zero_not_the_spacing() {
        let s = 0.01;
        let pts = grid_cloud(s, 40, 0.0);
        let grid = PointGrid::new(&pts, 4.0 * s);
        let surface = CloudSurface::new(&grid, None, s);
        let (a, b, _, o) = plane();
        let mut rng = Rng::new(11);
        let queries: Vec<Point3> = (0..5000)
            .map(|_| {
                o + a * (40.0 * s * (rng.uniform() - 0.5)) + b * (40.0 * s * (rng.uniform() - 0.5))
            })
            .collect();
        let old = grid.distances(&queries);
        let ratio = rms(&old) / (s * (1.0 / 6.0 as Real).sqrt());
        assert!((ratio - 1.0).abs() < 0.03, "{ratio}");
        let new = surface.distances(&queries);
        let worst = new.iter().fold(0.0, |m: Real, d| m.max(*d));
        assert!(worst < 1e-9, "{worst}");
        // Inside the grid (4 spacings from its edges) every surfel's radius
        // is the spacing (Σx² over the 21 points within 2.5 s is 34 s² per
        // axis: r = √(4π·34/21 / 21) s = 0.984 s).
        for i in 0..grid.len() as u32 {
            let q = grid.point(i) - o;
            if q.dot(a).abs() < 36.5 * s && q.dot(b).abs() < 36.5 * s {
                let r = surface.surfel(i).unwrap().radius / s;
                let want = (4.0 * std::f64::consts::PI * 34.0 / 21.0 / 21.0).sqrt();
                assert!((r - want).abs() < 1e-9, "{r} {want}");
            }
        }
    }

    /// Fibonacci points on a unit sphere (spacing `s = √(4π/N)`): points
    /// of the sphere are within the centroid's sagitta `R²/(2ρ)` of the
    /// surface, `R²/(4ρ)` in RMS (`R = 2.5 s`; the nearest point is about
    /// 6 times farther), and a point `h` off the sphere measures `h` to the
    /// same bound, inside and outside.
    #[test]
    fn a_sphere_measures_its_surface() {
        let n = 4000;
        let centre = Vec3::new(1.0, 2.0, -0.5);
        let (pts, _) = fibonacci(n, centre);
        let s = (4.0 * std::f64::consts::PI / n as Real).sqrt();
        let grid = PointGrid::new(&pts, 0.1);
        let surface = CloudSurface::new(&grid, None, s);
        let mut rng = Rng::new(5);
        let dirs: Vec<Vec3> = (0..3000).map(|_| random_unit(&mut rng)).collect();
        let on: Vec<Point3> = dirs.iter().map(|u| centre + *u).collect();
        let fit = FIT_RADIUS_SPACINGS * s;
        let bound = fit * fit / 2.0;
        let new = surface.distances(&on);
        let old = grid.distances(&on);
        assert!(new.iter().all(|d| *d < bound), "{bound}");
        assert!(rms(&new) < bound / 2.0, "{} {}", rms(&new), bound / 2.0);
        assert!(rms(&new) < 0.25 * rms(&old), "{} {}", rms(&new), rms(&old));
        for h in [0.05, -0.05] {
            let off: Vec<Point3> = dirs.iter().map(|u| centre + *u * (1.0 + h)).collect();
            for d in surface.distances(&off) {
                assert!((d - h.abs()).abs() < bound, "{h} {d}");
            }
        }
    }

    /// The cloud's exact normals and the fitted planes' give the same
    /// distances to within a small share of the spacing (the fitted
    /// normal's tilt times the in-plane offset).
    #[test]
    fn estimated_normals_match_exact_ones() {
        let n = 4000;
        let centre = Vec3::new(-0.3, 0.4, 2.0);
        let (pts, normals) = fibonacci(n, centre);
        let s = (4.0 * std::f64::consts::PI / n as Real).sqrt();
        let grid = PointGrid::new(&pts, 0.1);
        let with = CloudSurface::new(&grid, Some(&normals), s);
        let without = CloudSurface::new(&grid, None, s);
        let mut rng = Rng::new(8);
        let queries: Vec<Point3> = (0..3000)
            .map(|_| centre + random_unit(&mut rng) * (1.0 + 0.1 * (rng.uniform() - 0.5)))
            .collect();
        let (a, b) = (with.distances(&queries), without.distances(&queries));
        let worst = a
            .iter()
            .zip(&b)
            .fold(0.0, |m: Real, (x, y)| m.max((x - y).abs()));
        assert!(worst < 0.05 * s, "{worst} vs spacing {s}");
        // Normals that are not finite or zero count as missing.
        let mut broken = normals.clone();
        for (k, v) in broken.iter_mut().enumerate() {
            *v = if k % 2 == 0 {
                Vec3::new(Real::NAN, 0.0, 0.0)
            } else {
                Vec3::ZERO
            };
        }
        let none = CloudSurface::new(&grid, Some(&broken), s);
        assert_eq!(none.distances(&queries), b);
    }

    /// Over a circular hole of radius `R` in a sampled plane, the distance
    /// stays the distance to the hole's rim less the rim surfel's radius
    /// (about the spacing), not the distance to the plane (0).
    #[test]
    fn a_hole_stays_as_wide_as_it_is() {
        let s = 0.01;
        let hole = 10.5 * s;
        let pts = grid_cloud(s, 40, hole);
        let grid = PointGrid::new(&pts, 4.0 * s);
        let surface = CloudSurface::new(&grid, None, s);
        let (_, _, n, o) = plane();
        let nearest = pts
            .iter()
            .map(|p| p.distance(o))
            .fold(Real::INFINITY, Real::min);
        let rim = surface.surfel_near(o).unwrap();
        assert!(
            rim.radius > 0.9 * s && rim.radius < 1.3 * s,
            "{}",
            rim.radius
        );
        let d = surface.distance(o);
        assert!((d - (nearest - rim.radius)).abs() < 1e-9, "{d} {nearest}");
        assert!(d > hole - 1.3 * s, "{d}");
        // Above the hole's centre by h: √(h² + (R − r)²) (the nearest
        // point one of the rim's points at the same distance).
        let h = 3.0 * s;
        let rim = surface.surfel_near(o + n * h).unwrap();
        let d = surface.distance(o + n * h);
        let want = (h * h + (nearest - rim.radius).powi(2)).sqrt();
        assert!((d - want).abs() < 1e-9, "{d} {want}");
    }

    /// A right-angled ridge sampled on a grid (spacing `s` along both
    /// faces): across the ridge the fitted planes lie off both faces, and
    /// the distance never exceeds the nearest point's; on the faces, two
    /// fit radii from the ridge, it is 0 (exact planes).
    #[test]
    fn a_ridge_never_measures_beyond_its_points() {
        let s = 0.01;
        let (h, m) = (std::f64::consts::FRAC_1_SQRT_2, 30);
        let roof = |u: Real, y: Real| Vec3::new(u * h, y, -u.abs() * h);
        let mut pts = Vec::new();
        for i in -m..=m {
            for j in -m..=m {
                pts.push(roof(i as Real * s, j as Real * s));
            }
        }
        let grid = PointGrid::new(&pts, 4.0 * s);
        let surface = CloudSurface::new(&grid, None, s);
        let mut rng = Rng::new(4);
        let on: Vec<(Real, Point3)> = (0..4000)
            .map(|_| {
                let u = 40.0 * s * (rng.uniform() - 0.5);
                (u, roof(u, 40.0 * s * (rng.uniform() - 0.5)))
            })
            .collect();
        let queries: Vec<Point3> = on.iter().map(|(_, p)| *p).collect();
        let (near, d) = (grid.distances(&queries), surface.distances(&queries));
        for ((u, _), (near, d)) in on.iter().zip(near.iter().zip(&d)) {
            assert!(d <= near, "{u} {d} {near}");
            if u.abs() > 2.0 * FIT_RADIUS_SPACINGS * s {
                assert!(*d < 1e-9, "{u} {d}");
            }
        }
    }

    /// Empty clouds, clouds too small for a plane, collinear or coincident
    /// points, points and queries that are not finite, bad spacings and
    /// short normal arrays fall back to the nearest-point distance (∞ with
    /// no point), without a panic.
    #[test]
    fn degenerate_clouds_fall_back_to_the_nearest_point() {
        let q = [Vec3::new(0.1, 0.2, 0.3), Vec3::new(Real::NAN, 0.0, 0.0)];
        let empty: Vec<Point3> = Vec::new();
        let grid = PointGrid::new(&empty, 0.1);
        let d = CloudSurface::new(&grid, None, 0.1).distances(&q);
        assert!(d.iter().all(|d| *d == Real::INFINITY));

        let nan = Vec3::new(Real::NAN, 1.0, 1.0);
        let few = vec![nan, Vec3::ZERO, Vec3::X * 0.01, nan, Vec3::Y * 0.01];
        let line: Vec<Point3> = (0..50)
            .map(|k| Vec3::new(0.01 * k as Real, 0.0, 0.0))
            .collect();
        let same = vec![Vec3::new(0.1, 0.2, 0.25); 20];
        let normals = [Vec3::Z; 3];
        for pts in [&few, &line, &same] {
            let grid = PointGrid::new(pts, 0.1);
            let near = grid.distances(&q);
            for spacing in [0.01, 0.0, Real::NAN, Real::INFINITY, -1.0] {
                for n in [None, Some(&normals[..])] {
                    let surface = CloudSurface::new(&grid, n, spacing);
                    assert_eq!(surface.distances(&q)[0], near[0], "{spacing}");
                    assert_eq!(surface.distances(&q)[1], Real::INFINITY);
                }
            }
        }
    }

    /// The batch (Morton-ordered, over the cores, the neighbours gathered
    /// cell by cell) gives exactly each point's own surfel and distance.
    #[test]
    fn batch_equals_single_queries() {
        let (pts, normals) = fibonacci(3000, Vec3::ZERO);
        let grid = PointGrid::new(&pts, 0.1);
        let s = (4.0 * std::f64::consts::PI / 3000.0).sqrt();
        let mut rng = Rng::new(2);
        let queries: Vec<Point3> = (0..9000)
            .map(|_| random_unit(&mut rng) * (0.7 + 0.6 * rng.uniform()))
            .collect();
        for n in [None, Some(&normals[..])] {
            let surface = CloudSurface::new(&grid, n, s);
            let ids: Vec<u32> = (0..grid.len() as u32).collect();
            let single: Vec<Option<Surfel>> = ids.iter().map(|&i| surface.surfel(i)).collect();
            assert!(single.iter().all(Option::is_some));
            assert_eq!(surface.surfels(&ids), single);
            let batch = surface.distances(&queries);
            for (q, d) in queries.iter().zip(&batch).step_by(7) {
                assert_eq!(surface.distance(*q), *d);
            }
        }
    }
}
