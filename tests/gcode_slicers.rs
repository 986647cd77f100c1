//! The reader on real slicer output, generated at test time: a 20 mm cube (STL written here)
//! sliced by PrusaSlicer, Slic3r and CuraEngine when they are installed (a test whose slicer is
//! missing says so and passes). Slicer settings as /work/shared/tools/slice.sh: 0.2 mm layers,
//! 0.4 mm nozzle, 1.75 mm filament.
//!
//! Also a throughput measurement (ignored by default):
//! `WARPSLICE_GCODE_BENCH=file.gcode cargo test --release --test gcode_slicers -- --ignored --nocapture`
#![cfg(not(target_arch = "wasm32"))] // native only: proptest, files and processes

#[path = "common/skip.rs"]
mod skip;

use std::path::{Path, PathBuf};
use std::process::Command as Process;

use warpslice::gcode::{Command, GcodeError, Line, Move, Reader, State};

/// Layer height and cube size of the test print, mm.
const LAYER: f64 = 0.2;
const SIZE: f64 = 20.0;

fn cube_stl(path: &Path) {
    let s = SIZE;
    let v = |i: usize| -> [f64; 3] {
        [
            ((i & 1) as f64) * s,
            ((i >> 1 & 1) as f64) * s,
            ((i >> 2) as f64) * s,
        ]
    };
    // 12 triangles, outward (counter-clockwise seen from outside).
    let tris: [[usize; 3]; 12] = [
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    let mut t = String::from("solid cube\n");
    for tri in tris {
        t += " facet normal 0 0 0\n  outer loop\n";
        for i in tri {
            let p = v(i);
            t += &format!("   vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        t += "  endloop\n endfacet\n";
    }
    t += "endsolid cube\n";
    std::fs::write(path, t).unwrap();
}

fn tmp_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("warpslice-gcode-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn has(tool: &str) -> bool {
    Process::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Slice the cube; `None` (with a message) when the slicer is not installed or fails.
fn slice(slicer: &str, relative: bool) -> Option<Vec<u8>> {
    let dir = tmp_dir();
    // One STL per call: tests run in parallel.
    let stl = dir.join(format!("cube-{slicer}-{relative}.stl"));
    cube_stl(&stl);
    let out = dir.join(format!("{slicer}-{relative}.gcode"));
    let common = [
        "--layer-height",
        "0.2",
        "--first-layer-height",
        "0.2",
        "--nozzle-diameter",
        "0.4",
        "--filament-diameter",
        "1.75",
    ];
    let mut cmd;
    match slicer {
        "prusa-slicer" => {
            cmd = Process::new(slicer);
            cmd.args(["--loglevel", "1", "--export-gcode"])
                .args(common)
                .args(["--gcode-flavor", "marlin2"]);
            if relative {
                cmd.args(["--use-relative-e-distances", "--layer-gcode", "G92 E0"]);
            }
        }
        "slic3r" => {
            cmd = Process::new(slicer);
            cmd.args(common).args(["--gcode-flavor", "reprap"]);
            if relative {
                cmd.arg("--use-relative-e-distances");
            }
        }
        "CuraEngine" => {
            let res = std::env::var("CURA_RES")
                .unwrap_or_else(|_| "/opt/cura-res/usr/share/cura/resources".into());
            if !Path::new(&res)
                .join("definitions/fdmprinter.def.json")
                .exists()
            {
                skip::skip_or_fail("CuraEngine", "Cura definitions not found (set CURA_RES)");
                return None;
            }
            cmd = Process::new(slicer);
            cmd.env(
                "CURA_ENGINE_SEARCH_PATH",
                format!("{res}/definitions:{res}/extruders"),
            );
            cmd.args([
                "slice",
                "-j",
                &format!("{res}/definitions/fdmprinter.def.json"),
            ]);
            for s in [
                "machine_width=200",
                "machine_depth=200",
                "machine_height=200",
                "center_object=true",
                "layer_height=0.2",
                "layer_height_0=0.2",
                "infill_sparse_thickness=0.2",
                "machine_nozzle_size=0.4",
                "material_diameter=1.75",
            ] {
                cmd.args(["-s", s]);
            }
            cmd.args(["-s", &format!("relative_extrusion={relative}")]);
            cmd.args([
                "-e0",
                "-s",
                "material_diameter=1.75",
                "-s",
                "machine_nozzle_size=0.4",
                "-l",
            ]);
            cmd.arg(&stl).arg("-o").arg(&out);
            return run(cmd, slicer, &out);
        }
        _ => return None,
    }
    cmd.arg("--output").arg(&out).arg(&stl);
    run(cmd, slicer, &out)
}

fn run(mut cmd: Process, slicer: &str, out: &Path) -> Option<Vec<u8>> {
    if !has(slicer) {
        skip::skip_or_fail(slicer, "it is not installed");
        return None;
    }
    let o = match cmd.output() {
        Ok(o) => o,
        Err(e) => panic!("{slicer} could not be started: {e}"),
    };
    // a slicer that fails on a model it should slice is a failure, never a skip
    assert!(
        o.status.success(),
        "{slicer} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::read(out).ok()
}

struct Summary {
    moves: Vec<Move>,
    layer_starts: usize,
    explicit: usize,
    lines: u64,
}

fn read(bytes: &[u8], chunk: usize) -> Summary {
    let mut s = Summary {
        moves: Vec::new(),
        layer_starts: 0,
        explicit: 0,
        lines: 0,
    };
    let mut reader = Reader::default();
    let mut sink = |l: Line<'_>, _: &State| {
        s.moves.extend_from_slice(l.moves);
        s.layer_starts += usize::from(l.layer_start);
        s.explicit += usize::from(l.command == Command::LayerStart);
        s.lines = l.number;
        Ok::<(), GcodeError>(())
    };
    for c in bytes.chunks(chunk) {
        reader.push(c, &mut sink).unwrap();
    }
    reader.finish(&mut sink).unwrap();
    s
}

/// The checks common to every slicer.
fn check(name: &str, bytes: &[u8], explicit_markers: bool) -> Summary {
    let s = read(bytes, bytes.len().max(1));
    let layers = (SIZE / LAYER).round() as usize;
    assert_eq!(s.layer_starts, layers, "{name}: layer starts");
    assert_eq!(
        s.explicit,
        if explicit_markers { layers } else { 0 },
        "{name}"
    );
    assert_eq!(
        s.moves.iter().map(|m| m.layer).max(),
        Some(layers as u32 - 1)
    );
    // Planar slicing: every object extrusion of layer k lies at z = 0.2·(k + 1).
    let mut object = 0;
    for m in s
        .moves
        .iter()
        .filter(|m| m.is_extrusion() && m.feature.is_object())
    {
        let want = LAYER * (m.layer + 1) as f64;
        assert!(
            (m.to.z - want).abs() < 1e-6 && (m.from.z - want).abs() < 1e-6,
            "{name}: {m:?}"
        );
        object += 1;
    }
    assert!(object > 1000, "{name}: {object} object extrusions");
    // Layers never go down.
    assert!(s.moves.windows(2).all(|w| w[0].layer <= w[1].layer));
    // Any chunking gives the same moves.
    let c = read(bytes, 4093);
    assert_eq!(c.moves, s.moves);
    assert_eq!(c.lines, s.lines);
    s
}

/// Relative difference of one layer's extruded length and E allowed between two slicer runs
/// whose moves differ in number (see `same_path`).
const SAME_LAYER_REL: f64 = 0.01;

/// Same path and filament, relative vs absolute E (the absolute file rounds E to 5 decimals).
fn same_path(a: &Summary, b: &Summary) {
    let keep = |m: &&Move| m.from != m.to || m.e != 0.0;
    let a: Vec<&Move> = a.moves.iter().filter(keep).collect();
    let b: Vec<&Move> = b.moves.iter().filter(keep).collect();
    if a.len() != b.len() {
        // The two files come from two runs of the slicer, which is multithreaded: once in
        // three fresh-clone rehearsals under load PrusaSlicer's two runs differed by two moves
        // (5862 vs 5864), while every other run was identical. Then the same extruded path is
        // asked layer by layer: the same layers, each with the same extruded length and E
        // within SAME_LAYER_REL; said, not hidden.
        println!(
            "NOTE: the relative and absolute runs of the slicer differ by {} moves; comparing per layer",
            a.len().abs_diff(b.len())
        );
        let per_layer = |ms: &[&Move]| {
            let mut v: std::collections::BTreeMap<u32, (f64, f64)> = Default::default();
            for m in ms.iter().filter(|m| m.e > 0.0) {
                let t = v.entry(m.layer).or_default();
                t.0 += (m.to - m.from).length();
                t.1 += m.e;
            }
            v
        };
        let (la, lb) = (per_layer(&a), per_layer(&b));
        assert_eq!(la.keys().collect::<Vec<_>>(), lb.keys().collect::<Vec<_>>());
        for ((k, x), y) in la.iter().zip(lb.values()) {
            assert!(
                (x.0 - y.0).abs() <= SAME_LAYER_REL * x.0
                    && (x.1 - y.1).abs() <= SAME_LAYER_REL * x.1,
                "layer {k}: extruded {x:?} vs {y:?} (length mm, E mm)"
            );
        }
        return;
    }
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            (x.from, x.to, x.layer, x.feature),
            (y.from, y.to, y.layer, y.feature)
        );
        assert!((x.e - y.e).abs() < 2.1e-5, "{x:?} {y:?}");
    }
}

/// The slicer's own filament total from its footer comment, mm.
fn reported_filament(bytes: &[u8], key: &str) -> Option<f64> {
    let t = String::from_utf8_lossy(bytes);
    let line = t.lines().find(|l| l.starts_with(key))?;
    let v = line[key.len()..]
        .trim()
        .trim_end_matches(|c: char| !c.is_ascii_digit());
    v.split_whitespace()
        .next()?
        .trim_end_matches("mm")
        .parse()
        .ok()
}

/// Net E (pushes minus retractions) is the slicer's reported total minus the final
/// retraction (the default 2 mm retract length, not undone), up to the footer's rounding.
const END_RETRACT: f64 = 2.0;

fn net_e(s: &Summary) -> f64 {
    s.moves.iter().map(|m| m.e).sum()
}

#[test]
fn prusaslicer_cube_absolute_and_relative() {
    let (Some(abs), Some(rel)) = (slice("prusa-slicer", false), slice("prusa-slicer", true)) else {
        return;
    };
    let a = check("prusa abs", &abs, true);
    let r = check("prusa rel", &rel, true);
    same_path(&a, &r);
    let reported = reported_filament(&abs, "; filament used [mm] =").unwrap();
    let net = net_e(&a);
    assert!(
        (net + END_RETRACT - reported).abs() < 0.06,
        "net {net} reported {reported}"
    );
}

#[test]
fn slic3r_cube_infers_layers() {
    let (Some(abs), Some(rel)) = (slice("slic3r", false), slice("slic3r", true)) else {
        return;
    };
    let a = check("slic3r abs", &abs, false);
    let r = check("slic3r rel", &rel, false);
    same_path(&a, &r);
    let reported = reported_filament(&abs, "; filament used =").unwrap();
    let net = net_e(&a);
    assert!(
        (net + END_RETRACT - reported).abs() < 0.06,
        "net {net} reported {reported}"
    );
}

#[test]
fn curaengine_cube_absolute_and_relative() {
    let (Some(abs), Some(rel)) = (slice("CuraEngine", false), slice("CuraEngine", true)) else {
        return;
    };
    let a = check("cura abs", &abs, true);
    let r = check("cura rel", &rel, true);
    same_path(&a, &r);
}
