//! The points' share of the normal equations, summed as trigonometric
//! moments. A point's row is, per section `m` around its foot,
//! `n1_m x(v)` over the section's `a` and `n2_m y(v)` over its `b`, with
//! `x = (1, cos v, sin v, …)` and `y = (1, sin v, cos v, …)`. Every entry of
//! its outer product is a coefficient times a product of two harmonics,
//! and such a product is half a sum of two harmonics of the summed and the
//! differenced frequencies. So the sum over the points of a block of
//! `(2J+1)²` entries is a linear function of `4J+1` sums of harmonics:
//! those are what each point adds, and the blocks are expanded once.

use super::{Band, Layout};
use crate::curve::series::harmonics;
use crate::geom::math::Real;

/// How far apart (in sections) two sections of one point's row may lie.
const REACH: usize = 3;

/// The harmonic a basis function is: a cosine (`false`) or a sine (`true`)
/// and its frequency; `swapped` for `y`, whose sine and cosine trade places.
#[inline]
fn harmonic(i: usize, swapped: bool) -> (bool, usize) {
    if i == 0 {
        (false, 0)
    } else {
        (i.is_multiple_of(2) != swapped, i.div_ceil(2))
    }
}

/// Sums over points of `c · cos fv` and `c · sin fv` for every frequency
/// up to `2J`, one pair of vectors per pair of sections and pair of
/// bases; and the harmonics of the angle of the points being added.
pub(super) struct Moments {
    sections: usize,
    /// `2J + 1`: the frequencies 0 ..= 2J.
    width: usize,
    /// Per slot, the cosine sums then the sine sums.
    sums: Vec<Real>,
    touched: Vec<bool>,
    cos: Vec<Real>,
    sin: Vec<Real>,
}

/// The pairs of bases a block sums, row section's first: `a·a`, `a·b`,
/// `b·a`, `b·b` (`a` row with `b` column lies above the diagonal of a
/// section's own block, so that one is not stored there).
const PAIRS: [(bool, bool); 4] = [(false, false), (false, true), (true, false), (true, true)];

impl Moments {
    pub(super) fn new(layout: &Layout) -> Moments {
        let order = layout.len.iter().map(|l| (l - 1) / 2).max().unwrap_or(0);
        let sections = layout.len.len();
        let width = 2 * order + 1;
        let slots = sections * (REACH + 1) * PAIRS.len();
        Moments {
            sections,
            width,
            sums: vec![0.0; 2 * slots * width],
            touched: vec![false; sections * (REACH + 1)],
            cos: vec![0.0; width],
            sin: vec![0.0; width],
        }
    }

    /// Sets the angle `v` of the points added next.
    pub(super) fn at_angle(&mut self, v: Real) {
        harmonics(v, self.width - 1, &mut self.cos, &mut self.sin);
    }

    /// Basis function `i` of `x` (`y` when `swapped`) at the angle set.
    #[inline]
    pub(super) fn basis(&self, i: usize, swapped: bool) -> Real {
        match harmonic(i, swapped) {
            (true, f) => self.sin[f],
            (false, f) => self.cos[f],
        }
    }

    /// Adds `w · r rᵀ` for the row of a point at the angle set whose
    /// sections are `terms`: `(m, n1_m, n2_m)` in section order. `false`
    /// (nothing added) when they lie farther apart than the sums reach.
    pub(super) fn add(&mut self, terms: &[(usize, Real, Real)], w: Real) -> bool {
        let (Some(first), Some(last)) = (terms.first(), terms.last()) else {
            return true;
        };
        if last.0 - first.0 > REACH || last.0 >= self.sections {
            return false;
        }
        let width = self.width;
        for (q, &(l, n1l, n2l)) in terms.iter().enumerate() {
            for &(k, n1k, n2k) in &terms[..=q] {
                let d = l - k;
                let block = k * (REACH + 1) + d;
                self.touched[block] = true;
                for (p, &(row_b, col_b)) in PAIRS.iter().enumerate() {
                    if d == 0 && !row_b && col_b {
                        continue;
                    }
                    let c = w * if row_b { n2l } else { n1l } * if col_b { n2k } else { n1k };
                    let at = 2 * (block * PAIRS.len() + p) * width;
                    let (cs, ss) = self.sums[at..at + 2 * width].split_at_mut(width);
                    for (s, &h) in cs.iter_mut().zip(&self.cos) {
                        *s += c * h;
                    }
                    for (s, &h) in ss.iter_mut().zip(&self.sin) {
                        *s += c * h;
                    }
                }
            }
        }
        true
    }

    /// Adds the summed blocks to `band`.
    pub(super) fn expand(&self, layout: &Layout, band: &mut Band) {
        for k in 0..self.sections {
            for d in 0..=REACH {
                let l = k + d;
                if l >= self.sections || !self.touched[k * (REACH + 1) + d] {
                    continue;
                }
                for (p, &(row_b, col_b)) in PAIRS.iter().enumerate() {
                    if d == 0 && !row_b && col_b {
                        continue;
                    }
                    let at = 2 * ((k * (REACH + 1) + d) * PAIRS.len() + p) * self.width;
                    let sums = self.sums[at..at + 2 * self.width].split_at(self.width);
                    let lower = d == 0 && row_b == col_b;
                    for i in 0..layout.len[l] {
                        let hi = if lower { i + 1 } else { layout.len[k] };
                        let row = layout.at(l, row_b, i);
                        for j in 0..hi {
                            let value = product(sums, harmonic(i, row_b), harmonic(j, col_b));
                            *band.at(row, layout.at(k, col_b, j)) += value;
                        }
                    }
                }
            }
        }
    }
}

/// The sum of `h1 · h2` over the points from their sums of cosines and
/// sines (`(sine?, frequency)` each).
#[inline]
fn product(
    (cos, sin): (&[Real], &[Real]),
    (s1, f1): (bool, usize),
    (s2, f2): (bool, usize),
) -> Real {
    // sin of a signed frequency.
    let sin_at = |f: isize| {
        let s = sin[f.unsigned_abs()];
        if f < 0 {
            -s
        } else {
            s
        }
    };
    let diff = f1 as isize - f2 as isize;
    let (plus, minus) = (f1 + f2, f1.abs_diff(f2));
    0.5 * match (s1, s2) {
        (false, false) => cos[minus] + cos[plus],
        (true, true) => cos[minus] - cos[plus],
        (true, false) => sin_at(plus as isize) + sin_at(diff),
        (false, true) => sin_at(plus as isize) - sin_at(diff),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `x`'s basis (1, cos jv, sin jv, …) and `y`'s (1, sin jv, cos jv, …)
    /// at `v`, each harmonic computed on its own.
    fn basis(v: Real, order: usize, x: &mut Vec<Real>, y: &mut Vec<Real>) {
        x.clear();
        y.clear();
        x.push(1.0);
        y.push(1.0);
        for j in 1..=order {
            let (s, c) = (j as Real * v).sin_cos();
            x.extend([c, s]);
            y.extend([s, c]);
        }
    }

    /// The outer products summed as moments equal the rows' outer
    /// products added one by one, for sections of unequal orders.
    #[test]
    fn moments_give_the_outer_products() {
        let len = vec![5, 21, 21, 9, 21, 3];
        let mut off = vec![0];
        for l in &len {
            off.push(off.last().unwrap() + 2 * l);
        }
        let layout = Layout { off, len };
        let n = layout.unknowns();
        let (mut direct, mut summed) = (Band::new(n, n - 1), Band::new(n, n - 1));
        let mut moments = Moments::new(&layout);
        let (mut x, mut y) = (Vec::new(), Vec::new());
        for i in 0..200 {
            let f = |a: Real| (i as Real * a).fract() - 0.5;
            let (v, w) = (10.0 * f(0.618), 1.0 + f(0.754));
            let m0 = i % 3;
            let terms: Vec<(usize, Real, Real)> = (m0..m0 + 4)
                .map(|m| (m, f(0.569 + 0.1 * m as Real), f(0.431 + 0.07 * m as Real)))
                .collect();
            let mut row = Vec::new();
            for &(m, n1, n2) in &terms {
                basis(v, (layout.len[m] - 1) / 2, &mut x, &mut y);
                row.extend(
                    x.iter()
                        .enumerate()
                        .map(|(i, b)| (layout.at(m, false, i), b * n1)),
                );
                row.extend(
                    y.iter()
                        .enumerate()
                        .map(|(i, b)| (layout.at(m, true, i), b * n2)),
                );
            }
            direct.add_outer(&row, w);
            moments.at_angle(v);
            assert!(moments.add(&terms, w));
        }
        moments.expand(&layout, &mut summed);
        let mut worst: Real = 0.0;
        for i in 0..n {
            for j in 0..=i {
                worst = worst.max((direct.get(i, j) - summed.get(i, j)).abs());
            }
        }
        assert!(worst < 1e-12, "largest difference {worst}");
    }

    /// A point whose sections lie farther apart than the sums reach is
    /// left to the caller.
    #[test]
    fn a_row_beyond_the_reach_is_refused() {
        let layout = Layout {
            off: vec![0, 6, 12, 18, 24, 30],
            len: vec![3; 5],
        };
        let mut moments = Moments::new(&layout);
        moments.at_angle(0.3);
        assert!(!moments.add(&[(0, 1.0, 0.0), (4, 1.0, 0.0)], 1.0));
        assert!(moments.add(&[(1, 1.0, 0.0), (4, 1.0, 0.0)], 1.0));
    }
}
