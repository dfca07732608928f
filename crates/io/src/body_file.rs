//! A reconstructed [`Body`] as a model file (version 5) and its [`Report`]
//! as JSON.

use crate::model::{Model, ModelBody, ModelPart, ModelTransition};
use serde_json::{json, Value};
use trigbody_core::body::{Body, BodyCavity, BodyPart, BodyTransition, DistanceMm, Report, Units};
use trigbody_core::segment::{BodyFrame, PartName};

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

/// The names of cavities in model files and reports, in order: the part's
/// name and `_cavity` (`head_cavity`), numbered from the second cavity of
/// the same part on (`head_cavity_2`).
pub fn cavity_file_names(within: impl IntoIterator<Item = PartName>) -> Vec<String> {
    let mut seen: Vec<PartName> = Vec::new();
    within
        .into_iter()
        .map(|p| {
            let k = seen.iter().filter(|&&q| q == p).count();
            seen.push(p);
            match k {
                0 => format!("{}_cavity", part_file_name(p)),
                _ => format!("{}_cavity_{}", part_file_name(p), k + 1),
            }
        })
        .collect()
}

/// The model of a body: its parts by name (then its cavities, each
/// `cavity_of` its part, named by [`cavity_file_names`]), its frame and
/// height, its units.
pub fn model_of_body(body: &Body) -> Model {
    let cavity_names = cavity_file_names(body.cavities.iter().map(|c| c.within));
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

/// The [`Body`] of a model read from a file, the inverse of
/// [`model_of_body`]: its `body` frame and height, its parts by their file
/// names (`torso`, `head`, `left_arm`, …), its cavities and transitions. A
/// model without a `body` object (a loft), with units other than m, cm or
/// mm, or with a part name no body has is refused with a message saying so.
pub fn body_of_model(model: Model) -> Result<Body, String> {
    let frame = model.body.ok_or_else(|| {
        "a model of parts without a \"body\" object (e.g. from `trigbody loft`) has no \
         body frame to measure; make a body model with `trigbody reconstruct`"
            .to_string()
    })?;
    let units = Units::from_symbol(&model.units)
        .ok_or_else(|| format!("units \"{}\" are not m, cm or mm", model.units))?;
    let named = |n: &str| {
        PartName::ALL
            .iter()
            .copied()
            .find(|k| part_file_name(*k) == n)
    };
    let mut parts = Vec::with_capacity(model.parts.len());
    let mut cavities = Vec::new();
    for p in model.parts {
        if let Some(host) = &p.cavity_of {
            let within = named(host).ok_or_else(|| {
                format!(
                    "part \"{}\" is a cavity of \"{host}\", not a body part",
                    p.name
                )
            })?;
            cavities.push(BodyCavity {
                within,
                part: p.part,
                fits: Vec::new(),
            });
            continue;
        }
        let name = named(&p.name).ok_or_else(|| {
            format!(
                "part \"{}\" is not a body part (torso, head, left_arm, right_arm, \
                 left_leg, right_leg)",
                p.name
            )
        })?;
        parts.push(BodyPart {
            name,
            part: p.part,
            fits: Vec::new(),
        });
    }
    let part_named =
        |n: &str| named(n).ok_or_else(|| format!("transition names \"{n}\", not a body part"));
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

fn mm(d: &DistanceMm) -> Value {
    json!({"rms": d.rms, "p95": d.p95, "max": d.max})
}

/// The names of the report's parts, in order: a part's file name
/// ([`part_file_name`]), a cavity's as in model files
/// ([`cavity_file_names`]).
pub fn report_part_names(report: &Report) -> Vec<String> {
    let mut cavities =
        cavity_file_names(report.parts.iter().filter(|p| p.cavity).map(|p| p.name)).into_iter();
    report
        .parts
        .iter()
        .map(|p| match p.cavity {
            true => cavities.next().unwrap_or_default(),
            false => part_file_name(p.name).to_string(),
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
/// `interior_area_share` (the share of the pieces' tessellated area inside
/// other pieces, left out of both distance directions: they measure the
/// model's outer skin, see [`Report::interior_area_share`]), `parts` (per part: sections, orders {min, median, max},
/// worst E_a/E_M, sections meeting the tolerances, the ellipse baseline's
/// worst E_a/E_M, design parameters), `parts_found` and `warnings`.
pub fn report_json(report: &Report) -> Value {
    json!({
        "design_parameters": report.design_parameters,
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
        "parts_found": report.parts_found.iter().map(|p| part_file_name(*p)).collect::<Vec<_>>(),
        "warnings": report.warnings,
    })
}
