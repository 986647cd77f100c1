//! Machine-safe output (issue 10 §1–2): every written move of a machine file inside the
//! travel of the machine JSON (`travel`, the rotary ranges), refused with the exact output and
//! input lines otherwise; the reach margins and the axis-speed slow-down of a clean file.
//!
//! The oracles are independent of the emitter's check: the refused line is found by reading
//! the G-code that the same unwarp writes without `travel` (its text, the first line whose
//! written value leaves the travel given here), the input line by reading the slicer's G-code,
//! margins and slowed moves by reading the written axes and F of the output with the feed rule
//! of docs/machines.md ("Feed"), and poses by the tests' own kinematics (tests/common/fk.rs).
#![cfg(not(target_arch = "wasm32"))]

mod common;
#[path = "common/reach_cases.rs"]
mod reach_cases;
#[path = "common/synthetic.rs"]
mod synthetic;

use glam::DVec3;
use warpslice::emit::Emitter;
use warpslice::job::Job;
use warpslice::machine::{preset, FeedMode, MachineEmitter, MachineError, MachineSpec};
use warpslice::pipeline::{unwarp, warp_model, AnchorMode, WarpOptions};
use warpslice::toolpath::{Feature, ToolPoint};
use warpslice::warp::{WarpParams, WarpSpec};

use common::machine::fk;
use fk::Limits;
use reach_cases::{box_job, settings, three_z_pose, three_z_run, unlimited, wide_part_case};

/// Rounding of a written axis value (3 decimals), mm or degrees.
const WRITTEN: f64 = 0.0005;

// ---- reading a written file ----

/// One G1 of the output: its 1-based line number, the axis words it writes, F (if written).
#[derive(Clone, Debug)]
struct G1 {
    line: usize,
    words: Vec<(char, f64)>,
    f: Option<f64>,
    e: Option<f64>,
}

/// Every `G0`/`G1`/`G92` of `text` with its words (comments stripped), flagged `true` for
/// `G92` (it sets positions, it does not move).
fn read(text: &str) -> Vec<(bool, G1)> {
    let mut v = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let code = raw.split(';').next().unwrap_or("").trim();
        let mut it = code.split_whitespace();
        let cmd = it.next().unwrap_or("");
        if cmd != "G0" && cmd != "G1" && cmd != "G92" {
            continue;
        }
        let mut g = G1 {
            line: i + 1,
            words: Vec::new(),
            f: None,
            e: None,
        };
        for w in it {
            let (c, num) = w.split_at(1);
            let c = c.chars().next().unwrap();
            let x: f64 = num
                .parse()
                .unwrap_or_else(|_| panic!("line {}: {w}", i + 1));
            match c {
                'F' => g.f = Some(x),
                'E' => g.e = Some(x),
                _ => g.words.push((c, x)),
            }
        }
        v.push((cmd == "G92", g));
    }
    v
}

/// The first move writing all `n_axes` machine axes (the machine's own lines; the start
/// G-code and the slicer's travel into the printed region pass through verbatim with 3-axis
/// words) whose value of a limited axis is outside `travel`
/// (letter, min, max) by more than the writing's rounding: (line, letter, raw value).
fn first_outside(
    text: &str,
    n_axes: usize,
    travel: &[(char, f64, f64)],
) -> Option<(usize, char, f64)> {
    read(text)
        .into_iter()
        .filter(|(g92, g)| !g92 && g.words.len() == n_axes)
        .find_map(|(_, g)| {
            g.words.iter().find_map(|&(c, v)| {
                travel
                    .iter()
                    .find(|t| t.0 == c && (v < t.1 - WRITTEN || v > t.2 + WRITTEN))
                    .map(|_| (g.line, c, v))
            })
        })
}

/// The travel of a machine JSON's linear axes, as (letter, min, max).
fn travel_of(spec: &MachineSpec) -> Vec<(char, f64, f64)> {
    let v = serde_json::to_value(spec).unwrap();
    v["travel"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, t)| {
            (
                k.chars().next().unwrap(),
                t[0].as_f64().unwrap(),
                t[1].as_f64().unwrap(),
            )
        })
        .collect()
}

// ---- jobs ----

/// `warpslice check` (issue 10 §3) reads the file written without `travel` for the real
/// machine and finds the same first line beyond the travel, on the same axis: the checker and
/// the emitter's refusal agree on a file neither wrote for the other.
fn check_finds_first_reach(text: &str, spec: &MachineSpec, line: usize, axis: &str) {
    use warpslice::check::{check, CheckOptions, FindingKind};
    let r = check(text.as_bytes(), spec, &CheckOptions::default()).unwrap();
    let first = r
        .findings
        .iter()
        .filter(|f| f.kind == FindingKind::Reach)
        .min_by_key(|f| f.line)
        .unwrap_or_else(|| panic!("check found no reach finding: {:?}", r.findings));
    assert_eq!(
        (first.line as usize, first.axis.as_deref()),
        (line, Some(axis)),
        "check's first reach finding vs the emitter's refusal"
    );
}

// ---- refusals ----

/// A box 240 mm wide (the B head's bed is 230 mm, seed 000 §4.2.3) centred by the slicer on
/// x = 100: its skirt and left wall are at x < 0. The refusal names the first output line
/// beyond the travel — the one the same unwarp without `travel` writes there — and the input
/// line being read when that move was written: the slicer's travel to the skirt, before the
/// region (start-G-code moves are converted and reach-checked like the part's, docs/machines.md
/// "Start and end G-code").
#[test]
fn a_part_wider_than_the_b_heads_bed_is_refused_at_the_exact_output_line() {
    let spec = preset("fullcontrol-prusa-b").unwrap();
    // the box, its slicer's G-code, and the unwarp without travel: the first written value
    // beyond the bed
    let (job, input, out) = wide_part_case();
    let err = match unwarp(input.as_bytes(), &job, &settings(spec.clone())) {
        Ok(_) => panic!("a 240 mm part was written for a 230 mm bed"),
        Err(e) => e,
    };
    let text = err.to_string();
    assert!(
        text.contains("outside its travel") && text.contains("--place"),
        "{text}"
    );
    assert_eq!(warpslice::error::Coded::code(&err), "machine.travel");
    use warpslice::unwarp::UnwarpError;
    let error = match &err {
        warpslice::pipeline::Error::Unwarp(UnwarpError::Emit { error, .. })
        | warpslice::pipeline::Error::Unwarp(UnwarpError::Outside { error, .. }) => error,
        _ => panic!("not an emitter error: {err:?}"),
    };
    let Some(MachineError::Travel {
        axis,
        value,
        min,
        max,
        output_line,
        input_line,
        ..
    }) = error.downcast_ref::<MachineError>().cloned()
    else {
        panic!("not a travel error: {error}");
    };
    let (line, letter, raw) = first_outside(&out, 4, &travel_of(&spec)).unwrap();
    assert_eq!(
        output_line as usize, line,
        "refused line vs the first line beyond the bed"
    );
    assert_eq!(axis, letter.to_string());
    assert!((value - raw).abs() <= WRITTEN, "{value} vs written {raw}");
    assert_eq!((min, max), (0.0, 230.0));
    assert!(value < 0.0);
    check_finds_first_reach(&out, &spec, line, &axis);
    // the input line: the slicer's first move (travel or extrusion) that ends left of the bed
    // (every written G1 is a move to its end point)
    let mut pos = (0.0f64, 0.0f64);
    let mut want = None;
    for (i, l) in input.lines().enumerate() {
        let code = l.split(';').next().unwrap();
        if !(code.starts_with("G1 ") || code.starts_with("G0 ")) {
            continue;
        }
        let word = |c: char| {
            code.split_whitespace()
                .find_map(|w| w.strip_prefix(c).map(|v| v.parse::<f64>().unwrap()))
        };
        let to = (word('X').unwrap_or(pos.0), word('Y').unwrap_or(pos.1));
        if to != pos && to.0 < 0.0 {
            want = Some(i as u64 + 1);
            break;
        }
        pos = to;
    }
    assert_eq!(Some(input_line), want, "input line");
}

/// The triple-Z bed tilted 30° with the tip near the bed's right edge: the bed turns under the
/// nozzle so far that the nozzle would leave the 300 × 293 mm area (seed 001 Fig. 7: the
/// tilted volume shrinks by the axes' limits), although the tilt and the rails are fine.
#[test]
fn a_three_z_pose_outside_the_tilted_volume_is_refused() {
    let spec = preset("ratrig-vcore3-3z").unwrap();
    // a pose the tests' kinematics put outside the travel only (tilt and rails within limits)
    let (p, n) = three_z_pose(&spec);
    let run = |spec: &MachineSpec| three_z_run(spec, p, n);
    let (r, written) = run(&spec);
    let e = r.expect_err("the pose was written");
    let Some(MachineError::Travel {
        axis,
        value,
        output_line,
        input_line,
        ..
    }) = e.downcast_ref::<MachineError>().cloned()
    else {
        panic!("not a travel error: {e}");
    };
    assert_eq!(
        input_line, 42,
        "the reorientation came from the third point"
    );
    assert_eq!(output_line as usize, written.lines().count() + 1);
    let (r, free_out) = run(&unlimited(&spec));
    r.unwrap();
    // (the Z axes are written as the motor heights: no offset)
    let (line, letter, raw) = first_outside(&free_out, 5, &travel_of(&spec)).unwrap();
    assert_eq!(
        (output_line as usize, axis.as_str()),
        (line, letter.to_string().as_str())
    );
    assert!((value - raw).abs() <= WRITTEN);
    assert!(axis == "X" || axis == "Y", "{axis}");
    check_finds_first_reach(&free_out, &spec, line, &axis);
}

/// Seed 002's RTN turns within [−170°, 170°] (`M208 A-170 S1`, `M208 A170 S0`): a ring of
/// points on an outward 45° cone makes it go round once; no written A leaves the range, the
/// lifted rotate-around turns from one end to the other, and a point in the shadow (the
/// nozzle body towards +Y, A ≡ 180°) is written at the nearer end, 7.07° off the requested
/// axis (the angle between two 45° tilts 10° apart in azimuth).
#[test]
fn rtn_rotate_around_respects_its_170_degree_range() {
    let spec = preset("rtn-slicer4rtn").unwrap();
    let mut em = MachineEmitter::new(&spec, None, FeedMode::Xyz).unwrap();
    let c = DVec3::new(100.0, 100.0, 0.0);
    let mut out = Vec::new();
    em.begin_region(&mut out, c + DVec3::new(10.0, 0.0, 5.0), DVec3::Z)
        .unwrap();
    let t = 45f64.to_radians();
    for k in 0..=72 {
        // azimuths 0°, 5°, …, 360° (90° is the shadow's middle)
        let az = (k as f64 * 5.0).to_radians();
        let p = c + DVec3::new(10.0 * az.cos(), 10.0 * az.sin(), 5.0);
        let n = DVec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos());
        let tp = ToolPoint {
            p,
            n,
            e: 0.05,
            f: 1200.0,
            layer: 3,
            feature: Feature::OuterWall,
            travel: false,
            line: 100 + k,
        };
        em.point(&mut out, &tp, true).unwrap();
    }
    let text = String::from_utf8(out).unwrap();
    let a_of = |g: &G1| g.words.iter().find(|w| w.0 == 'A').map(|w| w.1);
    let lines: Vec<(G1, bool)> = read(&text)
        .into_iter()
        .filter(|(g92, g)| !g92 && a_of(g).is_some())
        .map(|(_, g)| {
            let around = text
                .lines()
                .nth(g.line - 1)
                .unwrap()
                .contains("; rotate-around");
            (g, around)
        })
        .collect();
    assert!(lines
        .iter()
        .all(|(g, _)| a_of(g).unwrap().abs() <= 170.0 + WRITTEN));
    let arounds: Vec<&(G1, bool)> = lines.iter().filter(|l| l.1).collect();
    assert_eq!(arounds.len(), 3, "one rotate-around (lift, turn, descend)");
    let turn = (a_of(&arounds[0].0).unwrap(), a_of(&arounds[2].0).unwrap());
    assert!(
        (turn.0.abs() - 170.0).abs() < WRITTEN && (turn.0 + turn.1).abs() < WRITTEN,
        "the turn goes from one end to the other: {turn:?}"
    );
    // printed lines never swing the long way
    for w in lines.windows(2) {
        if !w[1].1 {
            let (a, b) = (a_of(&w[0].0).unwrap(), a_of(&w[1].0).unwrap());
            assert!((b - a).abs() <= 180.0, "line {}: {a} → {b}", w[1].0.line);
        }
    }
    let rep = em.report();
    let want = (t.sin().powi(2) * 10f64.to_radians().cos() + t.cos().powi(2))
        .acos()
        .to_degrees();
    assert!(
        (rep.worst_dropped_deg - want).abs() < 1e-6,
        "{} vs {want}",
        rep.worst_dropped_deg
    );
    assert_eq!(rep.rotate_arounds, 1);
}

// ---- a clean file: margins and speeds ----

/// The 20 mm cube on the B head: written, and the report's margins are those of the written
/// axes (read back from the file) to the travel of the machine JSON.
#[test]
fn a_clean_file_reports_its_reach_margins() {
    let spec = preset("fullcontrol-prusa-b").unwrap();
    let job = box_job(1.0, 0.5, [1.0, 0.0]);
    let input = synthetic::gcode(&job, true, 2.0);
    let out = unwarp(input.as_bytes(), &job, &settings(spec.clone())).unwrap();
    let rep = out.report.machine.clone().unwrap();
    let text = String::from_utf8(out.gcode).unwrap();
    assert!(first_outside(&text, 4, &travel_of(&spec)).is_none());
    let travel = travel_of(&spec);
    for (letter, min, max) in travel {
        let values: Vec<f64> = read(&text)
            .into_iter()
            .filter(|(g92, g)| !g92 && g.words.len() == 4)
            .filter_map(|(_, g)| g.words.iter().find(|w| w.0 == letter).map(|w| w.1))
            .collect();
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let a = rep
            .axes
            .iter()
            .find(|a| a.axis == letter.to_string())
            .unwrap();
        assert_eq!((a.min, a.max), (Some(min), Some(max)));
        let (m0, m1) = (a.margin_min.unwrap(), a.margin_max.unwrap());
        assert!(
            (m0 - (lo - min)).abs() <= WRITTEN,
            "{letter}: {m0} vs {}",
            lo - min
        );
        assert!(
            (m1 - (max - hi)).abs() <= WRITTEN,
            "{letter}: {m1} vs {}",
            max - hi
        );
    }
    // the margins are in the file's last comment line
    let last = text.lines().rev().find(|l| l.starts_with(';')).unwrap();
    let x = &rep.axes[0];
    assert!(
        last.contains(&format!(
            "X {:.3}/{:.3} mm",
            x.margin_min.unwrap(),
            x.margin_max.unwrap()
        )),
        "{last}"
    );
}

/// What the oracle below counts in a written file.
#[derive(Debug, Default)]
struct Speeds {
    slowed: u64,
    /// Slowed moves within 0.1 % of a limit (the written values are rounded).
    near: u64,
    /// Slowed by less than 1.5×, and by more.
    mild: u64,
    strong: u64,
    minutes: f64,
}

/// Slowed moves and time of `text` for a machine with axes `letters` (`rotary` per axis) and
/// largest feeds `feeds`, written in feed mode `mode` — docs/machines.md "Feed": `xyz` F is
/// the speed along the linear axes (a pure rotation: along the rotary ones), `all-axes` along
/// all axes with degrees counted as mm, `inverse-time` F = 1/minutes — and the firmware's
/// slow-down: a move takes `max(1, maxᵢ vᵢ/max_feedᵢ)` times its nominal time. Retractions
/// take |E|/F (1/F in inverse time). After homing the head is nowhere known: the start
/// G-code's moves that give only some axes, and the first move that gives all of them, are
/// not timed (a `G92` of the axes sets them).
fn speeds_of(
    text: &str,
    letters: &[char],
    rotary: &[bool],
    feeds: &[(char, f64)],
    mode: FeedMode,
) -> Speeds {
    let k = letters.len();
    let mut s = Speeds::default();
    let mut head = [0.0; 3];
    let mut pos: Option<Vec<f64>> = None;
    let mut f = 0.0;
    for (g92, g) in read(text) {
        let has = |c: char| g.words.iter().find(|w| w.0 == c).map(|w| w.1);
        let start = |head: &[f64; 3]| -> Vec<f64> {
            letters
                .iter()
                .map(|c| match c {
                    'X' => head[0],
                    'Y' => head[1],
                    'Z' => head[2],
                    _ => 0.0,
                })
                .collect()
        };
        if g92 {
            let p = pos.get_or_insert_with(|| start(&head));
            for (i, c) in letters.iter().enumerate() {
                if let Some(v) = has(*c) {
                    p[i] = v;
                }
            }
            continue;
        }
        if let Some(v) = g.f {
            f = v;
        }
        if g.words.len() != k {
            if pos.is_none() {
                for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                    if let Some(v) = has(c) {
                        head[i] = v;
                    }
                }
            } else if let (Some(e), true) = (g.e, g.words.is_empty()) {
                s.minutes += if mode == FeedMode::InverseTime {
                    1.0 / f
                } else {
                    e.abs() / f
                };
            }
            continue;
        }
        let to: Vec<f64> = letters.iter().map(|c| has(*c).unwrap()).collect();
        // the first move with every axis after homing starts where homing left the head,
        // which neither the file nor the firmware's estimate knows: not timed
        let Some(from) = pos.clone() else {
            pos = Some(to);
            continue;
        };
        let d: Vec<f64> = (0..k).map(|i| to[i] - from[i]).collect();
        let len = |pick: &dyn Fn(usize) -> bool| {
            (0..k)
                .filter(|&i| pick(i))
                .map(|i| d[i] * d[i])
                .sum::<f64>()
                .sqrt()
        };
        let (lin, all) = (len(&|i| !rotary[i]), len(&|_| true));
        if all > 0.0 {
            let t = match mode {
                FeedMode::InverseTime => 1.0 / f,
                FeedMode::Xyz if lin > 0.0 => lin / f,
                _ => all / f,
            };
            let ratio = (0..k)
                .map(|i| {
                    let m = feeds.iter().find(|x| x.0 == letters[i]).unwrap().1;
                    d[i].abs() / t / m
                })
                .fold(0.0, f64::max);
            if ratio > 1.0 {
                s.slowed += 1;
                if ratio < 1.5 {
                    s.mild += 1;
                } else {
                    s.strong += 1;
                }
            }
            if (ratio - 1.0).abs() < 1e-3 {
                s.near += 1;
            }
            s.minutes += t * ratio.max(1.0);
        }
        pos = Some(to);
    }
    s
}

fn feeds_of(spec: &MachineSpec) -> Vec<(char, f64)> {
    serde_json::to_value(spec).unwrap()["max_feed"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.chars().next().unwrap(), v.as_f64().unwrap()))
        .collect()
}

/// The report against [`speeds_of`]: the same slowed moves (up to those within rounding of a
/// limit), the same time, each slowed move counted for one axis.
fn check_speeds(what: &str, rep: &warpslice::emit::MachineReport, want: &Speeds) {
    assert!(
        rep.speed_limited_moves.abs_diff(want.slowed) <= want.near,
        "{what}: report {} vs {} counted here ({} within 0.1 % of a limit)",
        rep.speed_limited_moves,
        want.slowed,
        want.near
    );
    // the written values are rounded to 0.001 mm / 0.001° and F to 0.1 mm/min (some moves'
    // times differ by a part in 10⁴ or so; their sum far less)
    assert!(
        (rep.print_time_min - want.minutes).abs() < 1e-4 * want.minutes,
        "{what}: {} vs {} min",
        rep.print_time_min,
        want.minutes
    );
    assert!(rep.slowdown_min > 0.0 && rep.slowdown_min < rep.print_time_min);
    let by: u64 = rep.axes.iter().map(|a| a.speed_limited_moves).sum();
    assert_eq!(
        by, rep.speed_limited_moves,
        "{what}: one axis per slowed move"
    );
}

/// The triple-Z bed (Z axes 1900 mm/min, seed 001 §4.8) on a 20° belt job: the moves the
/// report counts as slowed, and its time estimate, are those computed here from the written
/// axes and F ([`speeds_of`]) and each axis' max_feed. X and Y are given 1500 mm/min here,
/// below the synthetic slicer's 1800 mm/min walls, so slowed moves range from barely (a wall
/// at an angle) to 3× (the Z axes on a 6000 mm/min lift).
#[test]
fn slowed_moves_and_print_time_match_an_independent_count() {
    let mut spec = preset("ratrig-vcore3-3z").unwrap();
    let feeds = spec.max_feed.as_mut().unwrap();
    feeds.insert("X".into(), 1500.0);
    feeds.insert("Y".into(), 1500.0);
    let job = box_job(1.0, 20.0, [0.0, 1.0]);
    let input = synthetic::gcode(&job, true, 2.0);
    // the axis speeds; the collision check (on by default, collision_check.rs) finds nothing
    // on this box
    // `--feed xyz` (F = the slicer's, all five axes linear): the firmware slows the moves; the
    // default `tip` lowers F itself so no axis exceeds its limit (machine_emit.rs
    // tip_feed_moves_the_tip_at_the_slicers_speed_on_every_firmware)
    let mut s = settings(spec.clone());
    s.output.feed = FeedMode::Xyz;
    let out = unwarp(input.as_bytes(), &job, &s).unwrap();
    let rep = out.report.machine.clone().unwrap();
    let text = String::from_utf8(out.gcode).unwrap();
    let want = speeds_of(
        &text,
        &['X', 'Y', 'Z', 'U', 'V'],
        &[false; 5],
        &feeds_of(&spec),
        FeedMode::Xyz,
    );
    assert!(want.mild > 10 && want.strong > 10, "{want:?}");
    check_speeds("3Z", &rep, &want);
    assert!(rep
        .axes
        .iter()
        .all(|a| a.speed_limited_moves > 0 || a.axis == "U" || a.axis == "V"));
    // the default `tip` feed lowers F itself (issue 11 item 6): the firmware, read the same
    // way, slows no move beyond the rounding of the written values, and the report counts the
    // moves the feed rule slowed — at least those the firmware slowed by ≥ 1.5× above
    s.output.feed = FeedMode::Tip;
    let out = unwarp(input.as_bytes(), &job, &s).unwrap();
    let tip = out.report.machine.clone().unwrap();
    let fw = speeds_of(
        &String::from_utf8(out.gcode).unwrap(),
        &['X', 'Y', 'Z', 'U', 'V'],
        &[false; 5],
        &feeds_of(&spec),
        FeedMode::Xyz,
    );
    assert!(fw.strong == 0 && fw.slowed <= fw.near, "tip: {fw:?}");
    assert!(
        tip.speed_limited_moves >= want.strong,
        "tip: {} moves slowed by the feed rule, the firmware slowed {} by ≥ 1.5× at the slicer's F",
        tip.speed_limited_moves,
        want.strong
    );
}

/// The B head on a curved job (B turns along every wall), written with `--feed xyz` (the
/// firmware's length leaves B out) and `--feed inverse-time`, its B limited to 600 °/min so
/// the turning slows moves: the report against [`speeds_of`] again.
#[test]
fn slowed_moves_with_a_rotary_axis_match_an_independent_count() {
    let mut spec = preset("fullcontrol-prusa-b").unwrap();
    spec.max_feed.as_mut().unwrap().insert("B".into(), 600.0);
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "t");
    let job = warp_model(
        &stl,
        &WarpOptions {
            anchor: AnchorMode::Off,
            ..WarpOptions::new(WarpParams {
                spec: WarpSpec::Curved {
                    strength: 0.3,
                    direction: warpslice::warp::Direction::Outward,
                    offset: 0.0,
                    width: 0.0,
                },
                base: None,
            })
        },
    )
    .unwrap()
    .job;
    let input = synthetic::gcode(&job, true, 2.0);
    for mode in [FeedMode::Xyz, FeedMode::InverseTime] {
        let mut s = settings(spec.clone());
        s.output.feed = mode;
        let out = unwarp(input.as_bytes(), &job, &s).unwrap();
        let rep = out.report.machine.clone().unwrap();
        let text = String::from_utf8(out.gcode).unwrap();
        let want = speeds_of(
            &text,
            &['X', 'Y', 'Z', 'B'],
            &[false, false, false, true],
            &feeds_of(&spec),
            mode,
        );
        assert!(want.slowed > 10, "{mode:?}: {want:?}");
        check_speeds(&format!("{mode:?}"), &rep, &want);
        let b = rep.axes.iter().find(|a| a.axis == "B").unwrap();
        assert!(b.speed_limited_moves > 0, "{mode:?}: B slows moves");
    }
}

// ---- the machine file ----

/// Machine files without `travel` and `max_feed` (written before they existed) load, with
/// every linear axis unlimited; a travel naming no axis, or a rotary one, is refused by name.
#[test]
fn machine_files_without_travel_load_and_bad_travel_is_refused() {
    let old = r#"{"name":"old","kind":"b-head","pivot_to_tip_mm":46,"clip":true,"clip_b0_deg":18,"clip_z_mm":50,"b_limit_deg":90}"#;
    let spec = MachineSpec::from_json(old, "old").unwrap();
    let em = MachineEmitter::new(&spec, None, FeedMode::Xyz).unwrap();
    assert!(em.report().axes.iter().all(|a| a.rotary || a.min.is_none()));
    assert!(em.report().axes.iter().all(|a| a.max_feed.is_none()));
    // a one-revolution RTN file without rotation_range_deg takes seed 002's ±170°
    let rtn = MachineSpec::from_json(r#"{"kind":"rtn","revolution":"single"}"#, "old rtn")
        .unwrap()
        .build()
        .unwrap();
    let a = &rtn.limits()[3];
    assert_eq!((a.min, a.max), (-170.0, 170.0));
    for (bad, want) in [
        (r#""travel":{"Q":[0,1]}"#, "names axis 'Q'"),
        (r#""travel":{"B":[0,1]}"#, "rotary axis 'B'"),
        (r#""travel":{"X":[5,1]}"#, "min < max"),
        (r#""max_feed":{"Z":-1}"#, "positive number"),
    ] {
        let json = old.replace("\"kind\"", &format!("{bad},\"kind\""));
        let e = MachineSpec::from_json(&json, "bad")
            .and_then(|s| s.build().map(|_| ()))
            .unwrap_err();
        assert_eq!(warpslice::error::Coded::code(&e), "machine.bad-spec");
        assert!(e.to_string().contains(want), "{e}");
    }
}

/// The tests' own linear axes (tests/common/fk.rs, which confirms the real-slicer matrix's
/// travel refusals) agree with every preset's inverse kinematics on poses across its
/// workspace: the oracle is right where it will be asked.
#[test]
fn the_test_kinematics_linear_axes_agree_with_every_preset() {
    for name in warpslice::machine::preset_names() {
        let spec = preset(name).unwrap();
        let limits = Limits::from_spec(&spec).unwrap();
        let m = spec.build().unwrap();
        let ws = m.workspace();
        let mut checked = 0;
        for i in 0..200 {
            let u = |k: u32| ((i * 7919 + k * 104729) % 1000) as f64 / 1000.0;
            let p = ws.min + (ws.max - ws.min) * DVec3::new(u(1), u(2), u(3));
            let tilt = ws.max_tilt_deg.min(60.0).to_radians() * u(4);
            let az = std::f64::consts::TAU * u(5);
            let n = DVec3::new(tilt.sin() * az.cos(), tilt.sin() * az.sin(), tilt.cos());
            let (Ok(axes), Some(lin)) = (m.inverse(p, n, None), limits.fk.linear_axes(p, n)) else {
                continue;
            };
            for (k, v) in lin {
                assert!(
                    (axes[k] - v).abs() < 1e-6,
                    "{name} at {p} {n}: axis {k} = {} vs the tests' {v}",
                    axes[k]
                );
            }
            checked += 1;
        }
        assert!(checked > 100, "{name}: {checked} poses checked");
    }
}

// ---- the CLI ----

/// `warpslice unwarp --machine …` in a scratch directory: (success, stdout, stderr, output).
fn cli_unwarp(tag: &str, job: &Job, extra: &[&str]) -> (bool, String, String, String) {
    let dir = std::env::temp_dir().join(format!("warpslice-reach-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (g, j, o) = (
        dir.join("in.gcode"),
        dir.join("job.json"),
        dir.join("out.gcode"),
    );
    std::fs::write(&g, synthetic::gcode(job, true, 4.0)).unwrap();
    std::fs::write(&j, job.to_json_pretty()).unwrap();
    let mut args = vec![
        "unwarp".to_string(),
        g.display().to_string(),
        "--job".into(),
        j.display().to_string(),
        "-o".into(),
        o.display().to_string(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .args(&args)
        .output()
        .unwrap();
    let written = std::fs::read_to_string(&o).unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        written,
    )
}

/// Through the CLI: a clean file's summary line gives the slowed moves, the estimated time and
/// the margins (as the file's last comment line does); a part beyond the travel fails with the
/// output and input lines and the fix, and leaves no file behind.
#[test]
fn the_cli_reports_margins_and_speeds_and_refuses_beyond_the_travel() {
    let job = box_job(1.0, 0.5, [1.0, 0.0]);
    let (ok, stdout, stderr, written) =
        cli_unwarp("clean", &job, &["--machine", "fullcontrol-prusa-b"]);
    assert!(ok, "{stderr}");
    let last = written.lines().rev().find(|l| l.starts_with(';')).unwrap();
    for part in [
        "moves slowed by axis feed limits",
        "estimated time",
        "reach margins (to min/max) X ",
    ] {
        assert!(
            stdout.contains(part) && last.contains(part),
            "{part}: {stdout}\n{last}"
        );
    }
    let wide = box_job(12.0, 0.5, [1.0, 0.0]);
    let (ok, _, stderr, written) = cli_unwarp("wide", &wide, &["--machine", "fullcontrol-prusa-b"]);
    assert!(!ok);
    for part in [
        "output line ",
        "from input line ",
        "axis X = ",
        "outside its travel [0, 230]",
        "--place",
    ] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    assert!(written.is_empty(), "a refused file is not written");
}
