//! The slice graph (module docs, step 4): the loops of consecutive slices
//! linked where they overlap, chained into segments, and pruned of spurs,
//! fragments and bubbles.

use crate::geom::math::{Point2, Point3, Real, Vec2, Vec3};
use crate::section::girth::convex_hull;
use crate::section::mesh::{point_in_polygon, SectionLoop};

/// A loop of the slice graph, in the slices' common plane coordinates.
#[derive(Clone, Debug)]
pub(super) struct Node {
    pub(super) slice: usize,
    pub(super) centroid: Point3,
    pub(super) c2: Point2,
    pub(super) area: Real,
    pub(super) radius: Real,
    pub(super) hull_girth: Real,
    pub(super) poly: Vec<Point2>,
    lo: Point2,
    hi: Point2,
    active: bool,
}

impl Node {
    pub(super) fn from_parts(
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

    pub(super) fn new(slice: usize, l: &SectionLoop, e1: Vec3, e2: Vec3) -> Node {
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
pub(super) fn hull_perimeter(p: &[Point2]) -> Real {
    perimeter_2d(&convex_hull(p))
}

/// The slice graph: nodes, links, and segments (maximal one-to-one chains).
pub(super) struct Graph {
    pub(super) nodes: Vec<Node>,
    /// Per node: linked nodes above / below.
    up: Vec<Vec<usize>>,
    down: Vec<Vec<usize>>,
    pub(super) segments: Vec<Segment>,
    seg_of: Vec<usize>,
}

#[derive(Clone, Debug, Default)]
pub(super) struct Segment {
    pub(super) nodes: Vec<usize>,
    pub(super) parents: Vec<usize>,
    pub(super) children: Vec<usize>,
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
    pub(super) fn of_slices(slices: impl IntoIterator<Item = Vec<Node>>, min_span: usize) -> Graph {
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

    pub(super) fn mean_area(&self, s: usize) -> Real {
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
    pub(super) fn chain_up(&self, s: usize) -> (Vec<usize>, Option<usize>) {
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

    pub(super) fn chain_nodes(&self, chain: &[usize]) -> Vec<usize> {
        chain
            .iter()
            .flat_map(|&s| self.segments[s].nodes.iter().copied())
            .collect()
    }

    /// The mean offset along `dir` of the centroids of `nodes` (which
    /// side of the body a branch lies on).
    pub(super) fn mean_along(&self, nodes: &[usize], dir: Vec3) -> Real {
        nodes
            .iter()
            .map(|&a| self.nodes[a].centroid.dot(dir))
            .sum::<Real>()
            / nodes.len().max(1) as Real
    }
}

/// How much smaller the minimum is than the largest girth among `nodes`:
/// `1 − min/max`, clamped to [0, 1].
pub(super) fn girth_contrast(g: &Graph, nodes: &[usize], min_node: usize) -> Real {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_perimeter_of_a_square() {
        let sq = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.5, 0.5),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        assert!((hull_perimeter(&sq) - 4.0).abs() < 1e-12);
    }
}
