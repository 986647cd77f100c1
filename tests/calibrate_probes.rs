//! The raw probe formulas of seed 004 §5.4.1 (Eqs. 5.2–5.6) and §5.1.6–5.1.8, with
//! hand-worked numbers.

use glam::DVec3;
use warpslice::calibrate::probes::{self, evaluate, ProbeInput, ProbeOutput};
use warpslice::calibrate::CalibError;

#[test]
fn eq_5_2_a_position_error_is_19_um_for_5_mm_and_5_degrees() {
    let e = probes::a_pos_error(5.0, 5.0);
    // 5 − (cos 5° − cos 185°)/2·5 = 5 (1 − cos 5°) = 0.0190265…
    assert!((e - 5.0 * (1.0 - 5f64.to_radians().cos())).abs() < 1e-15);
    assert!((e - 0.019027).abs() < 1e-6, "{e}");
    assert_eq!(probes::a_pos_error(5.0, 0.0), 0.0);
}

/// z₀ = −5, y₉₀ = 4.2, y₋₉₀ = −3.8, c_y = 0.453 (the thesis' bias), r_p = 1:
/// A_pos = (0, 0.2, −5 + (8 − 0.453)/2 + 1) = (0, 0.2, −0.2265), y_m = 8.
#[test]
fn eq_5_3_a_position() {
    let (a, y_m) = probes::a_pos(-5.0, 4.2, -3.8, probes::THESIS_C_Y, probes::PROBE_RADIUS);
    assert!((y_m - 8.0).abs() < 1e-15);
    assert!((a - DVec3::new(0.0, 0.2, -0.2265)).length() < 1e-15, "{a}");
    // y_m is |y₉₀ − y₋₉₀|: swapping the sides changes nothing.
    let (b, _) = probes::a_pos(-5.0, -3.8, 4.2, 0.453, 1.0);
    assert_eq!(a, b);
}

/// m_zx = (1.02 − 0.98)/(2·10) = 0.002; m_zy = (0.5 − 0.52)/(2·5) = −0.002;
/// m_yx = ((4.1 − (−4.0))/2 − (3.9 − (−4.0))/2)/20 = (4.05 − 3.95)/20 = 0.005;
/// A_dir = (1, 0.005, 0.002)/√1.000029.
#[test]
fn eq_5_4_a_orientation() {
    let (m_zx, m_zy, m_yx, d) = probes::a_dir(
        [1.02, 0.98],
        10.0,
        [0.5, 0.52],
        5.0,
        [-4.0, 4.1],
        [-4.0, 3.9],
        20.0,
    )
    .unwrap();
    assert!((m_zx - 0.002).abs() < 1e-15);
    assert!((m_zy - -0.002).abs() < 1e-15);
    assert!((m_yx - 0.005).abs() < 1e-15);
    let want = DVec3::new(1.0, 0.005, 0.002) / 1.000029f64.sqrt();
    assert!((d - want).length() < 1e-15, "{d}");
    let e = probes::a_dir([0.0; 2], 0.0, [0.0; 2], 1.0, [0.0; 2], [0.0; 2], 1.0).unwrap_err();
    assert!(e.to_string().contains("d_zx"), "{e}");
}

/// x_p = (−2.14, 1.86), y_p = (2.09, −1.91) → B_pos = (−0.14, 0.09, −10): listing 4.1's b_axis.
#[test]
fn eq_5_5_b_position_gives_the_listing_value() {
    let b = probes::b_pos([-2.14, 1.86], [2.09, -1.91], probes::B_PROBE_Z);
    assert!((b - DVec3::new(-0.14, 0.09, -10.0)).length() < 1e-15, "{b}");
}

/// Four side points at z = −10 with mean (0.1, 0.2, −10), at z = −15 with mean
/// (0.095, 0.17, −15): B_dir = normalize(p₂ − p₁) = (−0.005, −0.03, −5)/|…|, turned up.
#[test]
fn eq_5_6_b_orientation() {
    let p1 = [
        DVec3::new(2.1, 0.2, -10.0),
        DVec3::new(-1.9, 0.2, -10.0),
        DVec3::new(0.1, 2.2, -10.0),
        DVec3::new(0.1, -1.8, -10.0),
    ];
    let p2 = [
        DVec3::new(2.095, 0.17, -15.0),
        DVec3::new(-1.905, 0.17, -15.0),
        DVec3::new(0.095, 2.17, -15.0),
        DVec3::new(0.095, -1.83, -15.0),
    ];
    let (m1, m2, d) = probes::b_dir(&p1, &p2).unwrap();
    assert!((m1 - DVec3::new(0.1, 0.2, -10.0)).length() < 1e-14);
    assert!((m2 - DVec3::new(0.095, 0.17, -15.0)).length() < 1e-14);
    let want = DVec3::new(0.005, 0.03, 5.0).normalize();
    assert!((d - want).length() < 1e-12, "{d}");
    // Same heights: refused.
    assert!(probes::b_dir(&p1, &p1).is_err());
}

/// z₉₀ = (2.3, 2.3), z₋₉₀ = (2.1): z_bias = ½(2.3 + 2.1 − 4) = 0.2, z_shift = 2.2.
#[test]
fn z_bias_and_shift_5_1_6() {
    let (b, s) = probes::z_bias(&[2.3, 2.3], &[2.1], probes::AXLE_FLATS).unwrap();
    assert!((b - 0.2).abs() < 1e-15);
    assert!((s - 2.2).abs() < 1e-15);
    assert!(probes::z_bias(&[], &[2.1], 4.0).is_err());
}

/// α = asin((0.1 − 0)/10) = asin 0.01 = 0.5729673°.
#[test]
fn a_scaling_5_1_7() {
    let a = probes::a_scaling(0.0, 0.1, 10.0).unwrap();
    assert!((a - 0.01f64.asin().to_degrees()).abs() < 1e-12);
    assert!((a - 0.572967).abs() < 1e-6);
    assert!(probes::a_scaling(2.0, 1.9, 10.0).unwrap() < 0.0);
    let e = probes::a_scaling(0.0, 11.0, 10.0).unwrap_err();
    assert!(e.to_string().contains("exceeds"), "{e}");
}

/// z_shift 2.13, A^B_pos.z 2.0 → z_d = 0.13 mm (the thesis' value); Eq. 5.1 gives ±z_d at
/// ±90° and half of it at 45°.
#[test]
fn wobble_5_1_8_and_eq_5_1() {
    let out = evaluate(&ProbeInput::Wobble {
        z_shift: 2.13,
        ab_z: 2.0,
    })
    .unwrap();
    let ProbeOutput::Wobble { z_d, correction } = out else {
        panic!("{out:?}")
    };
    assert!((z_d - 0.13).abs() < 1e-12);
    let at = |a: f64| correction.iter().find(|c| c[0] == a).unwrap()[1];
    assert!((at(90.0) - z_d).abs() < 1e-15);
    assert!((at(-90.0) + z_d).abs() < 1e-15);
    assert!((at(45.0) - z_d / 2.0).abs() < 1e-15);
    assert_eq!(at(0.0), 0.0);
}

#[test]
fn probe_inputs_from_json_with_defaults() {
    let i: ProbeInput =
        serde_json::from_str(r#"{"kind":"a-pos","z0":-5,"y90":4.2,"y_minus90":-3.8,"c_y":0.453}"#)
            .unwrap();
    let out = evaluate(&i).unwrap();
    let ProbeOutput::APos { a_pos, .. } = &out else {
        panic!()
    };
    assert!((a_pos.z - -0.2265).abs() < 1e-15);
    assert!(out.to_text().contains("a_axis {0,0.2"), "{}", out.to_text());
    let i: ProbeInput =
        serde_json::from_str(r#"{"kind":"b-pos","x_p":[-2.14,1.86],"y_p":[2.09,-1.91]}"#).unwrap();
    let ProbeOutput::BPos { b_pos } = evaluate(&i).unwrap() else {
        panic!()
    };
    assert_eq!(b_pos.z, -10.0);
    let bad = evaluate(&ProbeInput::APos {
        z0: f64::NAN,
        y90: 0.0,
        y_minus90: 0.0,
        c_y: 0.0,
        r_p: 1.0,
    })
    .unwrap_err();
    assert!(matches!(bad, CalibError::BadInput { .. }));
}

/// §6.2.2 worked by hand from the seed's own numbers: the line "approximated to have a length
/// of 40 mm" and an orientation error of −0.258°. Ends 10.000 and 10.180 mm from the −X side:
/// slope (10.000 − 10.180)/40 = −0.0045, atan(0.0045) = 0.0045 − 0.0045³/3 + … =
/// 0.004499969625 rad = 0.2578293° → α_A,z = −0.2578293° (the seed's −0.258°).
#[test]
fn a_orientation_test_gives_the_seeds_minus_0_258_degrees_from_a_0_18_mm_slope() {
    let out = evaluate(&ProbeInput::AOrientation {
        d_start: 10.0,
        d_end: 10.18,
        line_length: 40.0,
    })
    .unwrap();
    let ProbeOutput::AOrientation {
        slope,
        alpha_a_z_deg,
    } = out
    else {
        panic!("{out:?}")
    };
    assert!((slope + 0.0045).abs() < 1e-12, "{slope}");
    assert!((alpha_a_z_deg + 0.2578293).abs() < 1e-7, "{alpha_a_z_deg}");
    assert!(out.to_text().contains("§6.2.2"), "{}", out.to_text());
    assert!(out.to_text().contains("--a-z-correction -0.257829"));
    // the line length defaults to the seed's 40 mm in JSON (the wasm input)
    let json: ProbeInput =
        serde_json::from_str(r#"{"kind":"a-orientation","d_start":10,"d_end":10.18}"#).unwrap();
    assert_eq!(evaluate(&json).unwrap(), out);
    // a line of no length is refused by name
    let e = evaluate(&ProbeInput::AOrientation {
        d_start: 1.0,
        d_end: 1.0,
        line_length: 0.0,
    })
    .unwrap_err();
    assert!(matches!(e, CalibError::BadInput { .. }), "{e}");
    assert!(e.to_string().contains("line length 0"), "{e}");
}

/// The sign of §6.2.2's α_A,z from the kinematics, not from the formula: an A axis turned
/// ε = −0.258° about Z (its true direction R_z(ε)·x̂, right hand), the nozzle held on top of a
/// cylinder of radius 25 mm about it at x₀ = 7 while A turns from −53.13° to +53.13° (a chord
/// of 2·25·0.8 = 40 mm): the part points under the nozzle, found by turning the nozzle point
/// back about the true axis (glam's quaternions), are the line's ends; their X from the side
/// at x = 0, fed to the probe formula with L = 40, give back ε (to its first-order error, ε²).
#[test]
fn a_orientation_test_recovers_a_simulated_z_rotation_of_the_a_axis() {
    use glam::DQuat;
    for eps_deg in [-0.258f64, 0.4] {
        let eps = eps_deg.to_radians();
        let t = DVec3::new(eps.cos(), eps.sin(), 0.0);
        let m = DVec3::new(7.0, 0.0, 25.0);
        let theta = 0.8f64.asin();
        let under = |a: f64| DQuat::from_axis_angle(t, -a) * m;
        let (start, end) = (under(-theta), under(theta));
        let (d_start, d_end) = (start.x, end.x);
        let ProbeOutput::AOrientation { alpha_a_z_deg, .. } = evaluate(&ProbeInput::AOrientation {
            d_start,
            d_end,
            line_length: 40.0,
        })
        .unwrap() else {
            panic!()
        };
        assert!(
            (alpha_a_z_deg - eps_deg).abs() < 1e-3 * eps_deg.abs(),
            "ε {eps_deg}°: α_A,z {alpha_a_z_deg}° from ends {d_start}, {d_end}"
        );
    }
}
