//! Text on an RGB8 pixel buffer, with the bundled DejaVu Sans (no system
//! fonts, no display). Used for view labels and colour-bar ticks.

use crate::colormap::Rgb;
use crate::plot::register_font;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Where a text's anchor point sits relative to the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Anchor {
    /// The anchor is the top-left corner of the text.
    TopLeft,
    /// The anchor is the middle of the left edge.
    MiddleLeft,
    /// The anchor is the middle of the top edge.
    TopCenter,
}

/// One piece of text to draw.
#[derive(Clone, Debug)]
pub(crate) struct Label {
    pub text: String,
    /// Anchor point in pixels from the image's top-left corner.
    pub x: i32,
    pub y: i32,
    /// Font size in pixels (em height).
    pub size: f64,
    pub color: Rgb,
    pub anchor: Anchor,
}

/// Draws `labels` onto the `width × height` RGB8 buffer `rgb` (antialiased,
/// blended over what is there). Errors come from the drawing backend.
pub(crate) fn draw_labels(
    rgb: &mut [u8],
    width: u32,
    height: u32,
    labels: &[Label],
) -> Result<(), String> {
    if labels.is_empty() {
        return Ok(());
    }
    register_font();
    let root = BitMapBackend::with_buffer(rgb, (width, height)).into_drawing_area();
    for label in labels {
        let [r, g, b] = label.color;
        let color = RGBColor(r, g, b);
        let pos = match label.anchor {
            Anchor::TopLeft => Pos::new(HPos::Left, VPos::Top),
            Anchor::MiddleLeft => Pos::new(HPos::Left, VPos::Center),
            Anchor::TopCenter => Pos::new(HPos::Center, VPos::Top),
        };
        let style = ("sans-serif", label.size)
            .into_font()
            .color(&color)
            .pos(pos);
        root.draw_text(&label.text, &style, (label.x, label.y))
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Width and height in pixels of `text` at `size` px, as drawn.
pub(crate) fn text_size(text: &str, size: f64) -> Result<(u32, u32), String> {
    register_font();
    let mut scratch = [0u8; 3];
    let area = BitMapBackend::with_buffer(&mut scratch, (1, 1)).into_drawing_area();
    area.estimate_text_size(text, &("sans-serif", size).into_font().into())
        .map_err(|e| e.to_string())
}
