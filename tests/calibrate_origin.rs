//! Eq. 5.7 (seed 004 §5.4.2), the measurement file of listing 4.1, repeated series (Table 6.2)
//! and the calibrated machine JSON.

use glam::DVec3;
use warpslice::calibrate::measurements::write_measurements;
use warpslice::calibrate::origin::{closest_approach, Stat};
use warpslice::calibrate::{
    calibrate_origin, machine_origin, parse_measurements, CalibError, OriginOptions, Series,
};
use warpslice::machine::{laws, preset, MachineSpec};

const LISTING_4_1: &str = "a_axis {0,-0.1650009,-0.2140012}
a_z_in_y 0.0030937
a_axis_dir {0.9994476,0.0332315,-0.0004059}
b_axis {-0.1399994,0.0900002,-10}
b_axis_dir {0.0010010,0.0059996,0.9999815}
";

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}

#[test]
fn listing_4_1_parses_with_heading_and_listing_numbers() {
    let text = format!("ab_values measurement output\n\n{LISTING_4_1}");
    let s = parse_measurements(&text).unwrap();
    assert_eq!(s.len(), 1);
    assert_eq!(s[0].line, 3);
    assert_eq!(s[0].a_pos, DVec3::new(0.0, -0.1650009, -0.2140012));
    assert_eq!(s[0].a_z_in_y, Some(0.0030937));
    assert_eq!(s[0].b_dir, DVec3::new(0.0010010, 0.0059996, 0.9999815));
    // As printed in the thesis, with "n | " line numbers.
    let numbered: String = LISTING_4_1
        .lines()
        .enumerate()
        .map(|(i, l)| format!("{} | {l}\n", i + 1))
        .collect();
    assert_eq!(
        parse_measurements(&numbered).unwrap()[0],
        Series {
            line: 1,
            ..s[0].clone()
        }
    );
}

/// Eq. 5.7 on the listing 4.1 values, no corrections. Expected values computed independently
/// (plain Python, the formulas of Eq. 5.7 with normalised directions).
#[test]
fn eq_5_7_listing_4_1_sample() {
    let s = &parse_measurements(LISTING_4_1).unwrap()[0];
    let o = machine_origin(s, &OriginOptions::default()).unwrap();
    assert!((o.t1 - -0.11970778014872832).abs() < 1e-12, "{}", o.t1);
    assert!((o.t2 - 9.784332966210691).abs() < 1e-12, "{}", o.t2);
    assert!(close(
        o.a_closest,
        DVec3::new(
            -0.11964165342185162,
            -0.16897896909105417,
            -0.2139526106120982
        ),
        1e-12
    ));
    assert!(close(
        o.origin,
        DVec3::new(
            -0.13020528268879303,
            0.14870228413618114,
            -0.21584803193136004
        ),
        1e-12
    ));
    assert!(close(
        o.a_from_b,
        DVec3::new(
            0.010563629266941404,
            -0.3176812532272353,
            0.0018954213192618474
        ),
        1e-12
    ));
    assert!((o.theta_deg - 1.9043753148713238).abs() < 1e-10);
    // The closest-approach segment is perpendicular to both lines.
    assert!(o.a_from_b.dot(o.a_dir).abs() < 1e-14);
    assert!(o.a_from_b.dot(o.b_dir).abs() < 1e-14);
}

/// With the author's probe biases (c_x = 0.326, c_y = 0.453, §6.1.1; z 0.05) and the A
/// orientation test's −0.258° (§6.2.2).
#[test]
fn eq_5_7_listing_4_1_with_bias_and_a_z_correction() {
    let s = &parse_measurements(LISTING_4_1).unwrap()[0];
    let opts = OriginOptions {
        bias: DVec3::new(0.326, 0.453, 0.05),
        a_z_correction_deg: -0.258,
    };
    let o = machine_origin(s, &opts).unwrap();
    assert!(close(
        o.a_closest,
        DVec3::new(
            0.23065808244563438,
            -0.611371190717314,
            -0.16409486278841184
        ),
        1e-12
    ));
    assert!(close(
        o.origin,
        DVec3::new(0.1957892219005909, 0.601669346807977, -0.1713378510632264),
        1e-12
    ));
    assert!(close(
        o.a_from_b,
        DVec3::new(
            0.034868860545043484,
            -1.213040537525291,
            0.007242988274814566
        ),
        1e-12
    ));
    assert!((o.theta_deg - 1.6463753361451505).abs() < 1e-10);
}

/// By hand: A along X through (0, 1, 2), B along Z through (3, 4, −10): the common
/// perpendicular is along Y, A'' = (3, 1, 2), B'' = (3, 4, 2), A^B = (0, −3, 0), θ = 0.
#[test]
fn eq_5_7_hand_worked_perpendicular_axes() {
    let s = Series {
        line: 1,
        a_pos: DVec3::new(0.0, 1.0, 2.0),
        a_dir: DVec3::X,
        b_pos: DVec3::new(3.0, 4.0, -10.0),
        b_dir: DVec3::Z * 2.0, // lengths do not matter
        a_z_in_y: None,
    };
    let o = machine_origin(&s, &OriginOptions::default()).unwrap();
    assert!(close(o.a_closest, DVec3::new(3.0, 1.0, 2.0), 1e-14));
    assert!(close(o.origin, DVec3::new(3.0, 4.0, 2.0), 1e-14));
    assert!(close(o.a_from_b, DVec3::new(0.0, -3.0, 0.0), 1e-14));
    assert_eq!(o.theta_deg, 0.0);
    assert!((o.axes_angle_deg - 90.0).abs() < 1e-12);
}

/// By hand with corrections: bias (0.1, 0.2, 0.3), α_{A,z} = 30°: A'_pos = (0, 0.8, 2.3),
/// A'_dir = (√3/2, 1/2, 0), B'_pos = (3.1, 4.2, −9.7). The closest point of the A line to the
/// vertical B line is the projection of (3.1, 4.2) in XY: t₁ = 3.1·√3/2 + 3.4/2;
/// A'' = (t₁√3/2, 0.8 + t₁/2, 2.3), B'' = (3.1, 4.2, 2.3), θ = 30°.
#[test]
fn eq_5_7_hand_worked_bias_signs_and_rotation() {
    let s = Series {
        line: 1,
        a_pos: DVec3::new(0.0, 1.0, 2.0),
        a_dir: DVec3::X,
        b_pos: DVec3::new(3.0, 4.0, -10.0),
        b_dir: DVec3::Z,
        a_z_in_y: None,
    };
    let opts = OriginOptions {
        bias: DVec3::new(0.1, 0.2, 0.3),
        a_z_correction_deg: 30.0,
    };
    let o = machine_origin(&s, &opts).unwrap();
    let h = 3f64.sqrt() / 2.0;
    let t1 = 3.1 * h + 3.4 / 2.0;
    assert!((o.t1 - t1).abs() < 1e-12);
    assert!(close(o.a_pos, DVec3::new(0.0, 0.8, 2.3), 1e-15));
    assert!(close(o.b_pos, DVec3::new(3.1, 4.2, -9.7), 1e-15));
    assert!(close(o.a_dir, DVec3::new(h, 0.5, 0.0), 1e-15));
    assert!(close(
        o.a_closest,
        DVec3::new(t1 * h, 0.8 + t1 / 2.0, 2.3),
        1e-12
    ));
    assert!(close(o.origin, DVec3::new(3.1, 4.2, 2.3), 1e-12));
    assert!((o.theta_deg - 30.0).abs() < 1e-12);
}

#[test]
fn parallel_axes_are_refused() {
    let s = Series {
        line: 1,
        a_pos: DVec3::ZERO,
        a_dir: DVec3::Z,
        b_pos: DVec3::new(1.0, 0.0, 0.0),
        b_dir: DVec3::new(0.0, 1e-8, 1.0),
        a_z_in_y: None,
    };
    let e = machine_origin(&s, &OriginOptions::default()).unwrap_err();
    assert!(matches!(e, CalibError::ParallelAxes { .. }), "{e}");
    assert!(e.to_string().contains("parallel"));
    assert!(closest_approach(DVec3::ZERO, DVec3::X, DVec3::Y, -DVec3::X).is_err());
}

/// A machine with known non-ideal axes, in a frame where its origin is not at 0 → synthetic
/// measurements (A_pos at x = 0, B_pos at z = −10, as the scripts record them) → the
/// calibration recovers the lines and the origin.
#[test]
fn round_trip_synthetic_measurements_recover_lines_and_origin() {
    let a_dir = DVec3::new(0.9994476, 0.0332315, -0.0004059).normalize();
    let b_dir = DVec3::new(0.0010010, 0.0059996, 0.9999815).normalize();
    let a_point = DVec3::new(5.0, 0.37, -0.83); // some point of the A line
    let b_point = DVec3::new(-0.41, 0.29, 3.0); // some point of the B line
                                                // The true origin: independently, by minimising |a(u) − b(v)|² (2×2 normal equations).
    let r = b_point - a_point;
    let (aa, ab, bb, ar, br) = (1.0, a_dir.dot(b_dir), 1.0, a_dir.dot(r), b_dir.dot(r));
    let det = aa * bb - ab * ab;
    let u = (ar * bb - ab * br) / det;
    let v = (ab * ar - aa * br) / det;
    let true_origin = b_point + b_dir * v;
    let true_a_closest = a_point + a_dir * u;
    // What the measurement scripts write.
    let a_meas = a_point + a_dir * (-a_point.x / a_dir.x);
    let b_meas = b_point + b_dir * ((-10.0 - b_point.z) / b_dir.z);
    let series = Series {
        line: 2,
        a_pos: a_meas,
        a_dir,
        b_pos: b_meas,
        b_dir,
        a_z_in_y: Some(0.001),
    };
    let text = write_measurements(&[series], "synthetic");
    let parsed = parse_measurements(&text).unwrap();
    let base = preset("open5x-ab").unwrap();
    let (rep, spec) = calibrate_origin(&parsed, &OriginOptions::default(), &base).unwrap();
    assert!(
        close(rep.result.origin, true_origin, 1e-9),
        "{} vs {true_origin}",
        rep.result.origin
    );
    assert!(close(
        rep.result.a_from_b,
        true_a_closest - true_origin,
        1e-9
    ));
    assert!(close(rep.result.a_dir, a_dir, 1e-9));
    assert!(close(rep.result.b_dir, b_dir, 1e-9));
    // The calibrated machine is the true one shifted to the new origin: same kinematics.
    let json = spec.to_json();
    let calibrated = MachineSpec::from_json(&json, "calibrated.json")
        .unwrap()
        .build()
        .unwrap();
    let mut truth = base.clone();
    if let warpslice::machine::spec::Kinematics::AbTable(p) = &mut truth.kinematics {
        p.a_pos = a_point;
        p.a_dir = a_dir;
        p.b_pos = b_point;
        p.b_dir = b_dir;
    }
    let truth = truth.build().unwrap();
    for axes in [
        [1.0, 2.0, 3.0, 0.0, 0.0],
        [-10.0, 5.0, 20.0, 45.0, 130.0],
        [3.0, -7.0, 11.0, -89.0, -400.0],
    ] {
        let (p1, n1) = calibrated.forward(&axes).unwrap();
        let (p2, n2) = truth.forward(&axes).unwrap();
        assert!(close(p1, p2, 1e-9), "{axes:?}: {p1} vs {p2}");
        assert!(close(n1, n2, 1e-12));
    }
}

#[test]
fn calibrated_json_loads_builds_and_passes_the_machine_laws() {
    let s = parse_measurements(LISTING_4_1).unwrap();
    let (rep, spec) =
        calibrate_origin(&s, &OriginOptions::default(), &preset("open5x-ab").unwrap()).unwrap();
    let m = MachineSpec::from_json(&spec.to_json(), "calibrated.json")
        .unwrap()
        .build()
        .unwrap();
    assert_eq!(m.axis_names(), ["X", "Y", "Z", "A", "B"]);
    laws::check_round_trip(m.as_ref()).unwrap();
    laws::check_paths(m.as_ref()).unwrap();
    let text = rep.to_text();
    assert!(text.contains("A^B_pos"), "{text}");
    assert!(text.contains("θ = asin"), "{text}");
    assert!(text.contains("1.904375"), "{text}");
}

#[test]
fn non_ab_table_base_is_refused() {
    let s = parse_measurements(LISTING_4_1).unwrap();
    let e =
        calibrate_origin(&s, &OriginOptions::default(), &preset("cartesian").unwrap()).unwrap_err();
    assert!(e.to_string().contains("ab-table"), "{e}");
}

/// Table 6.2: three series; mean ± population std (max difference).
#[test]
fn repeated_series_statistics_like_table_6_2() {
    let mut text = String::from("heading\n");
    for (k, dy) in [-0.01, 0.0, 0.04].iter().enumerate() {
        text.push_str(&format!(
            "a_axis {{0,{},-0.2140012}}\na_axis_dir {{0.9994476,0.0332315,-0.0004059}}\nb_axis {{-0.14,0.09,-10}}\nb_axis_dir {{0.001001,0.0059996,0.9999815}}\n",
            -0.165 + dy
        ));
        let _ = k;
    }
    let s = parse_measurements(&text).unwrap();
    assert_eq!(s.len(), 3);
    assert_eq!(s.iter().map(|x| x.line).collect::<Vec<_>>(), [2, 6, 10]);
    let (rep, _) =
        calibrate_origin(&s, &OriginOptions::default(), &preset("open5x-ab").unwrap()).unwrap();
    let st = rep.stats.as_ref().unwrap();
    // y values −0.175, −0.165, −0.125: mean −0.155, population std √(0.0014/3), max diff 0.05.
    assert!((st.a_pos.y.mean - -0.155).abs() < 1e-12);
    assert!((st.a_pos.y.std - (0.0014f64 / 3.0).sqrt()).abs() < 1e-12);
    assert!((st.a_pos.y.max_diff - 0.05).abs() < 1e-12);
    assert_eq!(
        st.b_pos.z,
        Stat {
            mean: -10.0,
            std: 0.0,
            max_diff: 0.0
        }
    );
    assert_eq!(rep.per_series.len(), 3);
    // The machine uses the mean series.
    let mean = machine_origin(
        &Series {
            a_pos: DVec3::new(0.0, -0.155, -0.2140012),
            ..s[1].clone()
        },
        &OriginOptions::default(),
    )
    .unwrap();
    assert!(close(rep.result.origin, mean.origin, 1e-12));
    assert!(rep.to_text().contains("mean ± std (max difference)"));
}

#[test]
fn malformed_files_name_the_line() {
    let cases: [(&str, usize, &str); 6] = [
        ("head\na_axis {0,1}\n", 2, "3"),
        ("head\na_axis {0,x,2}\n", 2, "not a number"),
        ("head\na_axis 0,1,2\n", 2, "not a vector"),
        (
            "a_axis {0,1,2}\nb_axsi {0,1,2}\n",
            2,
            "unknown component 'b_axsi'",
        ),
        ("head\n\na_z_in_y abc\n", 3, "not a number"),
        ("head\na_axis\n", 2, "no value"),
    ];
    for (text, line, what) in cases {
        let e = parse_measurements(text).unwrap_err();
        match &e {
            CalibError::BadLine { line: l, .. } => assert_eq!(*l, line, "{text:?}: {e}"),
            other => panic!("{text:?}: expected BadLine, got {other:?}"),
        }
        let msg = e.to_string();
        assert!(msg.contains(&format!("line {line}")), "{msg}");
        assert!(msg.contains(what), "{msg}");
    }
    // Incomplete series: names the series' first line and the missing component.
    let e = parse_measurements(
        "head\na_axis {0,1,2}\na_axis_dir {1,0,0}\nb_axis {0,0,-10}\na_axis {0,1,2}\n",
    )
    .unwrap_err();
    assert_eq!(
        e,
        CalibError::IncompleteSeries {
            line: 2,
            missing: "b_axis_dir"
        }
    );
    assert!(e.to_string().contains("line 2"));
    assert_eq!(
        parse_measurements("only a heading\n").unwrap_err(),
        CalibError::NoSeries
    );
    assert_eq!(parse_measurements("").unwrap_err(), CalibError::NoSeries);
}

#[test]
fn zero_or_non_finite_directions_are_named() {
    let mut s = parse_measurements(LISTING_4_1).unwrap()[0].clone();
    s.a_dir = DVec3::ZERO;
    let e = machine_origin(&s, &OriginOptions::default()).unwrap_err();
    assert!(e.to_string().contains("a_axis_dir"), "{e}");
    let mut opts = OriginOptions::default();
    opts.bias.x = f64::NAN;
    let s = parse_measurements(LISTING_4_1).unwrap()[0].clone();
    assert!(machine_origin(&s, &opts).is_err());
}
