//! The one place where a command's body argument becomes what is measured
//! and drawn:
//!
//! * a **model file** (`.json`, version 2 to 5 with a `body` object, as written
//!   by `trigbody reconstruct`) is read back into a [`Body`] and measured
//!   from its own curves ([`measure_body`]);
//! * an **input** (a mesh or a scanned point cloud) is reconstructed first
//!   ([`trigbody_core::reconstruct`], default options), then the model is
//!   measured, and every girth is measured again directly on the input mesh
//!   in the same plane ([`compare_with_mesh`]);
//! * with `direct`, a mesh is measured as before reconstruction existed:
//!   fitted curves of its own sections ([`measure_mesh`]).
//!
//! Model files of parts without a body (v1, `trigbody loft`) can be drawn
//! (tessellated) but carry no body frame to measure.

use crate::exit::bad;
use anyhow::Result;
use std::path::Path;
use trigbody_core::internals::measure::model::compare_with_mesh;
use trigbody_core::reconstruct_with_progress;
use trigbody_core::{measure_body, ModelMeasureOptions};
use trigbody_core::{measure_mesh, MeasureOptions, Measurements};
use trigbody_core::{validate_input, Body, Units};
use trigbody_core::{Mesh, ReconstructOptions, TessellationOptions};
use trigbody_io::body_file::body_of_model;
use trigbody_io::model::{merge_pieces, Model};
use trigbody_io::tbm::read_any_model;
use trigbody_io::{Geometry, ReadOptions};

/// Whether a path names a model file (`.json`, or the compact `.tbm`).
pub fn is_model_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json") || e.eq_ignore_ascii_case("tbm"))
}

/// Reads a model file, JSON or compact (told apart by its first bytes);
/// errors (exit 2) name the file.
pub fn read_model_file(path: &Path) -> Result<Model> {
    let file = path.display();
    let bytes = std::fs::read(path).map_err(|e| bad(format!("{file}: {e}")))?;
    let model = read_any_model(&bytes).map_err(|e| bad(format!("{file}: {e}")))?;
    if model.parts.is_empty() {
        return Err(bad(format!("{file}: the model has no parts")));
    }
    Ok(model)
}

/// The [`Body`] of a model file ([`body_of_model`]); errors (exit 2) name
/// the file.
pub fn body_of_model_file(path: &Path) -> Result<Body> {
    let model = read_model_file(path)?;
    body_of_model(model).map_err(|e| bad(format!("{}: {e}", path.display())))
}

/// A body ready to measure or draw: the model, and the input it was
/// reconstructed from (when it was).
pub struct LoadedBody {
    pub body: Body,
    pub input: Option<Geometry>,
}

/// The unit an input is in: given, or `None` to infer it from the input's
/// extent ([`trigbody_core::validate_input`]).
pub type InputUnits = Option<Units>;

/// A model file as read, or an input reconstructed with default options
/// (the library checks it is one body in its unit first).
pub fn load_body(path: &Path, read: &ReadOptions, units: InputUnits) -> Result<LoadedBody> {
    if is_model_file(path) {
        return Ok(LoadedBody {
            body: body_of_model_file(path)?,
            input: None,
        });
    }
    let geometry = crate::input_file::read_geometry(path, read)?;
    let g = geometry.body();
    let mut bar = crate::progress::ProgressBar::new("reconstructing");
    let options = ReconstructOptions {
        units: units.unwrap_or_default(),
        infer_units: units.is_none(),
        ..ReconstructOptions::default()
    };
    let result = reconstruct_with_progress(g, &options, &mut |p| bar.update(p));
    bar.finish();
    let (body, _) = result.map_err(|e| bad(format!("{}: {e}", path.display())))?;
    Ok(LoadedBody {
        body,
        input: Some(geometry),
    })
}

/// The surface to draw: a mesh file as read, or a model file's parts
/// tessellated (edges about 0.3 % of the body's height for a body model,
/// the default grid for a loft) and merged.
pub fn drawable_mesh(path: &Path, read: &ReadOptions) -> Result<Mesh> {
    drawable_surface(path, read, trigbody_io::model::Skin::Whole)
}

/// [`drawable_mesh`] with a model file's pieces trimmed to `skin`.
pub fn drawable_surface(
    path: &Path,
    read: &ReadOptions,
    skin: trigbody_io::model::Skin,
) -> Result<Mesh> {
    if !is_model_file(path) {
        // The reader's errors name the file, line or element, and the value.
        return crate::input_file::read_mesh(path, read);
    }
    let file = path.display();
    let model = read_model_file(path)?;
    let tess = TessellationOptions {
        target_edge: model.body.as_ref().map(|b| 0.003 * b.height),
        ..TessellationOptions::default()
    };
    let pieces = model
        .tessellate_pieces(&tess)
        .map_err(|e| bad(format!("{file}: {e}")))?;
    let pieces = trigbody_io::model::skin_pieces(&model, pieces, skin)
        .map_err(|e| bad(format!("{file}: {e}")))?;
    Ok(merge_pieces(&pieces))
}

/// What a measurement was taken on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measured {
    /// A model file, from its curves.
    Model,
    /// A mesh or scan reconstructed first, then measured from the model's
    /// curves (girths compared with the input mesh's).
    Reconstructed,
    /// A mesh measured directly (its own fitted sections).
    Direct,
}

impl Measured {
    pub fn as_str(self) -> &'static str {
        match self {
            Measured::Model => "model file",
            Measured::Reconstructed => "reconstructed model",
            Measured::Direct => "input mesh sections",
        }
    }
}

/// A body's measurements, what they were taken on, and the unit they are
/// in (a model file's own; an input's as given or inferred).
pub struct BodyMeasurements {
    pub measurements: Measurements,
    pub measured: Measured,
    pub units: Units,
}

/// The measurements of a body (see the module doc); `compare` names a mesh
/// to measure every girth on in the same plane (default: the input a model
/// was reconstructed from, when it is a mesh).
pub fn measurements(
    path: &Path,
    read: &ReadOptions,
    direct: bool,
    compare: Option<&Path>,
    units: InputUnits,
) -> Result<BodyMeasurements> {
    let file = path.display();
    if direct && compare.is_some() {
        return Err(bad(
            "--direct already measures the mesh itself; leave out --input",
        ));
    }
    if direct {
        if is_model_file(path) {
            return Err(bad(format!(
                "{file}: --direct measures a mesh's own sections; a model file is measured from \
                 its curves (leave out --direct)"
            )));
        }
        let geometry = crate::input_file::read_geometry(path, read)?;
        let units =
            validate_input(geometry.body(), units).map_err(|e| bad(format!("{file}: {e}")))?;
        let mesh = match geometry {
            Geometry::Mesh(mesh) => mesh,
            Geometry::Points(_) => {
                return Err(bad(format!(
                    "{file}: --direct needs a closed mesh; a point cloud is measured through its \
                     reconstructed model (leave out --direct)"
                )))
            }
        };
        let m = measure_mesh(&mesh, &MeasureOptions::default())
            .map_err(|e| bad(format!("{file}: {e}")))?;
        return Ok(BodyMeasurements {
            measurements: m,
            measured: Measured::Direct,
            units,
        });
    }
    let loaded = load_body(path, read, units)?;
    let mut m = measure_body(&loaded.body, &ModelMeasureOptions::default())
        .map_err(|e| bad(format!("{file}: {e}")))?;
    let measured = match &loaded.input {
        None => Measured::Model,
        Some(_) => Measured::Reconstructed,
    };
    match (compare, &loaded.input) {
        (Some(other), _) => {
            let mesh = crate::input_file::read_mesh(other, read)?;
            compare_with_mesh(&mut m, &mesh);
        }
        (None, Some(Geometry::Mesh(mesh))) => compare_with_mesh(&mut m, mesh),
        _ => {}
    }
    Ok(BodyMeasurements {
        measurements: m,
        measured,
        // A model file's unit, or the input's as given or inferred.
        units: loaded.body.units,
    })
}
