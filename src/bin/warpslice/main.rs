//! The `warpslice` command line: parses arguments, calls the core, prints. Nothing else.

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::main()
}

#[cfg(not(target_arch = "wasm32"))]
mod args;
#[cfg(not(target_arch = "wasm32"))]
mod builtin;
#[cfg(not(target_arch = "wasm32"))]
mod calibrate;
#[cfg(not(target_arch = "wasm32"))]
mod out;
#[cfg(not(target_arch = "wasm32"))]
mod schema_args;
#[cfg(not(target_arch = "wasm32"))]
mod suggest;

#[cfg(not(target_arch = "wasm32"))]
mod cli {
    use std::io::{IsTerminal, Read, Write};
    use std::path::{Path, PathBuf};
    use std::process::ExitCode;

    use clap::{Parser, Subcommand, ValueEnum};

    use crate::args::machine_spec;
    use crate::out::{say, write};
    use crate::schema_args::{UnwarpArgs, WarpArgs};
    use indicatif::{ProgressBar, ProgressStyle};
    use warpslice::pipeline::files::{self, Observer};
    use warpslice::pipeline::WarpOutput;
    use warpslice::slicer::SliceReport;
    use warpslice::unwarp::UnwarpReport;

    /// Non-planar slicing with any planar slicer: warp an STL, slice it, unwarp the G-code.
    #[derive(Parser)]
    #[command(name = "warpslice", version, about)]
    struct Cli {
        #[command(subcommand)]
        command: Command,
    }

    #[derive(Subcommand)]
    enum Command {
        /// Warp an STL for slicing; writes WARPED.stl and WARPED.job.json.
        Warp {
            /// The model.
            model: PathBuf,
            #[command(flatten)]
            warp: WarpArgs<true>,
            /// Instead of --warp: entry N (1 = best) of `warpslice suggest` for --machine (the
            /// same deterministic search, run again).
            #[arg(long, value_name = "N", requires = "machine", conflicts_with = "warp")]
            suggested: Option<usize>,
            /// With --suggested: a preset or a machine JSON file (docs/machines.md).
            #[arg(long, value_name = "PRESET|FILE.json", requires = "suggested")]
            machine: Option<String>,
            #[command(flatten)]
            suggest: crate::suggest::SuggestArgs<{ crate::suggest::which::SUGGESTED }>,
            /// The warped STL to write (the job goes next to it as .job.json).
            #[arg(short, long)]
            output: PathBuf,
        },
        /// How much of a model overhangs, planar and under a warp (issue 15's measure).
        Overhangs {
            /// The model.
            model: PathBuf,
            #[command(flatten)]
            warp: WarpArgs<true>,
            #[command(flatten)]
            angle: crate::suggest::SuggestArgs<{ crate::suggest::which::ANGLE }>,
            /// Print the report as JSON, with per-facet flags (0/1, the input's facet order).
            #[arg(long)]
            json: bool,
        },
        /// Rank the admissible warps of the seed families that leave the least overhang on a
        /// machine.
        Suggest {
            /// The model.
            model: PathBuf,
            /// A preset or a machine JSON file (docs/machines.md).
            #[arg(long, value_name = "PRESET|FILE.json")]
            machine: String,
            #[command(flatten)]
            suggest: crate::suggest::SuggestArgs<{ crate::suggest::which::ALL }>,
            /// Print the suggestions as a JSON array, best first.
            #[arg(long)]
            json: bool,
        },
        /// Map a planar slicer's G-code of the warped STL back to the real part.
        Unwarp {
            /// The slicer's G-code of the warped STL.
            gcode: PathBuf,
            /// The job file written by `warp`.
            #[arg(long)]
            job: PathBuf,
            /// The warped STL written with the job: registers the G-code to the bead against
            /// its cross-sections (default: the one beside the job, `X.stl` for `X.job.json`,
            /// when it is this job's; without one, by bounding boxes).
            #[arg(long)]
            stl: Option<PathBuf>,
            #[command(flatten)]
            unwarp: Box<UnwarpArgs<false>>,
            /// The unwarped G-code to write.
            #[arg(short, long)]
            output: PathBuf,
            /// With --machine: also write the firmware configuration the G-code needs
            /// (RepRapFirmware config.g lines, Marlin Configuration.h block, Klipper
            /// printer.cfg sections, per --flavour) to this file, ready to paste.
            #[arg(long)]
            config_out: Option<PathBuf>,
        },
        /// Warp, slice (the built-in slicer, or a real slicer installed here), and unwarp: the
        /// main job in one command.
        Run {
            model: PathBuf,
            /// builtin (warpslice's own planar slicer, nothing to install), prusaslicer,
            /// slic3r or curaengine.
            #[arg(long, default_value = "builtin")]
            slicer: String,
            /// builtin: a JSON file of slicer settings (PrusaSlicer's option names,
            /// docs/builtin-slicer.md); keys left out keep their defaults.
            #[arg(long, value_name = "FILE.json")]
            slicer_settings: Option<PathBuf>,
            /// builtin: one slicer setting, after --slicer-settings (repeatable), e.g.
            /// --set fill_density=100.
            #[arg(long = "set", value_name = "KEY=VALUE")]
            set: Vec<String>,
            /// Also keep the planar G-code of the warped STL as FILE, with its job beside it as
            /// FILE.job.json, so any checker can compare the two.
            #[arg(long, value_name = "FILE")]
            keep_sliced: Option<PathBuf>,
            /// Relative (M83) or absolute (M82) E in the slicer's G-code.
            #[arg(long, value_enum, default_value_t = EModeArg::Relative)]
            e_mode: EModeArg,
            #[command(flatten)]
            warp: WarpArgs,
            #[command(flatten)]
            unwarp: Box<UnwarpArgs<true>>,
            /// The unwarped G-code to write (the warped STL, its job and the sliced G-code go
            /// next to it).
            #[arg(short, long)]
            output: PathBuf,
            /// With --machine: also write the firmware configuration the G-code needs
            /// (RepRapFirmware config.g lines, Marlin Configuration.h block, Klipper
            /// printer.cfg sections, per --flavour) to this file, ready to paste.
            #[arg(long)]
            config_out: Option<PathBuf>,
        },
        /// Calibrate an A/B rotary table (seed 004): origin, probes, test prints, simulation.
        Calibrate {
            #[command(subcommand)]
            cmd: crate::calibrate::CalibrateCommand,
        },
        /// Check a 4/5-axis G-code (any tool's) for a machine: reach, collisions, axis speeds,
        /// time, filament, tilt. Exit 0: clean; 1: findings; 2: the input cannot be read.
        Check {
            /// The G-code to check.
            gcode: PathBuf,
            /// A preset or a machine JSON file (docs/machines.md).
            #[arg(long, value_name = "PRESET|FILE.json")]
            machine: String,
            #[command(flatten)]
            check: crate::schema_args::CheckArgs,
            /// Print the whole report as JSON (findings listed up to --max-findings).
            #[arg(long)]
            json: bool,
        },
        /// Batch kinematics: CSV on stdin, CSV on stdout (`px,py,pz,nx,ny,nz` ↔ machine axes).
        Kinematics {
            #[arg(value_enum)]
            direction: KinematicsDirection,
            /// A preset name or a machine JSON file.
            #[arg(long)]
            machine: String,
        },
        /// Write one of the generated example parts as STL (cube, cylinder, sphere, overhang).
        Example {
            name: String,
            #[arg(short, long)]
            output: PathBuf,
        },
    }

    #[derive(Clone, Copy, ValueEnum)]
    enum KinematicsDirection {
        Inverse,
        Forward,
    }

    #[derive(Clone, Copy, ValueEnum)]
    enum EModeArg {
        Relative,
        Absolute,
    }

    /// Prints each step's report and shows progress on a terminal.
    struct Steps {
        bar: Option<ProgressBar>,
    }

    impl Observer for Steps {
        fn start(&mut self, step: &str, bytes: u64) {
            if !std::io::stderr().is_terminal() {
                return;
            }
            let pb = if bytes > 0 {
                let pb = ProgressBar::new(bytes);
                pb.set_style(
                    ProgressStyle::with_template("{msg} [{bar:40}] {bytes}/{total_bytes}")
                        .unwrap_or_else(|_| ProgressStyle::default_bar()),
                );
                pb
            } else {
                let pb = ProgressBar::new_spinner();
                pb.enable_steady_tick(std::time::Duration::from_millis(100));
                pb
            };
            pb.set_message(step.to_string());
            self.bar = Some(pb);
        }

        fn advance(&mut self, n: u64) {
            if let Some(pb) = &self.bar {
                pb.inc(n);
            }
        }

        fn finish(&mut self) {
            if let Some(pb) = self.bar.take() {
                pb.finish_and_clear();
            }
        }

        fn warped(&mut self, model: &Path, out: &WarpOutput, stl: &Path, job: &Path) {
            print_warp_report(model, out, stl, job);
        }

        fn sliced(&mut self, stl: &Path, gcode: &Path, report: &SliceReport) {
            say!(
                "sliced {} with {} → {}",
                stl.display(),
                report.slicer,
                gcode.display()
            );
        }

        fn sliced_builtin(
            &mut self,
            stl: &Path,
            gcode: &Path,
            report: &warpslice::planar::SliceReport,
        ) {
            crate::builtin::print_report(stl, gcode, report);
        }

        fn unwarped(&mut self, report: &UnwarpReport, output: &Path) {
            print_report(report, output);
        }
    }

    fn print_warp_report(model: &Path, out: &WarpOutput, stl: &Path, job: &Path) {
        let r = &out.report;
        say!(
            "model: {} ({} triangles, {} vertices)",
            model.display(),
            r.mesh.triangles,
            r.mesh.vertices
        );
        if r.mesh.degenerate + r.mesh.open_edges + r.mesh.nonmanifold_edges > 0 {
            say!(
                "defects: {} degenerate triangles, {} open edges, {} non-manifold edges (reported, not repaired)",
                r.mesh.degenerate, r.mesh.open_edges, r.mesh.nonmanifold_edges
            );
        }
        say!(
            "subdivided: {} → {} triangles",
            r.subdivide.triangles_before,
            r.subdivide.triangles_after
        );
        match r.anchor {
            Some(t) => say!("anchor: {t} mm slab under the warped bottom (slice with a first layer of {t} mm; unwarp drops it)"),
            None => say!("anchor: none (the first layer holds enough of the part)"),
        }
        let s = r.warped_bbox.size();
        say!(
            "warped: {:.2} × {:.2} × {:.2} mm, largest tool tilt {:.2}°",
            s.x,
            s.y,
            s.z,
            r.largest_tilt_deg
        );
        if let Some(t) = r.layer_thickness {
            say!(
                "layer thickness {} mm along the tool axis at {:.2}° tilt: slice with a layer height of {} mm (the job records both)",
                t.thickness,
                t.at_tilt_deg,
                r.layer_height
            );
        }
        say!(
            "wrote {} and {} (job {})",
            stl.display(),
            job.display(),
            out.job.hash
        );
        for w in &r.warnings {
            say!("warning: {w}");
        }
    }

    fn print_report(r: &UnwarpReport, output: &Path) {
        say!(
            "registration: translation {:.3} {:.3} {:.3} mm, residual {:.3} mm",
            r.translation[0],
            r.translation[1],
            r.translation[2],
            r.residual
        );
        if let Some(f) = &r.fit {
            say!(
                "fine registration: walls {:.3} mm inside the surface, RMS {:.4} mm over {} matches in {} layers (moved {:.3} mm from the bounding-box match)",
                f.bead_inset_mm, f.rms_mm, f.matched, f.layers, f.moved_mm
            );
        }
        say!(
            "lines: {} in, {} out; {} moves split into {} segments",
            r.lines_in,
            r.lines_out,
            r.moves_split,
            r.segments_out
        );
        say!(
            "E: {:.3} mm in, {:.3} mm out (anchor dropped {:.3} mm; skirt/brim {:.3} mm {})",
            r.e_in,
            r.e_out,
            r.e_anchor,
            r.e_skirt,
            r.skirt
        );
        say!("largest tilt {:.2}°; {} travels lifted ({} retractions added); {} points clamped to the bed; shape check: {} points outside the part, {:+.3} mm from the allowance", r.largest_tilt_deg, r.lifts, r.retracts_added, r.clamped_points, r.shape_outliers, r.shape_margin_mm);
        if let Some(m) = &r.machine {
            say!(
                "machine {} ({}): {} moves → {} G1; worst interpolation {:.5} mm / {:.4}°; largest dropped tool-axis angle {:.3}°; {} rotate-arounds; {} swing lifts{}; {} rotary resets; {}; {}",
                m.machine, m.flavour, m.moves_in, m.moves_out, m.worst_position_mm, m.worst_angle_deg, m.worst_dropped_deg, m.rotate_arounds, m.swing_lifts,
                crate::swing_lines(m), m.rotary_resets,
                warpslice::machine::emit::speed_summary(m),
                warpslice::machine::emit::margins_summary(&m.axes)
            );
        }
        for w in &r.warnings {
            say!("warning: {w}");
        }
        say!("wrote {}", output.display());
    }

    /// `--config-out FILE`: the firmware configuration of the output, built before the unwarp
    /// (a machine the flavour refuses fails here, before any file is written), written after
    /// it (no fragment for a G-code that was not written).
    fn firmware_config(
        settings: &warpslice::pipeline::UnwarpSettings,
        path: Option<&Path>,
    ) -> Result<Option<(PathBuf, warpslice::machine::config::FirmwareConfig)>, String> {
        let Some(path) = path else { return Ok(None) };
        let c = settings
            .output
            .firmware_config()
            .map_err(|e| e.to_string())?
            .ok_or("--config-out needs --machine: 3-axis G-code needs no firmware configuration")?;
        Ok(Some((path.to_path_buf(), c)))
    }

    fn write_config(
        config: Option<(PathBuf, warpslice::machine::config::FirmwareConfig)>,
    ) -> Result<(), String> {
        if let Some((path, c)) = config {
            write(&path, c.text.as_bytes())?;
            say!(
                "wrote {} ({} lines for {}'s {})",
                path.display(),
                c.text.lines().count(),
                c.flavour.name(),
                c.file
            );
        }
        Ok(())
    }

    /// Findings the human output of `check` lists (the JSON lists up to --max-findings).
    const CHECK_SHOWN: usize = 20;

    /// `warpslice check`: exit 0 clean (speed findings only reported), 1 reach or collision
    /// findings, 2 unreadable input (the error on stderr).
    fn check(
        gcode: &Path,
        machine: &str,
        options: &warpslice::check::CheckOptions,
        json: bool,
    ) -> ExitCode {
        let report = (|| -> Result<warpslice::check::CheckReport, String> {
            let spec = machine_spec(machine)?;
            let mut s =
                warpslice::check::CheckStream::new(&spec, options).map_err(|e| e.to_string())?;
            let mut f =
                std::fs::File::open(gcode).map_err(|e| format!("{}: {e}", gcode.display()))?;
            let mut buf = vec![0u8; 1 << 20];
            loop {
                let n = f
                    .read(&mut buf)
                    .map_err(|e| format!("{}: {e}", gcode.display()))?;
                if n == 0 {
                    break;
                }
                s.push(&buf[..n])
                    .map_err(|e| format!("{}: {e}", gcode.display()))?;
            }
            s.finish()
                .map(|(r, _)| r)
                .map_err(|e| format!("{}: {e}", gcode.display()))
        })();
        let r = match report {
            Ok(r) => r,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        };
        if json {
            match serde_json::to_string_pretty(&r) {
                Ok(t) => say!("{t}"),
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::from(2);
                }
            }
        } else {
            say!("{}: machine {} ({})", gcode.display(), r.machine, r.flavour);
            for f in r.findings.iter().take(CHECK_SHOWN) {
                say!("{f}");
            }
            let listed = r.findings.len().min(CHECK_SHOWN) as u64;
            if r.counts.total() > listed {
                say!(
                    "… {} more finding{} (--json lists them)",
                    r.counts.total() - listed,
                    if r.counts.total() - listed == 1 {
                        ""
                    } else {
                        "s"
                    }
                );
            }
            if let Some(w) = &r.worst_speed {
                say!("fastest axis over its feed: {w}");
            }
            say!("{}", warpslice::machine::emit::margins_summary(&r.axes));
            let hist: Vec<String> = r
                .tilt_histogram
                .iter()
                .enumerate()
                .filter(|(_, &n)| n > 0)
                .map(|(i, n)| {
                    format!(
                        "{}–{}° {n}",
                        i as f64 * r.tilt_bin_deg,
                        (i + 1) as f64 * r.tilt_bin_deg
                    )
                })
                .collect();
            if !hist.is_empty() {
                say!("tilt of extruding moves: {}", hist.join(", "));
            }
            for w in &r.warnings {
                say!("warning: {w}");
            }
            say!("{}", r.summary());
        }
        if r.is_clean() {
            ExitCode::SUCCESS
        } else {
            ExitCode::from(1)
        }
    }

    fn run() -> Result<ExitCode, String> {
        let cli = Cli::parse();
        match cli.command {
            Command::Check {
                gcode,
                machine,
                check: c,
                json,
            } => return Ok(check(&gcode, &machine, &c.options, json)),
            Command::Warp {
                model,
                warp,
                suggested,
                machine,
                suggest,
                output,
            } => {
                let options =
                    match suggested {
                        Some(n) => crate::suggest::suggested(
                            &model,
                            machine.as_deref(),
                            n,
                            &suggest.options,
                            warp.options,
                        )?,
                        None if warp.given => warp.options,
                        None => return Err(
                            "give --warp (and its parameters) or --suggested N --machine PRESET"
                                .into(),
                        ),
                    };
                files::warp_file(&model, &options, &output, &mut Steps { bar: None })
                    .map_err(|e| files::in_file(&model, &e))?;
            }
            Command::Overhangs {
                model,
                warp,
                angle,
                json,
            } => crate::suggest::overhangs(
                &model,
                warp.given.then_some(&warp.options),
                angle.options.overhang_angle,
                json,
            )?,
            Command::Suggest {
                model,
                machine,
                suggest,
                json,
            } => crate::suggest::suggest(&model, &machine, &suggest.options, json)?,
            Command::Unwarp {
                gcode,
                job,
                unwarp,
                stl,
                output,
                config_out,
            } => {
                let job_file = job;
                let job = files::read_job(&job_file).map_err(|e| files::in_file(&job_file, &e))?;
                let settings = unwarp.settings;
                // the warped STL beside the job registers to the bead, robust to features the
                // slicer did not print (not with --offset: the placement is given)
                let stl = stl.or_else(|| {
                    let beside = settings
                        .unwarp
                        .offset
                        .is_none()
                        .then(|| files::stl_beside(&job_file, &job))
                        .flatten();
                    if let Some(p) = &beside {
                        say!(
                            "registering against the warped STL beside the job: {}",
                            p.display()
                        );
                    }
                    beside
                });
                let config = firmware_config(&settings, config_out.as_deref())?;
                files::unwarp_file(
                    &gcode,
                    &job,
                    &settings,
                    stl.as_deref(),
                    &output,
                    &mut Steps { bar: None },
                )
                .map_err(|e| files::in_file(&gcode, &e))?;
                write_config(config)?;
            }
            Command::Run {
                model,
                slicer,
                slicer_settings,
                set,
                keep_sliced,
                e_mode,
                warp,
                unwarp,
                output,
                config_out,
            } => {
                let config = firmware_config(&unwarp.settings, config_out.as_deref())?;
                if slicer.trim().eq_ignore_ascii_case("builtin") {
                    let s = crate::builtin::settings(
                        warp.options.layer_height,
                        slicer_settings.as_deref(),
                        &set,
                        matches!(e_mode, EModeArg::Relative),
                    )?;
                    files::run_with(
                        &model,
                        &warp.options,
                        files::SliceWith::Builtin(&s),
                        &unwarp.settings,
                        &output,
                        &mut Steps { bar: None },
                    )
                    .map_err(|e| e.to_string())?;
                    crate::builtin::keep_sliced(&output, keep_sliced.as_deref())?;
                    write_config(config)?;
                    return Ok(ExitCode::SUCCESS);
                }
                if slicer_settings.is_some() || !set.is_empty() {
                    return Err(format!(
                        "--slicer-settings and --set are the built-in slicer's; {slicer} takes its own settings"
                    ));
                }
                let kind: warpslice::slicer::SlicerKind = slicer
                    .parse()
                    .map_err(|e: warpslice::slicer::SlicerError| e.to_string())?;
                let (opts, settings) = (warp.options, unwarp.settings);
                let so = warpslice::slicer::SliceOptions {
                    slicer: kind,
                    e_mode: match e_mode {
                        EModeArg::Relative => warpslice::slicer::EMode::Relative,
                        EModeArg::Absolute => warpslice::slicer::EMode::Absolute,
                    },
                    ..Default::default()
                };
                files::run(
                    &model,
                    &opts,
                    &so,
                    &settings,
                    &output,
                    &mut Steps { bar: None },
                )
                .map_err(|e| e.to_string())?;
                crate::builtin::keep_sliced(&output, keep_sliced.as_deref())?;
                write_config(config)?;
            }
            Command::Kinematics { direction, machine } => {
                let m = machine_spec(&machine)?.build().map_err(|e| e.to_string())?;
                let mut input = String::new();
                std::io::stdin()
                    .read_to_string(&mut input)
                    .map_err(|e| format!("stdin: {e}"))?;
                let out = match direction {
                    KinematicsDirection::Inverse => {
                        warpslice::machine::batch::inverse_csv(m.as_ref(), &input)
                    }
                    KinematicsDirection::Forward => {
                        warpslice::machine::batch::forward_csv(m.as_ref(), &input)
                    }
                }
                .map_err(|e| e.to_string())?;
                let _ = std::io::stdout().write_all(out.as_bytes());
            }
            Command::Calibrate { cmd } => crate::calibrate::run(cmd)?,
            Command::Example { name, output } => {
                let m = warpslice::shapes::example(&name).ok_or_else(|| {
                    format!(
                        "unknown example '{name}': one of {}",
                        warpslice::shapes::EXAMPLES.join(", ")
                    )
                })?;
                write(
                    &output,
                    &warpslice::mesh::write_stl(&m, &format!("warpslice example {name}")),
                )?;
                say!(
                    "wrote {} ({} triangles)",
                    output.display(),
                    m.triangles.len()
                );
            }
        }
        Ok(ExitCode::SUCCESS)
    }

    pub fn main() -> ExitCode {
        match run() {
            Ok(code) => code,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        }
    }
}

/// The output lines of the first swing lifts, for the summary (`" (output lines 143, 380, …)"`).
#[cfg(not(target_arch = "wasm32"))]
fn swing_lines(m: &warpslice::emit::MachineReport) -> String {
    const SHOWN: usize = 5;
    if m.swings.is_empty() {
        return String::new();
    }
    let lines: Vec<String> = m
        .swings
        .iter()
        .take(SHOWN)
        .map(|s| s.output_line.to_string())
        .collect();
    let more = if m.swings.len() > SHOWN { ", …" } else { "" };
    format!(" (output lines {}{more})", lines.join(", "))
}
