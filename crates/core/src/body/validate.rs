//! Is the input one human body, and in which unit? The first step of
//! [`reconstruct`](super::reconstruct) and of measuring an input directly,
//! so that every door (the CLI, `batch`, Python) refuses the same inputs
//! with the same message: a body in millimetres read as metres (a 1 730 m
//! stature), two people in one file, a non-finite coordinate.

use super::Units;
use crate::anatomy::BodyGeometry;
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{central_extent, Aabb, Mesh, MeshError};
use crate::geom::union_find::root;
use crate::spatial::cloud_clean::voxel_components;
use std::fmt;

/// The heights (m) a human body may have, after its unit: the longest side
/// of its bounding box (1st to 99th percentile of its points), so that a
/// lying body counts too.
pub const HUMAN_EXTENT_M: (Real, Real) = (0.4, 2.6);

/// A second connected piece at least this share of the largest one's extent
/// (and of human size itself) is a second body.
const SECOND_BODY_SHARE: Real = 0.5;

/// The units tried when the unit is inferred, in the order named.
const UNITS: [Units; 3] = [Units::Metres, Units::Centimetres, Units::Millimetres];

/// Why an input is not one human body in its unit.
#[derive(Debug, PartialEq)]
pub enum InputError {
    /// Malformed geometry: a non-finite coordinate, an index out of range,
    /// no points.
    Invalid(MeshError),
    /// The input's extent in the given unit is not a human height; `fits`
    /// holds each unit that would make it one and the height it gives (m).
    NotHumanSize {
        extent: Real,
        units: Units,
        fits: Vec<(Units, Real)>,
    },
    /// The unit was to be inferred and no unit, or more than one, gives a
    /// human height; `fits` holds those that do.
    UnitsNotInferred {
        extent: Real,
        fits: Vec<(Units, Real)>,
    },
    /// Two or more separate pieces of human size: their longest sides (m).
    SeveralBodies { sizes_m: Vec<Real> },
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (lo, hi) = HUMAN_EXTENT_M;
        let measures = |f: &mut fmt::Formatter<'_>, extent: &Real| {
            write!(
                f,
                "the input measures {extent:.4e} along its longest side (1st to 99th \
                 percentile of its points)"
            )
        };
        let tall = |fits: &[(Units, Real)]| {
            fits.iter()
                .map(|(u, m)| format!("in {} it is {m:.2} m tall", u.symbol()))
                .collect::<Vec<_>>()
                .join("; ")
        };
        match self {
            InputError::Invalid(e) => write!(f, "{e}"),
            InputError::NotHumanSize {
                extent,
                units,
                fits,
            } => {
                measures(f, extent)?;
                write!(
                    f,
                    ", which in {} is {:.4e} m: not a human body's height ({lo}-{hi} m); ",
                    units.symbol(),
                    extent * units.to_mm() / 1000.0
                )?;
                if fits.is_empty() {
                    write!(
                        f,
                        "no unit (m, cm, mm) makes it a human size; is it a body at all?"
                    )
                } else {
                    write!(f, "{}: give that unit, or auto to infer it", tall(fits))
                }
            }
            InputError::UnitsNotInferred { extent, fits } if fits.is_empty() => {
                measures(f, extent)?;
                let all: Vec<String> = UNITS
                    .iter()
                    .map(|u| format!("{:.4e} m in {}", extent * u.to_mm() / 1000.0, u.symbol()))
                    .collect();
                write!(
                    f,
                    ": no unit (m, cm, mm) makes it a human size ({lo}-{hi} m; it is {}); is \
                     it a body at all?",
                    all.join(", ")
                )
            }
            InputError::UnitsNotInferred { extent, fits } => {
                measures(f, extent)?;
                write!(
                    f,
                    ": its unit cannot be inferred, more than one gives a human height ({}); \
                     give the unit",
                    tall(fits)
                )
            }
            InputError::SeveralBodies { sizes_m } => {
                let sizes: Vec<String> = sizes_m.iter().map(|s| format!("{s:.2} m")).collect();
                write!(
                    f,
                    "the input holds {} separate bodies (connected pieces {} across); give one \
                     body per file",
                    sizes_m.len(),
                    sizes.join(", ")
                )
            }
        }
    }
}

impl std::error::Error for InputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            InputError::Invalid(e) => Some(e),
            _ => None,
        }
    }
}

impl From<MeshError> for InputError {
    fn from(e: MeshError) -> Self {
        InputError::Invalid(e)
    }
}

/// Checks that `body` is well formed and one human body, in `units` or,
/// with `None`, in the one unit (m, cm, mm) that makes it a human height,
/// and returns that unit.
pub fn validate_input(body: BodyGeometry<'_>, units: Option<Units>) -> Result<Units, InputError> {
    let (points, pieces) = match body {
        BodyGeometry::Mesh(m) => {
            m.validate()?;
            let labels = mesh_components(m);
            let pieces = if labels.windows(2).all(|w| w[0] == w[1]) {
                // One connected piece (most meshes): one box, nothing to merge.
                Aabb::from_points(&m.positions).into_iter().collect()
            } else {
                let (samples, labels) = surface_samples(m, &labels);
                clusters(&samples, &labels)
            };
            (&m.positions[..], pieces)
        }
        BodyGeometry::Cloud(c) => {
            c.validate()?;
            (
                &c.positions[..],
                clusters(&c.positions, &cloud_components(&c.positions)),
            )
        }
    };
    let pieces = largest_first(pieces);
    let extent = robust_extent(points);
    let units = match units {
        Some(u) => u,
        // Two people side by side are too wide for any unit: the unit is
        // then the largest piece's, and the second body is what is told.
        None => infer_units(extent).or_else(|e| {
            let largest = pieces.first().map(longest_side).unwrap_or(0.0);
            infer_units(largest).map_err(|_| e)
        })?,
    };
    check_one_body(&pieces, units)?;
    check_extent(extent, units)?;
    Ok(units)
}

/// The one unit under which `extent` is a human height.
fn infer_units(extent: Real) -> Result<Units, InputError> {
    let fits = fitting_units(extent);
    match fits[..] {
        [(u, _)] => Ok(u),
        _ => Err(InputError::UnitsNotInferred { extent, fits }),
    }
}

/// The units under which `extent` is a human height, each with that height.
fn fitting_units(extent: Real) -> Vec<(Units, Real)> {
    let (lo, hi) = HUMAN_EXTENT_M;
    UNITS
        .iter()
        .map(|&u| (u, extent * u.to_mm() / 1000.0))
        .filter(|(_, m)| (lo..=hi).contains(m))
        .collect()
}

/// An error unless `extent` in `units` is a human height.
fn check_extent(extent: Real, units: Units) -> Result<(), InputError> {
    let (lo, hi) = HUMAN_EXTENT_M;
    if (lo..=hi).contains(&(extent * units.to_mm() / 1000.0)) {
        return Ok(());
    }
    Err(InputError::NotHumanSize {
        extent,
        units,
        fits: fitting_units(extent),
    })
}

/// The longest side of the box from the 1st to the 99th percentile of the
/// points along each axis: stray points of a scan (1 % of body_011's, 0.6 m
/// beyond the body) do not count.
fn robust_extent(positions: &[Point3]) -> Real {
    central_extent(positions, 100).unwrap_or(0.0)
}

fn longest_side(b: &Aabb) -> Real {
    let d = b.max - b.min;
    d.x.max(d.y).max(d.z)
}

/// Largest first; equal sizes in a fixed order (the groups come out of a
/// hash map), so the first box, which the others are held against, does
/// not change from run to run.
fn largest_first(mut boxes: Vec<Aabb>) -> Vec<Aabb> {
    boxes.sort_by(|a, b| {
        let corner = |x: &Aabb| [x.min.x, x.min.y, x.min.z];
        longest_side(b).total_cmp(&longest_side(a)).then_with(|| {
            corner(a)
                .partial_cmp(&corner(b))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
    });
    boxes
}

/// An error when the pieces (largest first) hold two or more each of human
/// size (two people in one file); small pieces (eyes, stray points) and a
/// piece inside another (a mouth, an inner layer) do not count.
fn check_one_body(pieces: &[Aabb], units: Units) -> Result<(), InputError> {
    let Some(first) = pieces.first() else {
        return Ok(());
    };
    let big = longest_side(first);
    let to_m = units.to_mm() / 1000.0;
    let sizes_m: Vec<Real> = pieces
        .iter()
        .enumerate()
        .filter(|(i, b)| {
            let e = longest_side(b);
            e >= SECOND_BODY_SHARE * big
                && e * to_m >= HUMAN_EXTENT_M.0
                && (*i == 0 || !mostly_inside(b, first))
        })
        .map(|(_, b)| longest_side(b) * to_m)
        .collect();
    if sizes_m.len() < 2 {
        return Ok(());
    }
    Err(InputError::SeveralBodies { sizes_m })
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
    let vol = |d: Vec3| d.x.max(1e-300) * d.y.max(1e-300) * d.z.max(1e-300);
    let shared = overlap(lo.x, hi.x) * overlap(lo.y, hi.y) * overlap(lo.z, hi.z);
    shared >= 0.5 * vol(b.max - b.min)
}

/// The component of every vertex: vertices joined by triangles.
fn mesh_components(m: &Mesh) -> Vec<usize> {
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

/// Most points [`surface_samples`] adds: a mesh of huge triangles is
/// sampled more coarsely rather than without end.
const MAX_SURFACE_SAMPLES: usize = 2_000_000;

/// A mesh's vertices and, on every triangle longer than the grid
/// [`clusters`] merges pieces on, points at most that far apart, each with
/// its vertex's component: a coarse model's separate parts (a leg's
/// cylinder ending inside the torso's, rings 7 cm apart) come close where
/// their surfaces do, not only where their vertices happen to.
fn surface_samples(m: &Mesh, label: &[usize]) -> (Vec<Point3>, Vec<usize>) {
    let mut points = m.positions.clone();
    let mut labels = label.to_vec();
    let Some(b) = Aabb::from_points(&m.positions) else {
        return (points, labels);
    };
    let longest = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        (b - a).norm().max((c - b).norm()).max((a - c).norm())
    };
    // Points within a cell of each other fall in the same or neighbouring
    // cells, which `clusters` joins: a cell's spacing is enough.
    let mut spacing = 0.01 * longest_side(&b);
    if !(spacing > 0.0) {
        return (points, labels);
    }
    let count = |spacing: Real| -> usize {
        m.triangles
            .iter()
            .map(|t| {
                let n = (longest(t) / spacing).ceil() as usize;
                if n > 1 {
                    (n + 1) * (n + 2) / 2
                } else {
                    0
                }
            })
            .sum()
    };
    while count(spacing) > MAX_SURFACE_SAMPLES {
        spacing *= 2.0;
    }
    for t in &m.triangles {
        let n = (longest(t) / spacing).ceil() as usize;
        if n <= 1 {
            continue;
        }
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as Real / n as Real, j as Real / n as Real);
                points.push(a + (b - a) * u + (c - a) * v);
                labels.push(label[t[0] as usize]);
            }
        }
    }
    (points, labels)
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
    voxel_components(points, b.min, cell)
        .into_iter()
        .map(|c| c as usize)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::mesh::PointCloud;

    fn column(x: Real, height: Real) -> Vec<Point3> {
        (0..400)
            .map(|i| {
                Vec3::new(
                    x + 0.1 * height / 1.7 * (i % 4) as Real / 4.0,
                    height * i as Real / 399.0,
                    0.0,
                )
            })
            .collect()
    }

    fn check(points: Vec<Point3>, units: Option<Units>) -> Result<Units, InputError> {
        let cloud = PointCloud {
            positions: points,
            normals: None,
        };
        validate_input(BodyGeometry::Cloud(&cloud), units)
    }

    #[test]
    fn a_millimetre_body_read_as_metres_is_refused_with_the_unit_that_fits() {
        let e = check(column(0.0, 1730.0), Some(Units::Metres)).unwrap_err();
        assert!(matches!(e, InputError::NotHumanSize { .. }), "{e}");
        assert!(e.to_string().contains("in mm it is 1.70 m tall"), "{e}");
        assert_eq!(
            check(column(0.0, 1730.0), Some(Units::Millimetres)),
            Ok(Units::Millimetres)
        );
        let e = check(column(0.0, 1.73e20), Some(Units::Metres)).unwrap_err();
        assert!(e.to_string().contains("no unit"), "{e}");
    }

    #[test]
    fn the_unit_is_inferred_when_exactly_one_fits() {
        for (height, units) in [
            (1.73, Units::Metres),
            (173.0, Units::Centimetres),
            (1730.0, Units::Millimetres),
            (0.5, Units::Metres),
        ] {
            assert_eq!(check(column(0.0, height), None), Ok(units), "{height}");
        }
        for height in [1.73e20, 0.0017, 10.0] {
            let e = check(column(0.0, height), None).unwrap_err();
            assert!(
                matches!(e, InputError::UnitsNotInferred { ref fits, .. } if fits.is_empty()),
                "{e}"
            );
            assert!(e.to_string().contains("no unit (m, cm, mm)"), "{e}");
        }
    }

    /// Separate cylinders with rings 7 cm apart, each leg's top ring
    /// inside the torso's: their vertices never come near, their surfaces
    /// do.
    #[test]
    fn a_coarse_model_of_separate_parts_is_one_body() {
        let m = crate::geom::shapes::stick_body(1);
        assert_eq!(
            validate_input(BodyGeometry::Mesh(&m), None),
            Ok(Units::Metres)
        );
    }

    #[test]
    fn a_non_finite_point_is_refused() {
        let mut points = column(0.0, 1.7);
        points[7].y = Real::NAN;
        let e = check(points, Some(Units::Metres)).unwrap_err();
        assert!(matches!(e, InputError::Invalid(_)), "{e}");
        assert!(e.to_string().contains("vertex 7"), "{e}");
    }

    #[test]
    fn overlapping_pieces_are_one_body() {
        // A torso with two separate legs overlapping its box, as a
        // tessellated model's parts are.
        let mut pieces = column(0.0, 1.7);
        let leg = column(0.05, 0.9)
            .into_iter()
            .map(|p| p + Vec3::new(0.0, -0.1, 0.0));
        pieces.extend(leg);
        check(pieces, Some(Units::Metres)).unwrap();
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
        let e = check(two, Some(Units::Metres)).unwrap_err();
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
        for _ in 0..20 {
            check(sheet.clone(), Some(Units::Metres)).unwrap();
        }
    }

    #[test]
    fn two_people_side_by_side_are_two_bodies_and_one_is_one() {
        let mut two = column(0.0, 1.7);
        two.extend(column(1.0, 1.6));
        let e = check(two.clone(), Some(Units::Metres)).unwrap_err();
        assert!(e.to_string().contains("2 separate bodies"), "{e}");
        // Inferred, the unit is the largest piece's and the answer the same.
        let mm: Vec<Point3> = two.iter().map(|p| *p * 1000.0).collect();
        let e = check(mm, None).unwrap_err();
        assert!(matches!(e, InputError::SeveralBodies { .. }), "{e}");
        let mut one = column(0.0, 1.7);
        one.extend(column(1.0, 0.1)); // a small stray piece
        check(one, Some(Units::Metres)).unwrap();
    }
}
