//! Property tests of the fit: planted series in random planes, recovered
//! whatever the start point and direction of the input.

use proptest::prelude::*;
use std::f64::consts::TAU;
use trigbody_core::{fit_loop, FitOptions};
use trigbody_core::{Frame, OrderChoice, Real, TrigCurve, Vec3};

/// A star-shaped planted curve: a circle of radius 1 plus small harmonics,
/// so that the sampled loop never crosses itself.
fn planted(order: usize, coeffs: &[Real], frame: Frame) -> TrigCurve {
    let mut a = vec![0.0; 2 * order + 1];
    let mut b = a.clone();
    a[1] = 1.0;
    b[1] = 1.0;
    for k in 2..2 * order + 1 {
        a[k] = 0.08 * coeffs[2 * k] / k as Real;
        b[k] = 0.08 * coeffs[2 * k + 1] / k as Real;
    }
    TrigCurve::new(frame, a, b).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn sampled_series_is_reproduced_exactly(
        order in 1usize..8,
        coeffs in prop::collection::vec(-1.0f64..1.0, 40),
        normal in prop::array::uniform3(-1.0f64..1.0),
        origin in prop::array::uniform3(-100.0f64..100.0),
        scale in 0.01f64..100.0,
        roll in 0usize..200,
        reverse in any::<bool>(),
    ) {
        let n = Vec3::from(normal);
        prop_assume!(n.norm() > 0.1);
        let frame = Frame::from_normal(Vec3::from(origin), n, n.any_perpendicular()).unwrap();
        let mut curve = planted(order, &coeffs, frame);
        curve.a.iter_mut().for_each(|x| *x *= scale);
        curve.b.iter_mut().for_each(|x| *x *= scale);
        let count = 97;
        let mut pts: Vec<_> = (0..count).map(|i| curve.point(TAU * i as Real / count as Real)).collect();
        pts.rotate_left(roll % count);
        if reverse {
            pts.reverse();
        }
        let opts = FitOptions { order: OrderChoice::Fixed(order + 12), ..FitOptions::default() };
        let fit = fit_loop(&pts, &opts).unwrap();
        // Chord parameters differ from the planted ones, so the fit is not
        // exact, but a high order reproduces the samples closely; the
        // points' order never changes the fitted shape.
        prop_assert!(fit.errors.em < 1e-3, "E_M {}", fit.errors.em);
        prop_assert!(fit.curve.area() > 0.0);
        let expected_area = curve.area().abs();
        prop_assert!((fit.curve.area() - expected_area).abs() < 2e-3 * expected_area);
    }
}
