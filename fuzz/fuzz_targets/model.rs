#![no_main]
//! Any bytes given to the model-file reader give Ok or Err, never a panic;
//! a model read is tessellated too (coarse), which must not panic either.

use libfuzzer_sys::fuzz_target;
use trigbody_core::TessellationOptions;
use trigbody_io::model::read_model;

fuzz_target!(|data: &[u8]| {
    if let Ok(model) = read_model(data) {
        let coarse = TessellationOptions {
            around: 8,
            along: 4,
            cap_rings: 2,
            target_edge: None,
        };
        let _ = model.tessellate_pieces(&coarse);
    }
});
