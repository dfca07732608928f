#![no_main]
//! Any bytes given to the Ply reader give Ok or Err, never a panic.

use libfuzzer_sys::fuzz_target;
use trigbody_io::{read_bytes, Format, ReadOptions};

fuzz_target!(|data: &[u8]| {
    let _ = read_bytes(data, Format::Ply, &ReadOptions::default());
});
