//! Ordering a component along its contour (step 4 of the module docs of
//! [`super`]): rings and solid blobs are traced cell edge by cell edge.

use super::grid::{Grid, NONE};
use super::representatives;
use crate::geom::math::{Point2, Real, Vec2};
use crate::section::mesh::segment_parameter;
use std::collections::VecDeque;

/// The outcome of [`order_component`].
pub(super) enum Ordering {
    /// Representatives (indices into the slab points) in loop order and
    /// whether the ring closed; `None` when nothing could be traced.
    Done(Option<(Vec<usize>, bool)>),
    /// A thin open arc: ordered by angle after [`merge_arcs`](super::arcs::merge_arcs).
    Arc,
}

/// Orders one component's points along its contour, or says it is an arc.
pub(super) fn order_component(
    grid: &Grid,
    labels: &[u32],
    comp: u32,
    members: &[usize],
    pts: &[Point2],
    cell_of: &[usize],
) -> Ordering {
    // Work in the component's bounding box (plus one cell all round).
    let (gw, gh) = (grid.w, grid.h);
    let (mut x0, mut y0, mut x1, mut y1) = (gw, gh, 0, 0);
    for (k, _) in labels.iter().enumerate().filter(|(_, &l)| l == comp) {
        let (x, y) = (k % gw, k / gw);
        x0 = x0.min(x);
        y0 = y0.min(y);
        x1 = x1.max(x);
        y1 = y1.max(y);
    }
    if x0 > x1 || y0 > y1 {
        return Ordering::Done(None);
    }
    let (x0, y0) = (x0.saturating_sub(1), y0.saturating_sub(1));
    let (x1, y1) = ((x1 + 1).min(gw - 1), (y1 + 1).min(gh - 1));
    let sub = Grid::new(
        grid.origin + Vec2::new(x0 as Real, y0 as Real) * grid.cell,
        grid.cell,
        x1 - x0 + 1,
        y1 - y0 + 1,
    );
    let in_comp: Vec<bool> = (0..sub.h)
        .flat_map(|y| (0..sub.w).map(move |x| (x, y)))
        .map(|(x, y)| labels[(y + y0) * gw + x + x0] == comp)
        .collect();
    let local: Vec<usize> = cell_of
        .iter()
        .map(|&c| {
            let (x, y) = (c % gw, c / gw);
            if (x0..=x1).contains(&x) && (y0..=y1).contains(&y) {
                (y - y0) * sub.w + (x - x0)
            } else {
                0
            }
        })
        .collect();
    let grid = &sub;
    let cell_of = &local[..];
    let (w, h) = (grid.w, grid.h);
    let comp_cells = in_comp.iter().filter(|&&b| b).count();
    // Background reachable from the border through non-component cells
    // (4-connected, so an 8-connected ring seals).
    let mut outside = vec![false; w * h];
    let mut queue = VecDeque::new();
    for x in 0..w {
        for y in [0, h - 1] {
            let k = y * w + x;
            if !in_comp[k] && !outside[k] {
                outside[k] = true;
                queue.push_back(k);
            }
        }
    }
    for y in 0..h {
        for x in [0, w - 1] {
            let k = y * w + x;
            if !in_comp[k] && !outside[k] {
                outside[k] = true;
                queue.push_back(k);
            }
        }
    }
    while let Some(c) = queue.pop_front() {
        let (x, y) = (c % w, c / w);
        let mut visit = |k: usize| {
            if !in_comp[k] && !outside[k] {
                outside[k] = true;
                queue.push_back(k);
            }
        };
        if x > 0 {
            visit(c - 1);
        }
        if x + 1 < w {
            visit(c + 1);
        }
        if y > 0 {
            visit(c - w);
        }
        if y + 1 < h {
            visit(c + w);
        }
    }
    let filled: Vec<bool> = outside.iter().map(|&o| !o).collect();
    let interior = filled.iter().filter(|&&f| f).count() - comp_cells;
    let closed_ring = interior * 4 >= comp_cells;
    let perimeter_cells = boundary_edge_count(grid, &in_comp);
    // Mean thickness of the component in cells: 2·area / perimeter.
    let thickness = 2.0 * comp_cells as Real / perimeter_cells.max(1) as Real;
    if closed_ring || thickness > 4.0 {
        let (region, outer_only) = if closed_ring {
            (filled, false)
        } else {
            (in_comp, true)
        };
        Ordering::Done(
            order_by_contour(grid, &region, outer_only, members, pts, cell_of)
                .map(|r| (r, closed_ring)),
        )
    } else {
        Ordering::Arc
    }
}

/// Number of cell sides between the region and the rest.
fn boundary_edge_count(grid: &Grid, region: &[bool]) -> usize {
    let (w, h) = (grid.w, grid.h);
    let at = |x: isize, y: isize| {
        x >= 0
            && y >= 0
            && (x as usize) < w
            && (y as usize) < h
            && region[y as usize * w + x as usize]
    };
    let mut n = 0;
    for y in 0..h as isize {
        for x in 0..w as isize {
            if at(x, y) {
                n += usize::from(!at(x - 1, y))
                    + usize::from(!at(x + 1, y))
                    + usize::from(!at(x, y - 1))
                    + usize::from(!at(x, y + 1));
            }
        }
    }
    n
}

/// Traces the outer boundary of `region` (corner lattice, region on the
/// left, right turns preferred at saddles so diagonal cells stay
/// connected), labels every region cell with its nearest boundary vertex
/// (breadth-first), and bins the points by their arc position along the
/// (smoothed) boundary. With `outer_only` (a solid blob) only the points
/// within 1.5 cells of the boundary count: the blob's outline.
fn order_by_contour(
    grid: &Grid,
    region: &[bool],
    outer_only: bool,
    members: &[usize],
    pts: &[Point2],
    cell_of: &[usize],
) -> Option<Vec<usize>> {
    let (w, h) = (grid.w, grid.h);
    let cw = w + 1; // corners per row
    let at = |x: isize, y: isize| {
        x >= 0
            && y >= 0
            && (x as usize) < w
            && (y as usize) < h
            && region[y as usize * w + x as usize]
    };
    // out[corner] bit d: a boundary edge leaves the corner in direction d
    // (0 = +x, 1 = +y, 2 = −x, 3 = −y).
    let mut out = vec![0u8; cw * (h + 1)];
    let mut start: Option<(usize, u8)> = None;
    for y in 0..h as isize {
        for x in 0..w as isize {
            if !at(x, y) {
                continue;
            }
            let (ux, uy) = (x as usize, y as usize);
            if !at(x, y - 1) {
                out[uy * cw + ux] |= 1 << 0;
                if start.is_none() {
                    start = Some((uy * cw + ux, 0));
                }
            }
            if !at(x + 1, y) {
                out[uy * cw + ux + 1] |= 1 << 1;
            }
            if !at(x, y + 1) {
                out[(uy + 1) * cw + ux + 1] |= 1 << 2;
            }
            if !at(x - 1, y) {
                out[(uy + 1) * cw + ux] |= 1 << 3;
            }
        }
    }
    let (c0, d0) = start?;
    let step = |c: usize, d: u8| -> usize {
        match d {
            0 => c + 1,
            1 => c + cw,
            2 => c - 1,
            _ => c - cw,
        }
    };
    let mut contour: Vec<usize> = Vec::new();
    let (mut c, mut d) = (c0, d0);
    let limit = 4 * w * h + 4;
    loop {
        contour.push(c);
        out[c] &= !(1 << d);
        c = step(c, d);
        // Prefer a right turn, then straight, then left.
        let options = [(d + 3) % 4, d, (d + 1) % 4, (d + 2) % 4];
        match options.iter().find(|&&o| out[c] & (1 << o) != 0) {
            Some(&o) => d = o,
            None => break,
        }
        if contour.len() > limit {
            return None;
        }
    }
    if contour.len() < 3 {
        return None;
    }
    // Breadth-first labels from the boundary inward.
    let mut label = vec![NONE; w * h];
    let mut queue = VecDeque::new();
    for (i, &corner) in contour.iter().enumerate() {
        let (x, y) = ((corner % cw) as isize, (corner / cw) as isize);
        for (dx, dy) in [(0, 0), (-1, 0), (0, -1), (-1, -1)] {
            if at(x + dx, y + dy) {
                let k = (y + dy) as usize * w + (x + dx) as usize;
                if label[k] == NONE {
                    label[k] = i as u32;
                    queue.push_back(k);
                }
            }
        }
    }
    while let Some(k) = queue.pop_front() {
        let (x, y) = ((k % w) as isize, (k / w) as isize);
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            if at(x + dx, y + dy) {
                let n = (y + dy) as usize * w + (x + dx) as usize;
                if label[n] == NONE {
                    label[n] = label[k];
                    queue.push_back(n);
                }
            }
        }
    }
    // A smooth version of the staircase boundary (moving average of five
    // corners), its arc length, and each point's arc position: the nearest
    // point on the segments around its label.
    let nc = contour.len();
    let corner = |i: usize| {
        let c = contour[i % nc];
        grid.origin + Vec2::new((c % cw) as Real, (c / cw) as Real) * grid.cell
    };
    let smooth: Vec<Vec2> = (0..nc)
        .map(|i| (0..5).fold(Vec2::ZERO, |s, k| s + corner(i + nc + k - 2)) / 5.0)
        .collect();
    let mut arc = vec![0.0; nc + 1];
    for i in 0..nc {
        arc[i + 1] = arc[i] + (smooth[(i + 1) % nc] - smooth[i]).norm();
    }
    let total = arc[nc];
    if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let bins = ((total / grid.cell).round() as usize).max(8);
    let keys: Vec<(u32, usize)> = members
        .iter()
        .filter_map(|&m| {
            let l = label[cell_of[m]];
            if l == NONE {
                return None;
            }
            let q = pts[m];
            let mut best = (Real::INFINITY, 0.0);
            for k in 0..8 {
                let i = (l as usize + nc + k - 4) % nc;
                let (a, b) = (smooth[i], smooth[(i + 1) % nc]);
                let t = segment_parameter(q, a, b);
                let d = (a + (b - a) * t - q).norm_squared();
                if d < best.0 {
                    best = (d, arc[i] + t * (arc[i + 1] - arc[i]));
                }
            }
            if outer_only && best.0 > (1.5 * grid.cell).powi(2) {
                return None;
            }
            let bin = ((best.1 / total * bins as Real) as usize).min(bins - 1);
            Some((bin as u32, m))
        })
        .collect();
    Some(representatives(keys, pts, grid.cell))
}
