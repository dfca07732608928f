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
use trigbody_core::body::reconstruct_with_progress;
use trigbody_core::body::{Body, BodyCavity, BodyPart, BodyTransition, Units};
use trigbody_core::measure::{measure_mesh, MeasureOptions, Measurements};
use trigbody_core::measure_model::{compare_with_mesh, measure_body, ModelMeasureOptions};
use trigbody_core::segment::{BodyFrame, BodyGeometry, PartName};
use trigbody_core::{Mesh, ReconstructOptions, TessellationOptions};
use trigbody_io::body_file::part_file_name;
use trigbody_io::model::{merge_pieces, read_model, Model};
use trigbody_io::{Geometry, ReadOptions};

/// Whether a path names a model file (`.json`).
pub fn is_model_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Reads a model file; errors (exit 2) name the file.
fn read_model_file(path: &Path) -> Result<Model> {
    let file = path.display();
    let reader = std::fs::File::open(path).map_err(|e| bad(format!("{file}: {e}")))?;
    let model =
        read_model(std::io::BufReader::new(reader)).map_err(|e| bad(format!("{file}: {e}")))?;
    if model.parts.is_empty() {
        return Err(bad(format!("{file}: the model has no parts")));
    }
    Ok(model)
}

/// The [`Body`] of a model file: its `body` frame and height, its parts by
/// their file names (`torso`, `head`, `left_arm`, …). A model without a
/// `body` object (a loft) or with a part name no body has is refused.
pub fn body_of_model_file(path: &Path) -> Result<Body> {
    let file = path.display();
    let model = read_model_file(path)?;
    let frame = model.body.ok_or_else(|| {
        bad(format!(
            "{file}: a model of parts without a \"body\" object (e.g. from `trigbody loft`) has no \
             body frame to measure; make a body model with `trigbody reconstruct`"
        ))
    })?;
    let units = Units::from_symbol(&model.units).ok_or_else(|| {
        bad(format!(
            "{file}: units \"{}\" are not m, cm or mm",
            model.units
        ))
    })?;
    let names = PartName::ALL;
    let mut parts = Vec::with_capacity(model.parts.len());
    let mut cavities = Vec::new();
    for p in model.parts {
        if let Some(host) = &p.cavity_of {
            let within = names
                .iter()
                .copied()
                .find(|n| part_file_name(*n) == host)
                .ok_or_else(|| {
                    bad(format!(
                        "{file}: part \"{}\" is a cavity of \"{host}\", not a body part",
                        p.name
                    ))
                })?;
            cavities.push(BodyCavity {
                within,
                part: p.part,
                fits: Vec::new(),
            });
            continue;
        }
        let name = names
            .iter()
            .copied()
            .find(|n| part_file_name(*n) == p.name)
            .ok_or_else(|| {
                bad(format!(
                    "{file}: part \"{}\" is not a body part (torso, head, left_arm, right_arm, \
                     left_leg, right_leg)",
                    p.name
                ))
            })?;
        parts.push(BodyPart {
            name,
            part: p.part,
            fits: Vec::new(),
        });
    }
    let part_named = |n: &str| {
        names
            .iter()
            .copied()
            .find(|k| part_file_name(*k) == n)
            .ok_or_else(|| bad(format!("{file}: transition names \"{n}\", not a body part")))
    };
    let mut transitions = Vec::with_capacity(model.transitions.len());
    for t in model.transitions {
        transitions.push(BodyTransition {
            from: part_named(&t.from)?,
            to: part_named(&t.to)?,
            transition: t.transition,
        });
    }
    Ok(Body {
        transitions,
        cavities,
        units,
        frame: BodyFrame {
            up: frame.up,
            front: frame.front,
            left: frame.left,
            origin: frame.origin,
        },
        height: frame.height,
        parts,
    })
}

/// A body ready to measure or draw: the model, and the input it was
/// reconstructed from (when it was).
pub struct LoadedBody {
    pub body: Body,
    pub input: Option<Geometry>,
}

/// A model file as read, or an input reconstructed with default options.
pub fn load_body(path: &Path, read: &ReadOptions) -> Result<LoadedBody> {
    if is_model_file(path) {
        return Ok(LoadedBody {
            body: body_of_model_file(path)?,
            input: None,
        });
    }
    let geometry = trigbody_io::read_geometry(path, read).map_err(bad)?;
    let g = match &geometry {
        Geometry::Mesh(m) => BodyGeometry::Mesh(m),
        Geometry::Points(c) => BodyGeometry::Cloud(c),
    };
    let mut bar = crate::progress::ProgressBar::new("reconstructing");
    let result =
        reconstruct_with_progress(g, &ReconstructOptions::default(), &mut |p| bar.update(p));
    bar.finish();
    let (body, _) =
        result.map_err(|e| bad(format!("{}: reconstructing the body: {e}", path.display())))?;
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
        return trigbody_io::read_mesh(path, read).map_err(bad);
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

/// A body's measurements, what they were taken on, and the model file's
/// unit (`None` for an input: its unit is not known).
pub struct BodyMeasurements {
    pub measurements: Measurements,
    pub measured: Measured,
    pub units: Option<Units>,
}

/// The measurements of a body (see the module doc); `compare` names a mesh
/// to measure every girth on in the same plane (default: the input a model
/// was reconstructed from, when it is a mesh).
pub fn measurements(
    path: &Path,
    read: &ReadOptions,
    direct: bool,
    compare: Option<&Path>,
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
        let mesh = match trigbody_io::read_geometry(path, read).map_err(bad)? {
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
            units: None,
        });
    }
    let loaded = load_body(path, read)?;
    let mut m = measure_body(&loaded.body, &ModelMeasureOptions::default())
        .map_err(|e| bad(format!("{file}: {e}")))?;
    let measured = match &loaded.input {
        None => Measured::Model,
        Some(_) => Measured::Reconstructed,
    };
    match (compare, &loaded.input) {
        (Some(other), _) => {
            let mesh = trigbody_io::read_mesh(other, read).map_err(bad)?;
            compare_with_mesh(&mut m, &mesh);
        }
        (None, Some(Geometry::Mesh(mesh))) => compare_with_mesh(&mut m, mesh),
        _ => {}
    }
    Ok(BodyMeasurements {
        measurements: m,
        measured,
        // A model file knows its unit; an input's unit is not known here.
        units: (measured == Measured::Model).then_some(loaded.body.units),
    })
}
