//! What a reader returns: a mesh or a point cloud.

use crate::options::ReadOptions;
use std::collections::HashSet;
use trigbody_core::{BodyGeometry, Mesh, PointCloud, Vec3};

/// What reading cleaned out of a mesh (see [`Geometry::clean`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadNotes {
    /// Triangles that use one vertex twice (no area, no edges of their own).
    pub degenerate: usize,
    /// Triangles on the same three vertices as an earlier one (either
    /// orientation): a copy adds nothing but work for every step after.
    pub duplicate: usize,
}

impl ReadNotes {
    /// A one-line warning when anything was dropped.
    pub fn warning(&self) -> Option<String> {
        (self.degenerate + self.duplicate > 0).then(|| {
            format!(
                "dropped {} degenerate triangle(s) (a vertex used twice) and {} duplicate \
                 triangle(s) (the same three vertices as an earlier one)",
                self.degenerate, self.duplicate
            )
        })
    }
}

/// What a file held: a triangle mesh, or points only.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// Vertices and triangles (polygons are fan-triangulated on reading).
    Mesh(Mesh),
    /// Points without faces (a scan, a PLY with no faces, an XYZ file).
    Points(PointCloud),
}

impl Geometry {
    /// The geometry as the library's reconstruction and checks take it.
    pub fn body(&self) -> BodyGeometry<'_> {
        match self {
            Geometry::Mesh(m) => BodyGeometry::Mesh(m),
            Geometry::Points(c) => BodyGeometry::Cloud(c),
        }
    }

    /// The positions, whatever the kind.
    pub fn positions(&self) -> &[Vec3] {
        match self {
            Geometry::Mesh(m) => &m.positions,
            Geometry::Points(p) => &p.positions,
        }
    }

    /// The normals, whatever the kind.
    pub fn normals(&self) -> Option<&[Vec3]> {
        match self {
            Geometry::Mesh(m) => m.normals.as_deref(),
            Geometry::Points(p) => p.normals.as_deref(),
        }
    }

    /// The triangles (empty for points).
    pub fn triangles(&self) -> &[[u32; 3]] {
        match self {
            Geometry::Mesh(m) => &m.triangles,
            Geometry::Points(_) => &[],
        }
    }

    /// The points, dropping faces of a mesh.
    pub fn into_point_cloud(self) -> PointCloud {
        match self {
            Geometry::Mesh(m) => m.into(),
            Geometry::Points(p) => p,
        }
    }

    /// Drops a mesh's degenerate and duplicate triangles (see [`ReadNotes`])
    /// and says how many; a mesh left without triangles is an error.
    pub fn clean(&mut self) -> crate::Result<ReadNotes> {
        let Geometry::Mesh(mesh) = self else {
            return Ok(ReadNotes::default());
        };
        let notes = clean_triangles(&mut mesh.triangles);
        if mesh.triangles.is_empty() {
            return Err(crate::IoError::WrongKind {
                path: None,
                message: format!(
                    "every one of its {} triangles is degenerate or a duplicate",
                    notes.degenerate + notes.duplicate
                ),
            });
        }
        Ok(notes)
    }

    /// Builds a mesh when there are triangles, points otherwise.
    /// Empty input is a [`FormatErrorKind::Empty`](crate::FormatErrorKind::Empty)
    /// error of `format`; everything else is checked by the core's `validate`.
    pub(crate) fn build(
        format: crate::Format,
        mut positions: Vec<Vec3>,
        mut normals: Option<Vec<Vec3>>,
        triangles: Vec<[u32; 3]>,
        options: &ReadOptions,
    ) -> crate::Result<Geometry> {
        if positions.is_empty() {
            return Err(crate::FormatError::new(
                format,
                crate::Location::File,
                crate::FormatErrorKind::Empty,
            )
            .into());
        }
        options.apply(&mut positions, normals.as_mut());
        if triangles.is_empty() {
            let cloud = PointCloud { positions, normals };
            cloud.validate()?;
            Ok(Geometry::Points(cloud))
        } else {
            let mesh = Mesh {
                positions,
                normals,
                triangles,
            };
            mesh.validate()?;
            Ok(Geometry::Mesh(mesh))
        }
    }
}

/// Keeps the first triangle on each set of three distinct vertices, in
/// order; one pass with a hash set (linear in the triangles).
fn clean_triangles(triangles: &mut Vec<[u32; 3]>) -> ReadNotes {
    let mut notes = ReadNotes::default();
    let mut seen: HashSet<[u32; 3]> = HashSet::with_capacity(triangles.len());
    triangles.retain(|t| {
        let [a, b, c] = *t;
        if a == b || b == c || a == c {
            notes.degenerate += 1;
            return false;
        }
        let mut key = *t;
        key.sort_unstable();
        if !seen.insert(key) {
            notes.duplicate += 1;
            return false;
        }
        true
    });
    notes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degenerate_and_duplicate_triangles_are_dropped_and_counted() {
        let mut t = vec![
            [0, 1, 2],
            [0, 0, 1],
            [2, 1, 0],
            [1, 2, 0],
            [1, 2, 3],
            [3, 3, 3],
        ];
        let notes = clean_triangles(&mut t);
        assert_eq!(t, vec![[0, 1, 2], [1, 2, 3]]);
        assert_eq!(
            notes,
            ReadNotes {
                degenerate: 2,
                duplicate: 2
            }
        );
        assert!(notes.warning().unwrap().contains("2 duplicate"));
        assert_eq!(ReadNotes::default().warning(), None);
    }
}
