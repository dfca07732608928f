//! # trigbody-render
//!
//! Pictures for trigbody: plots of cross-sections (input points, the
//! trigonometric fit and the ellipse baseline, like the paper's Figures 1-2)
//! as SVG or PNG, and shaded renders of meshes from several views, plain or
//! coloured by a value per vertex (a distance map with its colour bar), from
//! a small software z-buffer rasterizer ([`raster`]). Drawing needs no
//! display, no GPU and no system fonts: PNG text uses a bundled DejaVu Sans.

pub mod colormap;
pub mod plot;
pub mod raster;
mod text;

pub use colormap::{Colormap, Rgb};
pub use plot::{plot_panels, Curve2, ImageFormat, Panel, PlotError, PlotOptions};
pub use raster::{
    area_weighted_normals, render_mesh, render_mesh_values, ParseViewError, Render, RenderError,
    RenderOptions, RgbImage, VertexValues, View, ViewFrame,
};
