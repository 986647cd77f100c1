//! The real-slicer driver against the slicers installed on this machine.
//!
//! A missing slicer FAILS these tests (CI installs all three through `scripts/setup.sh`); set
//! `WARPSLICE_ALLOW_SKIP=1` to skip them locally with a printed reason instead.
#![cfg(not(target_arch = "wasm32"))]

use std::path::{Path, PathBuf};
use std::time::Duration;
use warpslice::slicer::{self, EMode, SliceOptions, SlicerError, SlicerKind};

/// The bundled 20 mm cube (corner at the origin).
fn cube_stl() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cube20.stl")
}

/// A scratch folder removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!(
            "warpslice-slicer-driver-{}-{test}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create scratch dir");
        Scratch(dir)
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// True if `kind` can run. If not: panics, or with `WARPSLICE_ALLOW_SKIP=1` prints why and
/// returns false.
fn have(kind: SlicerKind, test: &str) -> bool {
    match slicer::available(kind) {
        Ok(_) => true,
        Err(e) => {
            if std::env::var("WARPSLICE_ALLOW_SKIP").as_deref() == Ok("1") {
                eprintln!("SKIP {test}: {e}");
                false
            } else {
                panic!("{e}\n(set WARPSLICE_ALLOW_SKIP=1 to skip slicer tests locally)");
            }
        }
    }
}

/// Writes an ASCII STL of `tris`.
fn write_stl(path: &Path, tris: &[[[f64; 3]; 3]]) {
    let mut s = String::from("solid t\n");
    for t in tris {
        s.push_str("facet normal 0 0 0\nouter loop\n");
        for v in t {
            s.push_str(&format!("vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        s.push_str("endloop\nendfacet\n");
    }
    s.push_str("endsolid t\n");
    std::fs::write(path, s).expect("write STL");
}

/// The 12 outward-facing triangles of an axis-aligned box.
fn box_tris(lo: [f64; 3], hi: [f64; 3]) -> Vec<[[f64; 3]; 3]> {
    let v = |i: usize| {
        [
            if i & 4 != 0 { hi[0] } else { lo[0] },
            if i & 2 != 0 { hi[1] } else { lo[1] },
            if i & 1 != 0 { hi[2] } else { lo[2] },
        ]
    };
    let quads = [
        [0, 2, 6, 4],
        [1, 5, 7, 3],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 6, 7, 5],
    ];
    quads
        .iter()
        .flat_map(|q| [[v(q[0]), v(q[1]), v(q[2])], [v(q[0]), v(q[2]), v(q[3])]])
        .collect()
}

/// What a G-code file does, read with a deliberately small independent parser.
#[derive(Debug)]
struct Summary {
    /// Moves in XY that extrude (positive E).
    extrusions: usize,
    /// The E mode in effect at the first of them.
    first_extrusion_mode: Option<EMode>,
    /// Filament fed by them, mm.
    filament: f64,
    /// Distinct z of them, µm, sorted.
    layers_um: Vec<i64>,
    /// Median of filament length per mm of XY travel over them.
    median_e_per_mm: f64,
}

fn summarise(gcode: &Path) -> Summary {
    let text = std::fs::read_to_string(gcode).expect("read G-code");
    let mut mode = EMode::Absolute; // Marlin's power-on default
    let (mut last_e, mut x, mut y, mut z) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut s = Summary {
        extrusions: 0,
        first_extrusion_mode: None,
        filament: 0.0,
        layers_um: Vec::new(),
        median_e_per_mm: 0.0,
    };
    let mut ratios = Vec::new();
    for raw in text.lines() {
        let line = raw.split(';').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let Some(cmd) = words.next() else { continue };
        let word = |w: &str| -> Option<(char, f64)> {
            let c = w.chars().next()?;
            Some((c, w[1..].parse().ok()?))
        };
        match cmd {
            "M82" => mode = EMode::Absolute,
            "M83" => mode = EMode::Relative,
            "G92" => {
                for (c, v) in words.filter_map(word) {
                    if c == 'E' {
                        last_e = v;
                    }
                }
            }
            "G0" | "G1" => {
                let (mut nx, mut ny, mut e) = (x, y, None);
                for (c, v) in words.filter_map(word) {
                    match c {
                        'X' => nx = v,
                        'Y' => ny = v,
                        'Z' => z = v,
                        'E' => e = Some(v),
                        _ => {}
                    }
                }
                if let Some(e) = e {
                    let de = match mode {
                        EMode::Relative => e,
                        EMode::Absolute => e - std::mem::replace(&mut last_e, e),
                    };
                    let len = (nx - x).hypot(ny - y);
                    if de > 0.0 && len > 0.0 {
                        s.extrusions += 1;
                        s.filament += de;
                        s.first_extrusion_mode.get_or_insert(mode);
                        s.layers_um.push((z * 1000.0).round() as i64);
                        ratios.push(de / len);
                    }
                }
                x = nx;
                y = ny;
            }
            _ => {}
        }
    }
    s.layers_um.sort_unstable();
    s.layers_um.dedup();
    ratios.sort_by(f64::total_cmp);
    s.median_e_per_mm = ratios.get(ratios.len() / 2).copied().unwrap_or(0.0);
    s
}

/// Slices the cube and checks the G-code: extrusion present, the E mode asked for, layers of
/// `layer_height` up to 20 mm, and an E per mm that fits 1.75 mm filament (CuraEngine's
/// extruder default of 2.85 mm would give about 0.4 times as much).
fn slice_cube(kind: SlicerKind, e_mode: EMode, layer_height: f64, test: &str) {
    if !have(kind, test) {
        return;
    }
    let dir = Scratch::new(test);
    let out = dir.path("cube.gcode");
    let opts = SliceOptions {
        slicer: kind,
        e_mode,
        layer_height,
        ..SliceOptions::default()
    };
    let report = slicer::slice(&cube_stl(), &out, &opts).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.gcode_path, out);
    assert!(report.gcode_bytes > 1000, "{report:?}");
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let s = summarise(&out);
    assert!(s.extrusions > 100, "{kind} {e_mode}: {s:?}");
    assert_eq!(s.first_extrusion_mode, Some(e_mode), "{kind}: {s:?}");
    let expected_layers = (20.0 / layer_height).round() as usize;
    let lh_um = (layer_height * 1000.0).round() as i64;
    assert_eq!(
        s.layers_um.first(),
        Some(&lh_um),
        "{kind}: first layer {s:?}"
    );
    assert_eq!(s.layers_um.last(), Some(&20_000), "{kind}: top layer {s:?}");
    assert_eq!(
        s.layers_um.len(),
        expected_layers,
        "{kind}: {:?}",
        s.layers_um
    );
    // A 0.4-0.5 mm wide line of height h needs about w·h/(π·1.75²/4) mm of filament per mm.
    let lo = 0.35 * layer_height / 2.405;
    let hi = 0.60 * layer_height / 2.405;
    assert!(
        (lo..hi).contains(&s.median_e_per_mm),
        "{kind}: E per mm {} outside [{lo}, {hi}]",
        s.median_e_per_mm
    );
    // Some infill and walls: between 10 % and 100 % of the solid cube's 3326 mm of filament.
    assert!((330.0..3400.0).contains(&s.filament), "{kind}: {s:?}");
}

macro_rules! cube_tests {
    ($($name:ident: $kind:expr, $mode:expr, $lh:expr;)*) => {$(
        #[test]
        fn $name() {
            slice_cube($kind, $mode, $lh, stringify!($name));
        }
    )*};
}

cube_tests! {
    prusaslicer_relative_cube: SlicerKind::PrusaSlicer, EMode::Relative, 0.2;
    prusaslicer_absolute_cube: SlicerKind::PrusaSlicer, EMode::Absolute, 0.2;
    slic3r_relative_cube: SlicerKind::Slic3r, EMode::Relative, 0.2;
    slic3r_absolute_cube: SlicerKind::Slic3r, EMode::Absolute, 0.2;
    curaengine_relative_cube: SlicerKind::CuraEngine, EMode::Relative, 0.2;
    curaengine_absolute_cube: SlicerKind::CuraEngine, EMode::Absolute, 0.2;
    prusaslicer_layer_height_025: SlicerKind::PrusaSlicer, EMode::Relative, 0.25;
    slic3r_layer_height_025: SlicerKind::Slic3r, EMode::Absolute, 0.25;
    curaengine_layer_height_025: SlicerKind::CuraEngine, EMode::Relative, 0.25;
}

#[test]
fn missing_executable_is_not_installed() {
    let dir = Scratch::new("missing_executable");
    for kind in SlicerKind::ALL {
        let opts = SliceOptions {
            slicer: kind,
            executable: Some(PathBuf::from("/nonexistent/warpslice-no-such-slicer")),
            cura_resources: Some(dir.0.clone()),
            ..SliceOptions::default()
        };
        match slicer::slice(&cube_stl(), &dir.path("x.gcode"), &opts) {
            Err(e @ SlicerError::NotInstalled { .. }) => {
                let msg = e.to_string();
                assert!(msg.contains(kind.install_hint()), "{msg}");
                assert!(msg.contains(kind.env_override()), "{msg}");
            }
            other => panic!("{kind}: expected NotInstalled, got {other:?}"),
        }
        // A bare name that is not on PATH is missing too.
        let opts = SliceOptions {
            executable: Some(PathBuf::from("warpslice-no-such-slicer")),
            ..opts
        };
        assert!(matches!(
            slicer::slice(&cube_stl(), &dir.path("x.gcode"), &opts),
            Err(SlicerError::NotInstalled { .. })
        ));
    }
}

#[test]
fn curaengine_without_definitions_is_reported() {
    if !have(SlicerKind::CuraEngine, "curaengine_without_definitions") {
        return;
    }
    let dir = Scratch::new("cura_no_defs");
    let opts = SliceOptions {
        slicer: SlicerKind::CuraEngine,
        cura_resources: Some(dir.0.clone()),
        ..SliceOptions::default()
    };
    let r = slicer::slice(&cube_stl(), &dir.path("x.gcode"), &opts);
    assert!(
        matches!(r, Err(SlicerError::CuraDefinitionsMissing { .. })),
        "{r:?}"
    );
}

/// Regression: a conic warp without base blend stands the mesh on its tip, and PrusaSlicer
/// exits 1 with "no extrusions in the first layer"; the user must be told about --base.
#[test]
fn prusaslicer_tip_on_bed_is_refused_with_advice() {
    if !have(SlicerKind::PrusaSlicer, "prusaslicer_tip_on_bed") {
        return;
    }
    let dir = Scratch::new("tip");
    let stl = dir.path("tip.stl");
    let apex = [0.0, 0.0, 0.0];
    let top = [
        [-10.0, -10.0, 20.0],
        [10.0, -10.0, 20.0],
        [10.0, 10.0, 20.0],
        [-10.0, 10.0, 20.0],
    ];
    let mut tris: Vec<[[f64; 3]; 3]> = (0..4).map(|i| [apex, top[(i + 1) % 4], top[i]]).collect();
    tris.push([top[0], top[1], top[2]]);
    tris.push([top[0], top[2], top[3]]);
    write_stl(&stl, &tris);
    let opts = SliceOptions::default();
    match slicer::slice(&stl, &dir.path("tip.gcode"), &opts) {
        Err(e @ SlicerError::Refused { .. }) => {
            let msg = e.to_string();
            assert!(msg.contains("no extrusions in the first layer"), "{msg}");
            assert!(msg.contains("--base"), "{msg}");
        }
        other => panic!("expected Refused, got {other:?}"),
    }
    assert!(!dir.path("tip.gcode").exists());
}

#[test]
fn prusaslicer_floating_part_is_a_warning() {
    if !have(SlicerKind::PrusaSlicer, "prusaslicer_floating_part") {
        return;
    }
    let dir = Scratch::new("gap");
    let stl = dir.path("gap.stl");
    let mut tris = box_tris([0.0; 3], [10.0, 10.0, 5.0]);
    tris.extend(box_tris([0.0, 0.0, 8.0], [10.0, 10.0, 13.0]));
    write_stl(&stl, &tris);
    match slicer::slice(&stl, &dir.path("gap.gcode"), &SliceOptions::default()) {
        // PrusaSlicer 2.5 warns and writes G-code; newer versions refuse ("Empty layers
        // detected"). Both must reach the user with advice.
        Ok(report) => {
            assert_eq!(report.warnings.len(), 1, "{report:?}");
            assert!(report.warnings[0].message.contains("Empty layer"));
            assert!(report.warnings[0].advice.contains("gap in z"));
        }
        Err(SlicerError::Refused { advice, .. }) => assert!(advice.contains("gap in z")),
        Err(e) => panic!("expected a warning, got {e}"),
    }
}

#[test]
fn prusaslicer_model_wider_than_bed_is_refused_and_extra_args_fix_it() {
    if !have(SlicerKind::PrusaSlicer, "prusaslicer_model_wider_than_bed") {
        return;
    }
    let dir = Scratch::new("wide");
    let stl = dir.path("wide.stl");
    write_stl(&stl, &box_tris([0.0; 3], [260.0, 20.0, 1.0]));
    let out = dir.path("wide.gcode");
    match slicer::slice(&stl, &out, &SliceOptions::default()) {
        Err(SlicerError::Refused { advice, .. }) => assert!(advice.contains("--bed-shape")),
        other => panic!("expected Refused, got {other:?}"),
    }
    let opts = SliceOptions {
        extra_args: vec![
            "--bed-shape".to_string(),
            "0x0,400x0,400x400,0x400".to_string(),
        ],
        ..SliceOptions::default()
    };
    let report = slicer::slice(&stl, &out, &opts).unwrap_or_else(|e| panic!("{e}"));
    assert!(summarise(&report.gcode_path).extrusions > 10);
}

#[test]
fn unreadable_stl_is_refused_by_every_slicer() {
    let dir = Scratch::new("unreadable");
    let stl = dir.path("garbage.stl");
    std::fs::write(&stl, "this is not an STL\n").expect("write");
    for kind in SlicerKind::ALL {
        if !have(kind, "unreadable_stl") {
            continue;
        }
        let opts = SliceOptions {
            slicer: kind,
            ..SliceOptions::default()
        };
        match slicer::slice(&stl, &dir.path("g.gcode"), &opts) {
            Err(SlicerError::Refused { advice, .. }) => {
                assert!(advice.contains("valid"), "{kind}: {advice}")
            }
            other => panic!("{kind}: expected Refused, got {other:?}"),
        }
    }
}

#[test]
fn non_stl_file_name_is_rejected_before_running() {
    let dir = Scratch::new("non_stl");
    let r = slicer::slice(
        &dir.path("model.bin"),
        &dir.path("x.gcode"),
        &SliceOptions::default(),
    );
    assert!(matches!(r, Err(SlicerError::InvalidOption { .. })), "{r:?}");
}

/// Writes an executable shell script standing in for a slicer.
fn fake_slicer(dir: &Scratch, name: &str, body: &str) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let p = dir.path(name);
    std::fs::write(&p, format!("#!/bin/sh\n{body}\n")).expect("write script");
    std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    p
}

#[test]
fn unknown_failure_keeps_the_meaningful_output_tail() {
    let dir = Scratch::new("fake_fail");
    let exe = fake_slicer(
        &dir,
        "fail.sh",
        "echo '10 => Processing triangulated mesh'; echo 'boom: the slicer broke' >&2; exit 3",
    );
    let opts = SliceOptions {
        executable: Some(exe),
        ..SliceOptions::default()
    };
    match slicer::slice(&cube_stl(), &dir.path("x.gcode"), &opts) {
        Err(SlicerError::Failed {
            status,
            output_tail,
            ..
        }) => {
            assert!(status.contains('3'), "{status}");
            assert_eq!(output_tail, "  boom: the slicer broke");
        }
        other => panic!("expected Failed, got {other:?}"),
    }
}

#[test]
fn success_without_gcode_is_no_output() {
    let dir = Scratch::new("fake_silent");
    let exe = fake_slicer(&dir, "silent.sh", "exit 0");
    let out = dir.path("x.gcode");
    std::fs::write(&out, "stale G-code from an earlier run").expect("write");
    let opts = SliceOptions {
        slicer: SlicerKind::Slic3r,
        executable: Some(exe),
        ..SliceOptions::default()
    };
    let r = slicer::slice(&cube_stl(), &out, &opts);
    assert!(matches!(r, Err(SlicerError::NoOutput { .. })), "{r:?}");
    assert!(
        !out.exists(),
        "the stale G-code must not be mistaken for this run's"
    );
}

#[test]
fn hanging_slicer_is_stopped_at_the_timeout() {
    let dir = Scratch::new("fake_hang");
    let exe = fake_slicer(&dir, "hang.sh", "exec sleep 30");
    let opts = SliceOptions {
        executable: Some(exe),
        timeout: Some(Duration::from_millis(300)),
        ..SliceOptions::default()
    };
    let started = std::time::Instant::now();
    let r = slicer::slice(&cube_stl(), &dir.path("x.gcode"), &opts);
    assert!(matches!(r, Err(SlicerError::TimedOut { .. })), "{r:?}");
    assert!(started.elapsed() < Duration::from_secs(10));
}

#[test]
fn slicer_names_round_trip() {
    for kind in SlicerKind::ALL {
        assert_eq!(kind.to_string().parse::<SlicerKind>(), Ok(kind));
    }
    assert_eq!("prusa-slicer".parse(), Ok(SlicerKind::PrusaSlicer));
    assert_eq!("CuraEngine".parse(), Ok(SlicerKind::CuraEngine));
    let e = "simplify3d".parse::<SlicerKind>().map(|_| ()).unwrap_err();
    assert!(e.to_string().contains("prusaslicer, slic3r or curaengine"));
    assert_eq!("abs".parse(), Ok(EMode::Absolute));
    assert_eq!("Relative".parse(), Ok(EMode::Relative));
}
