//! Issue 12, "report, not refuse": what the unwarp writes although the user should look at it is
//! a warning in the report's `warnings` (the CLI prints each as `warning: …`; the page lists
//! them; the wasm report carries them, `wasm_errors.rs`), with the count and the first line or
//! the largest value — not only a number in the summary line. Each test mutates the synthetic
//! slicer's G-code of a warped cube (`common/synthetic.rs`) and computes what the warning must
//! say from the G-code text or the warp's geometry, not from the report it checks.
#![cfg(not(target_arch = "wasm32"))]

#[path = "common/synthetic.rs"]
mod synthetic;

use std::path::{Path, PathBuf};
use std::process::Command;

use warpslice::job::Job;
use warpslice::machine::MachineOptions;
use warpslice::pipeline::{unwarp, UnwarpSettings, WarpOptions};
use warpslice::unwarp::UnwarpOptions;
use warpslice::warp::{Direction, WarpParams, WarpSpec};

const CLI: &str = env!("CARGO_BIN_EXE_warpslice");

fn scratch(tag: &str, job: &Job) -> (PathBuf, PathBuf) {
    let d = std::env::temp_dir().join(format!("warpslice-warn-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let j = d.join("part.job.json");
    std::fs::write(&j, job.to_json_pretty()).unwrap();
    (d, j)
}

/// The library's warnings for `g` unwarped with `job` (placed where the synthetic slicer puts
/// it), on `machine` or 3-axis.
fn lib_warnings(g: &str, job: &Job, machine: Option<&str>) -> Vec<String> {
    let s = UnwarpSettings {
        unwarp: UnwarpOptions {
            offset: Some([100.0, 100.0]),
            ..UnwarpOptions::default()
        },
        output: MachineOptions {
            machine: machine.map(|m| warpslice::machine::preset(m).unwrap()),
            // the warnings, not the head's clearance (collision_check.rs): written anyway
            allow_collisions: true,
            ..MachineOptions::default()
        },
    };
    unwarp(g.as_bytes(), job, &s)
        .unwrap_or_else(|e| panic!("{machine:?}: {e}"))
        .report
        .warnings
}

/// The `warning: …` lines `warpslice unwarp` prints for `g`.
fn cli_warnings(d: &Path, job: &Path, g: &str, extra: &[&str]) -> Vec<String> {
    let input = d.join("in.gcode");
    std::fs::write(&input, g).unwrap();
    let o = Command::new(CLI)
        .args(["unwarp", input.to_str().unwrap(), "--job"])
        .arg(job)
        // the warnings, not the head's clearance (collision_check.rs): written anyway
        .args(["--offset", "100,100", "--allow-collisions", "-o"])
        .arg(d.join("out.gcode"))
        .args(extra)
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out.lines()
        .filter_map(|l| l.strip_prefix("warning: ").map(String::from))
        .collect()
}

/// Object extrusions of the synthetic file before line `before` (1-based): lines `G1 … E+`
/// that move in X or Y after a `;TYPE:` naming a wall or infill; (count, first line).
fn object_extrusions_before(g: &str, before: usize) -> (u64, usize) {
    let mut object = false;
    let (mut n, mut first) = (0, 0);
    for (i, l) in g.lines().enumerate().take(before - 1) {
        if let Some(t) = l.strip_prefix(";TYPE:") {
            object = !t.contains("Skirt");
            continue;
        }
        let extrudes = l.split(' ').any(|w| {
            w.strip_prefix('E')
                .and_then(|v| v.parse::<f64>().ok())
                .is_some_and(|e| e > 0.0)
        });
        let moves = l
            .split(' ')
            .any(|w| w.starts_with('X') || w.starts_with('Y'));
        if object && l.starts_with("G1 ") && extrudes && moves {
            n += 1;
            if first == 0 {
                first = i + 1;
            }
        }
    }
    (n, first)
}

/// Issue 12: `;WARPSLICE_BEGIN` placed after the part's first layers left their extrusions
/// outside the region, written flat and unplaced, without a word. The report warns with the
/// count and the first line (counted here in the G-code text), by the library and the CLI;
/// markers that hold every layer give no warning.
#[test]
fn markers_that_leave_object_extrusions_outside_the_region_are_warned_about() {
    let w = synthetic::conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let (d, job) = scratch("markers", &w.job);
    // the region begins at the third layer
    let (late, begin) = synthetic::insert_after(&g, ";LAYER_CHANGE\n", 3, ";WARPSLICE_BEGIN\n");
    let (n, first) = object_extrusions_before(&late, begin);
    assert!(
        n > 10 && first > 0,
        "{n} object extrusions before line {begin}"
    );
    let want = format!("{n} object extrusions lie outside the ;WARPSLICE_BEGIN/;WARPSLICE_END region (the first on line {first})");
    for (by, warnings) in [
        ("library", lib_warnings(&late, &w.job, None)),
        ("CLI", cli_warnings(&d, &job, &late, &[])),
    ] {
        assert!(
            warnings.iter().any(|x| x.starts_with(&want)),
            "{by}: want {want:?} in {warnings:?}"
        );
    }
    // markers around every layer: nothing outside
    let (whole, _) = synthetic::insert_after(&g, "M83\n", 1, ";WARPSLICE_BEGIN\n");
    let whole = whole.replace("M104 S0\n", ";WARPSLICE_END\nM104 S0\n");
    let warnings = lib_warnings(&whole, &w.job, None);
    assert!(
        !warnings.iter().any(|x| x.contains("WARPSLICE_BEGIN")),
        "{warnings:?}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// The part of the warning naming dropped tilt: (moves, largest angle in degrees).
fn dropped(warnings: &[String]) -> Option<(u64, f64)> {
    let w = warnings
        .iter()
        .find(|w| w.contains("cannot tilt that way"))?;
    let words: Vec<&str> = w.split(' ').collect();
    let at = words.iter().position(|x| *x == "moves")?;
    let n = words[at - 1].parse().ok()?;
    let deg = words
        .iter()
        .find_map(|x| x.strip_suffix('°'))
        .and_then(|x| x.parse().ok())?;
    Some((n, deg))
}

/// Issue 12: a machine that cannot realise the warp's tilt (a B head tilting in XZ only, a
/// 3-axis printer) printed those layers with another tool axis, said only as "largest dropped
/// tool-axis angle" in the summary line. The report warns with the count of moves and the
/// largest angle. The 30° outward cone tilts the tool 30° toward the cube's sides (seed 002:
/// the cone's normal makes the cone's angle with vertical), so a vertical nozzle drops 30° and
/// the B head drops up to asin(sin 30° · |sin φ|) = 30° on the ±y walls (φ = 90°); the B head
/// on a gentle curved warp along x (its tilt plane; at most atan(2 · 0.1 · 10 / 10) ≈ 11.3°,
/// within its 18° clip near the bed) drops nothing and warns nothing.
#[test]
fn tilt_a_machine_cannot_realise_is_warned_with_count_and_largest_angle() {
    let w = synthetic::conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let (d, job) = scratch("tilt", &w.job);
    for machine in ["cartesian", "fullcontrol-prusa-b"] {
        for (by, warnings) in [
            ("library", lib_warnings(&g, &w.job, Some(machine))),
            ("CLI", cli_warnings(&d, &job, &g, &["--machine", machine])),
        ] {
            let (n, deg) = dropped(&warnings).unwrap_or_else(|| {
                panic!("{machine} {by}: no dropped-tilt warning in {warnings:?}")
            });
            assert!(n > 100, "{machine} {by}: {n} moves");
            assert!(
                (deg - 30.0).abs() < 0.2,
                "{machine} {by}: {deg}° dropped, want 30°"
            );
        }
    }
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "c");
    let curved = warpslice::pipeline::warp_model(
        &stl,
        &WarpOptions::new(WarpParams {
            spec: WarpSpec::Curved {
                strength: 0.1,
                direction: Direction::Outward,
                offset: 0.0,
                width: 0.0,
            },
            base: None,
        }),
    )
    .unwrap();
    let g = synthetic::gcode(&curved.job, true, 2.0);
    let warnings = lib_warnings(&g, &curved.job, Some("fullcontrol-prusa-b"));
    assert_eq!(dropped(&warnings), None, "{warnings:?}");
    let _ = std::fs::remove_dir_all(&d);
}
