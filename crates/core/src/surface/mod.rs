//! Surfaces from curves: Hermite patches between section curves, parts
//! skinned from them, end caps, transitions between parts, tessellation
//! (of one part, or of a model's pieces together), and the outer skin of a
//! set of pieces.

pub mod cap;
pub mod closed_skin;
pub mod fit;
pub mod local_skin;
pub mod part;
pub mod patch;
pub mod pieces;
pub mod skin;
pub mod tessellate;
pub mod transition;
