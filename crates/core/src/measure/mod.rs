//! Body measurements: on a mesh from fitted curves of its own sections
//! (`mesh`), and on a model from its curves and surfaces (`model`).

pub mod compare;
pub mod mesh;
pub mod model;
pub mod part_curves;
pub mod regions;
pub mod volume;
