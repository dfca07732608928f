//! The trunk's landmarks and axes (module docs, steps 5, 7 and 8): the
//! crotch, the neck, the head top, and the torso's and head's axes.

use crate::anatomy::{Landmark, LandmarkKind, PartName};
use crate::geom::math::{Point3, Real};
use crate::segment::axis::smooth_axis;
use crate::segment::branches::Trunk;
use crate::segment::frame::{Found, Landmarking};
use crate::segment::graph::girth_contrast;
use crate::segment::{PartAxis, SegmentError};

/// The least length of a head from the neck to its top, as a fraction of
/// the body's height: an adult's is about 0.13-0.15, a child's more.
const MIN_HEAD: Real = 0.06;
/// The least contrast (`1 − neck / widest`, hull girths) of a neck against
/// the widest trunk loop above the armpits: 0.6-0.75 on every body and
/// scan of the development corpus, 0.2-0.3 on a torso whose neck is closed.
const MIN_NECK_CONTRAST: Real = 0.4;

impl Landmarking<'_> {
    /// The crotch landmark, between the legs' top loops at the bottom of
    /// the slice where they merge. Returns it and its height above the
    /// floor.
    pub(super) fn place_crotch(&self, trunk: &Trunk, out: &mut Found) -> (Point3, Real) {
        let (g, lv) = (self.g, &self.lv);
        let (step, extent) = (lv.step, lv.extent);
        let (leg_nodes, crotch_node) = (&trunk.leg_nodes, trunk.crotch_node);
        let crotch_slice = trunk.crotch_slice;
        let leg_tops = [
            g.nodes[*leg_nodes[0].last().unwrap_or(&crotch_node)].centroid,
            g.nodes[*leg_nodes[1].last().unwrap_or(&crotch_node)].centroid,
        ];
        let crotch_h = lv.height_of(crotch_slice) - 0.5 * step;
        let crotch = lv.at_height((leg_tops[0] + leg_tops[1]) * 0.5, crotch_h);
        out.landmarks.push(Landmark {
            kind: LandmarkKind::Crotch,
            position: crotch,
            height_fraction: crotch_h / extent,
            confidence: 1.0,
            how: "the legs' branches merge into the trunk",
        });
        (crotch, crotch_h)
    }

    /// The neck, the head top and the torso's and head's axes, given the
    /// slice of the highest armpit.
    pub(super) fn place_torso_and_head(
        &self,
        trunk: &Trunk,
        armpit_slice: usize,
        crotch: Point3,
        out: &mut Found,
    ) -> Result<(), SegmentError> {
        let (g, lv, opts) = (self.g, &self.lv, self.opts);
        let (step, extent) = (lv.step, lv.extent);
        let (trunk_nodes, top_node) = (&trunk.trunk_nodes, trunk.top_node);
        let (crotch_node, crotch_slice) = (trunk.crotch_node, trunk.crotch_slice);
        let (neck_node, neck_conf) = self.find_neck(trunk, armpit_slice)?;
        let neck_p = g.nodes[neck_node].centroid;
        // A torso without its head (a neck cut off and closed) has no neck
        // much narrower than the loops above the armpits, nor a head above.
        let head_len = (g.nodes[top_node].slice - g.nodes[neck_node].slice) as Real * step;
        if neck_conf < MIN_NECK_CONTRAST || head_len < MIN_HEAD * extent {
            return Err(SegmentError::NotAStandingBody {
                what: "the head",
                why: format!(
                    "the narrowest slice above the armpits is {:.0} % narrower than the widest (a neck: at least {:.0} %) and the trunk runs {:.1} % of the height above it (a head: at least {:.0} %)",
                    100.0 * neck_conf,
                    100.0 * MIN_NECK_CONTRAST,
                    100.0 * head_len / extent,
                    100.0 * MIN_HEAD
                ),
            });
        }
        out.landmarks.push(Landmark {
            kind: LandmarkKind::Neck,
            position: neck_p,
            height_fraction: lv.hfrac(neck_p),
            confidence: neck_conf,
            how: "smallest hull girth between the armpits and the head's widest slice",
        });
        // The highest input point over the trunk's top loop (within twice
        // its radius across `up`), not the body's top: a hand raised above
        // the head may be that.
        let top = &g.nodes[top_node];
        let top_h = self
            .body
            .positions()
            .iter()
            .filter(|&&p| {
                let d = p - top.centroid;
                (d - lv.up * d.dot(lv.up)).norm() <= 2.0 * top.radius
            })
            .map(|&p| lv.hfrac(p) * extent)
            .fold(lv.height_of(top.slice), Real::max)
            .min(extent);
        let top_p = lv.at_height(g.nodes[top_node].centroid, top_h);
        out.landmarks.push(Landmark {
            kind: LandmarkKind::HeadTop,
            position: top_p,
            height_fraction: 1.0,
            confidence: 1.0,
            how: "highest input point over the trunk branch's top loop",
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
        out.parts.push(PartAxis {
            name: PartName::Torso,
            points: torso.0,
            radii: torso.1,
            start: LandmarkKind::Crotch,
            end: LandmarkKind::Neck,
        });
        let mut head_pts = pick(neck_slice, g.nodes[top_node].slice);
        head_pts.push((top_p, g.nodes[top_node].radius));
        let head = smooth_axis(&head_pts, opts.axis_smoothing * extent, step);
        out.parts.push(PartAxis {
            name: PartName::Head,
            points: head.0,
            radii: head.1,
            start: LandmarkKind::Neck,
            end: LandmarkKind::HeadTop,
        });
        Ok(())
    }

    /// The neck's node, the smallest hull girth of the trunk path between
    /// the highest armpit and the head's widest slice, and its confidence:
    /// how much smaller it is than the widest loop above the armpits.
    fn find_neck(&self, trunk: &Trunk, armpit_slice: usize) -> Result<(usize, Real), SegmentError> {
        let g = self.g;
        let (trunk_nodes, top_node) = (&trunk.trunk_nodes, trunk.top_node);
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
        let neck_conf = girth_contrast(g, &above, neck_node);
        Ok((neck_node, neck_conf))
    }
}
