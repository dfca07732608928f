//! Replays the saved fuzz corpus (`fuzz/corpus/<target>/`) through the
//! readers: every file must give Ok or Err, never a panic. Each file also
//! goes through every other reader, which costs little and widens the net.
//! Crashes the fuzzer found are also named tests in `fuzz_regressions.rs`.

use std::path::PathBuf;
use trigbody_io::{read_bytes, Format, ReadOptions};

const TARGETS: [(&str, Format); 4] = [
    ("obj", Format::Obj),
    ("ply", Format::Ply),
    ("stl", Format::Stl),
    ("xyz", Format::Xyz),
];

#[test]
fn saved_corpus_never_panics() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus");
    let mut files = 0;
    for (target, _) in TARGETS {
        let dir = root.join(target);
        let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        for entry in entries {
            let path = entry.expect("directory entry").path();
            let data = std::fs::read(&path).expect("corpus file");
            for (_, format) in TARGETS {
                let outcome = std::panic::catch_unwind(|| {
                    let _ = read_bytes(&data, format, &ReadOptions::default());
                });
                assert!(outcome.is_ok(), "{} panicked as {format}", path.display());
            }
            files += 1;
        }
    }
    assert!(files >= 12, "only {files} corpus files found");
}

/// The compact model reader's corpus (`fuzz/corpus/tbm/`): valid files,
/// truncated and damaged ones. Never a panic; the valid seeds read.
#[test]
fn saved_tbm_corpus_never_panics() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/tbm");
    let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let (mut files, mut valid) = (0, 0);
    for entry in entries {
        let path = entry.expect("directory entry").path();
        let data = std::fs::read(&path).expect("corpus file");
        let outcome = std::panic::catch_unwind(|| trigbody_io::tbm::read_any_model(&data).is_ok());
        let ok = outcome.unwrap_or_else(|_| panic!("{} panicked", path.display()));
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if name.starts_with("valid_") {
            assert!(ok, "{name} should read");
            valid += 1;
        }
        files += 1;
    }
    assert!(files >= 6 && valid >= 1, "{files} files, {valid} valid");
}

/// The model-file target's corpus (`fuzz/corpus/model/`): read, then
/// tessellated coarsely. Never a panic.
#[test]
fn saved_model_corpus_never_panics() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/model");
    let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let coarse = trigbody_core::TessellationOptions {
        around: 8,
        along: 4,
        cap_rings: 2,
        target_edge: None,
    };
    let mut files = 0;
    for entry in entries {
        let path = entry.expect("directory entry").path();
        let data = std::fs::read(&path).expect("corpus file");
        let outcome = std::panic::catch_unwind(|| {
            if let Ok(model) = trigbody_io::model::read_model(&data[..]) {
                let _ = model.tessellate_pieces(&coarse);
            }
        });
        assert!(outcome.is_ok(), "{} panicked", path.display());
        files += 1;
    }
    assert!(files >= 2, "only {files} model corpus files found");
}
