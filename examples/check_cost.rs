//! The collision check's cost on real slicer G-code (not a test): `cargo run --release --example
//! check_cost -- [--presets a,b] [--rounds N] NAME GCODE JOB STL [NAME GCODE JOB STL …]`.
//!
//! For each model and machine preset, `unwarp --machine P --allow-collisions` (into memory, the
//! warped STL registering the G-code as the CLI does; `--place 0,0` for the presets that turn
//! the part about the origin) with the check off and on, alternately, `N` rounds (default 3),
//! the least CPU time of each (this thread's, from `/proc/thread-self/schedstat`, else the
//! wall clock: so the figure is the work done, not the machine's load); prints both, the
//! check's share (`on / off − 1`, issue 10's target: at most +50 %) and the findings. Inputs:
//! e.g. `warpslice warp MODEL.stl --warp conic --angle 30 -o X.stl` then
//! `../shared/tools/slice.sh prusaslicer rel X.stl X.gcode` (the README's figures).

use std::time::Instant;

use warpslice::pipeline::{unwarp_with_stl, UnwarpSettings};
use warpslice::unwarp::UnwarpOptions;

/// Every preset the check runs on (the lathe's check is refused), with its placement.
const PRESETS: &[(&str, Option<[f64; 2]>)] = &[
    ("cartesian", None),
    ("core-r-theta", Some([0.0, 0.0])),
    ("fullcontrol-prusa-b", None),
    ("open5x-ab", Some([0.0, 0.0])),
    ("open5x-jubilee-bc", Some([0.0, 0.0])),
    ("open5x-prusa-uv", Some([0.0, 0.0])),
    ("pax-5axis", None),
    ("ratrig-vcore3-3z", None),
    ("rotbot", None),
    ("rtn-slicer4rtn", None),
];

/// CPU seconds of this thread so far (`/proc/thread-self/schedstat`'s first field, ns), or
/// `None` where the file is missing.
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// The seconds `f` took: CPU time where the system gives it, else wall time.
fn timed<T>(f: impl FnOnce() -> T) -> (f64, T) {
    let (c0, t0) = (cpu_seconds(), Instant::now());
    let r = f();
    let s = match (c0, cpu_seconds()) {
        (Some(a), Some(b)) => b - a,
        _ => t0.elapsed().as_secs_f64(),
    };
    (s, r)
}

/// The value after `flag` on the command line.
fn arg_value(args: &[String], flag: &str) -> Option<String> {
    args.iter().skip_while(|a| *a != flag).nth(1).cloned()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let only = arg_value(&args, "--presets");
    let rounds: usize = arg_value(&args, "--rounds")
        .and_then(|v| v.parse().ok())
        .unwrap_or(3)
        .max(1);
    let mut rest = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if a == "--presets" || a == "--rounds" {
            it.next();
        } else {
            rest.push(a.clone());
        }
    }
    if rest.is_empty() || !rest.len().is_multiple_of(4) {
        eprintln!("usage: check_cost [--presets a,b] [--rounds N] NAME GCODE JOB STL [NAME GCODE JOB STL …]");
        std::process::exit(2);
    }
    println!(
        "time: {}",
        if cpu_seconds().is_some() {
            "CPU s of the unwarp's thread"
        } else {
            "wall s (no /proc/thread-self/schedstat)"
        }
    );
    for m in rest.chunks(4) {
        let read = |p: &str| std::fs::read(p).unwrap_or_else(|e| panic!("{p}: {e}"));
        let gcode = read(&m[1]);
        let job_text = String::from_utf8(read(&m[2])).expect("job is UTF-8");
        let job = warpslice::job::Job::from_json(&job_text).expect("job");
        let stl = read(&m[3]);
        for &(name, place) in PRESETS {
            if only
                .as_ref()
                .is_some_and(|o| !o.split(',').any(|p| p == name))
            {
                continue;
            }
            let spec = warpslice::machine::preset(name).expect("preset");
            let settings = |check: bool| {
                let mut s = UnwarpSettings::with_machine(
                    UnwarpOptions {
                        place,
                        ..UnwarpOptions::default()
                    },
                    spec.clone(),
                );
                s.output.check_collisions = check;
                s.output.allow_collisions = true;
                s
            };
            let (off, on) = (settings(false), settings(true));
            let (mut t_off, mut t_on) = (f64::INFINITY, f64::INFINITY);
            let mut findings = None;
            for _ in 0..rounds {
                let (t, r) = timed(|| unwarp_with_stl(&gcode, &job, &off, Some(&stl)));
                if let Err(e) = r {
                    println!("{} × {name}: refused without the check: {e}", m[0]);
                    break;
                }
                t_off = t_off.min(t);
                let (t, r) = timed(|| unwarp_with_stl(&gcode, &job, &on, Some(&stl)));
                t_on = t_on.min(t);
                findings = r
                    .ok()
                    .and_then(|o| o.report.machine.map(|m| m.collisions.len()));
            }
            if t_off.is_finite() {
                println!(
                    "{} × {name}: check off {t_off:.2} s, on {t_on:.2} s: +{:.0} % ({} findings)",
                    m[0],
                    100.0 * (t_on / t_off - 1.0),
                    findings.map_or("?".into(), |f| f.to_string())
                );
            }
        }
    }
}
