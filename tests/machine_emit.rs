//! Machines end to end with a real slicer (PrusaSlicer, relative E): for every preset a
//! generated part is warped with a warp that suits the machine, sliced, and unwarped with the
//! machine. The output is parsed with the machine's axis letters (tests/common/machine.rs: the
//! crate's reader only tracks X Y Z E) and checked:
//! - every toolpath point is reached: walking the output in order, the forward kinematics of a
//!   line lands on each toolpath tip within 0.01 mm, and (where the machine realises the axis
//!   without a branch choice) on its realised tool axis within 0.1°; every line in between lies
//!   on the toolpath segment;
//! - interpolation: 100 points sampled on every output move stay within 0.02 mm / 0.1° of the
//!   intended path (linear tip, slerp tool axis, realised by the machine);
//! - each preset writes a sample G-code (kept in a temp dir) that parses; RotBot also with its
//!   nozzle misaligned (e_parallel 0.4 mm, e_perpendicular −0.25 mm).
//!
//! A missing PrusaSlicer fails the test unless `WARPSLICE_ALLOW_SKIP=1`.
#![cfg(not(target_arch = "wasm32"))]

mod common;

use common::machine::{check, deg, parse, AXIS_TOL_DEG, SAMPLES, TIP_TOL};
use common::preset_warp::{conic, warp_for};
use glam::DVec3;
use warpslice::machine::tessellate::slerp;
use warpslice::machine::{preset, MachineSpec};
use warpslice::machine::{FeedMode, Flavour, MachineOptions};
use warpslice::pipeline::{unwarp, UnwarpSettings};
use warpslice::pipeline::{warp_model, WarpOptions};
use warpslice::slicer::{self, EMode, SliceOptions, SlicerKind};
use warpslice::toolpath::ToolPoint;
use warpslice::unwarp::UnwarpOptions;
use warpslice::warp::{WarpParams, WarpSpec};

fn tmpdir(tag: &str) -> TmpDir {
    let d = std::env::temp_dir().join(format!("warpslice-mach-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    TmpDir(d)
}

/// A test's temporary directory, removed with everything in it when the test ends (the
/// README example's alone left 63 MB in the temp dir on every run).
struct TmpDir(std::path::PathBuf);

impl Drop for TmpDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

impl std::ops::Deref for TmpDir {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        &self.0
    }
}

impl AsRef<std::path::Path> for TmpDir {
    fn as_ref(&self) -> &std::path::Path {
        &self.0
    }
}

/// A 10 mm cube (the 20 mm example scaled), STL bytes.
fn part() -> Vec<u8> {
    let mut m = warpslice::shapes::example("cube").expect("cube");
    for v in &mut m.vertices {
        *v *= 0.5;
    }
    warpslice::mesh::write_stl(&m, "cube 10")
}

/// The slicer's G-code of the warped part, and the job.
/// Where the slicer centres the part (the machines turning about the output origin; the polar
/// machine off its centre, which is its singular point).
fn centre_for(preset: &str) -> Option<&'static str> {
    match preset {
        "core-r-theta" => Some("60,0"),
        "open5x-ab" | "open5x-prusa-uv" | "open5x-jubilee-bc" | "lathe-a" => Some("0,0"),
        _ => None,
    }
}

fn sliced(
    spec: &WarpSpec,
    centre: Option<&str>,
    dir: &std::path::Path,
    tag: &str,
) -> Option<(Vec<u8>, warpslice::job::Job)> {
    if let Err(e) = slicer::available(SlicerKind::PrusaSlicer) {
        if std::env::var("WARPSLICE_ALLOW_SKIP").as_deref() == Ok("1") {
            println!("SKIPPED {tag}: {e}");
            return None;
        }
        panic!("PrusaSlicer is needed for this test: {e}");
    }
    let w = warp_model(
        &part(),
        &WarpOptions::new(WarpParams {
            spec: spec.clone(),
            base: None,
        }),
    )
    .expect("warp");
    let stl = dir.join(format!("{tag}.stl"));
    let gcode = dir.join(format!("{tag}.sliced.gcode"));
    std::fs::write(&stl, &w.stl).expect("write stl");
    let mut so = SliceOptions {
        slicer: SlicerKind::PrusaSlicer,
        e_mode: EMode::Relative,
        ..SliceOptions::default()
    };
    if let Some(c) = centre {
        // machines whose rotation axes pass through the output origin: print near it
        so.extra_args = [
            "--bed-shape",
            "-100x-100,100x-100,100x100,-100x100",
            "--center",
            c,
        ]
        .map(String::from)
        .to_vec();
    }
    slicer::slice(&stl, &gcode, &so).expect("slice");
    Some((std::fs::read(&gcode).expect("read gcode"), w.job))
}

/// RotBot's nozzle misalignment (seed 002: e_parallel, e_perpendicular, rotated with U), mm.
const ROTBOT_MISALIGNMENT: (f64, f64) = (0.4, -0.25);

/// The machine a case name stands for: the preset, RotBot misaligned, the mandrel under the
/// part for the lathe.
fn spec_for(name: &str) -> Result<MachineSpec, String> {
    let base = if name == "rotbot-misaligned" {
        "rotbot"
    } else {
        name
    };
    let mut spec = preset(base).map_err(|e| e.to_string())?;
    if let (true, warpslice::machine::spec::Kinematics::Rtn(p)) =
        (base != name, &mut spec.kinematics)
    {
        spec.name = name.to_string();
        (p.e_parallel_mm, p.e_perpendicular_mm) = ROTBOT_MISALIGNMENT;
    }
    if let warpslice::machine::spec::Kinematics::LatheA(p) = &mut spec.kinematics {
        p.axis_z_mm = -20.0;
    }
    Ok(spec)
}

fn run_preset(name: &str, warp: &WarpSpec, dir: &std::path::Path) -> Result<String, String> {
    let spec = spec_for(name)?;
    let tag = format!("{name}-{}", warp.name());
    let Some((input, job)) = sliced(warp, centre_for(name), dir, &tag) else {
        return Ok("skipped".into());
    };
    let mut opts = UnwarpSettings::with_machine(
        UnwarpOptions {
            collect_toolpath: true,
            ..UnwarpOptions::default()
        },
        spec.clone(),
    );
    // the collision check (on by default) is tested in collision_check.rs; here the kinematics
    // end to end (the default head meets the bed on tilted parts): written anyway
    opts.output.allow_collisions = true;
    let out = unwarp(&input, &job, &opts).map_err(|e| format!("unwarp: {e}"))?;
    let path = dir.join(format!("{tag}.gcode"));
    std::fs::write(&path, &out.gcode).map_err(|e| e.to_string())?;
    let text = String::from_utf8(out.gcode.clone()).map_err(|e| e.to_string())?;
    if !text.contains(&format!("; warpslice machine = {name} reprapfirmware"))
        || !text.contains("; warpslice model_to_output = ")
    {
        return Err("the header lacks the warpslice lines".into());
    }
    let m = spec.build().map_err(|e| e.to_string())?;
    let names = m.axis_names();
    let lines = parse(&text, &names)?;
    let rep = out.report.machine.clone().ok_or("no machine report")?;
    if name == "cartesian" {
        return Ok(format!(
            "{name:22} sample written, {} lines; worst interpolation {:.5} mm / {:.4}°",
            text.lines().count(),
            rep.worst_position_mm,
            rep.worst_angle_deg
        ));
    }
    let meas = check(&spec, &out.toolpath, &lines, SAMPLES)
        .map_err(|e| format!("{e} [emitter report {rep:?}]"))?;
    // every move left beyond the bound is tagged in the file and counted in the report
    if meas.discontinuities as u64 != rep.depth_limited
        || text.matches("; discontinuity").count() as u64 != rep.depth_limited
    {
        return Err(format!(
            "{} discontinuities found, the report says {}",
            meas.discontinuities, rep.depth_limited
        ));
    }
    Ok(format!(
        "{tag:30} {:6} points {:6} lines: tip {:.5} mm, axis {:.4}°; interpolation measured {:.5} mm / {:.4}° ({} moves checked against their end tips), {} discontinuities (emitter report {:.5} mm / {:.4}°, dropped {:.2}°, {} rotate-arounds, {} resets, {} re-poses, {} depth-limited)",
        meas.points, meas.lines, meas.worst_tip, meas.worst_axis, meas.worst_interp_mm, meas.worst_interp_deg, meas.fallbacks, meas.discontinuities,
        rep.worst_position_mm, rep.worst_angle_deg, rep.worst_dropped_deg, rep.rotate_arounds, rep.rotary_resets, rep.reposes, rep.depth_limited
    ))
}

#[test]
fn every_preset_end_to_end_with_prusaslicer() {
    let dir = tmpdir("e2e");
    let mut fails = Vec::new();
    let only = std::env::var("WARPSLICE_ONLY_PRESET").ok();
    let mut cases: Vec<(&str, WarpSpec)> = warpslice::machine::preset_names()
        .into_iter()
        .map(|n| (n, warp_for(n)))
        .collect();
    cases.push((
        "pax-5axis",
        WarpSpec::Spherical {
            radius: 20.0,
            center: [0.0, 0.0, -20.0],
        },
    ));
    // the misaligned nozzle end to end (its kinematics alone are in machine_laws)
    cases.push(("rotbot-misaligned", warp_for("rotbot-misaligned")));
    for (name, warp) in &cases {
        if only.as_deref().is_some_and(|o| o != *name) {
            continue;
        }
        match run_preset(name, warp, &dir) {
            Ok(s) => println!("{s}"),
            Err(e) => fails.push(format!("{name}: {e}")),
        }
    }
    println!("sample G-code in {}", dir.display());
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

/// Relative speed error allowed between a move's tip speed on the firmware and the slicer's F
/// (issue 11: 1 %).
const TIP_SPEED_TOL: f64 = 0.01;
/// Relative excess of an axis' speed over its `max_feed` allowed (issue 11 item 6: 1 %), and
/// how close to its limit the axis that slows a move must run.
const AXIS_SPEED_TOL: f64 = 0.01;
/// Half a unit of the written axes' last decimal (3 decimals: 0.0005 mm or degrees): how far
/// the file's rounding moves each axis.
const AXIS_ROUNDING: f64 = 0.0005;

/// How far the 3-decimal rounding of the written axes can move the tip at `axes` (first order:
/// Σ over the axes of the tip's displacement when that axis moves by [`AXIS_ROUNDING`]), mm,
/// by the tests' own forward kinematics.
fn rounding_reach(fk: &common::machine::fk::Fk, axes: &[f64]) -> f64 {
    let p0 = fk.forward(axes).expect("forward").0;
    (0..axes.len())
        .map(|i| {
            let mut a = axes.to_vec();
            a[i] += AXIS_ROUNDING;
            (fk.forward(&a).expect("forward").0 - p0).length()
        })
        .sum()
}

/// One preset × flavour: the `--feed tip` output read with the firmware's own length rule
/// (tests/common/firmware.rs, from the firmware's documents) and the tests' forward kinematics
/// moves the tip at the slicer's F (the same file with `--feed xyz`, whose F is the slicer's:
/// every one of them is checked to be an F of the input or warpslice's travel feed), no axis
/// faster than its `max_feed` (+1 %), and where the slicer's F would drive an axis past it, that
/// axis at its limit (within 1 %; counted in `slowed`). Returns
/// (moves checked, moves whose tip travel is within the rounding of the written axes, worst
/// relative error of the moves the rounding changes by at most 0.1 %) or the first move off.
fn tip_speed_case(
    name: &str,
    flavour: common::firmware::Firmware,
    input: &[u8],
    job: &warpslice::job::Job,
    slowed: &mut usize,
) -> Result<(usize, usize, f64), String> {
    let spec = spec_for(name)?;
    let fk = common::machine::fk::Fk::from_spec(&spec)?;
    let m = spec.build().map_err(|e| e.to_string())?;
    let letters: Vec<char> = m
        .axis_names()
        .iter()
        .map(|n| n.chars().next().unwrap())
        .collect();
    // the axes the firmware is configured to turn: Open5x's published Duet 2 config.g creates
    // U and V without R1 (`M584 X0 Y1 Z2 E3 U4 V5`), so RepRapFirmware (and Marlin without
    // AXISn_ROTATES) count their degrees as linear; Klipper's rule does not ask
    let configured_linear: &[char] = match (name, flavour) {
        (
            "open5x-prusa-uv",
            common::firmware::Firmware::Rrf | common::firmware::Firmware::Marlin,
        ) => &['U', 'V'],
        _ => &[],
    };
    let rotary: Vec<char> = m
        .limits()
        .iter()
        .filter(|l| l.rotary)
        .map(|l| l.name.chars().next().unwrap())
        .filter(|c| !configured_linear.contains(c))
        .collect();
    let out = |feed: FeedMode| -> Result<String, String> {
        let opts = UnwarpSettings {
            unwarp: UnwarpOptions::default(),
            output: MachineOptions {
                machine: Some(spec.clone()),
                feed,
                flavour: Flavour::parse(flavour.flavour()),
                // the tip feed, not the head's clearance (collision_check.rs): written anyway
                allow_collisions: true,
                ..MachineOptions::default()
            },
        };
        let o = unwarp(input, job, &opts).map_err(|e| format!("{feed:?}: {e}"))?;
        String::from_utf8(o.gcode).map_err(|e| e.to_string())
    };
    let (xyz, tip) = (out(FeedMode::Xyz)?, out(FeedMode::Tip)?);
    let (mx, mt) = (
        common::firmware::motions(&xyz, &letters),
        common::firmware::motions(&tip, &letters),
    );
    if mx.len() != mt.len() {
        return Err(format!(
            "{} motion lines with xyz, {} with tip",
            mx.len(),
            mt.len()
        ));
    }
    let input_feeds: Vec<f64> = common::firmware::motions(&String::from_utf8_lossy(input), &[])
        .iter()
        .map(|m| m.f)
        .chain([warpslice::emit::DEFAULT_TRAVEL_FEED])
        .collect();
    let max_feed: std::collections::BTreeMap<char, f64> = serde_json::to_value(&spec)
        .map_err(|e| e.to_string())?["max_feed"]
        .as_object()
        .ok_or("the preset gives no max_feed")?
        .iter()
        .map(|(k, v)| (k.chars().next().unwrap(), v.as_f64().unwrap()))
        .collect();
    let (mut checked, mut rounding, mut worst) = (0, 0, 0.0f64);
    for k in 1..mt.len() {
        let (a, b, slicer) = (&mt[k - 1], &mt[k], &mx[k]);
        if b.pos != slicer.pos || (b.de - slicer.de).abs() > 1e-9 {
            return Err(format!(
                "line {}: xyz and tip outputs move differently",
                b.line
            ));
        }
        if !input_feeds.contains(&slicer.f) {
            return Err(format!(
                "line {}: xyz F {} is no F of the slicer",
                slicer.line, slicer.f
            ));
        }
        if !(a.full && b.full) {
            continue;
        }
        let delta = letters.iter().map(|c| (*c, b.pos[c] - a.pos[c])).collect();
        let d = flavour.move_length(&delta, &rotary, b.de);
        if d == 0.0 {
            continue;
        }
        let axes = |mo: &common::firmware::Motion| -> Vec<f64> {
            letters.iter().map(|c| mo.pos[c]).collect()
        };
        let tip_len = (fk.forward(&axes(b))?.0 - fk.forward(&axes(a))?.0).length();
        let reach = rounding_reach(&fk, &axes(a)) + rounding_reach(&fk, &axes(b));
        // T = D / F on the firmware; each axis' speed |Δᵢ| / T against its max_feed (the
        // machine file's): never over it by more than 1 %
        let ratio_at = |minutes: f64| -> f64 {
            letters
                .iter()
                .map(|c| (b.pos[c] - a.pos[c]).abs() / minutes / max_feed[c])
                .fold(0.0, f64::max)
        };
        let over = ratio_at(d / b.f);
        if over > 1.0 + AXIS_SPEED_TOL {
            return Err(format!(
                "line {}: an axis at {:.2} × its max_feed (F {}, {} length {d:.4})",
                b.line,
                over,
                b.f,
                flavour.flavour()
            ));
        }
        if tip_len <= reach {
            // the tip does not move beyond what the file's rounding can move it (a reorientation
            // in place): no tip speed to compare
            rounding += 1;
            continue;
        }
        // where the slicer's tip speed would drive an axis past its limit, the feed rule lowers
        // F so that axis runs at its limit (within 1 %; the tip is slower than the slicer's F)
        if ratio_at(tip_len / slicer.f) > 1.0 + AXIS_SPEED_TOL {
            if over < 1.0 - AXIS_SPEED_TOL {
                return Err(format!(
                    "line {}: slowed for an axis' limit, yet its fastest axis is at {:.3} × its max_feed (F {})",
                    b.line, over, b.f
                ));
            }
            *slowed += 1;
            continue;
        }
        // else the tip speed L / T against the slicer's F, within 1 % plus what the rounding of
        // the written axes can change L by
        let speed = tip_len * b.f / d;
        let err = (speed / slicer.f - 1.0).abs();
        let allowed = TIP_SPEED_TOL + reach / tip_len;
        checked += 1;
        if reach / tip_len <= 1e-3 {
            worst = worst.max(err);
        }
        if err > allowed {
            return Err(format!(
                "line {}: tip {tip_len:.4} mm, {} length {d:.4}, F {} → tip speed {speed:.1} mm/min, the slicer's F {} (error {:.2} %, allowed {:.2} %)",
                b.line,
                flavour.flavour(),
                b.f,
                slicer.f,
                err * 100.0,
                allowed * 100.0
            ));
        }
    }
    Ok((checked, rounding, worst))
}

/// `--feed tip` (the default) on every preset × flavour: the firmware's own length rule gives
/// each move of a PrusaSlicer file the slicer's tip speed within 1 %, or, where that speed
/// would drive an axis past its `max_feed`, that axis' limit (issue 11 item 6); no axis is ever
/// over its limit by more than 1 %.
#[test]
fn tip_feed_moves_the_tip_at_the_slicers_speed_on_every_firmware() {
    use common::firmware::Firmware;
    let dir = tmpdir("tip");
    let mut fails = Vec::new();
    for name in warpslice::machine::preset_names() {
        let Some((input, job)) = sliced(&warp_for(name), centre_for(name), &dir, name) else {
            return;
        };
        for fw in [Firmware::Rrf, Firmware::Marlin, Firmware::Klipper] {
            let mut slowed = 0;
            match tip_speed_case(name, fw, &input, &job, &mut slowed) {
                Ok((checked, rounding, worst)) => {
                    println!(
                        "{name:20} {:15} {checked:6} moves within 1 % (+ rounding) of the slicer's F, worst {:.3} % where the rounding is below 0.1 %; {slowed} slowed to an axis' limit; {rounding} moves turn in place",
                        fw.flavour(),
                        worst * 100.0
                    );
                    // seed 001 §4.8: the triple-Z bed's Z motors (1900 mm/min) cannot follow
                    // the slicer's travels on a tilted bed
                    if name == "ratrig-vcore3-3z" && slowed == 0 {
                        fails.push(format!(
                            "{name} {}: no move slowed for the Z motors",
                            fw.flavour()
                        ));
                    }
                    if checked < 100 || rounding * 20 > checked {
                        fails.push(format!(
                            "{name} {}: {checked} moves checked, {rounding} in place",
                            fw.flavour()
                        ));
                    }
                }
                Err(e) => fails.push(format!("{name} {}: {e}", fw.flavour())),
            }
        }
    }
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

fn cli(args: &[&str], stdin: &str) -> (bool, String, String) {
    use std::io::Write;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .args(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run warpslice");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(stdin.as_bytes())
        .expect("write stdin");
    let out = child.wait_with_output().expect("wait");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn kinematics_cli_round_trips_and_names_errors() {
    let (ok, out, err) = cli(
        &["kinematics", "inverse", "--machine", "pax-5axis"],
        "10,20,5,0,0,1\n10,20,5,0.5,0,0.8660254037844386\n",
    );
    assert!(ok, "{err}");
    let (ok, back, err) = cli(&["kinematics", "forward", "--machine", "pax-5axis"], &out);
    assert!(ok, "{err}");
    let v: Vec<f64> = back
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(
        (v[0] - 10.0).abs() < 1e-9 && (v[3] - 0.5).abs() < 1e-9,
        "{back}"
    );
    // unknown preset
    let (ok, _, err) = cli(
        &["kinematics", "inverse", "--machine", "no-such-machine"],
        "",
    );
    assert!(
        !ok && err.contains("unknown machine preset 'no-such-machine'")
            && err.contains("pax-5axis"),
        "{err}"
    );
    // a machine file that does not exist
    let (ok, _, err) = cli(
        &["kinematics", "inverse", "--machine", "/nonexistent/m.json"],
        "",
    );
    assert!(!ok && err.contains("cannot read the file"), "{err}");
    // bad CSV, with the line number
    let (ok, _, err) = cli(
        &["kinematics", "inverse", "--machine", "pax-5axis"],
        "1,2,3,0,0,1\n1,2,x,0,0,1\n",
    );
    assert!(
        !ok && err.contains("line 2") && err.contains("'x'"),
        "{err}"
    );
    let (ok, _, err) = cli(
        &["kinematics", "forward", "--machine", "pax-5axis"],
        "1,2,3\n",
    );
    assert!(
        !ok && err.contains("line 1") && err.contains("expected 5"),
        "{err}"
    );
    // unreachable orientation: the triple-Z bed tilts at most 30°
    let (ok, _, err) = cli(
        &["kinematics", "inverse", "--machine", "ratrig-vcore3-3z"],
        "100,100,5,0.7071067811865476,0,0.7071067811865476\n",
    );
    assert!(
        !ok && err.contains("cannot be reached") && err.contains("line 1"),
        "{err}"
    );
}

#[test]
fn unwarp_errors_are_named() {
    let dir = tmpdir("errors");
    // a 45° cone: beyond the triple-Z bed's 30° tilt
    let Some((input, job)) = sliced(&conic(45.0, [-15.0, 0.0]), None, &dir, "cone45") else {
        return;
    };
    let ratrig = UnwarpSettings::with_machine(
        UnwarpOptions::default(),
        preset("ratrig-vcore3-3z").unwrap(),
    );
    let e = unwarp(&input, &job, &ratrig).unwrap_err().to_string();
    assert!(
        e.starts_with("G-code line ")
            && e.contains("cannot be reached")
            && e.contains("max_tilt_deg"),
        "{e}"
    );
    // limit exceeded: the polar machine reaches 150 mm from its centre; the part is at (100, 100)
    let polar =
        UnwarpSettings::with_machine(UnwarpOptions::default(), preset("core-r-theta").unwrap());
    let e = unwarp(&input, &job, &polar).unwrap_err().to_string();
    assert!(
        e.starts_with("G-code line ") && e.contains("axis X") && e.contains("outside its travel"),
        "{e}"
    );
    // Klipper drives a 5-axis head, but has no G93
    let klipper = UnwarpSettings {
        unwarp: UnwarpOptions::default(),
        output: MachineOptions {
            machine: Some(preset("pax-5axis").unwrap()),
            flavour: Some(warpslice::machine::Flavour::Klipper),
            feed: FeedMode::InverseTime,
            ..MachineOptions::default()
        },
    };
    let e = unwarp(&input, &job, &klipper).unwrap_err().to_string();
    assert!(e.contains("Klipper has no G93"), "{e}");
    // options JSON: a preset name, an unknown one
    let o: UnwarpSettings =
        serde_json::from_str(r#"{"machine": "rotbot", "feed": "inverse-time"}"#).unwrap();
    assert_eq!(
        o.output.machine.as_ref().map(|m| m.name.as_str()),
        Some("rotbot")
    );
    let bad = serde_json::from_str::<UnwarpSettings>(r#"{"machine": "nope"}"#)
        .unwrap_err()
        .to_string();
    assert!(bad.contains("unknown machine preset 'nope'"), "{bad}");
    let bad = serde_json::from_str::<UnwarpSettings>(r#"{"machine": {"kind": "pax", "tilt": 3}}"#)
        .unwrap_err()
        .to_string();
    assert!(bad.contains("unknown field 'tilt'"), "{bad}");
    // through the CLI: the same unreachable orientation
    let g = dir.join("cone45.sliced.gcode");
    let j = dir.join("cone45.job.json");
    std::fs::write(&j, job.to_json_pretty()).unwrap();
    let o = dir.join("out.gcode");
    let (ok, _, err) = cli(
        &[
            "unwarp",
            g.to_str().unwrap(),
            "--job",
            j.to_str().unwrap(),
            "--machine",
            "ratrig-vcore3-3z",
            "-o",
            o.to_str().unwrap(),
        ],
        "",
    );
    assert!(
        !ok && err.contains("G-code line") && err.contains("cannot be reached"),
        "{err}"
    );
    let (ok, _, err) = cli(
        &[
            "unwarp",
            g.to_str().unwrap(),
            "--job",
            j.to_str().unwrap(),
            "--machine",
            "pax-5axis",
            "--flavour",
            "klipper",
            "--feed",
            "inverse-time",
            "-o",
            o.to_str().unwrap(),
        ],
        "",
    );
    assert!(!ok && err.contains("Klipper"), "{err}");
    // all-axes feed for Marlin, inverse-time for RepRapFirmware through the CLI; Marlin 2.1 has
    // no G93, so inverse-time with it is refused by name
    for (feed, flavour) in [
        ("inverse-time", "reprapfirmware"),
        ("all-axes", "marlin"),
        ("inverse-time", "marlin"),
    ] {
        let (ok, out, err) = cli(
            &[
                "unwarp",
                g.to_str().unwrap(),
                "--job",
                j.to_str().unwrap(),
                "--machine",
                "rotbot",
                "--feed",
                feed,
                "--flavour",
                flavour,
                "-o",
                o.to_str().unwrap(),
            ],
            "",
        );
        if (feed, flavour) == ("inverse-time", "marlin") {
            assert!(!ok && err.contains("Marlin 2.1 has no G93"), "{err}");
            continue;
        }
        assert!(ok, "{err}");
        assert!(
            out.contains(&format!("machine rotbot ({flavour})")),
            "{out}"
        );
        let text = std::fs::read_to_string(&o).unwrap();
        assert!(text.contains(&format!("; warpslice machine = rotbot {flavour}")));
        if flavour == "marlin" {
            assert!(text.contains("AXIS4_NAME 'U'"));
        }
        if feed == "inverse-time" {
            let g93 = text.find("\nG93").expect("G93");
            let g94 = text.rfind("\nG94").expect("G94");
            assert!(g93 < g94);
        }
    }
}

/// Two layers of a circle about the cone's axis, tool axis tilted 45° outward: the azimuth
/// turns twice through ±180°.
fn circle_path() -> Vec<ToolPoint> {
    let mut v = Vec::new();
    for layer in 0..2u32 {
        for i in 0..=72 {
            let t = (i as f64 * 5.0 + 2.5).to_radians();
            let (s, c) = t.sin_cos();
            v.push(ToolPoint {
                p: DVec3::new(100.0 + 10.0 * c, 100.0 + 10.0 * s, 1.0 + layer as f64),
                n: DVec3::new(c, s, 1.0).normalize(),
                e: 0.05,
                f: 1200.0,
                layer,
                feature: warpslice::toolpath::Feature::OuterWall,
                travel: false,
                line: 0,
            });
        }
    }
    v
}

fn emit_all(spec: &MachineSpec, path: &[ToolPoint]) -> (String, warpslice::machine::MachineReport) {
    use warpslice::emit::Emitter;
    let mut em =
        warpslice::machine::MachineEmitter::new(spec, None, warpslice::machine::FeedMode::Xyz)
            .unwrap();
    let mut out = Vec::new();
    em.header(&mut out);
    em.begin_region(&mut out, path[0].p, DVec3::Z).unwrap();
    for tp in path {
        em.point(&mut out, tp, true).unwrap();
    }
    em.end_region(&mut out).unwrap();
    em.finish(&mut out);
    (String::from_utf8(out).unwrap(), em.report())
}

#[test]
fn single_revolution_rotates_around_and_unlimited_resets_at_layer_change() {
    let path = circle_path();
    let spec = preset("rtn-slicer4rtn").unwrap();
    let (text, rep) = emit_all(&spec, &path);
    assert!(rep.rotate_arounds >= 2, "{rep:?}");
    assert_eq!(
        text.matches("; rotate-around").count() as u64,
        3 * rep.rotate_arounds
    );
    let m = spec.build().unwrap();
    let lines = parse(&text, &m.axis_names()).unwrap();
    assert!(lines.iter().all(|l| (-180.0..=180.0).contains(&l.axes[3])));
    // every point is reached (tip and realised axis; the descent of a rotate-around lands on
    // its point), the lifted moves are 1 mm up
    for tp in &path {
        let hit = lines.iter().any(|l| {
            let (p, n) = m.forward(&l.axes).unwrap();
            (p - tp.p).length() < TIP_TOL && deg(n, m.realised_axis(tp.p, tp.n)) < AXIS_TOL_DEG
        });
        assert!(hit, "point {:?} not reached", tp.p);
    }
    for l in lines.iter().filter(|l| l.rotate_around) {
        let (p, _) = m.forward(&l.axes).unwrap();
        assert!(
            p.z > 1.0 - 1e-6 && p.z < 3.0 + 1e-6,
            "a rotate-around line off the path: {p:?}"
        );
    }
    assert!(rep.e_skipped_mm > 0.0 && rep.e_skipped_mm < 0.05 * rep.rotate_arounds as f64 + 1e-9);

    let spec = preset("rotbot").unwrap();
    let (text, rep) = emit_all(&spec, &path);
    assert_eq!(rep.rotate_arounds, 0);
    assert!(rep.rotary_resets >= 1 && text.contains("G92 U"), "{text}");
    let m = spec.build().unwrap();
    let lines = parse(&text, &m.axis_names()).unwrap();
    // continuous: no jump of U between consecutive lines (a reset renames a line by 360°)
    for w in lines.windows(2) {
        let d = w[1].axes[3] - w[0].after.as_ref().unwrap_or(&w[0].axes)[3];
        assert!(d.abs() < 10.0, "{:?} → {:?}", w[0], w[1]);
    }
    assert!(lines.iter().all(|l| l.axes[3].abs() < 540.0));
    assert!(
        rep.worst_position_mm <= 0.02 && rep.worst_angle_deg <= 0.1,
        "{rep:?}"
    );
}

/// Regression: near the pole of the 5-axis head a split move's halves chose different (A, B)
/// branches, so the second half started from the midpoint solved from the move's start while
/// the first half had ended on the other branch: a 160° jump of A between two output lines
/// (1.87° off the path, found by the spherical warp's top pole on `pax-5axis`).
#[test]
fn split_halves_join_on_the_same_branch_near_the_pole() {
    use warpslice::machine::tessellate::{tessellate_move, TessellationReport, DEFAULT_BOUNDS};
    let m = preset("pax-5axis").unwrap().build().unwrap();
    // through the pole: the azimuth turns by ~170° while the tilt passes 0.3°
    let n0 = DVec3::new(-0.07, -0.11, 0.99).normalize();
    let n1 = DVec3::new(0.118, 0.118, 0.986).normalize();
    let (p0, p1) = (DVec3::new(99.0, 98.0, 10.0), DVec3::new(102.0, 101.8, 10.0));
    let a0 = m
        .inverse(p0, n0, Some(&[0.0, 0.0, 0.0, 1082.0, 0.0]))
        .unwrap();
    let to = ToolPoint {
        p: p1,
        n: n1,
        e: 0.1,
        f: 1200.0,
        layer: 1,
        feature: warpslice::toolpath::Feature::OuterWall,
        travel: false,
        line: 0,
    };
    let mut rep = TessellationReport::default();
    let moves = tessellate_move(m.as_ref(), (&a0, p0, n0), &to, &DEFAULT_BOUNDS, &mut rep).unwrap();
    let mut from = a0.clone();
    for mv in &moves {
        let (q0, r0) = m.forward(&from).unwrap();
        let (q1, r1) = m.forward(&mv.axes).unwrap();
        for i in 1..SAMPLES {
            let u = i as f64 / SAMPLES as f64;
            let axes: Vec<f64> = from
                .iter()
                .zip(&mv.axes)
                .map(|(x, y)| x + (y - x) * u)
                .collect();
            let (fp, fn_) = m.forward(&axes).unwrap();
            assert!((fp - q0.lerp(q1, u)).length() < 0.02);
            assert!(
                deg(fn_, slerp(r0, r1, u)) < 0.1,
                "jump {:?} → {:?}",
                from,
                mv.axes
            );
        }
        assert!(
            (mv.axes[3] - from[3]).abs() < 90.0,
            "A jumps {:?} → {:?}",
            from,
            mv.axes
        );
        from = mv.axes.clone();
    }
    assert_eq!(rep.depth_limited, 0);
}

/// The README's one command per machine runs as written (found: `--center -15,0` was taken for
/// a flag by the argument parser, so four of the documented commands failed).
#[test]
fn readme_machine_commands_run_as_written() {
    if let Err(e) = slicer::available(SlicerKind::PrusaSlicer) {
        if std::env::var("WARPSLICE_ALLOW_SKIP").as_deref() == Ok("1") {
            println!("SKIPPED the README's machine commands: {e}");
            return;
        }
        panic!("PrusaSlicer is needed for this test: {e}");
    }
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).expect("README");
    let start = readme
        .find("One command per machine")
        .expect("the README's machine commands");
    let commands: Vec<&str> = readme[start..]
        .lines()
        .skip_while(|l| !l.starts_with("```sh"))
        .skip(1)
        .take_while(|l| !l.starts_with("```"))
        .collect();
    assert!(
        commands.len() >= warpslice::machine::preset_names().len(),
        "{commands:?}"
    );
    let dir = tmpdir("readme");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
            .args(args)
            .current_dir(&dir)
            .output()
            .expect("run warpslice");
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    assert!(run(&["example", "cube", "-o", "cube.stl"]).0);
    let mut lathe = preset("lathe-a").unwrap();
    if let warpslice::machine::spec::Kinematics::LatheA(p) = &mut lathe.kinematics {
        p.axis_z_mm = -20.0;
    }
    std::fs::write(
        dir.join("lathe.json"),
        serde_json::to_string(&lathe).unwrap(),
    )
    .unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for c in &commands {
        let args: Vec<&str> = c.split_whitespace().skip(1).collect();
        let (ok, err) = run(&args);
        assert!(ok, "`{c}` failed: {err}");
        let out = args
            .windows(2)
            .find(|w| w[0] == "-o")
            .map(|w| w[1])
            .expect("-o");
        let text = std::fs::read_to_string(dir.join(out)).expect("output written");
        if let Some(m) = args.windows(2).find(|w| w[0] == "--machine").map(|w| w[1]) {
            let name = if m == "lathe.json" { "lathe-a" } else { m };
            assert!(
                text.contains(&format!("; warpslice machine = {name} ")),
                "`{c}`: no machine header"
            );
            seen.insert(name.to_string());
        } else {
            seen.insert("cartesian".to_string());
        }
    }
    let all: std::collections::BTreeSet<String> = warpslice::machine::preset_names()
        .into_iter()
        .map(String::from)
        .collect();
    assert_eq!(seen, all, "the README shows a command for every preset");
}
