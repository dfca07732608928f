//! Converts between geometry formats, picking them by extension:
//!
//! `cargo run --release -p trigbody-io --example convert -- IN OUT [--scale S] [--up AXIS] [--overwrite] [--double]`

use trigbody_io::{read_geometry, write_geometry, PlyPrecision, ReadOptions, WriteOptions};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mut paths = Vec::new();
    let mut read = ReadOptions::default();
    let mut write = WriteOptions::default();
    while let Some(a) = args.next() {
        match a.as_str() {
            "--scale" => read.scale = args.next().ok_or("--scale needs a value")?.parse()?,
            "--up" => read.up_axis = args.next().ok_or("--up needs a value")?.parse()?,
            "--overwrite" => write.overwrite = true,
            "--double" => write.ply_precision = PlyPrecision::Double,
            _ => paths.push(a),
        }
    }
    let [input, output] = paths.as_slice() else {
        return Err(
            "usage: convert IN OUT [--scale S] [--up AXIS] [--overwrite] [--double]".into(),
        );
    };
    let g = read_geometry(input, &read)?;
    println!(
        "{input}: {} vertices, {} triangles, normals: {}",
        g.positions().len(),
        g.triangles().len(),
        g.normals().is_some()
    );
    write_geometry(output, &g, &write)?;
    println!("wrote {output}");
    Ok(())
}
