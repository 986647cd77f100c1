//! `--interpolation LIN,ANG` and `--interpolation-caps MM,DEG` (seed 001 §4.5: "at most 1 mm
//! and 1° between points, corresponding to a worst-case error of 0.05 mm and 0.01°"), walked
//! with the tests' own forward kinematics (tests/common/fk.rs, nothing of the crate's):
//! - with `--interpolation 0.05,0.01 --interpolation-caps 1,1` every pair of consecutive
//!   machine lines of a pax-5axis output is at most 1 mm of tip and 1° of tool axis apart, and
//!   the firmware's linear interpolation between them (its midpoint and quarter points) stays
//!   within 0.05 mm / 0.01° of the straight tip segment with the tool axis turning evenly,
//!   plus the 3-decimal rounding of the written axes; without caps the same file has longer
//!   moves (the option changes the output);
//! - a value outside 0.001…10 is refused by name (`machine.bad-option`, through the CLI's
//!   message).
#![cfg(not(target_arch = "wasm32"))]

#[path = "common/cli_part.rs"]
#[allow(dead_code)]
mod cli_part;
#[path = "common/firmware.rs"]
#[allow(dead_code)]
mod firmware;
#[path = "common/fk.rs"]
#[allow(dead_code)]
mod fk;
#[path = "common/synthetic.rs"]
#[allow(dead_code)]
mod synthetic;

use glam::DVec3;

use cli_part::Part;

/// What the 3-decimal rounding of the written axes can add to a tip distance (mm) and a tool
/// angle (degrees) on pax-5axis (pivot-to-tip 0: the tip is X Y Z itself; A/B to 0.0005°).
const ROUND_MM: f64 = 0.002;
const ROUND_DEG: f64 = 0.005;

/// (tip, axis) of every full machine line (all of X Y Z A B) in order.
fn poses(text: &str, fk: &fk::Fk) -> Vec<(Vec<f64>, DVec3, DVec3)> {
    let letters = ['X', 'Y', 'Z', 'A', 'B'];
    firmware::motions(text, &letters)
        .into_iter()
        .filter(|m| m.full)
        .map(|m| {
            let x: Vec<f64> = letters.iter().map(|c| m.pos[c]).collect();
            let (p, n) = fk.forward(&x).expect("forward");
            (x, p, n)
        })
        .collect()
}

fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.normalize()
        .dot(b.normalize())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// Spherical interpolation of unit vectors a → b at t.
fn slerp(a: DVec3, b: DVec3, t: f64) -> DVec3 {
    let w = angle_deg(a, b).to_radians();
    if w < 1e-12 {
        return a;
    }
    (a * ((1.0 - t) * w).sin() + b * (t * w).sin()) / w.sin()
}

#[test]
fn seed_001_bounds_and_caps_hold_on_every_written_move() {
    let part = Part::new(
        "interp",
        &["--warp", "conic", "--angle", "25", "--center", "-15,0"],
    );
    let spec = warpslice::machine::preset("pax-5axis").unwrap();
    let fk = fk::Fk::from_spec(&spec).unwrap();
    let (capped, _, _) = part
        .unwarp(
            "capped",
            &[
                "--machine",
                "pax-5axis",
                "--interpolation",
                "0.05,0.01",
                "--interpolation-caps",
                "1,1",
            ],
        )
        .unwrap();
    assert!(capped.contains(
        "; warpslice interpolation bound = 0.05 mm / 0.01 deg; moves capped at 1 mm / 1 deg"
    ));
    let ps = poses(&capped, &fk);
    assert!(ps.len() > 1000, "{} machine lines", ps.len());
    let (mut worst_step, mut worst_turn, mut worst_dev, mut worst_ang) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for w in ps.windows(2) {
        let ((x0, p0, n0), (x1, p1, n1)) = (&w[0], &w[1]);
        worst_step = worst_step.max((*p1 - *p0).length());
        worst_turn = worst_turn.max(angle_deg(*n0, *n1));
        for t in [0.25, 0.5, 0.75] {
            let x: Vec<f64> = x0.iter().zip(x1).map(|(a, b)| a + (b - a) * t).collect();
            let (p, n) = fk.forward(&x).unwrap();
            worst_dev = worst_dev.max((p - p0.lerp(*p1, t)).length());
            worst_ang = worst_ang.max(angle_deg(n, slerp(*n0, *n1, t)));
        }
    }
    println!("capped: {} lines, largest step {worst_step:.4} mm / {worst_turn:.4}°, interpolation {worst_dev:.5} mm / {worst_ang:.5}°", ps.len());
    assert!(worst_step <= 1.0 + ROUND_MM, "a move of {worst_step} mm");
    assert!(
        worst_turn <= 1.0 + ROUND_DEG,
        "a move turning {worst_turn}°"
    );
    assert!(worst_dev <= 0.05 + ROUND_MM, "interpolation {worst_dev} mm");
    assert!(worst_ang <= 0.01 + ROUND_DEG, "interpolation {worst_ang}°");

    // the same part without the caps: longer moves (the option is what made them short)
    let (plain, _, _) = part.unwarp("plain", &["--machine", "pax-5axis"]).unwrap();
    let longest = poses(&plain, &fk)
        .windows(2)
        .map(|w| (w[1].1 - w[0].1).length())
        .fold(0.0f64, f64::max);
    assert!(longest > 2.0, "the default's longest move is {longest} mm");
}

#[test]
fn an_interpolation_outside_its_range_is_refused_by_name() {
    let part = Part::new("interp-bad", &["--warp", "curved", "--strength", "0.3"]);
    for (flag, v) in [
        ("--interpolation", "0,0.01"),
        ("--interpolation", "0.02,11"),
        ("--interpolation-caps", "1,-1"),
    ] {
        let e = part
            .unwarp("bad", &["--machine", "fullcontrol-prusa-b", flag, v])
            .unwrap_err();
        assert!(
            e.contains(&format!(
                "{flag} {v}: expected two numbers mm,degrees, each from 0.001 to 10"
            )),
            "{e}"
        );
    }
    use warpslice::error::Coded;
    let o = warpslice::machine::MachineOptions {
        interpolation: Some([0.0, 0.1]),
        ..Default::default()
    };
    assert_eq!(o.bounds().unwrap_err().code(), "machine.bad-option");
}
