//! Plain-text loops: one point per line as `x y` or `x y z`, separated by
//! whitespace and/or commas; `#` starts a comment; blank lines are skipped.
//! Every point line must have the same number of coordinates.

use std::io::Read;
use thiserror::Error;
use trigbody_core::{Point3, Real, Vec2, Vec3};

/// A loop read from text: 2D or 3D points in file order.
#[derive(Clone, Debug, PartialEq)]
pub enum LoopPoints {
    /// `x y` lines: a loop in the xy plane.
    Planar(Vec<Vec2>),
    /// `x y z` lines.
    Spatial(Vec<Point3>),
}

impl LoopPoints {
    /// The number of points.
    pub fn len(&self) -> usize {
        match self {
            LoopPoints::Planar(p) => p.len(),
            LoopPoints::Spatial(p) => p.len(),
        }
    }
    /// True when there are no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// What is wrong with a loop file; messages name the source and the line.
#[derive(Debug, Error)]
pub enum LoopTextError {
    /// The source could not be read.
    #[error("{source_name}: cannot read: {error}")]
    Io {
        /// The path, or `-` for standard input.
        source_name: String,
        /// The underlying error.
        error: std::io::Error,
    },
    /// The bytes are not UTF-8 text.
    #[error("{source_name}: the text is not valid UTF-8 (byte {offset})")]
    NotUtf8 {
        /// The path, or `-`.
        source_name: String,
        /// Offset of the first invalid byte.
        offset: usize,
    },
    /// A token that is not a number.
    #[error("{source_name}:{line}: '{token}' is not a number")]
    NotANumber {
        /// The path, or `-`.
        source_name: String,
        /// 1-based line number.
        line: usize,
        /// The offending text.
        token: String,
    },
    /// NaN or an infinity.
    #[error("{source_name}:{line}: '{token}' is not finite; remove or repair the point")]
    NotFinite {
        /// The path, or `-`.
        source_name: String,
        /// 1-based line number.
        line: usize,
        /// The offending text.
        token: String,
    },
    /// A line with other than 2 or 3 numbers.
    #[error("{source_name}:{line}: expected 2 (x y) or 3 (x y z) coordinates, found {found}")]
    BadCount {
        /// The path, or `-`.
        source_name: String,
        /// 1-based line number.
        line: usize,
        /// How many numbers the line has.
        found: usize,
    },
    /// 2D and 3D points mixed in one loop.
    #[error("{source_name}:{line}: {found} coordinates, but the first point (line {first_line}) has {expected}; use one form for the whole loop")]
    MixedDimensions {
        /// The path, or `-`.
        source_name: String,
        /// 1-based line number.
        line: usize,
        /// Coordinates on this line.
        found: usize,
        /// Coordinates on the first point's line.
        expected: usize,
        /// The first point's line.
        first_line: usize,
    },
}

/// Reads a loop from `reader`; `source_name` (a path, or `-` for standard
/// input) is used in error messages.
pub fn read_loop(mut reader: impl Read, source_name: &str) -> Result<LoopPoints, LoopTextError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|error| LoopTextError::Io {
            source_name: source_name.to_string(),
            error,
        })?;
    let text = std::str::from_utf8(&bytes).map_err(|e| LoopTextError::NotUtf8 {
        source_name: source_name.to_string(),
        offset: e.valid_up_to(),
    })?;
    parse_loop(text, source_name)
}

/// Parses loop text (see the module docs).
pub fn parse_loop(text: &str, source_name: &str) -> Result<LoopPoints, LoopTextError> {
    let name = || source_name.to_string();
    let mut coords: Vec<[Real; 3]> = Vec::new();
    let mut dim: Option<(usize, usize)> = None; // (coordinates, first line)
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let mut values = [0.0; 3];
        let mut count = 0;
        for token in content
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
        {
            let value: Real = token.parse().map_err(|_| LoopTextError::NotANumber {
                source_name: name(),
                line,
                token: token.to_string(),
            })?;
            if !value.is_finite() {
                return Err(LoopTextError::NotFinite {
                    source_name: name(),
                    line,
                    token: token.to_string(),
                });
            }
            if count < 3 {
                values[count] = value;
            }
            count += 1;
        }
        if !(2..=3).contains(&count) {
            return Err(LoopTextError::BadCount {
                source_name: name(),
                line,
                found: count,
            });
        }
        match dim {
            None => dim = Some((count, line)),
            Some((expected, first_line)) if expected != count => {
                return Err(LoopTextError::MixedDimensions {
                    source_name: name(),
                    line,
                    found: count,
                    expected,
                    first_line,
                })
            }
            _ => {}
        }
        coords.push(values);
    }
    Ok(match dim {
        Some((3, _)) => LoopPoints::Spatial(coords.iter().map(|c| Vec3::from(*c)).collect()),
        _ => LoopPoints::Planar(coords.iter().map(|c| Vec2::new(c[0], c[1])).collect()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_both_forms_with_comments_and_commas() {
        let t = "# a comment\n1, 2\n\n3 4 # trailing\n5,6\n";
        assert_eq!(
            parse_loop(t, "t").unwrap(),
            LoopPoints::Planar(vec![
                Vec2::new(1., 2.),
                Vec2::new(3., 4.),
                Vec2::new(5., 6.)
            ])
        );
        let t = "1 2 3\n4,5,6\n";
        assert_eq!(parse_loop(t, "t").unwrap().len(), 2);
        assert!(parse_loop("", "t").unwrap().is_empty());
    }

    #[test]
    fn names_the_line_of_bad_text() {
        let e = parse_loop("1 2\n3 x\n", "loop.txt").unwrap_err();
        assert_eq!(e.to_string(), "loop.txt:2: 'x' is not a number");
        let e = parse_loop("1 2\n3 nan\n", "f").unwrap_err();
        assert!(matches!(e, LoopTextError::NotFinite { line: 2, .. }), "{e}");
        let e = parse_loop("1 2\n3 4 5\n", "f").unwrap_err();
        assert!(
            matches!(e, LoopTextError::MixedDimensions { line: 2, .. }),
            "{e}"
        );
        let e = parse_loop("1\n", "f").unwrap_err();
        assert!(matches!(e, LoopTextError::BadCount { found: 1, .. }), "{e}");
        let e = read_loop(&[0x31, 0x20, 0xff, 0x0a][..], "f").unwrap_err();
        assert!(matches!(e, LoopTextError::NotUtf8 { offset: 2, .. }), "{e}");
    }
}
