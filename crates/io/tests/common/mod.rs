//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::PathBuf;
use trigbody_core::Mesh;

/// A file of `tests/fixtures/`.
pub fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

/// The shared data folder (`../shared/data` beside the repository), or
/// `None` when it is not there (a fresh clone on its own).
pub fn shared_data() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("TRIGBODY_DATA") {
        return Some(PathBuf::from(dir));
    }
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "note: {} not found; skipping shared-data checks",
            dir.display()
        );
        None
    }
}

/// Whether every edge is shared by exactly two triangles, traversed once in
/// each direction (a closed, consistently oriented surface).
pub fn is_closed_and_oriented(mesh: &Mesh) -> bool {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    directed
        .iter()
        .all(|(&(a, b), &n)| n == 1 && directed.get(&(b, a)) == Some(&1))
}
