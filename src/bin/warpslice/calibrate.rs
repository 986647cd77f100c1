//! `warpslice calibrate …`: argument parsing and printing for the calibration core
//! (`warpslice::calibrate`, seed 004); nothing else here.

use std::path::PathBuf;

use clap::{Args, Subcommand};
use glam::DVec3;
use warpslice::calibrate::patterns::{self, PrintOptions, TestKind};
use warpslice::calibrate::probes::{self, ProbeInput};
use warpslice::calibrate::simulate::{self, Deviation, SimInput};
use warpslice::calibrate::{self as cal, OriginOptions};

use crate::args::{machine_spec as machine, pair, vec3};
use crate::out::{put, read_text, say, write};

/// Calibration of A/B rotary tables (seed 004): origin, probe formulas, test prints, simulation.
#[derive(Subcommand)]
pub enum CalibrateCommand {
    /// Measurements (ab_values.out, listing 4.1) → machine origin (Eq. 5.7) and a calibrated
    /// open5x-ab machine JSON.
    Origin {
        /// The measurement file written by the Calibration AB macro.
        #[arg(long)]
        measurements: PathBuf,
        /// Probe biases x,y,z (mm), added as in Eq. 5.7.
        #[arg(long, value_parser = vec3, allow_hyphen_values = true)]
        bias: Option<DVec3>,
        /// α_{A,z}: A-axis rotation about Z from the A orientation test (§6.2.2; `calibrate probe
        /// a-orientation` computes it from the caliper readings), degrees.
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        a_z_correction: f64,
        /// The machine to calibrate (preset name or JSON file; kind ab-table).
        #[arg(long, default_value = "open5x-ab")]
        machine: String,
        /// Write the calibrated machine JSON here.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Print the report as JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// The raw probe formulas of §5.4.1 and §5.1.6–5.1.8.
    Probe {
        #[command(subcommand)]
        probe: ProbeCommand,
    },
    /// Write a test print (§6.2) for a machine as G-code, and its base object as STL.
    TestPrint {
        /// a-position, a-orientation, b-position, b-orientation or integrated.
        kind: String,
        /// Preset name or machine JSON file (kind ab-table).
        #[arg(long, default_value = "open5x-ab")]
        machine: String,
        /// The G-code to write.
        #[arg(short, long)]
        output: PathBuf,
        /// Also write the base object (print it planar first) as STL.
        #[arg(long)]
        base: Option<PathBuf>,
        /// b-position: write the simulated line for a B axis off by dx,dy (mm) as SVG (Fig. 6.16).
        #[arg(long)]
        svg: Option<PathBuf>,
        /// The B offset dx,dy for --svg, mm.
        #[arg(long, value_parser = pair, allow_hyphen_values = true, default_value = "0,-0.2")]
        b_offset: [f64; 2],
        /// Exaggeration of the error in the SVG.
        #[arg(long, default_value_t = 10.0)]
        exaggerate: f64,
        #[command(flatten)]
        print: PrintArgs,
    },
    /// Simulate calibration errors: G-code made by the believed machine, run by the true one.
    Simulate {
        /// The machine the G-code is made for (preset or JSON).
        #[arg(long, default_value = "open5x-ab")]
        believed: String,
        /// The true machine (JSON/preset); otherwise the believed one with the deviations below.
        #[arg(long = "true")]
        truth: Option<String>,
        #[command(flatten)]
        deviation: DeviationArgs,
        /// Toolpath CSV: x,y,z,nx,ny,nz per line (part frame, mm).
        #[arg(long)]
        toolpath: Option<PathBuf>,
        /// Or a test print's path (a-position, …, integrated).
        #[arg(long)]
        test: Option<String>,
        /// Write the plot here (SVG).
        #[arg(long)]
        svg: Option<PathBuf>,
        /// Write every point (intended, real, error) here (CSV).
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Exaggeration of the error in the SVG.
        #[arg(long, default_value_t = 1.0)]
        exaggerate: f64,
    },
}

/// The probe formulas.
#[derive(Subcommand)]
pub enum ProbeCommand {
    /// Eq. 5.2: Y error of the A position method for radius r and an A axis turned θ about Z.
    APosError {
        #[arg(long)]
        radius: f64,
        #[arg(long, allow_hyphen_values = true)]
        z_rotation: f64,
    },
    /// Eq. 5.3: A_pos from z₀, y₉₀, y₋₉₀, c_y and the probe radius.
    APos {
        #[arg(long, allow_hyphen_values = true)]
        z0: f64,
        #[arg(long, allow_hyphen_values = true)]
        y90: f64,
        #[arg(long, allow_hyphen_values = true)]
        y_minus90: f64,
        /// c_y: your probe's Y bias, mm (required: measured with an object of known size,
        /// §6.1.1; the thesis printer's was 0.453, another probe's is not)
        #[arg(long, allow_hyphen_values = true)]
        c_y: f64,
        #[arg(long, default_value_t = probes::PROBE_RADIUS)]
        r_p: f64,
    },
    /// Eq. 5.4: A_dir from the probed slopes. Note: as printed, m_yx takes the half
    /// differences of the two Y probes at each X: with plain Y coordinates that measures a taper
    /// (the width changing along X), not the centre line's slope (the half sums); it is the slope
    /// only if your probe script records the -Y and +Y probes with opposite signs.
    ADir {
        /// z_{x,1},z_{x,2}
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        z_x: [f64; 2],
        #[arg(long)]
        d_zx: f64,
        /// z_{y,1},z_{y,2}
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        z_y: [f64; 2],
        #[arg(long)]
        d_zy: f64,
        /// y_{x1,1},y_{x1,2}
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        y_x1: [f64; 2],
        /// y_{x2,1},y_{x2,2}
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        y_x2: [f64; 2],
        #[arg(long)]
        d_yx: f64,
    },
    /// Eq. 5.5: B_pos from the four side probes.
    BPos {
        /// x_{p1},x_{p2}
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        x_p: [f64; 2],
        /// y_{p1},y_{p2}
        #[arg(long, value_parser = pair, allow_hyphen_values = true)]
        y_p: [f64; 2],
        #[arg(long, allow_hyphen_values = true, default_value_t = probes::B_PROBE_Z)]
        z: f64,
    },
    /// Eq. 5.6: B_dir from four side points at each of two heights (x,y,z each).
    BDir {
        #[arg(long, value_parser = vec3, allow_hyphen_values = true, num_args = 4, required = true)]
        p1: Vec<DVec3>,
        #[arg(long, value_parser = vec3, allow_hyphen_values = true, num_args = 4, required = true)]
        p2: Vec<DVec3>,
    },
    /// §5.1.6: Z bias and Z shift from the flats probed at A = ±90°.
    ZBias {
        /// z₉₀ values, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            required = true
        )]
        z90: Vec<f64>,
        /// z₋₉₀ values, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            required = true
        )]
        z_minus90: Vec<f64>,
        #[arg(long, default_value_t = probes::AXLE_FLATS)]
        d_f: f64,
    },
    /// §5.1.7: A-axis scaling error α = asin((z₂ − z₁)/10 mm).
    AScaling {
        #[arg(long, allow_hyphen_values = true)]
        z1: f64,
        #[arg(long, allow_hyphen_values = true)]
        z2: f64,
        #[arg(long, default_value_t = probes::A_SCALING_DISTANCE)]
        distance: f64,
    },
    /// §5.1.7: the A axis' steps per degree from the α measured at A = +90° and −90°
    /// (`a-scaling` at each), and the zero-point shift left.
    ASteps {
        /// α at A = +90°, degrees.
        #[arg(long, allow_hyphen_values = true)]
        alpha_plus: f64,
        /// α at A = −90°, degrees.
        #[arg(long, allow_hyphen_values = true)]
        alpha_minus: f64,
        /// The firmware's steps per degree when they were measured (M92 A…).
        #[arg(long)]
        steps_per_deg: f64,
    },
    /// §6.2.2: α_A,z (the A axis' rotation about Z, for `calibrate origin --a-z-correction`)
    /// from the caliper readings of the A orientation test print: α_A,z = atan((d_start −
    /// d_end) / L), d from the object's −X side, the line's start at the smaller A.
    AOrientation {
        /// d_start: caliper distance from the line's start to the object's −X side, mm.
        #[arg(long, allow_hyphen_values = true)]
        d_start: f64,
        /// d_end: caliper distance from the line's end to the same side, mm.
        #[arg(long, allow_hyphen_values = true)]
        d_end: f64,
        /// L: the line's length, mm (the seed approximates it as 40 mm).
        #[arg(long, default_value_t = probes::A_ORIENTATION_LINE, allow_hyphen_values = true)]
        line_length: f64,
    },
    /// §5.1.8: wobble z_d from z_shift and the Z of A^B_pos.
    Wobble {
        #[arg(long, allow_hyphen_values = true)]
        z_shift: f64,
        #[arg(long, allow_hyphen_values = true)]
        ab_z: f64,
    },
}

/// Print settings of the test prints.
#[derive(Args)]
pub struct PrintArgs {
    #[arg(long, default_value_t = 0.2)]
    layer_height: f64,
    #[arg(long, default_value_t = 0.4)]
    line_width: f64,
    #[arg(long, default_value_t = 1.75)]
    filament_diameter: f64,
    /// mm/min
    #[arg(long, default_value_t = 600.0)]
    print_feed: f64,
    /// mm/min
    #[arg(long, default_value_t = 3000.0)]
    travel_feed: f64,
    /// Lift along the tool axis before travels, mm.
    #[arg(long, default_value_t = 5.0)]
    clearance: f64,
}

/// How the true machine differs from the believed one.
#[derive(Args)]
pub struct DeviationArgs {
    /// A line shifted by x,y,z (mm).
    #[arg(long, value_parser = vec3, allow_hyphen_values = true)]
    a_offset: Option<DVec3>,
    /// A direction turned about Z, degrees (Fig. 3.1: 2).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    a_rot_z: f64,
    /// A direction turned about Y, degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    a_rot_y: f64,
    /// B line shifted by x,y,z (mm).
    #[arg(long, value_parser = vec3, allow_hyphen_values = true)]
    b_offset: Option<DVec3>,
    /// B direction turned about X, degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    b_rot_x: f64,
    /// B direction turned about Y, degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    b_rot_y: f64,
}

fn print_options(a: &PrintArgs) -> PrintOptions {
    PrintOptions {
        layer_height: a.layer_height,
        line_width: a.line_width,
        filament_diameter: a.filament_diameter,
        print_feed: a.print_feed,
        travel_feed: a.travel_feed,
        clearance: a.clearance,
        ..PrintOptions::default()
    }
}

fn probe_input(p: ProbeCommand) -> Result<ProbeInput, String> {
    Ok(match p {
        ProbeCommand::APosError { radius, z_rotation } => ProbeInput::APosError {
            radius,
            z_rotation_deg: z_rotation,
        },
        ProbeCommand::APos {
            z0,
            y90,
            y_minus90,
            c_y,
            r_p,
        } => ProbeInput::APos {
            z0,
            y90,
            y_minus90,
            c_y,
            r_p,
        },
        ProbeCommand::ADir {
            z_x,
            d_zx,
            z_y,
            d_zy,
            y_x1,
            y_x2,
            d_yx,
        } => ProbeInput::ADir {
            z_x,
            d_zx,
            z_y,
            d_zy,
            y_x1,
            y_x2,
            d_yx,
        },
        ProbeCommand::BPos { x_p, y_p, z } => ProbeInput::BPos { x_p, y_p, z },
        ProbeCommand::BDir { p1, p2 } => {
            let four = |v: Vec<DVec3>, name: &str| -> Result<[DVec3; 4], String> {
                v.try_into()
                    .map_err(|_| format!("--{name} needs exactly four points x,y,z"))
            };
            ProbeInput::BDir {
                p_z1: four(p1, "p1")?,
                p_z2: four(p2, "p2")?,
            }
        }
        ProbeCommand::ZBias {
            z90,
            z_minus90,
            d_f,
        } => ProbeInput::ZBias {
            z90,
            z_minus90,
            d_f,
        },
        ProbeCommand::AScaling { z1, z2, distance } => ProbeInput::AScaling { z1, z2, distance },
        ProbeCommand::ASteps {
            alpha_plus,
            alpha_minus,
            steps_per_deg,
        } => ProbeInput::AStepsPerDegree {
            alpha_plus_deg: alpha_plus,
            alpha_minus_deg: alpha_minus,
            steps_per_deg,
        },
        ProbeCommand::AOrientation {
            d_start,
            d_end,
            line_length,
        } => ProbeInput::AOrientation {
            d_start,
            d_end,
            line_length,
        },
        ProbeCommand::Wobble { z_shift, ab_z } => ProbeInput::Wobble { z_shift, ab_z },
    })
}

/// Run a `calibrate` subcommand.
pub fn run(cmd: CalibrateCommand) -> Result<(), String> {
    match cmd {
        CalibrateCommand::Origin {
            measurements,
            bias,
            a_z_correction,
            machine: base,
            output,
            json,
        } => {
            let text = read_text(&measurements)?;
            let series = cal::parse_measurements(&text)
                .map_err(|e| format!("{}: {e}", measurements.display()))?;
            let opts = OriginOptions {
                bias: bias.unwrap_or(DVec3::ZERO),
                a_z_correction_deg: a_z_correction,
            };
            let (report, spec) = cal::calibrate_origin(&series, &opts, &machine(&base)?)
                .map_err(|e| e.to_string())?;
            if json {
                say!(
                    "{}",
                    serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?
                );
            } else {
                put(&report.to_text());
            }
            if let Some(out) = output {
                write(&out, spec.to_json().as_bytes())?;
                say!("wrote {} (use it with --machine)", out.display());
            }
        }
        CalibrateCommand::Probe { probe } => {
            let out = probes::evaluate(&probe_input(probe)?).map_err(|e| e.to_string())?;
            put(&out.to_text());
        }
        CalibrateCommand::TestPrint {
            kind,
            machine: m,
            output,
            base,
            svg,
            b_offset,
            exaggerate,
            print,
        } => {
            let kind: TestKind = kind.parse().map_err(|e: cal::CalibError| e.to_string())?;
            let spec = machine(&m)?;
            let opts = print_options(&print);
            let tp = patterns::test_print(&spec, kind, &opts).map_err(|e| e.to_string())?;
            write(&output, &tp.gcode)?;
            let r = &tp.report;
            say!(
                "{}: {} moves ({} printing), {:.2} mm of line, A {:.3}°…{:.3}°, B {:.3}°…{:.3}°, travel Z {:.2} mm",
                kind.name(),
                r.moves,
                r.print_moves,
                r.length_mm,
                r.a_range[0],
                r.a_range[1],
                r.b_range[0],
                r.b_range[1],
                r.z_safe
            );
            say!("wrote {}", output.display());
            if let Some(b) = base {
                write(&b, &patterns::base_stl(kind))?;
                say!(
                    "wrote {} (the base object; print it planar first)",
                    b.display()
                );
            }
            if let Some(path) = svg {
                let d = DVec3::new(b_offset[0], b_offset[1], 0.0);
                let (rep, text) = patterns::b_position_svg(&spec, d, &opts, exaggerate)
                    .map_err(|e| e.to_string())?;
                write(&path, text.as_bytes())?;
                say!(
                    "B axis off by ({}, {}) mm: the line waves by up to {:.3} mm; wrote {}",
                    d.x,
                    d.y,
                    rep.max_error_mm,
                    path.display()
                );
            }
        }
        CalibrateCommand::Simulate {
            believed,
            truth,
            deviation: d,
            toolpath,
            test,
            svg,
            csv,
            exaggerate,
        } => {
            let b = machine(&believed)?;
            let t = truth.as_deref().map(machine).transpose()?;
            let deviation = Deviation {
                a_offset: d.a_offset.unwrap_or(DVec3::ZERO),
                a_rot_z_deg: d.a_rot_z,
                a_rot_y_deg: d.a_rot_y,
                b_offset: d.b_offset.unwrap_or(DVec3::ZERO),
                b_rot_x_deg: d.b_rot_x,
                b_rot_y_deg: d.b_rot_y,
                z_wobble_mm: 0.0,
            };
            let (csv_text, name);
            let input = match (&toolpath, test) {
                (Some(path), None) => {
                    csv_text = read_text(path)?;
                    name = path.display().to_string();
                    SimInput::Toolpath {
                        csv: &csv_text,
                        name: &name,
                    }
                }
                (None, Some(kind)) => {
                    SimInput::TestPrint(kind.parse().map_err(|e: cal::CalibError| e.to_string())?)
                }
                _ => return Err("give either --toolpath FILE or --test KIND".to_string()),
            };
            let (report, title) =
                simulate::run(&b, t.as_ref(), &deviation, input).map_err(|e| match &toolpath {
                    Some(path) => format!("{}: {e}", path.display()),
                    None => e.to_string(),
                })?;
            let text = report.to_text();
            say!("{}", text.lines().next().unwrap_or_default());
            if let Some(path) = csv {
                let body: String = text.lines().skip(1).map(|l| format!("{l}\n")).collect();
                write(&path, body.as_bytes())?;
                say!("wrote {}", path.display());
            }
            if let Some(path) = svg {
                write(&path, simulate::svg(&report, &title, exaggerate).as_bytes())?;
                say!("wrote {}", path.display());
            }
        }
    }
    Ok(())
}
