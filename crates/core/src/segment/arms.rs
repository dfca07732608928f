//! The arms (module docs, steps 5, 7 and 8): the branches hanging from
//! the trunk or held out sideways, their armpits, hand tips and wrists,
//! and their axes continued out to the fingertips and into the shoulders.

use crate::anatomy::{BodyGeometry, Landmark, LandmarkKind, OwnedGeometry, PartName};
use crate::geom::math::{Point2, Point3, Real, Vec2, Vec3};
use crate::geom::mesh::PointCloud;
use crate::geom::stats::median;
use crate::section::cloud::ScanSectionOptions;
use crate::section::mesh::{point_in_polygon, MeshSlicer};
use crate::segment::axis::smooth_axis;
use crate::segment::branches::Trunk;
use crate::segment::cut::local_mesh;
use crate::segment::frame::{Found, Landmarking};
use crate::segment::geodesic;
use crate::segment::graph::{hull_perimeter, Graph, Node};
use crate::segment::slices::{AxisSlicer, SlabComponents};
use crate::segment::{PartAxis, SegmentOptions};

/// The names of one side's arm and its landmarks.
struct ArmNames {
    arm: PartName,
    tip: LandmarkKind,
    wrist: LandmarkKind,
    pit: LandmarkKind,
    pname: &'static str,
}

impl ArmNames {
    /// The left arm's for `k = 0`, else the right arm's.
    fn of(k: usize) -> ArmNames {
        if k == 0 {
            ArmNames {
                arm: PartName::LeftArm,
                tip: LandmarkKind::LeftHandTip,
                wrist: LandmarkKind::LeftWrist,
                pit: LandmarkKind::LeftArmpit,
                pname: "left arm",
            }
        } else {
            ArmNames {
                arm: PartName::RightArm,
                tip: LandmarkKind::RightHandTip,
                wrist: LandmarkKind::RightWrist,
                pit: LandmarkKind::RightArmpit,
                pname: "right arm",
            }
        }
    }
}

/// An arm hanging from the trunk: its branch's nodes (hand first) and the
/// trunk segment it merges into.
type HangingArm = (Vec<usize>, usize);

impl Landmarking<'_> {
    /// Both arms, left first, hanging down or else held out sideways, with
    /// their axes extended to the fingertips and into the shoulders.
    /// Returns the slice of the highest armpit (for the neck search).
    pub(super) fn place_arms(&self, trunk: &Trunk, crotch_h: Real, out: &mut Found) -> usize {
        let arm_found = self.hanging_arms(trunk);
        // Highest armpit (for the neck search).
        let mut armpit_slice = trunk.crotch_slice;
        for (k, found) in arm_found.iter().enumerate() {
            let names = ArmNames::of(k);
            let pit_slice = match found {
                Some((nodes, m)) => Some(self.place_hanging_arm(nodes, *m, k, trunk, out)),
                None => self.place_lateral_arm(k, &names, trunk, crotch_h, out),
            };
            if let Some(s) = pit_slice {
                armpit_slice = armpit_slice.max(s);
            }
        }
        self.extend_arms(out);
        if arm_found.iter().all(|a| a.is_none()) {
            let (g, crotch_slice) = (self.g, trunk.crotch_slice);
            armpit_slice = crotch_slice + (g.nodes[trunk.top_node].slice - crotch_slice) / 2;
        }
        armpit_slice
    }

    /// Per side (left, right), the longest branch without parents, at
    /// least [`SegmentOptions::min_arm`] of the height long, whose chain
    /// merges into the trunk path above the crotch.
    fn hanging_arms(&self, trunk: &Trunk) -> [Option<HangingArm>; 2] {
        let (g, left) = (self.g, self.left);
        let n = self.lv.n;
        let trunk_set: std::collections::HashSet<usize> =
            trunk.trunk_segs.iter().copied().collect();
        let mut arm_found: [Option<(Vec<usize>, usize)>; 2] = [None, None];
        let min_arm = (self.opts.min_arm * n as Real) as usize;
        let [chain_a, chain_b] = &trunk.leg_chains;
        let leg_seg_set: Vec<usize> = chain_a.iter().chain(chain_b.iter()).copied().collect();
        for &r in &trunk.roots {
            if leg_seg_set.contains(&r) {
                continue;
            }
            let (chain, merge) = g.chain_up(r);
            let Some(m) = merge else { continue };
            if !trunk_set.contains(&m) || m == trunk.crotch_seg {
                continue;
            }
            let nodes = g.chain_nodes(&chain);
            let span = g.nodes[*nodes.last().unwrap_or(&0)].slice - g.nodes[nodes[0]].slice + 1;
            if span < min_arm {
                continue;
            }
            // Side relative to the trunk loop at the merge.
            let merge_c = g.nodes[g.segments[m].nodes[0]].centroid;
            let off = g.mean_along(&nodes, left) - merge_c.dot(left);
            let k = if off > 0.0 { 0 } else { 1 };
            let better = match &arm_found[k] {
                None => true,
                Some((old, _)) => nodes.len() > old.len(),
            };
            if better {
                arm_found[k] = Some((nodes, m));
            }
        }
        arm_found
    }

    /// No arm hangs from the trunk on side `k`: one held out sideways
    /// (T-pose) in slices across the body and (a mesh) one found on the
    /// surface, joined ([`join_arms`]), its armpit, hand tip, wrist and
    /// axis. Returns its armpit's slice, or `None` (a warning) when there
    /// is none.
    fn place_lateral_arm(
        &self,
        k: usize,
        names: &ArmNames,
        trunk: &Trunk,
        crotch_h: Real,
        out: &mut Found,
    ) -> Option<usize> {
        let (opts, lv) = (self.opts, &self.lv);
        let (up, floor, extent, step) = (lv.up, lv.floor, lv.extent, lv.step);
        let ArmNames {
            arm,
            tip,
            pit,
            pname,
            ..
        } = *names;
        let side = if k == 0 { self.left } else { -self.left };
        let found = match (
            self.lateral_arm(side, floor + crotch_h),
            self.surface_arm(side, trunk, out),
        ) {
            (Some(l), Some(s)) => Some(join_arms(l, s, side, extent, LATERAL_TIP_SLACK)),
            (l, s) => l.or(s),
        };
        let Some(found) = found else {
            out.warnings.push(format!(
                "{pname} not found: no branch of at least {:.0} % of the height joins the trunk on the body's {} side above the crotch, hanging down or held out sideways (missing arm, or arm touching the body)",
                100.0 * opts.min_arm,
                if k == 0 { "left" } else { "right" }
            ));
            return None;
        };
        let pit_h = found.armpit.dot(up) - floor;
        out.landmarks.push(Landmark {
            kind: pit,
            position: found.armpit,
            height_fraction: pit_h / extent,
            confidence: 1.0,
            how: found.how,
        });
        out.landmarks.push(Landmark {
            kind: tip,
            position: found.tip,
            height_fraction: lv.hfrac(found.tip),
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
        self.place_wrist(&part, names, out);
        out.parts.push(part);
        Some((pit_h / step) as usize)
    }

    /// An arm hanging from the trunk on side `k` (its branch's `nodes`,
    /// hand first, merging into segment `m`), joined on a mesh with the
    /// arm found on the surface ([`join_arms`]: a forearm bent forward
    /// ends the branch at the elbow): its armpit, hand tip, wrist and
    /// axis. Returns its armpit's slice.
    fn place_hanging_arm(
        &self,
        nodes: &[usize],
        m: usize,
        k: usize,
        trunk: &Trunk,
        out: &mut Found,
    ) -> usize {
        let (g, lv, opts) = (self.g, &self.lv, self.opts);
        let (extent, step, e1, e2) = (lv.extent, lv.step, self.e1, self.e2);
        let names = ArmNames::of(k);
        let ArmNames { arm, tip, pit, .. } = names;
        let last = *nodes.last().unwrap_or(&nodes[0]);
        let merge_first = g.segments[m].nodes[0];
        // The trunk loop just below the merge: the other parent's last node.
        let trunk_below = g.segments[m]
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
        let pit_h = lv.height_of(g.nodes[merge_first].slice) - 0.5 * step;
        let pit_p = lv.at_height(e1 * mid2.x + e2 * mid2.y, pit_h);
        // Arm axis: from the armpit down to the hand tip.
        let mut cs: Vec<(Point3, Real)> = nodes
            .iter()
            .rev()
            .map(|&a| (g.nodes[a].centroid, g.nodes[a].radius))
            .collect();
        let tip_node = nodes[0];
        let tip_h = lv.height_of(g.nodes[tip_node].slice) - 0.5 * step;
        let tip_p = lv.at_height(g.nodes[tip_node].centroid, tip_h);
        cs.push((tip_p, g.nodes[tip_node].radius));
        let hanging = LateralArm {
            axis: cs,
            armpit: pit_p,
            tip: tip_p,
            how: "the arm's branch merges into the trunk",
        };
        let side = if k == 0 { self.left } else { -self.left };
        // The branch ends where horizontal slices stop cutting across the
        // arm: at the elbow of a forearm held forward, whose hand the
        // surface walk (a mesh's edges, a cloud's cubes) follows.
        let found = match self.surface_arm(side, trunk, out) {
            Some(s) => join_arms(hanging, s, side, extent, HANGING_TIP_SLACK),
            None => hanging,
        };
        let (pit_slice, pit_frac) = if found.armpit == pit_p {
            (g.nodes[merge_first].slice, pit_h / extent)
        } else {
            let h = found.armpit.dot(lv.up) - lv.floor;
            ((h / step) as usize, h / extent)
        };
        out.landmarks.push(Landmark {
            kind: pit,
            position: found.armpit,
            height_fraction: pit_frac,
            confidence: 1.0,
            how: found.how,
        });
        let axis = smooth_axis(&found.axis, opts.axis_smoothing * extent, step);
        let part = PartAxis {
            name: arm,
            points: axis.0,
            radii: axis.1,
            start: pit,
            end: tip,
        };
        out.landmarks.push(Landmark {
            kind: tip,
            position: found.tip,
            height_fraction: lv.hfrac(found.tip),
            confidence: 0.8,
            how: if found.tip == tip_p {
                "lowest slice of the arm's branch (fingers below may be dropped as small loops)"
            } else {
                "the hand's extremity on the surface (the branch ends at a bent elbow)"
            },
        });
        self.place_wrist(&part, &names, out);
        out.parts.push(part);
        pit_slice
    }

    /// The wrist landmark of an arm's axis, or a warning.
    fn place_wrist(&self, part: &PartAxis, names: &ArmNames, out: &mut Found) {
        let pname = names.pname;
        if let Some(mut w) = find_wrist(self.body, part, self.opts, self.spacing, names.wrist) {
            w.height_fraction = self.lv.hfrac(w.position);
            out.landmarks.push(w);
        } else {
            out.warnings
                .push(format!("{pname}: wrist not found on perpendicular cuts"));
        }
    }

    /// Lets each arm's axis continue out to the fingertips (fingers thinner
    /// than the small-loop limit are not in the graph), moving its hand tip
    /// there, and into the shoulder (method.md §8.5), the shoulder
    /// landmark.
    fn extend_arms(&self, out: &mut Found) {
        let lv = &self.lv;
        let positions = self.body.positions();
        for part in out.parts.iter_mut() {
            let kind = match part.name {
                PartName::LeftArm => LandmarkKind::LeftHandTip,
                PartName::RightArm => LandmarkKind::RightHandTip,
                _ => continue,
            };
            if let Some(tip) = extend_to_fingertips(positions, part) {
                if let Some(l) = out.landmarks.iter_mut().find(|l| l.kind == kind) {
                    l.position = tip;
                    l.height_fraction = lv.hfrac(tip);
                    l.how =
                        "farthest point along the arm's end direction near the hand (the fingertips)";
                }
            }
        }
        for part in out.parts.iter_mut() {
            let kind = match part.name {
                PartName::LeftArm => LandmarkKind::LeftShoulder,
                PartName::RightArm => LandmarkKind::RightShoulder,
                _ => continue,
            };
            if let Some(end) =
                extend_into_shoulder(self.body, part, self.opts, self.spacing, lv.step)
            {
                part.start = kind;
                out.landmarks.push(Landmark {
                    kind,
                    position: end,
                    height_fraction: lv.hfrac(end),
                    confidence: 0.7,
                    how: "the arm's axis continued past the armpit until its perpendicular cuts merge with the trunk",
                });
            }
        }
    }

    /// An arm touching or crossing the trunk, or raised, on `side`: found
    /// on the surface ([`geodesic`]: a mesh's edges, a cloud's cubes),
    /// which is walked once for both sides.
    fn surface_arm(&self, side: Vec3, trunk: &Trunk, out: &Found) -> Option<LateralArm> {
        let lv = &self.lv;
        let surface = self.surface.get_or_init(|| {
            let crotch = out
                .landmarks
                .iter()
                .find(|l| l.kind == LandmarkKind::Crotch)?
                .position;
            let q = geodesic::BodyQuery {
                crotch,
                head: self.g.nodes[trunk.top_node].centroid,
                up: lv.up,
                floor: lv.floor,
                extent: lv.extent,
            };
            match self.body {
                BodyGeometry::Mesh(m) => geodesic::Surface::new(m, q),
                BodyGeometry::Cloud(c) => geodesic::Surface::of_cloud(&c.positions, q),
            }
        });
        let a = surface.as_ref()?.find_arm(side)?;
        Some(LateralArm {
            axis: a.axis,
            armpit: a.armpit,
            tip: a.tip,
            how: SURFACE_ARM,
        })
    }

    /// An arm held out sideways (T-pose): horizontal slices cut it lengthwise,
    /// so it never branches off the trunk there. Slices normal to `side` (the
    /// body's left or right), ordered from the outermost inward, show the arm
    /// as a branch that starts at the body's lateral end and merges into the
    /// trunk at the shoulder: the same graph as the vertical one, on another
    /// axis. The branch must start in the outer 10 % of the lateral extent,
    /// lie above `crotch_level` and reach [`SegmentOptions::min_arm`] × `H`
    /// inward.
    fn lateral_arm(&self, side: Vec3, crotch_level: Real) -> Option<LateralArm> {
        let (body, opts, spacing) = (self.body, self.opts, self.spacing);
        let (up, step) = (self.lv.up, self.lv.step);
        let min_len = opts.min_arm * self.lv.extent;
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
        let wide = LATERAL_ARM_WIDE * median(&mut radii)?;
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
            how: "the arm's branch in slices across the body merges into the trunk (arm held out)",
        })
    }
}

/// How much wider than the arm's median loop (radius ratio) a loop of a
/// sideways arm's branch near the armpit may be and still start its axis
/// (see [`Landmarking::lateral_arm`]): wider loops cut the shoulder
/// lengthwise.
const LATERAL_ARM_WIDE: Real = 1.15;

/// How an arm found on the surface has its armpit (the landmark's `how`).
const SURFACE_ARM: &str = "the surface's rings around the hand farthest from the crotch, up to where they spread over the shoulder";

/// An arm found in slices across the body, or on the surface.
struct LateralArm {
    /// Centroids and radii from the shoulder junction out to the hand.
    axis: Vec<(Point3, Real)>,
    armpit: Point3,
    tip: Point3,
    /// How the armpit was found (its landmark's `how`).
    how: &'static str,
}

/// An arm found both in slices across the body (`lateral`) and on the
/// surface. Slices across the body find the shoulder well but cut a
/// forearm bent forward or up lengthwise, ending the arm at the elbow; the
/// surface rings follow the bend out to the hand but may stop short of the
/// shoulder. When the hands disagree, the surface arm stands if it reaches
/// the shoulder too (its armpit no farther out than the lateral one's);
/// else the lateral arm runs out to its last cut across the arm on the
/// surface arm's axis ([`splice_point`]) and the surface arm on to the
/// hand. The hands agree when the lateral
/// arm's tip lies within `slack` × `extent` of the surface's hand
/// extremity.
fn join_arms(
    lateral: LateralArm,
    surface: LateralArm,
    side: Vec3,
    extent: Real,
    slack: Real,
) -> LateralArm {
    if lateral.tip.distance(surface.tip) <= slack * extent {
        return lateral;
    }
    if (surface.armpit - lateral.armpit).dot(side) <= REACHES * extent {
        return surface;
    }
    let near_surface = |p: Point3| -> (usize, Real) {
        surface
            .axis
            .iter()
            .enumerate()
            .map(|(j, &(q, _))| (j, q.distance(p)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, Real::INFINITY))
    };
    let Some((last_on, j)) = splice_point(&lateral.axis, near_surface, extent) else {
        return lateral;
    };
    let mut axis = lateral.axis[..=last_on].to_vec();
    axis.extend_from_slice(&surface.axis[j + 1..]);
    LateralArm {
        axis,
        armpit: lateral.armpit,
        tip: surface.tip,
        how: lateral.how,
    }
}

/// Where a sliced arm's `axis` (shoulder first) hands over to the surface
/// arm, and the surface arm's ring nearest there: the last of its points on the surface arm's axis (`near` gives
/// the nearest ring and its distance: within the point's radius or
/// AXES_MEET × H) that a cut across the arm gave. Where the arm turns more
/// than 60° from the slices' normal they cut it lengthwise and their
/// centroids step more than twice as far as typical (1 / cos 60°). Past a
/// point that falls back more than a ring behind an earlier one (the
/// slices have run out along a bent arm and back) none is taken.
fn splice_point(
    axis: &[(Point3, Real)],
    near: impl Fn(Point3) -> (usize, Real),
    extent: Real,
) -> Option<(usize, usize)> {
    let steps: Vec<Real> = axis.windows(2).map(|w| w[0].0.distance(w[1].0)).collect();
    let typical = median(&mut steps.clone())?;
    let mut ahead = 0;
    let mut last = None;
    for (i, &(p, r)) in axis.iter().enumerate() {
        let (j, d) = near(p);
        if d > r.max(AXES_MEET * extent) {
            continue;
        }
        if j + 1 < ahead {
            break;
        }
        ahead = ahead.max(j);
        if i == 0 || steps[i - 1] <= 2.0 * typical {
            last = Some((i, j));
        }
    }
    last
}

/// How far (fraction of `H`) an arm's tip found in slices across the body
/// (at the outermost plane: the fingertips) may lie from the hand's
/// extremity on the surface and be that hand.
const LATERAL_TIP_SLACK: Real = 0.05;
/// The same for a hanging arm's tip (its lowest loop's centroid: up to a
/// hand's length, about 0.1 `H`, above the fingertips).
const HANGING_TIP_SLACK: Real = 0.1;
/// A surface arm whose armpit lies no more than this (fraction of `H`)
/// farther out than the lateral arm's reaches the shoulder.
const REACHES: Real = 0.03;
/// Axis points closer than this (fraction of `H`, or the arm's radius if
/// larger) lie on the same arm.
const AXES_MEET: Real = 0.02;

fn nearest_point(poly: &[Point2], q: Point2) -> Point2 {
    poly.iter()
        .copied()
        .min_by(|a, b| (*a - q).norm_squared().total_cmp(&(*b - q).norm_squared()))
        .unwrap_or(q)
}

/// The geometry near a point (within `radius`), to cut without sorting the
/// whole input for every plane.
fn local_geometry(body: BodyGeometry<'_>, centre: Point3, radius: Real) -> OwnedGeometry {
    let r2 = radius * radius;
    match body {
        BodyGeometry::Mesh(m) => OwnedGeometry::Mesh(local_mesh(m, centre, radius)),
        // The points in the ball, in order, over the cores.
        BodyGeometry::Cloud(c) => OwnedGeometry::Cloud(PointCloud {
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

/// A slicer across `dir` for the geometry near a point: plane sections of a
/// mesh, or occupancy components of a cloud's slabs (cells `graph_cell` ×
/// the point spacing, which a cloud needs).
fn axis_slicer<'a>(
    local: &'a OwnedGeometry,
    dir: Vec3,
    spacing: Option<Real>,
    opts: &SegmentOptions,
) -> Option<AxisSlicer<'a>> {
    Some(match local.geometry() {
        BodyGeometry::Mesh(m) => AxisSlicer::Mesh(MeshSlicer::new(m, dir, &opts.section).ok()?),
        BodyGeometry::Cloud(c) => {
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

/// Continues an arm's axis past its proximal end (the armpit) into the
/// shoulder, as method.md §8.5 suggests: step along the direction of the
/// arm's proximal tenth, cut perpendicular to it, and keep the loop around
/// the axis while it stays an arm's loop (area at most 1.5 times the arm's
/// typical area near its top, centre within one arm radius of the step
/// point); the first cut that merges with the trunk ends it. Prepends the
/// new centres to the axis and returns the new proximal end, or `None`
/// when the first cut already merges.
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
    let r = median(&mut arm.radii.get(..k_top)?.to_vec())?;
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
        // A loop under half the arm's area is a piece of it (a scan's slab
        // split where the cut runs obliquely through the armpit), whose
        // centroid lies off the arm's: step on past it.
        if nd.area < 0.5 * area {
            centre = q;
            continue;
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

    /// Points along a straight line from `a` to `b`, radius 0.03.
    fn line(a: Point3, b: Point3, n: usize) -> Vec<(Point3, Real)> {
        (0..=n)
            .map(|k| (a + (b - a) * (k as Real / n as Real), 0.03))
            .collect()
    }

    fn arm(axis: Vec<(Point3, Real)>) -> LateralArm {
        LateralArm {
            armpit: axis[0].0,
            tip: axis[axis.len() - 1].0,
            axis,
            how: "test",
        }
    }

    const SIDE: Vec3 = Vec3::new(1.0, 0.0, 0.0);
    const SHOULDER: Point3 = Vec3::new(0.2, 0.0, 1.4);
    const ELBOW: Point3 = Vec3::new(0.5, 0.0, 1.4);
    /// The forearm bent forward from the elbow.
    const HAND: Point3 = Vec3::new(0.5, -0.3, 1.4);

    #[test]
    fn hands_that_agree_keep_the_sliced_arm() {
        let sliced = arm(line(SHOULDER, ELBOW, 30));
        let surface = arm(line(Vec3::new(0.25, 0.0, 1.4), ELBOW + SIDE * 0.02, 20));
        let joined = join_arms(sliced, surface, SIDE, 1.7, LATERAL_TIP_SLACK);
        assert_eq!(joined.tip, ELBOW);
        assert_eq!(joined.axis.len(), 31);
    }

    #[test]
    fn a_surface_arm_reaching_the_shoulder_stands() {
        let sliced = arm(line(SHOULDER, ELBOW, 30));
        let mut bent = line(SHOULDER + SIDE * 0.01, ELBOW, 30);
        bent.extend(line(ELBOW, HAND, 30).into_iter().skip(1));
        let joined = join_arms(sliced, arm(bent.clone()), SIDE, 1.7, LATERAL_TIP_SLACK);
        assert_eq!(joined.tip, HAND);
        assert_eq!(joined.axis, bent);
    }

    #[test]
    fn a_short_surface_arm_continues_the_sliced_one_to_the_hand() {
        // The sliced arm ends at the elbow; the surface rings start mid
        // upper arm (too far out to be the shoulder) and follow the bend.
        let sliced = arm(line(SHOULDER, ELBOW, 30));
        let mid = Vec3::new(0.4, 0.0, 1.4);
        let mut bent = line(mid, ELBOW, 10);
        bent.extend(line(ELBOW, HAND, 30).into_iter().skip(1));
        let joined = join_arms(sliced, arm(bent), SIDE, 1.7, LATERAL_TIP_SLACK);
        assert_eq!(joined.armpit, SHOULDER);
        assert_eq!(joined.tip, HAND);
        // Shoulder to elbow from the slices, then the forearm, with no
        // point repeated or left out.
        let pts: Vec<Point3> = joined.axis.iter().map(|p| p.0).collect();
        assert_eq!(pts[0], SHOULDER);
        assert_eq!(*pts.last().unwrap(), HAND);
        for w in pts.windows(2) {
            let step = w[0].distance(w[1]);
            assert!(step > 1e-9 && step < 0.011, "step {step}");
        }
    }

    #[test]
    fn a_sliced_arm_cut_along_a_bent_forearm_is_not_followed_back() {
        // Past the elbow the slices across the body cut the forearm bent
        // forward lengthwise: their centroids jump out along it and back.
        let mut sliced = arm(line(SHOULDER, ELBOW, 30));
        for y in [-0.12, -0.2, -0.06, -0.15] {
            sliced.axis.push((Vec3::new(0.5, y, 1.4), 0.05));
        }
        sliced.tip = ELBOW + SIDE * 0.05;
        let mut surface = line(ELBOW, HAND, 30);
        surface.insert(0, (Vec3::new(0.45, 0.0, 1.4), 0.03));
        let joined = join_arms(sliced, arm(surface), SIDE, 1.7, LATERAL_TIP_SLACK);
        let pts: Vec<Point3> = joined.axis.iter().map(|p| p.0).collect();
        assert_eq!(pts[0], SHOULDER);
        assert_eq!(*pts.last().unwrap(), HAND);
        // Out along the forearm without turning back.
        for w in pts.windows(2) {
            assert!(w[1].y <= w[0].y + 1e-12, "{pts:?}");
            assert!(w[0].distance(w[1]) > 1e-9);
        }
    }

    #[test]
    fn a_splice_never_follows_the_slices_back_along_the_arm() {
        // Even steps 0.1 out along the surface arm, then back.
        let rings = line(SHOULDER, ELBOW, 30);
        let near = |p: Point3| {
            rings
                .iter()
                .enumerate()
                .map(|(j, q)| (j, q.0.distance(p)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap()
        };
        let mut axis = line(SHOULDER, SHOULDER + SIDE * 0.1, 10);
        axis.extend(
            line(SHOULDER + SIDE * 0.1, SHOULDER, 10)
                .into_iter()
                .skip(1),
        );
        // A ring back is noise; two rings back is the turn.
        assert_eq!(splice_point(&axis, near, 1.7).map(|s| s.0), Some(11));
        // One stray centroid is not a place to join, nor a reason to stop.
        let mut axis = line(SHOULDER, ELBOW, 30);
        axis[20].0.y += 0.05;
        assert_eq!(splice_point(&axis, near, 1.7).map(|s| s.0), Some(30));
        axis[30].0.y += 0.05;
        assert_eq!(splice_point(&axis, near, 1.7).map(|s| s.0), Some(29));
    }

    #[test]
    fn axes_that_never_meet_keep_the_sliced_arm() {
        let sliced = arm(line(SHOULDER, ELBOW, 30));
        let elsewhere = arm(line(Vec3::new(0.4, 0.3, 1.0), Vec3::new(0.4, 0.6, 1.0), 20));
        let joined = join_arms(sliced, elsewhere, SIDE, 1.7, LATERAL_TIP_SLACK);
        assert_eq!(joined.tip, ELBOW);
    }
}
