//! Speed of the built-in slicer (issue 14; figures, not a test):
//! `cargo run --release --example builtin_bench`.
//!
//! A 60 mm sphere of 225 000 triangles (UV sphere, 301 rings × 375 segments), warped conic 30°
//! outward with the default subdivision, is sliced by the builtin (its default settings,
//! single-threaded) and, when installed, by PrusaSlicer (the matrix's command line,
//! `warpslice::slicer::slice`) from the same warped STL; both wall times are printed side by
//! side with the machine's load average (the figures are from a shared machine). The issue's
//! target: at most 5 s natively. The warped STL and its job are left in `target/bench-inputs/`
//! for the same slice in Node wasm (`bash scripts/bench-wasm.sh`, which runs this with
//! `--no-prusaslicer`: the builtin only).

fn main() {
    #[cfg(not(target_arch = "wasm32"))]
    native::main();
}

#[cfg(not(target_arch = "wasm32"))]
mod native {
    use std::time::Instant;

    use glam::DVec3;
    use warpslice::mesh;
    use warpslice::pipeline::{slice_builtin, warp_model, WarpOptions};
    use warpslice::planar::Settings;
    use warpslice::slicer::{self, SliceOptions, SlicerKind};
    use warpslice::warp::{Direction, WarpParams, WarpSpec};

    fn load() -> String {
        std::fs::read_to_string("/proc/loadavg")
            .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
            .unwrap_or_else(|_| "n/a".into())
    }

    pub fn main() {
        let sphere = mesh::shapes::uv_sphere(DVec3::new(0.0, 0.0, 30.0), 30.0, 301, 375);
        let stl = mesh::write_stl(&sphere, "builtin bench sphere");
        let params = WarpParams {
            spec: WarpSpec::Conic {
                angle: 30.0,
                direction: Direction::Outward,
                center: [0.0, 0.0],
            },
            base: None,
        };
        let t = Instant::now();
        let w = warp_model(&stl, &WarpOptions::new(params)).expect("warp");
        let warp_s = t.elapsed().as_secs_f64();
        let warped_tris = (w.stl.len() - 84) / 50;
        println!(
            "model: sphere 60 mm, {} triangles; warped conic 30° outward and subdivided: {warped_tris} triangles ({warp_s:.2} s); load average {}",
            sphere.triangles.len(),
            load()
        );
        let settings = Settings {
            layer_height: w.job.layer_height,
            first_layer_height: w.job.layer_height,
            ..Settings::default()
        };
        let t = Instant::now();
        let out = slice_builtin(&w.stl, &w.job, &settings).expect("builtin slice");
        let builtin_s = t.elapsed().as_secs_f64();
        println!(
            "builtin: {builtin_s:.2} s (target ≤ 5 s), {} layers, {:.1} MB of G-code; load average {}",
            out.report.layers,
            out.gcode.len() as f64 / 1e6,
            load()
        );
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench-inputs");
        let _ = std::fs::create_dir_all(&dir);
        let path = dir.join("builtin-sphere-conic30.stl");
        std::fs::write(&path, &w.stl).expect("write warped STL");
        // its job too: scripts/bench-wasm.sh slices the same warped STL in wasm
        std::fs::write(
            dir.join("builtin-sphere-conic30.job.json"),
            w.job.to_json_pretty(),
        )
        .expect("write job");
        // `--no-prusaslicer`: the builtin only (scripts/bench-wasm.sh's rounds)
        if std::env::args().any(|a| a == "--no-prusaslicer") {
            return;
        }
        if let Err(e) = slicer::available(SlicerKind::PrusaSlicer) {
            println!("PrusaSlicer: not run ({e})");
            return;
        }
        let gcode = dir.join("builtin-sphere-conic30.prusaslicer.gcode");
        let opts = SliceOptions {
            slicer: SlicerKind::PrusaSlicer,
            layer_height: w.job.layer_height,
            ..SliceOptions::default()
        };
        let t = Instant::now();
        match slicer::slice(&path, &gcode, &opts) {
            Ok(_) => println!(
                "PrusaSlicer: {:.2} s on the same warped STL (its own threads); load average {}",
                t.elapsed().as_secs_f64(),
                load()
            ),
            Err(e) => println!("PrusaSlicer: failed: {e}"),
        }
    }
}
