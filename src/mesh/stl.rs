//! STL in (ASCII and binary) and out (binary).
//!
//! ## Binary or ASCII?
//! A binary STL is an 80-byte header, a little-endian u32 face count `n` and `n` records of
//! 50 bytes (normal, three vertices as 3 × f32 each, a u16 attribute), so its length is
//! exactly `84 + 50 n`. Many exporters start the header with `solid`, so the first word does
//! not decide: a file whose length is `84 + 50 n` is binary unless it starts with `solid` *and*
//! parses as ASCII; a file that starts with `solid` and has another length is ASCII (its
//! errors are reported with line numbers, unless it is clearly binary bytes, in which case
//! the size error is reported).
//!
//! Both formats are parsed here directly: stl_io 0.11 decides by the first line alone (ASCII
//! if it is valid UTF-8 starting with `solid `), so it misreads binaries whose header starts
//! with `solid ` and whose bytes up to the first 0x0A happen to be valid UTF-8 (zero normals
//! and round coordinates do that), and its ASCII reader gives no line numbers. stl_io serves
//! as an independent oracle in the tests.
//!
//! ## Welding
//! STL stores every triangle's three corners separately. Corners with bit-identical f32
//! coordinates (−0 taken as +0) become one vertex, numbered in order of first appearance;
//! coordinates are then widened exactly to f64.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};

use glam::DVec3;

use super::fxhash::FxBuild;
use super::stl_ascii::{self, RawFacet};
use super::{Mesh, MeshError, MeshReport};

/// Which kind of STL a file was.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StlFormat {
    /// Text STL (`solid … endsolid`).
    Ascii,
    /// Binary STL (80-byte header, face count, 50-byte facets).
    Binary,
    /// Binary whose 80-byte header starts with `solid`.
    BinarySolidHeader,
}

/// Bytes of the binary header (before the face count).
pub const BINARY_HEADER_BYTES: usize = 80;
/// Bytes of one binary facet record.
pub const BINARY_FACET_BYTES: usize = 50;
/// Bytes before the first binary facet record (header + u32 face count).
const BINARY_PREFIX_BYTES: usize = BINARY_HEADER_BYTES + 4;

/// A welding key: the f32 bit patterns of one corner.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Key([u32; 3]);

impl Hash for Key {
    #[inline]
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64((u64::from(self.0[0]) << 32) | u64::from(self.0[1]));
        state.write_u32(self.0[2]);
    }
}

/// Collects facets into an indexed mesh, checking coordinates and normals.
struct Welder {
    mesh: Mesh,
    index: HashMap<Key, u32, FxBuild>,
    zero_normals: usize,
    flipped_normals: usize,
}

impl Welder {
    fn with_capacity(triangles: usize) -> Self {
        // An STL's vertex count is typically about half its triangle count.
        let vertices = triangles / 2 + 3;
        let mut index = HashMap::with_hasher(FxBuild::default());
        index.reserve(vertices);
        Welder {
            mesh: Mesh {
                vertices: Vec::with_capacity(vertices),
                triangles: Vec::with_capacity(triangles),
            },
            index,
            zero_normals: 0,
            flipped_normals: 0,
        }
    }

    fn add(&mut self, f: RawFacet) -> Result<(), MeshError> {
        let triangle = self.mesh.triangles.len();
        let mut tri = [0u32; 3];
        let mut p = [DVec3::ZERO; 3];
        for k in 0..3 {
            let v = f.vertices[k];
            if !v.iter().all(|c| c.is_finite()) {
                return Err(MeshError::NonFinite { triangle });
            }
            // `+ 0.0` turns −0 into +0 so that the two weld (they compare equal).
            let v = v.map(|c| c + 0.0);
            let next = self.mesh.vertices.len() as u32;
            let i = *self.index.entry(Key(v.map(f32::to_bits))).or_insert(next);
            p[k] = DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
            if i == next {
                self.mesh.vertices.push(p[k]);
            }
            tri[k] = i;
        }
        self.mesh.triangles.push(tri);
        let n = DVec3::new(
            f64::from(f.normal[0]),
            f64::from(f.normal[1]),
            f64::from(f.normal[2]),
        );
        if n == DVec3::ZERO {
            self.zero_normals += 1;
        } else if n.dot((p[1] - p[0]).cross(p[2] - p[0])) < 0.0 {
            self.flipped_normals += 1;
        }
        Ok(())
    }

    fn finish(
        self,
        format: StlFormat,
        mut warnings: Vec<String>,
    ) -> Result<(Mesh, MeshReport), MeshError> {
        if self.mesh.triangles.is_empty() {
            return Err(MeshError::NoTriangles);
        }
        let mut report = MeshReport::of(&self.mesh, format);
        report.zero_normals = self.zero_normals;
        report.flipped_normals = self.flipped_normals;
        if self.flipped_normals > 0 {
            warnings.push(format!(
                "{} of {} facet normals point against their vertex order; the vertex order (counter-clockwise seen from outside) is used, so check the model is not inside out",
                self.flipped_normals, report.triangles
            ));
        }
        report.warnings = warnings;
        Ok((self.mesh, report))
    }
}

/// The face count stored in a binary header, if the file is long enough to have one.
fn binary_count(bytes: &[u8]) -> Option<u64> {
    let c = bytes.get(BINARY_HEADER_BYTES..BINARY_PREFIX_BYTES)?;
    Some(u64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]])))
}

/// `84 + 50 n`, the length of a binary STL of `n` facets.
fn binary_len(n: u64) -> u64 {
    BINARY_PREFIX_BYTES as u64 + BINARY_FACET_BYTES as u64 * n
}

/// Whether the start of the file holds bytes no text file has (NUL or other control
/// characters): then a failed ASCII parse is reported as a binary size error instead.
fn looks_binary(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .take(BINARY_PREFIX_BYTES + 4 * BINARY_FACET_BYTES)
        .any(|&c| c < 0x20 && !matches!(c, b'\t' | b'\n' | b'\r' | 0x0b | 0x0c))
}

/// Read a binary STL of `count` facets (the length was checked by the caller; at most
/// `BINARY_FACET_BYTES − 1` trailing bytes are ignored).
fn read_binary(
    bytes: &[u8],
    count: u64,
    format: StlFormat,
    warnings: Vec<String>,
) -> Result<(Mesh, MeshReport), MeshError> {
    let body = bytes.get(BINARY_PREFIX_BYTES..).unwrap_or(&[]);
    let count = usize::try_from(count)
        .unwrap_or(usize::MAX)
        .min(body.len() / BINARY_FACET_BYTES);
    let mut w = Welder::with_capacity(count);
    let f = |r: &[u8], k: usize| {
        f32::from_le_bytes([r[4 * k], r[4 * k + 1], r[4 * k + 2], r[4 * k + 3]])
    };
    for r in body.chunks_exact(BINARY_FACET_BYTES).take(count) {
        w.add(RawFacet {
            normal: [f(r, 0), f(r, 1), f(r, 2)],
            vertices: [
                [f(r, 3), f(r, 4), f(r, 5)],
                [f(r, 6), f(r, 7), f(r, 8)],
                [f(r, 9), f(r, 10), f(r, 11)],
            ],
        })?;
    }
    w.finish(format, warnings)
}

/// The error for a file that is not a well-formed binary STL.
fn binary_size_error(bytes: &[u8]) -> MeshError {
    let actual = bytes.len() as u64;
    let Some(count) = binary_count(bytes) else {
        return MeshError::Truncated {
            expected_bytes: BINARY_PREFIX_BYTES as u64,
            actual_bytes: actual,
        };
    };
    let expected = binary_len(count);
    let body = actual - BINARY_PREFIX_BYTES as u64;
    if actual < expected && !body.is_multiple_of(BINARY_FACET_BYTES as u64) {
        MeshError::Truncated {
            expected_bytes: expected,
            actual_bytes: actual,
        }
    } else {
        MeshError::FaceCountMismatch {
            header_count: count,
            bytes_for: body / BINARY_FACET_BYTES as u64,
        }
    }
}

fn read_ascii(bytes: &[u8]) -> Result<(Mesh, MeshReport), MeshError> {
    // ~250 bytes of text per facet
    let mut w = Welder::with_capacity(bytes.len() / 256);
    let notes = stl_ascii::parse(bytes, |f| w.add(f))?;
    let mut warnings = Vec::new();
    if notes.missing_endsolid {
        warnings.push(
            "the ASCII STL ends without `endsolid` (tolerated; the file may be cut short)"
                .to_string(),
        );
    }
    if notes.facets_without_normal > 0 {
        warnings.push(format!(
            "{} facets have no `normal` clause (tolerated)",
            notes.facets_without_normal
        ));
    }
    if notes.solids > 1 {
        warnings.push(format!(
            "the file holds {} solids; they are read as one mesh",
            notes.solids
        ));
    }
    w.finish(StlFormat::Ascii, warnings)
}

/// The warning for a binary whose header starts with `solid`.
fn solid_header_note(format: StlFormat) -> Vec<String> {
    if format == StlFormat::BinarySolidHeader {
        vec!["binary STL whose header starts with `solid` (read as binary by its length; some programs misread such files as ASCII)".to_string()]
    } else {
        Vec::new()
    }
}

/// The signatures of files people open by mistake as STL: a binary STL's 80-byte header is free
/// text, so a signature counts only when the file is not a binary STL of exactly its size.
const SIGNATURES: &[(&[u8], &str)] = &[
    (b"\x89PNG\r\n\x1a\n", "a PNG image"),
    (b"\xff\xd8\xff", "a JPEG image"),
    (b"GIF8", "a GIF image"),
    (b"%PDF", "a PDF document"),
    (
        b"PK\x03\x04",
        "a ZIP archive (a 3MF project is one: export STL instead)",
    ),
    (b"\x1f\x8b", "a gzip archive (unpack it first)"),
    (b"\xff\xfe", "a UTF-16 text (save it as UTF-8 or ASCII)"),
    (b"\xfe\xff", "a UTF-16 text (save it as UTF-8 or ASCII)"),
];

/// What another format's file looks like by its first bytes, if it is one of [`SIGNATURES`] or
/// a UTF-16 text without a byte order mark (in its first 64 bytes every other byte is 0 and
/// the others are text: a zero-filled binary header is not).
fn other_format(bytes: &[u8]) -> Option<&'static str> {
    if let Some((_, what)) = SIGNATURES.iter().find(|(sig, _)| bytes.starts_with(sig)) {
        return Some(what);
    }
    let head = &bytes[..bytes.len().min(64)];
    let text = |b: &u8| (0x09..=0x7e).contains(b);
    let utf16 = head.len() >= 16
        && (0..2).any(|p| {
            head.iter().skip(p).step_by(2).all(|&b| b == 0)
                && head.iter().skip(1 - p).step_by(2).all(text)
        });
    utf16.then_some("a UTF-16 text (save it as UTF-8 or ASCII)")
}

/// Read an STL (input frame). Defects are counted in the report, not refused; what cannot be
/// read at all is a [`MeshError`] that names the problem (and the line, for ASCII).
pub fn read_stl(bytes: &[u8]) -> Result<(Mesh, MeshReport), MeshError> {
    if bytes.is_empty() {
        return Err(MeshError::Empty);
    }
    let solid = stl_ascii::starts_with_solid(bytes);
    let count = binary_count(bytes);
    let exact = count.is_some_and(|n| binary_len(n) == bytes.len() as u64);
    if !solid && !exact {
        if let Some(looks_like) = other_format(bytes) {
            return Err(MeshError::NotStl { looks_like });
        }
    }
    let actual = bytes.len() as u64;
    let binary_format = if solid {
        StlFormat::BinarySolidHeader
    } else {
        StlFormat::Binary
    };
    if exact {
        let n = count.unwrap_or(0);
        if solid {
            if let Ok(r) = read_ascii(bytes) {
                return Ok(r);
            }
        }
        return read_binary(bytes, n, binary_format, solid_header_note(binary_format));
    }
    if solid || !looks_binary(bytes) {
        match read_ascii(bytes) {
            Ok(r) => return Ok(r),
            Err(e) if !looks_binary(bytes) => return Err(e),
            Err(_) => {}
        }
    }
    // Binary with the wrong length: bytes after the header's facets that are not a whole
    // number of records (data another program appended) are reported and ignored; whole
    // records may be facets the header does not count, so that stays an error.
    if let Some(n) = count {
        let expected = binary_len(n);
        let extra = actual.saturating_sub(expected);
        if n > 0 && extra > 0 && !extra.is_multiple_of(BINARY_FACET_BYTES as u64) {
            let mut w = solid_header_note(binary_format);
            w.push(format!(
                "{extra} bytes after the last of the header's {n} binary facets were ignored (data appended by another program; PrusaSlicer and other slicers refuse such a file — the warped STL warpslice writes has none)"
            ));
            return read_binary(bytes, n, binary_format, w);
        }
    }
    Err(binary_size_error(bytes))
}

/// Write a binary STL whose 80-byte header holds `header` (its UTF-8 bytes, truncated to 80
/// bytes, padded with spaces). Each facet's normal is the unit normal of its vertex order,
/// `n = (b−a)×(c−a) / |(b−a)×(c−a)|`, or zero for a degenerate triangle; coordinates are
/// rounded to f32. Triangles with an out-of-range vertex index are skipped.
///
/// A header that starts with `solid` is written as given; [`read_stl`] reads such files
/// correctly by their length, as do current slicers.
pub fn write_stl(mesh: &Mesh, header: &str) -> Vec<u8> {
    let valid = |t: &&[u32; 3]| t.iter().all(|&i| (i as usize) < mesh.vertices.len());
    let count = mesh.triangles.iter().filter(valid).count();
    let mut out = Vec::with_capacity(BINARY_PREFIX_BYTES + BINARY_FACET_BYTES * count);
    let h = header.as_bytes();
    let h = &h[..h.len().min(BINARY_HEADER_BYTES)];
    out.extend_from_slice(h);
    out.resize(BINARY_HEADER_BYTES, b' ');
    // More than u32::MAX facets cannot be described by the format (≥ 200 GiB of output).
    out.extend_from_slice(&u32::try_from(count).unwrap_or(u32::MAX).to_le_bytes());
    let put = |out: &mut Vec<u8>, v: DVec3| {
        for c in [v.x, v.y, v.z] {
            out.extend_from_slice(&(c as f32).to_le_bytes());
        }
    };
    for t in mesh.triangles.iter().filter(valid) {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let n = (b - a).cross(c - a);
        let len = n.length();
        let n = if len > 0.0 && len.is_finite() {
            n / len
        } else {
            DVec3::ZERO
        };
        put(&mut out, n);
        put(&mut out, a);
        put(&mut out, b);
        put(&mut out, c);
        out.extend_from_slice(&[0, 0]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed tetrahedron whose vertices are numbered in order of first use.
    fn tetra() -> Mesh {
        Mesh {
            vertices: vec![DVec3::ZERO, DVec3::Y, DVec3::X, DVec3::Z],
            triangles: vec![[0, 1, 2], [0, 2, 3], [0, 3, 1], [2, 1, 3]],
        }
    }

    #[test]
    fn binary_round_trip_welds_and_reports() {
        let bytes = write_stl(&tetra(), "t");
        assert_eq!(bytes.len(), 84 + 4 * 50);
        assert_eq!(&bytes[..2], b"t ");
        let (m, r) = read_stl(&bytes).unwrap();
        assert_eq!(m, tetra());
        assert_eq!(r.format, StlFormat::Binary);
        assert_eq!((r.flipped_normals, r.zero_normals), (0, 0));
        assert!(r.is_watertight());
    }

    #[test]
    fn negative_zero_welds_with_zero() {
        let mut m = tetra();
        m.vertices.push(DVec3::new(-0.0, 0.0, 0.0));
        m.triangles[1][0] = 4; // same position as vertex 0, spelled −0
        let (back, r) = read_stl(&write_stl(&m, "")).unwrap();
        assert_eq!(back.vertices.len(), 4);
        assert!(r.is_watertight());
    }

    #[test]
    fn header_is_truncated_to_80_bytes() {
        let long = "x".repeat(200);
        let b = write_stl(&tetra(), &long);
        assert_eq!(b.len(), 84 + 200);
        assert_eq!(u32::from_le_bytes([b[80], b[81], b[82], b[83]]), 4);
    }

    #[test]
    fn degenerate_triangle_gets_zero_normal() {
        let m = Mesh {
            vertices: vec![DVec3::ZERO, DVec3::X, DVec3::X * 2.0],
            triangles: vec![[0, 1, 2]],
        };
        let b = write_stl(&m, "");
        assert!(b[84..96].iter().all(|&x| x == 0));
    }
}
