//! The crate's tolerances: one name for each small number that decides
//! "equal", "degenerate" or "within rounding" in more than one place, and
//! the `assert_near!` family of test macros, which print both sides.
//!
//! Every constant is relative (multiplied by the size of what it
//! compares) unless its doc says otherwise. A tolerance that belongs to
//! one algorithm alone stays with it (e.g. `curve::lsq::PIVOT_TOLERANCE`).

use crate::geom::math::Real;

/// "These two geometric quantities are equal", relative to the size of
/// the geometry: a length below `GEOMETRIC_EPS` times the scale counts as
/// zero (distance floors, coincident points, degeneracy checks).
pub const GEOMETRIC_EPS: Real = 1e-12;

/// Two unit directions agree: a norm within it of 1, a dot product within
/// it of 0, a component off a line below it (absolute, as the vectors are
/// unit; relative to the norm otherwise).
pub const DIRECTION_EPS: Real = 1e-9;

/// The relative margin by which a search window or a pruning bound is
/// widened so that rounding never drops a candidate the exact test would
/// keep (an exact test after it decides).
pub const ROUNDING_MARGIN: Real = 1e-9;

/// A pivot of a small dense solve (`geom::linalg::Lu`) below this
/// fraction of the matrix's largest entry makes the system singular.
pub const PIVOT_EPS: Real = 1e-12;

/// The relative accuracy of a perimeter that only sizes something (a
/// girth in mm, a tessellation's sample count): 1 µm on a 1 m girth, at a
/// fraction of the cost of the curve's own default (1e-10).
pub const SIZING_ACCURACY: Real = 1e-6;

/// Asserts that two reals agree within an absolute tolerance, printing both.
#[doc(hidden)]
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            (a - b).abs() <= tol,
            "assert_near failed: {} = {a:e}, {} = {b:e}, |diff| = {:e} > {tol:e}",
            stringify!($a),
            stringify!($b),
            (a - b).abs()
        );
    }};
}

/// Asserts that two reals agree within a tolerance relative to the second
/// (the expected value), printing both.
#[doc(hidden)]
#[macro_export]
macro_rules! assert_rel_near {
    ($a:expr, $b:expr, $rel:expr) => {{
        let (a, b, rel): (f64, f64, f64) = ($a, $b, $rel);
        assert!(
            (a - b).abs() <= rel * b.abs(),
            "assert_rel_near failed: {} = {a:e}, {} = {b:e}, |diff| / |{}| = {:e} > {rel:e}",
            stringify!($a),
            stringify!($b),
            stringify!($b),
            (a - b).abs() / b.abs()
        );
    }};
}

/// Asserts that two points or vectors (`Vec2`, `Vec3`) lie within a
/// distance of each other, printing both.
#[doc(hidden)]
#[macro_export]
macro_rules! assert_vec_near {
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d: f64 = (a - b).norm();
        assert!(
            d <= tol,
            "assert_vec_near failed: {} = {a:?}, {} = {b:?}, distance {d:e} > {tol:e}",
            stringify!($a),
            stringify!($b),
        );
    }};
}

#[cfg(test)]
mod tests {
    use crate::geom::math::{Vec2, Vec3};

    #[test]
    fn near_values_pass() {
        assert_near!(1.0, 1.0 + 1e-13, 1e-12);
        assert_rel_near!(1000.0, 1000.0 + 1e-10, 1e-12);
        assert_vec_near!(Vec3::X, Vec3::new(1.0, 1e-13, 0.0), 1e-12);
        assert_vec_near!(Vec2::new(0.0, 1.0), Vec2::new(0.0, 1.0), 0.0);
    }

    #[test]
    #[should_panic(expected = "assert_near failed")]
    fn assert_near_fails_beyond_the_tolerance() {
        assert_near!(1.0, 1.1, 0.05);
    }

    #[test]
    #[should_panic(expected = "assert_rel_near failed")]
    fn assert_rel_near_is_relative_to_the_expected_value() {
        assert_rel_near!(1e-3, 2e-3, 0.1);
    }

    #[test]
    #[should_panic(expected = "assert_vec_near failed")]
    fn assert_vec_near_fails_beyond_the_distance() {
        assert_vec_near!(Vec3::X, Vec3::Y, 1.0);
    }

    #[test]
    #[should_panic(expected = "assert_near failed")]
    fn nan_is_near_nothing() {
        assert_near!(f64::NAN, f64::NAN, 1.0);
    }
}
