//! The one error type of the crate, with enough context to find the problem:
//! the file (when reading from a path), the line of a text format or the
//! element and byte offset of a binary one, and the offending value.

use crate::format::Format;
use std::fmt;
use std::path::PathBuf;
use thiserror::Error;
use trigbody_core::MeshError;

/// Where in the input a [`FormatError`] was found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// Nowhere in particular (the whole file, e.g. it is empty).
    File,
    /// A 1-based line number of a text format (or of a PLY header).
    Line(usize),
    /// A byte offset from the start of a binary file.
    Byte(u64),
    /// An element of a PLY body (`vertex 17`, `face 3`), with the byte offset
    /// where it starts for binary bodies or its line for ASCII ones.
    Element {
        /// The element's name in the header.
        element: String,
        /// 0-based index of the element instance.
        index: u64,
        /// Byte offset (binary) or 1-based line (ASCII) where it starts.
        at: ElementPosition,
    },
}

/// Position of a PLY element instance in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementPosition {
    /// Byte offset from the start of the file (binary PLY).
    Byte(u64),
    /// 1-based line number (ASCII PLY).
    Line(usize),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::File => Ok(()),
            Location::Line(l) => write!(f, "line {l}"),
            Location::Byte(b) => write!(f, "byte {b}"),
            Location::Element { element, index, at } => {
                write!(f, "{element} {index} (")?;
                match at {
                    ElementPosition::Byte(b) => write!(f, "byte {b})"),
                    ElementPosition::Line(l) => write!(f, "line {l})"),
                }
            }
        }
    }
}

/// What exactly is wrong with the bytes of a file.
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum FormatErrorKind {
    /// The input has no bytes, or no geometry at all.
    #[error("the file is empty (no vertices); check that it was written completely")]
    Empty,
    /// The input ends before the data that the header or syntax promises.
    #[error("unexpected end of file while reading {what}: the file is truncated or its header lies about the counts")]
    UnexpectedEof {
        /// What was being read.
        what: String,
    },
    /// A text line is not valid UTF-8.
    #[error("the line is not valid UTF-8 text; is this a binary file or a different encoding?")]
    NotUtf8,
    /// A token that should be a number is not one.
    #[error("expected {expected}, found {value:?}")]
    InvalidNumber {
        /// What kind of number was expected.
        expected: &'static str,
        /// The offending text.
        value: String,
    },
    /// A statement or line has the wrong number of values.
    #[error("{message}")]
    Syntax {
        /// A description of the problem, naming the value.
        message: String,
    },
    /// A face refers to a vertex (or normal) that does not exist.
    #[error("{what} index {index} is out of range: {count} defined{}", if *.index <= 0 { " (OBJ indices start at 1; negative ones count back from the last)" } else { "" })]
    IndexOutOfRange {
        /// "vertex", "normal" or "texture coordinate".
        what: &'static str,
        /// The index as written in the file.
        index: i64,
        /// How many exist at that point.
        count: usize,
    },
    /// A face has fewer than three corners.
    #[error("a face needs at least 3 vertices, this one has {count}")]
    DegenerateFace {
        /// Number of corners in the face.
        count: usize,
    },
    /// A face has more corners than any body mesh needs (a bound against
    /// files that would take minutes and gigabytes to triangulate).
    #[error(
        "a face has {count} corners, more than the {max} allowed; split it into smaller faces"
    )]
    FaceTooLarge {
        /// Corners of the face (counted up to `max + 1` for text formats).
        count: u64,
        /// The largest face allowed, [`crate::MAX_FACE_CORNERS`].
        max: usize,
    },
    /// The PLY magic number is missing.
    #[error("not a PLY file: it does not start with \"ply\"")]
    NotPly,
    /// The PLY `format` line names an unknown format.
    #[error("unknown PLY format {value:?}: expected ascii, binary_little_endian or binary_big_endian (version 1.0)")]
    UnknownPlyFormat {
        /// The format string found.
        value: String,
    },
    /// A PLY property has a type that is not one of the PLY scalar types.
    #[error("unknown PLY property type {value:?}: expected one of char uchar short ushort int uint float double (or int8 ... float64)")]
    UnknownPropertyType {
        /// The type name found.
        value: String,
    },
    /// The PLY header is malformed.
    #[error("bad PLY header: {message}")]
    BadHeader {
        /// What is wrong, naming the value.
        message: String,
    },
    /// A count in a header is impossible for the size of the file.
    #[error("the header declares {count} {what}, which need at least {needed} bytes, but only {available} remain; the header lies or the file is truncated")]
    CountTooLarge {
        /// What is being counted.
        what: String,
        /// The declared count.
        count: u64,
        /// Minimum bytes needed (saturating).
        needed: u64,
        /// Bytes actually left in the input.
        available: u64,
    },
}

/// A file whose content does not follow its format.
#[derive(Clone, Debug, PartialEq, Error)]
#[error("{}{format} file{}{}: {kind}",
    .file.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default(),
    if matches!(.location, Location::File) { "" } else { ", " },
    .location)]
pub struct FormatError {
    /// The file, when read through a path function.
    pub file: Option<PathBuf>,
    /// The format being read.
    pub format: Format,
    /// Where in the file.
    pub location: Location,
    /// What is wrong.
    pub kind: FormatErrorKind,
}

impl FormatError {
    pub(crate) fn new(format: Format, location: Location, kind: FormatErrorKind) -> Self {
        FormatError {
            file: None,
            format,
            location,
            kind,
        }
    }
}

/// Every error of reading or writing geometry.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum IoError {
    /// The operating system could not read or write.
    #[error("{}{source}", .path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    Io {
        /// The file, when known.
        path: Option<PathBuf>,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The bytes do not follow the format (boxed: it is the large variant).
    #[error(transparent)]
    Format(Box<FormatError>),
    /// The file was read but its geometry is unusable (e.g. a NaN coordinate);
    /// the message names the vertex.
    #[error("{}invalid geometry: {source}", .file.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    InvalidGeometry {
        /// The file, when known.
        file: Option<PathBuf>,
        /// What the core's validation found.
        #[source]
        source: MeshError,
    },
    /// The path's extension does not name a supported format.
    #[error("{}: unknown file extension; use .obj, .ply, .stl, .xyz, .csv or .txt", .path.display())]
    UnknownExtension {
        /// The path.
        path: PathBuf,
    },
    /// A path writer was told not to overwrite, and the file exists.
    #[error("{}: the file already exists; choose another name or allow overwriting", .path.display())]
    AlreadyExists {
        /// The path.
        path: PathBuf,
    },
    /// A mesh was asked for but the file holds only points, or the format
    /// cannot hold what is being written (points to STL).
    #[error("{}{message}", .path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    WrongKind {
        /// The file, when known.
        path: Option<PathBuf>,
        /// What was expected and found.
        message: String,
    },
}

impl IoError {
    /// Attaches a file name to the error when it has none yet.
    pub fn with_path(self, path: impl Into<PathBuf>) -> Self {
        let p = path.into();
        match self {
            IoError::Io { path: None, source } => IoError::Io {
                path: Some(p),
                source,
            },
            IoError::Format(mut e) => {
                if e.file.is_none() {
                    e.file = Some(p);
                }
                IoError::Format(e)
            }
            IoError::InvalidGeometry { file: None, source } => IoError::InvalidGeometry {
                file: Some(p),
                source,
            },
            IoError::WrongKind {
                path: None,
                message,
            } => IoError::WrongKind {
                path: Some(p),
                message,
            },
            other => other,
        }
    }

    /// The format error inside, if this is one.
    pub fn format_error(&self) -> Option<&FormatError> {
        match self {
            IoError::Format(e) => Some(e),
            _ => None,
        }
    }
}

impl From<FormatError> for IoError {
    fn from(e: FormatError) -> Self {
        IoError::Format(Box::new(e))
    }
}

impl From<std::io::Error> for IoError {
    fn from(source: std::io::Error) -> Self {
        IoError::Io { path: None, source }
    }
}

impl From<MeshError> for IoError {
    fn from(source: MeshError) -> Self {
        IoError::InvalidGeometry { file: None, source }
    }
}

/// The crate's result type.
pub type Result<T, E = IoError> = std::result::Result<T, E>;
