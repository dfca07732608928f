//! Skinned parts of the project's real bodies against the meshes they were
//! cut from (skipped with a note when `../shared/data` is not there).
//!
//! Only this file knows the bodies' conventions (metres, +y up, facing +z,
//! A-pose); the library code under test does not.
//!
//! For each body, the left leg (just below the crotch down to the ankle) and
//! the torso (crotch to armpits) are cut every 3 cm, each loop is fitted at
//! the default tolerances, and the curves are skinned with every scheme.
//! The surface is compared with the original mesh by a symmetric distance:
//! points of the mesh (its own loops every 5 mm, densified to 2 mm) to the
//! skinned surface, and the skinned surface's vertices (a fine
//! tessellation) to the mesh triangles of the same region (both by the
//! core's `MeshDistance`).
//!
//! `cargo test --release -p trigbody-io --test skinning_real -- --nocapture`
//! prints the variant × K table.

mod common;

use common::shared_data;
use trigbody_core::internals::section::mesh::{MeshSlicer, SectionLoop, SectionOptions};
use trigbody_core::internals::spatial::distance::MeshDistance;
use trigbody_core::{fit_loop, FitOptions};
use trigbody_core::{
    tessellate_part, Mesh, Part, PartOptions, Point3, Skinning, TessellationOptions, TrigCurve,
    Vec3,
};
use trigbody_io::{read_mesh, ReadOptions};

const SPACING: f64 = 0.03;

/// The loop of `loops` containing the horizontal point (x, y, z), else the
/// one whose centroid is nearest to it.
fn pick(loops: &[SectionLoop], p: Point3) -> Option<&SectionLoop> {
    loops.iter().find(|l| l.contains(p)).or_else(|| {
        loops
            .iter()
            .min_by(|a, b| a.centroid.distance(p).total_cmp(&b.centroid.distance(p)))
    })
}

/// Densifies a closed polyline to at most `step` between points.
fn densify(points: &[Point3], step: f64) -> Vec<Point3> {
    let mut out = Vec::new();
    for i in 0..points.len() {
        let (a, b) = (points[i], points[(i + 1) % points.len()]);
        let n = ((a.distance(b) / step).ceil() as usize).max(1);
        for k in 0..n {
            out.push(a + (b - a) * (k as f64 / n as f64));
        }
    }
    out
}

/// One part of one body: its fitted sections and the reference samples.
struct Region {
    curves: Vec<TrigCurve>,
    /// Points of the original surface (dense loops).
    mesh_points: Vec<Point3>,
    /// The original triangles of the region, for surface → mesh distances.
    mesh_region: Mesh,
    orders: Vec<usize>,
}

/// Cuts a part between heights `lo < hi` (sections every 3 cm down from
/// `hi`), following the loop that contains `seed(y)` (or is nearest).
fn region(
    mesh: &Mesh,
    slicer: &MeshSlicer,
    lo: f64,
    hi: f64,
    seed: &dyn Fn(f64) -> Point3,
    fit: &FitOptions,
) -> Region {
    let mut curves = Vec::new();
    let mut orders = Vec::new();
    let n = ((hi - lo) / SPACING).floor() as usize;
    let y0 = hi - n as f64 * SPACING;
    for k in 0..=n {
        let y = y0 + k as f64 * SPACING;
        let sec = slicer.section_at(y).unwrap();
        let l = pick(&sec.loops, seed(y)).unwrap();
        let f = fit_loop(&l.points, fit).unwrap();
        orders.push(f.order);
        curves.push(f.curve);
    }
    // Dense loops every 5 mm over [y0, hi].
    let mut mesh_points = Vec::new();
    let mut dense = Vec::new();
    let steps = ((hi - y0) / 0.005).round() as usize;
    for k in 0..=steps {
        let y = y0 + (hi - y0) * k as f64 / steps as f64;
        let sec = slicer.section_at(y).unwrap();
        let l = pick(&sec.loops, seed(y)).unwrap().clone();
        mesh_points.extend(densify(&l.points, 0.002));
        dense.push(l);
    }
    // The original triangles of the region: within the height range, inside
    // or within 1.5 cm of the part's loop at their height (so no hand or
    // other leg is included).
    let triangles: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .copied()
        .filter(|t| {
            let c = t
                .iter()
                .fold(Vec3::ZERO, |s, &i| s + mesh.positions[i as usize])
                / 3.0;
            if c.y < y0 - 0.01 || c.y > hi + 0.01 {
                return false;
            }
            let k = (((c.y - y0) / (hi - y0)) * steps as f64)
                .round()
                .clamp(0.0, steps as f64) as usize;
            dense[k].contains(c) || dense[k].distance(c) < 0.015
        })
        .collect();
    Region {
        curves,
        mesh_points,
        mesh_region: Mesh {
            positions: mesh.positions.clone(),
            normals: None,
            triangles,
        },
        orders,
    }
}

/// RMS and max (metres) of the symmetric distance between the skinned part
/// and the region's mesh.
fn compare(region: &Region, options: &PartOptions) -> (f64, f64) {
    let part = Part::new(region.curves.clone(), options).unwrap();
    let tess = TessellationOptions {
        around: 256,
        along: 8,
        ..TessellationOptions::default()
    };
    let s = tessellate_part(&part, &tess).unwrap();
    let surface = MeshDistance::new(&s);
    let original = MeshDistance::new(&region.mesh_region);
    let (mut sum, mut count, mut max) = (0.0, 0usize, 0.0f64);
    for &p in &region.mesh_points {
        let d = surface.distance(p);
        sum += d * d;
        max = max.max(d);
        count += 1;
    }
    for &p in &s.positions {
        let d = original.distance(p);
        sum += d * d;
        max = max.max(d);
        count += 1;
    }
    ((sum / count as f64).sqrt(), max)
}

/// Levels of one A-pose body: (ankle, crotch, armpit) heights, and the
/// left leg's seed point as a function of height.
fn levels(slicer: &MeshSlicer) -> (f64, f64, f64) {
    let (lo, hi) = slicer.range();
    let h = hi - lo;
    // Crotch: the lowest height (from 0.35 H up) where one loop contains the
    // body's mid-line (x = 0) at the torso's depth.
    let mid = |y: f64| {
        let sec = slicer.section_at(y).unwrap();
        let z = sec
            .loops
            .iter()
            .max_by(|a, b| a.area.total_cmp(&b.area))
            .map_or(0.0, |l| l.centroid.z);
        sec.loops.iter().any(|l| l.contains(Vec3::new(0.0, y, z)))
    };
    let mut crotch = lo + 0.35 * h;
    while !mid(crotch) {
        crotch += 0.002;
    }
    // Armpit: from the waist up, the torso loop (on the mid-line) is
    // separate from the arms until the cut meets the armpit, where the
    // count of loops drops.
    let count = |y: f64| slicer.section_at(y).unwrap().loops.len();
    let mut armpit = lo + 0.66 * h;
    while count(armpit) >= 3 {
        armpit += 0.002;
    }
    // Ankle: the thinnest left-leg loop between 0.03 H and 0.10 H.
    let mut ankle = (f64::INFINITY, lo + 0.05 * h);
    let mut y = lo + 0.03 * h;
    while y < lo + 0.10 * h {
        let sec = slicer.section_at(y).unwrap();
        if let Some(l) = sec
            .loops
            .iter()
            .filter(|l| l.centroid.x > 0.0)
            .min_by(|a, b| a.centroid.x.total_cmp(&b.centroid.x))
        {
            if l.perimeter < ankle.0 {
                ankle = (l.perimeter, y);
            }
        }
        y += 0.002;
    }
    (ankle.1, crotch, armpit)
}

fn variants() -> Vec<(String, PartOptions)> {
    let mut v = vec![
        ("catmull-rom".to_string(), PartOptions::default()),
        (
            "natural-spline".to_string(),
            PartOptions {
                skinning: Skinning::NaturalSpline,
                ..PartOptions::default()
            },
        ),
    ];
    for k in [3, 4, 5] {
        for (name, skinning) in [
            ("paper-chained", Skinning::PaperChained),
            ("paper-unchained", Skinning::PaperUnchained),
        ] {
            v.push((
                format!("{name} K={k}"),
                PartOptions {
                    skinning,
                    curves_per_patch: k,
                    ..PartOptions::default()
                },
            ));
        }
    }
    v
}

/// Runs the measurement for `variants` and returns the printed table;
/// asserts the targets for the default options.
fn measure(variants: &[(String, PartOptions)]) -> String {
    let Some(data) = shared_data() else {
        return String::new();
    };
    let fit = FitOptions {
        reference: Some(Vec3::Z),
        normal: Some(Vec3::Y),
        ..FitOptions::default()
    };
    let fine_fit = FitOptions { ea: 0.005, ..fit };
    let mut table = String::new();
    for name in ["mh_base.obj", "mh_male.obj", "mh_female.ply"] {
        let mesh = read_mesh(data.join("bodies").join(name), &ReadOptions::default()).unwrap();
        let slicer = MeshSlicer::new(&mesh, Vec3::Y, &SectionOptions::default()).unwrap();
        let (ankle, crotch, armpit) = levels(&slicer);
        // The left leg (the body's left is +x when it faces +z): follow the
        // loop nearest to the previous centroid, from the ankle up.
        let ankle_sec = slicer.section_at(ankle).unwrap();
        let start = ankle_sec
            .loops
            .iter()
            .filter(|l| l.centroid.x > 0.0)
            .min_by(|a, b| a.centroid.x.total_cmp(&b.centroid.x))
            .unwrap()
            .centroid;
        let leg_top = crotch - 0.02;
        let leg_axis = {
            let top = pick(
                &slicer.section_at(leg_top).unwrap().loops,
                Vec3::new(start.x + 0.03, leg_top, start.z),
            )
            .unwrap()
            .centroid;
            move |y: f64| start + (top - start) * ((y - ankle) / (leg_top - ankle))
        };
        let torso_z = slicer
            .section_at(0.5 * (crotch + armpit))
            .unwrap()
            .loops
            .iter()
            .max_by(|a, b| a.area.total_cmp(&b.area))
            .unwrap()
            .centroid
            .z;
        let torso_seed = move |y: f64| Vec3::new(0.0, y, torso_z);
        let regions = [
            (
                "leg",
                region(&mesh, &slicer, ankle, leg_top, &leg_axis, &fit),
                0.0007,
                0.005,
            ),
            (
                "torso",
                region(
                    &mesh,
                    &slicer,
                    crotch + 0.01,
                    armpit - 0.01,
                    &torso_seed,
                    &fit,
                ),
                0.0012,
                0.009,
            ),
            (
                "torso Ea≤0.5%",
                region(
                    &mesh,
                    &slicer,
                    crotch + 0.01,
                    armpit - 0.01,
                    &torso_seed,
                    &fine_fit,
                ),
                0.0012,
                0.009,
            ),
        ];
        for (part, r, rms_target, max_target) in &regions {
            table += &format!(
                "{name} {part}: {} sections, orders {:?}\n",
                r.curves.len(),
                r.orders
            );
            for (variant, options) in variants {
                let (rms, max) = compare(r, options);
                table += &format!(
                    "  {variant:22} RMS {:.3} mm  max {:.2} mm\n",
                    rms * 1e3,
                    max * 1e3
                );
                if *options == PartOptions::default() {
                    assert!(rms < *rms_target, "{name} {part}: RMS {rms} m");
                    assert!(max < *max_target, "{name} {part}: max {max} m");
                }
            }
        }
    }
    table
}

/// Every scheme and patch size on every body (the table of the report,
/// printed with `--nocapture`); the default (Catmull-Rom) must meet the
/// targets: leg RMS ≤ 0.7 mm, max ≤ 5 mm; torso RMS ≤ 1.2 mm, max ≤ 9 mm.
/// `cargo test --release -p trigbody-io --test skinning_real -- --nocapture`
#[test]
fn skinned_leg_and_torso_follow_the_body_for_every_scheme() {
    let table = measure(&variants());
    println!("{table}");
}
