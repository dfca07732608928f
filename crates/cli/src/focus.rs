//! `render --focus head|hands|feet` and `--focus-box`: the drawn mesh cut
//! down to a region, so the views frame it close up.

use crate::exit::bad;
use anyhow::Result;
use trigbody_core::internals::measure::regions::{Region, Regions};
use trigbody_core::internals::surface::skin::kept;
use trigbody_core::{segment, BodyGeometry, SegmentOptions};
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
    /// The body's left hand (on its left of the mid-plane).
    LeftHand,
    /// The body's right hand.
    RightHand,
    /// The body's left foot.
    LeftFoot,
    /// The body's right foot.
    RightFoot,
}

/// `mesh`'s triangles whose centroid lies in `region` (the regions of
/// [`trigbody_core::regions`], from segmenting `body`: the drawn mesh
/// itself, or the input a model was made from); `name` names `body`'s
/// file in errors. `up`: the body's up axis when the user gave it (else
/// found from the data).
pub fn focus_region(
    mesh: &Mesh,
    body: &Mesh,
    region: FocusFlag,
    name: &str,
    up: Option<trigbody_core::Vec3>,
) -> Result<Mesh> {
    let options = SegmentOptions {
        up,
        ..SegmentOptions::default()
    };
    let seg = segment(BodyGeometry::Mesh(body), &options).map_err(|e| {
        let hint = if up.is_some() { "" } else { " (or --up-axis)" };
        bad(format!(
            "{name}: --focus needs a body to find its regions ({e}); for a model, \
             --focus-from its input mesh{hint}"
        ))
    })?;
    let regions = Regions::new(&seg);
    use FocusFlag::*;
    let want = match region {
        Head => Region::Head,
        Hands | LeftHand | RightHand => Region::Hands,
        Feet | LeftFoot | RightFoot => Region::Feet,
    };
    // The side of the mid-plane (through the frame's origin, normal to
    // its left axis): +1 left, -1 right, 0 both.
    let side = match region {
        LeftHand | LeftFoot => 1.0,
        RightHand | RightFoot => -1.0,
        _ => 0.0,
    };
    let frame = seg.frame;
    let cut = kept(mesh, |t| {
        let c = centroid(mesh, t);
        regions.of(c) == want && side * (c - frame.origin).dot(frame.left) >= 0.0
    });
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
