//! Options for reading and writing, with documented defaults.

use std::fmt;
use std::str::FromStr;
use trigbody_core::{Mesh, PointCloud, Real, Vec3};

/// Which axis of the file points up. Reading rotates the geometry (a proper
/// rotation, so handedness and triangle winding are kept) so that this axis
/// becomes +y, the convention of the core.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UpAxis {
    /// Keep the file's axes as they are (the default).
    #[default]
    Keep,
    /// +x is up.
    PlusX,
    /// −x is up.
    MinusX,
    /// +y is up (same as `Keep`).
    PlusY,
    /// −y is up.
    MinusY,
    /// +z is up (most CAD programs, scanners and Blender):
    /// (x, y, z) ↦ (x, z, −y).
    PlusZ,
    /// −z is up.
    MinusZ,
}

impl UpAxis {
    /// Rotates a vector from the file's frame to the +y-up frame.
    #[inline]
    pub fn to_y_up(self, v: Vec3) -> Vec3 {
        let Vec3 { x, y, z } = v;
        match self {
            UpAxis::Keep | UpAxis::PlusY => v,
            UpAxis::MinusY => Vec3::new(x, -y, -z),
            UpAxis::PlusZ => Vec3::new(x, z, -y),
            UpAxis::MinusZ => Vec3::new(x, -z, y),
            UpAxis::PlusX => Vec3::new(-y, x, z),
            UpAxis::MinusX => Vec3::new(y, -x, z),
        }
    }
}

/// The text is not an axis name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown up axis {0:?}: expected keep, x, y, z, +x, +y, +z, -x, -y or -z")]
pub struct ParseUpAxisError(pub String);

impl FromStr for UpAxis {
    type Err = ParseUpAxisError;
    /// Parses `keep`, `x`, `+x`, `-x` (and the same for y and z), any case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s.trim().to_ascii_lowercase().as_str() {
            "keep" | "" => UpAxis::Keep,
            "x" | "+x" => UpAxis::PlusX,
            "-x" => UpAxis::MinusX,
            "y" | "+y" => UpAxis::PlusY,
            "-y" => UpAxis::MinusY,
            "z" | "+z" => UpAxis::PlusZ,
            "-z" => UpAxis::MinusZ,
            _ => return Err(ParseUpAxisError(s.to_string())),
        })
    }
}

impl fmt::Display for UpAxis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            UpAxis::Keep => "keep",
            UpAxis::PlusX => "+x",
            UpAxis::MinusX => "-x",
            UpAxis::PlusY => "+y",
            UpAxis::MinusY => "-y",
            UpAxis::PlusZ => "+z",
            UpAxis::MinusZ => "-z",
        })
    }
}

/// How to turn a file's coordinates into the core's (meters, +y up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Every coordinate is multiplied by this on reading, e.g. `0.001` for a
    /// file in millimetres. Default: `1.0` (the file is in meters).
    pub scale: Real,
    /// Which axis of the file is up; it is rotated onto +y.
    /// Default: [`UpAxis::Keep`].
    pub up_axis: UpAxis,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            scale: 1.0,
            up_axis: UpAxis::Keep,
        }
    }
}

impl ReadOptions {
    /// Applies scale then rotation to positions, rotation to normals.
    pub(crate) fn apply(&self, positions: &mut [Vec3], normals: Option<&mut Vec<Vec3>>) {
        let (s, up) = (self.scale, self.up_axis);
        if s != 1.0 || !matches!(up, UpAxis::Keep | UpAxis::PlusY) {
            for p in positions.iter_mut() {
                *p = up.to_y_up(*p * s);
            }
        }
        if let Some(ns) = normals {
            if !matches!(up, UpAxis::Keep | UpAxis::PlusY) {
                for n in ns.iter_mut() {
                    *n = up.to_y_up(*n);
                }
            }
            // A negative scale mirrors the geometry; normals follow the mirror.
            if s < 0.0 {
                for n in ns.iter_mut() {
                    *n = -*n;
                }
            }
        }
    }
}

/// Numeric type for PLY vertex coordinates and normals on writing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PlyPrecision {
    /// 32-bit `float`: read by every program; about 0.1 µm resolution at
    /// 1 m. The default.
    #[default]
    Float,
    /// 64-bit `double`: exact round trip of the core's f64.
    Double,
}

/// How to write a file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct WriteOptions {
    /// Path writers only: replace an existing file. Default `false`: an
    /// existing file gives [`IoError::AlreadyExists`](crate::IoError::AlreadyExists)
    /// and is left untouched.
    pub overwrite: bool,
    /// Coordinate type of written PLY files. Default [`PlyPrecision::Float`].
    pub ply_precision: PlyPrecision,
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
