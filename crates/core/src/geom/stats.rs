//! Order statistics of samples.

use crate::geom::math::Real;

/// The middle value of `v` in `total_cmp` order (the upper one of an even
/// count), by a selection in linear time: `v` is reordered. `None` when
/// `v` is empty. The same element as `sorted[v.len() / 2]`.
pub fn median(v: &mut [Real]) -> Option<Real> {
    nth_smallest(v, v.len() / 2)
}

/// The `k`-th smallest value of `v` (from 0) in `total_cmp` order, by a
/// selection in linear time: `v` is reordered. `None` when `k` is past the
/// end. The same element as `sorted[k]`.
pub fn nth_smallest(v: &mut [Real], k: usize) -> Option<Real> {
    (k < v.len()).then(|| *v.select_nth_unstable_by(k, Real::total_cmp).1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_is_the_sorted_middle() {
        assert_eq!(median(&mut []), None);
        assert_eq!(median(&mut [3.0]), Some(3.0));
        // An even count gives the upper of the two middle values.
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), Some(3.0));
        assert_eq!(median(&mut [5.0, -1.0, 2.0, 9.0, 0.0]), Some(2.0));
        let mut v: Vec<Real> = (0..101).map(|i| ((i * 37) % 101) as Real).collect();
        let mut sorted = v.clone();
        sorted.sort_by(Real::total_cmp);
        assert_eq!(median(&mut v), Some(sorted[50]));
        assert_eq!(nth_smallest(&mut v, 0), Some(0.0));
        assert_eq!(nth_smallest(&mut v, 100), Some(100.0));
        assert_eq!(nth_smallest(&mut v, 101), None);
    }
}
