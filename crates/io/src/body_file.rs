//! A reconstructed [`Body`] as a model file (version 5) and back, and its
//! [`Report`] as JSON.

use crate::model::{Model, ModelBody, ModelPart, ModelTransition};
use serde_json::{json, Value};
use thiserror::Error;
use trigbody_core::internals::body::DistanceMm;
use trigbody_core::{
    Body, BodyCavity, BodyDigit, BodyFrame, BodyPart, BodyTransition, PartName, Report, Units,
};

/// The name a part has in model files and GLB nodes: `torso`, `head`,
/// `left_arm`, `right_arm`, `left_leg`, `right_leg`, `left_foot`,
/// `right_foot`.
pub fn part_file_name(name: PartName) -> &'static str {
    match name {
        PartName::Torso => "torso",
        PartName::Head => "head",
        PartName::LeftArm => "left_arm",
        PartName::RightArm => "right_arm",
        PartName::LeftLeg => "left_leg",
        PartName::RightLeg => "right_leg",
        PartName::LeftFoot => "left_foot",
        PartName::RightFoot => "right_foot",
    }
}

/// Each item's number among the items of the same part before it, from 0.
fn per_part(parts: impl IntoIterator<Item = PartName>) -> Vec<(PartName, usize)> {
    let mut seen: Vec<PartName> = Vec::new();
    parts
        .into_iter()
        .map(|p| {
            let k = seen.iter().filter(|&&q| q == p).count();
            seen.push(p);
            (p, k)
        })
        .collect()
}

/// The names of cavities in model files and reports, in order: the part's
/// name and `_cavity` (`head_cavity`), numbered from the second cavity of
/// the same part on (`head_cavity_2`).
pub fn cavity_file_names(within: impl IntoIterator<Item = PartName>) -> Vec<String> {
    per_part(within)
        .into_iter()
        .map(|(p, k)| match k {
            0 => format!("{}_cavity", part_file_name(p)),
            _ => format!("{}_cavity_{}", part_file_name(p), k + 1),
        })
        .collect()
}

/// The names of digits in model files and reports, in order: the arm's
/// name, `_digit_` and the digit's number on that hand from 1
/// (`left_arm_digit_1`).
pub fn digit_file_names(hands: impl IntoIterator<Item = PartName>) -> Vec<String> {
    per_part(hands)
        .into_iter()
        .map(|(p, k)| format!("{}_digit_{}", part_file_name(p), k + 1))
        .collect()
}

/// The arm of a digit's file name ([`digit_file_names`]).
fn digit_hand(name: &str) -> Option<PartName> {
    let (arm, k) = name.rsplit_once("_digit_")?;
    k.parse::<usize>().ok().filter(|&k| k >= 1)?;
    [PartName::LeftArm, PartName::RightArm]
        .into_iter()
        .find(|&a| part_file_name(a) == arm)
}

/// The model of a body: its parts by name (then its digits, named by
/// [`digit_file_names`], then its cavities, each
/// `cavity_of` its part, named by [`cavity_file_names`]), its frame and
/// height, its units.
pub fn model_of_body(body: &Body) -> Model {
    let cavity_names = cavity_file_names(body.cavities.iter().map(|c| c.within));
    let digit_names = digit_file_names(body.digits.iter().map(|d| d.hand));
    Model {
        units: body.units.symbol().to_string(),
        body: Some(ModelBody {
            up: body.frame.up,
            front: body.frame.front,
            left: body.frame.left,
            origin: body.frame.origin,
            height: body.height,
        }),
        parts: body
            .parts
            .iter()
            .map(|p| ModelPart {
                name: part_file_name(p.name).to_string(),
                part: p.part.clone(),
                cavity_of: None,
            })
            .chain(
                body.digits
                    .iter()
                    .zip(digit_names)
                    .map(|(d, name)| ModelPart {
                        name,
                        part: d.part.clone(),
                        cavity_of: None,
                    }),
            )
            .chain(
                body.cavities
                    .iter()
                    .zip(cavity_names)
                    .map(|(c, name)| ModelPart {
                        name,
                        part: c.part.clone(),
                        cavity_of: Some(part_file_name(c.within).to_string()),
                    }),
            )
            .collect(),
        transitions: body
            .transitions
            .iter()
            .map(|t| ModelTransition {
                from: part_file_name(t.from).to_string(),
                to: part_file_name(t.to).to_string(),
                transition: t.transition.clone(),
            })
            .collect(),
    }
}

/// Why a model is not a body ([`body_of_model`]).
#[derive(Debug, Error, PartialEq)]
pub enum BodyOfModelError {
    /// A model of parts only (`trigbody loft`, model format 1).
    #[error(
        "a model of parts without a \"body\" object (e.g. from `trigbody loft`) has no body frame \
         to measure; make a body model with `trigbody reconstruct`"
    )]
    NoBody,
    /// Units other than m, cm, mm.
    #[error("units \"{0}\" are not m, cm or mm")]
    Units(String),
    /// A cavity inside something that is not a body part.
    #[error("part \"{part}\" is a cavity of \"{host}\", not a body part")]
    CavityHost {
        /// The cavity's name.
        part: String,
        /// The name it gives as its part.
        host: String,
    },
    /// A part name no body has.
    #[error(
        "part \"{0}\" is not a body part (torso, head, left_arm, right_arm, left_leg, right_leg, \
         or an arm's digit such as left_arm_digit_1)"
    )]
    NotABodyPart(String),
    /// A transition naming something that is not a body part.
    #[error("transition names \"{0}\", not a body part")]
    TransitionPart(String),
}

/// The body of a model, the inverse of [`model_of_body`]: its `body`
/// frame and height, its parts by their file names ([`part_file_name`]),
/// its cavities by the part they are in. A model without a `body` object
/// (a loft) or with a part name no body has is refused. Section fits are
/// not in model files: the parts come back without them.
pub fn body_of_model(model: Model) -> Result<Body, BodyOfModelError> {
    let frame = model.body.ok_or(BodyOfModelError::NoBody)?;
    let units =
        Units::from_symbol(&model.units).ok_or(BodyOfModelError::Units(model.units.clone()))?;
    let named = |n: &str| {
        PartName::ALL
            .iter()
            .copied()
            .find(|k| part_file_name(*k) == n)
    };
    let mut parts = Vec::with_capacity(model.parts.len());
    let (mut cavities, mut digits) = (Vec::new(), Vec::new());
    for p in model.parts {
        if let Some(host) = &p.cavity_of {
            let within = named(host).ok_or_else(|| BodyOfModelError::CavityHost {
                part: p.name.clone(),
                host: host.clone(),
            })?;
            cavities.push(BodyCavity {
                within,
                part: p.part,
                fits: Vec::new(),
            });
            continue;
        }
        if let Some(hand) = digit_hand(&p.name) {
            digits.push(BodyDigit {
                hand,
                part: p.part,
                fits: Vec::new(),
            });
            continue;
        }
        let name = named(&p.name).ok_or_else(|| BodyOfModelError::NotABodyPart(p.name.clone()))?;
        parts.push(BodyPart {
            name,
            part: p.part,
            fits: Vec::new(),
        });
    }
    let mut transitions = Vec::with_capacity(model.transitions.len());
    for t in model.transitions {
        let end = |n: &str| named(n).ok_or_else(|| BodyOfModelError::TransitionPart(n.into()));
        transitions.push(BodyTransition {
            from: end(&t.from)?,
            to: end(&t.to)?,
            transition: t.transition,
        });
    }
    Ok(Body {
        transitions,
        digits,
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

fn mm(d: &DistanceMm) -> Value {
    json!({"rms": d.rms, "p95": d.p95, "max": d.max})
}

/// The names of the report's parts, in order: a part's file name
/// ([`part_file_name`]), a digit's and a cavity's as in model files
/// ([`digit_file_names`], [`cavity_file_names`]).
pub fn report_part_names(report: &Report) -> Vec<String> {
    let mut cavities =
        cavity_file_names(report.parts.iter().filter(|p| p.cavity).map(|p| p.name)).into_iter();
    let mut digits =
        digit_file_names(report.parts.iter().filter(|p| p.digit).map(|p| p.name)).into_iter();
    report
        .parts
        .iter()
        .map(|p| match (p.cavity, p.digit) {
            (true, _) => cavities.next().unwrap_or_default(),
            (_, true) => digits.next().unwrap_or_default(),
            _ => part_file_name(p.name).to_string(),
        })
        .collect()
}

/// The report as JSON: `design_parameters`, `input_vertices`,
/// `polygon_parameters` (3 × vertices), `parameter_ratio`, `distance_mm`
/// (symmetric) with `input_to_model_mm` and `model_to_input_mm`,
/// `coverage` (0-1), `visible_coverage` (coverage of the input's outer
/// surface, see [`Report::visible_coverage`]), `hidden_samples`,
/// `unobserved_samples` (a cloud's model samples over its holes, see
/// [`Report::unobserved_samples`]), `visible_rms_mm` and `visible_p95_mm`
/// (the symmetric RMS and p95 without the hidden or unobserved samples),
/// `region_parameters` (the design parameters of the head, the hands, the
/// feet and the rest, [`Report::region_parameters`]), `interior_area_share` (the share of the pieces' tessellated area inside
/// other pieces, left out of both distance directions: they measure the
/// model's outer skin, see [`Report::interior_area_share`]), `parts` (per part: sections, orders {min, median, max},
/// worst E_a/E_M, sections meeting the tolerances, the ellipse baseline's
/// worst E_a/E_M, design parameters), `fit` (per part fitted to the input:
/// its points and those used, the residual RMS before and after in mm, how
/// far its curves moved, RMS and largest, the rounds taken and the
/// sections added; [`Report::fit`]), `parts_found`, `joints` (each joint
/// centre's name and position in the input's coordinates) and `warnings`.
pub fn report_json(report: &Report) -> Value {
    json!({
        "units": report.units.symbol(),
        "units_inferred": report.units_inferred,
        "design_parameters": report.design_parameters,
        "compact_numbers": report.compact_numbers,
        "region_parameters": {
            "head": report.region_parameters.head,
            "hands": report.region_parameters.hands,
            "feet": report.region_parameters.feet,
            "rest": report.region_parameters.rest,
        },
        "input_vertices": report.input_vertices,
        "polygon_parameters": 3 * report.input_vertices,
        "parameter_ratio": report.parameter_ratio(),
        "distance_mm": mm(&report.distance_mm),
        "input_to_model_mm": mm(&report.input_to_model_mm),
        "model_to_input_mm": mm(&report.model_to_input_mm),
        "coverage": report.coverage,
        "visible_coverage": report.visible_coverage,
        "hidden_samples": report.hidden_samples,
        "unobserved_samples": report.unobserved_samples,
        "visible_rms_mm": report.visible_rms_mm,
        "visible_p95_mm": report.visible_p95_mm,
        "interior_area_share": report.interior_area_share,
        "parts": report.parts.iter().zip(report_part_names(report)).map(|(p, name)| json!({
            "name": name,
            "sections": p.sections,
            "orders": {"min": p.orders.0, "median": p.orders.1, "max": p.orders.2},
            "worst_ea": p.worst_ea,
            "worst_em": p.worst_em,
            "sections_meeting_tolerances": p.met,
            "ellipse": {"worst_ea": p.ellipse_worst_ea, "worst_em": p.ellipse_worst_em},
            "design_parameters": p.design_parameters,
        })).collect::<Vec<_>>(),
        "fit": report.fit.iter().map(|f| json!({
            "name": f.name,
            "points": f.points,
            "used": f.used,
            "rms_before_mm": f.rms_before_mm,
            "rms_after_mm": f.rms_after_mm,
            "moved_rms_mm": f.moved_rms_mm,
            "moved_max_mm": f.moved_max_mm,
            "rounds": f.rounds,
            "sections_added": f.sections_added,
        })).collect::<Vec<_>>(),
        "parts_found": report.parts_found.iter().map(|p| part_file_name(*p)).collect::<Vec<_>>(),
        "joints": report.joints.iter().map(|(n, p)| (n.as_str().to_string(), json!(p.to_array()))).collect::<serde_json::Map<_, _>>(),
        "warnings": report.warnings,
    })
}
