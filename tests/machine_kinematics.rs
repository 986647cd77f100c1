//! Hand-worked poses of each machine's convention (signs, offsets, clips, corrections).

use glam::DVec3;
use warpslice::machine::{laws, preset, Machine, MachineSpec};
use warpslice::num::angle_between;

fn build(json: &str) -> Box<dyn Machine> {
    MachineSpec::from_json(json, "test")
        .and_then(|s| s.build())
        .unwrap()
}

fn close(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

#[test]
fn b_head_sign_pivot_and_dropped_y() {
    let m = preset("fullcontrol-prusa-b")
        .and_then(|s| s.build())
        .unwrap();
    // Above the clip height: B = +30° leans the nozzle body to +X; the pivot is r = 46 mm up
    // the nozzle: X = 46 sin 30° = 23, Z = 60 + 46 cos 30° − 46.
    let p = DVec3::new(0.0, 5.0, 60.0);
    let a = m.inverse(p, laws::axis(30.0, 0.0), None).unwrap();
    close(
        &a,
        &[
            23.0,
            5.0,
            60.0 + 46.0 * 30f64.to_radians().cos() - 46.0,
            30.0,
        ],
    );
    // B = 0 gives X Z = tip.
    close(
        &m.inverse(p, DVec3::Z, None).unwrap(),
        &[0.0, 5.0, 60.0, 0.0],
    );
    // The Y component is dropped: (1, 1, 1)/√3 → (1, 0, 1)/√2, 35.26° dropped.
    let n = DVec3::ONE.normalize();
    let r = m.realised_axis(p, n);
    assert!((r - DVec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-12);
    assert!((angle_between(n, r).to_degrees() - 35.264389682754654).abs() < 1e-9);
}

#[test]
fn b_head_collision_clip_of_seed_000() {
    let m = preset("fullcontrol-prusa-b")
        .and_then(|s| s.build())
        .unwrap();
    let n = laws::axis(80.0, 180.0); // leaning to −X by 80°
    for (z, want) in [(0.0, -18.0), (25.0, -54.0), (50.0, -80.0), (120.0, -80.0)] {
        let a = m.inverse(DVec3::new(0.0, 0.0, z), n, None).unwrap();
        assert!((a[3] - want).abs() < 1e-9, "z = {z}: {a:?}");
    }
}

#[test]
fn rtn_rotation_offset_and_misalignment() {
    let m = preset("rtn-slicer4rtn").and_then(|s| s.build()).unwrap();
    // Slicer4RTN's convention (issue 16): A = φ + 180° + rot_offset. Tool axis leaning to +X
    // (azimuth 0°) ⇒ A = 0° + 180° − 90° = 90°.
    let a = m
        .inverse(DVec3::new(1.0, 2.0, 3.0), laws::axis(45.0, 0.0), None)
        .unwrap();
    close(&a, &[1.0, 2.0, 3.0, 90.0]);
    // Leaning to −Y (azimuth −90°: the nozzle body in front) ⇒ A = 0°.
    let a = m
        .inverse(DVec3::ZERO, laws::axis(45.0, -90.0), None)
        .unwrap();
    assert!(a[3].abs() < 1e-9, "{a:?}");
    // RotBot misalignment: tip = XYZ + R_z(φ)(e_par, e_perp, 0); at φ = 90° the offset
    // (0.3, −0.2) turns into (0.2, 0.3); RotBot's convention U = φ + rot_offset (0).
    let r = build(
        r#"{"kind":"rtn","revolution":"unlimited","axis_names":["X","Y","Z","U"],"rot_convention":"rotbot","rot_offset_deg":0,"e_parallel_mm":0.3,"e_perpendicular_mm":-0.2}"#,
    );
    let a = r
        .inverse(DVec3::new(10.0, 10.0, 1.0), laws::axis(45.0, 90.0), None)
        .unwrap();
    close(&a, &[10.0 - 0.2, 10.0 - 0.3, 1.0, 90.0]);
    assert_eq!(r.axis_names(), vec!["X", "Y", "Z", "U"]);
}

#[test]
fn rtn_single_revolution_reports_the_rotate_around() {
    let spec = preset("rtn-slicer4rtn").unwrap();
    let warpslice::machine::spec::Kinematics::Rtn(p) = &spec.kinematics else {
        panic!()
    };
    let m = warpslice::machine::rtn::Rtn::new(
        "t",
        &["X".into(), "Y".into(), "Z".into(), "A".into()],
        p.clone(),
    )
    .unwrap();
    assert!(m.must_rotate_around(175.0, -175.0));
    assert!(!m.must_rotate_around(10.0, -10.0));
}

#[test]
fn pax_branch_keeps_a_through_the_vertical() {
    let m = build(r#"{"kind":"pax","pivot_to_tip_mm":35,"rot_offset_deg":-90}"#);
    let p = DVec3::new(5.0, 6.0, 7.0);
    let n = laws::axis(30.0, 0.0);
    let a = m.inverse(p, n, None).unwrap();
    let q = p + n * 35.0 - DVec3::Z * 35.0;
    // A = φ + 180° + rot_offset = 90° (Slicer4RTN's convention, the default).
    close(&a, &[q.x, q.y, q.z, 90.0, 30.0]);
    // Through the vertical to azimuth 180°: A stays, B goes negative.
    let a2 = m.inverse(p, laws::axis(10.0, 180.0), Some(&a)).unwrap();
    assert!(
        (a2[3] - 90.0).abs() < 1e-9 && (a2[4] + 10.0).abs() < 1e-9,
        "{a2:?}"
    );
}

#[test]
fn open5x_closed_form_and_wobble_eq_5_1() {
    let m = build(r#"{"kind":"ab-table","z_wobble_mm":0.13}"#);
    // n leaning 30° to +X: (A, B) = (30°, 90° − 0°).
    let a = m.inverse(DVec3::ZERO, laws::axis(30.0, 0.0), None).unwrap();
    close(&a[3..], &[30.0, 90.0]);
    // Wobble: z = clamp(2·z_d·A/180, ±z_d) = 0.13·30/90 at A = 30°, added to the ideal Z (0).
    assert!((a[2] - 0.13 * 30.0 / 90.0).abs() < 1e-12, "{a:?}");
    let a = m.inverse(DVec3::ZERO, laws::axis(90.0, 0.0), None).unwrap();
    assert!(
        (a[2] - 0.13).abs() < 1e-12 && (a[3] - 90.0).abs() < 1e-9,
        "{a:?}"
    );
    // A part point 10 mm up the table turns with it: A = 30° about X, B = 90° about Z.
    let a = m
        .inverse(DVec3::new(0.0, 0.0, 10.0), laws::axis(30.0, 0.0), None)
        .unwrap();
    close(&a[..2], &[0.0, -10.0 * 30f64.to_radians().sin()]);
    // Near the pole B is held.
    let prev = m.inverse(DVec3::ZERO, laws::axis(5.0, 40.0), None).unwrap();
    let held = m
        .inverse(DVec3::ZERO, laws::axis(0.3, 170.0), Some(&prev))
        .unwrap();
    assert_eq!(held[4], prev[4]);
}

#[test]
fn lathe_and_r_theta_conventions() {
    // X Z A: A is set by the position (the tip on the top line), n realised radially.
    let m = build(r#"{"kind":"lathe-a","axis_z_mm":50}"#);
    let n = DVec3::new(0.0, 20f64.to_radians().sin(), 20f64.to_radians().cos());
    let p = DVec3::new(3.0, 0.0, 50.0) + n * 10.0; // 10 mm from the mandrel axis
    close(&m.inverse(p, DVec3::Z, None).unwrap(), &[3.0, 60.0, 20.0]);
    assert!((m.realised_axis(p, DVec3::Z) - n).length() < 1e-12);
    // X Y Z A: A is set by the tool axis.
    let m = build(r#"{"kind":"lathe-a","axis_z_mm":50,"with_y":true}"#);
    close(&m.inverse(p, n, None).unwrap(), &[3.0, 0.0, 60.0, 20.0]);

    let r = preset("core-r-theta").and_then(|s| s.build()).unwrap();
    let a = r
        .inverse(DVec3::new(0.0, 50.0, 10.0), DVec3::Z, None)
        .unwrap();
    close(&a, &[50.0, -90.0, 10.0, 0.0]);
    // Tilted radially outwards by 20°: B = 20°, X = 50 + 43 sin 20°.
    let a = r
        .inverse(DVec3::new(0.0, 50.0, 10.0), laws::axis(20.0, 90.0), None)
        .unwrap();
    close(
        &a,
        &[
            50.0 + 43.0 * 20f64.to_radians().sin(),
            -90.0,
            10.0 + 43.0 * 20f64.to_radians().cos() - 43.0,
            20.0,
        ],
    );
}
