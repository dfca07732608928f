//! Slab loops of a cloud region split by what lies past each plane.
//!
//! A slab image's closing joins two surfaces closer than a few point
//! spacings (fingers held a little apart are one blob in a scan's slab).
//! Past a plane across a hand, though, each finger's points are linked to
//! each other and not to the next finger's: the region's points past the
//! plane, linked wherever two lie within `link`, fall into one component
//! per finger (the superlevel set's components). Each level's slab points
//! are split by the component they belong to, and each share is a slab of
//! its own ([`section_of_slab`]), so the closing joins nothing across
//! components. Each loop also says how far its component reaches: where a
//! finger's points end.

use super::{section_of_slab, ScanSectionOptions, Slab};
use crate::geom::math::{Point3, Real, Vec3};
use crate::section::mesh::SectionLoop;
use crate::spatial::point_grid::PointGrid;

/// A loop of one level, the farthest height (along the levels' axis) of
/// the points past the level linked to it, and which component holds it
/// at each level.
#[derive(Clone, Debug)]
pub struct LevelLoop {
    pub outline: SectionLoop,
    pub reach: Real,
    /// Per level (as given), the component holding this loop's points
    /// there: for its own level and every lower one, where its component
    /// has grown into a larger one (a finger's into the palm's);
    /// [`NO_COMPONENT`] for the levels above its own. Two loops at levels
    /// `j` below `k` are one run's when `component[j]` of both agree.
    pub component: Vec<u32>,
}

/// [`LevelLoop::component`] of a level above the loop's.
pub const NO_COMPONENT: u32 = u32::MAX;

/// The region of a cloud whose levels are cut: some of its points and the
/// planes' common normal.
pub struct Region<'a> {
    pub positions: &'a [Point3],
    pub ids: &'a [u32],
    /// The planes' normal, a unit vector; a plane is `{p : p·axis = offset}`.
    pub axis: Vec3,
}

/// Union-find over `0..n` with path halving; each root keeps its set's
/// largest height.
struct Links {
    parent: Vec<u32>,
    reach: Vec<Real>,
}

impl Links {
    fn find(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            let p = self.parent[i as usize];
            self.parent[i as usize] = self.parent[p as usize];
            i = self.parent[i as usize];
        }
        i
    }

    fn join(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.parent[hi as usize] = lo;
            self.reach[lo as usize] = self.reach[lo as usize].max(self.reach[hi as usize]);
        }
    }
}

/// The loops of `region` at each of `offsets` (one list per offset, in
/// the given order): each level's slab (half-thickness
/// `opts.half_thickness`, which must be set) split by the components of
/// the region's points at or past the slab's near side, linked within
/// `link`; each share's loops with occupancy cells of size `g`.
pub fn superlevel_loops(
    region: &Region<'_>,
    offsets: &[Real],
    link: Real,
    g: Real,
    opts: &ScanSectionOptions,
) -> Vec<Vec<LevelLoop>> {
    let mut out: Vec<Vec<LevelLoop>> = vec![Vec::new(); offsets.len()];
    let Some(t) = opts.half_thickness.filter(|t| *t > 0.0 && t.is_finite()) else {
        return out;
    };
    if !(link > 0.0 && link.is_finite() && g > 0.0 && g.is_finite()) {
        return out;
    }
    // The points from the highest down.
    let mut pts: Vec<(Real, u32)> = region
        .ids
        .iter()
        .map(|&i| (region.positions[i as usize].dot(region.axis), i))
        .filter(|(h, _)| h.is_finite())
        .collect();
    pts.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let local: Vec<Point3> = pts
        .iter()
        .map(|&(_, i)| region.positions[i as usize])
        .collect();
    let grid = PointGrid::new(&local, link);
    let mut links = Links {
        parent: (0..pts.len() as u32).collect(),
        reach: pts.iter().map(|p| p.0).collect(),
    };
    let mut added = 0usize;
    // Each loop emitted so far: (level, one of its points).
    let mut emitted: Vec<(usize, u32)> = Vec::new();
    let mut order: Vec<usize> = (0..offsets.len()).collect();
    order.sort_by(|&a, &b| offsets[b].total_cmp(&offsets[a]));
    for k in order {
        let c = offsets[k];
        if !c.is_finite() {
            continue;
        }
        while added < pts.len() && pts[added].0 >= c - t {
            let j = added as u32;
            grid.for_each_within(local[added], link, |gi, _| {
                let m = grid.input_index(gi) as u32;
                if m < j {
                    links.join(j, m);
                }
            });
            added += 1;
        }
        let lo = pts.partition_point(|p| p.0 > c + t);
        // The slab's points by component, each share ascending in height.
        let mut shares: Vec<(u32, u32)> = (lo..added)
            .map(|j| (links.find(j as u32), j as u32))
            .collect();
        shares.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(b.1.cmp(&a.1)));
        for share in shares.chunk_by(|a, b| a.0 == b.0) {
            if share.len() < opts.min_slab_points.max(3) {
                continue;
            }
            let ids: Vec<u32> = share.iter().map(|&(_, j)| pts[j as usize].1).collect();
            let slab = Slab {
                positions: region.positions,
                normals: None,
                axis: region.axis,
                offset: c,
                ids: &ids,
                half_thickness: t,
            };
            let (root, reach) = (share[0].0, links.reach[share[0].0 as usize]);
            for l in section_of_slab(&slab, g, opts).loops {
                out[k].push(LevelLoop {
                    outline: l.outline,
                    reach,
                    component: vec![NO_COMPONENT; offsets.len()],
                });
                emitted.push((k, root));
            }
        }
        // Where every loop so far lies at this level.
        let mut counts = vec![0usize; offsets.len()];
        for &(level, point) in &emitted {
            let c = links.find(point);
            out[level][counts[level]].component[k] = c;
            counts[level] += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on a circle of radius `r` about `(x, y)`, every `step` of
    /// height from `z0` to `z1`, `n` around.
    fn tube(x: Real, y: Real, r: Real, (z0, z1): (Real, Real), n: usize) -> Vec<Point3> {
        let mut out = Vec::new();
        let mut z = z0;
        while z <= z1 {
            for k in 0..n {
                let a = k as Real * std::f64::consts::TAU / n as Real;
                out.push(Point3::new(x + r * a.cos(), y + r * a.sin(), z));
            }
            z += 0.002;
        }
        out
    }

    #[test]
    fn fingers_closer_than_the_closing_are_apart_past_their_fork() {
        // A palm (z 0..0.05) and three fingers 0.012 apart (gap 0.004)
        // from 0.05 to 0.09: one slab image joins them, their links do not.
        let mut pts = tube(0.012, 0.0, 0.022, (0.0, 0.05), 60);
        // The palm's flat end, from which the fingers rise.
        for i in 0..23 {
            for j in 0..23 {
                let (x, y) = (-0.01 + 0.002 * i as Real, -0.022 + 0.002 * j as Real);
                if (x - 0.012).hypot(y) <= 0.022 {
                    pts.push(Point3::new(x, y, 0.05));
                }
            }
        }
        for x in [0.0, 0.012, 0.024] {
            pts.extend(tube(x, 0.0, 0.004, (0.05, 0.09 + x), 16));
        }
        let ids: Vec<u32> = (0..pts.len() as u32).collect();
        let region = Region {
            positions: &pts,
            ids: &ids,
            axis: Vec3::new(0.0, 0.0, 1.0),
        };
        let opts = ScanSectionOptions {
            half_thickness: Some(0.0021),
            closing_radius: 2,
            min_component_points: 3,
            ..ScanSectionOptions::default()
        };
        let levels = [0.02, 0.07, 0.108];
        let out = superlevel_loops(&region, &levels, 0.0035, 0.002, &opts);
        assert_eq!(out[0].len(), 1, "the palm is one loop");
        assert_eq!(out[1].len(), 3, "three fingers past the fork");
        let mut reach: Vec<Real> = out[1].iter().map(|l| l.reach).collect();
        reach.sort_by(Real::total_cmp);
        for (r, want) in reach.iter().zip([0.09, 0.102, 0.114]) {
            assert!((r - want).abs() < 0.0021, "reach {r} against {want}");
        }
        assert_eq!(out[2].len(), 1, "only the longest finger at 0.108");
        // The fingers lie in the palm's component at the palm's level
        // (they are linked to it below their fork), apart at theirs.
        let palm = out[0][0].component[0];
        let at = |l: &LevelLoop, k: usize| l.component[k];
        assert!(out[1]
            .iter()
            .all(|l| at(l, 0) == palm && at(l, 2) == NO_COMPONENT));
        let mut own: Vec<u32> = out[1].iter().map(|l| at(l, 1)).collect();
        own.dedup();
        assert_eq!(own.len(), 3);
        assert!(out[1].iter().any(|l| at(l, 1) == at(&out[2][0], 1)));
        // One slab image of the same level joins the fingers.
        let slab_ids: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&i| (pts[i as usize].z - 0.07).abs() <= 0.0021)
            .collect();
        let slab = Slab {
            positions: &pts,
            normals: None,
            axis: region.axis,
            offset: 0.07,
            ids: &slab_ids,
            half_thickness: 0.0021,
        };
        assert_eq!(section_of_slab(&slab, 0.002, &opts).loops.len(), 1);
    }
}
