//! `trigbody mesh MODEL.json|MODEL.tbm -o OUT.glb|obj|ply|stl`: tessellate a model.

use crate::exit::bad;
use crate::output::{output_extension, refuse_input, write_file};
use anyhow::Result;
use clap::Args;
use std::path::{Path, PathBuf};
use trigbody_core::{Real, TessellationOptions};
use trigbody_io::gltf::{glb_bytes, NamedMesh};
use trigbody_io::model::{merge_pieces, skin_pieces};
use trigbody_io::{write_mesh_as, Format, WriteOptions};

/// Arguments of `trigbody mesh`.
#[derive(Debug, Args)]
pub struct MeshArgs {
    /// The model file: JSON (`trigbody loft` and `reconstruct` write one)
    /// or compact `.tbm` (`reconstruct -o body.tbm`).
    pub model: PathBuf,
    /// The mesh to write: .glb (one node per part), .obj, .ply or .stl (all parts in one mesh).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Samples around every curve.
    #[arg(long, default_value_t = TessellationOptions::default().around,
          value_parser = crate::bounds::count_in(3usize, 4096))]
    pub around: usize,
    /// Intervals along each patch.
    #[arg(long, default_value_t = TessellationOptions::default().along,
          value_parser = crate::bounds::count_in(1usize, 1024))]
    pub along: usize,
    /// Rings on each cap.
    #[arg(long, default_value_t = TessellationOptions::default().cap_rings,
          value_parser = crate::bounds::count_in(1usize, 1024))]
    pub cap_rings: usize,
    /// Target edge length in model units (overrides --around, --along, --cap-rings).
    #[arg(long, value_parser = crate::bounds::positive)]
    pub edge: Option<Real>,
    /// Which surface to write: one closed surface (the union of the
    /// pieces), every piece whole, or only the model's outer skin (each
    /// piece's triangles inside another piece left out).
    #[arg(long, value_enum, default_value_t = SkinFlag::Closed)]
    pub skin: SkinFlag,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
}

/// `--skin`: the surface an export writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SkinFlag {
    /// One watertight, manifold surface: the boundary of the union of the
    /// pieces less the cavities.
    Closed,
    /// Every piece's whole tessellation.
    Whole,
    /// The boundary of the union of the pieces.
    Outer,
}

impl From<SkinFlag> for trigbody_io::model::Skin {
    fn from(s: SkinFlag) -> Self {
        match s {
            SkinFlag::Closed => trigbody_io::model::Skin::Closed,
            SkinFlag::Whole => trigbody_io::model::Skin::Whole,
            SkinFlag::Outer => trigbody_io::model::Skin::Outer,
        }
    }
}

pub fn run(args: MeshArgs) -> Result<()> {
    let out_name = args.output.display().to_string();
    let ext = output_extension(&args.output, "ply");
    let glb = ext == "glb";
    let format = Format::from_path(&Path::new("mesh").with_extension(&ext));
    if !glb && !matches!(format, Some(Format::Obj | Format::Ply | Format::Stl)) {
        return Err(bad(format!(
            "{out_name}: unknown mesh format; use a .glb, .obj, .ply or .stl file name"
        )));
    }
    let file = args.model.display().to_string();
    let model = crate::body_input::read_model_file(&args.model)?;
    if let Some(edge) = args.edge {
        check_edge(&model, edge, &file)?;
    }
    let options = TessellationOptions {
        around: args.around,
        along: args.along,
        cap_rings: args.cap_rings,
        target_edge: args.edge,
    };
    let pieces = model
        .tessellate_pieces(&options)
        .map_err(|e| bad(e.to_string()))?;
    let pieces =
        skin_pieces(&model, pieces, args.skin.into()).map_err(|e| bad(format!("{file}: {e}")))?;
    if glb {
        let named: Vec<NamedMesh> = pieces
            .iter()
            .map(|(name, mesh)| NamedMesh { name, mesh })
            .collect();
        let bytes = glb_bytes(&named)?;
        write_file(&args.output, &bytes, &[&args.model], args.force)?;
    } else {
        refuse_input(&args.output, &[&args.model])?;
        let options = WriteOptions {
            overwrite: args.force,
            ..WriteOptions::default()
        };
        let format = format.unwrap_or(Format::Ply);
        write_mesh_as(&args.output, &merge_pieces(&pieces), format, &options)
            .map_err(|e| bad(e.to_string()))?;
    }
    let (v, t) = pieces.iter().fold((0, 0), |(v, t), (_, m)| {
        (v + m.positions.len(), t + m.triangles.len())
    });
    crate::exit::print(&format!(
        "{out_name}: {} part(s) in {} piece(s), {v} vertices, {t} triangles\n",
        model.parts.len(),
        pieces.len()
    ))?;
    Ok(())
}

/// The model's size in edges of `--edge` must stay below 4000 (about 16
/// million vertices per part at most): a tiny edge would tessellate for
/// minutes into gigabytes. The size is the diagonal of the model's
/// default (coarse) tessellation.
fn check_edge(
    model: &trigbody_io::model::Model,
    edge: trigbody_core::Real,
    file: &str,
) -> Result<()> {
    let coarse = model
        .tessellate_pieces(&TessellationOptions::default())
        .map_err(|e| bad(format!("{file}: {e}")))?;
    let size = merge_pieces(&coarse)
        .bounds()
        .map_or(0.0, |b| (b.max - b.min).norm());
    let smallest = size / 4000.0;
    if edge < smallest {
        return Err(bad(format!(
            "--edge {edge}: must be at least {smallest:.3e} for {file}, whose size is {size:.4} (1/4000 of it)"
        )));
    }
    Ok(())
}
