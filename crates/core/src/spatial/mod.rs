//! Spatial queries over meshes and clouds: the triangle hierarchy and
//! point-to-mesh distances, visibility rays, the point grid, the surface a
//! cloud samples, and the virtual scanner. Depends on `geom` only.

pub mod cloud_clean;
pub mod cloud_surface;
pub mod distance;
pub mod morton;
pub mod point_grid;
pub mod scanner;
pub mod tri_intersect;
pub mod visibility;
