//! Section plots: one or more panels, each with input points and labelled
//! curves, drawn with equal axis scales so shapes are not distorted.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;
use thiserror::Error;
use trigbody_core::{Real, Vec2};

/// The output formats a plot can be written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Svg,
    Png,
}

impl ImageFormat {
    /// The format named by a file's extension (`.svg`, `.png`; any case).
    pub fn from_path(path: &std::path::Path) -> Option<ImageFormat> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "svg" => Some(ImageFormat::Svg),
            "png" => Some(ImageFormat::Png),
            _ => None,
        }
    }
}

/// A labelled curve (a closed polyline when `closed`).
#[derive(Clone, Debug)]
pub struct Curve2 {
    pub label: String,
    pub points: Vec<Vec2>,
    /// RGB colour.
    pub color: (u8, u8, u8),
    pub closed: bool,
}

/// One plot panel: a title, input points and curves.
#[derive(Clone, Debug, Default)]
pub struct Panel {
    pub title: String,
    /// Input points, drawn as small dots.
    pub points: Vec<Vec2>,
    /// Label for the points in the legend.
    pub points_label: String,
    /// Draw the points small and light grey beneath the curves (an outline
    /// for context) instead of as red dots over them.
    pub faint_points: bool,
    pub curves: Vec<Curve2>,
}

/// Layout options with documented defaults.
#[derive(Clone, Debug)]
pub struct PlotOptions {
    /// Size of one panel in pixels (default 520).
    pub panel_size: u32,
    /// Panels per row (default: up to 3).
    pub columns: Option<usize>,
    /// A title over all panels (default none).
    pub title: Option<String>,
    /// Unit label for the axes (default "m").
    pub unit: String,
}

impl Default for PlotOptions {
    fn default() -> Self {
        PlotOptions {
            panel_size: 520,
            columns: None,
            title: None,
            unit: "m".to_string(),
        }
    }
}

/// Why a plot could not be drawn.
#[derive(Debug, Error)]
pub enum PlotError {
    #[error("nothing to plot: no panels")]
    Empty,
    #[error("drawing failed: {0}")]
    Draw(String),
    #[error("PNG encoding failed: {0}")]
    Png(String),
}

/// The bundled font for bitmap text.
const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static FONT_ONCE: Once = Once::new();

pub(crate) fn register_font() {
    FONT_ONCE.call_once(|| {
        // The font is compiled in; a failure here is a build defect.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Draws `panels` and returns the file contents (SVG text or PNG bytes).
pub fn plot_panels(
    panels: &[Panel],
    format: ImageFormat,
    opts: &PlotOptions,
) -> Result<Vec<u8>, PlotError> {
    if panels.is_empty() {
        return Err(PlotError::Empty);
    }
    let cols = opts.columns.unwrap_or(panels.len().min(3)).max(1);
    let rows = panels.len().div_ceil(cols);
    let title_h = if opts.title.is_some() { 40 } else { 0 };
    let (w, h) = (
        opts.panel_size * cols as u32,
        opts.panel_size * rows as u32 + title_h,
    );
    // Both backends measure text with the registered font.
    register_font();
    match format {
        ImageFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
                draw(&root, panels, opts, rows, cols, title_h)?;
                root.present().map_err(|e| PlotError::Draw(e.to_string()))?;
            }
            Ok(svg.into_bytes())
        }
        ImageFormat::Png => {
            let mut buf = vec![255u8; (w * h * 3) as usize];
            {
                let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
                draw(&root, panels, opts, rows, cols, title_h)?;
                root.present().map_err(|e| PlotError::Draw(e.to_string()))?;
            }
            encode_png(&buf, w, h)
        }
    }
}

/// Encodes an RGB8 buffer as PNG.
pub fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, PlotError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc
            .write_header()
            .map_err(|e| PlotError::Png(e.to_string()))?;
        writer
            .write_image_data(rgb)
            .map_err(|e| PlotError::Png(e.to_string()))?;
    }
    Ok(out)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panels: &[Panel],
    opts: &PlotOptions,
    rows: usize,
    cols: usize,
    title_h: u32,
) -> Result<(), PlotError> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| PlotError::Draw(e.to_string());
    root.fill(&WHITE).map_err(err)?;
    let body = if let Some(t) = &opts.title {
        let (top, rest) = root.split_vertically(title_h);
        top.titled(t, ("sans-serif", 24)).map_err(err)?;
        rest
    } else {
        root.clone()
    };
    let areas = body.split_evenly((rows, cols));
    for (panel, area) in panels.iter().zip(areas.iter()) {
        draw_panel(area, panel, &opts.unit).map_err(err)?;
    }
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    unit: &str,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    // Equal scales: a square window around everything drawn.
    let all = panel
        .points
        .iter()
        .chain(panel.curves.iter().flat_map(|c| c.points.iter()));
    let (mut lo, mut hi) = (
        Vec2::new(Real::MAX, Real::MAX),
        Vec2::new(Real::MIN, Real::MIN),
    );
    for p in all.filter(|p| p.is_finite()) {
        lo = Vec2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Vec2::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    if lo.x > hi.x {
        (lo, hi) = (Vec2::new(-1.0, -1.0), Vec2::new(1.0, 1.0));
    }
    let c = (lo + hi) * 0.5;
    let half = 0.5 * (hi.x - lo.x).max(hi.y - lo.y).max(1e-12) * 1.12;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 16))
        .margin(8)
        .x_label_area_size(28)
        .y_label_area_size(48)
        // Extra room at the top for the legend.
        .build_cartesian_2d(
            (c.x - half * 1.2)..(c.x + half * 1.2),
            (c.y - half)..(c.y + half * 1.4),
        )?;
    chart
        .configure_mesh()
        .x_labels(5)
        .y_labels(5)
        .x_desc(unit)
        .label_style(("sans-serif", 11))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    if panel.faint_points && !panel.points.is_empty() {
        let grey = RGBColor(185, 185, 185);
        chart
            .draw_series(
                panel
                    .points
                    .iter()
                    .map(|p| Circle::new((p.x, p.y), 1, grey.filled())),
            )?
            .label(panel.points_label.clone())
            .legend(move |(x, y)| Circle::new((x + 9, y), 3, grey.filled()));
    }
    for curve in &panel.curves {
        let color = RGBColor(curve.color.0, curve.color.1, curve.color.2);
        let mut pts: Vec<(Real, Real)> = curve.points.iter().map(|p| (p.x, p.y)).collect();
        if curve.closed {
            if let Some(first) = pts.first().copied() {
                pts.push(first);
            }
        }
        let series = chart.draw_series(LineSeries::new(pts, color.stroke_width(2)))?;
        // An empty label keeps a curve out of the legend (one entry per kind).
        if !curve.label.is_empty() {
            series.label(curve.label.clone()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
            });
        }
    }
    if !panel.points.is_empty() && !panel.faint_points {
        let red = RGBColor(200, 30, 30);
        chart
            .draw_series(
                panel
                    .points
                    .iter()
                    .map(|p| Circle::new((p.x, p.y), 2, red.filled())),
            )?
            .label(panel.points_label.clone())
            .legend(move |(x, y)| Circle::new((x + 9, y), 3, red.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .label_font(("sans-serif", 12))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle_panel() -> Panel {
        let pts: Vec<Vec2> = (0..40)
            .map(|i| {
                let t = std::f64::consts::TAU * i as Real / 40.0;
                Vec2::new(t.cos(), 0.5 * t.sin())
            })
            .collect();
        Panel {
            title: "ellipse".into(),
            points: pts.clone(),
            points_label: "input".into(),
            faint_points: false,
            curves: vec![Curve2 {
                label: "fit".into(),
                points: pts,
                color: (0, 150, 0),
                closed: true,
            }],
        }
    }

    #[test]
    fn svg_and_png_are_produced() {
        let panels = vec![circle_panel(), circle_panel()];
        let svg = plot_panels(&panels, ImageFormat::Svg, &PlotOptions::default()).unwrap();
        let text = String::from_utf8(svg).unwrap();
        assert!(text.starts_with("<svg") && text.contains("fit") && text.contains("input"));
        let png = plot_panels(&panels, ImageFormat::Png, &PlotOptions::default()).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        assert!(matches!(
            plot_panels(&[], ImageFormat::Png, &PlotOptions::default()),
            Err(PlotError::Empty)
        ));
    }

    #[test]
    fn format_from_extension() {
        use std::path::Path;
        assert_eq!(
            ImageFormat::from_path(Path::new("a.SVG")),
            Some(ImageFormat::Svg)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("a.png")),
            Some(ImageFormat::Png)
        );
        assert_eq!(ImageFormat::from_path(Path::new("a.jpg")), None);
    }
}
