//! # trigbody-render
//!
//! Pictures for trigbody: plots of cross-sections (input points, the
//! trigonometric fit and the ellipse baseline, like the paper's Figures 1-2)
//! as SVG or PNG, and shaded renders of meshes from several views, plain or
//! coloured by a value per vertex (a distance map with its colour bar), from
//! a small software z-buffer rasterizer ([`raster`]). Drawing needs no
//! display, no GPU and no system fonts: PNG text uses a bundled DejaVu Sans.
//!
//! ```
//! use trigbody_core::{Mesh, Vec3};
//! use trigbody_render::{render_mesh, render_mesh_values, RenderOptions, VertexValues, View};
//!
//! // A tetrahedron, drawn from the front and from 45°.
//! let p = Vec3::new;
//! let mesh = Mesh::new(
//!     vec![p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.), p(0., 0., 1.)],
//!     vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
//! )
//! .unwrap();
//! let options = RenderOptions {
//!     width: 160,
//!     height: 120,
//!     views: vec![View::front(), "45".parse().unwrap()],
//!     ..RenderOptions::default()
//! };
//! let render = render_mesh(&mesh, &options).unwrap();
//! assert_eq!((render.image.width, render.image.height), (320, 120));
//!
//! // Coloured by a value per vertex (say millimetres of distance), with a
//! // colour bar to the right of the views.
//! let mm = [0.0, 1.5, 3.0, 4.5];
//! let field = VertexValues::new(&mm, (0.0, 5.0), "distance (mm)");
//! let render = render_mesh_values(&mesh, &field, &options).unwrap();
//! assert!(render.image.width > 320);
//! let png: Vec<u8> = render.image.to_png().unwrap();
//! assert_eq!(&png[1..4], b"PNG");
//! ```

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
