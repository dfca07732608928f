//! The colour bar of [`super::render_mesh_values`]: its gradient, ticks and
//! labels.

use super::{RenderError, RenderOptions, RgbImage, VertexValues};
use crate::text::{text_size, Anchor, Label};
use trigbody_core::Real;

/// Width of the colour-bar strip for panels `height` pixels tall.
pub(super) fn colour_bar_width(height: u32) -> usize {
    ((height as f64 * 0.24).round() as usize).max(90)
}

/// "Nice" tick values inside `[min, max]`: the smallest step of 1, 2, 2.5
/// or 5 × 10ⁿ that is at least ¾ of a fifth of the range (so 4 to 8 ticks),
/// with the number of decimals the step needs.
fn ticks(min: Real, max: Real) -> (Vec<Real>, usize) {
    let raw = 0.75 * (max - min) / 5.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|f| f * magnitude)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * magnitude);
    let decimals = {
        let d = -(step.log10().floor()) as i64;
        let d = if (step / 10f64.powi(-d as i32) - 2.5).abs() < 1e-9 {
            d + 1
        } else {
            d
        };
        d.clamp(0, 10) as usize
    };
    let first = (min / step).ceil() as i64;
    let last = (max / step).floor() as i64;
    let ticks = (first..=last).map(|i| i as Real * step).collect();
    (ticks, decimals)
}

/// Draws the gradient of `values`' colormap (top = max) into the strip at
/// column `left`, and queues its title and tick labels.
pub(super) fn colour_bar(
    image: &mut RgbImage,
    left: usize,
    width: usize,
    values: &VertexValues<'_>,
    options: &RenderOptions,
    labels: &mut Vec<Label>,
) -> Result<(), RenderError> {
    let h = image.height as usize;
    let stride = image.width as usize;
    let font = (h as f64 / 40.0).clamp(9.0, 32.0);
    let bar_x0 = left + (width as f64 * 0.12) as usize;
    let bar_w = ((width as f64 * 0.14) as usize).max(6);
    let top = (h as f64 * 0.14) as usize;
    let bottom = (h as f64 * 0.86) as usize;
    if bottom <= top + 1 {
        return Ok(());
    }
    let span = (bottom - 1 - top) as Real;
    for y in top..bottom {
        let t = 1.0 - (y - top) as Real / span;
        let c = values.colormap.color(t);
        for x in bar_x0..(bar_x0 + bar_w).min(left + width) {
            let o = 3 * (y * stride + x);
            image.pixels[o..o + 3].copy_from_slice(&c);
        }
    }
    let (min, max) = values.range;
    let (ticks, decimals) = ticks(min, max);
    let tick_x = bar_x0 + bar_w;
    for v in ticks {
        let y = top as Real + (1.0 - (v - min) / (max - min)) * span;
        let y = y.round() as usize;
        for x in tick_x..(tick_x + bar_w / 3).min(left + width) {
            let o = 3 * (y.min(h - 1) * stride + x);
            image.pixels[o..o + 3].copy_from_slice(&options.text_color);
        }
        let text = format!("{v:.decimals$}");
        let text = if text.starts_with('-') && text.trim_start_matches(['-', '0', '.']).is_empty() {
            text[1..].to_string() // "-0.0" → "0.0"
        } else {
            text
        };
        labels.push(Label {
            text,
            x: (tick_x + bar_w / 3 + 4) as i32,
            y: y as i32,
            size: font,
            color: options.text_color,
            anchor: Anchor::MiddleLeft,
        });
    }
    // The title, shrunk until it fits the strip.
    let mut size = font * 1.1;
    while size > 8.0 {
        let (tw, _) = text_size(&values.title, size).map_err(RenderError::Text)?;
        if (tw as usize) + 8 <= width {
            break;
        }
        size *= 0.9;
    }
    labels.push(Label {
        text: values.title.clone(),
        x: (left + 4) as i32,
        y: (h as f64 * 0.06) as i32,
        size,
        color: options.text_color,
        anchor: Anchor::TopLeft,
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_ticks() {
        let (t, d) = ticks(0.0, 10.0);
        assert_eq!(t, vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(d, 0);
        let (t, d) = ticks(0.0, 1.0);
        assert_eq!(t.len(), 6);
        assert_eq!(d, 1);
        let (t, d) = ticks(-5.0, 10.0);
        assert_eq!(t, vec![-5.0, -2.5, 0.0, 2.5, 5.0, 7.5, 10.0]);
        assert_eq!(d, 1); // step 2.5
        let (t, d) = ticks(-150.0, 150.0);
        assert_eq!(t, vec![-150.0, -100.0, -50.0, 0.0, 50.0, 100.0, 150.0]);
        assert_eq!(d, 0);
        for (lo, hi) in [(0.0, 1e-9), (-3.7, 12.1), (1e6, 1e6 + 3.0), (0.0, 7.0)] {
            let (t, _) = ticks(lo, hi);
            assert!((3..=8).contains(&t.len()), "{lo} {hi}: {t:?}");
            assert!(t
                .iter()
                .all(|v| *v >= lo - 1e-9 * hi.abs() && *v <= hi + 1e-9 * hi.abs()));
        }
    }
}
