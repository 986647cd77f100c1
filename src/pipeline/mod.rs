//! The two user-facing steps, as plain functions over bytes: [`warp_model`] (STL → warped STL
//! and job) and [`unwarp`] (G-code and job → non-planar G-code, 3-axis or a machine's axes).
//! The CLI, the wasm module and the web worker are thin faces over these.
//!
//! This is where the machine is chosen: [`UnwarpSettings`] holds the unwarp's options and the
//! machine's, [`unwarper`] builds the emitter the machine options ask for and hands it to the
//! unwarp, which knows nothing of machines.

use crate::error::Coded;
use crate::job::JobError;
use crate::mesh::MeshError;
use crate::warp::WarpError;

mod builtin_step;
mod checked_unwarp;
#[cfg(not(target_arch = "wasm32"))]
pub mod files;
mod unwarp_step;
mod warp_step;

pub use builtin_step::{builtin_settings, slice_builtin, start_builtin};
pub use checked_unwarp::CheckedUnwarper;
pub use unwarp_step::{
    unwarp, unwarp_stream, unwarp_with_stl, unwarper, unwarper_with_stl, warped_mesh,
    UnwarpSettings, STREAM_CHUNK,
};
pub use warp_step::{
    input_to_model, warp_model, warp_model_capped, AnchorMode, WarpOptions, WarpOutput, WarpReport,
    WARP_OPTION_PARAMS,
};

/// Any error of the pipeline, each from its own area.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The input STL cannot be read.
    Mesh(MeshError),
    /// The warp cannot be built for this model, or its parameters are invalid.
    Warp(WarpError),
    /// The job file cannot be used.
    Job(JobError),
    /// The slicer's G-code cannot be read.
    Gcode(crate::gcode::GcodeError),
    /// Pass 1 could not find where the slicer put the warped part.
    Register(crate::register::RegisterError),
    /// The G-code cannot be unwarped.
    Unwarp(crate::unwarp::UnwarpError),
    /// The machine cannot be set up (`--machine`, `--flavour`).
    Machine(crate::machine::MachineError),
    /// The built-in slicer's settings are invalid, or it found nothing to print.
    Planar(crate::planar::PlanarError),
    /// The planar slicer failed (`warpslice run`).
    #[cfg(not(target_arch = "wasm32"))]
    Slicer(crate::slicer::SlicerError),
    /// A file or stream could not be read or written (`what`: the file, `message`: the
    /// operating system's words).
    Io {
        /// What was being read or written (a file name, or `output`).
        what: String,
        /// The operating system's error message.
        message: String,
    },
    /// A bad option value (name, value, what is allowed).
    Option {
        /// The option's CLI name without dashes (e.g. `max-edge`).
        name: &'static str,
        /// The value given, as text.
        value: String,
        /// What the option accepts (e.g. `a positive number (mm)`).
        allowed: &'static str,
    },
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::Mesh(e) => write!(f, "STL: {e}"),
            Error::Warp(e) => e.fmt(f),
            Error::Job(e) => e.fmt(f),
            Error::Gcode(e) => e.fmt(f),
            Error::Register(e) => e.fmt(f),
            Error::Unwarp(e) => e.fmt(f),
            Error::Machine(e) => e.fmt(f),
            Error::Planar(e) => e.fmt(f),
            Error::Io { what, message } => write!(f, "{what}: {message}"),
            #[cfg(not(target_arch = "wasm32"))]
            Error::Slicer(e) => e.fmt(f),
            Error::Option {
                name,
                value,
                allowed,
            } => write!(f, "option {name} = {value} is not allowed: {allowed}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Mesh(e) => Some(e),
            Error::Warp(e) => Some(e),
            Error::Job(e) => Some(e),
            Error::Gcode(e) => Some(e),
            Error::Register(e) => Some(e),
            Error::Unwarp(e) => Some(e),
            Error::Machine(e) => Some(e),
            Error::Planar(e) => Some(e),
            #[cfg(not(target_arch = "wasm32"))]
            Error::Slicer(e) => Some(e),
            Error::Option { .. } | Error::Io { .. } => None,
        }
    }
}

impl Coded for Error {
    fn code(&self) -> &'static str {
        match self {
            Error::Mesh(e) => e.code(),
            Error::Warp(e) => e.code(),
            Error::Job(e) => e.code(),
            Error::Gcode(e) => e.code(),
            Error::Register(e) => e.code(),
            Error::Unwarp(e) => e.code(),
            Error::Machine(e) => e.code(),
            Error::Planar(e) => e.code(),
            #[cfg(not(target_arch = "wasm32"))]
            Error::Slicer(e) => e.code(),
            Error::Option { .. } => "options.invalid",
            Error::Io { .. } => "io.failed",
        }
    }
}

/// The codes of the pipeline's own errors (see [`crate::error`]); wrapped errors report theirs.
pub const ERROR_CODES: &[crate::error::ErrorCode] = &[
    crate::error::ErrorCode {
        code: "options.invalid",
        area: "options",
        summary: "an option value (or the options JSON) that is not allowed",
    },
    crate::error::ErrorCode {
        code: "io.failed",
        area: "io",
        summary: "a file or stream could not be read or written",
    },
];

macro_rules! from_error {
    ($($t:ty => $v:ident),*) => {$(
        impl From<$t> for Error {
            fn from(e: $t) -> Error { Error::$v(e) }
        }
    )*};
}
from_error!(MeshError => Mesh, WarpError => Warp, JobError => Job, crate::gcode::GcodeError => Gcode,
    crate::register::RegisterError => Register, crate::unwarp::UnwarpError => Unwarp,
    crate::machine::MachineError => Machine, crate::planar::PlanarError => Planar);
#[cfg(not(target_arch = "wasm32"))]
from_error!(crate::slicer::SlicerError => Slicer);
