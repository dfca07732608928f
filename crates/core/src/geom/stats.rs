//! Order statistics of samples.

use crate::geom::math::Real;

/// The middle value of `v` in `total_cmp` order (the upper one of an even
/// count), by a selection in linear time: `v` is reordered. `None` when
/// `v` is empty. The same element as `sorted[v.len() / 2]`.
pub fn median(v: &mut [Real]) -> Option<Real> {
    let k = v.len() / 2;
    (!v.is_empty()).then(|| *v.select_nth_unstable_by(k, Real::total_cmp).1)
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
    }
}
