//! How reconstruction fares on bodies it was not developed on: the
//! built-in body re-posed (arms raised toward a T-pose, legs spread) and
//! re-shaped (a shorter, wider body), each as a mesh and as its virtual
//! scan. A crude linear-blend re-posing: arm (leg) vertices turn about the
//! shoulder (hip) with a weight that ramps from 0 at the joint to 1 a fifth
//! of the limb further, so the surface stays connected.
//!
//! `cargo test --release -p trigbody-io --test pose_variants -- --nocapture`
//! prints the table. The issue-5 targets are printed as met or not; the
//! assertions guard what every variant must give (all parts found and
//! built) and each variant's RMS, p95 and coverage a little beyond what
//! was measured, so a regression fails while the open accuracy targets
//! stay visible.

use trigbody_core::internals::segment::PartAxis;
use trigbody_core::{reconstruct, Body, ReconstructOptions, Report};
use trigbody_core::{segment, BodyGeometry, PartName, SegmentOptions, Segmentation};
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_core::{Mesh, Point3, Real, Vec3};
use trigbody_io::{read_mesh, ReadOptions};

/// Closest point parameter (arc-length fraction) and distance of `p` to an
/// axis polyline.
fn on_axis(axis: &PartAxis, p: Point3) -> (Real, Real) {
    let len = axis.length().max(1e-12);
    let (mut best, mut at, mut run) = (Real::INFINITY, 0.0, 0.0);
    for w in axis.points.windows(2) {
        let d = w[1] - w[0];
        let l = d.norm();
        let s = if l > 0.0 {
            ((p - w[0]).dot(d) / (l * l)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dist = (w[0] + d * s).distance(p);
        if dist < best {
            best = dist;
            at = (run + s * l) / len;
        }
        run += l;
    }
    (at, best)
}

/// Rodrigues rotation of `v` about unit `k` by `angle`.
fn rotate(v: Vec3, k: Vec3, angle: Real) -> Vec3 {
    let (s, c) = angle.sin_cos();
    v * c + k.cross(v) * s + k * (k.dot(v) * (1.0 - c))
}

/// Turns the vertices of `limbs` about their first axis point, about
/// `pivot_axis`, by `angle` (signed per limb so that positive lifts the
/// limb away from the body's midline).
fn repose(mesh: &Mesh, limbs: &[PartName], angle: Real) -> Mesh {
    let seg = segment(BodyGeometry::Mesh(mesh), &SegmentOptions::default()).expect("segments");
    let axes: Vec<&PartAxis> = seg.parts.iter().collect();
    let front = seg.frame.front;
    let mut out = mesh.clone();
    for (i, p) in mesh.positions.iter().enumerate() {
        // The part this vertex belongs to: the nearest axis relative to its size.
        let (owner, _) = axes
            .iter()
            .map(|a| {
                let (t, d) = on_axis(a, *p);
                (a.name, t, d / a.max_radius().max(1e-9))
            })
            .min_by(|a, b| a.2.total_cmp(&b.2))
            .map(|(n, t, _)| (n, t))
            .unwrap();
        // A foot turns with its leg.
        let owner = match owner {
            PartName::LeftFoot => PartName::LeftLeg,
            PartName::RightFoot => PartName::RightLeg,
            o => o,
        };
        if !limbs.contains(&owner) {
            continue;
        }
        let (t, _) = on_axis(seg.part(owner).unwrap(), *p);
        let axis = seg.part(owner).unwrap();
        let pivot = axis.points[0];
        let dir = *axis.points.last().unwrap() - pivot;
        // Positive angle: the limb's far end moves away from the midline.
        let side = if dir.dot(seg.frame.left) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        let w = (t / 0.2).clamp(0.0, 1.0);
        let w = w * w * (3.0 - 2.0 * w);
        let k = front * side;
        out.positions[i] = pivot + rotate(*p - pivot, k, angle * w);
    }
    out.normals = None;
    out
}

fn scaled(mesh: &Mesh, up: Vec3, across: Real, along: Real) -> Mesh {
    let mut out = mesh.clone();
    for p in out.positions.iter_mut() {
        let h = p.dot(up);
        let flat = *p - up * h;
        *p = flat * across + up * (h * along);
    }
    out.normals = None;
    out
}

fn row(name: &str, r: &Report) {
    let ok = |b: bool| if b { "met" } else { "NOT met" };
    println!(
        "{name:<30} parts {}/{} | rms {:>5.2} p95 {:>5.2} max {:>6.1} mm | model->in rms {:>5.2} p95 {:>5.2} | coverage {:>6.2} % (shown surface {:>6.2} %, rms {:>5.2}, p95 {:>5.2}) | params {:>5.1} % | targets rms {} p95 {} coverage {}",
        r.parts.len(),
        r.parts_found.len(),
        r.distance_mm.rms,
        r.distance_mm.p95,
        r.distance_mm.max,
        r.model_to_input_mm.rms,
        r.model_to_input_mm.p95,
        100.0 * r.coverage,
        100.0 * r.visible_coverage,
        r.visible_rms_mm,
        r.visible_p95_mm,
        100.0 * r.parameter_ratio(),
        ok(r.distance_mm.rms <= 2.5),
        ok(r.distance_mm.p95 <= 6.0),
        ok(r.coverage >= 0.98),
    );
}

/// Upper bounds on RMS and p95 (mm) and a lower bound on coverage, for one
/// reconstruction.
struct Limits {
    rms: Real,
    p95: Real,
    coverage: Real,
}

fn check(name: &str, body: &Body, r: &Report, lim: &Limits) {
    row(name, r);
    // The built-in body faces +z (only this test knows): a scan whose feet
    // break into heel and toe loops near the floor once turned it round.
    assert!(
        body.frame.front.z > 0.95,
        "{name}: front {:?}",
        body.frame.front
    );
    assert_eq!(r.parts_found.len(), 8, "{name}: {:?}", r.parts_found);
    assert_eq!(body.parts.len(), 6, "{name}: {:?}", r.warnings);
    // A mesh's mouth is the head's cavity and its fingers apart are
    // digits (a scan has neither).
    assert_eq!(
        r.parts.len(),
        6 + body.digits.len() + body.cavities.len(),
        "{name}: {:?}",
        r.warnings
    );
    // Per-variant guards a little beyond what was measured (see the table
    // in docs/reconstruct.md, "Other poses and shapes"): a lost limb, a
    // hand flattened into a paddle (legs-spread mesh, RMS 5.96 mm before)
    // or sideways arms cut at a slant (T-pose scan, p95 24.7 mm before)
    // fails.
    assert!(r.distance_mm.rms < lim.rms, "{name}: {:?}", r.distance_mm);
    assert!(r.distance_mm.p95 < lim.p95, "{name}: {:?}", r.distance_mm);
    assert!(r.coverage > lim.coverage, "{name}: {}", r.coverage);
    assert!(
        r.parameter_ratio() < 0.31,
        "{name}: {}",
        r.parameter_ratio()
    );
    // An arm joins the torso through a side transition, or it has none and
    // the torso reaches into it; a side transition that was tried and left
    // out says so.
    for arm in [PartName::LeftArm, PartName::RightArm] {
        let side = body
            .transitions
            .iter()
            .filter(|t| t.from == arm)
            .map(|t| t.transition.spec().side.is_some())
            .collect::<Vec<_>>();
        assert!(side == [true] || side.is_empty(), "{name}: {arm}: {side:?}");
        let left_out = r
            .warnings
            .iter()
            .any(|w| w.starts_with(&format!("{arm}: the shoulder transition was left out")));
        assert!(!left_out || side.is_empty(), "{name}: {arm}");
    }
}

/// The built-in body and its segmentation.
fn built_in() -> (Mesh, Segmentation) {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&path, &ReadOptions::default()).expect("reads the built-in body");
    let seg = segment(BodyGeometry::Mesh(&mesh), &SegmentOptions::default()).expect("segments");
    (mesh, seg)
}

#[test]
fn re_posed_and_re_shaped_bodies_reconstruct() {
    let (mesh, seg) = built_in();
    let up = seg.frame.up;
    let arms = [PartName::LeftArm, PartName::RightArm];
    let legs = [PartName::LeftLeg, PartName::RightLeg];
    let deg = std::f64::consts::PI / 180.0;
    let lim = |rms, p95, coverage| Limits { rms, p95, coverage };
    // Measured (mesh; scan) on the outer skin: T 3.34 / 3.28 / 96.12 %;
    // 4.81 / 8.81 / 96.09 %. Legs 3.21 / 2.89 / 96.34 %; 3.34 / 6.88 /
    // 97.64 %. Shorter 3.06 / 2.43 / 97.14 %; 3.94 / 8.14 / 97.92 %
    // (the scans with the arms left out of the torso's slabs at the
    // armpits; before: 4.88 / 9.13 / 95.33 %, 3.44 / 7.60 / 97.38 %,
    // 3.99 / 8.43 / 97.46 %).
    // The T pose's mesh p95 and coverage and its scan's coverage are worse
    // than on the whole tessellation (2.77 / 96.52 %; 96.20 %): input
    // samples whose nearest model point lay on skin inside another piece
    // now measure to the outer skin.
    let variants: Vec<(&str, Mesh, Limits, Limits)> = vec![
        (
            "arms raised 45 deg (about T)",
            repose(&mesh, &arms, 45.0 * deg),
            lim(3.8, 3.5, 0.955),
            lim(5.5, 11.0, 0.95),
        ),
        (
            "legs spread 8 deg",
            repose(&mesh, &legs, 8.0 * deg),
            lim(3.7, 3.5, 0.955),
            lim(4.0, 9.0, 0.965),
        ),
        (
            "shorter x0.85, wider x1.1",
            scaled(&mesh, up, 1.1, 0.85),
            lim(3.6, 3.0, 0.96),
            lim(4.3, 10.0, 0.96),
        ),
    ];
    let opts = ReconstructOptions::default();
    for (name, m, mesh_lim, scan_lim) in &variants {
        let (body, r) = reconstruct(BodyGeometry::Mesh(m), &opts).expect(name);
        check(name, &body, &r, mesh_lim);
        let scan = virtual_scan(m, &ScannerOptions::default()).expect("scans");
        let (body, r) = reconstruct(BodyGeometry::Cloud(&scan.cloud), &opts).expect(name);
        check(&format!("{name}, scan"), &body, &r, scan_lim);
        let arm_transitions = body
            .transitions
            .iter()
            .filter(|t| matches!(t.from, PartName::LeftArm | PartName::RightArm))
            .count();
        println!(
            "    arm transitions: {arm_transitions}; {:?}",
            r.warnings
                .iter()
                .filter(|w| w.contains("shoulder"))
                .collect::<Vec<_>>()
        );
        if name.starts_with("legs") {
            // The legs-spread scan's arms' first sections are poor: a side
            // transition straying past its limit is left out (and the torso
            // cut again to reach into the arm), with a warning saying so.
            // Which way it goes turns on the scan's details (it flipped when
            // 4 points near the body were taken for strays, since kept):
            // every arm has one or the other.
            for (arm, part) in [
                ("left arm", PartName::LeftArm),
                ("right arm", PartName::RightArm),
            ] {
                let kept = body.transitions.iter().any(|t| t.from == part);
                let left_out = r.warnings.iter().any(|w| {
                    w.starts_with(&format!("{arm}: the shoulder transition was left out"))
                });
                assert!(
                    kept != left_out,
                    "{name}: {arm}: transition kept {kept}, left out {left_out}: {:?}",
                    r.warnings
                );
            }
        }
    }
}

/// The built-in body with its left arm raised above its head (the hand
/// the body's highest point): the head's top is the head's, not the
/// hand's height, and the model's head ends there.
#[test]
fn a_hand_raised_above_the_head_is_not_the_head_top() {
    let (mesh, seg) = built_in();
    let up = seg.frame.up;
    let head = seg.part(PartName::Head).expect("a head");
    let column = *head.points.last().unwrap();
    let height = |m: &Mesh, reach: Real| {
        m.positions
            .iter()
            .filter(|&&p| {
                let d = p - column;
                (d - up * d.dot(up)).norm() <= reach
            })
            .map(|p| p.dot(up))
            .fold(Real::NEG_INFINITY, Real::max)
    };
    let raised = repose(
        &mesh,
        &[PartName::LeftArm],
        160.0 * std::f64::consts::PI / 180.0,
    );
    let crown = height(&raised, 0.1);
    let top = height(&raised, Real::INFINITY);
    assert!(
        top > crown + 0.05,
        "the hand is above the head: {top} {crown}"
    );
    let seg = segment(BodyGeometry::Mesh(&raised), &SegmentOptions::default()).expect("segments");
    let found = seg
        .landmark(trigbody_core::LandmarkKind::HeadTop)
        .expect("a head top")
        .position
        .dot(up);
    println!("crown {crown:.3}, hand {top:.3}, head top found {found:.3}");
    assert!((found - crown).abs() < 0.01, "{found} against {crown}");
    let (body, _) = reconstruct(BodyGeometry::Mesh(&raised), &ReconstructOptions::default())
        .expect("reconstructs");
    let surface = body.tessellate(&Default::default()).expect("tessellates");
    let model_crown = height(&surface, 0.1);
    println!("model's head top {model_crown:.3}");
    assert!(
        (model_crown - crown).abs() < 0.01,
        "{model_crown} against {crown}"
    );
}
