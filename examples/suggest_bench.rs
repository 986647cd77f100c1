//! Speed of the overhang measure and of `suggest` (not a test):
//! `cargo run --release --example suggest_bench [-- --rounds N]`.
//!
//! 1. The bench sphere of `examples/bench.rs` (radius 120 mm, 301 × 375, 225 000 triangles),
//!    in the model frame: preparing the facets ([`Facets::new`] and the search's samples),
//!    one overhang measure under a 30° cone, and `suggest` on two presets with different tilt
//!    limits (`ratrig-vcore3-3z` 30°, `pax-5axis` 90°), the default families with the fitted
//!    field and then without it (issue 15's target: ≤ 2 s natively).
//! 2. The largest `accept` model of the corpus (`np_rear_case_bin_solidheader.stl`, 18 808
//!    triangles) when `../shared/corpus/stl` is there.
//!
//! Times are the best of `--rounds` (default 1) wall-clock runs on this machine, with that
//! run's CPU time. `--stl-out PATH` writes the bench sphere's STL and measures the sphere read
//! back from it: the input of `bench/suggest-wasm.mjs`, the same `suggest` in Node wasm.

use std::time::Instant;

use glam::DVec3;
use warpslice::machine::preset;
use warpslice::overhang::Facets;
use warpslice::suggest::{self, Family, Model, SuggestOptions, FAMILIES};
use warpslice::warp::{Direction, WarpParams, WarpSpec};

/// This process' CPU time (user + system), seconds, from /proc/self/stat (Linux; 0 elsewhere).
fn cpu_s() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|s| {
            let rest = s.rsplit_once(')')?.1.split_whitespace().collect::<Vec<_>>();
            // after the command: state is field 3, utime 14, stime 15 (1-based)
            let u: f64 = rest.get(11)?.parse().ok()?;
            let k: f64 = rest.get(12)?.parse().ok()?;
            Some((u + k) / 100.0)
        })
        .unwrap_or(0.0)
}

/// The best wall-clock time of `n` runs and the CPU time of that run (the machine may be
/// shared: CPU time is what the work costs).
fn best_of<T>(n: usize, mut f: impl FnMut() -> T) -> ((f64, f64), T) {
    let mut best = (f64::INFINITY, 0.0);
    let mut last = None;
    for _ in 0..n.max(1) {
        let (t, c) = (Instant::now(), cpu_s());
        let r = f();
        let wall = t.elapsed().as_secs_f64();
        if wall < best.0 {
            best = (wall, cpu_s() - c);
        }
        last = Some(r);
    }
    (best, last.expect("n ≥ 1"))
}

fn run_on(name: &str, model: &Model, rounds: usize) {
    println!(
        "{name}: {} triangles, {} samples ({} coarse)",
        model.mesh.triangles.len(),
        model.samples.len(),
        model.coarse_samples.len()
    );
    let cone = WarpParams {
        spec: WarpSpec::Conic {
            angle: 30.0,
            direction: Direction::Outward,
            center: [0.0, 0.0],
        },
        base: None,
    }
    .build(&model.bbox)
    .expect("cone");
    let ((t, _), m) = best_of(rounds, || model.facets.measure(Some(cone.as_ref()), 45.0));
    println!(
        "  one measure (conic 30° out): {:.1} ms, {:.1} mm² left of {:.1} planar",
        t * 1e3,
        m.area_mm2,
        model.facets.measure(None, 45.0).area_mm2
    );
    // the default families, then without the fitted field (what the fit itself costs)
    let families = [
        ("", SuggestOptions::default()),
        (
            " without the field",
            SuggestOptions {
                families: FAMILIES
                    .iter()
                    .copied()
                    .filter(|&f| f != Family::Field)
                    .collect(),
                ..SuggestOptions::default()
            },
        ),
    ];
    for machine in ["ratrig-vcore3-3z", "pax-5axis"] {
        let spec = preset(machine).expect("preset");
        for (what, options) in &families {
            let ((t, cpu), r) = best_of(rounds, || {
                suggest::suggest(model, &spec, options).expect("suggest")
            });
            println!(
            "  suggest{what} on {machine}: {t:.3} s wall, {cpu:.2} s CPU, {} warps measured; best: {}",
            r.measured,
            r.suggestions
                .first()
                .map_or("(planar)".to_string(), |s| format!(
                    "{} → {:.1} mm²",
                    s.flags, s.overhang_area_mm2
                ))
        );
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rounds = args
        .iter()
        .position(|a| a == "--rounds")
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let sphere = warpslice::mesh::shapes::uv_sphere(DVec3::new(0.0, 0.0, 120.0), 120.0, 301, 375);
    // `--stl-out PATH`: write the sphere as STL and run on it as read back (f32 vertices), the
    // input `bench/suggest-wasm.mjs` times in wasm
    let stl_out = args
        .iter()
        .position(|a| a == "--stl-out")
        .and_then(|i| args.get(i + 1));
    let sphere = match stl_out {
        Some(path) => {
            let bytes = warpslice::mesh::write_stl(&sphere, "suggest_bench sphere");
            std::fs::write(path, &bytes).expect("--stl-out");
            println!("bench sphere written to {path}; measured as read back");
            suggest::model_of(&bytes).expect("the written STL").mesh
        }
        None => sphere,
    };
    let ((t, _), model) = best_of(rounds, || Model::new(sphere.clone()));
    let ((tf, _), _) = best_of(rounds, || Facets::new(&sphere));
    println!(
        "bench sphere: prepared in {:.1} ms (facets alone {:.1} ms)",
        t * 1e3,
        tf * 1e3
    );
    run_on("bench sphere", &model, rounds);
    let rear = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/corpus/stl/np_rear_case_bin_solidheader.stl");
    match std::fs::read(&rear) {
        Ok(bytes) => run_on(
            "np_rear_case",
            &suggest::model_of(&bytes).expect("rear case"),
            rounds,
        ),
        Err(e) => println!("{}: {e} (skipped)", rear.display()),
    }
}
