//! The JSON form of a fitted loop: everything needed to evaluate the curve
//! from the file alone (paper coefficient layout and the frame), its errors,
//! how its order was chosen, and the ellipse baseline.

use serde_json::{json, Value};
use trigbody_core::{LoopFit, Real};

fn round_trip(x: Real) -> Value {
    json!(x)
}

/// The JSON object of one fitted loop. Keys: `order`, `a`, `b`,
/// `frame: {origin, e1, e2}`, `normal`, `ea`, `em`, `rms`, `max`, `met`,
/// `orders_tried`, `paper_order`, `minimal_order`, `errors_by_order`,
/// `ellipse: {ea, em, rms, max, a, b, axis}`, `points`, `dropped`,
/// `reversed`, `plane_deviation`, `fast_path`, `warnings`.
pub fn loop_fit_json(fit: &LoopFit) -> Value {
    let f = &fit.curve.frame;
    let ellipse = fit.ellipse.map(|e| {
        let axis = f.e1 * e.axis.x + f.e2 * e.axis.y;
        json!({
            "ea": e.errors.ea, "em": e.errors.em, "rms": e.errors.rms, "max": e.errors.max,
            "a": e.a, "b": e.b, "axis": axis.to_array(),
        })
    });
    json!({
        "order": fit.order,
        "a": fit.curve.a.iter().copied().map(round_trip).collect::<Vec<_>>(),
        "b": fit.curve.b.iter().copied().map(round_trip).collect::<Vec<_>>(),
        "frame": { "origin": f.origin.to_array(), "e1": f.e1.to_array(), "e2": f.e2.to_array() },
        "normal": f.normal().to_array(),
        "ea": fit.errors.ea,
        "em": fit.errors.em,
        "rms": fit.errors.rms,
        "max": fit.errors.max,
        "met": fit.met,
        "orders_tried": fit.orders_tried,
        "paper_order": fit.paper_order,
        "minimal_order": fit.minimal_order,
        "errors_by_order": fit.errors_by_order.iter().map(|(j, e)| json!({"order": j, "ea": e.ea, "em": e.em})).collect::<Vec<_>>(),
        "ellipse": ellipse,
        "points": fit.plane_points.len(),
        "dropped": fit.dropped,
        "reversed": fit.reversed,
        "plane_deviation": fit.plane_deviation,
        "fast_path": fit.fast_path,
        "warnings": fit.warnings,
    })
}
