//! The RatRig V-Core 3 triple-Z bed (seed 001): closed-form kinematics against the paper's
//! accuracy claim, the planar poses of Eq. 2, and tilted poses checked against an independent
//! generic solve of the physical constraints (Eqs. 1 and 3: ball heights and rail planes).

use glam::DVec3;
use warpslice::machine::{angles::rotate, laws, preset, Machine, MachineError};

fn machine() -> Box<dyn Machine> {
    preset("ratrig-vcore3-3z").and_then(|s| s.build()).unwrap()
}

const B_HAT: [[f64; 2]; 3] = [[-4.07, -12.16], [304.93, -12.16], [150.43, 296.84]];
const BALL_Z: f64 = -45.7;
const SLOTS: [f64; 3] = [29.89, 150.11, -90.0];

fn b_hat(i: usize) -> DVec3 {
    DVec3::new(B_HAT[i][0], B_HAT[i][1], BALL_Z)
}

/// Rotation by the rotation vector w.
fn rot(w: DVec3, v: DVec3) -> DVec3 {
    let a = w.length();
    if a == 0.0 {
        v
    } else {
        rotate(v, w / a, a)
    }
}

/// Residuals of the physical model for bed pose (rotation vector w, ball-0 world position c):
/// ball heights (b_i)_z = −z_i (Eq. 1) and rail planes n_i·b_i + k_i = 0 (Eq. 3), with
/// b_i = c + R (b̂_i − b̂_0).
fn residuals(x: &[f64; 6], z: [f64; 3]) -> [f64; 6] {
    let w = DVec3::new(x[0], x[1], x[2]);
    let c = DVec3::new(x[3], x[4], x[5]);
    let mut r = [0.0; 6];
    for i in 0..3 {
        let bar = b_hat(i) - b_hat(0);
        let b = c + rot(w, bar);
        let s = SLOTS[i].to_radians();
        let n = DVec3::new(-s.sin(), s.cos(), 0.0);
        r[i] = b.z + z[i];
        r[3 + i] = n.dot(b) - n.dot(bar);
    }
    r
}

/// Independent forward kinematics: Newton with a finite-difference Jacobian on the six
/// physical constraints, then the nozzle contact W(p̂) = (x, y, 0) − b̂₀ and the tool axis,
/// the world's vertical (the nozzle's direction) seen from the bed, Rᵀe₃.
fn generic_forward(axes: &[f64]) -> (DVec3, DVec3) {
    let z = [axes[2], axes[3], axes[4]];
    let mut x = [0.0, 0.0, 0.0, 0.0, 0.0, -z[0]];
    for _ in 0..50 {
        let r = residuals(&x, z);
        if r.iter().all(|v| v.abs() < 1e-13) {
            break;
        }
        let mut j = [[0.0; 7]; 6];
        for k in 0..6 {
            let mut xp = x;
            let h = 1e-7;
            xp[k] += h;
            let rp = residuals(&xp, z);
            for i in 0..6 {
                j[i][k] = (rp[i] - r[i]) / h;
            }
        }
        for i in 0..6 {
            j[i][6] = -r[i];
        }
        // Gaussian elimination with partial pivoting.
        for col in 0..6 {
            let piv = (col..6)
                .max_by(|&a, &b| j[a][col].abs().total_cmp(&j[b][col].abs()))
                .unwrap();
            j.swap(col, piv);
            let pivot_row = j[col];
            for row in j.iter_mut().skip(col + 1) {
                let f = row[col] / pivot_row[col];
                for (v, pv) in row.iter_mut().zip(pivot_row.iter()).skip(col) {
                    *v -= f * pv;
                }
            }
        }
        let mut dx = [0.0; 6];
        for row in (0..6).rev() {
            let s: f64 = (row + 1..6).map(|k| j[row][k] * dx[k]).sum();
            dx[row] = (j[row][6] - s) / j[row][row];
        }
        for k in 0..6 {
            x[k] += dx[k];
        }
    }
    let w = DVec3::new(x[0], x[1], x[2]);
    let c = DVec3::new(x[3], x[4], x[5]);
    // R(p̂ − b̂₀) + c = (x, y, 0) − b̂₀  ⇒  p̂ = Rᵀ((x, y, 0) − b̂₀ − c) + b̂₀.
    let p = rot(-w, DVec3::new(axes[0], axes[1], 0.0) - b_hat(0) - c) + b_hat(0);
    // the nozzle is vertical in the world: in bed space it points along Rᵀe₃
    (p, rot(-w, DVec3::Z))
}

#[test]
fn planar_poses_are_eq_2() {
    let m = machine();
    for p in [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(150.0, 146.5, 0.2),
        DVec3::new(300.0, 293.0, 205.0),
        DVec3::new(12.5, 280.0, 33.3),
    ] {
        let a = m.inverse(p, DVec3::Z, None).unwrap();
        let want = [p.x, p.y, p.z, p.z, p.z];
        for k in 0..5 {
            assert!((a[k] - want[k]).abs() < 1e-12, "{p}: {a:?} vs {want:?}");
        }
    }
}

#[test]
fn tilted_poses_satisfy_the_physical_constraints() {
    let m = machine();
    let poses = [
        (DVec3::new(150.0, 150.0, 10.0), laws::axis(10.0, 0.0)),
        (DVec3::new(150.0, 150.0, 10.0), laws::axis(10.0, 90.0)),
        (DVec3::new(20.0, 270.0, 100.0), laws::axis(30.0, 135.0)),
        (DVec3::new(300.0, 0.0, 0.0), laws::axis(30.0, -60.0)),
        (DVec3::new(75.0, 200.0, 205.0), laws::axis(22.5, 200.0)),
    ];
    for (p, n) in poses {
        let a = m.inverse(p, n, None).unwrap();
        let (q, nq) = generic_forward(&a);
        assert!(
            (q - p).length() < 1e-8,
            "{p} {n}: generic solve gives {q} from {a:?}"
        );
        assert!(
            (nq - n).length() < 1e-9,
            "{p} {n}: generic solve gives {nq}"
        );
        let (q2, n2) = m.forward(&a).unwrap();
        assert!((q2 - p).length() < 1e-12 && (n2 - n).length() < 1e-12);
    }
}

/// Worked by hand: a 10° tilt about the X axis only. Balls 0 and 1 share y = −12.16, so they
/// stay at the same height; ball 2 (y = 296.84) moves by about (296.84 + 12.16)·tan 10° =
/// 54.5 mm (less a little for the rails' sliding and the cos of the tilt).
#[test]
fn tilt_about_x_moves_the_back_ball_against_the_front_ones() {
    let m = machine();
    let p = DVec3::new(150.0, 140.0, 50.0);
    let a = m.inverse(p, laws::axis(10.0, 90.0), None).unwrap();
    // n̂ leans to +Y ⇒ bed normal n' = (0, −sin 10°, cos 10°) ⇒ the bed plane z = tan 10°·y
    // rises towards +Y ⇒ the back ball is higher ⇒ z₂ = −(b₂)_z < z₀ (Eq. 1).
    let back = a[4] - a[2];
    let front = a[3] - a[2];
    // Rigid-body estimate: Δz ≈ (y₂ − y₀)·tan 10° = 309 · 0.1763 = 54.5 mm.
    assert!(back < -45.0 && back > -65.0, "{a:?}");
    assert!(front.abs() < 2.0, "{a:?}");
}

/// The nozzle is vertical in the world, so the tool axis the bed realises is the world's up
/// seen from the bed, Rᵀe₃ (the generic solve's). Seed 001 Eq. 23's mirrored bed normal is
/// that only without a turn about the vertical: before this was caught, the real nozzle was
/// up to 0.14° off the requested axis at a 30° tilt (planted back: 0.14°, caught).
#[test]
fn the_nozzle_points_along_the_requested_tool_axis_at_every_tilt_and_azimuth() {
    let m = machine();
    let mut worst: f64 = 0.0;
    for p in [DVec3::new(150.0, 146.5, 20.0), DVec3::new(290.0, 10.0, 0.0)] {
        for t in [5.0, 15.0, 30.0] {
            for az in 0..24 {
                let n = laws::axis(t, 15.0 * az as f64);
                let a = m.inverse(p, n, None).unwrap();
                let (_, nq) = generic_forward(&a);
                worst = worst.max(nq.angle_between(n).to_degrees());
            }
        }
    }
    eprintln!("3Z nozzle direction vs requested tool axis: worst {worst:e}°");
    assert!(
        worst < 1e-6,
        "the nozzle is {worst}° off the requested tool axis"
    );
}

#[test]
fn round_trip_over_the_build_volume_is_below_1e_12_mm() {
    let m = machine();
    let mut worst_p: f64 = 0.0;
    let mut worst_n: f64 = 0.0;
    for i in 0..=6 {
        for j in 0..=6 {
            for k in 0..=4 {
                let p = DVec3::new(
                    300.0 * i as f64 / 6.0,
                    293.0 * j as f64 / 6.0,
                    205.0 * k as f64 / 4.0,
                );
                for t in [0.0, 1e-6, 0.1, 5.0, 10.0, 15.0, 20.0, 25.0, 29.0, 30.0] {
                    for az in 0..24 {
                        let n = laws::axis(t, 15.0 * az as f64);
                        let a = m.inverse(p, n, None).unwrap();
                        let (q, nq) = m.forward(&a).unwrap();
                        worst_p = worst_p.max((q - p).length());
                        worst_n = worst_n.max(warpslice::num::angle_between(nq, n));
                    }
                }
            }
        }
    }
    eprintln!("3Z round trip: worst {worst_p:e} mm, {worst_n:e} rad (paper: 3.2e-13 mm)");
    assert!(worst_p < 1e-12 && worst_n < 1e-12);
}

#[test]
fn tilt_beyond_30_degrees_is_a_named_error() {
    let m = machine();
    match m.inverse(DVec3::new(100.0, 100.0, 10.0), laws::axis(31.0, 45.0), None) {
        Err(e @ MachineError::UnreachableOrientation { .. }) => {
            assert!(e.to_string().contains("max_tilt_deg"))
        }
        other => panic!("{other:?}"),
    }
}

/// Seed 001 §4.1: the original carriages give the balls ±5 mm of rail (the paper reports about
/// 5° of tilt for the original machine, which also had shorter standoffs); the extended rails
/// (69 mm inward, 19 mm outward) allow 30°. Measured here: ±5 mm allows every azimuth up to
/// 10° at the bed centre and refuses 15°.
#[test]
fn rail_travel_limits_the_tilt() {
    let mut spec = preset("ratrig-vcore3-3z").unwrap();
    let warpslice::machine::spec::Kinematics::ThreeZ(params) = &mut spec.kinematics else {
        panic!()
    };
    params.rail_travel_mm = Some([5.0, 5.0]);
    let short = spec.build().unwrap();
    let p = DVec3::new(150.0, 140.0, 20.0);
    let mut worst_ok: f64 = 0.0;
    for t in [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 15.0] {
        let all = (0..36).all(|k| {
            short
                .inverse(p, laws::axis(t, 10.0 * k as f64), None)
                .is_ok()
        });
        if all {
            worst_ok = t;
        }
    }
    assert!(
        (2.0..=10.0).contains(&worst_ok),
        "±5 mm rails allow all azimuths up to {worst_ok}°"
    );
    match short.inverse(p, laws::axis(15.0, 0.0), None) {
        Err(e @ MachineError::UnreachableOrientation { .. }) => {
            assert!(e.to_string().contains("rail"), "{e}")
        }
        other => panic!("{other:?}"),
    }
    // The preset's extended rails take every 30° orientation.
    let m = machine();
    for k in 0..72 {
        m.inverse(p, laws::axis(30.0, 5.0 * k as f64), None)
            .unwrap();
    }
}
