//! The legs', crotch's and trunk's branches of the slice graph (module
//! docs, step 5).

use crate::geom::math::Vec3;
use crate::segment::graph::Graph;
use crate::segment::SegmentError;

/// The legs and the trunk path in the slice graph.
pub(super) struct Trunk {
    /// The segments without parents (legs, hanging arms, scraps).
    pub(super) roots: Vec<usize>,
    /// The two legs' chains of segments up to their merge.
    pub(super) leg_chains: [Vec<usize>; 2],
    /// The legs' nodes, bottom to top: the left leg's first once
    /// [`Trunk::left_leg_first`] has run.
    pub(super) leg_nodes: [Vec<usize>; 2],
    /// The segment the legs merge into; its first node is the crotch's.
    pub(super) crotch_seg: usize,
    pub(super) crotch_node: usize,
    pub(super) crotch_slice: usize,
    /// The trunk path, crotch to head top: its segments and nodes.
    pub(super) trunk_segs: Vec<usize>,
    pub(super) trunk_nodes: Vec<usize>,
    pub(super) top_node: usize,
}

impl Trunk {
    /// The two legs (the segments without parents that start in the lowest
    /// tenth of the `n` slices), where they merge (the crotch) and the
    /// trunk path from there up to the head top, taking the child nearest
    /// above it at any split.
    pub(super) fn find(
        g: &Graph,
        n: usize,
        warnings: &mut Vec<String>,
    ) -> Result<Trunk, SegmentError> {
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
        let leg_nodes = [g.chain_nodes(&chain_a), g.chain_nodes(&chain_b)];

        // Trunk path: up from the crotch, at any split the child that
        // continues it most nearly straight up (the neck between raised
        // arms, whose horizontal loops can be larger than the neck's).
        let mut trunk_segs = vec![crotch_seg];
        let mut cur = crotch_seg;
        loop {
            let seg = &g.segments[cur];
            let here = g.nodes[seg.nodes[seg.nodes.len() - 1]].c2;
            let offset = |c: usize| (g.nodes[g.segments[c].nodes[0]].c2 - here).norm();
            let Some(&next) = seg
                .children
                .iter()
                .filter(|c| !trunk_segs.contains(c))
                .min_by(|&&a, &&b| offset(a).total_cmp(&offset(b)))
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
        Ok(Trunk {
            roots,
            leg_chains: [chain_a, chain_b],
            leg_nodes,
            crotch_seg,
            crotch_node,
            crotch_slice,
            trunk_segs,
            trunk_nodes,
            top_node,
        })
    }

    /// Orders the legs left, right by their offset along `left`.
    pub(super) fn left_leg_first(&mut self, g: &Graph, left: Vec3) {
        if g.mean_along(&self.leg_nodes[0], left) < g.mean_along(&self.leg_nodes[1], left) {
            self.leg_nodes.swap(0, 1);
        }
    }
}
