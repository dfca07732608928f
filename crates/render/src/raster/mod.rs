//! Shaded pictures of a triangle mesh without a GPU: a small software
//! z-buffer rasterizer.
//!
//! # Pipeline
//!
//! For every [`View`] the mesh is drawn into its own panel of
//! [`RenderOptions::width`] × [`RenderOptions::height`] pixels; the panels sit
//! side by side, each with its label, and a colour bar follows on the right
//! when the surface is coloured by a value ([`render_mesh_values`]).
//!
//! 1. **Camera.** Orthographic. With the unit up vector `u` and the front
//!    direction `f` (made orthogonal to `u`), a view at azimuth `α` and
//!    elevation `ε` looks at the mesh from the direction
//!    `w = cos ε · (cos α · f + sin α · (u × f)) + sin ε · u`
//!    (the camera sits at `+∞·w`). The screen axes are
//!    `r = u × h / |u × h|` (right, with `h` the horizontal part of `w`) and
//!    `s = w × r` (screen up), so `(r, s, w)` is right-handed.
//! 2. **Projection and framing.** A point `p` goes to the sample
//!    `x = x₀ + k (p·r − c_r)`, `y = y₀ − k (p·s − c_s)` (image rows grow
//!    downwards) at depth `z = −p·w` (smaller is nearer). `c` is the centre
//!    of the projected extent of all vertices and `k` the largest scale at
//!    which every view's extent fits its panel inside the margin; all views
//!    share one `k`, so a length has the same size in each.
//! 3. **Rasterization.** Corners are snapped to fixed point (1/256 sample).
//!    The edge function of the directed edge `a → b`,
//!    `E_ab(p) = (b−a) × (p−a) = (b_x−a_x)(p_y−a_y) − (b_y−a_y)(p_x−a_x)`,
//!    is twice the signed area of the triangle `a b p`; a sample centre `p`
//!    lies in the triangle when all three edge functions have the sign of
//!    the triangle's area, and `E_12(p), E_20(p), E_01(p)` divided by that
//!    area are its barycentric coordinates `λ₀, λ₁, λ₂`. In integers the
//!    test is exact, and a sample exactly on an edge belongs to the triangle
//!    only if the edge is a top or a left edge, so triangles sharing an edge
//!    never both cover, nor both miss, a sample on it. Each triangle walks
//!    the samples of its bounding box, stepping the edge functions by
//!    constant increments; the depth `z = z₀ + λ₁(z₁−z₀) + λ₂(z₂−z₀)` is
//!    kept when nearer than the z-buffer's (ties keep the earlier triangle,
//!    so the picture never depends on timing). Zero-area triangles are
//!    skipped. The panel is cut into tiles of 32 × 32 pixels: the triangles
//!    are first sorted into the tiles their bounding boxes touch (keeping
//!    mesh order), then each tile is rasterized and shaded on its own, with a
//!    z-buffer small enough to stay in cache; rows of tiles run in parallel. Both sides of a triangle are drawn (open meshes show their
//!    inside).
//! 4. **Shading** (deferred: once per visible sample, not per fragment).
//!    The normal is `n = Σ λᵢ nᵢ / |Σ λᵢ nᵢ|` from per-vertex normals (the
//!    mesh's, or area-weighted ones: `nᵥ ∝ Σ (b−a)×(c−a)` over the triangles
//!    at `v`), turned towards the viewer when the triangle is seen from the
//!    side its normals point away from. With the unit direction to the light
//!    `L` (fixed in camera space: from the viewer's upper left by default),
//!    the view direction `V = w` and the half vector `H = (L+V)/|L+V|`
//!    (Blinn-Phong), the linear-light colour is
//!    `c = albedo · (k_a + k_d · max(0, n·L)) + k_s · max(0, n·H)^shininess`.
//!    The sRGB albedo is linearized first and the result encoded back to sRGB.
//! 5. **Antialiasing.** With [`RenderOptions::supersample`] `= m` the panel
//!    is rasterized at `m×` the size in each direction and each pixel is the
//!    mean of its `m²` samples in linear light (a pixel whose samples all hit
//!    one triangle is shaded once, at its centre).

use crate::colormap::{Colormap, Rgb};
use crate::text::{draw_labels, Anchor, Label};
use rayon::prelude::*;
use std::borrow::Cow;
use std::fmt;
use std::str::FromStr;
use thiserror::Error;
use trigbody_core::{Mesh, MeshError, Point3, Real, Vec3};

mod colour_bar;
mod rasterize;
mod shade;

use colour_bar::{colour_bar, colour_bar_width};
use rasterize::{bin, rasterize_tile, Cell, Tile, EMPTY_CELL, TILE};
use shade::{paint, srgb_to_linear, Shader, SrgbEncoder, NO_VALUE_GREY};

/// One direction to look at the mesh from (see the module docs for the
/// camera formula).
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// Text drawn over the view's panel.
    pub label: String,
    /// Rotation of the camera about the up axis from the front, in degrees,
    /// counter-clockwise seen from above: 0 looks at the front, 90 at the
    /// model's left side (the camera on `up × front`), 180 at the back.
    pub azimuth_deg: Real,
    /// Height of the camera above the horizontal, in degrees (−90 … 90).
    pub elevation_deg: Real,
}

impl View {
    /// From the front (azimuth 0).
    pub fn front() -> View {
        View::new("front", 0.0)
    }
    /// From the model's left side (azimuth 90; the model faces left in the
    /// picture).
    pub fn side() -> View {
        View::new("side", 90.0)
    }
    /// From the back (azimuth 180).
    pub fn back() -> View {
        View::new("back", 180.0)
    }
    /// From the model's left side, labelled "left" (azimuth 90).
    pub fn left() -> View {
        View::new("left", 90.0)
    }
    /// From the model's right side (azimuth −90).
    pub fn right() -> View {
        View::new("right", -90.0)
    }
    /// From any azimuth in degrees, labelled with the angle.
    pub fn azimuth(azimuth_deg: Real) -> View {
        View::new(format!("{azimuth_deg}°"), azimuth_deg)
    }
    /// A labelled view at `azimuth_deg`, elevation 0.
    pub fn new(label: impl Into<String>, azimuth_deg: Real) -> View {
        View {
            label: label.into(),
            azimuth_deg,
            elevation_deg: 0.0,
        }
    }
}

/// The text is not a view name or an angle.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error(
    "unknown view {0:?}: use front, side, back, left, right or an azimuth in degrees (e.g. 45)"
)]
pub struct ParseViewError(pub String);

impl FromStr for View {
    type Err = ParseViewError;
    /// `front`, `side`, `back`, `left`, `right` (any case), or a finite
    /// azimuth in degrees, optionally followed by `deg` or `°`.
    fn from_str(s: &str) -> Result<View, ParseViewError> {
        let t = s.trim();
        match t.to_ascii_lowercase().as_str() {
            "front" => return Ok(View::front()),
            "side" => return Ok(View::side()),
            "back" => return Ok(View::back()),
            "left" => return Ok(View::left()),
            "right" => return Ok(View::right()),
            _ => {}
        }
        let number = t.trim_end_matches("deg").trim_end_matches('°').trim();
        match number.parse::<Real>() {
            Ok(a) if a.is_finite() => Ok(View::azimuth(a)),
            _ => Err(ParseViewError(s.to_string())),
        }
    }
}

impl fmt::Display for View {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.label)
    }
}

/// Everything a render can be asked for, with documented defaults
/// (`RenderOptions::default()`).
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Width of one view's panel in pixels (default 1024).
    pub width: u32,
    /// Height of one view's panel in pixels (default 1024).
    pub height: u32,
    /// The views, drawn left to right (default front, side, back).
    pub views: Vec<View>,
    /// The model's up direction (default +y); any length but zero.
    pub up: Vec3,
    /// The direction the model faces (default +z); only its part
    /// perpendicular to `up` is used, which must not vanish.
    pub front: Vec3,
    /// Empty border around the framed mesh on every side, as a fraction of
    /// the panel's smaller side (default 0.06; must be in `[0, 0.45]`).
    pub margin: Real,
    /// Background colour, sRGB (default white).
    pub background: Rgb,
    /// Surface colour (albedo) when not coloured by values, sRGB
    /// (default a light clay, `[205, 190, 175]`).
    pub color: Rgb,
    /// Direction towards the light in camera space: x right, y up, z towards
    /// the viewer; any length but zero (default `(−0.45, 0.55, 0.70)`, from
    /// the viewer's upper left).
    pub light: [Real; 3],
    /// Ambient term `k_a` (default 0.15).
    pub ambient: Real,
    /// Diffuse (Lambert) term `k_d` (default 0.85).
    pub diffuse: Real,
    /// Specular (Blinn-Phong) term `k_s`, 0 for none (default 0.12).
    pub specular: Real,
    /// Specular exponent (default 32).
    pub shininess: Real,
    /// How strongly shading darkens a surface coloured by values, 0 (flat
    /// colours, exactly the colour bar's) to 1 (shaded like a plain
    /// surface); the light factor becomes `1 − t + t·(k_a + k_d·n·L)` and
    /// the highlight is scaled by `t` (default 0.4: the shape stays visible
    /// and the colours stay readable against the bar).
    pub value_shading: Real,
    /// Samples per pixel along each axis, 1 to 4 (default 2: 4 samples per
    /// pixel).
    pub supersample: u32,
    /// Draw the view labels (default true).
    pub labels: bool,
    /// Colour of labels and colour-bar text, sRGB (default near-black).
    pub text_color: Rgb,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 1024,
            height: 1024,
            views: vec![View::front(), View::side(), View::back()],
            up: Vec3::Y,
            front: Vec3::Z,
            margin: 0.06,
            background: [255, 255, 255],
            color: [205, 190, 175],
            light: [-0.45, 0.55, 0.70],
            ambient: 0.15,
            diffuse: 0.85,
            specular: 0.12,
            shininess: 32.0,
            value_shading: 0.4,
            supersample: 2,
            labels: true,
            text_color: [20, 20, 20],
        }
    }
}

/// A scalar value per vertex to colour the surface by (for instance the
/// distance in mm from a model to the scan it was fitted to), with the
/// range the colormap spans and the colour bar's title.
#[derive(Clone, Debug)]
pub struct VertexValues<'a> {
    /// One value per mesh vertex, in the unit named by `title`. NaN marks a
    /// vertex without a value (drawn grey); values outside `range` take the
    /// colour of the nearer end.
    pub values: &'a [Real],
    /// The values at the bottom and the top of the colour bar (finite,
    /// `min < max`).
    pub range: (Real, Real),
    /// The colour bar's title, e.g. `"distance (mm)"`.
    pub title: String,
    /// The colormap (default viridis).
    pub colormap: Colormap,
}

impl<'a> VertexValues<'a> {
    /// Values over `range` with viridis and the given title.
    pub fn new(values: &'a [Real], range: (Real, Real), title: impl Into<String>) -> Self {
        VertexValues {
            values,
            range,
            title: title.into(),
            colormap: Colormap::Viridis,
        }
    }
}

/// Why a picture could not be made.
#[derive(Debug, Error)]
pub enum RenderError {
    /// The mesh failed [`Mesh::validate`] (empty, non-finite, bad indices).
    #[error("cannot render the mesh: {0}")]
    Mesh(#[from] MeshError),
    /// A zero image size.
    #[error("image size {width}×{height} is empty: width and height must be at least 1 pixel")]
    EmptyImage { width: u32, height: u32 },
    /// More pixels than the renderer allocates.
    #[error("image of {width}×{height} per view, {views} views, supersample {supersample} is too large: at most {max} samples; use a smaller size or supersample")]
    TooLarge {
        width: u32,
        height: u32,
        views: usize,
        supersample: u32,
        max: u64,
    },
    /// No views asked for.
    #[error("no views to render: give at least one (e.g. front)")]
    NoViews,
    /// A view's angles are not finite.
    #[error("view {label:?} has a non-finite angle (azimuth {azimuth}, elevation {elevation})")]
    BadView {
        label: String,
        azimuth: Real,
        elevation: Real,
    },
    /// The up or front vector cannot define a camera.
    #[error("cannot orient the camera: up {up:?} and front {front:?} must be finite, non-zero and not parallel")]
    BadAxes { up: [Real; 3], front: [Real; 3] },
    /// An option out of its documented range.
    #[error("option {name} = {value} is out of range: {expected}")]
    BadOption {
        name: &'static str,
        value: String,
        expected: &'static str,
    },
    /// Value count differs from the vertex count.
    #[error("{values} values for {vertices} vertices: give one value per vertex")]
    ValueCount { values: usize, vertices: usize },
    /// A colour range that is empty or not finite.
    #[error("value range [{min}, {max}] is unusable: both ends and their difference must be finite, with min < max")]
    BadRange { min: Real, max: Real },
    /// Text drawing failed (a defect of the bundled font or backend).
    #[error("drawing text failed: {0}")]
    Text(String),
    /// PNG encoding failed.
    #[error("PNG encoding failed: {0}")]
    Png(String),
}

/// An RGB8 image, rows top to bottom, 3 bytes per pixel, sRGB.
#[derive(Clone, PartialEq, Eq)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    /// `width × height × 3` bytes.
    pub pixels: Vec<u8>,
}

impl fmt::Debug for RgbImage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "RgbImage({}×{})", self.width, self.height)
    }
}

impl RgbImage {
    /// The pixel at column `x`, row `y`, or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<Rgb> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 3 * (y as usize * self.width as usize + x as usize);
        Some([self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]])
    }

    /// The image as PNG file contents.
    pub fn to_png(&self) -> Result<Vec<u8>, RenderError> {
        crate::plot::encode_png(&self.pixels, self.width, self.height)
            .map_err(|e| RenderError::Png(e.to_string()))
    }
}

/// Where one view landed in the picture and how it maps space to pixels,
/// so callers (and tests) can relate pixels to model coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewFrame {
    pub view: View,
    /// The panel's left column in the image.
    pub left: u32,
    /// The panel's width and height in pixels.
    pub width: u32,
    pub height: u32,
    /// Pixels per model unit (the scale `k`, shared by all views).
    pub pixels_per_unit: Real,
    /// Screen right `r`, screen up `s` and towards-the-camera `w`, unit.
    pub right: Vec3,
    pub screen_up: Vec3,
    pub toward_camera: Vec3,
    /// `(c_r, c_s)`: the model-space `p·r`, `p·s` drawn at the panel centre.
    pub center: (Real, Real),
}

impl ViewFrame {
    /// Image coordinates (pixels, from the image's top-left corner; pixel
    /// `(i, j)` covers `[i, i+1) × [j, j+1)`) of the model point `p`.
    pub fn project(&self, p: Point3) -> (Real, Real) {
        let k = self.pixels_per_unit;
        (
            self.left as Real + 0.5 * self.width as Real + k * (p.dot(self.right) - self.center.0),
            0.5 * self.height as Real - k * (p.dot(self.screen_up) - self.center.1),
        )
    }
}

/// A finished picture and the framing of each view.
#[derive(Clone, Debug)]
pub struct Render {
    pub image: RgbImage,
    /// One per view, left to right.
    pub frames: Vec<ViewFrame>,
}

/// The most samples (all views, supersampled) one render allocates: 2²⁸
/// (about 2 GiB of buffers).
pub const MAX_SAMPLES: u64 = 1 << 28;

/// Renders `mesh` shaded in a uniform colour (see the module docs).
///
/// ```
/// use trigbody_core::{Mesh, Vec3};
/// use trigbody_render::{render_mesh, RenderOptions, View};
/// let mesh = Mesh::new(
///     vec![Vec3::new(0., 0., 0.), Vec3::new(1., 0., 0.), Vec3::new(0., 1., 0.)],
///     vec![[0, 1, 2]],
/// ).unwrap();
/// let options = RenderOptions { width: 64, height: 64, views: vec![View::front()], ..Default::default() };
/// let render = render_mesh(&mesh, &options).unwrap();
/// assert_eq!((render.image.width, render.image.height), (64, 64));
/// let png = render.image.to_png().unwrap();
/// assert_eq!(&png[1..4], b"PNG");
/// ```
pub fn render_mesh(mesh: &Mesh, options: &RenderOptions) -> Result<Render, RenderError> {
    render(mesh, None, options)
}

/// Renders `mesh` coloured by a value per vertex through a colormap, with a
/// colour bar and its tick labels to the right of the views. The value is
/// interpolated across each triangle before it is mapped to a colour; the
/// colour is then shaded like [`render_mesh`]'s surface.
pub fn render_mesh_values(
    mesh: &Mesh,
    values: &VertexValues<'_>,
    options: &RenderOptions,
) -> Result<Render, RenderError> {
    render(mesh, Some(values), options)
}

/// Area-weighted vertex normals: `n_v = normalize(Σ (b−a)×(c−a))` over the
/// triangles `abc` at `v` (the cross product's length is twice the area, so
/// large faces count more). A vertex whose sum vanishes gets the zero vector.
pub fn area_weighted_normals(mesh: &Mesh) -> Vec<Vec3> {
    mesh.vertex_normals()
}

/// The camera of one view: orthonormal `(r, s, w)`.
#[derive(Clone, Copy, Debug)]
struct Camera {
    right: Vec3,
    up: Vec3,
    toward: Vec3,
}

fn camera(view: &View, up: Vec3, front: Vec3) -> Result<Camera, RenderError> {
    if !(view.azimuth_deg.is_finite() && view.elevation_deg.is_finite()) {
        return Err(RenderError::BadView {
            label: view.label.clone(),
            azimuth: view.azimuth_deg,
            elevation: view.elevation_deg,
        });
    }
    let bad = || RenderError::BadAxes {
        up: up.to_array(),
        front: front.to_array(),
    };
    let u = up.normalized().ok_or_else(bad)?;
    let f = (front - u * front.dot(u)).normalized().ok_or_else(bad)?;
    // f must be clearly off the up axis, not just numerically.
    if front.dot(u).abs() > 0.999_999 * front.norm() {
        return Err(bad());
    }
    let side = u.cross(f);
    let (sa, ca) = view.azimuth_deg.to_radians().sin_cos();
    let (se, ce) = view.elevation_deg.to_radians().sin_cos();
    let horizontal = f * ca + side * sa;
    let toward = horizontal * ce + u * se;
    let right = u.cross(horizontal);
    let screen_up = toward.cross(right);
    Ok(Camera {
        right,
        up: screen_up,
        toward,
    })
}

fn check_options(options: &RenderOptions) -> Result<(), RenderError> {
    let o = options;
    if o.width == 0 || o.height == 0 {
        return Err(RenderError::EmptyImage {
            width: o.width,
            height: o.height,
        });
    }
    if o.views.is_empty() {
        return Err(RenderError::NoViews);
    }
    let range = |name, value: Real, lo: Real, hi: Real, expected| {
        if value >= lo && value <= hi {
            Ok(())
        } else {
            Err(RenderError::BadOption {
                name,
                value: value.to_string(),
                expected,
            })
        }
    };
    range("margin", o.margin, 0.0, 0.45, "between 0 and 0.45")?;
    range("ambient", o.ambient, 0.0, 1.0, "between 0 and 1")?;
    range("diffuse", o.diffuse, 0.0, 1.0, "between 0 and 1")?;
    range("specular", o.specular, 0.0, 1.0, "between 0 and 1")?;
    range(
        "shininess",
        o.shininess,
        1.0,
        10_000.0,
        "between 1 and 10000",
    )?;
    range(
        "value_shading",
        o.value_shading,
        0.0,
        1.0,
        "between 0 and 1",
    )?;
    if !(1..=4).contains(&o.supersample) {
        return Err(RenderError::BadOption {
            name: "supersample",
            value: o.supersample.to_string(),
            expected: "1, 2, 3 or 4",
        });
    }
    let light = Vec3::from(o.light);
    if light.normalized().is_none() {
        return Err(RenderError::BadOption {
            name: "light",
            value: format!("{:?}", o.light),
            expected: "a finite, non-zero direction",
        });
    }
    let m = o.supersample as u64;
    let samples = o.width as u64 * o.height as u64 * m * m * o.views.len() as u64;
    // The colour bar adds at most a quarter panel per row; keep headroom.
    if samples > MAX_SAMPLES || o.width as u64 * o.views.len() as u64 > u32::MAX as u64 / 2 {
        return Err(RenderError::TooLarge {
            width: o.width,
            height: o.height,
            views: o.views.len(),
            supersample: o.supersample,
            max: MAX_SAMPLES,
        });
    }
    Ok(())
}

/// What the rasterizer reads of a vertex: its corner in fixed point (1/256
/// sample) and its depth.
#[derive(Clone, Copy, Debug)]
struct RasterVertex {
    fx: i32,
    fy: i32,
    depth: f32,
}

/// What the shader reads of a vertex, in sample units (f32 is ample at
/// screen precision): position (x right, y down, depth away from the
/// viewer) and the normal in camera space (x right, y up, z towards the
/// viewer).
#[derive(Clone, Copy, Debug)]
struct ShadeVertex {
    x: f32,
    y: f32,
    depth: f32,
    normal: [f32; 3],
}

/// Per-vertex data of one view.
struct Projected {
    raster: Vec<RasterVertex>,
    shade: Vec<ShadeVertex>,
}

/// Sub-sample precision of the fixed-point corners: 8 bits.
const SUBPIXEL_BITS: u32 = 8;
const SUBPIXEL: i64 = 1 << SUBPIXEL_BITS;
const NO_TRIANGLE: u32 = u32::MAX;

/// Fit to view (step 2 of the module docs): the centre `(c_r, c_s)` of
/// each view's projected extent, and the one scale `k` (pixels per unit)
/// at which every extent fits its panel inside the margin.
fn frame_views(
    mesh: &Mesh,
    cameras: &[Camera],
    options: &RenderOptions,
) -> (Vec<(Real, Real)>, Real) {
    let (pw, ph) = (options.width as Real, options.height as Real);
    let margin_px = options.margin * pw.min(ph);
    let (avail_w, avail_h) = (
        (pw - 2.0 * margin_px).max(1.0),
        (ph - 2.0 * margin_px).max(1.0),
    );
    let mut centers = Vec::with_capacity(cameras.len());
    let mut scale = Real::INFINITY;
    for cam in cameras {
        let (mut lo_r, mut hi_r, mut lo_s, mut hi_s) = (
            Real::INFINITY,
            Real::NEG_INFINITY,
            Real::INFINITY,
            Real::NEG_INFINITY,
        );
        for p in &mesh.positions {
            let (r, s) = (p.dot(cam.right), p.dot(cam.up));
            lo_r = lo_r.min(r);
            hi_r = hi_r.max(r);
            lo_s = lo_s.min(s);
            hi_s = hi_s.max(s);
        }
        centers.push((0.5 * (lo_r + hi_r), 0.5 * (lo_s + hi_s)));
        for (extent, avail) in [(hi_r - lo_r, avail_w), (hi_s - lo_s, avail_h)] {
            if extent > 0.0 {
                scale = scale.min(avail / extent);
            }
        }
    }
    if !scale.is_finite() {
        // Every vertex projects to one point in every view: nothing has area.
        scale = 1.0;
    }
    (centers, scale)
}

/// Projects every vertex of `mesh` for one view into a sample grid of
/// `width × height` at `k` samples per unit (step 2), turning the normals
/// into camera space (unit length; zero when unusable).
fn project(
    mesh: &Mesh,
    normals: &[Vec3],
    cam: &Camera,
    center: (Real, Real),
    k: Real,
    width: usize,
    height: usize,
) -> Projected {
    let (cx, cy) = (0.5 * width as Real, 0.5 * height as Real);
    // Framing keeps every corner inside the grid; the clamp only guards the
    // integer arithmetic.
    let limit = 4.0 * width.max(height) as Real;
    let fixed = |v: Real| (v.clamp(-limit, limit) * SUBPIXEL as Real).round() as i32;
    let n = mesh.positions.len();
    let mut raster = vec![
        RasterVertex {
            fx: 0,
            fy: 0,
            depth: 0.0
        };
        n
    ];
    let mut shade = vec![
        ShadeVertex {
            x: 0.0,
            y: 0.0,
            depth: 0.0,
            normal: [0.0; 3]
        };
        n
    ];
    raster
        .par_iter_mut()
        .zip(shade.par_iter_mut())
        .zip(mesh.positions.par_iter().zip(normals))
        .for_each(|((r, sv), (p, nv))| {
            let x = cx + k * (p.dot(cam.right) - center.0);
            let y = cy - k * (p.dot(cam.up) - center.1);
            let depth = (-k * p.dot(cam.toward)) as f32;
            let n = Vec3::new(nv.dot(cam.right), nv.dot(cam.up), nv.dot(cam.toward));
            let normal = n
                .normalized()
                .map_or([0.0; 3], |n| [n.x as f32, n.y as f32, n.z as f32]);
            *r = RasterVertex {
                fx: fixed(x),
                fy: fixed(y),
                depth,
            };
            *sv = ShadeVertex {
                x: x as f32,
                y: y as f32,
                depth,
                normal,
            };
        });
    Projected { raster, shade }
}

/// The common path of [`render_mesh`] and [`render_mesh_values`].
fn render(
    mesh: &Mesh,
    values: Option<&VertexValues<'_>>,
    options: &RenderOptions,
) -> Result<Render, RenderError> {
    check_options(options)?;
    mesh.validate()?;
    if mesh.triangles.len() >= NO_TRIANGLE as usize {
        return Err(RenderError::BadOption {
            name: "mesh triangles",
            value: mesh.triangles.len().to_string(),
            expected: "fewer than 2³² − 1",
        });
    }
    let paint = paint(mesh, values, options)?;
    let cameras = options
        .views
        .iter()
        .map(|v| camera(v, options.up, options.front))
        .collect::<Result<Vec<_>, _>>()?;

    let (centers, scale) = frame_views(mesh, &cameras, options);

    let vertex_normals: Cow<'_, [Vec3]> = match &mesh.normals {
        Some(n) => Cow::Borrowed(n),
        None => Cow::Owned(area_weighted_normals(mesh)),
    };
    let light = Vec3::from(options.light).normalized().unwrap_or(Vec3::Z);
    let half = (light + Vec3::Z).normalized().unwrap_or(Vec3::Z);
    let to_f32 = |v: Vec3| [v.x as f32, v.y as f32, v.z as f32];
    let shader = Shader {
        light: to_f32(light),
        half: to_f32(half),
        ambient: options.ambient as f32,
        diffuse: options.diffuse as f32,
        specular: options.specular as f32,
        shininess: options.shininess as f32,
        shading: if values.is_some() {
            options.value_shading as f32
        } else {
            1.0
        },
        paint,
        no_value: [srgb_to_linear(NO_VALUE_GREY); 3],
        highlight_cutoff: (1e-4f64).powf(1.0 / options.shininess) as f32,
    };
    let encoder = SrgbEncoder::new();
    let background = options.background.map(srgb_to_linear);

    let m = options.supersample as usize;
    let (w, h) = (options.width as usize, options.height as usize);
    let bar_width = if values.is_some() {
        colour_bar_width(options.height)
    } else {
        0
    };
    let image_w = w * cameras.len() + bar_width;
    let mut image = RgbImage {
        width: image_w as u32,
        height: h as u32,
        pixels: options
            .background
            .iter()
            .copied()
            .cycle()
            .take(image_w * h * 3)
            .collect(),
    };
    let mut frames = Vec::with_capacity(cameras.len());
    let k = scale * m as Real;
    for (v, (cam, &center)) in cameras.iter().zip(&centers).enumerate() {
        let proj = project(mesh, &vertex_normals, cam, center, k, w * m, h * m);
        let view = PanelView {
            mesh,
            proj: &proj,
            shader: &shader,
            m,
            background,
        };
        draw_panel(&view, &encoder, &mut image, v * w, (w, h));
        frames.push(ViewFrame {
            view: options.views[v].clone(),
            left: (v * w) as u32,
            width: w as u32,
            height: h as u32,
            pixels_per_unit: scale,
            right: cam.right,
            screen_up: cam.up,
            toward_camera: cam.toward,
            center,
        });
    }

    let mut labels = Vec::new();
    if options.labels {
        let size = (h.min(w) as f64 / 26.0).clamp(9.0, 48.0);
        for f in &frames {
            labels.push(Label {
                text: f.view.label.clone(),
                x: f.left as i32 + (w / 2) as i32,
                y: (size * 0.4) as i32,
                size,
                color: options.text_color,
                anchor: Anchor::TopCenter,
            });
        }
    }
    if let Some(v) = values {
        colour_bar(
            &mut image,
            w * cameras.len(),
            bar_width,
            v,
            options,
            &mut labels,
        )?;
    }
    draw_labels(&mut image.pixels, image.width, image.height, &labels)
        .map_err(RenderError::Text)?;
    Ok(Render { image, frames })
}

/// What one panel draws: the mesh, its projection into the view, the
/// shading, the samples per pixel side `m` and the background colour.
#[derive(Clone, Copy)]
struct PanelView<'a> {
    mesh: &'a Mesh,
    proj: &'a Projected,
    shader: &'a Shader<'a>,
    m: usize,
    background: [f32; 3],
}

/// Draws one view into the panel of `image` at column `left`: bins the
/// triangles, then for each tile clears a small z-buffer, rasterizes the
/// tile's triangles (step 3) and averages each pixel's samples (step 5).
/// Rows of tiles run in parallel; each tile takes its triangles in mesh
/// order and owns its pixels, so the picture is the same for any number
/// of threads.
fn draw_panel(
    view: &PanelView<'_>,
    encoder: &SrgbEncoder,
    image: &mut RgbImage,
    left: usize,
    (w, h): (usize, usize),
) {
    let PanelView { mesh, proj, m, .. } = *view;
    let (grid_w, grid_h) = (w * m, h * m);
    let tile = TILE * m;
    let bins = bin(mesh, proj, grid_w, grid_h, tile);
    let stride = 3 * image.width as usize;
    image
        .pixels
        .par_chunks_mut(stride * TILE)
        .enumerate()
        .for_each(|(ty, strip)| {
            let mut cells = vec![EMPTY_CELL; tile * tile];
            let y0 = ty * tile;
            let height = tile.min(grid_h - y0);
            for tx in 0..bins.tiles_x {
                let x0 = tx * tile;
                let width = tile.min(grid_w - x0);
                let cells = &mut cells[..width * height];
                cells.fill(EMPTY_CELL);
                let mut t = Tile {
                    x0,
                    y0,
                    width,
                    height,
                    cells,
                };
                rasterize_tile(mesh, proj, &mut t, bins.tile(tx, ty));
                for py in 0..height / m {
                    let row = &mut strip[py * stride..(py + 1) * stride];
                    for px in 0..width / m {
                        let (x, y) = (x0 / m + px, y0 / m + py);
                        if let Some(c) = resolve_pixel(view, &t, x, y) {
                            let o = 3 * (left + x);
                            row[o] = encoder.encode(c[0]);
                            row[o + 1] = encoder.encode(c[1]);
                            row[o + 2] = encoder.encode(c[2]);
                        }
                    }
                }
            }
        });
}

/// The linear-light colour of panel pixel `(x, y)` from the samples of
/// `tile`, or `None` where no sample hit the mesh (the background is
/// already there).
#[inline]
fn resolve_pixel(view: &PanelView<'_>, tile: &Tile<'_>, x: usize, y: usize) -> Option<[f32; 3]> {
    let PanelView {
        mesh,
        proj,
        shader,
        m,
        background,
    } = *view;
    let sample = |i: usize, j: usize| (y * m + j - tile.y0) * tile.width + x * m + i - tile.x0;
    let first = tile.cells[sample(0, 0)].triangle;
    // A pixel covered by one continuous surface (no background sample,
    // depths within `continuity`) is shaded once at its centre:
    // antialiasing is only needed at silhouettes and occlusion edges,
    // where every sample is shaded. Depth spread in sample units: a slope
    // of up to 2 (about 63° from the viewer) still counts as continuous.
    let continuity = 2.0 * m as f32;
    let (mut any, mut all) = (false, true);
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    for j in 0..m {
        for i in 0..m {
            let Cell { depth, triangle } = tile.cells[sample(i, j)];
            let hit = triangle != NO_TRIANGLE;
            any |= hit;
            all &= hit;
            lo = lo.min(depth);
            hi = hi.max(depth);
        }
    }
    if !any {
        return None;
    }
    if all && hi - lo <= continuity {
        let c = (m as f32) * 0.5;
        return Some(shader.shade(
            mesh,
            proj,
            first as usize,
            (x * m) as f32 + c,
            (y * m) as f32 + c,
        ));
    }
    let mut sum = [0.0f32; 3];
    for j in 0..m {
        for i in 0..m {
            let t = tile.cells[sample(i, j)].triangle;
            let c = if t == NO_TRIANGLE {
                background
            } else {
                shader.shade(
                    mesh,
                    proj,
                    t as usize,
                    (x * m + i) as f32 + 0.5,
                    (y * m + j) as f32 + 0.5,
                )
            };
            sum = [sum[0] + c[0], sum[1] + c[1], sum[2] + c[2]];
        }
    }
    let inv = 1.0 / (m * m) as f32;
    Some(sum.map(|s| s * inv))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_parse() {
        assert_eq!("Front".parse::<View>().unwrap(), View::front());
        assert_eq!("back".parse::<View>().unwrap().azimuth_deg, 180.0);
        assert_eq!("45".parse::<View>().unwrap().azimuth_deg, 45.0);
        assert_eq!("-30deg".parse::<View>().unwrap().azimuth_deg, -30.0);
        assert!("top".parse::<View>().is_err());
        assert!("nan".parse::<View>().is_err());
    }

    #[test]
    fn camera_is_right_handed_and_front_view_has_x_right() {
        let c = camera(&View::front(), Vec3::Y, Vec3::Z).unwrap();
        assert!((c.right - Vec3::X).norm() < 1e-15);
        assert!((c.up - Vec3::Y).norm() < 1e-15);
        assert!((c.toward - Vec3::Z).norm() < 1e-15);
        let s = camera(&View::side(), Vec3::Y, Vec3::Z).unwrap();
        assert!((s.toward - Vec3::X).norm() < 1e-15);
        for az in [0.0, 33.0, 90.0, 200.0] {
            for el in [-90.0, -20.0, 0.0, 45.0, 90.0] {
                let v = View {
                    elevation_deg: el,
                    ..View::azimuth(az)
                };
                let c = camera(&v, Vec3::new(0., 0., 2.), Vec3::new(1., 1., 0.)).unwrap();
                assert!((c.right.cross(c.up) - c.toward).norm() < 1e-12, "{az} {el}");
                assert!((c.right.norm() - 1.0).abs() < 1e-12);
                assert!(c.right.dot(c.up).abs() < 1e-12);
            }
        }
        assert!(camera(&View::front(), Vec3::Y, Vec3::Y * 3.0).is_err());
        assert!(camera(&View::front(), Vec3::ZERO, Vec3::Z).is_err());
    }
}
