//! `trigbody mesh MODEL.json -o OUT.glb|obj|ply|stl`: tessellate a model.

use crate::exit::bad;
use crate::output::{refuse_input, write_file};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use trigbody_core::{Real, TessellationOptions};
use trigbody_io::gltf::{glb_bytes, NamedMesh};
use trigbody_io::model::{merge_pieces, read_model, skin_pieces};
use trigbody_io::{write_mesh, Format, WriteOptions};

/// Arguments of `trigbody mesh`.
#[derive(Debug, Args)]
pub struct MeshArgs {
    /// The model file (`trigbody loft` writes one).
    pub model: PathBuf,
    /// The mesh to write: .glb (one node per part), .obj, .ply or .stl (all parts in one mesh).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Samples around every curve.
    #[arg(long, default_value_t = TessellationOptions::default().around)]
    pub around: usize,
    /// Intervals along each patch.
    #[arg(long, default_value_t = TessellationOptions::default().along)]
    pub along: usize,
    /// Rings on each cap.
    #[arg(long, default_value_t = TessellationOptions::default().cap_rings)]
    pub cap_rings: usize,
    /// Target edge length in model units (overrides --around, --along, --cap-rings).
    #[arg(long)]
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
    let file = args.model.display().to_string();
    let out_name = args.output.display().to_string();
    let ext = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let glb = ext == "glb";
    let format = Format::from_path(&args.output);
    if !glb && !matches!(format, Some(Format::Obj | Format::Ply | Format::Stl)) {
        return Err(bad(format!(
            "{out_name}: unknown mesh format; use a .glb, .obj, .ply or .stl file name"
        )));
    }
    let reader = std::fs::File::open(&args.model).map_err(|e| bad(format!("{file}: {e}")))?;
    let model =
        read_model(std::io::BufReader::new(reader)).map_err(|e| bad(format!("{file}: {e}")))?;
    if model.parts.is_empty() {
        return Err(bad(format!("{file}: the model has no parts")));
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
        write_mesh(&args.output, &merge_pieces(&pieces), &options)
            .map_err(|e| bad(e.to_string()))?;
    }
    let (v, t) = pieces.iter().fold((0, 0), |(v, t), (_, m)| {
        (v + m.positions.len(), t + m.triangles.len())
    });
    println!(
        "{out_name}: {} part(s) in {} piece(s), {v} vertices, {t} triangles",
        model.parts.len(),
        pieces.len()
    );
    Ok(())
}
