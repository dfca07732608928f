//! # trigbody-render
//!
//! Pictures for trigbody: plots of cross-sections (input points, the
//! trigonometric fit and the ellipse baseline, like the paper's Figures 1-2)
//! as SVG or PNG. Drawing needs no display and no system fonts: PNG text uses
//! a bundled DejaVu Sans.

pub mod plot;

pub use plot::{plot_panels, Curve2, ImageFormat, Panel, PlotError, PlotOptions};
