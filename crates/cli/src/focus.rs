//! `render --focus head|hands|feet` and `--focus-box`: the drawn mesh cut
//! down to a region, so the views frame it close up.

use crate::exit::bad;
use anyhow::Result;
use trigbody_core::regions::{Region, Regions};
use trigbody_core::segment::{segment, BodyGeometry, SegmentOptions};
use trigbody_core::skin::kept;
use trigbody_core::{Mesh, Point3};

/// `--focus`: a region of the body, found by segmenting the drawn mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FocusFlag {
    /// Above the neck.
    Head,
    /// Past the wrists.
    Hands,
    /// Below the ankles.
    Feet,
}

/// `mesh`'s triangles whose centroid lies in `region` (the regions of
/// [`trigbody_core::regions`], from segmenting `mesh` itself); `name`
/// names the file in errors.
pub fn focus_region(mesh: &Mesh, region: FocusFlag, name: &str) -> Result<Mesh> {
    let seg = segment(BodyGeometry::Mesh(mesh), &SegmentOptions::default()).map_err(|e| {
        bad(format!(
            "{name}: --focus needs a body to find its regions: {e}"
        ))
    })?;
    let regions = Regions::new(&seg);
    let want = match region {
        FocusFlag::Head => Region::Head,
        FocusFlag::Hands => Region::Hands,
        FocusFlag::Feet => Region::Feet,
    };
    let cut = kept(mesh, |t| regions.of(centroid(mesh, t)) == want);
    if cut.triangles.is_empty() {
        return Err(bad(format!(
            "{name}: --focus {}: no part of the mesh lies there (the landmark was not found)",
            want.name()
        )));
    }
    Ok(cut)
}

/// `mesh`'s triangles whose centroid lies in the box `x0,y0,z0,x1,y1,z1`.
pub fn focus_box(mesh: &Mesh, corners: &[f64], name: &str) -> Result<Mesh> {
    let [x0, y0, z0, x1, y1, z1] = corners else {
        return Err(bad(format!(
            "--focus-box: six numbers x0,y0,z0,x1,y1,z1, not {}",
            corners.len()
        )));
    };
    if corners.iter().any(|c| !c.is_finite()) || !(x0 < x1 && y0 < y1 && z0 < z1) {
        return Err(bad(format!(
            "--focus-box: {x0},{y0},{z0},{x1},{y1},{z1} is not a box (finite, each low corner below its high one)"
        )));
    }
    let inside = |p: Point3| {
        p.x >= *x0 && p.x <= *x1 && p.y >= *y0 && p.y <= *y1 && p.z >= *z0 && p.z <= *z1
    };
    let cut = kept(mesh, |t| inside(centroid(mesh, t)));
    if cut.triangles.is_empty() {
        return Err(bad(format!(
            "{name}: --focus-box: no triangle lies in the box"
        )));
    }
    Ok(cut)
}

fn centroid(m: &Mesh, t: usize) -> Point3 {
    let [a, b, c] = m.triangle(t);
    (a + b + c) / 3.0
}
