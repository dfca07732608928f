//! The up axis (module docs, steps 1-3): the principal axis of largest
//! variance, the slices across it, and its sign from the feet.

use crate::anatomy::BodyGeometry;
use crate::geom::linalg::symmetric_eigen3;
use crate::geom::math::{Point3, Real, Vec3};
use crate::segment::graph::Node;
use crate::segment::slices::AxisSlicer;
use crate::segment::{SegmentError, SegmentOptions};

/// The principal axis of largest variance, if it is distinct. Meshes are
/// weighted by surface area (uniform density over the triangles, whose
/// second moment is `A [(aaᵀ + bbᵀ + ccᵀ)/12 + ¾ mmᵀ]` with `m` the
/// centroid), so dense vertices (a face, the poles of a UV sphere) do not
/// tilt it; clouds are taken point by point.
pub(super) fn principal_axis(body: BodyGeometry<'_>, needed: Real) -> Result<Vec3, SegmentError> {
    let mut w = 0.0;
    let mut first = Vec3::ZERO;
    let mut second = [[0.0; 3]; 3];
    let mut add = |p: Vec3, weight: Real, outer: &[[Real; 3]; 3]| {
        w += weight;
        first += p * weight;
        for i in 0..3 {
            for j in 0..3 {
                second[i][j] += weight * outer[i][j];
            }
        }
    };
    let outer = |v: Vec3| {
        let a = v.to_array();
        let mut o = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                o[i][j] = a[i] * a[j];
            }
        }
        o
    };
    match body {
        BodyGeometry::Mesh(m) if !m.triangles.is_empty() => {
            for t in 0..m.triangles.len() {
                let [a, b, c] = m.triangle(t);
                let area = 0.5 * (b - a).cross(c - a).norm();
                let centroid = (a + b + c) / 3.0;
                let (oa, ob, oc, om) = (outer(a), outer(b), outer(c), outer(centroid));
                let mut o = [[0.0; 3]; 3];
                for i in 0..3 {
                    for j in 0..3 {
                        o[i][j] = (oa[i][j] + ob[i][j] + oc[i][j]) / 12.0 + 0.75 * om[i][j];
                    }
                }
                add(centroid, area, &o);
            }
        }
        _ => {
            for &p in body.positions() {
                add(p, 1.0, &outer(p));
            }
        }
    }
    if w.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(SegmentError::NoUpAxis { ratio: 1.0, needed });
    }
    let mean = first / w;
    let om = outer(mean);
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = second[i][j] / w - om[i][j];
        }
    }
    let (vals, vecs) = symmetric_eigen3(c);
    let ratio = if vals[1] > 0.0 {
        vals[0] / vals[1]
    } else {
        Real::INFINITY
    };
    if ratio.partial_cmp(&needed) == Some(std::cmp::Ordering::Less) || ratio.is_nan() {
        return Err(SegmentError::NoUpAxis { ratio, needed });
    }
    vecs[0]
        .normalized()
        .ok_or(SegmentError::NoUpAxis { ratio, needed })
}

/// The body's slices across its axis, bottom to top along it.
pub(super) struct Slices {
    /// Per slice: its offset along the axis and its loops (small loops
    /// dropped).
    pub(super) raw: Vec<(Real, Vec<Node>)>,
    /// The sliced range along the axis.
    pub(super) min: Real,
    pub(super) max: Real,
    /// Plane coordinates shared by all slices (any orthonormal pair ⊥ axis).
    pub(super) e1: Vec3,
    pub(super) e2: Vec3,
}

/// Cuts the body into [`SegmentOptions::slices`] slices across `axis`
/// (step 2 of the module docs), over the range that holds loops.
pub(super) fn slice_along_axis(
    slicer: &AxisSlicer<'_>,
    positions: &[Point3],
    axis: Vec3,
    opts: &SegmentOptions,
) -> Result<Slices, SegmentError> {
    let (mut min, mut max) = slicer.range();
    let n = opts.slices;
    // Plane coordinates shared by all slices (any orthonormal pair ⊥ axis).
    let (e1, e2) = {
        let e1 = axis.any_perpendicular();
        (e1, axis.cross(e1))
    };
    // Slice, drop small loops; then, if two or more slices at an end hold
    // nothing (stray scan points far beyond the body), slice again over
    // the range that holds loops, so that H is the body's height.
    let mut raw: Vec<(Real, Vec<Node>)>;
    let mut pass = 0;
    loop {
        if (max - min).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(SegmentError::NotAStandingBody {
                what: "a body",
                why: "the input has no extent along the up axis".into(),
            });
        }
        let step = (max - min) / n as Real;
        // Independent slices, split over the cores (in order).
        let ks: Vec<usize> = (0..n).collect();
        raw = crate::geom::parallel::parallel_map(&ks, 32, |run| {
            run.iter()
                .map(|&k| {
                    let off = min + (k as Real + 0.5) * step;
                    (off, slicer.nodes_at(off, e1, e2))
                })
                .collect()
        });
        let largest = raw
            .iter()
            .flat_map(|(_, l)| l.iter().map(|l| l.area))
            .fold(0.0, Real::max);
        if largest.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(SegmentError::NotAStandingBody {
                what: "a body",
                why: "no slice has a closed loop".into(),
            });
        }
        // The reference area is the largest loop, but at most twice the
        // 95th percentile of the slices' largest loops: a horizontal slice
        // along arms held out sideways is several times the trunk's area,
        // and against it a scan's ankles fall out of the graph; a standing
        // body's largest loop (hips, chest) is well within twice it.
        let mut per_slice: Vec<Real> = raw
            .iter()
            .filter_map(|(_, l)| l.iter().map(|l| l.area).reduce(Real::max))
            .collect();
        per_slice.sort_by(Real::total_cmp);
        let p95 = per_slice[(per_slice.len() * 19 / 20).min(per_slice.len() - 1)];
        let reference = largest.min(2.0 * p95);
        for (_, loops) in &mut raw {
            loops.retain(|l| l.area >= opts.min_loop_area * reference);
        }
        let first = raw.iter().position(|r| !r.1.is_empty()).unwrap_or(0);
        let last = raw.iter().rposition(|r| !r.1.is_empty()).unwrap_or(n - 1);
        if pass == 1 || (first < 2 && last + 2 >= n) {
            break;
        }
        pass += 1;
        // The extreme points within a slice of the occupied range.
        let (lo, hi) = (
            min + first as Real * step - step,
            min + (last + 1) as Real * step + step,
        );
        let (a, b) = positions
            .iter()
            .map(|p| p.dot(axis))
            .filter(|h| (lo..=hi).contains(h))
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), h| {
                (a.min(h), b.max(h))
            });
        min = a;
        max = b;
    }
    Ok(Slices {
        raw,
        min,
        max,
        e1,
        e2,
    })
}

/// The sign of a principal axis (step 3 of the module docs): `axis` when
/// the feet are at its low end, else `−axis` with `raw` reversed (bottom
/// to top along the result).
pub(super) fn orient_up(
    raw: &mut [(Real, Vec<Node>)],
    axis: Vec3,
    n: usize,
) -> Result<Vec3, SegmentError> {
    let share = |range: std::ops::Range<Real>| {
        let (mut multi, mut total) = (0usize, 0usize);
        for k in 0..n {
            let f = (k as Real + 0.5) / n as Real;
            if range.contains(&f) && !raw[k].1.is_empty() {
                total += 1;
                multi += usize::from(raw[k].1.len() >= 2);
            }
        }
        multi as Real / total.max(1) as Real
    };
    // The slices' area centroid as a fraction of the extent: the trunk,
    // whose sections are the largest, lies above the long thin legs in
    // every standing pose, raised arms included (0.57-0.60 on the
    // development bodies, arms down or raised), so the centroid lies
    // nearer the head.
    let centroid = {
        let (mut m, mut mh) = (0.0, 0.0);
        for (k, (_, loops)) in raw.iter().enumerate() {
            let a: Real = loops.iter().map(|l| l.area).sum();
            m += a;
            mh += a * (k as Real + 0.5) / n as Real;
        }
        mh / m.max(Real::MIN_POSITIVE)
    };
    let low = share(0.02..0.09);
    let high = share(0.91..0.98);
    // Both ends branch (arms raised above the head): the feet are the
    // end farther from the area centroid.
    let both = low >= 0.5 && high >= 0.5 && (low - high).abs() < 0.5;
    if low >= high + 0.5 || (both && centroid >= 0.53) {
        Ok(axis)
    } else if high >= low + 0.5 || (both && centroid <= 0.47) {
        raw.reverse();
        Ok(-axis)
    } else {
        Err(SegmentError::NotAStandingBody {
            what: "two feet at either end of the longest axis",
            why: format!(
                "slices with two or more loops: {:.0} % near one end, {:.0} % near the other, the volume centroid at {:.2} of the extent; pass the up axis",
                100.0 * low,
                100.0 * high,
                centroid
            ),
        })
    }
}
