//! Sections of the project's real bodies and scans (from `../shared/data`;
//! skipped with a note when that folder is not beside the repository).
//!
//! Only these tests know the bodies' conventions (metres, +y up, facing
//! +z); the library code under test does not.
//!
//! Run with `--nocapture` to see the loop-count and scan-versus-mesh tables.

mod common;

use common::shared_data;
use trigbody_core::internals::section::cloud::{CloudSlicer, ScanSectionOptions};
use trigbody_core::internals::section::mesh::{MeshSlicer, SectionLoop, SectionOptions};
use trigbody_core::{fit_loop, FitOptions, OrderChoice};
use trigbody_core::{virtual_scan, ScannerOptions};
use trigbody_core::{Mesh, Point3, PointCloud, Vec2, Vec3};
use trigbody_io::{read_mesh, read_point_cloud, ReadOptions};

fn bodies() -> Vec<(String, Mesh)> {
    let Some(data) = shared_data() else {
        return Vec::new();
    };
    ["mh_base.obj", "mh_male.obj", "mh_female.ply"]
        .iter()
        .map(|n| {
            let m = read_mesh(data.join("bodies").join(n), &ReadOptions::default()).unwrap();
            (n.to_string(), m)
        })
        .collect()
}

/// Named levels as fractions of the height above the soles, and the loops
/// a horizontal cut there meets on these A-pose bodies (checked by eye on
/// the full 2 cm tables the first test prints).
const LEVELS: [(&str, f64, usize); 8] = [
    ("calf", 0.20, 2),
    ("knee", 0.28, 2),
    ("thigh", 0.40, 2),
    ("hip", 0.51, 1),   // torso only: the hands hang lower (0.53-0.59)
    ("waist", 0.62, 3), // torso and both forearms
    ("chest", 0.72, 3), // torso and both upper arms
    ("neck", 0.85, 1),
    ("head", 0.96, 1),
];

fn plane_points(l: &SectionLoop) -> Vec<Vec2> {
    l.points
        .iter()
        .map(|&p| Vec2::new(p.dot(l.frame.e1), p.dot(l.frame.e2)))
        .collect()
}

fn signed_area(p: &[Vec2]) -> f64 {
    0.5 * (0..p.len())
        .map(|k| p[k].cross(p[(k + 1) % p.len()]))
        .sum::<f64>()
}

/// True when two non-adjacent edges of the closed polygon cross.
fn self_intersects(p: &[Vec2]) -> bool {
    let n = p.len();
    let orient = |a: Vec2, b: Vec2, c: Vec2| (b - a).cross(c - a);
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        for j in i + 2..n {
            if (j + 1) % n == i {
                continue;
            }
            let (c, d) = (p[j], p[(j + 1) % n]);
            let (o1, o2) = (orient(a, b, c), orient(a, b, d));
            let (o3, o4) = (orient(c, d, a), orient(c, d, b));
            if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
                return true;
            }
        }
    }
    false
}

#[test]
fn horizontal_sections_every_2cm_are_closed_ordered_ccw() {
    for (name, m) in bodies() {
        let s = MeshSlicer::new(&m, Vec3::Y, &SectionOptions::default()).unwrap();
        let (lo, hi) = s.range();
        let height = hi - lo;
        let mut table = String::new();
        let mut k = 0;
        while lo + 0.01 + 0.02 * k as f64 <= hi {
            let y = lo + 0.01 + 0.02 * k as f64;
            let sec = s.section_at(y).unwrap();
            assert!(sec.open_chains.is_empty(), "{name} y={y}: open chains");
            assert!(!sec.loops.is_empty(), "{name} y={y}: no loop");
            for l in &sec.loops {
                assert!(l.frame.e1.cross(l.frame.e2).dot(Vec3::Y) > 0.999_999);
                let p = plane_points(l);
                assert!(signed_area(&p) > 0.0, "{name} y={y}: clockwise loop");
                assert!((signed_area(&p) - l.area).abs() < 1e-9);
                // The female mesh folds on itself by a fraction of a
                // millimetre at the sole (1 cm up): the section faithfully
                // crosses there. Everywhere above the feet loops are simple.
                if self_intersects(&p) {
                    println!(
                        "  {name}: a loop crosses itself at {:.3} H",
                        (y - lo) / height
                    );
                    assert!(
                        (y - lo) / height < 0.03,
                        "{name} y={y}: loop crosses itself"
                    );
                }
                for i in 0..l.points.len() {
                    let d = l.points[i].distance(l.points[(i + 1) % l.points.len()]);
                    assert!(d < 0.05, "{name} y={y}: a {d} m jump in a loop");
                    assert!((l.points[i].y - y).abs() < 1e-9);
                }
            }
            table += &format!("{:.2}:{} ", (y - lo) / height, sec.loops.len());
            k += 1;
        }
        println!("{name} (fraction of height: loops)\n  {table}");
        for (level, f, expected) in LEVELS {
            let sec = s.section_at(lo + f * height).unwrap();
            println!("  {name} {level} ({f} H): {} loops", sec.loops.len());
            assert_eq!(sec.loops.len(), expected, "{name} at the {level}");
        }
    }
}

/// Symmetric RMS of nearest-point distances between two closed polylines.
fn curve_rms(a: &[Point3], b: &[Point3]) -> f64 {
    let d = |p: Point3, poly: &[Point3]| {
        (0..poly.len())
            .map(|i| {
                let (s, e) = (poly[i], poly[(i + 1) % poly.len()]);
                let ab = e - s;
                let t = ((p - s).dot(ab) / ab.norm_squared()).clamp(0.0, 1.0);
                (s + ab * t).distance(p)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let sum: f64 = a.iter().map(|&p| d(p, b).powi(2)).sum::<f64>()
        + b.iter().map(|&p| d(p, a).powi(2)).sum::<f64>();
    (sum / (a.len() + b.len()) as f64).sqrt()
}

/// Fits the mesh loop (automatic order) and the scan loop at the same order
/// (plain least squares: at a known order the smoothness penalty only costs
/// accuracy, see `quarter_loop_holes_are_bridged_by_the_fit` for where it
/// is needed), and returns the RMS distance between the two curves (1000
/// samples each) with the order.
fn fitted_rms(mesh_loop: &[Point3], scan_loop: &[Point3]) -> (f64, usize) {
    let base = FitOptions {
        reference: Some(Vec3::Z),
        normal: Some(Vec3::Y),
        ..Default::default()
    };
    let mf = fit_loop(mesh_loop, &base).unwrap();
    let fixed = FitOptions {
        order: OrderChoice::Fixed(mf.order),
        ..base
    };
    let sf = fit_loop(scan_loop, &fixed).unwrap();
    (
        curve_rms(&mf.curve.sample(1000), &sf.curve.sample(1000)),
        mf.order,
    )
}

fn scan_versus_mesh(name: &str, m: &Mesh, cloud: &PointCloud) {
    let ms = MeshSlicer::new(m, Vec3::Y, &SectionOptions::default()).unwrap();
    let cs = CloudSlicer::new(cloud, Vec3::Y).unwrap();
    let (lo, hi) = ms.range();
    println!("{name}: spacing {:.1} mm", cs.spacing() * 1e3);
    for (level, f, expected) in LEVELS.iter().take(6) {
        let y = lo + f * (hi - lo);
        let sec = ms.section_at(y).unwrap();
        let scan = cs.section_at(y, &ScanSectionOptions::default()).unwrap();
        assert_eq!(
            scan.loops.len(),
            *expected,
            "{name}: scan loops at the {level}"
        );
        let largest = sec.loops.iter().map(|l| l.area).fold(0.0, f64::max);
        for l in &sec.loops {
            let i = scan.select(l.centroid).unwrap();
            let sl = &scan.loops[i];
            assert!(sl.outline.contains(l.centroid) || sl.outline.distance(l.centroid) < 0.02);
            let (rms, order) = fitted_rms(&l.points, &sl.outline.points);
            // Every loop, the forearms cut obliquely at the waist included.
            let is_arm = *expected == 3 && l.area < largest;
            let bound = 0.002;
            println!(
                "  {level:5} {:5} J={order:2} rms {:.2} mm  (widest gap {:.0} mm, {} points, ring {})",
                if is_arm { "arm" } else { "main" },
                rms * 1e3,
                sl.max_gap * 1e3,
                sl.outline.points.len(),
                if sl.closed_ring { "closed" } else { "open" },
            );
            assert!(
                rms < bound,
                "{name} {level}: scan and mesh curves differ by {rms} m RMS"
            );
        }
    }
}

#[test]
fn virtual_scans_match_mesh_sections() {
    for (name, m) in bodies() {
        let scan = virtual_scan(&m, &ScannerOptions::default()).unwrap();
        assert_eq!(scan.cloud.positions.len(), 200_000);
        assert!(scan.up.y.abs() > 0.99, "{name}: up axis {:?}", scan.up);
        println!(
            "{name}: virtual scan sees {:.1} % of the surface",
            scan.seen_fraction * 100.0
        );
        assert!(scan.seen_fraction > 0.9 && scan.seen_fraction < 0.99);
        scan_versus_mesh(&name, &m, &scan.cloud);
    }
}

#[test]
fn external_scan_matches_mesh_sections() {
    let Some(data) = shared_data() else { return };
    let m = read_mesh(data.join("bodies/mh_male.obj"), &ReadOptions::default()).unwrap();
    let cloud =
        read_point_cloud(data.join("scans/mh_male_scan.ply"), &ReadOptions::default()).unwrap();
    scan_versus_mesh("mh_male_scan.ply (external)", &m, &cloud);
}

/// A scanner hole covering a quarter of a loop: the points of the virtual
/// scan in a 90° wedge around one thigh (and one calf) are removed. The
/// slab loop is ordered across the gap and the fit bridges it; the
/// smoothness penalty keeps the bridge close to the true section.
#[test]
fn quarter_loop_holes_are_bridged_by_the_fit() {
    let Some((name, m)) = bodies().into_iter().nth(1) else {
        return;
    };
    let scan = virtual_scan(&m, &ScannerOptions::default()).unwrap();
    let ms = MeshSlicer::new(&m, Vec3::Y, &SectionOptions::default()).unwrap();
    let (lo, hi) = ms.range();
    for (level, f) in [("thigh", 0.40), ("calf", 0.20)] {
        let y = lo + f * (hi - lo);
        let sec = ms.section_at(y).unwrap();
        for l in &sec.loops {
            let c = l.centroid;
            for start in [0.0f64, 90.0, 180.0, 270.0] {
                let (a0, a1) = (start.to_radians(), (start + 90.0).to_radians());
                let keep: Vec<usize> = (0..scan.cloud.positions.len())
                    .filter(|&i| {
                        let p = scan.cloud.positions[i];
                        let d = p - c;
                        let a = d.x.atan2(d.z).rem_euclid(std::f64::consts::TAU);
                        !((p.y - y).abs() < 0.05 && d.x.hypot(d.z) < 0.15 && a >= a0 && a < a1)
                    })
                    .collect();
                let holed = PointCloud {
                    positions: keep.iter().map(|&i| scan.cloud.positions[i]).collect(),
                    normals: scan
                        .cloud
                        .normals
                        .as_ref()
                        .map(|n| keep.iter().map(|&i| n[i]).collect()),
                };
                let cs = CloudSlicer::new(&holed, Vec3::Y).unwrap();
                let s = cs.section_at(y, &ScanSectionOptions::default()).unwrap();
                let i = s.select(c).unwrap();
                let sl = &s.loops[i];
                let base = FitOptions {
                    reference: Some(Vec3::Z),
                    normal: Some(Vec3::Y),
                    ..Default::default()
                };
                let mf = fit_loop(&l.points, &base).unwrap();
                let mesh_curve = mf.curve.sample(1000);
                let mut line = format!(
                    "  {name} {level} hole {start:>3}°-{:>3}°: gap {:.0} mm; rms (mm)",
                    start + 90.0,
                    sl.max_gap * 1e3
                );
                let default = trigbody_core::internals::section::cloud::DEFAULT_SCAN_SMOOTHING;
                let mut results = Vec::new();
                for (order, label) in [
                    (OrderChoice::Fixed(mf.order), "mesh's J"),
                    (OrderChoice::Auto, "auto J"),
                ] {
                    for smoothing in [0.0, default, 1e-4] {
                        let o = FitOptions {
                            order,
                            smoothing,
                            ..base
                        };
                        let sf = fit_loop(&sl.outline.points, &o).unwrap();
                        let rms = curve_rms(&mesh_curve, &sf.curve.sample(1000));
                        line += &format!(" {label} λ={smoothing:e}: {:.2}", rms * 1e3);
                        results.push(rms);
                    }
                }
                println!("{line}");
                assert!(sl.max_gap > 0.03, "the hole should show as a gap");
                // at the mesh's order with the default smoothing, and at the
                // automatic order with λ = 1e-4 (without smoothing the
                // automatic order can run away across the hole)
                assert!(
                    results[1] < 0.005,
                    "{level}: bridged curve {} m RMS from the mesh's",
                    results[1]
                );
                assert!(
                    results[5] < 0.004,
                    "{level}: auto-order bridged curve {} m RMS",
                    results[5]
                );
            }
        }
    }
}

/// The virtual scanner's holes are where a real scanner's are: nothing on
/// the flat of the soles or the top of the head (seen only at grazing
/// angles from the horizontal cameras), little of the downward-facing
/// crotch, while the front of the chest is densely covered.
#[test]
fn virtual_scan_holes_are_where_real_scanners_have_them() {
    for (name, m) in bodies() {
        let scan = virtual_scan(&m, &ScannerOptions::default()).unwrap();
        let b = m.bounds().unwrap();
        let h = b.size().y;
        let normals = scan.cloud.normals.as_ref().unwrap();
        let pts = &scan.cloud.positions;
        let count = |f: &dyn Fn(&Point3, &Vec3) -> bool| {
            pts.iter().zip(normals).filter(|(p, n)| f(p, n)).count()
        };
        let soles = count(&|p, n| p.y < b.min.y + 0.01 && n.y < -0.95);
        let crown = count(&|p, n| p.y > b.max.y - 0.01 && n.y > 0.95);
        // the crotch: downward-facing surface between the legs
        let crotch = count(&|p, n| {
            p.x.abs() < 0.03 && (p.y - (b.min.y + 0.47 * h)).abs() < 0.05 && n.y < -0.95
        });
        // the same area of upward/forward chest for comparison
        let chest = count(&|p, n| {
            p.x.abs() < 0.03 && (p.y - (b.min.y + 0.72 * h)).abs() < 0.05 && n.z > 0.7
        });
        println!("  {name}: points on soles {soles}, crown {crown}, crotch {crotch}; chest front {chest}");
        assert_eq!(soles, 0, "{name}");
        assert!(crown < 20, "{name}: {crown} points on the crown");
        assert!(crotch * 3 < chest, "{name}: crotch {crotch}, chest {chest}");
    }
}
