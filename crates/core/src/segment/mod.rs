//! Segmentation of a standing body (A-pose or T-pose) into torso, head with
//! neck, two arms with hands, two legs and two feet (method.md §8.1-§8.4),
//! for a triangle mesh or a scanned point cloud alike, with the landmarks
//! that separate them (crotch, armpits, neck, wrists, ankles, head top,
//! soles, heels, toes) and a smoothed axis per part that [`cut_part`] cuts
//! across.
//!
//! ```no_run
//! # // A body mesh from any reader (`trigbody_io::read_mesh`, say).
//! # fn load() -> trigbody_core::Mesh { trigbody_core::Mesh::default() }
//! use trigbody_core::internals::segment::cut_part;
//! use trigbody_core::{segment, BodyGeometry, PartName, SegmentOptions};
//! let mesh = load();
//! let body = BodyGeometry::Mesh(&mesh);
//! let opts = SegmentOptions::default();
//! let seg = segment(body, &opts)?;
//! for w in &seg.warnings {
//!     eprintln!("warning: {w}");
//! }
//! // The forearm cut across its own axis, halfway along the arm.
//! let cut = cut_part(body, &seg, PartName::LeftArm, 0.5, &opts)?;
//! println!("{} points, girth {}", cut.outline.points.len(), cut.outline.perimeter);
//! # Ok::<(), trigbody_core::SegmentError>(())
//! ```
//!
//! # The algorithm
//!
//! Nothing below knows a coordinate, a size or a vertex order of any
//! particular body: every length is a fraction of the body's own height `H`
//! (its extent along the up axis) or a multiple of a scan's point spacing,
//! every area a fraction of the largest section area.
//!
//! 1. **Up axis.** [`SegmentOptions::up`] if given, else the principal axis
//!    of largest variance (meshes weighted by surface area, so dense vertex
//!    regions do not tilt it; clouds point by point). It must be distinct:
//!    when the largest variance is less than
//!    [`SegmentOptions::min_axis_ratio`] times the second (a sphere, a cube)
//!    the result is [`SegmentError::NoUpAxis`]. A body lying down is found
//!    lying down: its longest axis is still its height.
//! 2. **Slices.** The body is cut by [`SegmentOptions::slices`] planes
//!    normal to the axis, evenly spread over its extent. Mesh: plane
//!    sections through [`MeshSlicer`]. Cloud: slabs as in [`CloudSlicer`]
//!    (half-thickness one point spacing `s`, an occupancy image, its
//!    8-connected components), but with cells of
//!    [`SegmentOptions::graph_cell`] × `s` and without ordering the points
//!    along loops, which the graph does not need: each component stands as
//!    the convex hull of its points (area, centroid, girth). A ring broken
//!    by a scanner hole has no inside to fill, but its hull is still the
//!    section's outline. Loops smaller than
//!    [`SegmentOptions::min_loop_area`] times the reference area (the
//!    largest loop, at most twice the 95th percentile of the slices'
//!    largest: not a slice along arms held out sideways) are dropped
//!    (fingers, noise, the grazing cut at either end).
//! 3. **Sign of the axis** (only when the axis came from the principal
//!    axes). The feet end is the end whose slices have two loops (two feet);
//!    the head end has one. Over the outer 2-9 % of the extent at either
//!    end, the share of slices with two or more loops is measured; the end
//!    with a share larger by at least one half is the bottom. When neither
//!    end has two feet the result is [`SegmentError::NotAStandingBody`].
//! 4. **Slice graph.** Loops of neighbouring slices are linked when they
//!    overlap: the centroid of one lies inside the other, or the centroids
//!    are closer than half the sum of the loops' equivalent radii
//!    `r = √(A/π)`. A loop without a link upward may link up to three
//!    slices further (a scan slab that lost a loop). Maximal chains of
//!    one-to-one links are *segments*; a segment's *parents* are the
//!    segments linked below its first loop, its *children* those above its
//!    last. Segments shorter than [`SegmentOptions::min_branch`] × `H` are
//!    removed when they are dead ends (a thumb, a noise blob), fragments
//!    (less than 30 % of the area of a neighbour: a scan ring that broke
//!    for a slice) or the smaller side of a bubble (split and joined
//!    again) — inner pieces only while every neighbour keeps a link, so a
//!    trunk that broke into pieces for a slice keeps its largest piece —
//!    and the segments are rebuilt until nothing changes.
//! 5. **Parts.** The *legs* are the two segments without parents that start
//!    in the lowest tenth of the height; each is followed up through
//!    one-to-one continuations to the segment where it merges: both must
//!    merge into the same one, and its first loop is the **crotch**. The
//!    *trunk path* runs up from there, taking at any split the child whose
//!    loops over the next twelfth of the height lie nearest (across `up`)
//!    to the trunk's line below its first split, to a segment without
//!    children: the **head top**. The
//!    *arms* are the other segments without parents, at least
//!    [`SegmentOptions::min_arm`] × `H` long, whose chain merges into the
//!    trunk path above the crotch; the merge is the **armpit**, and the side
//!    is the sign of the arm's offset from the trunk along `left`.
//!    **T-pose:** an arm held out sideways never branches in horizontal
//!    slices, so when a side has no hanging arm the same graph is built on
//!    slices across the body (normal to `left`, from the outermost slice
//!    inward): a branch that starts in the outer tenth, lies above the
//!    crotch and merges into the trunk is the arm, the merge its armpit.
//!    **Any other pose, on a mesh** (an arm touching or crossing the
//!    trunk, raised, bent): the arm is found on the surface
//!    ([`geodesic`]): the hand is an extremity of the distance along the
//!    surface from the crotch whose arm ends on that side, the axis the
//!    centroids of the rings of the distance from the hand, up to where
//!    they spread over the shoulder.
//!    A missing arm is a warning and a partial model; missing legs or a
//!    missing crotch are errors naming what was not found.
//! 6. **Front** ([`SegmentOptions::front`] if given): the feet point
//!    forward. For each leg, the area centroid of its slices 1-3 % of `H`
//!    above the floor minus that of its slices 6-9 % above it, made
//!    horizontal; when the two agree within 60° their unit directions are
//!    averaged (each leg on its own, so a slightly tilted axis that cuts
//!    one foot lower does not pull the answer sideways). Feet that disagree
//!    (one lifted or bent back) give only the sign: the front is square to
//!    the line through the legs' top loops (side by side below the crotch),
//!    towards the two feet's sum. `left = up × front`. A foot that reaches
//!    less than 0.5 % of `H` forward gives a warning.
//! 7. **Landmarks on branches.** The **neck** is the smallest convex-hull
//!    girth of the trunk path between the highest armpit and the head's
//!    widest slice. The **ankle** is the smallest hull girth of a leg
//!    between the foot's widest slice and the calf's widest slice. The
//!    **wrist** is found on cuts *perpendicular* to the arm's axis
//!    (horizontal cuts of an arm at 45° are skewed): walking up the arm from
//!    the hand, the widest cut of the hand comes first, then the narrowest
//!    cut between it and the middle of the arm is the wrist. The **sole**
//!    is the middle of the foot on the floor; **heel** and **toe** the ends
//!    of the foot's axis.
//! 8. **Axes.** Each part's axis is the polyline of its loops' area
//!    centroids, smoothed by a running median and then a moving average
//!    over ± [`SegmentOptions::axis_smoothing`] × `H`, and resampled evenly
//!    by arc length, oriented as method.md §2 asks (up for torso and head,
//!    away from the trunk for limbs): torso crotch → neck, head neck → top,
//!    arms shoulder → hand tip, legs crotch → ankle. An arm's axis is
//!    continued past the armpit into the shoulder (method.md §8.5): steps
//!    along the direction of its top tenth, each cut perpendicular to it,
//!    while the cut's loop stays an arm's loop (at most 1.5 times the arm's
//!    typical area, centred within an arm radius); where the cuts merge
//!    with the trunk is the **shoulder** landmark. Feet get a straight
//!    axis from heel to toe: the principal horizontal direction of the
//!    foot's slices below the ankle, oriented to the front, at a third of
//!    the ankle height. [`cut_part`] cuts a part again with the plane
//!    perpendicular to its axis at a given arc-length fraction and returns
//!    the part's loop (a plane across a foot behind the ankle runs up the
//!    leg; cut feet in front of it).
//!
//! Heights in the results are measured from the floor (the lowest point
//! along `up`); landmarks carry their height as a fraction of `H`. Units
//! are the input's: nothing assumes metres.
//!
//! Not handled (reported, not guessed): a scan's arm touching the trunk or
//! raised above the head (a cloud has no surface to walk), a hand touching
//! the thigh or hip in the slices (the legs then do not merge only with
//! each other: an error naming the crotch), sitting poses.
//! Fingers thinner than [`SegmentOptions::min_loop_area`] are not in the
//! graph; the arm's axis is extended from its last slice to the farthest
//! input point along the forearm-hand direction (the **hand tip**).
//!
//! [`MeshSlicer`]: crate::section::mesh::MeshSlicer
//! [`CloudSlicer`]: crate::section::cloud::CloudSlicer

mod arms;
mod axis;
mod branches;
mod cut;
mod frame;
mod geodesic;
mod graph;
pub mod joints;
mod legs;
pub mod regions;
mod slices;
mod torso;
mod up_axis;

pub use cut::{cut_part, cut_part_along, Cutter, MIN_FACING_POCKET_SHARE, MIN_POCKET_SHARE};

use crate::anatomy::{BodyFrame, BodyGeometry, Landmark, LandmarkKind, PartName};
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::MeshError;
use crate::section::cloud::{ScanSectionError, ScanSectionOptions};
use crate::section::mesh::{Plane, SectionError, SectionLoop, SectionOptions};
use branches::Trunk;
use frame::{find_front, Found, Landmarking, Levels};
use graph::Graph;
use slices::AxisSlicer;
use std::fmt;
use thiserror::Error;
use up_axis::{orient_up, principal_axis, slice_along_axis};

/// Options of [`segment`]. Lengths are fractions of the body's height `H`,
/// areas fractions of the largest section area, so nothing depends on units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentOptions {
    /// The up direction (head above feet); `None` finds it (principal axis,
    /// sign from the feet). Default `None`.
    pub up: Option<Vec3>,
    /// The direction the body faces; `None` finds it from the feet.
    /// Default `None`.
    pub front: Option<Vec3>,
    /// Number of slices over the height (spacing `H / slices`). Default 400
    /// (about 4 mm on a 1.7 m body).
    pub slices: usize,
    /// Loops smaller than this fraction of the reference area (the largest
    /// loop of all slices, at most twice the 95th percentile of the slices'
    /// largest) are dropped. Default 0.008 (fingers and noise go, wrists
    /// and ankles stay).
    pub min_loop_area: Real,
    /// Dead-end branches shorter than this fraction of `H` are spurs and
    /// removed. Default 0.025.
    pub min_branch: Real,
    /// An arm must be at least this fraction of `H` long. Default 0.1.
    pub min_arm: Real,
    /// Half-width of the moving average that smooths part axes, as a
    /// fraction of `H`. Default 0.015.
    pub axis_smoothing: Real,
    /// The largest principal variance must exceed the second by this factor
    /// for the principal axis to be the up axis. Default 1.5.
    pub min_axis_ratio: Real,
    /// Plane-section options for meshes.
    pub section: SectionOptions,
    /// Slab-section options for clouds (used by [`cut_part`]; the slice
    /// graph takes `half_thickness` and `max_cells` from here).
    pub scan: ScanSectionOptions,
    /// Cell size of the slice graph's occupancy images for clouds, as a
    /// multiple of the point spacing. Default 2 (the graph needs where the
    /// parts are, not their outlines; 4 times fewer cells than the scan
    /// sections).
    pub graph_cell: Real,
    /// Closing radius (cells) of the graph's occupancy images. Default 0:
    /// cells of twice the spacing are already contiguous on a scanned
    /// surface, and any closing bridges the narrow gap between the thighs
    /// below the crotch (putting the crotch low). Rings broken by holes
    /// become arcs, which the graph's pruning absorbs.
    pub graph_closing: usize,
}

impl Default for SegmentOptions {
    fn default() -> Self {
        SegmentOptions {
            up: None,
            front: None,
            slices: 400,
            min_loop_area: 0.008,
            min_branch: 0.025,
            min_arm: 0.1,
            axis_smoothing: 0.015,
            min_axis_ratio: 1.5,
            section: SectionOptions::default(),
            scan: ScanSectionOptions::default(),
            graph_cell: 2.0,
            graph_closing: 0,
        }
    }
}

/// What went wrong in [`segment`] or [`cut_part`].
#[derive(Debug, Error, PartialEq)]
pub enum SegmentError {
    #[error("invalid input: {0}")]
    Input(#[from] MeshError),
    #[error("bad option {name}: {why}")]
    BadOption {
        name: &'static str,
        why: &'static str,
    },
    #[error("no up axis: the largest principal variance is only {ratio:.2} times the second (at least {needed} is needed for a standing body); the shape has no long axis — pass the up axis as an option")]
    NoUpAxis { ratio: Real, needed: Real },
    #[error("not a standing body: {what} not found ({why})")]
    NotAStandingBody { what: &'static str, why: String },
    #[error("section failed: {0}")]
    Section(#[from] SectionError),
    #[error("scan section failed: {0}")]
    ScanSection(#[from] ScanSectionError),
    #[error("the part {0} is not in this segmentation")]
    NoSuchPart(PartName),
    #[error("the plane perpendicular to {part} at {at} meets no loop of the part")]
    EmptyCut { part: PartName, at: Real },
}

/// A part and its axis.
#[derive(Clone, Debug, PartialEq)]
pub struct PartAxis {
    pub name: PartName,
    /// The smoothed axis from the proximal end (`start`) to the distal end
    /// (`end`); for torso and head upward. Evenly spaced by arc length,
    /// except the arms' shoulder extension (one point per cut, about a
    /// slice spacing apart).
    pub points: Vec<Point3>,
    /// Equivalent radius `√(A/π)` of the part's loops near each axis point
    /// (from the slices that built the axis).
    pub radii: Vec<Real>,
    pub start: LandmarkKind,
    pub end: LandmarkKind,
}

impl PartAxis {
    /// Length of the axis polyline.
    pub fn length(&self) -> Real {
        self.points.windows(2).map(|w| w[0].distance(w[1])).sum()
    }

    /// The point and unit tangent at arc-length fraction `t ∈ [0, 1]`
    /// (clamped). `None` for an axis with fewer than two distinct points.
    pub fn point_and_tangent(&self, t: Real) -> Option<(Point3, Vec3)> {
        let n = self.points.len();
        if n < 2 {
            return None;
        }
        let total = self.length();
        if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let target = t.clamp(0.0, 1.0) * total;
        let mut acc = 0.0;
        for k in 0..n - 1 {
            let d = self.points[k].distance(self.points[k + 1]);
            if acc + d >= target || k == n - 2 {
                let u = if d > 0.0 {
                    ((target - acc) / d).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let p = self.points[k] + (self.points[k + 1] - self.points[k]) * u;
                // Tangent: central difference over the neighbouring segments.
                let a = self.points[k.saturating_sub(1)];
                let b = self.points[(k + 2).min(n - 1)];
                let tan = (b - a)
                    .normalized()
                    .or_else(|| (self.points[k + 1] - self.points[k]).normalized())?;
                return Some((p, tan));
            }
            acc += d;
        }
        None
    }

    /// The largest equivalent radius along the part.
    pub fn max_radius(&self) -> Real {
        self.radii.iter().copied().fold(0.0, Real::max)
    }

    /// The equivalent radius at the axis point nearest `p`.
    pub fn radius_near(&self, p: Point3) -> Real {
        self.points
            .iter()
            .zip(&self.radii)
            .min_by(|a, b| a.0.distance(p).total_cmp(&b.0.distance(p)))
            .map_or(0.0, |(_, &r)| r)
    }

    /// The axis's point at height `level` along `up`: the crossing nearest
    /// its distal end. `None` when the axis does not reach it.
    pub fn point_at_level(&self, up: Vec3, level: Real) -> Option<Point3> {
        self.points.windows(2).rev().find_map(|w| {
            let (a, b) = (w[0].dot(up) - level, w[1].dot(up) - level);
            (a * b <= 0.0 && a != b).then(|| w[0] + (w[1] - w[0]) * (a / (a - b)))
        })
    }
}

/// The result of [`segment`].
#[derive(Clone, Debug, PartialEq)]
pub struct Segmentation {
    pub frame: BodyFrame,
    /// The body's extent along `up` (soles to head top), in input units.
    pub height: Real,
    /// Spacing of the slices used.
    pub slice_spacing: Real,
    /// The scan's estimated point spacing (clouds only).
    pub point_spacing: Option<Real>,
    /// The scan's estimated noise across its surface (clouds only; see
    /// [`crate::section::cloud::CloudSlicer::noise`]).
    pub point_noise: Option<Real>,
    pub landmarks: Vec<Landmark>,
    pub parts: Vec<PartAxis>,
    /// What was not found or is doubtful (a missing arm, a weak front).
    pub warnings: Vec<String>,
    /// For a cloud, its sort by height along `up` (the slicing's own),
    /// handed to the [`Cutter`]'s horizontal cuts.
    pub(crate) sorted_up: SortedUp,
}

#[cfg(test)]
impl Segmentation {
    /// A hand-made segmentation for tests: up +z, front −y, left +x, the
    /// origin at 0, slices 0.005 apart.
    pub(crate) fn z_up(height: Real, landmarks: Vec<Landmark>, parts: Vec<PartAxis>) -> Self {
        Segmentation {
            frame: BodyFrame {
                up: Vec3::new(0.0, 0.0, 1.0),
                front: Vec3::new(0.0, -1.0, 0.0),
                left: Vec3::new(1.0, 0.0, 0.0),
                origin: Point3::new(0.0, 0.0, 0.0),
            },
            height,
            slice_spacing: 0.005,
            point_spacing: None,
            point_noise: None,
            landmarks,
            parts,
            warnings: Vec::new(),
            sorted_up: Default::default(),
        }
    }
}

/// A cloud's point indices sorted by height along the frame's `up` (ties
/// by index) and those heights, as the [`Cutter`] sorts them: the
/// segmentation sorts the cloud along its slicing axis (`±up`) anyway, so
/// the cutter does not sort it again (a 200 000-point scan: a few ms on
/// one core). Not part of the segmentation's value: any two compare
/// equal.
#[derive(Clone, Default)]
pub(crate) struct SortedUp(Option<std::sync::Arc<HeightSort>>);

/// Point indices sorted by height along an axis (ties by index) and those
/// heights.
type HeightSort = (Vec<u32>, Vec<Real>);

impl PartialEq for SortedUp {
    fn eq(&self, _: &SortedUp) -> bool {
        true
    }
}

impl fmt::Debug for SortedUp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Some(s) => write!(f, "SortedUp({} points)", s.0.len()),
            None => write!(f, "SortedUp(None)"),
        }
    }
}

impl SortedUp {
    /// From the slicing's sort along its unit `axis` (indices and heights
    /// in ascending order) for `up = ±axis` exactly: the same when `up =
    /// axis`; reversed, heights negated, when `up = −axis` (`p·(−a) =
    /// −(p·a)` exactly; ties then run in descending index order, which the
    /// cutter does not see: it takes whole height ranges and sorts each
    /// slab itself). Nothing for another `up` (the cutter sorts then).
    fn along(sorted: Option<(Vec3, HeightSort)>, up: Vec3) -> SortedUp {
        SortedUp(
            sorted
                .and_then(|(axis, (mut order, mut heights))| {
                    if up == axis {
                        Some((order, heights))
                    } else if up == -axis {
                        order.reverse();
                        heights.reverse();
                        heights.iter_mut().for_each(|h| *h = -*h);
                        Some((order, heights))
                    } else {
                        None
                    }
                })
                .map(std::sync::Arc::new),
        )
    }
}

impl Segmentation {
    /// The landmark of a kind, when found.
    pub fn landmark(&self, kind: LandmarkKind) -> Option<&Landmark> {
        self.landmarks.iter().find(|l| l.kind == kind)
    }

    /// The part of a name, when found.
    pub fn part(&self, name: PartName) -> Option<&PartAxis> {
        self.parts.iter().find(|p| p.name == name)
    }

    /// The height along `up` of the lower armpit landmark (infinite when
    /// neither armpit was found).
    pub fn armpit_level(&self) -> Real {
        [LandmarkKind::LeftArmpit, LandmarkKind::RightArmpit]
            .iter()
            .filter_map(|&k| self.landmark(k))
            .map(|l| l.position.dot(self.frame.up))
            .fold(Real::INFINITY, Real::min)
    }
}

/// One plane section cut by [`cut_part`].
#[derive(Clone, Debug, PartialEq)]
pub struct PartCut {
    pub plane: Plane,
    /// The part's loop in that plane (for clouds: the slab outline).
    pub outline: SectionLoop,
    /// For clouds, the index in the cloud of each outline point.
    pub scan_indices: Option<Vec<usize>>,
}

/// Segments a standing body (see the module docs for the algorithm).
///
/// ```
/// use trigbody_core::internals::geom::shapes;
/// use trigbody_core::{segment, BodyGeometry, SegmentError, SegmentOptions, Vec3};
/// // A sphere has no long axis: a clear error, not a body.
/// let ball = shapes::uv_sphere(Vec3::ZERO, 1.0, 32, 64);
/// let err = segment(BodyGeometry::Mesh(&ball), &SegmentOptions::default()).unwrap_err();
/// assert!(matches!(err, SegmentError::NoUpAxis { .. }));
/// ```
pub fn segment(
    body: BodyGeometry<'_>,
    opts: &SegmentOptions,
) -> Result<Segmentation, SegmentError> {
    check_options(opts)?;
    let positions = body.positions();
    match body {
        BodyGeometry::Mesh(m) => m.validate()?,
        BodyGeometry::Cloud(c) => c.validate()?,
    }
    if positions.is_empty() {
        return Err(MeshError::NoVertices.into());
    }
    let mut warnings = Vec::new();

    // 1. Axis.
    let (axis, axis_given) = match opts.up {
        Some(u) => (
            u.normalized().ok_or(SegmentError::BadOption {
                name: "up",
                why: "must be a finite non-zero vector",
            })?,
            true,
        ),
        None => (principal_axis(body, opts.min_axis_ratio)?, false),
    };

    // 2. Slices.
    let (slicer, sorted_along_axis) = AxisSlicer::new_sorted(body, axis, opts)?;
    let mut slices = slice_along_axis(&slicer, positions, axis, opts)?;
    let n = opts.slices;
    let (min, max) = (slices.min, slices.max);
    let extent = max - min;
    let step = extent / n as Real;

    // 3. Sign.
    let up = if axis_given {
        axis
    } else {
        orient_up(&mut slices.raw, axis, n)?
    };
    // A point's height above the floor is p·up − floor, the floor being
    // the low end of the sliced range.
    let floor = if up.dot(axis) > 0.0 { min } else { -max };
    let lv = Levels {
        n,
        up,
        floor,
        extent,
        step,
    };

    // 4. Graph.
    let min_span = ((opts.min_branch * n as Real).ceil() as usize).max(2);
    let g = Graph::of_slices(slices.raw.iter().map(|(_, loops)| loops.clone()), min_span);

    // 5. Legs and crotch, the trunk path.
    let mut trunk = Trunk::find(&g, n, &mut warnings)?;

    // 6. Front, left.
    let front = find_front(&g, &trunk, &lv, opts.front, &mut warnings)?;
    let left = up.cross(front);
    // Legs: left/right by offset along `left`.
    trunk.left_leg_first(&g, left);

    // 7-8. Landmarks and axes.
    let stage = Landmarking {
        body,
        opts,
        spacing: slicer.spacing(),
        g: &g,
        lv,
        e1: slices.e1,
        e2: slices.e2,
        front,
        left,
        surface: std::sync::OnceLock::new(),
    };
    let mut out = Found {
        warnings,
        ..Found::default()
    };
    let (crotch, crotch_h) = stage.place_crotch(&trunk, &mut out);
    let armpit_slice = stage.place_arms(&trunk, crotch_h, &mut out);
    stage.place_torso_and_head(&trunk, armpit_slice, crotch, &mut out)?;
    stage.place_legs(&trunk, crotch, &mut out);

    let Found {
        mut landmarks,
        mut parts,
        warnings,
    } = out;
    landmarks.sort_by_key(|l| l.kind);
    parts.sort_by_key(|p| p.name);
    let origin = crotch - up * (crotch.dot(up) - floor);
    Ok(Segmentation {
        frame: BodyFrame {
            up,
            front,
            left,
            origin,
        },
        height: extent,
        slice_spacing: step,
        point_spacing: slicer.spacing(),
        point_noise: slicer.noise(),
        landmarks,
        parts,
        warnings,
        sorted_up: SortedUp::along(sorted_along_axis, up),
    })
}

fn check_options(o: &SegmentOptions) -> Result<(), SegmentError> {
    let frac = |v: Real| v.is_finite() && v > 0.0 && v < 1.0;
    if o.slices < 50 {
        return Err(SegmentError::BadOption {
            name: "slices",
            why: "at least 50 slices are needed to find a body's branches",
        });
    }
    if !frac(o.min_loop_area) {
        return Err(SegmentError::BadOption {
            name: "min_loop_area",
            why: "must be a fraction in (0, 1)",
        });
    }
    if !frac(o.min_branch)
        || !frac(o.min_arm)
        || !o.axis_smoothing.is_finite()
        || o.axis_smoothing < 0.0
    {
        return Err(SegmentError::BadOption {
            name: "min_branch, min_arm or axis_smoothing",
            why: "must be fractions of the height in (0, 1)",
        });
    }
    if !o.graph_cell.is_finite() || o.graph_cell <= 0.0 {
        return Err(SegmentError::BadOption {
            name: "graph_cell",
            why: "must be finite and positive",
        });
    }
    if !o.min_axis_ratio.is_finite() || o.min_axis_ratio < 1.0 {
        return Err(SegmentError::BadOption {
            name: "min_axis_ratio",
            why: "must be at least 1",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests;
