//! The tolerances a noisy loop allows.
//!
//! A scanned loop's points scatter about the surface by the scanner's noise
//! (and by the slab's thickness on a sloping surface). A series fitted to
//! them meets `E_a` and `E_M` only once it follows that scatter, so without
//! a floor the order grows with the noise, not with the shape: the same
//! body scanned ten times as densely (whose loops' representatives scatter
//! less) got orders a third as high. [`noise_tolerances`] raises the
//! tolerances to what the noise alone gives, so the order stops where the
//! shape is followed. The noise is the cloud's, measured across its surface
//! by the scan sections (`section::cloud`, which sit above this module):
//! one number that detail at a loop's point spacing (a mitten's fingers)
//! cannot inflate.

use crate::geom::math::{Real, Vec2};

/// `E_a` allowed per unit of noise relative to the radius: the mean of
/// `|N(0, σ²)|` is `0.80 σ`; the fit's residual also has a share along the
/// loop and the noise estimate its own error, hence half as much again.
const EA_PER_NOISE: Real = 1.2;

/// `E_M` allowed per unit of relative noise on top of the expected largest
/// of `n` Gaussian deviations, `sqrt(2 ln n)`.
const EM_MARGIN: Real = 1.0;

/// The tolerances `(E_a, E_M)` for a loop of `points` (relative to its
/// centroid, as the fit measures them) whose points scatter by `noise`
/// (a standard deviation in their units): each the larger of the given one
/// and what the noise alone makes it. `E_a` and `E_M` are relative to
/// each point's distance from the centroid, so the noise is taken relative
/// to the mean of their inverses.
pub fn noise_tolerances(points: &[Vec2], noise: Real, ea: Real, em: Real) -> (Real, Real) {
    let (sum, count) = points
        .iter()
        .map(|p| p.norm())
        .filter(|&d| d > 0.0)
        .fold((0.0, 0usize), |(s, n), d| (s + 1.0 / d, n + 1));
    if count == 0 || !(noise > 0.0) {
        return (ea, em);
    }
    let relative = noise * sum / count as Real;
    let largest = (2.0 * (points.len().max(2) as Real).ln()).sqrt() + EM_MARGIN;
    (ea.max(EA_PER_NOISE * relative), em.max(largest * relative))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn tolerances_rise_with_the_noise_only() {
        // A 50 mm circle of 100 points.
        let q: Vec<Vec2> = (0..100)
            .map(|i| {
                let t = TAU * i as Real / 100.0;
                Vec2::new(0.05 * t.cos(), 0.05 * t.sin())
            })
            .collect();
        assert_eq!(noise_tolerances(&q, 0.0, 0.01, 0.05), (0.01, 0.05));
        // 0.1 mm: under what the tolerances allow.
        assert_eq!(noise_tolerances(&q, 1e-4, 0.01, 0.05), (0.01, 0.05));
        // 2 mm: 4 % relative noise; E_a 1.2 x, E_M (3.03 + 1) x that.
        let (ea, em) = noise_tolerances(&q, 0.002, 0.01, 0.05);
        assert!((ea - 0.048).abs() < 1e-9, "{ea}");
        assert!(
            (em - 0.04 * ((2.0 * 100f64.ln()).sqrt() + 1.0)).abs() < 1e-9,
            "{em}"
        );
    }
}
