//! Inputs that once hung or crashed a reader (found by review or by the
//! fuzzer); each is also a file in `fuzz/corpus/`.

use std::time::{Duration, Instant};
use trigbody_io::{read_bytes, Format, ReadOptions};

/// An ASCII PLY element with no properties but a huge count looped over
/// nothing for 10¹² iterations.
#[test]
fn ascii_ply_element_without_properties_and_huge_count() {
    let d = b"ply\nformat ascii 1.0\nelement junk 1000000000000\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
    let start = Instant::now();
    let g = read_bytes(d, Format::Ply, &ReadOptions::default()).unwrap();
    assert_eq!(g.positions().len(), 1);
    assert!(start.elapsed() < Duration::from_secs(1));
}
