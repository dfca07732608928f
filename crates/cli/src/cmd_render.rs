//! `trigbody render MODEL.json|MESH -o OUT.png`: a shaded picture of a
//! mesh or of a model file (tessellated) from several views side by side;
//! `--compare INPUT` colours it by the distance to an input mesh or scan.

use crate::exit::{bad, print};
use crate::output::write_file;
use anyhow::Result;
use clap::Args;
use std::path::{Path, PathBuf};
use trigbody_core::internals::spatial::cloud_surface::CloudSurface;
use trigbody_core::internals::spatial::distance::MeshDistance;
use trigbody_core::internals::spatial::point_grid::PointGrid;
use trigbody_core::Mesh;
use trigbody_io::{Geometry, ReadOptions, UpAxis};
use trigbody_render::{
    render_mesh, render_mesh_values, RenderError, RenderOptions, VertexValues, View,
};

/// Flags of `trigbody render`; each maps onto one field of
/// [`RenderOptions`] or [`ReadOptions`].
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// What to draw: a mesh (.obj, .ply, .stl) or a model file (.json,
    /// tessellated).
    pub input: PathBuf,
    /// The picture to write (PNG).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Width and height of each view in pixels.
    #[arg(long, default_value_t = 1024, value_parser = crate::bounds::count_in(16u32, 8192))]
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
    /// Colour the drawn surface by its distance to this input, a mesh (each
    /// vertex to the closest point of its surface) or a point cloud (to the
    /// surface it samples, as the report measures), with a colour bar in mm.
    #[arg(long)]
    pub compare: Option<PathBuf>,
    /// Millimetres per input unit, for --compare (1000: the input is in
    /// metres).
    #[arg(long, default_value_t = 1000.0)]
    pub mm_per_unit: f64,
    /// Top of the colour bar in mm for --compare (default: the 99th
    /// percentile of the distances, at least 1 mm).
    #[arg(long)]
    pub max_mm: Option<f64>,
    /// Zoom onto a region of the body: head (above the neck), hands (past
    /// the wrists), feet (below the ankles), or one of left-hand,
    /// right-hand, left-foot, right-foot, found by segmenting the
    /// drawn mesh (a model file's closed skin); only its triangles there
    /// are drawn.
    #[arg(long, value_enum, conflicts_with = "focus_box")]
    pub focus: Option<crate::focus::FocusFlag>,
    /// Find --focus's regions on this mesh instead of the drawn one (the
    /// input a model was reconstructed from, to see the model's regions
    /// where the input has them).
    #[arg(long, requires = "focus")]
    pub focus_from: Option<PathBuf>,
    /// Zoom onto a box x0,y0,z0,x1,y1,z1 (the file's coordinates after
    /// --up-axis): only the triangles whose centre lies inside are drawn.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub focus_box: Option<Vec<f64>>,
    /// Replace an existing output file (the input is never replaced).
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: RenderArgs) -> Result<()> {
    if crate::output::output_extension(&args.output, "png") != "png" {
        return Err(bad(format!(
            "{}: the output must be a .png file",
            args.output.display()
        )));
    }
    let read = ReadOptions {
        up_axis: args.up_axis,
        ..ReadOptions::default()
    };
    // A model's close-up shows its outer skin (no piece's skin inside
    // another), which is also what the regions are found on.
    let zoomed = args.focus.is_some() || args.focus_box.is_some();
    let mesh = if zoomed {
        crate::body_input::drawable_surface(&args.input, &read, trigbody_io::model::Skin::Outer)?
    } else {
        load_mesh(&args.input, &read)?
    };
    let name = args.input.display().to_string();
    // An up axis the user gave is +y once read: the regions are found with it.
    let up = (args.up_axis != UpAxis::Keep).then_some(trigbody_core::Vec3::Y);
    let mesh = match (args.focus, &args.focus_box) {
        (Some(region), _) => match &args.focus_from {
            Some(path) => {
                let body = trigbody_io::read_mesh(path, &read).map_err(bad)?;
                let from = path.display().to_string();
                crate::focus::focus_region(&mesh, &body, region, &from, up)?
            }
            // A model's pieces overlap, which the segmentation cannot
            // follow; its one closed skin is a body like any mesh.
            None if crate::body_input::is_model_file(&args.input) => {
                let skin = trigbody_io::model::Skin::Closed;
                let body = crate::body_input::drawable_surface(&args.input, &read, skin)?;
                crate::focus::focus_region(&mesh, &body, region, &name, up)?
            }
            None => crate::focus::focus_region(&mesh, &mesh, region, &name, up)?,
        },
        (None, Some(corners)) => crate::focus::focus_box(&mesh, corners, &name)?,
        (None, None) => mesh,
    };
    let options = RenderOptions {
        width: args.size,
        height: args.size,
        views: args.views,
        supersample: args.supersample,
        ..RenderOptions::default()
    };
    let render = match &args.compare {
        None => render_mesh(&mesh, &options),
        Some(reference) => {
            if !(args.mm_per_unit.is_finite() && args.mm_per_unit > 0.0) {
                return Err(bad(format!(
                    "--mm-per-unit: must be positive, not {}",
                    args.mm_per_unit
                )));
            }
            let target = crate::input_file::read_geometry(reference, &read)?;
            let mm: Vec<f64> = distances_mm(&mesh, &target, args.mm_per_unit);
            let top = match args.max_mm {
                Some(t) if t.is_finite() && t > 0.0 => t,
                Some(t) => return Err(bad(format!("--max-mm: must be positive, not {t}"))),
                None => percentile(&mm, 0.99).max(1.0),
            };
            let field = VertexValues::new(&mm, (0.0, top), "distance to input (mm)");
            render_mesh_values(&mesh, &field, &options)
        }
    }
    .map_err(|e| render_failure(&args.input, e))?;
    let png = render
        .image
        .to_png()
        .map_err(|e| render_failure(&args.input, e))?;
    let mut inputs = vec![args.input.as_path()];
    inputs.extend(args.compare.as_deref());
    write_file(&args.output, &png, &inputs, args.force)?;
    print(&format!(
        "{}: {} triangles, {} view(s), {}×{} pixels\n",
        args.output.display(),
        mesh.triangles.len(),
        render.frames.len(),
        render.image.width,
        render.image.height
    ))
}

/// Every kind of input becomes the one [`Mesh`] that is drawn, in
/// [`crate::body_input::drawable_mesh`]: mesh files as read, model files
/// (`.json`) tessellated.
pub fn load_mesh(path: &Path, read: &ReadOptions) -> Result<Mesh> {
    crate::body_input::drawable_mesh(path, read)
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

/// The distance in mm from each vertex of `mesh` to the closest point of
/// `target`'s surface, or for a cloud to the surface it samples (the
/// report's [`CloudSurface`], its spacing `√(A/N)` from the drawn
/// surface's area `A` and the `N` points; NaN where none is found: drawn
/// grey).
fn distances_mm(mesh: &Mesh, target: &Geometry, mm_per_unit: f64) -> Vec<f64> {
    match target {
        Geometry::Mesh(t) => {
            let bvh = MeshDistance::new(t);
            mesh.positions
                .iter()
                .map(|&p| {
                    bvh.closest(p)
                        .map_or(f64::NAN, |c| c.distance * mm_per_unit)
                })
                .collect()
        }
        Geometry::Points(c) => {
            // Cells of 1 % of the cloud's largest extent.
            let size = c.bounds().map_or(1.0, |b| {
                let s = b.size();
                s.x.max(s.y).max(s.z)
            });
            let grid = PointGrid::new(&c.positions, 0.01 * size);
            let spacing = (mesh.surface_area() / c.positions.len().max(1) as f64).sqrt();
            CloudSurface::new(&grid, c.normals.as_deref(), spacing)
                .distances(&mesh.positions)
                .into_iter()
                .map(|d| {
                    if d.is_finite() {
                        d * mm_per_unit
                    } else {
                        f64::NAN
                    }
                })
                .collect()
        }
    }
}

/// The `q`-quantile of the finite values (0 when there are none).
pub(crate) fn percentile(values: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

#[cfg(test)]
mod tests {
    use super::*;
    use trigbody_core::{PointCloud, Vec3};

    /// A unit square in the plane z = 0 as two triangles.
    fn square() -> Mesh {
        let p = |x, y| Vec3::new(x, y, 0.0);
        Mesh::new(
            vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap()
    }

    /// A cloud colours by the distance to the surface it samples, as the
    /// report measures: the square's own vertices and a grid over it
    /// (spacing 0.01) lie on it, though a third of the way between grid
    /// points is 0.0047 from the nearest one.
    #[test]
    fn a_cloud_on_the_surface_measures_zero() {
        let mut positions = Vec::new();
        for i in 0..=100 {
            for j in 0..=100 {
                positions.push(Vec3::new(i as f64 / 100.0, j as f64 / 100.0, 0.0));
            }
        }
        let cloud = Geometry::Points(PointCloud {
            positions,
            normals: None,
        });
        let mut mesh = square();
        mesh.positions
            .extend([Vec3::new(0.333, 0.667, 0.0), Vec3::new(0.5, 0.5, 0.002)]);
        let d = distances_mm(&mesh, &cloud, 1000.0);
        for (p, mm) in mesh.positions.iter().zip(&d) {
            let expected = 1000.0 * p.z;
            assert!((mm - expected).abs() < 1e-6, "{p:?}: {mm}");
        }
        // The same points against the square as a mesh.
        let d = distances_mm(&mesh, &Geometry::Mesh(square()), 1000.0);
        assert!((d[5] - 2.0).abs() < 1e-9 && d[4].abs() < 1e-9, "{d:?}");
    }
}
