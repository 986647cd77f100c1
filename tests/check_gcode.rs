//! `warpslice check` (issue 10 §3, §5): any 4/5-axis G-code read for a machine, its findings
//! with exact 1-based file lines, through the library and the CLI (exit codes 0, 1, 2).
//!
//! Oracles, independent of the checker:
//! - the tip path of a file warpslice wrote is the tests' own forward kinematics
//!   (tests/common/fk.rs: closed forms from the seeds and docs/machines.md) of the axis words
//!   read by the tests' own parser (tests/common/machine.rs);
//! - reach, speed and time findings of hand-built files: limits read from the preset JSON
//!   files (presets/*.json, as text), speeds from docs/machines.md's feed rule
//!   (`T = D / F`, D the NIST length: the linear axes' norm, else the rotary axes' norm;
//!   `T = 1 / F` in G93), written here.
#![cfg(not(target_arch = "wasm32"))]

#[path = "common/check_files.rs"]
mod check_files;
mod common;
#[path = "common/synthetic.rs"]
mod synthetic;

use check_files::{bhead_speed_file, clean_file, rtn_reach_file, Lines};

use std::process::Command;

use common::machine::{fk::Fk, parse};
use common::preset_warp::{spec_for, warped_cube6};
use warpslice::check::{check, CheckError, CheckOptions, CheckStream, FindingKind};
use warpslice::error::Coded;
use warpslice::machine::{preset, preset_names};
use warpslice::pipeline::{unwarp, UnwarpSettings};
use warpslice::unwarp::UnwarpOptions;

/// Tip agreement of the check's path with the tests' forward kinematics of the same written
/// numbers, mm: both evaluate closed forms of the same values (rounding only; a `G92` rotary
/// reset renames an angle by 360°, exact in the sines).
const SAME_TIP_MM: f64 = 1e-6;

/// A preset's JSON as the file says (the oracle's limits, read without the crate).
fn preset_json(name: &str) -> serde_json::Value {
    let path = format!("{}/presets/{name}.json", env!("CARGO_MANIFEST_DIR"));
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Where the part goes (the machines turning about the output origin).
fn place_for(preset: &str) -> Option<[f64; 2]> {
    match preset {
        "core-r-theta" => Some([60.0, 0.0]),
        "open5x-ab" | "open5x-prusa-uv" | "open5x-jubilee-bc" | "lathe-a" => Some([0.0, 0.0]),
        _ => None,
    }
}

/// warpslice's machine G-code of a 6 mm cube for `name` (synthetic slicer, tests/common;
/// small so the nine presets' unwarps and checks stay quick).
fn written_by_warpslice(name: &str) -> Vec<u8> {
    let w = warped_cube6(name);
    let input = synthetic::gcode(&w.job, true, 3.0);
    let mut settings = UnwarpSettings::with_machine(
        UnwarpOptions {
            place: place_for(name),
            ..UnwarpOptions::default()
        },
        spec_for(name),
    );
    // the file is read back for its kinematics; the default head meets some presets' warped
    // cube (the collision check, on by default, is tested in tests/collision_check.rs)
    settings.output.allow_collisions = true;
    unwarp(input.as_bytes(), &w.job, &settings)
        .unwrap_or_else(|e| panic!("{name}: unwarp: {e}"))
        .gcode
}

/// The cartesian file's G1 lines (every line with X, Y and Z; tests/common/machine.rs reads
/// only files with a rotary axis): X Y Z modal, no G92 on them in warpslice's output.
fn xyz_lines(text: &str) -> Vec<common::machine::AxisLine> {
    let mut cur = [None::<f64>; 3];
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let code = raw.split(';').next().unwrap_or("");
        let mut words = code.split_whitespace();
        if !matches!(words.next(), Some("G1" | "G0")) {
            continue;
        }
        let mut named = false;
        for w in words {
            let (l, v) = w.split_at(1);
            if let Some(k) = ["X", "Y", "Z"].iter().position(|c| *c == l) {
                cur[k] = Some(v.parse().unwrap());
                named = true;
            }
        }
        if let ([Some(x), Some(y), Some(z)], true) = (cur, named) {
            out.push(common::machine::AxisLine {
                number: i + 1,
                axes: vec![x, y, z],
                rotate_around: false,
                after: None,
                reorient: false,
                discontinuity: false,
            });
        }
    }
    out
}

#[test]
fn check_reads_warpslice_output_of_every_preset_on_the_tests_forward_kinematics() {
    for name in preset_names() {
        let spec = spec_for(name);
        let gcode = written_by_warpslice(name);
        // the check's path, fed in odd slices (a line split across pushes)
        let mut s = CheckStream::new(
            &spec,
            &CheckOptions {
                path: true,
                ..CheckOptions::default()
            },
        )
        .unwrap();
        for chunk in gcode.chunks(977) {
            s.push(chunk).unwrap();
        }
        let (report, path) = s.finish().unwrap();
        // the tests' reader and kinematics of the same text
        let text = String::from_utf8(gcode).unwrap();
        let names = spec.build().unwrap().axis_names();
        let lines = if name == "cartesian" {
            xyz_lines(&text)
        } else {
            parse(&text, &names).unwrap()
        };
        let fk = Fk::from_spec(&spec).unwrap();
        let mut compared = 0;
        for l in &lines {
            let (p, n) = fk.forward(&l.axes).unwrap();
            let got = path
                .iter()
                .find(|q| q.line == l.number as u64)
                .unwrap_or_else(|| panic!("{name}: no check point at line {}", l.number));
            assert!(
                (got.p - p).length() < SAME_TIP_MM && (got.n - n).length() < SAME_TIP_MM,
                "{name} line {}: check tip {:?} axis {:?}, forward kinematics {p:?} {n:?}",
                l.number,
                got.p,
                got.n
            );
            compared += 1;
        }
        assert!(compared > 500, "{name}: only {compared} machine lines");
        // warpslice's own file passes the check's reach on every line, the start and end
        // G-code included (converted to the machine's axes, tests/machine_outside.rs)
        let reach: Vec<_> = report
            .findings
            .iter()
            .filter(|f| f.kind == FindingKind::Reach)
            .collect();
        assert!(
            reach.is_empty(),
            "{name}: reach findings in warpslice's own file: {reach:?}"
        );
        assert!(report.extruded_mm > 0.0, "{name}");
        println!("{name:20} {compared} lines; {}", report.summary());
    }
}

#[test]
fn a_rotary_axis_past_its_range_is_a_reach_finding_on_its_line() {
    let (text, bad) = rtn_reach_file();
    let limit = preset_json("rtn-slicer4rtn")["rotation_range_deg"][1]
        .as_f64()
        .unwrap();
    let r = check(
        text.as_bytes(),
        &preset("rtn-slicer4rtn").unwrap(),
        &CheckOptions::default(),
    )
    .unwrap();
    assert_eq!(r.counts.reach, 1, "{:?}", r.findings);
    assert_eq!(
        r.counts.total(),
        1,
        "only the reach finding: {:?}",
        r.findings
    );
    let f = r
        .findings
        .iter()
        .find(|f| f.kind == FindingKind::Reach)
        .unwrap();
    assert_eq!(
        (f.line, f.axis.as_deref(), f.value, f.limit),
        (bad, Some("A"), Some(175.0), Some(limit))
    );
    let a = r.axes.iter().find(|a| a.axis == "A").unwrap();
    assert_eq!(
        (a.highest, a.margin_max),
        (Some(175.0), Some(limit - 175.0))
    );
}

#[test]
fn an_axis_over_its_largest_feed_is_a_speed_finding_with_its_speed() {
    let (text, fast) = bhead_speed_file();
    let max_b = preset_json("fullcontrol-prusa-b")["max_feed"]["B"]
        .as_f64()
        .unwrap();
    assert!(max_b < 36000.0);
    let r = check(
        text.as_bytes(),
        &preset("fullcontrol-prusa-b").unwrap(),
        &CheckOptions::default(),
    )
    .unwrap();
    assert_eq!(r.counts.speed, 1, "{:?}", r.findings);
    let w = r.worst_speed.as_ref().unwrap();
    assert_eq!(w.line, fast);
    assert_eq!(w.axis.as_deref(), Some("B"));
    assert!((w.value.unwrap() - 36000.0).abs() < 1e-6, "{w:?}");
    assert_eq!(w.limit, Some(max_b));
    // time: X 10 mm at F1000; B 60° slowed to its limit; B back 60° at F1000 (1000 °/min);
    // the return √(10² + 2²) mm at F1000 (the first move's start is unknown: not timed)
    let want = 10.0 / 1000.0 + 60.0 / max_b + 60.0 / 1000.0 + 104f64.sqrt() / 1000.0;
    assert!(
        (r.print_time_min - want).abs() < 1e-9,
        "{} vs {want}",
        r.print_time_min
    );
    assert!((r.slowdown_min - (60.0 / max_b - 60.0 / 36000.0)).abs() < 1e-9);
    assert!((r.total_e_mm - 1.0).abs() < 1e-12);
}

#[test]
fn a_clean_file_reports_nothing_and_counts_its_filament_and_tilt() {
    let r = check(
        clean_file().as_bytes(),
        &preset("cartesian").unwrap(),
        &CheckOptions::default(),
    )
    .unwrap();
    assert!(r.is_clean(), "{:?}", r.findings);
    assert!(r.collisions_checked);
    assert_eq!(r.extruding_moves, 20);
    assert!((r.total_e_mm - 8.0).abs() < 1e-9);
    // every extruding move vertical: all in the first 5° bin
    assert_eq!(r.tilt_histogram[0], 20);
    assert_eq!(r.tilt_histogram.iter().sum::<u64>(), 20);
}

/// A cartesian pad of 10 layers (top at 2.0 mm), then the nozzle plunged to Z 1 at its
/// middle: line `plunge`.
fn plunge_file() -> (String, u64) {
    let mut g = check_files::pad(10, 23, 10.0, [10.0, 20.0], 0.5);
    g.add("G1 Z10 F600");
    g.add("G1 X15 Y15 F1800");
    let plunge = g.add("G1 Z1.0 F600");
    (g.0, plunge)
}

#[test]
fn a_plunge_into_the_print_is_a_collision_on_its_line_unless_collisions_are_skipped() {
    let (text, plunge) = plunge_file();
    let spec = preset("cartesian").unwrap();
    let r = check(text.as_bytes(), &spec, &CheckOptions::default()).unwrap();
    let lines: Vec<u64> = r
        .findings
        .iter()
        .filter(|f| f.kind == FindingKind::Collision)
        .map(|f| f.line)
        .collect();
    assert_eq!(lines, vec![plunge], "{:?}", r.findings);
    // the flat tip 1 mm below the pad's top (2.0 mm): 1 mm deep on the axis, less the contact
    // allowance docs/machines.md "Head and bed" gives the nozzle's face, s ≤ (ρ + w/2)·tan 30°,
    // at most (0.5 + 0.45/2)·tan 30° = 0.419 mm at the face's rim (E3D-V6 tip radius 0.5 mm,
    // default line width 0.45 mm); 0.01 mm for the height field's cells
    let c = r.findings[0].collision.as_ref().unwrap();
    let rim = (0.5 + 0.45 / 2.0) * 30f64.to_radians().tan();
    assert!(
        c.depth_mm <= 1.0 + 1e-4 && c.depth_mm >= 1.0 - rim - 0.01,
        "{c:?}"
    );
    assert_eq!(r.findings[0].layer, 10);
    let skip = CheckOptions {
        skip_collisions: true,
        ..CheckOptions::default()
    };
    let r = check(text.as_bytes(), &spec, &skip).unwrap();
    assert!(r.is_clean() && !r.collisions_checked, "{:?}", r.findings);
    assert!(r
        .warnings
        .iter()
        .any(|w| w.contains("collisions not checked")));
}

#[test]
fn the_path_names_the_parts_in_collision_on_each_move_even_past_the_listed_findings() {
    // the RTN rotate-around beside a pad (tests/collision_check.rs): A 179 is past the
    // preset's ±170° on every line before it, so its one collision, the nozzle swept into the
    // pad by the turn, comes after thousands of reach findings
    let (text, _, turn, _) = check_files::rtn_rotate_around_case();
    let mut s = CheckStream::new(
        &preset("rtn-slicer4rtn").unwrap(),
        &CheckOptions {
            path: true,
            max_findings: 10,
            ..CheckOptions::default()
        },
    )
    .unwrap();
    s.push(text.as_bytes()).unwrap();
    let (report, path) = s.finish().unwrap();
    assert_eq!(report.findings.len(), 10);
    assert!(report.counts.reach > 1000 && report.counts.collision == 1);
    assert!(report.findings.iter().all(|f| f.kind == FindingKind::Reach));
    let hit: Vec<(u64, Vec<String>)> = path
        .iter()
        .filter(|q| !q.collisions.is_empty())
        .map(|q| (q.line, q.collisions.clone()))
        .collect();
    assert_eq!(hit, vec![(turn, vec!["nozzle".to_string()])]);
}

#[test]
fn unreadable_input_is_a_named_error() {
    let spec = preset("rtn-slicer4rtn").unwrap();
    let bad = "G90\nG1 X1 Y1 Z1 A0\nG1 X1.2.3 Y1\n";
    let e = check(bad.as_bytes(), &spec, &CheckOptions::default()).unwrap_err();
    assert!(matches!(e, CheckError::BadNumber { line: 3, .. }), "{e:?}");
    assert_eq!(e.code(), "check.bad-number");
    assert!(e.to_string().contains("line 3: '.3'"), "{e}");
    let e = check(b"G1 XNaN Y1\n", &spec, &CheckOptions::default()).unwrap_err();
    assert!(matches!(e, CheckError::BadNumber { line: 1, .. }), "{e:?}");
    let e = check(
        &[0x89, b'P', b'N', b'G', 0, 1, 2],
        &spec,
        &CheckOptions::default(),
    )
    .unwrap_err();
    assert_eq!(e.code(), "check.no-moves", "{e}");
}

/// A Slicer4RTN-style file: inverse-time feed (G93, F = 1/minutes on every move), A in
/// degrees, relative E, comments and a `G92 E0`; then back to G94.
fn rtn_inverse_time_file() -> (String, f64, f64) {
    let mut g = Lines::default();
    let mut minutes = 0.0;
    let mut e = 0.0;
    g.add("; generated by Slicer4RTN-like script");
    g.add("G21 ; mm");
    g.add("G90");
    g.add("M83");
    g.add("G92 E0");
    g.add("G1 X94 Y100 Z12 A-150 F3000");
    g.add("G93 ; inverse time");
    // each extrusion 1 mm along +Y at its own X (6 mm apart: a tilted nozzle never over the
    // previous bead), reached by a lifted travel; A turns 25° per extrusion
    for k in 0..12 {
        let a = -150.0 + 25.0 * k as f64;
        let x = 100.0 + 6.0 * k as f64;
        for (line, f) in [
            (format!("G1 X{x:.3} Y100 Z12 A{a:.1}"), 40.0 + k as f64),
            ("G1 Z10".to_string(), 60.0),
            ("G1 Y101 E0.05".to_string(), 30.0),
            ("G1 Z12".to_string(), 60.0),
        ] {
            g.add(&format!("{line} F{f}"));
            minutes += 1.0 / f;
        }
        e += 0.05;
    }
    g.add("G94");
    g.add("G1 Z30 F600");
    minutes += 18.0 / 600.0;
    (g.0, minutes, e)
}

#[test]
fn another_tools_rtn_file_in_inverse_time_is_read_and_timed() {
    let (text, minutes, e) = rtn_inverse_time_file();
    let r = check(
        text.as_bytes(),
        &preset("rtn-slicer4rtn").unwrap(),
        &CheckOptions::default(),
    )
    .unwrap();
    assert_eq!(r.counts.reach, 0, "{:?}", r.findings);
    assert_eq!(r.inverse_time_moves, 48);
    assert_eq!(r.counts.collision, 0, "{:?}", r.findings);
    assert_eq!(r.extruding_moves, 12);
    assert!((r.total_e_mm - e).abs() < 1e-9);
    // the RTN nozzle is tilted 45° (seed 002): every extrusion in the 45–50° bin
    let tilt = preset_json("rtn-slicer4rtn")["tilt_deg"].as_f64().unwrap();
    let bin = (tilt / r.tilt_bin_deg) as usize;
    assert_eq!(r.tilt_histogram[bin], 12, "{:?}", r.tilt_histogram);
    // G93: each move 1/F minutes unless an axis is over its feed (A 25° in 1/40 min = 1000
    // °/min, under 3600; X 6 mm in 1/40 min = 240 mm/min; Z 2 mm in 1/60 min = 120 mm/min,
    // under 720): no slow-down
    assert_eq!(r.counts.speed, 0, "{:?}", r.findings);
    assert!(
        (r.print_time_min - minutes).abs() < 1e-9,
        "{} vs {minutes}",
        r.print_time_min
    );
}

#[test]
fn a_fullcontrol_style_b_head_file_is_read_with_its_tilts() {
    // B-head: the tip tilts by |B| from +Z (seed 000); FullControl writes absolute E
    let mut g = Lines::default();
    g.add("; FullControl B-axis demo");
    g.add("G90");
    g.add("M82");
    g.add("G92 E0");
    g.add("G1 X100 Y100 Z60 B0 F1000");
    let mut e = 0.0;
    for (k, b) in [0.0, 12.0, 27.0, 33.0, 41.0].iter().enumerate() {
        e += 0.2;
        g.add(&format!(
            "G1 X{:.1} Y100 Z60 B{b} E{e:.3}",
            101.0 + k as f64
        ));
    }
    g.add("G1 E0.8 ; retract (absolute)");
    g.add("G1 X90 Y100 Z70 B0");
    g.add("G1 E1.0 ; unretract");
    g.add("G1 X95 Y100 Z70 B0 E1.2");
    let r = check(
        g.0.as_bytes(),
        &preset("fullcontrol-prusa-b").unwrap(),
        &CheckOptions::default(),
    )
    .unwrap();
    assert_eq!(r.counts.reach, 0, "{:?}", r.findings);
    // absolute E: the retraction −0.2, the unretraction +0.2, the last move +0.2
    assert_eq!(r.extruding_moves, 6);
    assert!((r.total_e_mm - 1.2).abs() < 1e-12 && (r.extruded_mm - 1.2).abs() < 1e-12);
    let mut want = vec![0u64; r.tilt_histogram.len()];
    for b in [0.0, 12.0, 27.0, 33.0, 41.0, 0.0] {
        want[(b / 5.0) as usize] += 1;
    }
    assert_eq!(r.tilt_histogram, want);
    assert!((r.largest_tilt_deg - 41.0).abs() < 1e-9);
}

// ---- the CLI ----

fn cli(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .args(args)
        .output()
        .expect("run warpslice");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn tmp(name: &str, text: &[u8]) -> String {
    let dir = std::env::temp_dir().join(format!("warpslice-check-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn cli_check_exits_0_clean_1_with_findings_on_their_lines_2_unreadable() {
    let clean = tmp("clean.gcode", clean_file().as_bytes());
    let (code, out, err) = cli(&["check", &clean, "--machine", "cartesian"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("0 findings"), "{out}");

    let (text, bad) = rtn_reach_file();
    let limit = preset_json("rtn-slicer4rtn")["rotation_range_deg"][1]
        .as_f64()
        .unwrap();
    let reach = tmp("reach.gcode", text.as_bytes());
    let (code, out, err) = cli(&["check", &reach, "--machine", "rtn-slicer4rtn"]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains(&format!(
            "line {bad}: reach: axis A = 175.000 is beyond its limit {limit}"
        )),
        "{out}"
    );

    let (text, fast) = bhead_speed_file();
    let speed = tmp("speed.gcode", text.as_bytes());
    let (code, out, _) = cli(&[
        "check",
        &speed,
        "--machine",
        "fullcontrol-prusa-b",
        "--json",
    ]);
    // a speed finding is reported but is not a failure: the firmware slows the move down
    assert_eq!(code, 0, "{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["counts"]["speed"], 1);
    assert_eq!(v["findings"][0]["line"], fast);
    assert_eq!(v["findings"][0]["kind"], "speed");

    // unreadable: a bad number (named with its line), a missing file, an unknown machine
    let bad_num = tmp("bad.gcode", b"G90\nG1 X1 Y1 Z1 A0\nG1 X1.2.3 Y1\n");
    let (code, _, err) = cli(&["check", &bad_num, "--machine", "rtn-slicer4rtn"]);
    assert_eq!(code, 2);
    assert!(err.contains("line 3: '.3' is not a G-code number"), "{err}");
    let (code, _, err) = cli(&["check", "/nonexistent.gcode", "--machine", "cartesian"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = cli(&["check", &clean, "--machine", "no-such-machine"]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown machine preset"), "{err}");
}
