//! `trigbody render MESH -o OUT.png`: a shaded picture of a mesh from
//! several views side by side.

use crate::cmd_fit::write_output;
use crate::exit::{bad, print};
use anyhow::Result;
use clap::Args;
use std::path::{Path, PathBuf};
use trigbody_core::Mesh;
use trigbody_io::{ReadOptions, UpAxis};
use trigbody_render::{render_mesh, RenderError, RenderOptions, View};

/// Flags of `trigbody render`; each maps onto one field of
/// [`RenderOptions`] or [`ReadOptions`].
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The mesh to draw: .obj, .ply or .stl.
    pub input: PathBuf,
    /// The picture to write (PNG).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Width and height of each view in pixels.
    #[arg(long, default_value_t = 1024)]
    pub size: u32,
    /// Views, left to right: front, side, back, left, right, or an azimuth
    /// in degrees (e.g. 45), separated by commas.
    #[arg(long, value_delimiter = ',', default_value = "front,side,back")]
    pub views: Vec<View>,
    /// The file's up axis (x, -x, y, -y, z, -z, or keep); it is turned onto
    /// +y. The model is drawn facing +z.
    #[arg(long, default_value = "keep", allow_hyphen_values = true)]
    pub up_axis: UpAxis,
    /// Samples per pixel along each axis (1-4; 2 smooths the edges).
    #[arg(long, default_value_t = 2)]
    pub supersample: u32,
}

pub fn run(args: RenderArgs) -> Result<()> {
    if !has_extension(&args.output, "png") {
        return Err(bad(format!(
            "{}: the output must be a .png file",
            args.output.display()
        )));
    }
    let read = ReadOptions {
        up_axis: args.up_axis,
        ..ReadOptions::default()
    };
    let mesh = load_mesh(&args.input, &read)?;
    let options = RenderOptions {
        width: args.size,
        height: args.size,
        views: args.views,
        supersample: args.supersample,
        ..RenderOptions::default()
    };
    let render = render_mesh(&mesh, &options).map_err(|e| render_failure(&args.input, e))?;
    let png = render
        .image
        .to_png()
        .map_err(|e| render_failure(&args.input, e))?;
    write_output(&args.output, &png, Some(&args.input))?;
    print(&format!(
        "{}: {} triangles, {} view(s), {}×{} pixels\n",
        args.output.display(),
        mesh.triangles.len(),
        render.frames.len(),
        render.image.width,
        render.image.height
    ))
}

/// Every kind of input becomes the one [`Mesh`] that is drawn, here and
/// only here: mesh files are read by trigbody-io; model files (`.json`) will
/// be tessellated here when the model format lands.
pub fn load_mesh(path: &Path, read: &ReadOptions) -> Result<Mesh> {
    if has_extension(path, "json") {
        return Err(bad(format!(
            "{}: model files cannot be rendered yet; give a mesh (.obj, .ply, .stl)",
            path.display()
        )));
    }
    // The reader's errors name the file, line or element, and the value.
    trigbody_io::read_mesh(path, read).map_err(bad)
}

fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// Rendering errors caused by the input or the flags are bad input (exit
/// 2); text drawing and PNG encoding failures are internal (exit 1).
fn render_failure(input: &Path, e: RenderError) -> anyhow::Error {
    match e {
        RenderError::Text(_) | RenderError::Png(_) => {
            anyhow::Error::new(e).context(format!("rendering {}", input.display()))
        }
        RenderError::EmptyImage { .. } | RenderError::TooLarge { .. } => {
            bad(format!("--size / --supersample: {e}"))
        }
        RenderError::BadOption {
            name: "supersample",
            ..
        } => bad(format!("--supersample: {e}")),
        _ => bad(format!("{}: {e}", input.display())),
    }
}
