//! Fuzz the streaming G-code reader: arbitrary bytes cut into arbitrary chunks must never
//! panic, and must give the same lines, states, move pieces and error as one chunk.
#![no_main]

use libfuzzer_sys::fuzz_target;
use warpslice::gcode::{GcodeError, Line, Move, ReadOptions, Reader, State};

/// What the sink saw, flattened; floats as bits so NaN compares equal to itself.
#[derive(PartialEq, Debug)]
struct Seen {
    raw: Vec<u8>,
    number: u64,
    command: String,
    layer_start: bool,
    state: Vec<u64>,
    moves: Vec<u64>,
}

fn bits3(v: [f64; 3]) -> [u64; 3] {
    v.map(f64::to_bits)
}

fn state_bits(s: &State) -> Vec<u64> {
    let mut v = bits3(s.position.to_array()).to_vec();
    v.extend([
        s.e.to_bits(),
        s.feed.to_bits(),
        u64::from(s.layer),
        u64::from(s.e_relative) | u64::from(s.positioning_relative) << 1 | u64::from(s.inch) << 2,
        u64::from(s.layer_markers),
        s.layer_z.map_or(1, f64::to_bits),
    ]);
    v
}

fn move_bits(m: &Move, out: &mut Vec<u64>) {
    out.extend(bits3(m.from.to_array()));
    out.extend(bits3(m.to.to_array()));
    out.extend([
        m.e.to_bits(),
        m.f.to_bits(),
        u64::from(m.layer),
        u64::from(m.rapid),
    ]);
}

fn run(data: &[u8], step: usize) -> (Vec<Seen>, Result<(), GcodeError>) {
    let mut out = Vec::new();
    let mut reader = Reader::new(ReadOptions::default());
    let mut sink = |line: Line<'_>, state: &State| {
        let mut moves = Vec::with_capacity(line.moves.len() * 10);
        for m in line.moves {
            move_bits(m, &mut moves);
        }
        out.push(Seen {
            raw: line.raw.to_vec(),
            number: line.number,
            command: format!("{:?} {:?}", line.command, state.feature),
            layer_start: line.layer_start,
            state: state_bits(state),
            moves,
        });
        Ok::<(), GcodeError>(())
    };
    let mut r = Ok(());
    for c in data.chunks(step.max(1)) {
        r = reader.push(c, &mut sink);
        if r.is_err() {
            break;
        }
    }
    if r.is_ok() {
        r = reader.finish(&mut sink);
    }
    // Errors are sticky.
    if let Err(e) = &r {
        assert_eq!(reader.push(b"G1 X1\n", &mut sink).as_ref(), Err(e));
    }
    (out, r)
}

fuzz_target!(|input: &[u8]| {
    // First byte: the chunk size; the rest is the G-code.
    let Some((&seed, data)) = input.split_first() else {
        return;
    };
    let whole = run(data, data.len());
    let chunked = run(data, usize::from(seed % 17) + 1);
    assert_eq!(whole, chunked);
});
