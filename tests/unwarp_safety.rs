//! Issue 12, "never a silently wrong G-code": what the unwarp does with commands and files a
//! planar slicer (or its user) puts inside the printed region — head moves, non-move lines
//! around travels, arcs, truncated files, a wipe tower beside the part. Each test mutates the
//! synthetic slicer's G-code of a conic cube (`common/synthetic.rs`), runs the library and the
//! CLI, and checks the written file with a reader of its own (below: it shares nothing with
//! `warpslice::gcode`), or the refusal's code and the line it names.

#[path = "common/synthetic.rs"]
mod synthetic;

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::Command;

use warpslice::error::Coded;
use warpslice::job::Job;
use warpslice::machine::MachineOptions;
use warpslice::pipeline::{unwarp, warp_model, UnwarpSettings, WarpOptions};
use warpslice::unwarp::{UnwarpOptions, UnwarpOutput};
use warpslice::warp::{Direction, WarpParams, WarpSpec};

const CLI: &str = env!("CARGO_BIN_EXE_warpslice");

/// The warped 20 mm cube (conic 30° outward) and its job.
fn conic_cube() -> warpslice::pipeline::WarpOutput {
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "t");
    let p = WarpParams {
        spec: WarpSpec::Conic {
            angle: 30.0,
            direction: Direction::Outward,
            center: [0.0, 0.0],
        },
        base: None,
    };
    warp_model(&stl, &WarpOptions::new(p)).unwrap()
}

/// `what` inserted after the `n`th (1-based) occurrence of `marker`; the text and the 1-based
/// line number of the first inserted line.
fn insert_after(g: &str, marker: &str, n: usize, what: &str) -> (String, usize) {
    let mut at = 0;
    for _ in 0..n {
        at += g[at..].find(marker).expect("marker") + marker.len();
    }
    let line = g[..at].matches('\n').count() + 1;
    (format!("{}{what}{}", &g[..at], &g[at..]), line)
}

/// The 3-axis unwarp placed where the synthetic slicer put the part.
fn run_lib(
    g: &str,
    job: &Job,
    machine: Option<&str>,
) -> Result<UnwarpOutput, warpslice::pipeline::Error> {
    let s = UnwarpSettings {
        unwarp: UnwarpOptions {
            offset: Some([100.0, 100.0]),
            ..UnwarpOptions::default()
        },
        output: MachineOptions {
            machine: machine.map(|m| warpslice::machine::preset(m).unwrap()),
            ..MachineOptions::default()
        },
    };
    unwarp(g.as_bytes(), job, &s)
}

/// The error of a run that must be refused (without printing a whole accepted output).
fn refused<T>(what: &str, r: Result<T, warpslice::pipeline::Error>) -> warpslice::pipeline::Error {
    match r {
        Ok(_) => panic!("{what}: accepted, must be refused"),
        Err(e) => e,
    }
}

/// A scratch directory with the job written in it.
fn scratch(tag: &str, job: &Job) -> (PathBuf, PathBuf) {
    let d = std::env::temp_dir().join(format!("warpslice-safety-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let j = d.join("part.job.json");
    std::fs::write(&j, job.to_json_pretty()).unwrap();
    (d, j)
}

/// `warpslice unwarp` of `g`: Ok(output text, stdout) or Err(stderr).
fn run_cli(
    dir: &std::path::Path,
    job: &std::path::Path,
    g: &str,
    extra: &[&str],
) -> Result<(String, String), String> {
    let input = dir.join("in.gcode");
    let out = dir.join("out.gcode");
    let _ = std::fs::remove_file(&out);
    std::fs::write(&input, g).unwrap();
    let mut args = vec![
        "unwarp".to_string(),
        input.display().to_string(),
        "--job".into(),
        job.display().to_string(),
        "-o".into(),
        out.display().to_string(),
        "--offset".into(),
        "100,100".into(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let o = Command::new(CLI).args(&args).output().unwrap();
    if o.status.success() {
        Ok((
            std::fs::read_to_string(&out).unwrap(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        ))
    } else {
        Err(String::from_utf8_lossy(&o.stderr).into_owned())
    }
}

// ── the tests' own reading of an output file ───────────────────────────────────────────────

/// One output line: its text, and for a `G<n>`/`M<n>`/`T<n>` line the letter and number and
/// the words after it (letter → value; a bare letter is NaN).
#[derive(Clone, Debug)]
struct Step {
    text: String,
    cmd: Option<(char, u32)>,
    words: HashMap<char, f64>,
}

fn steps(out: &str) -> Vec<Step> {
    out.lines()
        .map(|l| {
            let code = l.split(';').next().unwrap_or("").trim();
            let mut it = code.split_whitespace();
            let cmd = it.next().and_then(|w| {
                let mut c = w.chars();
                let letter = c.next()?.to_ascii_uppercase();
                match c.as_str().parse::<u32>() {
                    Ok(n) => Some((letter, n)),
                    // Prusa's `T?`, `Tx`, `Tc`
                    Err(_) if letter == 'T' => Some((letter, u32::MAX)),
                    Err(_) => None,
                }
            });
            let words = it
                .filter_map(|w| {
                    let mut c = w.chars();
                    let letter = c.next()?.to_ascii_uppercase();
                    let v = c.as_str();
                    Some((
                        letter,
                        if v.is_empty() {
                            f64::NAN
                        } else {
                            v.parse().ok()?
                        },
                    ))
                })
                .collect();
            Step {
                text: l.to_string(),
                cmd,
                words,
            }
        })
        .collect()
}

/// Walks a 3-axis output as a firmware would (relative E) and checks that after a command that
/// moves the head where the file does not say (`G28 X/Y`, `G27`, `T<n>`), nothing extrudes and
/// nothing moves in X/Y until the head has climbed, by a Z-only move, above every extrusion
/// written so far by at least `clearance`; returns how many such climbs there were.
fn climbs_after_head_moves(out: &str, clearance: f64) -> Result<usize, String> {
    // known[k]: X, Y, Z known; pos: where they are
    let mut known = [false; 3];
    let mut top = f64::NEG_INFINITY;
    let mut z = 0.0;
    let mut climbs = 0;
    let mut unknown_since: Option<usize> = None;
    for (i, s) in steps(out).iter().enumerate() {
        let n = i + 1;
        match s.cmd {
            Some(('G', 28)) => {
                let named: Vec<usize> = "XYZ"
                    .chars()
                    .enumerate()
                    .filter(|(_, c)| s.words.contains_key(c))
                    .map(|(k, _)| k)
                    .collect();
                for k in 0..3 {
                    if named.is_empty() || named.contains(&k) {
                        known[k] = false;
                    }
                }
                unknown_since = Some(n);
            }
            Some(('G', 27)) | Some(('T', _)) => {
                known = [false; 3];
                unknown_since = Some(n);
            }
            Some(('G', 0 | 1)) => {
                let xy = s.words.contains_key(&'X') || s.words.contains_key(&'Y');
                let e = s.words.get(&'E').copied().unwrap_or(0.0);
                let new_z = s.words.get(&'Z').copied();
                if !(known[0] && known[1]) {
                    if e > 0.0 {
                        return Err(format!(
                            "line {n}: extrudes with X/Y unknown since line {unknown_since:?}: {}",
                            s.text
                        ));
                    }
                    if xy {
                        let zz = new_z.unwrap_or(z);
                        if !known[2] && new_z.is_none() || zz < top + clearance - 1e-9 {
                            return Err(format!(
                                "line {n}: moves in X/Y from an unknown place at Z {zz} (printed top {top}): {}",
                                s.text
                            ));
                        }
                    } else if let Some(v) = new_z {
                        if v < top + clearance - 1e-9 {
                            return Err(format!("line {n}: the climb from an unknown place stops at Z {v}, under the printed top {top} + {clearance}"));
                        }
                        climbs += 1;
                    }
                }
                if let Some(v) = new_z {
                    z = v;
                    known[2] = true;
                }
                if s.words.contains_key(&'X') {
                    known[0] = true;
                }
                if s.words.contains_key(&'Y') {
                    known[1] = true;
                }
                if e > 0.0 && xy {
                    top = top.max(z);
                }
            }
            _ => {}
        }
    }
    Ok(climbs)
}

// ── item 1: head moves inside the region ────────────────────────────────────────────────────

/// Issue 12 item 1: after `G28` inside the region the output went on with an extruding `G1`
/// from home, because pass 2 still believed the head was where it had been. Now every head move
/// the file does not give (`G28 X Y`, `G27`, a tool change) is followed by a climb to above the
/// printed part, wherever the head is, before anything moves in X/Y or extrudes — whether the
/// command follows an extrusion or a travel.
#[test]
fn a_head_move_in_the_region_is_followed_by_a_climb_never_an_extrusion() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let clearance = UnwarpOptions::default().travel_clearance;
    let (d, job) = scratch("head", &w.job);
    let base = climbs_after_head_moves(
        &String::from_utf8(run_lib(&g, &w.job, None).unwrap().gcode).unwrap(),
        clearance,
    );
    // the start G-code's own G28 is followed by its first Z move
    let base = base.expect("the clean file");
    for (marker, n, what) in [
        // after the last extrusion of a perimeter (no travel waiting)
        (";TYPE:Internal infill\n", 12, "G28 X Y\n"),
        // after a travel, before the extrusion it leads to
        ("F6000\n", 40, "G28 X\n"),
        ("F6000\n", 41, "T1\n"),
        (";TYPE:Internal infill\n", 20, "G27\n"),
        ("F6000\n", 61, "T?\n"),
    ] {
        let (bad, _) = insert_after(&g, marker, n, what);
        let lib = String::from_utf8(run_lib(&bad, &w.job, None).unwrap().gcode).unwrap();
        let cli = run_cli(&d, &job, &bad, &[]).unwrap().0;
        for (how, out) in [("library", &lib), ("CLI", &cli)] {
            assert!(out.contains(what), "{how}: {what:?} is passed through");
            let climbs = climbs_after_head_moves(out, clearance)
                .unwrap_or_else(|e| panic!("{how}, {what:?}: {e}"));
            assert_eq!(climbs, base + 1, "{how}, {what:?}: one more climb");
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// The walker above must catch the bug it is for: the output of a clean file with a `G28 X Y`
/// inserted right after the unwarp's output (no climb) fails it.
#[test]
fn the_head_move_walker_catches_an_extrusion_from_home() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let out = String::from_utf8(run_lib(&g, &w.job, None).unwrap().gcode).unwrap();
    let (planted, _) = insert_after(&out, ";TYPE:Internal infill\n", 12, "G28 X Y\n");
    assert!(climbs_after_head_moves(&planted, 1.0).is_err());
}

/// Issue 12 item 1, the other half: `G28` homing Z (`G28`, `G28 Z`, Prusa's `G28 W`), `G29` and
/// `G30` inside the region drive the nozzle or the probe down to the bed, where the part
/// stands: refused by name, naming the line; the same commands in the start G-code pass.
#[test]
fn homing_z_or_probing_in_the_region_is_refused_naming_the_line() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let (d, job) = scratch("probe", &w.job);
    let (start, _) = insert_after(&g, "G28\n", 1, "G29\nG30\n");
    run_lib(&start, &w.job, None).expect("probing in the start G-code is fine");
    for what in ["G28\n", "G28 Z\n", "G28 W\n", "G29\n", "G30 X10 Y10\n"] {
        let (bad, line) = insert_after(&g, ";TYPE:Internal infill\n", 7, what);
        let e = refused(what, run_lib(&bad, &w.job, None));
        assert_eq!(e.code(), "unwarp.probe-in-region", "{what:?}: {e}");
        let m = e.to_string();
        assert!(
            m.contains(&format!("G-code line {line}:")) && m.contains(what.trim()),
            "{m}"
        );
        let cli = run_cli(&d, &job, &bad, &[]).unwrap_err();
        assert!(
            cli.contains(&format!("G-code line {line}:")) && cli.contains("start G-code"),
            "{cli}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A multi-axis head cannot be brought back from a pose the file does not give: a tool change
/// inside the region is refused by the machine emitter, naming the line and the command.
#[test]
fn a_head_move_in_the_region_is_refused_for_a_multi_axis_machine() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    run_lib(&g, &w.job, Some("pax-5axis")).expect("the clean file on pax-5axis");
    let (bad, line) = insert_after(&g, ";TYPE:Internal infill\n", 7, "T1\n");
    let e = refused("T1 on pax-5axis", run_lib(&bad, &w.job, Some("pax-5axis")));
    assert_eq!(e.code(), "machine.pose-lost", "{e}");
    // the climb is decided at the next travel, on the line of the next extrusion at the latest
    let m = e.to_string();
    assert!(m.contains("tool change") && m.contains("pax-5axis"), "{m}");
    let named: usize = m
        .strip_prefix("G-code line ")
        .and_then(|r| r.split(':').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("names a line: {m}"));
    assert!(
        named == line,
        "names line {named}, the T1 is on {line}: {m}"
    );
}
