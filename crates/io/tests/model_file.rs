//! The model file: exact round trips and clear errors for bad input.

use trigbody_core::PartError;
use trigbody_core::{CapKind, Frame, Part, PartOptions, Skinning, TrigCurve, Vec3};
use trigbody_io::model::{read_curves, read_model, write_model, Model, ModelError, ModelPart};

fn sections() -> Vec<TrigCurve> {
    (0..6)
        .map(|k| {
            let z = 0.031 * k as f64 + 1e-3 * (k as f64).sin();
            let frame = Frame::from_normal(
                Vec3::new(0.1 + 0.002 * k as f64, -0.3, z),
                Vec3::new(0.02 * (k as f64).cos(), 0.01, 1.0),
                Vec3::X,
            )
            .unwrap();
            let a = vec![
                1e-3,
                0.061 + 0.001 * k as f64,
                0.0021,
                0.0043 / 3.0,
                -0.0007,
            ];
            let b = vec![
                -2e-4,
                0.05 - 0.0013 * k as f64,
                0.0011,
                1.0 / 7.0 * 1e-3,
                0.0003,
            ];
            // Phase-shifted so that twist alignment has work to do.
            TrigCurve::new(frame, a, b).unwrap().shifted(0.1 * k as f64)
        })
        .collect()
}

fn model(options: &PartOptions) -> Model {
    Model {
        units: "m".into(),
        body: None,
        parts: vec![
            ModelPart {
                name: "leg_left".into(),
                part: Part::new(sections(), options).unwrap(),
                cavity_of: None,
            },
            ModelPart {
                name: "tube \"two\"".into(),
                part: Part::new(sections()[1..4].to_vec(), &PartOptions::default()).unwrap(),
                cavity_of: None,
            },
        ],
        transitions: Vec::new(),
    }
}

fn round_trip(m: &Model) -> Model {
    let mut bytes = Vec::new();
    write_model(&mut bytes, m).unwrap();
    read_model(bytes.as_slice()).unwrap()
}

#[test]
fn round_trip_is_exact_for_every_option() {
    for skinning in Skinning::ALL {
        for (start_cap, end_cap) in [
            (CapKind::Open, CapKind::Open),
            (
                CapKind::Flat,
                CapKind::Dome {
                    relative_height: 0.7,
                    fullness: 1.0,
                    axis: trigbody_core::DomeAxis::Tangent,
                },
            ),
            (
                CapKind::Dome {
                    relative_height: 1.2,
                    fullness: 1.5,
                    axis: trigbody_core::DomeAxis::Normal,
                },
                CapKind::Dome {
                    relative_height: 0.7,
                    fullness: 2.0,
                    axis: trigbody_core::DomeAxis::Tangent,
                },
            ),
        ] {
            let options = PartOptions {
                skinning,
                curves_per_patch: 3,
                curvature_continuity: skinning == Skinning::PaperChained,
                align_twist: true,
                start_cap,
                end_cap,
            };
            let m = model(&options);
            let back = round_trip(&m);
            // Exact f64 equality of everything, patches included.
            assert_eq!(back, m, "{skinning:?}");
        }
    }
}

fn text(m: &Model) -> String {
    let mut bytes = Vec::new();
    write_model(&mut bytes, m).unwrap();
    String::from_utf8(bytes).unwrap()
}

fn edit(f: impl FnOnce(&mut serde_json::Value)) -> Result<Model, ModelError> {
    let mut doc: serde_json::Value =
        serde_json::from_str(&text(&model(&PartOptions::default()))).unwrap();
    f(&mut doc);
    read_model(doc.to_string().as_bytes())
}

#[test]
fn nan_coefficients_are_refused() {
    let err = edit(|d| d["parts"][0]["sections"][2]["a"][3] = serde_json::Value::Null).unwrap_err();
    assert!(
        matches!(
            err,
            ModelError::NonFinite {
                section: 2,
                field: "a",
                index: 3,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("leg_left"), "{err}");
    // A literal NaN is not JSON: a parse error with its position.
    let t = text(&model(&PartOptions::default())).replacen("0.061", "NaN", 1);
    let err = read_model(t.as_bytes()).unwrap_err();
    assert!(matches!(err, ModelError::Json(_)));
    assert!(err.to_string().contains("line"), "{err}");
    let err = edit(|d| d["parts"][0]["sections"][0]["frame"]["e1"][1] = serde_json::Value::Null)
        .unwrap_err();
    assert!(
        matches!(err, ModelError::NonFinite { field: "e1", .. }),
        "{err}"
    );
}

#[test]
fn unknown_version_and_format_are_refused() {
    let err = edit(|d| d["version"] = 6.into()).unwrap_err();
    assert!(matches!(err, ModelError::UnknownVersion { .. }), "{err}");
    assert!(err.to_string().contains('5'));
    let err = edit(|d| d["format"] = "something-else".into()).unwrap_err();
    assert!(matches!(err, ModelError::NotAModel { .. }), "{err}");
}

#[test]
fn missing_and_mixed_frames_are_refused() {
    let err = edit(|d| {
        d["parts"][0]["sections"][3]
            .as_object_mut()
            .unwrap()
            .remove("frame");
    })
    .unwrap_err();
    assert!(
        matches!(err, ModelError::MissingFrame { section: 3, .. }),
        "{err}"
    );
    // One frame flipped (its normal against the part's axis).
    let err = edit(|d| {
        let e2 = d["parts"][0]["sections"][4]["frame"]["e2"].clone();
        let e1 = d["parts"][0]["sections"][4]["frame"]["e1"].clone();
        d["parts"][0]["sections"][4]["frame"]["e1"] = e2;
        d["parts"][0]["sections"][4]["frame"]["e2"] = e1;
    })
    .unwrap_err();
    assert!(
        matches!(
            err,
            ModelError::Part {
                source: PartError::MixedFrames { index: 4, .. },
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn short_section_lists_and_crossing_planes_are_refused() {
    let err = edit(|d| {
        d["parts"][0]["sections"]
            .as_array_mut()
            .unwrap()
            .truncate(1);
    })
    .unwrap_err();
    assert!(
        matches!(err, ModelError::TooFewSections { count: 1, .. }),
        "{err}"
    );
    // Section 2's plane tilted 60° about x: it cuts through sections 1 and 3.
    let err = edit(|d| {
        d["parts"][0]["sections"][2]["frame"]["e2"] =
            serde_json::json!([0.0, 0.5, -0.8660254037844386]);
        d["parts"][0]["sections"][2]["frame"]["e1"] = serde_json::json!([1.0, 0.0, 0.0]);
    })
    .unwrap_err();
    assert!(
        matches!(
            err,
            ModelError::Part {
                source: PartError::CrossingPlanes { .. },
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("cross"), "{err}");
}

#[test]
fn curve_lists_read_and_validate() {
    let json = r#"{"curves": [
        {"frame": {"origin": [0,0,0], "e1": [1,0,0], "e2": [0,1,0]}, "a": [0, 0.1, 0], "b": [0, 0.1, 0]},
        {"frame": {"origin": [0,0,0.1], "e1": [1,0,0], "e2": [0,1,0]}, "a": [0, 0.1, 0, 0.01, 0], "b": [0, 0.1, 0, 0, 0]}
    ]}"#;
    let curves = read_curves(json.as_bytes(), "in.json").unwrap();
    assert_eq!(curves.len(), 2);
    assert_eq!(curves[1].order(), 2);
    let bad = json.replace("\"a\": [0, 0.1, 0, 0.01, 0]", "\"a\": [0, 0.1]");
    let err = read_curves(bad.as_bytes(), "in.json").unwrap_err();
    assert!(err.to_string().contains("in.json"), "{err}");
    assert!(err.to_string().contains("section 1"), "{err}");
}

#[test]
fn sections_files_read_per_level() {
    use trigbody_io::model::read_curve_levels;
    let loop_json = |x: f64, y: f64| {
        format!(
            r#"{{"origin": [{x}, {y}, 0], "e1": [0, 0, 1], "e2": [1, 0, 0], "normal": [0, 1, 0],
                "order": 1, "a": [0, 0.05, 0], "b": [0, 0.04, 0], "ea": 0.001, "em": 0.002, "met": true}}"#
        )
    };
    let doc = format!(
        r#"{{"format": "trigbody-sections", "version": 1, "input": "body.obj", "kind": "mesh",
            "axis": [0, 1, 0], "levels": [
              {{"offset": 0.1, "loops": [{}, {}]}},
              {{"offset": 0.13, "loops": [{}]}}
            ]}}"#,
        loop_json(-0.1, 0.1),
        loop_json(0.1, 0.1),
        loop_json(0.1, 0.13)
    );
    let levels = read_curve_levels(doc.as_bytes(), "s.json").unwrap();
    assert_eq!(levels.iter().map(Vec::len).collect::<Vec<_>>(), [2, 1]);
    assert_eq!(levels[1][0].frame.origin, Vec3::new(0.1, 0.13, 0.0));
    let v2 = doc.replace("\"version\": 1", "\"version\": 2");
    assert!(matches!(
        read_curve_levels(v2.as_bytes(), "s.json"),
        Err(ModelError::UnknownVersion { .. })
    ));
    let flat = r#"{"curves": [{"frame": {"origin": [0,0,0], "e1": [1,0,0], "e2": [0,1,0]}, "a": [0,1,0], "b": [0,1,0]}]}"#;
    assert_eq!(
        read_curve_levels(flat.as_bytes(), "c.json").unwrap().len(),
        1
    );
}

#[test]
fn version_2_body_frame_round_trips_and_version_1_still_reads() {
    let mut m = model(&PartOptions::default());
    m.body = Some(trigbody_io::model::ModelBody {
        up: Vec3::new(0.0, 1.0, 0.0),
        front: Vec3::new(0.0, 0.0, 1.0),
        left: Vec3::new(1.0, 0.0, 0.0),
        origin: Vec3::new(0.01, -0.82, 0.1 / 3.0),
        height: 1.7312345678901234,
    });
    assert_eq!(round_trip(&m), m);
    let v2 = text(&m);
    assert!(v2.contains("\"version\": 5") && v2.contains("\"transitions\": []"));
    assert!(!v2.contains("cavity_of"), "no cavity: no field");
    // The same document as version 2 (no dome fullness in it) reads alike.
    let mut doc: serde_json::Value = serde_json::from_str(&v2).unwrap();
    doc["version"] = 2.into();
    assert_eq!(read_model(doc.to_string().as_bytes()).unwrap(), m);
    // A version-1 document (no body, no transitions) reads as before.
    let mut doc: serde_json::Value = serde_json::from_str(&v2).unwrap();
    doc["version"] = 1.into();
    let obj = doc.as_object_mut().unwrap();
    obj.remove("body");
    obj.remove("transitions");
    let old = read_model(doc.to_string().as_bytes()).unwrap();
    assert_eq!(old.body, None);
    assert_eq!(old.parts, m.parts);
    // A body with a non-positive height is refused, naming it.
    let err = edit(|d| {
        d["body"] = serde_json::json!({"frame": {"up": [0,1,0], "front": [0,0,1], "left": [1,0,0], "origin": [0,0,0]}, "height": -1.0})
    })
    .unwrap_err();
    assert!(err.to_string().contains("height"), "{err}");
}

#[test]
fn transitions_round_trip_and_bad_ones_are_refused() {
    use trigbody_core::internals::surface::transition::{
        Seam, SideCut, Transition, TransitionSpec,
    };
    use trigbody_io::model::ModelTransition;
    let mut m = model(&PartOptions::default());
    let (from, to) = (&m.parts[0].part, &m.parts[1].part);
    let plain = TransitionSpec {
        from_start: false,
        to_start: true,
        magnitudes: [0.013, 0.1 / 3.0],
        seam: None,
        side: None,
        order: 12,
    };
    let centre = to.curves()[0].frame.origin;
    let seamed = TransitionSpec {
        from_start: true,
        seam: Some(Seam {
            point: centre - Vec3::Z * 0.01,
            normal: Vec3::X,
            up: Vec3::Z,
        }),
        order: 7,
        ..plain
    };
    // A side cut across the second part's middle section (its plane,
    // through a point inside the curve).
    let mid = &to.curves()[1];
    let side = TransitionSpec {
        from_start: true,
        side: Some(SideCut {
            point: mid.frame.origin + mid.frame.e1 * 0.001,
            normal: mid.frame.normal(),
        }),
        order: 9,
        ..plain
    };
    for spec in [plain, seamed, side] {
        m.transitions.push(ModelTransition {
            from: m.parts[0].name.clone(),
            to: m.parts[1].name.clone(),
            transition: Transition::between(from, to, spec).unwrap(),
        });
    }
    let back = round_trip(&m);
    // Exact f64 equality, the transitions' patches included.
    assert_eq!(back, m);
    assert_eq!(back.transitions[1].transition.design_parameters(), 8);
    assert_eq!(back.transitions[2].transition.design_parameters(), 8);
    let t = text(&m);
    assert!(t.contains("\"from_end\": \"end\"") && t.contains("\"seam\""));
    assert!(t.contains("\"side\"") && t.contains("\"version\": 5"));
    // A side plane that misses the part is refused, naming the transition.
    let mut doc: serde_json::Value = serde_json::from_str(&t).unwrap();
    doc["transitions"][2]["side"]["point"][0] = 10.0.into();
    let err = read_model(doc.to_string().as_bytes()).unwrap_err();
    assert!(err.to_string().contains("transition 2"), "{err}");
    // A version-3 reader would ignore `side` and end the transition on
    // the part's end: a version-3 document with a side is not what this
    // build writes, but one without reads unchanged (below, as version 2).
    // An unknown part and a non-positive magnitude are refused, naming them.
    let mut doc: serde_json::Value = serde_json::from_str(&t).unwrap();
    doc["transitions"][0]["to"] = "arm".into();
    let err = read_model(doc.to_string().as_bytes()).unwrap_err();
    assert!(err.to_string().contains("no part named 'arm'"), "{err}");
    let mut doc: serde_json::Value = serde_json::from_str(&t).unwrap();
    doc["transitions"][1]["magnitudes"][0] = (-1.0).into();
    let err = read_model(doc.to_string().as_bytes()).unwrap_err();
    assert!(err.to_string().contains("transition 1"), "{err}");
}

/// A cavity (version 5): a part lying in another one, its surface facing
/// into the pocket. It round-trips exactly, tessellates turned inside out,
/// stays whole in the outer skin, and must name a part of the model.
#[test]
fn cavities_round_trip_face_inward_and_must_name_their_part() {
    use trigbody_io::model::{skin_pieces, Skin};
    let mut m = model(&PartOptions::default());
    let host = m.parts[0].part.clone();
    // The host's sections shrunk about their centres to a third: inside it.
    let inner: Vec<TrigCurve> = host
        .sections()
        .iter()
        .map(|c| {
            let mut c = c.clone();
            for s in [&mut c.a, &mut c.b] {
                for x in s.iter_mut().skip(1) {
                    *x /= 3.0;
                }
            }
            c
        })
        .collect();
    let options = PartOptions {
        start_cap: CapKind::dome(),
        end_cap: CapKind::dome(),
        ..PartOptions::default()
    };
    m.parts.push(ModelPart {
        name: "leg_left_cavity".into(),
        part: Part::new(inner, &options).unwrap(),
        cavity_of: Some("leg_left".into()),
    });
    let back = round_trip(&m);
    assert_eq!(back, m);
    let t = text(&m);
    assert!(t.contains("\"cavity_of\": \"leg_left\""), "{t}");
    // Tessellated, the cavity encloses a negative volume (it faces into
    // the pocket); the host a positive one.
    let tess = trigbody_core::TessellationOptions::default();
    let pieces = m.tessellate_pieces(&tess).unwrap();
    let cavity = &pieces[2].1;
    let host_mesh = &pieces[0].1;
    assert!(cavity.signed_volume() < 0.0, "{}", cavity.signed_volume());
    assert!(host_mesh.signed_volume() > 0.0);
    // The outer skin keeps the whole cavity (it lies inside its host).
    let outer = skin_pieces(&m, pieces.clone(), Skin::Outer).unwrap();
    let kept = outer.iter().find(|(n, _)| n == "leg_left_cavity").unwrap();
    assert_eq!(kept.1.triangles.len(), cavity.triangles.len());
    // A cavity of a part the model does not have is refused, naming it.
    let mut doc: serde_json::Value = serde_json::from_str(&t).unwrap();
    doc["parts"][2]["cavity_of"] = "arm".into();
    let err = read_model(doc.to_string().as_bytes()).unwrap_err();
    assert!(
        err.to_string().contains("leg_left_cavity") && err.to_string().contains("arm"),
        "{err}"
    );
}

/// A body becomes a model and comes back the same (without section fits,
/// which model files do not hold); models that are not bodies are refused
/// with what is wrong.
#[test]
fn body_to_model_and_back() {
    use trigbody_core::{Body, BodyCavity, BodyDigit, BodyFrame, BodyPart, PartName, Units};
    use trigbody_io::body_file::{body_of_model, model_of_body, BodyOfModelError};
    let part = Part::new(sections(), &PartOptions::default()).unwrap();
    let body = Body {
        parts: vec![
            BodyPart {
                name: PartName::Torso,
                part: part.clone(),
                fits: Vec::new(),
            },
            BodyPart {
                name: PartName::Head,
                part: part.clone(),
                fits: Vec::new(),
            },
        ],
        transitions: Vec::new(),
        // Two digits of the left hand, one of the right: named by hand and
        // number, read back to their hands.
        digits: [PartName::LeftArm, PartName::RightArm, PartName::LeftArm]
            .into_iter()
            .map(|hand| BodyDigit {
                hand,
                part: part.clone(),
                fits: Vec::new(),
            })
            .collect(),
        cavities: vec![BodyCavity {
            within: PartName::Head,
            part: part.clone(),
            fits: Vec::new(),
        }],
        units: Units::Millimetres,
        frame: BodyFrame {
            up: Vec3::Z,
            front: Vec3::Y,
            left: Vec3::new(-1.0, 0.0, 0.0),
            origin: Vec3::new(0.0, 0.0, 0.0),
        },
        height: 1.7,
    };
    let model = round_trip(&model_of_body(&body));
    let names: Vec<&str> = model.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "torso",
            "head",
            "left_arm_digit_1",
            "right_arm_digit_1",
            "left_arm_digit_2",
            "head_cavity"
        ]
    );
    assert_eq!(body_of_model(model.clone()), Ok(body));
    let mut stray = model.clone();
    stray.parts[2].name = "left_leg_digit_1".into();
    assert_eq!(
        body_of_model(stray),
        Err(BodyOfModelError::NotABodyPart("left_leg_digit_1".into()))
    );
    let mut loft = model.clone();
    loft.body = None;
    assert_eq!(body_of_model(loft), Err(BodyOfModelError::NoBody));
    let mut renamed = model.clone();
    renamed.parts[0].name = "tail".into();
    let e = body_of_model(renamed).unwrap_err();
    assert_eq!(e, BodyOfModelError::NotABodyPart("tail".into()));
    assert!(e
        .to_string()
        .starts_with("part \"tail\" is not a body part (torso, head,"));
    let mut inches = model;
    inches.units = "in".into();
    assert_eq!(
        body_of_model(inches).unwrap_err().to_string(),
        "units \"in\" are not m, cm or mm"
    );
}
