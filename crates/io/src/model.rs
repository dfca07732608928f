//! The trigbody model file: a versioned JSON document holding everything
//! needed to regenerate a model's surfaces (method.md §7).
//!
//! ```json
//! {
//!   "format": "trigbody-model",
//!   "version": 5,
//!   "units": "m",
//!   "body": { "frame": { "up": [0, 1, 0], "front": [0, 0, 1],
//!                        "left": [1, 0, 0], "origin": [0, -0.82, 0] },
//!             "height": 1.73 },
//!   "parts": [
//!     {
//!       "name": "leg_left",
//!       "skinning": { "method": "catmull-rom", "curves_per_patch": 4,
//!                     "curvature_continuity": false, "align_twist": true },
//!       "caps": { "start": { "kind": "open" },
//!                 "end": { "kind": "dome", "relative_height": 1.0 } },
//!       "sections": [
//!         { "frame": { "origin": [0, 0, 0], "e1": [1, 0, 0], "e2": [0, 1, 0] },
//!           "a": [0.0, 0.06, 0.0], "b": [0.0, 0.05, 0.0] }
//!       ]
//!     }
//!   ],
//!   "transitions": []
//! }
//! ```
//!
//! `body` (a reconstructed body's frame) is optional; version-1 files (no
//! `body`, no `transitions`) are still read. A transition stores what the
//! parts do not give (`from`/`to` part and end, the two tangent magnitudes,
//! an optional seam and its order) and is rebuilt from the parts by
//! [`Transition::between`]. The full schema is in `docs/model-format.md`.
//!
//! Curves keep the paper's coefficient layout (`a`, `b`, Eq. 3) and their
//! plane frames; sections are stored as given (before twist alignment), so
//! reading a file rebuilds exactly the part that was written (f64 values
//! round-trip exactly: shortest representation out, correctly rounded in).
//! The document is meant to grow (landmarks beside `parts`); readers ignore fields they do not know and refuse versions
//! they do not know.

use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::io::{Read, Write};
use thiserror::Error;
use trigbody_core::internals::surface::pieces::{tessellate_pieces, Piece};
use trigbody_core::internals::surface::transition::{
    Seam, SideCut, Transition, TransitionError, TransitionSpec,
};
use trigbody_core::TessellateError;
use trigbody_core::{
    CapKind, Frame, Mesh, Part, PartError, PartOptions, Skinning, TessellationOptions, TrigCurve,
    Vec3,
};

/// The `format` field of every model file.
pub const MODEL_FORMAT: &str = "trigbody-model";
/// The model file version this build writes (it reads 1 to 5).
/// Version 2 adds the optional `body` object (the body's frame and height)
/// and the `transitions` list; a version-1 file reads as a model without
/// them. Version 3 adds a dome cap's optional `fullness` and `axis`: a
/// version-2 reader, which ignores fields it does not know, would build
/// another dome, so it must refuse the file. Version 4 adds a
/// transition's optional `side` (an arm's transition ending on the
/// torso's shoulder): a version-3 reader would end it on the torso's end
/// curve instead. Version 5 adds a part's optional `cavity_of` (a pocket
/// of skin inside another part, facing into the pocket): a version-4
/// reader would take it for a solid part.
pub const MODEL_VERSION: u64 = 5;

/// A named part of a model.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelPart {
    /// The part's name (kept in the model file and as the GLB node name).
    pub name: String,
    /// The skinned part.
    pub part: Part,
    /// For a cavity (a pocket of skin inside another part, such as a
    /// modelled mouth: [`trigbody_core::BodyCavity`]), the name of
    /// the part it lies in. Its surface faces into the pocket (tessellated
    /// turned inside out) and its solid is empty space (version 5).
    pub cavity_of: Option<String>,
}

/// A reconstructed body's frame and size (model file version 2 and later).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelBody {
    /// Unit up direction (head above feet).
    pub up: Vec3,
    /// Unit direction the body faces.
    pub front: Vec3,
    /// Unit `up × front`.
    pub left: Vec3,
    /// The point on the floor below the crotch.
    pub origin: Vec3,
    /// Soles to head top, in the model's units.
    pub height: f64,
}

/// A transition surface between two named parts (see
/// [`trigbody_core::internals::surface::transition`]); rebuilt from the parts and its spec.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelTransition {
    /// The part where the transition starts (`u = 0`).
    pub from: String,
    /// The part where it ends (`u = 1`).
    pub to: String,
    /// The surface.
    pub transition: Transition,
}

/// A model: named parts in one unit of length, and the transitions between
/// them.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// The unit of every coordinate, e.g. `"m"` (informational; never
    /// converted).
    pub units: String,
    /// The body's frame, for a reconstructed body (`None` for a loft).
    pub body: Option<ModelBody>,
    /// The parts, in file order.
    pub parts: Vec<ModelPart>,
    /// Transition surfaces between parts, in file order.
    pub transitions: Vec<ModelTransition>,
}

impl Model {
    /// Each part, then each transition (named `from-to`, e.g.
    /// `left_leg-torso`), tessellated with `options`, in that order: the
    /// pieces a GLB writes as nodes, or merges into one mesh. A cavity's
    /// surface is turned to face into its pocket. The pieces are taken by
    /// the cores as they come free, as
    /// [`trigbody_core::Body::tessellate_pieces`] takes a body's.
    pub fn tessellate_pieces(
        &self,
        options: &TessellationOptions,
    ) -> Result<Vec<(String, Mesh)>, PieceError> {
        let (names, pieces): (Vec<String>, Vec<Piece>) = self
            .parts
            .iter()
            .map(|p| {
                let piece = match p.cavity_of {
                    Some(_) => Piece::Cavity(&p.part),
                    None => Piece::Part(&p.part),
                };
                (p.name.clone(), piece)
            })
            .chain(self.transitions.iter().map(|t| {
                let name = format!("{}-{}", t.from, t.to);
                (name, Piece::Transition(&t.transition))
            }))
            .unzip();
        let meshes = tessellate_pieces(&pieces, options).map_err(|(i, source)| PieceError {
            part: names[i].clone(),
            source,
        })?;
        Ok(names.into_iter().zip(meshes).collect())
    }
}

/// Which surface an export writes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Skin {
    /// One closed surface ([`trigbody_core::closed_skin`]): the boundary of
    /// the union of the pieces less the cavities, watertight, manifold and
    /// consistently oriented, as one piece named `skin`.
    #[default]
    Closed,
    /// Every piece's whole tessellation (where pieces overlap, the skin of
    /// one runs on inside the other).
    Whole,
    /// The outer skin ([`trigbody_core::internals::surface::skin`]): each piece's triangles
    /// inside another piece left out.
    Outer,
}

/// The pieces of [`Model::tessellate_pieces`] trimmed to `skin`: for
/// [`Skin::Outer`], with the depth tolerance 0.0003 × the body's height
/// (the report's, [`trigbody_core::ReconstructOptions::skin_depth`]),
/// or × the pieces' bounding-box diagonal for a model without a body.
/// For [`Skin::Closed`], the one closed piece, or why it could not be made
/// (a piece whose open ends do not form loops).
pub fn skin_pieces(
    model: &Model,
    pieces: Vec<(String, Mesh)>,
    skin: Skin,
) -> Result<Vec<(String, Mesh)>, trigbody_core::internals::surface::closed_skin::ClosedSkinError> {
    if skin == Skin::Whole {
        return Ok(pieces);
    }
    let scale = model.body.as_ref().map(|b| b.height).unwrap_or_else(|| {
        trigbody_core::Aabb::from_points(pieces.iter().flat_map(|(_, m)| &m.positions))
            .map_or(0.0, |b| b.diagonal())
    });
    let depth = trigbody_core::ReconstructOptions::default().skin_depth * scale;
    // A cavity lies inside its part and bounds empty space there: it is on
    // the outer skin whole, and nothing is inside it.
    let cavity = |name: &str| {
        model
            .parts
            .iter()
            .any(|p| p.name == name && p.cavity_of.is_some())
    };
    if skin == Skin::Closed {
        let (mut solids, mut cavities) = (Vec::new(), Vec::new());
        for (name, mesh) in pieces {
            if cavity(&name) {
                cavities.push(mesh);
            } else {
                solids.push(mesh);
            }
        }
        let closed =
            trigbody_core::internals::surface::closed_skin::closed_skin(&solids, &cavities)?;
        return Ok(vec![("skin".to_string(), closed)]);
    }
    let (names, mut meshes): (Vec<String>, Vec<Mesh>) = pieces.into_iter().unzip();
    let solid: Vec<usize> = (0..names.len()).filter(|&i| !cavity(&names[i])).collect();
    // The solid pieces moved out in order, trimmed, and put back.
    let solids: Vec<Mesh> = solid
        .iter()
        .map(|&i| std::mem::take(&mut meshes[i]))
        .collect();
    for (i, trimmed) in
        solid
            .into_iter()
            .zip(trigbody_core::internals::surface::skin::outer_pieces(
                &solids, depth,
            ))
    {
        meshes[i] = trimmed;
    }
    Ok(names.into_iter().zip(meshes).collect())
}

/// The pieces of [`Model::tessellate_pieces`] in one mesh (indices
/// shifted; normals kept when every piece has them).
pub fn merge_pieces(pieces: &[(String, Mesh)]) -> Mesh {
    let meshes: Vec<&Mesh> = pieces.iter().map(|(_, m)| m).collect();
    trigbody_core::internals::geom::mesh::concatenate(&meshes).0
}

/// A part of a model that could not be tessellated.
#[derive(Debug, Error)]
#[error("part '{part}': {source}")]
pub struct PieceError {
    /// The part's name in the model.
    pub part: String,
    /// What the tessellation found.
    #[source]
    pub source: TessellateError,
}

/// What is wrong with a model file (every message names the part and
/// section, and the value).
#[derive(Debug, Error)]
pub enum ModelError {
    /// Not JSON at all (the message has the line and column; NaN and
    /// infinities are not JSON either).
    #[error("not valid JSON: {0}")]
    Json(#[source] serde_json::Error),
    /// The document's `format` is not `trigbody-model`.
    #[error("not a trigbody model: \"format\" is {found}, expected \"{MODEL_FORMAT}\"")]
    NotAModel {
        /// The `format` value found (or `missing`).
        found: String,
    },
    /// A version this build cannot read.
    #[error(
        "model version {found} is not supported (this build reads versions 1 to {MODEL_VERSION})"
    )]
    UnknownVersion {
        /// The `version` value found (or `missing`).
        found: String,
    },
    /// A field is missing or has the wrong type.
    #[error("{context}: {message}")]
    Structure {
        /// Where: the part or section.
        context: String,
        /// What (serde's message, naming the field).
        message: String,
    },
    /// A part with fewer than 2 sections.
    #[error("part '{part}': {count} section(s); a part needs at least 2")]
    TooFewSections {
        /// The part's name.
        part: String,
        /// How many sections it has.
        count: usize,
    },
    /// A section without its plane frame.
    #[error("part '{part}', section {section}: no \"frame\" (every section needs its plane: origin, e1, e2)")]
    MissingFrame {
        /// The part's name.
        part: String,
        /// The section's index.
        section: usize,
    },
    /// A coefficient or frame component that is null (NaN written by a
    /// careless writer) or otherwise not a finite number.
    #[error("part '{part}', section {section}: {field}[{index}] is {value}, not a finite number of magnitude at most 1e9")]
    NonFinite {
        /// The part's name.
        part: String,
        /// The section's index.
        section: usize,
        /// `a`, `b`, `origin`, `e1` or `e2`.
        field: &'static str,
        /// The index in that list.
        index: usize,
        /// The value found.
        value: String,
    },
    /// A skinning method this build does not know.
    #[error("part '{part}': unknown skinning method \"{method}\" (expected one of catmull-rom, natural-spline, paper-chained, paper-unchained)")]
    UnknownSkinning {
        /// The part's name.
        part: String,
        /// The method found.
        method: String,
    },
    /// The sections do not make a part (crossing planes, mixed frames, bad
    /// curves…; see [`PartError`]).
    #[error("part '{part}': {source}")]
    Part {
        /// The part's name.
        part: String,
        /// Why.
        #[source]
        source: PartError,
    },
    /// A transition names a part the model does not have.
    #[error("transition {index}: no part named '{name}'")]
    UnknownPart {
        /// The transition's index.
        index: usize,
        /// The name found.
        name: String,
    },
    /// A transition that cannot be built from its parts and spec.
    #[error("transition {index} ('{from}' to '{to}'): {source}")]
    Transition {
        /// The transition's index.
        index: usize,
        /// Its `from` part.
        from: String,
        /// Its `to` part.
        to: String,
        /// Why.
        #[source]
        source: TransitionError,
    },
    /// Reading or writing failed.
    #[error("model I/O: {0}")]
    Io(#[from] std::io::Error),
}

#[derive(Serialize, Deserialize)]
struct FrameRecord {
    origin: Vec<Option<f64>>,
    e1: Vec<Option<f64>>,
    e2: Vec<Option<f64>>,
}

#[derive(Serialize, Deserialize)]
struct SectionRecord {
    #[serde(default)]
    frame: Option<FrameRecord>,
    a: Vec<Option<f64>>,
    b: Vec<Option<f64>>,
}

#[derive(Serialize, Deserialize)]
struct SkinningRecord {
    method: String,
    #[serde(default = "default_k")]
    curves_per_patch: usize,
    #[serde(default)]
    curvature_continuity: bool,
    #[serde(default = "default_true")]
    align_twist: bool,
}

fn default_k() -> usize {
    trigbody_core::internals::surface::part::DEFAULT_CURVES_PER_PATCH
}
fn default_true() -> bool {
    true
}

#[derive(Serialize, Deserialize, Default)]
struct CapsRecord {
    #[serde(default)]
    start: CapKind,
    #[serde(default)]
    end: CapKind,
}

#[derive(Serialize, Deserialize)]
struct PartRecord {
    name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    cavity_of: Option<String>,
    skinning: SkinningRecord,
    #[serde(default)]
    caps: CapsRecord,
    sections: Vec<SectionRecord>,
}

fn structure(context: impl Into<String>) -> impl FnOnce(serde_json::Error) -> ModelError {
    let context = context.into();
    move |e| ModelError::Structure {
        context,
        message: e.to_string(),
    }
}

/// The largest dome height and fullness a model file may give (relative
/// to the end curve's radius; reconstructed bodies use up to about 3.5): a
/// dome of height 1e300 tessellated to coordinates of 3e298.
pub const MAX_DOME_RELATIVE: f64 = 100.0;

/// The largest magnitude of a coordinate or coefficient in a model file
/// (a body of a million kilometres in metres, or a kilometre in µm).
pub const MAX_MAGNITUDE: f64 = 1e9;

fn check_cap(cap: CapKind) -> Result<(), String> {
    if let CapKind::Dome {
        relative_height,
        fullness,
        ..
    } = cap
    {
        for (field, x) in [("relative_height", relative_height), ("fullness", fullness)] {
            if !(x > 0.0 && x <= MAX_DOME_RELATIVE) {
                return Err(format!(
                    "dome {field} {x:e} must lie in (0, {MAX_DOME_RELATIVE}]"
                ));
            }
        }
    }
    Ok(())
}

fn finite_vec(
    values: &[Option<f64>],
    part: &str,
    section: usize,
    field: &'static str,
) -> Result<Vec<f64>, ModelError> {
    values
        .iter()
        .enumerate()
        .map(|(index, v)| match v {
            Some(x) if x.abs() <= MAX_MAGNITUDE => Ok(*x),
            other => Err(ModelError::NonFinite {
                part: part.to_string(),
                section,
                field,
                index,
                value: other.map_or("null".to_string(), |x| x.to_string()),
            }),
        })
        .collect()
}

fn vec3(
    values: &[Option<f64>],
    part: &str,
    section: usize,
    field: &'static str,
) -> Result<Vec3, ModelError> {
    let v = finite_vec(values, part, section, field)?;
    <[f64; 3]>::try_from(v.as_slice())
        .map(Vec3::from)
        .map_err(|_| ModelError::Structure {
            context: format!("part '{part}', section {section}"),
            message: format!("frame.{field} has {} components, expected 3", v.len()),
        })
}

/// Checks one section record and makes it a curve (validated by the core).
fn section_curve(rec: &SectionRecord, part: &str, section: usize) -> Result<TrigCurve, ModelError> {
    let frame = rec.frame.as_ref().ok_or_else(|| ModelError::MissingFrame {
        part: part.to_string(),
        section,
    })?;
    let frame = Frame {
        origin: vec3(&frame.origin, part, section, "origin")?,
        e1: vec3(&frame.e1, part, section, "e1")?,
        e2: vec3(&frame.e2, part, section, "e2")?,
    };
    let a = finite_vec(&rec.a, part, section, "a")?;
    let b = finite_vec(&rec.b, part, section, "b")?;
    TrigCurve::new(frame, a, b).map_err(|source| ModelError::Part {
        part: part.to_string(),
        source: PartError::Curve {
            index: section,
            source,
        },
    })
}

fn section_record(c: &TrigCurve) -> SectionRecord {
    let some = |v: &[f64]| v.iter().map(|x| Some(*x)).collect();
    SectionRecord {
        frame: Some(FrameRecord {
            origin: some(&c.frame.origin.to_array()),
            e1: some(&c.frame.e1.to_array()),
            e2: some(&c.frame.e2.to_array()),
        }),
        a: some(&c.a),
        b: some(&c.b),
    }
}

/// Reads a list of curves from `{"curves": [{frame, a, b}, …]}` (the
/// hand-written input of `trigbody loft`, the paper's modelling workflow).
/// Every curve is validated; `what` names the input in messages.
pub fn read_curves<R: Read>(reader: R, what: &str) -> Result<Vec<TrigCurve>, ModelError> {
    let doc: Value = serde_json::from_reader(reader).map_err(ModelError::Json)?;
    curves_of(&doc, what)
}

fn curves_of(doc: &Value, what: &str) -> Result<Vec<TrigCurve>, ModelError> {
    let list = doc
        .get("curves")
        .cloned()
        .ok_or_else(|| ModelError::Structure {
            context: what.to_string(),
            message: "expected an object with a \"curves\" list".to_string(),
        })?;
    let records: Vec<SectionRecord> = serde_json::from_value(list).map_err(structure(what))?;
    records
        .iter()
        .enumerate()
        .map(|(i, r)| section_curve(r, what, i))
        .collect()
}

/// The `format` of the file `trigbody sections --json` writes.
pub const SECTIONS_FORMAT: &str = "trigbody-sections";

/// Curves for lofting, per level along the part. Accepts
///
/// * one list `{"curves": [{frame, a, b}, ...]}` (one curve per level, in
///   order: the hand-written input of the paper's modelling workflow);
/// * levels with several curves each, `{"sections": [{"curves": [...]},
///   ...]}`;
/// * the output of `trigbody sections --json`: `{"format":
///   "trigbody-sections", "version": 1, "levels": [{"loops": [{origin, e1,
///   e2, a, b, ...}, ...]}, ...]}` (every loop a cut met, its frame inline).
pub fn read_curve_levels<R: Read>(
    reader: R,
    what: &str,
) -> Result<Vec<Vec<TrigCurve>>, ModelError> {
    let doc: Value = serde_json::from_reader(reader).map_err(ModelError::Json)?;
    if doc.get("format").and_then(Value::as_str) == Some(SECTIONS_FORMAT) {
        return sections_file_levels(&doc, what);
    }
    if doc.get("curves").is_some() {
        return Ok(curves_of(&doc, what)?
            .into_iter()
            .map(|c| vec![c])
            .collect());
    }
    let Some(Value::Array(levels)) = doc.get("sections") else {
        return Err(ModelError::Structure {
            context: what.to_string(),
            message: "expected \"curves\" (a list of curves), \"sections\" (a list of levels, each with \"curves\") or a trigbody-sections file".to_string(),
        });
    };
    levels
        .iter()
        .enumerate()
        .map(|(i, level)| curves_of(level, &format!("{what}, section {i}")))
        .collect()
}

fn sections_file_levels(doc: &Value, what: &str) -> Result<Vec<Vec<TrigCurve>>, ModelError> {
    match doc.get("version") {
        Some(v) if v.as_u64() == Some(1) => {}
        other => {
            return Err(ModelError::UnknownVersion {
                found: other.map_or("missing".to_string(), |v| v.to_string()),
            })
        }
    }
    let Some(Value::Array(levels)) = doc.get("levels") else {
        return Err(ModelError::Structure {
            context: what.to_string(),
            message: "a trigbody-sections file needs a \"levels\" list".to_string(),
        });
    };
    levels
        .iter()
        .enumerate()
        .map(|(i, level)| {
            let context = format!("{what}, level {i}");
            let loops = level
                .get("loops")
                .and_then(Value::as_array)
                .ok_or_else(|| ModelError::Structure {
                    context: context.clone(),
                    message: "no \"loops\" list".to_string(),
                })?;
            loops
                .iter()
                .enumerate()
                .map(|(k, l)| {
                    // The frame is inline: {origin, e1, e2, a, b, ...}.
                    let mut rec = l.clone();
                    if rec.get("frame").is_none() {
                        if let (Some(o), Some(e1), Some(e2)) =
                            (l.get("origin"), l.get("e1"), l.get("e2"))
                        {
                            rec["frame"] = serde_json::json!({ "origin": o, "e1": e1, "e2": e2 });
                        }
                    }
                    let r: SectionRecord = serde_json::from_value(rec)
                        .map_err(structure(format!("{context}, loop {k}")))?;
                    section_curve(&r, &context, k)
                })
                .collect()
        })
        .collect()
}

/// Parses a model from JSON text.
pub fn read_model<R: Read>(reader: R) -> Result<Model, ModelError> {
    let doc: Value = serde_json::from_reader(reader).map_err(ModelError::Json)?;
    model_of_value(doc)
}

/// The model of a parsed JSON document (also the last step of reading a
/// compact `.tbm` file, which rebuilds this document).
pub(crate) fn model_of_value(doc: Value) -> Result<Model, ModelError> {
    match doc.get("format") {
        Some(Value::String(s)) if s == MODEL_FORMAT => {}
        other => {
            return Err(ModelError::NotAModel {
                found: other.map_or("missing".to_string(), |v| v.to_string()),
            })
        }
    }
    match doc.get("version") {
        Some(v) if matches!(v.as_u64(), Some(1..=MODEL_VERSION)) => {}
        other => {
            return Err(ModelError::UnknownVersion {
                found: other.map_or("missing".to_string(), |v| v.to_string()),
            })
        }
    }
    let units = match doc.get("units") {
        Some(Value::String(s)) => s.clone(),
        None => "m".to_string(),
        Some(other) => {
            return Err(ModelError::Structure {
                context: "model".to_string(),
                message: format!("\"units\" must be a string, got {other}"),
            })
        }
    };
    let parts_value = doc
        .get("parts")
        .cloned()
        .unwrap_or(Value::Array(Vec::new()));
    let Value::Array(part_values) = parts_value else {
        return Err(ModelError::Structure {
            context: "model".to_string(),
            message: "\"parts\" must be a list".to_string(),
        });
    };
    let mut parts = Vec::with_capacity(part_values.len());
    for (i, pv) in part_values.into_iter().enumerate() {
        let rec: PartRecord = serde_json::from_value(pv).map_err(structure(format!("part {i}")))?;
        let name = rec.name.clone();
        if rec.sections.len() < 2 {
            return Err(ModelError::TooFewSections {
                part: name,
                count: rec.sections.len(),
            });
        }
        for (end, cap) in [("start", rec.caps.start), ("end", rec.caps.end)] {
            check_cap(cap).map_err(|message| ModelError::Structure {
                context: format!("part '{name}', {end} cap"),
                message,
            })?;
        }
        let skinning = Skinning::from_name(&rec.skinning.method).ok_or_else(|| {
            ModelError::UnknownSkinning {
                part: name.clone(),
                method: rec.skinning.method.clone(),
            }
        })?;
        let curves = rec
            .sections
            .iter()
            .enumerate()
            .map(|(k, s)| section_curve(s, &name, k))
            .collect::<Result<Vec<_>, _>>()?;
        let options = PartOptions {
            skinning,
            curves_per_patch: rec.skinning.curves_per_patch,
            curvature_continuity: rec.skinning.curvature_continuity,
            align_twist: rec.skinning.align_twist,
            start_cap: rec.caps.start,
            end_cap: rec.caps.end,
        };
        let part = Part::new(curves, &options).map_err(|source| ModelError::Part {
            part: name.clone(),
            source,
        })?;
        parts.push(ModelPart {
            name,
            part,
            cavity_of: rec.cavity_of,
        });
    }
    for (i, p) in parts.iter().enumerate() {
        let Some(host) = &p.cavity_of else { continue };
        if !parts
            .iter()
            .any(|q| q.cavity_of.is_none() && &q.name == host)
        {
            return Err(ModelError::Structure {
                context: format!("part {i} ('{}')", p.name),
                message: format!("cavity_of names \"{host}\", which is not a part of the model"),
            });
        }
    }
    let body = match doc.get("body") {
        None | Some(Value::Null) => None,
        Some(v) => {
            let r: BodyRecord = serde_json::from_value(v.clone()).map_err(structure("body"))?;
            let fin = |field: &'static str, x: [f64; 3]| {
                if x.iter().all(|c| c.is_finite()) {
                    Ok(Vec3::from(x))
                } else {
                    Err(ModelError::Structure {
                        context: "body".to_string(),
                        message: format!("{field} {x:?} is not finite"),
                    })
                }
            };
            if !(r.height.is_finite() && r.height > 0.0) {
                return Err(ModelError::Structure {
                    context: "body".to_string(),
                    message: format!("height {} must be a positive number", r.height),
                });
            }
            Some(ModelBody {
                up: fin("up", r.frame.up)?,
                front: fin("front", r.frame.front)?,
                left: fin("left", r.frame.left)?,
                origin: fin("origin", r.frame.origin)?,
                height: r.height,
            })
        }
    };
    let transitions = match doc.get("transitions") {
        None | Some(Value::Null) => Vec::new(),
        Some(Value::Array(list)) => list
            .iter()
            .enumerate()
            .map(|(index, v)| read_transition(index, v, &parts))
            .collect::<Result<Vec<_>, _>>()?,
        Some(_) => {
            return Err(ModelError::Structure {
                context: "model".to_string(),
                message: "\"transitions\" must be a list".to_string(),
            })
        }
    };
    Ok(Model {
        units,
        body,
        parts,
        transitions,
    })
}

#[derive(Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum EndRecord {
    Start,
    End,
}

#[derive(Serialize, Deserialize)]
struct SeamRecord {
    point: [f64; 3],
    normal: [f64; 3],
    up: [f64; 3],
}

#[derive(Serialize, Deserialize)]
struct SideRecord {
    point: [f64; 3],
    normal: [f64; 3],
}

#[derive(Serialize, Deserialize)]
struct TransitionRecord {
    from: String,
    from_end: EndRecord,
    to: String,
    to_end: EndRecord,
    magnitudes: [f64; 2],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    seam: Option<SeamRecord>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    side: Option<SideRecord>,
    #[serde(default = "default_order")]
    order: usize,
}

fn default_order() -> usize {
    12
}

fn read_transition(
    index: usize,
    v: &Value,
    parts: &[ModelPart],
) -> Result<ModelTransition, ModelError> {
    let r: TransitionRecord =
        serde_json::from_value(v.clone()).map_err(structure(format!("transition {index}")))?;
    let find = |name: &str| {
        parts
            .iter()
            .find(|p| p.name == name)
            .map(|p| &p.part)
            .ok_or_else(|| ModelError::UnknownPart {
                index,
                name: name.to_string(),
            })
    };
    let (from, to) = (find(&r.from)?, find(&r.to)?);
    let fin = |x: [f64; 3]| {
        if x.iter().all(|c| c.is_finite()) {
            Ok(Vec3::from(x))
        } else {
            Err(ModelError::Structure {
                context: format!("transition {index}"),
                message: format!("seam or side vector {x:?} is not finite"),
            })
        }
    };
    let seam = match &r.seam {
        Some(s) => Some(Seam {
            point: fin(s.point)?,
            normal: fin(s.normal)?,
            up: fin(s.up)?,
        }),
        None => None,
    };
    let side = match &r.side {
        Some(c) => Some(SideCut {
            point: fin(c.point)?,
            normal: fin(c.normal)?,
        }),
        None => None,
    };
    let spec = TransitionSpec {
        from_start: matches!(r.from_end, EndRecord::Start),
        to_start: matches!(r.to_end, EndRecord::Start),
        magnitudes: r.magnitudes,
        seam,
        side,
        order: r.order,
    };
    let transition =
        Transition::between(from, to, spec).map_err(|source| ModelError::Transition {
            index,
            from: r.from.clone(),
            to: r.to.clone(),
            source,
        })?;
    Ok(ModelTransition {
        from: r.from,
        to: r.to,
        transition,
    })
}

fn transition_record(t: &ModelTransition) -> TransitionRecord {
    let s = t.transition.spec();
    let end = |start: bool| {
        if start {
            EndRecord::Start
        } else {
            EndRecord::End
        }
    };
    TransitionRecord {
        from: t.from.clone(),
        from_end: end(s.from_start),
        to: t.to.clone(),
        to_end: end(s.to_start),
        magnitudes: s.magnitudes,
        seam: s.seam.map(|m| SeamRecord {
            point: m.point.to_array(),
            normal: m.normal.to_array(),
            up: m.up.to_array(),
        }),
        side: s.side.map(|c| SideRecord {
            point: c.point.to_array(),
            normal: c.normal.to_array(),
        }),
        order: s.order,
    }
}

#[derive(Serialize, Deserialize)]
struct BodyFrameRecord {
    up: [f64; 3],
    front: [f64; 3],
    left: [f64; 3],
    origin: [f64; 3],
}

#[derive(Serialize, Deserialize)]
struct BodyRecord {
    frame: BodyFrameRecord,
    height: f64,
}

#[derive(Serialize)]
pub(crate) struct ModelRecord<'a> {
    format: &'static str,
    version: u64,
    units: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    body: Option<BodyRecord>,
    parts: Vec<PartRecord>,
    /// Transition surfaces between parts (docs/model-format.md).
    transitions: Vec<TransitionRecord>,
}

pub(crate) fn model_record(model: &Model) -> ModelRecord<'_> {
    let parts = model
        .parts
        .iter()
        .map(|p| {
            let o = p.part.options();
            PartRecord {
                name: p.name.clone(),
                cavity_of: p.cavity_of.clone(),
                skinning: SkinningRecord {
                    method: o.skinning.name().to_string(),
                    curves_per_patch: o.curves_per_patch,
                    curvature_continuity: o.curvature_continuity,
                    align_twist: o.align_twist,
                },
                caps: CapsRecord {
                    start: o.start_cap,
                    end: o.end_cap,
                },
                sections: p.part.sections().iter().map(section_record).collect(),
            }
        })
        .collect();
    ModelRecord {
        format: MODEL_FORMAT,
        version: MODEL_VERSION,
        units: &model.units,
        body: model.body.map(|b| BodyRecord {
            frame: BodyFrameRecord {
                up: b.up.to_array(),
                front: b.front.to_array(),
                left: b.left.to_array(),
                origin: b.origin.to_array(),
            },
            height: b.height,
        }),
        parts,
        transitions: model.transitions.iter().map(transition_record).collect(),
    }
}

/// Writes the model as pretty-printed JSON (fields in the documented order:
/// format, version, units, parts).
pub fn write_model<W: Write>(mut writer: W, model: &Model) -> Result<(), ModelError> {
    serde_json::to_writer_pretty(&mut writer, &model_record(model)).map_err(ModelError::Json)?;
    writer.write_all(b"\n")?;
    writer.flush()?;
    Ok(())
}
