//! A part's axis from its loops' centres (module docs, step 8).

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::stats::median;

/// Moving average (half-width `w` in length units, by position along the
/// polyline) of centre points with radii, then resampled evenly by arc
/// length at about `step`. The end points are kept as they are.
pub(super) fn smooth_axis(pts: &[(Point3, Real)], w: Real, step: Real) -> (Vec<Point3>, Vec<Real>) {
    if pts.len() < 2 {
        return (
            pts.iter().map(|p| p.0).collect(),
            pts.iter().map(|p| p.1).collect(),
        );
    }
    // Window half-width in samples (one sample per slice, `step` apart
    // in height), shrunk symmetrically near the ends.
    let half = ((w / step.max(Real::MIN_POSITIVE)).round() as usize).min(pts.len());
    let n = pts.len();
    let window = |i: usize| {
        let h = half.min(i).min(n - 1 - i);
        (i - h, i + h)
    };
    // A running median first (a scan slice whose loop lost a piece moves
    // its centroid for a slice or two), then a moving average.
    let median: Vec<(Point3, Real)> = (0..n)
        .map(|i| {
            let (a, b) = window(i);
            // `a..=b` holds at least point `i`.
            let med = |f: &dyn Fn(&(Point3, Real)) -> Real| {
                let mut v: Vec<Real> = pts[a..=b].iter().map(f).collect();
                median(&mut v).unwrap_or(Real::NAN)
            };
            (
                Vec3::new(med(&|p| p.0.x), med(&|p| p.0.y), med(&|p| p.0.z)),
                med(&|p| p.1),
            )
        })
        .collect();
    let smoothed: Vec<(Point3, Real)> = (0..n)
        .map(|i| {
            let (a, b) = window(i);
            let m = (b - a + 1) as Real;
            let c = median[a..=b].iter().fold(Vec3::ZERO, |s, p| s + p.0) / m;
            let r = median[a..=b].iter().map(|p| p.1).sum::<Real>() / m;
            (c, r)
        })
        .collect();
    let mut len = vec![0.0];
    for k in 1..smoothed.len() {
        let d = smoothed[k].0.distance(smoothed[k - 1].0);
        len.push(len[k - 1] + d);
    }
    let total = len[len.len() - 1];
    let count = ((total / step.max(Real::MIN_POSITIVE)).ceil() as usize).clamp(2, 2000);
    let mut out_p = Vec::with_capacity(count + 1);
    let mut out_r = Vec::with_capacity(count + 1);
    let mut j = 0;
    for i in 0..=count {
        let t = total * i as Real / count as Real;
        while j + 2 < len.len() && len[j + 1] < t {
            j += 1;
        }
        let d = len[j + 1] - len[j];
        let u = if d > 0.0 {
            ((t - len[j]) / d).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out_p.push(smoothed[j].0 + (smoothed[j + 1].0 - smoothed[j].0) * u);
        out_r.push(smoothed[j].1 + (smoothed[j + 1].1 - smoothed[j].1) * u);
    }
    (out_p, out_r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::anatomy::{LandmarkKind, PartName};
    use crate::segment::PartAxis;

    #[test]
    fn axis_smoothing_keeps_a_line_and_resamples() {
        let pts: Vec<(Point3, Real)> = (0..50)
            .map(|i| (Vec3::new(0.0, 0.0, i as Real * 0.01), 0.1))
            .collect();
        let (p, r) = smooth_axis(&pts, 0.03, 0.01);
        assert_eq!(p.len(), r.len());
        assert!(p.iter().all(|q| q.x.abs() < 1e-12 && q.y.abs() < 1e-12));
        assert!((p[0].z).abs() < 1e-12 && (p[p.len() - 1].z - 0.49).abs() < 1e-12);
        let axis = PartAxis {
            name: PartName::Torso,
            points: p,
            radii: r,
            start: LandmarkKind::Crotch,
            end: LandmarkKind::Neck,
        };
        let (q, t) = axis.point_and_tangent(0.5).unwrap();
        assert!((q.z - 0.245).abs() < 1e-9 && (t.z - 1.0).abs() < 1e-9);
    }
}
