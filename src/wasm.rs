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
    js_sys::Reflect::set(obj, &JsValue::from_str(key), v)
        .map(|_| ())
        .map_err(|_| JsError::new("cannot build the result object"))
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
    set(
        &obj,
        "stl",
        &js_sys::Uint8Array::from(out.stl.as_slice()).into(),
    )?;
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
    set(
        &obj,
        "gcode",
        &js_sys::Uint8Array::from(out.gcode.as_slice()).into(),
    )?;
    set(&obj, "report", &to_js(&out.report)?)?;
    Ok(obj.into())
}

/// An STL of a generated example part (`cube`, `cylinder`, `sphere`, `overhang`).
#[wasm_bindgen]
pub fn example_stl(name: &str) -> Result<Vec<u8>, JsError> {
    let m = crate::shapes::example(name)
        .ok_or_else(|| JsError::new(&format!("unknown example '{name}'")))?;
    Ok(crate::mesh::write_stl(
        &m,
        &format!("warpslice example {name}"),
    ))
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
        Ok(UnwarpStream {
            inner: Unwarper::new(&job, &opts).map_err(js)?,
        })
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
            v.extend_from_slice(&[
                p.p.x,
                p.p.y,
                p.p.z,
                p.n.x,
                p.n.y,
                p.n.z,
                p.e,
                p.layer as f64,
                if p.travel { 1.0 } else { 0.0 },
                p.feature as u8 as f64,
            ]);
        }
        v
    }
    /// End of pass 2: the report. Drain `takeOutput` once more after it.
    pub fn finish(&mut self) -> Result<JsValue, JsError> {
        let r = self.inner.finish().map_err(js)?;
        to_js(&r)
    }
}

// ── Calibration of A/B tables (seed 004), `crate::calibrate` ────────────────────────────────

/// A machine argument: a JSON object text, a preset name, or empty for `open5x-ab`.
fn calibrate_machine(arg: &str) -> Result<crate::machine::MachineSpec, JsError> {
    let a = arg.trim();
    if a.is_empty() {
        crate::machine::preset("open5x-ab").map_err(js)
    } else if a.starts_with('{') {
        crate::machine::MachineSpec::from_json(a, "machine JSON").map_err(js)
    } else {
        crate::machine::preset(a).map_err(js)
    }
}

fn parse_or_default<T: serde::de::DeserializeOwned + Default>(
    what: &str,
    json: &str,
) -> Result<T, JsError> {
    if json.trim().is_empty() {
        Ok(T::default())
    } else {
        parse(what, json)
    }
}

/// `calibrate_origin(measurementsText, optionsJson, machine)` → `{ report: object, text: string,
/// machineJson: string }`. Options: `{ "bias": [x, y, z], "a_z_correction_deg": α }` (or "");
/// machine: the base machine (JSON text, preset name, or "" for open5x-ab).
#[wasm_bindgen]
pub fn calibrate_origin(
    measurements: &str,
    options_json: &str,
    machine: &str,
) -> Result<JsValue, JsError> {
    let series = crate::calibrate::parse_measurements(measurements).map_err(js)?;
    let opts: crate::calibrate::OriginOptions = parse_or_default("origin options", options_json)?;
    let (report, spec) =
        crate::calibrate::calibrate_origin(&series, &opts, &calibrate_machine(machine)?)
            .map_err(js)?;
    let obj = js_sys::Object::new();
    set(&obj, "report", &to_js(&report)?)?;
    set(&obj, "text", &JsValue::from_str(&report.to_text()))?;
    set(&obj, "machineJson", &JsValue::from_str(&spec.to_json()))?;
    Ok(obj.into())
}

/// `calibrate_probe(inputJson)` → `{ result: object, text: string }`; input e.g.
/// `{"kind": "a-pos", "z0": -5, "y90": 4.2, "y_minus90": -3.8, "c_y": 0.453}` (kinds: a-pos-error,
/// a-pos, a-dir, b-pos, b-dir, z-bias, a-scaling, wobble).
#[wasm_bindgen]
pub fn calibrate_probe(input_json: &str) -> Result<JsValue, JsError> {
    let input: crate::calibrate::probes::ProbeInput = parse("probe input", input_json)?;
    let out = crate::calibrate::probes::evaluate(&input).map_err(js)?;
    let obj = js_sys::Object::new();
    set(&obj, "result", &to_js(&out)?)?;
    set(&obj, "text", &JsValue::from_str(&out.to_text()))?;
    Ok(obj.into())
}

/// `calibrate_test_print(machine, kind, optionsJson)` → `{ gcode: Uint8Array, stl: Uint8Array,
/// report: object }`; kind: a-position, a-orientation, b-position, b-orientation, integrated.
#[wasm_bindgen]
pub fn calibrate_test_print(
    machine: &str,
    kind: &str,
    options_json: &str,
) -> Result<JsValue, JsError> {
    use crate::calibrate::patterns;
    let kind: patterns::TestKind = kind.parse().map_err(js)?;
    let opts: patterns::PrintOptions = parse_or_default("print options", options_json)?;
    let tp = patterns::test_print(&calibrate_machine(machine)?, kind, &opts).map_err(js)?;
    let obj = js_sys::Object::new();
    set(
        &obj,
        "gcode",
        &js_sys::Uint8Array::from(tp.gcode.as_slice()).into(),
    )?;
    set(
        &obj,
        "stl",
        &js_sys::Uint8Array::from(patterns::base_stl(kind).as_slice()).into(),
    )?;
    set(&obj, "report", &to_js(&tp.report)?)?;
    Ok(obj.into())
}

fn sim_result(
    rep: &crate::calibrate::simulate::SimReport,
    svg: String,
) -> Result<JsValue, JsError> {
    let obj = js_sys::Object::new();
    let errors: Vec<f64> = rep.points.iter().map(|l| l.error_mm).collect();
    set(
        &obj,
        "errors",
        &js_sys::Float64Array::from(errors.as_slice()).into(),
    )?;
    set(&obj, "maxErrorMm", &JsValue::from_f64(rep.max_error_mm))?;
    set(&obj, "meanErrorMm", &JsValue::from_f64(rep.mean_error_mm))?;
    set(
        &obj,
        "maxAxisErrorDeg",
        &JsValue::from_f64(rep.max_axis_error_deg),
    )?;
    set(&obj, "svg", &JsValue::from_str(&svg))?;
    set(&obj, "text", &JsValue::from_str(&rep.to_text()))?;
    Ok(obj.into())
}

/// `calibrate_b_position_svg(machine, dx, dy, optionsJson, exaggerate)` → `{ errors: Float64Array,
/// maxErrorMm, meanErrorMm, maxAxisErrorDeg, svg, text }`: the B position test run by a machine
/// whose B axis is off by (dx, dy) mm (Fig. 6.16).
#[wasm_bindgen]
pub fn calibrate_b_position_svg(
    machine: &str,
    dx: f64,
    dy: f64,
    options_json: &str,
    exaggerate: f64,
) -> Result<JsValue, JsError> {
    let opts: crate::calibrate::patterns::PrintOptions =
        parse_or_default("print options", options_json)?;
    let (rep, svg) = crate::calibrate::patterns::b_position_svg(
        &calibrate_machine(machine)?,
        glam::DVec3::new(dx, dy, 0.0),
        &opts,
        exaggerate,
    )
    .map_err(js)?;
    sim_result(&rep, svg)
}

/// `calibrate_simulate(believed, truth, deviationJson, toolpathCsv, testKind, exaggerate)` →
/// `{ errors: Float64Array, maxErrorMm, meanErrorMm, maxAxisErrorDeg, svg, text }`. The true
/// machine is `truth` (JSON/preset) or, when "", the believed one with the deviation
/// (`{"a_rot_z_deg": 2, "b_offset": [0, -0.2, 0], …}`); the toolpath is the CSV
/// (`x,y,z,nx,ny,nz` lines) or, when "", the path of the test print `testKind`.
#[wasm_bindgen]
pub fn calibrate_simulate(
    believed: &str,
    truth: &str,
    deviation_json: &str,
    toolpath_csv: &str,
    test_kind: &str,
    exaggerate: f64,
) -> Result<JsValue, JsError> {
    use crate::calibrate::{patterns, simulate};
    let b = calibrate_machine(believed)?;
    let t = if truth.trim().is_empty() {
        let d: simulate::Deviation = parse_or_default("deviation", deviation_json)?;
        simulate::deviate(&b, &d).map_err(js)?
    } else {
        calibrate_machine(truth)?
    };
    let pair = simulate::Pair::new(&b, &t).map_err(js)?;
    let (rep, title) = if toolpath_csv.trim().is_empty() {
        let kind: patterns::TestKind = test_kind.parse().map_err(js)?;
        let tp = patterns::test_print(&b, kind, &patterns::PrintOptions::default()).map_err(js)?;
        let (axes, tips): (Vec<Vec<f64>>, Vec<glam::DVec3>) = tp
            .moves
            .iter()
            .filter_map(|m| m.tip.map(|p| (m.axes.clone(), p)))
            .unzip();
        (
            simulate::simulate_axes(&pair, &axes, &tips).map_err(js)?,
            format!("{} test", kind.name()),
        )
    } else {
        let poses = simulate::parse_poses(toolpath_csv).map_err(js)?;
        (
            simulate::simulate(&pair, &poses).map_err(js)?,
            "toolpath".to_string(),
        )
    };
    let svg = simulate::svg(&rep, &title, exaggerate);
    sim_result(&rep, svg)
}

/// Fig. 3.1 in numbers: a point `radius` mm from an A axis believed along X but truly turned
/// `aRotZDeg` about Z, turned 90°: how far it lands from where it should, mm (20, 2 → 0.698).
#[wasm_bindgen]
pub fn calibrate_fig_3_1(radius: f64, a_rot_z_deg: f64) -> Result<f64, JsError> {
    crate::calibrate::simulate::fig_3_1(radius, a_rot_z_deg).map_err(js)
}

/// The mesh report of an STL (format, triangles, bbox, defects), without warping it.
#[wasm_bindgen]
pub fn stl_report(stl: &[u8]) -> Result<JsValue, JsError> {
    let (_, report) = crate::mesh::read_stl(stl).map_err(|e| JsError::new(&format!("STL: {e}")))?;
    to_js(&report)
}

/// Every shipped machine preset as JSON: `[{ name, kind, flavour, spec, axes: [{ name, rotary,
/// min, max }], workspace_max_tilt_deg }]`; `spec` is the preset's JSON object, unbounded limits
/// are `null`. Pass a `name` (or a `spec`, edited) as `"machine"` in the unwarp options.
#[wasm_bindgen]
pub fn machine_presets() -> Result<String, JsError> {
    let finite = |v: f64| {
        if v.is_finite() {
            serde_json::json!(v)
        } else {
            serde_json::Value::Null
        }
    };
    let mut list = Vec::new();
    for name in crate::machine::preset_names() {
        let spec = crate::machine::preset(name).map_err(js)?;
        let machine = spec.build().map_err(js)?;
        let axes: Vec<serde_json::Value> = machine
            .limits()
            .iter()
            .map(|l| serde_json::json!({ "name": l.name, "rotary": l.rotary, "min": finite(l.min), "max": finite(l.max) }))
            .collect();
        let spec_value = serde_json::to_value(&spec).map_err(js)?;
        list.push(serde_json::json!({
            "name": name,
            "kind": spec_value.get("kind").cloned().unwrap_or(serde_json::Value::Null),
            "flavour": spec.flavour.unwrap_or_default().name(),
            "spec": spec_value,
            "axes": axes,
            "workspace_max_tilt_deg": finite(machine.workspace().max_tilt_deg),
        }));
    }
    serde_json::to_string(&list).map_err(js)
}

/// Layer surfaces of a job for display: every `every`-th slicing plane z' = k·h, sampled on a
/// `grid`×`grid` lattice over the model's XY bounding box and mapped back to the model frame by
/// T⁻¹. Returns 5 numbers per sample: x y z (model frame, mm), tilt of the tool axis from +Z
/// (degrees), layer index k; samples whose z falls outside the model's z range are skipped.
#[wasm_bindgen]
pub fn layer_surfaces(job_json: &str, every: u32, grid: u32) -> Result<Vec<f64>, JsError> {
    let job = Job::from_json(job_json).map_err(js)?;
    let mut params = job.warp.clone();
    let warp = params.build(&job.model_bbox).map_err(js)?;
    let (b, h) = (job.model_bbox, job.layer_height);
    let every = every.max(1) as f64;
    let grid = grid.clamp(2, 256);
    let zt_min = job.warped_bbox.min.z - job.stl_z_offset;
    let zt_max = job.warped_bbox.max.z - job.stl_z_offset;
    let mut out = Vec::new();
    if !h.is_finite() || h <= 0.0 {
        return Ok(out);
    }
    let k0 = (zt_min / h).floor() as i64;
    let k1 = (zt_max / h).ceil() as i64;
    let mut k = k0;
    while k <= k1 {
        let zq = k as f64 * h;
        for i in 0..grid {
            for j in 0..grid {
                let x = b.min.x + (b.max.x - b.min.x) * i as f64 / (grid - 1) as f64;
                let y = b.min.y + (b.max.y - b.min.y) * j as f64 / (grid - 1) as f64;
                let p = warp.inverse(glam::DVec3::new(x, y, zq));
                if p.z < b.min.z || p.z > b.max.z || !p.is_finite() {
                    continue;
                }
                let tilt =
                    crate::num::deg(crate::num::angle_between(warp.tool_axis(p), glam::DVec3::Z));
                out.extend_from_slice(&[p.x, p.y, p.z, tilt, k as f64]);
            }
        }
        k += every as i64;
    }
    Ok(out)
}

/// Machine axes of preview points, for the preview's machine-coordinate view:
/// `points` holds 6 numbers per point, the tip `p` (output frame, mm) and the unit tool axis
/// `n` (tip → nozzle); returns the machine's axes per point in its axis order (linear axes mm,
/// rotary axes degrees), from `Machine::inverse` with the previous point's axes picking the
/// branch (continuous rotary axes). An unreachable point is an error naming its index.
#[wasm_bindgen]
pub fn machine_axes(machine: &str, points: &[f64]) -> Result<Vec<f64>, JsError> {
    if points.len() % 6 != 0 {
        return Err(JsError::new(&format!(
            "machine_axes: {} numbers is not a whole number of points (6 per point: px py pz nx ny nz)",
            points.len()
        )));
    }
    let m = crate::machine::preset(machine)
        .map_err(js)?
        .build()
        .map_err(js)?;
    let k = m.limits().len();
    let mut out = Vec::with_capacity(points.len() / 6 * k);
    let mut previous: Option<Vec<f64>> = None;
    for (i, q) in points.chunks_exact(6).enumerate() {
        let p = glam::DVec3::new(q[0], q[1], q[2]);
        let n = glam::DVec3::new(q[3], q[4], q[5]);
        let axes = m
            .inverse(p, n, previous.as_deref())
            .map_err(|e| JsError::new(&format!("machine_axes: preview point {i}: {e}")))?;
        out.extend_from_slice(&axes);
        previous = Some(axes);
    }
    Ok(out)
}
