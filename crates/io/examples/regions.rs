//! Region by region, how a reconstruction fits its input mesh
//! (`trigbody_core::regions`): the head above the neck, the hands past the
//! wrists, the feet below the ankles and the rest.
//!
//! ```text
//! cargo run --release -p trigbody-io --example regions [BODY.obj|ply|stl ...]
//! ```
//!
//! Without arguments, the built-in body. Per body and region: input → model
//! RMS, p95 and max in mm, the share of area whose model normal is more
//! than 30° off the input's and that angle's 90th percentile, against the
//! model's outer skin (the report's tessellation and skin), the closed skin
//! (`--mesh`'s default) when `CLOSED=1`, and the floor (the input against
//! its own once-subdivided copy). `SAMPLES` overrides the 200 000 samples.

use trigbody_core::internals::geom::subdivide::loop_subdivide;
use trigbody_core::internals::measure::regions::{region_fit, RegionFit, Regions};
use trigbody_core::internals::surface::skin::outer_skin;
use trigbody_core::{reconstruct, ReconstructOptions};
use trigbody_core::{segment, BodyGeometry};
use trigbody_core::{Mesh, TessellationOptions};
use trigbody_io::{read_mesh, ReadOptions};

fn row(body: &str, what: &str, fits: &[RegionFit]) {
    for f in fits {
        println!(
            "{body:<14} {what:<8} {:<6} {:>7} {:>7.2} {:>7.2} {:>7.1} {:>6.1} % {:>6.1}",
            f.region.map_or("?", |r| r.name()),
            f.samples,
            f.rms,
            f.p95,
            f.max,
            100.0 * f.off_30,
            f.angle_p90
        );
    }
}

fn main() {
    let mut paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        paths.push(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/bodies/mh_male.obj").into());
    }
    let samples = std::env::var("SAMPLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200_000);
    let closed = std::env::var("CLOSED").is_ok_and(|v| v == "1");
    println!(
        "{:<14} {:<8} {:<6} {:>7} {:>7} {:>7} {:>7} {:>8} {:>6}",
        "body", "surface", "region", "samples", "rms mm", "p95 mm", "max mm", ">30°", "p90°"
    );
    for path in paths {
        let name = std::path::Path::new(&path)
            .file_stem()
            .map_or(path.clone(), |s| s.to_string_lossy().into_owned());
        let input = read_mesh(&path, &ReadOptions::default()).expect("read a mesh");
        let opts = ReconstructOptions::default();
        let geometry = BodyGeometry::Mesh(&input);
        let seg = segment(geometry, &opts.segment).expect("segment");
        let regions = Regions::new(&seg);
        let (model, _) = reconstruct(geometry, &opts).expect("reconstruct");
        let mm = opts.units.to_mm();
        let tess = TessellationOptions {
            target_edge: Some(opts.report_edge * model.height),
            ..TessellationOptions::default()
        };
        let pieces = model.tessellate_pieces(&tess).expect("tessellate");
        let (solids, cavities) = pieces.split_at(pieces.len() - model.cavities.len());
        let (outer, _) = outer_skin(solids, opts.skin_depth * model.height);
        let with_cavities: Vec<&trigbody_core::Mesh> =
            std::iter::once(&outer).chain(cavities).collect();
        let skin = trigbody_core::internals::geom::mesh::concatenate(&with_cavities).0;
        row(
            &name,
            "outer",
            &region_fit(&input, &skin, &regions, samples, mm),
        );
        if closed {
            let closed =
                trigbody_core::internals::surface::closed_skin::closed_skin(solids, cavities)
                    .expect("closed");
            row(
                &name,
                "closed",
                &region_fit(&input, &closed, &regions, samples, mm),
            );
        }
        let smooth: Mesh = loop_subdivide(&input);
        row(
            &name,
            "floor",
            &region_fit(&input, &smooth, &regions, samples, mm),
        );
    }
}
