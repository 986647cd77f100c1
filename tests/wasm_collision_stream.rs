//! The browser's streaming unwarp judges its output with the core's collision check
//! (`wasm-pack test --node -- --test wasm_collision_stream`): `UnwarpStream`, driven as the web
//! worker drives it (4 kB chunks, `takeOutput` after every push), writes with
//! `allow_collisions` the one-shot `unwarp`'s bytes with every finding listed at the end and in
//! the report's `machine.collisions`, and without it throws the one-shot's `machine.collision`
//! error, message for message. The case is tests/collision_stream.rs's: the synthetic 16 mm
//! cube (infill lines 4 mm apart) warped conic 30° outward on the cartesian preset, whose
//! default heater block meets the cone's rising layers. The listed findings are counted against a fresh whole-file walk of the
//! written body (`collision::check_gcode`), not the stream's own walker and verdict.
//!
//! wasm only: the glue (`src/wasm.rs`) exists only for wasm32.
#![cfg(target_arch = "wasm32")]

#[path = "common/synthetic.rs"]
mod synthetic;

use warpslice::wasm;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::wasm_bindgen_test as test;

/// The worker's slice size is 4 MB; smaller here so the case is cut into many chunks.
const CHUNK: usize = 4096;

/// The first characters of every finding comment at the end of an `allow_collisions` file.
const LISTED: &str = "; warpslice collision: line ";

fn get(obj: &JsValue, key: &str) -> JsValue {
    js_sys::Reflect::get(obj, &JsValue::from_str(key)).unwrap()
}

/// (job JSON, slicer G-code).
fn case() -> (String, Vec<u8>) {
    let w = synthetic::conic_cube_of(16.0);
    let g = synthetic::gcode(&w.job, true, 4.0).into_bytes();
    (w.job.to_json_pretty(), g)
}

fn options(allow: bool) -> String {
    format!(r#"{{"machine":"cartesian","allow_collisions":{allow}}}"#)
}

/// `UnwarpStream` as the worker drives it: the output and the report, or what it threw.
fn stream(gcode: &[u8], job: &str, options: &str) -> Result<(Vec<u8>, JsValue), JsValue> {
    let mut s = wasm::UnwarpStream::new(job, options)?;
    for c in gcode.chunks(CHUNK) {
        s.scan(c)?;
    }
    s.end_scan()?;
    let mut out = Vec::new();
    for c in gcode.chunks(CHUNK) {
        s.push(c)?;
        out.extend(s.take_output());
    }
    let report = s.finish()?;
    out.extend(s.take_output());
    Ok((out, report))
}

/// The code and message of a JS error.
fn thrown(e: &JsValue) -> (String, String) {
    let error = e.dyn_ref::<js_sys::Error>().expect("an Error");
    let code = get(e, "code").as_string().expect("a string .code");
    (code, String::from(error.message()))
}

#[test]
fn unwarp_stream_with_allow_collisions_writes_the_one_shots_bytes_and_lists_every_finding() {
    let (job, g) = case();
    let one_shot = wasm::unwarp(&g, &job, &options(true)).expect("allow_collisions writes");
    let want = js_sys::Uint8Array::new(&get(&one_shot, "gcode")).to_vec();
    let (out, report) = stream(&g, &job, &options(true)).expect("allow_collisions writes");
    assert!(
        out == want,
        "UnwarpStream: {} B, the one-shot unwarp {} B",
        out.len(),
        want.len()
    );

    let text = String::from_utf8(out).unwrap();
    let listed: Vec<&str> = text.lines().filter(|l| l.starts_with(LISTED)).collect();
    let body: String = text
        .lines()
        .filter(|l| !l.starts_with(LISTED))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(
        text.ends_with(&listed.iter().map(|l| format!("{l}\n")).collect::<String>()),
        "the findings are listed at the end of the file"
    );
    let spec = warpslice::machine::preset("cartesian").unwrap();
    let (found, _) = warpslice::collision::check_gcode(body.as_bytes(), &spec).unwrap();
    assert!(found.len() >= 2, "the case must have several findings");
    assert_eq!(listed.len(), found.len(), "one comment per finding");

    // the report the page lists: every finding, with its output line, part and obstacle
    let machine = get(&report, "machine");
    assert_eq!(get(&machine, "collisions_checked"), JsValue::TRUE);
    let collisions: js_sys::Array = get(&machine, "collisions").dyn_into().unwrap();
    assert_eq!(collisions.length() as usize, found.len());
    for (i, f) in found.iter().enumerate() {
        let c = collisions.get(i as u32);
        assert_eq!(get(&c, "line").as_f64(), Some(f.line as f64), "finding {i}");
        assert_eq!(get(&c, "part").as_string().as_deref(), Some(&*f.part));
        assert_eq!(
            get(&c, "obstacle").as_string().as_deref(),
            Some(&*f.obstacle)
        );
        assert!(
            listed[i].starts_with(&format!(
                "{LISTED}{} layer {}: {} into {}",
                f.line, f.layer, f.part, f.obstacle
            )),
            "{} vs {f:?}",
            listed[i]
        );
    }
}

#[test]
fn unwarp_stream_refuses_a_collision_with_the_one_shots_error() {
    let (job, g) = case();
    let one_shot = wasm::unwarp(&g, &job, &options(false))
        .expect_err("the one-shot unwarp refuses the colliding file");
    let (code, message) = thrown(&one_shot);
    assert_eq!(code, "machine.collision", "{message}");
    let streamed =
        stream(&g, &job, &options(false)).expect_err("UnwarpStream refuses the colliding file");
    let (scode, smessage) = thrown(&streamed);
    assert_eq!(scode, code);
    assert_eq!(smessage, message);
    // the message names the first finding the allowed file lists
    let (out, _) = stream(&g, &job, &options(true)).unwrap();
    let text = String::from_utf8(out).unwrap();
    let first = text
        .lines()
        .find(|l| l.starts_with(LISTED))
        .expect("a listed finding");
    let line: &str = first[LISTED.len()..].split(' ').next().unwrap();
    assert!(
        message.contains(&format!("output line {line} (layer ")),
        "{message} vs {first}"
    );
}
