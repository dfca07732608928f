//! Cuts perpendicular to a part's axis: [`cut_part`], [`cut_part_along`]
//! and the [`Cutter`] that shares what many cuts of one body need.

use crate::anatomy::{BodyGeometry, PartName};
use crate::geom::math::{Point2, Point3, Real, Vec2, Vec3};
use crate::geom::mesh::{Mesh, PointCloud};
use crate::geom::tolerance::ROUNDING_MARGIN;
use crate::section::cloud::{
    height_key, keyed_heights, section_of_slab, sort_keyed, sorted_heights, CloudSlicer,
    ScanSectionOptions, Slab,
};
use crate::section::girth::convex_hull;
use crate::section::inlets::{bridge_inlets, Facing, InletRule};
use crate::section::mesh::{section_mesh, MeshSlicer, Plane, SectionLoop};
use crate::segment::{HeightSort, PartAxis, PartCut, SegmentError, SegmentOptions, Segmentation};
use std::sync::OnceLock;

/// A mesh head's loop is taken with a pocket bridged
/// (`section::inlets::bridge_inlets`) that holds at least this share of its area: a cut
/// that follows a modelled mouth's skin in through the parted lips takes
/// the straight line across instead (the pocket itself is lined by a
/// cavity of the head, `body::cavity`). The folds behind the
/// ears, the nostrils and the eye sockets hold far less (the eye sockets,
/// opening to the front, have [`MIN_FACING_POCKET_SHARE`]). Only the head has
/// such a pocket: elsewhere a deep fold is the gap between two toes or
/// between an arm and the chest, which the model follows; and a cloud's
/// slab outline is left as it is (a scanner sees no pocket).
pub const MIN_POCKET_SHARE: Real = 0.1;

/// A mesh head's pocket that opens to the front is bridged from this
/// share of the loop's area: an eye socket, where a cut runs in through
/// the parted eyelids and round the eyeball (2.5 % of a head's loop). Its
/// extra length shifted the whole loop's parameter against its
/// neighbours', and the skin twisted in a band all round the head. The
/// pocket is lined by a cavity instead (`body::cavity`). The folds behind
/// the ears and in them, which lower shares also took, open sideways or
/// back.
pub const MIN_FACING_POCKET_SHARE: Real = 0.005;

/// A front-facing pocket of a mesh head holds at least this many times
/// its mouth's width squared (not `section::inlets::MIN_POCKET`'s 3):
/// where the lids part widest the socket is a cup as deep as its mouth is
/// wide (the built-in body at eye level: a 14 mm mouth over a 22 mm cup),
/// and that level kept the twisted band. A half disc holds 0.39 times
/// its width squared: the face's shallow hollows stay.
pub const MIN_FACING_POCKET: Real = 1.0;

/// A plane's loops as the cutter takes them ([`Cutter::cut_loops`]): the
/// part's is `loops[k]`, and `pockets` are those bridged off it (a mesh
/// head's, [`bridge_inlets`]).
struct PlaneLoops {
    plane: Plane,
    loops: Vec<(SectionLoop, Option<Vec<usize>>)>,
    k: usize,
    pockets: Vec<SectionLoop>,
}

/// One loop round several of a plane's loops (toes apart): their convex
/// hull, its edges split no longer than the loops' median edge, with the
/// loops' cloud indices together.
fn hull_of_loops(
    loops: Vec<(SectionLoop, Option<Vec<usize>>)>,
) -> Option<(SectionLoop, Option<Vec<usize>>)> {
    let frame = loops.first()?.0.frame;
    let (o, e1, e2) = (frame.origin, frame.e1, frame.e2);
    let mut edges: Vec<Real> = Vec::new();
    let mut flat = Vec::new();
    for (l, _) in &loops {
        let n = l.points.len();
        for (k, &p) in l.points.iter().enumerate() {
            edges.push(p.distance(l.points[(k + 1) % n]));
            flat.push(Point2::new((p - o).dot(e1), (p - o).dot(e2)));
        }
    }
    let step = crate::geom::stats::median(&mut edges)?.max(Real::EPSILON);
    let hull = convex_hull(&flat);
    let mut points = Vec::new();
    for (k, &a) in hull.iter().enumerate() {
        let b = hull[(k + 1) % hull.len()];
        let pieces = ((b - a).norm() / step).ceil().max(1.0) as usize;
        for j in 0..pieces {
            let q = a + (b - a) * (j as Real / pieces as Real);
            points.push(o + e1 * q.x + e2 * q.y);
        }
    }
    let indices = loops
        .iter()
        .map(|(_, i)| i.clone())
        .collect::<Option<Vec<Vec<usize>>>>()
        .map(|v| v.concat());
    Some((SectionLoop::from_points(points, e1, e2)?, indices))
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
    unseen: OnceLock<Option<Vec3>>,
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
            unseen: OnceLock::new(),
        }
    }

    /// The horizontal direction a cloud was not seen from when it was
    /// seen from one side only ([`unseen_side`]: slabs through the trunk
    /// from a fifth to three fifths of the torso's axis, the points within
    /// 0.15 H of it); `None` for a mesh or a cloud seen all round.
    pub fn unseen_side(&self) -> Option<Vec3> {
        *self.unseen.get_or_init(|| {
            let BodyGeometry::Cloud(cloud) = self.body else {
                return None;
            };
            let (seg, f) = (self.seg, &self.seg.frame);
            let torso = seg.part(PartName::Torso)?;
            let half = 1.5 * self.seg.point_spacing.unwrap_or(0.002 * seg.height);
            let centres: Vec<Point3> = (0..12)
                .filter_map(|k| torso.point_and_tangent(0.2 + 0.4 * k as Real / 11.0))
                .map(|(p, _)| p)
                .collect();
            let mut slabs = vec![Vec::new(); centres.len()];
            for &p in &cloud.positions {
                for (slab, c) in slabs.iter_mut().zip(&centres) {
                    let d = p - *c;
                    let across = d - f.up * d.dot(f.up);
                    if d.dot(f.up).abs() <= half && across.norm() <= 0.15 * seg.height {
                        slab.push(Vec2::new(across.dot(f.left), across.dot(f.front)));
                    }
                }
            }
            let v = crate::section::cloud::unseen_side(&slabs)?;
            (f.left * v.x + f.front * v.y).normalized()
        })
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
        let PlaneLoops {
            plane, loops, k, ..
        } = self.cut_loops(part, at, normal, outermost, opts)?;
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

    /// [`Cutter::cut`], but the part's loop is made of the loops whose
    /// centroids `within` accepts, not the one around the axis point: the
    /// largest when it holds half their area or more, else their hull
    /// ([`hull_of_loops`]: toes apart). A run of a part's end follows its
    /// previous outline this way where the outlines leave the axis (a
    /// tilted foot's toes ahead of the line down from the ankle, where the
    /// loop nearest that line can be a stray fragment).
    pub fn cut_within(
        &self,
        part: PartName,
        at: Real,
        normal: Option<Vec3>,
        within: &dyn Fn(Point3) -> bool,
        opts: &SegmentOptions,
    ) -> Result<PartCut, SegmentError> {
        let PlaneLoops { plane, loops, .. } = self.cut_loops(part, at, normal, true, opts)?;
        let mut kept: Vec<_> = loops
            .into_iter()
            .filter(|(l, _)| within(l.centroid))
            .collect();
        kept.sort_by(|a, b| b.0.area.total_cmp(&a.0.area));
        let total: Real = kept.iter().map(|(l, _)| l.area).sum();
        let (outline, scan_indices) = match kept.first() {
            None => return Err(SegmentError::EmptyCut { part, at }),
            // A loop holding half the area or more is the part's (a sole's
            // outline with a toe or two beside it: a hull would fill the
            // arch).
            Some((l, _)) if l.area >= 0.5 * total => kept.swap_remove(0),
            _ => hull_of_loops(kept).ok_or(SegmentError::EmptyCut { part, at })?,
        };
        Ok(PartCut {
            plane,
            outline,
            scan_indices,
        })
    }

    /// Every loop of the plane through `part`'s axis point at `at` with
    /// the normal `normal` (`None`: the axis tangent) near that point, with
    /// the plane: a hand's cut past the knuckles meets each finger apart.
    pub fn loops_at(
        &self,
        part: PartName,
        at: Real,
        normal: Option<Vec3>,
        opts: &SegmentOptions,
    ) -> Result<(Plane, Vec<SectionLoop>), SegmentError> {
        let PlaneLoops { plane, loops, .. } = self.cut_loops(part, at, normal, true, opts)?;
        Ok((plane, loops.into_iter().map(|(l, _)| l).collect()))
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
        let PlaneLoops {
            plane,
            loops,
            k,
            pockets,
        } = self.cut_loops(part, at, normal, true, opts)?;
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
                // The pockets bridged off the outline (its lining where the
                // pocket opens through a slit) are pockets too.
                inside
                    .into_iter()
                    .zip(depth_one)
                    .filter_map(|(l, keep)| keep.then_some(l))
                    .chain(pockets)
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

    /// A cloud's slab options: `opts.scan` with the half-thickness and
    /// cell size the cloud's point spacing gives where unset (the
    /// segmentation's spacing, else estimated once). `None` for a mesh or
    /// a cloud whose spacing is unknown.
    pub(crate) fn slab_options(&self, opts: &SegmentOptions) -> Option<ScanSectionOptions> {
        let BodyGeometry::Cloud(c) = self.body else {
            return None;
        };
        let spacing = (*self.spacing.get_or_init(|| {
            self.seg.point_spacing.or_else(|| {
                CloudSlicer::new(c, self.seg.frame.up)
                    .ok()
                    .map(|s| s.spacing())
            })
        }))?;
        Some(ScanSectionOptions {
            half_thickness: opts.scan.half_thickness.or(Some(spacing)),
            cell_size: opts.scan.cell_size.or(Some(spacing)),
            ..opts.scan
        })
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
    ) -> Result<PlaneLoops, SegmentError> {
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
        let left_out = self.left_out(part, &plane, opts);
        let mut pockets = Vec::new();
        let loops: Vec<_> = self
            .loops(&plane, p, radius, opts, &left_out)
            .into_iter()
            .map(|(l, i)| match self.body {
                BodyGeometry::Mesh(_) if part == PartName::Head => {
                    let rule = InletRule {
                        min_share: MIN_POCKET_SHARE,
                        facing: Some(Facing {
                            dir: self.seg.frame.front,
                            min_share: MIN_FACING_POCKET_SHARE,
                            min_pocket: MIN_FACING_POCKET,
                        }),
                    };
                    let (bridged, bridged_pockets) = bridge_inlets(&l, &rule);
                    pockets.push(bridged_pockets);
                    (bridged, i)
                }
                _ => {
                    pockets.push(Vec::new());
                    (l, i)
                }
            })
            .collect();
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
        let pockets = pockets.swap_remove(k);
        Ok(PlaneLoops {
            plane,
            loops,
            k,
            pockets,
        })
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

    /// What `part`'s slab in `plane` leaves out of a cloud ([`SlabExclusion`]).
    fn left_out(&self, part: PartName, plane: &Plane, opts: &SegmentOptions) -> SlabExclusion {
        // Two surfaces closer than the image's closing bridges are one blob.
        let cell = opts
            .scan
            .cell_size
            .or(self.seg.point_spacing)
            .unwrap_or(0.0);
        let bridged = 2.0 * opts.scan.closing_radius as Real * cell;
        SlabExclusion {
            arms: self.torso_arms(part, plane),
            beyond: self.other_leg(part, plane, bridged),
        }
    }

    /// For a leg's cut of a cloud, the half-space of the other leg: beyond
    /// the plane midway between the two legs' axis points in `plane`
    /// (normal to the line between them, in the plane). Thighs that touch
    /// are one blob in a scan's slab, and a leg's loop round both folds
    /// (body_003_scan's crotch, 9 mm RMS there); without the other leg's
    /// points its loop is its own, the contact bridged like a scanner's
    /// hole. `None` for other parts, a mesh (its loops are exact), where
    /// the other leg's axis does not cross the plane, or where the legs'
    /// surfaces lie farther apart than the slab image's closing bridges
    /// (their radii there and `reach`: then the other leg is a loop of its
    /// own).
    fn other_leg(&self, part: PartName, plane: &Plane, reach: Real) -> Option<(Point3, Vec3)> {
        let other = match part {
            PartName::LeftLeg => PartName::RightLeg,
            PartName::RightLeg => PartName::LeftLeg,
            _ => return None,
        };
        if !matches!(self.body, BodyGeometry::Cloud(_)) {
            return None;
        }
        let (mine, axis) = (self.seg.part(part)?, self.seg.part(other)?);
        let n = plane.normal.normalized()?;
        let q = axis.point_at_level(n, plane.origin.dot(n))?;
        let d = q - plane.origin;
        let flat = d - n * d.dot(n);
        if flat.norm() > mine.radius_near(plane.origin) + axis.radius_near(q) + reach {
            return None;
        }
        Some((plane.origin + flat * 0.5, flat.normalized()?))
    }

    /// All loops in `plane` of the geometry near `centre` (see the type's
    /// doc), with cloud indices; a cloud's points that `left_out` names
    /// ([`SlabExclusion`]) left out.
    fn loops(
        &self,
        plane: &Plane,
        centre: Point3,
        radius: Real,
        opts: &SegmentOptions,
        left_out: &SlabExclusion,
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
            BodyGeometry::Cloud(c) => self.cloud_loops(c, plane, centre, radius, opts, left_out),
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
        left_out: &SlabExclusion,
    ) -> Vec<(SectionLoop, Option<Vec<usize>>)> {
        let Some(axis) = plane.normal.normalized() else {
            return Vec::new();
        };
        let Some(so) = self.slab_options(opts) else {
            return Vec::new();
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
                if h >= offset - t && h <= offset + t && !left_out.excludes(p) {
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
                let pad = ROUNDING_MARGIN * (c_up.abs() + t);
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
        let slab = Slab {
            positions: pos,
            normals: None,
            axis,
            offset,
            ids: &ids,
            half_thickness: t,
        };
        let section = section_of_slab(&slab, g, &so);
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
const ARMPIT_ABOVE: Real = 0.01;

/// An arm's axis point: its index along the axis, position and radius.
type AxisBall = (usize, Point3, Real);

/// The points a part's slab of a cloud leaves out: the arms' tubes near a
/// torso's armpits ([`Cutter::torso_arms`]), the other leg's side of a
/// leg's ([`Cutter::other_leg`]: a point and the normal pointing there).
struct SlabExclusion {
    arms: Vec<Vec<AxisBall>>,
    beyond: Option<(Point3, Vec3)>,
}

impl SlabExclusion {
    fn excludes(&self, p: Point3) -> bool {
        self.beyond.is_some_and(|(m, n)| (p - m).dot(n) > 0.0)
            || self.arms.iter().any(|a| in_arm(a, p))
    }
}

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
        let margin = ROUNDING_MARGIN * (radius + g);
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
pub(super) fn local_mesh(m: &Mesh, centre: Point3, radius: Real) -> Mesh {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::anatomy::LandmarkKind;
    use crate::geom::shapes;
    use crate::segment::segment;

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

    fn square(x0: Real, side: Real, n: usize) -> SectionLoop {
        let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let mut points = Vec::new();
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            for j in 0..n {
                let f = j as Real / n as Real;
                let (x, y) = (a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f);
                points.push(Vec3::new(x0 + side * x, side * y, 0.0));
            }
        }
        SectionLoop::from_points(points, Vec3::X, Vec3::Y).unwrap()
    }

    /// Two toes apart give one loop round both: their convex hull, its
    /// long edges split no longer than the loops' own edges, with both
    /// loops' cloud indices (none when one has none).
    #[test]
    fn loops_apart_give_their_hull() {
        let (a, b) = (square(0.0, 1.0, 4), square(2.0, 1.0, 4));
        let (hull, ids) = hull_of_loops(vec![
            (a.clone(), Some(vec![0, 1])),
            (b.clone(), Some(vec![2])),
        ])
        .unwrap();
        assert!((hull.area - 3.0).abs() < 1e-12, "{}", hull.area);
        assert!((hull.centroid - Vec3::new(1.5, 0.5, 0.0)).norm() < 1e-12);
        assert!((hull.perimeter - 8.0).abs() < 1e-12);
        let n = hull.points.len();
        for k in 0..n {
            let edge = hull.points[k].distance(hull.points[(k + 1) % n]);
            assert!(edge <= 0.25 + 1e-12, "edge {edge}");
        }
        assert_eq!(ids, Some(vec![0, 1, 2]));
        let (_, ids) = hull_of_loops(vec![(a, Some(vec![0])), (b, None)]).unwrap();
        assert_eq!(ids, None);
    }

    /// A run's next loop is the one inside the last outline, not the one
    /// nearest the axis: with the predicate taking one leg's loop, that
    /// loop; taking both legs' (equal), the larger alone, as it holds half
    /// the area; taking none, an empty cut. [`hull_of_loops`] is tested
    /// above.
    #[test]
    fn a_cut_within_takes_the_loops_the_predicate_accepts() {
        let mesh = shapes::stick_body(2);
        let body = BodyGeometry::Mesh(&mesh);
        let seg = segment(body, &Default::default()).unwrap();
        let cutter = Cutter::new(body, &seg);
        let opts = SegmentOptions::default();
        let up = Some(seg.frame.up);
        let left = cutter.cut(PartName::LeftLeg, 0.5, up, true, &opts).unwrap();
        let loops = cutter
            .cut_loops(PartName::LeftLeg, 0.5, up, true, &opts)
            .unwrap()
            .loops;
        let right = loops
            .iter()
            .map(|(l, _)| l)
            .find(|l| l.centroid.distance(left.outline.centroid) > 0.05)
            .expect("the other leg's loop in the plane");
        let near = |c: Point3| move |p: Point3| p.distance(c) < 1e-3;
        let own = near(left.outline.centroid);
        let one = cutter
            .cut_within(PartName::LeftLeg, 0.5, up, &own, &opts)
            .unwrap();
        assert!((one.outline.area - left.outline.area).abs() < 1e-12);
        let both = |p: Point3| near(left.outline.centroid)(p) || near(right.centroid)(p);
        let pair = cutter
            .cut_within(PartName::LeftLeg, 0.5, up, &both, &opts)
            .unwrap();
        let larger = left.outline.area.max(right.area);
        assert!((pair.outline.area - larger).abs() < 1e-12);
        assert!(cutter
            .cut_within(PartName::LeftLeg, 0.5, up, &|_| false, &opts)
            .is_err());
    }

    /// The cut the way it was made before the [`Cutter`]: the geometry in
    /// the ball around the axis point (a cloud's less what the part's slab
    /// leaves out, [`Cutter::left_out`]), sliced on its own.
    fn ball_cut(
        cutter: &Cutter<'_>,
        part: PartName,
        at: Real,
        normal: Option<Vec3>,
    ) -> Vec<(SectionLoop, Option<Vec<usize>>)> {
        let (body, seg) = (cutter.body(), cutter.segmentation());
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
                let left_out = cutter.left_out(part, &plane, &SegmentOptions::default());
                let idx: Vec<usize> = (0..c.positions.len())
                    .filter(|&i| {
                        (c.positions[i] - p).norm_squared() <= r2
                            && !left_out.excludes(c.positions[i])
                    })
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
                        let reference = ball_cut(&cutter, part, at, normal);
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
}
