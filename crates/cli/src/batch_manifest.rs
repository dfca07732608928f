//! `trigbody batch --manifest inputs.csv`: one row per input with its own
//! options, so that a folder of files in mixed units and axes runs in one
//! command.
//!
//! The CSV has a header naming its columns: `path` (required; relative to
//! the manifest's folder), and optionally `units` (m, cm, mm or auto),
//! `up` and `front` (x, -y, … or three numbers). An empty cell, or a column
//! left out, takes the command line's value. Other columns are ignored (a
//! manifest may carry notes); a bad value is refused before any input is
//! read, naming the line and the value.

use crate::cmd_reconstruct::{parse_direction, UnitsFlag};
use crate::exit::bad;
use anyhow::Result;
use clap::ValueEnum;
use std::path::{Path, PathBuf};
use trigbody_core::{ReconstructOptions, Vec3};

/// One input's options beyond the command line's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    pub units: Option<UnitsFlag>,
    pub up: Option<Vec3>,
    pub front: Option<Vec3>,
}

impl Overrides {
    /// `base` with these options put in.
    pub fn apply(&self, base: &ReconstructOptions) -> ReconstructOptions {
        let mut o = *base;
        if let Some(u) = self.units {
            o.units = u.units().unwrap_or_default();
            o.infer_units = u == UnitsFlag::Auto;
        }
        if let Some(up) = self.up {
            o.segment.up = Some(up);
        }
        if let Some(front) = self.front {
            o.segment.front = Some(front);
        }
        o
    }
}

/// The inputs a manifest names, each with its options, in its order.
pub fn read_manifest(path: &Path) -> Result<Vec<(PathBuf, Overrides)>> {
    let file = path.display();
    let text = std::fs::read(path).map_err(|e| bad(format!("{file}: {e}")))?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(&text[..]);
    let header = reader
        .headers()
        .map_err(|e| bad(format!("{file}: {e}")))?
        .clone();
    let column = |name: &str| header.iter().position(|h| h.eq_ignore_ascii_case(name));
    let Some(path_at) = column("path") else {
        return Err(bad(format!(
            "{file} line 1: no `path` column (the header names {:?}; columns: path, and \
             optionally units, up, front)",
            header.iter().collect::<Vec<_>>()
        )));
    };
    let (units_at, up_at, front_at) = (column("units"), column("up"), column("front"));
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| bad(format!("{file}: {e}")))?;
        let line = record.position().map_or(0, |p| p.line());
        let cell = |at: Option<usize>| at.and_then(|i| record.get(i)).filter(|s| !s.is_empty());
        let at_line = |what: &str, value: &str, why: &str| {
            bad(format!("{file} line {line}: {what} '{value}' {why}"))
        };
        let Some(input) = cell(Some(path_at)) else {
            return Err(bad(format!("{file} line {line}: the path is empty")));
        };
        let units = cell(units_at)
            .map(|u| {
                UnitsFlag::from_str(u, true)
                    .map_err(|_| at_line("units", u, "is not m, cm, mm or auto"))
            })
            .transpose()?;
        let direction = |what: &str, at: Option<usize>| {
            cell(at)
                .map(|s| {
                    parse_direction(s).map_err(|e| at_line(what, s, &format!("is wrong: {e}")))
                })
                .transpose()
        };
        let overrides = Overrides {
            units,
            up: direction("up", up_at)?,
            front: direction("front", front_at)?,
        };
        rows.push((folder.join(input), overrides));
    }
    if rows.is_empty() {
        return Err(bad(format!("{file}: no input rows under the header")));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifest(name: &str, text: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("trigbody-manifest-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn rows_take_their_own_options_and_paths_beside_the_manifest() {
        let p = manifest(
            "a.csv",
            "path,units,up,note\nbody_a.ply,mm,z,lying\n\"b, c.obj\",,,\nd.ply,auto,-y,\n",
        );
        let rows = read_manifest(&p).unwrap();
        let folder = p.parent().unwrap();
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[0].0, folder.join("body_a.ply"));
        assert_eq!(rows[0].1.units, Some(UnitsFlag::Mm));
        assert_eq!(rows[0].1.up, Some(Vec3::Z));
        assert_eq!(rows[1].0, folder.join("b, c.obj"));
        assert_eq!(rows[1].1, Overrides::default());
        assert_eq!(rows[2].1.units, Some(UnitsFlag::Auto));
        let o = rows[2].1.apply(&ReconstructOptions::default());
        assert!(o.infer_units && o.segment.up == Some(-Vec3::Y));
    }

    #[test]
    fn a_bad_value_names_the_line_and_the_value() {
        let p = manifest("b.csv", "path,units\na.ply,m\nb.ply,inch\n");
        let e = read_manifest(&p).unwrap_err().to_string();
        assert!(
            e.contains("b.csv line 3: units 'inch' is not m, cm, mm or auto"),
            "{e}"
        );
        let p = manifest("c.csv", "file,units\na.ply,m\n");
        let e = read_manifest(&p).unwrap_err().to_string();
        assert!(e.contains("line 1: no `path` column"), "{e}");
        let p = manifest("d.csv", "path,up\na.ply,0,0,0\n");
        assert!(read_manifest(&p).is_err());
        let p = manifest("e.csv", "path,up\na.ply,sideways\n");
        let e = read_manifest(&p).unwrap_err().to_string();
        assert!(e.contains("line 2: up 'sideways'"), "{e}");
        let p = manifest("f.csv", "path\n");
        assert!(read_manifest(&p)
            .unwrap_err()
            .to_string()
            .contains("no input rows"));
    }
}
