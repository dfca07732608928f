use super::split::halfway_section;
use super::*;
use crate::curve::trig::Frame;
use crate::surface::part::PartOptions;

/// A curve at height `z`, its plane tilted by `tilt` about x, with a few
/// harmonics of its own.
fn curve(z: Real, tilt: Real, k: Real) -> TrigCurve {
    let frame = Frame::from_normal(
        Point3::new(0.01 * k, z, 0.005 * k),
        Vec3::new(0.0, tilt.cos(), tilt.sin()),
        Vec3::X,
    )
    .unwrap();
    let mut c = TrigCurve::circle(frame, 0.1 + 0.01 * k, 4);
    c.a[5] = 0.004 * k;
    c.b[4] = -0.003;
    c.a[2] = 0.002 * (k - 1.0);
    c
}

fn lumpy_part() -> Part {
    let curves = (0..7)
        .map(|k| {
            curve(
                0.05 * k as Real + 0.003 * (k * k) as Real,
                0.05 * k as Real,
                k as Real,
            )
        })
        .collect();
    Part::new(curves, &PartOptions::default()).unwrap()
}

/// Points on `part` at a grid of (s, v) inside its ends.
fn samples(part: &Part, along: usize, around: usize) -> Vec<Point3> {
    let l = part.length();
    (0..along)
        .flat_map(|i| {
            let s = l * (0.01 + 0.98 * i as Real / (along - 1) as Real);
            (0..around).map(move |j| {
                part.point(
                    s,
                    std::f64::consts::TAU * (j as Real + 0.3) / around as Real,
                )
            })
        })
        .collect()
}

#[test]
fn section_weights_reproduce_the_surface() {
    let part = lumpy_part();
    let sw = SectionWeights::of(&part).unwrap();
    let l = part.length();
    for i in 0..=40 {
        let s = l * i as Real / 40.0;
        for j in 0..12 {
            let v = 0.5 * j as Real;
            let sum = sw.at(s).iter().fold(Vec3::ZERO, |acc, &(m, w)| {
                acc + part.curves()[m].point(v) * w
            });
            assert!(sum.distance(part.point(s, v)) < 1e-12, "s {s} v {v}");
        }
    }
}

#[test]
fn the_fast_surface_is_the_part() {
    let part = lumpy_part();
    let surface = Surface::of(&part).unwrap();
    let l = part.length();
    for i in 0..=30 {
        let s = l * i as Real / 30.0;
        for j in 0..10 {
            let v = 0.63 * j as Real;
            let [p, ds, dv] = surface.eval(s, v);
            assert!(p.distance(part.point(s, v)) < 1e-12);
            assert!(ds.distance(part.derivative(s, v, 1, 0)) < 1e-9, "s {s}");
            assert!(dv.distance(part.derivative(s, v, 0, 1)) < 1e-12);
        }
        assert!(surface.centre(s).distance(part.centre(s)) < 1e-12);
    }
}

#[test]
fn the_grid_lies_on_the_part() {
    let part = lumpy_part();
    let grid = PartGrid::new(&part, 37, 3);
    assert_eq!(grid.params.len(), grid.mesh.positions.len());
    for (&[s, v], &p) in grid.params.iter().zip(&grid.mesh.positions) {
        assert!(p.distance(part.point(s, v)) < 1e-12, "s {s} v {v}");
    }
}

#[test]
fn projection_finds_the_foot() {
    let part = lumpy_part();
    let grid = PartGrid::new(&part, 64, 3);
    let tree = MeshDistance::new(grid.mesh());
    let surface = Surface::of(&part).unwrap();
    let l = part.length();
    for (s, v) in [(0.3 * l, 1.0), (0.77 * l, 4.0), (0.5 * l, 6.0)] {
        let on = part.point(s, v);
        let n = part
            .derivative(s, v, 1, 0)
            .cross(part.derivative(s, v, 0, 1))
            .normalized()
            .unwrap();
        let outward = if n.dot(on - part.centre(s)) > 0.0 {
            n
        } else {
            -n
        };
        let foot = project(&surface, &grid, &tree, on + outward * 0.004).unwrap();
        assert!(
            (foot.s - s).abs() < 1e-6 && (foot.v - v).abs() < 1e-6,
            "{foot:?}"
        );
        assert!((foot.signed - 0.004).abs() < 1e-12 && !foot.at_end);
        let inside = project(&surface, &grid, &tree, on - outward * 0.003).unwrap();
        assert!((inside.signed + 0.003).abs() < 1e-12);
    }
    let past = project(
        &surface,
        &grid,
        &tree,
        part.point(l, 1.0) + (part.point(l, 1.0) - part.point(0.9 * l, 1.0)),
    );
    assert!(past.unwrap().at_end);
    // Anywhere around the part, near or far, past the ends too: the foot
    // is never farther than the grid's nearest point but for the grid's
    // own chordal error (a Gauss-Newton step that leads away, past a
    // strongly curved end, is not taken: such steps once gave feet 24 cm
    // away).
    let mut rng = crate::geom::rng::Rng::new(7);
    for _ in 0..2000 {
        let q = Point3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * 0.15
            + part.centre(l * 0.5)
            + Vec3::new(0.0, 0.25 * rng.gaussian(), 0.0);
        let foot = project(&surface, &grid, &tree, q).unwrap();
        let grid_best = tree.closest(q).unwrap().distance;
        assert!(
            q.distance(foot.point) <= grid_best + 1e-3,
            "{q:?}: {foot:?} vs {grid_best}"
        );
    }
}

#[test]
fn a_part_fitted_to_its_own_points_does_not_move() {
    let part = lumpy_part();
    let points = samples(&part, 60, 48);
    let weights = vec![1.0; points.len()];
    let opts = SurfaceFitOptions {
        min_cutoff: 0.01,
        ..SurfaceFitOptions::default()
    };
    let (_, stats) = fit_part(&part, &points, &weights, &opts);
    assert!(stats.moved_max < 1e-9, "{stats:?}");
    assert!(stats.rms_after < 1e-9);
}

#[test]
fn sinusoids_on_a_cylinder_give_back_their_coefficients() {
    // The same curve every 0.1 along z: the skinned surface is its
    // extrusion, and points on it are fitted from circles.
    let truth = |z: Real| {
        let mut c = TrigCurve::circle(
            Frame::from_normal(Point3::new(0.0, 0.0, z), Vec3::Z, Vec3::X).unwrap(),
            0.12,
            4,
        );
        c.a[3] = 0.006;
        c.b[4] = -0.004;
        c.a[8] = 0.002;
        c.b[5] = 0.003;
        c
    };
    let options = PartOptions::default();
    let target = Part::new((0..6).map(|k| truth(0.1 * k as Real)).collect(), &options).unwrap();
    let start = Part::new(
        (0..6)
            .map(|k| {
                TrigCurve::circle(
                    Frame::from_normal(Point3::new(0.0, 0.0, 0.1 * k as Real), Vec3::Z, Vec3::X)
                        .unwrap(),
                    0.11,
                    4,
                )
            })
            .collect(),
        &options,
    )
    .unwrap();
    let points = samples(&target, 80, 64);
    let weights = vec![1.0; points.len()];
    let opts = SurfaceFitOptions {
        // Little damping: the exact answer in a few rounds.
        rounds: 20,
        pull: 1e-7,
        anchor: 0.0,
        min_cutoff: 0.05,
        ..SurfaceFitOptions::default()
    };
    let (fitted, stats) = fit_part(&start, &points, &weights, &opts);
    assert!(stats.rms_after < 1e-7, "{stats:?}");
    // Points fix a curve's shape, not where its parameter starts: the
    // coefficients compare after the best phase shift.
    for (got, want) in fitted.sections().iter().zip(target.sections()) {
        let got = got.shifted(crate::surface::part::best_phase_shift(
            &want.world_series(),
            &got.world_series(),
        ));
        for (g, w) in got.a.iter().chain(&got.b).zip(want.a.iter().chain(&want.b)) {
            assert!((g - w).abs() < 1e-6, "{:?} vs {:?}", got.a, want.a);
        }
    }
}

#[test]
fn far_outliers_move_nothing() {
    let part = lumpy_part();
    let mut points = samples(&part, 60, 50);
    // 2 % of the points 0.2 away, in every direction.
    for (k, i) in (0..points.len()).step_by(50).enumerate() {
        let a = k as Real * 2.399;
        points[i] += Vec3::new(a.cos(), 0.3 * a.sin(), a.sin())
            * (0.2 / (1.0 + 0.09 * a.sin().powi(2)).sqrt());
    }
    let weights = vec![1.0; points.len()];
    let opts = SurfaceFitOptions {
        min_cutoff: 0.005,
        ..SurfaceFitOptions::default()
    };
    let (_, stats) = fit_part(&part, &points, &weights, &opts);
    assert!(stats.moved_max < 1e-4, "{stats:?}");
}

#[test]
fn band_cholesky_solves_a_banded_system() {
    // A tridiagonal system with a known solution.
    let n = 9;
    let mut band = Band::new(n, 2);
    for i in 0..n {
        *band.at(i, i) = 4.0;
        if i > 0 {
            *band.at(i, i - 1) = -1.0;
        }
        if i > 1 {
            *band.at(i, i - 2) = 0.5;
        }
    }
    let x: Vec<Real> = (0..n).map(|i| i as Real - 3.0).collect();
    let b: Vec<Real> = (0..n)
        .map(|i| {
            (i.saturating_sub(2)..(i + 3).min(n))
                .map(|j| {
                    let (r, c) = (i.max(j), i.min(j));
                    band.get(r, c) * x[j]
                })
                .sum()
        })
        .collect();
    let got = band.solve(b).unwrap();
    for (g, w) in got.iter().zip(&x) {
        assert!((g - w).abs() < 1e-12);
    }
}

/// A step that would leave the part invalid is taken at half its length,
/// then a quarter, and not at all below that: a section's curve turned
/// clockwise (its y radius driven to its negative: the full step) or flat
/// (half) is not a part; a quarter of the step halves that radius.
#[test]
fn a_step_is_halved_until_the_part_is_valid() {
    let part = lumpy_part();
    let opts = SurfaceFitOptions::default();
    let layout = Layout::new(part.curves(), opts.max_order);
    let mut delta = vec![0.0; layout.unknowns()];
    let r = part.curves()[3].b[1];
    delta[layout.at(3, true, 1)] = -2.0 * r;
    let (moved, share) = scaled_step(&part, &delta, 1.0, &opts).expect("a quarter step");
    assert_eq!(share, 0.25);
    // (Read in the moved part's own twist, which the rebuild re-aligns.)
    let radius = moved.curves()[3].b[1];
    assert!((radius / r - 0.5).abs() < 0.01, "{radius} against {r}");
    // A step no share of which down to a quarter makes a part.
    let far: Vec<Real> = delta.iter().map(|x| x * 4.0).collect();
    assert!(scaled_step(&part, &far, 1.0, &opts).is_none());
}

/// A cylinder of radius 0.1 along y whose middle section bulges to
/// `middle` (a mitten's skin across a gap: no points of its own).
fn bulged_cylinder(middle: Real) -> Part {
    let curves = (0..9)
        .map(|k| {
            let frame =
                Frame::from_normal(Point3::new(0.0, 0.05 * k as Real, 0.0), Vec3::Y, Vec3::X)
                    .unwrap();
            TrigCurve::circle(frame, if k == 4 { middle } else { 0.1 }, 2)
        })
        .collect();
    Part::new(curves, &PartOptions::default()).unwrap()
}

/// The mean distance of a curve's points from the y axis.
fn mean_radius_about_y(c: &TrigCurve) -> Real {
    (0..32)
        .map(|j| {
            let p = c.point(std::f64::consts::TAU * j as Real / 32.0);
            (p.x * p.x + p.z * p.z).sqrt()
        })
        .sum::<Real>()
        / 32.0
}

/// Skin with no points of its own (a band of the cylinder the input does
/// not sample) is held to the input's points nearest it: the bulge is
/// pulled most of the way in, where the points alone leave it standing.
#[test]
fn skin_over_a_hole_is_held_to_the_nearest_points() {
    let truth = bulged_cylinder(0.1);
    let start = bulged_cylinder(0.13);
    let points: Vec<Point3> = samples(&truth, 81, 48)
        .into_iter()
        .filter(|p| (p.y - 0.2).abs() > 0.06)
        .collect();
    let weights = vec![1.0; points.len()];
    let bulge = |coverage: Real| {
        let opts = SurfaceFitOptions {
            min_cutoff: 0.005,
            coverage,
            coverage_reach: 0.1,
            ..SurfaceFitOptions::default()
        };
        let (fitted, _) = fit_part(&start, &points, &weights, &opts);
        mean_radius_about_y(&fitted.sections()[4]) - 0.1
    };
    let (without, with) = (bulge(0.0), bulge(1.0));
    assert!(
        without > 0.02,
        "the points alone moved the bulge: {without}"
    );
    assert!(with < 0.3 * without, "held: {with}, alone: {without}");
}

/// The section added halfway along an interval is the surface's own curve
/// there: on a part of parallel planes, exactly.
#[test]
fn a_halfway_section_is_the_surface_s_curve() {
    let part = bulged_cylinder(0.13);
    let (a, b) = (&part.curves()[3], &part.curves()[4]);
    let mid = part.segments()[3].patch.curve_at(0.5);
    let c = halfway_section(&mid, a, b).unwrap();
    assert!((c.frame.origin.y - 0.175).abs() < 1e-12, "{:?}", c.frame);
    for j in 0..40 {
        let v = 0.157 * j as Real;
        assert!(c.point(v).distance(mid.point(v)) < 1e-12, "v {v}");
    }
}

/// A bump between two sections is out of the fit's reach until a section
/// is added there: with `split`, one is, and the points come near.
#[test]
fn a_bump_between_sections_gets_a_section() {
    let ring = |y: Real, r: Real| {
        TrigCurve::circle(
            Frame::from_normal(Point3::new(0.0, y, 0.0), Vec3::Y, Vec3::X).unwrap(),
            r,
            2,
        )
    };
    let options = PartOptions::default();
    let truth = Part::new(
        (0..17)
            .map(|k| ring(0.025 * k as Real, if k == 9 { 0.125 } else { 0.1 }))
            .collect(),
        &options,
    )
    .unwrap();
    let start = Part::new(
        (0..9).map(|k| ring(0.05 * k as Real, 0.1)).collect(),
        &options,
    )
    .unwrap();
    // A little noise, so that the robust scale is not zero, and weights
    // that leave every point a plain least-squares one.
    let points: Vec<Point3> = samples(&truth, 161, 32)
        .into_iter()
        .enumerate()
        .map(|(i, p)| p + Vec3::new(p.x, 0.0, p.z) * (0.01 * (i as Real * 2.399).sin()))
        .collect();
    let weights = vec![1.0; points.len()];
    let fitted = |split: Real| {
        let opts = SurfaceFitOptions {
            min_cutoff: 0.05,
            huber: 100.0,
            cutoff: 100.0,
            split,
            min_gap: 0.01,
            ..SurfaceFitOptions::default()
        };
        fit_part(&start, &points, &weights, &opts)
    };
    let (kept, without) = fitted(0.0);
    let (split, with) = fitted(0.004);
    assert_eq!(kept.sections().len(), 9);
    assert!(split.sections().len() > 9, "{}", split.sections().len());
    assert!(
        with.rms_after < 0.5 * without.rms_after,
        "with {with:?}, without {without:?}"
    );
}
