//! Segmentation of the project's real bodies and scans (from
//! `../shared/data`; skipped with a note when that folder is absent).
//!
//! Only these tests know the bodies' conventions (metres, +y up, facing
//! +z, A-pose); the library under test does not.
//!
//! Run with `--nocapture` to see the landmark tables.

mod common;

use common::shared_data;
use trigbody_core::segment::{
    cut_part, segment, BodyGeometry, LandmarkKind, PartName, SegmentOptions, Segmentation,
};
use trigbody_core::{Mesh, PointCloud, Vec3};
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

fn scan() -> Option<PointCloud> {
    let data = shared_data()?;
    Some(
        read_point_cloud(
            data.join("scans").join("mh_male_scan.ply"),
            &ReadOptions::default(),
        )
        .unwrap(),
    )
}

fn print(name: &str, s: &Segmentation) {
    println!(
        "{name}: H = {:.4}, up {:?}, front {:?}, warnings {:?}",
        s.height,
        s.frame.up.to_array().map(|v| (v * 1000.0).round() / 1000.0),
        s.frame
            .front
            .to_array()
            .map(|v| (v * 1000.0).round() / 1000.0),
        s.warnings
    );
    for l in &s.landmarks {
        println!(
            "  {:<13} h/H = {:.3}  conf {:.2}  at {:?}",
            l.kind.to_string(),
            l.height_fraction,
            l.confidence,
            l.position.to_array().map(|v| (v * 1000.0).round() / 1000.0)
        );
    }
    for p in &s.parts {
        println!(
            "  part {:<10} {} points, length/H {:.3}, max r/H {:.3}",
            p.name.to_string(),
            p.points.len(),
            p.length() / s.height,
            p.max_radius() / s.height
        );
    }
}

#[test]
fn bodies_and_scan_table() {
    for (name, mesh) in bodies() {
        let t = std::time::Instant::now();
        let s = segment(BodyGeometry::Mesh(&mesh), &SegmentOptions::default());
        println!("time {:?}", t.elapsed());
        match s {
            Ok(s) => print(&name, &s),
            Err(e) => println!("{name}: {e}"),
        }
    }
    if let Some(c) = scan() {
        let t = std::time::Instant::now();
        let s = segment(BodyGeometry::Cloud(&c), &SegmentOptions::default());
        println!("time {:?}", t.elapsed());
        match s {
            Ok(s) => print("scan", &s),
            Err(e) => println!("scan: {e}"),
        }
    }
}

#[test]
#[ignore]
fn debug_scan() {
    if let Some(c) = scan() {
        let t = std::time::Instant::now();
        let s = segment(BodyGeometry::Cloud(&c), &SegmentOptions::default());
        println!("time {:?}", t.elapsed());
        match s {
            Ok(s) => print("scan", &s),
            Err(e) => println!("scan: {e}"),
        }
    }
}
