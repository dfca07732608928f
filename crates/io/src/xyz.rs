//! Plain-text point lists (`.xyz`, `.txt`, `.csv`): one point a line,
//! `x y z` or `x y z nx ny nz`, separated by whitespace, commas or
//! semicolons. `#` starts a comment. The first data line may be a header of
//! column names (any line whose first field is not a number); then the
//! columns named `x y z` (and `nx ny nz`, also spelled `normal_x` …) are
//! used wherever they are. Without a header, the first three columns are
//! the position and, when a line has six or more, columns 4–6 the normal
//! (unless, on the first line, they look like an 8-bit colour: integers in
//! 0..=255, not all 0 or 1); lines of four or five columns (intensity, …)
//! give positions only. The first data line decides for the whole file.

use crate::error::{FormatError, FormatErrorKind, IoError, Location, Result};
use crate::format::Format;
use crate::geometry::Geometry;
use crate::options::ReadOptions;
use crate::text::{excerpt, is_blank, parse_real, read_all, Lines};
use std::io::{BufWriter, Read, Write};
use trigbody_core::{PointCloud, Vec3};

fn err(line: usize, kind: FormatErrorKind) -> IoError {
    FormatError::new(Format::Xyz, Location::Line(line), kind).into()
}

fn fields(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| c == ',' || c == ';' || c.is_ascii_whitespace())
        .filter(|f| !f.is_empty())
}

/// Column positions of the coordinates and (optionally) the normal.
#[derive(Clone, Copy, Debug)]
struct Columns {
    position: [usize; 3],
    normal: Option<[usize; 3]>,
}

fn columns_from_header(text: &str, line: usize) -> Result<Columns> {
    let names: Vec<String> = fields(text)
        .map(|f| {
            f.trim_matches(|c| c == '"' || c == '\'' || c == '/' || c == '#')
                .to_ascii_lowercase()
                .replace(['_', ' '], "")
        })
        .collect();
    let find = |options: &[&str]| names.iter().position(|n| options.contains(&n.as_str()));
    let position = [
        find(&["x", "px", "posx", "positionx"]),
        find(&["y", "py", "posy", "positiony"]),
        find(&["z", "pz", "posz", "positionz"]),
    ];
    let [Some(x), Some(y), Some(z)] = position else {
        return Err(err(
            line,
            FormatErrorKind::Syntax {
                message: format!(
                    "the header line {:?} does not name columns x, y and z",
                    excerpt(text)
                ),
            },
        ));
    };
    let normal = [
        find(&["nx", "normalx", "normx"]),
        find(&["ny", "normaly", "normy"]),
        find(&["nz", "normalz", "normz"]),
    ];
    let normal = match normal {
        [Some(a), Some(b), Some(c)] => Some([a, b, c]),
        _ => None,
    };
    Ok(Columns {
        position: [x, y, z],
        normal,
    })
}

/// Whether three values look like an 8-bit RGB colour (`x y z r g b`
/// files are common) rather than a normal: integers in 0..=255, not all
/// of them 0 or 1.
fn looks_like_colour(v: &[f64]) -> bool {
    v.iter()
        .all(|c| c.fract() == 0.0 && (0.0..=255.0).contains(c))
        && v.iter().any(|&c| c > 1.0)
}

/// Reads a point list from `reader`.
pub fn read<R: Read>(reader: R, options: &ReadOptions) -> Result<Geometry> {
    read_bytes(&read_all(reader)?, options)
}

/// Reads a point list held in memory.
pub fn read_bytes(data: &[u8], options: &ReadOptions) -> Result<Geometry> {
    if is_blank(data) {
        return Err(FormatError::new(Format::Xyz, Location::File, FormatErrorKind::Empty).into());
    }
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut columns: Option<Columns> = None;
    let mut first_data_line = true;
    let mut values: Vec<f64> = Vec::with_capacity(8);
    for (line, bytes) in Lines::new(data) {
        let text = std::str::from_utf8(bytes).map_err(|_| err(line, FormatErrorKind::NotUtf8))?;
        let text = text.split('#').next().unwrap_or("").trim();
        let text = text.strip_prefix('\u{feff}').unwrap_or(text); // byte-order mark
        if text.is_empty() {
            continue;
        }
        if let Some(rest) = text.strip_prefix("//") {
            // CloudCompare writes its header as `//X,Y,Z,...`.
            if first_data_line && columns_from_header(rest, line).is_ok() {
                columns = Some(columns_from_header(rest, line)?);
                first_data_line = false;
            }
            continue;
        }
        if first_data_line {
            first_data_line = false;
            let first = fields(text).next().unwrap_or("");
            if parse_real(first).is_none() {
                columns = Some(columns_from_header(text, line)?);
                continue;
            }
        }
        values.clear();
        for f in fields(text) {
            values.push(parse_real(f).ok_or_else(|| {
                err(
                    line,
                    FormatErrorKind::InvalidNumber {
                        expected: "a number",
                        value: excerpt(f),
                    },
                )
            })?);
        }
        let cols = match columns {
            Some(c) => c,
            None => {
                // Decided by the first data line, kept for the rest.
                let c = Columns {
                    position: [0, 1, 2],
                    normal: (values.len() >= 6 && !looks_like_colour(&values[3..6]))
                        .then_some([3, 4, 5]),
                };
                columns = Some(c);
                c
            }
        };
        let needed = cols
            .position
            .iter()
            .chain(cols.normal.iter().flatten())
            .max()
            .map_or(3, |m| m + 1);
        if values.len() < needed {
            return Err(err(
                line,
                FormatErrorKind::Syntax {
                    message: format!(
                        "expected at least {needed} values (as in the first line), found {}",
                        values.len()
                    ),
                },
            ));
        }
        positions.push(Vec3::from(cols.position.map(|i| values[i])));
        if let Some(n) = cols.normal {
            normals.push(Vec3::from(n.map(|i| values[i])));
        }
    }
    let with_normals = columns.is_some_and(|c| c.normal.is_some());
    Geometry::build(
        Format::Xyz,
        positions,
        with_normals.then_some(normals),
        Vec::new(),
        options,
    )
}

/// How [`write_points`] separates values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Delimiter {
    /// `x y z [nx ny nz]`, no header (`.xyz`, `.txt`).
    #[default]
    Space,
    /// `x,y,z[,nx,ny,nz]` after a header line of column names (`.csv`).
    Comma,
}

/// Writes points as text, one a line, in the shortest decimal form that
/// reads back to the same f64 (round trips are exact).
pub fn write_points<W: Write>(writer: W, cloud: &PointCloud, delimiter: Delimiter) -> Result<()> {
    cloud.validate()?;
    write_vertices(
        writer,
        &cloud.positions,
        cloud.normals.as_deref(),
        delimiter,
    )
}

/// Writes positions (and normals, same length) as text lines.
pub(crate) fn write_vertices<W: Write>(
    writer: W,
    positions: &[Vec3],
    normals: Option<&[Vec3]>,
    delimiter: Delimiter,
) -> Result<()> {
    let mut w = BufWriter::new(writer);
    let sep = match delimiter {
        Delimiter::Space => " ",
        Delimiter::Comma => ",",
    };
    if delimiter == Delimiter::Comma {
        let names: &[&str] = if normals.is_some() {
            &["x", "y", "z", "nx", "ny", "nz"]
        } else {
            &["x", "y", "z"]
        };
        writeln!(w, "{}", names.join(sep))?;
    }
    for (i, p) in positions.iter().enumerate() {
        write!(w, "{:?}{sep}{:?}{sep}{:?}", p.x, p.y, p.z)?;
        if let Some(n) = normals.and_then(|ns| ns.get(i)) {
            write!(w, "{sep}{:?}{sep}{:?}{sep}{:?}", n.x, n.y, n.z)?;
        }
        writeln!(w)?;
    }
    w.flush()?;
    Ok(())
}
