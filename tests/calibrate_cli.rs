//! `warpslice calibrate …` end to end (the binary).
#![cfg(not(target_arch = "wasm32"))]

use std::path::PathBuf;
use std::process::Command;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "warpslice-calibrate-cli-{name}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn origin_writes_a_machine_that_test_print_uses() {
    let d = dir("origin");
    let meas = d.join("ab_values.out");
    std::fs::write(
        &meas,
        "ab_values\na_axis {0,-0.1650009,-0.2140012}\na_z_in_y 0.0030937\na_axis_dir {0.9994476,0.0332315,-0.0004059}\nb_axis {-0.1399994,0.0900002,-10}\nb_axis_dir {0.0010010,0.0059996,0.9999815}\n",
    )
    .unwrap();
    let json = d.join("machine.json");
    let (ok, out, err) = run(&[
        "calibrate",
        "origin",
        "--measurements",
        meas.to_str().unwrap(),
        "--bias",
        "0.326,0.453,-0.05",
        "--a-z-correction",
        "-0.258",
        "-o",
        json.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("A^B_pos") && out.contains("θ = asin"), "{out}");
    // the G55 line: the offsets in force (RRF's object model) plus B''_pos, axis by axis
    let origin: Vec<f64> = out
        .split("new origin B''_pos (current frame; shift the G55 frame by it) = (")
        .nth(1)
        .and_then(|r| r.split(')').next())
        .expect("the origin line")
        .split(", ")
        .map(|v| v.parse().unwrap())
        .collect();
    let g10 = out
        .lines()
        .find(|l| l.starts_with("G10 L2 P2 "))
        .expect("a G10 L2 P2 line");
    for (i, (letter, v)) in ["X", "Y", "Z"].iter().zip(&origin).enumerate() {
        let want = format!("{letter}{{move.axes[{i}].workplaceOffsets[1] + {v:.6}}}");
        assert!(g10.contains(&want), "{want} not in {g10}");
    }
    let gcode = d.join("a.gcode");
    let stl = d.join("a.stl");
    let (ok, out, err) = run(&[
        "calibrate",
        "test-print",
        "integrated",
        "--machine",
        json.to_str().unwrap(),
        "-o",
        gcode.to_str().unwrap(),
        "--base",
        stl.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("integrated:"), "{out}");
    assert!(std::fs::read_to_string(&gcode).unwrap().contains("G1 X"));
    assert!(std::fs::metadata(&stl).unwrap().len() > 84);
}

#[test]
fn malformed_measurements_fail_with_the_line_number() {
    let d = dir("bad");
    let meas = d.join("bad.out");
    std::fs::write(&meas, "heading\na_axis {0,-0.1650009}\n").unwrap();
    let (ok, _, err) = run(&[
        "calibrate",
        "origin",
        "--measurements",
        meas.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("line 2"), "{err}");
}

#[test]
fn probes_and_simulation_print_results() {
    let a_pos = [
        "calibrate",
        "probe",
        "a-pos",
        "--z0",
        "-5",
        "--y90",
        "4.2",
        "--y-minus90",
        "-3.8",
    ];
    // the probe bias c_y has no default: the thesis printer's 0.453 is not another probe's
    let (ok, _, err) = run(&a_pos);
    assert!(!ok && err.contains("--c-y"), "{err}");
    let mut with_c_y = a_pos.to_vec();
    with_c_y.extend_from_slice(&["--c-y", "0.453"]);
    let (ok, out, err) = run(&with_c_y);
    assert!(ok, "{err}");
    assert!(out.contains("-0.2265"), "{out}");
    let (ok, out, err) = run(&[
        "calibrate",
        "probe",
        "z-bias",
        "--z90",
        "2.3,2.3",
        "--z-minus90",
        "2.1",
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("z_bias = 0.200000"), "{out}");
    let d = dir("sim");
    let csv = d.join("p.csv");
    std::fs::write(&csv, "x,y,z,nx,ny,nz\n0,20,0,0,1,0\n").unwrap();
    let svg = d.join("p.svg");
    let (ok, out, err) = run(&[
        "calibrate",
        "simulate",
        "--a-rot-z",
        "2",
        "--toolpath",
        csv.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("tip error max 0.6981"), "{out}");
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
}

/// §5.1.7 end to end: an A axis that turns `actual = k·commanded + c` (k = 0.9972, c = −0.2°)
/// tilts the flat of the B axle at ±90° by α = actual − commanded, so two probes 10 mm apart
/// read z₂ − z₁ = 10·sin α; `a-scaling` at both ends, then `a-steps`, must give back the
/// steps per degree S/k and the zero shift c.
#[test]
fn a_steps_per_degree_undoes_a_simulated_scaling_and_names_the_zero_shift() {
    let (k, c, s) = (0.9972f64, -0.2f64, 35.556f64);
    let alpha = |cmd: f64| -> String {
        let a = (k * cmd + c - cmd).to_radians();
        let (ok, out, err) = run(&[
            "calibrate",
            "probe",
            "a-scaling",
            "--z1",
            "1",
            "--z2",
            &format!("{}", 1.0 + 10.0 * a.sin()),
        ]);
        assert!(ok, "{err}");
        out.split("α = ")
            .nth(1)
            .unwrap()
            .split('°')
            .next()
            .unwrap()
            .to_string()
    };
    let (plus, minus) = (alpha(90.0), alpha(-90.0));
    let (ok, out, err) = run(&[
        "calibrate",
        "probe",
        "a-steps",
        "--alpha-plus",
        &plus,
        "--alpha-minus",
        &minus,
        "--steps-per-deg",
        &s.to_string(),
    ]);
    assert!(ok, "{err}");
    let want = format!("M92 A{:.4}", s / k);
    assert!(out.contains(&want), "{want} not in {out}");
    assert!(out.contains("zero-point shift = -0.2000°"), "{out}");
    let (ok, _, err) = run(&[
        "calibrate",
        "probe",
        "a-steps",
        "--alpha-plus",
        "50",
        "--alpha-minus",
        "0",
        "--steps-per-deg",
        "10",
    ]);
    assert!(!ok && err.contains("small angle error below 45°"), "{err}");
}

/// The Eq. 5.4 note (as printed, m_yx measures a taper) is in the help and in the output, not
/// only in a code comment.
#[test]
fn eq_5_4_note_is_in_help_and_output() {
    let (ok, help, _) = run(&["calibrate", "probe", "a-dir", "--help"]);
    assert!(ok && help.contains("taper"), "{help}");
    let (ok, out, err) = run(&[
        "calibrate",
        "probe",
        "a-dir",
        "--z-x",
        "1,1",
        "--d-zx",
        "10",
        "--z-y",
        "1,1",
        "--d-zy",
        "10",
        "--y-x1",
        "-5,5",
        "--y-x2",
        "-5,5",
        "--d-yx",
        "20",
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("measures a taper"), "{out}");
}

/// §6.2.2 through the CLI: the caliper readings give α_A,z with the formula's source and the
/// `calibrate origin` flag it goes to; a bad line length is refused by name.
#[test]
fn a_orientation_probe_prints_alpha_a_z_with_its_source() {
    let readings = [
        "calibrate",
        "probe",
        "a-orientation",
        "--d-start",
        "10",
        "--d-end",
        "10.18",
    ];
    let (ok, out, err) = run(&readings);
    assert!(ok, "{err}");
    assert!(out.contains("α_A,z = -0.257829°"), "{out}");
    assert!(out.contains("seed 004 §6.2.2"), "{out}");
    assert!(
        out.contains("calibrate origin --a-z-correction -0.257829"),
        "{out}"
    );
    let (ok, _, err) = run(&[&readings[..], &["--line-length", "-40"]].concat());
    assert!(!ok && err.contains("line length -40"), "{err}");
}
