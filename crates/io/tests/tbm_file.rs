//! The compact binary model (`.tbm`): round trips within the stated bound,
//! and damaged or truncated files are clear errors, never a panic.

use std::sync::OnceLock;
use trigbody_core::{reconstruct, BodyGeometry, ReconstructOptions};
use trigbody_io::model::{read_model, write_model, Model};
use trigbody_io::tbm::{
    decode_tbm, encode_tbm, read_any_model, TbmError, TbmOptions, TbmStats, TBM_VERSION,
};
use trigbody_io::{read_mesh, ReadOptions};

/// The built-in body's model (it is in the repository: no shared data
/// needed), written compactly with the default options.
fn built_in() -> &'static (Model, Vec<u8>, TbmStats) {
    &built_in_with_body().1
}

/// A model, its compact file and the file's statistics.
type Written = (Model, Vec<u8>, TbmStats);

/// The built-in body, its model, the compact file and its statistics.
fn built_in_with_body() -> &'static (trigbody_core::Body, Written) {
    static MODEL: OnceLock<(trigbody_core::Body, Written)> = OnceLock::new();
    MODEL.get_or_init(|| {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/bodies/mh_male.obj");
        let mesh = read_mesh(path, &ReadOptions::default()).unwrap();
        let (body, _) =
            reconstruct(BodyGeometry::Mesh(&mesh), &ReconstructOptions::default()).unwrap();
        let model = trigbody_io::body_file::model_of_body(&body);
        let (bytes, stats) = encode_tbm(&model, &TbmOptions::default()).unwrap();
        (body, (model, bytes, stats))
    })
}

/// The numbers a JSON model file stores for its sections: a frame (9)
/// and the coefficients of each.
fn json_section_numbers(model: &Model) -> usize {
    model
        .parts
        .iter()
        .flat_map(|p| p.part.sections())
        .map(|c| 9 + 2 * c.a.len())
        .sum()
}

/// The report's count of the compact file's numbers is the encoder's:
/// the design parameters less the JSON's section numbers plus the `.tbm`'s.
#[test]
fn the_compact_count_is_what_the_encoder_stores() {
    let (body, (model, _, stats)) = built_in_with_body();
    assert_eq!(
        body.compact_numbers(),
        body.design_parameters() - json_section_numbers(model) + stats.section_numbers
    );
    assert!(body.compact_numbers() < body.design_parameters());
}

/// The largest distance between corresponding section curve points of two
/// models with the same parts and section counts.
fn max_section_displacement(a: &Model, b: &Model) -> f64 {
    assert_eq!(a.parts.len(), b.parts.len());
    let mut worst: f64 = 0.0;
    for (pa, pb) in a.parts.iter().zip(&b.parts) {
        assert_eq!(pa.name, pb.name);
        assert_eq!(pa.cavity_of, pb.cavity_of);
        assert_eq!(pa.part.options(), pb.part.options());
        assert_eq!(pa.part.sections().len(), pb.part.sections().len());
        for (ca, cb) in pa.part.sections().iter().zip(pb.part.sections()) {
            assert_eq!(ca.order(), cb.order());
            for (p, q) in ca.sample(256).iter().zip(cb.sample(256)) {
                worst = worst.max(p.distance(q));
            }
        }
    }
    worst
}

#[test]
fn the_built_in_body_reads_back_within_the_bound() {
    let (model, bytes, stats) = built_in();
    let back = decode_tbm(bytes).unwrap();
    let moved = max_section_displacement(model, &back);
    eprintln!(
        "tbm: {} bytes, {} section numbers, step {:.4} mm, bound {:.3} mm, measured {:.4} mm \
         (encoder {:.4} mm), zstd {} B, order-0 entropy {:.0} B, per index {:.0} B",
        stats.bytes,
        stats.section_numbers,
        stats.step * 1e3,
        stats.bound * 1e3,
        moved * 1e3,
        stats.max_error * 1e3,
        stats.zstd_bytes,
        stats.entropy_bytes,
        stats.entropy_by_index_bytes
    );
    assert!(moved <= stats.bound, "{moved} > bound {}", stats.bound);
    assert!((moved - stats.max_error).abs() < 1e-12);
    assert!(
        moved > 0.0,
        "quantization moved nothing: the test cannot see it"
    );
    assert_eq!(back.units, model.units);
    assert_eq!(back.body, model.body);
    assert_eq!(back.transitions.len(), model.transitions.len());
    for (t, u) in model.transitions.iter().zip(&back.transitions) {
        assert_eq!((&t.from, &t.to), (&u.from, &u.to));
        assert_eq!(t.transition.spec(), u.transition.spec());
    }
    // Fewer numbers than the JSON file's design parameters, and a file a
    // small fraction of the JSON's size (407 KB).
    assert!(stats.section_numbers < json_section_numbers(model));
    assert!(bytes.len() < 40_000, "{} bytes", bytes.len());
}

#[test]
fn json_to_tbm_to_json_keeps_the_decoded_model_exactly() {
    let (_, bytes, _) = built_in();
    let back = decode_tbm(bytes).unwrap();
    let mut json = Vec::new();
    write_model(&mut json, &back).unwrap();
    let again = read_model(json.as_slice()).unwrap();
    assert_eq!(again, back);
    // Writing the decoded model compactly again changes it by at most the
    // bound once more (the frames are already the predicted ones).
    let (bytes2, stats2) = encode_tbm(&back, &TbmOptions::default()).unwrap();
    let twice = decode_tbm(&bytes2).unwrap();
    assert!(max_section_displacement(&back, &twice) <= stats2.bound);
    // JSON still reads through the same entry point.
    assert_eq!(read_any_model(&json).unwrap(), back);
}

#[test]
fn truncated_and_damaged_files_are_errors() {
    let (_, bytes, _) = built_in();
    for n in (0..bytes.len()).step_by(97).chain([bytes.len() - 1]) {
        let e = read_any_model(&bytes[..n]).expect_err("a truncated file must not read");
        let msg = e.to_string();
        assert!(
            msg.contains("compact") || msg.contains("JSON") || msg.contains("model"),
            "{n} bytes: {msg}"
        );
    }
    // Any flipped byte past the header: the zstd checksum (or the frame
    // structure) refuses it.
    for i in (4..bytes.len()).step_by(61) {
        let mut bad = bytes.clone();
        bad[i] ^= 0x5a;
        assert!(decode_tbm(&bad).is_err(), "byte {i} flipped still read");
    }
    let mut newer = bytes.clone();
    newer[3] = TBM_VERSION + 1;
    assert!(matches!(
        decode_tbm(&newer),
        Err(TbmError::UnknownVersion(v)) if v == TBM_VERSION + 1
    ));
    assert!(matches!(decode_tbm(b"{}"), Err(TbmError::NotTbm)));
}

#[test]
fn a_coarser_step_gives_a_smaller_file_and_a_larger_error() {
    let (model, bytes, stats) = built_in();
    let coarse = TbmOptions {
        step: Some(4.0 * stats.step),
        ..TbmOptions::default()
    };
    let (small, s4) = encode_tbm(model, &coarse).unwrap();
    assert!(small.len() < bytes.len());
    assert!(s4.max_error > stats.max_error);
    assert!(max_section_displacement(model, &decode_tbm(&small).unwrap()) <= s4.bound);
}

/// Version 1 files (first frames as doubles) still read: the saved seed
/// reads, and written again (version 2, first frames on the grid) it reads
/// back within the new file's bound.
#[test]
fn a_version_1_file_still_reads() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/tbm");
    let v1 = std::fs::read(dir.join("valid_small_v1.tbm")).unwrap();
    assert_eq!(v1[3], 1);
    let old = decode_tbm(&v1).unwrap();
    let (v2, stats) = encode_tbm(&old, &TbmOptions::default()).unwrap();
    assert_eq!(v2[3], TBM_VERSION);
    let new = decode_tbm(&v2).unwrap();
    let worst = max_section_displacement(&old, &new);
    assert!(worst <= stats.bound, "{worst} over {}", stats.bound);
}
