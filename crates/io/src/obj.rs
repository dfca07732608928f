//! Wavefront OBJ: `v`, `vn`, `vt` and `f` statements; everything else
//! (`o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, free-form geometry) is
//! skipped.
//!
//! Faces of any size are fan-triangulated (`a b c d` → `a b c`, `a c d`),
//! which is exact for the convex polygons exporters write. Indices are
//! 1-based; negative ones count back from the last vertex defined so far.
//! Corner forms `v`, `v/vt`, `v//vn` and `v/vt/vn` are accepted, and a
//! data statement ending in `\` continues on the next line.
//!
//! Normals in OBJ belong to face corners, the core's to vertices: when every
//! face corner names a normal, a vertex gets the normal its corners name (the
//! normalized mean when they disagree, as at a hard edge; zero for a vertex
//! no face uses). When some corner has none, the mesh has no normals. A file
//! without faces is a point cloud; its `vn` lines pair with its `v` lines in
//! order when there are as many of each.
//!
//! Hand-written rather than the `tobj` crate so that every error names its
//! line and value, no input panics, and no dependency is added.

use crate::error::{FormatError, FormatErrorKind, IoError, Location, Result};
use crate::format::Format;
use crate::geometry::Geometry;
use crate::options::ReadOptions;
use crate::text::{excerpt, is_blank, parse_real, read_all, Lines};
use std::borrow::Cow;
use std::io::{BufWriter, Read, Write};
use trigbody_core::{Mesh, PointCloud, Vec3};

fn err(line: usize, kind: FormatErrorKind) -> IoError {
    FormatError::new(Format::Obj, Location::Line(line), kind).into()
}

/// Reads an OBJ file from `reader`.
pub fn read<R: Read>(reader: R, options: &ReadOptions) -> Result<Geometry> {
    read_bytes(&read_all(reader)?, options)
}

/// Resolves an OBJ index (1-based, or negative relative) against `count`
/// items defined so far.
fn resolve(token: &str, count: usize, what: &'static str, line: usize) -> Result<u32> {
    let index: i64 = token.parse().map_err(|_| {
        err(
            line,
            FormatErrorKind::InvalidNumber {
                expected: "an integer index",
                value: excerpt(token),
            },
        )
    })?;
    let out_of_range = || {
        err(
            line,
            FormatErrorKind::IndexOutOfRange { what, index, count },
        )
    };
    let resolved = if index > 0 {
        let i = (index - 1) as u64;
        if i >= count as u64 {
            return Err(out_of_range());
        }
        i
    } else if index < 0 {
        let back = index.unsigned_abs();
        if back > count as u64 {
            return Err(out_of_range());
        }
        count as u64 - back
    } else {
        return Err(out_of_range());
    };
    u32::try_from(resolved).map_err(|_| out_of_range())
}

fn parse_xyz<'a>(
    mut tokens: impl Iterator<Item = &'a str>,
    keyword: &str,
    line: usize,
) -> Result<Vec3> {
    let mut v = [0.0; 3];
    for (k, slot) in v.iter_mut().enumerate() {
        let token = tokens.next().ok_or_else(|| {
            err(
                line,
                FormatErrorKind::Syntax {
                    message: format!("`{keyword}` needs 3 coordinates, found {k}"),
                },
            )
        })?;
        *slot = parse_real(token).ok_or_else(|| {
            err(
                line,
                FormatErrorKind::InvalidNumber {
                    expected: "a coordinate",
                    value: excerpt(token),
                },
            )
        })?;
    }
    Ok(Vec3::from(v))
}

/// The data keywords whose statements are read.
fn is_data_keyword(keyword: &[u8]) -> bool {
    matches!(keyword, b"v" | b"vn" | b"vt" | b"f" | b"fo")
}

fn keyword_of(line: &[u8]) -> &[u8] {
    let line = line.trim_ascii_start();
    let end = line
        .iter()
        .position(|b| b.is_ascii_whitespace())
        .unwrap_or(line.len());
    &line[..end]
}

/// Lines with OBJ's continuation joined: a data statement whose line ends
/// in `\` goes on in the next line. The number is that of the first line.
/// (Only data statements: a comment ending in a backslash, like a Windows
/// folder name, must not swallow the next line.)
#[derive(Debug)]
struct LogicalLines<'a> {
    inner: Lines<'a>,
}

impl<'a> Iterator for LogicalLines<'a> {
    type Item = (usize, Cow<'a, [u8]>);
    fn next(&mut self) -> Option<Self::Item> {
        let (first, raw) = self.inner.next()?;
        if !(raw.trim_ascii_end().ends_with(b"\\") && is_data_keyword(keyword_of(raw))) {
            return Some((first, Cow::Borrowed(raw)));
        }
        let mut joined = Vec::new();
        let mut current = raw;
        loop {
            match current.trim_ascii_end().strip_suffix(b"\\") {
                Some(body) => {
                    joined.extend_from_slice(body);
                    joined.push(b' ');
                    match self.inner.next() {
                        Some((_, next)) => current = next,
                        None => break,
                    }
                }
                None => {
                    joined.extend_from_slice(current);
                    break;
                }
            }
        }
        Some((first, Cow::Owned(joined)))
    }
}

/// Reads an OBJ file held in memory.
pub fn read_bytes(data: &[u8], options: &ReadOptions) -> Result<Geometry> {
    if is_blank(data) {
        return Err(FormatError::new(Format::Obj, Location::File, FormatErrorKind::Empty).into());
    }
    let mut positions: Vec<Vec3> = Vec::new();
    let mut file_normals: Vec<Vec3> = Vec::new();
    let mut texcoords = 0usize;
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    // (vertex, normal) for every face corner, while all corners have normals.
    let mut corners: Vec<(u32, u32)> = Vec::new();
    let mut all_corners_have_normals = true;
    let mut polygon: Vec<(u32, Option<u32>)> = Vec::new();

    for (line, logical) in (LogicalLines {
        inner: Lines::new(data),
    }) {
        let bytes: &[u8] = &logical;
        let start = bytes
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .unwrap_or(bytes.len());
        let bytes = &bytes[start..];
        let keyword = keyword_of(bytes);
        if !is_data_keyword(keyword) {
            continue; // comments, names, materials, smoothing groups, ...
        }
        let text = std::str::from_utf8(bytes).map_err(|_| err(line, FormatErrorKind::NotUtf8))?;
        // Strip a trailing comment.
        let text = text.split('#').next().unwrap_or("");
        let mut tokens = text.split_ascii_whitespace();
        tokens.next();
        match keyword {
            b"v" => positions.push(parse_xyz(tokens, "v", line)?),
            b"vn" => file_normals.push(parse_xyz(tokens, "vn", line)?),
            b"vt" => texcoords += 1,
            _ => {
                polygon.clear();
                for corner in tokens {
                    let mut parts = corner.split('/');
                    let v = resolve(parts.next().unwrap_or(""), positions.len(), "vertex", line)?;
                    if let Some(t) = parts.next().filter(|t| !t.is_empty()) {
                        resolve(t, texcoords, "texture coordinate", line)?;
                    }
                    let n = match parts.next().filter(|n| !n.is_empty()) {
                        Some(n) => Some(resolve(n, file_normals.len(), "normal", line)?),
                        None => None,
                    };
                    if parts.next().is_some() {
                        return Err(err(
                            line,
                            FormatErrorKind::Syntax {
                                message: format!(
                                    "face corner {:?} has more than 3 parts (expected v, v/vt, v//vn or v/vt/vn)",
                                    excerpt(corner)
                                ),
                            },
                        ));
                    }
                    polygon.push((v, n));
                    crate::check_face_size(polygon.len() as u64).map_err(|k| err(line, k))?;
                }
                if polygon.len() < 3 {
                    return Err(err(
                        line,
                        FormatErrorKind::DegenerateFace {
                            count: polygon.len(),
                        },
                    ));
                }
                for k in 1..polygon.len() - 1 {
                    triangles.push([polygon[0].0, polygon[k].0, polygon[k + 1].0]);
                }
                if all_corners_have_normals {
                    if polygon.iter().all(|c| c.1.is_some()) {
                        corners.extend(polygon.iter().map(|&(v, n)| (v, n.unwrap_or(0))));
                    } else {
                        all_corners_have_normals = false;
                        corners = Vec::new();
                    }
                }
            }
        }
    }

    let normals = if triangles.is_empty() {
        (!file_normals.is_empty() && file_normals.len() == positions.len()).then_some(file_normals)
    } else if all_corners_have_normals && !file_normals.is_empty() {
        Some(vertex_normals(positions.len(), &file_normals, &corners))
    } else {
        None
    };
    Geometry::build(Format::Obj, positions, normals, triangles, options)
}

/// Per-vertex normals from per-corner ones: the corner's normal when all
/// corners of a vertex agree, their normalized mean when not.
fn vertex_normals(count: usize, file_normals: &[Vec3], corners: &[(u32, u32)]) -> Vec<Vec3> {
    const NONE: u32 = u32::MAX;
    let mut first = vec![NONE; count];
    let mut conflict = false;
    for &(v, n) in corners {
        let f = &mut first[v as usize];
        if *f == NONE {
            *f = n;
        } else if *f != n {
            conflict = true;
        }
    }
    if !conflict {
        return first
            .iter()
            .map(|&n| file_normals.get(n as usize).copied().unwrap_or(Vec3::ZERO))
            .collect();
    }
    let mut sum = vec![Vec3::ZERO; count];
    for &(v, n) in corners {
        sum[v as usize] += file_normals[n as usize];
    }
    sum.into_iter()
        .map(|s| s.normalized().unwrap_or(Vec3::ZERO))
        .collect()
}

/// Writes `w` as text; `{:?}` of f64 is the shortest text that reads back
/// to the same number, so OBJ round trips are exact.
fn write_vertices<W: Write>(w: &mut W, positions: &[Vec3], normals: Option<&[Vec3]>) -> Result<()> {
    for p in positions {
        writeln!(w, "v {:?} {:?} {:?}", p.x, p.y, p.z)?;
    }
    if let Some(ns) = normals {
        for n in ns {
            writeln!(w, "vn {:?} {:?} {:?}", n.x, n.y, n.z)?;
        }
    }
    Ok(())
}

/// Writes a mesh as OBJ text: `v`, then `vn` when the mesh has normals,
/// then one `f` per triangle (`f a//a b//b c//c` with normals).
/// The mesh is validated first.
pub fn write_mesh<W: Write>(writer: W, mesh: &Mesh) -> Result<()> {
    mesh.validate()?;
    let mut w = BufWriter::new(writer);
    writeln!(
        w,
        "# trigbody mesh: {} vertices, {} triangles",
        mesh.positions.len(),
        mesh.triangles.len()
    )?;
    write_vertices(&mut w, &mesh.positions, mesh.normals.as_deref())?;
    let with_normals = mesh.normals.is_some();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| u64::from(i) + 1);
        if with_normals {
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
        } else {
            writeln!(w, "f {a} {b} {c}")?;
        }
    }
    w.flush()?;
    Ok(())
}

/// Writes a point cloud as OBJ text: `v` lines (and `vn` lines in the same
/// order when it has normals), no faces.
pub fn write_points<W: Write>(writer: W, cloud: &PointCloud) -> Result<()> {
    cloud.validate()?;
    let mut w = BufWriter::new(writer);
    writeln!(
        w,
        "# trigbody point cloud: {} points",
        cloud.positions.len()
    )?;
    write_vertices(&mut w, &cloud.positions, cloud.normals.as_deref())?;
    w.flush()?;
    Ok(())
}
