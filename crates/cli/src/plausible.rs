//! Is the input one human body in the given unit? Checked before a body is
//! reconstructed or measured, so that a wrong unit or a file of two people
//! is exit 2 with what was measured, never a silently wrong model (a body in
//! millimetres read as metres gave a 1 730 m stature and exit 0).

use crate::exit::bad;
use anyhow::Result;
use trigbody_core::internals::geom::union_find::root;
use trigbody_core::Units;
use trigbody_core::{Aabb, Point3, Real};
use trigbody_io::Geometry;

/// The heights (m) a human body may have, after its unit: the longest side
/// of its bounding box, so that a lying body counts too.
pub const HUMAN_EXTENT_M: (Real, Real) = (0.4, 2.6);

/// A second connected piece at least this share of the largest one's extent
/// (and of human size itself) is a second body.
const SECOND_BODY_SHARE: Real = 0.5;

/// Both checks below (two people side by side are wider than any one); `flag` is the option that sets the unit (`--units`).
pub fn check_body_input(name: &str, geometry: &Geometry, units: Units, flag: &str) -> Result<()> {
    check_one_body(name, geometry, units)?;
    check_extent(name, geometry.positions(), units, flag)
}

/// Exit 2 unless the input's extent lies in [`HUMAN_EXTENT_M`] in `units`;
/// the message names the extent and the units that would fit.
pub fn check_extent(name: &str, positions: &[Point3], units: Units, flag: &str) -> Result<()> {
    let Some(extent) = robust_extent(positions) else {
        return Ok(());
    };
    let (lo, hi) = HUMAN_EXTENT_M;
    let metres = |u: Units| extent * u.to_mm() / 1000.0;
    if (lo..=hi).contains(&metres(units)) {
        return Ok(());
    }
    let fits: Vec<String> = [Units::Metres, Units::Centimetres, Units::Millimetres]
        .into_iter()
        .filter(|u| (lo..=hi).contains(&metres(*u)))
        .map(|u| format!("with {flag} {} it is {:.2} m tall", u.symbol(), metres(u)))
        .collect();
    let hint = if fits.is_empty() {
        "no unit (m, cm, mm) makes it a human size; is it a body at all?".to_string()
    } else {
        fits.join("; ")
    };
    Err(bad(format!(
        "{name}: the input measures {extent:.4e} along its longest side (1st to 99th \
         percentile of its points), which in {flag} {} is \
         {:.4e} m: not a human body's height ({lo}-{hi} m); {hint}",
        units.symbol(),
        metres(units)
    )))
}

/// The longest side of the box from the 1st to the 99th percentile of the
/// points along each axis: stray points of a scan (1 % of body_011's, 0.6 m
/// beyond the body) do not count.
fn robust_extent(positions: &[Point3]) -> Option<Real> {
    trigbody_core::internals::geom::mesh::central_extent(positions, 100)
}

fn longest_side(b: &Aabb) -> Real {
    let d = b.max - b.min;
    d.x.max(d.y).max(d.z)
}

/// Exit 2 when the input holds two or more separate pieces each of human
/// size (two people in one file); small pieces (eyes, stray points) and a
/// piece inside another (a mouth, an inner layer) do not count.
pub fn check_one_body(name: &str, geometry: &Geometry, units: Units) -> Result<()> {
    let (points, labels) = match geometry {
        Geometry::Mesh(m) => (&m.positions[..], mesh_components(m)),
        Geometry::Points(c) => (&c.positions[..], cloud_components(&c.positions)),
    };
    let mut boxes = clusters(points, &labels);
    // Largest first; equal sizes in a fixed order (the groups come out of
    // a hash map), so the first box, which the others are held against,
    // does not change from run to run.
    boxes.sort_by(|a, b| {
        let corner = |x: &Aabb| [x.min.x, x.min.y, x.min.z];
        longest_side(b).total_cmp(&longest_side(a)).then_with(|| {
            corner(a)
                .partial_cmp(&corner(b))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
    });
    let Some(first) = boxes.first().copied() else {
        return Ok(());
    };
    let big = longest_side(&first);
    let to_m = units.to_mm() / 1000.0;
    let bodies: Vec<Aabb> = boxes
        .into_iter()
        .enumerate()
        .filter(|(i, b)| {
            let e = longest_side(b);
            e >= SECOND_BODY_SHARE * big
                && e * to_m >= HUMAN_EXTENT_M.0
                && (*i == 0 || !mostly_inside(b, &first))
        })
        .map(|(_, b)| b)
        .collect();
    if bodies.len() < 2 {
        return Ok(());
    }
    let sizes: Vec<String> = bodies
        .iter()
        .map(|b| format!("{:.2} m", longest_side(b) * to_m))
        .collect();
    Err(bad(format!(
        "{name}: the input holds {} separate bodies (connected pieces {} across); give one \
         body per file",
        bodies.len(),
        sizes.join(", ")
    )))
}

/// The pieces of one body come close (a tessellated model's parts are
/// separate meshes that cross; a scan's arm may be cut off at the shoulder):
/// pieces larger than 2 % of the largest with points within about 2 % of
/// its extent of each other (in the same or neighbouring cells of a grid of
/// 1 %) are merged, and each group's box is returned. Two people side by
/// side are apart, though their boxes overlap where arms held out reach
/// past the other's side.
fn clusters(points: &[Point3], label: &[usize]) -> Vec<Aabb> {
    let mut pieces = component_boxes(points, label);
    let big = pieces.values().map(longest_side).fold(0.0, Real::max);
    if !(big > 0.0) {
        // Only single points (a cloud too sparse to join): nothing to merge,
        // and no grid to merge them on.
        return pieces.into_values().collect();
    }
    pieces.retain(|_, b| longest_side(b) >= 0.02 * big);
    if pieces.len() > 1000 {
        // A soup of large unconnected faces: no pieces to tell apart.
        return Vec::new();
    }
    let ids: Vec<usize> = pieces.keys().copied().collect();
    let index: std::collections::HashMap<usize, usize> =
        ids.iter().enumerate().map(|(k, &l)| (l, k)).collect();
    let mut parent: Vec<u32> = (0..ids.len() as u32).collect();
    let cell = 0.01 * big;
    let key = |p: &Point3| [p.x, p.y, p.z].map(|v| (v / cell).floor() as i64);
    let mut cells: std::collections::HashMap<[i64; 3], Vec<u32>> = Default::default();
    for (p, l) in points.iter().zip(label) {
        if let (Some(&k), true) = (index.get(l), p.is_finite()) {
            let k = k as u32;
            let here = cells.entry(key(p)).or_default();
            if !here.contains(&k) {
                here.push(k);
            }
        }
    }
    for (c, here) in &cells {
        for d in 0..27i64 {
            let n = [c[0] + d % 3 - 1, c[1] + (d / 3) % 3 - 1, c[2] + d / 9 - 1];
            let Some(there) = cells.get(&n) else {
                continue;
            };
            for &a in here {
                for &b in there {
                    let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                    parent[rb as usize] = ra;
                }
            }
        }
    }
    let mut groups: std::collections::HashMap<u32, Aabb> = Default::default();
    for (k, l) in ids.iter().enumerate() {
        let b = pieces[l];
        groups
            .entry(root(&mut parent, k as u32))
            .and_modify(|g| {
                g.min = g.min.min(b.min);
                g.max = g.max.max(b.max);
            })
            .or_insert(b);
    }
    groups.into_values().collect()
}

/// Whether at least half of `b`'s box lies inside `outer`'s.
fn mostly_inside(b: &Aabb, outer: &Aabb) -> bool {
    let overlap = |lo: Real, hi: Real| (hi - lo).max(0.0);
    let lo = b.min.max(outer.min);
    let hi = b.max.min(outer.max);
    let vol = |d: trigbody_core::Vec3| d.x.max(1e-300) * d.y.max(1e-300) * d.z.max(1e-300);
    let shared = overlap(lo.x, hi.x) * overlap(lo.y, hi.y) * overlap(lo.z, hi.z);
    shared >= 0.5 * vol(b.max - b.min)
}

/// The component of every vertex: vertices joined by triangles.
fn mesh_components(m: &trigbody_core::Mesh) -> Vec<usize> {
    let mut parent: Vec<u32> = (0..m.positions.len() as u32).collect();
    for t in &m.triangles {
        let a = root(&mut parent, t[0]);
        for &v in &t[1..] {
            let b = root(&mut parent, v);
            parent[b as usize] = a;
        }
    }
    (0..parent.len() as u32)
        .map(|i| root(&mut parent, i) as usize)
        .collect()
}

/// The bounding box of every component (by label) that has points.
fn component_boxes(points: &[Point3], label: &[usize]) -> std::collections::HashMap<usize, Aabb> {
    let mut boxes: std::collections::HashMap<usize, Aabb> = Default::default();
    for (p, &l) in points.iter().zip(label) {
        boxes
            .entry(l)
            .and_modify(|b| {
                b.min = b.min.min(*p);
                b.max = b.max.max(*p);
            })
            .or_insert(Aabb { min: *p, max: *p });
    }
    boxes
}

/// A cloud's pieces: points in touching cells of a grid 1/60 of its extent
/// (about 3 cm on a standing body: a gap wider than that separates).
fn cloud_components(points: &[Point3]) -> Vec<usize> {
    let Some(b) = Aabb::from_points(points) else {
        return vec![0; points.len()];
    };
    let cell = (longest_side(&b) / 60.0).max(Real::MIN_POSITIVE);
    trigbody_core::internals::spatial::cloud_clean::voxel_components(points, b.min, cell)
        .into_iter()
        .map(|c| c as usize)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use trigbody_core::{PointCloud, Vec3};

    fn column(x: Real, height: Real) -> Vec<Point3> {
        (0..400)
            .map(|i| {
                Vec3::new(
                    x + 0.1 * (i % 4) as Real / 4.0,
                    height * i as Real / 399.0,
                    0.0,
                )
            })
            .collect()
    }

    #[test]
    fn a_millimetre_body_read_as_metres_is_refused_with_the_unit_that_fits() {
        let mm: Vec<Point3> = column(0.0, 1730.0);
        let e = check_extent("b.obj", &mm, Units::Metres, "--units").unwrap_err();
        let e = e.to_string();
        assert!(e.contains("with --units mm it is 1.70 m tall"), "{e}");
        check_extent("b.obj", &mm, Units::Millimetres, "--units").unwrap();
        let huge: Vec<Point3> = column(0.0, 1.73e20);
        let e = check_extent("b.obj", &huge, Units::Metres, "--units").unwrap_err();
        assert!(e.to_string().contains("no unit"), "{e}");
    }

    #[test]
    fn overlapping_pieces_are_one_body() {
        // A torso with two separate legs overlapping its box, as a
        // tessellated model's parts are.
        let mut pieces = column(0.0, 1.7);
        let leg: Vec<Point3> = column(0.05, 0.9)
            .into_iter()
            .map(|p| p + Vec3::new(0.0, -0.1, 0.0))
            .collect();
        pieces.extend(leg);
        let cloud = Geometry::Points(PointCloud {
            positions: pieces,
            normals: None,
        });
        check_one_body("one.ply", &cloud, Units::Metres).unwrap();
    }

    /// Points every 5 mm from `a` to `b`.
    fn line(a: Vec3, b: Vec3) -> Vec<Point3> {
        let n = ((b - a).norm() / 0.005).ceil() as usize;
        (0..=n)
            .map(|i| a + (b - a) * (i as Real / n as Real))
            .collect()
    }

    /// Two people whose arms held out reach past each other's side, 10 cm
    /// apart (one on a step): their boxes overlap, their points do not
    /// come near. Merged by their boxes, they were reconstructed as one
    /// body at 337 mm RMS, exit 0.
    #[test]
    fn people_whose_boxes_overlap_are_still_two() {
        let v = Vec3::new;
        let mut two = line(v(0.0, 0.0, 0.0), v(0.0, 1.7, 0.0));
        two.extend(line(v(0.0, 1.4, 0.0), v(0.9, 1.4, 0.0)));
        two.extend(line(v(1.0, 0.3, 0.0), v(1.0, 2.0, 0.0)));
        two.extend(line(v(1.0, 1.0, 0.0), v(0.1, 1.0, 0.0)));
        let cloud = Geometry::Points(PointCloud {
            positions: two,
            normals: None,
        });
        let e = check_one_body("two.ply", &cloud, Units::Metres).unwrap_err();
        assert!(e.to_string().contains("2 separate bodies"), "{e}");
    }

    /// A sheet of points farther apart than a cloud's pieces join: every
    /// point a piece of no extent, none of them a body, on every run (the
    /// merging grid once took its cell from a zero extent and put every
    /// point in one of two cells; which pieces came first in a hash map then
    /// decided between "2 separate bodies" and no complaint).
    #[test]
    fn a_sparse_sheet_is_not_two_bodies() {
        let sheet: Vec<Point3> = (0..900)
            .map(|i| Vec3::new((i % 30) as Real / 29.0, (i / 30) as Real / 29.0, 0.0))
            .collect();
        let cloud = Geometry::Points(PointCloud {
            positions: sheet,
            normals: None,
        });
        for _ in 0..20 {
            check_one_body("sheet.xyz", &cloud, Units::Metres).unwrap();
        }
    }

    #[test]
    fn two_people_side_by_side_are_two_bodies_and_one_is_one() {
        let mut two = column(0.0, 1.7);
        two.extend(column(1.0, 1.6));
        let cloud = Geometry::Points(PointCloud {
            positions: two,
            normals: None,
        });
        let e = check_one_body("two.ply", &cloud, Units::Metres).unwrap_err();
        assert!(e.to_string().contains("2 separate bodies"), "{e}");
        let mut one = column(0.0, 1.7);
        one.extend(column(1.0, 0.1)); // a small stray piece
        let cloud = Geometry::Points(PointCloud {
            positions: one,
            normals: None,
        });
        check_one_body("one.ply", &cloud, Units::Metres).unwrap();
    }
}
