//! Two surfaces compared both ways, as a user would judge a model against
//! the mesh it should match: area-uniform samples of each surface, their
//! distances to the other, and the shares near and far.

use crate::geom::math::{Point3, Real};
use crate::geom::mesh::Mesh;
use crate::spatial::distance::{sample_surface, DistanceStats, MeshDistance};
use crate::spatial::point_grid::PointGrid;

/// Options of [`compare_surfaces`]; distances in the meshes' units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompareOptions {
    /// Samples on each surface (area-uniform). Default 100 000.
    pub samples: usize,
    /// A sample is near the other surface within this distance.
    pub near: Real,
    /// A sample is far from the other surface beyond this distance.
    pub far: Real,
}

/// [`compare_surfaces`]'s result: `truth` is the reference surface, `model`
/// the one judged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceComparison {
    /// Truth samples to the model.
    pub truth_to_model: DistanceStats,
    /// Model samples to the truth.
    pub model_to_truth: DistanceStats,
    /// `√((rms₁² + rms₂²) / 2)` of the two directions.
    pub symmetric_rms: Real,
    /// The larger of the two directions' 95th percentiles.
    pub p95: Real,
    /// Share of the truth's area within `near` of the model.
    pub truth_near: Real,
    /// Share of the model's area within `near` of the truth.
    pub model_near: Real,
    /// Share of the model's area farther than `far` from the truth.
    pub model_far: Real,
    /// Share of the truth's area left out of truth → model as unseen
    /// ([`compare_surfaces_seen`]; 0 when all of it counts).
    pub truth_unseen: Real,
}

/// Compares `model` against `truth` both ways (see the module doc).
pub fn compare_surfaces(truth: &Mesh, model: &Mesh, opts: &CompareOptions) -> SurfaceComparison {
    compare(sample_surface(truth, opts.samples), 0.0, model, truth, opts)
}

/// [`compare_surfaces`] for a model made from scanned `points`: truth →
/// model only over the truth the scanner saw, its samples within `seen`
/// of a point (the inside of a mouth, the soles the body stood on or a
/// missed crown are nobody's to know from the scan); model → truth
/// everywhere.
pub fn compare_surfaces_seen(
    truth: &Mesh,
    model: &Mesh,
    points: &[Point3],
    seen: Real,
    opts: &CompareOptions,
) -> SurfaceComparison {
    let all = sample_surface(truth, opts.samples);
    let grid = PointGrid::new(points, seen);
    let count = all.len();
    let seen_samples: Vec<Point3> = all
        .into_iter()
        .filter(|&p| grid.nearest(p) <= seen)
        .collect();
    let unseen = 1.0 - seen_samples.len() as Real / count.max(1) as Real;
    compare(seen_samples, unseen, model, truth, opts)
}

fn compare(
    t_samples: Vec<Point3>,
    truth_unseen: Real,
    model: &Mesh,
    truth: &Mesh,
    opts: &CompareOptions,
) -> SurfaceComparison {
    let m_samples = sample_surface(model, opts.samples);
    let to_model = MeshDistance::new(model).distances(&t_samples);
    let to_truth = MeshDistance::new(truth).distances(&m_samples);
    let a = DistanceStats::of(&to_model);
    let b = DistanceStats::of(&to_truth);
    SurfaceComparison {
        truth_to_model: a,
        model_to_truth: b,
        symmetric_rms: ((a.rms * a.rms + b.rms * b.rms) / 2.0).sqrt(),
        p95: a.p95.max(b.p95),
        truth_near: share(&to_model, |x| x <= opts.near),
        model_near: share(&to_truth, |x| x <= opts.near),
        model_far: share(&to_truth, |x| x > opts.far),
        truth_unseen,
    }
}

/// The share of `d` for which `f` holds (0 for none).
fn share(d: &[Real], f: impl Fn(Real) -> bool) -> Real {
    if d.is_empty() {
        0.0
    } else {
        d.iter().filter(|&&x| f(x)).count() as Real / d.len() as Real
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::math::Vec3;
    use crate::geom::shapes::uv_sphere;

    #[test]
    fn a_sphere_against_a_larger_one_measures_the_gap_both_ways() {
        let a = uv_sphere(Vec3::ZERO, 1.0, 96, 48);
        let b = uv_sphere(Vec3::ZERO, 1.01, 96, 48);
        let opts = CompareOptions {
            samples: 5000,
            near: 0.02,
            far: 0.005,
        };
        let c = compare_surfaces(&a, &b, &opts);
        // Facets lie inside their sphere by up to 1 - cos(π/48) ≈ 2e-3.
        assert!((c.symmetric_rms - 0.01).abs() < 2e-3, "{c:?}");
        assert_eq!(c.truth_near, 1.0);
        assert_eq!(c.model_near, 1.0);
        assert!(c.model_far > 0.99, "{c:?}");
        let same = compare_surfaces(&a, &a, &opts);
        assert!(same.symmetric_rms < 1e-9, "{same:?}");
        assert_eq!(same.model_far, 0.0);
    }

    #[test]
    fn truth_the_points_never_saw_is_left_out() {
        // Points over the upper half of a sphere; a model that is the
        // sphere's upper half alone is then exact where it was seen.
        let sphere = uv_sphere(Vec3::ZERO, 1.0, 96, 48);
        let points: Vec<Point3> = sample_surface(&sphere, 20_000)
            .into_iter()
            .filter(|p| p.y > 0.0)
            .collect();
        let upper = Mesh {
            triangles: sphere
                .triangles
                .iter()
                .copied()
                .filter(|t| t.iter().all(|&i| sphere.positions[i as usize].y >= -1e-9))
                .collect(),
            ..sphere.clone()
        };
        let opts = CompareOptions {
            samples: 20_000,
            near: 0.02,
            far: 0.05,
        };
        let all = compare_surfaces(&sphere, &upper, &opts);
        assert!(all.truth_to_model.rms > 0.3, "{all:?}");
        let seen = compare_surfaces_seen(&sphere, &upper, &points, 0.03, &opts);
        assert!(seen.truth_to_model.max < 0.05, "{seen:?}");
        assert!((seen.truth_unseen - 0.5).abs() < 0.03, "{seen:?}");
        assert_eq!(seen.model_to_truth, all.model_to_truth);
    }
}
