//! `warpslice check` through the wasm API (`wasm-pack test --node -- --test check_wasm`): the
//! streaming `CheckStream` object on the hand-built files of tests/common/check_files.rs (each
//! knows the line of its finding), fed in small slices; the report is a plain JS object with
//! the CLI's `--json` shape; unreadable input throws the core's code. Limits and feeds of the
//! oracle are read from the machine's own description (`describe_machine`), not the checker.
//!
//! wasm only: the glue (`src/wasm.rs`) exists only for wasm32 (natively tests/check_gcode.rs
//! checks the same files through the library and the CLI).
#![cfg(target_arch = "wasm32")]

#[path = "common/check_files.rs"]
mod check_files;

use check_files::{bhead_speed_file, clean_file, rtn_reach_file};
use warpslice::wasm;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::wasm_bindgen_test as test;

/// Check `text` for `machine` in 100-byte slices: the report as JSON, and the path's lines.
fn checked(machine: &str, text: &str) -> Result<(serde_json::Value, Vec<f64>), JsValue> {
    checked_with_axes(machine, text).map(|(r, lines, _)| (r, lines))
}

/// [`checked`], with the path's axis values (one `Vec` per point).
#[allow(clippy::type_complexity)]
fn checked_with_axes(
    machine: &str,
    text: &str,
) -> Result<(serde_json::Value, Vec<f64>, Vec<Vec<f64>>), JsValue> {
    let mut s = wasm::CheckStream::new(machine, r#"{"path": true}"#)?;
    let mut lines = Vec::new();
    let mut axes = Vec::new();
    let mut take = |s: &mut wasm::CheckStream| -> Result<(), JsValue> {
        let o = s.take_path()?;
        let get = |k: &str| js_sys::Reflect::get(&o, &JsValue::from_str(k));
        let l = get("lines")?.dyn_into::<js_sys::Float64Array>()?.to_vec();
        let a = get("axes")?.dyn_into::<js_sys::Float64Array>()?.to_vec();
        let k = get("axisCount")?.as_f64().unwrap_or(0.0) as usize;
        if !l.is_empty() {
            assert_eq!(a.len(), k * l.len(), "{k} axes per point");
            axes.extend(a.chunks(k).map(<[f64]>::to_vec));
        }
        lines.extend(l);
        Ok(())
    };
    for chunk in text.as_bytes().chunks(100) {
        s.push(chunk)?;
        take(&mut s)?;
    }
    let r = s.finish()?;
    take(&mut s)?;
    let json = js_sys::JSON::stringify(&r)?.as_string().unwrap();
    Ok((serde_json::from_str(&json).unwrap(), lines, axes))
}

/// The axis `name` of `machine` as the machine describes itself.
fn axis(machine: &str, name: &str) -> serde_json::Value {
    let d: serde_json::Value =
        serde_json::from_str(&wasm::describe_machine(machine).unwrap()).unwrap();
    d["axes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["name"] == name)
        .cloned()
        .unwrap()
}

#[test]
fn reach_finding_on_its_line_through_wasm() {
    let (text, bad) = rtn_reach_file();
    let (r, lines) = checked("rtn-slicer4rtn", &text).unwrap();
    assert_eq!(r["counts"]["reach"], 1, "{r}");
    assert_eq!(
        r["findings"].as_array().unwrap().len(),
        1,
        "only the reach finding: {r}"
    );
    let f = &r["findings"][0];
    assert_eq!(
        (f["kind"].as_str(), f["line"].as_u64()),
        (Some("reach"), Some(bad))
    );
    assert_eq!(f["axis"], "A");
    assert_eq!(f["value"], 175.0);
    assert_eq!(
        f["limit"].as_f64(),
        axis("rtn-slicer4rtn", "A")["max"].as_f64()
    );
    // one path point per move line (lines 4 to 12), in order
    assert_eq!(lines, (4..=12).map(f64::from).collect::<Vec<_>>());
}

#[test]
fn speed_finding_on_its_line_through_wasm() {
    let (text, fast) = bhead_speed_file();
    let (r, _) = checked("fullcontrol-prusa-b", &text).unwrap();
    assert_eq!(r["counts"]["speed"], 1, "{r}");
    let w = &r["worst_speed"];
    assert_eq!(w["line"].as_u64(), Some(fast));
    assert_eq!(w["axis"], "B");
    assert!((w["value"].as_f64().unwrap() - 36000.0).abs() < 1e-6);
    assert_eq!(
        w["limit"].as_f64(),
        axis("fullcontrol-prusa-b", "B")["max_feed"].as_f64()
    );
}

#[test]
fn clean_file_through_wasm_and_unreadable_input_throws_its_code() {
    let (r, _) = checked("cartesian", &clean_file()).unwrap();
    assert_eq!(r["counts"]["reach"], 0, "{r}");
    assert_eq!(r["counts"]["collision"], 0, "{r}");
    assert_eq!(r["counts"]["speed"], 0, "{r}");
    assert_eq!(r["extruding_moves"], 20);
    let code = |e: JsValue| {
        js_sys::Reflect::get(&e, &JsValue::from_str("code"))
            .unwrap()
            .as_string()
            .unwrap()
    };
    let e = checked("rtn-slicer4rtn", "G90\nG1 X1 Y1 Z1 A0\nG1 X1.2.3 Y1\n").unwrap_err();
    assert_eq!(code(e), "check.bad-number");
    let e = checked("no-such-machine", "G1 X1\n").unwrap_err();
    assert_eq!(code(e), "machine.unknown-preset");
    let e = checked("cartesian", "just text\n").unwrap_err();
    assert_eq!(code(e), "check.no-moves");
}

#[test]
fn path_points_carry_the_files_axis_values_and_the_head_is_posed_there_through_wasm() {
    // rtn_reach_file's moves (lines 4 to 12), their X Y Z A as the file writes them (modal)
    let (text, _) = rtn_reach_file();
    let (_, lines, axes) = checked_with_axes("rtn-slicer4rtn", &text).unwrap();
    assert_eq!(lines, (4..=12).map(f64::from).collect::<Vec<_>>());
    let want: [[f64; 4]; 9] = [
        [100.0, 100.0, 5.0, 0.0],
        [100.0, 101.0, 5.0, 0.0],
        [100.0, 101.0, 8.0, 0.0],
        [120.0, 100.0, 8.0, 90.0],
        [120.0, 100.0, 5.0, 90.0],
        [120.0, 101.0, 5.0, 90.0],
        [120.0, 101.0, 8.0, 90.0],
        [140.0, 100.0, 8.0, 175.0],
        [160.0, 100.0, 8.0, 100.0],
    ];
    assert_eq!(axes, want.map(|a| a.to_vec()).to_vec());
    // the B head at X 120 Y 80 Z 30 B 40: the nozzle's base disc at the tip of docs/machines.md
    // (X − r sin B, Y, Z − r cos B + r), r = pivot_to_tip_mm from the machine's description
    let d: serde_json::Value =
        serde_json::from_str(&wasm::describe_machine("fullcontrol-prusa-b").unwrap()).unwrap();
    let r = d["spec"]["pivot_to_tip_mm"].as_f64().unwrap();
    let h = wasm::head_pose("fullcontrol-prusa-b", &[120.0, 80.0, 30.0, 40.0]).unwrap();
    let json = js_sys::JSON::stringify(&h).unwrap().as_string().unwrap();
    let h: serde_json::Value = serde_json::from_str(&json).unwrap();
    let (s, c) = 40f64.to_radians().sin_cos();
    let tip = [120.0 - r * s, 80.0, 30.0 - r * c + r];
    let nozzle = &h["parts"][0];
    assert_eq!(
        (nozzle["name"].as_str(), nozzle["kind"].as_str()),
        (Some("nozzle"), Some("frustum"))
    );
    for (k, t) in tip.iter().enumerate() {
        assert!(
            (nozzle["base"][k].as_f64().unwrap() - t).abs() < 1e-9,
            "{h}"
        );
    }
    let e = wasm::head_pose("fullcontrol-prusa-b", &[1.0, 2.0]).unwrap_err();
    let code = js_sys::Reflect::get(&e, &JsValue::from_str("code")).unwrap();
    assert_eq!(
        code.as_string().as_deref(),
        Some("machine.wrong-axis-count")
    );
}
