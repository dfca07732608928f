//! glTF 2.0 binary (GLB) export of triangle meshes: one glTF mesh and one
//! node per part, names kept, with normals.
//!
//! The JSON is written by hand with `serde_json` (the few objects a static
//! mesh needs; no dependency on a glTF object model). Layout of the one
//! binary buffer, per mesh: positions (`VEC3` `FLOAT`, with the `min`/`max`
//! the specification requires), normals (`VEC3` `FLOAT`, unit length), then
//! indices (`SCALAR` `UNSIGNED_INT`), each in its own buffer view. glTF
//! stores 32-bit floats: positions are rounded to f32 on the way out, and
//! the bounds are those of the rounded values. Both chunks are padded to 4
//! bytes (JSON with spaces, binary with zeros).

use serde_json::{json, Value};
use std::io::Write;
use thiserror::Error;
use trigbody_core::{Mesh, MeshError};

/// Why a GLB could not be written.
#[derive(Debug, Error)]
pub enum GltfError {
    /// The list of meshes was empty: give at least one.
    #[error("nothing to export: no meshes given")]
    Empty,
    /// A mesh failed [`Mesh::validate`] (no triangles, NaN, bad indices…).
    #[error("mesh {index} ('{name}'): {source}")]
    Mesh {
        /// Position of the mesh in the list.
        index: usize,
        /// Its name.
        name: String,
        /// What is wrong with it.
        #[source]
        source: MeshError,
    },
    /// The binary chunk would exceed GLB's 32-bit length fields: export
    /// fewer or coarser meshes.
    #[error("the binary buffer would be {0} bytes, more than GLB's 4 GiB limit")]
    TooLarge(u64),
    /// The writer failed.
    #[error("writing the GLB: {0}")]
    Io(#[from] std::io::Error),
}

const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF"
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const TRIANGLES: u32 = 4;

/// A named mesh to export (one glTF mesh and node).
#[derive(Clone, Copy, Debug)]
pub struct NamedMesh<'a> {
    /// The node's and the mesh's name in the file (e.g. the part's).
    pub name: &'a str,
    /// The triangles, with normals when the mesh has them.
    pub mesh: &'a Mesh,
}

/// Builds the GLB file's bytes for `meshes`.
pub fn glb_bytes(meshes: &[NamedMesh<'_>]) -> Result<Vec<u8>, GltfError> {
    if meshes.is_empty() {
        return Err(GltfError::Empty);
    }
    let mut bin: Vec<u8> = Vec::new();
    let mut views: Vec<Value> = Vec::new();
    let mut accessors: Vec<Value> = Vec::new();
    let mut gltf_meshes: Vec<Value> = Vec::new();
    let mut nodes: Vec<Value> = Vec::new();
    let mut push_view = |bin: &mut Vec<u8>, bytes: &[u8], target: u32| -> usize {
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        views.push(json!({
            "buffer": 0,
            "byteOffset": offset,
            "byteLength": bytes.len(),
            "target": target,
        }));
        views.len() - 1
    };
    for (index, m) in meshes.iter().enumerate() {
        m.mesh.validate().map_err(|source| GltfError::Mesh {
            index,
            name: m.name.to_string(),
            source,
        })?;
        let positions: Vec<[f32; 3]> = m
            .mesh
            .positions
            .iter()
            .map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect();
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        for p in &positions {
            for k in 0..3 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
            }
        }
        let bytes: Vec<u8> = positions
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let view = push_view(&mut bin, &bytes, ARRAY_BUFFER);
        accessors.push(json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": positions.len(),
            "type": "VEC3",
            "min": min,
            "max": max,
        }));
        let mut attributes = json!({ "POSITION": accessors.len() - 1 });
        if let Some(normals) = &m.mesh.normals {
            // Unit length in f32 (the validator checks it); a zero normal
            // (none defined) becomes +z rather than an invalid value.
            let bytes: Vec<u8> = normals
                .iter()
                .flat_map(|n| {
                    let v = n.normalized().unwrap_or(trigbody_core::Vec3::Z);
                    let f = [v.x as f32, v.y as f32, v.z as f32];
                    let len = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
                    [f[0] / len, f[1] / len, f[2] / len]
                })
                .flat_map(|x| x.to_le_bytes())
                .collect();
            let view = push_view(&mut bin, &bytes, ARRAY_BUFFER);
            accessors.push(json!({
                "bufferView": view,
                "componentType": FLOAT,
                "count": normals.len(),
                "type": "VEC3",
            }));
            attributes["NORMAL"] = json!(accessors.len() - 1);
        }
        let bytes: Vec<u8> = m
            .mesh
            .triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let view = push_view(&mut bin, &bytes, ELEMENT_ARRAY_BUFFER);
        accessors.push(json!({
            "bufferView": view,
            "componentType": UNSIGNED_INT,
            "count": 3 * m.mesh.triangles.len(),
            "type": "SCALAR",
        }));
        gltf_meshes.push(json!({
            "name": m.name,
            "primitives": [{
                "attributes": attributes,
                "indices": accessors.len() - 1,
                "mode": TRIANGLES,
            }],
        }));
        nodes.push(json!({ "name": m.name, "mesh": index }));
    }
    if bin.len() as u64 + 64 > u32::MAX as u64 {
        return Err(GltfError::TooLarge(bin.len() as u64));
    }
    let doc = json!({
        "asset": { "version": "2.0", "generator": concat!("trigbody ", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "meshes": gltf_meshes,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{ "byteLength": bin.len() }],
    });
    let mut json_bytes = serde_json::to_vec(&doc).map_err(std::io::Error::from)?;
    json_bytes.resize(json_bytes.len().next_multiple_of(4), b' ');
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json_bytes.len() + 8 + bin.len();
    let total32 = u32::try_from(total).map_err(|_| GltfError::TooLarge(total as u64))?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&GLB_MAGIC.to_le_bytes());
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total32.to_le_bytes());
    out.extend_from_slice(&(json_bytes.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(&json_bytes);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
    out.extend_from_slice(&bin);
    Ok(out)
}

/// Writes `meshes` as a GLB to `w`.
pub fn write_glb<W: Write>(mut w: W, meshes: &[NamedMesh<'_>]) -> Result<(), GltfError> {
    w.write_all(&glb_bytes(meshes)?)?;
    w.flush()?;
    Ok(())
}
