use trigbody_core::segment::{segment, BodyGeometry, PartName, SegmentOptions};
use trigbody_io::{read_mesh, ReadOptions};
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let mesh = read_mesh(&path, &ReadOptions::default()).unwrap();
    let seg = segment(BodyGeometry::Mesh(&mesh), &SegmentOptions::default()).unwrap();
    println!("frame {:?} H {}", seg.frame, seg.height);
    for l in &seg.landmarks {
        println!("{:?} {:?} h={:.3}", l.kind, l.position, l.height_fraction);
    }
    for p in &seg.parts {
        let (_, t0) = p.point_and_tangent(0.0).unwrap();
        println!(
            "{:?} len {:.3} maxr {:.3} start {:?} t0 {:?} end {:?}",
            p.name,
            p.length(),
            p.max_radius(),
            p.points[0],
            t0,
            p.points.last().unwrap()
        );
        if p.name == PartName::Torso {
            for (q, r) in p.points.iter().zip(&p.radii).step_by(5) {
                println!("   {:?} r {:.3}", q, r);
            }
        }
    }
}
