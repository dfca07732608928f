//! A virtual 3D body scanner: the point cloud a real multi-view scanner
//! would make of a mesh, deterministic for a given seed.
//!
//! # The model
//!
//! * **Cameras.** `azimuths × heights` pinhole cameras on a ring around the
//!   body's up axis (the line through the vertex mean along `up`), at
//!   distance `distance × H` from it, where `H` is the body's extent along
//!   `up`. Camera `k` of ring `l` sits at height `min + (l + ½)/heights · H`
//!   and azimuth `2π k / azimuths`, and looks horizontally at the axis.
//! * **Visibility.** Each view rasterizes the mesh into a depth buffer (with
//!   the id of the nearest triangle per pixel; depth is interpolated as
//!   `1/z`, linear in screen space). A surface point is seen by a view when
//!   the nearest triangle at its pixel is its own or shares a vertex with it,
//!   or its depth is within two pixel footprints of the buffer's; and when
//!   the angle between its surface normal and the direction to the camera is
//!   at most `max_incidence_deg` (real scanners lose grazing surfaces).
//!   Holes appear where no view sees: armpits, crotch, inner thighs, under
//!   the chin, the soles, tops of shoulders and head.
//! * **Sampling.** Points are drawn uniformly by area (a triangle with
//!   probability ∝ its area, then `(1 − √r₁, √r₁(1 − r₂), √r₁ r₂)`
//!   barycentric coordinates), and the first `points` samples seen by at
//!   least one view are kept (more candidates are drawn when needed).
//! * **Noise.** Gaussian (Box–Muller), `σ_n` along the surface normal and
//!   `σ_t` along each of two tangent directions.
//! * **Normals.** The mesh's surface normal at the sample (the mesh's own
//!   vertex normals interpolated, or area-weighted ones computed here, made
//!   to point outward).
//!
//! Nothing depends on units, coordinates or vertex order: the up axis is an
//! option (default: the direction of largest extent), and every length
//! default is a fraction of the body's extent.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{Mesh, MeshError, PointCloud};
use crate::geom::rng::Rng;
use thiserror::Error;

/// Options of [`virtual_scan`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScannerOptions {
    /// Number of points to produce. Default 200 000.
    pub points: usize,
    /// Seed of the random generator: same seed, same cloud. Default 1.
    pub seed: u64,
    /// Cameras per ring. Default 8.
    pub azimuths: usize,
    /// Number of rings (camera heights). Default 3.
    pub heights: usize,
    /// The body's up axis; `None` takes the principal direction of largest
    /// spread of the vertices (the height of a standing body).
    pub up: Option<Vec3>,
    /// Camera distance from the up axis, as a multiple of the body's extent
    /// `H` along it. Default 1.0.
    pub distance: Real,
    /// Depth-buffer pixels along the longer side of each image. Default 1024
    /// (about 2 mm per pixel on a 1.7 m body).
    pub resolution: usize,
    /// Largest angle (degrees) between the surface normal and the direction
    /// to the camera at which a point is still captured. Default 75.
    pub max_incidence_deg: Real,
    /// Noise along the normal, σ_n, as a fraction of `H`. Default
    /// 1/1700 (1 mm on a 1.7 m body).
    pub noise_normal: Real,
    /// Noise along each tangent direction, σ_t, as a fraction of `H`.
    /// Default 1/3400 (0.5 mm on a 1.7 m body).
    pub noise_tangent: Real,
}

impl Default for ScannerOptions {
    fn default() -> Self {
        ScannerOptions {
            points: 200_000,
            seed: 1,
            azimuths: 8,
            heights: 3,
            up: None,
            distance: 1.0,
            resolution: 1024,
            max_incidence_deg: 75.0,
            noise_normal: 1.0 / 1700.0,
            noise_tangent: 1.0 / 3400.0,
        }
    }
}

/// What went wrong in [`virtual_scan`].
#[derive(Debug, Error, PartialEq)]
pub enum ScannerError {
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    #[error("the mesh has zero surface area")]
    NoArea,
    #[error("bad scanner option {name} = {value}: {why}")]
    BadOption {
        name: &'static str,
        value: String,
        why: &'static str,
    },
    #[error("no view sees the surface (after {tested} samples): is the mesh inside out, or are the cameras inside it?")]
    NothingSeen { tested: usize },
}

/// A virtual scan and what it saw.
#[derive(Clone, Debug, PartialEq)]
pub struct VirtualScan {
    /// The points, with normals.
    pub cloud: PointCloud,
    /// Fraction of the surface area seen by at least one view (estimated
    /// from the candidate samples).
    pub seen_fraction: Real,
    /// The up axis used.
    pub up: Vec3,
    /// The camera positions.
    pub cameras: Vec<Point3>,
}

/// Scans `mesh` as a ring of cameras would (see the module docs).
///
/// ```
/// use trigbody_core::internals::geom::shapes;
/// use trigbody_core::{virtual_scan, ScannerOptions};
/// let body = shapes::stick_body(1);
/// let opts = ScannerOptions { points: 2000, resolution: 256, ..Default::default() };
/// let scan = virtual_scan(&body, &opts).unwrap();
/// assert_eq!(scan.cloud.positions.len(), 2000);
/// assert!(scan.seen_fraction < 1.0); // the legs hide each other's insides
/// ```
pub fn virtual_scan(mesh: &Mesh, opts: &ScannerOptions) -> Result<VirtualScan, ScannerError> {
    mesh.validate()?;
    check_options(opts)?;
    let normals = vertex_normals(mesh);
    // Area table for sampling.
    let mut cumulative = Vec::with_capacity(mesh.triangles.len());
    let mut total = 0.0;
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.triangle(t);
        total += (b - a).cross(c - a).norm() * 0.5;
        cumulative.push(total);
    }
    if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !total.is_finite() {
        return Err(ScannerError::NoArea);
    }
    let up = match opts.up {
        Some(u) => u.normalized().ok_or(ScannerError::BadOption {
            name: "up",
            value: format!("{:?}", u.to_array()),
            why: "must be a finite non-zero vector",
        })?,
        None => principal_axis(&mesh.positions),
    };
    let n = mesh.positions.len() as Real;
    let mean = mesh.positions.iter().fold(Vec3::ZERO, |s, &p| s + p) / n;
    let (lo, hi) = mesh
        .positions
        .iter()
        .map(|p| (*p - mean).dot(up))
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), x| {
            (l.min(x), h.max(x))
        });
    let extent = hi - lo;
    let side = up.any_perpendicular();
    let side2 = up.cross(side);
    let mut cameras = Vec::new();
    for l in 0..opts.heights {
        let z = lo + (l as Real + 0.5) / opts.heights as Real * extent;
        for k in 0..opts.azimuths {
            let phi = std::f64::consts::TAU * k as Real / opts.azimuths as Real;
            let dir = side * phi.cos() + side2 * phi.sin();
            cameras.push(mean + up * z + dir * (opts.distance * extent));
        }
    }

    let mut rng = Rng::new(opts.seed);
    let sigma_n = opts.noise_normal * extent;
    let sigma_t = opts.noise_tangent * extent;
    let cos_max = opts.max_incidence_deg.to_radians().cos();
    let mut positions = Vec::with_capacity(opts.points);
    let mut out_normals = Vec::with_capacity(opts.points);
    let (mut tested, mut seen_total) = (0usize, 0usize);
    let mut fraction: Real = 1.0;
    // A few rounds: draw candidates, keep the seen ones, until enough.
    for _round in 0..8 {
        let need = opts.points - positions.len();
        if need == 0 {
            break;
        }
        let count = ((need as Real / fraction.max(0.02)) * 1.1).ceil() as usize + 16;
        let samples: Vec<Sample> = (0..count)
            .map(|_| sample_surface(mesh, &normals, &cumulative, total, &mut rng))
            .collect();
        let mut seen = vec![false; samples.len()];
        for &cam in &cameras {
            let view = View::new(
                mesh,
                cam,
                mean + up * ((cam - mean).dot(up)),
                up,
                opts.resolution,
            );
            for (s, flag) in samples.iter().zip(seen.iter_mut()) {
                if !*flag {
                    *flag = view.sees(mesh, s, cos_max);
                }
            }
        }
        tested += samples.len();
        seen_total += seen.iter().filter(|&&s| s).count();
        fraction = seen_total as Real / tested as Real;
        if seen_total == 0 {
            continue;
        }
        for (s, _) in samples.iter().zip(&seen).filter(|(_, &f)| f) {
            if positions.len() == opts.points {
                break;
            }
            let t1 = s.normal.any_perpendicular();
            let t2 = s.normal.cross(t1);
            let p = s.position
                + s.normal * (sigma_n * rng.gaussian())
                + t1 * (sigma_t * rng.gaussian())
                + t2 * (sigma_t * rng.gaussian());
            positions.push(p);
            out_normals.push(s.normal);
        }
    }
    if positions.is_empty() {
        return Err(ScannerError::NothingSeen { tested });
    }
    Ok(VirtualScan {
        cloud: PointCloud {
            positions,
            normals: Some(out_normals),
        },
        seen_fraction: fraction,
        up,
        cameras,
    })
}

fn check_options(o: &ScannerOptions) -> Result<(), ScannerError> {
    let bad = |name, value: String, why| Err(ScannerError::BadOption { name, value, why });
    if o.points == 0 {
        return bad("points", o.points.to_string(), "must be at least 1");
    }
    if o.azimuths == 0 || o.heights == 0 {
        return bad(
            "azimuths/heights",
            format!("{}/{}", o.azimuths, o.heights),
            "need at least one camera",
        );
    }
    if !(o.distance.is_finite() && o.distance > 0.0) {
        return bad("distance", o.distance.to_string(), "must be positive");
    }
    if o.resolution < 16 || o.resolution > 16384 {
        return bad(
            "resolution",
            o.resolution.to_string(),
            "must be in 16..=16384",
        );
    }
    if !(o.max_incidence_deg > 0.0 && o.max_incidence_deg <= 90.0) {
        return bad(
            "max_incidence_deg",
            o.max_incidence_deg.to_string(),
            "must be in (0, 90]",
        );
    }
    for (name, v) in [
        ("noise_normal", o.noise_normal),
        ("noise_tangent", o.noise_tangent),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return bad(name, v.to_string(), "must be finite and ≥ 0");
        }
    }
    Ok(())
}

/// One candidate surface point.
#[derive(Clone, Copy, Debug)]
struct Sample {
    position: Point3,
    normal: Vec3,
    triangle: u32,
}

fn sample_surface(
    mesh: &Mesh,
    normals: &[Vec3],
    cumulative: &[Real],
    total: Real,
    rng: &mut Rng,
) -> Sample {
    let x = rng.uniform() * total;
    let t = cumulative
        .partition_point(|&c| c <= x)
        .min(cumulative.len() - 1);
    let (r1, r2) = (rng.uniform().sqrt(), rng.uniform());
    let w = [1.0 - r1, r1 * (1.0 - r2), r1 * r2];
    let [a, b, c] = mesh.triangles[t];
    let [pa, pb, pc] = mesh.triangle(t);
    let position = pa * w[0] + pb * w[1] + pc * w[2];
    let face = (pb - pa).cross(pc - pa).normalized().unwrap_or(Vec3::Z);
    let smooth =
        normals[a as usize] * w[0] + normals[b as usize] * w[1] + normals[c as usize] * w[2];
    let normal = smooth
        .normalized()
        .filter(|n| n.dot(face) > 0.0)
        .unwrap_or(face);
    Sample {
        position,
        normal,
        triangle: t as u32,
    }
}

/// Per-vertex unit normals pointing out of the body: the mesh's own when
/// present, else area-weighted sums of face normals; flipped when the
/// mesh's signed volume says the faces are oriented inward.
fn vertex_normals(mesh: &Mesh) -> Vec<Vec3> {
    let outward = if mesh.signed_volume() < 0.0 {
        -1.0
    } else {
        1.0
    };
    let n: Vec<Vec3> = mesh
        .vertex_normal_sums()
        .into_iter()
        .map(|s| s * outward)
        .collect();
    // Per-face orientation decides (sample_surface keeps the smooth normal
    // only when it agrees with the face); provided normals are used if they
    // agree on the whole with the computed ones.
    if let Some(given) = &mesh.normals {
        let agree: Real = given.iter().zip(&n).map(|(g, c)| g.dot(*c)).sum();
        if agree > 0.0 {
            return given
                .iter()
                .zip(&n)
                .map(|(g, c)| g.normalized().or(c.normalized()).unwrap_or(Vec3::Z))
                .collect();
        }
    }
    n.iter()
        .map(|v| v.normalized().unwrap_or(Vec3::Z))
        .collect()
}

/// The unit eigenvector of the largest eigenvalue of the vertices'
/// covariance (power iteration from the axis of largest extent).
fn principal_axis(points: &[Point3]) -> Vec3 {
    let n = points.len().max(1) as Real;
    let mean = points.iter().fold(Vec3::ZERO, |s, &p| s + p) / n;
    let mut c = [[0.0; 3]; 3];
    for p in points {
        let d = (*p - mean).to_array();
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] += d[i] * d[j] / n;
            }
        }
    }
    let mut v = [1.0, 1.0, 1.0];
    let diag = [c[0][0], c[1][1], c[2][2]];
    let imax = (0..3)
        .max_by(|&a, &b| diag[a].total_cmp(&diag[b]))
        .unwrap_or(1);
    v[imax] = 10.0;
    for _ in 0..200 {
        let w = [
            c[0][0] * v[0] + c[0][1] * v[1] + c[0][2] * v[2],
            c[1][0] * v[0] + c[1][1] * v[1] + c[1][2] * v[2],
            c[2][0] * v[0] + c[2][1] * v[1] + c[2][2] * v[2],
        ];
        match Vec3::from(w).normalized() {
            Some(u) => v = u.to_array(),
            None => break,
        }
    }
    Vec3::from(v).normalized().unwrap_or(Vec3::Y)
}

/// One camera's depth and triangle-id buffers.
struct View {
    eye: Point3,
    right: Vec3,
    down: Vec3,
    forward: Vec3,
    /// Image-plane bounds (x/z, y/z) and pixel size in those units.
    u0: Real,
    v0: Real,
    pixel: Real,
    width: usize,
    height: usize,
    depth: Vec<f32>,
    id: Vec<u32>,
}

const NO_TRIANGLE: u32 = u32::MAX;

impl View {
    fn new(mesh: &Mesh, eye: Point3, target: Point3, up: Vec3, resolution: usize) -> View {
        let forward = (target - eye).normalized().unwrap_or(-Vec3::Z);
        let right = forward
            .cross(up)
            .normalized()
            .unwrap_or(forward.any_perpendicular());
        let down = forward.cross(right);
        let near = 1e-9 * (target - eye).norm();
        let cam: Vec<(Real, Real, Real)> = mesh
            .positions
            .iter()
            .map(|&p| {
                let d = p - eye;
                let z = d.dot(forward);
                if z > near {
                    (d.dot(right) / z, d.dot(down) / z, z)
                } else {
                    (0.0, 0.0, -1.0)
                }
            })
            .collect();
        let (mut umin, mut umax, mut vmin, mut vmax) = (
            Real::INFINITY,
            Real::NEG_INFINITY,
            Real::INFINITY,
            Real::NEG_INFINITY,
        );
        for &(u, v, z) in &cam {
            if z > 0.0 {
                umin = umin.min(u);
                umax = umax.max(u);
                vmin = vmin.min(v);
                vmax = vmax.max(v);
            }
        }
        if !(umax > umin && vmax > vmin) {
            (umin, umax, vmin, vmax) = (0.0, 1.0, 0.0, 1.0);
        }
        let pixel = (umax - umin).max(vmax - vmin) / resolution as Real;
        let width = ((umax - umin) / pixel).ceil() as usize + 2;
        let height = ((vmax - vmin) / pixel).ceil() as usize + 2;
        let (u0, v0) = (umin - pixel, vmin - pixel);
        let mut view = View {
            eye,
            right,
            down,
            forward,
            u0,
            v0,
            pixel,
            width,
            height,
            depth: vec![f32::INFINITY; width * height],
            id: vec![NO_TRIANGLE; width * height],
        };
        for (ti, t) in mesh.triangles.iter().enumerate() {
            let c = [cam[t[0] as usize], cam[t[1] as usize], cam[t[2] as usize]];
            if c.iter().any(|v| v.2 <= 0.0) {
                continue;
            }
            view.rasterize(ti as u32, c);
        }
        view
    }

    /// Fills the pixels whose centres lie in the projected triangle,
    /// keeping the nearest depth (1/z interpolated linearly on screen).
    fn rasterize(&mut self, id: u32, c: [(Real, Real, Real); 3]) {
        let s: Vec<(Real, Real)> = c
            .iter()
            .map(|&(u, v, _)| ((u - self.u0) / self.pixel, (v - self.v0) / self.pixel))
            .collect();
        let area = (s[1].0 - s[0].0) * (s[2].1 - s[0].1) - (s[2].0 - s[0].0) * (s[1].1 - s[0].1);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        let xmin = s
            .iter()
            .map(|p| p.0)
            .fold(Real::INFINITY, Real::min)
            .floor()
            .max(0.0) as usize;
        let ymin = s
            .iter()
            .map(|p| p.1)
            .fold(Real::INFINITY, Real::min)
            .floor()
            .max(0.0) as usize;
        let xmax = (s
            .iter()
            .map(|p| p.0)
            .fold(Real::NEG_INFINITY, Real::max)
            .ceil() as usize)
            .min(self.width - 1);
        let ymax = (s
            .iter()
            .map(|p| p.1)
            .fold(Real::NEG_INFINITY, Real::max)
            .ceil() as usize)
            .min(self.height - 1);
        let inv_z = [1.0 / c[0].2, 1.0 / c[1].2, 1.0 / c[2].2];
        for y in ymin..=ymax {
            let py = y as Real + 0.5;
            for x in xmin..=xmax {
                let px = x as Real + 0.5;
                let edge = |a: (Real, Real), b: (Real, Real)| {
                    (b.0 - a.0) * (py - a.1) - (px - a.0) * (b.1 - a.1)
                };
                let w0 = edge(s[1], s[2]) / area;
                let w1 = edge(s[2], s[0]) / area;
                let w2 = edge(s[0], s[1]) / area;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let z = (1.0 / (w0 * inv_z[0] + w1 * inv_z[1] + w2 * inv_z[2])) as f32;
                let k = y * self.width + x;
                if z < self.depth[k] {
                    self.depth[k] = z;
                    self.id[k] = id;
                }
            }
        }
    }

    /// Whether this camera captures the sample (see the module docs).
    fn sees(&self, mesh: &Mesh, s: &Sample, cos_max: Real) -> bool {
        let to_eye = self.eye - s.position;
        let dist = to_eye.norm();
        if s.normal.dot(to_eye) < cos_max * dist {
            return false;
        }
        let d = s.position - self.eye;
        let z = d.dot(self.forward);
        if z <= 0.0 {
            return false;
        }
        let x = ((d.dot(self.right) / z - self.u0) / self.pixel).floor();
        let y = ((d.dot(self.down) / z - self.v0) / self.pixel).floor();
        if x < 0.0 || y < 0.0 || x >= self.width as Real || y >= self.height as Real {
            return false;
        }
        let k = y as usize * self.width + x as usize;
        let id = self.id[k];
        if id == NO_TRIANGLE || id == s.triangle {
            return true;
        }
        let (a, b) = (
            mesh.triangles[id as usize],
            mesh.triangles[s.triangle as usize],
        );
        if a.iter().any(|v| b.contains(v)) {
            return true;
        }
        z <= self.depth[k] as Real + 2.0 * self.pixel * z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::geom::shapes;

    #[test]
    fn rng_is_deterministic_and_gaussian_has_unit_variance() {
        let mut a = Rng::new(7);
        let mut b = Rng::new(7);
        assert!((0..100).all(|_| a.next_u64() == b.next_u64()));
        let mut r = Rng::new(3);
        let n = 200_000;
        let xs: Vec<Real> = (0..n).map(|_| r.gaussian()).collect();
        let mean = xs.iter().sum::<Real>() / n as Real;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<Real>() / n as Real;
        assert_near!(mean, 0.0, 0.01);
        assert_near!(var, 1.0, 0.02);
        let u: Vec<Real> = (0..1000).map(|_| r.uniform()).collect();
        assert!(u.iter().all(|&x| (0.0..1.0).contains(&x)));
    }

    fn small() -> ScannerOptions {
        ScannerOptions {
            points: 20_000,
            resolution: 512,
            ..Default::default()
        }
    }

    /// A convex solid seen from all around: every point is on the surface
    /// within the noise, normals are the sphere's, and the same seed gives
    /// the same cloud.
    #[test]
    fn sphere_scan_lies_on_the_sphere_with_the_right_noise() {
        let r = 0.5;
        let m = shapes::uv_sphere(Vec3::new(1.0, 2.0, 3.0), r, 64, 128);
        let opts = ScannerOptions {
            up: Some(Vec3::Z),
            ..small()
        };
        let scan = virtual_scan(&m, &opts).unwrap();
        let c = Vec3::new(1.0, 2.0, 3.0);
        let pts = &scan.cloud.positions;
        assert_eq!(pts.len(), 20_000);
        let extent = 2.0 * r;
        let sn = opts.noise_normal * extent;
        let radial: Vec<Real> = pts.iter().map(|p| p.distance(c) - r).collect();
        let rms = (radial.iter().map(|d| d * d).sum::<Real>() / pts.len() as Real).sqrt();
        // faceting shrinks the radius by < 1e-4 r; noise σ_n dominates
        assert_near!(rms / sn, 1.0, 0.1);
        let normals = scan.cloud.normals.as_ref().unwrap();
        for (p, n) in pts.iter().zip(normals) {
            assert!(n.dot((*p - c) / r) > 0.99);
        }
        // the poles are seen only at grazing angles from horizontal cameras
        // at ±1/3 of the height: the caps above 75° incidence are holes
        assert!(scan.seen_fraction < 0.999 && scan.seen_fraction > 0.8);
        let again = virtual_scan(&m, &opts).unwrap();
        assert_eq!(again.cloud, scan.cloud);
        let other = virtual_scan(&m, &ScannerOptions { seed: 2, ..opts }).unwrap();
        assert_ne!(other.cloud, scan.cloud);
    }

    /// Occlusion: of two cylinders 1 cm apart, the facing inner sides are
    /// hidden (by the other cylinder from the side and diagonal cameras, by
    /// the grazing angle from the front and back ones); the outer sides are
    /// seen. The up axis (the long one) is found.
    #[test]
    fn occlusion_makes_holes_between_close_parts() {
        let m = shapes::merge(&[
            shapes::cylinder(Vec3::new(-0.105, 0.0, 0.0), 0.1, 1.5, 16, 96),
            shapes::cylinder(Vec3::new(0.105, 0.0, 0.0), 0.1, 1.5, 16, 96),
        ]);
        let scan = virtual_scan(&m, &small()).unwrap();
        assert!(scan.up.z.abs() > 0.99, "up = {:?}", scan.up);
        let pts = &scan.cloud.positions;
        let band = |p: &&Point3| p.z < 1.2 && p.z > 0.3;
        // strips ±12° about the inner and the outer direction of each
        let inner = pts
            .iter()
            .filter(band)
            .filter(|p| p.x.abs() < 0.105 - 0.1 * (12f64).to_radians().cos())
            .count();
        let outer = pts
            .iter()
            .filter(band)
            .filter(|p| p.x.abs() > 0.105 + 0.1 * (12f64).to_radians().cos())
            .count();
        assert!(outer > 300);
        assert!(inner * 20 < outer, "inner {inner}, outer {outer}");
        assert!(scan.seen_fraction < 0.95);
    }

    #[test]
    fn bad_options_and_meshes_are_typed_errors() {
        let m = shapes::uv_sphere(Vec3::ZERO, 1.0, 8, 8);
        for o in [
            ScannerOptions {
                points: 0,
                ..small()
            },
            ScannerOptions {
                resolution: 2,
                ..small()
            },
            ScannerOptions {
                distance: -1.0,
                ..small()
            },
            ScannerOptions {
                up: Some(Vec3::ZERO),
                ..small()
            },
            ScannerOptions {
                noise_normal: f64::NAN,
                ..small()
            },
        ] {
            assert!(matches!(
                virtual_scan(&m, &o),
                Err(ScannerError::BadOption { .. })
            ));
        }
        assert_eq!(
            virtual_scan(&Mesh::default(), &small()),
            Err(ScannerError::Mesh(MeshError::NoVertices))
        );
        let flat = Mesh {
            positions: vec![Vec3::ZERO; 3],
            normals: None,
            triangles: vec![[0, 1, 2]],
        };
        assert_eq!(virtual_scan(&flat, &small()), Err(ScannerError::NoArea));
    }
}
