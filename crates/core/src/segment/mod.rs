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
//!    *trunk path* runs up from there, taking the child of largest area at
//!    any split, to a segment without children: the **head top**. The
//!    *arms* are the other segments without parents, at least
//!    [`SegmentOptions::min_arm`] × `H` long, whose chain merges into the
//!    trunk path above the crotch; the merge is the **armpit**, and the side
//!    is the sign of the arm's offset from the trunk along `left`.
//!    **T-pose:** an arm held out sideways never branches in horizontal
//!    slices, so when a side has no hanging arm the same graph is built on
//!    slices across the body (normal to `left`, from the outermost slice
//!    inward): a branch that starts in the outer tenth, lies above the
//!    crotch and merges into the trunk is the arm, the merge its armpit.
//!    A missing arm is a warning and a partial model; missing legs or a
//!    missing crotch are errors naming what was not found.
//! 6. **Front** ([`SegmentOptions::front`] if given): the feet point
//!    forward. For each leg, the area centroid of its slices 1-3 % of `H`
//!    above the floor minus that of its slices 6-9 % above it, made
//!    horizontal; the two legs' unit directions are averaged (each leg on
//!    its own, so a slightly tilted axis that cuts one foot lower does not
//!    pull the answer sideways). `left = up × front`. A foot that reaches
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
//! Not handled (reported, not guessed): a hand touching the thigh or hip
//! (the legs then do not merge only with each other: an error naming the
//! crotch, or an arm reported missing), arms above the head, sitting poses.
//! Fingers thinner than [`SegmentOptions::min_loop_area`] are not in the
//! graph; the arm's axis is extended from its last slice to the farthest
//! input point along the forearm-hand direction (the **hand tip**).

pub mod joints;

use crate::anatomy::{BodyFrame, BodyGeometry, Landmark, LandmarkKind, PartName};
use crate::geom::linalg::symmetric_eigen3;
use crate::geom::math::{Point2, Point3, Real, Vec2, Vec3};
use crate::geom::mesh::{Mesh, MeshError, PointCloud};
use crate::section::cloud::{
    height_key, keyed_heights, section_of_slab, sort_keyed, sorted_heights, CloudSlicer,
    ScanSectionError, ScanSectionOptions,
};
use crate::section::girth::convex_hull;
use crate::section::mesh::{
    point_in_polygon, polygon_area_centroid, section_mesh, MeshSlicer, Plane, SectionError,
    SectionLoop, SectionOptions,
};
use std::fmt;
use std::sync::OnceLock;
use thiserror::Error;

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
    /// below the crotch (measured on virtual scans: a closing of one cell
    /// put the crotch 3 % of the height low). Rings broken by holes become
    /// arcs, which the graph's pruning absorbs.
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
    pub landmarks: Vec<Landmark>,
    pub parts: Vec<PartAxis>,
    /// What was not found or is doubtful (a missing arm, a weak front).
    pub warnings: Vec<String>,
    /// For a cloud, its sort by height along `up` (the slicing's own),
    /// handed to the [`Cutter`]'s horizontal cuts.
    pub(crate) sorted_up: SortedUp,
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

// ---------------------------------------------------------------------------
// Slicing along one axis, for meshes and clouds alike.

/// Sections normal to one axis, from a mesh or a cloud, as graph nodes.
enum AxisSlicer<'a> {
    Mesh(MeshSlicer<'a>),
    Cloud(SlabComponents),
}

impl<'a> AxisSlicer<'a> {
    /// `spacing`: a cloud's point spacing when already known.
    fn new(
        body: BodyGeometry<'a>,
        axis: Vec3,
        opts: &SegmentOptions,
        spacing: Option<Real>,
    ) -> Result<AxisSlicer<'a>, SegmentError> {
        Ok(match body {
            BodyGeometry::Mesh(m) => AxisSlicer::Mesh(MeshSlicer::new(m, axis, &opts.section)?),
            BodyGeometry::Cloud(c) => {
                // The spacing estimate of the scan sections, so that both
                // agree on what a cell is.
                let spacing = match spacing {
                    Some(s) => s,
                    None => CloudSlicer::new(c, axis)?.spacing(),
                };
                let graph = ScanSectionOptions {
                    cell_size: Some(opts.scan.cell_size.unwrap_or(spacing) * opts.graph_cell),
                    closing_radius: opts.graph_closing,
                    ..opts.scan
                };
                AxisSlicer::Cloud(SlabComponents::new(&c.positions, axis, spacing, &graph)?)
            }
        })
    }

    /// [`AxisSlicer::new`] with the spacing estimated here, and for a
    /// cloud the estimate's sort by height (indices and heights,
    /// [`CloudSlicer`]'s) with the unit axis of those heights.
    fn new_sorted(
        body: BodyGeometry<'a>,
        axis: Vec3,
        opts: &SegmentOptions,
    ) -> Result<(AxisSlicer<'a>, Option<(Vec3, HeightSort)>), SegmentError> {
        match body {
            BodyGeometry::Mesh(_) => Ok((AxisSlicer::new(body, axis, opts, None)?, None)),
            BodyGeometry::Cloud(c) => {
                let cloud = CloudSlicer::new(c, axis)?;
                let slicer = AxisSlicer::new(body, axis, opts, Some(cloud.spacing()))?;
                Ok((slicer, Some((cloud.axis(), cloud.into_sorted()))))
            }
        }
    }

    fn range(&self) -> (Real, Real) {
        match self {
            AxisSlicer::Mesh(s) => s.range(),
            AxisSlicer::Cloud(s) => s.range(),
        }
    }

    fn spacing(&self) -> Option<Real> {
        match self {
            AxisSlicer::Mesh(_) => None,
            AxisSlicer::Cloud(s) => Some(s.spacing),
        }
    }

    /// The section's loops at `offset` as nodes (slice index 0, set by the
    /// caller); none where the plane misses or the slab is too thin. A
    /// mesh's loop nested in another (a pocket of skin inside a part, such
    /// as a modelled mouth) is no branch of the body: left out.
    fn nodes_at(&self, offset: Real, e1: Vec3, e2: Vec3) -> Vec<Node> {
        match self {
            AxisSlicer::Mesh(s) => s
                .section_at(offset)
                .map(|s| {
                    let nested = |l: &SectionLoop| {
                        s.loops
                            .iter()
                            .any(|o| o.area > l.area && o.contains(l.centroid))
                    };
                    s.loops
                        .iter()
                        .filter(|l| !nested(l))
                        .map(|l| Node::new(0, l, e1, e2))
                        .collect()
                })
                .unwrap_or_default(),
            AxisSlicer::Cloud(s) => s.nodes_at(offset, e1, e2),
        }
    }
}

/// Slabs of a point cloud reduced to what the slice graph needs: the
/// connected components of each slab's occupancy image (the construction
/// of [`CloudSlicer`]: cells of the point spacing, a morphological closing,
/// 8-connected components) with their filled area, area centroid and the
/// convex hull of their points. Ordering the points along each loop (what
/// the curve fit needs, and most of [`CloudSlicer::section_at`]'s time) is
/// skipped: the graph only asks where a part is and how big.
#[derive(Debug)]
struct SlabComponents {
    axis: Vec3,
    /// Points and heights in bin order (sorted by bin, not within a bin).
    points: Vec<Point3>,
    heights: Vec<Real>,
    /// Bin `b` holds `points[bin_start[b]..bin_start[b + 1]]`.
    bin_start: Vec<usize>,
    bin_low: Real,
    bin_width: Real,
    range: (Real, Real),
    spacing: Real,
    half_thickness: Real,
    cell: Real,
    closing: usize,
    min_points: usize,
    max_cells: usize,
}

impl SlabComponents {
    fn new(
        points: &[Point3],
        axis: Vec3,
        spacing: Real,
        o: &ScanSectionOptions,
    ) -> Result<SlabComponents, SegmentError> {
        let axis = axis.normalized().ok_or(SegmentError::BadOption {
            name: "up",
            why: "must be a finite non-zero vector",
        })?;
        let len = |v: Option<Real>, name: &'static str| match v {
            None => Ok(spacing),
            Some(x) if x.is_finite() && x > 0.0 => Ok(x),
            Some(_) => Err(SegmentError::BadOption {
                name,
                why: "must be finite and positive",
            }),
        };
        // Bucket (counting) sort by height into bins of about a quarter
        // of the point spacing: linear time, and a slab is a run of bins
        // (points of its two end bins are checked one by one).
        let heights: Vec<Real> = points.iter().map(|p| p.dot(axis)).collect();
        let (lo, hi) = heights
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), &h| {
                (a.min(h), b.max(h))
            });
        let bins =
            (((hi - lo) / (0.25 * spacing)).ceil() as usize).clamp(1, 4 * points.len().max(1));
        let width = ((hi - lo) / bins as Real).max(Real::MIN_POSITIVE);
        let bin_of = |h: Real| (((h - lo) / width) as usize).min(bins - 1);
        // Each point's bin and the bins' counts, each bin's points'
        // indices (in index order), then the points and heights gathered
        // in that order, side by side on two cores (written in sequence,
        // no zero-filled arrays first).
        let mut start = vec![0usize; bins + 1];
        let bin: Vec<usize> = heights
            .iter()
            .map(|&h| {
                let b = bin_of(h);
                start[b + 1] += 1;
                b
            })
            .collect();
        for b in 0..bins {
            start[b + 1] += start[b];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; points.len()];
        for (i, &b) in bin.iter().enumerate() {
            order[fill[b]] = i as u32;
            fill[b] += 1;
        }
        let (sorted_points, sorted_heights): (Vec<Point3>, Vec<Real>) = crate::geom::parallel::join(
            || order.iter().map(|&i| points[i as usize]).collect(),
            || order.iter().map(|&i| heights[i as usize]).collect(),
        );
        Ok(SlabComponents {
            axis,
            heights: sorted_heights,
            points: sorted_points,
            bin_start: start,
            bin_low: lo,
            bin_width: width,
            range: (lo, hi),
            spacing,
            half_thickness: len(o.half_thickness, "scan.half_thickness")?,
            cell: len(o.cell_size, "scan.cell_size")?,
            closing: o.closing_radius,
            min_points: o.min_component_points.max(3),
            max_cells: o.max_cells.max(64),
        })
    }

    fn range(&self) -> (Real, Real) {
        self.range
    }

    fn nodes_at(&self, offset: Real, e1: Vec3, e2: Vec3) -> Vec<Node> {
        let t = self.half_thickness;
        let bins = self.bin_start.len() - 1;
        let bin = |h: Real| ((h - self.bin_low) / self.bin_width).floor();
        let (b0, b1) = (bin(offset - t), bin(offset + t));
        if !(b0.is_finite() && b1.is_finite()) || b1 < 0.0 || b0 >= bins as Real {
            return Vec::new();
        }
        let (b0, b1) = ((b0.max(0.0)) as usize, (b1 as usize).min(bins - 1));
        let range = self.bin_start[b0]..self.bin_start[b1 + 1];
        let pts: Vec<Point2> = range
            .filter(|&i| (self.heights[i] - offset).abs() <= t)
            .map(|i| {
                let p = self.points[i];
                Vec2::new(p.dot(e1), p.dot(e2))
            })
            .collect();
        if pts.len() < self.min_points {
            return Vec::new();
        }
        let (mut min, mut max) = (pts[0], pts[0]);
        for p in &pts {
            min = Vec2::new(min.x.min(p.x), min.y.min(p.y));
            max = Vec2::new(max.x.max(p.x), max.y.max(p.y));
        }
        let r = self.closing;
        let margin = (r + 2) as Real;
        let mut g = self.cell;
        let dims = |g: Real| {
            (
                ((max.x - min.x) / g + 2.0 * margin).ceil() as usize + 1,
                ((max.y - min.y) / g + 2.0 * margin).ceil() as usize + 1,
            )
        };
        while {
            let (w, h) = dims(g);
            w.saturating_mul(h) > self.max_cells
        } {
            g *= 1.5;
        }
        let (w, h) = dims(g);
        let origin = min - Vec2::new(margin * g, margin * g);
        let cell_of = |p: Point2| {
            let x = (((p.x - origin.x) / g) as usize).min(w - 1);
            let y = (((p.y - origin.y) / g) as usize).min(h - 1);
            y * w + x
        };
        let mut img = vec![false; w * h];
        let cells: Vec<usize> = pts.iter().map(|&p| cell_of(p)).collect();
        for &c in &cells {
            img[c] = true;
        }
        let img = if r > 0 {
            box_filter(&box_filter(&img, w, h, r, true), w, h, r, false)
        } else {
            img
        };
        // 8-connected components.
        let mut label = vec![u32::MAX; w * h];
        let mut comps: Vec<Vec<usize>> = Vec::new();
        let mut stack = Vec::new();
        for start in 0..w * h {
            if !img[start] || label[start] != u32::MAX {
                continue;
            }
            let id = comps.len() as u32;
            let mut members = Vec::new();
            label[start] = id;
            stack.push(start);
            while let Some(c) = stack.pop() {
                members.push(c);
                let (x, y) = ((c % w) as isize, (c / w) as isize);
                for dy in -1..=1isize {
                    for dx in -1..=1isize {
                        let (nx, ny) = (x + dx, y + dy);
                        if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                            continue;
                        }
                        let nc = ny as usize * w + nx as usize;
                        if img[nc] && label[nc] == u32::MAX {
                            label[nc] = id;
                            stack.push(nc);
                        }
                    }
                }
            }
            comps.push(members);
        }
        let mut comp_points: Vec<Vec<Point2>> = vec![Vec::new(); comps.len()];
        for (k, &c) in cells.iter().enumerate() {
            if let Some(v) = comp_points.get_mut(label[c] as usize) {
                v.push(pts[k]);
            }
        }
        let mut out = Vec::new();
        for id in 0..comps.len() {
            if comp_points[id].len() < self.min_points {
                continue;
            }
            // Area and centroid of the convex hull of the points: a ring
            // broken by a scanner hole has no inside to fill, but its hull
            // is still the section's outline (over-counting only the
            // concavities).
            let hull = convex_hull(&comp_points[id]);
            let Some((area, c2)) = polygon_area_centroid(&hull) else {
                continue;
            };
            let area = area.abs();
            out.push(Node::from_parts(
                0,
                self.axis * offset + e1 * c2.x + e2 * c2.y,
                c2,
                area,
                hull,
            ));
        }
        out
    }
}

/// Dilation (`dilate`) or erosion of a binary image by a square of radius
/// `r`, separably (rows, then columns) with running counts.
fn box_filter(img: &[bool], w: usize, h: usize, r: usize, dilate: bool) -> Vec<bool> {
    let pass = |src: &[bool], len: usize, lines: usize, at: &dyn Fn(usize, usize) -> usize| {
        let mut out = vec![false; src.len()];
        for line in 0..lines {
            let mut count = 0usize;
            // Window [i - r, i + r]; out of range counts as unset.
            for i in 0..r.min(len) {
                count += usize::from(src[at(line, i)]);
            }
            for i in 0..len {
                if i + r < len {
                    count += usize::from(src[at(line, i + r)]);
                }
                if i > r {
                    count -= usize::from(src[at(line, i - r - 1)]);
                }
                let full = 2 * r + 1;
                out[at(line, i)] = if dilate { count > 0 } else { count == full };
            }
        }
        out
    };
    let rows = pass(img, w, h, &|line, i| line * w + i);
    pass(&rows, h, w, &|line, i| i * w + line)
}

/// A loop of the slice graph, in the slices' common plane coordinates.
#[derive(Clone, Debug)]
struct Node {
    slice: usize,
    centroid: Point3,
    c2: Point2,
    area: Real,
    radius: Real,
    hull_girth: Real,
    poly: Vec<Point2>,
    lo: Point2,
    hi: Point2,
    active: bool,
}

impl Node {
    fn from_parts(
        slice: usize,
        centroid: Point3,
        c2: Point2,
        area: Real,
        poly: Vec<Point2>,
    ) -> Node {
        let (mut lo, mut hi) = (
            Vec2::new(Real::INFINITY, Real::INFINITY),
            Vec2::new(Real::NEG_INFINITY, Real::NEG_INFINITY),
        );
        for p in &poly {
            lo = Vec2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Vec2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        Node {
            slice,
            centroid,
            c2,
            area,
            radius: (area / std::f64::consts::PI).sqrt(),
            hull_girth: hull_perimeter(&poly),
            poly,
            lo,
            hi,
            active: true,
        }
    }

    fn new(slice: usize, l: &SectionLoop, e1: Vec3, e2: Vec3) -> Node {
        let poly: Vec<Point2> = l
            .points
            .iter()
            .map(|&p| Vec2::new(p.dot(e1), p.dot(e2)))
            .collect();
        let c2 = Vec2::new(l.centroid.dot(e1), l.centroid.dot(e2));
        Node::from_parts(slice, l.centroid, c2, l.area, poly)
    }

    fn overlaps(&self, o: &Node) -> bool {
        if self.hi.x < o.lo.x || o.hi.x < self.lo.x || self.hi.y < o.lo.y || o.hi.y < self.lo.y {
            return false;
        }
        (self.c2 - o.c2).norm() < 0.5 * (self.radius + o.radius)
            || point_in_polygon(self.c2, &o.poly)
            || point_in_polygon(o.c2, &self.poly)
    }
}

/// Perimeter of a closed polygon.
fn perimeter_2d(p: &[Point2]) -> Real {
    let m = p.len();
    (0..m).map(|i| (p[(i + 1) % m] - p[i]).norm()).sum()
}

/// Perimeter of the convex hull of `p`: a girth that ignores concavities,
/// gaps between fingers and scan noise.
fn hull_perimeter(p: &[Point2]) -> Real {
    perimeter_2d(&convex_hull(p))
}

/// The slice graph: nodes, links, and segments (maximal one-to-one chains).
struct Graph {
    nodes: Vec<Node>,
    /// Per node: linked nodes above / below.
    up: Vec<Vec<usize>>,
    down: Vec<Vec<usize>>,
    segments: Vec<Segment>,
    seg_of: Vec<usize>,
}

#[derive(Clone, Debug, Default)]
struct Segment {
    nodes: Vec<usize>,
    parents: Vec<usize>,
    children: Vec<usize>,
}

const NO_SEG: usize = usize::MAX;

/// Most slices a link may skip (see [`Graph::new`]).
const MAX_BRIDGE: usize = 3;

/// A short inner segment with less than this fraction of the area of its
/// largest neighbour is a fragment and removed.
const FRAGMENT_AREA: Real = 0.3;

impl Graph {
    /// `slices[k]` are the node ids of slice `k`, bottom to top.
    /// The graph of the loops of consecutive slices (slice `k` the `k`-th
    /// item), with dead-end branches shorter than `min_span` slices pruned.
    fn of_slices(slices: impl IntoIterator<Item = Vec<Node>>, min_span: usize) -> Graph {
        let mut nodes = Vec::new();
        let mut slice_nodes = Vec::new();
        for (k, loops) in slices.into_iter().enumerate() {
            let mut ids = Vec::with_capacity(loops.len());
            for mut node in loops {
                node.slice = k;
                nodes.push(node);
                ids.push(nodes.len() - 1);
            }
            slice_nodes.push(ids);
        }
        let mut g = Graph::new(nodes, &slice_nodes);
        g.prune(min_span);
        g
    }

    fn new(nodes: Vec<Node>, slices: &[Vec<usize>]) -> Graph {
        let n = nodes.len();
        let mut g = Graph {
            nodes,
            up: vec![Vec::new(); n],
            down: vec![Vec::new(); n],
            segments: Vec::new(),
            seg_of: vec![NO_SEG; n],
        };
        for k in 0..slices.len().saturating_sub(1) {
            for &a in &slices[k] {
                for &b in &slices[k + 1] {
                    if g.nodes[a].overlaps(&g.nodes[b]) {
                        g.up[a].push(b);
                        g.down[b].push(a);
                    }
                }
            }
        }
        // Bridge up to MAX_BRIDGE slices where a loop is missing (a scan
        // slab that lost it, a garbled loop that was dropped): a loop with
        // no link upward links to the nearest later slice with an
        // overlapping loop that has no link downward.
        for k in 0..slices.len() {
            for &a in &slices[k] {
                if !g.up[a].is_empty() {
                    continue;
                }
                for gap in 2..=MAX_BRIDGE + 1 {
                    let Some(later) = slices.get(k + gap) else {
                        break;
                    };
                    let found: Vec<usize> = later
                        .iter()
                        .copied()
                        .filter(|&b| g.down[b].is_empty() && g.nodes[a].overlaps(&g.nodes[b]))
                        .collect();
                    if !found.is_empty() {
                        for b in found {
                            g.up[a].push(b);
                            g.down[b].push(a);
                        }
                        break;
                    }
                }
            }
        }
        g
    }

    fn active_up(&self, a: usize) -> Vec<usize> {
        self.up[a]
            .iter()
            .copied()
            .filter(|&b| self.nodes[b].active)
            .collect()
    }

    fn active_down(&self, a: usize) -> Vec<usize> {
        self.down[a]
            .iter()
            .copied()
            .filter(|&b| self.nodes[b].active)
            .collect()
    }

    /// Rebuilds the segments from the active nodes (nodes are stored in
    /// slice order, so a single pass sees every node after those below it).
    fn build_segments(&mut self) {
        self.segments.clear();
        self.seg_of.iter_mut().for_each(|s| *s = NO_SEG);
        for a in 0..self.nodes.len() {
            if !self.nodes[a].active {
                continue;
            }
            let down = self.active_down(a);
            let cont = if down.len() == 1 && self.active_up(down[0]).len() == 1 {
                Some(self.seg_of[down[0]])
            } else {
                None
            };
            match cont {
                Some(s) if s != NO_SEG => {
                    self.segments[s].nodes.push(a);
                    self.seg_of[a] = s;
                }
                _ => {
                    self.segments.push(Segment {
                        nodes: vec![a],
                        ..Default::default()
                    });
                    self.seg_of[a] = self.segments.len() - 1;
                }
            }
        }
        for s in 0..self.segments.len() {
            let first = self.segments[s].nodes[0];
            let mut parents: Vec<usize> = self
                .active_down(first)
                .iter()
                .map(|&b| self.seg_of[b])
                .collect();
            parents.sort_unstable();
            parents.dedup();
            for &p in &parents {
                self.segments[p].children.push(s);
            }
            self.segments[s].parents = parents;
        }
        for s in &mut self.segments {
            s.children.sort_unstable();
            s.children.dedup();
        }
    }

    fn span(&self, s: usize) -> usize {
        let seg = &self.segments[s];
        let a = self.nodes[seg.nodes[0]].slice;
        let b = self.nodes[seg.nodes[seg.nodes.len() - 1]].slice;
        b - a + 1
    }

    fn mean_area(&self, s: usize) -> Real {
        let seg = &self.segments[s];
        seg.nodes.iter().map(|&a| self.nodes[a].area).sum::<Real>() / seg.nodes.len() as Real
    }

    /// Removes spurs, isolated scraps and the smaller side of bubbles
    /// shorter than `min_span` slices; repeats until stable.
    fn prune(&mut self, min_span: usize) {
        for _round in 0..100 {
            self.build_segments();
            let mut remove: Vec<usize> = Vec::new();
            let mut inner: Vec<usize> = Vec::new();
            for s in 0..self.segments.len() {
                let seg = &self.segments[s];
                if self.span(s) >= min_span {
                    continue;
                }
                if seg.parents.is_empty() || seg.children.is_empty() {
                    remove.push(s);
                    continue;
                }
                // Fragment: a short piece much smaller than its neighbours
                // (a trunk loop that broke for a slice or two in a scan).
                let neighbour_area = seg
                    .parents
                    .iter()
                    .chain(seg.children.iter())
                    .map(|&o| self.mean_area(o))
                    .fold(0.0, Real::max);
                let fragment = self.mean_area(s) < FRAGMENT_AREA * neighbour_area;
                // Bubble: a larger sibling shares its parent and child.
                let bubble = seg.parents.iter().any(|&p| {
                    self.segments[p].children.iter().any(|&o| {
                        o != s
                            && self.mean_area(o) >= self.mean_area(s)
                            && self.segments[o]
                                .children
                                .iter()
                                .any(|c| seg.children.contains(c))
                    })
                });
                if fragment || bubble {
                    inner.push(s);
                }
            }
            // Inner pieces go smallest first, and only while every parent
            // keeps a child and every child a parent: a trunk that split
            // into several pieces for a slice keeps its largest one.
            inner.sort_by(|&a, &b| self.mean_area(a).total_cmp(&self.mean_area(b)));
            let mut gone = vec![false; self.segments.len()];
            for &s in &remove {
                gone[s] = true;
            }
            for s in inner {
                let seg = &self.segments[s];
                let keeps = seg.parents.iter().all(|&p| {
                    self.segments[p]
                        .children
                        .iter()
                        .any(|&o| o != s && !gone[o])
                }) && seg
                    .children
                    .iter()
                    .all(|&c| self.segments[c].parents.iter().any(|&o| o != s && !gone[o]));
                if keeps {
                    gone[s] = true;
                    remove.push(s);
                }
            }
            if remove.is_empty() {
                return;
            }
            for s in remove {
                for &a in &self.segments[s].nodes {
                    self.nodes[a].active = false;
                }
            }
        }
        self.build_segments();
    }

    /// Follows single continuations upward from segment `s` until the chain
    /// reaches a segment with several parents (a merge) or ends. Returns
    /// the chain's segments and the merge segment.
    fn chain_up(&self, s: usize) -> (Vec<usize>, Option<usize>) {
        let mut chain = vec![s];
        let mut cur = s;
        loop {
            let children = &self.segments[cur].children;
            if children.len() != 1 {
                return (chain, None);
            }
            let c = children[0];
            if self.segments[c].parents.len() > 1 {
                return (chain, Some(c));
            }
            if chain.contains(&c) {
                return (chain, None);
            }
            chain.push(c);
            cur = c;
        }
    }

    fn chain_nodes(&self, chain: &[usize]) -> Vec<usize> {
        chain
            .iter()
            .flat_map(|&s| self.segments[s].nodes.iter().copied())
            .collect()
    }
}

// ---------------------------------------------------------------------------

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
    let (mut min, mut max) = slicer.range();
    let n = opts.slices;
    // Plane coordinates shared by all slices (any orthonormal pair ⊥ axis).
    let (e1, e2) = {
        let e1 = axis.any_perpendicular();
        (e1, axis.cross(e1))
    };
    // Slice, drop small loops; then, if two or more slices at an end hold
    // nothing (stray scan points far beyond the body), slice again over
    // the range that holds loops, so that H is the body's height.
    let mut raw: Vec<(Real, Vec<Node>)>;
    let mut pass = 0;
    loop {
        if (max - min).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(SegmentError::NotAStandingBody {
                what: "a body",
                why: "the input has no extent along the up axis".into(),
            });
        }
        let step = (max - min) / n as Real;
        // Independent slices, split over the cores (in order).
        let ks: Vec<usize> = (0..n).collect();
        raw = crate::geom::parallel::parallel_map(&ks, 32, |run| {
            run.iter()
                .map(|&k| {
                    let off = min + (k as Real + 0.5) * step;
                    (off, slicer.nodes_at(off, e1, e2))
                })
                .collect()
        });
        let largest = raw
            .iter()
            .flat_map(|(_, l)| l.iter().map(|l| l.area))
            .fold(0.0, Real::max);
        if largest.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(SegmentError::NotAStandingBody {
                what: "a body",
                why: "no slice has a closed loop".into(),
            });
        }
        // The reference area is the largest loop, but at most twice the
        // 95th percentile of the slices' largest loops: a horizontal slice
        // along arms held out sideways is several times the trunk's area
        // (measured 6.6 times the 95th percentile on a T-pose scan), and
        // against it a scan's ankles fell out of the graph and took the
        // feet with them. Standing bodies' largest loops (hips, chest) are
        // 1.02-1.40 times that percentile, so they keep the largest.
        let mut per_slice: Vec<Real> = raw
            .iter()
            .filter_map(|(_, l)| l.iter().map(|l| l.area).reduce(Real::max))
            .collect();
        per_slice.sort_by(Real::total_cmp);
        let p95 = per_slice[(per_slice.len() * 19 / 20).min(per_slice.len() - 1)];
        let reference = largest.min(2.0 * p95);
        for (_, loops) in &mut raw {
            loops.retain(|l| l.area >= opts.min_loop_area * reference);
        }
        let first = raw.iter().position(|r| !r.1.is_empty()).unwrap_or(0);
        let last = raw.iter().rposition(|r| !r.1.is_empty()).unwrap_or(n - 1);
        if pass == 1 || (first < 2 && last + 2 >= n) {
            break;
        }
        pass += 1;
        // The extreme points within a slice of the occupied range.
        let (lo, hi) = (
            min + first as Real * step - step,
            min + (last + 1) as Real * step + step,
        );
        let (a, b) = positions
            .iter()
            .map(|p| p.dot(axis))
            .filter(|h| (lo..=hi).contains(h))
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), h| {
                (a.min(h), b.max(h))
            });
        min = a;
        max = b;
    }
    let extent = max - min;
    let step = extent / n as Real;

    // 3. Sign.
    let up = if axis_given {
        axis
    } else {
        let share = |range: std::ops::Range<Real>| {
            let (mut multi, mut total) = (0usize, 0usize);
            for k in 0..n {
                let f = (k as Real + 0.5) / n as Real;
                if range.contains(&f) && !raw[k].1.is_empty() {
                    total += 1;
                    multi += usize::from(raw[k].1.len() >= 2);
                }
            }
            multi as Real / total.max(1) as Real
        };
        // The slices' area centroid as a fraction of the extent: the trunk,
        // whose sections are the largest, lies above the long thin legs in
        // every standing pose, raised arms included (0.57-0.60 on the
        // development bodies, arms down or raised), so the centroid lies
        // nearer the head.
        let centroid = {
            let (mut m, mut mh) = (0.0, 0.0);
            for (k, (_, loops)) in raw.iter().enumerate() {
                let a: Real = loops.iter().map(|l| l.area).sum();
                m += a;
                mh += a * (k as Real + 0.5) / n as Real;
            }
            mh / m.max(Real::MIN_POSITIVE)
        };
        let low = share(0.02..0.09);
        let high = share(0.91..0.98);
        // Both ends branch (arms raised above the head): the feet are the
        // end farther from the area centroid.
        let both = low >= 0.5 && high >= 0.5 && (low - high).abs() < 0.5;
        if low >= high + 0.5 || (both && centroid >= 0.53) {
            axis
        } else if high >= low + 0.5 || (both && centroid <= 0.47) {
            raw.reverse();
            -axis
        } else {
            return Err(SegmentError::NotAStandingBody {
                what: "two feet at either end of the longest axis",
                why: format!(
                    "slices with two or more loops: {:.0} % near one end, {:.0} % near the other, the volume centroid at {:.2} of the extent; pass the up axis",
                    100.0 * low,
                    100.0 * high,
                    centroid
                ),
            });
        }
    };
    // Heights above the soles: slice k sits at (k + ½) step.
    let height_of = |slice: usize| (slice as Real + 0.5) * step;

    // 4. Graph.
    let min_span = ((opts.min_branch * n as Real).ceil() as usize).max(2);
    let g = Graph::of_slices(raw.iter().map(|(_, loops)| loops.clone()), min_span);

    // 5. Legs and crotch.
    let roots: Vec<usize> = (0..g.segments.len())
        .filter(|&s| g.segments[s].parents.is_empty())
        .collect();
    let low_limit = n / 10;
    let mut leg_roots: Vec<usize> = roots
        .iter()
        .copied()
        .filter(|&s| g.nodes[g.segments[s].nodes[0]].slice <= low_limit)
        .collect();
    if leg_roots.len() < 2 {
        return Err(SegmentError::NotAStandingBody {
            what: "two legs",
            why: format!(
                "{} branch(es) start in the lowest tenth of the height; the lowest slices never split into two feet",
                leg_roots.len()
            ),
        });
    }
    if leg_roots.len() > 2 {
        // Keep the two longest.
        leg_roots.sort_by_key(|&s| std::cmp::Reverse(g.chain_nodes(&g.chain_up(s).0).len()));
        warnings.push(format!(
            "{} branches start near the floor; the two longest are taken as legs",
            leg_roots.len()
        ));
        leg_roots.truncate(2);
    }
    let (chain_a, merge_a) = g.chain_up(leg_roots[0]);
    let (chain_b, merge_b) = g.chain_up(leg_roots[1]);
    let crotch_seg = match (merge_a, merge_b) {
        (Some(a), Some(b)) if a == b => a,
        _ => {
            return Err(SegmentError::NotAStandingBody {
                what: "the crotch",
                why: "the two legs never merge into one trunk loop (or merge with another branch first, e.g. a hand touching a thigh)".into(),
            })
        }
    };
    let mut leg_nodes = [g.chain_nodes(&chain_a), g.chain_nodes(&chain_b)];

    // Trunk path: up from the crotch, biggest child at any split.
    let mut trunk_segs = vec![crotch_seg];
    let mut cur = crotch_seg;
    loop {
        let children = &g.segments[cur].children;
        let Some(&next) = children
            .iter()
            .filter(|c| !trunk_segs.contains(c))
            .max_by(|&&a, &&b| g.mean_area(a).total_cmp(&g.mean_area(b)))
        else {
            break;
        };
        trunk_segs.push(next);
        cur = next;
    }
    let trunk_nodes = g.chain_nodes(&trunk_segs);
    let top_node = *trunk_nodes
        .last()
        .unwrap_or(&g.segments[crotch_seg].nodes[0]);
    let crotch_node = g.segments[crotch_seg].nodes[0];
    let crotch_slice = g.nodes[crotch_node].slice;
    if g.nodes[top_node].slice < crotch_slice + n / 5 {
        return Err(SegmentError::NotAStandingBody {
            what: "a trunk above the crotch",
            why: "the branch above the legs' junction ends within a fifth of the height".into(),
        });
    }

    // 6. Front, left.
    let front = match opts.front {
        Some(f) => (f - up * f.dot(up))
            .normalized()
            .ok_or(SegmentError::BadOption {
                name: "front",
                why: "must be finite, non-zero and not parallel to up",
            })?,
        None => {
            // Per leg: the area centroid of its foot's loops 1-3 % of the
            // height above the floor minus that of its loops 6-9 % above
            // it; the two legs' unit directions are averaged (one leg at a
            // time, so a slightly tilted axis that cuts one foot lower than
            // the other does not pull the answer sideways). A foot's loops
            // are every loop at those heights nearer (across `up`) to its
            // leg than to the other leg, not only its own branch: a scan
            // that sees a foot's top but not its sole shows heel and toes
            // as separate loops near the floor, and the heel's branch
            // alone pointed the body backwards.
            let band = |nodes: &[usize], lo: Real, hi: Real| {
                let (mut s, mut w) = (Vec3::ZERO, 0.0);
                for &a in nodes {
                    let f = (g.nodes[a].slice as Real + 0.5) / n as Real;
                    if f >= lo && f < hi {
                        s += g.nodes[a].centroid * g.nodes[a].area;
                        w += g.nodes[a].area;
                    }
                }
                (w > 0.0).then(|| s / w)
            };
            let all: Vec<usize> = (0..g.nodes.len()).collect();
            let across = |p: Point3| p - up * p.dot(up);
            let refs = [&chain_a, &chain_b].map(|c| {
                let nodes = g.chain_nodes(c);
                band(&nodes, 0.06, 0.09).or_else(|| nodes.first().map(|&a| g.nodes[a].centroid))
            });
            let leg_dir = |mine: usize| {
                let (Some(me), Some(other)) = (refs[mine], refs[1 - mine]) else {
                    return Vec3::ZERO;
                };
                let foot: Vec<usize> = all
                    .iter()
                    .copied()
                    .filter(|&a| {
                        let c = across(g.nodes[a].centroid);
                        (c - across(me)).norm() < (c - across(other)).norm()
                    })
                    .collect();
                match (band(&foot, 0.01, 0.03), band(&foot, 0.06, 0.09)) {
                    (Some(a), Some(b)) => {
                        let d = a - b;
                        d - up * d.dot(up)
                    }
                    _ => Vec3::ZERO,
                }
            };
            let (da, db) = (leg_dir(0), leg_dir(1));
            let dir = (da.normalized().unwrap_or(Vec3::ZERO)
                + db.normalized().unwrap_or(Vec3::ZERO))
                * (0.25 * (da.norm() + db.norm()));
            if dir.norm() < 0.005 * extent {
                warnings.push(format!(
                    "front direction weakly determined: the feet reach only {:.2} % of the height in front of the ankles",
                    100.0 * dir.norm() / extent
                ));
            }
            dir.normalized().unwrap_or_else(|| up.any_perpendicular())
        }
    };
    let left = up.cross(front);

    // A point's height above the floor is p·up − floor, the floor being
    // the low end of the sliced range.
    let floor = if up.dot(axis) > 0.0 { min } else { -max };
    let hfrac = |p: Point3| (p.dot(up) - floor) / extent;
    let at_height = |p: Point3, h: Real| p + up * (floor + h - p.dot(up));

    // Legs: left/right by offset along `left`.
    let side = |nodes: &[usize]| {
        nodes
            .iter()
            .map(|&a| g.nodes[a].centroid.dot(left))
            .sum::<Real>()
            / nodes.len().max(1) as Real
    };
    if side(&leg_nodes[0]) < side(&leg_nodes[1]) {
        leg_nodes.swap(0, 1);
    }
    let mut landmarks = Vec::new();
    let mut parts = Vec::new();

    // Crotch.
    let leg_tops = [
        g.nodes[*leg_nodes[0].last().unwrap_or(&crotch_node)].centroid,
        g.nodes[*leg_nodes[1].last().unwrap_or(&crotch_node)].centroid,
    ];
    let crotch_h = height_of(crotch_slice) - 0.5 * step;
    let crotch = at_height((leg_tops[0] + leg_tops[1]) * 0.5, crotch_h);
    landmarks.push(Landmark {
        kind: LandmarkKind::Crotch,
        position: crotch,
        height_fraction: crotch_h / extent,
        confidence: 1.0,
        how: "the legs' branches merge into the trunk",
    });

    // Arms.
    let trunk_set: std::collections::HashSet<usize> = trunk_segs.iter().copied().collect();
    let mut arm_found: [Option<(Vec<usize>, usize)>; 2] = [None, None];
    let min_arm = (opts.min_arm * n as Real) as usize;
    let leg_seg_set: Vec<usize> = chain_a.iter().chain(chain_b.iter()).copied().collect();
    for &r in &roots {
        if leg_seg_set.contains(&r) {
            continue;
        }
        let (chain, merge) = g.chain_up(r);
        let Some(m) = merge else { continue };
        if !trunk_set.contains(&m) || m == crotch_seg {
            continue;
        }
        let nodes = g.chain_nodes(&chain);
        let span = g.nodes[*nodes.last().unwrap_or(&0)].slice - g.nodes[nodes[0]].slice + 1;
        if span < min_arm {
            continue;
        }
        // Side relative to the trunk loop at the merge.
        let merge_c = g.nodes[g.segments[m].nodes[0]].centroid;
        let off = side(&nodes) - merge_c.dot(left);
        let k = if off > 0.0 { 0 } else { 1 };
        let better = match &arm_found[k] {
            None => true,
            Some((old, _)) => nodes.len() > old.len(),
        };
        if better {
            arm_found[k] = Some((nodes, m));
        }
    }

    // Highest armpit (for the neck search).
    let mut armpit_slice = crotch_slice;
    for (k, found) in arm_found.iter().enumerate() {
        let (arm, tip, wrist, pit, pname) = if k == 0 {
            (
                PartName::LeftArm,
                LandmarkKind::LeftHandTip,
                LandmarkKind::LeftWrist,
                LandmarkKind::LeftArmpit,
                "left arm",
            )
        } else {
            (
                PartName::RightArm,
                LandmarkKind::RightHandTip,
                LandmarkKind::RightWrist,
                LandmarkKind::RightArmpit,
                "right arm",
            )
        };
        let Some((nodes, m)) = found else {
            // No arm hangs from the trunk on this side: look for one held
            // out sideways (T-pose) in slices across the body.
            let side = if k == 0 { left } else { -left };
            let lateral = lateral_arm(
                body,
                opts,
                slicer.spacing(),
                side,
                up,
                floor + crotch_h,
                opts.min_arm * extent,
                step,
            );
            let Some(found) = lateral else {
                warnings.push(format!(
                    "{pname} not found: no branch of at least {:.0} % of the height joins the trunk on the body's {} side above the crotch, hanging down or held out sideways (missing arm, or arm touching the body)",
                    100.0 * opts.min_arm,
                    if k == 0 { "left" } else { "right" }
                ));
                continue;
            };
            let pit_h = found.armpit.dot(up) - floor;
            armpit_slice = armpit_slice.max((pit_h / step) as usize);
            landmarks.push(Landmark {
                kind: pit,
                position: found.armpit,
                height_fraction: pit_h / extent,
                confidence: 1.0,
                how: "the arm's branch in slices across the body merges into the trunk (arm held out)",
            });
            landmarks.push(Landmark {
                kind: tip,
                position: found.tip,
                height_fraction: hfrac(found.tip),
                confidence: 0.8,
                how: "outermost slice across the body of the arm's branch",
            });
            let axis = smooth_axis(&found.axis, opts.axis_smoothing * extent, step);
            let part = PartAxis {
                name: arm,
                points: axis.0,
                radii: axis.1,
                start: pit,
                end: tip,
            };
            if let Some(mut w) = find_wrist(body, &part, opts, slicer.spacing(), wrist) {
                w.height_fraction = hfrac(w.position);
                landmarks.push(w);
            } else {
                warnings.push(format!("{pname}: wrist not found on perpendicular cuts"));
            }
            parts.push(part);
            continue;
        };
        let last = *nodes.last().unwrap_or(&nodes[0]);
        let merge_first = g.segments[*m].nodes[0];
        armpit_slice = armpit_slice.max(g.nodes[merge_first].slice);
        // The trunk loop just below the merge: the other parent's last node.
        let trunk_below = g.segments[*m]
            .parents
            .iter()
            .filter(|&&p| g.segments[p].nodes.last() != Some(&last))
            .map(|&p| *g.segments[p].nodes.last().unwrap_or(&merge_first))
            .max_by(|&a, &b| g.nodes[a].area.total_cmp(&g.nodes[b].area))
            .unwrap_or(merge_first);
        let arm_c = g.nodes[last].c2;
        let torso_c = g.nodes[trunk_below].c2;
        let near_t = nearest_point(&g.nodes[trunk_below].poly, arm_c);
        let near_a = nearest_point(&g.nodes[last].poly, torso_c);
        let mid2 = (near_t + near_a) * 0.5;
        let pit_h = height_of(g.nodes[merge_first].slice) - 0.5 * step;
        let pit_p = at_height(e1 * mid2.x + e2 * mid2.y, pit_h);
        landmarks.push(Landmark {
            kind: pit,
            position: pit_p,
            height_fraction: pit_h / extent,
            confidence: 1.0,
            how: "the arm's branch merges into the trunk",
        });
        // Arm axis: from the armpit down to the hand tip.
        let mut cs: Vec<(Point3, Real)> = nodes
            .iter()
            .rev()
            .map(|&a| (g.nodes[a].centroid, g.nodes[a].radius))
            .collect();
        let tip_node = nodes[0];
        let tip_h = height_of(g.nodes[tip_node].slice) - 0.5 * step;
        let tip_p = at_height(g.nodes[tip_node].centroid, tip_h);
        cs.push((tip_p, g.nodes[tip_node].radius));
        let axis = smooth_axis(&cs, opts.axis_smoothing * extent, step);
        let part = PartAxis {
            name: arm,
            points: axis.0,
            radii: axis.1,
            start: pit,
            end: tip,
        };
        landmarks.push(Landmark {
            kind: tip,
            position: tip_p,
            height_fraction: hfrac(tip_p),
            confidence: 0.8,
            how: "lowest slice of the arm's branch (fingers below may be dropped as small loops)",
        });
        if let Some(w) = find_wrist(body, &part, opts, slicer.spacing(), wrist) {
            let mut w = w;
            w.height_fraction = hfrac(w.position);
            landmarks.push(w);
        } else {
            warnings.push(format!("{pname}: wrist not found on perpendicular cuts"));
        }
        parts.push(part);
    }
    // Let each arm's axis continue into the shoulder (method.md §8.5).
    // And out to the fingertips: fingers thinner than the small-loop limit
    // are not in the graph.
    for part in parts.iter_mut() {
        let kind = match part.name {
            PartName::LeftArm => LandmarkKind::LeftHandTip,
            PartName::RightArm => LandmarkKind::RightHandTip,
            _ => continue,
        };
        if let Some(tip) = extend_to_fingertips(positions, part) {
            if let Some(l) = landmarks.iter_mut().find(|l| l.kind == kind) {
                l.position = tip;
                l.height_fraction = hfrac(tip);
                l.how =
                    "farthest point along the arm's end direction near the hand (the fingertips)";
            }
        }
    }
    for part in parts.iter_mut() {
        let kind = match part.name {
            PartName::LeftArm => LandmarkKind::LeftShoulder,
            PartName::RightArm => LandmarkKind::RightShoulder,
            _ => continue,
        };
        if let Some(end) = extend_into_shoulder(body, part, opts, slicer.spacing(), step) {
            part.start = kind;
            landmarks.push(Landmark {
                kind,
                position: end,
                height_fraction: hfrac(end),
                confidence: 0.7,
                how: "the arm's axis continued past the armpit until its perpendicular cuts merge with the trunk",
            });
        }
    }
    if arm_found.iter().all(|a| a.is_none()) {
        armpit_slice = crotch_slice + (g.nodes[top_node].slice - crotch_slice) / 2;
    }

    // Neck: smallest hull girth between the head's widest slice and the
    // highest armpit.
    let above: Vec<usize> = trunk_nodes
        .iter()
        .copied()
        .filter(|&a| g.nodes[a].slice > armpit_slice)
        .collect();
    let neck_node = {
        let upper_half: Vec<usize> = above
            .iter()
            .copied()
            .filter(|&a| g.nodes[a].slice * 2 >= armpit_slice + g.nodes[top_node].slice)
            .collect();
        let head_max = upper_half
            .iter()
            .copied()
            .max_by(|&a, &b| g.nodes[a].hull_girth.total_cmp(&g.nodes[b].hull_girth));
        let Some(head_max) = head_max else {
            return Err(SegmentError::NotAStandingBody {
                what: "the head",
                why: "the trunk ends at the armpits".into(),
            });
        };
        above
            .iter()
            .copied()
            .filter(|&a| g.nodes[a].slice < g.nodes[head_max].slice)
            .min_by(|&a, &b| g.nodes[a].hull_girth.total_cmp(&g.nodes[b].hull_girth))
            .ok_or(SegmentError::NotAStandingBody {
                what: "the neck",
                why: "no slice between the armpits and the head's widest slice".into(),
            })?
    };
    let neck_p = g.nodes[neck_node].centroid;
    let neck_conf = girth_contrast(&g, &above, neck_node);
    landmarks.push(Landmark {
        kind: LandmarkKind::Neck,
        position: neck_p,
        height_fraction: hfrac(neck_p),
        confidence: neck_conf,
        how: "smallest hull girth between the armpits and the head's widest slice",
    });
    let top_p = at_height(g.nodes[top_node].centroid, extent);
    landmarks.push(Landmark {
        kind: LandmarkKind::HeadTop,
        position: top_p,
        height_fraction: 1.0,
        confidence: 1.0,
        how: "top end of the trunk's branch",
    });

    // Torso and head axes.
    let pick = |lo: usize, hi: usize| -> Vec<(Point3, Real)> {
        trunk_nodes
            .iter()
            .filter(|&&a| g.nodes[a].slice >= lo && g.nodes[a].slice <= hi)
            .map(|&a| (g.nodes[a].centroid, g.nodes[a].radius))
            .collect()
    };
    let neck_slice = g.nodes[neck_node].slice;
    let mut torso_pts = vec![(crotch, g.nodes[crotch_node].radius)];
    torso_pts.extend(pick(crotch_slice, neck_slice));
    let torso = smooth_axis(&torso_pts, opts.axis_smoothing * extent, step);
    parts.push(PartAxis {
        name: PartName::Torso,
        points: torso.0,
        radii: torso.1,
        start: LandmarkKind::Crotch,
        end: LandmarkKind::Neck,
    });
    let mut head_pts = pick(neck_slice, g.nodes[top_node].slice);
    head_pts.push((top_p, g.nodes[top_node].radius));
    let head = smooth_axis(&head_pts, opts.axis_smoothing * extent, step);
    parts.push(PartAxis {
        name: PartName::Head,
        points: head.0,
        radii: head.1,
        start: LandmarkKind::Neck,
        end: LandmarkKind::HeadTop,
    });

    // Legs, ankles, feet.
    for (k, nodes) in leg_nodes.iter().enumerate() {
        let names = if k == 0 {
            (
                PartName::LeftLeg,
                PartName::LeftFoot,
                LandmarkKind::LeftAnkle,
                LandmarkKind::LeftSole,
                LandmarkKind::LeftHeel,
                LandmarkKind::LeftToe,
            )
        } else {
            (
                PartName::RightLeg,
                PartName::RightFoot,
                LandmarkKind::RightAnkle,
                LandmarkKind::RightSole,
                LandmarkKind::RightHeel,
                LandmarkKind::RightToe,
            )
        };
        let (leg, foot, ankle, sole, heel, toe) = names;
        let sole_node = nodes[0];
        // Ankle: smallest hull girth below the calf's widest slice (the
        // widest slice in the lower half of the leg).
        let top_slice = g.nodes[*nodes.last().unwrap_or(&sole_node)].slice;
        let sole_slice = g.nodes[sole_node].slice;
        let half = sole_slice + (top_slice - sole_slice) / 2;
        let lower: Vec<usize> = nodes
            .iter()
            .copied()
            .filter(|&a| g.nodes[a].slice <= half)
            .collect();
        let calf = lower
            .iter()
            .copied()
            .filter(|&a| g.nodes[a].slice > sole_slice + (half - sole_slice) / 4)
            .max_by(|&a, &b| g.nodes[a].hull_girth.total_cmp(&g.nodes[b].hull_girth))
            .unwrap_or(sole_node);
        // Walking up from the sole the foot's widest slice comes first
        // (the sole's first slices are small), then the ankle.
        let calf_slice = g.nodes[calf].slice;
        let foot_max = lower
            .iter()
            .copied()
            .filter(|&a| 2 * g.nodes[a].slice < sole_slice + calf_slice)
            .max_by(|&a, &b| g.nodes[a].hull_girth.total_cmp(&g.nodes[b].hull_girth))
            .unwrap_or(sole_node);
        let ankle_node = lower
            .iter()
            .copied()
            .filter(|&a| {
                g.nodes[a].slice > g.nodes[foot_max].slice && g.nodes[a].slice < calf_slice
            })
            .min_by(|&a, &b| g.nodes[a].hull_girth.total_cmp(&g.nodes[b].hull_girth))
            .unwrap_or(sole_node);
        let ankle_p = g.nodes[ankle_node].centroid;
        let below: Vec<usize> = lower
            .iter()
            .copied()
            .filter(|&a| g.nodes[a].slice < g.nodes[calf].slice)
            .collect();
        landmarks.push(Landmark {
            kind: ankle,
            position: ankle_p,
            height_fraction: hfrac(ankle_p),
            confidence: girth_contrast(&g, &below, ankle_node),
            how: "smallest hull girth of the leg below the calf's widest slice",
        });
        let ankle_slice = g.nodes[ankle_node].slice;
        let mut pts: Vec<(Point3, Real)> = nodes
            .iter()
            .rev()
            .filter(|&&a| g.nodes[a].slice >= ankle_slice)
            .map(|&a| (g.nodes[a].centroid, g.nodes[a].radius))
            .collect();
        pts.insert(
            0,
            (crotch, g.nodes[*nodes.last().unwrap_or(&sole_node)].radius),
        );
        let axis = smooth_axis(&pts, opts.axis_smoothing * extent, step);
        parts.push(PartAxis {
            name: leg,
            points: axis.0,
            radii: axis.1,
            start: LandmarkKind::Crotch,
            end: ankle,
        });
        // Foot: principal horizontal direction of the slices below the
        // ankle, oriented to the front.
        let foot_nodes: Vec<usize> = nodes
            .iter()
            .copied()
            .filter(|&a| g.nodes[a].slice < ankle_slice)
            .collect();
        let mut foot_pts: Vec<Point2> = Vec::new();
        for &a in &foot_nodes {
            foot_pts.extend(g.nodes[a].poly.iter().copied());
        }
        let f2 = Vec2::new(front.dot(e1), front.dot(e2));
        if let Some(d2) = principal_2d(&foot_pts) {
            let d2 = if d2.dot(f2) < 0.0 { -d2 } else { d2 };
            let (lo, hi) = foot_pts
                .iter()
                .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p.dot(d2)), hi.max(p.dot(d2)))
                });
            let across = d2.perp();
            let mean_across =
                foot_pts.iter().map(|p| p.dot(across)).sum::<Real>() / foot_pts.len() as Real;
            let foot_h = height_of(ankle_slice) / 3.0;
            let to3 = |along: Real| {
                let q = d2 * along + across * mean_across;
                at_height(e1 * q.x + e2 * q.y, foot_h)
            };
            let (heel_p, toe_p) = (to3(lo), to3(hi));
            let r = foot_nodes
                .iter()
                .map(|&a| g.nodes[a].radius)
                .fold(0.0, Real::max)
                * 0.5;
            let m = 16;
            parts.push(PartAxis {
                name: foot,
                points: (0..=m)
                    .map(|i| heel_p + (toe_p - heel_p) * (i as Real / m as Real))
                    .collect(),
                radii: vec![r; m + 1],
                start: heel,
                end: toe,
            });
            for (kind, p, how) in [
                (
                    heel,
                    heel_p,
                    "rearmost point of the foot's slices below the ankle",
                ),
                (
                    toe,
                    toe_p,
                    "foremost point of the foot's slices below the ankle",
                ),
            ] {
                landmarks.push(Landmark {
                    kind,
                    position: p,
                    height_fraction: hfrac(p),
                    confidence: 0.8,
                    how,
                });
            }
            landmarks.push(Landmark {
                kind: sole,
                position: at_height((heel_p + toe_p) * 0.5, 0.0),
                height_fraction: 0.0,
                confidence: 1.0,
                how: "middle of the foot (heel to toe), on the floor",
            });
        } else {
            warnings.push(format!(
                "{foot}: too few slices below the ankle for a foot axis"
            ));
            landmarks.push(Landmark {
                kind: sole,
                position: at_height(ankle_p, 0.0),
                height_fraction: 0.0,
                confidence: 0.5,
                how: "below the ankle, on the floor (no foot axis)",
            });
        }
    }

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

/// The principal axis of largest variance, if it is distinct. Meshes are
/// weighted by surface area (uniform density over the triangles, whose
/// second moment is `A [(aaᵀ + bbᵀ + ccᵀ)/12 + ¾ mmᵀ]` with `m` the
/// centroid), so dense vertices (a face, the poles of a UV sphere) do not
/// tilt it; clouds are taken point by point.
fn principal_axis(body: BodyGeometry<'_>, needed: Real) -> Result<Vec3, SegmentError> {
    let mut w = 0.0;
    let mut first = Vec3::ZERO;
    let mut second = [[0.0; 3]; 3];
    let mut add = |p: Vec3, weight: Real, outer: &[[Real; 3]; 3]| {
        w += weight;
        first += p * weight;
        for i in 0..3 {
            for j in 0..3 {
                second[i][j] += weight * outer[i][j];
            }
        }
    };
    let outer = |v: Vec3| {
        let a = v.to_array();
        let mut o = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                o[i][j] = a[i] * a[j];
            }
        }
        o
    };
    match body {
        BodyGeometry::Mesh(m) if !m.triangles.is_empty() => {
            for t in 0..m.triangles.len() {
                let [a, b, c] = m.triangle(t);
                let area = 0.5 * (b - a).cross(c - a).norm();
                let centroid = (a + b + c) / 3.0;
                let (oa, ob, oc, om) = (outer(a), outer(b), outer(c), outer(centroid));
                let mut o = [[0.0; 3]; 3];
                for i in 0..3 {
                    for j in 0..3 {
                        o[i][j] = (oa[i][j] + ob[i][j] + oc[i][j]) / 12.0 + 0.75 * om[i][j];
                    }
                }
                add(centroid, area, &o);
            }
        }
        _ => {
            for &p in body.positions() {
                add(p, 1.0, &outer(p));
            }
        }
    }
    if w.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(SegmentError::NoUpAxis { ratio: 1.0, needed });
    }
    let mean = first / w;
    let om = outer(mean);
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = second[i][j] / w - om[i][j];
        }
    }
    let (vals, vecs) = symmetric_eigen3(c);
    let ratio = if vals[1] > 0.0 {
        vals[0] / vals[1]
    } else {
        Real::INFINITY
    };
    if ratio.partial_cmp(&needed) == Some(std::cmp::Ordering::Less) || ratio.is_nan() {
        return Err(SegmentError::NoUpAxis { ratio, needed });
    }
    vecs[0]
        .normalized()
        .ok_or(SegmentError::NoUpAxis { ratio, needed })
}

/// Principal direction of 2D points (unit), if the spread is not round.
fn principal_2d(p: &[Point2]) -> Option<Vec2> {
    if p.len() < 3 {
        return None;
    }
    let n = p.len() as Real;
    let m = p.iter().fold(Vec2::ZERO, |s, &q| s + q) / n;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for q in p {
        let d = *q - m;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    Some(Vec2::new(angle.cos(), angle.sin()))
}

fn nearest_point(poly: &[Point2], q: Point2) -> Point2 {
    poly.iter()
        .copied()
        .min_by(|a, b| (*a - q).norm_squared().total_cmp(&(*b - q).norm_squared()))
        .unwrap_or(q)
}

/// How much smaller the minimum is than the largest girth among `nodes`:
/// `1 − min/max`, clamped to [0, 1].
fn girth_contrast(g: &Graph, nodes: &[usize], min_node: usize) -> Real {
    let max = nodes
        .iter()
        .map(|&a| g.nodes[a].hull_girth)
        .fold(0.0, Real::max);
    if max > 0.0 {
        (1.0 - g.nodes[min_node].hull_girth / max).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Moving average (half-width `w` in length units, by position along the
/// polyline) of centre points with radii, then resampled evenly by arc
/// length at about `step`. The end points are kept as they are.
fn smooth_axis(pts: &[(Point3, Real)], w: Real, step: Real) -> (Vec<Point3>, Vec<Real>) {
    if pts.len() < 2 {
        return (
            pts.iter().map(|p| p.0).collect(),
            pts.iter().map(|p| p.1).collect(),
        );
    }
    // Window half-width in samples (one sample per slice, `step` apart
    // in height), shrunk symmetrically near the ends.
    let half = ((w / step.max(Real::MIN_POSITIVE)).round() as usize).min(pts.len());
    let n = pts.len();
    let window = |i: usize| {
        let h = half.min(i).min(n - 1 - i);
        (i - h, i + h)
    };
    // A running median first (a scan slice whose loop lost a piece moves
    // its centroid for a slice or two), then a moving average.
    let median: Vec<(Point3, Real)> = (0..n)
        .map(|i| {
            let (a, b) = window(i);
            let med = |f: &dyn Fn(&(Point3, Real)) -> Real| {
                let mut v: Vec<Real> = pts[a..=b].iter().map(f).collect();
                let k = v.len() / 2;
                *v.select_nth_unstable_by(k, |x, y| x.total_cmp(y)).1
            };
            (
                Vec3::new(med(&|p| p.0.x), med(&|p| p.0.y), med(&|p| p.0.z)),
                med(&|p| p.1),
            )
        })
        .collect();
    let smoothed: Vec<(Point3, Real)> = (0..n)
        .map(|i| {
            let (a, b) = window(i);
            let m = (b - a + 1) as Real;
            let c = median[a..=b].iter().fold(Vec3::ZERO, |s, p| s + p.0) / m;
            let r = median[a..=b].iter().map(|p| p.1).sum::<Real>() / m;
            (c, r)
        })
        .collect();
    let mut len = vec![0.0];
    for k in 1..smoothed.len() {
        let d = smoothed[k].0.distance(smoothed[k - 1].0);
        len.push(len[k - 1] + d);
    }
    let total = len[len.len() - 1];
    let count = ((total / step.max(Real::MIN_POSITIVE)).ceil() as usize).clamp(2, 2000);
    let mut out_p = Vec::with_capacity(count + 1);
    let mut out_r = Vec::with_capacity(count + 1);
    let mut j = 0;
    for i in 0..=count {
        let t = total * i as Real / count as Real;
        while j + 2 < len.len() && len[j + 1] < t {
            j += 1;
        }
        let d = len[j + 1] - len[j];
        let u = if d > 0.0 {
            ((t - len[j]) / d).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out_p.push(smoothed[j].0 + (smoothed[j + 1].0 - smoothed[j].0) * u);
        out_r.push(smoothed[j].1 + (smoothed[j + 1].1 - smoothed[j].1) * u);
    }
    (out_p, out_r)
}

// ---------------------------------------------------------------------------
// Cuts perpendicular to a part's axis.

/// The geometry near a point (within `radius`), to cut without sorting the
/// whole input for every plane.
enum Local {
    Mesh(Mesh),
    Cloud(PointCloud),
}

fn local_geometry(body: BodyGeometry<'_>, centre: Point3, radius: Real) -> Local {
    let r2 = radius * radius;
    match body {
        BodyGeometry::Mesh(m) => Local::Mesh(local_mesh(m, centre, radius)),
        // The points in the ball, in order, over the cores.
        BodyGeometry::Cloud(c) => Local::Cloud(PointCloud {
            positions: crate::geom::parallel::parallel_map(&c.positions, 1 << 15, |run| {
                run.iter()
                    .copied()
                    .filter(|p| (*p - centre).norm_squared() <= r2)
                    .collect()
            }),
            normals: None,
        }),
    }
}

/// Cuts `part` with the plane perpendicular to its axis at arc-length
/// fraction `at ∈ [0, 1]` (0 the proximal end) and returns the part's loop:
/// the innermost loop around the axis point, else the nearest one.
/// `body` must be the geometry `seg` came from. For many cuts of one body
/// use a [`Cutter`].
pub fn cut_part(
    body: BodyGeometry<'_>,
    seg: &Segmentation,
    part: PartName,
    at: Real,
    opts: &SegmentOptions,
) -> Result<PartCut, SegmentError> {
    cut_part_along(body, seg, part, at, None, false, opts)
}

/// [`cut_part`] with the plane's normal given (`None`: the axis tangent).
/// The plane passes through the axis point at `at`; e.g. horizontal cuts
/// (`normal = up`) of a nearly vertical part give parallel sections. With
/// `outermost`, the *largest* loop around the axis point is taken instead
/// of the innermost: the skin rather than a cavity inside it (a cut through
/// the mouth of a mesh that models the mouth's inside has the throat's loop
/// nested in the head's). For many cuts of one body use a [`Cutter`].
pub fn cut_part_along(
    body: BodyGeometry<'_>,
    seg: &Segmentation,
    part: PartName,
    at: Real,
    normal: Option<Vec3>,
    outermost: bool,
    opts: &SegmentOptions,
) -> Result<PartCut, SegmentError> {
    Cutter {
        reuse: false,
        ..Cutter::new(body, seg)
    }
    .cut(part, at, normal, outermost, opts)
}

/// Many cuts of one body ([`cut_part_along`] for each), with what every
/// plane needs built once, lazily, and shared by all cuts:
///
/// * **Horizontal cuts** (normal `±up`, the frame's up axis) of a mesh use
///   one [`MeshSlicer`] of the whole mesh per direction (triangles sorted
///   by their lowest height once; a plane visits only the triangles
///   spanning it). Of a cloud, one index of the points sorted by height
///   along `up`: a slab `|p·n − c| ≤ t` is a contiguous run found by binary
///   search. The segmentation's own sort of the cloud (its slicing axis is
///   `±up`) is that index ([`Segmentation`]'s `sorted_up`), checked to be
///   this cloud's; the cutter sorts only without it.
/// * **Other normals** (the arms' own axes): a mesh is cut through the
///   triangles with a vertex in the ball of radius `ρ` around the axis
///   point; a cloud's slab is the points of that ball found through a
///   uniform grid of cells `0.02 H`, tested exactly.
///
/// A cloud's slab is then the points within `ρ = 3 max(r_max, 0.02 H)` of
/// the axis point (`r_max` the part's largest radius) and within the slab,
/// sorted by height (ties by index), sectioned as
/// [`CloudSlicer::section_at`] does: the same loops as cutting the ball's
/// points alone, without sorting a ball of up to the whole cloud for every
/// plane. A horizontal mesh section uses the whole plane's loops (a loop
/// crossing the ball's boundary is no longer cut open there); the loop
/// chosen (largest or innermost around the axis point, else the nearest)
/// is the same wherever the ball held that loop whole.
#[derive(Debug)]
pub struct Cutter<'a> {
    body: BodyGeometry<'a>,
    seg: &'a Segmentation,
    /// False for one cut ([`cut_part_along`]): the ball's geometry is
    /// gathered directly (one pass over the input) instead of building
    /// shared slicers and grids first.
    reuse: bool,
    /// Mesh slicers along `up` and `−up` (`None`: the mesh is invalid).
    mesh_slicers: [OnceLock<Option<MeshSlicer<'a>>>; 2],
    /// Cloud indices sorted by height along `up`, and those heights.
    sorted: OnceLock<std::sync::Arc<HeightSort>>,
    grid: OnceLock<BallGrid>,
    /// Meshes: a grid of the vertices, each vertex's triangles (CSR: the
    /// triangles of vertex `v` are `tris[start[v]..start[v + 1]]`) and the
    /// mesh's bounding box corners.
    #[allow(clippy::type_complexity)]
    mesh_grid: OnceLock<(BallGrid, Vec<u32>, Vec<u32>, [Point3; 2])>,
    /// The cloud's point spacing: the segmentation's, else estimated once.
    spacing: OnceLock<Option<Real>>,
}

impl<'a> Cutter<'a> {
    /// A cutter for `body`, which must be the geometry `seg` came from.
    /// Nothing is built before the first cut.
    pub fn new(body: BodyGeometry<'a>, seg: &'a Segmentation) -> Cutter<'a> {
        Cutter {
            body,
            seg,
            reuse: true,
            mesh_slicers: [OnceLock::new(), OnceLock::new()],
            sorted: OnceLock::new(),
            grid: OnceLock::new(),
            mesh_grid: OnceLock::new(),
            spacing: OnceLock::new(),
        }
    }

    /// The geometry cut.
    pub fn body(&self) -> BodyGeometry<'a> {
        self.body
    }

    /// The segmentation whose axes place the cuts.
    pub fn segmentation(&self) -> &'a Segmentation {
        self.seg
    }

    /// [`cut_part_along`]: the cut of `part` at `at` with the plane normal
    /// `normal` (`None`: the axis tangent), the largest loop around the axis
    /// point when `outermost`.
    pub fn cut(
        &self,
        part: PartName,
        at: Real,
        normal: Option<Vec3>,
        outermost: bool,
        opts: &SegmentOptions,
    ) -> Result<PartCut, SegmentError> {
        let (plane, loops, k) = self.cut_loops(part, at, normal, outermost, opts)?;
        let (outline, scan_indices) = loops
            .into_iter()
            .nth(k)
            .ok_or(SegmentError::EmptyCut { part, at })?;
        Ok(PartCut {
            plane,
            outline,
            scan_indices,
        })
    }

    /// [`Cutter::cut`] (the largest loop around the axis point), and the
    /// other loops of the plane nested in it: each one smaller than it
    /// whose centroid it contains, and not itself inside a larger nested
    /// loop (a pocket of skin inside the part, such as a modelled mouth:
    /// the reconstruction's cavities; a loop inside the pocket's bounds solid
    /// again, a tongue or teeth left in). Nested loops of a cloud's slab are
    /// outlines of occupied cells, not surface: none are returned for a
    /// cloud.
    pub fn cut_nested(
        &self,
        part: PartName,
        at: Real,
        normal: Option<Vec3>,
        opts: &SegmentOptions,
    ) -> Result<(PartCut, Vec<SectionLoop>), SegmentError> {
        let (plane, loops, k) = self.cut_loops(part, at, normal, true, opts)?;
        let mut outline = None;
        let mut others = Vec::new();
        for (i, (l, indices)) in loops.into_iter().enumerate() {
            if i == k {
                outline = Some((l, indices));
            } else {
                others.push(l);
            }
        }
        let (outline, scan_indices) = outline.ok_or(SegmentError::EmptyCut { part, at })?;
        let nested = match self.body {
            BodyGeometry::Mesh(_) => {
                let inside: Vec<SectionLoop> = others
                    .into_iter()
                    .filter(|l| l.area < outline.area && outline.contains(l.centroid))
                    .collect();
                // A loop inside another nested loop bounds solid again (a
                // tongue or teeth left inside a mouth): not a pocket.
                let depth_one: Vec<bool> = inside
                    .iter()
                    .map(|l| {
                        !inside
                            .iter()
                            .any(|o| o.area > l.area && o.contains(l.centroid))
                    })
                    .collect();
                inside
                    .into_iter()
                    .zip(depth_one)
                    .filter_map(|(l, keep)| keep.then_some(l))
                    .collect()
            }
            BodyGeometry::Cloud(_) => Vec::new(),
        };
        Ok((
            PartCut {
                plane,
                outline,
                scan_indices,
            },
            nested,
        ))
    }

    /// The plane of [`Cutter::cut`], all its loops near the axis point and
    /// the index of the part's.
    #[allow(clippy::type_complexity)]
    fn cut_loops(
        &self,
        part: PartName,
        at: Real,
        normal: Option<Vec3>,
        outermost: bool,
        opts: &SegmentOptions,
    ) -> Result<(Plane, Vec<(SectionLoop, Option<Vec<usize>>)>, usize), SegmentError> {
        let seg = self.seg;
        let axis = seg.part(part).ok_or(SegmentError::NoSuchPart(part))?;
        let (p, t) = axis
            .point_and_tangent(at)
            .ok_or(SegmentError::EmptyCut { part, at })?;
        let n = match normal {
            // Keep the normal pointing along the axis (method.md §2).
            Some(n) if n.dot(t) < 0.0 => -n,
            Some(n) => n,
            None => t,
        };
        let plane = Plane::new(p, n)?;
        let radius = 3.0 * axis.max_radius().max(seg.height * 0.02);
        let arms = self.torso_arms(part, &plane);
        let loops = self.loops(&plane, p, radius, opts, &arms);
        let outlines: Vec<SectionLoop> = loops.iter().map(|l| l.0.clone()).collect();
        let enclosing = outlines
            .iter()
            .enumerate()
            .filter(|(_, l)| l.contains(p))
            .max_by(|a, b| a.1.area.total_cmp(&b.1.area))
            .map(|(i, _)| i);
        let k = match enclosing {
            Some(k) if outermost => k,
            _ => crate::section::mesh::select_loop(&outlines, p)
                .ok_or(SegmentError::EmptyCut { part, at })?,
        };
        Ok((plane, loops, k))
    }

    /// `0` for `n = up`, `1` for `n = −up`, else `None`.
    fn vertical(&self, n: Vec3) -> Option<usize> {
        let up = self.seg.frame.up;
        if n == up {
            Some(0)
        } else if n == -up {
            Some(1)
        } else {
            None
        }
    }

    /// For a torso cut of a cloud near the armpits (from [`ARMPIT_BAND`]
    /// below to [`ARMPIT_ABOVE`] above the lower armpit landmark), each
    /// arm's axis points that can be nearest to a point of the plane's slab
    /// within the arm's radius ([`near_axis`]): a scan's slab there has the
    /// arms touching the torso, and the closing joins their rings into one
    /// (the male virtual scan's torso at 0.75 H came out as two arm-sized
    /// loops and none around the torso); points in an arm's tube are left
    /// out of the slab ([`in_arm`]). Empty otherwise.
    fn torso_arms(&self, part: PartName, plane: &Plane) -> Vec<Vec<AxisBall>> {
        let seg = self.seg;
        if part != PartName::Torso || !matches!(self.body, BodyGeometry::Cloud(_)) {
            return Vec::new();
        }
        let armpit = seg.armpit_level();
        let level = plane.origin.dot(seg.frame.up);
        if !(level <= armpit + ARMPIT_ABOVE * seg.height
            && level >= armpit - ARMPIT_BAND * seg.height)
        {
            return Vec::new();
        }
        // A slab is a few point spacings thick: 0.01 H is ample.
        let reach = 0.01 * seg.height;
        [PartName::LeftArm, PartName::RightArm]
            .iter()
            .filter_map(|&a| seg.part(a))
            .map(|a| near_axis(a, plane, reach))
            .collect()
    }

    /// All loops in `plane` of the geometry near `centre` (see the type's
    /// doc), with cloud indices; a cloud's points in the `arms` tubes
    /// ([`Cutter::torso_arms`]) left out.
    fn loops(
        &self,
        plane: &Plane,
        centre: Point3,
        radius: Real,
        opts: &SegmentOptions,
        arms: &[Vec<AxisBall>],
    ) -> Vec<(SectionLoop, Option<Vec<usize>>)> {
        match self.body {
            BodyGeometry::Mesh(m) => {
                let shared = self.vertical(plane.normal).filter(|_| self.reuse);
                let section = match shared {
                    Some(k) => {
                        let slicer = self.mesh_slicers[k]
                            .get_or_init(|| MeshSlicer::new(m, plane.normal, &opts.section).ok());
                        slicer.as_ref().and_then(|s| {
                            let mut s = s.section_at(plane.offset()).ok()?;
                            s.plane = *plane;
                            Some(s)
                        })
                    }
                    None => {
                        let local = if self.reuse {
                            self.ball_mesh(m, centre, radius)
                        } else {
                            local_mesh(m, centre, radius)
                        };
                        if local.triangles.is_empty() {
                            None
                        } else {
                            section_mesh(&local, plane, &opts.section).ok()
                        }
                    }
                };
                section
                    .map(|s| s.loops.into_iter().map(|l| (l, None)).collect())
                    .unwrap_or_default()
            }
            BodyGeometry::Cloud(c) => self.cloud_loops(c, plane, centre, radius, opts, arms),
        }
    }

    /// The triangles of `m` with a vertex within `radius` of `centre`, in
    /// their order, on their vertices only (renumbered in order) plus the
    /// two corners of the whole mesh's bounding box: the same section as
    /// [`local_mesh`] (whose tolerances follow the bounding box's
    /// diagonal), from a grid of the vertices and their triangle lists.
    fn ball_mesh(&self, m: &Mesh, centre: Point3, radius: Real) -> Mesh {
        let (grid, tri_start, tris, corners) = self.mesh_grid.get_or_init(|| {
            let mut start = vec![0u32; m.positions.len() + 1];
            for t in &m.triangles {
                for &v in t {
                    if let Some(c) = start.get_mut(v as usize + 1) {
                        *c += 1;
                    }
                }
            }
            for i in 1..start.len() {
                start[i] += start[i - 1];
            }
            let mut fill = start.clone();
            let mut tris = vec![0u32; *start.last().unwrap_or(&0) as usize];
            for (k, t) in m.triangles.iter().enumerate() {
                for &v in t {
                    if let Some(f) = fill.get_mut(v as usize) {
                        tris[*f as usize] = k as u32;
                        *f += 1;
                    }
                }
            }
            let corners = m
                .bounds()
                .map_or([Vec3::ZERO, Vec3::ZERO], |b| [b.min, b.max]);
            let grid = BallGrid::new(&m.positions, 0.02 * self.seg.height);
            (grid, start, tris, corners)
        });
        let r2 = radius * radius;
        // Bit sets over triangles and vertices: picked in any order, read
        // back in ascending order.
        let mut tri_bits = vec![0u64; m.triangles.len().div_ceil(64)];
        grid.for_each_within(centre, radius, None, &mut |v| {
            if (m.positions[v as usize] - centre).norm_squared() <= r2 {
                let (a, b) = (tri_start[v as usize], tri_start[v as usize + 1]);
                for &t in &tris[a as usize..b as usize] {
                    tri_bits[t as usize / 64] |= 1 << (t % 64);
                }
            }
        });
        let ones = |bits: &[u64]| -> Vec<u32> {
            let mut out = Vec::new();
            for (w, &word) in bits.iter().enumerate() {
                let mut x = word;
                while x != 0 {
                    out.push((w * 64) as u32 + x.trailing_zeros());
                    x &= x - 1;
                }
            }
            out
        };
        // (A triangle naming a vertex the mesh lacks is left out: the mesh
        // should have been validated by the segmentation.)
        let count = m.positions.len();
        let picked: Vec<u32> = ones(&tri_bits)
            .into_iter()
            .filter(|&t| {
                m.triangles[t as usize]
                    .iter()
                    .all(|&v| (v as usize) < count)
            })
            .collect();
        let mut vert_bits = vec![0u64; m.positions.len().div_ceil(64)];
        for &t in &picked {
            for v in m.triangles[t as usize] {
                vert_bits[v as usize / 64] |= 1 << (v % 64);
            }
        }
        let vertices = ones(&vert_bits);
        let mut index = vec![0u32; m.positions.len()];
        for (k, &v) in vertices.iter().enumerate() {
            index[v as usize] = k as u32;
        }
        let triangles = picked
            .iter()
            .map(|&t| m.triangles[t as usize].map(|v| index[v as usize]))
            .collect();
        let mut positions: Vec<Point3> =
            vertices.iter().map(|&v| m.positions[v as usize]).collect();
        positions.extend_from_slice(corners);
        Mesh {
            positions,
            normals: None,
            triangles,
        }
    }

    fn cloud_loops(
        &self,
        c: &PointCloud,
        plane: &Plane,
        centre: Point3,
        radius: Real,
        opts: &SegmentOptions,
        arms: &[Vec<AxisBall>],
    ) -> Vec<(SectionLoop, Option<Vec<usize>>)> {
        let Some(axis) = plane.normal.normalized() else {
            return Vec::new();
        };
        let spacing = *self.spacing.get_or_init(|| {
            self.seg.point_spacing.or_else(|| {
                CloudSlicer::new(c, self.seg.frame.up)
                    .ok()
                    .map(|s| s.spacing())
            })
        });
        let Some(spacing) = spacing else {
            return Vec::new();
        };
        let so = ScanSectionOptions {
            half_thickness: opts.scan.half_thickness.or(Some(spacing)),
            cell_size: opts.scan.cell_size.or(Some(spacing)),
            ..opts.scan
        };
        let (Some(t), Some(g)) = (so.half_thickness, so.cell_size) else {
            return Vec::new();
        };
        let offset = plane.offset();
        if !(t.is_finite() && t > 0.0 && g.is_finite() && g > 0.0 && offset.is_finite()) {
            return Vec::new();
        }
        let r2 = radius * radius;
        let pos = &c.positions;
        // The slab of the ball, exactly as a slicer of the ball's points
        // would find it: heights `p·axis` in [offset − t, offset + t].
        let mut slab: Vec<(u64, u32)> = Vec::new();
        let mut keep = |i: u32| {
            let p = pos[i as usize];
            if (p - centre).norm_squared() <= r2 {
                let h = p.dot(axis);
                if h >= offset - t && h <= offset + t && !arms.iter().any(|a| in_arm(a, p)) {
                    slab.push((height_key(h), i));
                }
            }
        };
        match self.vertical(plane.normal) {
            _ if !self.reuse => (0..pos.len() as u32).for_each(&mut keep),
            Some(_) => {
                let up = self.seg.frame.up;
                let sorted = self.sorted.get_or_init(|| {
                    // The segmentation's sort when it is this cloud's
                    // (checked at its ends and middle), else sorted here.
                    let same = |s: &HeightSort| {
                        s.0.len() == pos.len()
                            && s.1.len() == pos.len()
                            && [0, pos.len() / 2, pos.len().saturating_sub(1)]
                                .iter()
                                .filter(|&&k| k < pos.len())
                                .all(|&k| {
                                    pos.get(s.0[k] as usize)
                                        .is_some_and(|p| p.dot(up) == s.1[k])
                                })
                    };
                    match &self.seg.sorted_up.0 {
                        Some(s) if same(s) => s.clone(),
                        _ => {
                            let mut keyed = keyed_heights(pos, up);
                            sort_keyed(&mut keyed);
                            std::sync::Arc::new(sorted_heights(&keyed, pos, up))
                        }
                    }
                });
                let (order, heights) = (&sorted.0, &sorted.1);
                // The same slab along `up` (heights along `−up` are the
                // exact negations), widened by a rounding margin; the exact
                // test above decides.
                let c_up = offset * plane.normal.dot(up).signum();
                let pad = 1e-9 * (c_up.abs() + t);
                let lo = heights.partition_point(|&h| h < c_up - t - pad);
                let hi = heights.partition_point(|&h| h <= c_up + t + pad);
                for &i in &order[lo..hi] {
                    keep(i);
                }
            }
            None => {
                let grid = self
                    .grid
                    .get_or_init(|| BallGrid::new(pos, 0.02 * self.seg.height));
                grid.for_each_within(centre, radius, Some((axis, offset, t)), &mut keep);
            }
        }
        let needed = so.min_slab_points.max(3);
        if slab.len() < needed {
            return Vec::new();
        }
        slab.sort_unstable();
        let ids: Vec<u32> = slab.iter().map(|k| k.1).collect();
        // The local cloud of a ball had no normals.
        let section = section_of_slab(pos, None, axis, offset, &ids, t, g, &so);
        section
            .loops
            .into_iter()
            .map(|l| (l.outline, Some(l.scan_indices)))
            .collect()
    }
}

/// How far below the armpits (fraction of `H`) a scan's torso slab leaves
/// the arms' points out (see `Cutter::torso_arms`).
const ARMPIT_BAND: Real = 0.05;

/// ... and how far above them (the landmark sits where the slices' loops
/// join; a scan's slab still holds the rings touching a little higher).
/// Measured with `reconstruct_real` and `pose_variants` at 0, 0.005 and
/// 0.01 (0.01 tried first): at 0 the virtual scans barely move; at 0.005
/// the four shared scans are best (male, base, female virtual and external
/// RMS 2.63 / 2.85 / 2.44 / 3.92 mm) but the shorter-and-wider scan's p95
/// goes 8.4 -> 10.8 mm; at 0.01 every pose variant's scan improves and the
/// base virtual scan's p95 goes 5.17 -> 6.26 mm (a shelf where the torso's
/// last armless section meets its shoulder section). Kept: 0.01.
const ARMPIT_ABOVE: Real = 0.01;

/// An arm's axis point: its index along the axis, position and radius.
type AxisBall = (usize, Point3, Real);

/// The axis points of `arm` within `R + reach` of `plane` (`R` the arm's
/// largest radius): for a point within `reach` of the plane, the nearest
/// axis point lies among them whenever it is nearer than `R` (any other
/// is farther than `R`), so [`in_arm`] over them answers as over the whole
/// axis.
fn near_axis(arm: &PartAxis, plane: &Plane, reach: Real) -> Vec<AxisBall> {
    let big = arm.radii.iter().copied().fold(0.0, Real::max);
    arm.points
        .iter()
        .zip(&arm.radii)
        .enumerate()
        .filter(|(_, (q, _))| ((**q - plane.origin).dot(plane.normal)).abs() <= big + reach)
        .map(|(k, (q, r))| (k, *q, *r))
        .collect()
}

/// True when `p` lies within the arm's tube: nearer its nearest axis point
/// (of `axis`, [`near_axis`]) than the radius there, that point not the
/// axis's first (the shoulder end, inside the torso).
fn in_arm(axis: &[AxisBall], p: Point3) -> bool {
    let mut best: Option<(Real, usize, Real)> = None;
    for &(k, q, r) in axis {
        let d = (q - p).norm_squared();
        if best.is_none_or(|b| d < b.0) {
            best = Some((d, k, r));
        }
    }
    best.is_some_and(|(d, k, r)| k > 0 && d <= r * r)
}

/// A uniform grid of a cloud's points for ball queries: cells of side
/// `cell` (grown so there are at most ~2M cells), points bucketed by cell.
#[derive(Debug)]
struct BallGrid {
    origin: Point3,
    cell: Real,
    dims: [usize; 3],
    /// Cell `k` holds `order[starts[k]..starts[k + 1]]`.
    starts: Vec<u32>,
    order: Vec<u32>,
}

impl BallGrid {
    fn new(points: &[Point3], cell: Real) -> BallGrid {
        let (lo, cell, dims) = crate::geom::mesh::grid_layout(points, cell, 2.0e6);
        let mut grid = BallGrid {
            origin: lo,
            cell,
            dims,
            starts: vec![0; dims[0] * dims[1] * dims[2] + 1],
            order: Vec::new(),
        };
        let keys: Vec<Option<usize>> = points
            .iter()
            .map(|p| p.is_finite().then(|| grid.key(grid.coords(*p))))
            .collect();
        for k in keys.iter().flatten() {
            grid.starts[k + 1] += 1;
        }
        for i in 1..grid.starts.len() {
            grid.starts[i] += grid.starts[i - 1];
        }
        let mut fill = grid.starts.clone();
        grid.order = vec![0; *grid.starts.last().unwrap_or(&0) as usize];
        for (i, k) in keys.iter().enumerate() {
            if let Some(k) = *k {
                grid.order[fill[k] as usize] = i as u32;
                fill[k] += 1;
            }
        }
        grid
    }

    /// Integer cell coordinates, clamped to the grid.
    fn coords(&self, p: Point3) -> [usize; 3] {
        crate::geom::mesh::grid_cell(p, self.origin, self.cell, self.dims)
    }

    fn key(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Calls `f` with every point in a cell that meets the ball and, when
    /// `slab = Some((n, c, t))` (`n` a unit vector), the slab
    /// `|p·n − c| ≤ t`: a superset of the points in both (the caller tests
    /// them exactly). A cell is skipped when its box lies beyond `radius`
    /// from `centre`, or when its centre's height `h` along `n` has
    /// `|h − c| > t + (g/2)(|n_x| + |n_y| + |n_z|)` (how far the box of side
    /// `g` reaches along `n`), each with a small margin.
    fn for_each_within(
        &self,
        centre: Point3,
        radius: Real,
        slab: Option<(Vec3, Real, Real)>,
        f: &mut impl FnMut(u32),
    ) {
        if !(centre.is_finite() && radius.is_finite()) {
            return;
        }
        let r = Vec3::new(radius, radius, radius);
        let (a, b) = (self.coords(centre - r), self.coords(centre + r));
        let g = self.cell;
        let margin = 1e-9 * (radius + g);
        let reach2 = (radius + margin) * (radius + margin);
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                let row = self.key([0, y, z]);
                for x in a[0]..=b[0] {
                    let lo = self.origin + Vec3::new(x as Real, y as Real, z as Real) * g;
                    let hi = lo + Vec3::new(g, g, g);
                    let d = Vec3::new(
                        (lo.x - centre.x).max(0.0).max(centre.x - hi.x),
                        (lo.y - centre.y).max(0.0).max(centre.y - hi.y),
                        (lo.z - centre.z).max(0.0).max(centre.z - hi.z),
                    );
                    if d.norm_squared() > reach2 {
                        continue;
                    }
                    if let Some((n, c, t)) = slab {
                        let h = ((lo + hi) * 0.5).dot(n);
                        let half = 0.5 * g * (n.x.abs() + n.y.abs() + n.z.abs());
                        if (h - c).abs() > t + half + margin {
                            continue;
                        }
                    }
                    let k = row + x;
                    let (s, e) = (self.starts[k], self.starts[k + 1]);
                    for &i in &self.order[s as usize..e as usize] {
                        f(i);
                    }
                }
            }
        }
    }
}

/// The triangles of `m` with a vertex within `radius` of `centre` (all
/// positions kept, so the bounds and thus the section's tolerances are the
/// whole mesh's).
fn local_mesh(m: &Mesh, centre: Point3, radius: Real) -> Mesh {
    let r2 = radius * radius;
    let triangles = m
        .triangles
        .iter()
        .copied()
        .filter(|t| {
            t.iter().any(|&v| {
                m.positions
                    .get(v as usize)
                    .is_some_and(|p| (*p - centre).norm_squared() <= r2)
            })
        })
        .collect();
    Mesh {
        positions: m.positions.clone(),
        normals: None,
        triangles,
    }
}

/// How much wider than the arm's median loop (radius ratio) a loop of a
/// sideways arm's branch near the armpit may be and still start its axis
/// (see [`lateral_arm`]). Measured on the built-in body raised to a T-pose
/// (`pose_variants`), scan RMS / p95: 1.5 → 7.55 / 20.4 mm, 1.25 → 6.34 /
/// 15.9, 1.15 → 6.12 / 13.9, 1.1 → 6.14 / 14.0 (the mesh 3.58-3.63 mm
/// throughout); without the rule 7.66 / 24.7.
const LATERAL_ARM_WIDE: Real = 1.15;

/// An arm found in slices across the body.
struct LateralArm {
    /// Centroids and radii from the shoulder junction out to the hand.
    axis: Vec<(Point3, Real)>,
    armpit: Point3,
    tip: Point3,
}

/// An arm held out sideways (T-pose): horizontal slices cut it lengthwise,
/// so it never branches off the trunk there. Slices normal to `side` (the
/// body's left or right), ordered from the outermost inward, show the arm
/// as a branch that starts at the body's lateral end and merges into the
/// trunk at the shoulder: the same graph as the vertical one, on another
/// axis. The branch must start in the outer 10 % of the lateral extent,
/// lie above the crotch and reach `min_len` inward.
// Its arguments become one struct in the pose-robust segmentation rewrite.
#[allow(clippy::too_many_arguments)]
fn lateral_arm(
    body: BodyGeometry<'_>,
    opts: &SegmentOptions,
    spacing: Option<Real>,
    side: Vec3,
    up: Vec3,
    crotch_level: Real,
    min_len: Real,
    step: Real,
) -> Option<LateralArm> {
    // Heights along −side grow inward: the outermost slice is the first.
    let axis = -side;
    let slicer = AxisSlicer::new(body, axis, opts, spacing).ok()?;
    let (min, max) = slicer.range();
    let count = (((max - min) / step).ceil() as usize).clamp(50, 4000);
    let lstep = (max - min) / count as Real;
    let e1 = axis.any_perpendicular();
    let e2 = axis.cross(e1);
    let mut largest: Real = 0.0;
    let mut raw = Vec::with_capacity(count);
    for k in 0..count {
        let found = slicer.nodes_at(min + (k as Real + 0.5) * lstep, e1, e2);
        largest = found.iter().map(|nd| nd.area).fold(largest, Real::max);
        raw.push(found);
    }
    let floor = opts.min_loop_area * largest;
    let min_span = ((opts.min_branch * count as Real).ceil() as usize).max(2);
    let g = Graph::of_slices(
        raw.into_iter()
            .map(|found| found.into_iter().filter(|nd| nd.area >= floor).collect()),
        min_span,
    );
    let best = (0..g.segments.len())
        .filter(|&s| g.segments[s].parents.is_empty())
        .filter(|&s| g.nodes[g.segments[s].nodes[0]].slice <= count / 10)
        .filter_map(|s| {
            let (chain, merge) = g.chain_up(s);
            merge?;
            let ids = g.chain_nodes(&chain);
            let first = *ids.first()?;
            let last = *ids.last()?;
            let span = (g.nodes[last].slice - g.nodes[first].slice + 1) as Real * lstep;
            let above = ids
                .iter()
                .all(|&a| g.nodes[a].centroid.dot(up) > crotch_level);
            (span >= min_len && above).then_some(ids)
        })
        .max_by_key(|ids| ids.len())?;
    let first = *best.first()?;
    let last = *best.last()?;
    // Near the armpit the slices across the body cut the shoulder
    // lengthwise: their loops (deltoid and chest) are far wider than the
    // arm and their centroids rise to the shoulder's top, so an axis
    // through them climbs before it runs out, and the arm's first
    // perpendicular cuts slant through the shoulder (T-pose scan: arms
    // p95 30 mm). The axis starts where the loops are arm-sized again
    // (radius at most `LATERAL_ARM_WIDE` times the chain's median);
    // the shoulder extension then continues it inward along the arm.
    let mut radii: Vec<Real> = best.iter().map(|&a| g.nodes[a].radius).collect();
    radii.sort_by(Real::total_cmp);
    let wide = LATERAL_ARM_WIDE * radii[radii.len() / 2];
    let keep = best.len()
        - best
            .iter()
            .rev()
            .take_while(|&&a| g.nodes[a].radius > wide)
            .count()
            .min(best.len() / 2);
    let mut axis_pts: Vec<(Point3, Real)> = best[..keep]
        .iter()
        .rev()
        .map(|&a| (g.nodes[a].centroid, g.nodes[a].radius))
        .collect();
    let armpit = g.nodes[last].centroid + axis * (0.5 * lstep);
    // In place of the wide loops: the arm's direction (over its first
    // tenth) continued straight inward to the armpit's depth.
    if keep < best.len() && axis_pts.len() >= 10 {
        let (q0, r0) = axis_pts[0];
        let q1 = axis_pts[axis_pts.len() / 10].0;
        if let Some(d) = (q0 - q1).normalized() {
            let reach = (armpit - q0).dot(d);
            let n = (reach / lstep).floor().max(0.0) as usize;
            let inward: Vec<(Point3, Real)> = (1..=n)
                .rev()
                .map(|k| (q0 + d * (reach * k as Real / n as Real), r0))
                .collect();
            axis_pts.splice(0..0, inward);
        }
    }
    let tip = g.nodes[first].centroid + axis * (min - g.nodes[first].centroid.dot(axis));
    axis_pts.push((tip, g.nodes[first].radius));
    Some(LateralArm {
        axis: axis_pts,
        armpit,
        tip,
    })
}

/// Extends an arm's axis from its last slice to the fingertips: the input
/// points within a cylinder around the direction from 60 % of the arm to
/// its end (radius three
/// times the arm's radius at the hand, reaching up to a fifth of the arm's
/// length beyond the end) are projected on that direction; the farthest
/// gives the tip, and the axis gets a straight piece out to it. Returns the
/// tip, or `None` when nothing lies beyond the end.
fn extend_to_fingertips(positions: &[Point3], arm: &mut PartAxis) -> Option<Point3> {
    let n = arm.points.len();
    let end = *arm.points.last()?;
    // The direction of the forearm and hand (the last slices alone wobble
    // in a scan).
    let (before, _) = arm.point_and_tangent(0.6)?;
    let dir = (end - before).normalized()?;
    let r = 3.0
        * arm
            .radii
            .get(n.saturating_sub(n / 10 + 1)..)?
            .iter()
            .copied()
            .fold(0.0, Real::max);
    let reach = 0.2 * arm.length();
    let mut best: Real = 0.0;
    for &p in positions {
        let d = p - end;
        let along = d.dot(dir);
        if along > best && along <= reach && (d - dir * along).norm() <= r {
            best = along;
        }
    }
    if best.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let tip = end + dir * best;
    let r_end = arm.radii.last().copied().unwrap_or(0.0);
    let spacing = arm.length() / (n.max(2) - 1) as Real;
    let extra = ((best / spacing.max(Real::MIN_POSITIVE)).ceil() as usize).clamp(1, 1000);
    for i in 1..=extra {
        let t = i as Real / extra as Real;
        arm.points.push(end + dir * (best * t));
        arm.radii.push(r_end * (1.0 - 0.5 * t));
    }
    Some(tip)
}

/// Continues an arm's axis past its proximal end (the armpit) into the
/// shoulder, as method.md §8.5 suggests: step along the direction of the
/// arm's proximal tenth, cut perpendicular to it, and keep the loop around
/// the axis while it stays an arm's loop (area at most 1.5 times the arm's
/// typical area near its top, centre within one arm radius of the step
/// point); the first cut that merges with the trunk ends it. Prepends the
/// new centres to the axis and returns the new proximal end, or `None`
/// when the first cut already merges.
/// A slicer across `dir` for the geometry near a point: plane sections of a
/// mesh, or occupancy components of a cloud's slabs (cells `graph_cell` ×
/// the point spacing, which a cloud needs).
fn axis_slicer<'a>(
    local: &'a Local,
    dir: Vec3,
    spacing: Option<Real>,
    opts: &SegmentOptions,
) -> Option<AxisSlicer<'a>> {
    Some(match local {
        Local::Mesh(m) => AxisSlicer::Mesh(MeshSlicer::new(m, dir, &opts.section).ok()?),
        Local::Cloud(c) => {
            let spacing = spacing?;
            let graph = ScanSectionOptions {
                cell_size: Some(opts.scan.cell_size.unwrap_or(spacing) * opts.graph_cell),
                closing_radius: opts.graph_closing,
                ..opts.scan
            };
            AxisSlicer::Cloud(SlabComponents::new(&c.positions, dir, spacing, &graph).ok()?)
        }
    })
}

fn extend_into_shoulder(
    body: BodyGeometry<'_>,
    arm: &mut PartAxis,
    opts: &SegmentOptions,
    spacing: Option<Real>,
    step: Real,
) -> Option<Point3> {
    let p0 = *arm.points.first()?;
    let (p1, _) = arm.point_and_tangent(0.1)?;
    let dir = (p0 - p1).normalized()?;
    let k_top = (arm.radii.len() / 4).max(1);
    let mut top: Vec<Real> = arm.radii.get(..k_top)?.to_vec();
    top.sort_by(|a, b| a.total_cmp(b));
    let r = top[top.len() / 2];
    if r.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let area = std::f64::consts::PI * r * r;
    let reach = 4.0 * r;
    let local = local_geometry(body, p0 + dir * (0.5 * reach), reach + 4.0 * r);
    let slicer = axis_slicer(&local, dir, spacing, opts)?;
    let e1 = dir.any_perpendicular();
    let e2 = dir.cross(e1);
    let mut added: Vec<(Point3, Real)> = Vec::new();
    let steps = (reach / step).ceil() as usize;
    let mut centre = p0;
    for _ in 0..steps {
        let q = centre + dir * step;
        let q2 = Vec2::new(q.dot(e1), q.dot(e2));
        let nodes = slicer.nodes_at(q.dot(dir), e1, e2);
        let Some(nd) = nodes
            .iter()
            .filter(|nd| point_in_polygon(q2, &nd.poly) || (nd.c2 - q2).norm() < r)
            .min_by(|a, b| (a.c2 - q2).norm().total_cmp(&(b.c2 - q2).norm()))
        else {
            break;
        };
        if nd.area > 1.5 * area || (nd.c2 - q2).norm() > r {
            break;
        }
        centre = nd.centroid;
        added.push((nd.centroid, nd.radius));
    }
    let end = added.last()?.0;
    let mut points: Vec<Point3> = added.iter().rev().map(|a| a.0).collect();
    let mut radii: Vec<Real> = added.iter().rev().map(|a| a.1).collect();
    points.extend(arm.points.iter().copied());
    radii.extend(arm.radii.iter().copied());
    arm.points = points;
    arm.radii = radii;
    Some(end)
}

/// The wrist on cuts perpendicular to the arm's distal half: walking up
/// from the hand tip, the widest cut (the hand) comes first; the narrowest
/// cut between it and the middle of the arm is the wrist. All cuts are
/// parallel (normal = the distal half's direction), so one sorted slicer
/// serves them all.
fn find_wrist(
    body: BodyGeometry<'_>,
    arm: &PartAxis,
    opts: &SegmentOptions,
    spacing: Option<Real>,
    kind: LandmarkKind,
) -> Option<Landmark> {
    let (mid, _) = arm.point_and_tangent(0.45)?;
    let (tip, _) = arm.point_and_tangent(1.0)?;
    let dir = (tip - mid).normalized()?;
    let len = tip.distance(mid);
    let r = arm.max_radius();
    let centre = (mid + tip) * 0.5;
    let local = local_geometry(body, centre, 0.5 * len + 3.0 * r);
    let slicer = axis_slicer(&local, dir, spacing, opts)?;
    let e1 = dir.any_perpendicular();
    let e2 = dir.cross(e1);
    let count = 40;
    // Cuts at fractions 0.45..0.97 of the arm: (fraction, hull girth, point).
    // The axis points first (none missing), then the slabs' components
    // over the cores (independent, in order).
    let at: Vec<(Real, Point3)> = (0..=count)
        .map(|i| {
            let f = 0.45 + 0.52 * i as Real / count as Real;
            arm.point_and_tangent(f).map(|(p, _)| (f, p))
        })
        .collect::<Option<_>>()?;
    let slices: Vec<Vec<Node>> = crate::geom::parallel::parallel_map(&at, 8, |run| {
        run.iter()
            .map(|&(_, p)| slicer.nodes_at(p.dot(dir), e1, e2))
            .collect()
    });
    let mut cuts: Vec<(Real, Real, Point3)> = Vec::new();
    for (&(f, p), nodes) in at.iter().zip(slices) {
        // Hull of every loop near the axis point (fingers count as hand).
        let near: Vec<&Node> = nodes
            .iter()
            .filter(|nd| nd.centroid.distance(p) <= 1.5 * r)
            .collect();
        let pts: Vec<Point2> = near.iter().flat_map(|nd| nd.poly.iter().copied()).collect();
        let m: Real = near.iter().map(|nd| nd.area).sum();
        if pts.len() >= 3 && m > 0.0 {
            let c = near
                .iter()
                .fold(Vec3::ZERO, |s, nd| s + nd.centroid * nd.area)
                / m;
            cuts.push((f, hull_perimeter(&pts), c));
        }
    }
    if cuts.len() < 5 {
        return None;
    }
    // The hand's widest cut in the distal part of the range.
    let hand = cuts
        .iter()
        .filter(|c| c.0 >= 0.72)
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let wrist = cuts
        .iter()
        .filter(|c| c.0 < hand.0)
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let max_before = cuts
        .iter()
        .filter(|c| c.0 <= wrist.0)
        .map(|c| c.1)
        .fold(0.0, Real::max);
    let contrast = if hand.1 > 0.0 && max_before > 0.0 {
        (1.0 - wrist.1 / hand.1.min(max_before)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Some(Landmark {
        kind,
        position: wrist.2,
        height_fraction: 0.0,
        confidence: contrast,
        how:
            "narrowest perpendicular cut of the forearm between the elbow and the hand's widest cut",
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::section::girth::{from_height_key, monotone_chain};

    /// The slicing's sort handed to the cutter along `up = ±axis`: heights
    /// ascending and equal to `p·up` for the points in that order, each
    /// point once; nothing for another `up`.
    #[test]
    fn sorted_up_follows_the_axis_either_way() {
        let mut rng = crate::geom::rng::Rng::new(5);
        let points: Vec<Point3> = (0..3000)
            .map(|k| {
                // Repeated heights (ties) among random ones.
                let y = if k % 3 == 0 {
                    (k % 7) as Real * 0.1
                } else {
                    rng.uniform() - 0.5
                };
                Vec3::new(rng.uniform(), y, rng.uniform())
            })
            .collect();
        let cloud = PointCloud {
            positions: points.clone(),
            normals: None,
        };
        let slicer = || CloudSlicer::new(&cloud, Vec3::new(0.1, 1.0, -0.2)).unwrap();
        let axis = slicer().axis();
        for up in [axis, -axis] {
            let got = SortedUp::along(Some((axis, slicer().into_sorted())), up);
            let (order, heights) = got.0.as_deref().expect("a sort for ±axis");
            assert!(heights.windows(2).all(|w| w[0] <= w[1]));
            for (&i, &h) in order.iter().zip(heights) {
                assert_eq!(points[i as usize].dot(up), h);
            }
            let mut seen = order.clone();
            seen.sort_unstable();
            assert!(seen.iter().enumerate().all(|(k, &i)| k as u32 == i));
        }
        let nearly = Vec3::new(axis.x, axis.y, f64::from_bits(axis.z.to_bits() + 1));
        for up in [Vec3::X, nearly] {
            assert!(SortedUp::along(Some((axis, slicer().into_sorted())), up)
                .0
                .is_none());
        }
    }

    /// The hull from integer keys is the hull of the comparator sort it
    /// replaced, point for point and bit for bit (duplicates, signed
    /// zeros, collinear and grid points included); the keys decode to the
    /// same bits.
    #[test]
    fn keyed_hull_is_the_comparator_hull() {
        // The comparator sort the keys replaced, then the same chain.
        let reference = |p: &[Point2]| {
            let mut pts: Vec<Point2> = p.to_vec();
            pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
            monotone_chain(pts)
        };
        let bits = |h: &[Point2]| -> Vec<[u64; 2]> {
            h.iter().map(|p| [p.x.to_bits(), p.y.to_bits()]).collect()
        };
        let mut rng = crate::geom::rng::Rng::new(11);
        for case in 0..200 {
            let n = 1 + case % 60;
            let mut pts: Vec<Point2> = (0..n)
                .map(|_| match case % 4 {
                    // On a coarse grid: many duplicates and collinear runs.
                    0 => Vec2::new(
                        (4.0 * rng.uniform()).floor() - 2.0,
                        (3.0 * rng.uniform()).floor() - 1.0,
                    ),
                    1 => Vec2::new(rng.uniform() - 0.5, 0.0),
                    _ => Vec2::new(rng.gaussian(), 0.3 * rng.gaussian()),
                })
                .collect();
            if case % 5 == 0 {
                pts.push(Vec2::new(-0.0, 0.0));
                pts.push(Vec2::new(0.0, -0.0));
            }
            assert_eq!(
                bits(&convex_hull(&pts)),
                bits(&reference(&pts)),
                "case {case}"
            );
        }
        for x in [
            0.0,
            -0.0,
            1.5,
            -1.5,
            1e-300,
            -1e300,
            Real::INFINITY,
            Real::MIN,
        ] {
            assert_eq!(from_height_key(height_key(x)).to_bits(), x.to_bits());
        }
    }

    /// A point is in an arm's tube when nearer its nearest axis point than
    /// the radius there, never at the axis's first point (the shoulder
    /// end, where the torso is); the axis points near a plane answer as
    /// the whole axis for points near it.
    #[test]
    fn in_arm_is_the_tube_past_the_shoulder() {
        let arm = PartAxis {
            name: PartName::LeftArm,
            points: (0..=10)
                .map(|k| Vec3::new(0.3, 1.4 - 0.05 * k as Real, 0.0))
                .collect(),
            radii: vec![0.05; 11],
            start: LandmarkKind::LeftArmpit,
            end: LandmarkKind::LeftWrist,
        };
        let all: Vec<AxisBall> = arm
            .points
            .iter()
            .zip(&arm.radii)
            .enumerate()
            .map(|(k, (q, r))| (k, *q, *r))
            .collect();
        assert!(in_arm(&all, Vec3::new(0.34, 1.2, 0.0)));
        assert!(in_arm(&all, Vec3::new(0.3, 1.0, 0.049)));
        assert!(!in_arm(&all, Vec3::new(0.36, 1.2, 0.0)));
        assert!(!in_arm(&all, Vec3::new(0.2, 1.2, 0.0)));
        // nearest the first axis point: the shoulder end, not the arm
        assert!(!in_arm(&all, Vec3::new(0.3, 1.41, 0.0)));
        // Near a plane, its nearby axis points answer as the whole axis.
        let mut rng = crate::geom::rng::Rng::new(4);
        for h in [1.42, 1.3, 1.12, 0.9] {
            let plane = Plane::new(Vec3::new(0.0, h, 0.0), Vec3::Y).unwrap();
            let near = near_axis(&arm, &plane, 0.01);
            for _ in 0..500 {
                let p = Vec3::new(
                    0.2 + 0.2 * rng.uniform(),
                    h + 0.02 * (rng.uniform() - 0.5),
                    0.1 * (rng.uniform() - 0.5),
                );
                assert_eq!(in_arm(&near, p), in_arm(&all, p), "{p:?}");
            }
        }
    }
    use crate::geom::shapes;

    fn cube(size: Real) -> Mesh {
        let s = size;
        let p = |x: Real, y: Real, z: Real| Vec3::new(x * s, y * s, z * s);
        let positions = vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(1.0, 1.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(0.0, 0.0, 1.0),
            p(1.0, 0.0, 1.0),
            p(1.0, 1.0, 1.0),
            p(0.0, 1.0, 1.0),
        ];
        let triangles = vec![
            [0, 2, 1],
            [0, 3, 2],
            [4, 5, 6],
            [4, 6, 7],
            [0, 1, 5],
            [0, 5, 4],
            [1, 2, 6],
            [1, 6, 5],
            [2, 3, 7],
            [2, 7, 6],
            [3, 0, 4],
            [3, 4, 7],
        ];
        Mesh::new(positions, triangles).unwrap()
    }

    fn not_standing(err: SegmentError) -> (&'static str, String) {
        match err {
            SegmentError::NotAStandingBody { what, why } => (what, why),
            e => panic!("expected NotAStandingBody, got {e}"),
        }
    }

    #[test]
    fn sphere_has_no_up_axis() {
        let ball = shapes::uv_sphere(Vec3::new(3.0, -2.0, 1.0), 0.5, 48, 96);
        let err = segment(BodyGeometry::Mesh(&ball), &SegmentOptions::default()).unwrap_err();
        assert!(matches!(err, SegmentError::NoUpAxis { .. }), "{err}");
        assert!(err.to_string().contains("pass the up axis"));
    }

    #[test]
    fn sphere_with_up_has_no_legs() {
        let ball = shapes::uv_sphere(Vec3::ZERO, 0.5, 48, 96);
        let opts = SegmentOptions {
            up: Some(Vec3::Z),
            ..Default::default()
        };
        let (what, why) = not_standing(segment(BodyGeometry::Mesh(&ball), &opts).unwrap_err());
        assert_eq!(what, "two legs");
        assert!(why.contains("never split into two feet"), "{why}");
    }

    #[test]
    fn cube_is_rejected_with_or_without_up() {
        let c = cube(2.0);
        let err = segment(BodyGeometry::Mesh(&c), &SegmentOptions::default()).unwrap_err();
        assert!(matches!(err, SegmentError::NoUpAxis { .. }), "{err}");
        let opts = SegmentOptions {
            up: Some(Vec3::new(0.0, 0.0, -1.0)),
            ..Default::default()
        };
        let (what, _) = not_standing(segment(BodyGeometry::Mesh(&c), &opts).unwrap_err());
        assert_eq!(what, "two legs");
    }

    #[test]
    fn cube_cloud_is_rejected() {
        let c = PointCloud::from(cube(1.0));
        let err = segment(BodyGeometry::Cloud(&c), &SegmentOptions::default()).unwrap_err();
        assert!(matches!(err, SegmentError::NoUpAxis { .. }), "{err}");
    }

    #[test]
    fn long_cylinder_has_no_feet() {
        let rod = shapes::cylinder(Vec3::ZERO, 0.1, 2.0, 40, 48);
        let (what, why) = not_standing(
            segment(BodyGeometry::Mesh(&rod), &SegmentOptions::default()).unwrap_err(),
        );
        assert_eq!(what, "two feet at either end of the longest axis");
        assert!(why.contains("0 %"), "{why}");
    }

    #[test]
    fn empty_and_bad_options_are_errors() {
        let empty = PointCloud::default();
        assert!(matches!(
            segment(BodyGeometry::Cloud(&empty), &SegmentOptions::default()),
            Err(SegmentError::Input(_))
        ));
        let mut nan = PointCloud::from(cube(1.0));
        nan.positions[3].y = Real::NAN;
        assert!(matches!(
            segment(BodyGeometry::Cloud(&nan), &SegmentOptions::default()),
            Err(SegmentError::Input(_))
        ));
        let ball = shapes::uv_sphere(Vec3::ZERO, 0.5, 8, 16);
        for opts in [
            SegmentOptions {
                slices: 3,
                ..Default::default()
            },
            SegmentOptions {
                min_loop_area: Real::NAN,
                ..Default::default()
            },
            SegmentOptions {
                up: Some(Vec3::ZERO),
                ..Default::default()
            },
        ] {
            assert!(matches!(
                segment(BodyGeometry::Mesh(&ball), &opts),
                Err(SegmentError::BadOption { .. })
            ));
        }
    }

    /// The stick body's arms hang beside the trunk without touching it, so
    /// no arm joins the trunk: a partial model that says so, never arms
    /// guessed. Legs, crotch, trunk and head are found.
    #[test]
    fn stick_body_is_partial_with_warnings() {
        let body = shapes::stick_body(2);
        let s = segment(BodyGeometry::Mesh(&body), &SegmentOptions::default()).unwrap();
        assert!(
            (s.frame.up.dot(Vec3::Z) - 1.0).abs() < 1e-6,
            "{:?}",
            s.frame.up
        );
        let crotch = s.landmark(LandmarkKind::Crotch).unwrap();
        // The trunk cylinder starts at z = 0.8 of a 1.66 tall body.
        assert!(
            (crotch.position.z - 0.8).abs() < 0.01,
            "{:?}",
            crotch.position
        );
        for name in [
            PartName::Torso,
            PartName::Head,
            PartName::LeftLeg,
            PartName::RightLeg,
        ] {
            assert!(s.part(name).is_some(), "{name} missing");
        }
        assert!(s.part(PartName::LeftArm).is_none());
        assert!(s
            .warnings
            .iter()
            .any(|w| w.starts_with("left arm not found")));
        assert!(s
            .warnings
            .iter()
            .any(|w| w.starts_with("right arm not found")));
    }

    /// The cut the way it was made before the [`Cutter`]: the geometry in
    /// the ball around the axis point, sliced on its own.
    fn ball_cut(
        body: BodyGeometry<'_>,
        seg: &Segmentation,
        part: PartName,
        at: Real,
        normal: Option<Vec3>,
    ) -> Vec<(SectionLoop, Option<Vec<usize>>)> {
        let axis = seg.part(part).unwrap();
        let (p, t) = axis.point_and_tangent(at).unwrap();
        let n = match normal {
            Some(n) if n.dot(t) < 0.0 => -n,
            Some(n) => n,
            None => t,
        };
        let plane = Plane::new(p, n).unwrap();
        let radius = 3.0 * axis.max_radius().max(seg.height * 0.02);
        let r2 = radius * radius;
        match body {
            BodyGeometry::Mesh(m) => {
                section_mesh(&local_mesh(m, p, radius), &plane, &Default::default())
                    .map(|s| s.loops.into_iter().map(|l| (l, None)).collect())
                    .unwrap_or_default()
            }
            BodyGeometry::Cloud(c) => {
                let idx: Vec<usize> = (0..c.positions.len())
                    .filter(|&i| (c.positions[i] - p).norm_squared() <= r2)
                    .collect();
                let local = PointCloud {
                    positions: idx.iter().map(|&i| c.positions[i]).collect(),
                    normals: None,
                };
                let so = ScanSectionOptions {
                    half_thickness: seg.point_spacing,
                    cell_size: seg.point_spacing,
                    ..Default::default()
                };
                CloudSlicer::new(&local, plane.normal)
                    .unwrap()
                    .section_at(plane.offset(), &so)
                    .map(|s| {
                        s.loops
                            .into_iter()
                            .map(|l| {
                                let ids = l.scan_indices.iter().map(|&k| idx[k]).collect();
                                (l.outline, Some(ids))
                            })
                            .collect()
                    })
                    .unwrap_or_default()
            }
        }
    }

    #[test]
    fn cutter_gives_the_ball_cuts() {
        let mesh = shapes::stick_body(2);
        let scan = crate::spatial::scanner::virtual_scan(
            &mesh,
            &crate::spatial::scanner::ScannerOptions {
                points: 60_000,
                ..Default::default()
            },
        )
        .unwrap()
        .cloud;
        let opts = SegmentOptions::default();
        for body in [BodyGeometry::Mesh(&mesh), BodyGeometry::Cloud(&scan)] {
            let seg = segment(body, &opts).unwrap();
            let cutter = Cutter::new(body, &seg);
            let up = seg.frame.up;
            let mut compared = 0;
            for part in [PartName::Torso, PartName::Head, PartName::LeftLeg] {
                for k in 1..10 {
                    let at = k as Real / 10.0;
                    // Horizontal (shared slicers) and along the axis (ball grids).
                    for normal in [Some(up), None] {
                        let Ok(cut) = cutter.cut(part, at, normal, true, &opts) else {
                            continue;
                        };
                        let reference = ball_cut(body, &seg, part, at, normal);
                        // One cut on its own is the ball's cut exactly.
                        let once =
                            cut_part_along(body, &seg, part, at, normal, true, &opts).unwrap();
                        assert!(reference
                            .iter()
                            .any(|(l, ids)| l.points == once.outline.points
                                && *ids == once.scan_indices));
                        let same = reference.iter().any(|(l, ids)| {
                            if matches!(body, BodyGeometry::Cloud(_)) || normal.is_none() {
                                // Exactly the same points.
                                l.points == cut.outline.points && *ids == cut.scan_indices
                            } else {
                                // The whole mesh's loop: the same polygon, maybe
                                // starting elsewhere.
                                l.points.len() == cut.outline.points.len()
                                    && (l.area - cut.outline.area).abs() <= 1e-12 * l.area
                                    && l.points.iter().all(|p| cut.outline.points.contains(p))
                            }
                        });
                        assert!(same, "{part} at {at} normal {normal:?}");
                        compared += 1;
                    }
                }
            }
            assert!(compared >= 40, "{compared}");
        }
    }

    #[test]
    fn hull_and_box_filter() {
        let sq = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.5, 0.5),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        assert!((hull_perimeter(&sq) - 4.0).abs() < 1e-12);
        // Closing a one-cell gap in a row with radius 1.
        let (w, h) = (9, 5);
        let mut img = vec![false; w * h];
        for x in [2, 3, 5, 6] {
            img[2 * w + x] = true;
        }
        let closed = box_filter(&box_filter(&img, w, h, 1, true), w, h, 1, false);
        assert!((2..=6).all(|x| closed[2 * w + x]));
        assert!(!closed[2 * w + 1] && !closed[2 * w + 7]);
    }

    #[test]
    fn axis_smoothing_keeps_a_line_and_resamples() {
        let pts: Vec<(Point3, Real)> = (0..50)
            .map(|i| (Vec3::new(0.0, 0.0, i as Real * 0.01), 0.1))
            .collect();
        let (p, r) = smooth_axis(&pts, 0.03, 0.01);
        assert_eq!(p.len(), r.len());
        assert!(p.iter().all(|q| q.x.abs() < 1e-12 && q.y.abs() < 1e-12));
        assert!((p[0].z).abs() < 1e-12 && (p[p.len() - 1].z - 0.49).abs() < 1e-12);
        let axis = PartAxis {
            name: PartName::Torso,
            points: p,
            radii: r,
            start: LandmarkKind::Crotch,
            end: LandmarkKind::Neck,
        };
        let (q, t) = axis.point_and_tangent(0.5).unwrap();
        assert!((q.z - 0.245).abs() < 1e-9 && (t.z - 1.0).abs() < 1e-9);
    }
}
