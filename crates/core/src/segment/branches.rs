//! The legs', crotch's and trunk's branches of the slice graph (module
//! docs, step 5).

use crate::geom::math::{Point2, Vec2, Vec3};
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
    /// trunk path from there up to the head top, taking at any split the
    /// child that continues it most nearly straight up.
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
        // arms, whose horizontal loops can be larger than the neck's):
        // the least mean offset across `up` of the child's loops over the
        // next twelfth of the height ([`straightness`]), not of its first
        // loop alone, which a forearm raised beside the head can win by
        // a couple of scan points; measured from the trunk's own line
        // ([`TrunkLine`]), not the parent's last loop, which may already
        // hold a raised arm.
        let mut trunk_segs = vec![crotch_seg];
        let mut cur = crotch_seg;
        let line = TrunkLine::of(g, crotch_seg, n);
        loop {
            let seg = &g.segments[cur];
            let last = g.nodes[seg.nodes[seg.nodes.len() - 1]].slice;
            let here = g.nodes[seg.nodes[seg.nodes.len() - 1]].c2;
            let offset = |c: usize| {
                straightness(
                    g,
                    c,
                    &|k| line.as_ref().map_or(here, |l| l.at(k)),
                    last + n / 12,
                )
            };
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

/// The mean distance across `up` from the trunk's `line` (its point at
/// each slice) of the loops of `child` and of every segment above it, up
/// to slice `until`.
/// The trunk's line across `up`, slice by slice: the least-squares line
/// through the centroids of the middle half of the crotch's segment (the
/// trunk up to its first split; its top may hold a raised arm's root
/// merged into the shoulder's loop, its bottom the hips), so a lean is
/// followed and an arm merged into the loops above does not pull it.
struct TrunkLine {
    at0: Point2,
    per_slice: Vec2,
    slice0: f64,
}

impl TrunkLine {
    /// `None` when the middle half spans less than a tenth of the `n`
    /// slices: a few noisy centroids give no line to extrapolate (the path
    /// is then measured from the parent's last loop).
    fn of(g: &Graph, crotch_seg: usize, n: usize) -> Option<TrunkLine> {
        let nodes = &g.segments[crotch_seg].nodes;
        let middle = &nodes[nodes.len() / 4..3 * nodes.len() / 4];
        let span = |a: &[usize]| match (a.first(), a.last()) {
            (Some(&lo), Some(&hi)) => g.nodes[hi].slice - g.nodes[lo].slice,
            _ => 0,
        };
        if middle.len() < 4 || span(middle) < n / 10 {
            return None;
        }
        let k = middle.len() as f64;
        let mean_s = middle.iter().map(|&a| g.nodes[a].slice as f64).sum::<f64>() / k;
        let mean_c = middle.iter().fold(Vec2::ZERO, |m, &a| m + g.nodes[a].c2) * (1.0 / k);
        let (mut sxx, mut sxc) = (0.0, Vec2::ZERO);
        for &a in middle {
            let ds = g.nodes[a].slice as f64 - mean_s;
            sxx += ds * ds;
            sxc += (g.nodes[a].c2 - mean_c) * ds;
        }
        (sxx > 0.0).then(|| TrunkLine {
            at0: mean_c,
            per_slice: sxc * (1.0 / sxx),
            slice0: mean_s,
        })
    }

    /// The line's point at `slice`.
    fn at(&self, slice: usize) -> Point2 {
        self.at0 + self.per_slice * (slice as f64 - self.slice0)
    }
}

fn straightness(g: &Graph, child: usize, line: &dyn Fn(usize) -> Point2, until: usize) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    let mut seen = vec![false; g.segments.len()];
    let mut stack = vec![child];
    while let Some(s) = stack.pop() {
        if std::mem::replace(&mut seen[s], true) {
            continue;
        }
        let nodes = &g.segments[s].nodes;
        for &a in nodes.iter().filter(|&&a| g.nodes[a].slice <= until) {
            sum += (g.nodes[a].c2 - line(g.nodes[a].slice)).norm();
            count += 1;
        }
        if nodes.first().is_some_and(|&a| g.nodes[a].slice <= until) {
            stack.extend(g.segments[s].children.iter().copied());
        }
    }
    if count == 0 {
        f64::INFINITY
    } else {
        sum / count as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::math::{Point2, Vec2};
    use crate::segment::graph::Node;

    /// A square loop of half-side `r` centred at `(x, 0)` in slice `k`.
    fn square(k: usize, x: f64, r: f64) -> Node {
        let c = Vec2::new(x, 0.0);
        let poly: Vec<Point2> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(a, b)| c + Vec2::new(a * r, b * r))
            .collect();
        Node::from_parts(k, Vec3::new(x, k as f64, 0.0), c, 4.0 * r * r, poly)
    }

    /// Legs, a trunk, and above the shoulders an arm going out, the head
    /// straight up a little off the trunk's line, and a forearm whose
    /// first loop is nearer that line than the head's but which turns
    /// away: the path takes the head.
    #[test]
    fn the_trunk_path_takes_the_branch_that_goes_straight_up() {
        let n = 120;
        let slices: Vec<Vec<Node>> = (0..n)
            .map(|k| match k {
                0..30 => vec![square(k, -0.1, 0.04), square(k, 0.1, 0.04)],
                30..81 => vec![square(k, 0.0, 0.15)],
                _ => {
                    let up = (k - 81) as f64;
                    let mut loops =
                        vec![square(k, -0.2 - 0.005 * up, 0.02), square(k, 0.03, 0.012)];
                    if k < 93 {
                        loops.push(square(k, -0.01 - 0.008 * up, 0.01));
                    }
                    loops
                }
            })
            .collect();
        let g = Graph::of_slices(slices, 2);
        let trunk = Trunk::find(&g, n, &mut Vec::new()).unwrap();
        let top = &g.nodes[trunk.top_node];
        assert_eq!(top.slice, n - 1);
        assert!((top.c2.x - 0.03).abs() < 1e-12, "{:?}", top.c2);
    }

    /// Above the trunk a wide loop holds the trunk and a raised arm (its
    /// centroid pulled toward the arm); at the split the arm goes straight
    /// up nearer that centroid than the head does. Measured from the
    /// trunk's own line, the path still takes the head.
    #[test]
    fn the_trunk_path_is_measured_from_the_trunk_not_from_a_merged_loop() {
        let n = 120;
        let slices: Vec<Vec<Node>> = (0..n)
            .map(|k| match k {
                0..30 => vec![square(k, -0.1, 0.04), square(k, 0.1, 0.04)],
                30..75 => vec![square(k, 0.0, 0.15)],
                75..81 => vec![square(k, -0.1, 0.2)],
                _ => vec![square(k, -0.16, 0.02), square(k, 0.0, 0.02)],
            })
            .collect();
        let g = Graph::of_slices(slices, 2);
        let trunk = Trunk::find(&g, n, &mut Vec::new()).unwrap();
        let top = &g.nodes[trunk.top_node];
        assert_eq!(top.slice, n - 1);
        assert!(top.c2.x.abs() < 1e-12, "{:?}", top.c2);
    }
}
