//! The built-in slicer gives the same bytes natively and in wasm (issue 14, acceptance 4): for
//! two generated parts × the five acceptance warps × relative and absolute E, the warped STL
//! is sliced by the builtin (its default settings) and unwarped against it, as `warpslice run`
//! does; the planar G-code and the unwarped G-code are hashed (FNV-1a 64) and compared with
//! `tests/golden/planar_parity.txt`, natively (`cargo test --test planar_parity`) and under
//! wasm (`wasm-pack test --node -- --test planar_parity`, part of `bash scripts/test.sh wasm`).
//! `WARPSLICE_BLESS=1 cargo test --test planar_parity` rewrites the golden file after an
//! intended change of the slicer's output.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use warpslice::job::fnv1a64;
use warpslice::pipeline::{slice_builtin, unwarp_with_stl, UnwarpSettings};
use warpslice::pipeline::{warp_model, WarpOptions};
use warpslice::planar::Settings;

#[path = "common/acceptance.rs"]
mod acceptance;

const GOLDEN: &str = include_str!("golden/planar_parity.txt");

/// The generated parts of the cases (`warpslice::shapes::EXAMPLES`).
const PARTS: [&str; 2] = ["sphere", "overhang"];

/// `part warp rel|abs planar-hash unwarped-hash` per case.
fn compute() -> String {
    let mut out = String::new();
    for part in PARTS {
        let stl = warpslice::mesh::write_stl(&warpslice::shapes::example(part).unwrap(), part);
        for (name, params) in acceptance::acceptance_warps() {
            let w = warp_model(&stl, &WarpOptions::new(params)).unwrap();
            for relative in [true, false] {
                let settings = Settings {
                    layer_height: w.job.layer_height,
                    first_layer_height: w.job.layer_height,
                    use_relative_e_distances: relative,
                    ..Settings::default()
                };
                let sliced = slice_builtin(&w.stl, &w.job, &settings)
                    .unwrap_or_else(|e| panic!("{part} × {name}: slice: {e}"));
                let u = unwarp_with_stl(
                    sliced.gcode.as_bytes(),
                    &w.job,
                    &UnwarpSettings::default(),
                    Some(&w.stl),
                )
                .unwrap_or_else(|e| panic!("{part} × {name}: unwarp: {e}"));
                assert!(
                    u.report.segments_out > 100,
                    "{part} × {name}: {:?}",
                    u.report
                );
                out += &format!(
                    "{part} {name} {} {:016x} {:016x}\n",
                    if relative { "rel" } else { "abs" },
                    fnv1a64(sliced.gcode.as_bytes()),
                    fnv1a64(&u.gcode)
                );
            }
        }
    }
    out
}

#[test]
fn builtin_slice_and_unwarp_are_byte_identical_to_the_recorded_native_output() {
    let got = compute();
    #[cfg(not(target_arch = "wasm32"))]
    if std::env::var("WARPSLICE_BLESS").as_deref() == Ok("1") {
        std::fs::write(
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/tests/golden/planar_parity.txt"
            ),
            &got,
        )
        .unwrap();
        return;
    }
    assert_eq!(
        got, GOLDEN,
        "output differs from tests/golden/planar_parity.txt (WARPSLICE_BLESS=1 after an intended change)"
    );
}
