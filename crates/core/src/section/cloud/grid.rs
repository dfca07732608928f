//! The occupancy image of a slab (step 3 of the module docs of [`super`]):
//! cells, morphological closing and 8-connected components. Also the
//! slice graph's (`segment::slices`).

use crate::geom::math::{Point2, Real, Vec2};

pub(crate) const NONE: u32 = u32::MAX;

/// A square-celled image over the plane.
pub(crate) struct Grid {
    pub(super) origin: Vec2,
    pub(super) cell: Real,
    pub(super) w: usize,
    pub(super) h: usize,
}

/// Where a grid over points starts, in cells below their lowest
/// coordinate beyond its margin: the golden section's `(3 − √5)/2`, far
/// from every simple fraction. The lowest point, and a scanner's points on
/// a lattice of the cell size, would otherwise sit on the cells' edges,
/// where a coordinate's last digit chose their cell (a nanometre's shift of
/// a scan changed its model).
const EDGE_OFFSET: Real = 0.381_966_011_250_105_1;

impl Grid {
    pub(crate) fn new(origin: Vec2, cell: Real, w: usize, h: usize) -> Grid {
        Grid { origin, cell, w, h }
    }

    /// A `w` × `h` grid over points whose lowest coordinates are `min`,
    /// with `margin` free cells below them (and their edges
    /// [`EDGE_OFFSET`] of a cell off them).
    pub(crate) fn below(min: Vec2, margin: usize, cell: Real, w: usize, h: usize) -> Grid {
        let lead = (margin as Real + EDGE_OFFSET) * cell;
        Grid::new(min - Vec2::new(lead, lead), cell, w, h)
    }

    pub(crate) fn cell(&self, p: Point2) -> usize {
        // `v as usize` is `v.floor().max(0.0) as usize` for every `v` (the
        // cast truncates, takes negatives and NaN to 0 and saturates),
        // without a call to `floor`.
        let x = (((p.x - self.origin.x) / self.cell) as usize).min(self.w - 1);
        let y = (((p.y - self.origin.y) / self.cell) as usize).min(self.h - 1);
        y * self.w + x
    }

    /// Morphological closing by a (2r+1)² square: dilation then erosion,
    /// each separable into a row pass and a column pass.
    pub(crate) fn close(&self, img: &[bool], r: usize) -> Vec<bool> {
        if r == 0 {
            return img.to_vec();
        }
        let dil = self.filter(img, r, true);
        self.filter(&dil, r, false)
    }

    /// Separable square max (`dilate`) or min filter of radius `r`, with
    /// everything outside the image unset. Running window counts: a row
    /// pass, then a column pass that slides one row of counts down the
    /// image (cache friendly).
    fn filter(&self, img: &[bool], r: usize, dilate: bool) -> Vec<bool> {
        let (w, h) = (self.w, self.h);
        let full = (2 * r + 1) as u32;
        let decide = |count: u32| if dilate { count > 0 } else { count == full };
        let mut tmp = vec![false; w * h];
        for y in 0..h {
            let row = &img[y * w..(y + 1) * w];
            let out = &mut tmp[y * w..(y + 1) * w];
            let mut count = row[..r.min(w)].iter().map(|&b| u32::from(b)).sum::<u32>();
            for x in 0..w {
                if x + r < w {
                    count += u32::from(row[x + r]);
                }
                if x > r {
                    count -= u32::from(row[x - r - 1]);
                }
                out[x] = decide(count);
            }
        }
        let mut counts = vec![0u32; w];
        for y in 0..r.min(h) {
            for (c, &b) in counts.iter_mut().zip(&tmp[y * w..(y + 1) * w]) {
                *c += u32::from(b);
            }
        }
        let mut out = vec![false; w * h];
        for y in 0..h {
            if y + r < h {
                for (c, &b) in counts.iter_mut().zip(&tmp[(y + r) * w..(y + r + 1) * w]) {
                    *c += u32::from(b);
                }
            }
            if y > r {
                for (c, &b) in counts.iter_mut().zip(&tmp[(y - r - 1) * w..(y - r) * w]) {
                    *c -= u32::from(b);
                }
            }
            for (o, &c) in out[y * w..(y + 1) * w].iter_mut().zip(&counts) {
                *o = decide(c);
            }
        }
        out
    }

    /// 8-connected components of the set cells: labels (NONE for unset)
    /// and their count, numbered in scan order.
    pub(crate) fn components(&self, img: &[bool]) -> (Vec<u32>, usize) {
        let (w, h) = (self.w, self.h);
        let mut labels = vec![NONE; w * h];
        let mut n = 0u32;
        let mut stack = Vec::new();
        for start in 0..w * h {
            if !img[start] || labels[start] != NONE {
                continue;
            }
            labels[start] = n;
            stack.push(start);
            while let Some(c) = stack.pop() {
                let (x, y) = ((c % w) as isize, (c / w) as isize);
                for dy in -1..=1isize {
                    for dx in -1..=1isize {
                        let (nx, ny) = (x + dx, y + dy);
                        if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                            continue;
                        }
                        let k = ny as usize * w + nx as usize;
                        if img[k] && labels[k] == NONE {
                            labels[k] = n;
                            stack.push(k);
                        }
                    }
                }
            }
            n += 1;
        }
        (labels, n as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closing fills gaps up to 2r cells and keeps the outside unset.
    #[test]
    fn closing_bridges_small_gaps_only() {
        let g = Grid::new(Vec2::ZERO, 1.0, 20, 5);
        let mut img = vec![false; 100];
        for x in [3, 4, 5, 8, 9, 15, 16] {
            img[2 * 20 + x] = true;
        }
        let c = g.close(&img, 1);
        let row: Vec<bool> = (0..20).map(|x| c[2 * 20 + x]).collect();
        // the 2-cell gap (6, 7) closes, the 5-cell gap (10..=14) does not
        assert!(row[3..=9].iter().all(|&b| b));
        assert!(row[10..=14].iter().all(|&b| !b));
        assert!(row[15] && row[16] && !row[17] && !row[2]);
        assert!(c[20 + 5..20 + 8].iter().all(|&b| !b));
    }
}
