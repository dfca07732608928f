//! The symmetric RMS distance between two meshes, the one distance tool of
//! `scripts/compactness.py` (every contender is measured with it):
//!
//! `cargo run --release -p trigbody-io --example mesh_distance -- A B [--samples N] [--mm-per-unit S]`
//!
//! Samples each surface with [`sample_surface`] (`N` points, default 60 000,
//! the reconstruction report's count), measures each sample's distance to
//! the other surface, and prints one JSON line: `a_to_b_mm` and `b_to_a_mm`
//! (RMS of each direction), `rms_mm = √((a² + b²)/2)` (the report's
//! symmetric RMS) and the two meshes' vertex and triangle counts.

use trigbody_core::internals::spatial::distance::{sample_surface, DistanceStats, MeshDistance};
use trigbody_io::{read_geometry, Geometry, ReadOptions};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}

fn read_mesh(path: &str) -> Result<trigbody_core::Mesh, Box<dyn std::error::Error>> {
    match read_geometry(path, &ReadOptions::default())? {
        Geometry::Mesh(m) => Ok(m),
        Geometry::Points(_) => Err(format!("{path}: points, not a mesh").into()),
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mut paths = Vec::new();
    let mut samples = 60_000usize;
    let mut mm = 1000.0;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--samples" => samples = args.next().ok_or("--samples needs a value")?.parse()?,
            "--mm-per-unit" => mm = args.next().ok_or("--mm-per-unit needs a value")?.parse()?,
            _ => paths.push(a),
        }
    }
    let [a, b] = paths.as_slice() else {
        return Err("usage: mesh_distance A B [--samples N] [--mm-per-unit S]".into());
    };
    let (ma, mb) = (read_mesh(a)?, read_mesh(b)?);
    let rms_to = |from: &trigbody_core::Mesh, to: &trigbody_core::Mesh| {
        let d = MeshDistance::new(to).distances(&sample_surface(from, samples));
        DistanceStats::of(&d).rms * mm
    };
    let (ab, ba) = (rms_to(&ma, &mb), rms_to(&mb, &ma));
    println!(
        "{{\"a_to_b_mm\": {ab:.5}, \"b_to_a_mm\": {ba:.5}, \"rms_mm\": {:.5}, \
         \"a_vertices\": {}, \"a_triangles\": {}, \"b_vertices\": {}, \"b_triangles\": {}}}",
        ((ab * ab + ba * ba) / 2.0).sqrt(),
        ma.positions.len(),
        ma.triangles.len(),
        mb.positions.len(),
        mb.triangles.len()
    );
    Ok(())
}
