//! Fuzz the streaming G-code reader: arbitrary bytes cut into arbitrary chunks must never
//! panic, and must give the same lines, states and error as one chunk.
#![no_main]

use libfuzzer_sys::fuzz_target;
use warpslice::gcode::{GcodeError, ReadOptions, Reader};

/// Everything the sink sees, flattened for comparison.
fn run(data: &[u8], cuts: &[usize]) -> (Vec<String>, Result<(), GcodeError>) {
    let mut out = Vec::new();
    let mut reader = Reader::new(ReadOptions::default());
    let mut sink = |line: warpslice::gcode::Line<'_>, state: &warpslice::gcode::State| {
        out.push(format!(
            "{:?} {:?} {:?} {}",
            line.raw,
            line.command,
            state,
            line.moves.len()
        ));
        for m in line.moves {
            out.push(format!("{m:?}"));
        }
        Ok::<(), GcodeError>(())
    };
    let mut start = 0;
    let mut r = Ok(());
    for &c in cuts {
        let end = c.min(data.len()).max(start);
        r = reader.push(&data[start..end], &mut sink);
        start = end;
        if r.is_err() {
            break;
        }
    }
    if r.is_ok() {
        r = reader.push(&data[start..], &mut sink);
    }
    if r.is_ok() {
        r = reader.finish(&mut sink);
    }
    (out, r)
}

fuzz_target!(|input: &[u8]| {
    // First byte: a chunking seed; the rest is the G-code.
    let Some((&seed, data)) = input.split_first() else {
        return;
    };
    let whole = run(data, &[]);
    let step = usize::from(seed % 17) + 1;
    let cuts: Vec<usize> = (1..=data.len() / step).map(|k| k * step).collect();
    let chunked = run(data, &cuts);
    assert_eq!(whole, chunked);
});
