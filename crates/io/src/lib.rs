//! # trigbody-io
//!
//! File formats for trigbody: everything that turns bytes into the core's
//! [`Mesh`] and [`PointCloud`] and back. The core never reads or writes
//! files itself.
//!
//! | format | read | write |
//! | --- | --- | --- |
//! | OBJ | `v vn vt f`, polygons fan-triangulated, negative indices | `v`, `vn`, `f` (exact f64 text) |
//! | PLY | ASCII, binary LE/BE, any scalar types, normals, polygon faces, points | binary LE, float or double |
//! | STL | ASCII and binary (told apart by size, not by "solid"), corners merged | binary |
//! | XYZ / CSV / TXT | `x y z [nx ny nz]`, header of names optional | space- or comma-separated |
//!
//! Every reader works against [`std::io::Read`], every writer against
//! [`std::io::Write`]; the path functions pick the format by extension.
//! Readers take the whole input into memory first and parse the bytes:
//! that is fast, and it lets every count in a header be checked against
//! the real length before anything is allocated.
//! Reading applies [`ReadOptions`] (unit scale, up axis) and then the core's
//! validation, so NaN or infinite coordinates are rejected with the vertex
//! index. No input makes a reader panic: malformed files give an
//! [`IoError`] naming the file, line or element and byte offset, and the
//! offending value.
//!
//! ```
//! use trigbody_io::{obj, Geometry, ReadOptions};
//! // A unit square in millimetres, z up.
//! let text = "v 0 0 0\nv 1000 0 0\nv 1000 0 1000\nv 0 0 1000\nf 1 2 3 4\n";
//! let options = ReadOptions { scale: 0.001, up_axis: "z".parse().unwrap() };
//! let Geometry::Mesh(mesh) = obj::read(text.as_bytes(), &options).unwrap() else {
//!     panic!("expected a mesh")
//! };
//! assert_eq!(mesh.triangles.len(), 2);
//! // z (up in the file) became y.
//! assert_eq!(mesh.positions[2].to_array(), [1.0, 1.0, 0.0]);
//! ```

#![warn(missing_docs)]

mod atomic;
pub mod body_file;
mod error;
pub mod fit_json;
mod format;
mod geometry;
pub mod gltf;
pub mod loop_text;
pub mod model;
pub mod obj;
mod options;
pub mod ply;
pub mod stl;
pub mod tbm;
mod text;
pub mod xyz;

pub use atomic::{remove_temporaries, write_atomically, TemporariesRemoved};
pub use error::{ElementPosition, FormatError, FormatErrorKind, IoError, Location, Result};
pub use format::Format;
pub use geometry::{Geometry, ReadNotes};

/// The most corners a face may have (OBJ, PLY, ASCII STL); a larger one is
/// a [`FormatErrorKind::FaceTooLarge`] naming its line or element.
pub const MAX_FACE_CORNERS: usize = 65_536;

/// A face of `n` corners is refused when larger than [`MAX_FACE_CORNERS`]
/// (checked before its indices are read, where the format gives `n` first).
pub(crate) fn check_face_size(n: u64) -> std::result::Result<(), FormatErrorKind> {
    if n > MAX_FACE_CORNERS as u64 {
        return Err(FormatErrorKind::FaceTooLarge {
            count: n,
            max: MAX_FACE_CORNERS,
        });
    }
    Ok(())
}
pub use options::{ParseUpAxisError, PlyPrecision, ReadOptions, UpAxis, WriteOptions};

use std::fs::File;
use std::io::{Read, Write};
use std::path::Path;
use trigbody_core::{Mesh, PointCloud};

/// Reads geometry of a known format from any reader; degenerate and
/// duplicate triangles are dropped ([`Geometry::clean`]).
pub fn read_from<R: Read>(reader: R, format: Format, options: &ReadOptions) -> Result<Geometry> {
    let mut data = Vec::new();
    let mut reader = reader;
    reader.read_to_end(&mut data)?;
    read_bytes(&data, format, options)
}

/// Reads geometry of a known format from bytes in memory; degenerate and
/// duplicate triangles are dropped ([`Geometry::clean`]).
pub fn read_bytes(data: &[u8], format: Format, options: &ReadOptions) -> Result<Geometry> {
    read_bytes_noted(data, format, options).map(|(g, _)| g)
}

/// [`read_bytes`], also saying what was cleaned out.
pub fn read_bytes_noted(
    data: &[u8],
    format: Format,
    options: &ReadOptions,
) -> Result<(Geometry, ReadNotes)> {
    let mut geometry = match format {
        Format::Obj => obj::read_bytes(data, options),
        Format::Ply => ply::read_bytes(data, options),
        Format::Stl => stl::read_bytes(data, options),
        Format::Xyz => xyz::read_bytes(data, options),
    }?;
    let notes = geometry.clean()?;
    Ok((geometry, notes))
}

fn format_of(path: &Path) -> Result<Format> {
    Format::from_path(path).ok_or_else(|| IoError::UnknownExtension {
        path: path.to_path_buf(),
    })
}

/// Reads a file, choosing the format by its extension (case-insensitive
/// `.obj .ply .stl .xyz .csv .txt`). A file with faces gives
/// [`Geometry::Mesh`], one without (an XYZ file, a PLY or OBJ of points)
/// [`Geometry::Points`]. Errors name the file.
pub fn read_geometry(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Geometry> {
    read_geometry_noted(path, options).map(|(g, _)| g)
}

/// [`read_geometry`], also saying what was cleaned out. A path that is not
/// a regular file (a FIFO, a device) is refused before it is opened:
/// opening a FIFO without a writer would wait forever.
pub fn read_geometry_noted(
    path: impl AsRef<Path>,
    options: &ReadOptions,
) -> Result<(Geometry, ReadNotes)> {
    let path = path.as_ref();
    let run = || -> Result<(Geometry, ReadNotes)> {
        let format = format_of(path)?;
        if !std::fs::metadata(path)?.is_file() {
            return Err(IoError::WrongKind {
                path: None,
                message: "not a regular file (a directory, FIFO or device); give a mesh or \
                          scan file"
                    .into(),
            });
        }
        let mut data = Vec::new();
        File::open(path)?.read_to_end(&mut data)?;
        read_bytes_noted(&data, format, options)
    };
    run().map_err(|e| e.with_path(path))
}

/// Reads a file that must hold a triangle mesh (see [`read_geometry`]);
/// a file of points only is an [`IoError::WrongKind`].
pub fn read_mesh(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Mesh> {
    let path = path.as_ref();
    match read_geometry(path, options)? {
        Geometry::Mesh(m) => Ok(m),
        Geometry::Points(p) => Err(IoError::WrongKind {
            path: Some(path.to_path_buf()),
            message: format!(
                "expected a mesh, but the file holds {} points and no faces",
                p.positions.len()
            ),
        }),
    }
}

/// Reads a file as points: a mesh's vertices (faces dropped) or a cloud.
pub fn read_point_cloud(path: impl AsRef<Path>, options: &ReadOptions) -> Result<PointCloud> {
    read_geometry(path, options).map(Geometry::into_point_cloud)
}

/// Writes geometry in `format` to any writer. A mesh written as XYZ keeps
/// its vertices only; points cannot be written as STL
/// ([`IoError::WrongKind`]). XYZ is written space-separated here; use
/// [`xyz::write_points`] for CSV.
pub fn write_to<W: Write>(
    writer: W,
    geometry: &Geometry,
    format: Format,
    options: &WriteOptions,
) -> Result<()> {
    GeometryRef::from(geometry).write(writer, format, false, options)
}

/// Borrowed geometry for the path writers (no copy of the data).
#[derive(Clone, Copy, Debug)]
enum GeometryRef<'a> {
    Mesh(&'a Mesh),
    Points(&'a PointCloud),
}

impl GeometryRef<'_> {
    fn validate(self) -> std::result::Result<(), trigbody_core::MeshError> {
        match self {
            GeometryRef::Mesh(m) => m.validate(),
            GeometryRef::Points(p) => p.validate(),
        }
    }

    fn write<W: Write>(
        self,
        w: W,
        format: Format,
        csv: bool,
        options: &WriteOptions,
    ) -> Result<()> {
        let delimiter = if csv {
            xyz::Delimiter::Comma
        } else {
            xyz::Delimiter::Space
        };
        match (self, format) {
            (GeometryRef::Mesh(m), Format::Obj) => obj::write_mesh(w, m),
            (GeometryRef::Points(p), Format::Obj) => obj::write_points(w, p),
            (GeometryRef::Mesh(m), Format::Ply) => ply::write_mesh(w, m, options),
            (GeometryRef::Points(p), Format::Ply) => ply::write_points(w, p, options),
            (GeometryRef::Mesh(m), Format::Stl) => stl::write_mesh(w, m),
            (GeometryRef::Points(_), Format::Stl) => Err(IoError::WrongKind {
                path: None,
                message: "STL holds triangles only; write points as PLY, OBJ or XYZ".into(),
            }),
            (GeometryRef::Mesh(m), Format::Xyz) => {
                m.validate()?;
                xyz::write_vertices(w, &m.positions, m.normals.as_deref(), delimiter)
            }
            (GeometryRef::Points(p), Format::Xyz) => xyz::write_points(w, p, delimiter),
        }
    }
}

impl<'a> From<&'a Geometry> for GeometryRef<'a> {
    fn from(g: &'a Geometry) -> Self {
        match g {
            Geometry::Mesh(m) => GeometryRef::Mesh(m),
            Geometry::Points(p) => GeometryRef::Points(p),
        }
    }
}

/// Writes geometry to a file, choosing the format by extension (`.csv`
/// gives comma-separated values with a header). An existing file is an
/// [`IoError::AlreadyExists`] unless `options.overwrite` is true; the check
/// and the creation are one atomic step. Invalid geometry is rejected before
/// the file is created; the file is written atomically
/// ([`write_atomically`]): a failure leaves the old file, or none.
pub fn write_geometry(
    path: impl AsRef<Path>,
    geometry: &Geometry,
    options: &WriteOptions,
) -> Result<()> {
    write_path(path.as_ref(), geometry.into(), options)
}

/// Writes a mesh to a file (see [`write_geometry`]).
pub fn write_mesh(path: impl AsRef<Path>, mesh: &Mesh, options: &WriteOptions) -> Result<()> {
    write_path(path.as_ref(), GeometryRef::Mesh(mesh), options)
}

/// Writes a point cloud to a file (see [`write_geometry`]).
pub fn write_point_cloud(
    path: impl AsRef<Path>,
    cloud: &PointCloud,
    options: &WriteOptions,
) -> Result<()> {
    write_path(path.as_ref(), GeometryRef::Points(cloud), options)
}

/// True when `path` exists and is neither a regular file nor a directory
/// (a device such as `/dev/null` or `/dev/stdout`, a FIFO, a socket): a
/// writer writes it in place, since a rename over it would put a regular
/// file where the device was.
pub fn is_special_file(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

fn write_path(path: &Path, geometry: GeometryRef<'_>, options: &WriteOptions) -> Result<()> {
    let format = format_of(path)?;
    write_path_as(path, geometry, format, Format::is_csv(path), options)
}

/// Writes geometry to a file in `format` whatever its name (a device such
/// as `/dev/null` has no extension), atomically ([`write_atomically`]).
fn write_path_as(
    path: &Path,
    geometry: GeometryRef<'_>,
    format: Format,
    csv: bool,
    options: &WriteOptions,
) -> Result<()> {
    // Check what can be checked before touching the file system.
    geometry
        .validate()
        .map_err(|e| IoError::from(e).with_path(path))?;
    if let (GeometryRef::Points(_), Format::Stl) = (geometry, format) {
        return geometry
            .write(std::io::sink(), format, csv, options)
            .map_err(|e| e.with_path(path));
    }
    write_atomically(path, options.overwrite, |w| {
        geometry.write(w, format, csv, options)
    })
}

/// Writes a mesh to a file in `format` (see [`write_geometry`]); for a
/// target whose name gives no format, such as `/dev/null`.
pub fn write_mesh_as(
    path: impl AsRef<Path>,
    mesh: &Mesh,
    format: Format,
    options: &WriteOptions,
) -> Result<()> {
    write_path_as(
        path.as_ref(),
        GeometryRef::Mesh(mesh),
        format,
        false,
        options,
    )
}

/// Writes a point cloud to a file in `format` (see [`write_mesh_as`]).
pub fn write_point_cloud_as(
    path: impl AsRef<Path>,
    cloud: &PointCloud,
    format: Format,
    options: &WriteOptions,
) -> Result<()> {
    let csv = Format::is_csv(path.as_ref());
    write_path_as(
        path.as_ref(),
        GeometryRef::Points(cloud),
        format,
        csv,
        options,
    )
}
