//! Cross-sections: a mesh cut by planes, a cloud cut into slabs, the holes
//! of a scan, and girths of loops and curves. Depends on `geom`, `spatial`
//! and `curve` (a slab's loop is fitted to close it).

pub mod cloud;
pub mod girth;
pub mod holes;
pub mod inlets;
pub mod mesh;
