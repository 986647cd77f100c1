//! The motion lines outside the printed region on a machine output (issues 10 and 12: "never a
//! silently wrong G-code"): the start G-code, the slicer's travel to the skirt and the end
//! G-code are in the slicer's frame; on a machine output each is placed and converted to the
//! machine's axes at the rest pose (tool axis +Z) and reach-checked, or refused by name.
//!
//! Oracles, independent of the crate's kinematics and emitter:
//! - the written axis words are read by the tests' own parser (tests/common/machine.rs) and
//!   turned into tips and tool axes by the tests' own forward kinematics (tests/common/fk.rs);
//! - where a slicer-frame point must land: the synthetic slicer centres the warped part's box
//!   at (100, 100) (tests/common/synthetic.rs), so with `place` the output is the slicer's point
//!   moved by `place − (100 − c_x, 100 − c_y)`, c the centre of the job's warped box
//!   (docs/machines.md: the part's footprint centre goes to `place`, the flat skirt with it);
//! - the linear travel of each preset is read from presets/*.json as text.
#![cfg(not(target_arch = "wasm32"))]

mod common;
#[path = "common/synthetic.rs"]
mod synthetic;

use glam::DVec3;

use common::machine::{fk::Fk, parse, AxisLine};
use common::preset_warp::{spec_for, warped_cube6};
use warpslice::error::Coded;
use warpslice::job::Job;
use warpslice::pipeline::{unwarp, UnwarpSettings};
use warpslice::unwarp::UnwarpOptions;

/// Agreement of a converted point with where it must land, mm: the registration's residual on
/// the synthetic slicer's exact box (well below 1 µm) plus the 3 written decimals.
const LANDS_MM: f64 = 2e-3;
/// Agreement of a tool axis with +Z (unit vector difference): the written 3 decimals of a
/// rotary angle, 0.0005° ≈ 1e-5.
const VERTICAL: f64 = 1e-4;

/// The warped 6 mm cube of `name`'s warp, its job and the synthetic slicer's G-code (relative E).
fn sliced(name: &str) -> (Job, String) {
    let w = warped_cube6(name);
    let g = synthetic::gcode(&w.job, true, 3.0);
    (w.job, g)
}

fn run(
    name: &str,
    job: &Job,
    g: &str,
    place: Option<[f64; 2]>,
) -> Result<String, warpslice::pipeline::Error> {
    let mut settings = UnwarpSettings::with_machine(
        UnwarpOptions {
            place,
            ..UnwarpOptions::default()
        },
        spec_for(name),
    );
    // the moves outside the printed region, not the head's clearance (collision_check.rs): the
    // default head meets some presets' warped cube, so written anyway
    settings.output.allow_collisions = true;
    unwarp(g.as_bytes(), job, &settings).map(|o| String::from_utf8(o.gcode).unwrap())
}

/// The error of a run that must be refused (without printing the whole file otherwise).
fn refused(r: Result<String, warpslice::pipeline::Error>) -> warpslice::pipeline::Error {
    match r {
        Ok(out) => panic!("written, {} lines, not refused", out.lines().count()),
        Err(e) => e,
    }
}

/// Where the synthetic slicer's point `g` lands with the part placed at `place`.
fn landed(job: &Job, place: [f64; 2], g: DVec3) -> DVec3 {
    let c = job.warped_bbox.center();
    DVec3::new(
        g.x + place[0] - (100.0 - c.x),
        g.y + place[1] - (100.0 - c.y),
        g.z,
    )
}

/// The full-axis lines of a machine file and the tests' kinematics of its preset.
fn walk(name: &str, text: &str) -> (Vec<AxisLine>, Fk) {
    let spec = spec_for(name);
    let names = spec.build().unwrap().axis_names();
    (parse(text, &names).unwrap(), Fk::from_spec(&spec).unwrap())
}

/// `(letter, min, max)` of each linear axis with a travel in presets/NAME.json.
fn travel_of(name: &str) -> Vec<(String, f64, f64)> {
    let path = format!("{}/presets/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["travel"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, r)| (k.clone(), r[0].as_f64().unwrap(), r[1].as_f64().unwrap()))
        .collect()
}

/// The X Y of the first `G0 X… Y…` line of the synthetic slicer's file (its travel to the
/// skirt, before the first object point).
fn first_travel(g: &str) -> (String, f64, f64) {
    let l = g.lines().find(|l| l.starts_with("G0 X")).unwrap();
    let num = |p: &str| -> f64 {
        let w = l.split(' ').find(|w| w.starts_with(p)).unwrap();
        w[1..].parse().unwrap()
    };
    (l.to_string(), num("X"), num("Y"))
}

#[test]
fn open5x_prusa_uv_start_travel_is_placed_converted_and_within_reach() {
    let name = "open5x-prusa-uv";
    let (job, g) = sliced(name);
    let (travel_line, gx, gy) = first_travel(&g);
    let out = run(name, &job, &g, Some([0.0, 0.0])).unwrap();
    assert!(
        !out.lines().any(|l| l == travel_line),
        "the slicer's travel '{travel_line}' was written in the slicer's frame"
    );
    let (lines, fk) = walk(name, &out);
    // the first full-axis line is that travel, placed, with the tool vertical
    let (p, n) = fk.forward(&lines[0].axes).unwrap();
    let want = landed(&job, [0.0, 0.0], DVec3::new(gx, gy, 0.2));
    assert!(
        (p - want).length() < LANDS_MM && (n - DVec3::Z).length() < VERTICAL,
        "line {}: tip {p:?} axis {n:?}, want {want:?} +Z",
        lines[0].number
    );
    // every written move within the preset's travel (Y up to 50 mm: the slicer's Y 92 was not)
    let names = spec_for(name).build().unwrap().axis_names();
    let travel = travel_of(name);
    for l in &lines {
        for (letter, lo, hi) in &travel {
            let k = names.iter().position(|n| n == letter).unwrap();
            assert!(
                l.axes[k] >= lo - 1e-9 && l.axes[k] <= hi + 1e-9,
                "line {}: {letter} = {} outside [{lo}, {hi}]",
                l.number,
                l.axes[k]
            );
        }
    }
}

#[test]
fn core_r_theta_and_lathe_start_gcode_moves_are_converted_to_their_axes() {
    for (name, place) in [("core-r-theta", [60.0, 0.0]), ("lathe-a", [0.0, 0.0])] {
        let (job, g) = sliced(name);
        // an absolute start move after homing, X Y Z given (the slicer's frame)
        let start = "G1 X95 Y95 Z8 F3000";
        let (g, _) = synthetic::insert_after(&g, "G21\n", 1, &format!("{start}\n"));
        let out = run(name, &job, &g, Some(place)).unwrap();
        assert!(
            !out.lines().any(|l| l == start),
            "{name}: '{start}' written verbatim"
        );
        let (lines, fk) = walk(name, &out);
        let (p, n) = fk.forward(&lines[0].axes).unwrap();
        let want = landed(&job, place, DVec3::new(95.0, 95.0, 8.0));
        assert!(
            (p - want).length() < LANDS_MM,
            "{name} line {}: tip {p:?}, want {want:?}",
            lines[0].number
        );
        if name == "core-r-theta" {
            assert!(
                (n - DVec3::Z).length() < VERTICAL,
                "{name}: tool axis {n:?}"
            );
        }
    }
}

#[test]
fn the_end_gcode_after_the_region_starts_from_the_rest_pose() {
    for name in [
        "open5x-ab",
        "pax-5axis",
        "fullcontrol-prusa-b",
        "core-r-theta",
        "ratrig-vcore3-3z",
        "lathe-a",
    ] {
        let (job, g) = sliced(name);
        let place = match name {
            "core-r-theta" => Some([60.0, 0.0]),
            "open5x-ab" | "lathe-a" => Some([0.0, 0.0]),
            _ => None,
        };
        let out = run(name, &job, &g, place).unwrap();
        let (lines, fk) = walk(name, &out);
        // the end G-code's `G1 Z<top + 5>` (the last full-axis line) and the line before it
        // (where the region left the head) have the tool vertical (the lathe's nozzle is
        // vertical in its own frame only: radial to the mandrel in the part's)
        let last = &lines[lines.len() - 1];
        let before = &lines[lines.len() - 2];
        for l in [before, last].into_iter().filter(|_| name != "lathe-a") {
            let (_, n) = fk.forward(&l.axes).unwrap();
            assert!(
                (n - DVec3::Z).length() < VERTICAL,
                "{name} line {}: tool axis {n:?} after the region",
                l.number
            );
        }
        // the end G-code's `G1 Z<top + 5>` gives only Z: it lifts straight up from where the
        // region left the head, at least to the slicer's height
        let z_end: f64 = g.lines().rev().find(|l| l.starts_with("G1 Z")).unwrap()[4..]
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        let (p, _) = fk.forward(&last.axes).unwrap();
        let (q, _) = fk.forward(&before.axes).unwrap();
        assert!(
            (p.truncate() - q.truncate()).length() < LANDS_MM && p.z > z_end - LANDS_MM,
            "{name} line {}: end move tip {p:?}, want above {q:?} at Z >= {z_end}",
            last.number
        );
    }
}

#[test]
fn a_relative_move_outside_the_region_on_a_non_cartesian_machine_is_refused_by_name() {
    let name = "core-r-theta";
    let (job, g) = sliced(name);
    let (g, at) = synthetic::insert_after(&g, "G21\n", 1, "G91\nG1 Z5 F600\nG90\n");
    let e = refused(run(name, &job, &g, Some([60.0, 0.0])));
    assert_eq!(e.code(), "unwarp.outside-relative", "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains(&format!("line {}", at + 1))
            && msg.contains("G1 Z5 F600")
            && msg.contains("absolute moves"),
        "{msg}"
    );
    // to 3-axis G-code the same file is written, its start G-code verbatim
    let three = unwarp(
        g.as_bytes(),
        &job,
        &UnwarpSettings::three_axis(UnwarpOptions::default()),
    )
    .unwrap();
    assert!(String::from_utf8(three.gcode)
        .unwrap()
        .contains("G91\nG1 Z5 F600\nG90\n"));
}

#[test]
fn arcs_and_axis_resets_outside_the_region_are_refused_by_name() {
    let name = "open5x-ab";
    let (job, g) = sliced(name);
    for (what, code) in [
        (
            "G1 X90 Y90 Z5 F600\nG2 X100 Y90 I5 J0 F600\n",
            "unwarp.outside-arc",
        ),
        ("G92 X0 Y0\n", "unwarp.outside-axis-reset"),
    ] {
        let (g, _) = synthetic::insert_after(&g, "G21\n", 1, what);
        let e = refused(run(name, &job, &g, Some([0.0, 0.0])));
        assert_eq!(e.code(), code, "{e}");
    }
}

#[test]
fn an_end_gcode_park_move_out_of_reach_is_refused_naming_its_line() {
    let name = "open5x-prusa-uv";
    let (job, g) = sliced(name);
    // 300 mm from the part in the slicer's frame: beyond X and Y whatever the table's V
    let g = format!("{g}G1 X0 Y400 F3000\n");
    let line = g.lines().count();
    let e = refused(run(name, &job, &g, Some([0.0, 0.0])));
    assert_eq!(e.code(), "machine.travel", "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains(&format!("G-code line {line}: 'G1 X0 Y400 F3000'"))
            && msg.contains("outside its travel")
            && msg.contains("start/end G-code"),
        "{msg}"
    );
}

#[test]
fn a_move_after_homing_the_lathe_cannot_make_alone_waits_for_x_y_z() {
    let name = "lathe-a";
    let (job, g) = sliced(name);
    // the synthetic slicer's `G1 Z0.200 F600` after `G28`: the lathe's Z is the radius about
    // the mandrel, it needs the unknown Y too
    let out = run(name, &job, &g, Some([0.0, 0.0])).unwrap();
    assert!(
        out.contains("; warpslice: not written (G1 Z0.200 F600)"),
        "{}",
        &out[..2000]
    );
    assert!(!out.lines().any(|l| l == "G1 Z0.200 F600"));
    // the same move extruding is refused
    let g = g.replacen("G1 Z0.200 F600", "G1 Z0.200 E1 F600", 1);
    let e = refused(run(name, &job, &g, Some([0.0, 0.0])));
    assert_eq!(e.code(), "unwarp.outside-partial-extrusion", "{e}");
}

#[test]
fn the_cartesian_preset_keeps_start_gcode_verbatim_unless_placed() {
    let name = "cartesian";
    let (job, g) = sliced(name);
    let (travel_line, gx, gy) = first_travel(&g);
    let out = run(name, &job, &g, None).unwrap();
    assert!(out.lines().any(|l| l == travel_line));
    let out = run(name, &job, &g, Some([50.0, 60.0])).unwrap();
    assert!(!out.lines().any(|l| l == travel_line));
    let want = landed(&job, [50.0, 60.0], DVec3::new(gx, gy, 0.2));
    // the first line with X, Y and Z words is the placed travel
    let first = out
        .lines()
        .find(|l| l.starts_with("G1 X") && l.contains(" Y") && l.contains(" Z"))
        .unwrap();
    let v: Vec<f64> = first
        .split(' ')
        .skip(1)
        .take(3)
        .map(|w| w[1..].parse().unwrap())
        .collect();
    assert!(
        (DVec3::new(v[0], v[1], v[2]) - want).length() < LANDS_MM,
        "{first}: want {want:?}"
    );
}

/// Cura's end G-code for Creality printers lifts and wipes in relative moves (`G91`, then
/// `G90` and a park move). From a known position a relative move goes to where the head is
/// plus the slicer's delta: after the last absolute line, the tips of the converted lines
/// climb 0.2 mm, wipe (+5, +5) and climb 10 mm more, the tool vertical throughout.
#[test]
fn a_relative_end_gcode_lift_and_wipe_moves_by_its_deltas_from_where_the_head_is() {
    let block = "G91\nG1 E-2 F2700\nG1 E-2 Z0.2 F2400\nG1 X5 Y5 F3000\nG1 Z10\nG90\n";
    for name in ["fullcontrol-prusa-b", "core-r-theta", "ratrig-vcore3-3z"] {
        let (job, g) = sliced(name);
        let (g, _) = synthetic::insert_after(&g, "M104 S0\n", 1, &format!(";MARK\n{block}"));
        assert!(g.contains(block), "{name}: the block was not inserted");
        let place = (name == "core-r-theta").then_some([60.0, 0.0]);
        let out = run(name, &job, &g, place).unwrap();
        let mark = out.lines().position(|l| l == ";MARK").unwrap() + 1;
        let (lines, fk) = walk(name, &out);
        let tip = |l: &AxisLine| fk.forward(&l.axes).unwrap();
        let p0 = tip(lines.iter().rev().find(|l| l.number < mark).unwrap()).0;
        let after: Vec<_> = lines.iter().filter(|l| l.number > mark).collect();
        assert!(
            !after.is_empty(),
            "{name}: nothing converted after the mark"
        );
        for l in &after {
            let (_, n) = tip(l);
            assert!(
                (n - DVec3::Z).length() < VERTICAL,
                "{name} line {}: {n:?}",
                l.number
            );
        }
        let end = tip(after[after.len() - 1]).0;
        let want = p0 + DVec3::new(5.0, 5.0, 10.2);
        assert!(
            (end - want).length() < LANDS_MM,
            "{name}: after the relative lift and wipe the tip is at {end:?}, want {want:?}"
        );
        // the 0.2 mm climb and the wipe land on their own lines
        for step in [DVec3::new(0.0, 0.0, 0.2), DVec3::new(5.0, 5.0, 0.2)] {
            let w = p0 + step;
            assert!(
                after.iter().any(|l| (tip(l).0 - w).length() < LANDS_MM),
                "{name}: no line lands at {w:?}"
            );
        }
    }
}
