//! STL, ASCII and binary. Identical corners are merged into one vertex so
//! that the result is an indexed mesh (bitwise-equal coordinates, with −0
//! and +0 the same); facet normals are not kept (the core's normals belong
//! to vertices).
//!
//! Which kind a file is: a binary file's size is exactly 84 + 50·n for the
//! triangle count n at byte 80, and many binary files begin with "solid" in
//! their header, so the size decides first. Otherwise a file that begins
//! with `solid` and whose next line starts with `facet` or `endsolid` is
//! ASCII, and anything else is binary. A binary count of 0 followed by
//! whole 50-byte records (a streaming writer that never went back to fill
//! in the count) is read as those records.
//!
//! Hand-written: both forms are a few lines of parsing, and `stl_io` reads
//! into f32 and says nothing about where a file went wrong.

use crate::error::{FormatError, FormatErrorKind, IoError, Location, Result};
use crate::format::Format;
use crate::geometry::Geometry;
use crate::options::ReadOptions;
use crate::text::{excerpt, is_blank, parse_real, read_all, Lines};
use std::collections::HashMap;
use std::io::{BufWriter, Read, Write};
use trigbody_core::{Mesh, Vec3};

const HEADER: usize = 80;
const TRIANGLE: usize = 50;

/// Reads an STL file from `reader`.
pub fn read<R: Read>(reader: R, options: &ReadOptions) -> Result<Geometry> {
    read_bytes(&read_all(reader)?, options)
}

/// Reads an STL file held in memory.
pub fn read_bytes(data: &[u8], options: &ReadOptions) -> Result<Geometry> {
    if is_blank(data) {
        return Err(FormatError::new(Format::Stl, Location::File, FormatErrorKind::Empty).into());
    }
    let (positions, triangles) = if is_ascii(data) {
        read_ascii(data)?
    } else {
        read_binary(data)?
    };
    Geometry::build(Format::Stl, positions, None, triangles, options)
}

/// The triangle count a binary file declares, if it is long enough to have one.
fn binary_count(data: &[u8]) -> Option<u32> {
    let b: [u8; 4] = data.get(HEADER..HEADER + 4)?.try_into().ok()?;
    Some(u32::from_le_bytes(b))
}

fn is_ascii(data: &[u8]) -> bool {
    if let Some(n) = binary_count(data) {
        if (HEADER as u64 + 4 + TRIANGLE as u64 * u64::from(n)) == data.len() as u64 {
            return false;
        }
    }
    let start = data
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(0);
    let text = &data[start..];
    if !text
        .get(..5)
        .is_some_and(|s| s.eq_ignore_ascii_case(b"solid"))
    {
        return false;
    }
    let mut lines = Lines::new(text)
        .map(|(_, l)| l.trim_ascii())
        .filter(|l| !l.is_empty());
    lines.next();
    match lines.next() {
        None => true, // "solid name" alone: an empty ASCII file
        Some(l) => l.starts_with(b"facet") || l.starts_with(b"endsolid"),
    }
}

/// Merges bitwise-identical corners into indexed vertices.
#[derive(Debug, Default)]
struct Welder {
    index: HashMap<[u64; 3], u32>,
    positions: Vec<Vec3>,
}

impl Welder {
    fn vertex(&mut self, p: [f64; 3]) -> u32 {
        // Adding 0 turns −0 into +0 and keeps every other value.
        let key = p.map(|c| (c + 0.0).to_bits());
        let next = self.positions.len() as u32;
        *self.index.entry(key).or_insert_with(|| {
            self.positions.push(Vec3::from(p));
            next
        })
    }
}

fn read_binary(data: &[u8]) -> Result<(Vec<Vec3>, Vec<[u32; 3]>)> {
    let Some(count) = binary_count(data) else {
        return Err(FormatError::new(
            Format::Stl,
            Location::Byte(data.len() as u64),
            FormatErrorKind::UnexpectedEof {
                what: "the 84-byte binary STL header (file is not ASCII STL either: it does not begin with `solid`)".into(),
            },
        )
        .into());
    };
    let body = &data[HEADER + 4..];
    // Some streaming exporters write 0 and never come back to fix the count:
    // then the whole triangle records that follow are the triangles.
    let count = if count == 0 && !body.is_empty() && body.len() % TRIANGLE == 0 {
        u32::try_from(body.len() / TRIANGLE).unwrap_or(u32::MAX)
    } else {
        count
    };
    let needed = u64::from(count) * TRIANGLE as u64;
    if needed > body.len() as u64 {
        return Err(FormatError::new(
            Format::Stl,
            Location::Byte((HEADER + 4 + body.len() / TRIANGLE * TRIANGLE) as u64),
            FormatErrorKind::CountTooLarge {
                what: "triangles".into(),
                count: u64::from(count),
                needed,
                available: body.len() as u64,
            },
        )
        .into());
    }
    // Trailing bytes after the declared triangles are ignored.
    let mut welder = Welder::default();
    let mut triangles = Vec::with_capacity(count as usize);
    for chunk in body.chunks_exact(TRIANGLE).take(count as usize) {
        let f = |k: usize| -> f64 {
            let b = [chunk[k], chunk[k + 1], chunk[k + 2], chunk[k + 3]];
            f64::from(f32::from_le_bytes(b))
        };
        let mut t = [0u32; 3];
        for (c, slot) in t.iter_mut().enumerate() {
            let o = 12 + 12 * c;
            *slot = welder.vertex([f(o), f(o + 4), f(o + 8)]);
        }
        triangles.push(t);
    }
    Ok((welder.positions, triangles))
}

fn read_ascii(data: &[u8]) -> Result<(Vec<Vec3>, Vec<[u32; 3]>)> {
    let err = |line: usize, kind: FormatErrorKind| -> IoError {
        FormatError::new(Format::Stl, Location::Line(line), kind).into()
    };
    let mut welder = Welder::default();
    let mut triangles = Vec::new();
    let mut polygon: Vec<u32> = Vec::new();
    let mut in_facet = false;
    let mut last_line = 0;
    for (line, bytes) in Lines::new(data) {
        last_line = line;
        let bytes = bytes.trim_ascii();
        let end = bytes
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(bytes.len());
        let keyword = &bytes[..end];
        match keyword {
            b"" | b"outer" | b"endloop" => {}
            b"solid" | b"endsolid" => {
                if in_facet {
                    return Err(err(
                        line,
                        FormatErrorKind::Syntax {
                            message: "`solid`/`endsolid` inside a facet (missing endfacet)".into(),
                        },
                    ));
                }
            }
            b"facet" => {
                if in_facet {
                    return Err(err(
                        line,
                        FormatErrorKind::Syntax {
                            message: "a facet inside a facet (missing endfacet)".into(),
                        },
                    ));
                }
                in_facet = true;
                polygon.clear();
            }
            b"vertex" => {
                if !in_facet {
                    return Err(err(
                        line,
                        FormatErrorKind::Syntax {
                            message: "a vertex outside a facet".into(),
                        },
                    ));
                }
                let text =
                    std::str::from_utf8(bytes).map_err(|_| err(line, FormatErrorKind::NotUtf8))?;
                let mut tokens = text.split_ascii_whitespace().skip(1);
                let mut p = [0.0; 3];
                for (k, slot) in p.iter_mut().enumerate() {
                    let token = tokens.next().ok_or_else(|| {
                        err(
                            line,
                            FormatErrorKind::Syntax {
                                message: format!("`vertex` needs 3 coordinates, found {k}"),
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
                polygon.push(welder.vertex(p));
                crate::check_face_size(polygon.len() as u64).map_err(|k| err(line, k))?;
            }
            b"endfacet" => {
                if !in_facet {
                    return Err(err(
                        line,
                        FormatErrorKind::Syntax {
                            message: "`endfacet` without `facet`".into(),
                        },
                    ));
                }
                in_facet = false;
                if polygon.len() < 3 {
                    return Err(err(
                        line,
                        FormatErrorKind::DegenerateFace {
                            count: polygon.len(),
                        },
                    ));
                }
                for k in 1..polygon.len() - 1 {
                    triangles.push([polygon[0], polygon[k], polygon[k + 1]]);
                }
            }
            other => {
                let word = String::from_utf8_lossy(other);
                return Err(err(
                    line,
                    FormatErrorKind::Syntax {
                        message: format!("unexpected {:?} in ASCII STL", excerpt(&word)),
                    },
                ));
            }
        }
    }
    if in_facet {
        return Err(err(
            last_line,
            FormatErrorKind::UnexpectedEof {
                what: "a facet (no endfacet)".into(),
            },
        ));
    }
    Ok((welder.positions, triangles))
}

/// Writes a mesh as binary STL (f32 coordinates; facet normals computed
/// from the corners, zero for a degenerate triangle). The 80-byte header
/// does not begin with "solid", so no reader mistakes the file for ASCII.
/// The mesh is validated first; vertex normals are not stored (STL has none).
pub fn write_mesh<W: Write>(writer: W, mesh: &Mesh) -> Result<()> {
    mesh.validate()?;
    let count = u32::try_from(mesh.triangles.len()).map_err(|_| IoError::WrongKind {
        path: None,
        message: format!(
            "{} triangles do not fit in a binary STL (at most 2^32 − 1)",
            mesh.triangles.len()
        ),
    })?;
    let mut w = BufWriter::new(writer);
    let mut header = [b' '; HEADER];
    let title = b"binary STL written by trigbody";
    header[..title.len()].copy_from_slice(title);
    w.write_all(&header)?;
    w.write_all(&count.to_le_bytes())?;
    let mut record = [0u8; TRIANGLE];
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.triangle(t);
        let n = (b - a).cross(c - a).normalized().unwrap_or(Vec3::ZERO);
        for (k, v) in [n, a, b, c].iter().enumerate() {
            for (j, x) in v.to_array().iter().enumerate() {
                let o = 12 * k + 4 * j;
                record[o..o + 4].copy_from_slice(&(*x as f32).to_le_bytes());
            }
        }
        w.write_all(&record)?;
    }
    w.flush()?;
    Ok(())
}
