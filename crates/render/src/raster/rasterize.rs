//! Rasterization (step 3 of the module docs of [`super`]): the z-buffer
//! cells, the binning of triangles into tiles and the edge-function walk.

use super::{Projected, NO_TRIANGLE, SUBPIXEL};
use rayon::prelude::*;
use trigbody_core::Mesh;

/// One sample of the z-buffer: the nearest depth so far and its triangle,
/// side by side so that a depth test and its write touch one cache line.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cell {
    pub(super) depth: f32,
    pub(super) triangle: u32,
}

pub(super) const EMPTY_CELL: Cell = Cell {
    depth: f32::INFINITY,
    triangle: NO_TRIANGLE,
};

/// Whether the directed edge `(dx, dy)` is a top or left edge for a
/// triangle whose inside has non-negative edge functions: the inside lies
/// along the gradient `(−dy, dx)`; a left edge has it pointing right
/// (`dy < 0`), a top edge is horizontal with it pointing down (`dx > 0`).
#[inline]
fn is_top_left(dx: i64, dy: i64) -> bool {
    dy < 0 || (dy == 0 && dx > 0)
}

/// Smallest sample index whose centre `(i + ½)·SUBPIXEL` is ≥ `v`.
#[inline]
fn first_sample_at_or_after(v: i64) -> i64 {
    let c = v - SUBPIXEL / 2;
    -((-c).div_euclid(SUBPIXEL))
}

/// Largest sample index whose centre is ≤ `v`.
#[inline]
fn last_sample_at_or_before(v: i64) -> i64 {
    (v - SUBPIXEL / 2).div_euclid(SUBPIXEL)
}

/// Side of a square tile in pixels. A tile's samples (at most 128 × 128
/// cells of 8 bytes with 4 × 4 supersampling, 32 KiB at the default 2 × 2)
/// stay in the core's cache while its triangles are drawn and its pixels
/// shaded.
pub(super) const TILE: usize = 32;

/// The triangles that may cover each tile, in mesh order. The mesh is cut
/// into chunks binned in parallel; a tile's triangles are its list in the
/// first chunk, then in the second, and so on.
pub(super) struct Bins {
    pub(super) tiles_x: usize,
    chunks: Vec<Vec<Vec<u32>>>,
}

impl Bins {
    /// The triangles of tile `(tx, ty)`, in mesh order.
    pub(super) fn tile(&self, tx: usize, ty: usize) -> impl Iterator<Item = u32> + '_ {
        let i = ty * self.tiles_x + tx;
        self.chunks.iter().flat_map(move |c| c[i].iter().copied())
    }
}

/// The sample rectangle of a triangle's sample centres inside a
/// `width × height` grid, `None` when it covers none or has no area.
#[inline]
fn sample_bounds(
    p: &Projected,
    tri: &[u32; 3],
    width: usize,
    height: usize,
) -> Option<(i64, i64, i64, i64)> {
    let [v0, v1, v2] = tri.map(|i| p.raster[i as usize]);
    let (x0, y0) = (v0.fx as i64, v0.fy as i64);
    let (x1, y1) = (v1.fx as i64, v1.fy as i64);
    let (x2, y2) = (v2.fx as i64, v2.fy as i64);
    let min_x = first_sample_at_or_after(x0.min(x1).min(x2)).max(0);
    let max_x = last_sample_at_or_before(x0.max(x1).max(x2)).min(width as i64 - 1);
    let min_y = first_sample_at_or_after(y0.min(y1).min(y2)).max(0);
    let max_y = last_sample_at_or_before(y0.max(y1).max(y2)).min(height as i64 - 1);
    if min_x > max_x || min_y > max_y {
        return None;
    }
    let area = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0);
    (area != 0).then_some((min_x, max_x, min_y, max_y))
}

/// Sorts the triangles into the tiles (of `tile` samples) of a
/// `width × height` sample grid; triangles without area or without a sample
/// centre are dropped here.
pub(super) fn bin(mesh: &Mesh, p: &Projected, width: usize, height: usize, tile: usize) -> Bins {
    let tiles_x = width.div_ceil(tile);
    let tiles = tiles_x * height.div_ceil(tile);
    let chunk = mesh
        .triangles
        .len()
        .div_ceil(4 * rayon::current_num_threads())
        .max(4096);
    let chunks = mesh
        .triangles
        .par_chunks(chunk)
        .enumerate()
        .map(|(c, triangles)| {
            let mut bins = vec![Vec::new(); tiles];
            for (k, tri) in triangles.iter().enumerate() {
                let Some((x0, x1, y0, y1)) = sample_bounds(p, tri, width, height) else {
                    continue;
                };
                let t = (c * chunk + k) as u32;
                let (tx0, tx1) = (x0 as usize / tile, x1 as usize / tile);
                for ty in y0 as usize / tile..=y1 as usize / tile {
                    for tx in tx0..=tx1 {
                        bins[ty * tiles_x + tx].push(t);
                    }
                }
            }
            bins
        })
        .collect();
    Bins { tiles_x, chunks }
}

/// The samples of one tile: `width × height` cells whose top-left sample is
/// `(x0, y0)` in the panel's sample grid.
pub(super) struct Tile<'a> {
    pub(super) x0: usize,
    pub(super) y0: usize,
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) cells: &'a mut [Cell],
}

/// Rasterizes `triangles` into the tile's z-buffer (step 3 of the module
/// docs), in the order given.
pub(super) fn rasterize_tile(
    mesh: &Mesh,
    p: &Projected,
    tile: &mut Tile<'_>,
    triangles: impl Iterator<Item = u32>,
) {
    let (tile_x0, tile_y0) = (tile.x0 as i64, tile.y0 as i64);
    let (tile_x1, tile_y1) = (
        (tile.x0 + tile.width) as i64 - 1,
        (tile.y0 + tile.height) as i64 - 1,
    );
    for t in triangles {
        let [i0, i1, i2] = mesh.triangles[t as usize].map(|i| i as usize);
        let (v0, v1, v2) = (p.raster[i0], p.raster[i1], p.raster[i2]);
        let (x0, y0) = (v0.fx as i64, v0.fy as i64);
        let (mut x1, mut y1) = (v1.fx as i64, v1.fy as i64);
        let (mut x2, mut y2) = (v2.fx as i64, v2.fy as i64);
        let (mut z1, mut z2) = (v1.depth, v2.depth);
        let mut area = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0);
        if area == 0 {
            continue;
        }
        if area < 0 {
            std::mem::swap(&mut z1, &mut z2);
            std::mem::swap(&mut x1, &mut x2);
            std::mem::swap(&mut y1, &mut y2);
            area = -area;
        }
        let min_x = first_sample_at_or_after(x0.min(x1).min(x2)).max(tile_x0);
        let max_x = last_sample_at_or_before(x0.max(x1).max(x2)).min(tile_x1);
        let min_y = first_sample_at_or_after(y0.min(y1).min(y2)).max(tile_y0);
        let max_y = last_sample_at_or_before(y0.max(y1).max(y2)).min(tile_y1);
        if min_x > max_x || min_y > max_y {
            continue;
        }
        // Edge k is opposite vertex k: E_12 weighs v0, E_20 weighs v1,
        // E_01 weighs v2. Each is `dx (p_y − a_y) − dy (p_x − a_x)`, minus a
        // bias of 1 off top-left edges so that `≥ 0` applies the tie rule.
        let px = min_x * SUBPIXEL + SUBPIXEL / 2;
        let py = min_y * SUBPIXEL + SUBPIXEL / 2;
        let edge = |ax: i64, ay: i64, bx: i64, by: i64| {
            let (dx, dy) = (bx - ax, by - ay);
            let bias = if is_top_left(dx, dy) { 0 } else { 1 };
            let start = dx * (py - ay) - dy * (px - ax) - bias;
            (start, -dy * SUBPIXEL, dx * SUBPIXEL)
        };
        let (e0, e0x, e0y) = edge(x1, y1, x2, y2);
        let (e1, e1x, e1y) = edge(x2, y2, x0, y0);
        let (e2, e2x, e2y) = edge(x0, y0, x1, y1);
        let z0 = v0.depth;
        let inv_area = 1.0 / area as f32;
        let dz1 = (z1 - z0) * inv_area;
        let dz2 = (z2 - z0) * inv_area;
        let (mut r0, mut r1, mut r2) = (e0, e1, e2);
        for y in min_y..=max_y {
            let row = (y - tile_y0) as usize * tile.width;
            let (mut w0, mut w1, mut w2) = (r0, r1, r2);
            for x in min_x..=max_x {
                if (w0 | w1 | w2) >= 0 {
                    // The biases are at most 1 in units of 2⁻¹⁶ sample²;
                    // they do not matter for depth.
                    let z = z0 + w1 as f32 * dz1 + w2 as f32 * dz2;
                    let cell = &mut tile.cells[row + (x - tile_x0) as usize];
                    if z < cell.depth {
                        *cell = Cell {
                            depth: z,
                            triangle: t,
                        };
                    }
                }
                w0 += e0x;
                w1 += e1x;
                w2 += e2x;
            }
            r0 += e0y;
            r1 += e1y;
            r2 += e2y;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_rounding() {
        // Sample i has its centre at (i + ½)·256.
        assert_eq!(first_sample_at_or_after(128), 0);
        assert_eq!(first_sample_at_or_after(129), 1);
        assert_eq!(last_sample_at_or_before(383), 0);
        assert_eq!(last_sample_at_or_before(384), 1);
        assert_eq!(last_sample_at_or_before(0), -1);
        assert_eq!(first_sample_at_or_after(-1000), -4);
    }
}
