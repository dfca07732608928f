//! The input as the pipeline's steps see it: a scan without its floor and
//! strays, a mesh with its holes closed, and a mesh in its own frame.
//!
//! The body in its own frame: a mesh is reconstructed as a copy moved
//! into the body's frame (origin on the floor under the crotch, left +x,
//! up +y, front +z) with its vertices and triangles in a canonical order,
//! and its model is moved back. Grids, slices and samples then see the
//! same body whichever way the user's file turned it, moved it or
//! numbered it: the model of a rotated mesh is the rotated model, with
//! the same design parameters.
//!
//! A scan is moved too, into a frame whose horizontal axes are its
//! points' principal axes ([`own_pose_cloud`]): its segmentation turns on
//! the pixels of its slab images, and the front found from the feet
//! moves by a degree under a sub-millimetre shift, so that front only
//! signs the axes. [`Body::moved`] takes a model back, rebuilt from its moved sections as
//! a model file rebuilds it.

use super::{
    Body, BodyCavity, BodyDigit, BodyPart, BodyTransition, ReconstructError, ReconstructOptions,
    Report, Units,
};
use crate::anatomy::{BodyGeometry, OwnedGeometry, PartName};
use crate::geom::holes::{close_holes, ClosedHoles};
use crate::geom::linalg::principal;
use crate::geom::math::{Point3, Real, Vec3};
use crate::geom::mesh::{Mesh, PointCloud};
use crate::geom::rigid::Rigid;
use crate::segment::segment;
use crate::spatial::cloud_clean::{clean_cloud, CleanOptions, CleanReport};
use crate::surface::part::Part;
use crate::surface::transition::{Seam, SideCut, Transition};
use std::borrow::Cow;

/// The input as given, prepared and segmented: what its own frame is
/// found from.
fn segmented_as_given(
    body: BodyGeometry<'_>,
    opts: &ReconstructOptions,
) -> Result<crate::segment::Segmentation, ReconstructError> {
    let prepared = Prepared::of(body, opts);
    Ok(segment(
        prepared.geometry(),
        &prepared.options(opts).segment,
    )?)
}

/// The mesh moved into the body's own frame (found by segmenting it as
/// given) and order, and the motion that did it.
pub(super) fn own_pose(
    mesh: &Mesh,
    opts: &ReconstructOptions,
) -> Result<(Mesh, Rigid), ReconstructError> {
    let seg = segmented_as_given(BodyGeometry::Mesh(mesh), opts)?;
    let into = seg
        .frame
        .into_own_axes()
        .ok_or(ReconstructError::Frame { frame: seg.frame })?;
    Ok((in_own_frame(mesh, &into, seg.height), into))
}

/// A scan moved into a frame of its own and ordered, and the motion that
/// did it: origin the centroid of all its points, axes their principal
/// axes, the one nearest the up found by segmenting the cleaned scan as
/// +y, the one of the others nearest its left (or front) as +x (or +z),
/// each signed by those. The centroid and the axes are sums over the raw
/// points, so they turn and move with the scan to rounding, whatever the
/// cleaning or the slab images' pixels did; the found up, left and front
/// (a degree's jitter under a sub-millimetre shift) only choose among
/// them. The steps find the body's own up again in this frame.
pub(super) fn own_pose_cloud(
    cloud: &PointCloud,
    opts: &ReconstructOptions,
) -> Result<(PointCloud, Rigid), ReconstructError> {
    let seg = segmented_as_given(BodyGeometry::Cloud(cloud), opts)?;
    let frame_error = || ReconstructError::Frame { frame: seg.frame };
    let (centre, _, axes) = principal(&cloud.positions);
    let nearest = |v: Vec3, among: &[Vec3]| {
        among
            .iter()
            .map(|&a| a * a.dot(v).signum())
            .max_by(|a, b| a.dot(v).total_cmp(&b.dot(v)))
    };
    let up = nearest(seg.frame.up, &axes).ok_or_else(frame_error)?;
    let across: Vec<Vec3> = axes
        .iter()
        .copied()
        .filter(|a| *a != up && *a != -up)
        .collect();
    let (left, front) = (seg.frame.left, seg.frame.front);
    let x = match (nearest(left, &across), nearest(front, &across)) {
        (Some(l), Some(f)) if l.dot(left) >= f.dot(front) => l,
        (_, Some(f)) => up.cross(f),
        _ => return Err(frame_error()),
    };
    let into = Rigid::into_axes(centre, x, up).ok_or_else(frame_error)?;
    let moved = into.cloud(cloud);
    let order = sorted_order(&moved.positions, ORDER_QUANTUM * seg.height);
    let moved = PointCloud {
        positions: permuted(&moved.positions, &order),
        normals: moved.normals.as_ref().map(|v| permuted(v, &order)),
    };
    Ok((moved, into))
}

/// The input moved into its own frame and order ([`own_pose`],
/// [`own_pose_cloud`]) and the motion that did it.
pub(super) fn own_frame(
    body: BodyGeometry<'_>,
    opts: &ReconstructOptions,
) -> Result<(OwnedGeometry, Rigid), ReconstructError> {
    match body {
        BodyGeometry::Mesh(mesh) => own_pose(mesh, opts).map(|(m, r)| (OwnedGeometry::Mesh(m), r)),
        BodyGeometry::Cloud(cloud) => {
            own_pose_cloud(cloud, opts).map(|(c, r)| (OwnedGeometry::Cloud(c), r))
        }
    }
}

/// The input as the steps see it: a scan without its floor and strays, a
/// mesh with its holes closed (sections through a hole are open chains).
pub(super) struct Prepared<'a> {
    input: BodyGeometry<'a>,
    cleaned: Option<(Cow<'a, PointCloud>, CleanReport)>,
    closed: Option<(Mesh, ClosedHoles)>,
}

impl<'a> Prepared<'a> {
    pub(super) fn of(input: BodyGeometry<'a>, opts: &ReconstructOptions) -> Prepared<'a> {
        let clean = CleanOptions {
            up: opts.segment.up,
            ..opts.clean
        };
        match input {
            BodyGeometry::Cloud(cloud) => Prepared {
                input,
                cleaned: Some(clean_cloud(cloud, &clean)),
                closed: None,
            },
            BodyGeometry::Mesh(mesh) => Prepared {
                input,
                cleaned: None,
                closed: close_holes(mesh),
            },
        }
    }

    /// The input as the steps see it, `own` its copy in its own frame
    /// ([`own_frame`]), with the options for it: a mesh's up is the frame's
    /// +y, a scan's a given up turned with it, else its floor's normal
    /// ([`Prepared::options`]) or the one its segmentation finds; a given
    /// front turned with it.
    pub(super) fn in_own_frame(
        input: BodyGeometry<'a>,
        own: Option<&'a (OwnedGeometry, Rigid)>,
        opts: &ReconstructOptions,
    ) -> (Prepared<'a>, ReconstructOptions) {
        let mut own_opts = *opts;
        if let Some((own, into)) = own {
            own_opts.segment.up = match own {
                OwnedGeometry::Mesh(_) => Some(Vec3::Y),
                OwnedGeometry::Cloud(_) => opts.segment.up.map(|u| into.vector(u)),
            };
            own_opts.segment.front = opts.segment.front.map(|f| into.vector(f));
        }
        let prepared = Prepared::of(own.map_or(input, |o| o.0.geometry()), &own_opts);
        let own_opts = prepared.options(&own_opts);
        (prepared, own_opts)
    }

    pub(super) fn geometry(&self) -> BodyGeometry<'_> {
        match (&self.cleaned, &self.closed) {
            (Some((cloud, _)), _) => BodyGeometry::Cloud(cloud),
            (None, Some((mesh, _))) => BodyGeometry::Mesh(mesh),
            (None, None) => self.input,
        }
    }

    /// `opts` with the floor's normal as `up` when a floor was found and
    /// no `up` given.
    pub(super) fn options(&self, opts: &ReconstructOptions) -> ReconstructOptions {
        let mut o = *opts;
        if let Some((_, cleaning)) = &self.cleaned {
            o.segment.up = o.segment.up.or(cleaning.floor_normal);
        }
        o
    }

    /// What cleaning and closing did, for the report (whose vertex count
    /// loses the fans' centres, one per hole).
    pub(super) fn warnings(&self, report: &mut Report, units: Units) -> Vec<String> {
        let mut w = self
            .cleaned
            .as_ref()
            .map(|c| c.1.warnings())
            .unwrap_or_default();
        if let Some((_, holes)) = &self.closed {
            report.input_vertices -= holes.holes;
            w.push(format!(
                "closed {} hole(s) in the mesh ({:.0} mm of rim, {:.2} % of its area added); the model and its distances use the closed mesh",
                holes.holes,
                holes.rim_length * units.to_mm(),
                100.0 * holes.area_share
            ));
        }
        w
    }
}

impl Body {
    /// The body moved by `m`: its frame, and its parts, digits, cavities and
    /// transitions rebuilt from their moved sections and specifications as
    /// a model file rebuilds them (written and read back, the moved body is
    /// the same body).
    pub fn moved(&self, m: &Rigid) -> Result<Body, ReconstructError> {
        let part = |name: PartName, p: &Part| {
            p.moved(m)
                .map_err(|source| ReconstructError::Part { part: name, source })
        };
        let parts = self
            .parts
            .iter()
            .map(|p| {
                Ok(BodyPart {
                    name: p.name,
                    part: part(p.name, &p.part)?,
                    fits: p.fits.clone(),
                })
            })
            .collect::<Result<Vec<_>, ReconstructError>>()?;
        let cavities = self
            .cavities
            .iter()
            .map(|c| {
                Ok(BodyCavity {
                    within: c.within,
                    part: part(c.within, &c.part)?,
                    fits: c.fits.clone(),
                })
            })
            .collect::<Result<Vec<_>, ReconstructError>>()?;
        let digits = self
            .digits
            .iter()
            .map(|d| {
                Ok(BodyDigit {
                    hand: d.hand,
                    part: part(d.hand, &d.part)?,
                    fits: d.fits.clone(),
                })
            })
            .collect::<Result<Vec<_>, ReconstructError>>()?;
        let find = |name: PartName| parts.iter().find(|p| p.name == name).map(|p| &p.part);
        let transitions = self
            .transitions
            .iter()
            .map(|t| {
                let mut spec = *t.transition.spec();
                spec.seam = spec.seam.map(|s| Seam {
                    point: m.point(s.point),
                    normal: m.vector(s.normal),
                    up: m.vector(s.up),
                });
                spec.side = spec.side.map(|s| SideCut {
                    point: m.point(s.point),
                    normal: m.vector(s.normal),
                });
                let failed = |why: String| ReconstructError::Transition {
                    from: t.from,
                    to: t.to,
                    why,
                };
                let (Some(from), Some(to)) = (find(t.from), find(t.to)) else {
                    return Err(failed("a part is missing".into()));
                };
                Ok(BodyTransition {
                    from: t.from,
                    to: t.to,
                    transition: Transition::between(from, to, spec)
                        .map_err(|e| failed(e.to_string()))?,
                })
            })
            .collect::<Result<Vec<_>, ReconstructError>>()?;
        Ok(Body {
            units: self.units,
            frame: self.frame.moved(m),
            height: self.height,
            parts,
            transitions,
            digits,
            cavities,
        })
    }
}

/// Coordinates are compared in steps of this fraction of the height when
/// ordering: two copies of a body that differ by rounding (one turned and
/// turned back) then sort alike, and mirror-image vertices at one height
/// sort by their other coordinates.
const ORDER_QUANTUM: Real = 1e-9;

/// `mesh` moved by `m`, its vertices sorted by height, then across, then
/// front to back (in steps of [`ORDER_QUANTUM`] of `height`), its
/// triangles renumbered, each started at its lowest vertex (orientation
/// kept) and sorted.
pub(super) fn in_own_frame(mesh: &Mesh, m: &Rigid, height: Real) -> Mesh {
    let moved = m.mesh(mesh);
    let order = sorted_order(&moved.positions, ORDER_QUANTUM * height);
    let mut new_index = vec![0u32; order.len()];
    for (new, &old) in order.iter().enumerate() {
        new_index[old] = new as u32;
    }
    let mut triangles: Vec<[u32; 3]> = moved
        .triangles
        .iter()
        .map(|t| lowest_first(t.map(|i| new_index[i as usize])))
        .collect();
    triangles.sort_unstable();
    Mesh {
        positions: permuted(&moved.positions, &order),
        normals: moved.normals.as_ref().map(|n| permuted(n, &order)),
        triangles,
    }
}

/// The indices of `points` sorted by quantized (y, x, z); ties keep the
/// input's order.
fn sorted_order(points: &[Point3], q: Real) -> Vec<usize> {
    let key = |p: &Point3| [p.y, p.x, p.z].map(|c| (c / q).round() as i64);
    let keys: Vec<[i64; 3]> = points.iter().map(key).collect();
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by_key(|&i| keys[i]);
    order
}

fn permuted<T: Copy>(v: &[T], order: &[usize]) -> Vec<T> {
    order.iter().map(|&i| v[i]).collect()
}

/// The same triangle (same orientation) started at its lowest index.
fn lowest_first(t: [u32; 3]) -> [u32; 3] {
    let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::math::Vec3;
    use crate::geom::shapes;

    #[test]
    fn a_reordered_mesh_becomes_the_same_mesh() {
        let mesh = shapes::uv_sphere(Vec3::new(1.0, 2.0, 3.0), 0.5, 8, 12);
        let n = mesh.positions.len();
        // Reverse the vertices, renumber, turn every triangle's start and
        // reverse the triangles' order.
        let old_of = |i: u32| (n as u32 - 1) - i;
        let shuffled = Mesh {
            positions: mesh.positions.iter().rev().copied().collect(),
            normals: None,
            triangles: mesh
                .triangles
                .iter()
                .rev()
                .map(|t| [old_of(t[1]), old_of(t[2]), old_of(t[0])])
                .collect(),
        };
        let m = Rigid::into_axes(Vec3::new(1.0, 2.0, 3.0), Vec3::X, Vec3::Y).unwrap();
        let (a, b) = (
            in_own_frame(&mesh, &m, 1.0),
            in_own_frame(&shuffled, &m, 1.0),
        );
        assert_eq!(a, b);
        // Moved: the centre at the origin; the orientation kept.
        let c = a.positions.iter().fold(Vec3::ZERO, |s, &p| s + p) / a.positions.len() as Real;
        assert!(c.norm() < 1e-12);
        assert!((a.signed_volume() - mesh.signed_volume()).abs() < 1e-12);
        assert!(a.triangles.iter().all(|t| t[0] < t[1] && t[0] < t[2]));
    }
}
