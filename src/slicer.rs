//! Driving the real planar slicers installed on this machine (native only).
//!
//! The warped STL is an ordinary mesh, so any planar slicer can slice it. This module runs one
//! of three through [`std::process::Command`] with the same settings as
//! `shared/tools/slice.sh`, so their G-code is comparable:
//!
//! | setting            | value                                   |
//! |--------------------|-----------------------------------------|
//! | layer height       | [`SliceOptions::layer_height`] (0.2 mm) |
//! | first layer height | the same as the layer height            |
//! | nozzle diameter    | 0.4 mm                                  |
//! | filament diameter  | 1.75 mm                                 |
//! | arcs (G2/G3)       | off (none of the three emits them here) |
//! | flavour            | PrusaSlicer `marlin2`, Slic3r `reprap`, CuraEngine `RepRap (Marlin/Sprinter)` |
//! | E                  | relative (M83) or absolute (M82), [`EMode`] |
//!
//! All lengths are mm. The slicer places the mesh on its own bed (PrusaSlicer and Slic3r centre
//! it on a 200 × 200 mm bed, CuraEngine on a 200 × 200 × 200 mm machine with
//! `center_object=true`); [`crate::register`] finds that shift afterwards.
//!
//! Executables are found by [`available`]: the override in [`SliceOptions::executable`], else
//! the environment variable named by [`SlicerKind::env_override`] (e.g.
//! `WARPSLICE_PRUSASLICER=/opt/bin/prusa-slicer`), else `PATH`. CuraEngine also needs the Cura
//! definitions (`fdmprinter.def.json`), looked up by [`cura_resources`].

mod command;
mod error;
mod locate;
mod run;

pub use error::{SlicerError, ERROR_CODES};
pub use locate::{cura_resources, CURA_RES_FALLBACKS};

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::{Duration, Instant};

/// Nozzle diameter passed to every slicer, mm.
pub const DEFAULT_NOZZLE_DIAMETER: f64 = 0.4;
/// Filament diameter passed to every slicer, mm.
pub const DEFAULT_FILAMENT_DIAMETER: f64 = 1.75;
/// Longest a slicer may run before it is killed ([`SlicerError::TimedOut`]).
pub const DEFAULT_SLICE_TIMEOUT: Duration = Duration::from_secs(600);

/// One of the planar slicers warpslice knows how to drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SlicerKind {
    /// PrusaSlicer (`prusa-slicer`, Debian package `prusa-slicer`).
    PrusaSlicer,
    /// Slic3r 1.3 (`slic3r`, Debian package `slic3r`).
    Slic3r,
    /// CuraEngine (`CuraEngine`, Debian package `cura-engine`, plus the definitions of `cura`).
    CuraEngine,
}

impl SlicerKind {
    /// Every slicer, in a fixed order.
    pub const ALL: [SlicerKind; 3] = [
        SlicerKind::PrusaSlicer,
        SlicerKind::Slic3r,
        SlicerKind::CuraEngine,
    ];

    /// The name used on the command line and in [`fmt::Display`]: `prusaslicer`, `slic3r`,
    /// `curaengine`.
    pub fn cli_name(self) -> &'static str {
        match self {
            SlicerKind::PrusaSlicer => "prusaslicer",
            SlicerKind::Slic3r => "slic3r",
            SlicerKind::CuraEngine => "curaengine",
        }
    }

    /// The executable looked up on `PATH`.
    pub fn executable_name(self) -> &'static str {
        match self {
            SlicerKind::PrusaSlicer => "prusa-slicer",
            SlicerKind::Slic3r => "slic3r",
            SlicerKind::CuraEngine => "CuraEngine",
        }
    }

    /// The environment variable that overrides the executable (a path or a name on `PATH`).
    pub fn env_override(self) -> &'static str {
        match self {
            SlicerKind::PrusaSlicer => "WARPSLICE_PRUSASLICER",
            SlicerKind::Slic3r => "WARPSLICE_SLIC3R",
            SlicerKind::CuraEngine => "WARPSLICE_CURAENGINE",
        }
    }

    /// How to install it on Debian/Ubuntu.
    pub fn install_hint(self) -> &'static str {
        match self {
            SlicerKind::PrusaSlicer => "apt-get install prusa-slicer",
            SlicerKind::Slic3r => "apt-get install slic3r",
            SlicerKind::CuraEngine => "apt-get install cura-engine",
        }
    }
}

impl fmt::Display for SlicerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.cli_name())
    }
}

impl FromStr for SlicerKind {
    type Err = SlicerError;

    /// Accepts `prusaslicer`, `slic3r`, `curaengine` (any case) and the executable names
    /// `prusa-slicer`, `cura-engine`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "prusaslicer" | "prusa-slicer" => Ok(SlicerKind::PrusaSlicer),
            "slic3r" => Ok(SlicerKind::Slic3r),
            "curaengine" | "cura-engine" => Ok(SlicerKind::CuraEngine),
            _ => Err(SlicerError::UnknownSlicer {
                name: s.to_string(),
            }),
        }
    }
}

/// How the slicer writes the E (extruder) axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum EMode {
    /// `M83`: each E value is the filament length of its own move.
    #[default]
    Relative,
    /// `M82`: E is the running total since the last `G92 E`.
    Absolute,
}

impl fmt::Display for EMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            EMode::Relative => "relative",
            EMode::Absolute => "absolute",
        })
    }
}

impl FromStr for EMode {
    type Err = SlicerError;

    /// Accepts `relative`/`rel` and `absolute`/`abs` (any case).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "relative" | "rel" => Ok(EMode::Relative),
            "absolute" | "abs" => Ok(EMode::Absolute),
            _ => Err(SlicerError::InvalidOption {
                option: "e-mode",
                value: s.to_string(),
                expected: "relative or absolute",
            }),
        }
    }
}

/// What to slice with and how. Build it with `SliceOptions { slicer, ..Default::default() }`.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceOptions {
    /// Which slicer to run.
    pub slicer: SlicerKind,
    /// Relative (M83) or absolute (M82) E.
    pub e_mode: EMode,
    /// Layer height and first-layer height, mm (> 0).
    pub layer_height: f64,
    /// Nozzle diameter, mm (> 0).
    pub nozzle_diameter: f64,
    /// Filament diameter, mm (> 0).
    pub filament_diameter: f64,
    /// PrusaSlicer and Slic3r `--resolution`, mm (≥ 0; 0 = full resolution): see
    /// [`crate::tolerance::SLICER_RESOLUTION`].
    pub resolution: f64,
    /// Extra arguments appended to the slicer's command line after the defaults above (for
    /// PrusaSlicer and Slic3r a later option wins, e.g. `--bed-shape 0x0,400x0,400x400,0x400`;
    /// for CuraEngine they are global `-s key=value` settings, placed before the `-e0` block).
    pub extra_args: Vec<String>,
    /// The executable to run instead of the one found by [`available`] (a path, or a name
    /// looked up on `PATH`).
    pub executable: Option<PathBuf>,
    /// CuraEngine only: the Cura `resources` folder (holding `definitions/` and `extruders/`)
    /// instead of the one found by [`cura_resources`].
    pub cura_resources: Option<PathBuf>,
    /// Kill the slicer after this long; `None` waits for ever.
    pub timeout: Option<Duration>,
}

impl Default for SliceOptions {
    fn default() -> Self {
        SliceOptions {
            slicer: SlicerKind::PrusaSlicer,
            e_mode: EMode::Relative,
            layer_height: crate::tolerance::DEFAULT_LAYER_HEIGHT,
            nozzle_diameter: DEFAULT_NOZZLE_DIAMETER,
            filament_diameter: DEFAULT_FILAMENT_DIAMETER,
            resolution: crate::tolerance::SLICER_RESOLUTION,
            extra_args: Vec::new(),
            executable: None,
            cura_resources: None,
            timeout: Some(DEFAULT_SLICE_TIMEOUT),
        }
    }
}

/// A warning the slicer printed while still writing G-code, with what to do about it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlicerWarning {
    /// The slicer's own line.
    pub message: String,
    /// What the user can change.
    pub advice: &'static str,
}

impl fmt::Display for SlicerWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.message, self.advice)
    }
}

/// What a successful [`slice`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceReport {
    /// The slicer that ran.
    pub slicer: SlicerKind,
    /// The executable that ran.
    pub executable: PathBuf,
    /// The full argument list passed to it (for logs and bug reports).
    pub args: Vec<String>,
    /// The G-code written.
    pub gcode_path: PathBuf,
    /// Its size in bytes (> 0).
    pub gcode_bytes: u64,
    /// Known warnings recognised in the slicer's output.
    pub warnings: Vec<SlicerWarning>,
    /// Wall-clock time of the slicer run.
    pub elapsed: Duration,
}

/// Finds the executable of `kind` (environment override, else `PATH`); for CuraEngine also
/// checks that its definitions are present ([`cura_resources`]).
pub fn available(kind: SlicerKind) -> Result<PathBuf, SlicerError> {
    let exe = locate::find_executable(kind, None)?;
    if kind == SlicerKind::CuraEngine {
        cura_resources(None)?;
    }
    Ok(exe)
}

/// Slices `stl_path` (which must end in `.stl`: all three slicers pick the reader by extension)
/// into `gcode_out` with `opts`.
///
/// An existing `gcode_out` is removed first, so a file found afterwards is this run's. Known
/// refusals (no extrusions in the first layer, objects larger than the bed, unreadable STL)
/// become [`SlicerError::Refused`] with advice; any other non-zero exit is
/// [`SlicerError::Failed`] with the meaningful tail of the slicer's output.
pub fn slice(
    stl_path: &Path,
    gcode_out: &Path,
    opts: &SliceOptions,
) -> Result<SliceReport, SlicerError> {
    command::validate(stl_path, opts)?;
    if !stl_path.is_file() {
        return Err(SlicerError::Io {
            path: stl_path.to_path_buf(),
            action: "read the STL",
            message: "no such file".to_string(),
        });
    }
    let executable = locate::find_executable(opts.slicer, opts.executable.as_deref())?;
    let cura_res = match opts.slicer {
        SlicerKind::CuraEngine => Some(cura_resources(opts.cura_resources.as_deref())?),
        _ => None,
    };
    match std::fs::remove_file(gcode_out) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => {
            return Err(SlicerError::Io {
                path: gcode_out.to_path_buf(),
                action: "remove the old G-code",
                message: e.to_string(),
            })
        }
    }
    let inv = command::build(stl_path, gcode_out, opts, cura_res.as_deref());
    let started = Instant::now();
    let outcome = run::run(&executable, &inv, opts.timeout).map_err(|e| match e {
        run::RunError::Spawn(err) if err.kind() == std::io::ErrorKind::NotFound => {
            SlicerError::NotInstalled {
                slicer: opts.slicer,
                searched: executable.display().to_string(),
                hint: opts.slicer.install_hint(),
            }
        }
        run::RunError::Spawn(err) => SlicerError::Io {
            path: executable.clone(),
            action: "start the slicer",
            message: err.to_string(),
        },
        run::RunError::TimedOut(after) => SlicerError::TimedOut {
            slicer: opts.slicer,
            seconds: after.as_secs_f64(),
        },
    })?;
    let elapsed = started.elapsed();
    let text = outcome.combined_text();
    let gcode_bytes = std::fs::metadata(gcode_out).map(|m| m.len()).unwrap_or(0);
    if !outcome.status.success() || gcode_bytes == 0 {
        if let Some(refusal) = error::recognise_refusal(opts.slicer, &text) {
            return Err(refusal);
        }
        if !outcome.status.success() {
            return Err(SlicerError::Failed {
                slicer: opts.slicer,
                status: outcome.status.to_string(),
                output_tail: error::meaningful_tail(&text),
            });
        }
        return Err(SlicerError::NoOutput {
            slicer: opts.slicer,
            gcode_out: gcode_out.to_path_buf(),
            output_tail: error::meaningful_tail(&text),
        });
    }
    Ok(SliceReport {
        slicer: opts.slicer,
        executable,
        args: inv.args,
        gcode_path: gcode_out.to_path_buf(),
        gcode_bytes,
        warnings: error::recognise_warnings(opts.slicer, &text),
        elapsed,
    })
}
