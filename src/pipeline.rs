//! The two user-facing steps, as plain functions over bytes: [`warp_model`] (STL → warped STL
//! and job) and [`unwarp`] (G-code and job → non-planar G-code, 3-axis or a machine's axes).
//! The CLI, the wasm module and the web worker are thin faces over these.
//!
//! This is where the machine is chosen: [`UnwarpSettings`] holds the unwarp's options and the
//! machine's, [`unwarper`] builds the emitter the machine options ask for and hands it to the
//! unwarp, which knows nothing of machines.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::anchor;
use crate::error::Coded;
use crate::job::{fnv1a64, Job, JobError, JOB_FORMAT};
use crate::machine::{MachineOptions, MachineSpec};
use crate::mesh::{self, Aabb, Mesh, MeshError, MeshReport, SubdivideOptions, SubdivideStats};
use crate::schema::{Param, ParamDefault, ParamType};
use crate::tolerance::{DEFAULT_LAYER_HEIGHT, DEFAULT_MAX_EDGE, DEFAULT_TOLERANCE};
use crate::unwarp::{UnwarpOptions, UnwarpOutput, Unwarper};
use crate::warp::{WarpError, WarpParams};

/// Whether to put the removable anchor slab under the warped part (see [`crate::anchor`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum AnchorMode {
    /// When the warped bottom is not flat.
    #[default]
    Auto,
    /// Always: a slab even under a flat warped bottom.
    On,
    /// Never: the warped part goes to the slicer as it is.
    Off,
}

/// Options of the warp step (CLI: `warpslice warp`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WarpOptions {
    /// The warp kind, its parameters and the optional flat base (`--warp` and its options).
    pub warp: WarpParams,
    /// `--max-edge`, mm.
    #[serde(default = "default_max_edge")]
    pub max_edge: f64,
    /// `--tolerance`, mm.
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// `--layer-height`, mm: the layer height you will slice with (anchor thickness).
    #[serde(default = "default_layer_height")]
    pub layer_height: f64,
    /// `--anchor auto|on|off`.
    #[serde(default)]
    pub anchor: AnchorMode,
}

fn default_max_edge() -> f64 {
    DEFAULT_MAX_EDGE
}
fn default_tolerance() -> f64 {
    DEFAULT_TOLERANCE
}
fn default_layer_height() -> f64 {
    DEFAULT_LAYER_HEIGHT
}

impl WarpOptions {
    /// The options for `warp` with every other option at its default.
    pub fn new(warp: WarpParams) -> WarpOptions {
        WarpOptions {
            warp,
            max_edge: DEFAULT_MAX_EDGE,
            tolerance: DEFAULT_TOLERANCE,
            layer_height: DEFAULT_LAYER_HEIGHT,
            anchor: AnchorMode::Auto,
        }
    }
}

/// The parameters of the warp step besides the warp's own ([`crate::warp::WARPS`]): the
/// `--base` blend (key in the warp object) and the options' top-level keys.
pub const WARP_OPTION_PARAMS: &[Param] = &[
    Param::number("base", "--base", "Flat base z0,z1")
        .of(ParamType::Pair)
        .unit("mm")
        .optional()
        .help("keep the layers flat below z0 and blend the warp in up to z1 (shear warps only)"),
    Param::number("max_edge", "--max-edge", "Max edge")
        .unit("mm")
        .range(Some(0.0), None, (true, false))
        .step(0.1)
        .default(ParamDefault::Number(DEFAULT_MAX_EDGE))
        .help("split mesh edges longer than this before warping"),
    Param::number("tolerance", "--tolerance", "Tolerance")
        .unit("mm")
        .range(Some(0.0), None, (true, false))
        .step(0.001)
        .default(ParamDefault::Number(DEFAULT_TOLERANCE))
        .help("split where the warped midpoint of an edge (or a move) deviates more than this"),
    Param::number("layer_height", "--layer-height", "Layer height")
        .unit("mm")
        .range(Some(0.0), None, (true, false))
        .step(0.05)
        .default(ParamDefault::Number(DEFAULT_LAYER_HEIGHT))
        .help("the layer height you will slice with (the anchor's thickness and first layer)"),
    Param::number("anchor", "--anchor", "Anchor")
        .choices(&["auto", "on", "off"])
        .default(ParamDefault::Text("auto"))
        .help("a removable one-layer slab under a warped bottom that is not flat"),
];

/// What the warp step did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WarpReport {
    /// What the input STL held and what is wrong with it.
    pub mesh: MeshReport,
    /// What the subdivision before warping did.
    pub subdivide: SubdivideStats,
    /// Anchor slab thickness, if one was added.
    pub anchor: Option<f64>,
    /// Bounding box of the warped part in STL coordinates.
    pub warped_bbox: Aabb,
    /// Largest angle between the tool axis and vertical over the mesh's vertices, degrees.
    pub largest_tilt_deg: f64,
    /// Triangles written (part + anchor).
    pub triangles_out: usize,
}

/// Result of the warp step.
#[derive(Clone, Debug)]
pub struct WarpOutput {
    /// The warped binary STL.
    pub stl: Vec<u8>,
    /// The job to slice and unwarp with (also written as `WARPED.job.json`).
    pub job: Job,
    /// What the warp step did.
    pub report: WarpReport,
}

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
            Error::Io { what, message } => write!(f, "{what}: {message}"),
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

/// The unwarp step's settings as the CLI and the web page give them: the unwarp's own options
/// and the machine's (`--machine`, `--feed`, `--flavour`), side by side in one JSON object.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct UnwarpSettings {
    /// The unwarp's options.
    #[serde(flatten)]
    pub unwarp: UnwarpOptions,
    /// The machine's options.
    #[serde(flatten)]
    pub output: MachineOptions,
}

impl From<UnwarpOptions> for UnwarpSettings {
    /// 3-axis output with these unwarp options.
    fn from(unwarp: UnwarpOptions) -> UnwarpSettings {
        UnwarpSettings::three_axis(unwarp)
    }
}

impl UnwarpSettings {
    /// 3-axis output with these unwarp options.
    pub fn three_axis(unwarp: UnwarpOptions) -> UnwarpSettings {
        UnwarpSettings {
            unwarp,
            output: MachineOptions::default(),
        }
    }
    /// Output for `machine` with these unwarp options (feed `xyz`, the machine's flavour).
    pub fn with_machine(unwarp: UnwarpOptions, machine: MachineSpec) -> UnwarpSettings {
        UnwarpSettings {
            unwarp,
            output: MachineOptions {
                machine: Some(machine),
                ..MachineOptions::default()
            },
        }
    }
}

/// The streaming unwarp for `settings`: the emitter the machine options ask for, handed to
/// [`Unwarper`].
pub fn unwarper(job: &Job, settings: &UnwarpSettings) -> Result<Unwarper, Error> {
    let emitter = settings.output.emitter()?;
    Ok(Unwarper::new(job, &settings.unwarp, emitter)?)
}

/// One-shot unwarp of a whole G-code in memory (see [`crate::unwarp`]).
pub fn unwarp(gcode: &[u8], job: &Job, settings: &UnwarpSettings) -> Result<UnwarpOutput, Error> {
    let emitter = settings.output.emitter()?;
    Ok(crate::unwarp::unwarp(
        gcode,
        job,
        &settings.unwarp,
        emitter,
    )?)
}

macro_rules! from_error {
    ($($t:ty => $v:ident),*) => {$(
        impl From<$t> for Error {
            fn from(e: $t) -> Error { Error::$v(e) }
        }
    )*};
}
from_error!(MeshError => Mesh, WarpError => Warp, JobError => Job, crate::gcode::GcodeError => Gcode,
    crate::register::RegisterError => Register, crate::unwarp::UnwarpError => Unwarp,
    crate::machine::MachineError => Machine);

fn check_positive(name: &'static str, v: f64) -> Result<(), Error> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::Option {
            name,
            value: v.to_string(),
            allowed: "a positive number (mm)",
        })
    }
}

/// The model-frame translation of a mesh: centre of the XY bbox to (0, 0), lowest point to z = 0.
pub fn input_to_model(bbox: &Aabb) -> DVec3 {
    let c = bbox.center();
    DVec3::new(-c.x, -c.y, -bbox.min.z)
}

/// Warp an STL: read, move to the model frame, subdivide, warp, add the anchor if needed,
/// lift to z ≥ 0 and write the warped STL and its job.
pub fn warp_model(stl: &[u8], opts: &WarpOptions) -> Result<WarpOutput, Error> {
    check_positive("max-edge", opts.max_edge)?;
    check_positive("tolerance", opts.tolerance)?;
    check_positive("layer-height", opts.layer_height)?;
    let (mut model, mesh_report) = mesh::read_stl(stl)?;
    let t = input_to_model(&mesh_report.bbox);
    model.translate(t);
    let model_bbox = model.bbox();
    let mut params = opts.warp.clone();
    let warp = params.build(&model_bbox)?;

    let sub = SubdivideOptions {
        max_edge: opts.max_edge,
        tolerance: opts.tolerance,
    };
    let (model, warped_vertices, stats) =
        mesh::subdivide_warped(&model, &sub, &|p| warp.forward(p));
    let mut warped = Mesh {
        vertices: warped_vertices,
        triangles: model.triangles.clone(),
    };
    let min_nz = model
        .vertices
        .iter()
        .map(|&p| warp.tool_axis(p).z)
        .fold(1.0, f64::min);
    let largest_tilt_deg = crate::num::deg(crate::num::acos(min_nz.clamp(-1.0, 1.0)));

    let part_bbox_t = warped.bbox();
    let anchor = match opts.anchor {
        AnchorMode::On => true,
        AnchorMode::Off => false,
        AnchorMode::Auto => anchor::needs_anchor(&warped, opts.layer_height),
    };
    let mut anchor_thickness = None;
    if anchor && anchor::add_slab(&mut warped, part_bbox_t.min.z, opts.layer_height) {
        anchor_thickness = Some(opts.layer_height);
    }
    let stl_z_offset = -part_bbox_t.min.z + anchor_thickness.unwrap_or(0.0);
    warped.translate(DVec3::new(0.0, 0.0, stl_z_offset));
    let warped_bbox = Aabb {
        min: part_bbox_t.min + DVec3::new(0.0, 0.0, stl_z_offset),
        max: part_bbox_t.max + DVec3::new(0.0, 0.0, stl_z_offset),
    };

    let mut job = Job {
        version: env!("CARGO_PKG_VERSION").to_string(),
        format: JOB_FORMAT,
        warp: params,
        input_to_model: t.to_array(),
        model_bbox,
        stl_z_offset,
        warped_bbox,
        layer_height: opts.layer_height,
        anchor: anchor_thickness,
        max_edge: opts.max_edge,
        tolerance: opts.tolerance,
        input_hash: format!("{:016x}", fnv1a64(stl)),
        hash: String::new(),
    };
    job.seal();
    let header = format!("warpslice job {} {}", job.hash, job.warp.spec.name());
    let out = mesh::write_stl(&warped, &header);
    let report = WarpReport {
        mesh: mesh_report,
        subdivide: stats,
        anchor: anchor_thickness,
        warped_bbox,
        largest_tilt_deg,
        triangles_out: warped.triangles.len(),
    };
    Ok(WarpOutput {
        stl: out,
        job,
        report,
    })
}

/// Read size of [`unwarp_stream`], bytes.
pub const STREAM_CHUNK: usize = 1 << 20;

/// The two-pass streaming unwarp over a source that can be read twice (a file): `open` gives
/// a fresh reader from the start, `out` takes the output as it is produced, `progress` is told
/// the bytes read (both passes count, so the total is twice the input's size). Memory stays
/// bounded by the chunk, the height grid and the longest line, whatever the file's size.
/// `name` names the source in I/O errors.
pub fn unwarp_stream<R: std::io::Read>(
    job: &Job,
    settings: &UnwarpSettings,
    name: &str,
    mut open: impl FnMut() -> std::io::Result<R>,
    out: &mut dyn std::io::Write,
    mut progress: impl FnMut(u64),
) -> Result<crate::unwarp::UnwarpReport, Error> {
    let io = |e: std::io::Error| Error::Io {
        what: name.to_string(),
        message: e.to_string(),
    };
    let out_err = |e: std::io::Error| Error::Io {
        what: "output".to_string(),
        message: e.to_string(),
    };
    let mut u = unwarper(job, settings)?;
    let mut buf = vec![0u8; STREAM_CHUNK];
    let mut f = open().map_err(io)?;
    loop {
        let n = f.read(&mut buf).map_err(io)?;
        if n == 0 {
            break;
        }
        u.scan(&buf[..n])?;
        progress(n as u64);
    }
    u.end_scan()?;
    let mut f = open().map_err(io)?;
    loop {
        let n = f.read(&mut buf).map_err(io)?;
        if n == 0 {
            break;
        }
        u.push(&buf[..n])?;
        out.write_all(&u.take_output()).map_err(out_err)?;
        progress(n as u64);
    }
    let report = u.finish()?;
    out.write_all(&u.take_output()).map_err(out_err)?;
    out.flush().map_err(out_err)?;
    Ok(report)
}
