//! The ground layer: numbers and vectors, the tolerances, small dense
//! linear algebra, triangle meshes and point clouds, closing a mesh's
//! holes, rigid motions, reference shapes, the median, the random
//! generator, disjoint sets and the data-parallel helpers. Depends on nothing else.

pub mod holes;
pub mod linalg;
pub mod math;
pub mod mesh;
pub mod parallel;
pub mod rigid;
pub mod rng;
pub mod shapes;
pub mod stats;
pub mod subdivide;
pub mod tolerance;
pub mod union_find;
