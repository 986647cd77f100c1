//! Speed and memory figures (not a test): `cargo run --release --example bench`.
//!
//! 1. warp + subdivide: a 225 000-triangle sphere (radius 100 mm, edges ≈ 1–1.7 mm) warped
//!    conic 30° outward with the default 1 mm / 0.01 mm subdivision (≥ 900 000 triangles out):
//!    the core step (subdivide + warp) and the whole `warp_model` (read STL, …, write STL).
//! 2. unwarp: PrusaSlicer's G-code (≈ 4 MB) of a 64 mm sphere warped conic 30° outward —
//!    or, without PrusaSlicer, a synthetic planar slicer's (tests/common/synthetic.rs), said so
//!    in the output — streamed in 1 MiB chunks through both passes into a file (memory bounded
//!    by streaming): input MB/s and output lines/s.
//!    Peak memory: VmHWM of this process (Linux), printed after each step.
//! 3. `unwarp --machine` of the same G-code into memory per preset (`--presets a,b` runs only
//!    those; `--rounds N` takes the best of N, default 1), in both interpolation modes (the
//!    default 0.02 mm / 0.1°, and with the paper's 1 mm / 1° caps unless `--no-caps`): the time, its ratio to the
//!    3-axis unwarp of the same G-code measured in this run (issue 13's target: ×2), output
//!    lines/s, and kinematics evaluations per output move (the library's counters,
//!    `machine::tessellate::counters`, with the pieces sampled and bounded in closed form).
//!    Then the collision check as by default (`--no-collisions` skips it): the time ratio, and
//!    whether the default head passed or was refused (at its first finding).
//!
//! The inputs are left in `target/bench-inputs/` for the same work in Node wasm:
//! `bash scripts/bench-wasm.sh` (run this bench first); with the warped ball
//! (`ball.warped.stl`) for the collision check's whole listing of the ball,
//! `cargo run --release --example check_cost -- ball target/bench-inputs/ball.gcode
//! target/bench-inputs/ball.job.json target/bench-inputs/ball.warped.stl`.

#[cfg(not(target_arch = "wasm32"))]
#[path = "../tests/common/synthetic.rs"]
mod synthetic;

fn main() {
    #[cfg(not(target_arch = "wasm32"))]
    native::main();
}

/// The bench needs files, processes and a slicer: native only.
#[cfg(not(target_arch = "wasm32"))]
mod native {
    use super::synthetic;
    use std::io::Write;
    use std::time::Instant;

    use glam::DVec3;
    use warpslice::machine::tessellate::counters;
    use warpslice::mesh::{self, SubdivideOptions};
    use warpslice::pipeline::{warp_model, WarpOptions};
    use warpslice::unwarp::UnwarpOptions;
    use warpslice::warp::{Direction, WarpParams, WarpSpec};

    fn peak_mib() -> String {
        std::fs::read_to_string("/proc/self/status")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("VmHWM:"))
                    .map(|l| l.split_whitespace().nth(1).unwrap_or("0").to_string())
            })
            .and_then(|kb| kb.parse::<f64>().ok())
            .map_or("n/a".into(), |kb| format!("{:.0} MiB", kb / 1024.0))
    }

    fn best_of<T>(n: usize, mut f: impl FnMut() -> T) -> (f64, T) {
        let mut best = f64::INFINITY;
        let mut last = None;
        for _ in 0..n {
            let t = Instant::now();
            let r = f();
            best = best.min(t.elapsed().as_secs_f64());
            last = Some(r);
        }
        (best, last.expect("n > 0"))
    }

    /// This thread's CPU time (user + system), s, from `/proc/thread-self/stat` (USER_HZ =
    /// 100 ticks/s on Linux: 10 ms resolution); `None` off Linux. Step 3 prints it beside the
    /// wall time: on a loaded machine the CPU ratio is the steadier figure.
    fn cpu_s() -> Option<f64> {
        let stat = std::fs::read_to_string("/proc/thread-self/stat").ok()?;
        // the fields after the command's closing parenthesis; utime and stime are 14 and 15
        let rest = &stat[stat.rfind(')')? + 2..];
        let f: Vec<&str> = rest.split_whitespace().collect();
        let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
        Some(ticks / 100.0)
    }

    /// [`best_of`] with the least CPU time of the rounds too (NaN without one).
    fn best_of_cpu<T>(n: usize, mut f: impl FnMut() -> T) -> (f64, f64, T) {
        let mut cpu = f64::INFINITY;
        let (wall, r) = best_of(n, || {
            let c0 = cpu_s();
            let r = f();
            cpu = cpu.min(cpu_s().zip(c0).map_or(f64::NAN, |(b, a)| b - a));
            r
        });
        (wall, cpu, r)
    }

    fn conic() -> WarpParams {
        WarpParams {
            spec: WarpSpec::Conic {
                angle: 30.0,
                direction: Direction::Outward,
                center: [0.0, 0.0],
            },
            base: None,
        }
    }

    pub fn main() {
        // `--machine-only`: step 3 alone (for profiling the machine output with `perf`)
        let machine_only = std::env::args().any(|a| a == "--machine-only");
        if machine_only {
            println!("--machine-only: steps 1 and 2 (warp, 3-axis streaming unwarp) skipped");
        } else {
            warp_and_subdivide();
        }
        unwarp_figures(machine_only);
    }

    /// Step 1's mesh: a 225 000-triangle sphere, radius 120 mm.
    fn big_sphere() -> mesh::Mesh {
        mesh::shapes::uv_sphere(DVec3::new(0.0, 0.0, 120.0), 120.0, 301, 375)
    }

    fn warp_and_subdivide() {
        // 1. warp + subdivide
        let sphere = big_sphere();
        let tris = sphere.triangles.len();
        let mut params = conic();
        let warp = params.build(&sphere.bbox()).expect("warp");
        let (t_core, (out, _, stats)) = best_of(5, || {
            mesh::subdivide_warped(&sphere, &SubdivideOptions::default(), &|p| warp.forward(p))
        });
        println!(
            "warp+subdivide (core): {tris} → {} triangles in {:.3} s = {:.2} M input triangles/s, {:.2} M output triangles/s",
            out.triangles.len(),
            t_core,
            tris as f64 / t_core / 1e6,
            out.triangles.len() as f64 / t_core / 1e6
        );
        let _ = stats;
        let stl = mesh::write_stl(&sphere, "bench sphere");
        let (t_full, w) = best_of(3, || {
            warp_model(&stl, &WarpOptions::new(conic())).expect("warp_model")
        });
        println!(
            "warp_model (read STL, subdivide, warp, anchor, write STL): {:.3} s, {} → {} triangles, STL {:.1} MB → {:.1} MB; peak memory {}",
            t_full,
            tris,
            w.report.triangles_out,
            stl.len() as f64 / 1e6,
            w.stl.len() as f64 / 1e6,
            peak_mib()
        );
    }

    fn unwarp_figures(machine_only: bool) {
        // 2. unwarp
        let ball = mesh::shapes::uv_sphere(DVec3::new(0.0, 0.0, 32.0), 32.0, 48, 96);
        let w = warp_model(
            &mesh::write_stl(&ball, "bench ball"),
            &WarpOptions::new(conic()),
        )
        .expect("warp ball");
        // `--reuse-inputs`: the G-code a previous run left (scripts/bench-wasm.sh, so native and
        // wasm unwarp the same bytes; PrusaSlicer's output differs slightly from run to run)
        let keep = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench-inputs");
        let reuse = std::env::args().any(|a| a == "--reuse-inputs");
        let kept = if reuse {
            std::fs::read(keep.join("ball.gcode")).ok()
        } else {
            None
        };
        let dir = std::env::temp_dir().join(format!("warpslice-bench-{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        let (stl_path, gcode_path) = (dir.join("ball.stl"), dir.join("ball.gcode"));
        let sliced = kept.is_none()
            && std::fs::write(&stl_path, &w.stl).is_ok()
            && warpslice::slicer::slice(
                &stl_path,
                &gcode_path,
                &warpslice::slicer::SliceOptions::default(),
            )
            .is_ok();
        let gcode = if let Some(g) = kept {
            println!("unwarp input: target/bench-inputs/ball.gcode (--reuse-inputs)");
            g
        } else if sliced {
            println!("unwarp input: PrusaSlicer's G-code of a 64 mm sphere, conic 30° outward");
            std::fs::read(&gcode_path).expect("sliced G-code")
        } else {
            println!(
                "unwarp input: PrusaSlicer not available: a synthetic slicer's G-code instead"
            );
            synthetic::gcode(&w.job, true, 1.0).into_bytes()
        };
        let _ = std::fs::remove_dir_all(&dir);
        if !reuse && std::fs::create_dir_all(&keep).is_ok() {
            let sphere = mesh::write_stl(&big_sphere(), "bench sphere");
            let _ = std::fs::write(keep.join("sphere225k.stl"), &sphere);
            let _ = std::fs::write(keep.join("ball.job.json"), w.job.to_json_pretty());
            let _ = std::fs::write(keep.join("ball.gcode"), &gcode);
            // the warped ball, for `check_cost`'s full check (`--allow-collisions`) of the ball:
            // `cargo run --release --example check_cost -- ball target/bench-inputs/ball.gcode
            // target/bench-inputs/ball.job.json target/bench-inputs/ball.warped.stl`
            let _ = std::fs::write(keep.join("ball.warped.stl"), &w.stl);
        }
        if !machine_only {
            streaming_unwarp(&w, &gcode);
        }
        machine_figures(&w, &gcode);
    }

    fn streaming_unwarp(w: &warpslice::pipeline::WarpOutput, gcode: &[u8]) {
        let path =
            std::env::temp_dir().join(format!("warpslice-bench-{}.gcode", std::process::id()));
        let mut lines_out = 0;
        let mut bytes_out = 0;
        let (t_unwarp, _) = best_of(3, || {
            let mut f = std::io::BufWriter::new(std::fs::File::create(&path).expect("temp file"));
            let mut u = warpslice::pipeline::unwarper(&w.job, &UnwarpOptions::default().into())
                .expect("unwarper");
            for c in gcode.chunks(1 << 20) {
                u.scan(c).expect("scan");
            }
            u.end_scan().expect("registration");
            for c in gcode.chunks(1 << 20) {
                u.push(c).expect("push");
                f.write_all(&u.take_output()).expect("write");
            }
            let r = u.finish().expect("finish");
            f.write_all(&u.take_output()).expect("write");
            f.flush().expect("flush");
            lines_out = r.lines_out;
            bytes_out = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        });
        let _ = std::fs::remove_file(&path);
        // the same work into memory (what the Node wasm figure measures: no file writes)
        let (t_mem, _) = best_of(3, || {
            let mut u = warpslice::pipeline::unwarper(&w.job, &UnwarpOptions::default().into())
                .expect("unwarper");
            for c in gcode.chunks(1 << 20) {
                u.scan(c).expect("scan");
            }
            u.end_scan().expect("registration");
            let mut bytes = 0;
            for c in gcode.chunks(1 << 20) {
                u.push(c).expect("push");
                bytes += u.take_output().len();
            }
            u.finish().expect("finish");
            bytes += u.take_output().len();
            std::hint::black_box(bytes);
        });
        let mb_in = gcode.len() as f64 / 1e6;
        println!(
            "unwarp (2 streaming passes, into memory, as the wasm figure): {:.3} s = {:.1} MB/s input",
            t_mem,
            mb_in / t_mem
        );
        println!(
            "unwarp (2 streaming passes, to a file): {:.1} MB → {:.1} MB ({lines_out} lines) in {:.3} s = {:.1} MB/s input, {:.2} M lines/s output; peak memory {}",
            mb_in,
            bytes_out as f64 / 1e6,
            t_unwarp,
            mb_in / t_unwarp,
            lines_out as f64 / t_unwarp / 1e6,
            peak_mib()
        );
    }

    fn machine_figures(w: &warpslice::pipeline::WarpOutput, gcode: &[u8]) {
        // 3. `unwarp --machine` against the 3-axis unwarp of the same G-code, measured in this
        // run (issue 13: within 2×), in both interpolation modes, with the tessellation's
        // counters; then the collision check's cost (`--no-collisions` skips it)
        let only: Option<String> = arg_value("--presets");
        let rounds: usize = arg_value("--rounds")
            .and_then(|v| v.parse().ok())
            .unwrap_or(1)
            .max(1);
        let collisions = !std::env::args().any(|a| a == "--no-collisions");
        let no_caps = std::env::args().any(|a| a == "--no-caps");
        let (t3, c3, out3) = best_of_cpu(3, || {
            warpslice::pipeline::unwarp(gcode, &w.job, &UnwarpOptions::default().into())
                .expect("3-axis unwarp")
        });
        let lines3 = count_lines(&out3.gcode);
        println!(
            "3-axis unwarp (the reference: into memory, best of 3): {t3:.3} s (CPU {c3:.2} s), {lines3} lines, {:.2} M lines/s",
            lines3 as f64 / t3 / 1e6
        );
        for (name, place) in [
            ("cartesian", None),
            ("fullcontrol-prusa-b", None),
            ("rtn-slicer4rtn", None),
            ("pax-5axis", None),
            ("open5x-ab", Some([0.0, 0.0])),
            ("ratrig-vcore3-3z", None),
        ] {
            if only
                .as_ref()
                .is_some_and(|o| !o.split(',').any(|p| p == name))
            {
                continue;
            }
            let spec = warpslice::machine::preset(name).expect("preset");
            let settings = |caps: Option<[f64; 2]>, check: bool| {
                let mut s = warpslice::pipeline::UnwarpSettings::with_machine(
                    UnwarpOptions {
                        place,
                        ..UnwarpOptions::default()
                    },
                    spec.clone(),
                );
                s.output.interpolation_caps = caps;
                s.output.check_collisions = check;
                s
            };
            let mut t_default = f64::NAN;
            for (mode, caps) in [
                ("0.02 mm / 0.1°", None),
                ("0.02 mm / 0.1°, caps 1 mm / 1°", Some([1.0, 1.0])),
            ] {
                if no_caps && caps.is_some() {
                    continue;
                }
                let s = settings(caps, false);
                let before = counters();
                let (t, c, r) =
                    best_of_cpu(rounds, || warpslice::pipeline::unwarp(gcode, &w.job, &s));
                let after = counters();
                let out = match r {
                    Ok(o) => o,
                    Err(e) => {
                        println!("unwarp --machine {name} [{mode}]: refused: {e}");
                        continue;
                    }
                };
                if caps.is_none() {
                    t_default = t;
                }
                let lines = count_lines(&out.gcode);
                let moves = out
                    .report
                    .machine
                    .as_ref()
                    .map_or(0, |m| m.moves_out)
                    .max(1);
                let per_round = |a: u64, b: u64| (b - a) as f64 / rounds as f64;
                let evals = per_round(before.evaluations, after.evaluations);
                println!(
                    "unwarp --machine {name} [{mode}]: {t:.2} s = ×{:.1} the 3-axis unwarp (target ×2; CPU {c:.2} s = ×{:.1}); {lines} lines, {:.2} M lines/s; {:.1} kinematics evaluations per output move ({:.0} pieces sampled, {:.0} bounded in closed form)",
                    t / t3,
                    c / c3,
                    lines as f64 / t / 1e6,
                    evals / moves as f64,
                    per_round(before.sampled, after.sampled),
                    per_round(before.bounded, after.bounded),
                );
            }
            if collisions {
                let t = Instant::now();
                let on = warpslice::pipeline::unwarp(gcode, &w.job, &settings(None, true));
                let t_on = t.elapsed().as_secs_f64();
                let verdict = match on {
                    Ok(_) => "passed: no collision".to_string(),
                    Err(e) => format!(
                        "refused: {}",
                        e.to_string().chars().take(110).collect::<String>()
                    ),
                };
                println!(
                    "unwarp --machine {name} with the collision check: {t_on:.2} s (×{:.2} of the check off); {verdict}",
                    t_on / t_default
                );
            }
        }
    }

    /// The value after `flag` on the command line.
    fn arg_value(flag: &str) -> Option<String> {
        std::env::args().skip_while(|a| a != flag).nth(1)
    }

    fn count_lines(text: &[u8]) -> usize {
        text.iter().filter(|&&b| b == b'\n').count()
    }
}
