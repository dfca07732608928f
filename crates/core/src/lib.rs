//! # trigbody-core
//!
//! The math core of trigbody: human body models built from planar
//! cross-section curves described by trigonometric (Fourier) series, after
//! "Trigonometric curve-based human modeling" (GRAPP 2011). This crate holds
//! no I/O: formats, pictures and the command line sit on top of it.
//!
//! ```
//! use trigbody_core::{Frame, TrigCurve};
//! // A circle of radius 0.1 m in the plane z = 0, written at order 3.
//! let c = TrigCurve::circle(Frame::XY, 0.1, 3);
//! assert!((c.perimeter() - std::f64::consts::TAU * 0.1).abs() < 1e-12);
//! assert!((c.area() - std::f64::consts::PI * 0.01).abs() < 1e-15);
//! ```

pub mod body;
pub mod cap;
pub mod closed_skin;
pub mod cloud_surface;
pub mod curve;
pub mod distance;
pub mod ellipse;
pub mod fit;
pub mod girth;
pub mod holes;
pub mod linalg;
pub mod lsq;
pub mod math;
pub mod measure;
pub mod measure_model;
pub mod mesh;
pub mod order;
pub mod part;
pub mod patch;
pub mod regions;
pub mod scan_section;
pub mod scanner;
pub mod section;
pub mod segment;
pub mod series;
pub mod shapes;
pub mod skin;
pub mod subdivide;
pub mod tessellate;
pub mod transition;
pub mod tri_intersect;
pub mod visibility;

pub use body::{reconstruct, Body, BodyPart, ReconstructError, ReconstructOptions, Report, Units};
pub use cap::{Cap, CapKind, DomeAxis};
pub use curve::{CurveError, Frame, SpaceCurve, TrigCurve};
pub use ellipse::EllipseFit;
pub use fit::{
    fit_loop, fit_loop_2d, FitError, FitOptions, LoopFit, OrderChoice, Parameterization, Weighting,
};
pub use lsq::FitErrors;
pub use math::{Point2, Point3, Real, Vec2, Vec3};
pub use measure::{
    measure_mesh, MeasureError, MeasureOptions, Measurement, MeasurementKind, Measurements,
};
pub use mesh::{Aabb, Mesh, MeshError, PointCloud};
pub use part::{Part, PartError, PartOptions, Segment, Skinning};
pub use patch::{EndConditions, Patch, PatchError};
pub use series::Series;
pub use tessellate::{tessellate_part, tessellate_part_into, TessellateError, TessellationOptions};
