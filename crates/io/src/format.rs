//! The supported file formats and how a path's extension picks one.

use std::fmt;
use std::path::Path;

/// A geometry file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Wavefront OBJ (text).
    Obj,
    /// Stanford PLY (ASCII or binary).
    Ply,
    /// STL (ASCII or binary).
    Stl,
    /// Plain-text point list: `x y z [nx ny nz]`, whitespace or comma
    /// separated (`.xyz`, `.txt`, `.csv`).
    Xyz,
}

impl Format {
    /// The format named by a path's extension, case-insensitive:
    /// `.obj`, `.ply`, `.stl`, `.xyz`, `.csv`, `.txt`.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Format::Obj),
            "ply" => Some(Format::Ply),
            "stl" => Some(Format::Stl),
            "xyz" | "csv" | "txt" => Some(Format::Xyz),
            _ => None,
        }
    }

    /// Whether a path's extension is `.csv` (written comma-separated with a
    /// header line).
    pub(crate) fn is_csv(path: &Path) -> bool {
        path.extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::Ply => "PLY",
            Format::Stl => "STL",
            Format::Xyz => "XYZ",
        })
    }
}
