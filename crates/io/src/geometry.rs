//! What a reader returns: a mesh or a point cloud.

use crate::options::ReadOptions;
use trigbody_core::{Mesh, PointCloud, Vec3};

/// What a file held: a triangle mesh, or points only.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// Vertices and triangles (polygons are fan-triangulated on reading).
    Mesh(Mesh),
    /// Points without faces (a scan, a PLY with no faces, an XYZ file).
    Points(PointCloud),
}

impl Geometry {
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
