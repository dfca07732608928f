//! Section panels shared by `sections --plot`, `fit --plot` and
//! `plot-sections`: a loop's input points, its trigonometric curve and its
//! ellipse, drawn in the loop's own plane.

use trigbody_core::{Point3, TrigCurve, Vec2, Vec3};
use trigbody_render::{Curve2, Panel};

/// One loop to draw: the input points, the fitted curve, the ellipse.
pub struct LoopDrawing<'a> {
    pub points: &'a [Point3],
    pub curve: &'a TrigCurve,
    pub ellipse: Option<TrigCurve>,
}

/// Two unit vectors across `axis`: the first is the coordinate axis least
/// aligned with it (x for a y axis: a front view of a y-up body), projected;
/// the second completes a right-handed frame.
pub fn across(axis: Vec3) -> (Vec3, Vec3) {
    let n = axis.normalized().unwrap_or(Vec3::Y);
    let a = [n.x.abs(), n.y.abs(), n.z.abs()];
    let helper = if a[0] <= a[1] && a[0] <= a[2] {
        Vec3::X
    } else if a[1] <= a[2] {
        Vec3::Y
    } else {
        Vec3::Z
    };
    let u = (helper - n * helper.dot(n)).normalized().unwrap_or(Vec3::X);
    (u, n.cross(u))
}

/// A panel of loops in the plane spanned by `u`, `w`: red input points, the
/// green trig series and the blue ellipse, labelled once each.
pub fn loops_panel(title: String, loops: &[LoopDrawing<'_>], u: Vec3, w: Vec3) -> Panel {
    let top = |p: Point3| Vec2::new(p.dot(u), p.dot(w));
    let mut panel = Panel {
        title,
        points_label: "section points".into(),
        ..Panel::default()
    };
    for (i, l) in loops.iter().enumerate() {
        let label = |s: &str| if i == 0 { s.to_string() } else { String::new() };
        panel.points.extend(l.points.iter().map(|p| top(*p)));
        panel.curves.push(Curve2 {
            label: label("trig series"),
            points: l.curve.sample(300).into_iter().map(top).collect(),
            color: (20, 150, 40),
            closed: true,
        });
        if let Some(e) = &l.ellipse {
            panel.curves.push(Curve2 {
                label: label("ellipse"),
                points: e.sample(300).into_iter().map(top).collect(),
                color: (30, 60, 220),
                closed: true,
            });
        }
    }
    panel
}
