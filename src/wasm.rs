//! wasm-bindgen glue: converts types and returns `Result<_, JsError>`; nothing else.
//! Error texts are the core's `Display`, the same as the CLI prints.
//!
//! Options and reports cross as JSON strings / plain JS objects with the core's serde shapes
//! (`pipeline::WarpOptions`, `unwarp::UnwarpOptions`, `job::Job`, the reports).

use wasm_bindgen::prelude::*;

use crate::job::Job;
use crate::pipeline::{self, WarpOptions};
use crate::unwarp::{self, UnwarpOptions, Unwarper};

fn js<E: std::fmt::Display>(e: E) -> JsError {
    JsError::new(&e.to_string())
}

fn to_js<T: serde::Serialize>(v: &T) -> Result<JsValue, JsError> {
    let s = serde_wasm_bindgen::Serializer::json_compatible();
    v.serialize(&s).map_err(js)
}

fn set(obj: &js_sys::Object, key: &str, v: &JsValue) -> Result<(), JsError> {
    js_sys::Reflect::set(obj, &JsValue::from_str(key), v).map(|_| ()).map_err(|_| JsError::new("cannot build the result object"))
}

fn parse<T: serde::de::DeserializeOwned>(what: &str, json: &str) -> Result<T, JsError> {
    serde_json::from_str(json).map_err(|e| JsError::new(&format!("{what}: {e}")))
}

/// The crate version.
#[wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// `warp(stl, optionsJson)` → `{ stl: Uint8Array, job: string, report: object }`.
#[wasm_bindgen]
pub fn warp(stl: &[u8], options_json: &str) -> Result<JsValue, JsError> {
    let opts: WarpOptions = parse("warp options", options_json)?;
    let out = pipeline::warp_model(stl, &opts).map_err(js)?;
    let obj = js_sys::Object::new();
    set(&obj, "stl", &js_sys::Uint8Array::from(out.stl.as_slice()).into())?;
    set(&obj, "job", &JsValue::from_str(&out.job.to_json_pretty()))?;
    set(&obj, "report", &to_js(&out.report)?)?;
    Ok(obj.into())
}

/// `unwarp(gcode, jobJson, optionsJson)` → `{ gcode: Uint8Array, report: object }`.
#[wasm_bindgen]
pub fn unwarp(gcode: &[u8], job_json: &str, options_json: &str) -> Result<JsValue, JsError> {
    let job = Job::from_json(job_json).map_err(js)?;
    let opts: UnwarpOptions = parse("unwarp options", options_json)?;
    let out = unwarp::unwarp(gcode, &job, &opts).map_err(js)?;
    let obj = js_sys::Object::new();
    set(&obj, "gcode", &js_sys::Uint8Array::from(out.gcode.as_slice()).into())?;
    set(&obj, "report", &to_js(&out.report)?)?;
    Ok(obj.into())
}

/// An STL of a generated example part (`cube`, `cylinder`, `sphere`, `overhang`).
#[wasm_bindgen]
pub fn example_stl(name: &str) -> Result<Vec<u8>, JsError> {
    let m = crate::shapes::example(name).ok_or_else(|| JsError::new(&format!("unknown example '{name}'")))?;
    Ok(crate::mesh::write_stl(&m, &format!("warpslice example {name}")))
}

/// Streaming unwarp for the web worker: `scan` every chunk, `endScan`, `push` every chunk
/// again draining `takeOutput`, then `finish`. Memory stays bounded by the chunk size.
#[wasm_bindgen]
pub struct UnwarpStream {
    inner: Unwarper,
}

#[wasm_bindgen]
impl UnwarpStream {
    #[wasm_bindgen(constructor)]
    pub fn new(job_json: &str, options_json: &str) -> Result<UnwarpStream, JsError> {
        let job = Job::from_json(job_json).map_err(js)?;
        let opts: UnwarpOptions = parse("unwarp options", options_json)?;
        Ok(UnwarpStream { inner: Unwarper::new(&job, &opts).map_err(js)? })
    }
    /// Pass 1: a chunk of the G-code.
    pub fn scan(&mut self, chunk: &[u8]) -> Result<(), JsError> {
        self.inner.scan(chunk).map_err(js)
    }
    /// End of pass 1: the registration (translation, residual, region…).
    #[wasm_bindgen(js_name = endScan)]
    pub fn end_scan(&mut self) -> Result<JsValue, JsError> {
        let r = self.inner.end_scan().map_err(js)?;
        to_js(&r)
    }
    /// Pass 2: the same chunk again.
    pub fn push(&mut self, chunk: &[u8]) -> Result<(), JsError> {
        self.inner.push(chunk).map_err(js)
    }
    /// The output written so far (drains it).
    #[wasm_bindgen(js_name = takeOutput)]
    pub fn take_output(&mut self) -> Vec<u8> {
        self.inner.take_output()
    }
    /// The toolpath collected so far (drains it), 10 numbers per point:
    /// x y z nx ny nz e layer travel(0/1) feature-index.
    #[wasm_bindgen(js_name = takeToolpath)]
    pub fn take_toolpath(&mut self) -> Vec<f64> {
        let tp = self.inner.take_toolpath();
        let mut v = Vec::with_capacity(tp.len() * 10);
        for p in tp {
            v.extend_from_slice(&[p.p.x, p.p.y, p.p.z, p.n.x, p.n.y, p.n.z, p.e, p.layer as f64, if p.travel { 1.0 } else { 0.0 }, p.feature as u8 as f64]);
        }
        v
    }
    /// End of pass 2: the report. Drain `takeOutput` once more after it.
    pub fn finish(&mut self) -> Result<JsValue, JsError> {
        let r = self.inner.finish().map_err(js)?;
        to_js(&r)
    }
}

/// The shipped machine presets: a JSON list of `{ name, kind, flavour, axes: [{ name, rotary,
/// min, max }], spec }` (unlimited travel as `null`). Pass a `name` (or a `spec`, edited) as
/// `"machine"` in the unwarp options.
#[wasm_bindgen]
pub fn machine_presets() -> Result<String, JsError> {
    let mut list = Vec::new();
    for name in crate::machine::preset_names() {
        let spec = crate::machine::preset(name).map_err(js)?;
        let m = spec.build().map_err(js)?;
        let axes: Vec<serde_json::Value> = m
            .limits()
            .iter()
            .map(|l| {
                let lim = |v: f64| if v.is_finite() { serde_json::json!(v) } else { serde_json::Value::Null };
                serde_json::json!({ "name": l.name, "rotary": l.rotary, "min": lim(l.min), "max": lim(l.max) })
            })
            .collect();
        let spec_json: serde_json::Value = serde_json::from_str(&spec.to_json()).map_err(js)?;
        list.push(serde_json::json!({
            "name": name,
            "kind": spec_json.get("kind").cloned().unwrap_or(serde_json::Value::Null),
            "flavour": spec.flavour.unwrap_or_default().name(),
            "axes": axes,
            "spec": spec_json,
        }));
    }
    serde_json::to_string(&list).map_err(js)
}
