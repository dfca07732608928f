//! Triangle meshes from skinned parts.
//!
//! The surface is sampled on a grid: `around` equally spaced `v_i = 2π i/around`
//! (the same for every row, so rows join without cracks) and, per patch,
//! `along + 1` equally spaced `u` values. Consecutive patches share their
//! boundary row, and a cap's apex is one vertex, so a part capped at both
//! ends tessellates to one closed, manifold surface (every edge in exactly
//! two triangles), oriented outward (counter-clockwise seen from outside).
//!
//! Speed: `cos jv_i` and `sin jv_i` are tabulated once; each patch then
//! evaluates its coefficient functions `f_m(v_i)` and `f_m'(v_i)` once, after
//! which a row at `u` costs one small sum over `m` per vertex:
//! `t = Σ u^m f_m(v_i)`, `∂t/∂u = Σ m u^{m-1} f_m(v_i)`,
//! `∂t/∂v = Σ u^m f_m'(v_i)`, and the analytic normal `∂t/∂v × ∂t/∂u`.

use crate::curve::series::harmonics;
use crate::geom::math::{Real, Vec3};
use crate::geom::mesh::Mesh;
use crate::geom::tolerance::SIZING_ACCURACY;
use crate::surface::cap::Cap;
use crate::surface::part::{Part, Skinning};
use crate::surface::patch::Patch;
use std::f64::consts::TAU;
use thiserror::Error;

/// How finely a part is sampled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TessellationOptions {
    /// Samples around every curve (`v`), at least 3. Default 64.
    pub around: usize,
    /// Intervals along each patch (`u`), at least 1. Default 8.
    pub along: usize,
    /// Rings on each cap from its curve to the apex, at least 1. Default 16 (a dome turns through 90° in its rings).
    pub cap_rings: usize,
    /// When set, overrides the three counts: each is chosen so that the grid
    /// edges (along `u` and `v`) are at most about this long, in model units
    /// (the quads' diagonals are up to √2 times longer).
    pub target_edge: Option<Real>,
}

impl Default for TessellationOptions {
    fn default() -> Self {
        TessellationOptions {
            around: 64,
            along: 8,
            cap_rings: 16,
            target_edge: None,
        }
    }
}

/// Why a tessellation was refused.
#[derive(Debug, Error, PartialEq)]
pub enum TessellateError {
    #[error("resolution too low: around = {around} (≥ 3), along = {along} (≥ 1), cap rings = {cap_rings} (≥ 1)")]
    TooCoarse {
        around: usize,
        along: usize,
        cap_rings: usize,
    },
    #[error("the target edge length must be finite and positive, got {0}")]
    BadEdgeLength(Real),
    #[error("the mesh would have {0} vertices, more than 32-bit indices allow; use a coarser resolution")]
    TooManyVertices(u128),
}

/// `cos j v_i`, `sin j v_i` for the `around` sample angles, `j = 0..=order`.
struct TrigTable {
    around: usize,
    order: usize,
    cos: Vec<Real>,
    sin: Vec<Real>,
}

impl TrigTable {
    fn new(around: usize, order: usize) -> TrigTable {
        let w = order + 1;
        let mut cos = vec![0.0; around * w];
        let mut sin = vec![0.0; around * w];
        for i in 0..around {
            let v = TAU * i as Real / around as Real;
            harmonics(
                v,
                order,
                &mut cos[i * w..(i + 1) * w],
                &mut sin[i * w..(i + 1) * w],
            );
        }
        TrigTable {
            around,
            order,
            cos,
            sin,
        }
    }
}

/// A patch's coefficient functions evaluated at the table's angles, laid out
/// per vertex: `g[i * terms + m] = f_m(v_i)`, `gv[…] = f_m'(v_i)`.
struct PatchSamples {
    terms: usize,
    g: Vec<Vec3>,
    gv: Vec<Vec3>,
}

impl PatchSamples {
    fn new(patch: &Patch, table: &TrigTable) -> PatchSamples {
        let f = patch.coefficients();
        let (n, w, terms) = (table.around, table.order + 1, f.len());
        let mut g = vec![Vec3::ZERO; terms * n];
        let mut gv = vec![Vec3::ZERO; terms * n];
        for (m, c) in f.iter().enumerate() {
            let order =
                c.x.order()
                    .min(c.y.order())
                    .min(c.z.order())
                    .min(table.order);
            let (cx, cy, cz) = (
                &c.x.c[..2 * order + 1],
                &c.y.c[..2 * order + 1],
                &c.z.c[..2 * order + 1],
            );
            for i in 0..n {
                let (co, si) = (
                    &table.cos[i * w..i * w + order + 1],
                    &table.sin[i * w..i * w + order + 1],
                );
                let mut p = [cx[0], cy[0], cz[0]];
                let mut d = [0.0; 3];
                for j in 1..=order {
                    let (cj, sj, fj) = (co[j], si[j], j as Real);
                    let (ax, bx) = (cx[2 * j - 1], cx[2 * j]);
                    let (ay, by) = (cy[2 * j - 1], cy[2 * j]);
                    let (az, bz) = (cz[2 * j - 1], cz[2 * j]);
                    p[0] += ax * cj + bx * sj;
                    p[1] += ay * cj + by * sj;
                    p[2] += az * cj + bz * sj;
                    d[0] += fj * (bx * cj - ax * sj);
                    d[1] += fj * (by * cj - ay * sj);
                    d[2] += fj * (bz * cj - az * sj);
                }
                g[i * terms + m] = Vec3::from(p);
                gv[i * terms + m] = Vec3::from(d);
            }
        }
        PatchSamples { terms, g, gv }
    }

    /// Appends the row at `u` (positions and normals `sign · ∂v × ∂u`).
    /// Returns true when some normal is undefined (written as zero).
    fn row(&self, u: Real, sign: Real, positions: &mut Vec<Vec3>, normals: &mut Vec<Vec3>) -> bool {
        // Monomorphized for the common patch sizes (cubic patches have 4
        // terms), so the sums over m unroll.
        match self.terms {
            2 => self.row_n::<2>(u, sign, positions, normals),
            3 => self.row_n::<3>(u, sign, positions, normals),
            4 => self.row_n::<4>(u, sign, positions, normals),
            5 => self.row_n::<5>(u, sign, positions, normals),
            6 => self.row_n::<6>(u, sign, positions, normals),
            _ => {
                let n = self.g.len() / self.terms;
                let start = positions.len();
                positions.resize(start + n, Vec3::ZERO);
                normals.resize(start + n, Vec3::ZERO);
                self.row_any(u, sign, &mut positions[start..], &mut normals[start..])
            }
        }
    }

    /// Positions and normals in two passes over the samples (each a
    /// length-exact iterator, so `extend` writes without checks or zeroing).
    fn row_n<const N: usize>(
        &self,
        u: Real,
        sign: Real,
        positions: &mut Vec<Vec3>,
        normals: &mut Vec<Vec3>,
    ) -> bool {
        let (mut pw, mut dpw) = ([0.0; N], [0.0; N]);
        powers(u, &mut pw, &mut dpw);
        positions.extend(self.g.chunks_exact(N).map(|g| {
            let mut p = Vec3::ZERO;
            for m in 0..N {
                p += g[m] * pw[m];
            }
            p
        }));
        let mut undefined = false;
        normals.extend(
            self.g
                .chunks_exact(N)
                .zip(self.gv.chunks_exact(N))
                .map(|(g, gv)| {
                    let (mut du, mut dv) = (Vec3::ZERO, Vec3::ZERO);
                    for m in 0..N {
                        du += g[m] * dpw[m];
                        dv += gv[m] * pw[m];
                    }
                    let c = dv.cross(du);
                    let len2 = c.norm_squared();
                    if len2 > 0.0 && len2.is_finite() {
                        c * (sign / len2.sqrt())
                    } else {
                        undefined = true;
                        Vec3::ZERO
                    }
                }),
        );
        undefined
    }

    fn row_any(&self, u: Real, sign: Real, pos: &mut [Vec3], nrm: &mut [Vec3]) -> bool {
        let terms = self.terms;
        let mut pw = vec![0.0; terms];
        let mut dpw = vec![0.0; terms];
        powers(u, &mut pw, &mut dpw);
        let mut undefined = false;
        let samples = self.g.chunks_exact(terms).zip(self.gv.chunks_exact(terms));
        for ((g, gv), (p_out, n_out)) in samples.zip(pos.iter_mut().zip(nrm.iter_mut())) {
            let (mut p, mut du, mut dv) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
            for m in 0..terms {
                p += g[m] * pw[m];
                du += g[m] * dpw[m];
                dv += gv[m] * pw[m];
            }
            *p_out = p;
            let c = dv.cross(du);
            let len2 = c.norm_squared();
            if len2 > 0.0 && len2.is_finite() {
                *n_out = c * (sign / len2.sqrt());
            } else {
                undefined = true;
            }
        }
        undefined
    }
}

/// A row of the output grid: a ring of `around` vertices or a single apex.
#[derive(Clone, Copy)]
enum Row {
    Ring(u32),
    Apex(u32),
}

/// An estimate of the longest `u`-line of a patch (for target edge
/// lengths): the polyline through 17 points `u = i/16` along each of the
/// 8 lines `v = 2πk/8`, the longest of the 8. `table` holds those 8 angles
/// (evaluated through [`PatchSamples`], as the rows are: a tenth of the
/// time of evaluating the patch point by point).
fn u_length(patch: &Patch, table: &TrigTable) -> Real {
    let samples = PatchSamples::new(patch, table);
    let n = table.around;
    let (mut pos, mut nrm) = (Vec::with_capacity(17 * n), Vec::with_capacity(17 * n));
    for i in 0..=16 {
        samples.row(i as Real / 16.0, 1.0, &mut pos, &mut nrm);
    }
    (0..n)
        .map(|k| {
            (0..16)
                .map(|i| pos[(i + 1) * n + k].distance(pos[i * n + k]))
                .sum::<Real>()
        })
        .fold(0.0, Real::max)
}

fn steps(length: Real, edge: Real) -> usize {
    ((length / edge).ceil() as usize).clamp(1, 1 << 20)
}

/// Tessellates a part (and its caps) into one mesh with analytic normals.
pub fn tessellate_part(
    part: &Part,
    options: &TessellationOptions,
) -> Result<Mesh, TessellateError> {
    let mut mesh = Mesh::default();
    tessellate_part_into(part, options, &mut mesh)?;
    Ok(mesh)
}

/// [`tessellate_part`] into an existing mesh, replacing its contents but
/// reusing its allocations (for repeated tessellation, e.g. interactive
/// editing: fresh memory costs about as much as computing the vertices).
pub fn tessellate_part_into(
    part: &Part,
    options: &TessellationOptions,
    mesh: &mut Mesh,
) -> Result<(), TessellateError> {
    let segments = part.segments();
    let caps = [part.start_cap(), part.end_cap()];
    let order = segments
        .iter()
        .map(|s| s.patch.order())
        .chain(caps.iter().flatten().map(|c| c.patch.order()))
        .max()
        .unwrap_or(1);
    let (around, along_per, rings, ring_count) = resolution(part, options, order)?;
    let vertex_count = ring_count as u128 * around as u128 + 2;
    if vertex_count >= u32::MAX as u128 {
        return Err(TessellateError::TooManyVertices(vertex_count));
    }

    let table = TrigTable::new(around, order);
    let cap_samples = caps.map(|c| c.map(|c: &Cap| PatchSamples::new(&c.patch, &table)));

    let capacity = vertex_count as usize;
    let mut positions = std::mem::take(&mut mesh.positions);
    let mut normals = mesh.normals.take().unwrap_or_default();
    let mut triangles = std::mem::take(&mut mesh.triangles);
    positions.clear();
    normals.clear();
    triangles.clear();
    positions.reserve(capacity);
    normals.reserve(capacity);
    triangles.reserve(2 * capacity);
    let mut rows: Vec<Row> = Vec::with_capacity(ring_count + 2);
    let push_ring = |rows: &mut Vec<Row>, positions: &Vec<Vec3>| {
        rows.push(Row::Ring((positions.len() - around) as u32))
    };

    // Rings (by first vertex) where some normal is undefined.
    let mut undefined: Vec<usize> = Vec::new();

    // Start cap: apex first, then rings from the apex toward the first curve.
    // Its u runs against the part, so its normals are negated.
    if let (Some(cap), Some(samples)) = (part.start_cap(), &cap_samples[0]) {
        rows.push(Row::Apex(positions.len() as u32));
        positions.push(cap.apex);
        normals.push(Vec3::ZERO);
        for r in (1..rings[0]).rev() {
            let u = r as Real / rings[0] as Real;
            if samples.row(u, -1.0, &mut positions, &mut normals) {
                undefined.push(positions.len() - around);
            }
            push_ring(&mut rows, &positions);
        }
    }
    for (k, seg) in segments.iter().enumerate() {
        let samples = PatchSamples::new(&seg.patch, &table);
        let steps = along_per[k];
        if k > 0 && part.options().skinning == Skinning::PaperUnchained {
            // The shared row: average this patch's normals into the previous
            // patch's (they differ only where the scheme is C0; elsewhere the
            // surfaces are C1 and the normals agree).
            let start = positions.len() - around;
            let mut p = Vec::with_capacity(around);
            let mut n = Vec::with_capacity(around);
            samples.row(0.0, 1.0, &mut p, &mut n);
            for i in 0..around {
                normals[start + i] = (normals[start + i] + n[i]).normalized().unwrap_or(n[i]);
            }
            if normals[start..].contains(&Vec3::ZERO) {
                undefined.push(start);
            }
        }
        let first = if k == 0 { 0 } else { 1 };
        for j in first..=steps {
            let u = j as Real / steps as Real;
            if samples.row(u, 1.0, &mut positions, &mut normals) {
                undefined.push(positions.len() - around);
            }
            push_ring(&mut rows, &positions);
        }
    }
    if let (Some(cap), Some(samples)) = (part.end_cap(), &cap_samples[1]) {
        for r in 1..rings[1] {
            let u = r as Real / rings[1] as Real;
            if samples.row(u, 1.0, &mut positions, &mut normals) {
                undefined.push(positions.len() - around);
            }
            push_ring(&mut rows, &positions);
        }
        rows.push(Row::Apex(positions.len() as u32));
        positions.push(cap.apex);
        normals.push(Vec3::ZERO);
    }

    // Apex normals: the mean of the neighbouring ring's (the limit at a smooth
    // dome's tip, the plane normal of a flat cap).
    let ring_mean = |normals: &Vec<Vec3>, start: u32| {
        let s = start as usize;
        normals[s..s + around]
            .iter()
            .fold(Vec3::ZERO, |a, &b| a + b)
            .normalized()
            .unwrap_or(Vec3::ZERO)
    };
    if let [Row::Apex(a), Row::Ring(r), ..] = rows[..] {
        normals[a as usize] = ring_mean(&normals, r);
    }
    if let [.., Row::Ring(r), Row::Apex(a)] = rows[..] {
        normals[a as usize] = ring_mean(&normals, r);
    }
    // Normals the grid cannot give (a collapsed ring): the ring's mean.
    for &r in &undefined {
        let m = ring_mean(&normals, r as u32);
        for n in &mut normals[r..r + around] {
            if *n == Vec3::ZERO {
                *n = m;
            }
        }
    }

    stitch(&rows, around, &mut triangles);
    if part.is_clockwise() {
        for t in &mut triangles {
            t.swap(1, 2);
        }
        for nrm in &mut normals {
            *nrm = -*nrm;
        }
    }
    *mesh = Mesh {
        positions,
        normals: Some(normals),
        triangles,
    };
    Ok(())
}

/// The grid's resolution: points around, rows along each segment, rings
/// of each cap, and the rings in all (from `options`' counts, or from its
/// target edge length).
fn resolution(
    part: &Part,
    options: &TessellationOptions,
    order: usize,
) -> Result<(usize, Vec<usize>, [usize; 2], usize), TessellateError> {
    let (mut around, along, cap_rings) = (options.around, options.along, options.cap_rings);
    let segments = part.segments();
    let caps = [part.start_cap(), part.end_cap()];
    let mut along_per: Vec<usize> = vec![along; segments.len()];
    let mut rings = [cap_rings, cap_rings];
    if let Some(e) = options.target_edge {
        if !(e.is_finite() && e > 0.0) {
            return Err(TessellateError::BadEdgeLength(e));
        }
        // The perimeter only picks a sample count: the curve's default
        // accuracy would double the quadrature's samples a few more times.
        let perimeter = part
            .curves()
            .iter()
            .map(|c| c.perimeter_with_accuracy(SIZING_ACCURACY))
            .fold(0.0, Real::max);
        around = steps(perimeter, e).max(8);
        let eighths = TrigTable::new(8, order);
        along_per = segments
            .iter()
            .map(|s| steps(u_length(&s.patch, &eighths), e))
            .collect();
        for (r, cap) in rings.iter_mut().zip(caps) {
            if let Some(c) = cap {
                *r = steps(u_length(&c.patch, &eighths), e);
            }
        }
    } else if around < 3 || along < 1 || cap_rings < 1 {
        return Err(TessellateError::TooCoarse {
            around,
            along,
            cap_rings,
        });
    }
    let ring_count: usize = 1
        + along_per.iter().sum::<usize>()
        + caps
            .iter()
            .zip(rings)
            .map(|(c, r)| if c.is_some() { r - 1 } else { 0 })
            .sum::<usize>();
    Ok((around, along_per, rings, ring_count))
}

/// The triangles between consecutive rows (rings of `around` vertices or
/// apexes), appended to `triangles`.
fn stitch(rows: &[Row], around: usize, triangles: &mut Vec<[u32; 3]>) {
    let n = around as u32;
    for w in rows.windows(2) {
        let start = triangles.len();
        match (w[0], w[1]) {
            (Row::Ring(a), Row::Ring(b)) => {
                triangles.resize(start + 2 * around, [0; 3]);
                for (i, pair) in triangles[start..].chunks_exact_mut(2).enumerate() {
                    let i = i as u32;
                    let i1 = if i + 1 == n { 0 } else { i + 1 };
                    pair[0] = [a + i, a + i1, b + i1];
                    pair[1] = [a + i, b + i1, b + i];
                }
            }
            (Row::Apex(a), Row::Ring(b)) => {
                for i in 0..n {
                    let i1 = if i + 1 == n { 0 } else { i + 1 };
                    triangles.push([a, b + i1, b + i]);
                }
            }
            (Row::Ring(a), Row::Apex(b)) => {
                for i in 0..n {
                    let i1 = if i + 1 == n { 0 } else { i + 1 };
                    triangles.push([a + i, a + i1, b]);
                }
            }
            (Row::Apex(_), Row::Apex(_)) => {}
        }
    }
}

/// The powers `u^m` and their derivatives `m u^(m−1)` for `m < pw.len()`,
/// each from the previous power (no `powi` per term).
fn powers(u: Real, pw: &mut [Real], dpw: &mut [Real]) {
    let mut x = 1.0;
    for m in 0..pw.len() {
        pw[m] = x;
        dpw[m] = if m == 0 { 0.0 } else { m as Real * pw[m - 1] };
        x *= u;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::assert_vec_near;
    use crate::curve::trig::{Frame, TrigCurve};
    use crate::surface::cap::CapKind;
    use crate::surface::part::PartOptions;
    use std::collections::HashMap;
    use std::f64::consts::PI;

    fn tube(radii: &[Real], dz: Real, frame_flip: bool) -> Vec<TrigCurve> {
        radii
            .iter()
            .enumerate()
            .map(|(k, &r)| {
                let mut f = Frame {
                    origin: Vec3::new(0.1, -0.2, 0.3 + dz * k as Real),
                    e1: Vec3::X,
                    e2: Vec3::Y,
                };
                if frame_flip {
                    f = Frame {
                        origin: f.origin,
                        e1: Vec3::Y,
                        e2: Vec3::X,
                    };
                }
                TrigCurve::circle(f, r, 3)
            })
            .collect()
    }

    /// Every edge in exactly two triangles, used once in each direction.
    fn assert_closed_oriented(m: &Mesh) {
        let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
        for t in &m.triangles {
            assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "edge {a}->{b} used {count} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}->{b} has no twin");
        }
    }

    #[test]
    fn equal_circles_loft_to_a_cylinder() {
        let r = 0.07;
        for skinning in Skinning::ALL {
            let opts = PartOptions {
                skinning,
                ..PartOptions::default()
            };
            let part = Part::new(tube(&[r; 7], 0.05, false), &opts).unwrap();
            let mesh = tessellate_part(&part, &TessellationOptions::default()).unwrap();
            for (p, n) in mesh.positions.iter().zip(mesh.normals.as_ref().unwrap()) {
                let radial = Vec3::new(p.x - 0.1, p.y + 0.2, 0.0);
                assert_near!(radial.norm(), r, 1e-9);
                assert!((*n - radial / r).norm() < 1e-9, "normal {n:?}");
            }
        }
    }

    #[test]
    fn growing_circles_loft_to_a_cone() {
        let radii: Vec<Real> = (0..6).map(|k| 0.02 + 0.01 * k as Real).collect();
        let part = Part::new(tube(&radii, 0.04, false), &PartOptions::default()).unwrap();
        let mesh = tessellate_part(&part, &TessellationOptions::default()).unwrap();
        for p in &mesh.positions {
            let expected = 0.02 + 0.25 * (p.z - 0.3);
            assert_near!(Vec3::new(p.x - 0.1, p.y + 0.2, 0.0).norm(), expected, 1e-9);
        }
    }

    #[test]
    fn capped_cylinder_is_closed_outward_and_has_the_right_volume() {
        let (r, dz, n) = (0.05, 0.04, 6);
        let h = dz * (n - 1) as Real;
        for flip in [false, true] {
            let opts = PartOptions {
                start_cap: CapKind::Flat,
                end_cap: CapKind::Flat,
                ..PartOptions::default()
            };
            let part = Part::new(tube(&vec![r; n], dz, flip), &opts).unwrap();
            assert_eq!(part.is_clockwise(), flip);
            let mesh = tessellate_part(&part, &TessellationOptions::default()).unwrap();
            mesh.validate().unwrap();
            assert_closed_oriented(&mesh);
            let v = mesh.signed_volume();
            let exact = PI * r * r * h;
            println!(
                "flat-capped cylinder: volume {v:.6e} vs πr²h {exact:.6e} ({:+.3} %)",
                100.0 * (v / exact - 1.0)
            );
            assert!((v - exact).abs() < 0.005 * exact, "{v} vs {exact}");
            // Normals agree with the triangles' orientation.
            let normals = mesh.normals.as_ref().unwrap();
            for t in 0..mesh.triangles.len() {
                let [a, b, c] = mesh.triangle(t);
                let face = (b - a).cross(c - a);
                let vn = mesh.triangles[t]
                    .iter()
                    .fold(Vec3::ZERO, |s, &i| s + normals[i as usize]);
                assert!(face.dot(vn) > 0.0);
            }
        }
    }

    #[test]
    fn domed_cylinder_volume_matches_its_profile() {
        let (r, dz, n) = (0.05, 0.04, 4);
        let opts = PartOptions {
            start_cap: CapKind::dome(),
            end_cap: CapKind::dome(),
            ..PartOptions::default()
        };
        let part = Part::new(tube(&vec![r; n], dz, false), &opts).unwrap();
        let mesh = tessellate_part(&part, &TessellationOptions::default()).unwrap();
        assert_closed_oriented(&mesh);
        // Exact volume of one dome: ∫ π ρ(u)² z'(u) du over the Hermite
        // profile (radius ρ, height z), by fine midpoint quadrature.
        let cap = part.end_cap().unwrap();
        let steps = 20000;
        let dome: Real = (0..steps)
            .map(|i| {
                let u = (i as Real + 0.5) / steps as Real;
                let p = cap.patch.point(u, 0.0);
                let rho = Vec3::new(p.x - 0.1, p.y + 0.2, 0.0).norm();
                PI * rho * rho * cap.patch.du(u, 0.0).z / steps as Real
            })
            .sum();
        let exact = PI * r * r * dz * (n - 1) as Real + 2.0 * dome;
        let v = mesh.signed_volume();
        println!(
            "domed cylinder: volume {v:.6e} vs exact {exact:.6e} ({:+.3} %)",
            100.0 * (v / exact - 1.0)
        );
        assert!((v - exact).abs() < 0.005 * exact, "{v} vs {exact}");
        // A hemisphere's volume for reference: the dome is within 5 %.
        assert!((dome - 2.0 / 3.0 * PI * r.powi(3)).abs() < 0.05 * dome);
        // One apex vertex per cap.
        let apexes = mesh
            .positions
            .iter()
            .filter(|p| (**p - cap.apex).norm() < 1e-12)
            .count();
        assert_eq!(apexes, 1);
    }

    #[test]
    fn target_edge_and_bad_options() {
        let part = Part::new(tube(&[0.05; 3], 0.1, false), &PartOptions::default()).unwrap();
        let opts = TessellationOptions {
            target_edge: Some(0.01),
            ..TessellationOptions::default()
        };
        let mesh = tessellate_part(&part, &opts).unwrap();
        let max_edge = mesh
            .triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
            .map(|(a, b)| mesh.positions[a as usize].distance(mesh.positions[b as usize]))
            .fold(0.0, Real::max);
        // Grid edges are at most the target; quad diagonals up to √2 times it.
        assert!(max_edge < 0.0101 * 2f64.sqrt(), "{max_edge}");
        assert!(matches!(
            tessellate_part(
                &part,
                &TessellationOptions {
                    around: 2,
                    ..TessellationOptions::default()
                }
            ),
            Err(TessellateError::TooCoarse { .. })
        ));
        assert!(matches!(
            tessellate_part(
                &part,
                &TessellationOptions {
                    target_edge: Some(-1.0),
                    ..TessellationOptions::default()
                }
            ),
            Err(TessellateError::BadEdgeLength(_))
        ));
    }

    /// Rotating and translating the sections moves the mesh rigidly
    /// (the twist alignment, knots and caps are all frame-independent).
    #[test]
    fn rigid_motion_moves_the_mesh_rigidly() {
        let curves: Vec<TrigCurve> = (0..6)
            .map(|k| {
                let z = 0.04 * k as Real;
                let frame = Frame {
                    origin: Vec3::new(0.01 * k as Real, 0.0, z),
                    e1: Vec3::X,
                    e2: Vec3::Y,
                };
                TrigCurve::new(
                    frame,
                    vec![0.0, 0.05, 0.0, 0.004, 0.002],
                    vec![0.0, 0.04, 0.0, 0.001, -0.003],
                )
                .unwrap()
                .shifted(0.2 * k as Real)
            })
            .collect();
        // A rotation about (1, 2, 3) by 0.9 rad, and a large translation.
        let axis = Vec3::new(1.0, 2.0, 3.0).normalized().unwrap();
        let (s, c) = 0.9f64.sin_cos();
        let rot = |v: Vec3| v * c + axis.cross(v) * s + axis * (axis.dot(v) * (1.0 - c));
        let t = Vec3::new(100.0, -50.0, 20.0);
        let moved: Vec<TrigCurve> = curves
            .iter()
            .map(|cv| TrigCurve {
                frame: Frame {
                    origin: rot(cv.frame.origin) + t,
                    e1: rot(cv.frame.e1),
                    e2: rot(cv.frame.e2),
                },
                ..cv.clone()
            })
            .collect();
        let opts = PartOptions {
            start_cap: CapKind::Flat,
            end_cap: CapKind::dome(),
            ..PartOptions::default()
        };
        let a = tessellate_part(
            &Part::new(curves, &opts).unwrap(),
            &TessellationOptions::default(),
        )
        .unwrap();
        let b = tessellate_part(
            &Part::new(moved, &opts).unwrap(),
            &TessellationOptions::default(),
        )
        .unwrap();
        assert_eq!(a.triangles, b.triangles);
        for (p, q) in a.positions.iter().zip(&b.positions) {
            assert_vec_near!(rot(*p) + t, *q, 1e-9);
        }
        for (n, m) in a.normals.unwrap().iter().zip(b.normals.as_ref().unwrap()) {
            assert_vec_near!(rot(*n), *m, 1e-9);
        }
    }
}
