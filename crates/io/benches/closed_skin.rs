//! The closed skin of the built-in body's model (`trigbody_core::closed_skin`)
//! at `--mesh`'s tessellation (edge 0.004 × H): what `--skin closed`, the
//! default of `--mesh`, adds to a reconstruction (the tessellation, which
//! every `--mesh` pays, is timed beside it, and so is the whole-soup
//! rebuild the local one falls back to).
//!
//! `cargo bench -p trigbody-io --bench closed_skin`

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::PathBuf;
use trigbody_core::internals::surface::closed_skin::{closed_skin, closed_soup, whole_soup_skin};
use trigbody_core::BodyGeometry;
use trigbody_core::TessellationOptions;
use trigbody_core::{reconstruct, ReconstructOptions};
use trigbody_io::{read_mesh, ReadOptions};

fn bench(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/bodies/mh_male.obj");
    let mesh = read_mesh(&path, &ReadOptions::default()).expect("the built-in body");
    let (model, _) =
        reconstruct(BodyGeometry::Mesh(&mesh), &ReconstructOptions::default()).expect("model");
    let tess = TessellationOptions {
        target_edge: Some(0.004 * model.height),
        ..TessellationOptions::default()
    };
    let pieces = model.tessellate_pieces(&tess).expect("tessellated");
    let (solids, cavities) = pieces.split_at(pieces.len() - model.cavities.len());
    let mut g = c.benchmark_group("closed skin");
    g.sample_size(10);
    g.bench_function("built-in body model, tessellate for --mesh", |b| {
        b.iter(|| model.tessellate_pieces(black_box(&tess)).map(|p| p.len()))
    });
    g.bench_function("built-in body model, closed skin of the pieces", |b| {
        b.iter(|| closed_skin(black_box(solids), cavities).map(|m| m.triangles.len()))
    });
    // The fallback, timed beside the default under the same load.
    let (soup, _) = closed_soup(solids, cavities).expect("soup");
    g.bench_function("built-in body model, whole-soup rebuild (fallback)", |b| {
        b.iter(|| whole_soup_skin(black_box(&soup)).map(|m| m.triangles.len()))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
