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
mod calibrate;
#[cfg(not(target_arch = "wasm32"))]
mod out;

#[cfg(not(target_arch = "wasm32"))]
mod cli {
    use std::io::{IsTerminal, Read, Write};
    use std::path::{Path, PathBuf};
    use std::process::ExitCode;

    use clap::{Args, Parser, Subcommand, ValueEnum};

    use crate::args::{machine_spec, pair, triple};
    use crate::out::{say, write};
    use indicatif::{ProgressBar, ProgressStyle};
    use warpslice::pipeline::files::{self, Observer};
    use warpslice::pipeline::{AnchorMode, UnwarpSettings, WarpOptions, WarpOutput};
    use warpslice::slicer::SliceReport;
    use warpslice::unwarp::{Flow, UnwarpOptions, UnwarpReport};
    use warpslice::warp::{Direction, WarpParams, WarpSpec};

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
            warp: WarpArgs,
            /// The warped STL to write (the job goes next to it as .job.json).
            #[arg(short, long)]
            output: PathBuf,
        },
        /// Map a planar slicer's G-code of the warped STL back to the real part.
        Unwarp {
            /// The slicer's G-code of the warped STL.
            gcode: PathBuf,
            /// The job file written by `warp`.
            #[arg(long)]
            job: PathBuf,
            #[command(flatten)]
            unwarp: UnwarpArgs,
            /// The slicer's placement dx,dy (mm) instead of finding it.
            #[arg(long, value_parser = pair, allow_hyphen_values = true)]
            offset: Option<[f64; 2]>,
            /// Chord tolerance, mm.
            #[arg(long, default_value_t = warpslice::tolerance::DEFAULT_TOLERANCE)]
            tolerance: f64,
            #[arg(short, long)]
            output: PathBuf,
        },
        /// Warp, slice with a real slicer installed here, and unwarp: the main job in one command.
        Run {
            model: PathBuf,
            #[arg(long)]
            slicer: String,
            /// Relative (M83) or absolute (M82) E in the slicer's G-code.
            #[arg(long, value_enum, default_value_t = EModeArg::Relative)]
            e_mode: EModeArg,
            #[command(flatten)]
            warp: WarpArgs,
            #[command(flatten)]
            unwarp: UnwarpArgs,
            #[arg(short, long)]
            output: PathBuf,
        },
        /// Calibrate an A/B rotary table (seed 004): origin, probes, test prints, simulation.
        Calibrate {
            #[command(subcommand)]
            cmd: crate::calibrate::CalibrateCommand,
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
    enum FeedArg {
        Xyz,
        AllAxes,
        InverseTime,
    }

    #[derive(Clone, Copy, ValueEnum)]
    enum FlavourArg {
        Reprapfirmware,
        Marlin,
        Klipper,
    }

    #[derive(Clone, Copy, ValueEnum)]
    enum EModeArg {
        Relative,
        Absolute,
    }

    #[derive(Clone, Copy, ValueEnum)]
    enum WarpKind {
        Curved,
        Tilted,
        Conic,
        Belt,
        Cylindrical,
        Spherical,
    }

    #[derive(Clone, Copy, ValueEnum)]
    enum AnchorArg {
        Auto,
        On,
        Off,
    }

    #[derive(Args)]
    struct WarpArgs {
        /// The warp.
        #[arg(long, value_enum)]
        warp: WarpKind,
        /// curved/tilted: strength s (seed 000 Eqs. 1–2).
        #[arg(long, default_value_t = 0.3)]
        strength: f64,
        /// outward (layers fall away from the centre, tool tilts outward) or inward.
        #[arg(long, default_value = "outward")]
        direction: String,
        /// curved/tilted: offset a of the vertex/crease, mm (the crease is at x = −a).
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        offset: f64,
        /// conic/belt: angle α in degrees (0 < α < 90).
        #[arg(long, default_value_t = 30.0)]
        angle: f64,
        /// conic: axis position cx,cy in the model frame, mm.
        #[arg(long, value_parser = pair, default_value = "0,0", allow_hyphen_values = true)]
        center: [f64; 2],
        /// belt: direction dx,dy the layers fall toward.
        #[arg(long, value_parser = pair, default_value = "0,1", allow_hyphen_values = true)]
        toward: [f64; 2],
        /// cylindrical/spherical: radius R of the first layer (mandrel or inner sphere), mm.
        #[arg(long, default_value_t = 10.0)]
        radius: f64,
        /// cylindrical: the mandrel axis (parallel to X) at y,z in the model frame, mm
        /// (default: 0,−radius, just under the part).
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        axis_yz: Option<[f64; 2]>,
        /// spherical: the centre x,y,z in the model frame, mm (default: 0,0,−radius).
        #[arg(long, value_parser = triple, allow_hyphen_values = true)]
        sphere_center: Option<[f64; 3]>,
        /// Keep the layers flat below z0 and blend in the warp up to z1 (mm): --base z0,z1.
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        base: Option<[f64; 2]>,
        /// Split triangle edges longer than this, mm.
        #[arg(long, default_value_t = warpslice::tolerance::DEFAULT_MAX_EDGE)]
        max_edge: f64,
        /// Layer height you will slice with, mm (the anchor's thickness and first layer).
        #[arg(long, default_value_t = warpslice::tolerance::DEFAULT_LAYER_HEIGHT)]
        layer_height: f64,
        /// The removable flat anchor under a non-flat warped bottom.
        #[arg(long, value_enum, default_value_t = AnchorArg::Auto)]
        anchor: AnchorArg,
    }

    #[derive(Args)]
    struct UnwarpArgs {
        /// Longest extruding segment after unwarping, mm.
        #[arg(long, default_value_t = warpslice::tolerance::DEFAULT_MAX_SEGMENT)]
        max_segment: f64,
        /// Flow factor.
        #[arg(long, default_value_t = 1.0)]
        flow: f64,
        /// Flow ramp f0,z_ramp: from f0 at z = 0 to 1 at z_ramp (seed 000: 0.8,1.2).
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        ramp: Option<[f64; 2]>,
        /// Added to every output z, mm.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        z_offset: f64,
        /// Drop skirt and brim instead of printing them flat.
        #[arg(long)]
        drop_skirt: bool,
        /// Put the part's footprint centre at x,y (mm) in the output instead of where the
        /// slicer put it (e.g. 0,0 on an A/B table whose axes meet at the origin).
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        place: Option<[f64; 2]>,
        /// Write a 4/5-axis machine's axes: a preset name or a machine JSON file (docs/machines.md).
        #[arg(long)]
        machine: Option<String>,
        /// Feed mode for a machine: xyz, all-axes, inverse-time (G93).
        #[arg(long, value_enum, default_value_t = FeedArg::Xyz)]
        feed: FeedArg,
        /// Firmware flavour for a machine (default: the machine's, else reprapfirmware).
        #[arg(long, value_enum)]
        flavour: Option<FlavourArg>,
    }

    impl WarpArgs {
        fn options(&self, tolerance: f64) -> Result<WarpOptions, String> {
            let direction: Direction = self
                .direction
                .parse()
                .map_err(|e: warpslice::warp::WarpError| e.to_string())?;
            let spec = match self.warp {
                WarpKind::Curved => WarpSpec::Curved {
                    strength: self.strength,
                    direction,
                    offset: self.offset,
                    width: 0.0,
                },
                WarpKind::Tilted => WarpSpec::Tilted {
                    strength: self.strength,
                    direction,
                    offset: self.offset,
                },
                WarpKind::Conic => WarpSpec::Conic {
                    angle: self.angle,
                    direction,
                    center: self.center,
                },
                WarpKind::Belt => WarpSpec::Belt {
                    angle: self.angle,
                    toward: self.toward,
                },
                WarpKind::Cylindrical => WarpSpec::Cylindrical {
                    radius: self.radius,
                    axis: self.axis_yz.unwrap_or([0.0, -self.radius]),
                },
                WarpKind::Spherical => WarpSpec::Spherical {
                    radius: self.radius,
                    center: self.sphere_center.unwrap_or([0.0, 0.0, -self.radius]),
                },
            };
            let mut o = WarpOptions::new(WarpParams {
                spec,
                base: self.base,
            });
            o.max_edge = self.max_edge;
            o.tolerance = tolerance;
            o.layer_height = self.layer_height;
            o.anchor = match self.anchor {
                AnchorArg::Auto => AnchorMode::Auto,
                AnchorArg::On => AnchorMode::On,
                AnchorArg::Off => AnchorMode::Off,
            };
            Ok(o)
        }
    }

    impl UnwarpArgs {
        fn options(
            &self,
            tolerance: f64,
            offset: Option<[f64; 2]>,
        ) -> Result<UnwarpSettings, String> {
            use warpslice::machine::{FeedMode, Flavour, MachineOptions};
            let unwarp = UnwarpOptions {
                tolerance,
                max_segment: self.max_segment,
                flow: Flow {
                    factor: self.flow,
                    ramp: self.ramp,
                },
                z_offset: self.z_offset,
                drop_skirt: self.drop_skirt,
                place: self.place,
                offset,
                ..UnwarpOptions::default()
            };
            let output = MachineOptions {
                machine: self.machine.as_deref().map(machine_spec).transpose()?,
                feed: match self.feed {
                    FeedArg::Xyz => FeedMode::Xyz,
                    FeedArg::AllAxes => FeedMode::AllAxes,
                    FeedArg::InverseTime => FeedMode::InverseTime,
                },
                flavour: self.flavour.map(|f| match f {
                    FlavourArg::Reprapfirmware => Flavour::RepRapFirmware,
                    FlavourArg::Marlin => Flavour::Marlin,
                    FlavourArg::Klipper => Flavour::Klipper,
                }),
            };
            Ok(UnwarpSettings { unwarp, output })
        }
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
        say!(
            "wrote {} and {} (job {})",
            stl.display(),
            job.display(),
            out.job.hash
        );
    }

    fn print_report(r: &UnwarpReport, output: &Path) {
        say!(
            "registration: translation {:.3} {:.3} {:.3} mm, residual {:.3} mm",
            r.translation[0],
            r.translation[1],
            r.translation[2],
            r.residual
        );
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
        say!("largest tilt {:.2}°; {} travels lifted ({} retractions added); {} points clamped to the bed", r.largest_tilt_deg, r.lifts, r.retracts_added, r.clamped_points);
        if let Some(m) = &r.machine {
            say!(
                "machine {} ({}): {} moves → {} G1; worst interpolation {:.5} mm / {:.4}°; largest dropped tool-axis angle {:.3}°; {} rotate-arounds; {} rotary resets",
                m.machine, m.flavour, m.moves_in, m.moves_out, m.worst_position_mm, m.worst_angle_deg, m.worst_dropped_deg, m.rotate_arounds, m.rotary_resets
            );
        }
        say!("wrote {}", output.display());
    }

    fn run() -> Result<(), String> {
        let cli = Cli::parse();
        match cli.command {
            Command::Warp {
                model,
                warp,
                output,
            } => {
                let opts = warp.options(warpslice::tolerance::DEFAULT_TOLERANCE)?;
                files::warp_file(&model, &opts, &output, &mut Steps { bar: None })
                    .map_err(|e| files::in_file(&model, &e))?;
            }
            Command::Unwarp {
                gcode,
                job,
                unwarp,
                offset,
                tolerance,
                output,
            } => {
                let job = files::read_job(&job).map_err(|e| files::in_file(&job, &e))?;
                let settings = unwarp.options(tolerance, offset)?;
                files::unwarp_file(&gcode, &job, &settings, &output, &mut Steps { bar: None })
                    .map_err(|e| files::in_file(&gcode, &e))?;
            }
            Command::Run {
                model,
                slicer,
                e_mode,
                warp,
                unwarp,
                output,
            } => {
                let kind: warpslice::slicer::SlicerKind = slicer
                    .parse()
                    .map_err(|e: warpslice::slicer::SlicerError| e.to_string())?;
                let opts = warp.options(warpslice::tolerance::DEFAULT_TOLERANCE)?;
                let settings = unwarp.options(opts.tolerance, None)?;
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
        Ok(())
    }

    pub fn main() -> ExitCode {
        match run() {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        }
    }
}
