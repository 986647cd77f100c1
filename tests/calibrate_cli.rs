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
    let (ok, out, err) = run(&[
        "calibrate",
        "probe",
        "a-pos",
        "--z0",
        "-5",
        "--y90",
        "4.2",
        "--y-minus90",
        "-3.8",
    ]);
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
