//! A second G-code interpreter as an oracle: LinuxCNC's RS274NGC interpreter (Debian's
//! linuxcnc-uspace, its Python module `gcode`, run by `scripts/rs274_oracle.py`; installed,
//! extracted not installed, by `scripts/setup.sh rs274`) reads every machine output — every
//! preset, `--feed tip` and `--feed inverse-time` (RepRapFirmware, the flavour that has G93) —
//! and every motion it reports is compared, line by line, with the tests' own walk of the same
//! file (`tests/common/firmware.rs`: positions with `G92` renames, modal F): every axis value
//! within 0.001 mm / 0.001°, the extruder (mapped to a spare axis letter) within 0.001 mm, the
//! feed mode (G93 inverse time or G94 units per minute) the walk's, and its rate the file's F.
//!
//! What the interpreter is given (the harness here, not the oracle): the file with each line's
//! comment removed; `G0`/`G1`/`G92`/`G90`/`G93`/`G94`/`G21` kept; E mapped to the first of
//! A B C U V W the machine does not use, as the cumulative filament (relative or absolute E,
//! `G92 E` resets, read here); every other command (M-codes, `G28`, `T…`, `G4`) blanked, so
//! the line numbers stay the file's. The machine letters all fit LinuxCNC's X Y Z A B C U V W
//! and keep their names (docs/machines.md gives each preset's letters): no mapping needed.
//!
//! The G-code is the synthetic slicer's for the job the CLI wrote (tests/common/cli_part.rs).
//! Without the interpreter the test fails with the reason, unless `WARPSLICE_ALLOW_SKIP=1`
//! (then it prints that it skipped and why).
#![cfg(not(target_arch = "wasm32"))]

#[path = "common/cli_part.rs"]
#[allow(dead_code)]
mod cli_part;
#[path = "common/firmware.rs"]
#[allow(dead_code)]
mod firmware;
#[path = "common/skip.rs"]
#[allow(dead_code)]
mod skip;
#[path = "common/synthetic.rs"]
#[allow(dead_code)]
mod synthetic;

use std::collections::BTreeMap;
use std::process::Command;

use cli_part::{cases, documented, machine_arg, Part};

/// The largest difference allowed between the interpreter's and the walk's axis values (mm or
/// degrees): both read the same 3-decimal numbers, so this bounds unit conversion only.
const AXIS_TOL: f64 = 1e-3;
/// Relative difference allowed between the interpreter's feed rate and the file's F (it prints
/// 9 significant digits after an inch round trip).
const FEED_REL_TOL: f64 = 1e-6;

/// LinuxCNC's "moves" threshold of `find_straight_length` (1e-7 in its internal inches), mm.
const RS274_TINY_MM: f64 = 1e-7 * 25.4;

/// LinuxCNC's axis letters, in the order the oracle prints them.
const LINUXCNC: [char; 9] = ['X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W'];

fn script() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/rs274_oracle.py").to_string()
}

/// Whether the interpreter runs here; the reason when not.
fn available() -> Result<(), String> {
    let o = Command::new("python3")
        .args([&script(), "--probe"])
        .output()
        .map_err(|e| format!("python3: {e}"))?;
    if o.status.success() {
        Ok(())
    } else {
        Err(format!(
            "LinuxCNC's gcode module is not installed ({}); `bash scripts/setup.sh rs274` extracts it",
            String::from_utf8_lossy(&o.stderr).trim()
        ))
    }
}

/// The first of A B C U V W the machine's `letters` leave free: the extruder's letter.
fn spare(letters: &str) -> char {
    "ABCUVW"
        .chars()
        .find(|c| !letters.contains(*c))
        .expect("a free letter")
}

/// The file as the interpreter gets it (see the module documentation); one line per line.
fn for_interpreter(text: &str, letters: &str) -> String {
    let e_letter = spare(letters);
    let (mut relative, mut e_written, mut e_total) = (false, 0.0f64, 0.0f64);
    let mut out = String::with_capacity(text.len());
    for raw in text.lines() {
        let code = raw.split(';').next().unwrap_or("").trim();
        let mut words = code.split_whitespace();
        let cmd = words.next().map(str::to_ascii_uppercase);
        let mut line = String::new();
        match cmd.as_deref() {
            Some("M82") => relative = false,
            Some("M83") => relative = true,
            Some("G90" | "G93" | "G94" | "G21") => line.push_str(code),
            Some(c @ ("G0" | "G1" | "G92")) => {
                let mut kept = vec![c.to_string()];
                for w in words {
                    let letter = w.chars().next().unwrap().to_ascii_uppercase();
                    let v: f64 = w[1..].parse().expect("a number");
                    if letter == 'E' {
                        if c == "G92" {
                            e_written = v;
                            continue;
                        }
                        let de = if relative { v } else { v - e_written };
                        e_written = if relative { e_written + v } else { v };
                        e_total += de;
                        kept.push(format!("{e_letter}{e_total:.6}"));
                    } else {
                        // (a letter the machine does not have — the slicer's own start moves,
                        // passed through verbatim — goes to the interpreter as it is: both
                        // readers must still agree on it)
                        kept.push(w.to_string());
                    }
                }
                if kept.len() > 1 {
                    line = kept.join(" ");
                }
            }
            Some("G91") => panic!("relative positioning (G91) in a machine output: {raw}"),
            _ => {}
        }
        out.push_str(&line);
        out.push('\n');
    }
    out.push_str("M2\n");
    out
}

/// One motion the interpreter reports.
struct Reported {
    traverse: bool,
    inverse: bool,
    rate: f64,
    axes: [f64; 9],
}

fn interpret(path: &str) -> Result<BTreeMap<usize, Reported>, String> {
    let o = Command::new("python3")
        .args([&script(), path])
        .output()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&o.stdout);
    let mut m = BTreeMap::new();
    for l in text.lines() {
        let t: Vec<&str> = l.split_whitespace().collect();
        if t[0] == "error" || t.get(1) == Some(&"arc") {
            return Err(format!("the interpreter: {l}"));
        }
        let mut axes = [0.0; 9];
        for (k, a) in axes.iter_mut().enumerate() {
            *a = t[4 + k].parse().unwrap();
        }
        let prev = m.insert(
            t[0].parse::<usize>().unwrap(),
            Reported {
                traverse: t[1] == "traverse",
                inverse: t[2] == "inverse",
                rate: t[3].parse().unwrap(),
                axes,
            },
        );
        assert!(prev.is_none(), "two motions on line {}", t[0]);
    }
    if !o.status.success() {
        return Err(format!(
            "the interpreter failed: {}",
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    Ok(m)
}

/// The mismatches between the interpreter's motions and the walk's, and how many motions were
/// compared.
fn compare(text: &str, letters: &str, got: &BTreeMap<usize, Reported>) -> (Vec<String>, usize) {
    let ls: Vec<char> = letters.chars().collect();
    let e_letter = spare(letters);
    let walk = firmware::motions(text, &ls);
    // the feed mode in force on each line, read here
    let mut inverse = vec![false; text.lines().count() + 2];
    let mut mode = false;
    for (i, l) in text.lines().enumerate() {
        match l.split(';').next().unwrap().split_whitespace().next() {
            Some("G93") => mode = true,
            Some("G94") => mode = false,
            _ => {}
        }
        inverse[i + 1] = mode;
    }
    let slot = |c: char| LINUXCNC.iter().position(|x| *x == c).unwrap();
    if let Some(m) = walk.iter().find(|m| m.pos.keys().any(|c| !ls.contains(c))) {
        let foreign: String = m.pos.keys().filter(|c| !ls.contains(c)).collect();
        println!(
            "NOTE: line {} writes {foreign}, which the machine ({letters}) does not have (the slicer's start moves, passed through verbatim)",
            m.line
        );
    }
    let mut bad = Vec::new();
    let mut e_total = 0.0;
    let mut prev: Option<&firmware::Motion> = None;
    let mut prev_vals = [0.0f64; 9];
    let mut compared = 0;
    for m in &walk {
        e_total += m.de;
        // the walk's values of LinuxCNC's nine axes: E on its spare letter, every other letter
        // as the file last set it (0 before: where both readers start). A letter the machine
        // does not have (the polar machine's Y) comes from the slicer's own start moves, passed
        // through verbatim: counted below and reported, both readers must still agree on it.
        let mut vals = [0.0f64; 9];
        for (k, c) in LINUXCNC.iter().enumerate() {
            vals[k] = if *c == e_letter {
                e_total
            } else {
                m.pos.get(c).copied().unwrap_or(0.0)
            };
        }
        // LinuxCNC's move length for inverse time (`Interp::find_straight_length`, NIST
        // RS274NGC §2.1.2.5 extended to U V W): the X Y Z norm when one of them moves (by more
        // than 1e-7 inch), else the U V W norm when one of them moves, else the A B C norm
        let norm = |group: &str| {
            LINUXCNC
                .iter()
                .enumerate()
                .filter(|(_, c)| group.contains(**c))
                .map(|(k, _)| (vals[k] - prev_vals[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        let moves = |group: &str| {
            LINUXCNC
                .iter()
                .enumerate()
                .any(|(k, c)| group.contains(*c) && (vals[k] - prev_vals[k]).abs() > RS274_TINY_MM)
        };
        let length = if moves("XYZ") {
            norm("XYZ")
        } else if moves("UVW") {
            norm("UVW")
        } else {
            norm("ABC")
        };
        prev_vals = vals;
        let Some(r) = got.get(&m.line) else {
            let moved = m.de != 0.0 || prev.is_none_or(|p| p.pos != m.pos);
            if moved {
                bad.push(format!(
                    "line {}: the interpreter reports no motion",
                    m.line
                ));
            }
            prev = Some(m);
            continue;
        };
        compared += 1;
        for c in LINUXCNC {
            let want = vals[slot(c)];
            let v = r.axes[slot(c)];
            if (v - want).abs() > AXIS_TOL {
                bad.push(format!(
                    "line {}: {c} = {v} by the interpreter, {want} by the walk",
                    m.line
                ));
            }
        }
        if !r.traverse {
            if r.inverse != inverse[m.line] {
                bad.push(format!(
                    "line {}: the interpreter is in {} mode",
                    m.line,
                    if r.inverse { "G93" } else { "G94" }
                ));
            }
            // G94: the rate is the file's F (mm/min); G93: F is 1/minutes, so the interpreter
            // moves at length × F (mm/min, or °/min for a rotation alone)
            let want = if inverse[m.line] { m.f * length } else { m.f };
            // (a move of no length has no rate to check)
            let idle = inverse[m.line] && length == 0.0;
            if !idle && (r.rate - want).abs() > FEED_REL_TOL * want.max(1.0) {
                bad.push(format!(
                    "line {}: feed {} by the interpreter, {want} from F{} in the file",
                    m.line, r.rate, m.f
                ));
            }
        }
        prev = Some(m);
    }
    for line in got.keys() {
        if !walk.iter().any(|m| m.line == *line) {
            bad.push(format!(
                "line {line}: the interpreter moves where the file has no G0/G1"
            ));
        }
    }
    (bad, compared)
}

/// Every preset × `tip` / `inverse-time`: zero mismatches (see the module documentation).
#[test]
fn linuxcnc_reads_every_machine_output_as_the_walk_does() {
    if let Err(why) = available() {
        skip::skip_or_fail("the rs274 oracle", &why);
        return;
    }
    let mut fails = Vec::new();
    // WARPSLICE_CASES=preset,preset: only those (says how many it left out)
    let only: Option<Vec<String>> = std::env::var("WARPSLICE_CASES")
        .ok()
        .map(|v| v.split(',').map(str::to_string).collect());
    let all = cases();
    let chosen: Vec<_> = all
        .into_iter()
        .filter(|c| only.as_ref().is_none_or(|o| o.iter().any(|n| n == c.0)))
        .collect();
    if only.is_some() {
        println!(
            "WARPSLICE_CASES: {} presets run, the others left out",
            chosen.len()
        );
    }
    // the presets in two threads (the CLI's unwarp and the interpreter are separate
    // processes; this test is most of its binary's time): each preset's lines and failures are
    // printed and kept in preset order
    let one = |(preset, warp, place): &(&'static str, Vec<&'static str>, Vec<&'static str>)| {
        let (mut lines, mut fails) = (Vec::new(), Vec::new());
        let part = Part::new(&format!("rs274-{preset}"), warp);
        let machine = machine_arg(&part, preset);
        let (letters, _) = documented(preset);
        for feed in ["tip", "inverse-time"] {
            // the interpreter's reading, not the head's clearance (collision_check.rs): the
            // default head meets some presets' warped part, so written anyway
            let mut flags = vec![
                "--machine",
                machine.as_str(),
                "--feed",
                feed,
                "--allow-collisions",
            ];
            flags.extend_from_slice(place);
            let (gcode, _, _) = part
                .unwarp(feed, &flags)
                .unwrap_or_else(|e| panic!("{preset} {feed}: {e}"));
            let ngc = part.path(&format!("{feed}.ngc"));
            std::fs::write(&ngc, for_interpreter(&gcode, letters)).unwrap();
            match interpret(&ngc) {
                Err(e) => fails.push(format!("{preset} {feed}: {e}")),
                Ok(got) => {
                    let (bad, compared) = compare(&gcode, letters, &got);
                    lines.push(format!(
                        "{preset:20} {feed:13} {compared:6} motions compared, {} mismatches (E as {}){}",
                        bad.len(),
                        spare(letters),
                        bad.first().map_or(String::new(), |b| format!(", first: {b}"))
                    ));
                    if compared <= 1000 {
                        fails.push(format!("{preset} {feed}: only {compared} motions"));
                    }
                    if !bad.is_empty() {
                        fails.push(format!(
                            "{preset} {feed}: {} mismatches, first: {}",
                            bad.len(),
                            bad[..bad.len().min(3)].join("; ")
                        ));
                    }
                }
            }
        }
        (lines, fails)
    };
    let half = chosen.len().div_ceil(2);
    let results: Vec<(Vec<String>, Vec<String>)> = std::thread::scope(|s| {
        let (a, b) = chosen.split_at(half);
        let hb = s.spawn(|| b.iter().map(one).collect::<Vec<_>>());
        let mut r: Vec<_> = a.iter().map(one).collect();
        r.extend(hb.join().expect("the second thread's presets"));
        r
    });
    for (lines, f) in results {
        for l in lines {
            println!("{l}");
        }
        fails.extend(f);
    }
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

/// The comparison finds what it must: an axis value off by 0.002, a G93 line read as G94, a
/// feed changed, a motion the interpreter reports where the file has none.
#[test]
fn the_comparison_sees_a_wrong_value_mode_or_feed() {
    // line 5 moves X by 1 mm in 1/3.5 min: the interpreter's rate is 3.5 mm/min
    let text = "G90\nM83\nG1 X1 Y2 Z3 A10 E0.5 F600\nG93\nG1 X2 A20 F3.5\nG94\n";
    let mk = |inverse: bool, rate: f64, x: f64| Reported {
        traverse: false,
        inverse,
        rate,
        axes: [x, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    };
    let good = |a: &mut BTreeMap<usize, Reported>| {
        let mut r3 = mk(false, 600.0, 1.0);
        r3.axes[3] = 10.0;
        r3.axes[4] = 0.5; // E on B, the first letter XYZA leaves free
        let mut r5 = mk(true, 3.5, 2.0);
        r5.axes[3] = 20.0;
        r5.axes[4] = 0.5;
        a.insert(3, r3);
        a.insert(5, r5);
    };
    let mut g = BTreeMap::new();
    good(&mut g);
    assert_eq!(compare(text, "XYZA", &g).0, Vec::<String>::new());
    g.get_mut(&5).unwrap().axes[0] += 0.002;
    assert_eq!(compare(text, "XYZA", &g).0.len(), 1);
    good(&mut g);
    g.get_mut(&5).unwrap().inverse = false;
    assert!(compare(text, "XYZA", &g).0[0].contains("G94 mode"));
    good(&mut g);
    g.get_mut(&3).unwrap().rate = 601.0;
    assert!(compare(text, "XYZA", &g).0[0].contains("feed 601"));
    good(&mut g);
    g.insert(4, mk(true, 1.0, 2.0));
    assert!(compare(text, "XYZA", &g)
        .0
        .iter()
        .any(|b| b.contains("no G0/G1")));
    // and the harness' file keeps the line numbers, E as the cumulative filament on B
    let ngc = for_interpreter(text, "XYZA");
    assert_eq!(ngc.lines().count(), text.lines().count() + 1);
    assert_eq!(ngc.lines().nth(2), Some("G1 X1 Y2 Z3 A10 B0.500000 F600"));
}
