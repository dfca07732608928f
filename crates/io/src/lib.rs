//! # trigbody-io
//!
//! File formats for trigbody: everything that turns bytes into the core's
//! types and back. The core never reads or writes files itself.

pub mod fit_json;
pub mod gltf;
pub mod loop_text;
pub mod model;
