//! Morton (Z-order) sorting of points: the traversal order of the
//! spatial structures, which keeps near points near in memory.

use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::parallel::{par_for_each_mut, parallel_map};

/// The indices of `centres` in Morton order, and their codes (see
/// the triangle hierarchy's build): 10 bits per axis of the centres' bounding box,
/// interleaved; sorted by an LSD radix sort (stable: equal codes keep
/// their index order).
pub(crate) fn morton_sort(centres: &[Point3]) -> (Vec<u32>, Vec<u32>) {
    morton_sort_by(centres.len(), |i| centres[i])
}

/// [`morton_sort`] of the points `centre(0..n)` (each asked twice, never
/// stored).
pub(crate) fn morton_sort_by(
    n: usize,
    centre: impl Fn(usize) -> Point3 + Sync,
) -> (Vec<u32>, Vec<u32>) {
    let inf = Real::INFINITY;
    // The bounds and the codes over the cores, in runs of the indices.
    // (Runs' bounds combined in another order than one pass's can differ
    // only in the sign of a zero bound, which gives the same codes: `v −
    // (±0)` and `h − (±0)` are equal but for `v = −0`, which quantizes to
    // 0 either way.)
    let runs: Vec<std::ops::Range<usize>> = (0..n)
        .step_by(1 << 14)
        .map(|s| s..(s + (1 << 14)).min(n))
        .collect();
    let bounds: Vec<(Vec3, Vec3)> = parallel_map(&runs, 1, |rs| {
        rs.iter()
            .map(|r| {
                let (mut lo, mut hi) = (Vec3::new(inf, inf, inf), Vec3::new(-inf, -inf, -inf));
                for i in r.clone() {
                    let c = centre(i);
                    if c.is_finite() {
                        lo = lo.min(c);
                        hi = hi.max(c);
                    }
                }
                (lo, hi)
            })
            .collect()
    });
    let (mut lo, mut hi) = (Vec3::new(inf, inf, inf), Vec3::new(-inf, -inf, -inf));
    for (l, h) in bounds {
        lo = lo.min(l);
        hi = hi.max(h);
    }
    let scale = |l: Real, h: Real| if h > l { 1023.0 / (h - l) } else { 0.0 };
    let s = Vec3::new(scale(lo.x, hi.x), scale(lo.y, hi.y), scale(lo.z, hi.z));
    // Spreads the 10 low bits of x to every third bit.
    let spread = |x: u32| {
        let mut x = x & 0x3ff;
        x = (x | (x << 16)) & 0x0300_00ff;
        x = (x | (x << 8)) & 0x0300_f00f;
        x = (x | (x << 4)) & 0x030c_30c3;
        (x | (x << 2)) & 0x0924_9249
    };
    let q = |v: Real, l: Real, s: Real| {
        let x = (v - l) * s;
        if x.is_finite() {
            x.clamp(0.0, 1023.0) as u32
        } else {
            0
        }
    };
    let mut codes = vec![0u32; n];
    par_for_each_mut(&mut codes, 1 << 14, |i, code| {
        let c = centre(i);
        *code = (spread(q(c.x, lo.x, s.x)) << 2)
            | (spread(q(c.y, lo.y, s.y)) << 1)
            | spread(q(c.z, lo.z, s.z));
    });
    let mut keyed: Vec<(u32, u32)> = codes
        .iter()
        .enumerate()
        .map(|(i, &c)| (c, i as u32))
        .collect();
    drop(codes);
    let mut scratch = vec![(0u32, 0u32); keyed.len()];
    for shift in [0u32, 11, 22] {
        let mut count = [0usize; 2049];
        for k in &keyed {
            count[((k.0 >> shift) & 0x7ff) as usize + 1] += 1;
        }
        for b in 0..2048 {
            count[b + 1] += count[b];
        }
        for k in &keyed {
            let b = ((k.0 >> shift) & 0x7ff) as usize;
            scratch[count[b]] = *k;
            count[b] += 1;
        }
        std::mem::swap(&mut keyed, &mut scratch);
    }
    keyed.into_iter().map(|(c, i)| (i, c)).unzip()
}
