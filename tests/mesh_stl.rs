//! STL reading and writing: formats, malformed inputs (named errors, never a panic), round
//! trips. Models are generated in code.
#![cfg(not(target_arch = "wasm32"))] // native only: proptest, files and processes

use glam::DVec3;
use proptest::prelude::*;
use warpslice::mesh::{read_stl, shapes, write_stl, Mesh, MeshError, StlFormat};

/// An ASCII STL of the given facets (three vertices each, zero normals), `\n` line ends.
fn ascii(facets: &[[[f32; 3]; 3]]) -> String {
    let mut s = String::from("solid test\n");
    for f in facets {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for v in f {
            s += &format!("      vertex {:e} {:e} {:e}\n", v[0], v[1], v[2]);
        }
        s += "    endloop\n  endfacet\n";
    }
    s + "endsolid test\n"
}

/// The facets of a mesh as f32 corners.
fn facets(m: &Mesh) -> Vec<[[f32; 3]; 3]> {
    m.triangles
        .iter()
        .map(|t| t.map(|i| m.vertices[i as usize].as_vec3().to_array()))
        .collect()
}

fn cube() -> Mesh {
    shapes::cuboid(DVec3::ZERO, DVec3::splat(20.0))
}

#[test]
fn ascii_cube_welds_to_eight_vertices_and_is_closed() {
    let (m, r) = read_stl(ascii(&facets(&cube())).as_bytes()).unwrap();
    assert_eq!(r.format, StlFormat::Ascii);
    assert_eq!(
        (
            r.triangles,
            r.vertices,
            r.open_edges,
            r.nonmanifold_edges,
            r.degenerate
        ),
        (12, 8, 0, 0, 0)
    );
    assert_eq!(m.bbox().max, DVec3::splat(20.0));
}

#[test]
fn ascii_with_crlf_reads_like_lf() {
    let lf = ascii(&facets(&cube()));
    let crlf = lf.replace('\n', "\r\n");
    let a = read_stl(lf.as_bytes()).unwrap();
    let b = read_stl(crlf.as_bytes()).unwrap();
    assert_eq!(a, b);
    // and an error's line number counts CRLF lines
    let bad = crlf.replacen("vertex", "vertexx", 1);
    assert_eq!(
        read_stl(bad.as_bytes()).unwrap_err(),
        MeshError::Syntax {
            line: 4,
            message: "expected `vertex` or `endloop`, found `vertexx`".into()
        }
    );
}

#[test]
fn binary_with_solid_header_is_read_as_binary() {
    let bytes = write_stl(&cube(), "solid cube exported by a CAD program");
    assert!(bytes.starts_with(b"solid "));
    let (m, r) = read_stl(&bytes).unwrap();
    assert_eq!(r.format, StlFormat::BinarySolidHeader);
    assert_eq!(m.triangles.len(), 12);
    assert!(r.is_watertight());
}

#[test]
fn binary_with_solid_header_and_utf8_clean_body_is_binary() {
    // Coordinates 0 and 2 (0x40000000) and zero normals (as many exporters write them): every
    // byte is ASCII, so a reader that decides by the first word and UTF-8 validity (stl_io)
    // takes the file for ASCII; the size decides here.
    let mut bytes = write_stl(
        &shapes::cuboid(DVec3::ZERO, DVec3::splat(2.0)),
        "solid cube",
    );
    for t in 0..12 {
        bytes[84 + 50 * t..84 + 50 * t + 12].fill(0);
    }
    assert!(std::str::from_utf8(&bytes).is_ok());
    let (m, r) = read_stl(&bytes).unwrap();
    assert_eq!(
        (r.format, m.triangles.len(), r.zero_normals),
        (StlFormat::BinarySolidHeader, 12, 12)
    );
    assert!(r.is_watertight());
    let theirs = stl_io::read_stl(&mut std::io::Cursor::new(bytes));
    assert!(!matches!(theirs, Ok(m) if m.faces.len() == 12));
}

#[test]
fn binary_with_plain_header_is_binary() {
    let (_, r) = read_stl(&write_stl(&cube(), "")).unwrap();
    assert_eq!(r.format, StlFormat::Binary);
}

#[test]
fn empty_file_is_named() {
    assert_eq!(read_stl(b"").unwrap_err(), MeshError::Empty);
}

#[test]
fn truncated_binary_is_named_with_sizes() {
    let bytes = write_stl(&cube(), "");
    let cut = &bytes[..bytes.len() - 7];
    assert_eq!(
        read_stl(cut).unwrap_err(),
        MeshError::Truncated {
            expected_bytes: 84 + 12 * 50,
            actual_bytes: 84 + 12 * 50 - 7
        }
    );
    let bytes = write_stl(&cube(), "\0binary");
    assert_eq!(
        read_stl(&bytes[..40]).unwrap_err(),
        MeshError::Truncated {
            expected_bytes: 84,
            actual_bytes: 40
        }
    );
    // a file of spaces only holds no triangles
    assert_eq!(read_stl(&[b' '; 40]).unwrap_err(), MeshError::NoTriangles);
}

#[test]
fn face_count_mismatch_is_named() {
    let mut bytes = write_stl(&cube(), "");
    bytes[80..84].copy_from_slice(&20u32.to_le_bytes());
    assert_eq!(
        read_stl(&bytes).unwrap_err(),
        MeshError::FaceCountMismatch {
            header_count: 20,
            bytes_for: 12
        }
    );
    bytes[80..84].copy_from_slice(&5u32.to_le_bytes());
    assert_eq!(
        read_stl(&bytes).unwrap_err(),
        MeshError::FaceCountMismatch {
            header_count: 5,
            bytes_for: 12
        }
    );
}

#[test]
fn few_trailing_bytes_after_binary_are_tolerated_and_noted() {
    let mut bytes = write_stl(&cube(), "");
    bytes.extend_from_slice(&[0; 3]);
    let (m, r) = read_stl(&bytes).unwrap();
    assert_eq!(m.triangles.len(), 12);
    assert!(
        r.warnings.iter().any(|w| w.contains("3 bytes")),
        "{:?}",
        r.warnings
    );
}

/// Issue 12, "report, not refuse": a binary STL with data appended after its facets (73 bytes,
/// not a whole record; slicers refuse such a file) is read, and the bytes are reported by the
/// reader, in the warp step's `warnings` and by `warpslice warp`; whole records beyond the
/// header's count may be facets it does not count, which stays `mesh.face-count`.
#[test]
fn a_binary_stl_with_appended_bytes_is_warped_and_the_bytes_reported() {
    let mut bytes = write_stl(&cube(), "");
    bytes.extend(std::iter::repeat_n(b'x', 73));
    let (m, r) = read_stl(&bytes).unwrap();
    assert_eq!(m.triangles.len(), 12);
    let says = |w: &str| w.contains("73 bytes after the last of the header's 12 binary facets");
    assert!(r.warnings.iter().any(|w| says(w)), "{:?}", r.warnings);
    let opts = warpslice::pipeline::WarpOptions::new(warpslice::warp::WarpParams {
        spec: warpslice::warp::WarpSpec::Conic {
            angle: 20.0,
            direction: warpslice::warp::Direction::Outward,
            center: [0.0, 0.0],
        },
        base: None,
    });
    let w = warpslice::pipeline::warp_model(&bytes, &opts).unwrap();
    assert!(
        w.report.warnings.iter().any(|w| says(w)),
        "{:?}",
        w.report.warnings
    );
    let d = std::env::temp_dir().join(format!("warpslice-stl-tail-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("m.stl"), &bytes).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .args([
            "warp",
            d.join("m.stl").to_str().unwrap(),
            "--warp",
            "conic",
            "-o",
        ])
        .arg(d.join("w.stl"))
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success()
            && out
                .lines()
                .any(|l| l.starts_with("warning: model:") && says(l)),
        "{out}"
    );
    // two whole records more than the header counts: a wrong count, not appended data
    let mut more = write_stl(&cube(), "");
    more.extend(std::iter::repeat_n(0u8, 100));
    assert_eq!(
        read_stl(&more).unwrap_err(),
        MeshError::FaceCountMismatch {
            header_count: 12,
            bytes_for: 14
        }
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn zero_triangles_is_named_for_both_formats() {
    assert_eq!(
        read_stl(&write_stl(&Mesh::default(), "")).unwrap_err(),
        MeshError::NoTriangles
    );
    assert_eq!(
        read_stl(b"solid empty\nendsolid empty\n").unwrap_err(),
        MeshError::NoTriangles
    );
}

#[test]
fn non_finite_coordinates_are_named_with_the_triangle() {
    let mut f = facets(&cube());
    f[5][1][2] = f32::NAN;
    assert_eq!(
        read_stl(ascii(&f).as_bytes()).unwrap_err(),
        MeshError::NonFinite { triangle: 5 }
    );
    let mut bytes = write_stl(&cube(), "");
    let at = 84 + 7 * 50 + 12; // triangle 7, first vertex x
    bytes[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert_eq!(
        read_stl(&bytes).unwrap_err(),
        MeshError::NonFinite { triangle: 7 }
    );
    // a number too large for f32 is infinite too
    let big = ascii(&facets(&cube())).replacen("vertex 0e0", "vertex 1e39", 1);
    assert!(matches!(
        read_stl(big.as_bytes()).unwrap_err(),
        MeshError::NonFinite { .. }
    ));
}

#[test]
fn quad_facet_is_not_a_triangle_with_line_number() {
    let s = ascii(&facets(&cube()));
    // the second facet starts on line 2 + 7 = 9; give it a fourth vertex
    let mut lines: Vec<&str> = s.lines().collect();
    assert!(lines[8].contains("facet normal"));
    lines.insert(13, "      vertex 1 2 3");
    let s = lines.join("\n");
    assert_eq!(
        read_stl(s.as_bytes()).unwrap_err(),
        MeshError::NotATriangle {
            line: 9,
            vertices: 4
        }
    );
    let two =
        s.replacen("      vertex 1 2 3\n", "", 1)
            .replacen("      vertex 2e1 0e0 2e1\n", "", 1);
    assert!(matches!(
        read_stl(two.as_bytes()).unwrap_err(),
        MeshError::NotATriangle { .. } | MeshError::Syntax { .. }
    ));
}

#[test]
fn syntax_errors_carry_line_numbers_and_say_what_was_found() {
    let s = ascii(&facets(&cube()));
    let bad = s.replacen("outer loop", "outer lop", 1);
    let e = read_stl(bad.as_bytes()).unwrap_err();
    assert_eq!(
        e,
        MeshError::Syntax {
            line: 3,
            message: "expected `loop` after `outer`, found `lop`".into()
        }
    );
    assert!(e.to_string().starts_with("line 3: "));
    let bad = s.replacen("endfacet", "endfacett", 1);
    assert!(matches!(
        read_stl(bad.as_bytes()).unwrap_err(),
        MeshError::Syntax { line: 8, .. }
    ));
}

#[test]
fn text_that_is_not_stl_is_a_syntax_error_not_a_size_error() {
    let e = read_stl(b"hello, this is a text file and not an STL at all\n").unwrap_err();
    assert!(matches!(e, MeshError::Syntax { line: 1, .. }), "{e:?}");
}

#[test]
fn ascii_cut_short_names_the_facet() {
    let s = ascii(&facets(&cube()));
    // the file ends after the last facet's third vertex
    let cut = &s[..s.rfind("endloop").unwrap()];
    assert!(matches!(
        read_stl(cut.as_bytes()).unwrap_err(),
        MeshError::Syntax { .. }
    ));
}

#[test]
fn flipped_normals_are_counted() {
    let mut s = String::from("solid t\n");
    for (n, z) in [("0 0 -1", 0.0), ("0 0 1", 1.0)] {
        // triangle counter-clockwise seen from +z: normal +z; the first says −z
        s += &format!("facet normal {n}\nouter loop\nvertex 0 0 {z}\nvertex 1 0 {z}\nvertex 0 1 {z}\nendloop\nendfacet\n");
    }
    s += "endsolid t\n";
    let (_, r) = read_stl(s.as_bytes()).unwrap();
    assert_eq!((r.flipped_normals, r.zero_normals), (1, 0));
    assert!(!r.warnings.is_empty());
}

#[test]
fn one_degenerate_triangle_loads_and_is_reported() {
    let s = "solid d\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 1 1\nvertex 2 2 2\nendloop\nendfacet\nendsolid d\n";
    let (m, r) = read_stl(s.as_bytes()).unwrap();
    assert_eq!((r.triangles, r.degenerate, r.open_edges), (1, 1, 3));
    let back = read_stl(&write_stl(&m, "")).unwrap().0;
    assert_eq!(back, m);
}

/// An arbitrary mesh with f32-representable coordinates, vertices numbered in order of first
/// use and all used (what read_stl returns), possibly with repeated vertices.
fn arb_mesh() -> impl Strategy<Value = Mesh> {
    (1usize..40)
        .prop_flat_map(|nv| {
            let coord = (-1.0e4f32..1.0e4).prop_map(f64::from);
            (
                prop::collection::vec((coord.clone(), coord.clone(), coord), nv),
                prop::collection::vec(prop::array::uniform3(0..nv as u32), 1..60),
            )
        })
        .prop_map(|(v, t)| {
            // renumber in order of first use, dropping duplicates of position and unused vertices
            let pts: Vec<DVec3> = v.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect();
            let mut out = Mesh::default();
            for tri in t {
                let tri = tri.map(|i| {
                    let p = pts[i as usize];
                    match out.vertices.iter().position(|&q| q == p) {
                        Some(k) => k as u32,
                        None => {
                            out.vertices.push(p);
                            (out.vertices.len() - 1) as u32
                        }
                    }
                });
                out.triangles.push(tri);
            }
            out
        })
}

proptest! {
    #[test]
    fn round_trip_binary_is_exact_for_f32_meshes(m in arb_mesh()) {
        let (back, r) = read_stl(&write_stl(&m, "prop")).unwrap();
        prop_assert_eq!(r.format, StlFormat::Binary);
        prop_assert_eq!(back, m);
    }

    #[test]
    fn round_trip_ascii_is_exact_for_f32_meshes(m in arb_mesh()) {
        let (back, _) = read_stl(ascii(&facets(&m)).as_bytes()).unwrap();
        prop_assert_eq!(back, m);
    }

    #[test]
    fn round_trip_of_f64_mesh_is_exact_up_to_f32(scale in 0.001f64..1000.0) {
        // f64 coordinates are rounded to f32 on writing; reading gives them back within
        // half an f32 ulp
        let m = shapes::uv_sphere(DVec3::new(1.0, 2.0, 3.0), scale, 7, 9);
        let (back, r) = read_stl(&write_stl(&m, "sphere")).unwrap();
        prop_assert!(r.is_watertight());
        prop_assert_eq!(back.triangles.len(), m.triangles.len());
        for (tb, tm) in back.triangles.iter().zip(&m.triangles) {
            for k in 0..3 {
                let (a, b) = (back.vertices[tb[k] as usize], m.vertices[tm[k] as usize]);
                prop_assert!((a - b).abs().max_element() <= b.abs().max_element() * f64::from(f32::EPSILON));
            }
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        let _ = read_stl(&bytes);
    }

    #[test]
    fn arbitrary_text_after_solid_never_panics(s in "solid [a-z ]{0,5}\n[ -~\n]{0,300}") {
        let _ = read_stl(s.as_bytes());
    }
}

#[test]
fn written_normals_are_unit_and_outward() {
    let bytes = write_stl(&cube(), "");
    let f = |o: usize| f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    for t in 0..12 {
        let o = 84 + 50 * t;
        let n = glam::Vec3::new(f(o), f(o + 4), f(o + 8));
        assert!((n.length() - 1.0).abs() < 1e-6);
        // the normal points away from the centre (10, 10, 10)
        let a = glam::Vec3::new(f(o + 12), f(o + 16), f(o + 20));
        assert!(n.dot(a - glam::Vec3::splat(10.0)) > 0.0);
    }
}
