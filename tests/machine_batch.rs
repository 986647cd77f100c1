//! Batch kinematics over CSV: round trips for every preset, bit-exact number formatting, and
//! every error case named with its line.

use warpslice::machine::{batch, laws, preset, preset_names, MachineError, MachineSpec};

fn input_for(max_tilt: f64) -> String {
    let mut s = String::from("# px,py,pz,nx,ny,nz\n\n");
    for i in 0..40 {
        let t = (i as f64 * 3.7) % max_tilt.min(60.0);
        let n = laws::axis(t, -170.0 + 23.0 * i as f64);
        s.push_str(&format!(
            "{},{},{},{},{},{}\n",
            10.0 + 0.5 * i as f64,
            20.0 - 0.3 * i as f64,
            5.0 + 0.1 * i as f64,
            n.x,
            n.y,
            n.z
        ));
    }
    s
}

#[test]
fn inverse_then_forward_round_trips_for_every_preset() {
    for name in preset_names() {
        let m = preset(name).and_then(|s| s.build()).unwrap();
        let ws = m.workspace();
        let input = input_for(ws.max_tilt_deg);
        let axes = batch::inverse_csv(m.as_ref(), &input).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(axes.lines().count(), 40, "{name}");
        for line in axes.lines() {
            assert_eq!(line.split(',').count(), m.limits().len());
            // Shortest round-trip formatting: every value parses back to the same f64.
            for f in line.split(',') {
                let v: f64 = f.parse().unwrap();
                assert_eq!(format!("{v}"), f);
            }
        }
        let back = batch::forward_csv(m.as_ref(), &axes).unwrap();
        for (want, got) in input
            .lines()
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .zip(back.lines())
        {
            let w: Vec<f64> = want.split(',').map(|f| f.parse().unwrap()).collect();
            let g: Vec<f64> = got.split(',').map(|f| f.parse().unwrap()).collect();
            let p = glam::DVec3::new(w[0], w[1], w[2]);
            let n = glam::DVec3::new(w[3], w[4], w[5]);
            let realised = m.realised_axis(p, n);
            assert!(
                (glam::DVec3::new(g[0], g[1], g[2]) - p).length() < 1e-9,
                "{name}: {want} -> {got}"
            );
            assert!(
                (glam::DVec3::new(g[3], g[4], g[5]) - realised).length() < 1e-9,
                "{name}: {want} -> {got}"
            );
        }
    }
}

#[test]
fn rotbot_unwraps_across_180_degrees_in_a_batch() {
    let m = preset("rotbot").and_then(|s| s.build()).unwrap();
    let mut input = String::new();
    // tool-axis azimuths 60°…205°: RotBot's U = φ crosses 180°, and so does Slicer4RTN's
    // A = φ + 180° − 90° (its seam, the nozzle opening looking forward, is at φ = 90°)
    for i in 0..30 {
        let n = laws::axis(45.0, 60.0 + 5.0 * i as f64);
        input.push_str(&format!("0,0,1,{},{},{}\n", n.x, n.y, n.z));
    }
    let out = batch::inverse_csv(m.as_ref(), &input).unwrap();
    let u: Vec<f64> = out
        .lines()
        .map(|l| l.split(',').nth(3).unwrap().parse().unwrap())
        .collect();
    for w in u.windows(2) {
        assert!((w[1] - w[0] - 5.0).abs() < 1e-9, "{u:?}");
    }
    assert!(
        u.last().copied().unwrap() > 180.0,
        "unlimited rotation goes past 180: {u:?}"
    );
    // Slicer4RTN (single revolution) wraps instead, and says a rotate-around is needed.
    let s = preset("rtn-slicer4rtn").and_then(|s| s.build()).unwrap();
    let out = batch::inverse_csv(s.as_ref(), &input).unwrap();
    let a: Vec<f64> = out
        .lines()
        .map(|l| l.split(',').nth(3).unwrap().parse().unwrap())
        .collect();
    assert!(a.iter().all(|v| (-180.0..=180.0).contains(v)), "{a:?}");
    assert!(a.windows(2).any(|w| (w[1] - w[0]).abs() > 180.0));
}

#[test]
fn bad_lines_are_named_errors_with_their_line_number() {
    let m = preset("pax-5axis").and_then(|s| s.build()).unwrap();
    let cases = [
        ("0,0,0,0,0,1\n1,2,x,0,0,1\n", 2, "not a finite number"),
        ("0,0,0,0,0,1\n\n1,2,3,0,0\n", 3, "expected 6"),
        ("1,2,3,0,0,2\n", 1, "not a unit vector"),
        ("1,2,3,0,0,NaN\n", 1, "not a finite number"),
        ("1,2,3,0,0,-1\n", 1, "outside its travel"),
    ];
    for (input, line, what) in cases {
        match batch::inverse_csv(m.as_ref(), input) {
            Err(e @ MachineError::BadCsv { .. }) => {
                let MachineError::BadCsv { line: l, .. } = &e else {
                    unreachable!()
                };
                assert_eq!(*l, line, "{e}");
                assert!(e.to_string().contains(what), "{e}");
                assert!(e.to_string().contains(&format!("line {line}")), "{e}");
            }
            other => panic!("{input:?}: {other:?}"),
        }
    }
    match batch::forward_csv(m.as_ref(), "1,2,3,4\n") {
        Err(MachineError::BadCsv { line: 1, message }) => assert!(message.contains("expected 5")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn unreachable_orientations_are_named() {
    let m = preset("open5x-ab").and_then(|s| s.build()).unwrap();
    match batch::inverse_csv(m.as_ref(), "0,0,0,0,0,1\n0,0,0,0.6,0,-0.8\n") {
        Err(MachineError::BadCsv { line: 2, message }) => {
            assert!(message.contains("cannot be reached"), "{message}")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn unknown_presets_list_the_known_ones() {
    match preset("prusa-xl-5axis") {
        Err(e @ MachineError::UnknownPreset { .. }) => {
            let s = e.to_string();
            for n in preset_names() {
                assert!(s.contains(n), "{s}");
            }
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_json_and_bad_specs_are_named() {
    for (json, what) in [
        ("{\"kind\": \"b-head\", \"pivot_to_tip_mm\": }", "invalid"),
        ("{\"kind\": \"warp-drive\"}", "unknown variant"),
        (
            "{\"kind\": \"pax\", \"pivot_to_tip_mm\": \"long\"}",
            "invalid",
        ),
        (
            "{\"kind\": \"pax\", \"pivot_to_tip\": 40}",
            "unknown field 'pivot_to_tip' for kind 'pax'",
        ),
    ] {
        match MachineSpec::from_json(json, "my.json") {
            Err(e @ MachineError::BadJson { .. }) => assert!(
                e.to_string().contains(what) && e.to_string().contains("my.json"),
                "{e}"
            ),
            other => panic!("{json}: {other:?}"),
        }
    }
    for json in [
        r#"{"kind": "rtn", "tilt_deg": 95}"#,
        r#"{"kind": "ab-table", "a_dir": [0, 0, 1], "b_dir": [0, 0, 2]}"#,
        r#"{"kind": "three-z", "balls_xy": [[0, 0], [1, 0], [2, 0]]}"#,
        r#"{"kind": "pax", "axis_names": ["X", "Y", "Z", "A"]}"#,
    ] {
        let spec = MachineSpec::from_json(json, "my.json").unwrap();
        match spec.build() {
            Err(e @ MachineError::BadSpec { .. }) => {
                assert!(e.to_string().contains("fix the machine JSON"), "{e}")
            }
            other => panic!("{json}: {other:?}"),
        }
    }
}

#[test]
fn presets_round_trip_through_json() {
    for name in preset_names() {
        let spec = preset(name).unwrap();
        assert_eq!(spec.name, name);
        let again = MachineSpec::from_json(&spec.to_json(), "again").unwrap();
        assert_eq!(again, spec);
    }
}

#[test]
fn non_finite_axes_are_named_in_forward() {
    let m = preset("lathe-a").and_then(|s| s.build()).unwrap();
    match m.forward(&[0.0, f64::NAN, 0.0]) {
        Err(e @ MachineError::InvalidAxes { .. }) => assert!(e.to_string().contains("finite")),
        other => panic!("{other:?}"),
    }
    match m.forward(&[0.0, 0.0]) {
        Err(MachineError::WrongAxisCount {
            expected: 3,
            got: 2,
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
}

#[test]
fn machine_arguments_are_presets_or_files() {
    let spec = MachineSpec::from_arg("rotbot", |_| Err("no files".into())).unwrap();
    assert_eq!(spec.name, "rotbot");
    let spec = MachineSpec::from_arg("my/pax.json", |p| {
        assert_eq!(p, "my/pax.json");
        Ok(r#"{"kind":"pax","pivot_to_tip_mm":12}"#.into())
    })
    .unwrap();
    assert_eq!(spec.name, "my/pax.json");
    match MachineSpec::from_arg("gone.json", |_| Err("No such file or directory".into())) {
        Err(e @ MachineError::BadJson { .. }) => {
            assert!(e.to_string().contains("gone.json") && e.to_string().contains("No such file"))
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        MachineSpec::from_arg("nonesuch", |_| unreachable!()),
        Err(MachineError::UnknownPreset { .. })
    ));
}
