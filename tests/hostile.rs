//! Issue 12's hostile-input suite: generated mutations of a real slicer's output, each of which
//! must end in a named error or in an output that the project's independent checker
//! (tests/common/check.rs: placement, layer surfaces, E per class, travels, retractions, bed)
//! accepts — never a panic, never an unnamed failure, never a silently wrong file.
//!
//! The input: PrusaSlicer's G-code of the 20 mm cube warped by the 30° outward cone. Mutations
//! (drawn with a fixed seed; `WARPSLICE_HOSTILE_CASES=N` draws N per kind instead of the CI's
//! budget, `WARPSLICE_HOSTILE_SEED=S` another seed):
//! - inserted head moves (`G28 X Y`, `G28 X`, `G27`, `T1`, `T0`) at a random line of the region;
//! - number spellings of a random move word (`1e0`, `+`, leading/trailing point, `NaN`, `inf`,
//!   an empty value, a doubled word);
//! - truncations at a random byte;
//! - two adjacent lines of the region swapped;
//! - the job of every other warp family and of small parameter changes (must be refused);
//! - absurd options (must be refused).
#![cfg(not(target_arch = "wasm32"))]

mod common;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use warpslice::error::Coded;
use warpslice::job::Job;
use warpslice::pipeline::files::{self, RunFiles};
use warpslice::pipeline::{unwarp, warp_model, UnwarpSettings, WarpOptions};
use warpslice::slicer::{SliceOptions, SlicerKind};
use warpslice::unwarp::UnwarpOptions;
use warpslice::warp::{Direction, WarpParams, WarpSpec};

/// Mutations per kind in CI (the suite stays well under two minutes).
const CI_CASES: usize = 12;
/// The CI's seed.
const CI_SEED: u64 = 0x5eed_0012;

/// xorshift64*: the suite's own reproducible random numbers.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn env_usize(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn conic(angle: f64, direction: Direction, center: [f64; 2]) -> WarpParams {
    WarpParams {
        spec: WarpSpec::Conic {
            angle,
            direction,
            center,
        },
        base: None,
    }
}

/// The case: the warped cube, its job, PrusaSlicer's G-code of it.
struct Case {
    dir: PathBuf,
    warped: PathBuf,
    job: Job,
    gcode: String,
}

fn case() -> Option<Case> {
    if let Err(e) = warpslice::slicer::available(SlicerKind::PrusaSlicer) {
        common::skip::skip_or_fail("PrusaSlicer", &e.to_string());
        return None;
    }
    let dir = std::env::temp_dir().join(format!("warpslice-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("cube.stl");
    std::fs::write(
        &model,
        warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "cube"),
    )
    .unwrap();
    let files = RunFiles::next_to(&dir.join("part.gcode"));
    let w = files::warp_file(
        &model,
        &WarpOptions::new(conic(30.0, Direction::Outward, [0.0, 0.0])),
        &files.warped,
        &mut (),
    )
    .unwrap();
    warpslice::slicer::slice(&files.warped, &files.sliced, &SliceOptions::default()).unwrap();
    let gcode = std::fs::read_to_string(&files.sliced).unwrap();
    Some(Case {
        dir,
        warped: files.warped,
        job: w.job,
        gcode,
    })
}

/// The independent checker on an accepted output.
fn checked(c: &Case, input: &str, output: &[u8], opts: &UnwarpOptions) -> Result<(), String> {
    let (mesh, _) = warpslice::mesh::read_stl(&std::fs::read(&c.warped).unwrap()).unwrap();
    let b = c.job.warped_bbox.center();
    let expect = common::check::Expect {
        job: &c.job,
        warped: &mesh,
        placement: glam::DVec2::new(100.0 - b.x, 100.0 - b.y),
        max_segment: opts.max_segment,
        tolerance: opts.tolerance,
        clearance: opts.travel_clearance,
    };
    common::check::check(&expect, input.as_bytes(), output).map(|_| ())
}

/// What one mutation gave: Ok(description) or Err(what is wrong).
fn verdict(
    c: &Case,
    what: &str,
    input: &str,
    job: &Job,
    opts: &UnwarpOptions,
    must_refuse: bool,
) -> Result<String, String> {
    let r = catch_unwind(AssertUnwindSafe(|| {
        unwarp(
            input.as_bytes(),
            job,
            &UnwarpSettings::three_axis(opts.clone()),
        )
    }))
    .map_err(|_| format!("{what}: panicked"))?;
    match r {
        Err(e) => {
            let (code, m) = (e.code(), e.to_string());
            if code.is_empty() || code == "io.failed" || m.is_empty() {
                return Err(format!("{what}: unnamed error {code:?}: {m}"));
            }
            Ok(format!("{what}: refused {code}"))
        }
        Ok(_) if must_refuse => Err(format!("{what}: accepted, must be refused")),
        Ok(out) => {
            checked(c, input, &out.gcode, opts).map_err(|e| {
                // WARPSLICE_KEEP_FAILED=DIR (local reproduction): the mutated input and its output
                if let Some(dir) = std::env::var_os("WARPSLICE_KEEP_FAILED") {
                    let dir = std::path::PathBuf::from(dir);
                    let tag: String = what
                        .chars()
                        .map(|ch| if ch.is_ascii_alphanumeric() { ch } else { '_' })
                        .collect();
                    let _ = std::fs::create_dir_all(&dir);
                    let _ = std::fs::write(dir.join(format!("{tag}.in.gcode")), input);
                    let _ = std::fs::write(dir.join(format!("{tag}.out.gcode")), &out.gcode);
                    let _ = std::fs::write(dir.join("job.json"), job.to_json_pretty());
                }
                format!("{what}: accepted, but {e}")
            })?;
            Ok(format!("{what}: accepted and checked"))
        }
    }
}

/// The lines of the warped region (between the first and last `;LAYER_CHANGE`).
fn region(lines: &[&str]) -> (usize, usize) {
    let first = lines
        .iter()
        .position(|l| l.starts_with(";LAYER_CHANGE"))
        .unwrap();
    let last = lines
        .iter()
        .rposition(|l| l.starts_with(";LAYER_CHANGE"))
        .unwrap();
    (first + 1, last)
}

/// A random move line of the region with a word of letter X, Y, Z or E: its index.
fn move_line(rng: &mut Rng, lines: &[&str]) -> usize {
    let (a, b) = region(lines);
    loop {
        let i = a + rng.below(b - a);
        if lines[i].starts_with("G1 ")
            && lines[i].split(' ').skip(1).any(|w| "XYE".contains(&w[..1]))
        {
            return i;
        }
    }
}

fn mutations(c: &Case, rng: &mut Rng, n: usize) -> Vec<(String, String)> {
    let lines: Vec<&str> = c.gcode.lines().collect();
    let join = |v: &[String]| v.join("\n") + "\n";
    let mut out = Vec::new();
    let (a, b) = region(&lines);
    for _ in 0..n {
        // a head move inserted
        let cmd = ["G28 X Y", "G28 X", "G27", "T1", "T0"][rng.below(5)];
        let at = a + rng.below(b - a);
        let mut v: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
        v.insert(at, cmd.to_string());
        out.push((format!("'{cmd}' before line {}", at + 1), join(&v)));
        // a number spelled otherwise
        let i = move_line(rng, &lines);
        let words: Vec<&str> = lines[i].split(' ').collect();
        let k = 1 + rng.below(words.len() - 1);
        let (letter, value) = words[k].split_at(1);
        let spelled = match rng.below(8) {
            0 => format!("{letter}{}e0", value.trim_end_matches(';')),
            1 => format!("{letter}+{value}"),
            2 => format!("{letter}{}", value.trim_start_matches('0')),
            3 => format!("{letter}{value}0"),
            4 => format!("{letter}NaN"),
            5 => format!("{letter}inf"),
            6 => letter.to_string(),
            _ => format!("{letter}{value} {letter}{value}"),
        };
        let mut v: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
        let mut w: Vec<String> = words.iter().map(|s| s.to_string()).collect();
        w[k] = spelled.clone();
        v[i] = w.join(" ");
        out.push((
            format!("line {}: '{}' as '{spelled}'", i + 1, words[k]),
            join(&v),
        ));
        // cut short
        let cut = c.gcode.len() / 2 + rng.below(c.gcode.len() / 2);
        out.push((format!("cut at byte {cut}"), c.gcode[..cut].to_string()));
        // two lines of the region swapped
        let i = a + rng.below(b - a - 1);
        let mut v: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
        v.swap(i, i + 1);
        out.push((format!("lines {} and {} swapped", i + 1, i + 2), join(&v)));
    }
    out
}

/// The jobs of the other warp families and of small changes to this one.
fn wrong_jobs() -> Vec<(String, Job)> {
    let cube = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "cube");
    let mut v: Vec<(String, WarpParams)> = common::acceptance_warps()
        .into_iter()
        .filter(|(n, _)| *n != "conic-out-30")
        .map(|(n, p)| (n.to_string(), p))
        .collect();
    for (n, p) in [
        ("conic 31°", conic(31.0, Direction::Outward, [0.0, 0.0])),
        ("conic 29.5°", conic(29.5, Direction::Outward, [0.0, 0.0])),
        (
            "conic centre +0.5 x",
            conic(30.0, Direction::Outward, [0.5, 0.0]),
        ),
        (
            "conic centre −0.5 y",
            conic(30.0, Direction::Outward, [0.0, -0.5]),
        ),
        (
            "cylindrical",
            WarpParams {
                spec: WarpSpec::Cylindrical {
                    radius: 10.0,
                    axis: [0.0, -10.0],
                },
                base: None,
            },
        ),
        (
            "spherical",
            WarpParams {
                spec: WarpSpec::Spherical {
                    radius: 10.0,
                    center: [0.0, 0.0, -10.0],
                },
                base: None,
            },
        ),
    ] {
        v.push((n.into(), p));
    }
    v.into_iter()
        .filter_map(|(n, p)| {
            warp_model(&cube, &WarpOptions::new(p))
                .ok()
                .map(|w| (n, w.job))
        })
        .collect()
}

fn absurd_options() -> Vec<(String, UnwarpOptions)> {
    let d = UnwarpOptions::default;
    vec![
        (
            "tolerance 1e-12".into(),
            UnwarpOptions {
                tolerance: 1e-12,
                ..d()
            },
        ),
        (
            "max-segment 0.001".into(),
            UnwarpOptions {
                max_segment: 0.001,
                ..d()
            },
        ),
        (
            "place 1e9,0".into(),
            UnwarpOptions {
                place: Some([1e9, 0.0]),
                ..d()
            },
        ),
        (
            "place NaN".into(),
            UnwarpOptions {
                place: Some([f64::NAN, 0.0]),
                ..d()
            },
        ),
        (
            "offset 1e12,0".into(),
            UnwarpOptions {
                offset: Some([1e12, 0.0]),
                ..d()
            },
        ),
        (
            "offset 10 mm off".into(),
            UnwarpOptions {
                offset: Some([110.0, 100.0]),
                ..d()
            },
        ),
        (
            "z-offset −50".into(),
            UnwarpOptions {
                z_offset: -50.0,
                ..d()
            },
        ),
        (
            "z-offset inf".into(),
            UnwarpOptions {
                z_offset: f64::INFINITY,
                ..d()
            },
        ),
        (
            "tolerance 0".into(),
            UnwarpOptions {
                tolerance: 0.0,
                ..d()
            },
        ),
    ]
}

#[test]
fn every_hostile_mutation_is_refused_by_name_or_checked() {
    let Some(c) = case() else { return };
    let n = env_usize("WARPSLICE_HOSTILE_CASES", CI_CASES as u64) as usize;
    let seed = env_usize("WARPSLICE_HOSTILE_SEED", CI_SEED);
    let mut rng = Rng(seed.max(1));
    let opts = UnwarpOptions::default();
    let mut failures = Vec::new();
    let mut seen = 0;
    // the file itself passes
    if let Err(e) = verdict(&c, "the file as sliced", &c.gcode, &c.job, &opts, false) {
        failures.push(e);
    }
    for (what, input) in mutations(&c, &mut rng, n) {
        match verdict(&c, &what, &input, &c.job, &opts, false) {
            Ok(v) => println!("{v}"),
            Err(e) => failures.push(e),
        }
        seen += 1;
    }
    let wrong = wrong_jobs();
    assert_eq!(
        wrong.len(),
        10,
        "every other family and four small changes warp the cube"
    );
    for (what, job) in wrong {
        match verdict(&c, &format!("the {what} job"), &c.gcode, &job, &opts, true) {
            Ok(v) => println!("{v}"),
            Err(e) => failures.push(e),
        }
        seen += 1;
    }
    for (what, o) in absurd_options() {
        match verdict(&c, &what, &c.gcode, &c.job, &o, true) {
            Ok(v) => println!("{v}"),
            Err(e) => failures.push(e),
        }
        seen += 1;
    }
    println!(
        "{seen} mutations (seed {seed:#x}), {} failed",
        failures.len()
    );
    let _ = std::fs::remove_dir_all(&c.dir);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
