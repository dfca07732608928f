//! How well a model fits its input region by region (issue 16): the head
//! above the neck, the hands past the wrists, the feet below the ankles and
//! the rest, each measured by what a close look sees: the distance from the
//! input's surface to the model's and the share of the input's area where
//! the model's normal is more than 30° off the input's.
//!
//! Regions come from the segmentation's landmarks ([`Regions::new`], in
//! the segmentation's layer, where the report counts each region's design
//! parameters too).
//!
//! [`region_fit`] samples the input evenly by area, finds each sample's
//! nearest point on the model (its triangle's normal there) and compares
//! it with the normal of the input triangle it lies on. The same against a
//! once-subdivided copy of the input ([`crate::geom::subdivide`]) gives the
//! floor: how far a smooth surface through the input already differs.

use crate::geom::math::{Point3, Real};
use crate::geom::mesh::Mesh;
pub use crate::segment::regions::{Region, Regions};
use crate::spatial::distance::{sample_surface_on_triangles, DistanceStats, MeshDistance};

/// One region's numbers (distances in the mesh's units × `scale`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RegionFit {
    pub region: Option<Region>,
    /// Input samples in the region.
    pub samples: usize,
    /// Input → model distances.
    pub rms: Real,
    pub p95: Real,
    pub max: Real,
    /// Share of the region's samples (of its area) whose model normal is
    /// more than 30° off the input's.
    pub off_30: Real,
    /// The 90th percentile of that angle, in degrees.
    pub angle_p90: Real,
}

/// Per region (in [`Region::ALL`]'s order), how `model` fits `input` (see
/// the module doc): `samples` spread over the input, distances multiplied
/// by `scale` (to millimetres).
pub fn region_fit(
    input: &Mesh,
    model: &Mesh,
    regions: &Regions,
    samples: usize,
    scale: Real,
) -> Vec<RegionFit> {
    let (points, on, _) = sample_surface_on_triangles(input, samples);
    let tree = MeshDistance::new(model);
    let normal = |m: &Mesh, t: usize| {
        let [a, b, c] = m.triangle(t);
        (b - a).cross(c - a).normalized()
    };
    // Per sample: region, distance and angle (degrees; 180 where a normal
    // is undefined).
    let items: Vec<(Point3, u32)> = points.into_iter().zip(on).collect();
    let measured: Vec<(Region, Real, Real)> =
        crate::geom::parallel::parallel_map(&items, 256, |run| {
            run.iter()
                .map(|&(p, t)| {
                    let Some(c) = tree.closest(p) else {
                        return (regions.of(p), Real::INFINITY, 180.0);
                    };
                    let angle = match (normal(input, t as usize), normal(model, c.triangle)) {
                        (Some(a), Some(b)) => a.dot(b).clamp(-1.0, 1.0).acos().to_degrees(),
                        _ => 180.0,
                    };
                    (regions.of(p), c.distance, angle)
                })
                .collect()
        });
    Region::ALL
        .iter()
        .map(|&region| {
            let (d, a): (Vec<Real>, Vec<Real>) = measured
                .iter()
                .filter(|m| m.0 == region)
                .map(|m| (m.1, m.2))
                .unzip();
            fit_of(region, &d, &a, scale)
        })
        .collect()
}

/// The statistics of one region's distances and angles.
fn fit_of(region: Region, d: &[Real], angles: &[Real], scale: Real) -> RegionFit {
    let s = DistanceStats::of(d);
    let mut sorted = angles.to_vec();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let p90 = sorted
        .get(((sorted.len() as Real * 0.9).ceil() as usize).saturating_sub(1))
        .copied()
        .unwrap_or(0.0);
    RegionFit {
        region: Some(region),
        samples: d.len(),
        rms: s.rms * scale,
        p95: s.p95 * scale,
        max: s.max * scale,
        off_30: angles.iter().filter(|&&a| a > 30.0).count() as Real / angles.len().max(1) as Real,
        angle_p90: p90,
    }
}
