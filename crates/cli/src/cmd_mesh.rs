//! `trigbody mesh MODEL.json -o OUT.glb|obj|ply|stl`: tessellate a model.

use crate::exit::bad;
use crate::output::{refuse_input, write_file};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use trigbody_core::{tessellate_part, Mesh, Real, TessellationOptions};
use trigbody_io::gltf::{glb_bytes, NamedMesh};
use trigbody_io::model::read_model;
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
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
}

/// All meshes in one (indices offset).
fn merged(meshes: &[Mesh]) -> Mesh {
    let mut out = Mesh {
        normals: Some(Vec::new()),
        ..Mesh::default()
    };
    for m in meshes {
        let base = out.positions.len() as u32;
        out.positions.extend_from_slice(&m.positions);
        if let (Some(all), Some(n)) = (out.normals.as_mut(), m.normals.as_ref()) {
            all.extend_from_slice(n);
        }
        out.triangles
            .extend(m.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    out
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
    let meshes = model
        .parts
        .iter()
        .map(|p| {
            tessellate_part(&p.part, &options).map_err(|e| bad(format!("part '{}': {e}", p.name)))
        })
        .collect::<Result<Vec<Mesh>>>()?;
    // Transitions: a grid of about the parts' resolution.
    let mut meshes = meshes;
    meshes.extend(model.transitions.iter().map(|t| match options.target_edge {
        Some(e) => t.transition.tessellate_edge(e),
        None => t.transition.tessellate(options.around, options.along),
    }));
    let transition_names: Vec<String> = model
        .transitions
        .iter()
        .map(|t| format!("{}-{}", t.from, t.to))
        .collect();
    if glb {
        let names = model
            .parts
            .iter()
            .map(|p| p.name.as_str())
            .chain(transition_names.iter().map(String::as_str));
        let named: Vec<NamedMesh> = names
            .zip(&meshes)
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
        write_mesh(&args.output, &merged(&meshes), &options).map_err(|e| bad(e.to_string()))?;
    }
    let (v, t) = meshes.iter().fold((0, 0), |(v, t), m| {
        (v + m.positions.len(), t + m.triangles.len())
    });
    println!(
        "{out_name}: {} part(s), {v} vertices, {t} triangles",
        model.parts.len()
    );
    Ok(())
}
