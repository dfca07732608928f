//! Tests of [`segment`](super::segment) on shapes that are no body, and of
//! the sort it hands the cutter.

use super::*;
use crate::geom::math::{Point2, Vec2};
use crate::geom::mesh::{Mesh, PointCloud};
use crate::geom::shapes;
use crate::section::cloud::{height_key, CloudSlicer};
use crate::section::girth::{convex_hull, from_height_key, monotone_chain};

/// The slicing's sort handed to the cutter along `up = ±axis`: heights
/// ascending and equal to `p·up` for the points in that order, each
/// point once; nothing for another `up`.
#[test]
fn sorted_up_follows_the_axis_either_way() {
    let mut rng = crate::geom::rng::Rng::new(5);
    let points: Vec<Point3> = (0..3000)
        .map(|k| {
            // Repeated heights (ties) among random ones.
            let y = if k % 3 == 0 {
                (k % 7) as Real * 0.1
            } else {
                rng.uniform() - 0.5
            };
            Vec3::new(rng.uniform(), y, rng.uniform())
        })
        .collect();
    let cloud = PointCloud {
        positions: points.clone(),
        normals: None,
    };
    let slicer = || CloudSlicer::new(&cloud, Vec3::new(0.1, 1.0, -0.2)).unwrap();
    let axis = slicer().axis();
    for up in [axis, -axis] {
        let got = SortedUp::along(Some((axis, slicer().into_sorted())), up);
        let (order, heights) = got.0.as_deref().expect("a sort for ±axis");
        assert!(heights.windows(2).all(|w| w[0] <= w[1]));
        for (&i, &h) in order.iter().zip(heights) {
            assert_eq!(points[i as usize].dot(up), h);
        }
        let mut seen = order.clone();
        seen.sort_unstable();
        assert!(seen.iter().enumerate().all(|(k, &i)| k as u32 == i));
    }
    let nearly = Vec3::new(axis.x, axis.y, f64::from_bits(axis.z.to_bits() + 1));
    for up in [Vec3::X, nearly] {
        assert!(SortedUp::along(Some((axis, slicer().into_sorted())), up)
            .0
            .is_none());
    }
}

/// The hull from integer keys is the hull of the comparator sort it
/// replaced, point for point and bit for bit (duplicates, signed
/// zeros, collinear and grid points included); the keys decode to the
/// same bits.
#[test]
fn keyed_hull_is_the_comparator_hull() {
    // The comparator sort the keys replaced, then the same chain.
    let reference = |p: &[Point2]| {
        let mut pts: Vec<Point2> = p.to_vec();
        pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        monotone_chain(pts)
    };
    let bits = |h: &[Point2]| -> Vec<[u64; 2]> {
        h.iter().map(|p| [p.x.to_bits(), p.y.to_bits()]).collect()
    };
    let mut rng = crate::geom::rng::Rng::new(11);
    for case in 0..200 {
        let n = 1 + case % 60;
        let mut pts: Vec<Point2> = (0..n)
            .map(|_| match case % 4 {
                // On a coarse grid: many duplicates and collinear runs.
                0 => Vec2::new(
                    (4.0 * rng.uniform()).floor() - 2.0,
                    (3.0 * rng.uniform()).floor() - 1.0,
                ),
                1 => Vec2::new(rng.uniform() - 0.5, 0.0),
                _ => Vec2::new(rng.gaussian(), 0.3 * rng.gaussian()),
            })
            .collect();
        if case % 5 == 0 {
            pts.push(Vec2::new(-0.0, 0.0));
            pts.push(Vec2::new(0.0, -0.0));
        }
        assert_eq!(
            bits(&convex_hull(&pts)),
            bits(&reference(&pts)),
            "case {case}"
        );
    }
    for x in [
        0.0,
        -0.0,
        1.5,
        -1.5,
        1e-300,
        -1e300,
        Real::INFINITY,
        Real::MIN,
    ] {
        assert_eq!(from_height_key(height_key(x)).to_bits(), x.to_bits());
    }
}

fn cube(size: Real) -> Mesh {
    shapes::cuboid(Vec3::ZERO, Vec3::new(size, size, size))
}

fn not_standing(err: SegmentError) -> (&'static str, String) {
    match err {
        SegmentError::NotAStandingBody { what, why } => (what, why),
        e => panic!("expected NotAStandingBody, got {e}"),
    }
}

#[test]
fn sphere_has_no_up_axis() {
    let ball = shapes::uv_sphere(Vec3::new(3.0, -2.0, 1.0), 0.5, 48, 96);
    let err = segment(BodyGeometry::Mesh(&ball), &SegmentOptions::default()).unwrap_err();
    assert!(matches!(err, SegmentError::NoUpAxis { .. }), "{err}");
    assert!(err.to_string().contains("pass the up axis"));
}

#[test]
fn sphere_with_up_has_no_legs() {
    let ball = shapes::uv_sphere(Vec3::ZERO, 0.5, 48, 96);
    let opts = SegmentOptions {
        up: Some(Vec3::Z),
        ..Default::default()
    };
    let (what, why) = not_standing(segment(BodyGeometry::Mesh(&ball), &opts).unwrap_err());
    assert_eq!(what, "two legs");
    assert!(why.contains("never split into two feet"), "{why}");
}

#[test]
fn cube_is_rejected_with_or_without_up() {
    let c = cube(2.0);
    let err = segment(BodyGeometry::Mesh(&c), &SegmentOptions::default()).unwrap_err();
    assert!(matches!(err, SegmentError::NoUpAxis { .. }), "{err}");
    let opts = SegmentOptions {
        up: Some(Vec3::new(0.0, 0.0, -1.0)),
        ..Default::default()
    };
    let (what, _) = not_standing(segment(BodyGeometry::Mesh(&c), &opts).unwrap_err());
    assert_eq!(what, "two legs");
}

#[test]
fn cube_cloud_is_rejected() {
    let c = PointCloud::from(cube(1.0));
    let err = segment(BodyGeometry::Cloud(&c), &SegmentOptions::default()).unwrap_err();
    assert!(matches!(err, SegmentError::NoUpAxis { .. }), "{err}");
}

#[test]
fn long_cylinder_has_no_feet() {
    let rod = shapes::cylinder(Vec3::ZERO, 0.1, 2.0, 40, 48);
    let (what, why) =
        not_standing(segment(BodyGeometry::Mesh(&rod), &SegmentOptions::default()).unwrap_err());
    assert_eq!(what, "two feet at either end of the longest axis");
    assert!(why.contains("0 %"), "{why}");
}

#[test]
fn empty_and_bad_options_are_errors() {
    let empty = PointCloud::default();
    assert!(matches!(
        segment(BodyGeometry::Cloud(&empty), &SegmentOptions::default()),
        Err(SegmentError::Input(_))
    ));
    let mut nan = PointCloud::from(cube(1.0));
    nan.positions[3].y = Real::NAN;
    assert!(matches!(
        segment(BodyGeometry::Cloud(&nan), &SegmentOptions::default()),
        Err(SegmentError::Input(_))
    ));
    let ball = shapes::uv_sphere(Vec3::ZERO, 0.5, 8, 16);
    for opts in [
        SegmentOptions {
            slices: 3,
            ..Default::default()
        },
        SegmentOptions {
            min_loop_area: Real::NAN,
            ..Default::default()
        },
        SegmentOptions {
            up: Some(Vec3::ZERO),
            ..Default::default()
        },
    ] {
        assert!(matches!(
            segment(BodyGeometry::Mesh(&ball), &opts),
            Err(SegmentError::BadOption { .. })
        ));
    }
}

/// The stick body's arms hang beside the trunk without touching it, so
/// no arm joins the trunk: a partial model that says so, never arms
/// guessed. Legs, crotch, trunk and head are found.
#[test]
fn stick_body_is_partial_with_warnings() {
    let body = shapes::stick_body(2);
    let s = segment(BodyGeometry::Mesh(&body), &SegmentOptions::default()).unwrap();
    assert!(
        (s.frame.up.dot(Vec3::Z) - 1.0).abs() < 1e-6,
        "{:?}",
        s.frame.up
    );
    let crotch = s.landmark(LandmarkKind::Crotch).unwrap();
    // The trunk cylinder starts at z = 0.8 of a 1.66 tall body.
    assert!(
        (crotch.position.z - 0.8).abs() < 0.01,
        "{:?}",
        crotch.position
    );
    for name in [
        PartName::Torso,
        PartName::Head,
        PartName::LeftLeg,
        PartName::RightLeg,
    ] {
        assert!(s.part(name).is_some(), "{name} missing");
    }
    assert!(s.part(PartName::LeftArm).is_none());
    assert!(s
        .warnings
        .iter()
        .any(|w| w.starts_with("left arm not found")));
    assert!(s
        .warnings
        .iter()
        .any(|w| w.starts_with("right arm not found")));
}
