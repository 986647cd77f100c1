//! Deterministic number formatting for output G-code, and a move writer that omits unchanged
//! words.
//!
//! A value v with d decimals is written as n = round(v·10^d) (half away from zero; an exact
//! operation) split into integer and fraction digits by integer arithmetic, then trailing
//! zeros and a bare dot are trimmed and a zero is written `0` (never `-0`). Only IEEE
//! multiplication and rounding are involved, so native and wasm builds write the same bytes.
//! Values with |v·10^d| ≥ 9·10^15 (beyond exact integers) go through core's exact decimal
//! formatting instead; non-finite values are written as core writes them (`NaN`, `inf`) —
//! callers must not pass them.

use glam::DVec3;

/// Decimals of coordinates (mm) and angles (degrees): 0.001 mm.
pub const MM_DECIMALS: u32 = 3;
/// Decimals of E (mm of filament): 0.00001 mm.
pub const E_DECIMALS: u32 = 5;
/// Decimals of feed rates (mm/min).
pub const FEED_DECIMALS: u32 = 3;
/// Largest |v·10^d| handled with integers (below 2^53, where every integer is exact).
const EXACT_LIMIT: f64 = 9.0e15;

/// Append a coordinate in mm (3 decimals, trailing zeros trimmed, no `-0`).
pub fn push_mm(out: &mut Vec<u8>, v: f64) {
    push_fixed(out, v, MM_DECIMALS);
}
/// Append an E value (5 decimals, trailing zeros trimmed, no `-0`).
pub fn push_e(out: &mut Vec<u8>, v: f64) {
    push_fixed(out, v, E_DECIMALS);
}
/// Append a feed rate in mm/min (at most 3 decimals, trimmed).
pub fn push_feed(out: &mut Vec<u8>, v: f64) {
    push_fixed(out, v, FEED_DECIMALS);
}

/// round(v·10^d) when exact, else `None`.
#[inline]
fn scaled(v: f64, decimals: u32) -> Option<i64> {
    let x = v * pow10(decimals);
    if x.abs() < EXACT_LIMIT {
        Some(crate::num::round(x) as i64)
    } else {
        None
    }
}

#[inline]
fn pow10(decimals: u32) -> f64 {
    const P: [f64; 10] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];
    P[(decimals as usize).min(P.len() - 1)]
}

/// The number a reader gets back from what [`push_fixed`]`(v, decimals)` writes:
/// `round(v·10^d) / 10^d` (IEEE division is correctly rounded, so this is the f64 nearest the
/// written decimal, as a parser reads it). `v` itself beyond the exact range.
pub fn written_value(v: f64, decimals: u32) -> f64 {
    let decimals = decimals.min(9);
    match scaled(v, decimals) {
        Some(n) => n as f64 / pow10(decimals),
        None => v,
    }
}

/// [`push_mm`] returning what a reader gets back from the word written
/// ([`written_value`]`(v, MM_DECIMALS)`), from the one rounding both need (the machine
/// emitter times and checks each move by its written values).
pub fn push_mm_read(out: &mut Vec<u8>, v: f64) -> f64 {
    match scaled(v, MM_DECIMALS) {
        Some(n) => {
            push_scaled(out, n, MM_DECIMALS);
            n as f64 / pow10(MM_DECIMALS)
        }
        None => {
            push_core(out, v, MM_DECIMALS);
            v
        }
    }
}

/// Append `v` with at most `decimals` decimals (0–9), trimmed, never `-0`.
pub fn push_fixed(out: &mut Vec<u8>, v: f64, decimals: u32) {
    let decimals = decimals.min(9);
    match scaled(v, decimals) {
        Some(n) => push_scaled(out, n, decimals),
        None => push_core(out, v, decimals),
    }
}

/// Append n·10^−d (`decimals` ≤ 9, |n| < 2⁶³): the digits are assembled right to left in a
/// stack buffer and appended at once. One 64-bit division splits |n| into the integer part and
/// the fraction (< 10⁹); everything else is 32-bit arithmetic on values below 2³², where a
/// division by a constant is a multiplication in wasm too (a 64-bit one needs the high half of
/// a 128-bit product, which wasm lacks).
fn push_scaled(out: &mut Vec<u8>, n: i64, decimals: u32) {
    if n == 0 {
        out.push(b'0');
        return;
    }
    let a = n.unsigned_abs();
    let d = decimals as usize;
    let p = POW10_U64[d];
    let (int, frac) = (a / p, (a % p) as u32);
    // sign, ≤ 19 integer digits, the dot and ≤ 9 decimals
    let mut buf = [b'0'; 32];
    let mut end = buf.len();
    let mut start = end - d;
    if frac == 0 {
        end = start;
    } else {
        // d digits with leading zeros, then the trailing zeros trimmed
        let mut f = frac;
        for b in buf[start..end].iter_mut().rev() {
            *b = b'0' + (f % 10) as u8;
            f /= 10;
        }
        while buf[end - 1] == b'0' {
            end -= 1;
        }
        start -= 1;
        buf[start] = b'.';
    }
    start = digits_before(&mut buf, start, int);
    if n < 0 {
        start -= 1;
        buf[start] = b'-';
    }
    out.extend_from_slice(&buf[start..end]);
}

/// 10^d for d = 0..=9.
const POW10_U64: [u64; 10] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
    1_000_000_000,
];

/// Writes the decimal digits of `v` into `buf` ending just before `end` (at least one digit,
/// `0` for 0); returns where they start.
fn digits_before(buf: &mut [u8], mut end: usize, mut v: u64) -> usize {
    while v > u64::from(u32::MAX) {
        end -= 1;
        buf[end] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    let mut w = v as u32;
    loop {
        end -= 1;
        buf[end] = b'0' + (w % 10) as u8;
        w /= 10;
        if w == 0 {
            return end;
        }
    }
}

/// Huge or non-finite values: core's exact formatting, trimmed.
fn push_core(out: &mut Vec<u8>, v: f64, decimals: u32) {
    use std::io::Write;
    let start = out.len();
    // Writing into a Vec cannot fail.
    let _ = write!(out, "{:.*}", decimals as usize, v);
    if out[start..].contains(&b'.') {
        while out.last() == Some(&b'0') {
            out.pop();
        }
        if out.last() == Some(&b'.') {
            out.pop();
        }
    }
}

/// Writes `G0`/`G1` lines, leaving out X Y Z, rotary axes and F when their written value is
/// the one last written, and E when it rounds to 0. The comparison is on the rounded values,
/// so an omitted word is exactly what the printer already has.
///
/// Call [`MoveWriter::forget`] after writing anything that moves the machine or changes its
/// coordinates behind the writer's back (passed-through moves, G92, G28).
#[derive(Clone, Debug, Default)]
pub struct MoveWriter {
    xyz: [Option<i64>; 3],
    /// A, B, C (degrees).
    abc: [Option<i64>; 3],
    f: Option<i64>,
}

impl MoveWriter {
    /// A writer that has written nothing yet (the first move writes every axis it is given, and F).
    pub fn new() -> MoveWriter {
        MoveWriter::default()
    }

    /// Forget the last position (the next move writes every axis it is given).
    pub fn forget(&mut self) {
        self.xyz = [None; 3];
        self.abc = [None; 3];
    }

    /// Forget the last feed rate (the next move writes F).
    pub fn forget_feed(&mut self) {
        self.f = None;
    }

    /// `G0`/`G1` to `to` (mm) pushing `e` mm of filament (a relative E, for M83 output) at feed
    /// `f` (mm/min). Returns whether a line was written (nothing changes → nothing written).
    pub fn linear(&mut self, out: &mut Vec<u8>, rapid: bool, to: DVec3, e: f64, f: f64) -> bool {
        self.linear_axes(out, rapid, to, &[], e, f)
    }

    /// Like [`MoveWriter::linear`] with rotary axes `(letter, degrees)`, letters `A`, `B`, `C`
    /// (others are ignored), written after Z in the order given.
    pub fn linear_axes(
        &mut self,
        out: &mut Vec<u8>,
        rapid: bool,
        to: DVec3,
        rotary: &[(u8, f64)],
        e: f64,
        f: f64,
    ) -> bool {
        let start = out.len();
        out.extend_from_slice(if rapid { b"G0" } else { b"G1" });
        let mut any = false;
        for (k, letter) in [b'X', b'Y', b'Z'].into_iter().enumerate() {
            any |= word(out, letter, to[k], MM_DECIMALS, &mut self.xyz[k]);
        }
        for &(letter, v) in rotary {
            if let Some(k) = letter.checked_sub(b'A').filter(|&k| k < 3) {
                any |= word(out, letter, v, MM_DECIMALS, &mut self.abc[k as usize]);
            }
        }
        if scaled(e, E_DECIMALS) != Some(0) {
            out.extend_from_slice(b" E");
            push_e(out, e);
            any = true;
        }
        any |= word(out, b'F', f, FEED_DECIMALS, &mut self.f);
        if any {
            out.push(b'\n');
        } else {
            out.truncate(start);
        }
        any
    }
}

/// Write ` Lv` unless `v` rounds to `last`; update `last`.
fn word(out: &mut Vec<u8>, letter: u8, v: f64, decimals: u32, last: &mut Option<i64>) -> bool {
    let k = scaled(v, decimals);
    if k.is_some() && k == *last {
        return false;
    }
    *last = k;
    out.push(b' ');
    out.push(letter);
    match k {
        Some(n) => push_scaled(out, n, decimals),
        None => push_core(out, v, decimals),
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(f: fn(&mut Vec<u8>, f64), v: f64) -> String {
        let mut o = Vec::new();
        f(&mut o, v);
        String::from_utf8(o).unwrap()
    }

    type Push = fn(&mut Vec<u8>, f64);

    #[test]
    fn formatting_table() {
        let cases: &[(Push, f64, &str)] = &[
            (push_mm, 0.0, "0"),
            (push_mm, -0.0, "0"),
            (push_mm, -0.0004, "0"),
            (push_mm, 1.5, "1.5"),
            (push_mm, 2.0, "2"),
            (push_mm, -2.25, "-2.25"),
            (push_mm, 0.2, "0.2"),
            (push_mm, 100.0006, "100.001"),
            (push_mm, -0.0006, "-0.001"),
            (push_mm, 123.456789, "123.457"),
            (push_e, 12345.67891, "12345.67891"),
            (push_e, 0.000004, "0"),
            (push_e, -0.8, "-0.8"),
            (push_e, 0.01, "0.01"),
            (push_feed, 1800.0, "1800"),
            (push_feed, 1234.5678, "1234.568"),
            (push_mm, 1e20, "100000000000000000000"),
            (push_mm, -1.5e17, "-150000000000000000"),
        ];
        for &(f, v, want) in cases {
            assert_eq!(s(f, v), want, "{v}");
        }
    }

    /// What `push_fixed(v, d)` must write, by std's rounding and integer formatting and string
    /// work: round(v·10^d) as digits, the dot inserted d digits from the right, trailing zeros
    /// and a bare dot trimmed, `-` only before a nonzero value.
    fn fixed_oracle(v: f64, d: u32) -> String {
        let scale: f64 = format!("1e{d}").parse().unwrap();
        let n = (v * scale).round();
        let digits = format!("{:0>w$}", n.abs() as u64, w = d as usize + 1);
        let (int, frac) = digits.split_at(digits.len() - d as usize);
        let frac = frac.trim_end_matches('0');
        let body = if frac.is_empty() {
            int.to_string()
        } else {
            format!("{int}.{frac}")
        };
        if n < 0.0 && body != "0" {
            format!("-{body}")
        } else {
            body
        }
    }

    #[test]
    fn fixed_point_text_matches_a_string_oracle() {
        let mut rng = crate::test_rng::Lcg(7);
        let mut cases = vec![
            (0.0, 3),
            (4_294.967_295, 3),
            (4_294.967_296, 3),
            (-4_294.967_296, 3),
            (42_949.672_96, 5),
            (80_142.725_49, 5),
            (8.999e15, 0),
            (-8.999e11, 4),
            (0.000_000_001, 9),
            (-0.000_000_000_5, 9),
            (1.0, 9),
            (0.1, 1),
        ];
        for _ in 0..100_000 {
            let d = (rng.unit() * 10.0) as u32;
            // magnitudes up to the exact range (|v·10^d| < 9·10^15), and values on the grid
            let m = 10f64.powf(rng.range(-(d as f64) - 1.0, 15.0 - d as f64));
            let v = rng.range(-m, m);
            cases.push((v, d));
            let grid: f64 = format!("1e-{d}").parse().unwrap();
            cases.push(((v / grid).trunc() * grid, d));
        }
        for (v, d) in cases {
            let mut o = Vec::new();
            push_fixed(&mut o, v, d);
            assert_eq!(
                String::from_utf8(o).unwrap(),
                fixed_oracle(v, d),
                "{v:e} with {d} decimals"
            );
        }
    }

    #[test]
    fn push_mm_read_writes_push_mm_and_returns_the_written_value() {
        let mut rng = crate::test_rng::Lcg(7);
        let mut values = vec![0.0, -0.0, -0.0004, 0.0005, -0.0005, 1e20, -1.5e17, 9.0e12];
        values.extend([f64::NAN, f64::INFINITY, f64::NEG_INFINITY]);
        for _ in 0..20_000 {
            let mag = 10f64.powf(rng.range(-5.0, 14.0));
            let v = rng.range(-mag, mag);
            values.push(v);
            // on a written step's half: the rounding's tie
            values.push(((v * 1e3).trunc() + 0.5) / 1e3);
        }
        for v in values {
            let (mut a, mut b) = (Vec::new(), Vec::new());
            let r = push_mm_read(&mut a, v);
            push_mm(&mut b, v);
            assert_eq!(a, b, "{v:e}");
            let w = written_value(v, MM_DECIMALS);
            assert!(
                r.to_bits() == w.to_bits() || (r.is_nan() && w.is_nan()),
                "{v:e}: {r} vs {w}"
            );
        }
    }

    #[test]
    fn move_writer_omits_unchanged_words() {
        let mut w = MoveWriter::new();
        let mut o = Vec::new();
        assert!(w.linear(&mut o, false, DVec3::new(1.0, 2.0, 0.2), 0.5, 1800.0));
        assert!(w.linear(&mut o, false, DVec3::new(3.0, 2.0004, 0.2), 0.0, 1800.0));
        assert!(!w.linear(&mut o, false, DVec3::new(3.0, 2.0, 0.2), 0.000001, 1800.0));
        assert!(w.linear_axes(
            &mut o,
            true,
            DVec3::new(3.0, 2.0, 0.2),
            &[(b'B', -15.0)],
            0.0,
            7200.0
        ));
        w.forget();
        assert!(w.linear(&mut o, false, DVec3::new(3.0, 2.0, 0.2), -0.8, 7200.0));
        assert_eq!(
            String::from_utf8(o).unwrap(),
            "G1 X1 Y2 Z0.2 E0.5 F1800\nG1 X3\nG0 B-15 F7200\nG1 X3 Y2 Z0.2 E-0.8\n"
        );
    }
}
