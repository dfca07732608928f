//! Stanford PLY: ASCII, binary little endian and binary big endian.
//!
//! Reading takes positions from the `vertex` element's `x y z` (any scalar
//! type), normals from `nx ny nz` when all three are present, and faces
//! from the `face` element's `vertex_indices` (or `vertex_index`) list, with
//! any integer count and index types; polygons are fan-triangulated. Every
//! other element and property is skipped. A file with no faces is a point
//! cloud.
//!
//! Hand-written rather than built on `ply-rs-bw`: binary PLY is simple, and
//! this reader works on the whole input in memory, checks every count from
//! the header against the bytes actually present before allocating (a lying
//! header cannot request terabytes), reports the element and byte offset of
//! a truncation, never panics, and reads a 200 000-point scan at several
//! hundred MB/s.

use crate::error::{ElementPosition, FormatError, FormatErrorKind, IoError, Location, Result};
use crate::format::Format;
use crate::geometry::Geometry;
use crate::options::{PlyPrecision, ReadOptions, WriteOptions};
use crate::text::{excerpt, read_all, Lines};
use std::io::{BufWriter, Read, Write};
use trigbody_core::{Mesh, PointCloud, Vec3};

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// A property's type: one scalar, or a list with a count type and an item type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// What the reader does with a property's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Slot {
    Coord(usize),
    Normal(usize),
    FaceIndices,
    Skip,
}

#[derive(Debug)]
struct Property {
    name: String,
    kind: Kind,
    slot: Slot,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
    role: Role,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Vertex,
    Face,
    Other,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    LittleEndian,
    BigEndian,
}

#[derive(Debug)]
struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    /// Byte offset of the body.
    body: usize,
    /// Line number of the last header line (ASCII bodies count on from it).
    lines: usize,
}

fn header_err(line: usize, kind: FormatErrorKind) -> IoError {
    FormatError::new(Format::Ply, Location::Line(line), kind).into()
}

fn bad_header(line: usize, message: String) -> IoError {
    header_err(line, FormatErrorKind::BadHeader { message })
}

fn parse_header(data: &[u8]) -> Result<Header> {
    if data.is_empty() {
        return Err(FormatError::new(Format::Ply, Location::File, FormatErrorKind::Empty).into());
    }
    let mut lines = Lines::new(data);
    match lines.next() {
        Some((_, magic)) if magic.trim_ascii_end() == b"ply" => {}
        _ => return Err(header_err(1, FormatErrorKind::NotPly)),
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some((line, bytes)) = lines.next() else {
            return Err(FormatError::new(
                Format::Ply,
                Location::Line(data.iter().filter(|&&b| b == b'\n').count() + 1),
                FormatErrorKind::UnexpectedEof {
                    what: "the header (no end_header line)".into(),
                },
            )
            .into());
        };
        if bytes.starts_with(b"comment") || bytes.starts_with(b"obj_info") {
            continue; // free text, any encoding
        }
        let text =
            std::str::from_utf8(bytes).map_err(|_| header_err(line, FormatErrorKind::NotUtf8))?;
        let mut tokens = text.split_ascii_whitespace();
        match tokens.next() {
            None => continue,
            Some("end_header") => {
                let encoding = encoding
                    .ok_or_else(|| bad_header(line, "no `format` line before end_header".into()))?;
                if !elements.iter().any(|e| e.role == Role::Vertex) {
                    return Err(bad_header(line, "no `vertex` element".into()));
                }
                return Ok(Header {
                    encoding,
                    elements,
                    body: lines.offset(),
                    lines: line,
                });
            }
            Some("format") => encoding = Some(parse_format(line, text, &mut tokens)?),
            Some("element") => {
                let element = parse_element(line, text, &mut tokens, &elements)?;
                elements.push(element);
            }
            Some("property") => {
                let Some(element) = elements.last_mut() else {
                    return Err(bad_header(line, "a property before any element".into()));
                };
                element.properties.push(parse_property(line, &mut tokens)?);
            }
            Some(other) => {
                return Err(bad_header(
                    line,
                    format!("unknown header keyword {:?}", excerpt(other)),
                ))
            }
        }
    }
}

/// The encoding of a `format <name> <version>` header line.
fn parse_format(
    line: usize,
    text: &str,
    tokens: &mut std::str::SplitAsciiWhitespace<'_>,
) -> Result<Encoding> {
    let name = tokens.next().unwrap_or("");
    let version = tokens.next().unwrap_or("");
    let encoding = match name {
        "ascii" => Encoding::Ascii,
        "binary_little_endian" => Encoding::LittleEndian,
        "binary_big_endian" => Encoding::BigEndian,
        _ => {
            return Err(header_err(
                line,
                FormatErrorKind::UnknownPlyFormat {
                    value: excerpt(text.trim()),
                },
            ))
        }
    };
    if !version.starts_with('1') {
        return Err(header_err(
            line,
            FormatErrorKind::UnknownPlyFormat {
                value: excerpt(text.trim()),
            },
        ));
    }
    Ok(encoding)
}

/// The element of an `element <name> <count>` header line (a second vertex
/// or face element is refused).
fn parse_element(
    line: usize,
    text: &str,
    tokens: &mut std::str::SplitAsciiWhitespace<'_>,
    elements: &[Element],
) -> Result<Element> {
    let (Some(name), Some(count)) = (tokens.next(), tokens.next()) else {
        return Err(bad_header(
            line,
            format!(
                "expected `element <name> <count>`, found {:?}",
                excerpt(text)
            ),
        ));
    };
    let count: u64 = count.parse().map_err(|_| {
        header_err(
            line,
            FormatErrorKind::InvalidNumber {
                expected: "an element count",
                value: excerpt(count),
            },
        )
    })?;
    let role = if name.eq_ignore_ascii_case("vertex") {
        Role::Vertex
    } else if name.eq_ignore_ascii_case("face") {
        Role::Face
    } else {
        Role::Other
    };
    if role != Role::Other && elements.iter().any(|e| e.role == role) {
        return Err(bad_header(line, format!("a second `{name}` element")));
    }
    Ok(Element {
        name: name.to_string(),
        count,
        properties: Vec::new(),
        role,
    })
}

/// The property of a `property <type> <name>` or `property list <count
/// type> <item type> <name>` header line.
fn parse_property(
    line: usize,
    tokens: &mut std::str::SplitAsciiWhitespace<'_>,
) -> Result<Property> {
    let scalar = |name: Option<&str>| -> Result<Scalar> {
        let name = name.unwrap_or("");
        Scalar::parse(name).ok_or_else(|| {
            header_err(
                line,
                FormatErrorKind::UnknownPropertyType {
                    value: excerpt(name),
                },
            )
        })
    };
    let first = tokens.next();
    let kind = if first == Some("list") {
        let count = scalar(tokens.next())?;
        let item = scalar(tokens.next())?;
        if !count.is_integer() {
            return Err(bad_header(
                line,
                "the count type of a list must be an integer type".into(),
            ));
        }
        Kind::List { count, item }
    } else {
        Kind::Scalar(scalar(first)?)
    };
    let Some(name) = tokens.next() else {
        return Err(bad_header(line, "a property without a name".into()));
    };
    Ok(Property {
        name: name.to_string(),
        kind,
        slot: Slot::Skip,
    })
}

/// Decides which property feeds what; returns whether normals are present.
fn assign_slots(elements: &mut [Element]) -> Result<bool> {
    let mut normals = false;
    for element in elements.iter_mut() {
        match element.role {
            Role::Vertex => {
                let find = |name: &str| element.properties.iter().position(|p| p.name == name);
                let coords = ["x", "y", "z"].map(find);
                let normal = ["nx", "ny", "nz"].map(find);
                for (k, c) in coords.iter().enumerate() {
                    let Some(i) = *c else {
                        return Err(FormatError::new(
                            Format::Ply,
                            Location::File,
                            FormatErrorKind::BadHeader {
                                message: format!(
                                    "the vertex element has no `{}` property",
                                    ["x", "y", "z"][k]
                                ),
                            },
                        )
                        .into());
                    };
                    if !matches!(element.properties[i].kind, Kind::Scalar(_)) {
                        return Err(FormatError::new(
                            Format::Ply,
                            Location::File,
                            FormatErrorKind::BadHeader {
                                message: format!(
                                    "vertex property `{}` is a list",
                                    ["x", "y", "z"][k]
                                ),
                            },
                        )
                        .into());
                    }
                    element.properties[i].slot = Slot::Coord(k);
                }
                if normal.iter().all(|n| {
                    n.is_some_and(|i| matches!(element.properties[i].kind, Kind::Scalar(_)))
                }) {
                    normals = true;
                    for (k, n) in normal.iter().enumerate() {
                        if let Some(i) = *n {
                            element.properties[i].slot = Slot::Normal(k);
                        }
                    }
                }
            }
            Role::Face => {
                let lists: Vec<usize> = element
                    .properties
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| matches!(p.kind, Kind::List { item, .. } if item.is_integer()))
                    .map(|(i, _)| i)
                    .collect();
                let named = lists.iter().copied().find(|&i| {
                    matches!(
                        element.properties[i].name.as_str(),
                        "vertex_indices" | "vertex_index"
                    )
                });
                // Any single integer list is taken as the indices.
                match named.or((lists.len() == 1).then(|| lists[0])) {
                    Some(i) => element.properties[i].slot = Slot::FaceIndices,
                    None if element.count > 0 => {
                        return Err(FormatError::new(
                            Format::Ply,
                            Location::File,
                            FormatErrorKind::BadHeader {
                                message: format!(
                                    "the face element has no integer list `vertex_indices` (its properties: {})",
                                    element
                                        .properties
                                        .iter()
                                        .map(|p| p.name.as_str())
                                        .collect::<Vec<_>>()
                                        .join(", ")
                                ),
                            },
                        )
                        .into())
                    }
                    None => {}
                }
            }
            Role::Other => {}
        }
    }
    Ok(normals)
}

/// Everything the body readers fill.
#[derive(Debug, Default)]
struct Sink {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    /// Whether the vertex element has `nx ny nz`.
    with_normals: bool,
    triangles: Vec<[u32; 3]>,
    vertex_count: u64,
    polygon: Vec<u32>,
}

impl Sink {
    /// Adds a polygon's triangles (fan) once its indices are in `polygon`.
    fn finish_polygon(&mut self) -> std::result::Result<(), FormatErrorKind> {
        let p = &self.polygon;
        if p.len() < 3 {
            return Err(FormatErrorKind::DegenerateFace { count: p.len() });
        }
        for k in 1..p.len() - 1 {
            self.triangles.push([p[0], p[k], p[k + 1]]);
        }
        Ok(())
    }

    fn index(&self, value: i64) -> std::result::Result<u32, FormatErrorKind> {
        if value < 0 || value as u64 >= self.vertex_count {
            return Err(FormatErrorKind::IndexOutOfRange {
                what: "vertex",
                index: value,
                count: usize::try_from(self.vertex_count).unwrap_or(usize::MAX),
            });
        }
        u32::try_from(value).map_err(|_| FormatErrorKind::IndexOutOfRange {
            what: "vertex",
            index: value,
            count: usize::try_from(self.vertex_count).unwrap_or(usize::MAX),
        })
    }
}

/// Reads a PLY file from `reader`.
pub fn read<R: Read>(reader: R, options: &ReadOptions) -> Result<Geometry> {
    read_bytes(&read_all(reader)?, options)
}

/// Reads a PLY file held in memory.
pub fn read_bytes(data: &[u8], options: &ReadOptions) -> Result<Geometry> {
    let mut header = parse_header(data)?;
    let with_normals = assign_slots(&mut header.elements)?;
    let mut sink = Sink {
        vertex_count: header
            .elements
            .iter()
            .find(|e| e.role == Role::Vertex)
            .map_or(0, |e| e.count),
        with_normals,
        ..Sink::default()
    };
    let body = data.get(header.body..).unwrap_or(&[]);
    match header.encoding {
        Encoding::Ascii => read_ascii(&header, body, &mut sink)?,
        Encoding::LittleEndian => read_binary::<false>(&header, data, &mut sink)?,
        Encoding::BigEndian => read_binary::<true>(&header, data, &mut sink)?,
    }
    let normals = sink.with_normals.then_some(sink.normals);
    Geometry::build(
        Format::Ply,
        sink.positions,
        normals,
        sink.triangles,
        options,
    )
}

/// A bounds-checked cursor over a binary body.
struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
}

impl Cursor<'_> {
    #[inline]
    fn take<const N: usize>(&mut self) -> Option<[u8; N]> {
        let end = self.pos.checked_add(N)?;
        let bytes: [u8; N] = self.data.get(self.pos..end)?.try_into().ok()?;
        self.pos = end;
        Some(bytes)
    }

    #[inline]
    fn real<const BIG: bool>(&mut self, s: Scalar) -> Option<f64> {
        macro_rules! num {
            ($t:ty, $n:literal) => {{
                let b = self.take::<$n>()?;
                if BIG {
                    <$t>::from_be_bytes(b)
                } else {
                    <$t>::from_le_bytes(b)
                }
            }};
        }
        Some(match s {
            Scalar::I8 => f64::from(num!(i8, 1)),
            Scalar::U8 => f64::from(num!(u8, 1)),
            Scalar::I16 => f64::from(num!(i16, 2)),
            Scalar::U16 => f64::from(num!(u16, 2)),
            Scalar::I32 => f64::from(num!(i32, 4)),
            Scalar::U32 => f64::from(num!(u32, 4)),
            Scalar::F32 => f64::from(num!(f32, 4)),
            Scalar::F64 => num!(f64, 8),
        })
    }

    /// An integer value; `None` at the end of input. Float types are read
    /// and truncated only when integral (otherwise `Some(Err)`).
    #[inline]
    fn int<const BIG: bool>(&mut self, s: Scalar) -> Option<std::result::Result<i64, f64>> {
        macro_rules! num {
            ($t:ty, $n:literal) => {{
                let b = self.take::<$n>()?;
                i64::from(if BIG {
                    <$t>::from_be_bytes(b)
                } else {
                    <$t>::from_le_bytes(b)
                })
            }};
        }
        Some(Ok(match s {
            Scalar::I8 => num!(i8, 1),
            Scalar::U8 => num!(u8, 1),
            Scalar::I16 => num!(i16, 2),
            Scalar::U16 => num!(u16, 2),
            Scalar::I32 => num!(i32, 4),
            Scalar::U32 => num!(u32, 4),
            Scalar::F32 | Scalar::F64 => {
                let v = self.real::<BIG>(s)?;
                return Some(Err(v));
            }
        }))
    }

    #[inline]
    fn skip(&mut self, bytes: u64) -> Option<()> {
        let end = self.pos.checked_add(usize::try_from(bytes).ok()?)?;
        if end > self.data.len() {
            return None;
        }
        self.pos = end;
        Some(())
    }
}

/// The smallest number of bytes one instance of `element` can take.
fn min_size(element: &Element) -> u64 {
    element
        .properties
        .iter()
        .map(|p| match p.kind {
            Kind::Scalar(s) => s.size() as u64,
            Kind::List { count, .. } => count.size() as u64,
        })
        .sum()
}

fn read_binary<const BIG: bool>(header: &Header, data: &[u8], sink: &mut Sink) -> Result<()> {
    let mut cur = Cursor {
        data,
        pos: header.body,
    };
    for element in &header.elements {
        let min = min_size(element);
        if min == 0 {
            continue; // nothing stored per instance, however many
        }
        let available = (data.len() - cur.pos.min(data.len())) as u64;
        let all_scalar = element
            .properties
            .iter()
            .all(|p| matches!(p.kind, Kind::Scalar(_)));
        let needed = element.count.saturating_mul(min);
        if all_scalar && needed > available {
            // Fixed size: the first instance that cannot be complete is known.
            let index = available / min;
            return Err(FormatError::new(
                Format::Ply,
                Location::Element {
                    element: element.name.clone(),
                    index,
                    at: ElementPosition::Byte(cur.pos as u64 + index * min),
                },
                FormatErrorKind::CountTooLarge {
                    what: format!("`{}` elements", element.name),
                    count: element.count,
                    needed,
                    available,
                },
            )
            .into());
        }
        // Never reserve more than the bytes left could hold; an element with
        // lists that claims more runs out of input at a known instance below
        // (every instance takes at least `min` ≥ 1 bytes, so that is soon).
        let cap = usize::try_from(element.count.min(available / min)).unwrap_or(0);
        match element.role {
            Role::Vertex => {
                sink.positions.reserve_exact(cap);
                if sink.with_normals {
                    sink.normals.reserve_exact(cap);
                }
            }
            Role::Face => sink.triangles.reserve(cap),
            Role::Other => {}
        }
        if element.role == Role::Other && all_scalar {
            // Unused and fixed size: skip in one step (checked above).
            cur.pos += cap * min as usize;
            continue;
        }
        if element.role == Role::Vertex && all_scalar {
            // Fixed-size records, all present (checked above): the fast path.
            let bytes = &data[cur.pos..cur.pos + cap * min as usize];
            read_vertex_records::<BIG>(element, bytes, min as usize, sink);
            cur.pos += bytes.len();
            continue;
        }
        for index in 0..element.count {
            let start = cur.pos;
            let at = |kind: FormatErrorKind| -> IoError {
                FormatError::new(
                    Format::Ply,
                    Location::Element {
                        element: element.name.clone(),
                        index,
                        at: ElementPosition::Byte(start as u64),
                    },
                    kind,
                )
                .into()
            };
            let eof = |p: &Property| {
                at(FormatErrorKind::UnexpectedEof {
                    what: format!("property `{}`", p.name),
                })
            };
            let mut p3 = [0.0; 3];
            let mut n3 = [0.0; 3];
            for p in &element.properties {
                match (p.kind, p.slot) {
                    (Kind::Scalar(s), Slot::Coord(k)) => {
                        p3[k] = cur.real::<BIG>(s).ok_or_else(|| eof(p))?
                    }
                    (Kind::Scalar(s), Slot::Normal(k)) => {
                        n3[k] = cur.real::<BIG>(s).ok_or_else(|| eof(p))?
                    }
                    (Kind::Scalar(s), _) => cur.skip(s.size() as u64).ok_or_else(|| eof(p))?,
                    (Kind::List { count, item }, slot) => {
                        let n = match cur.int::<BIG>(count).ok_or_else(|| eof(p))? {
                            Ok(n) if n >= 0 => n as u64,
                            Ok(n) => {
                                return Err(at(FormatErrorKind::Syntax {
                                    message: format!("list `{}` has a negative length {n}", p.name),
                                }))
                            }
                            Err(f) => {
                                return Err(at(FormatErrorKind::InvalidNumber {
                                    expected: "an integer list length",
                                    value: f.to_string(),
                                }))
                            }
                        };
                        if slot == Slot::FaceIndices {
                            sink.polygon.clear();
                            crate::check_face_size(n).map_err(&at)?;
                            for _ in 0..n {
                                let v = match cur.int::<BIG>(item).ok_or_else(|| eof(p))? {
                                    Ok(v) => v,
                                    Err(f) => {
                                        return Err(at(FormatErrorKind::InvalidNumber {
                                            expected: "an integer vertex index",
                                            value: f.to_string(),
                                        }))
                                    }
                                };
                                let v = sink.index(v).map_err(&at)?;
                                sink.polygon.push(v);
                            }
                            sink.finish_polygon().map_err(&at)?;
                        } else {
                            let bytes = n.saturating_mul(item.size() as u64);
                            cur.skip(bytes).ok_or_else(|| eof(p))?;
                        }
                    }
                }
            }
            if element.role == Role::Vertex {
                sink.positions.push(Vec3::from(p3));
                if sink.with_normals {
                    sink.normals.push(Vec3::from(n3));
                }
            }
        }
    }
    Ok(())
}

/// Reads one scalar at `offset` of a record known to be long enough.
#[inline(always)]
fn scalar_at<const BIG: bool>(record: &[u8], offset: usize, s: Scalar) -> f64 {
    macro_rules! num {
        ($t:ty, $n:literal) => {{
            let mut b = [0u8; $n];
            b.copy_from_slice(&record[offset..offset + $n]);
            if BIG {
                <$t>::from_be_bytes(b)
            } else {
                <$t>::from_le_bytes(b)
            }
        }};
    }
    match s {
        Scalar::I8 => f64::from(num!(i8, 1)),
        Scalar::U8 => f64::from(num!(u8, 1)),
        Scalar::I16 => f64::from(num!(i16, 2)),
        Scalar::U16 => f64::from(num!(u16, 2)),
        Scalar::I32 => f64::from(num!(i32, 4)),
        Scalar::U32 => f64::from(num!(u32, 4)),
        Scalar::F32 => f64::from(num!(f32, 4)),
        Scalar::F64 => num!(f64, 8),
    }
}

/// The vertex element when every property is a scalar: `bytes` holds whole
/// records of `stride` bytes, so the offsets of x y z (nx ny nz) are fixed.
fn read_vertex_records<const BIG: bool>(
    element: &Element,
    bytes: &[u8],
    stride: usize,
    sink: &mut Sink,
) {
    let mut coords = [(0usize, Scalar::F32); 3];
    let mut normals = [(0usize, Scalar::F32); 3];
    let mut offset = 0;
    for p in &element.properties {
        if let Kind::Scalar(s) = p.kind {
            match p.slot {
                Slot::Coord(k) => coords[k] = (offset, s),
                Slot::Normal(k) => normals[k] = (offset, s),
                _ => {}
            }
            offset += s.size();
        }
    }
    let read3 = |r: &[u8], f: &[(usize, Scalar); 3]| {
        Vec3::new(
            scalar_at::<BIG>(r, f[0].0, f[0].1),
            scalar_at::<BIG>(r, f[1].0, f[1].1),
            scalar_at::<BIG>(r, f[2].0, f[2].1),
        )
    };
    let records = bytes.chunks_exact(stride);
    if sink.with_normals {
        // Positions and normals side by side on two cores: most of the
        // time is the first touch of the two fresh arrays' pages.
        let (positions, normals) = trigbody_core::internals::geom::parallel::join(
            || {
                records
                    .clone()
                    .map(|r| read3(r, &coords))
                    .collect::<Vec<_>>()
            },
            || {
                records
                    .clone()
                    .map(|r| read3(r, &normals))
                    .collect::<Vec<_>>()
            },
        );
        for (to, from) in [
            (&mut sink.positions, positions),
            (&mut sink.normals, normals),
        ] {
            if to.is_empty() {
                *to = from; // no copy (the reserved array was never touched)
            } else {
                to.extend(from);
            }
        }
    } else {
        sink.positions.extend(records.map(|r| read3(r, &coords)));
    }
}

/// Whitespace-separated tokens of an ASCII body with their line numbers.
struct Tokens<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Tokens<'a> {
    /// Skips whitespace so that `line` is the line of the next token.
    fn skip_space(&mut self) {
        while let Some(&b) = self.data.get(self.pos) {
            if b == b'\n' {
                self.line += 1;
            } else if !b.is_ascii_whitespace() {
                break;
            }
            self.pos += 1;
        }
    }

    /// The next token and its line, `Ok(None)` at the end.
    fn next(&mut self) -> Result<Option<(&'a str, usize)>> {
        self.skip_space();
        let start = self.pos;
        while self
            .data
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        if start == self.pos {
            return Ok(None);
        }
        let token = std::str::from_utf8(&self.data[start..self.pos])
            .map_err(|_| header_err(self.line, FormatErrorKind::NotUtf8))?;
        Ok(Some((token, self.line)))
    }
}

fn read_ascii(header: &Header, body: &[u8], sink: &mut Sink) -> Result<()> {
    let mut tokens = Tokens {
        data: body,
        pos: 0,
        line: header.lines + 1,
    };
    for element in &header.elements {
        if element.properties.is_empty() {
            continue; // nothing stored, however many are declared
        }
        // Each value takes at least two bytes (a digit and a separator).
        let cap = usize::try_from(element.count)
            .unwrap_or(usize::MAX)
            .min(body.len() / 2);
        match element.role {
            Role::Vertex => {
                sink.positions.reserve_exact(cap);
                if sink.with_normals {
                    sink.normals.reserve_exact(cap);
                }
            }
            Role::Face => sink.triangles.reserve(cap),
            Role::Other => {}
        }
        for index in 0..element.count {
            tokens.skip_space();
            let start_line = tokens.line;
            let at = |kind: FormatErrorKind, line: usize| -> IoError {
                FormatError::new(
                    Format::Ply,
                    Location::Element {
                        element: element.name.clone(),
                        index,
                        at: ElementPosition::Line(line),
                    },
                    kind,
                )
                .into()
            };
            let mut value = |name: &str, int: bool| -> Result<(f64, usize)> {
                let (token, line) = tokens.next()?.ok_or_else(|| {
                    at(
                        FormatErrorKind::UnexpectedEof {
                            what: format!(
                                "`{}` {index} of {}: property `{name}`",
                                element.name, element.count
                            ),
                        },
                        start_line,
                    )
                })?;
                let v = if int {
                    token.parse::<i64>().ok().map(|v| v as f64)
                } else {
                    token.parse::<f64>().ok()
                };
                let v = v.ok_or_else(|| {
                    at(
                        FormatErrorKind::InvalidNumber {
                            expected: if int { "an integer" } else { "a number" },
                            value: excerpt(token),
                        },
                        line,
                    )
                })?;
                Ok((v, line))
            };
            let mut p3 = [0.0; 3];
            let mut n3 = [0.0; 3];
            for p in &element.properties {
                let what = p.name.as_str();
                match (p.kind, p.slot) {
                    (Kind::Scalar(_), Slot::Coord(k)) => p3[k] = value(what, false)?.0,
                    (Kind::Scalar(_), Slot::Normal(k)) => n3[k] = value(what, false)?.0,
                    (Kind::Scalar(_), _) => {
                        // Unused: any number will do (some writers put
                        // `255.0` in a uchar column).
                        value(what, false)?;
                    }
                    (Kind::List { .. }, slot) => {
                        let (n, line) = value(what, true)?;
                        if n < 0.0 {
                            return Err(at(
                                FormatErrorKind::Syntax {
                                    message: format!("list `{}` has a negative length {n}", p.name),
                                },
                                line,
                            ));
                        }
                        if slot == Slot::FaceIndices {
                            sink.polygon.clear();
                            crate::check_face_size(n as u64).map_err(|k| at(k, start_line))?;
                        }
                        // Bounded by the input: each item needs a token.
                        for _ in 0..n as u64 {
                            let (v, line) = value(what, slot == Slot::FaceIndices)?;
                            if slot == Slot::FaceIndices {
                                let v = sink.index(v as i64).map_err(|k| at(k, line))?;
                                sink.polygon.push(v);
                            }
                        }
                        if slot == Slot::FaceIndices {
                            sink.finish_polygon().map_err(|k| at(k, start_line))?;
                        }
                    }
                }
            }
            if element.role == Role::Vertex {
                sink.positions.push(Vec3::from(p3));
                if sink.with_normals {
                    sink.normals.push(Vec3::from(n3));
                }
            }
        }
    }
    Ok(())
}

fn write_header<W: Write>(
    w: &mut W,
    vertices: usize,
    normals: bool,
    triangles: usize,
    options: &WriteOptions,
) -> Result<()> {
    let ty = match options.ply_precision {
        PlyPrecision::Float => "float",
        PlyPrecision::Double => "double",
    };
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment written by trigbody\nelement vertex {vertices}\n"
    )?;
    for axis in ["x", "y", "z"] {
        writeln!(w, "property {ty} {axis}")?;
    }
    if normals {
        for axis in ["nx", "ny", "nz"] {
            writeln!(w, "property {ty} {axis}")?;
        }
    }
    if triangles > 0 {
        let index = if vertices <= i32::MAX as usize {
            "int"
        } else {
            "uint"
        };
        write!(
            w,
            "element face {triangles}\nproperty list uchar {index} vertex_indices\n"
        )?;
    }
    w.write_all(b"end_header\n")?;
    Ok(())
}

fn write_body<W: Write>(
    w: &mut W,
    positions: &[Vec3],
    normals: Option<&[Vec3]>,
    triangles: &[[u32; 3]],
    options: &WriteOptions,
) -> Result<()> {
    let put = |v: Vec3, w: &mut W| -> std::io::Result<()> {
        match options.ply_precision {
            PlyPrecision::Float => {
                for c in v.to_array() {
                    w.write_all(&(c as f32).to_le_bytes())?;
                }
            }
            PlyPrecision::Double => {
                for c in v.to_array() {
                    w.write_all(&c.to_le_bytes())?;
                }
            }
        }
        Ok(())
    };
    for (i, p) in positions.iter().enumerate() {
        put(*p, w)?;
        if let Some(n) = normals.and_then(|ns| ns.get(i)) {
            put(*n, w)?;
        }
    }
    for t in triangles {
        w.write_all(&[3])?;
        for i in t {
            w.write_all(&i.to_le_bytes())?;
        }
    }
    Ok(())
}

/// Writes a mesh as binary little-endian PLY: `x y z` (and `nx ny nz` when
/// the mesh has normals) as `float` or `double` (see
/// [`WriteOptions::ply_precision`]), then `list uchar int vertex_indices`.
/// The mesh is validated first.
pub fn write_mesh<W: Write>(writer: W, mesh: &Mesh, options: &WriteOptions) -> Result<()> {
    mesh.validate()?;
    let mut w = BufWriter::new(writer);
    let normals = mesh.normals.as_deref();
    write_header(
        &mut w,
        mesh.positions.len(),
        normals.is_some(),
        mesh.triangles.len(),
        options,
    )?;
    write_body(&mut w, &mesh.positions, normals, &mesh.triangles, options)?;
    w.flush()?;
    Ok(())
}

/// Writes a point cloud as binary little-endian PLY with a `vertex`
/// element only.
pub fn write_points<W: Write>(writer: W, cloud: &PointCloud, options: &WriteOptions) -> Result<()> {
    cloud.validate()?;
    let mut w = BufWriter::new(writer);
    let normals = cloud.normals.as_deref();
    write_header(&mut w, cloud.positions.len(), normals.is_some(), 0, options)?;
    write_body(&mut w, &cloud.positions, normals, &[], options)?;
    w.flush()?;
    Ok(())
}
