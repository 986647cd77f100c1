//! The wasm API's error paths (`wasm-pack test --node -- --test wasm_errors`): every exported
//! function driven with bad input throws a JS `Error` whose `.code` is the core's stable code
//! (a code of `describe().errors`, the page's advice key) and whose message names what to fix
//! (the key, value, line or limit at fault). Each refusal is paired with the same call on good
//! input succeeding, so the error is the bad input's and not the fixture's; what the message
//! must name is computed here (line numbers counted in the input, limits read from the machine's
//! own description, angles from the tool axis), not copied from the code under test.
//!
//! wasm only: the glue (`src/wasm.rs`) exists only for wasm32.
#![cfg(target_arch = "wasm32")]

#[path = "common/synthetic.rs"]
mod synthetic;

use warpslice::job::Job;
use warpslice::wasm;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::wasm_bindgen_test as test;

/// The codes of `describe().errors` (plus `options.invalid` and `io.failed`, the glue's own).
fn catalogue() -> Vec<String> {
    let d: serde_json::Value = serde_json::from_str(&wasm::describe().unwrap()).unwrap();
    d["errors"]
        .as_array()
        .expect("describe().errors")
        .iter()
        .map(|e| e["code"].as_str().unwrap().to_string())
        .collect()
}

/// The code and message of a failed call: panics if it succeeded or threw anything but an
/// `Error` with a string `code`.
fn thrown<T>(what: &str, r: Result<T, JsValue>) -> (String, String) {
    let e = match r {
        Ok(_) => panic!("{what}: accepted, should have been refused"),
        Err(e) => e,
    };
    let error = e
        .dyn_ref::<js_sys::Error>()
        .unwrap_or_else(|| panic!("{what}: threw a non-Error {e:?}"));
    let code = js_sys::Reflect::get(&e, &JsValue::from_str("code"))
        .unwrap()
        .as_string()
        .unwrap_or_else(|| panic!("{what}: the Error has no string .code"));
    (code, String::from(error.message()))
}

/// Asserts the call was refused with `code`, a code the core lists, and a message holding each
/// of `names`; returns the message.
fn refused<T>(what: &str, r: Result<T, JsValue>, code: &str, names: &[&str]) -> String {
    let (c, m) = thrown(what, r);
    assert_eq!(c, code, "{what}: the code (message: {m})");
    assert!(
        code == "options.invalid" || catalogue().iter().any(|k| k == code),
        "{what}: {code} is a code of describe().errors"
    );
    for n in names {
        assert!(m.contains(n), "{what}: the message names {n:?}: {m}");
    }
    m
}

fn get(obj: &JsValue, key: &str) -> JsValue {
    js_sys::Reflect::get(obj, &JsValue::from_str(key)).unwrap()
}

const BELT: &str =
    r#"{"warp":{"spec":{"kind":"belt","angle":0.5,"toward":[0,1]},"base":null},"anchor":"off"}"#;

/// A warped example: (warped STL, job JSON, job).
fn warped(example: &str, options: &str) -> (Vec<u8>, String, Job) {
    let stl = wasm::example_stl(example).unwrap();
    let out = wasm::warp(&stl, options).unwrap();
    let warped = js_sys::Uint8Array::new(&get(&out, "stl")).to_vec();
    let job_json = get(&out, "job").as_string().unwrap();
    let job = Job::from_json(&job_json).unwrap();
    (warped, job_json, job)
}

/// `what` inserted after the `n`th `marker`; returns the text and the 1-based line number of
/// the first inserted line.
fn insert_after(g: &str, marker: &str, n: usize, what: &str) -> (String, usize) {
    let mut at = 0;
    for _ in 0..n {
        at += g[at..].find(marker).expect("marker") + marker.len();
    }
    let line = g[..at].matches('\n').count() + 1;
    (format!("{}{what}{}", &g[..at], &g[at..]), line)
}

/// The streaming unwarp as the worker drives it (scan, endScan, push, takeOutput, finish),
/// in 4 kB chunks: the output, or the first error.
fn stream(gcode: &[u8], job: &str, options: &str) -> Result<Vec<u8>, JsValue> {
    let mut s = wasm::UnwarpStream::new(job, options)?;
    for c in gcode.chunks(4096) {
        s.scan(c)?;
    }
    s.end_scan()?;
    let mut out = Vec::new();
    for c in gcode.chunks(4096) {
        s.push(c)?;
        out.extend(s.take_output());
    }
    s.finish()?;
    out.extend(s.take_output());
    Ok(out)
}

// ── warp(stl, optionsJson) ───────────────────────────────────────────────────────────────────

#[test]
fn warp_options_that_are_wrong_are_refused_naming_the_fault() {
    let stl = wasm::example_stl("cube").unwrap();
    wasm::warp(&stl, BELT).expect("the good options warp");

    let bad = r#"{"warp":"#;
    refused(
        "truncated JSON",
        wasm::warp(&stl, bad),
        "options.invalid",
        &[
            "warp options",
            &format!("line 1 column {}", bad.len()),
            "JSON object",
        ],
    );

    // an unknown warp: named, and every warp of describe() offered
    let m = refused(
        "unknown warp",
        wasm::warp(&stl, r#"{"warp":{"spec":{"kind":"spiral"},"base":null}}"#),
        "options.invalid",
        &["`spiral`"],
    );
    let d: serde_json::Value = serde_json::from_str(&wasm::describe().unwrap()).unwrap();
    let warps: Vec<&str> = d["warps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["name"].as_str().unwrap())
        .collect();
    assert!(warps.len() >= 6, "{warps:?}");
    for w in &warps {
        assert!(m.contains(&format!("`{w}`")), "offers {w}: {m}");
    }

    // a parameter past its limit: the limit is describe()'s
    let conic = d["warps"]
        .as_array()
        .unwrap()
        .iter()
        .find(|w| w["name"] == "conic")
        .unwrap();
    let angle = conic["params"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["key"] == "angle")
        .unwrap();
    let max = angle["max"].as_f64().expect("conic angle max");
    wasm::warp(
        &stl,
        &format!(
            r#"{{"warp":{{"spec":{{"kind":"conic","angle":{}}},"base":null}}}}"#,
            max - 1.0
        ),
    )
    .expect("an angle under the limit warps");
    refused(
        "conic angle past its limit",
        wasm::warp(
            &stl,
            &format!(
                r#"{{"warp":{{"spec":{{"kind":"conic","angle":{}}},"base":null}}}}"#,
                max + 5.0
            ),
        ),
        "warp.bad-parameter",
        &[&format!("angle = {}", max + 5.0), &format!("{max}")],
    );

    refused(
        "negative max_edge",
        wasm::warp(
            &stl,
            r#"{"warp":{"spec":{"kind":"conic","angle":30},"base":null},"max_edge":-1}"#,
        ),
        "options.invalid",
        &["max-edge = -1", "positive"],
    );
    refused(
        "--base on the cylindrical warp",
        wasm::warp(
            &stl,
            r#"{"warp":{"spec":{"kind":"cylindrical","radius":20},"base":[1,2]}}"#,
        ),
        "warp.base-not-supported",
        &["cylindrical", "--base"],
    );
    // an inward cone of 60° over a 1 mm blend folds the layers; outward it does not
    wasm::warp(
        &stl,
        r#"{"warp":{"spec":{"kind":"conic","angle":60,"direction":"outward"},"base":[0,1]}}"#,
    )
    .expect("outward with a base warps");
    let m = refused(
        "a base blend that folds the layers",
        wasm::warp(
            &stl,
            r#"{"warp":{"spec":{"kind":"conic","angle":60,"direction":"inward"},"base":[0,1]}}"#,
        ),
        "warp.not-monotonic",
        &["--base 0,1", "largest allowed angle"],
    );
    // the largest allowed angle it names is allowed, and just past it is not
    let largest: f64 = m
        .split("largest allowed angle for this model and base is ")
        .nth(1)
        .and_then(|t| t.split(|c: char| c == ';' || c.is_whitespace()).next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("a number after 'largest allowed angle': {m}"));
    assert!(largest > 0.0 && largest < 60.0, "{largest}");
    let with = |a: f64| {
        format!(
            r#"{{"warp":{{"spec":{{"kind":"conic","angle":{a},"direction":"inward"}},"base":[0,1]}}}}"#
        )
    };
    wasm::warp(&stl, &with(largest * 0.98)).expect("the named largest angle (less 2 %) warps");
    refused(
        "just past the named largest angle",
        wasm::warp(&stl, &with(largest * 1.1)),
        "warp.not-monotonic",
        &[],
    );
}

#[test]
fn a_bad_stl_is_refused_by_warp_and_stl_report_naming_the_fault() {
    let good = wasm::example_stl("cube").unwrap();
    assert_eq!(good.len(), 84 + 50 * 12);
    wasm::stl_report(&good).expect("the good STL reads");
    // binary with a NaN coordinate
    let mut nan = good.clone();
    nan[84 + 12..84 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
    // binary whose face count is larger than its size
    let mut count = good.clone();
    count[80..84].copy_from_slice(&13u32.to_le_bytes());
    let ascii = b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zz\n".to_vec();
    let cases: Vec<(&str, Vec<u8>, &str, Vec<String>)> = vec![
        ("empty", vec![], "mesh.empty", vec!["0 bytes".into()]),
        (
            "truncated",
            good[..200].to_vec(),
            "mesh.truncated",
            vec![format!("{}", good.len()), "200".into()],
        ),
        (
            "face count past the end",
            count,
            "mesh.face-count",
            vec!["13".into()],
        ),
        ("NaN coordinate", nan, "mesh.non-finite", vec![]),
        (
            "ASCII syntax",
            ascii,
            "mesh.syntax",
            vec!["line 4".into(), "`zz`".into()],
        ),
    ];
    for (what, bytes, code, names) in cases {
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let a = refused(
            &format!("stl_report: {what}"),
            wasm::stl_report(&bytes),
            code,
            &names,
        );
        let b = refused(
            &format!("warp: {what}"),
            wasm::warp(&bytes, BELT),
            code,
            &names,
        );
        assert!(a.starts_with("STL") && b.starts_with("STL"), "{a} | {b}");
    }
    refused(
        "an unknown example",
        wasm::example_stl("dodecahedron"),
        "options.invalid",
        &["'dodecahedron'", "cube", "cylinder", "sphere", "overhang"],
    );
}

// ── unwarp / UnwarpStream ───────────────────────────────────────────────────────────────────

#[test]
fn gcode_that_cannot_be_unwarped_is_refused_by_both_unwarp_paths() {
    let (stl, job_json, job) = warped("cube", BELT);
    let g = synthetic::gcode(&job, true, 2.0);
    let whole = wasm::unwarp(g.as_bytes(), &job_json, "{}").expect("the clean G-code unwarps");
    let streamed = stream(g.as_bytes(), &job_json, "{}").expect("and streams");
    assert_eq!(
        js_sys::Uint8Array::new(&get(&whole, "gcode")).to_vec(),
        streamed
    );

    // G91 in the region, on a line we count; G91 … G90 in the start G-code is fine
    let (g91, line) = insert_after(
        &g,
        ";LAYER_CHANGE\n",
        3,
        "G91\nG1 Z1 F600\nG1 Z-1 F600\nG90\nM83\n",
    );
    assert!(g91.lines().nth(line - 1) == Some("G91"));
    let (ok, _) = insert_after(&g, "G28\n", 1, "G91\nG1 Z5 F600\nG90\n");
    wasm::unwarp(ok.as_bytes(), &job_json, "{}").expect("G91 before the region is fine");
    let (g20, line20) = insert_after(&g, ";LAYER_CHANGE\n", 3, "G20\nG21\n");
    assert!(g20.lines().nth(line20 - 1) == Some("G20"));
    let (ok20, _) = insert_after(&g, "G28\n", 1, "G20\n");
    wasm::unwarp(ok20.as_bytes(), &job_json, "{}").expect("G20 then G21 before the region");

    // issue 12 item 1: homing Z inside the region (the nozzle or the probe goes down where
    // the part stands)
    let (g28, line28) = insert_after(&g, ";LAYER_CHANGE\n", 3, "G28\n");
    assert!(g28.lines().nth(line28 - 1) == Some("G28"));

    // the G-code of another job (the overhang block with the same warp)
    let (_, _, other) = warped("overhang", BELT);
    let foreign = synthetic::gcode(&other, true, 2.0);

    let cases = [
        (
            "G91 in the region",
            g91.as_str(),
            "unwarp.relative-positioning",
            vec![
                format!("G-code line {line}:"),
                "G91".into(),
                "absolute".into(),
            ],
        ),
        (
            "G20 in the region",
            g20.as_str(),
            "unwarp.inches",
            vec![
                format!("G-code line {line20}:"),
                "G20".into(),
                "millimetres".into(),
            ],
        ),
        (
            "G28 in the region",
            g28.as_str(),
            "unwarp.probe-in-region",
            vec![
                format!("G-code line {line28}:"),
                "G28".into(),
                "start G-code".into(),
            ],
        ),
        (
            "another job's G-code",
            foreign.as_str(),
            "register.mismatch",
            vec![],
        ),
        (
            "no object extrusions",
            "G28\nG1 X10 Y10 Z0.2 F1200\n",
            "register.no-object-extrusions",
            vec!["object extrusions".into()],
        ),
    ];
    for (what, gcode, code, names) in &cases {
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let a = refused(
            &format!("unwarp: {what}"),
            wasm::unwarp(gcode.as_bytes(), &job_json, "{}"),
            code,
            &names,
        );
        let b = refused(
            &format!("UnwarpStream: {what}"),
            stream(gcode.as_bytes(), &job_json, "{}"),
            code,
            &names,
        );
        assert_eq!(a, b, "{what}: the same message both ways");
    }

    // the warped STL of another job, given to the stream of this one
    let (other_stl, _, _) = warped("overhang", BELT);
    let mut s = wasm::UnwarpStream::new(&job_json, "{}").unwrap();
    s.set_warped_stl(&stl).expect("this job's own STL");
    let mut s = wasm::UnwarpStream::new(&job_json, "{}").unwrap();
    refused(
        "another job's warped STL",
        s.set_warped_stl(&other_stl),
        "job.stl-mismatch",
        &[&job.hash, "warped STL"],
    );

    // calls out of order
    let mut s = wasm::UnwarpStream::new(&job_json, "{}").unwrap();
    refused(
        "push before endScan",
        s.push(g.as_bytes()),
        "unwarp.order",
        &["end_scan"],
    );
    refused(
        "finish before endScan",
        s.finish(),
        "unwarp.order",
        &["end_scan"],
    );
}

#[test]
fn a_bad_job_or_bad_unwarp_options_are_refused_naming_the_fault() {
    let (_, job_json, job) = warped("cube", BELT);
    let g = synthetic::gcode(&job, true, 2.0);
    let edited = job_json.replacen("\"layer_height\": 0.2", "\"layer_height\": 0.3", 1);
    assert_ne!(edited, job_json);
    let jobs = [
        ("not JSON", "{".to_string(), "job.parse", vec!["not valid"]),
        (
            "not a job",
            "{}".to_string(),
            "job.parse",
            vec!["missing field `version`"],
        ),
        (
            "edited",
            edited,
            "job.hash",
            vec![job.hash.as_str(), "warp the model again"],
        ),
    ];
    for (what, j, code, names) in &jobs {
        refused(
            &format!("unwarp, job {what}"),
            wasm::unwarp(g.as_bytes(), j, "{}"),
            code,
            names,
        );
        refused(
            &format!("UnwarpStream, job {what}"),
            wasm::UnwarpStream::new(j, "{}"),
            code,
            names,
        );
        refused(
            &format!("layer_surfaces, job {what}"),
            wasm::layer_surfaces(j, 5, 16),
            code,
            names,
        );
    }

    let tol = r#"{"tolerance":"x"}"#;
    let flavour = r#"{"flavour":"grbl"}"#;
    let opts = [
        (
            "a string for a number",
            tol,
            "options.invalid",
            // (serde reads the flattened options as one map: the position is the map's end)
            vec![
                "unwarp options".to_string(),
                "string \"x\"".into(),
                "expected f64".into(),
            ],
        ),
        (
            "an unknown flavour",
            flavour,
            "options.invalid",
            vec![
                "`grbl`".to_string(),
                "`reprapfirmware`".into(),
                "`marlin`".into(),
                "`klipper`".into(),
            ],
        ),
        (
            "a negative tolerance",
            r#"{"tolerance":-1}"#,
            "unwarp.option",
            vec!["tolerance = -1".to_string(), "positive".into()],
        ),
    ];
    wasm::unwarp(
        g.as_bytes(),
        &job_json,
        r#"{"tolerance":0.02,"flavour":"marlin"}"#,
    )
    .expect("good options unwarp");
    for (what, o, code, names) in &opts {
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        refused(
            &format!("unwarp: {what}"),
            wasm::unwarp(g.as_bytes(), &job_json, o),
            code,
            &names,
        );
        refused(
            &format!("UnwarpStream: {what}"),
            wasm::UnwarpStream::new(&job_json, o),
            code,
            &names,
        );
    }
}

// ── machines ────────────────────────────────────────────────────────────────────────────────

fn presets() -> Vec<String> {
    let v: serde_json::Value = serde_json::from_str(&wasm::machine_presets().unwrap()).unwrap();
    v.as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn an_unknown_machine_is_refused_with_its_code_by_every_function_that_takes_one() {
    let (_, job_json, job) = warped("cube", BELT);
    let g = synthetic::gcode(&job, true, 2.0);
    let point = [10.0, 0.0, 5.0, 0.0, 0.0, 1.0];
    wasm::machine_axes("pax-5axis", &point).expect("a known preset");
    wasm::unwarp(g.as_bytes(), &job_json, r#"{"machine":"pax-5axis"}"#)
        .expect("a known preset unwarps");
    let names = presets();
    assert!(names.len() >= 9, "{names:?}");
    let mut want: Vec<&str> = vec!["'warp-9000'"];
    want.extend(names.iter().map(String::as_str));
    let opts = r#"{"machine":"warp-9000"}"#;
    let calls: Vec<(&str, Result<(), JsValue>)> = vec![
        (
            "describe_machine",
            wasm::describe_machine("warp-9000").map(drop),
        ),
        (
            "machine_axes",
            wasm::machine_axes("warp-9000", &point).map(drop),
        ),
        (
            "machine_view",
            wasm::machine_view("warp-9000", &point).map(drop),
        ),
        (
            "unwarp",
            wasm::unwarp(g.as_bytes(), &job_json, opts).map(drop),
        ),
        (
            "UnwarpStream",
            wasm::UnwarpStream::new(&job_json, opts).map(drop),
        ),
        (
            "calibrate_test_print",
            wasm::calibrate_test_print("warp-9000", "integrated", "").map(drop),
        ),
        (
            "calibrate_simulate (truth)",
            wasm::calibrate_simulate("", "warp-9000", "", "", "integrated", 1.0).map(drop),
        ),
    ];
    for (what, r) in calls {
        refused(what, r, "machine.unknown-preset", &want);
    }

    // a machine JSON with a misspelt parameter: named, with the fields the kind knows
    let bad = r#"{"name":"x","kind":"pax","axis_names":["X","Y","Z","A","B"],"pivot_to_tip_mm":0,"rot_offset_deg":-90,"max_tilt_deg":90,"pivot_to_tipmm":1}"#;
    let good = bad.replace(r#","pivot_to_tipmm":1"#, "");
    wasm::describe_machine(&good).expect("the good machine JSON");
    let names = ["'pivot_to_tipmm'", "pivot_to_tip_mm", "rot_offset_deg"];
    refused(
        "describe_machine, misspelt",
        wasm::describe_machine(bad),
        "machine.bad-json",
        &names,
    );
    refused(
        "unwarp, misspelt machine object",
        wasm::unwarp(g.as_bytes(), &job_json, &format!(r#"{{"machine":{bad}}}"#)),
        "machine.bad-json",
        &names,
    );
    refused(
        "unwarp, a machine that is a number",
        wasm::unwarp(g.as_bytes(), &job_json, r#"{"machine":5}"#),
        "options.invalid",
        &["machine", "preset name or a machine object", "5"],
    );
    // Klipper has no G93
    refused(
        "klipper with inverse time",
        wasm::unwarp(
            g.as_bytes(),
            &job_json,
            r#"{"machine":"pax-5axis","flavour":"klipper","feed":"inverse-time"}"#,
        ),
        "machine.unsupported-flavour",
        &["pax-5axis", "klipper", "has no G93", "--feed tip"],
    );
    wasm::unwarp(
        g.as_bytes(),
        &job_json,
        r#"{"machine":"cartesian","flavour":"klipper"}"#,
    )
    .expect("klipper on the cartesian machine");
}

/// The machine's own description: (min, max) of axis `name`, and its spec.
fn machine_limits(machine: &str, name: &str) -> ((f64, f64), serde_json::Value) {
    let d: serde_json::Value =
        serde_json::from_str(&wasm::describe_machine(machine).unwrap()).unwrap();
    let a = d["axes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["name"] == name)
        .unwrap_or_else(|| panic!("{machine} has an axis {name}"));
    (
        (
            a["min"].as_f64().unwrap_or(f64::NEG_INFINITY),
            a["max"].as_f64().unwrap_or(f64::INFINITY),
        ),
        d["spec"].clone(),
    )
}

#[test]
fn a_pose_the_machine_cannot_take_is_refused_with_the_limit_of_its_file() {
    // pax-5axis: n = (sin B cos φ, sin B sin φ, cos B) (docs/machines.md), so a tool axis 120°
    // from +Z needs |B| = 120°, past the B travel the machine describes
    let ((bmin, bmax), _) = machine_limits("pax-5axis", "B");
    let tilt = |deg: f64| {
        let r = deg.to_radians();
        [10.0, 0.0, 5.0, 0.0, r.sin(), r.cos()]
    };
    assert!(bmax < 120.0 && bmin > -120.0);
    let inside = wasm::machine_axes("pax-5axis", &tilt(bmax - 1.0)).expect("inside the travel");
    assert!((inside[4].abs() - (bmax - 1.0)).abs() < 1e-9, "{inside:?}");
    refused(
        "pax-5axis tilted 120°",
        wasm::machine_axes("pax-5axis", &tilt(120.0)),
        "machine.axis-limit",
        &[
            "pax-5axis",
            "axis B = 120.0",
            &format!("[{bmin}, {bmax}]"),
            "point (10.0000, 0.0000, 5.0000)",
        ],
    );
    refused(
        "machine_view, pax-5axis tilted 120°",
        wasm::machine_view("pax-5axis", &tilt(120.0)),
        "machine.axis-limit",
        &["axis B = 120.0"],
    );

    // ratrig-vcore3-3z: the bed tilts at most max_tilt_deg of its file
    let (_, spec) = machine_limits("ratrig-vcore3-3z", "X");
    let max = spec["max_tilt_deg"].as_f64().expect("max_tilt_deg");
    let lean = |deg: f64| {
        let r = deg.to_radians();
        [10.0, 0.0, 5.0, r.sin(), 0.0, r.cos()]
    };
    wasm::machine_axes("ratrig-vcore3-3z", &lean(max - 1.0)).expect("inside its tilt");
    refused(
        "ratrig tilted past its limit",
        wasm::machine_axes("ratrig-vcore3-3z", &lean(max + 15.0)),
        "machine.unreachable-orientation",
        &[
            &format!("tilt {:.3}°", max + 15.0),
            &format!("max_tilt_deg = {max}°"),
        ],
    );

    // the same refusal through the unwarp: a belt of max + 10° on that machine names the
    // G-code line of a move in the printed region
    let belt = format!(
        r#"{{"warp":{{"spec":{{"kind":"belt","angle":{},"toward":[0,1]}},"base":null}},"anchor":"off"}}"#,
        max + 10.0
    );
    let (_, job_json, job) = warped("cube", &belt);
    let g = synthetic::gcode(&job, true, 2.0);
    // (reach is tested here; the default head meets this belt's synthetic layers)
    wasm::unwarp(
        g.as_bytes(),
        &job_json,
        r#"{"machine":"pax-5axis","allow_collisions":true}"#,
    )
    .expect("a machine that reaches the belt's tilt");
    let m = refused(
        "unwarp on ratrig past its tilt",
        wasm::unwarp(g.as_bytes(), &job_json, r#"{"machine":"ratrig-vcore3-3z"}"#),
        "machine.unreachable-orientation",
        &[
            &format!("tilt {:.3}°", max + 10.0),
            &format!("max_tilt_deg = {max}°"),
        ],
    );
    let line: usize = m
        .strip_prefix("G-code line ")
        .and_then(|t| t.split(':').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("names the G-code line: {m}"));
    let text = g.lines().nth(line - 1).unwrap();
    assert!(
        text.starts_with("G1 X") && text.contains(" E"),
        "line {line} is an extrusion: {text}"
    );

    // input that is not points
    for (what, pts, names) in [
        (
            "5 numbers",
            vec![10.0, 0.0, 5.0, 0.0, 0.0],
            vec!["5 numbers", "6 per point"],
        ),
        (
            "7 numbers",
            vec![10.0, 0.0, 5.0, 0.0, 0.0, 1.0, 3.0],
            vec!["7 numbers", "6 per point"],
        ),
    ] {
        refused(
            &format!("machine_axes: {what}"),
            wasm::machine_axes("pax-5axis", &pts),
            "machine.bad-csv",
            &names,
        );
        refused(
            &format!("machine_view: {what}"),
            wasm::machine_view("pax-5axis", &pts),
            "machine.bad-csv",
            &names,
        );
    }
    refused(
        "a zero tool axis",
        wasm::machine_axes("pax-5axis", &[10.0, 0.0, 5.0, 0.0, 0.0, 0.0]),
        "machine.invalid-input",
        &["tool axis (0, 0, 0)"],
    );
}

// ── calibration ─────────────────────────────────────────────────────────────────────────────

/// Listing 4.1 of seed 004 (as tests/calibrate_wasm.rs).
const LISTING_4_1: &str = "ab_values\na_axis {0,-0.1650009,-0.2140012}\na_z_in_y 0.0030937\na_axis_dir {0.9994476,0.0332315,-0.0004059}\nb_axis {-0.1399994,0.0900002,-10}\nb_axis_dir {0.0010010,0.0059996,0.9999815}\n";

#[test]
fn bad_calibration_input_is_refused_naming_the_fault() {
    wasm::calibrate_origin(LISTING_4_1, "", "").expect("Listing 4.1 calibrates");
    let bad_number = LISTING_4_1.replace("{0,-0.1650009", "{0,x");
    let incomplete = LISTING_4_1.replace("a_axis_dir {0.9994476,0.0332315,-0.0004059}\n", "");
    let parallel = LISTING_4_1.replace(
        "b_axis_dir {0.0010010,0.0059996,0.9999815}",
        "b_axis_dir {0.9994476,0.0332315,-0.0004059}",
    );
    let origin = [
        (
            "a number that is not",
            bad_number.as_str(),
            "",
            "",
            "calibrate.bad-line",
            vec!["line 2", "'x'", "a_axis {0,x,-0.2140012}"],
        ),
        (
            "no series",
            "hello\n",
            "",
            "",
            "calibrate.no-series",
            vec!["a_axis", "b_axis_dir"],
        ),
        (
            "a series without a_axis_dir",
            incomplete.as_str(),
            "",
            "",
            "calibrate.incomplete-series",
            vec!["line 2", "'a_axis_dir'"],
        ),
        (
            "parallel axes",
            parallel.as_str(),
            "",
            "",
            "calibrate.parallel-axes",
            vec!["parallel", "a_axis_dir and b_axis_dir"],
        ),
        (
            "bad options",
            LISTING_4_1,
            r#"{"bias":3}"#,
            "",
            "options.invalid",
            vec!["origin options", "`3`", "line 1 column 9"],
        ),
        (
            "an unknown machine",
            LISTING_4_1,
            "",
            "warp-9000",
            "machine.unknown-preset",
            vec!["'warp-9000'", "open5x-ab"],
        ),
        (
            "a machine that is not an A/B table",
            LISTING_4_1,
            "",
            "pax-5axis",
            "calibrate.bad-input",
            vec!["pax-5axis", "ab-table"],
        ),
    ];
    for (what, text, opts, machine, code, names) in &origin {
        refused(
            &format!("calibrate_origin: {what}"),
            wasm::calibrate_origin(text, opts, machine),
            code,
            names,
        );
    }

    let good = r#"{"kind":"a-pos","z0":-5,"y90":4.2,"y_minus90":-3.8,"c_y":0.453}"#;
    wasm::calibrate_probe(good).expect("the good probe input");
    let probes = [
        (
            "truncated JSON",
            r#"{"kind":"a-pos""#,
            "options.invalid",
            vec!["probe input"],
        ),
        (
            "a missing value",
            r#"{"kind":"a-pos","z0":-5}"#,
            "options.invalid",
            vec!["missing field `y90`"],
        ),
        (
            "an unknown kind",
            r#"{"kind":"c-pos"}"#,
            "options.invalid",
            vec![
                "`c-pos`",
                "`a-pos-error`",
                "`a-pos`",
                "`a-dir`",
                "`b-pos`",
                "`b-dir`",
                "`z-bias`",
                "`a-scaling`",
                "`wobble`",
            ],
        ),
        (
            "A scaling past the probe distance",
            r#"{"kind":"a-scaling","z1":0,"z2":5,"distance":2}"#,
            "calibrate.bad-input",
            vec!["A scaling", "= 5", "distance 2"],
        ),
        (
            "a zero probe spacing",
            r#"{"kind":"a-dir","z_x":[0,0],"d_zx":0,"z_y":[0,0],"d_zy":1,"y_x1":[0,0],"y_x2":[0,0],"d_yx":1}"#,
            "calibrate.bad-input",
            vec!["d_zx", "non-zero"],
        ),
        (
            "no probed values",
            r#"{"kind":"z-bias","z90":[],"z_minus90":[1],"d_f":1}"#,
            "calibrate.bad-input",
            vec!["z90", "at least one"],
        ),
    ];
    for (what, input, code, names) in &probes {
        refused(
            &format!("calibrate_probe: {what}"),
            wasm::calibrate_probe(input),
            code,
            names,
        );
    }
    wasm::calibrate_probe(r#"{"kind":"a-scaling","z1":0,"z2":1,"distance":2}"#)
        .expect("A scaling within the distance");

    let kinds = [
        "a-position",
        "a-orientation",
        "b-position",
        "b-orientation",
        "integrated",
    ];
    let mut want = vec!["'spiral'"];
    want.extend(kinds);
    refused(
        "calibrate_test_print: an unknown kind",
        wasm::calibrate_test_print("", "spiral", ""),
        "calibrate.bad-input",
        &want,
    );
    refused(
        "calibrate_simulate: an unknown kind",
        wasm::calibrate_simulate("", "", "", "", "spiral", 1.0),
        "calibrate.bad-input",
        &want,
    );
    refused(
        "calibrate_simulate: a toolpath line of three numbers",
        wasm::calibrate_simulate("", "", "", "0,0,5,0,0,1\n1,2,3\n", "", 1.0),
        "calibrate.bad-input",
        &["line 2", "'1,2,3'", "six numbers"],
    );
    refused(
        "calibrate_simulate: a bad deviation",
        wasm::calibrate_simulate("", "", r#"{"a_rot_z_deg":"x"}"#, "", "integrated", 1.0),
        "options.invalid",
        &["deviation", "\"x\""],
    );
    refused(
        "calibrate_b_position_svg: NaN",
        wasm::calibrate_b_position_svg("", f64::NAN, 0.0, "", 1.0),
        "calibrate.bad-input",
        &["B offset", "NaN", "finite"],
    );
    assert!((wasm::calibrate_fig_3_1(20.0, 2.0).unwrap() - 0.698).abs() < 1e-3);
    refused(
        "calibrate_fig_3_1: NaN radius",
        wasm::calibrate_fig_3_1(f64::NAN, 2.0),
        "calibrate.bad-input",
        &["radius", "NaN"],
    );
    refused(
        "calibrate_fig_3_1: infinite angle",
        wasm::calibrate_fig_3_1(20.0, f64::INFINITY),
        "calibrate.bad-input",
        &["aRotZDeg", "inf"],
    );
}

// ── warnings in the report ──────────────────────────────────────────────────────────────────

/// The `warnings` array of a report object (its strings).
fn warnings(report: &JsValue) -> Vec<String> {
    let w = get(report, "warnings");
    js_sys::Array::from(&w)
        .iter()
        .map(|v| v.as_string().expect("a warning is a string"))
        .collect()
}

/// Issue 12 item 10 in the browser: a G-code cut short is unwarped, and the report of both
/// unwarp paths (`unwarp`, `UnwarpStream.finish`) says so; the whole file's says nothing.
#[test]
fn a_truncated_gcode_is_unwarped_with_a_warning_in_the_report() {
    let (_, job_json, job) = warped("cube", BELT);
    let g = synthetic::gcode(&job, true, 2.0);
    let whole = wasm::unwarp(g.as_bytes(), &job_json, "{}").unwrap();
    assert!(warnings(&get(&whole, "report")).is_empty());
    // the cut file's top is lower than the mesh's: place it where the whole file was found
    let t = js_sys::Array::from(&get(&get(&whole, "report"), "translation"));
    let (dx, dy) = (t.get(0).as_f64().unwrap(), t.get(1).as_f64().unwrap());
    let opts = format!(r#"{{"offset":[{dx},{dy}]}}"#);
    // cut in the middle of a line of its last layers: no line end, no end G-code
    let at = g.len() * 9 / 10;
    let at = at + g[at..].find("G1 X").unwrap() + 5;
    let cut = &g[..at];
    let last = cut.matches('\n').count() + 1;
    let whole = wasm::unwarp(cut.as_bytes(), &job_json, &opts).expect("a cut file still unwarps");
    let mut s = wasm::UnwarpStream::new(&job_json, &opts).unwrap();
    for c in cut.as_bytes().chunks(4096) {
        s.scan(c).unwrap();
    }
    s.end_scan().unwrap();
    for c in cut.as_bytes().chunks(4096) {
        s.push(c).unwrap();
        s.take_output();
    }
    let streamed = s.finish().unwrap();
    for (how, report) in [
        ("unwarp", get(&whole, "report")),
        ("UnwarpStream", streamed),
    ] {
        let w = warnings(&report);
        assert_eq!(w.len(), 2, "{how}: {w:?}");
        assert!(
            w[0].contains(&format!("last line ({last}) has no line end")),
            "{how}: {w:?}"
        );
        assert!(w[1].contains("ends the print"), "{how}: {w:?}");
    }
}

/// Issue 12 in the browser: two copies of the object are refused as
/// `register.more-than-the-model` naming two objects and the fix; Bambu/Orca `; FEATURE:`
/// labels are read; `;WARPSLICE_BEGIN` after the first layers is a warning in the report.
#[test]
fn two_objects_labels_and_markers_are_named_in_the_browser() {
    let (_, job_json, job) = warped("cube", BELT);
    let g = synthetic::gcode(&job, true, 2.0);
    // every layer printed again 26 mm to the right
    let mut two = String::new();
    for (i, layer) in g.split(";LAYER_CHANGE\n").enumerate() {
        if i > 0 {
            two.push_str(";LAYER_CHANGE\n");
        }
        two.push_str(layer);
        if i > 0 {
            two.push_str(&synthetic::shifted(layer, 26.0, 0.0));
        }
    }
    refused(
        "two copies",
        stream(two.as_bytes(), &job_json, "{}"),
        "register.more-than-the-model",
        &["2 objects", "one object per file"],
    );
    let orca = g
        .replace(";TYPE:External perimeter", "; FEATURE: Outer wall")
        .replace(";TYPE:Internal infill", "; FEATURE: Sparse infill")
        .replace(";TYPE:Skirt/Brim", "; FEATURE: Skirt");
    assert!(stream(orca.as_bytes(), &job_json, "{}").is_ok());
    let whole = wasm::unwarp(g.as_bytes(), &job_json, "{}").unwrap();
    let t = js_sys::Array::from(&get(&get(&whole, "report"), "translation"));
    let opts = format!(
        r#"{{"offset":[{},{}]}}"#,
        t.get(0).as_f64().unwrap(),
        t.get(1).as_f64().unwrap()
    );
    let (late, _) = insert_after(&g, ";LAYER_CHANGE\n", 3, ";WARPSLICE_BEGIN\n");
    let out = wasm::unwarp(late.as_bytes(), &job_json, &opts).unwrap();
    let w = warnings(&get(&out, "report"));
    assert!(
        w.iter()
            .any(|x| x.contains("object extrusions lie outside the ;WARPSLICE_BEGIN")),
        "{w:?}"
    );
}
