//! Bytes of one line → words, comment and checksum.
//!
//! Grammar accepted (RepRap/Marlin dialect, what slicers write):
//!
//! ```text
//! line     := ws* [word ws*]* [ '*' digits ] [ ';' comment ]
//! word     := letter ws* [ sign ] number        (a letter alone has no value)
//! number   := digits [ '.' digits* ] | '.' digits
//! comment  := ';' anything to the end of the line  |  '(' anything up to ')'
//! ```
//!
//! Letters are case-insensitive (returned upper-case). There is no exponent: `E` is a word
//! letter, so `X1E5` is `X1` then `E5`. Numbers are converted to f64 with correct rounding
//! (Clinger's fast path when the digits fit, core's parser otherwise), so `E12345.67891` is the
//! f64 nearest to 12345.67891 on every platform.
//!
//! The checksum (`*n`) is the XOR of every byte of the line before the `*`
//! (`N123 G1 X1*cs`, RepRap host protocol).

/// One word: an upper-case letter and its value (`None` for a letter with no number, `G28 X`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    /// The word's letter, ASCII upper-case (`b'G'`, `b'X'`, …).
    pub letter: u8,
    /// The number after the letter, `None` when the letter stands alone.
    pub value: Option<f64>,
}

/// The parts of a line: where the code ends, the `;` comment, the checksum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split<'a> {
    /// The code part: the line up to the first `;` or checksum `*` (may contain `( )` comments).
    pub code: &'a [u8],
    /// The text after the first `;` outside parentheses, if any.
    pub comment: Option<&'a [u8]>,
    /// `*` checksum: (XOR of the bytes before `*`, the text of the number after it).
    pub checksum: Option<(u8, &'a [u8])>,
}

/// Eight copies of a byte.
#[inline]
const fn splat(b: u8) -> u64 {
    (b as u64) * 0x0101_0101_0101_0101
}

/// Whether any byte of `x` is zero (exact: Mycroft's SWAR test).
#[inline]
const fn has_zero(x: u64) -> bool {
    (x.wrapping_sub(splat(1)) & !x & splat(0x80)) != 0
}

/// Index of the first byte of `s` equal to one of `needles` (1–3 bytes), or `s.len()`.
/// Eight bytes at a time (SWAR), so long comment-free lines are skipped quickly.
#[inline]
pub fn find_any(s: &[u8], needles: &[u8]) -> usize {
    let masks: [u64; 3] = [
        splat(needles.first().copied().unwrap_or(0)),
        splat(needles.get(1).or(needles.first()).copied().unwrap_or(0)),
        splat(needles.get(2).or(needles.first()).copied().unwrap_or(0)),
    ];
    let mut i = 0;
    while i + 8 <= s.len() {
        let mut w = [0u8; 8];
        w.copy_from_slice(&s[i..i + 8]);
        let x = u64::from_le_bytes(w);
        if has_zero(x ^ masks[0]) || has_zero(x ^ masks[1]) || has_zero(x ^ masks[2]) {
            break;
        }
        i += 8;
    }
    while i < s.len() && !needles.contains(&s[i]) {
        i += 1;
    }
    i
}

/// Split a line (no terminator) into code, comment and checksum.
pub fn split(line: &[u8]) -> Split<'_> {
    let mut i = find_any(line, b";(*");
    let mut in_paren = false;
    while i < line.len() {
        let b = line[i];
        if in_paren {
            if b == b')' {
                in_paren = false;
            }
        } else if b == b'(' {
            in_paren = true;
        } else if b == b';' {
            return Split {
                code: &line[..i],
                comment: Some(&line[i + 1..]),
                checksum: None,
            };
        } else if b == b'*' {
            // A checksum is '*' and digits, then only blanks or a comment; otherwise the '*' is
            // part of the code (free text of M117, or a bad word the command will report).
            let rest = &line[i + 1..];
            let mut j = 0;
            while j < rest.len() && rest[j] == b' ' {
                j += 1;
            }
            let start = j;
            while j < rest.len() && rest[j].is_ascii_digit() {
                j += 1;
            }
            let digits = &rest[start..j];
            while j < rest.len() && matches!(rest[j], b' ' | b'\t') {
                j += 1;
            }
            if !digits.is_empty() && (j == rest.len() || rest[j] == b';') {
                let xor = line[..i].iter().fold(0u8, |a, &c| a ^ c);
                let comment = rest.get(j + 1..).filter(|_| j < rest.len());
                return Split {
                    code: &line[..i],
                    comment,
                    checksum: Some((xor, digits)),
                };
            }
        }
        i += 1;
    }
    Split {
        code: line,
        comment: None,
        checksum: None,
    }
}

/// Parse the checksum digits: a decimal integer 0–255.
pub fn parse_checksum(digits: &[u8]) -> Option<u8> {
    if digits.is_empty() || digits.len() > 3 {
        return None;
    }
    let mut v: u32 = 0;
    for &d in digits {
        v = v * 10 + u32::from(d - b'0');
    }
    u8::try_from(v).ok()
}

/// A word that does not parse: the byte range of the word in the code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BadWord {
    /// Byte offset of the word's first byte in the code part.
    pub start: usize,
    /// Byte offset one past the word's last byte in the code part.
    pub end: usize,
}

/// Iterator over the words of the code part of a line.
pub struct Words<'a> {
    s: &'a [u8],
    i: usize,
}

impl<'a> Words<'a> {
    /// Iterate over the words of `code`, the code part of a line (see [`Split::code`]).
    pub fn new(code: &'a [u8]) -> Words<'a> {
        Words { s: code, i: 0 }
    }

    /// Skip spaces, tabs and `( )` comments.
    #[inline]
    fn skip_blank(&mut self) {
        while self.i < self.s.len() {
            match self.s[self.i] {
                b' ' | b'\t' | b'\r' => self.i += 1,
                b'(' => match self.s[self.i..].iter().position(|&c| c == b')') {
                    Some(p) => self.i += p + 1,
                    None => self.i = self.s.len(),
                },
                _ => break,
            }
        }
    }

    /// Whether only blanks and `( )` comments remain.
    pub fn is_empty(&mut self) -> bool {
        self.skip_blank();
        self.i >= self.s.len()
    }
}

impl Iterator for Words<'_> {
    type Item = Result<Word, BadWord>;

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        self.skip_blank();
        let start = self.i;
        let &l = self.s.get(self.i)?;
        self.i += 1;
        if !l.is_ascii_alphabetic() {
            // Skip to the next blank so one bad byte gives one error.
            while self.i < self.s.len() && !matches!(self.s[self.i], b' ' | b'\t') {
                self.i += 1;
            }
            return Some(Err(BadWord { start, end: self.i }));
        }
        let letter = l.to_ascii_uppercase();
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t') {
            self.i += 1;
        }
        let num_start = self.i;
        match parse_number(&self.s[self.i..]) {
            Number::None => {
                self.i = num_start;
                Some(Ok(Word {
                    letter,
                    value: None,
                }))
            }
            Number::Ok(v, n) => {
                self.i = num_start + n;
                Some(Ok(Word {
                    letter,
                    value: Some(v),
                }))
            }
            Number::Bad(n) => {
                self.i = num_start + n;
                Some(Err(BadWord { start, end: self.i }))
            }
        }
    }
}

/// Result of reading a number at the start of a slice.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Number {
    /// No sign, digit or dot: the letter has no value.
    None,
    /// The value and the bytes consumed.
    Ok(f64, usize),
    /// A sign or dot without digits, or a value out of range; the bytes consumed.
    Bad(usize),
}

/// Powers of ten exactly representable in f64 (10^0 … 10^22).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Most digits accumulated in a u64 without overflow (10^19 < 2^64).
const MAX_FAST_DIGITS: usize = 19;

/// Longest mantissa (2^53) for which `m / 10^k` is one correctly rounded division.
const EXACT_MANTISSA: u64 = 1 << 53;

/// Read `[+-] digits [. digits]` or `[+-] . digits`.
#[inline]
fn parse_number(s: &[u8]) -> Number {
    let mut i = 0;
    let mut neg = false;
    if let Some(&c) = s.first() {
        if c == b'+' || c == b'-' {
            neg = c == b'-';
            i = 1;
        }
    }
    // Accumulate every digit (wrapping); more than MAX_FAST_DIGITS digits take the slow path,
    // so a wrapped mantissa is never used.
    let mut mantissa: u64 = 0;
    let int_start = i;
    while let Some(d) = s.get(i).map(|&c| c.wrapping_sub(b'0')).filter(|&d| d <= 9) {
        mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    let int_digits = i - int_start;
    let mut frac_digits = 0usize;
    if s.get(i) == Some(&b'.') {
        i += 1;
        let frac_start = i;
        while let Some(d) = s.get(i).map(|&c| c.wrapping_sub(b'0')).filter(|&d| d <= 9) {
            mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(d));
            i += 1;
        }
        frac_digits = i - frac_start;
    }
    if int_digits + frac_digits == 0 {
        return if i == 0 { Number::None } else { Number::Bad(i) };
    }
    let overflow = int_digits + frac_digits > MAX_FAST_DIGITS;
    let v = if !overflow && mantissa <= EXACT_MANTISSA && frac_digits < POW10.len() {
        // Both operands exact: one IEEE division is correctly rounded (Clinger 1990).
        mantissa as f64 / POW10[frac_digits]
    } else {
        match slow_parse(&s[..i]) {
            Some(v) => v.abs(),
            None => return Number::Bad(i),
        }
    };
    if !v.is_finite() {
        return Number::Bad(i);
    }
    Number::Ok(if neg { -v } else { v }, i)
}

/// A whole slice that is one number (`0.2`, `-.5`), as in `;Z:0.2`.
pub fn parse_value(s: &[u8]) -> Option<f64> {
    match parse_number(s) {
        Number::Ok(v, n) if n == s.len() => Some(v),
        _ => None,
    }
}

/// Correctly rounded parse through core (ASCII digits, sign and dot only).
fn slow_parse(text: &[u8]) -> Option<f64> {
    let t = core::str::from_utf8(text).ok()?;
    let t = t.strip_prefix('+').unwrap_or(t);
    // core rejects "5." and ".5"? It accepts both; an empty integer part is fine too.
    t.parse::<f64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &str) -> Vec<Result<Word, BadWord>> {
        Words::new(s.as_bytes()).collect()
    }

    #[test]
    fn numbers_in_every_spelling() {
        let w = words("g1 x.5 Y5. Z -1.25 e+2 F 1800");
        let v: Vec<(u8, Option<f64>)> = w
            .into_iter()
            .map(|r| r.map(|w| (w.letter, w.value)).unwrap())
            .collect();
        assert_eq!(
            v,
            vec![
                (b'G', Some(1.0)),
                (b'X', Some(0.5)),
                (b'Y', Some(5.0)),
                (b'Z', Some(-1.25)),
                (b'E', Some(2.0)),
                (b'F', Some(1800.0))
            ]
        );
    }

    #[test]
    fn letters_without_value_and_packed_words() {
        let v: Vec<Word> = words("G28 X Y").into_iter().map(|r| r.unwrap()).collect();
        assert_eq!(
            v[1],
            Word {
                letter: b'X',
                value: None
            }
        );
        let v: Vec<Word> = words("G1X1E5").into_iter().map(|r| r.unwrap()).collect();
        assert_eq!(v.len(), 3);
        assert_eq!(
            v[2],
            Word {
                letter: b'E',
                value: Some(5.0)
            }
        );
    }

    #[test]
    fn fast_and_slow_paths_agree_with_core() {
        for s in [
            "12345.67891",
            "0.1",
            "-0.3",
            "123456789012345678901234567890.5",
            "0.000000000000000000000000001",
            "9007199254740993",
            "1.00000000000000000000000000001",
        ] {
            let w = words(&format!("X{s}"));
            let got = w[0].unwrap().value.unwrap();
            assert_eq!(got, s.parse::<f64>().unwrap(), "{s}");
        }
    }

    #[test]
    fn bad_words() {
        assert!(words("X-").iter().any(|r| r.is_err()));
        assert!(words("X.").iter().any(|r| r.is_err()));
        assert!(words("1 G1").iter().any(|r| r.is_err()));
        assert!(words(&format!("X{}", "9".repeat(400)))
            .iter()
            .any(|r| r.is_err()));
    }

    #[test]
    fn split_comments_and_checksum() {
        let s = split(b"N3 T0*57 ; c");
        assert_eq!(s.code, b"N3 T0");
        assert_eq!(s.checksum.map(|c| c.0), Some(57));
        assert_eq!(s.comment, Some(&b" c"[..]));
        let s = split(b"G1 (a;b) X1 ; real");
        assert_eq!(s.comment, Some(&b" real"[..]));
        let v: Vec<Word> = Words::new(s.code).map(|r| r.unwrap()).collect();
        assert_eq!(v.len(), 2);
        assert_eq!(parse_checksum(b"255"), Some(255));
        assert_eq!(parse_checksum(b"256"), None);
        assert_eq!(parse_checksum(b""), None);
    }
}

#[cfg(test)]
mod find_tests {
    use super::find_any;

    #[test]
    fn find_any_matches_a_plain_scan_at_every_position() {
        let base = b"G1 X10.5 Y20 E0.1234 F1800 ".repeat(3);
        for k in 0..base.len() {
            for needle in [b';', b'(', b'*', b'\n'] {
                let mut s = base.clone();
                s[k] = needle;
                let want = s.iter().position(|b| b";(*".contains(b)).unwrap_or(s.len());
                assert_eq!(find_any(&s, b";(*"), want);
                let want = s.iter().position(|&b| b == b'\n').unwrap_or(s.len());
                assert_eq!(find_any(&s, b"\n"), want);
            }
        }
        assert_eq!(find_any(b"", b"\n"), 0);
        assert_eq!(find_any(&[0x80, 0xff, 0x0a], b"\n"), 2);
    }
}
