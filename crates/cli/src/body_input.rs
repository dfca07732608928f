//! The one place where a command's body argument (`MODEL.json`, a mesh, and
//! later a scan to reconstruct) becomes what is measured and drawn.
//!
//! Today a body is a closed mesh (.obj, .ply, .stl), measured by fitting its
//! sections ([`trigbody_core::measure::measure_mesh`]); a model file of
//! parts (v1, `trigbody loft`) can be drawn but carries no landmarks to
//! measure. When whole-body models and `trigbody reconstruct` land (issue
//! 5), [`measurements`] is where a `Body` model is measured from its own
//! curves and an INPUT is reconstructed first; nothing else changes.

use crate::exit::bad;
use anyhow::Result;
use std::path::Path;
use trigbody_core::measure::{measure_mesh, MeasureOptions, Measurements};
use trigbody_core::{tessellate_part, Mesh, TessellationOptions};
use trigbody_io::model::read_model;
use trigbody_io::{Geometry, ReadOptions};

/// Whether a path names a model file (`.json`).
pub fn is_model_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// The surface to draw: a mesh file as read, or a model file's parts
/// tessellated with the default options and merged.
pub fn drawable_mesh(path: &Path, read: &ReadOptions) -> Result<Mesh> {
    if !is_model_file(path) {
        // The reader's errors name the file, line or element, and the value.
        return trigbody_io::read_mesh(path, read).map_err(bad);
    }
    let file = path.display();
    let reader = std::fs::File::open(path).map_err(|e| bad(format!("{file}: {e}")))?;
    let model =
        read_model(std::io::BufReader::new(reader)).map_err(|e| bad(format!("{file}: {e}")))?;
    if model.parts.is_empty() {
        return Err(bad(format!("{file}: the model has no parts")));
    }
    let mut merged = Mesh::default();
    for p in &model.parts {
        let m = tessellate_part(&p.part, &TessellationOptions::default())
            .map_err(|e| bad(format!("{file}: part '{}': {e}", p.name)))?;
        let base = merged.positions.len() as u32;
        merged.positions.extend(m.positions);
        merged
            .triangles
            .extend(m.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    Ok(merged)
}

/// The measurements of a body: the landmarks, girth planes, curves and
/// volume of [`measure_mesh`] for a mesh. Model files are refused with
/// exit 2 until whole-body models exist.
pub fn measurements(
    path: &Path,
    read: &ReadOptions,
    opts: &MeasureOptions,
) -> Result<Measurements> {
    if is_model_file(path) {
        return Err(bad(format!(
            "{}: a model file of parts has no landmarks to measure; whole-body models come with \
             `trigbody reconstruct` — for now measure the mesh (.obj, .ply, .stl) itself",
            path.display()
        )));
    }
    let mesh = match trigbody_io::read_geometry(path, read).map_err(bad)? {
        Geometry::Mesh(mesh) => mesh,
        // The plug-in point for scans: reconstruct, then measure the body.
        Geometry::Points(_) => {
            return Err(bad(format!(
                "{}: a point cloud (scan) is measured once `trigbody reconstruct` has turned it \
                 into a body model; for now give a closed mesh (.obj, .ply with faces, .stl)",
                path.display()
            )))
        }
    };
    measure_mesh(&mesh, opts).map_err(|e| bad(format!("{}: {e}", path.display())))
}
