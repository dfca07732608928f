#![no_main]
//! Any bytes given to the model reader (compact `.tbm`, or JSON when they
//! do not start with `TBM`) give Ok or Err, never a panic.

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = trigbody_io::tbm::read_any_model(data);
});
