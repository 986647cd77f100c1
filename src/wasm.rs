//! wasm-bindgen glue: converts types and returns `Result<_, JsValue>`; nothing else.
//! Error texts are the core's `Display`, the same as the CLI prints.
//!
//! Options and reports cross as JSON strings / plain JS objects with the core's serde shapes
//! (`pipeline::WarpOptions`, `unwarp::UnwarpOptions`, `job::Job`, the reports).

use wasm_bindgen::prelude::*;

use crate::error::Coded;
use crate::job::Job;
use crate::pipeline::{self, UnwarpSettings, WarpOptions};

/// A JS `Error` with the core's message and its stable code (`error.code`, see
/// [`crate::error`]): the page keys its advice by the code, never by the message.
fn fail(code: &str, message: &str) -> JsValue {
    let e = js_sys::Error::new(message);
    // setting a property on a fresh Error object cannot fail
    let _ = js_sys::Reflect::set(&e, &JsValue::from_str("code"), &JsValue::from_str(code));
    e.into()
}

/// The JS error of a core error.
fn js<E: Coded>(e: E) -> JsValue {
    fail(e.code(), &e.to_string())
}

/// The JS error of a bad option or options JSON.
fn bad_options(message: &str) -> JsValue {
    fail("options.invalid", message)
}

fn to_js<T: serde::Serialize>(v: &T) -> Result<JsValue, JsValue> {
    let s = serde_wasm_bindgen::Serializer::json_compatible();
    v.serialize(&s).map_err(|e| bad_options(&e.to_string()))
}

fn set(obj: &js_sys::Object, key: &str, v: &JsValue) -> Result<(), JsValue> {
    js_sys::Reflect::set(obj, &JsValue::from_str(key), v)
        .map(|_| ())
        .map_err(|_| bad_options("cannot build the result object"))
}

fn parse<T: serde::de::DeserializeOwned>(what: &str, json: &str) -> Result<T, JsValue> {
    serde_json::from_str(json).map_err(|e| bad_options(&format!("{what}: {e}")))
}

/// The unwarp options JSON. Its `machine` (a preset name or a machine object) is checked here
/// first, so that its errors keep their own code (`machine.unknown-preset`, `machine.bad-json`,
/// …) as in `describe_machine` and the CLI, instead of serde's `options.invalid`; the text is
/// then read as a whole (serde's errors keep their line and column).
fn unwarp_settings(json: &str) -> Result<UnwarpSettings, JsValue> {
    let v: serde_json::Value = parse("unwarp options", json)?;
    match v.get("machine") {
        None | Some(serde_json::Value::Null) => {}
        Some(serde_json::Value::String(name)) => {
            crate::machine::preset(name).map_err(js)?;
        }
        Some(m @ serde_json::Value::Object(_)) => {
            crate::machine::MachineSpec::from_json(&m.to_string(), "unwarp options 'machine'")
                .map_err(js)?;
        }
        Some(other) => {
            return Err(bad_options(&format!(
                "unwarp options: machine must be a preset name or a machine object, not {other}"
            )))
        }
    }
    parse("unwarp options", json)
}

/// The crate version.
#[wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// `warp(stl, optionsJson)` → `{ stl: Uint8Array, job: string, report: object }`.
#[wasm_bindgen]
pub fn warp(stl: &[u8], options_json: &str) -> Result<JsValue, JsValue> {
    let opts = WarpOptions::from_json(options_json).map_err(js)?;
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
pub fn unwarp(gcode: &[u8], job_json: &str, options_json: &str) -> Result<JsValue, JsValue> {
    let job = Job::from_json(job_json).map_err(js)?;
    let settings = unwarp_settings(options_json)?;
    let out = pipeline::unwarp(gcode, &job, &settings).map_err(js)?;
    gcode_and_report(&out.gcode, &out.report)
}

/// `{ gcode: Uint8Array, report: object }`, what `unwarp` and `BuiltinSlice.finish` return.
fn gcode_and_report<R: serde::Serialize>(gcode: &[u8], report: &R) -> Result<JsValue, JsValue> {
    let obj = js_sys::Object::new();
    set(&obj, "gcode", &js_sys::Uint8Array::from(gcode).into())?;
    set(&obj, "report", &to_js(report)?)?;
    Ok(obj.into())
}

/// An STL of a generated example part (`cube`, `cylinder`, `sphere`, `overhang`).
#[wasm_bindgen]
pub fn example_stl(name: &str) -> Result<Vec<u8>, JsValue> {
    let m = crate::shapes::example(name).ok_or_else(|| {
        bad_options(&format!(
            "unknown example '{name}': one of {}",
            crate::shapes::EXAMPLES.join(", ")
        ))
    })?;
    Ok(crate::mesh::write_stl(
        &m,
        &format!("warpslice example {name}"),
    ))
}

/// Streaming unwarp for the web worker: `scan` every chunk, `endScan`, `push` every chunk
/// again draining `takeOutput`, then `finish`. Memory stays bounded by the chunk size. The
/// output goes through the core's collision check as it streams
/// ([`pipeline::CheckedUnwarper`], the CLI's code): `finish` refuses with `machine.collision`
/// or, with `allow_collisions`, ends the file with the findings, as the CLI does.
#[wasm_bindgen]
pub struct UnwarpStream {
    inner: pipeline::CheckedUnwarper,
    job: Job,
}

#[wasm_bindgen]
impl UnwarpStream {
    /// One G-code's stream: `job_json` is the job file, `options_json` the [`UnwarpSettings`] JSON.
    #[wasm_bindgen(constructor)]
    pub fn new(job_json: &str, options_json: &str) -> Result<UnwarpStream, JsValue> {
        let job = Job::from_json(job_json).map_err(js)?;
        let settings = unwarp_settings(options_json)?;
        Ok(UnwarpStream {
            inner: pipeline::CheckedUnwarper::new(&job, &settings, None).map_err(js)?,
            job,
        })
    }
    /// Register to the bead against the job's warped STL (the bytes `warp` returned; checked
    /// to be this job's). Call before `endScan`; the CLI's `unwarp --stl`.
    #[wasm_bindgen(js_name = setWarpedStl)]
    pub fn set_warped_stl(&mut self, stl: &[u8]) -> Result<(), JsValue> {
        let mesh = pipeline::warped_mesh(&self.job, stl).map_err(js)?;
        self.inner.set_warped_mesh(mesh);
        Ok(())
    }
    /// Pass 1: a chunk of the G-code.
    pub fn scan(&mut self, chunk: &[u8]) -> Result<(), JsValue> {
        self.inner.scan(chunk).map_err(js)
    }
    /// End of pass 1: the registration (translation, residual, region…).
    #[wasm_bindgen(js_name = endScan)]
    pub fn end_scan(&mut self) -> Result<JsValue, JsValue> {
        let r = self.inner.end_scan().map_err(js)?;
        to_js(&r)
    }
    /// Pass 2: the same chunk again.
    pub fn push(&mut self, chunk: &[u8]) -> Result<(), JsValue> {
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
    /// End of pass 2: the report (its `machine.collisions` with `allow_collisions`), or the
    /// core's refusal (`machine.collision`, the CLI's message). Drain `takeOutput` once more
    /// after it.
    pub fn finish(&mut self) -> Result<JsValue, JsValue> {
        let r = self.inner.finish().map_err(js)?;
        to_js(&r)
    }
}

// ── `warpslice check` of any machine G-code, `crate::check` ──────────────────────────────────

/// Numbers per point of [`CheckStream::take_path`]'s `points` (the unwarp toolpath's layout).
pub const CHECK_POINT_NUMBERS: usize = 10;

/// Streaming check of a machine G-code for the web worker: `push` every chunk (4 MB slices),
/// draining `takePath` for the preview, then `finish` for the report (the CLI's `--json`).
#[wasm_bindgen]
pub struct CheckStream {
    inner: Option<crate::check::CheckStream>,
    /// The path of the last line, after `finish`.
    rest: Vec<crate::check::PathPoint>,
}

#[wasm_bindgen]
impl CheckStream {
    /// A check for `machine` (a preset name or a machine JSON object text) with `options_json`
    /// (the [`crate::check::CheckOptions`] JSON: `flavour`, `max_findings`, `path`; "" for
    /// the defaults).
    #[wasm_bindgen(constructor)]
    pub fn new(machine: &str, options_json: &str) -> Result<CheckStream, JsValue> {
        let spec = crate::machine::MachineSpec::from_name_or_json(machine).map_err(js)?;
        let options: crate::check::CheckOptions = parse_or_default("check options", options_json)?;
        Ok(CheckStream {
            inner: Some(crate::check::CheckStream::new(&spec, &options).map_err(js)?),
            rest: Vec::new(),
        })
    }
    /// A chunk of the G-code.
    pub fn push(&mut self, chunk: &[u8]) -> Result<(), JsValue> {
        self.stream()?.push(chunk).map_err(js)
    }
    /// The tip path so far (drains it; with `path: true`): `{ points, lines, axes, axisCount,
    /// collisions }`, points [`CHECK_POINT_NUMBERS`] numbers each (x y z nx ny nz e layer
    /// travel(0/1) feature(0)), lines the 1-based file line of each point, axes the machine's
    /// `axisCount` axis values of each point (the pose `head_pose` takes), collisions
    /// `[line, [part, …]]` for each point with parts in collision (all of them, whatever
    /// `max_findings` lists). Call once more after `finish`.
    #[wasm_bindgen(js_name = takePath)]
    pub fn take_path(&mut self) -> Result<JsValue, JsValue> {
        let path = match self.inner.as_mut() {
            Some(s) => s.take_path(),
            None => std::mem::take(&mut self.rest),
        };
        let mut points = Vec::with_capacity(path.len() * CHECK_POINT_NUMBERS);
        let mut lines = Vec::with_capacity(path.len());
        let axis_count = path.first().map_or(0, |q| q.axes.len());
        let mut axes = Vec::with_capacity(path.len() * axis_count);
        let mut collisions: Vec<(u64, &[String])> = Vec::new();
        for q in &path {
            axes.extend_from_slice(&q.axes);
            if !q.collisions.is_empty() {
                collisions.push((q.line, &q.collisions));
            }
            points.extend_from_slice(&[
                q.p.x,
                q.p.y,
                q.p.z,
                q.n.x,
                q.n.y,
                q.n.z,
                q.de,
                q.layer as f64,
                if q.travel { 1.0 } else { 0.0 },
                0.0,
            ]);
            lines.push(q.line as f64);
        }
        let o = js_sys::Object::new();
        set(
            &o,
            "points",
            &js_sys::Float64Array::from(points.as_slice()).into(),
        )?;
        set(
            &o,
            "lines",
            &js_sys::Float64Array::from(lines.as_slice()).into(),
        )?;
        set(
            &o,
            "axes",
            &js_sys::Float64Array::from(axes.as_slice()).into(),
        )?;
        set(&o, "axisCount", &JsValue::from_f64(axis_count as f64))?;
        set(&o, "collisions", &to_js(&collisions)?)?;
        Ok(o.into())
    }
    /// The last line and the report (the stream is spent after it; `takePath` gives the last
    /// points).
    pub fn finish(&mut self) -> Result<JsValue, JsValue> {
        self.finish_with(None)
    }
    /// `finish` of a check with `skip_collisions` of a machine file whose collisions the
    /// unwarp that wrote it found (`UnwarpStream.finish`'s `report.machine.collisions`): the
    /// report lists them as its own ([`crate::check::CheckStream::finish_with_collisions`]).
    #[wasm_bindgen(js_name = finishWithCollisions)]
    pub fn finish_with_collisions(&mut self, collisions: JsValue) -> Result<JsValue, JsValue> {
        let found: Vec<crate::emit::CollisionFinding> = serde_wasm_bindgen::from_value(collisions)
            .map_err(|e| bad_options(&format!("check: collisions: {e}")))?;
        self.finish_with(Some(&found))
    }
    fn finish_with(
        &mut self,
        found: Option<&[crate::emit::CollisionFinding]>,
    ) -> Result<JsValue, JsValue> {
        let s = self
            .inner
            .take()
            .ok_or_else(|| bad_options("check: finish was called already"))?;
        let (r, rest) = match found {
            Some(found) => s.finish_with_collisions(found),
            None => s.finish(),
        }
        .map_err(js)?;
        self.rest = rest;
        to_js(&r)
    }
    fn stream(&mut self) -> Result<&mut crate::check::CheckStream, JsValue> {
        self.inner
            .as_mut()
            .ok_or_else(|| bad_options("check: the stream is finished"))
    }
}

// ── Calibration of A/B tables (seed 004), `crate::calibrate` ────────────────────────────────

/// A machine argument: a JSON object text, a preset name, or empty for `open5x-ab`.
fn calibrate_machine(arg: &str) -> Result<crate::machine::MachineSpec, JsValue> {
    let a = if arg.trim().is_empty() {
        "open5x-ab"
    } else {
        arg
    };
    crate::machine::MachineSpec::from_name_or_json(a).map_err(js)
}

fn parse_or_default<T: serde::de::DeserializeOwned + Default>(
    what: &str,
    json: &str,
) -> Result<T, JsValue> {
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
) -> Result<JsValue, JsValue> {
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
/// a-pos, a-dir, b-pos, b-dir, z-bias, a-scaling, a-steps-per-degree, a-orientation, wobble).
#[wasm_bindgen]
pub fn calibrate_probe(input_json: &str) -> Result<JsValue, JsValue> {
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
) -> Result<JsValue, JsValue> {
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
) -> Result<JsValue, JsValue> {
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
) -> Result<JsValue, JsValue> {
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
) -> Result<JsValue, JsValue> {
    use crate::calibrate::{patterns, simulate};
    let b = calibrate_machine(believed)?;
    let t = if truth.trim().is_empty() {
        None
    } else {
        Some(calibrate_machine(truth)?)
    };
    let d: simulate::Deviation = parse_or_default("deviation", deviation_json)?;
    let input = if toolpath_csv.trim().is_empty() {
        let kind: patterns::TestKind = test_kind.parse().map_err(js)?;
        simulate::SimInput::TestPrint(kind)
    } else {
        simulate::SimInput::Toolpath {
            csv: toolpath_csv,
            name: "toolpath",
        }
    };
    let (rep, title) = simulate::run(&b, t.as_ref(), &d, input).map_err(js)?;
    let svg = simulate::svg(&rep, &title, exaggerate);
    sim_result(&rep, svg)
}

/// Fig. 3.1 in numbers: a point `radius` mm from an A axis believed along X but truly turned
/// `aRotZDeg` about Z, turned 90°: how far it lands from where it should, mm (20, 2 → 0.698).
#[wasm_bindgen]
pub fn calibrate_fig_3_1(radius: f64, a_rot_z_deg: f64) -> Result<f64, JsValue> {
    // named here: the core would refuse a NaN radius as a point of the open5x-ab machine
    for (what, v) in [("radius", radius), ("aRotZDeg", a_rot_z_deg)] {
        if !v.is_finite() {
            return Err(js(crate::calibrate::CalibError::BadInput {
                what: what.to_string(),
                message: format!("{v} is not a finite number"),
            }));
        }
    }
    crate::calibrate::simulate::fig_3_1(radius, a_rot_z_deg).map_err(js)
}

/// The mesh report of an STL (format, triangles, bbox, defects), without warping it.
#[wasm_bindgen]
pub fn stl_report(stl: &[u8]) -> Result<JsValue, JsValue> {
    let (_, report) =
        crate::mesh::read_stl(stl).map_err(|e| fail(e.code(), &format!("STL: {e}")))?;
    to_js(&report)
}

/// Every shipped machine preset as JSON: `describe().machines` (name, kind, flavour, axes,
/// capabilities, spec; see [`crate::describe::MachineInfo`]).
#[wasm_bindgen]
pub fn machine_presets() -> Result<String, JsValue> {
    let d = crate::describe::describe().map_err(js)?;
    serde_json::to_string(&d.machines).map_err(|e| bad_options(&e.to_string()))
}

/// Layer surfaces of a job for display (see [`crate::surfaces`]): 5 numbers per sample, x y z
/// (model frame, mm), tilt from +Z (degrees), layer index.
#[wasm_bindgen]
pub fn layer_surfaces(job_json: &str, every: u32, grid: u32) -> Result<Vec<f64>, JsValue> {
    let job = Job::from_json(job_json).map_err(js)?;
    crate::surfaces::layer_surfaces(&job, every, grid).map_err(js)
}

/// Machine axes of preview points (see [`crate::machine::view::axes_of`]): 6 numbers per
/// point in (p, n), the machine's axes per point out. `machine`: a preset name or machine JSON.
#[wasm_bindgen]
pub fn machine_axes(machine: &str, points: &[f64]) -> Result<Vec<f64>, JsValue> {
    // as `machine_view` (`head_frames`) does: a trailing partial point is refused, not dropped
    if !points.len().is_multiple_of(6) {
        return Err(js(crate::machine::MachineError::BadCsv {
            line: points.len() / 6 + 1,
            message: format!(
                "{} numbers is not a whole number of points (6 per point: px py pz nx ny nz)",
                points.len()
            ),
        }));
    }
    let m = crate::machine::MachineSpec::from_name_or_json(machine)
        .and_then(|s| s.build())
        .map_err(js)?;
    crate::machine::view::axes_of(m.as_ref(), points).map_err(js)
}

/// The preview in machine coordinates (see [`crate::machine::view::head_frames`]): 6 numbers
/// per point in (p, n); 12 out per point: the head position in the machine frame, then the
/// columns of the part → machine rotation. `machine`: a preset name or machine JSON.
#[wasm_bindgen]
pub fn machine_view(machine: &str, points: &[f64]) -> Result<Vec<f64>, JsValue> {
    let m = crate::machine::MachineSpec::from_name_or_json(machine)
        .and_then(|s| s.build())
        .map_err(js)?;
    crate::machine::view::head_frames(m.as_ref(), points).map_err(js)
}

/// The head of `machine` (a preset name or machine JSON) at the axis values `axes` (machine
/// order), each part placed as the collision check places it ([`crate::collision::posed_head`]):
/// `{ tip, axis, parts: [{ name, kind: "frustum", base, top, base_radius, top_radius } |
/// { name, kind: "box", center, axes, half }] }`, output (part) frame, mm.
#[wasm_bindgen]
pub fn head_pose(machine: &str, axes: &[f64]) -> Result<JsValue, JsValue> {
    let spec = crate::machine::MachineSpec::from_name_or_json(machine).map_err(js)?;
    let head = crate::collision::posed_head::head_at(&spec, axes).map_err(js)?;
    to_js(&head)
}

/// What one machine (a preset name or a machine JSON, e.g. a user's custom machine) says of
/// itself, as JSON: the same shape as an entry of `describe().machines` (axes, limits,
/// capabilities, warps it can print, spec).
#[wasm_bindgen]
pub fn describe_machine(machine: &str) -> Result<String, JsValue> {
    let spec = crate::machine::MachineSpec::from_name_or_json(machine).map_err(js)?;
    let info = crate::describe::machine_info(&spec.name, &spec).map_err(js)?;
    serde_json::to_string(&info).map_err(|e| bad_options(&e.to_string()))
}

/// The firmware configuration fragment for the unwarp options' machine, flavour and feed (the
/// CLI's `--config-out`): the text to paste into the firmware's configuration, with the file
/// it belongs in as its first line's subject. 3-axis options (no `machine`) are refused
/// (`options.invalid`): they need no configuration.
#[wasm_bindgen]
pub fn firmware_config(options_json: &str) -> Result<JsValue, JsValue> {
    let settings = unwarp_settings(options_json)?;
    let c = settings
        .output
        .firmware_config()
        .map_err(js)?
        .ok_or_else(|| {
            bad_options("firmware_config: the options give no machine (3-axis output needs no firmware configuration)")
        })?;
    let obj = js_sys::Object::new();
    set(&obj, "file", &JsValue::from_str(c.file))?;
    set(&obj, "flavour", &JsValue::from_str(c.flavour.name()))?;
    set(&obj, "text", &JsValue::from_str(&c.text))?;
    Ok(obj.into())
}

/// Everything the core says of itself, as JSON (see [`crate::describe`]): warps and their
/// parameters, the options of both steps, the machines and their capabilities, feature names,
/// error codes. The page builds its forms and advice from it.
#[wasm_bindgen]
pub fn describe() -> Result<String, JsValue> {
    crate::describe::describe_json().map_err(js)
}

/// `overhangs(stl, warpOptionsJson, overhangAngle)` → the overhang report with per-facet
/// 0/1 flags (`suggest::OverhangReport`): planar, and under the warp of the options JSON (the
/// shape `warp` takes; `""` for planar only).
#[wasm_bindgen]
pub fn overhangs(stl: &[u8], options_json: &str, overhang_angle: f64) -> Result<JsValue, JsValue> {
    let model = crate::suggest::model_of(stl).map_err(js)?;
    let warp = match options_json.trim() {
        "" => None,
        text => Some(WarpOptions::from_json(text).map_err(js)?.warp),
    };
    let r = crate::suggest::overhangs(&model, warp.as_ref(), overhang_angle, true).map_err(js)?;
    to_js(&r)
}

/// `suggest(stl, machine, optionsJson)` → the ranked admissible warps
/// (`suggest::SuggestReport`; `suggestions[i].warp` is the `warp` options' `warp` object).
/// `machine`: a preset name or a machine JSON object; `optionsJson`: `suggest::SuggestOptions`
/// (`""`: the defaults).
#[wasm_bindgen]
pub fn suggest(stl: &[u8], machine: &str, options_json: &str) -> Result<JsValue, JsValue> {
    let model = crate::suggest::model_of(stl).map_err(js)?;
    let spec = crate::machine::MachineSpec::from_name_or_json(machine).map_err(js)?;
    let options: crate::suggest::SuggestOptions = match options_json.trim() {
        "" => Default::default(),
        text => parse("suggest options", text)?,
    };
    let r = crate::suggest::suggest(&model, &spec, &options).map_err(js)?;
    to_js(&r)
}

// ── The built-in slicer, one layer per step (`pipeline::start_builtin`) ──────────────────────

/// The built-in planar slicer of a job's warped STL for the web worker: `step()` until it
/// says `done == total` (a step cuts or writes one layer; the worker posts the progress and
/// stops between steps when cancelled), then `finish()` for the planar G-code.
#[wasm_bindgen]
pub struct BuiltinSlice {
    inner: Option<crate::planar::Slicing>,
}

#[wasm_bindgen]
impl BuiltinSlice {
    /// `stl`: the warped STL `warp` returned; `job_json`: its job; `settings_json`: the
    /// built-in slicer's settings, the JSON of the CLI's `--slicer-settings` (keys left out
    /// keep their defaults, both layer heights default to the job's; `""` for none). Unknown
    /// keys are `planar.settings-json`, bad values `planar.setting`, layer heights other than
    /// the warp's `planar.layer-height`.
    #[wasm_bindgen(constructor)]
    pub fn new(stl: &[u8], job_json: &str, settings_json: &str) -> Result<BuiltinSlice, JsValue> {
        let job = Job::from_json(job_json).map_err(js)?;
        let settings = pipeline::builtin_settings(&job, settings_json).map_err(js)?;
        let inner = pipeline::start_builtin(stl, &job, &settings).map_err(js)?;
        Ok(BuiltinSlice { inner: Some(inner) })
    }
    /// One step: `{ done, total, layers }` after it.
    pub fn step(&mut self) -> Result<JsValue, JsValue> {
        let s = self.slicing()?;
        let p = s.step().map_err(js)?;
        to_js(&p)
    }
    /// The steps left, then `{ gcode: Uint8Array, report: object }` (the slice is spent).
    pub fn finish(&mut self) -> Result<JsValue, JsValue> {
        let s = self
            .inner
            .take()
            .ok_or_else(|| bad_options("builtin slice: finish was called already"))?;
        let out = s.finish().map_err(js)?;
        gcode_and_report(out.gcode.as_bytes(), &out.report)
    }
    fn slicing(&mut self) -> Result<&mut crate::planar::Slicing, JsValue> {
        self.inner
            .as_mut()
            .ok_or_else(|| bad_options("builtin slice: the slice is finished"))
    }
}
