//! Whole-body reconstruction of the project's real bodies, their virtual
//! scans and the external scan (from `../shared/data`; skipped with a note
//! when that folder is absent), with the issue-5 table printed
//! (`--nocapture`), invariance under rigid motions and units, and bad input.
//! The three bodies and their virtual scans are held to the issue's
//! targets (RMS ≤ 2.5 mm, p95 ≤ 6 mm, coverage ≥ 98 %, parameters ≤ 25 %).
//!
//! Only these tests know the bodies' conventions (metres, +y up, facing +z,
//! the body's left is +x). The targets are printed as met or not;
//! the assertions guard what is met today (with a margin), so a regression
//! fails while the open targets stay visible in the table.

mod common;

use std::path::PathBuf;

use common::shared_data;
use trigbody_core::internals::geom::mesh::concatenate;
use trigbody_core::internals::geom::rng::Rng;
use trigbody_core::internals::geom::shapes;
use trigbody_core::internals::spatial::distance::{sample_surface, DistanceStats, MeshDistance};
use trigbody_core::internals::surface::skin::outer_triangles;
use trigbody_core::{clean_cloud, CleanOptions};
use trigbody_core::{reconstruct, Body, ReconstructError, ReconstructOptions, Report, Units};
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_core::{BodyGeometry, PartName, SegmentError};
use trigbody_core::{Mesh, PointCloud, Rigid, TessellationOptions, Vec3};
use trigbody_io::{read_mesh, read_point_cloud, ReadOptions};

/// The repository's body (the built-in one, `data/bodies/mh_male.obj`).
fn repo_body() -> Mesh {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    read_mesh(&path, &ReadOptions::default()).unwrap()
}

/// `part` tessellated finely (edges 0.002 of the body's height).
fn fine(part: &trigbody_core::Part, body: &Body) -> Mesh {
    trigbody_core::tessellate_part(
        part,
        &TessellationOptions {
            target_edge: Some(0.002 * body.height),
            ..TessellationOptions::default()
        },
    )
    .unwrap()
}

/// Every part's section orders.
fn orders(b: &Body) -> Vec<Vec<usize>> {
    b.parts
        .iter()
        .map(|p| p.fits.iter().map(|f| f.order).collect())
        .collect()
}

/// A virtual scan of [`repo_body`] (the scanner's defaults).
fn repo_scan(mesh: &Mesh) -> PointCloud {
    virtual_scan(mesh, &ScannerOptions::default())
        .unwrap()
        .cloud
}

fn print_row(name: &str, r: &Report) {
    let ok = |b: bool| if b { "met" } else { "NOT met" };
    println!(
        "{name:<28} parts {}/{} | rms {:>5.2} p95 {:>5.2} max {:>6.1} mm | in->model rms {:>5.2} p95 {:>5.2} | model->in rms {:>5.2} p95 {:>5.2} | coverage {:>6.2} % (shown surface {:>6.2} %, rms {:>5.2}, p95 {:>5.2}) | params {:>5} / 3x{} = {:>5.1} %",
        r.parts.len(),
        r.parts_found.len(),
        r.distance_mm.rms,
        r.distance_mm.p95,
        r.distance_mm.max,
        r.input_to_model_mm.rms,
        r.input_to_model_mm.p95,
        r.model_to_input_mm.rms,
        r.model_to_input_mm.p95,
        100.0 * r.coverage,
        100.0 * r.visible_coverage,
        r.visible_rms_mm,
        r.visible_p95_mm,
        r.design_parameters,
        r.input_vertices,
        100.0 * r.parameter_ratio()
    );
    println!(
        "    targets: rms <= 2.5 mm {} (shown surface {}); p95 <= 6 mm {} (shown surface {}); coverage >= 98 % {} (shown surface {}); params <= 25 % {}",
        ok(r.distance_mm.rms <= 2.5),
        ok(r.visible_rms_mm <= 2.5),
        ok(r.distance_mm.p95 <= 6.0),
        ok(r.visible_p95_mm <= 6.0),
        ok(r.coverage >= 0.98),
        ok(r.visible_coverage >= 0.98),
        ok(r.parameter_ratio() <= 0.25)
    );
}

fn check_parts(name: &str, body: &Body, r: &Report) {
    assert_eq!(r.parts_found.len(), 8, "{name}: {:?}", r.parts_found);
    assert_eq!(body.parts.len(), 6, "{name}: {:?}", r.warnings);
    // The regions' parameters add up, and each lies within its parts: the
    // hands within the arms, the feet within the legs, the head mostly
    // the head part's and its cavity's.
    let by = r.region_parameters;
    assert_eq!(by.total(), r.design_parameters, "{name}: {by:?}");
    let of = |names: &[PartName]| -> usize {
        r.parts
            .iter()
            .filter(|p| names.contains(&p.name))
            .map(|p| p.design_parameters)
            .sum()
    };
    let arms = of(&[PartName::LeftArm, PartName::RightArm]);
    let legs = of(&[PartName::LeftLeg, PartName::RightLeg]);
    assert!(
        by.hands > 0 && by.hands < arms,
        "{name}: {by:?}, arms {arms}"
    );
    assert!(by.feet > 0 && by.feet < legs, "{name}: {by:?}, legs {legs}");
    let head = of(&[PartName::Head]);
    assert!(
        by.head >= head * 4 / 5,
        "{name}: {by:?}, head part and cavity {head}"
    );
    // Both legs join the torso's bottom through a transition.
    for leg in [PartName::LeftLeg, PartName::RightLeg] {
        assert!(
            body.transitions
                .iter()
                .any(|t| t.from == leg && t.to == PartName::Torso),
            "{name}: {leg} has no transition: {:?}",
            r.warnings
        );
    }
    // Both arms join the torso's shoulder through a side transition: it
    // starts on the arm's first curve exactly and ends on the torso's
    // surface (its curve there lies on the torso's tessellation).
    let torso = body.part(PartName::Torso).expect("a torso");
    let skin = fine(&torso.part, body);
    let on_torso = MeshDistance::new(&skin);
    for arm in [PartName::LeftArm, PartName::RightArm] {
        let t = body
            .transitions
            .iter()
            .find(|t| t.from == arm && t.to == PartName::Torso)
            .unwrap_or_else(|| panic!("{name}: {arm} has no transition: {:?}", r.warnings));
        assert!(t.transition.spec().side.is_some(), "{name}: {arm}");
        let first = body.part(arm).unwrap().part.curves()[0].world_series();
        let patch = t.transition.patch();
        let vs: Vec<f64> = (0..64)
            .map(|i| std::f64::consts::TAU * i as f64 / 64.0)
            .collect();
        for &v in &vs {
            assert!(
                patch.point(0.0, v).distance(first.point(v)) < 1e-9,
                "{name}: {arm} at v = {v}"
            );
        }
        let ends: Vec<Vec3> = vs.iter().map(|&v| patch.point(1.0, v)).collect();
        let off = on_torso.distances(&ends).into_iter().fold(0.0, f64::max);
        println!(
            "    {arm}: transition end {:.2} mm off the torso",
            off * 1000.0
        );
        // Measured 0.08-0.21 mm on the meshes, 0.10-0.60 mm on the scans
        // (the curve is the contour fitted at order 32; the torso's
        // tessellation's chords sag by about 0.03 mm).
        assert!(off < 0.001, "{name}: {arm}: {off}");
    }
}

/// A mesh's mouth (the shared bodies model its inside, about 1.5 % of
/// their surface) and its eye sockets (the eyelids part over pockets
/// round the eyeballs) are the head's three cavities, the mouth the
/// largest and lowest, the sockets side by side above it; each lines its
/// pocket: its surface lies on the input's (measured: the mouth RMS
/// 0.75-1.26 mm, p95 1.6-3.0 mm; the sockets, two sections each between
/// two domes, 1.48-2.24 mm and 3.0-4.5 mm) and inside the head (below the
/// head's top, above its first section).
fn check_mouth(name: &str, body: &Body, mesh: &Mesh) {
    assert_eq!(body.cavities.len(), 3, "{name}");
    let head = &body.part(PartName::Head).unwrap().part;
    let up = body.frame.up;
    let levels = |m: &Mesh| {
        m.positions
            .iter()
            .map(|p| p.dot(up))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| {
                (lo.min(h), hi.max(h))
            })
    };
    let head_mesh = trigbody_core::tessellate_part(head, &TessellationOptions::default()).unwrap();
    let (hl, hh) = levels(&head_mesh);
    let mut found = Vec::new();
    let mut linings = Vec::new();
    for c in &body.cavities {
        assert_eq!(c.within, PartName::Head, "{name}");
        let lining = fine(&c.part, body);
        let d = MeshDistance::new(mesh).distances(&lining.positions);
        let s = DistanceStats::of(&d);
        println!(
            "    head cavity: {} sections, lining {:.2} mm RMS, p95 {:.2} mm from the input",
            c.fits.len(),
            1000.0 * s.rms,
            1000.0 * s.p95
        );
        assert!(s.rms < 0.003 && s.p95 < 0.006, "{name}: {s:?}");
        linings.push((s.rms, s.p95));
        let (cl, ch) = levels(&lining);
        assert!(
            cl > hl && ch < hh,
            "{name}: cavity {cl}..{ch}, head {hl}..{hh}"
        );
        let centre =
            lining.positions.iter().fold(Vec3::ZERO, |a, &p| a + p) / lining.positions.len() as f64;
        found.push((lining.surface_area(), centre));
    }
    // The mouth: the largest lining, below both sockets; the sockets apart
    // across the face (left and right of the mouth).
    // The mouth's lining within 2 mm RMS, 4 mm p95 (the sockets' within
    // 3 and 6, above).
    let mouth_at = (0..found.len())
        .max_by(|&a, &b| found[a].0.total_cmp(&found[b].0))
        .unwrap();
    let (rms, p95) = linings[mouth_at];
    assert!(
        rms < 0.002 && p95 < 0.004,
        "{name}: the mouth's lining {rms} {p95}"
    );
    found.sort_by(|a, b| b.0.total_cmp(&a.0));
    let (mouth, eyes) = (found[0].1, [found[1].1, found[2].1]);
    let left = body.frame.left;
    for e in eyes {
        assert!(
            e.dot(up) > mouth.dot(up),
            "{name}: a socket under the mouth"
        );
    }
    let apart = (eyes[0] - eyes[1]).dot(left).abs();
    assert!(apart > 0.03 * body.height, "{name}: sockets {apart} apart");
}

#[test]
fn real_bodies_and_scans_table() {
    let Some(data) = shared_data() else {
        return;
    };
    let opts = ReconstructOptions::default();
    for n in ["mh_male.obj", "mh_base.obj", "mh_female.ply"] {
        let mesh = read_mesh(data.join("bodies").join(n), &ReadOptions::default()).unwrap();
        let (body, r) = reconstruct(BodyGeometry::Mesh(&mesh), &opts).unwrap();
        print_row(n, &r);
        check_parts(n, &body, &r);
        check_mouth(n, &body, &mesh);
        // Measured 1.33-1.48 mm, p95 1.85-1.89, coverage 98.37-99.00 %
        // (outer surface 98.5-99.1 %), 24.2-24.6 % of the polygon
        // parameters.
        assert!(r.distance_mm.rms <= 2.0, "{n}: {:?}", r.distance_mm);
        assert!(r.distance_mm.p95 <= 2.5, "{n}: {:?}", r.distance_mm);
        assert!(r.coverage >= 0.98, "{n}: {}", r.coverage);
        assert!(r.visible_coverage >= 0.98, "{n}: {}", r.visible_coverage);
        assert_eq!(r.unobserved_samples, 0, "{n}");
        assert!(r.parameter_ratio() <= 0.25, "{n}: {}", r.parameter_ratio());
        // No buried pieces: the model's outer skin stays near the input
        // (measured p95 2.0-2.2 mm).
        assert!(
            r.model_to_input_mm.p95 <= 3.0,
            "{n}: {:?}",
            r.model_to_input_mm
        );

        let scan = virtual_scan(&mesh, &ScannerOptions::default())
            .unwrap()
            .cloud;
        let (body, r) = reconstruct(BodyGeometry::Cloud(&scan), &opts).unwrap();
        let label = format!("{n} (virtual scan)");
        print_row(&label, &r);
        check_parts(&label, &body, &r);
        assert!(body.cavities.is_empty(), "{label}: a scan has no cavities");
        // The targets (measured rms 2.00-2.35 mm, p95 3.1-4.0 mm,
        // coverage 98.55-98.87 %).
        assert!(r.distance_mm.rms <= 2.5, "{label}: {:?}", r.distance_mm);
        assert!(r.distance_mm.p95 <= 6.0, "{label}: {:?}", r.distance_mm);
        assert!(r.coverage >= 0.98, "{label}: {}", r.coverage);
        // A scan's holes (soles, crown, crotch) are left out of the shown
        // surface's numbers (measured 1.5-1.7 mm, p95 3.0-3.3 mm); a mesh
        // has none.
        assert!(r.unobserved_samples > 0, "{label}");
        assert!(
            r.visible_rms_mm <= 2.0 && r.visible_p95_mm <= 4.0,
            "{label}: {} {}",
            r.visible_rms_mm,
            r.visible_p95_mm
        );
        assert!(r.visible_rms_mm < r.distance_mm.rms, "{label}");
    }
    let scan =
        read_point_cloud(data.join("scans/mh_male_scan.ply"), &ReadOptions::default()).unwrap();
    let (body, r) = reconstruct(BodyGeometry::Cloud(&scan), &opts).unwrap();
    print_row("mh_male_scan.ply", &r);
    check_parts("mh_male_scan.ply", &body, &r);
    // Measured: rms 2.79 mm (input->model 2.39, model->input 3.14), p95
    // 4.78 mm, coverage 98.20 %.
    assert!(r.input_to_model_mm.rms <= 2.7, "{:?}", r.input_to_model_mm);
    assert!(r.distance_mm.rms <= 3.2, "{:?}", r.distance_mm);
    assert!(r.distance_mm.p95 <= 6.0, "{:?}", r.distance_mm);
    assert!(r.coverage >= 0.98, "{}", r.coverage);
    // Shown surface: rms 2.33, p95 3.40 mm.
    assert!(r.visible_p95_mm <= 4.0, "{}", r.visible_p95_mm);
    assert!(r.visible_rms_mm <= 2.6, "{}", r.visible_rms_mm);
}

/// `p ↦ s R p + t` with `R` a rotation about a skew axis.
fn transform(p: Vec3, s: f64, t: Vec3) -> Vec3 {
    let axis = Vec3::new(1.0, 2.0, 3.0).normalized().unwrap();
    let angle: f64 = 0.7;
    let (sn, cs) = angle.sin_cos();
    let r = p * cs + axis.cross(p) * sn + axis * (axis.dot(p) * (1.0 - cs));
    r * s + t
}

fn surface(body: &Body) -> Mesh {
    body.tessellate(&TessellationOptions {
        target_edge: Some(0.004 * body.height),
        ..TessellationOptions::default()
    })
    .unwrap()
}

#[test]
fn rotated_moved_and_centimetre_bodies_give_the_same_model() {
    let Some(data) = shared_data() else {
        return;
    };
    let mesh = read_mesh(data.join("bodies/mh_male.obj"), &ReadOptions::default()).unwrap();
    let (body, report) =
        reconstruct(BodyGeometry::Mesh(&mesh), &ReconstructOptions::default()).unwrap();
    let reference = surface(&body);
    // The model file reads back into the identical model.
    let model = trigbody_io::body_file::model_of_body(&body);
    let mut bytes = Vec::new();
    trigbody_io::model::write_model(&mut bytes, &model).unwrap();
    let back = trigbody_io::model::read_model(bytes.as_slice()).unwrap();
    assert_eq!(back, model);
    assert_eq!(back.transitions.len(), body.transitions.len());
    assert!(body.transitions.len() >= 2);
    for (scale, shift, units) in [
        (1.0, Vec3::new(3.0, -2.0, 50.0), Units::Metres),
        (100.0, Vec3::new(-120.0, 40.0, 7.0), Units::Centimetres),
    ] {
        let moved = Mesh {
            positions: mesh
                .positions
                .iter()
                .map(|&p| transform(p, scale, shift))
                .collect(),
            normals: None,
            triangles: mesh.triangles.clone(),
        };
        let opts = ReconstructOptions {
            units,
            ..ReconstructOptions::default()
        };
        let (b2, r2) = reconstruct(BodyGeometry::Mesh(&moved), &opts).unwrap();
        assert_eq!(b2.parts.len(), body.parts.len());
        // The reports agree in millimetres.
        assert!(
            (r2.distance_mm.rms - report.distance_mm.rms).abs() < 1e-3,
            "{:?} vs {:?}",
            r2.distance_mm,
            report.distance_mm
        );
        assert!((r2.coverage - report.coverage).abs() < 0.01);
        // The surfaces agree up to the transform: sample the reference
        // model, move the samples, measure to the new model (in mm).
        let other = surface(&b2);
        let md = MeshDistance::new(&other);
        let d: Vec<f64> = sample_surface(&reference, 20_000)
            .iter()
            .map(|&p| md.distance(transform(p, scale, shift)) / scale * 1000.0)
            .collect();
        let s = DistanceStats::of(&d);
        println!(
            "scale {scale}: model vs transformed model rms {:.3} mm p95 {:.3} max {:.2}",
            s.rms, s.p95, s.max
        );
        // The same model moved (a mesh is built in its own frame).
        assert!(s.max < 1e-3, "{s:?}");
    }
}

/// A random proper rotation (a normalized Gaussian quaternion) and a shift.
fn random_motion(rng: &mut Rng, reach: f64) -> Rigid {
    let q: Vec<f64> = (0..4).map(|_| rng.gaussian()).collect();
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let [w, x, y, z] = [q[0] / n, q[1] / n, q[2] / n, q[3] / n];
    let x_axis = Vec3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + z * w),
        2.0 * (x * z - y * w),
    );
    let y_axis = Vec3::new(
        2.0 * (x * y - z * w),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z + x * w),
    );
    let origin = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * reach;
    // `into_axes` takes the axes to x and y; its inverse is the rotation
    // whose columns they are, then the shift.
    Rigid::into_axes(origin, x_axis, y_axis).unwrap().inverse()
}

/// The mesh with its vertices numbered backwards, its triangles in
/// reverse order and each started at its second vertex (the same surface).
fn renumbered(m: &Mesh) -> Mesh {
    let n = m.positions.len() as u32;
    Mesh {
        positions: m.positions.iter().rev().copied().collect(),
        normals: None,
        triangles: m
            .triangles
            .iter()
            .rev()
            .map(|t| [t[1], t[2], t[0]].map(|i| n - 1 - i))
            .collect(),
    }
}

/// Issue 19: a mesh turned and moved (five random rigid motions), in
/// millimetres, or renumbered gives the same model moved: the same design
/// parameters and orders part by part, surfaces that agree to rounding,
/// and the report's distances within 0.5 %. On the repository's body and
/// on a remeshed corpus body in another frame.
#[test]
fn a_mesh_turned_moved_in_mm_or_renumbered_gives_the_same_model() {
    let repo =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mut inputs = vec![(repo, Units::Metres)];
    match shared_data() {
        Some(d) => inputs.push((d.join("corpus/body_002.ply"), Units::Metres)),
        None => eprintln!(
            "NOTE: shared data missing: the invariance test runs on the repository's body only"
        ),
    }
    let mut rng = Rng::new(19);
    for (path, units) in inputs {
        let mesh = read_mesh(&path, &ReadOptions::default()).unwrap();
        let opts = ReconstructOptions {
            units,
            ..ReconstructOptions::default()
        };
        let (body, report) = reconstruct(BodyGeometry::Mesh(&mesh), &opts).unwrap();
        let reference = sample_surface(&surface(&body), 20_000);
        let mut cases: Vec<(String, Mesh, f64, Rigid)> = (0..5)
            .map(|k| {
                let m = random_motion(&mut rng, 50.0);
                (format!("motion {k}"), m.mesh(&mesh), 1.0, m)
            })
            .collect();
        let mm = Mesh {
            positions: mesh.positions.iter().map(|&p| p * 1000.0).collect(),
            ..mesh.clone()
        };
        cases.push(("in mm".into(), mm, 1000.0, Rigid::IDENTITY));
        cases.push(("renumbered".into(), renumbered(&mesh), 1.0, Rigid::IDENTITY));
        for (name, input, scale, motion) in cases {
            let o = ReconstructOptions {
                units: if scale == 1.0 {
                    units
                } else {
                    Units::Millimetres
                },
                ..opts
            };
            let (b2, r2) = reconstruct(BodyGeometry::Mesh(&input), &o).unwrap();
            let what = format!("{}: {name}", path.display());
            assert_eq!(r2.design_parameters, report.design_parameters, "{what}");
            assert_eq!(orders(&b2), orders(&body), "{what}");
            let rel = r2.distance_mm.rms / report.distance_mm.rms - 1.0;
            assert!(
                rel.abs() < 0.005,
                "{what}: rms {} vs {}",
                r2.distance_mm.rms,
                report.distance_mm.rms
            );
            let moved = surface(&b2);
            let md = MeshDistance::new(&moved);
            let worst = reference
                .iter()
                .map(|&p| md.distance(motion.point(p * scale)) / scale)
                .fold(0.0, f64::max);
            println!(
                "{what}: rms {:.4} mm ({:+.2e}), surfaces {worst:.1e} apart",
                r2.distance_mm.rms, rel
            );
            assert!(worst < 1e-6 * body.height, "{what}: surfaces {worst} apart");
        }
    }
}

/// A virtual scan of the repository's body turned and moved anywhere (five
/// random rigid motions), moved by a micrometre, in millimetres or with
/// its points shuffled gives the same model (the same design parameters
/// and orders, surfaces within 1e-8 H (in mm 1e-3 H), the report's
/// distances within 0.5 %): it is built in a frame of its own, from its points in an order
/// of their own, and nothing after that turns on a coordinate's last
/// digits. A micrometre's shift of a corpus scan once took it from 3.8 to
/// 5.7 mm (a cell edged at the slab's lowest point, a tie between two
/// points of a cell, a slice image turned by 90° on an up of
/// `(-2e-15, 1, 3e-15)`).
#[test]
fn a_scan_turned_moved_shifted_in_mm_or_shuffled_gives_the_same_model() {
    let scan = repo_scan(&repo_body());
    let opts = ReconstructOptions::default();
    let (body, report) = reconstruct(BodyGeometry::Cloud(&scan), &opts).unwrap();
    let reference = sample_surface(&surface(&body), 20_000);
    let mut rng = Rng::new(23);
    // The shift by (1, -1, 1) µm: the motion taking its opposite to zero.
    let micrometre = Rigid::into_axes(Vec3::new(-1e-6, 1e-6, -1e-6), Vec3::X, Vec3::Y).unwrap();
    let mut cases: Vec<(String, PointCloud, f64, Rigid)> = (0..5)
        .map(|k| {
            let m = random_motion(&mut rng, 50.0);
            (format!("motion {k}"), m.cloud(&scan), 1.0, m)
        })
        .collect();
    cases.push((
        "a micrometre".into(),
        micrometre.cloud(&scan),
        1.0,
        micrometre,
    ));
    let mm = PointCloud {
        positions: scan.positions.iter().map(|&p| p * 1000.0).collect(),
        normals: scan.normals.clone(),
    };
    cases.push(("in mm".into(), mm, 1000.0, Rigid::IDENTITY));
    // Fisher-Yates with the test's generator, normals alongside.
    let mut order: Vec<usize> = (0..scan.positions.len()).collect();
    for i in (1..order.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        order.swap(i, j);
    }
    let shuffled = PointCloud {
        positions: order.iter().map(|&i| scan.positions[i]).collect(),
        normals: scan
            .normals
            .as_ref()
            .map(|n| order.iter().map(|&i| n[i]).collect()),
    };
    cases.push(("shuffled".into(), shuffled, 1.0, Rigid::IDENTITY));
    for (name, cloud, scale, motion) in cases {
        let o = ReconstructOptions {
            units: if scale == 1.0 {
                opts.units
            } else {
                Units::Millimetres
            },
            ..opts
        };
        let (b2, r2) = reconstruct(BodyGeometry::Cloud(&cloud), &o).unwrap();
        assert_eq!(r2.design_parameters, report.design_parameters, "{name}");
        assert_eq!(orders(&b2), orders(&body), "{name}");
        let rel = r2.distance_mm.rms / report.distance_mm.rms - 1.0;
        let moved = surface(&b2);
        let md = MeshDistance::new(&moved);
        let worst = reference
            .iter()
            .map(|&p| md.distance(motion.point(p * scale)) / scale)
            .fold(0.0, f64::max);
        println!("virtual scan, {name}: rms {rel:+.2e}, surfaces {worst:.1e} apart");
        // In millimetres one arm section already tilts before the fit
        // (below); the fit to the points, started from it, lands 0.58 %
        // away in RMS (measured), the rest within 1e-11.
        let rms_bound = if scale == 1.0 { 0.005 } else { 0.01 };
        assert!(
            rel.abs() < rms_bound,
            "{name}: rms {} vs {}",
            r2.distance_mm.rms,
            report.distance_mm.rms
        );
        // Measured 1e-13 m; 1.7e-6 with a slice image turned by 90° on
        // rounding. In millimetres one section of an arm tilts by half a
        // degree (1.2 mm at worst before the fit; every other section
        // within 1e-15 m); the fit started from it, which holds the skin
        // to the points nearest it, lands up to 2.5 mm apart (measured):
        // the same parameters and distances, not the same bits.
        let bound = if scale == 1.0 { 1e-8 } else { 2e-3 };
        assert!(
            worst < bound * body.height,
            "{name}: surfaces {worst} apart"
        );
    }
}

/// A corpus scan without a floor, moved by half a millimetre or two: a
/// candidate plane's refit turned into a "floor" 0.2 E thick across the
/// raised arms (0.11 E² of area) in three shifts of three, and the legs
/// were lost. A floor must be a thin sheet
/// (`CleanOptions::max_floor_width`): the scan stays floorless and
/// reconstructs with every part, moved or not.
#[test]
fn a_floorless_scan_moved_a_little_stays_floorless() {
    let Some(data) = shared_data() else {
        eprintln!("NOTE: shared data missing: the thick-floor regression is not checked");
        return;
    };
    let path = data.join("corpus/body_001_scan.ply");
    let cloud = read_point_cloud(&path, &ReadOptions::default()).unwrap();
    for d in [
        Vec3::ZERO,
        Vec3::new(0.0005, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.002),
    ] {
        let moved = PointCloud {
            positions: cloud.positions.iter().map(|&p| p + d).collect(),
            normals: None,
        };
        let (_, clean) = clean_cloud(&moved, &CleanOptions::default());
        assert_eq!(clean.floor_normal, None, "moved by {d:?}");
        let (_, r) = reconstruct(BodyGeometry::Cloud(&moved), &ReconstructOptions::default())
            .unwrap_or_else(|e| panic!("moved by {d:?}: {e}"));
        assert_eq!(r.parts_found.len(), 8, "moved by {d:?}");
    }
}

/// Issue 19, density: the built-in body's virtual scan merged with a copy
/// of itself jittered by 0.5, 1 and 1.5 mm is the same surface sampled
/// twice as densely and more noisily. At 1 mm the twins' distances gave a
/// spacing of 2.5 mm where the slab images need about 3.1 and the model
/// was 8-22 mm off or refused; the spacing now has a floor of three times
/// the cloud's noise. Each stays within 0.4 mm RMS of the scan alone.
#[test]
fn a_scan_merged_with_a_jittered_copy_gives_the_same_model() {
    let mesh = repo_body();
    let scan = repo_scan(&mesh);
    let opts = ReconstructOptions::default();
    let (_, alone) = reconstruct(BodyGeometry::Cloud(&scan), &opts).unwrap();
    let mut rng = Rng::new(5);
    for sigma in [0.0005, 0.001, 0.0015] {
        let mut positions = scan.positions.clone();
        positions.extend(
            scan.positions
                .iter()
                .map(|&p| p + Vec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * sigma),
        );
        let merged = PointCloud {
            positions,
            normals: None,
        };
        let (_, r) = reconstruct(BodyGeometry::Cloud(&merged), &opts)
            .unwrap_or_else(|e| panic!("jitter {sigma}: {e}"));
        println!(
            "jitter {sigma}: rms {:.2} mm against {:.2} alone",
            r.distance_mm.rms, alone.distance_mm.rms
        );
        assert_eq!(r.parts_found.len(), 8, "jitter {sigma}");
        assert!(
            r.distance_mm.rms < alone.distance_mm.rms + 0.4,
            "jitter {sigma}: rms {} against {}",
            r.distance_mm.rms,
            alone.distance_mm.rms
        );
    }
}

/// The report measures the model's outer skin (crate `skin`): on the
/// built-in body, the torso's skin inside the arms' transitions (and their
/// ends inside the torso) is left out, a small share of the whole, and no
/// input sample moves farther from the model than that trimming can
/// explain.
#[test]
fn the_report_measures_the_outer_skin() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&path, &ReadOptions::default()).unwrap();
    let opts = ReconstructOptions::default();
    let (body, r) = reconstruct(BodyGeometry::Mesh(&mesh), &opts).unwrap();
    let h = body.height;
    let tess = TessellationOptions {
        target_edge: Some(opts.report_edge * h),
        ..TessellationOptions::default()
    };
    let pieces = body.tessellate_pieces(&tess).unwrap();
    let (surface, ranges) = concatenate(&pieces);
    let tree = MeshDistance::new(&surface);
    // The cavities (the last pieces) are nobody's: on the skin whole.
    let solids = &ranges[..ranges.len() - body.cavities.len()];
    let skin = outer_triangles(&tree, solids, opts.skin_depth * h);
    assert_eq!(skin.unclosed, 0);
    // Less than the pieces' sum (measured 1.7 % less); the report's share
    // is the same.
    let area = surface.surface_area();
    let share = skin.dropped_area / area;
    assert!(share > 0.005 && share < 0.05, "{share}");
    assert!(
        (r.interior_area_share - share).abs() < 1e-9,
        "{}",
        r.interior_area_share
    );
    let skin_mesh = skin.mesh(&surface);
    assert!((skin_mesh.surface_area() - (area - skin.dropped_area)).abs() < 1e-9 * area);
    // Interior triangles are the torso's (its loops reach past the side
    // planes, into the arms' transitions), the arms' transitions' (where
    // they meet the torso at the armpit), the arms' (the palm's flat end
    // among its fingers) and the digits' (their starts inside the palm);
    // the pieces' order: torso, head, arms, legs, then the transitions
    // (legs', then arms'), the digits, then the head's cavities (none
    // dropped).
    let names: Vec<PartName> = body.parts.iter().map(|p| p.name).collect();
    let arms = [PartName::LeftArm, PartName::RightArm];
    let with_digits = |arm: PartName| body.digits.iter().any(|d| d.hand == arm);
    assert_eq!(
        body.digits.len(),
        10,
        "the built-in body's fingers are apart"
    );
    let (n_parts, n_transitions) = (names.len(), body.transitions.len());
    for (k, range) in ranges.iter().enumerate() {
        let dropped = range.clone().filter(|&t| !skin.outer[t]).count();
        let expected = match names.get(k) {
            Some(&name) => name == PartName::Torso || (arms.contains(&name) && with_digits(name)),
            None if k < n_parts + n_transitions => {
                arms.contains(&body.transitions[k - n_parts].from)
            }
            None => k < n_parts + n_transitions + body.digits.len(),
        };
        assert_eq!(dropped > 0, expected, "piece {k}: {dropped}");
    }
    // An input sample outside the model is no farther from the skin than
    // from the whole tessellation by more than a triangle's diameter (the
    // nearest point on a dropped triangle is within a diameter of the
    // other piece's surface): measured at most 0.0015 H, 145 of 60 000
    // samples moved by more than 0.0003 H.
    let diameter = (0..surface.triangles.len())
        .map(|t| {
            let [a, b, c] = surface.triangle(t);
            a.distance(b).max(b.distance(c)).max(c.distance(a))
        })
        .fold(0.0, f64::max);
    let samples = sample_surface(&mesh, opts.report_samples);
    let full = tree.distances(&samples);
    let outer = tree.distances_where(&samples, f64::INFINITY, |_| true, |t| skin.outer[t]);
    let mut moved = 0;
    for (f, o) in full.iter().zip(&outer) {
        assert!(
            o >= f && o - f <= diameter,
            "{f} -> {o} (diameter {diameter})"
        );
        moved += usize::from(o - f > 0.0003 * h);
    }
    assert!(moved < samples.len() / 100, "{moved}");
}

#[test]
fn a_sphere_and_a_cube_are_clear_errors() {
    let sphere = shapes::uv_sphere(Vec3::ZERO, 0.3, 48, 24);
    let e = reconstruct(BodyGeometry::Mesh(&sphere), &ReconstructOptions::default()).unwrap_err();
    assert!(
        matches!(e, ReconstructError::Segment(SegmentError::NoUpAxis { .. })),
        "{e}"
    );
    assert!(e.to_string().contains("up axis"), "{e}");
    // A cube as a cloud of its corners and face points.
    let mut pts = Vec::new();
    for i in 0..20 {
        for j in 0..20 {
            let (u, v) = (i as f64 / 19.0, j as f64 / 19.0);
            for p in [
                Vec3::new(u, v, 0.0),
                Vec3::new(u, v, 1.0),
                Vec3::new(u, 0.0, v),
                Vec3::new(u, 1.0, v),
                Vec3::new(0.0, u, v),
                Vec3::new(1.0, u, v),
            ] {
                pts.push(p);
            }
        }
    }
    let cube = PointCloud::new(pts).unwrap();
    let e = reconstruct(BodyGeometry::Cloud(&cube), &ReconstructOptions::default()).unwrap_err();
    assert!(e.to_string().contains("up axis"), "{e}");
    // A long box with an up axis given is not a body: the error names what
    // was not found.
    let stick = shapes::cylinder(Vec3::ZERO, 0.1, 1.7, 40, 32);
    let mut o = ReconstructOptions::default();
    o.segment.up = Some(Vec3::Z);
    let e = reconstruct(BodyGeometry::Mesh(&stick), &o).unwrap_err();
    assert!(e.to_string().contains("not found"), "{e}");
}

#[test]
fn a_body_lying_down_and_a_scan_without_an_arm() {
    let Some(data) = shared_data() else {
        return;
    };
    let mesh = read_mesh(data.join("bodies/mh_male.obj"), &ReadOptions::default()).unwrap();
    // Lying along x, no up axis given: found lying down (its longest axis
    // is its height), the same body.
    let lying = Mesh {
        positions: mesh
            .positions
            .iter()
            .map(|p| Vec3::new(p.y, -p.x, p.z))
            .collect(),
        normals: None,
        triangles: mesh.triangles.clone(),
    };
    let (b, r) = reconstruct(BodyGeometry::Mesh(&lying), &ReconstructOptions::default()).unwrap();
    assert_eq!(b.parts.len(), 6);
    assert!(b.frame.up.dot(Vec3::X) > 0.99, "{:?}", b.frame.up);
    assert!(r.distance_mm.rms < 4.0, "{:?}", r.distance_mm);
    // A scan with the left arm cut away (points left of the torso above the
    // crotch): a partial model and a warning naming the arm.
    let scan = virtual_scan(&mesh, &ScannerOptions::default())
        .unwrap()
        .cloud;
    let kept: Vec<Vec3> = scan
        .positions
        .iter()
        .copied()
        .filter(|p| !(p.x > 0.19 && p.y > -0.1))
        .collect();
    let cloud = PointCloud::new(kept).unwrap();
    match reconstruct(BodyGeometry::Cloud(&cloud), &ReconstructOptions::default()) {
        Ok((b, r)) => {
            println!(
                "scan without its left arm: {} parts; warnings {:?}",
                b.parts.len(),
                r.warnings
                    .iter()
                    .filter(|w| w.contains("arm"))
                    .collect::<Vec<_>>()
            );
            assert!(b.part(PartName::LeftArm).is_none());
            assert!(
                r.warnings.iter().any(|w| w.contains("left arm")),
                "{:?}",
                r.warnings
            );
        }
        Err(e) => {
            println!("scan without its left arm: {e}");
            assert!(e.to_string().contains("not found"), "{e}")
        }
    }
}

/// A scan that missed the top of the head (the data ends in an open rim 50
/// mm under the crown, as ring scanners leave it) gets a crown estimated
/// from the head's shape, near the true one, with a warning; the whole
/// scan and the mesh get none. The built-in body, always present.
#[test]
fn a_scan_without_its_crown_gets_one_near_the_true_crown() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&path, &ReadOptions::default()).unwrap();
    let crown = mesh.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
    let scan = virtual_scan(&mesh, &ScannerOptions::default())
        .unwrap()
        .cloud;
    let opts = ReconstructOptions::default();
    let unseen = |w: &String| w.contains("crown unseen");
    let top = |body: &Body| {
        let s = surface(body);
        s.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max)
    };
    for (what, input) in [
        ("the mesh", BodyGeometry::Mesh(&mesh)),
        ("the whole scan", BodyGeometry::Cloud(&scan)),
    ] {
        let (body, r) = reconstruct(input, &opts).unwrap();
        assert!(!r.warnings.iter().any(unseen), "{what}: {:?}", r.warnings);
        println!("{what}: top {:+.1} mm", (top(&body) - crown) * 1000.0);
    }
    let topless = PointCloud::new(
        scan.positions
            .iter()
            .copied()
            .filter(|p| p.y < crown - 0.05)
            .collect(),
    )
    .unwrap();
    let (body, r) = reconstruct(BodyGeometry::Cloud(&topless), &opts).unwrap();
    assert!(r.warnings.iter().any(unseen), "{:?}", r.warnings);
    let miss = (top(&body) - crown) * 1000.0;
    println!("the scan without its crown: top {miss:+.1} mm");
    assert!(miss.abs() <= 20.0, "{miss:+.1} mm");
}

/// A scan is reconstructed in `scan_frames` frames and the model nearest
/// its input kept: never farther than the as-given frame alone (the first
/// frame is that reconstruction), returned in the scan's own frame (its
/// surface as near the scan as the report says), and the frames named in a
/// warning. A mesh is reconstructed once. The built-in body, always present.
#[test]
fn a_scan_s_best_frame_is_kept_and_returned_in_the_scan_s_frame() {
    let mesh = repo_body();
    let scan = repo_scan(&mesh);
    let once = ReconstructOptions {
        scan_frames: 1,
        ..ReconstructOptions::default()
    };
    let (single, r1) = reconstruct(BodyGeometry::Cloud(&scan), &once).unwrap();
    let three = ReconstructOptions {
        scan_frames: 3,
        ..ReconstructOptions::default()
    };
    let (best, r3) = reconstruct(BodyGeometry::Cloud(&scan), &three).unwrap();
    println!(
        "one frame {:.2} mm, best of three {:.2} mm",
        r1.distance_mm.rms, r3.distance_mm.rms
    );
    assert!(r3.distance_mm.rms <= r1.distance_mm.rms + 1e-9);
    let frames: Vec<&String> = r3
        .warnings
        .iter()
        .filter(|w| w.contains("3 frames"))
        .collect();
    assert_eq!(frames.len(), 1, "{:?}", r3.warnings);
    assert!(!r1.warnings.iter().any(|w| w.contains("frames")));
    // In the scan's frame: up as found from the scan, and the surface on
    // the scan's points (the report's input -> model RMS, within sampling).
    assert!(
        best.frame.up.dot(single.frame.up) > 0.999,
        "{:?}",
        best.frame.up
    );
    let d = MeshDistance::new(&surface(&best)).distances(&scan.positions);
    let rms = DistanceStats::of(&d).rms * 1000.0;
    assert!(
        (rms - r3.input_to_model_mm.rms).abs() < 0.3,
        "{rms} against {}",
        r3.input_to_model_mm.rms
    );
    // A mesh: once, whatever the option.
    let (_, rm) = reconstruct(BodyGeometry::Mesh(&mesh), &three).unwrap();
    assert!(!rm.warnings.iter().any(|w| w.contains("frames")));
    for bad in [0, trigbody_core::MAX_SCAN_FRAMES + 1] {
        let o = ReconstructOptions {
            scan_frames: bad,
            ..ReconstructOptions::default()
        };
        let e = reconstruct(BodyGeometry::Cloud(&scan), &o).unwrap_err();
        assert!(e.to_string().contains("scan_frames"), "{e}");
    }
}

/// Issue 19, density: the repository's body scanned with 200 000 points
/// and with 2 000 000 gives the same model within noise: distances within
/// 5 %, waist and hip girths within 5 mm, design parameters within 20 %.
/// The denser scan's loops scatter less (each cell's representative is
/// the point nearest its points' mean); without the noise floor on the
/// tolerances the sparser scan's orders chased its scatter (8 627
/// parameters against 5 327).
#[test]
fn a_scan_ten_times_as_dense_gives_the_same_model() {
    let mesh = repo_body();
    let opts = ReconstructOptions::default();
    let mut rows = Vec::new();
    for points in [200_000, 2_000_000] {
        let scan = virtual_scan(
            &mesh,
            &ScannerOptions {
                points,
                ..ScannerOptions::default()
            },
        )
        .unwrap()
        .cloud;
        let (body, report) = reconstruct(BodyGeometry::Cloud(&scan), &opts).unwrap();
        let m = trigbody_core::measure_body(&body, &Default::default()).unwrap();
        let girth = |name: &str| m.get(name).map(|g| g.value).unwrap();
        println!(
            "{points} points: rms {:.2} mm, {} parameters, waist {:.1} mm, hip {:.1} mm",
            report.distance_mm.rms,
            report.design_parameters,
            1e3 * girth("waist"),
            1e3 * girth("hip")
        );
        rows.push((
            report.distance_mm.rms,
            report.design_parameters as f64,
            girth("waist"),
            girth("hip"),
        ));
    }
    let (a, b) = (rows[0], rows[1]);
    assert!((b.0 / a.0 - 1.0).abs() < 0.05, "rms {} vs {}", b.0, a.0);
    assert!(
        (b.1 / a.1 - 1.0).abs() < 0.2,
        "parameters {} vs {}",
        b.1,
        a.1
    );
    assert!((b.2 - a.2).abs() < 0.005, "waist {} vs {}", b.2, a.2);
    assert!((b.3 - a.3).abs() < 0.005, "hip {} vs {}", b.3, a.3);
}

/// The model's outer skin as `reconstruct --mesh M --skin outer` writes it.
fn outer_skin(body: &Body) -> Mesh {
    use trigbody_io::body_file::model_of_body;
    use trigbody_io::model::{merge_pieces, skin_pieces, Skin};
    let model = model_of_body(body);
    let tess = TessellationOptions {
        target_edge: Some(0.004 * body.height),
        ..TessellationOptions::default()
    };
    let pieces = model.tessellate_pieces(&tess).unwrap();
    merge_pieces(&skin_pieces(&model, pieces, Skin::Outer).unwrap())
}

/// The symmetric RMS (metres) of a body's outer skin against the truth,
/// judged as the corpus runner judges a scan: the truth only where
/// within 5 mm of one of `seen`.
fn rms_on_seen_truth(truth: &Mesh, body: &Body, seen: &[Vec3]) -> f64 {
    use trigbody_core::{compare_surfaces_seen, CompareOptions};
    let compare = CompareOptions {
        samples: 60_000,
        near: 0.005,
        far: 0.01,
    };
    compare_surfaces_seen(truth, &outer_skin(body), seen, 0.005, &compare).symmetric_rms
}

/// The fit to the input (docs/global-fit.md) on the repository body's
/// virtual scan, in one frame: the model nearer the body than without it
/// (judged on the truth the scanner saw), no part's residual on the points
/// more than 5 % higher (the skin held to the points trades a little of
/// it: the head 1.68 -> 1.73 mm), and a mesh not fitted by default.
/// Measured: 1.958 -> 1.890 mm (1.761 before the skin was held: its
/// crown, above the band the eyes leave, moves out; the corpus scans come
/// nearer).
#[test]
fn the_fit_brings_a_scan_s_model_nearer_the_body() {
    use trigbody_core::FitMode;
    let mesh = repo_body();
    let scan = repo_scan(&mesh);
    let judged = |mode: FitMode| {
        let mut opts = ReconstructOptions {
            scan_frames: 1,
            ..ReconstructOptions::default()
        };
        opts.global_fit.mode = mode;
        let (body, report) = reconstruct(BodyGeometry::Cloud(&scan), &opts).unwrap();
        (
            rms_on_seen_truth(&mesh, &body, &scan.positions) * 1000.0,
            report,
        )
    };
    let (without, none) = judged(FitMode::Off);
    let (with, fitted) = judged(FitMode::Scans);
    println!("virtual scan of the repository body: {without:.3} mm without the fit, {with:.3} mm with it");
    assert!(none.fit.is_empty());
    assert!(with < 0.97 * without, "{without:.3} -> {with:.3} mm");
    assert!(fitted.fit.len() >= 6, "{:?}", fitted.fit);
    for f in &fitted.fit {
        assert!(f.rms_after_mm <= f.rms_before_mm * 1.05, "{f:?}");
        assert!(f.used > 0 && f.rms_after_mm < 3.0, "{f:?}");
    }
    let (_, mesh_report) =
        reconstruct(BodyGeometry::Mesh(&mesh), &ReconstructOptions::default()).unwrap();
    assert!(mesh_report.fit.is_empty());
}

/// A scan whose forearms are held forward (corpus body_007_scan, the
/// "close" pose): horizontal slices end an arm's branch at the elbow, and
/// in the scan's own frame its left forearm and hand were lost (9.6 mm
/// RMS to the scan, the wrist 14 cm off the rig's). The surface walk
/// follows them on a cloud as on a mesh: in one frame, both wrists within
/// 30 mm of the rig's (measured 9 and 11 mm) and the model 3.9 mm RMS
/// from the scan.
#[test]
fn a_scan_s_forearms_held_forward_reach_the_hands_in_one_frame() {
    use trigbody_core::JointName;
    let Some(data) = shared_data() else {
        eprintln!("NOTE: shared data missing: the forearms held forward are not checked");
        return;
    };
    let corpus = data.join("corpus");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(corpus.join("manifest.json")).unwrap())
            .unwrap();
    let body = manifest["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["name"] == "body_007")
        .unwrap();
    assert_eq!(body["units"], "m");
    let cloud =
        read_point_cloud(corpus.join("body_007_scan.ply"), &ReadOptions::default()).unwrap();
    let opts = ReconstructOptions {
        scan_frames: 1,
        ..ReconstructOptions::default()
    };
    let (_, report) = reconstruct(BodyGeometry::Cloud(&cloud), &opts).unwrap();
    assert!(report.distance_mm.rms < 5.0, "{:?}", report.distance_mm);
    for (joint, name) in [
        (JointName::LeftWrist, "left_wrist"),
        (JointName::RightWrist, "right_wrist"),
    ] {
        let found = report.joints.iter().find(|(j, _)| *j == joint).unwrap().1;
        let rig: Vec<f64> = body["landmarks"][name]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let off = found.distance(Vec3::new(rig[0], rig[1], rig[2]));
        assert!(off < 0.03, "{name} {:.1} mm off", off * 1000.0);
    }
}

/// The cloud one depth camera in front of a body gives (issue 37), made
/// from a corpus body as `scripts/depth_cloud.py` makes it: one point per
/// 5 mm cube of its surface, the skin facing away from the camera (about
/// the back third) dropped, 1 mm of noise and three clumps of strays.
fn depth_cloud(truth: &Mesh, front: Vec3, rng: &mut Rng) -> PointCloud {
    use std::collections::HashSet;
    use trigbody_core::internals::spatial::distance::sample_surface_on_triangles;
    let (points, on, area) = sample_surface_on_triangles(truth, 400_000);
    let spacing = 0.005;
    assert!(points.len() as f64 > 4.0 * area / (spacing * spacing));
    let mut cubes = HashSet::new();
    let mut kept: Vec<Vec3> = Vec::new();
    for (p, &t) in points.iter().zip(&on) {
        let [a, b, c] = truth.triangle(t as usize);
        let Some(n) = (b - a).cross(c - a).normalized() else {
            continue;
        };
        let cube = (*p * (1.0 / spacing)).to_array().map(|x| x.floor() as i64);
        if n.dot(front) > -0.3 && cubes.insert(cube) {
            let noise = Vec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * 0.001;
            kept.push(*p + noise);
        }
    }
    let centre =
        kept.iter().fold(Vec3::new(0.0, 0.0, 0.0), |a, &p| a + p) * (1.0 / kept.len() as f64);
    for place in [
        front * 0.6,
        Vec3::new(0.7, -0.2, 0.0),
        Vec3::new(0.0, 1.2, 0.0),
    ] {
        for _ in 0..150 {
            let noise = Vec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * 0.02;
            kept.push(centre + place + noise);
        }
    }
    PointCloud {
        positions: kept,
        normals: None,
    }
}

/// A depth camera's cloud (no back, 5 mm spacing, strays, no normals) of
/// corpus body_005 is reconstructed, not refused: the trunk is found
/// seen from one side, the loops' unseen sides bridged the way the seen
/// sides head. Judged as the corpus runner judges a scan (model → truth
/// everywhere, truth → model where the camera saw it): measured 7.4 mm
/// RMS (the issue asks 5; the bridged backs bulge at the shoulder
/// blades), 26 mm before the one-sided bridge (its curves dropped as far
/// from the input), and refused on four of eight corpus bodies.
#[test]
fn a_depth_camera_s_cloud_without_a_back_is_reconstructed() {
    let Some(data) = shared_data() else {
        eprintln!("NOTE: shared data missing: the depth camera's cloud is not checked");
        return;
    };
    let corpus = data.join("corpus");
    let truth = read_mesh(corpus.join("body_005.ply"), &ReadOptions::default()).unwrap();
    let mut rng = Rng::new(5);
    let cloud = depth_cloud(&truth, Vec3::new(0.0, 0.0, 1.0), &mut rng);
    assert!(
        (30_000..70_000).contains(&cloud.positions.len()),
        "{}",
        cloud.positions.len()
    );
    let (body, report) = reconstruct(BodyGeometry::Cloud(&cloud), &ReconstructOptions::default())
        .unwrap_or_else(|e| panic!("refused: {e}"));
    assert!(
        report
            .warnings
            .iter()
            .any(|w| w.contains("seen from one side")),
        "{:?}",
        report.warnings
    );
    let rms = rms_on_seen_truth(&truth, &body, &cloud.positions);
    println!(
        "depth camera's cloud of body_005: {:.2} mm RMS",
        rms * 1000.0
    );
    assert!(rms < 0.010, "{:.2} mm", rms * 1000.0);
    // A scanner all round is not taken for one camera.
    let scan = read_point_cloud(corpus.join("body_005_scan.ply"), &ReadOptions::default()).unwrap();
    let (_, all_round) =
        reconstruct(BodyGeometry::Cloud(&scan), &ReconstructOptions::default()).unwrap();
    assert!(!all_round
        .warnings
        .iter()
        .any(|w| w.contains("seen from one side")));
}

/// The closed skin in one solid piece where a limb started short of its
/// parent (corpus meshes). body_027 and body_036 press their arms to the
/// trunk: an arm without a shoulder transition started short of the
/// torso (its upper arm's cuts took in the trunk and were dropped, or its
/// surface walk ended at a bent elbow), and the arm was a solid of its
/// own. body_038's right thumb started beside its palm. One solid shell
/// each (the other shells are the head's cavities, voids), with the
/// warning where a first section was carried back.
#[test]
fn a_limb_that_started_short_of_its_parent_is_joined_to_it() {
    use trigbody_core::internals::surface::closed_skin::{check_closed, closed_skin};
    let Some(data) = shared_data() else {
        eprintln!("NOTE: shared data missing: arms pressed to the trunk are not checked");
        return;
    };
    for (name, units, carried) in [
        ("body_027", Units::Metres, None),
        (
            "body_036",
            Units::Centimetres,
            Some("right arm: its tube started outside the torso"),
        ),
        (
            "body_038",
            Units::Millimetres,
            Some("right arm: digit 1: its tube started outside the hand"),
        ),
    ] {
        let path = data.join("corpus").join(format!("{name}.ply"));
        let mesh = read_mesh(&path, &ReadOptions::default()).unwrap();
        let opts = ReconstructOptions {
            units,
            ..ReconstructOptions::default()
        };
        let (model, report) = reconstruct(BodyGeometry::Mesh(&mesh), &opts).unwrap();
        if let Some(warning) = carried {
            assert!(
                report.warnings.iter().any(|w| w.contains(warning)),
                "{name}: {:?}",
                report.warnings
            );
        }
        let tess = TessellationOptions {
            target_edge: Some(0.004 * model.height),
            ..TessellationOptions::default()
        };
        let pieces = model.tessellate_pieces(&tess).unwrap();
        let (solids, cavities) = pieces.split_at(pieces.len() - model.cavities.len());
        let check = check_closed(&closed_skin(solids, cavities).unwrap());
        let solid_shells = check.shells.iter().filter(|s| s.1 > 0.0).count();
        println!("{name}: {check:?}");
        assert_eq!(solid_shells, 1, "{name}: {check:?}");
        assert_eq!(check.bad_edges, 0, "{name}: {check:?}");
    }
}

/// A scan's fingers held apart are digits: its slab image joins fingers
/// a few point spacings apart, the points past each level do not
/// (`section/cloud/superlevel.rs`). body_005_scan and body_009_scan in
/// one frame: each hand split into four digits or more, and the hands'
/// skin within issue 39's 4 mm RMS of the truth, both ways (the truth
/// where the scanner saw it, within 5 mm of a point; the hands are the
/// truth's own, past its wrists).
#[test]
fn a_scan_s_fingers_apart_are_digits() {
    use trigbody_core::internals::measure::regions::{Region, Regions};
    use trigbody_core::internals::spatial::point_grid::PointGrid;
    use trigbody_core::{segment, SegmentOptions};
    let Some(data) = shared_data() else {
        eprintln!("NOTE: shared data missing: a scan's fingers are not checked");
        return;
    };
    let corpus = data.join("corpus");
    for (name, units, mm) in [
        ("body_005", Units::Metres, 1000.0),
        ("body_009", Units::Millimetres, 1.0),
    ] {
        let read = ReadOptions::default();
        let scan = read_point_cloud(corpus.join(format!("{name}_scan.ply")), &read).unwrap();
        let truth = read_mesh(corpus.join(format!("{name}.ply")), &read).unwrap();
        let opts = ReconstructOptions {
            units,
            scan_frames: 1,
            ..ReconstructOptions::default()
        };
        let (body, report) = reconstruct(BodyGeometry::Cloud(&scan), &opts).unwrap();
        for hand in [PartName::LeftArm, PartName::RightArm] {
            let n = body.digits.iter().filter(|d| d.hand == hand).count();
            assert!(n >= 4, "{name} {hand}: {n} digits; {:?}", report.warnings);
        }
        let regions =
            Regions::new(&segment(BodyGeometry::Mesh(&truth), &SegmentOptions::default()).unwrap());
        let skin = outer_skin(&body);
        // Cells of a quarter of the 5 mm that counts as seen.
        let seen = PointGrid::new(&scan.positions, 1.25 / mm);
        let (to_truth, to_model) = (MeshDistance::new(&truth), MeshDistance::new(&skin));
        let mut squares = Vec::new();
        for (from, onto, seen_only) in [(&skin, &to_truth, false), (&truth, &to_model, true)] {
            for p in sample_surface(from, 200_000) {
                let seen = !seen_only || seen.nearest(p) * mm <= 5.0;
                if seen && regions.of(p) == Region::Hands {
                    let d = onto.closest(p).unwrap().distance * mm;
                    squares.push(d * d);
                }
            }
        }
        let rms = (squares.iter().sum::<f64>() / squares.len() as f64).sqrt();
        println!(
            "{name}: hands {rms:.2} mm RMS both ways over {} samples",
            squares.len()
        );
        assert!(
            squares.len() > 1000,
            "{name}: {} hand samples",
            squares.len()
        );
        assert!(rms <= 4.0, "{name}: hands {rms:.2} mm RMS");
    }
}
