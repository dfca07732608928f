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
//!
//! ## The pipeline
//!
//! [`reconstruct`] turns a body mesh or a cloud of scanned points into a
//! [`Body`] and a [`Report`]. Its stages, in order, each in a module layer
//! that depends only on the layers before it:
//!
//! 1. **Input** (`geom`): a [`Mesh`] or a [`PointCloud`], seen as a
//!    [`BodyGeometry`]. `spatial` answers distance, visibility and
//!    nearest-point queries on it. [`validate_input`] checks it first:
//!    well formed, one body, a human height in its unit (or the unit
//!    inferred), so every caller refuses the same inputs alike. A mesh or
//!    a scan is reconstructed in
//!    its own frame and point order (a [`Rigid`] motion there and back),
//!    so the model does not depend on how the file turned, moved or
//!    numbered it.
//! 2. **Segmentation** (`segment`): the up axis, the body's frame
//!    ([`BodyFrame`]), the landmarks and a skeleton of named parts
//!    ([`PartName`]), from a graph of horizontal slices.
//! 3. **Sections** (`section`): every part cut perpendicular to its axis,
//!    a mesh by planes, a cloud by thin slabs (holes closed).
//! 4. **Curves** (`curve`): each section loop fitted by a [`TrigCurve`]
//!    ([`fit_loop`]) whose order is the smallest meeting the error
//!    tolerances E_a and E_M (the ellipse [`EllipseFit`] is the baseline).
//! 5. **Surfaces** (`surface`): consecutive curves skinned by Hermite
//!    [`Patch`]es into a [`Part`] ([`Part::new`]), closed by [`Cap`]s and
//!    joined by transitions; [`tessellate_part`] makes a mesh of it.
//! 6. **Body** (`body`): the parts, refined where the fit is poor, then
//!    (a scan's by default, [`GlobalFitOptions`]) fitted to every input
//!    point labelled with them by one least squares per round
//!    ([`fit_part`]); their transitions and cavities assembled into a
//!    [`Body`], and judged against the input (the [`Report`]: sizes,
//!    errors, distances, what the fit did).
//! 7. **Measurement** (`measure`): stature, girths, lengths, volume and
//!    area of a model ([`measure_body`]) or of a mesh directly
//!    ([`measure_mesh`]).
//!
//! Reading and writing files (meshes, scans, the model file) is the
//! `trigbody-io` crate's.

mod anatomy;
mod body;
mod curve;
mod geom;
mod measure;
mod section;
mod segment;
mod spatial;
mod surface;

pub use anatomy::{BodyFrame, BodyGeometry, Landmark, LandmarkKind, PartName};
pub use body::{
    reconstruct, reconstruct_with_progress, validate_input, Body, BodyCavity, BodyDigit, BodyPart,
    BodyTransition, FitMode, GlobalFitOptions, InputError, PartFit, Progress, ReconstructError,
    ReconstructOptions, Report, SectionFit, Units, HUMAN_EXTENT_M, MAX_PRUNE_TOLERANCE,
    MAX_SCAN_FRAMES,
};
pub use curve::ellipse::{fit_ellipse, EllipseFit};
pub use curve::fit::{
    fit_loop, fit_loop_2d, FitError, FitOptions, LoopFit, OrderChoice, Parameterization, Weighting,
};
pub use curve::lsq::FitErrors;
pub use curve::series::Series;
pub use curve::trig::{CurveError, Frame, SpaceCurve, TrigCurve};
pub use geom::math::{Point2, Point3, Real, Vec2, Vec3};
pub use geom::mesh::{Aabb, Mesh, MeshError, PointCloud};
pub use geom::rigid::Rigid;
pub use measure::compare::{
    compare_surfaces, compare_surfaces_seen, CompareOptions, SurfaceComparison,
};
pub use measure::mesh::{
    measure_mesh, MeasureError, MeasureOptions, Measurement, MeasurementKind, Measurements,
};
pub use measure::model::{measure_body, ModelMeasureOptions};
pub use segment::joints::{estimate_joints, JointName};
pub use segment::{segment, SegmentError, SegmentOptions, Segmentation};
pub use spatial::cloud_clean::{clean_cloud, CleanOptions, CleanReport};
pub use spatial::scanner::{virtual_scan, ScannerOptions};
pub use surface::cap::{Cap, CapKind, DomeAxis};
pub use surface::closed_skin::{check_closed, closed_skin, ClosedSkinError};
pub use surface::fit::{fit_part, SurfaceFitOptions, SurfaceFitStats};
pub use surface::part::{Part, PartError, PartOptions, Segment, Skinning};
pub use surface::patch::{EndConditions, Patch, PatchError};
pub use surface::tessellate::{
    tessellate_part, tessellate_part_into, TessellateError, TessellationOptions,
};

/// The building blocks the workspace's own crates (io, render, the
/// command line, benches and tests) reach below the public API. Not part
/// of it: names and signatures here change without notice.
#[doc(hidden)]
pub mod internals {
    /// The `geom` layer.
    pub mod geom {
        pub use crate::geom::{
            linalg, math, mesh, parallel, rigid, rng, shapes, stats, subdivide, tolerance,
            union_find,
        };
    }
    /// The `spatial` layer.
    pub mod spatial {
        pub use crate::spatial::{
            cloud_clean, cloud_surface, distance, morton, point_grid, scanner, tri_intersect,
            visibility,
        };
    }
    /// The `curve` layer.
    pub mod curve {
        pub use crate::curve::{ellipse, fit, lsq, noise, order, series, trig};
    }
    /// The `section` layer.
    pub mod section {
        pub use crate::section::{cloud, girth, holes, mesh};
    }
    /// The `surface` layer.
    pub mod surface {
        pub use crate::surface::{
            cap, closed_skin, fit, local_skin, part, patch, pieces, skin, tessellate, transition,
        };
    }
    /// The `segment` layer.
    pub mod segment {
        pub use crate::segment::*;
    }
    /// The `body` layer.
    pub mod body {
        pub use crate::body::*;
    }
    /// The `measure` layer.
    pub mod measure {
        pub use crate::measure::{compare, mesh, model, regions, volume};
    }
}
