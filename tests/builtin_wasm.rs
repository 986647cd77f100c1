//! The wasm export of the built-in slicer, `BuiltinSlice` (what the web worker steps, one layer
//! per `step()`): stepped to the end it writes the planar G-code whose hash
//! `tests/golden/planar_parity.txt` recorded natively for the same part, warp and settings; its
//! progress counts up by one per step to twice its layer count; bad settings are refused with
//! the core's codes (`wasm-pack test --node -- --test builtin_wasm`).
//!
//! wasm only: the glue (`src/wasm.rs`) exists only for wasm32.
#![cfg(target_arch = "wasm32")]

#[path = "common/acceptance.rs"]
mod acceptance;

use warpslice::job::fnv1a64;
use warpslice::pipeline::{warp_model, WarpOptions};
use warpslice::wasm;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::wasm_bindgen_test as test;

const GOLDEN: &str = include_str!("golden/planar_parity.txt");

fn get(v: &JsValue, key: &str) -> JsValue {
    js_sys::Reflect::get(v, &JsValue::from_str(key)).unwrap()
}

fn code_of(e: JsValue) -> (String, String) {
    let code = get(&e, "code").as_string().expect("a string .code");
    let message = String::from(e.dyn_ref::<js_sys::Error>().expect("an Error").message());
    (code, message)
}

/// The sphere example warped by the acceptance warp `name`: (warped STL, job JSON).
fn warped(name: &str) -> (Vec<u8>, String) {
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("sphere").unwrap(), "sphere");
    let (_, params) = acceptance::acceptance_warps()
        .into_iter()
        .find(|(n, _)| *n == name)
        .unwrap();
    let w = warp_model(&stl, &WarpOptions::new(params)).unwrap();
    (w.stl, w.job.to_json_pretty())
}

#[test]
fn stepped_to_the_end_it_writes_the_natively_recorded_planar_gcode() {
    for (warp, rel) in [("conic-out-30", true), ("curved-out-0.3", false)] {
        let (stl, job) = warped(warp);
        let settings = if rel {
            ""
        } else {
            r#"{"use_relative_e_distances": false}"#
        };
        let mut s = wasm::BuiltinSlice::new(&stl, &job, settings).unwrap();
        let mut done = 0.0;
        let (total, layers) = loop {
            let p = s.step().unwrap();
            let d = get(&p, "done").as_f64().unwrap();
            assert_eq!(d, done + 1.0, "{warp}: one step at a time");
            done = d;
            let (t, l) = (
                get(&p, "total").as_f64().unwrap(),
                get(&p, "layers").as_f64().unwrap(),
            );
            if d >= t {
                break (t, l);
            }
        };
        assert_eq!(total, 2.0 * layers);
        let out = s.finish().unwrap();
        let gcode = js_sys::Uint8Array::new(&get(&out, "gcode")).to_vec();
        let report = get(&out, "report");
        assert_eq!(get(&report, "layers").as_f64(), Some(layers));
        let want = GOLDEN
            .lines()
            .find(|l| {
                l.starts_with(&format!(
                    "sphere {warp} {} ",
                    if rel { "rel" } else { "abs" }
                ))
            })
            .and_then(|l| l.split_whitespace().nth(3))
            .unwrap();
        assert_eq!(format!("{:016x}", fnv1a64(&gcode)), want, "sphere × {warp}");
        // spent: a second finish is a named error
        let (code, _) = code_of(s.finish().err().unwrap());
        assert_eq!(code, "options.invalid");
    }
}

#[test]
fn bad_settings_are_refused_with_the_cores_codes() {
    let (stl, job) = warped("conic-out-30");
    assert!(wasm::BuiltinSlice::new(&stl, &job, r#"{"fill_density": 35}"#).is_ok());
    for (settings, code, names) in [
        (
            r#"{"fill_densty": 35}"#,
            "planar.settings-json",
            vec!["fill_densty"],
        ),
        (
            r#"{"fill_density": 135}"#,
            "planar.setting",
            vec!["fill_density", "135"],
        ),
        (
            r#"{"layer_height": 0.3}"#,
            "planar.layer-height",
            vec!["layer_height", "0.3"],
        ),
        ("[1, 2]", "planar.settings-json", vec!["JSON object"]),
    ] {
        let (c, m) = code_of(wasm::BuiltinSlice::new(&stl, &job, settings).err().unwrap());
        assert_eq!(c, code, "{settings}: {m}");
        for n in names {
            assert!(m.contains(n), "{settings}: the message names {n}: {m}");
        }
    }
    let (c, _) = code_of(wasm::BuiltinSlice::new(&stl, "{}", "").err().unwrap());
    assert_eq!(c, "job.parse");
}
