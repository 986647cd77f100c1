//! Writer round trips: text → parsed → written → parsed gives the same moves.

use glam::DVec3;
use warpslice::gcode::write::{push_e, push_feed, push_mm};
use warpslice::gcode::{GcodeError, Line, Move, MoveWriter, Reader, State};

fn parse(text: &[u8]) -> Vec<Move> {
    let mut out = Vec::new();
    let mut reader = Reader::default();
    let mut sink = |l: Line<'_>, _: &State| {
        out.extend_from_slice(l.moves);
        Ok::<(), GcodeError>(())
    };
    reader.push(text, &mut sink).unwrap();
    reader.finish(&mut sink).unwrap();
    out
}

/// Write moves as the output does: relative E (M83), absolute XYZ, unchanged words omitted.
fn write(moves: &[Move]) -> Vec<u8> {
    let mut out = b"G21\nG90\nM83\n".to_vec();
    let mut w = MoveWriter::new();
    for m in moves {
        w.linear(&mut out, m.rapid, m.to, m.e, m.f);
    }
    out
}

/// Same moves up to the written precision, ignoring pieces that move nothing and push nothing.
fn same(a: &[Move], b: &[Move]) {
    let keep = |m: &&Move| (m.to - m.from).length() > 5e-4 || m.e.abs() > 5e-6;
    let a: Vec<&Move> = a.iter().filter(keep).collect();
    let b: Vec<&Move> = b.iter().filter(keep).collect();
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (x.to - y.to).abs().max_element() <= 5e-4 + 1e-12,
            "{x:?} {y:?}"
        );
        assert!((x.e - y.e).abs() <= 5e-6 + 1e-12, "{x:?} {y:?}");
        assert_eq!(x.rapid, y.rapid);
    }
}

#[test]
fn round_trip_table() {
    let table: &[&str] = &[
        "G1 X10 Y10 Z0.2 F1800\nG1 X20 E0.5\nG1 Y20 E1.5\nG0 X0 Y0 F7200\n",
        "M82\nG92 E0\nG1 X1 Y1 E0.1\nG1 X2 Y1 E0.3\nG1 E-0.5\nG92 E0\nG1 X3 E0.2\n",
        "G91\nG1 X1 Y1 E1 F600\nG1 X1 Y-1 E1\nG90\nG1 X0 Y0\n",
        "G20\nG1 X1 Y1 F10\nG1 X2 E0.01\n",
        "G1 X10 Y0 F1200\nG3 X0 Y10 I-10 J0 E3\nG2 X10 Y0 R-10 E1\nG2 X10 Y0 I-10 J0 Z1 E2\n",
        "G1 X-0.0001 Y.0004 E.000004\nG1 X123.4567 Y-98.7654 E12345.67891\n",
    ];
    for text in table {
        let first = parse(text.as_bytes());
        let written = write(&first);
        let second = parse(&written);
        same(&first, &second);
        // Writing again gives the same bytes (the format is a fixed point).
        assert_eq!(write(&second), written, "{text}");
    }
}

#[test]
fn exact_text_survives_parse_and_write() {
    let text = "G1 X10.5 Y-0.2 Z0.35 E0.12345 F1800\nG1 X11 E0.5\nG0 X0.001 F7200.5\n";
    let moves = parse(format!("M83\n{text}").as_bytes());
    let mut out = Vec::new();
    let mut w = MoveWriter::new();
    for m in &moves {
        w.linear(&mut out, m.rapid, m.to, m.e, m.f);
    }
    assert_eq!(String::from_utf8(out).unwrap(), text);
}

#[test]
fn numbers_never_print_negative_zero_and_trim() {
    let mut o = Vec::new();
    for v in [-0.0, -1e-9, -0.00049, 0.00049] {
        o.clear();
        push_mm(&mut o, v);
        assert_eq!(o, b"0");
    }
    o.clear();
    push_e(&mut o, -0.000004);
    assert_eq!(o, b"0");
    o.clear();
    push_feed(&mut o, 2400.0);
    assert_eq!(o, b"2400");
    // Every parsed 3-decimal value is written back as itself.
    for k in -20000i64..20000 {
        let text = format!("{}", k as f64 / 1000.0);
        let v: f64 = text.parse().unwrap();
        o.clear();
        push_mm(&mut o, v);
        assert_eq!(String::from_utf8_lossy(&o), text);
    }
}

#[test]
fn move_writer_writes_the_first_move_in_full() {
    let mut o = Vec::new();
    let mut w = MoveWriter::new();
    assert!(w.linear(&mut o, true, DVec3::ZERO, 0.0, 600.0));
    assert_eq!(o, b"G0 X0 Y0 Z0 F600\n");
}
