//! Calibration under wasm (`wasm-pack test --node -- --test calibrate_wasm`): the core gives the
//! same bytes as natively (all trigonometry through libm), and the wasm glue
//! (`warpslice::wasm::calibrate_*`) works. The core checks also run natively.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use warpslice::calibrate::patterns::{self, PrintOptions, TestKind};
use warpslice::calibrate::{calibrate_origin, parse_measurements, simulate, OriginOptions};
use warpslice::job::fnv1a64;
use warpslice::machine::preset;

const LISTING_4_1: &str = "ab_values\na_axis {0,-0.1650009,-0.2140012}\na_z_in_y 0.0030937\na_axis_dir {0.9994476,0.0332315,-0.0004059}\nb_axis {-0.1399994,0.0900002,-10}\nb_axis_dir {0.0010010,0.0059996,0.9999815}\n";

/// The calibrated machine JSON and the integrated test print for it (hashes).
fn outputs() -> (u64, u64, u64) {
    let s = parse_measurements(LISTING_4_1).unwrap();
    let opts = OriginOptions {
        bias: glam::DVec3::new(0.326, 0.453, 0.05),
        a_z_correction_deg: -0.258,
    };
    let (_, spec) = calibrate_origin(&s, &opts, &preset("open5x-ab").unwrap()).unwrap();
    let tp = patterns::test_print(&spec, TestKind::Integrated, &PrintOptions::default()).unwrap();
    let fig = simulate::fig_3_1(20.0, 2.0).unwrap();
    (
        fnv1a64(spec.to_json().as_bytes()),
        fnv1a64(&tp.gcode),
        fig.to_bits(),
    )
}

/// Produced natively (the assertion prints what to paste here when the output changes).
const EXPECTED: (u64, u64, u64) = (
    17144976751020874729,
    9822540106536362821,
    4604463111635489894,
);

#[test]
fn calibration_outputs_are_bit_identical_to_native() {
    assert_eq!(outputs(), EXPECTED);
}

#[cfg(target_arch = "wasm32")]
mod glue {
    use warpslice::wasm;
    use wasm_bindgen::JsValue;
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn get(obj: &JsValue, key: &str) -> JsValue {
        js_sys::Reflect::get(obj, &JsValue::from_str(key)).unwrap()
    }

    #[test]
    fn origin_gives_report_text_and_machine_json() {
        let r = wasm::calibrate_origin(super::LISTING_4_1, "", "")
            .map_err(|_| "origin failed")
            .unwrap();
        let text = get(&r, "text").as_string().unwrap();
        assert!(text.contains("1.904375"), "{text}");
        let json = get(&r, "machineJson").as_string().unwrap();
        let m = warpslice::machine::MachineSpec::from_json(&json, "wasm")
            .unwrap()
            .build()
            .unwrap();
        warpslice::machine::laws::check_round_trip(m.as_ref()).unwrap();
        // A malformed file is an error (the message names the line; JsError hides it here).
        assert!(wasm::calibrate_origin("head\na_axis {0,1}\n", "", "").is_err());
    }

    #[test]
    fn probe_test_print_and_simulation() {
        let r = wasm::calibrate_probe(
            r#"{"kind":"a-pos","z0":-5,"y90":4.2,"y_minus90":-3.8,"c_y":0.453}"#,
        )
        .map_err(|_| "probe failed")
        .unwrap();
        assert!(get(&r, "text").as_string().unwrap().contains("-0.2265"));
        let t = wasm::calibrate_test_print("open5x-ab", "b-position", "")
            .map_err(|_| "print failed")
            .unwrap();
        let g = js_sys::Uint8Array::new(&get(&t, "gcode")).to_vec();
        assert!(String::from_utf8(g).unwrap().contains("B720"));
        let s = wasm::calibrate_simulate(
            "open5x-ab",
            "",
            r#"{"a_rot_z_deg": 2}"#,
            "0,20,0,0,1,0\n",
            "",
            1.0,
        )
        .map_err(|_| "simulate failed")
        .unwrap();
        let e = get(&s, "maxErrorMm").as_f64().unwrap();
        assert_eq!(format!("{e:.3}"), "0.698");
        assert!(get(&s, "svg").as_string().unwrap().starts_with("<svg"));
        let f = wasm::calibrate_fig_3_1(20.0, 2.0)
            .map_err(|_| "fig failed")
            .unwrap();
        assert_eq!(f, e);
        let b = wasm::calibrate_b_position_svg("open5x-ab", 0.0, -0.2, "", 10.0)
            .map_err(|_| "svg failed")
            .unwrap();
        assert!((get(&b, "maxErrorMm").as_f64().unwrap() - 0.4).abs() < 1e-3);
    }
}
