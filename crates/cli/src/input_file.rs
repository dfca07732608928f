//! Reading a command's mesh or scan: the readers' errors as bad input
//! (exit 2, naming the file and line), and what reading cleaned out
//! (degenerate and duplicate triangles) as a warning naming the file.

use crate::exit::bad;
use anyhow::Result;
use std::path::Path;
use trigbody_core::Mesh;
use trigbody_io::{Geometry, ReadOptions};

/// A mesh or a point cloud, whichever the file holds.
pub fn read_geometry(path: &Path, read: &ReadOptions) -> Result<Geometry> {
    let (geometry, notes) = trigbody_io::read_geometry_noted(path, read).map_err(bad)?;
    if let Some(w) = notes.warning() {
        crate::exit::diag(format_args!("trigbody: warning: {}: {w}", path.display()));
    }
    Ok(geometry)
}

/// A file that must hold a triangle mesh.
pub fn read_mesh(path: &Path, read: &ReadOptions) -> Result<Mesh> {
    match read_geometry(path, read)? {
        Geometry::Mesh(m) => Ok(m),
        Geometry::Points(p) => Err(bad(format!(
            "{}: expected a mesh, but the file holds {} points and no faces",
            path.display(),
            p.positions.len()
        ))),
    }
}
