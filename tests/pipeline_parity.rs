//! Native and wasm give byte-identical output: for every warp, the warped STL of a generated
//! part and the unwarp of a synthetic slicer's G-code are hashed (FNV-1a 64) and compared with
//! `tests/golden/pipeline_parity.txt`, natively (`cargo test`) and under wasm (`wasm-pack test
//! --node`), so both produce exactly the recorded bytes. `WARPSLICE_BLESS=1 cargo test --test
//! pipeline_parity` rewrites the golden file after an intended change.
//! Also: the warp laws on a fixed grid (the property tests do not run under wasm).

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

#[path = "common/synthetic.rs"]
mod synthetic;

use glam::DVec3;
use warpslice::job::fnv1a64;
use warpslice::pipeline::{unwarp, UnwarpSettings};
use warpslice::pipeline::{warp_model, WarpOptions};
use warpslice::warp::{laws, Direction, WarpParams, WarpSpec};

const GOLDEN: &str = include_str!("golden/pipeline_parity.txt");

fn cases() -> Vec<(&'static str, WarpParams)> {
    vec![
        (
            "curved",
            WarpParams {
                spec: WarpSpec::Curved {
                    strength: 0.3,
                    direction: Direction::Outward,
                    offset: 0.0,
                    width: 0.0,
                },
                base: None,
            },
        ),
        (
            "tilted",
            WarpParams {
                spec: WarpSpec::Tilted {
                    strength: 0.2,
                    direction: Direction::Outward,
                    offset: 0.0,
                },
                base: None,
            },
        ),
        (
            "conic-out",
            WarpParams {
                spec: WarpSpec::Conic {
                    angle: 30.0,
                    direction: Direction::Outward,
                    center: [0.0, 0.0],
                },
                base: None,
            },
        ),
        (
            "conic-in",
            WarpParams {
                spec: WarpSpec::Conic {
                    angle: 30.0,
                    direction: Direction::Inward,
                    center: [0.0, 0.0],
                },
                base: None,
            },
        ),
        (
            "belt-base",
            WarpParams {
                spec: WarpSpec::Belt {
                    angle: 15.0,
                    toward: [0.0, 1.0],
                },
                base: Some([0.6, 10.0]),
            },
        ),
    ]
}

/// `name stl-hash gcode-hash` per case.
fn compute() -> String {
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("sphere").unwrap(), "parity");
    let mut out = String::new();
    for (name, params) in cases() {
        let w = warp_model(&stl, &WarpOptions::new(params)).unwrap();
        for relative in [true, false] {
            let g = synthetic::gcode(&w.job, relative, 2.0);
            let u = unwarp(g.as_bytes(), &w.job, &UnwarpSettings::default()).unwrap();
            assert!(u.report.segments_out > 100, "{name}: {:?}", u.report);
            out += &format!(
                "{name} {} {:016x} {:016x}\n",
                if relative { "rel" } else { "abs" },
                fnv1a64(&w.stl),
                fnv1a64(&u.gcode)
            );
        }
    }
    out
}

#[test]
fn output_is_byte_identical_to_the_recorded_native_output() {
    let got = compute();
    #[cfg(not(target_arch = "wasm32"))]
    if std::env::var("WARPSLICE_BLESS").as_deref() == Ok("1") {
        std::fs::write(
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/tests/golden/pipeline_parity.txt"
            ),
            &got,
        )
        .unwrap();
        return;
    }
    assert_eq!(got, GOLDEN, "output differs from tests/golden/pipeline_parity.txt (WARPSLICE_BLESS=1 after an intended change)");
}

#[test]
fn warp_laws_on_a_grid() {
    let bbox = warpslice::mesh::Aabb {
        min: DVec3::new(-20.0, -15.0, 0.0),
        max: DVec3::new(20.0, 15.0, 30.0),
    };
    for (name, mut params) in cases() {
        let w = params.build(&bbox).unwrap();
        for i in 0..9 {
            for j in 0..7 {
                for k in 0..6 {
                    // offsets keep the grid off creases, apexes and blend ends
                    let p = DVec3::new(
                        -19.3 + 4.7 * i as f64,
                        -14.1 + 4.3 * j as f64,
                        0.37 + 5.3 * k as f64,
                    );
                    laws::check_point(w.as_ref(), p, true)
                        .unwrap_or_else(|e| panic!("{name}: {e}"));
                }
            }
        }
    }
}
