//! Every kind of broken input gives a typed error with its location and the
//! offending value, never a panic.

use trigbody_core::MeshError;
use trigbody_io::{
    obj, ply, read_bytes, stl, xyz, ElementPosition, Format, FormatErrorKind, IoError, Location,
    ReadOptions,
};

fn read(data: &[u8], format: Format) -> IoError {
    read_bytes(data, format, &ReadOptions::default()).expect_err("should fail")
}

fn kind_at(e: &IoError) -> (&FormatErrorKind, &Location) {
    let f = e
        .format_error()
        .unwrap_or_else(|| panic!("expected a format error, got {e:?}"));
    (&f.kind, &f.location)
}

/// A small binary little-endian point PLY with `n` float points.
fn binary_points(declared: usize, actual: usize) -> Vec<u8> {
    let mut d = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {declared}\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
    )
    .into_bytes();
    for i in 0..actual {
        for c in [i as f32, 1.0, 2.0] {
            d.extend_from_slice(&c.to_le_bytes());
        }
    }
    d
}

#[test]
fn truncated_binary_ply_names_element_and_byte() {
    let mut d = binary_points(10, 10);
    let header = d.len() - 120;
    d.truncate(d.len() - 5); // vertex 9 is cut
    let e = read(&d, Format::Ply);
    let (kind, loc) = kind_at(&e);
    assert!(
        matches!(kind, FormatErrorKind::CountTooLarge { count: 10, .. }),
        "{kind:?}"
    );
    assert_eq!(
        loc,
        &Location::Element {
            element: "vertex".into(),
            index: 9,
            at: ElementPosition::Byte((header + 9 * 12) as u64)
        }
    );
    assert!(e.to_string().contains("vertex 9"), "{e}");
}

#[test]
fn truncated_face_list_names_the_face() {
    let mut d = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    for _ in 0..9 {
        d.extend_from_slice(&0f32.to_le_bytes());
    }
    d.push(3);
    for i in [0i32, 1, 2] {
        d.extend_from_slice(&i.to_le_bytes());
    }
    d.push(3);
    d.extend_from_slice(&0i32.to_le_bytes()); // the second face is cut short
    let e = read(&d, Format::Ply);
    let (kind, loc) = kind_at(&e);
    assert!(
        matches!(kind, FormatErrorKind::UnexpectedEof { .. }),
        "{kind:?}"
    );
    assert!(
        matches!(loc, Location::Element { element, index: 1, .. } if element == "face"),
        "{loc:?}"
    );
}

#[test]
fn header_count_larger_than_data_does_not_allocate_it() {
    // A lying header: four billion vertices in a 100-byte file.
    let d = binary_points(4_000_000_000, 2);
    let e = read(&d, Format::Ply);
    assert!(matches!(
        kind_at(&e).0,
        FormatErrorKind::CountTooLarge {
            count: 4_000_000_000,
            ..
        }
    ));
    // Same for a face count and for list lengths.
    let mut d = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 18446744073709551615\nproperty list uint int vertex_indices\nend_header\n".to_vec();
    d.extend_from_slice(&[0; 36]);
    d.extend_from_slice(&u32::MAX.to_le_bytes());
    let e = read(&d, Format::Ply);
    let (kind, loc) = kind_at(&e);
    // The list claims 2^32 − 1 indices: refused as a face too large, at face 0.
    assert!(
        matches!(
            kind,
            FormatErrorKind::FaceTooLarge {
                count: 4_294_967_295,
                ..
            }
        ),
        "{kind:?}"
    );
    assert!(
        matches!(loc, Location::Element { element, index: 0, .. } if element == "face"),
        "{loc:?}"
    );
}

#[test]
fn ascii_ply_with_too_few_values() {
    let d = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n";
    let e = read(d, Format::Ply);
    let (kind, loc) = kind_at(&e);
    assert!(
        matches!(kind, FormatErrorKind::UnexpectedEof { .. }),
        "{kind:?}"
    );
    assert!(
        matches!(
            loc,
            Location::Element {
                index: 2,
                at: ElementPosition::Line(10),
                ..
            }
        ),
        "{loc:?}"
    );
}

#[test]
fn unknown_property_type() {
    let d = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty half y\nproperty float z\nend_header\n0 0 0\n";
    let e = read(d, Format::Ply);
    assert_eq!(
        kind_at(&e),
        (
            &FormatErrorKind::UnknownPropertyType {
                value: "half".into()
            },
            &Location::Line(5)
        )
    );
    assert!(e.to_string().contains("\"half\""), "{e}");
}

#[test]
fn unknown_ply_format_string() {
    let d = b"ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n";
    let e = read(d, Format::Ply);
    let (kind, loc) = kind_at(&e);
    assert!(
        matches!(kind, FormatErrorKind::UnknownPlyFormat { value } if value.contains("binary_middle_endian")),
        "{kind:?}"
    );
    assert_eq!(loc, &Location::Line(2));
}

#[test]
fn not_a_ply_and_missing_end_header() {
    assert!(matches!(
        kind_at(&read(b"PK\x03\x04", Format::Ply)).0,
        FormatErrorKind::NotPly
    ));
    let e = read(b"ply\nformat ascii 1.0\nelement vertex 1\n", Format::Ply);
    assert!(matches!(
        kind_at(&e).0,
        FormatErrorKind::UnexpectedEof { .. }
    ));
}

#[test]
fn ply_face_index_out_of_range() {
    let d = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
    let e = read(d, Format::Ply);
    let (kind, loc) = kind_at(&e);
    assert_eq!(
        kind,
        &FormatErrorKind::IndexOutOfRange {
            what: "vertex",
            index: 3,
            count: 3
        }
    );
    assert!(
        matches!(loc, Location::Element { element, index: 0, at: ElementPosition::Line(13) } if element == "face"),
        "{loc:?}"
    );
}

#[test]
fn obj_face_index_zero_or_out_of_range_names_the_line() {
    let e = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", Format::Obj);
    assert_eq!(
        kind_at(&e),
        (
            &FormatErrorKind::IndexOutOfRange {
                what: "vertex",
                index: 0,
                count: 3
            },
            &Location::Line(4)
        )
    );
    let e = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n# c\nf 1 2 4\n", Format::Obj);
    assert_eq!(kind_at(&e).1, &Location::Line(5));
    assert!(
        e.to_string().contains("line 5") && e.to_string().contains("index 4"),
        "{e}"
    );
    let e = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", Format::Obj);
    assert!(matches!(
        kind_at(&e).0,
        FormatErrorKind::IndexOutOfRange { index: -4, .. }
    ));
    let e = read(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n",
        Format::Obj,
    );
    assert!(matches!(
        kind_at(&e).0,
        FormatErrorKind::IndexOutOfRange { what: "normal", .. }
    ));
}

#[test]
fn obj_bad_numbers_and_short_faces() {
    let e = read(b"v 0 0 0\nv 1 zero 0\n", Format::Obj);
    assert_eq!(
        kind_at(&e),
        (
            &FormatErrorKind::InvalidNumber {
                expected: "a coordinate",
                value: "zero".into()
            },
            &Location::Line(2)
        )
    );
    let e = read(b"v 0 0 0\nv 1 0 0\nf 1 2\n", Format::Obj);
    assert_eq!(kind_at(&e).0, &FormatErrorKind::DegenerateFace { count: 2 });
    let e = read(b"v 0 0\n", Format::Obj);
    assert!(matches!(kind_at(&e).0, FormatErrorKind::Syntax { .. }));
}

#[test]
fn empty_files_in_every_format() {
    for format in [Format::Obj, Format::Ply, Format::Stl, Format::Xyz] {
        for data in [&b""[..], b"\n  \n"] {
            let e = read(data, format);
            let kind = e.format_error().map(|f| &f.kind);
            assert!(
                matches!(
                    kind,
                    Some(FormatErrorKind::Empty) | Some(FormatErrorKind::NotPly)
                ),
                "{format}: {e:?}"
            );
        }
    }
    // Files with structure but no vertices are empty too.
    let e = read(b"# nothing\no empty\n", Format::Obj);
    assert_eq!(kind_at(&e).0, &FormatErrorKind::Empty);
    let e = read(
        b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        Format::Ply,
    );
    assert_eq!(kind_at(&e).0, &FormatErrorKind::Empty);
    let e = read(b"solid empty\nendsolid empty\n", Format::Stl);
    assert_eq!(kind_at(&e).0, &FormatErrorKind::Empty);
    let e = read(b"x,y,z\n", Format::Xyz);
    assert_eq!(kind_at(&e).0, &FormatErrorKind::Empty);
}

#[test]
fn non_utf8_text_names_the_line() {
    let e = read(b"v 0 0 0\nv 1 \xff 0\n", Format::Obj);
    assert_eq!(kind_at(&e), (&FormatErrorKind::NotUtf8, &Location::Line(2)));
    let e = read(b"1 2 3\n4 \xfe\xff 6\n", Format::Xyz);
    assert_eq!(kind_at(&e), (&FormatErrorKind::NotUtf8, &Location::Line(2)));
    let e = read(
        b"solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 \xc3 0\n",
        Format::Stl,
    );
    assert_eq!(kind_at(&e), (&FormatErrorKind::NotUtf8, &Location::Line(4)));
    let e = read(
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 \x80 0\n",
        Format::Ply,
    );
    assert_eq!(kind_at(&e).0, &FormatErrorKind::NotUtf8);
    // Free text in another encoding (a Latin-1 comment or object name) is fine.
    let ok = obj::read(
        &b"# caf\xe9\no caf\xe9\nv 0 0 0\n"[..],
        &ReadOptions::default(),
    );
    assert!(ok.is_ok(), "{ok:?}");
}

#[test]
fn nan_and_infinite_coordinates_are_rejected_with_the_vertex_index() {
    let o = ReadOptions::default();
    let cases: Vec<(Format, Vec<u8>)> = vec![
        (
            Format::Obj,
            b"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n".to_vec(),
        ),
        (Format::Xyz, b"0 0 0\n1 inf 0\n".to_vec()),
        (Format::Ply, {
            let mut d = binary_points(3, 0);
            for c in [0f32, 0., 0., 1., f32::NAN, 0., 0., 1., 0.] {
                d.extend_from_slice(&c.to_le_bytes());
            }
            d
        }),
    ];
    for (format, data) in cases {
        match read_bytes(&data, format, &o) {
            Err(IoError::InvalidGeometry {
                source: MeshError::NonFinite { index: 1, .. },
                ..
            }) => {}
            other => panic!("{format}: {other:?}"),
        }
    }
    // A scale that overflows is caught the same way.
    let huge = ReadOptions { scale: 1e300, ..o };
    let e = xyz::read(&b"0 0 0\n1e300 0 0\n"[..], &huge).unwrap_err();
    assert!(matches!(
        e,
        IoError::InvalidGeometry {
            source: MeshError::NonFinite { index: 1, .. },
            ..
        }
    ));
    assert!(e.to_string().contains("vertex 1"), "{e}");
}

#[test]
fn stl_errors() {
    // Binary with a triangle count larger than the data.
    let mut d = vec![0u8; 80];
    d.extend_from_slice(&1000u32.to_le_bytes());
    d.extend_from_slice(&[0; 50 * 2]);
    let e = read(&d, Format::Stl);
    assert!(matches!(
        kind_at(&e).0,
        FormatErrorKind::CountTooLarge { count: 1000, .. }
    ));
    // Too short to be binary, and not ASCII.
    let e = read(b"\x00\x01garbage", Format::Stl);
    assert!(matches!(
        kind_at(&e).0,
        FormatErrorKind::UnexpectedEof { .. }
    ));
    // ASCII with a typo.
    let e = read(
        b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertx 0 1 0\n",
        Format::Stl,
    );
    assert_eq!(kind_at(&e).1, &Location::Line(6));
    // ASCII cut off inside a facet.
    let e = read(
        b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
        Format::Stl,
    );
    assert!(matches!(
        kind_at(&e).0,
        FormatErrorKind::UnexpectedEof { .. }
    ));
    let _ = stl::read(&b"solid"[..], &ReadOptions::default()).unwrap_err();
}

#[test]
fn xyz_errors() {
    let e = read(b"1 2 3\n4 5\n", Format::Xyz);
    assert!(matches!(
        kind_at(&e),
        (FormatErrorKind::Syntax { .. }, Location::Line(2))
    ));
    let e = read(b"1 2 3\n4 5 six\n", Format::Xyz);
    assert_eq!(
        kind_at(&e),
        (
            &FormatErrorKind::InvalidNumber {
                expected: "a number",
                value: "six".into()
            },
            &Location::Line(2)
        )
    );
    let e = read(b"a,b,c\n1,2,3\n", Format::Xyz);
    assert!(matches!(
        kind_at(&e),
        (FormatErrorKind::Syntax { .. }, Location::Line(1))
    ));
}

#[test]
fn errors_from_paths_name_the_file() {
    let dir = std::env::temp_dir().join(format!("trigbody-io-err-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("broken.obj");
    std::fs::write(&path, "v 0 0 0\nf 1 1 9\n").unwrap();
    let e = trigbody_io::read_geometry(&path, &ReadOptions::default()).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("broken.obj") && text.contains("line 2"),
        "{text}"
    );
    let e =
        trigbody_io::read_geometry(dir.join("missing.ply"), &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, IoError::Io { path: Some(_), .. }), "{e:?}");
    let e = trigbody_io::read_geometry(dir.join("model.fbx"), &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, IoError::UnknownExtension { .. }), "{e:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn error_messages_read_well() {
    let e = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", Format::Obj);
    assert_eq!(
        e.to_string(),
        "OBJ file, line 4: vertex index 0 is out of range: 3 defined (OBJ indices start at 1; negative ones count back from the last)"
    );
    let _ = ply::read(&b""[..], &ReadOptions::default()).unwrap_err();
}

#[test]
fn ply_faces_without_an_index_list_are_an_error_not_points() {
    let d = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar float weights\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0.5 0.5 0.5\n";
    let e = read(d, Format::Ply);
    assert!(
        matches!(kind_at(&e).0, FormatErrorKind::BadHeader { message } if message.contains("weights")),
        "{e}"
    );
}
