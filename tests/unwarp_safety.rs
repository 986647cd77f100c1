//! Issue 12, "never a silently wrong G-code": what the unwarp does with commands and files a
//! planar slicer (or its user) puts inside the printed region — head moves, non-move lines
//! around travels, arcs, truncated files, a wipe tower beside the part. Each test mutates the
//! synthetic slicer's G-code of a conic cube (`common/synthetic.rs`), runs the library and the
//! CLI, and checks the written file with a reader of its own (below: it shares nothing with
//! `warpslice::gcode`), or the refusal's code and the line it names. Native only (the CLI, a
//! real slicer); the wasm report's warnings are checked in `wasm_errors.rs`.
#![cfg(not(target_arch = "wasm32"))]

mod common;
#[path = "common/synthetic.rs"]
mod synthetic;

use std::collections::HashMap;

use glam::DVec3;
use std::path::PathBuf;
use std::process::Command;

use warpslice::error::Coded;
use warpslice::job::Job;
use warpslice::machine::MachineOptions;
use warpslice::pipeline::{unwarp, UnwarpSettings, WarpOptions};
use warpslice::unwarp::{UnwarpOptions, UnwarpOutput};
use warpslice::warp::{Direction, WarpParams, WarpSpec};

const CLI: &str = env!("CARGO_BIN_EXE_warpslice");

use synthetic::{conic_cube, insert_after};

/// The project's independent checker (tests/common/check.rs: placement, surfaces, E, travels,
/// retraction balance) on a `run`'s output `written` of the slicer's `sliced`, the warped STL
/// at `warped` (its job beside it), placed by the slicers on the bed centre (100, 100).
fn independent_check(warped: &std::path::Path, sliced: &str, written: &str) {
    let job = warpslice::pipeline::files::read_job(&warpslice::pipeline::files::job_path(warped))
        .unwrap();
    let (mesh, _) = warpslice::mesh::read_stl(&std::fs::read(warped).unwrap()).unwrap();
    let c = job.warped_bbox.center();
    let d0 = UnwarpOptions::default();
    let expect = common::check::Expect {
        job: &job,
        warped: &mesh,
        placement: glam::DVec2::new(100.0 - c.x, 100.0 - c.y),
        max_segment: d0.max_segment,
        tolerance: d0.tolerance,
        clearance: d0.travel_clearance,
    };
    common::check::check(&expect, sliced.as_bytes(), written.as_bytes()).unwrap();
}

/// The 3-axis unwarp placed where the synthetic slicer put the part.
fn run_lib(
    g: &str,
    job: &Job,
    machine: Option<&str>,
) -> Result<UnwarpOutput, warpslice::pipeline::Error> {
    let s = settings(
        machine.map(|m| warpslice::machine::preset(m).unwrap()),
        None,
    );
    unwarp(g.as_bytes(), job, &s)
}

/// The settings of these tests: the slicers' part at (100, 100), on `machine` in `flavour`.
fn settings(
    machine: Option<warpslice::machine::MachineSpec>,
    flavour: Option<warpslice::machine::Flavour>,
) -> UnwarpSettings {
    UnwarpSettings {
        unwarp: UnwarpOptions {
            offset: Some([100.0, 100.0]),
            ..UnwarpOptions::default()
        },
        output: MachineOptions {
            machine,
            flavour,
            // head moves and line order, not the head's clearance (collision_check.rs): the
            // default head meets the bed on the conic cube's tilted layers, so written anyway
            allow_collisions: true,
            ..MachineOptions::default()
        },
    }
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
    ];
    if !extra.contains(&"--offset") {
        args.extend(["--offset".into(), "100,100".into()]);
    }
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
/// moves the head where the file does not say (`G28 X/Y`, `G27`, `T<n>`) from the first
/// `;LAYER_CHANGE` on (the start G-code before it is the slicer's, passed through), nothing
/// extrudes and nothing moves in X/Y until the head has climbed, by a Z-only move, above every
/// extrusion written so far by at least `clearance`; returns how many such climbs there were.
fn climbs_after_head_moves(out: &str, clearance: f64) -> Result<usize, String> {
    // known[k]: X, Y, Z known
    let mut known = [true; 3];
    let mut top = f64::NEG_INFINITY;
    let mut z = 0.0;
    let mut climbs = 0;
    let mut unknown_since: Option<usize> = None;
    let mut printing = false;
    for (i, s) in steps(out).iter().enumerate() {
        let n = i + 1;
        printing |= s.text.starts_with(";LAYER_CHANGE");
        if !printing {
            continue;
        }
        match s.cmd {
            Some(('G', 28)) => {
                let named: Vec<usize> = "XYZ"
                    .chars()
                    .enumerate()
                    .filter(|(_, c)| s.words.contains_key(c))
                    .map(|(k, _)| k)
                    .collect();
                for (k, known) in known.iter_mut().enumerate() {
                    if named.is_empty() || named.contains(&k) {
                        *known = false;
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
                    // filament pushed in place (an unretract after a tool change) moves nothing
                    if e > 0.0 && xy {
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

// ── item 5: non-move lines around travels ───────────────────────────────────────────────────

/// The tests' own reading of the order of action lines (not a move, not a comment) from the
/// second `;LAYER_CHANGE` (the first layer is the anchor's: its extrusions are dropped, so its
/// lines come before travels) to the last extrusion of a file with relative E: for each, its
/// text, whether the head moved in X/Y between the extrusion before it and it (it follows a
/// travel), and whether it moves in X/Y between it and the next extrusion (a travel follows it).
/// An extrusion is a move in X/Y with an E word ≥ 0 (a point clamped to the bed gets E0).
fn action_order(text: &str) -> Vec<(String, bool, bool)> {
    struct Ev {
        action: Option<String>,
        xy: bool,
        extrudes: bool,
    }
    let mut evs = Vec::new();
    let (mut x, mut y) = (f64::NAN, f64::NAN);
    let mut layers = 0;
    for s in steps(text) {
        if s.text.starts_with(";LAYER_CHANGE") {
            layers += 1;
        }
        if layers < 2 {
            if let Some(('G', 0 | 1)) = s.cmd {
                x = s.words.get(&'X').copied().unwrap_or(x);
                y = s.words.get(&'Y').copied().unwrap_or(y);
            }
            continue;
        }
        match s.cmd {
            Some(('G', 0 | 1)) => {
                let nx = s.words.get(&'X').copied().unwrap_or(x);
                let ny = s.words.get(&'Y').copied().unwrap_or(y);
                let xy = !(nx == x && ny == y);
                let e = s.words.get(&'E').copied();
                evs.push(Ev {
                    action: None,
                    xy,
                    extrudes: xy && e.is_some_and(|e| e >= 0.0),
                });
                (x, y) = (nx, ny);
            }
            // mode lines say how the words after them read: not actions
            Some(('G', 20 | 21 | 90 | 91 | 92) | ('M', 82 | 83)) => {}
            Some(_) => evs.push(Ev {
                action: Some(s.text.split(';').next().unwrap().trim().to_string()),
                xy: false,
                extrudes: false,
            }),
            None => {}
        }
    }
    let first = evs.iter().position(|e| e.extrudes).unwrap_or(0);
    let last = evs.iter().rposition(|e| e.extrudes).unwrap_or(0);
    let mut out = Vec::new();
    for k in first..=last {
        let Some(a) = &evs[k].action else { continue };
        let before = evs[..k]
            .iter()
            .rev()
            .take_while(|e| !e.extrudes)
            .any(|e| e.xy);
        let after = evs[k + 1..]
            .iter()
            .take_while(|e| !e.extrudes)
            .any(|e| e.xy);
        out.push((a.clone(), before, after));
    }
    out
}

/// Every action line of `input`'s printed region is in `output` in the same order, and none
/// moved across a travel: one that followed a travel still follows one (except a retraction,
/// `G10`: in front of a travel it only oozes less), one that came right before an extrusion
/// (no travel between) still does. Err names the first that moved.
fn order_kept(input: &str, output: &str) -> Result<usize, String> {
    let (a, b) = (action_order(input), action_order(output));
    let texts = |v: &[(String, bool, bool)]| v.iter().map(|x| x.0.clone()).collect::<Vec<_>>();
    if texts(&a) != texts(&b) {
        return Err(format!(
            "the action lines differ:\n in: {:?}\nout: {:?}",
            texts(&a),
            texts(&b)
        ));
    }
    for (k, (i, o)) in a.iter().zip(&b).enumerate() {
        if i.1 && !o.1 && i.0 != "G10" {
            return Err(format!(
                "action {k} '{}' followed a travel, now comes before it",
                i.0
            ));
        }
        if !i.2 && o.2 {
            return Err(format!(
                "action {k} '{}' came right before an extrusion, now a travel follows it",
                i.0
            ));
        }
    }
    Ok(a.len())
}

/// Issue 12 item 5: travels wait for the next extrusion while other lines were written at once,
/// so with firmware retraction every `G11` came before the travel it ended (stringing), and
/// `M106`, `G4` moved in front of travels. The synthetic file with `G10`/`G11` instead of E
/// retractions and a fan, a dwell and a detour after travels keeps every line's place.
#[test]
fn lines_after_a_travel_stay_after_it() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0)
        .replace("G1 E-0.8 F2400\n", "G10\n")
        .replace("G1 E0.8 F2400\n", "G11\n");
    assert!(g.contains("G11\n"));
    // the travel lines of the infill: a fan after one, a dwell and a detour after another
    let travels: Vec<&str> = g
        .lines()
        .filter(|l| l.starts_with("G0 ") && l.ends_with("F6000"))
        .collect();
    let (g, _) = insert_after(&g, &format!("{}\n", travels[30]), 1, "M106 S128\n");
    let detour = format!("G4 P10\nG0 X100 Y100 F6000\n{}\n", travels[55]);
    let (g, _) = insert_after(&g, &format!("{}\n", travels[55]), 1, &detour);
    let (d, job) = scratch("order", &w.job);
    let lib = run_lib(&g, &w.job, None).unwrap();
    let out = String::from_utf8(lib.gcode).unwrap();
    let n = order_kept(&g, &out).unwrap_or_else(|e| panic!("library: {e}"));
    assert!(n > 100, "{n} action lines checked");
    // a firmware retraction counts: no retraction of warpslice's own on top of a G10
    assert_eq!(lib.report.retracts_added, 0);
    let cli = run_cli(&d, &job, &g, &[]).unwrap().0;
    order_kept(&g, &cli).unwrap_or_else(|e| panic!("CLI: {e}"));
    let _ = std::fs::remove_dir_all(&d);
}

/// The order check must catch the bug it is for: the unwarp's output with each `G11` moved in
/// front of the travel before it fails it.
#[test]
fn the_order_check_catches_an_unretract_before_its_travel() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0)
        .replace("G1 E-0.8 F2400\n", "G10\n")
        .replace("G1 E0.8 F2400\n", "G11\n");
    let out = String::from_utf8(run_lib(&g, &w.job, None).unwrap().gcode).unwrap();
    // each G11 moved in front of the travel (one G0 or a lift's three) before it
    let mut planted: Vec<&str> = out.lines().collect();
    let mut moved = 0;
    for k in 1..planted.len() {
        if planted[k] == "G11" && planted[k - 1].starts_with("G0") {
            let mut j = k - 1;
            while j > 0 && planted[j - 1].starts_with("G0") {
                j -= 1;
            }
            let l = planted.remove(k);
            planted.insert(j, l);
            moved += 1;
        }
    }
    assert!(moved > 100, "{moved} G11 moved");
    assert!(order_kept(&g, &planted.join("\n")).is_err());
}

/// Issue 12 item 5 with a real slicer: PrusaSlicer with `--use-firmware-retraction` writes
/// `G10`/`G11` around its travels; the unwarp keeps each where it was relative to the motion,
/// and adds no retraction of its own inside a firmware retraction.
#[test]
fn prusaslicer_firmware_retraction_keeps_its_place() {
    use common::skip;
    use warpslice::slicer::{SliceOptions, SlicerKind};
    let model =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/stl/ps_20mmbox_ascii.stl");
    if !model.exists() {
        return skip::skip_or_fail("firmware retraction", "no corpus at ../shared/corpus/stl");
    }
    if let Err(e) = warpslice::slicer::available(SlicerKind::PrusaSlicer) {
        return skip::skip_or_fail("firmware retraction", &e.to_string());
    }
    let d = std::env::temp_dir().join(format!("warpslice-safety-{}-fwretract", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let out = d.join("box.gcode");
    let warp = WarpOptions::new(WarpParams {
        spec: WarpSpec::Conic {
            angle: 30.0,
            direction: Direction::Outward,
            center: [0.0, 0.0],
        },
        base: None,
    });
    let slice = SliceOptions {
        slicer: SlicerKind::PrusaSlicer,
        extra_args: vec!["--use-firmware-retraction".into()],
        ..SliceOptions::default()
    };
    let report = warpslice::pipeline::files::run(
        &model,
        &warp,
        &slice,
        &UnwarpSettings::default(),
        &out,
        &mut (),
    )
    .unwrap();
    let sliced =
        std::fs::read_to_string(warpslice::pipeline::files::RunFiles::next_to(&out).sliced)
            .unwrap();
    let written = std::fs::read_to_string(&out).unwrap();
    let count = |t: &str, w: &str| {
        t.lines()
            .filter(|l| l.split(';').next().unwrap().trim() == w)
            .count()
    };
    assert!(
        count(&sliced, "G11") > 20,
        "PrusaSlicer wrote firmware retraction"
    );
    assert_eq!(count(&written, "G10"), count(&sliced, "G10"));
    assert_eq!(count(&written, "G11"), count(&sliced, "G11"));
    let n = order_kept(&sliced, &written).unwrap();
    assert!(n >= count(&sliced, "G11"));
    assert!(report.retracts_added < report.lifts.max(1), "{report:?}");
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    // and the file passes the project's independent checker (placement, surfaces, E, travels,
    // retraction balance with G10/G11)
    let files = warpslice::pipeline::files::RunFiles::next_to(&out);
    independent_check(&files.warped, &sliced, &written);
    let _ = std::fs::remove_dir_all(&d);
}

// ── items 9 and the arc hang: arcs ──────────────────────────────────────────────────────────

/// Issue 12 item 9 and the arc hang, through the unwarp: an arc with full turns (`P2`) inside
/// the region, and 3,000 arcs of radius 9 km in the start G-code, are refused by name (the
/// code, the line of the first), by the library and the CLI.
#[test]
fn arcs_with_turns_or_absurd_radii_are_refused_by_the_unwarp() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let (d, job) = scratch("arcs", &w.job);
    // a full circle with two turns, at the end of a perimeter
    let (turns, line_p) = insert_after(
        &g,
        ";TYPE:Internal infill\n",
        9,
        "G3 X100 Y100 I1 J0 P2 E0.5\n",
    );
    let huge: String = (0..3000)
        .map(|k| format!("G2 X{} Y0 I-9000000 J0 ; arc {k}\n", 10 + k % 2))
        .collect();
    let (hang, line_h) = insert_after(&g, "G28\n", 1, &format!("G1 X10 Y0 F6000\n{huge}"));
    for (what, bad, line, words) in [
        ("P2", &turns, line_p, "P word"),
        ("I-9000000", &hang, line_h + 1, "larger than any machine"),
    ] {
        let e = refused(what, run_lib(bad, &w.job, None));
        assert_eq!(e.code(), "gcode.bad-arc", "{what}: {e}");
        let m = e.to_string();
        assert!(
            m.contains(&format!("G-code line {line}:")) && m.contains(words),
            "{what}: {m}"
        );
        let cli = run_cli(&d, &job, bad, &[]).unwrap_err();
        assert!(
            cli.contains(&format!("G-code line {line}:")) && cli.contains(words),
            "{what}: {cli}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

// ── item 10: truncated files ────────────────────────────────────────────────────────────────

/// Issue 12 item 10: a G-code cut short (in its last layers, or in its end G-code) was unwarped
/// without a word, heaters left on. The report (and the CLI) warns when the last line has no
/// line end, and when nothing after the last layer ends the print; a whole file, and one whose
/// end G-code is only an end macro, get no warning.
#[test]
fn a_truncated_gcode_is_unwarped_with_a_warning() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    assert!(
        g.ends_with("M104 S0\nM84\n"),
        "the synthetic file's end G-code"
    );
    let (d, job) = scratch("cut", &w.job);
    let whole = run_lib(&g, &w.job, None).unwrap();
    assert!(
        whole.report.warnings.is_empty(),
        "{:?}",
        whole.report.warnings
    );
    let (_, stdout) = run_cli(&d, &job, &g, &[]).unwrap();
    assert!(!stdout.contains("warning"), "{stdout}");
    // the end macro of Klipper users instead of the end G-code
    let klipper = g.replace("M104 S0\nM84\n", "END_PRINT\n");
    assert!(run_lib(&klipper, &w.job, None)
        .unwrap()
        .report
        .warnings
        .is_empty());
    // cut in the last layers, at a line end: no end
    let lines: Vec<&str> = g.lines().collect();
    let cut_layers = lines[..lines.len() * 9 / 10].join("\n") + "\n";
    // cut in the middle of a line of the last layers (`G1 X1` of `G1 X105.3 …`)
    let at = g.len() * 9 / 10;
    let at = at + g[at..].find("G1 X").unwrap() + 5;
    let cut_mid = &g[..at];
    let n_mid = cut_mid.matches('\n').count() + 1;
    // the end G-code gone after the last extrusion (its lift and M104 S0 … lost)
    let cut_end = g.replace("M104 S0\nM84\n", "");
    for (what, text, unterminated) in [
        ("cut in the last layers", cut_layers.as_str(), None),
        ("cut mid-line", cut_mid, Some(n_mid)),
        ("no end G-code", cut_end.as_str(), None),
    ] {
        let r = run_lib(text, &w.job, None)
            .unwrap_or_else(|e| panic!("{what}: {e}"))
            .report;
        let ends = r
            .warnings
            .iter()
            .filter(|w| w.contains("ends the print"))
            .count();
        assert_eq!(ends, 1, "{what}: {:?}", r.warnings);
        let line_end = r.warnings.iter().find(|w| w.contains("has no line end"));
        match unterminated {
            Some(n) => assert!(
                line_end.is_some_and(|w| w.contains(&format!("({n})"))),
                "{what}: {:?}",
                r.warnings
            ),
            None => assert!(line_end.is_none(), "{what}: {:?}", r.warnings),
        }
        let (_, stdout) = run_cli(&d, &job, text, &[]).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!(
            stdout.contains("warning: nothing after the last layer"),
            "{what}: {stdout}"
        );
        // without the placement, a file cut in its last layers is lower than the warped mesh:
        // named as cut short (it was "does not match the warped model")
        let cut_in_layers = what != "no end G-code";
        let reg = UnwarpSettings::default();
        match (cut_in_layers, unwarp(text.as_bytes(), &w.job, &reg)) {
            (true, r) => {
                let e = refused(what, r);
                assert_eq!(e.code(), "register.cut-short", "{what}: {e}");
                assert!(e.to_string().contains("cut short"), "{e}");
            }
            (false, r) => assert!(r.is_ok(), "{what}: the whole object is there"),
        }
    }
    // another model's G-code is still a mismatch, cut short or not
    let mut other = w.job.clone();
    other.warped_bbox.max.x += 3.0;
    other.model_bbox.max.x += 3.0;
    let foreign = synthetic::gcode(&other, true, 2.0).replace("M104 S0\nM84\n", "");
    let e = refused(
        "another model",
        unwarp(foreign.as_bytes(), &w.job, &UnwarpSettings::default()),
    );
    assert_eq!(e.code(), "register.mismatch", "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

// ── item 4: a wipe tower beside the part ────────────────────────────────────────────────────

/// The synthetic file with a flat "wipe tower" (a 10 mm square, outline and infill, `;TYPE:Wipe
/// tower`) printed on every layer `dx` mm beside the part's centre, and the travels to it and
/// back that a slicer writes.
fn with_tower(g: &str, h: f64, dx: f64) -> String {
    let (x0, x1, y0, y1) = (100.0 + dx, 110.0 + dx, 95.0, 105.0);
    let mut out = String::new();
    let mut layer = 0;
    for l in g.lines() {
        if l == ";LAYER_CHANGE" {
            if layer > 0 {
                let z = layer as f64 * h;
                out += &format!(";TYPE:Wipe tower\nG1 E-0.8 F2400\nG0 X{x0} Y{y0} Z{z:.3} F6000\nG1 E0.8 F2400\n");
                for (x, y) in [(x1, y0), (x1, y1), (x0, y1), (x0, y0)] {
                    out += &format!("G1 X{x} Y{y} E0.4 F1800\n");
                }
                let mut y = y0 + 1.0;
                while y < y1 {
                    out += &format!("G0 X{x0} Y{y:.3}\nG1 X{x1} Y{y:.3} E0.4\n");
                    y += 1.0;
                }
            }
            layer += 1;
        }
        out += l;
        out.push('\n');
    }
    out
}

/// The tests' own obstacle check of a 3-axis output: every extruding move (E > 0) is a bead,
/// sampled every 0.25 mm into 0.5 mm cells keeping the highest z; every travel (the moves
/// between two extrusions) is sampled likewise and must not pass more than 0.1 mm below a bead
/// printed before it within 0.5 mm, except within 3.5 mm of the travel's two ends (where the
/// nozzle just printed or is about to print). Returns (travels checked, deepest dip) or the
/// first travel that passes through material.
fn travels_clear_every_bead(out: &str) -> Result<(usize, f64), String> {
    use glam::DVec3;
    let cell = |x: f64, y: f64| ((x / 0.5).floor() as i64, (y / 0.5).floor() as i64);
    let samples = |a: DVec3, b: DVec3| {
        let n = (((b - a).length() / 0.25).ceil() as usize).max(1);
        (0..=n).map(move |k| a.lerp(b, k as f64 / n as f64))
    };
    let mut top: HashMap<(i64, i64), f64> = HashMap::new();
    let mut p = DVec3::splat(f64::NAN);
    // the travel moves since the last bead: (line, from, to)
    let mut gap: Vec<(usize, DVec3, DVec3)> = Vec::new();
    let (mut travels, mut worst) = (0, f64::NEG_INFINITY);
    for (i, s) in steps(out).iter().enumerate() {
        if !matches!(s.cmd, Some(('G', 0 | 1))) {
            continue;
        }
        let w = |c: char, v: f64| s.words.get(&c).copied().unwrap_or(v);
        let q = DVec3::new(w('X', p.x), w('Y', p.y), w('Z', p.z));
        let e = s.words.get(&'E').copied().unwrap_or(0.0);
        if q == p || !p.is_finite() {
            p = q;
            continue;
        }
        if e <= 0.0 {
            gap.push((i + 1, p, q));
            p = q;
            continue;
        }
        if let (Some(&(_, a, _)), b) = (gap.first(), p) {
            travels += 1;
            for &(line, m0, m1) in &gap {
                for t in samples(m0, m1) {
                    if (t - a).truncate().length() < 3.5 || (t - b).truncate().length() < 3.5 {
                        continue;
                    }
                    let (cx, cy) = cell(t.x, t.y);
                    let hi = (-1..=1)
                        .flat_map(|dx| (-1..=1).map(move |dy| (cx + dx, cy + dy)))
                        .filter_map(|c| top.get(&c).copied())
                        .fold(f64::NEG_INFINITY, f64::max);
                    worst = worst.max(hi - t.z);
                    if hi - t.z > 0.1 {
                        return Err(format!(
                            "line {line}: a travel at {t} passes {:.3} mm below a bead printed before it",
                            hi - t.z
                        ));
                    }
                }
            }
            gap.clear();
        }
        for t in samples(p, q) {
            let c = top.entry(cell(t.x, t.y)).or_insert(f64::NEG_INFINITY);
            *c = c.max(t.z);
        }
        p = q;
    }
    Ok((travels, worst))
}

/// Issue 12 item 4: the travel height grid covered the object's box + 20 mm only, so travels
/// between a low non-planar part and a flat tower beside it went through the tower (41
/// travels, up to 1.44 mm deep, with PrusaSlicer's wipe tower). Everything printed in the
/// region is an obstacle now: a tower 40 mm from the part's centre (beyond the old grid) is
/// cleared by every travel, through the library and the CLI.
#[test]
fn travels_to_and_from_a_tower_beside_the_part_clear_it() {
    let w = conic_cube();
    let g = with_tower(
        &synthetic::gcode(&w.job, true, 2.0),
        w.job.layer_height,
        40.0,
    );
    let (d, job) = scratch("tower", &w.job);
    let lib = String::from_utf8(run_lib(&g, &w.job, None).unwrap().gcode).unwrap();
    let (n, worst) = travels_clear_every_bead(&lib).unwrap_or_else(|e| panic!("library: {e}"));
    assert!(n > 200 && worst.is_finite(), "{n} travels, deepest {worst}");
    let cli = run_cli(&d, &job, &g, &[]).unwrap().0;
    travels_clear_every_bead(&cli).unwrap_or_else(|e| panic!("CLI: {e}"));
    let _ = std::fs::remove_dir_all(&d);
}

// ── item 6: RotBot at a cone apex ───────────────────────────────────────────────────────────

/// The synthetic slicer's G-code of the conic cube `job` with a zig-zag whose corners are the
/// cone's apex (100, 100) in the infill of the layers whose cross-section holds it (r ≤ 7.1 mm:
/// z from 4.1 + 0.2 mm to the top's 20.2 mm at the apex): the tool axis flips 180° there.
fn apex_zigzag(job: &Job) -> String {
    let zigzag = "G0 X95 Y95 F6000\nG1 X100 Y100 E0.2 F3000\nG1 X105 Y95 E0.2\nG1 X100 Y100 E0.2\nG1 X95 Y100 E0.2\nG1 X100 Y100 E0.2\nG1 X100 Y105 E0.2\nG0 X92 Y92\n";
    let g = synthetic::gcode(job, true, 1.96);
    let (lo, hi) = (
        g.find(";Z:5.000\n").unwrap(),
        g.find(";Z:19.000\n").unwrap(),
    );
    format!(
        "{}{}{}",
        &g[..lo],
        g[lo..hi].replace(
            ";TYPE:Internal infill\n",
            &format!(";TYPE:Internal infill\n{zigzag}"),
        ),
        &g[hi..]
    )
}

/// How far above the largest `max_feed` of a machine's axes a written F may be. With every axis
/// at or below its largest feed, the firmware's length over the move's time is at most the
/// norm of the largest feeds of the axes it counts (NIST: the linear ones, else the rotary
/// ones; Klipper: X Y Z, else the largest one): √n times the largest, n ≤ 5 axes here, so
/// √5 ≈ 2.24; F ≈ 5·10¹² (the old apex reorientations) is far beyond it.
const FEED_CEILING_FACTOR: f64 = 2.25;

/// The words of a G1 line other than F, as written (the move the firmware reads).
fn move_words(code: &str) -> Vec<&str> {
    code.split_whitespace()
        .filter(|w| !w.starts_with('F'))
        .collect()
}

/// Issue 12 item 6 / issue 11 on every preset and flavour (the default `--feed tip`): at the
/// cone's apex, where RTN and RotBot reorient in place, no G1 line moves the axes and E to
/// where the line before it left them (F aside: the firmware reads no move there), and no F
/// is above [`FEED_CEILING_FACTOR`] × the machine's largest `max_feed` (the reorientations
/// were written with F ≈ 5·10¹² from a tip motion of ~1e-8 mm, and the B head's turns near
/// the apex with F ≈ 3·10⁵ from f · D / L before the feed rule knew the axes' limits). A preset or flavour that
/// refuses the job does so by name; RTN and RotBot print it and reorient.
#[test]
fn every_machine_at_a_cone_apex_writes_no_repeated_move_and_no_runaway_feed() {
    use warpslice::machine::Flavour;
    let w = conic_cube();
    let g = apex_zigzag(&w.job);
    let mut printed = Vec::new();
    for name in warpslice::machine::preset_names() {
        let spec = warpslice::machine::preset(name).unwrap();
        let feeds = serde_json::to_value(&spec).unwrap()["max_feed"].clone();
        let ceiling = feeds
            .as_object()
            .expect("every preset gives max_feed")
            .values()
            .map(|v| v.as_f64().unwrap())
            .fold(0.0, f64::max)
            * FEED_CEILING_FACTOR;
        for flavour in ["reprapfirmware", "marlin", "klipper"] {
            let s = settings(Some(spec.clone()), Flavour::parse(flavour));
            let out = match unwarp(g.as_bytes(), &w.job, &s) {
                Ok(o) => String::from_utf8(o.gcode).unwrap(),
                Err(e) => {
                    assert!(
                        e.code().starts_with("machine.") || e.code().starts_with("unwarp."),
                        "{name} {flavour}: refused without a machine code: {e}"
                    );
                    println!("{name:20} {flavour:15} refused: {}", e.code());
                    continue;
                }
            };
            let (mut prev, mut reorients, mut top) = (Vec::new(), 0, 0.0f64);
            for (i, l) in out.lines().enumerate() {
                let code = l.split(';').next().unwrap().trim();
                if !code.starts_with("G1 ") {
                    if !code.is_empty() {
                        prev.clear();
                    }
                    continue;
                }
                let words = move_words(code);
                assert!(
                    words != prev,
                    "{name} {flavour} line {}: '{code}' moves nothing after the line before it",
                    i + 1
                );
                if let Some(f) = code.split_whitespace().find_map(|w| w.strip_prefix('F')) {
                    let f: f64 = f.parse().unwrap();
                    top = top.max(f);
                    assert!(
                        f <= ceiling,
                        "{name} {flavour} line {}: F{f} above {ceiling} ({FEED_CEILING_FACTOR} × the largest max_feed): '{l}'",
                        i + 1
                    );
                }
                // turns in place, on the part or lifted over (a swing lift)
                reorients += (l.contains("reorient") || l.contains("swing-lift")) as usize;
                prev = words;
            }
            println!("{name:20} {flavour:15} {reorients:5} reorientation lines, largest F {top}");
            printed.push((name, reorients));
        }
    }
    for m in ["rotbot", "rtn-slicer4rtn"] {
        assert!(
            printed.iter().any(|(n, r)| *n == m && *r > 20),
            "{m} did not print the apex with reorientations: {printed:?}"
        );
    }
}

/// Issue 12 item 6: on RotBot (unlimited rotation) each in-place reorientation at a cone's apex
/// (the tool axis flips 180° there) repeated an identical no-op line about 20 times. The conic
/// cube with a zig-zag whose corners are the apex: no G1 line repeats the one before it, the
/// reorientations are still written, and no extruding line turns U by more than 30° (read
/// here, `G92 U` resets followed).
#[test]
fn rotbot_reorients_at_a_cone_apex_without_repeated_lines() {
    let w = conic_cube();
    let g = apex_zigzag(&w.job);
    let out = String::from_utf8(run_lib(&g, &w.job, Some("rotbot")).unwrap().gcode).unwrap();
    let (mut prev, mut u): (&str, Option<f64>) = ("", None);
    let mut reorients = 0;
    for (i, l) in out.lines().enumerate() {
        let code = l.split(';').next().unwrap().trim();
        let word = |c: char| {
            code.split_whitespace()
                .find_map(|w| w.strip_prefix(c))
                .map(|v| v.parse::<f64>().unwrap())
        };
        if code.starts_with("G92") {
            u = word('U').or(u);
            continue;
        }
        if !code.starts_with("G1") {
            continue;
        }
        assert!(
            code != prev,
            "line {}: '{code}' repeats the line before it",
            i + 1
        );
        reorients += (l.contains("reorient") || l.contains("swing-lift")) as usize;
        if let (Some(a), Some(b)) = (u, word('U')) {
            assert!(
                word('E').unwrap_or(0.0) <= 0.0 || (b - a).abs() <= 30.0,
                "line {}: an extruding line turns U from {a} to {b}",
                i + 1
            );
        }
        u = word('U').or(u);
        prev = code;
    }
    assert!(reorients > 50, "{reorients} reorientation lines");
}

// ── issue 10 §2: singularities ───────────────────────────────────────────────────────────────

/// The swing the issue names: a rotary axis turning this much (degrees) …
const SWING_TURN_DEG: f64 = 90.0;
/// … while the tip, extruding or turning in place on the part, travels at most this, mm
/// (issue 10: "about 175° within 0.15 mm of extrusion").
const SWING_TIP_MM: f64 = 0.15;
/// A line whose tip moves less than this from the line before it turns in place, mm.
const IN_PLACE_MM: f64 = 0.005;
/// A swing lift's lines in the air are at least this far above the part's line before them, mm
/// (the emitter's lift is 1 mm; the run's own path rises less than a tenth of it).
const LIFTED_MM: f64 = 0.9;

/// Issue 10 §2 "singularities", on every preset (RepRapFirmware): at a cone's apex (the
/// zig-zag whose corners are the apex, where the tool axis flips 180°) no rotary axis turns
/// [`SWING_TURN_DEG`] while the tip stays on the part within [`SWING_TIP_MM`] of path
/// (extruding lines and turns in place, of an extruding move or a travel, read with the tests'
/// own forward kinematics, `fk.rs`);
/// instead the head is lifted ([`LIFTED_MM`] above the part for every line in the air of a
/// `; swing-lift` group), turned and set down, and the report lists every such place. pax-5axis
/// and open5x-ab (the issue's two) lift at least once. A preset that refuses the job does so by
/// name.
#[test]
fn every_machine_lifts_over_a_swing_at_a_cone_apex_instead_of_turning_on_the_part() {
    let w = conic_cube();
    let g = apex_zigzag(&w.job);
    let mut lifted = HashMap::new();
    for name in warpslice::machine::preset_names() {
        let spec = warpslice::machine::preset(name).unwrap();
        // a table machine prints the part on its axes: placed at the origin when the slicer's
        // placement is beyond its travel
        let placed = || {
            let mut s = settings(Some(spec.clone()), None);
            s.unwarp.place = Some([0.0, 0.0]);
            unwarp(g.as_bytes(), &w.job, &s)
        };
        let out = match run_lib(&g, &w.job, Some(name)).or_else(|e| match e.code() {
            "machine.travel" => placed(),
            _ => Err(e),
        }) {
            Ok(o) => o,
            Err(e) => {
                assert!(
                    e.code().starts_with("machine.") || e.code().starts_with("unwarp."),
                    "{name}: refused without a machine code: {e}"
                );
                println!("{name:20} refused: {}", e.code());
                continue;
            }
        };
        let rep = out.report.machine.clone().expect("a machine report");
        let text = String::from_utf8(out.gcode).unwrap();
        let m = spec.build().unwrap();
        let names = m.axis_names();
        let rotary: Vec<bool> = m.limits().iter().map(|l| l.rotary).collect();
        let fk = common::machine::fk::Fk::from_spec(&spec).unwrap();
        let lines = common::machine::parse(&text, &names).unwrap();
        let all: Vec<&str> = text.lines().collect();
        let e_of = |l: &common::machine::AxisLine| {
            all[l.number - 1]
                .split(';')
                .next()
                .unwrap()
                .split_whitespace()
                .find_map(|w| w.strip_prefix('E'))
                .map_or(0.0, |v| v.parse::<f64>().unwrap())
        };
        let tips: Vec<DVec3> = lines
            .iter()
            .map(|l| fk.forward(&l.axes).unwrap().0)
            .collect();
        let mut window: Vec<(usize, f64, Vec<f64>)> = Vec::new(); // (line, tip path so far, axes)
        let mut path = 0.0;
        let (mut groups, mut in_group, mut before_z) = (0u64, false, f64::NAN);
        let mut prev: Option<(DVec3, Vec<f64>)> = None;
        for (k, l) in lines.iter().enumerate() {
            let tip = tips[k];
            let src = all[l.number - 1];
            let swing = src.contains("; swing-lift");
            let e = e_of(l);
            let (moved, start_axes) = match &prev {
                Some((p, a)) => ((tip - *p).length(), a.clone()),
                None => (f64::INFINITY, l.axes.clone()),
            };
            if swing && !in_group {
                groups += 1;
                before_z = prev.as_ref().map_or(tip.z, |(p, _)| p.z);
            }
            // the lines in the air: every line of a group but the set-down (its last)
            let next_swing = all
                .get(l.number)
                .is_some_and(|n| n.contains("; swing-lift"));
            if swing && next_swing {
                assert!(
                    tip.z >= before_z + LIFTED_MM,
                    "{name} line {}: a swing lift's line at z {:.3}, not {LIFTED_MM} mm above the part's {before_z:.3}",
                    l.number,
                    tip.z
                );
            }
            in_group = swing;
            // a rotate-around (a single-revolution axis' lifted turn) is in the air too
            let air = swing || src.contains("; rotate-around");
            let on_part = !air && (e > 0.0 || moved < IN_PLACE_MM);
            if !on_part {
                window.clear();
                path = 0.0;
            } else {
                if window.is_empty() {
                    window.push((l.number, 0.0, start_axes));
                }
                path += if moved.is_finite() { moved } else { 0.0 };
                window.push((l.number, path, l.axes.clone()));
                for (from_line, at, axes) in &window {
                    if path - at > SWING_TIP_MM {
                        continue;
                    }
                    for (i, &r) in rotary.iter().enumerate() {
                        let turn = (l.axes[i] - axes[i]).abs();
                        assert!(
                            !r || turn < SWING_TURN_DEG,
                            "{name}: lines {from_line}–{}: {} turns {turn:.1}° with the tip on the part over {:.3} mm",
                            l.number,
                            names[i],
                            path - at
                        );
                    }
                }
            }
            if l.after.is_some() {
                // a G92 renames the rotary axes: turns are not compared across it
                window.clear();
                path = 0.0;
            }
            prev = Some((tip, l.after.clone().unwrap_or_else(|| l.axes.clone())));
        }
        assert_eq!(
            groups, rep.swing_lifts,
            "{name}: the file's swing-lift groups and the report's count"
        );
        assert_eq!(rep.swings.len() as u64, rep.swing_lifts, "{name}");
        for sw in &rep.swings {
            assert!(
                all[sw.output_line as usize - 1].contains("; swing-lift"),
                "{name}: the report's swing at output line {} is not one",
                sw.output_line
            );
        }
        println!(
            "{name:20} {} swing lifts, {:.3} mm of tip path lifted over",
            rep.swing_lifts, rep.swing_skipped_mm
        );
        lifted.insert(name, rep.swing_lifts);
    }
    for m in ["pax-5axis", "open5x-ab"] {
        assert!(
            lifted.get(m).is_some_and(|&n| n > 0),
            "{m} has no swing lift at the apex: {lifted:?}"
        );
    }
}

/// Issue 12 item 4 with a real slicer: PrusaSlicer with two extruders (perimeters from the
/// second) and its wipe tower at (180, 140), 80 mm from the part — beyond the old grid. Every
/// travel of the unwarp clears every bead printed before it (the tests' own walk), every tool
/// change is kept and followed by a climb, and the file passes the independent checker.
#[test]
fn prusaslicer_wipe_tower_travels_clear_the_tower() {
    use common::skip;
    use warpslice::slicer::{SliceOptions, SlicerKind};
    let model =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/stl/ps_20mmbox_ascii.stl");
    if !model.exists() {
        return skip::skip_or_fail("wipe tower", "no corpus at ../shared/corpus/stl");
    }
    if let Err(e) = warpslice::slicer::available(SlicerKind::PrusaSlicer) {
        return skip::skip_or_fail("wipe tower", &e.to_string());
    }
    let d = std::env::temp_dir().join(format!(
        "warpslice-safety-{}-ps-wipe-tower",
        std::process::id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    let out = d.join("box.gcode");
    let warp = WarpOptions::new(WarpParams {
        spec: WarpSpec::Conic {
            angle: 30.0,
            direction: Direction::Outward,
            center: [0.0, 0.0],
        },
        base: None,
    });
    let two = |v: &str| format!("{v},{v}");
    let extra: Vec<String> = [
        "--nozzle-diameter".to_string(),
        two("0.4"),
        "--filament-diameter".into(),
        two("1.75"),
        "--temperature".into(),
        two("210"),
        "--first-layer-temperature".into(),
        two("210"),
        "--extrusion-multiplier".into(),
        two("1"),
        "--retract-length".into(),
        two("0.8"),
        "--wipe-tower".into(),
        "--perimeter-extruder".into(),
        "2".into(),
        "--infill-extruder".into(),
        "1".into(),
        "--solid-infill-extruder".into(),
        "1".into(),
    ]
    .into();
    let slice = SliceOptions {
        slicer: SlicerKind::PrusaSlicer,
        extra_args: extra,
        ..SliceOptions::default()
    };
    let settings = UnwarpSettings::default();
    let report =
        warpslice::pipeline::files::run(&model, &warp, &slice, &settings, &out, &mut ()).unwrap();
    let files = warpslice::pipeline::files::RunFiles::next_to(&out);
    let sliced = std::fs::read_to_string(&files.sliced).unwrap();
    let written = std::fs::read_to_string(&out).unwrap();
    let tools = |t: &str| t.lines().filter(|l| l.starts_with('T')).count();
    assert!(
        sliced.contains(";TYPE:Wipe tower") && tools(&sliced) > 20,
        "PrusaSlicer printed a wipe tower and changed tools"
    );
    assert_eq!(tools(&written), tools(&sliced));
    let (n, worst) = travels_clear_every_bead(&written).unwrap();
    assert!(n > 100, "{n} travels, deepest {worst}");
    let climbs = climbs_after_head_moves(&written, settings.unwarp.travel_clearance).unwrap();
    // one climb per tool change after the start G-code (its prime lines change tools too)
    let printing = &written[written.find(";LAYER_CHANGE").unwrap()..];
    assert_eq!(climbs, tools(printing), "a climb after every tool change");
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    independent_check(&files.warped, &sliced, &written);
    let _ = std::fs::remove_dir_all(&d);
}

// ── item 2: never below the bed ─────────────────────────────────────────────────────────────

/// The lowest Z any G0/G1 of `out` reaches (the tests' own reading; `Z` words only, absolute
/// positioning as the unwarp writes it), and how many extrusions are written at Z 0.
fn lowest_z(out: &str) -> (f64, usize) {
    let mut lowest = f64::INFINITY;
    let mut at_bed = 0;
    for s in steps(out) {
        if matches!(s.cmd, Some(('G', 0 | 1))) {
            if let Some(&z) = s.words.get(&'Z') {
                lowest = lowest.min(z);
                if z == 0.0 && s.words.get(&'E').is_some_and(|&e| e > 0.0) {
                    at_bed += 1;
                }
            }
        }
    }
    (lowest, at_bed)
}

/// Issue 12 item 2, second half: a wrong `--offset` (10 mm: the slicer put the part elsewhere)
/// mapped the part's points millimetres below the bed, and the clamp flattened them onto it
/// with E scaled toward 0 (12,381 moves at Z 0: the nozzle ploughs the bed). Now an object point
/// mapped outside the part (below its bottom among others) by more than the shape check's
/// tolerance refuses the unwarp by name (`unwarp.shape-mismatch`, the line, the fix), through
/// the library and the CLI; with the right offset nothing is written below the bed and no
/// extrusion is flattened onto it.
#[test]
fn a_wrong_offset_that_pushes_the_part_into_the_bed_is_refused() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let (d, job) = scratch("bed", &w.job);
    let with_offset = |o: [f64; 2]| {
        let s = UnwarpSettings {
            unwarp: UnwarpOptions {
                offset: Some(o),
                ..UnwarpOptions::default()
            },
            output: MachineOptions::default(),
        };
        unwarp(g.as_bytes(), &w.job, &s)
    };
    let right = with_offset([100.0, 100.0]).unwrap();
    let text = String::from_utf8(right.gcode).unwrap();
    let (low, at_bed) = lowest_z(&text);
    assert!(low >= 0.0, "a move at Z {low}");
    assert_eq!(at_bed, 0, "extrusions flattened onto the bed");
    for (dx, dy) in [(10.0, 0.0), (0.0, -10.0), (-3.0, 0.0), (0.0, 0.5)] {
        let o = [100.0 + dx, 100.0 + dy];
        let e = refused(&format!("offset {o:?}"), with_offset(o));
        assert_eq!(e.code(), "unwarp.shape-mismatch", "{o:?}: {e}");
        let m = e.to_string();
        assert!(
            m.starts_with("G-code line ") && m.contains("maps") && m.contains("--offset is wrong"),
            "{m}"
        );
        let cli = run_cli(&d, &job, &g, &["--offset", &format!("{},{}", o[0], o[1])]).unwrap_err();
        assert!(
            cli.contains("does not fit this job's part") && cli.contains("--offset"),
            "{o:?}: {cli}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

// ── misleading errors ───────────────────────────────────────────────────────────────────────

/// `warpslice warp MODEL --warp conic -o OUT`: Err(stderr) or Ok(stdout).
fn cli_warp(model: &std::path::Path, out: &std::path::Path) -> Result<String, String> {
    let o = Command::new(CLI)
        .args(["warp", model.to_str().unwrap(), "--warp", "conic", "-o"])
        .arg(out)
        .output()
        .unwrap();
    if o.status.success() {
        Ok(String::from_utf8_lossy(&o.stdout).into_owned())
    } else {
        Err(String::from_utf8_lossy(&o.stderr).into_owned())
    }
}

/// Issue 12, misleading errors: a PNG or a UTF-16 text opened as STL got "truncated binary
/// STL", a 1 µm model was accepted by `warp` (the slicer failed later), a binary file as the
/// job got a UTF-8 error, CR-only line ends got "line 1 is longer than 65536 bytes", and a NUL
/// in a number was echoed raw. Each now names the real cause and the fix (its code, its words),
/// by the library and the CLI; a binary STL cut short is still "truncated" (a zero-filled header
/// is not taken for UTF-16).
#[test]
fn misleading_inputs_are_named_with_their_real_cause() {
    use warpslice::pipeline::warp_model;
    let w = conic_cube();
    let (d, job) = scratch("misleading", &w.job);
    let opts = WarpOptions::new(w.job.warp.clone());
    let cube = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "c");
    let ascii = format!(
        "solid c\n{}endsolid c\n",
        "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
            .repeat(4)
    );
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(std::iter::repeat_n(7u8, 300));
    let utf16: Vec<u8> = ascii.encode_utf16().flat_map(|u| u.to_le_bytes()).collect();
    let mut utf16_bom = vec![0xff, 0xfe];
    utf16_bom.extend(&utf16);
    // the corpus box scaled to 1 µm
    let (mut tiny, _) = warpslice::mesh::read_stl(&cube).unwrap();
    for v in &mut tiny.vertices {
        *v *= 5e-5;
    }
    let tiny = warpslice::mesh::write_stl(&tiny, "tiny");
    let mut cut = cube.clone();
    cut.truncate(cube.len() - 60);
    for (what, bytes, code, words) in [
        (
            "PNG",
            png.clone(),
            "mesh.not-stl",
            "not an STL file: it starts like a PNG image",
        ),
        ("UTF-16", utf16.clone(), "mesh.not-stl", "UTF-16"),
        ("UTF-16 with BOM", utf16_bom, "mesh.not-stl", "UTF-16"),
        ("1 µm", tiny, "mesh.too-small", "metres"),
        ("cut short", cut, "mesh.truncated", "truncated"),
    ] {
        let e = warp_model(&bytes, &opts)
            .err()
            .unwrap_or_else(|| panic!("{what} accepted"));
        assert_eq!(e.code(), code, "{what}: {e}");
        assert!(e.to_string().contains(words), "{what}: {e}");
        let f = d.join("model.stl");
        std::fs::write(&f, &bytes).unwrap();
        let cli = cli_warp(&f, &d.join("w.stl")).unwrap_err();
        assert!(cli.contains(words), "{what}: {cli}");
    }
    // a model of half a millimetre is printable
    let (mut small, _) = warpslice::mesh::read_stl(&cube).unwrap();
    for v in &mut small.vertices {
        *v *= 0.025;
    }
    assert!(warp_model(&warpslice::mesh::write_stl(&small, "s"), &opts).is_ok());

    // a binary file as the job
    let e = warpslice::job::Job::from_bytes(&png).unwrap_err();
    assert_eq!(e.code(), "job.parse", "{e}");
    assert!(e.to_string().contains("not text"), "{e}");
    let bad_job = d.join("bad.job.json");
    std::fs::write(&bad_job, &png).unwrap();
    let g = synthetic::gcode(&w.job, true, 2.0);
    std::fs::write(d.join("in.gcode"), &g).unwrap();
    let o = Command::new(CLI)
        .args(["unwarp", d.join("in.gcode").to_str().unwrap(), "--job"])
        .arg(&bad_job)
        .arg("-o")
        .arg(d.join("o.gcode"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("not text"), "{err}");

    // CR-only line ends
    let cr = g.replace('\n', "\r");
    let e = refused("CR", run_lib(&cr, &w.job, None));
    assert_eq!(e.code(), "gcode.cr-line-ends", "{e}");
    assert!(e.to_string().contains("carriage return"), "{e}");
    let cli = run_cli(&d, &job, &cr, &[]).unwrap_err();
    assert!(cli.contains("carriage return"), "{cli}");
    // CR LF is read as ever
    assert!(run_lib(&g.replace('\n', "\r\n"), &w.job, None).is_ok());

    // a NUL inside a number: named, not echoed raw
    let (nul, line) = insert_after(&g, ";TYPE:Internal infill\n", 5, "G1 X100\0 Y100 E0.1\n");
    let e = refused("NUL", run_lib(&nul, &w.job, None));
    let m = e.to_string();
    assert!(
        m.contains(&format!("G-code line {line}:")) && m.contains("NUL") && !m.contains('\0'),
        "{m:?}"
    );
    let o = Command::new(CLI)
        .args(["unwarp", "--offset", "100,100", "--job"])
        .arg(&job)
        .arg("-o")
        .arg(d.join("o.gcode"))
        .arg({
            std::fs::write(d.join("nul.gcode"), &nul).unwrap();
            d.join("nul.gcode")
        })
        .output()
        .unwrap();
    assert!(!o.status.success() && !o.stderr.contains(&0u8));
    assert!(String::from_utf8_lossy(&o.stderr).contains("NUL"));
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 12, misleading errors: a slicer's Z offset (every layer lifted by the same amount) got
/// advice about the first-layer height only. The refusal now names both causes — the first layer
/// height, or the slicer's Z offset with its value — and the fix for each.
#[test]
fn a_slicer_z_offset_is_named_as_such() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    // every Z word 0.1 mm higher, as PrusaSlicer's z_offset writes them
    let lifted: String = g
        .lines()
        .map(|l| {
            let words: Vec<String> = l
                .split(' ')
                .map(|w| match w.strip_prefix('Z') {
                    Some(v) if l.starts_with("G1 ") => {
                        format!("Z{:.3}", v.parse::<f64>().unwrap() + 0.1)
                    }
                    _ => w.to_string(),
                })
                .collect();
            words.join(" ") + "\n"
        })
        .collect();
    let (d, job) = scratch("zoffset", &w.job);
    let e = refused("Z offset", run_lib(&lifted, &w.job, None));
    assert_eq!(e.code(), "register.anchor-layer", "{e}");
    let m = e.to_string();
    assert!(
        m.contains("Z offset is +0.100 mm") && m.contains("--z-offset"),
        "{m}"
    );
    let cli = run_cli(&d, &job, &lifted, &[]).unwrap_err();
    assert!(cli.contains("Z offset is +0.100 mm"), "{cli}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The largest and smallest Y of `text`'s G1 lines that carry a Y word (the machine file's own
/// words: the travel the firmware is asked for).
fn y_range(text: &str) -> (f64, f64) {
    text.lines()
        .filter(|l| l.starts_with("G1 "))
        .filter_map(|l| {
            l.split(';')
                .next()
                .unwrap()
                .split_whitespace()
                .find_map(|w| w.strip_prefix('Y'))
                .map(|v| v.parse::<f64>().unwrap())
        })
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
            (lo.min(y), hi.max(y))
        })
}

/// Issue 10 §2 "singularities", the A/B table's two solutions: the table carries a tip to
/// machine Y ≈ ±(r·cos t − z·sin t) depending on the branch, `(A, B)` or `(−A, B ± 180°)`
/// (on the pole of a tall part, ±z·sin t: ±50 mm at 100 mm and 30°, past Open5x's Y travel
/// on one side — PrusaSlicer's rear case × conic-out-30 × open5x-prusa-uv with thin walls).
/// The conic cube without its skirt spans Y −14.8 … 14.6 on the branches the emitter keeps by
/// continuity; with the Y travel cut to [−14, 100] the file is still written: where a move
/// would leave the travel the table flips to its other branch in the air — a `; swing-lift`
/// group turning B by at least [`FLIP_TURN_DEG`] with every line in the air
/// [`LIFTED_MM`] above the part's last line — every Y word is within the travel (read from
/// the file), the extrusions are the toolpath's (the tests' walker and forward kinematics,
/// `common/machine.rs`), and the report lists each flip with the swings. Plants: no other
/// branch (refused with `machine.travel`: caught), the flip lifted along +Z instead of the tool
/// axis (refused: caught), the whole turn in one line (the interpolated tip at A = 0 is below
/// the part's top: caught by the samples).
#[test]
fn an_ab_table_flips_its_branch_in_the_air_where_a_move_would_leave_the_travel() {
    const Y_TRAVEL: [f64; 2] = [-30.0, 100.0];
    let w = synthetic::conic_box(DVec3::new(12.0, 12.0, 60.0));
    let g = synthetic::gcode(&w.job, true, 1.96);
    let mut spec = warpslice::machine::preset("open5x-ab").unwrap();
    let mut travel = spec.travel.clone().unwrap();
    travel.insert("Y".into(), Y_TRAVEL);
    spec.travel = Some(travel);
    let mut s = settings(Some(spec.clone()), None);
    s.unwarp.place = Some([0.0, 0.0]);
    s.unwarp.drop_skirt = true;
    s.unwarp.collect_toolpath = true;
    let out = unwarp(g.as_bytes(), &w.job, &s).expect("the table flips instead of refusing");
    let text = String::from_utf8(out.gcode).unwrap();
    let (lo, hi) = y_range(&text);
    assert!(
        lo >= Y_TRAVEL[0] && hi <= Y_TRAVEL[1],
        "Y words {lo} … {hi} beyond the travel {Y_TRAVEL:?}"
    );
    let names = spec.build().unwrap().axis_names();
    let lines = common::machine::parse(&text, &names).unwrap();
    common::machine::check(&spec, &out.toolpath, &lines, 0).expect("the extrusions on the path");
    // the flips: swing-lift groups whose B turns half a revolution
    let fk = common::machine::fk::Fk::from_spec(&spec).unwrap();
    let b = names.iter().position(|n| n == "B").unwrap();
    let all: Vec<&str> = text.lines().collect();
    let mut flips = 0;
    let mut k = 0;
    while k < lines.len() {
        if !all[lines[k].number - 1].contains("; swing-lift") || k == 0 {
            k += 1;
            continue;
        }
        let before = &lines[k - 1];
        let part_z = fk.forward(&before.axes).unwrap().0.z;
        let mut end = k;
        while end + 1 < lines.len() && all[lines[end + 1].number - 1].contains("; swing-lift") {
            end += 1;
        }
        if (lines[end].axes[b] - before.axes[b]).abs() >= FLIP_TURN_DEG {
            flips += 1;
            // the firmware interpolates the axes linearly: sampled along every line but the
            // lift and the set-down, the tip stays in the air
            for pair in lines[k..end].windows(2) {
                for i in 0..=FLIP_SAMPLES {
                    let s = i as f64 / FLIP_SAMPLES as f64;
                    let axes: Vec<f64> = (pair[0].axes.iter().zip(&pair[1].axes))
                        .map(|(a, b)| a + (b - a) * s)
                        .collect();
                    let z = fk.forward(&axes).unwrap().0.z;
                    assert!(
                        z >= part_z + LIFTED_MM,
                        "line {}: a flip at z {z:.3} ({s} of the line), not {LIFTED_MM} mm above {part_z:.3}",
                        pair[1].number
                    );
                }
            }
        }
        k = end + 1;
    }
    let rep = out.report.machine.expect("a machine report");
    let listed = rep
        .swings
        .iter()
        .filter(|sw| sw.tip_mm == 0.0 && sw.turn_deg >= FLIP_TURN_DEG)
        .count();
    println!("Y {lo:.3} … {hi:.3}: {flips} flips in the file, {listed} in the report");
    assert!(flips > 0, "no flip: the travel cut does not need one");
    assert_eq!(flips, listed, "the file's flips and the report's");
}

/// Samples along each line of a flip (the firmware's linear interpolation of the axes).
const FLIP_SAMPLES: usize = 8;

/// A branch flip turns B by at least this much, degrees (half a revolution, less the tilt's
/// share of the turn near the pole).
const FLIP_TURN_DEG: f64 = 150.0;
