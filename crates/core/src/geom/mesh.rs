//! The one triangle-mesh and point-cloud types that every reader fills and
//! every consumer (sections, tessellation, writers, renderer, measurements)
//! uses.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::stats::nth_smallest;
use thiserror::Error;

/// An indexed triangle mesh with f64 positions and optional per-vertex normals.
///
/// Triangles are counter-clockwise seen from outside (right-hand rule gives the
/// outward normal) when the mesh is a closed surface written that way.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Point3>,
    /// Per-vertex normals, same length as `positions` when present.
    pub normals: Option<Vec<Vec3>>,
    pub triangles: Vec<[u32; 3]>,
}

/// A cloud of points with optional per-point normals (a scan).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointCloud {
    pub positions: Vec<Point3>,
    /// Per-point normals, same length as `positions` when present.
    pub normals: Option<Vec<Vec3>>,
}

/// What is wrong with a mesh or point cloud handed to the core.
#[derive(Debug, Error, PartialEq)]
pub enum MeshError {
    #[error("the mesh has no vertices")]
    NoVertices,
    #[error("the mesh has no triangles")]
    NoTriangles,
    #[error("vertex {index} has a non-finite coordinate ({value:?}); remove or repair it")]
    NonFinite { index: usize, value: [Real; 3] },
    #[error("triangle {triangle} refers to vertex {vertex}, but there are only {count} vertices")]
    IndexOutOfRange {
        triangle: usize,
        vertex: u32,
        count: usize,
    },
    #[error("{normals} normals for {positions} vertices: the counts must match")]
    NormalCount { normals: usize, positions: usize },
}

/// The layout of a uniform grid over the finite points of `points`:
/// `(origin, cell, dims)`. The cell is `cell` (1 when that is not a
/// positive number), grown so the grid has at most about `max_cells`
/// cells; an input with no finite point gives a one-cell grid at the
/// origin. Shared by the point grids of the report and of the cutter.
pub(crate) fn grid_layout(
    points: &[Point3],
    cell: Real,
    max_cells: Real,
) -> (Point3, Real, [usize; 3]) {
    let fin = || points.iter().filter(|p| p.is_finite());
    let lo = fin().fold(
        Vec3::new(Real::INFINITY, Real::INFINITY, Real::INFINITY),
        |a, p| a.min(*p),
    );
    let hi = fin().fold(
        Vec3::new(Real::NEG_INFINITY, Real::NEG_INFINITY, Real::NEG_INFINITY),
        |a, p| a.max(*p),
    );
    let (lo, hi) = if lo.x <= hi.x {
        (lo, hi)
    } else {
        (Vec3::ZERO, Vec3::ZERO)
    };
    let ext = hi - lo;
    let mut cell = if cell.is_finite() && cell > 0.0 {
        cell
    } else {
        1.0
    };
    let vol = (ext.x / cell + 1.0) * (ext.y / cell + 1.0) * (ext.z / cell + 1.0);
    if vol > max_cells {
        cell *= (vol / max_cells).cbrt();
    }
    let dims = [
        (ext.x / cell) as usize + 1,
        (ext.y / cell) as usize + 1,
        (ext.z / cell) as usize + 1,
    ];
    (lo, cell, dims)
}

/// The cell of `p` in a grid laid out by [`grid_layout`] (`origin`,
/// `cell`, `dims`), clamped to the grid.
pub(crate) fn grid_cell(p: Point3, origin: Point3, cell: Real, dims: [usize; 3]) -> [usize; 3] {
    let d = (p - origin) / cell;
    // `v as usize` is `v.floor().max(0.0) as usize` for every `v` (the
    // cast truncates, takes negatives and NaN to 0 and saturates).
    let c = |v: Real, n: usize| (v as usize).min(n - 1);
    [c(d.x, dims[0]), c(d.y, dims[1]), c(d.z, dims[2])]
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Point3,
    pub max: Point3,
}

impl Aabb {
    /// The box around `points`, or `None` when there are none.
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Point3>) -> Option<Aabb> {
        let mut it = points.into_iter();
        let first = *it.next()?;
        let (min, max) = it.fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        Some(Aabb { min, max })
    }
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }
    pub fn center(&self) -> Point3 {
        (self.min + self.max) * 0.5
    }
    /// Length of the box diagonal: the natural length scale of the geometry.
    pub fn diagonal(&self) -> Real {
        self.size().norm()
    }
    /// True when the two closed boxes share a point.
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.min.x <= o.max.x
            && o.min.x <= self.max.x
            && self.min.y <= o.max.y
            && o.min.y <= self.max.y
            && self.min.z <= o.max.z
            && o.min.z <= self.max.z
    }
    /// The box grown by `margin` on every side.
    pub fn grown(&self, margin: Real) -> Aabb {
        let m = Vec3::new(margin, margin, margin);
        Aabb {
            min: self.min - m,
            max: self.max + m,
        }
    }
}

fn check_points(positions: &[Point3], normals: Option<&Vec<Vec3>>) -> Result<(), MeshError> {
    if positions.is_empty() {
        return Err(MeshError::NoVertices);
    }
    if let Some((index, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(MeshError::NonFinite {
            index,
            value: p.to_array(),
        });
    }
    if let Some(n) = normals {
        if n.len() != positions.len() {
            return Err(MeshError::NormalCount {
                normals: n.len(),
                positions: positions.len(),
            });
        }
    }
    Ok(())
}

impl Mesh {
    /// A mesh from positions and triangles, validated (see [`Mesh::validate`]).
    pub fn new(positions: Vec<Point3>, triangles: Vec<[u32; 3]>) -> Result<Mesh, MeshError> {
        let mesh = Mesh {
            positions,
            normals: None,
            triangles,
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// Checks what every algorithm relies on: at least one vertex and one
    /// triangle, finite coordinates, indices in range, normal count.
    pub fn validate(&self) -> Result<(), MeshError> {
        check_points(&self.positions, self.normals.as_ref())?;
        if self.triangles.is_empty() {
            return Err(MeshError::NoTriangles);
        }
        let count = self.positions.len();
        for (triangle, t) in self.triangles.iter().enumerate() {
            if let Some(&vertex) = t.iter().find(|&&i| i as usize >= count) {
                return Err(MeshError::IndexOutOfRange {
                    triangle,
                    vertex,
                    count,
                });
            }
        }
        Ok(())
    }

    /// The bounding box, or `None` for an empty mesh.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::from_points(&self.positions)
    }

    /// The three corners of triangle `t`.
    #[inline]
    pub fn triangle(&self, t: usize) -> [Point3; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Total surface area, Σ |(b−a)×(c−a)|/2.
    pub fn surface_area(&self) -> Real {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.triangle(t);
                (b - a).cross(c - a).norm() * 0.5
            })
            .sum()
    }

    /// Turns the mesh inside out: each triangle's winding reversed (`[a, b,
    /// c]` → `[a, c, b]`) and each normal negated, so the surface faces the
    /// other way (a cavity's, which faces into the pocket).
    pub fn flip_orientation(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
        if let Some(n) = &mut self.normals {
            for v in n.iter_mut() {
                *v = -*v;
            }
        }
    }

    /// The edges that keep the mesh from being a closed, consistently
    /// oriented surface: `(bad, misoriented)`, the undirected edges not in
    /// exactly two triangles, and those in two triangles that run it the
    /// same way.
    pub fn edge_faults(&self) -> (usize, usize) {
        // Each triangle edge as its undirected key and whether it runs up.
        let mut edges: Vec<(u64, bool)> = self
            .triangles
            .iter()
            .flat_map(|t| {
                (0..3).map(move |k| {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    (((a.min(b) as u64) << 32) | a.max(b) as u64, a < b)
                })
            })
            .collect();
        edges.sort_unstable();
        let (mut bad, mut misoriented) = (0, 0);
        for run in edges.chunk_by(|x, y| x.0 == y.0) {
            let up = run.iter().filter(|e| e.1).count();
            if run.len() != 2 {
                bad += 1;
            } else if up != 1 {
                misoriented += 1;
            }
        }
        (bad, misoriented)
    }

    /// Signed enclosed volume by the divergence theorem,
    /// V = Σ a·(b×c)/6 over the triangles (positive for a closed,
    /// outward-oriented surface; exact for any origin when closed).
    pub fn signed_volume(&self) -> Real {
        let o = self.bounds().map(|b| b.center()).unwrap_or_default();
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.triangle(t);
                (a - o).dot((b - o).cross(c - o)) / 6.0
            })
            .sum()
    }

    /// Per vertex, the sum of its triangles' `(b−a)×(c−a)` (twice their
    /// area along their normal, so large faces count more); triangles with
    /// an index out of range are skipped.
    pub fn vertex_normal_sums(&self) -> Vec<Vec3> {
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.positions.get(i as usize).copied());
            let (Some(a), Some(b), Some(c)) = (a, b, c) else {
                continue;
            };
            let n = (b - a).cross(c - a);
            for &i in t {
                normals[i as usize] += n;
            }
        }
        normals
    }

    /// Area-weighted unit vertex normals ([`Mesh::vertex_normal_sums`]
    /// normalized); a vertex whose sum vanishes gets the zero vector.
    pub fn vertex_normals(&self) -> Vec<Vec3> {
        let mut normals = self.vertex_normal_sums();
        for n in &mut normals {
            *n = n.normalized().unwrap_or(Vec3::ZERO);
        }
        normals
    }
}

impl PointCloud {
    /// A cloud from positions, validated (non-empty, finite).
    pub fn new(positions: Vec<Point3>) -> Result<PointCloud, MeshError> {
        let cloud = PointCloud {
            positions,
            normals: None,
        };
        cloud.validate()?;
        Ok(cloud)
    }

    /// Non-empty, finite coordinates, normal count matching.
    pub fn validate(&self) -> Result<(), MeshError> {
        check_points(&self.positions, self.normals.as_ref())
    }

    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::from_points(&self.positions)
    }
}

impl From<Mesh> for PointCloud {
    /// The mesh's vertices as a cloud (faces dropped).
    fn from(m: Mesh) -> Self {
        PointCloud {
            positions: m.positions,
            normals: m.normals,
        }
    }
}

/// The bounding box of triangle `t`.
pub(crate) fn tri_bounds(m: &Mesh, t: usize) -> Aabb {
    let [a, b, c] = m.triangle(t);
    Aabb {
        min: a.min(b).min(c),
        max: a.max(b).max(c),
    }
}

/// The smallest box holding both.
pub(crate) fn union(a: Aabb, b: Aabb) -> Aabb {
    Aabb {
        min: a.min.min(b.min),
        max: a.max.max(b.max),
    }
}

/// The longest side of the box that leaves out `n / tail` of the `n`
/// finite points at either end along each axis (stray points far from the
/// rest do not set it); `None` without finite points.
pub fn central_extent(points: &[Point3], tail: usize) -> Option<Real> {
    let mut v: Vec<Real> = Vec::with_capacity(points.len());
    let mut side: Real = 0.0;
    for axis in 0..3 {
        v.clear();
        v.extend(
            points
                .iter()
                .filter(|p| p.is_finite())
                .map(|p| p.to_array()[axis]),
        );
        if v.is_empty() {
            return None;
        }
        let lo = v.len() / tail.max(1);
        let hi = v.len() - 1 - lo;
        let low = nth_smallest(&mut v, lo)?;
        let high = nth_smallest(&mut v, hi)?;
        side = side.max(high - low);
    }
    Some(side)
}

/// The pieces one after another in one mesh, and each piece's range of
/// triangles in it (normals kept only when every piece has them). The
/// positions and the renumbered triangles are copied side by side: most of
/// the time goes to the first touch of the fresh arrays' pages.
pub fn concatenate<M: std::borrow::Borrow<Mesh> + Sync>(
    pieces: &[M],
) -> (Mesh, Vec<std::ops::Range<usize>>) {
    let meshes = || pieces.iter().map(|m| m.borrow());
    let gather = |f: &(dyn Fn(&Mesh) -> &[Point3] + Sync)| {
        let mut out = Vec::with_capacity(meshes().map(|m| f(m).len()).sum());
        for m in meshes() {
            out.extend_from_slice(f(m));
        }
        out
    };
    let with_normals = !pieces.is_empty() && meshes().all(|m| m.normals.is_some());
    let (positions, (triangles, normals)) = rayon::join(
        || gather(&|m| &m.positions),
        || {
            let mut out = Vec::with_capacity(meshes().map(|m| m.triangles.len()).sum());
            let mut base = 0u32;
            for m in meshes() {
                out.extend(m.triangles.iter().map(|t| t.map(|v| v + base)));
                base += m.positions.len() as u32;
            }
            let normals = with_normals.then(|| gather(&|m| m.normals.as_deref().unwrap_or(&[])));
            (out, normals)
        },
    );
    let mut ranges = Vec::with_capacity(pieces.len());
    let mut start = 0;
    for m in meshes() {
        ranges.push(start..start + m.triangles.len());
        start += m.triangles.len();
    }
    let mesh = Mesh {
        positions,
        normals,
        triangles,
    };
    (mesh, ranges)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed tetrahedron has no faulty edge; one face turned over
    /// misorients its three edges; one face taken away opens them.
    #[test]
    fn edge_faults_of_a_tetrahedron() {
        let positions = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        let faces = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        let tet = Mesh::new(positions, faces).unwrap();
        assert!(tet.signed_volume() > 0.0);
        assert_eq!(tet.edge_faults(), (0, 0));
        let mut flipped = tet.clone();
        flipped.triangles[0] = [0, 1, 2];
        assert_eq!(flipped.edge_faults(), (0, 3));
        let mut open = tet.clone();
        open.triangles.pop();
        assert_eq!(open.edge_faults(), (3, 0));
    }

    /// A cell index by a plain cast is the floor clamped at 0, for every
    /// value (negatives, NaN, infinities, huge values).
    #[test]
    fn grid_cell_cast_is_the_clamped_floor() {
        let old = |v: Real, n: usize| (v.floor().max(0.0) as usize).min(n - 1);
        let values = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            -1.0,
            -1.5,
            1.0,
            1.999_999_999,
            2.0,
            7.5,
            1e300,
            -1e300,
            -1e-300,
            5e-324,
            1.8e19,
            2e19,
        ];
        for v in values
            .into_iter()
            .chain([Real::INFINITY, Real::NEG_INFINITY, Real::NAN])
        {
            for n in [1, 3, 1 << 20, usize::MAX] {
                let c = grid_cell(Vec3::new(v, v, v), Vec3::ZERO, 1.0, [n, n, n]);
                assert_eq!(c, [old(v, n); 3], "{v} {n}");
            }
        }
    }
    use crate::assert_near;

    fn unit_cube() -> Mesh {
        let p = |x, y, z| Vec3::new(x, y, z);
        let positions = vec![
            p(0., 0., 0.),
            p(1., 0., 0.),
            p(1., 1., 0.),
            p(0., 1., 0.),
            p(0., 0., 1.),
            p(1., 0., 1.),
            p(1., 1., 1.),
            p(0., 1., 1.),
        ];
        let quads = [
            [0, 3, 2, 1],
            [4, 5, 6, 7],
            [0, 1, 5, 4],
            [2, 3, 7, 6],
            [1, 2, 6, 5],
            [0, 4, 7, 3],
        ];
        let triangles = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        Mesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn cube_volume_and_area() {
        let m = unit_cube();
        assert_near!(m.signed_volume(), 1.0, 1e-14);
        assert_near!(m.surface_area(), 6.0, 1e-14);
    }

    #[test]
    fn flipping_turns_the_volume_negative_and_back() {
        let mut m = unit_cube();
        m.normals = Some(vec![Vec3::new(0.0, 0.0, 1.0); m.positions.len()]);
        m.flip_orientation();
        assert_near!(m.signed_volume(), -1.0, 1e-14);
        assert_near!(m.surface_area(), 6.0, 1e-14);
        assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::new(0.0, 0.0, -1.0));
        m.flip_orientation();
        assert_eq!(m, {
            let mut c = unit_cube();
            c.normals = Some(vec![Vec3::new(0.0, 0.0, 1.0); c.positions.len()]);
            c
        });
    }

    #[test]
    fn rejects_bad_meshes() {
        assert_eq!(Mesh::new(vec![], vec![]), Err(MeshError::NoVertices));
        assert_eq!(
            Mesh::new(vec![Vec3::ZERO], vec![]),
            Err(MeshError::NoTriangles)
        );
        assert!(matches!(
            Mesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 3]]),
            Err(MeshError::IndexOutOfRange { vertex: 3, .. })
        ));
        assert!(matches!(
            Mesh::new(vec![Vec3::new(f64::NAN, 0., 0.); 3], vec![[0, 1, 2]]),
            Err(MeshError::NonFinite { index: 0, .. })
        ));
        assert_eq!(PointCloud::new(vec![]), Err(MeshError::NoVertices));
    }
}
