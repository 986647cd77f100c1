//! Fuzz the whole unwarp, 3-axis and through every machine preset: a valid slicer G-code of
//! a warped 6 mm cube (the tests' synthetic slicer, conic 30° outward) edited by the fuzzer
//! (lines replaced, inserted or deleted) must give an output or a named error, never a panic
//! or a hang (libFuzzer's `-timeout` bounds one run).
//!
//! Input layout: byte 0 chooses the output (0: 3-axis, else a machine preset), byte 1 the E
//! mode of the base file; then edits, each `[line hi, line lo, kind, len, len bytes]`.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use warpslice::machine::{preset, preset_names};
use warpslice::pipeline::{unwarp, UnwarpSettings, WarpOutput};
use warpslice::unwarp::UnwarpOptions;

#[path = "../../tests/common/synthetic.rs"]
#[allow(dead_code)]
mod synthetic;

/// Infill spacing of the base files, mm: sparse, so one run stays short under the sanitizer.
const INFILL_STEP: f64 = 2.0;
/// Edge of the fuzzed cube, mm (the tests' cube is 20 mm: scaled down, ~30 layers).
const CUBE_MM: f64 = 6.0;

struct Base {
    part: WarpOutput,
    /// The base G-code's lines, absolute and relative E.
    lines: [Vec<String>; 2],
}

fn base() -> &'static Base {
    static BASE: OnceLock<Base> = OnceLock::new();
    BASE.get_or_init(|| {
        let part = synthetic::conic_cube_of(CUBE_MM);
        let lines = [false, true].map(|relative| {
            synthetic::gcode(&part.job, relative, INFILL_STEP)
                .lines()
                .map(str::to_string)
                .collect()
        });
        Base { part, lines }
    })
}

fuzz_target!(|data: &[u8]| {
    let Some((&[out, mode], mut rest)) = data.split_first_chunk::<2>().map(|(a, r)| (a, r)) else {
        return;
    };
    let b = base();
    let mut lines: Vec<Vec<u8>> = b.lines[usize::from(mode & 1)]
        .iter()
        .map(|l| l.as_bytes().to_vec())
        .collect();
    while let Some((&[hi, lo, kind, len], r)) = rest.split_first_chunk::<4>().map(|(a, r)| (a, r))
    {
        let take = usize::from(len).min(r.len());
        let (text, r) = r.split_at(take);
        rest = r;
        if lines.is_empty() {
            break;
        }
        let at = usize::from(u16::from_be_bytes([hi, lo])) % lines.len();
        match kind % 3 {
            0 => lines[at] = text.to_vec(),
            1 => lines.insert(at, text.to_vec()),
            _ => {
                lines.remove(at);
            }
        }
    }
    let gcode = lines.join(&b'\n');
    let names = preset_names();
    let settings = match usize::from(out) % (names.len() + 1) {
        0 => UnwarpSettings::three_axis(UnwarpOptions::default()),
        i => UnwarpSettings::with_machine(
            UnwarpOptions::default(),
            preset(names[i - 1]).expect("every named preset loads"),
        ),
    };
    if let Ok(o) = unwarp(&gcode, &b.part.job, &settings) {
        assert!(!o.gcode.is_empty(), "an accepted unwarp writes something");
    }
});
