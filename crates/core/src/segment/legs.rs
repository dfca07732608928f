//! The legs' landmarks and axes (module docs, steps 7 and 8): ankles,
//! the legs' axes, and the feet with their soles, heels and toes.

use crate::anatomy::{Landmark, LandmarkKind, PartName};
use crate::geom::linalg::{scatter2, symmetric_eigen2};
use crate::geom::math::{Point2, Point3, Real, Vec2};
use crate::segment::axis::smooth_axis;
use crate::segment::branches::Trunk;
use crate::segment::frame::{Found, Landmarking};
use crate::segment::graph::girth_contrast;
use crate::segment::PartAxis;

/// The names of one side's leg and foot and their landmarks.
#[derive(Clone, Copy)]
struct LegNames {
    leg: PartName,
    foot: PartName,
    ankle: LandmarkKind,
    sole: LandmarkKind,
    heel: LandmarkKind,
    toe: LandmarkKind,
}

impl LegNames {
    /// The left side's for `k = 0`, else the right side's.
    fn of(k: usize) -> LegNames {
        if k == 0 {
            LegNames {
                leg: PartName::LeftLeg,
                foot: PartName::LeftFoot,
                ankle: LandmarkKind::LeftAnkle,
                sole: LandmarkKind::LeftSole,
                heel: LandmarkKind::LeftHeel,
                toe: LandmarkKind::LeftToe,
            }
        } else {
            LegNames {
                leg: PartName::RightLeg,
                foot: PartName::RightFoot,
                ankle: LandmarkKind::RightAnkle,
                sole: LandmarkKind::RightSole,
                heel: LandmarkKind::RightHeel,
                toe: LandmarkKind::RightToe,
            }
        }
    }
}

impl Landmarking<'_> {
    /// Both legs, left first: ankle, leg axis, foot.
    pub(super) fn place_legs(&self, trunk: &Trunk, crotch: Point3, out: &mut Found) {
        for (k, nodes) in trunk.leg_nodes.iter().enumerate() {
            let names = LegNames::of(k);
            let (ankle_slice, ankle_p) = self.place_leg(nodes, names, crotch, out);
            self.place_foot(nodes, ankle_slice, ankle_p, names, out);
        }
    }

    /// A leg's ankle and its axis from the crotch down to the ankle, for
    /// the leg's `nodes` (sole first). Returns the ankle's slice and point.
    fn place_leg(
        &self,
        nodes: &[usize],
        names: LegNames,
        crotch: Point3,
        out: &mut Found,
    ) -> (usize, Point3) {
        let (g, lv, opts) = (self.g, &self.lv, self.opts);
        let (step, extent) = (lv.step, lv.extent);
        let LegNames { leg, ankle, .. } = names;
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
        out.landmarks.push(Landmark {
            kind: ankle,
            position: ankle_p,
            height_fraction: lv.hfrac(ankle_p),
            confidence: girth_contrast(g, &below, ankle_node),
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
        out.parts.push(PartAxis {
            name: leg,
            points: axis.0,
            radii: axis.1,
            start: LandmarkKind::Crotch,
            end: ankle,
        });
        (ankle_slice, ankle_p)
    }

    /// A foot's axis from heel to toe: the principal horizontal direction
    /// of the leg's slices below the ankle, oriented to the front, with the
    /// heel, toe and sole landmarks (only a sole below the ankle without
    /// enough slices).
    fn place_foot(
        &self,
        nodes: &[usize],
        ankle_slice: usize,
        ankle_p: Point3,
        names: LegNames,
        out: &mut Found,
    ) {
        let (g, lv) = (self.g, &self.lv);
        let (front, e1, e2) = (self.front, self.e1, self.e2);
        let LegNames {
            foot,
            sole,
            heel,
            toe,
            ..
        } = names;
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
            let foot_h = lv.height_of(ankle_slice) / 3.0;
            let to3 = |along: Real| {
                let q = d2 * along + across * mean_across;
                lv.at_height(e1 * q.x + e2 * q.y, foot_h)
            };
            let (heel_p, toe_p) = (to3(lo), to3(hi));
            let r = foot_nodes
                .iter()
                .map(|&a| g.nodes[a].radius)
                .fold(0.0, Real::max)
                * 0.5;
            let m = 16;
            out.parts.push(PartAxis {
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
                out.landmarks.push(Landmark {
                    kind,
                    position: p,
                    height_fraction: lv.hfrac(p),
                    confidence: 0.8,
                    how,
                });
            }
            out.landmarks.push(Landmark {
                kind: sole,
                position: lv.at_height((heel_p + toe_p) * 0.5, 0.0),
                height_fraction: 0.0,
                confidence: 1.0,
                how: "middle of the foot (heel to toe), on the floor",
            });
        } else {
            out.warnings.push(format!(
                "{foot}: too few slices below the ankle for a foot axis"
            ));
            out.landmarks.push(Landmark {
                kind: sole,
                position: lv.at_height(ankle_p, 0.0),
                height_fraction: 0.0,
                confidence: 0.5,
                how: "below the ankle, on the floor (no foot axis)",
            });
        }
    }
}

/// Principal direction of 2D points (unit), if the spread is not round.
fn principal_2d(p: &[Point2]) -> Option<Vec2> {
    if p.len() < 3 {
        return None;
    }
    let m = p.iter().fold(Vec2::ZERO, |s, &q| s + q) / p.len() as Real;
    let (sxx, sxy, syy) = scatter2(p, m);
    Some(symmetric_eigen2(sxx, sxy, syy).0)
}
