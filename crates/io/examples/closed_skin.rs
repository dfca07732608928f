//! The closed skin of a reconstructed body (`trigbody_core::closed_skin`):
//! how long the union takes and what the independent check finds.
//!
//! ```text
//! cargo run --release -p trigbody-io --example closed_skin [BODY...]
//! ```
//!
//! Without arguments, the built-in body. Per body: the pieces and their
//! triangles at the `--mesh` tessellation (edge 0.004 × H), the union's
//! time (fastest of 3), its triangles, and the check: edges not in exactly
//! two triangles, misoriented edges, components, intersecting triangle
//! pairs, and the volume against the pieces' union measured by rays.

use std::time::Instant;
use trigbody_core::internals::surface::closed_skin::{check_closed, closed_skin, union_volume};
use trigbody_core::TessellationOptions;
use trigbody_core::{reconstruct, ReconstructOptions};
use trigbody_io::{read_geometry, ReadOptions};

fn main() {
    let mut paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        paths.push(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/bodies/mh_male.obj").into());
    }
    for path in paths {
        let geometry = read_geometry(&path, &ReadOptions::default()).expect("read");
        let body = geometry.body();
        let (model, _) = reconstruct(body, &ReconstructOptions::default()).expect("reconstruct");
        let tess = TessellationOptions {
            target_edge: Some(0.004 * model.height),
            ..TessellationOptions::default()
        };
        let t0 = Instant::now();
        let pieces = model.tessellate_pieces(&tess).expect("tessellate");
        let t_tess = t0.elapsed().as_secs_f64();
        let split = pieces.len() - model.cavities.len();
        let (solids, cavities) = pieces.split_at(split);
        let triangles: usize = pieces.iter().map(|m| m.triangles.len()).sum();
        let mut best = f64::INFINITY;
        let mut skin = None;
        for _ in 0..3 {
            let t = Instant::now();
            let s = closed_skin(solids, cavities);
            best = best.min(t.elapsed().as_secs_f64());
            skin = Some(s);
        }
        let skin = skin.expect("ran").expect("closed skin");
        let check = check_closed(&skin);
        let rays = union_volume(solids, cavities, model.frame.up, 0.001 * model.height);
        println!(
            "{path}: {} pieces ({} cavities), {triangles} triangles, tessellated in {:.3} s; \
             closed skin in {best:.3} s: {} vertices, {} triangles; {check:?}; \
             volume {:.6} vs rays {:.6} ({:+.3} %)",
            pieces.len(),
            cavities.len(),
            t_tess,
            skin.positions.len(),
            skin.triangles.len(),
            check.volume,
            rays,
            100.0 * (check.volume / rays - 1.0)
        );
    }
}
