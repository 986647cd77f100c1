//! ASCII STL parser with line numbers (stl_io's reader reports none).
//!
//! Grammar (keywords case-insensitive, any whitespace incl. CRLF between tokens):
//! ```text
//! file   := solid+ | solid* solid-without-endsolid-at-EOF
//! solid  := "solid" [name to end of line] facet* "endsolid" [name to end of line]
//! facet  := "facet" ["normal" x y z] "outer" "loop" ("vertex" x y z)* "endloop" "endfacet"
//! ```
//! Numbers are parsed straight to f32 (the precision STL stores), so equal text gives equal
//! bits and vertex welding is exact. A missing `normal` and a missing final `endsolid` are
//! tolerated and noted; anything else unexpected is a [`MeshError::Syntax`] naming the line.

use super::MeshError;

/// One facet as stored: normal and three vertices (f32, as in the file).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RawFacet {
    pub normal: [f32; 3],
    pub vertices: [[f32; 3]; 3],
}

/// What the parser tolerated.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct AsciiNotes {
    /// The file ended without `endsolid`.
    pub missing_endsolid: bool,
    /// Facets without a `normal` clause.
    pub facets_without_normal: usize,
    /// Number of `solid … endsolid` blocks.
    pub solids: usize,
}

struct Lexer<'a> {
    b: &'a [u8],
    pos: usize,
    /// 1-based line of `pos`.
    line: usize,
}

#[inline]
fn is_space(c: u8) -> bool {
    matches!(c, b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c)
}

impl<'a> Lexer<'a> {
    fn new(b: &'a [u8]) -> Self {
        // UTF-8 byte-order mark
        let pos = if b.starts_with(&[0xef, 0xbb, 0xbf]) {
            3
        } else {
            0
        };
        Lexer { b, pos, line: 1 }
    }

    /// Next whitespace-separated token and its line.
    fn next(&mut self) -> Option<(&'a [u8], usize)> {
        while self.pos < self.b.len() && is_space(self.b[self.pos]) {
            if self.b[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        if self.pos >= self.b.len() {
            return None;
        }
        let s = self.pos;
        while self.pos < self.b.len() && !is_space(self.b[self.pos]) {
            self.pos += 1;
        }
        Some((&self.b[s..self.pos], self.line))
    }

    /// Skip to the end of the current line (a solid's name).
    fn skip_line(&mut self) {
        while self.pos < self.b.len() && self.b[self.pos] != b'\n' {
            self.pos += 1;
        }
    }

    /// Whether only whitespace and NUL padding remain.
    fn rest_is_blank(&self) -> bool {
        self.b[self.pos.min(self.b.len())..]
            .iter()
            .all(|&c| is_space(c) || c == 0)
    }
}

/// A token for an error message: lossy UTF-8, at most 40 characters.
fn show(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(tok);
    let mut out: String = s.chars().take(40).collect();
    if s.chars().count() > 40 {
        out.push('…');
    }
    out
}

fn syntax(line: usize, message: String) -> MeshError {
    MeshError::Syntax { line, message }
}

fn expect_kw(lx: &mut Lexer<'_>, kw: &str, context: &str) -> Result<usize, MeshError> {
    match lx.next() {
        Some((t, line)) if t.eq_ignore_ascii_case(kw.as_bytes()) => Ok(line),
        Some((t, line)) => Err(syntax(
            line,
            format!("expected `{kw}` {context}, found `{}`", show(t)),
        )),
        None => Err(syntax(
            lx.line,
            format!("unexpected end of file: expected `{kw}` {context}"),
        )),
    }
}

fn number(lx: &mut Lexer<'_>, what: &str) -> Result<f32, MeshError> {
    match lx.next() {
        Some((t, line)) => std::str::from_utf8(t)
            .ok()
            .and_then(|s| s.parse::<f32>().ok())
            .ok_or_else(|| {
                syntax(
                    line,
                    format!("expected a number ({what}), found `{}`", show(t)),
                )
            }),
        None => Err(syntax(
            lx.line,
            format!("unexpected end of file: expected a number ({what})"),
        )),
    }
}

fn xyz(lx: &mut Lexer<'_>, what: &str) -> Result<[f32; 3], MeshError> {
    Ok([number(lx, what)?, number(lx, what)?, number(lx, what)?])
}

/// Whether `bytes` (after an optional BOM and leading whitespace) begins with the keyword
/// `solid` followed by whitespace or the end of the file.
pub(crate) fn starts_with_solid(bytes: &[u8]) -> bool {
    let mut lx = Lexer::new(bytes);
    matches!(lx.next(), Some((t, _)) if t.eq_ignore_ascii_case(b"solid"))
        || bytes
            .get(..5)
            .is_some_and(|h| h.eq_ignore_ascii_case(b"solid"))
}

/// Parse an ASCII STL, handing every facet to `sink` in file order.
pub(crate) fn parse(
    bytes: &[u8],
    mut sink: impl FnMut(RawFacet) -> Result<(), MeshError>,
) -> Result<AsciiNotes, MeshError> {
    let mut lx = Lexer::new(bytes);
    let mut notes = AsciiNotes::default();
    match lx.next() {
        Some((t, _)) if t.eq_ignore_ascii_case(b"solid") => {}
        Some((t, line)) => {
            return Err(syntax(
                line,
                format!("an ASCII STL must start with `solid`, found `{}`", show(t)),
            ))
        }
        None => return Err(MeshError::NoTriangles),
    }
    lx.skip_line();
    notes.solids = 1;
    loop {
        let Some((tok, line)) = lx.next() else {
            notes.missing_endsolid = true;
            return Ok(notes);
        };
        if tok.eq_ignore_ascii_case(b"facet") {
            sink(facet(&mut lx, line, &mut notes)?)?;
        } else if tok.eq_ignore_ascii_case(b"endsolid") {
            lx.skip_line();
            if lx.rest_is_blank() {
                return Ok(notes);
            }
            match lx.next() {
                Some((t, _)) if t.eq_ignore_ascii_case(b"solid") => {
                    lx.skip_line();
                    notes.solids += 1;
                }
                Some((t, line)) => {
                    return Err(syntax(
                        line,
                        format!(
                            "expected `solid` or the end of the file after `endsolid`, found `{}`",
                            show(t)
                        ),
                    ))
                }
                None => return Ok(notes),
            }
        } else {
            return Err(syntax(
                line,
                format!("expected `facet` or `endsolid`, found `{}`", show(tok)),
            ));
        }
    }
}

/// The rest of a facet after its `facet` keyword (on line `facet_line`).
fn facet(
    lx: &mut Lexer<'_>,
    facet_line: usize,
    notes: &mut AsciiNotes,
) -> Result<RawFacet, MeshError> {
    let mut normal = [0.0f32; 3];
    match lx.next() {
        Some((t, _)) if t.eq_ignore_ascii_case(b"normal") => {
            normal = xyz(lx, "facet normal")?;
            expect_kw(lx, "outer", "after the facet normal")?;
        }
        Some((t, _)) if t.eq_ignore_ascii_case(b"outer") => notes.facets_without_normal += 1,
        Some((t, line)) => {
            return Err(syntax(
                line,
                format!("expected `normal` after `facet`, found `{}`", show(t)),
            ))
        }
        None => {
            return Err(syntax(
                lx.line,
                "unexpected end of file inside a facet".into(),
            ))
        }
    }
    expect_kw(lx, "loop", "after `outer`")?;
    let mut vertices = [[0.0f32; 3]; 3];
    let mut n = 0usize;
    loop {
        match lx.next() {
            Some((t, _)) if t.eq_ignore_ascii_case(b"vertex") => {
                let v = xyz(lx, "vertex coordinate")?;
                if let Some(slot) = vertices.get_mut(n) {
                    *slot = v;
                }
                n += 1;
            }
            Some((t, _)) if t.eq_ignore_ascii_case(b"endloop") => break,
            Some((t, line)) => {
                return Err(syntax(
                    line,
                    format!("expected `vertex` or `endloop`, found `{}`", show(t)),
                ))
            }
            None => {
                return Err(syntax(
                    lx.line,
                    format!(
                        "unexpected end of file inside the facet that starts on line {facet_line}"
                    ),
                ))
            }
        }
    }
    if n != 3 {
        return Err(MeshError::NotATriangle {
            line: facet_line,
            vertices: n,
        });
    }
    expect_kw(lx, "endfacet", "after `endloop`")?;
    Ok(RawFacet { normal, vertices })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(src: &str) -> Result<(Vec<RawFacet>, AsciiNotes), MeshError> {
        let mut v = Vec::new();
        let notes = parse(src.as_bytes(), |f| {
            v.push(f);
            Ok(())
        })?;
        Ok((v, notes))
    }

    const ONE: &str = "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n";

    #[test]
    fn one_facet() {
        let (f, n) = all(ONE).unwrap();
        assert_eq!(f.len(), 1);
        assert_eq!(f[0].vertices[1], [1.0, 0.0, 0.0]);
        assert_eq!(f[0].normal, [0.0, 0.0, 1.0]);
        assert!(!n.missing_endsolid);
    }

    #[test]
    fn crlf_and_uppercase() {
        let src = ONE.replace('\n', "\r\n").to_uppercase();
        let (f, _) = all(&src).unwrap();
        assert_eq!(f.len(), 1);
    }

    #[test]
    fn quad_facet_is_not_a_triangle_with_its_line() {
        let src = ONE.replace("   vertex 0 1 0\n", "   vertex 0 1 0\n   vertex 1 1 0\n");
        assert_eq!(
            all(&src).unwrap_err(),
            MeshError::NotATriangle {
                line: 2,
                vertices: 4
            }
        );
    }

    #[test]
    fn bad_number_names_its_line() {
        let src = ONE.replace("vertex 1 0 0", "vertex 1 zero 0");
        match all(&src).unwrap_err() {
            MeshError::Syntax { line, message } => {
                assert_eq!(line, 5);
                assert!(message.contains("zero"), "{message}");
            }
            e => panic!("{e:?}"),
        }
    }

    #[test]
    fn missing_endsolid_is_noted() {
        let src = ONE.replace("endsolid t\n", "");
        let (f, n) = all(&src).unwrap();
        assert_eq!(f.len(), 1);
        assert!(n.missing_endsolid);
    }

    #[test]
    fn eof_inside_facet_is_a_syntax_error() {
        let src = &ONE[..ONE.find("endloop").unwrap()];
        assert!(matches!(all(src).unwrap_err(), MeshError::Syntax { .. }));
    }

    #[test]
    fn two_solids_and_trailing_nul_padding() {
        let src = format!("{ONE}{ONE}\0\0\0");
        let (f, n) = all(&src).unwrap();
        assert_eq!((f.len(), n.solids), (2, 2));
    }

    #[test]
    fn garbage_after_endsolid_is_a_syntax_error() {
        let src = format!("{ONE}garbage\n");
        assert_eq!(
            all(&src).unwrap_err(),
            MeshError::Syntax {
                line: 10,
                message:
                    "expected `solid` or the end of the file after `endsolid`, found `garbage`"
                        .into()
            }
        );
    }
}
