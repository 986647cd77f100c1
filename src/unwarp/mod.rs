//! Unwarp: map a planar slicer's G-code of the warped mesh back to the real part.
//!
//! Two streaming passes over the G-code bytes (memory is bounded by the longest line, the
//! height grid and the caller's output buffer, never by the file):
//! 1. [`crate::register`]: find where the slicer put the mesh and which lines are the warped
//!    region, the skirt, the anchor layer.
//! 2. This module: every object extrusion is split adaptively ([`segment`]) so that the mapped
//!    polyline stays within `tolerance` of the exact image of the straight move under T⁻¹ and
//!    no piece is longer than `max_segment`; every point is mapped with T⁻¹, gets the tool
//!    axis (layer normal), layer, feature and feed; E is made volume-correct ([`extrusion`]);
//!    travels are re-planned ([`travel`]); skirt and brim stay flat at their slicer height (or
//!    are dropped, `drop_skirt`); the anchor layer's extrusions are dropped; lines outside the
//!    region, and non-move lines inside it, pass through verbatim and in order.
//!
//! Coordinates: a G-code point g (slicer bed frame) → STL point g − (dx, dy, 0) → T-space
//! q = STL − (0, 0, stl_z_offset) → model p = T⁻¹(q) → output p + model_to_output, with
//! model_to_output = (dx, dy, z_offset), written as `; warpslice model_to_output = dx dy dz`.
//! With `place` = (px, py) the part goes there instead of where the slicer put it:
//! model_to_output = (px, py, z_offset), and the flat skirt and brim move with it by
//! (px − dx, py − dy) (for machines whose rotary axes pass through a fixed point, e.g. an A/B
//! table's origin). Lines outside the region (start and end G-code) are never moved.
//!
//! **Never below the bed.** A mapped object point with z < 0 (hundredths of a millimetre from
//! a slicer's first-layer offset on a steep warp) is clamped to z = 0 and the E of the
//! segments ending there is scaled by (h − depth)/h (h = job layer height); the report counts
//! such points.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::gcode::write::push_e;
use crate::gcode::{Command, GcodeError, Line, Move, ReadOptions, Reader, State};
use crate::job::Job;
use crate::machine::{FeedMode, Flavour, MachineEmitter, MachineError, MachineReport, MachineSpec};
use crate::pipeline::Error;
use crate::register::{Registration, Scanner};
use crate::tolerance::{
    DEFAULT_MAX_SEGMENT, DEFAULT_RETRACT_LENGTH, DEFAULT_TOLERANCE, DEFAULT_TRAVEL_CLEARANCE,
    LENGTH_EPSILON,
};
use crate::toolpath::{Feature, ToolPoint};
use crate::warp::Warp;

pub mod emit;
pub mod extrusion;
pub mod segment;
pub mod travel;

pub use emit::{Cartesian, Emitter};
pub use extrusion::{EWriter, Flow};

/// Feed for the retractions warpslice adds, mm/min (40 mm/s).
pub const RETRACT_FEED: f64 = 2400.0;
/// Feed for lifts and descents warpslice adds when the slicer gave none, mm/min.
pub const DEFAULT_TRAVEL_FEED: f64 = 6000.0;

/// Options of the unwarp step (CLI: `warpslice unwarp`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct UnwarpOptions {
    /// `--tolerance`, mm.
    pub tolerance: f64,
    /// `--max-segment`, mm.
    pub max_segment: f64,
    /// `--flow`, `--ramp`.
    pub flow: Flow,
    /// `--z-offset`, mm: added to every output z (seed 000 §4.3.2 uses +0.2 … +0.3 mm).
    pub z_offset: f64,
    /// `--drop-skirt`.
    pub drop_skirt: bool,
    /// `--offset dx,dy`: the slicer's placement, instead of finding it.
    pub offset: Option<[f64; 2]>,
    /// `--place x,y`: where the model frame's origin (the centre of the part's footprint) goes
    /// in the output, instead of the slicer's placement.
    pub place: Option<[f64; 2]>,
    /// Clearance above printed material on lifted travels, mm.
    pub travel_clearance: f64,
    /// Retraction added before a lifted travel when the slicer did not retract, mm.
    pub retract_length: f64,
    /// Keep the toolpath in memory (for the machines and the preview).
    pub collect_toolpath: bool,
    /// `--machine`: write the machine's axes instead of 3-axis G-code. In JSON a machine
    /// object or a preset name (`"machine": "pax-5axis"`).
    #[serde(deserialize_with = "machine_from_json")]
    pub machine: Option<MachineSpec>,
    /// `--feed`: how F is written for a machine.
    pub feed: FeedMode,
    /// `--flavour`: the firmware (overrides the machine's).
    pub flavour: Option<Flavour>,
}

/// `machine` in the options JSON: `null`, a preset name or a machine object.
fn machine_from_json<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<MachineSpec>, D::Error> {
    use serde::de::Error as _;
    match Option::<serde_json::Value>::deserialize(d)? {
        None | Some(serde_json::Value::Null) => Ok(None),
        Some(serde_json::Value::String(name)) => crate::machine::preset(&name)
            .map(Some)
            .map_err(D::Error::custom),
        Some(v @ serde_json::Value::Object(_)) => {
            MachineSpec::from_json(&v.to_string(), "unwarp options 'machine'")
                .map(Some)
                .map_err(D::Error::custom)
        }
        Some(other) => Err(D::Error::custom(format!(
            "machine must be a preset name or a machine object, not {other}"
        ))),
    }
}

impl UnwarpOptions {
    /// The emitter these options ask for: 3-axis, or the machine's.
    pub fn emitter(&self) -> Result<Box<dyn Emitter>, MachineError> {
        Ok(match &self.machine {
            None => Box::new(Cartesian::new()),
            Some(spec) => Box::new(MachineEmitter::new(spec, self.flavour, self.feed)?),
        })
    }
}

impl Default for UnwarpOptions {
    fn default() -> Self {
        UnwarpOptions {
            tolerance: DEFAULT_TOLERANCE,
            max_segment: DEFAULT_MAX_SEGMENT,
            flow: Flow::default(),
            z_offset: 0.0,
            drop_skirt: false,
            offset: None,
            place: None,
            travel_clearance: DEFAULT_TRAVEL_CLEARANCE,
            retract_length: DEFAULT_RETRACT_LENGTH,
            collect_toolpath: false,
            machine: None,
            feed: FeedMode::default(),
            flavour: None,
        }
    }
}

/// What unwarp did.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct UnwarpReport {
    /// STL → G-code translation found (or given), mm.
    pub translation: [f64; 3],
    pub residual: f64,
    /// Translation from model-frame coordinates to the output's X Y Z.
    pub model_to_output: [f64; 3],
    pub lines_in: u64,
    pub lines_out: u64,
    /// Object extrusion moves split into more than one piece.
    pub moves_split: u64,
    /// Extrusion segments written.
    pub segments_out: u64,
    /// Filament of all extrusions read, mm.
    pub e_in: f64,
    /// Filament of all extrusions written, mm.
    pub e_out: f64,
    /// Filament of the anchor layer (dropped), mm.
    pub e_anchor: f64,
    /// Filament of skirt/brim/custom extrusions (kept flat or dropped), mm.
    pub e_skirt: f64,
    /// "flat" or "dropped".
    pub skirt: String,
    /// Largest angle between tool axis and vertical on an extrusion, degrees.
    pub largest_tilt_deg: f64,
    /// Points clamped to the bed.
    pub clamped_points: u64,
    /// Travels lifted over printed material.
    pub lifts: u64,
    /// Retractions added around lifted travels.
    pub retracts_added: u64,
    /// The machine emitter's measurements (`--machine`).
    pub machine: Option<MachineReport>,
}

/// Why a G-code cannot be unwarped.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum UnwarpError {
    /// G91 relative positioning inside the printed region.
    RelativePositioning {
        line: u64,
    },
    /// G92 with X, Y or Z inside the printed region.
    AxisReset {
        line: u64,
    },
    /// G20 inches inside the printed region.
    Inches {
        line: u64,
    },
    Gcode(GcodeError),
    /// The streaming calls came in the wrong order.
    Order {
        expected: &'static str,
    },
    /// The machine cannot follow the toolpath (or cannot be set up): the G-code line being
    /// unwarped when it happened (`None`: before the first line).
    Machine {
        line: Option<u64>,
        error: MachineError,
    },
    /// `place` is not two finite numbers.
    BadPlace {
        place: [f64; 2],
    },
    /// A cylindrical job's layer axis is not the lathe's mandrel axis (output frame, y and z
    /// in mm): printing would wind the layers round the wrong line.
    MandrelMismatch {
        machine: String,
        warp: [f64; 2],
        mandrel: [f64; 2],
    },
}

impl From<GcodeError> for UnwarpError {
    fn from(e: GcodeError) -> Self {
        UnwarpError::Gcode(e)
    }
}

impl std::fmt::Display for UnwarpError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UnwarpError::RelativePositioning { line } => write!(
                f,
                "G-code line {line}: relative positioning (G91) inside the printed region is not supported; export absolute coordinates"
            ),
            UnwarpError::AxisReset { line } => write!(
                f,
                "G-code line {line}: G92 resets X/Y/Z inside the printed region; remove it (only G92 E is allowed there)"
            ),
            UnwarpError::Inches { line } => {
                write!(f, "G-code line {line}: inches (G20) inside the printed region; export the G-code in millimetres")
            }
            UnwarpError::Gcode(e) => e.fmt(f),
            UnwarpError::Order { expected } => write!(f, "unwarp: call {expected} first"),
            UnwarpError::Machine { line: Some(line), error } => write!(f, "G-code line {line}: {error}"),
            UnwarpError::Machine { line: None, error } => error.fmt(f),
            UnwarpError::MandrelMismatch { machine, warp, mandrel } => write!(
                f,
                "the cylindrical warp's layers are coaxial about the line y = {}, z = {} (along X, in the output) but machine {machine} turns about y = {}, z = {}: set \"axis_y_mm\": {}, \"axis_z_mm\": {} in the machine JSON, or --place the part so that its warp axis lies on the mandrel",
                fmt(warp[0]), fmt(warp[1]), fmt(mandrel[0]), fmt(mandrel[1]), fmt(warp[0]), fmt(warp[1])
            ),
            UnwarpError::BadPlace { place } => {
                write!(f, "place {},{} is not a position: give two finite numbers x,y in mm", place[0], place[1])
            }
        }
    }
}

impl std::error::Error for UnwarpError {}

/// What kind of extrusion a move piece is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Object,
    Flat,
    Dropped,
}

/// A travel waiting for its destination to be known (the start of the next extrusion).
#[derive(Clone, Copy, Debug)]
struct Pending {
    f: f64,
    /// Unretraction the slicer wrote during the travel, mm.
    unretract: f64,
    /// Feed of that unretraction.
    unretract_f: f64,
}

/// Pass 2 state.
struct Core {
    job: Job,
    warp: Box<dyn Warp>,
    opts: UnwarpOptions,
    reg: Registration,
    dx: f64,
    dy: f64,
    /// Output shift of the slicer-frame points: `place` − (dx, dy), or zero.
    shift: DVec3,
    out: Vec<u8>,
    emit: Box<dyn Emitter>,
    /// The first error the emitter returned (the driver stops at the end of that line).
    emit_error: Option<UnwarpError>,
    /// The slicer's own E position (absolute files), to re-synchronise after the region.
    slicer_e: f64,
    /// Output position and tool axis, output frame.
    cur: Option<(DVec3, DVec3)>,
    pending: Option<Pending>,
    /// Filament the slicer retracted and has not yet pushed back, mm.
    retracted: f64,
    grid: travel::HeightGrid,
    inside: bool,
    done_region: bool,
    /// Smallest z component of an object extrusion's tool axis (cos of the largest tilt).
    min_nz: f64,
    /// The file's E mode at the last line (M83 = relative).
    e_relative: bool,
    report: UnwarpReport,
    toolpath: Vec<ToolPoint>,
    stack: Vec<(f64, DVec3, u32)>,
    pieces: Vec<(f64, DVec3)>,
}

/// Streaming unwarp: [`Unwarper::scan`] the whole G-code, [`Unwarper::end_scan`], then
/// [`Unwarper::push`] it again, draining [`Unwarper::take_output`] as you go, and
/// [`Unwarper::finish`].
pub struct Unwarper {
    job: Job,
    opts: UnwarpOptions,
    scanner: Option<Scanner>,
    reader: Reader,
    core: Option<Core>,
    /// The emitter, until pass 2 starts.
    emitter: Option<Box<dyn Emitter>>,
    finished: bool,
}

impl Unwarper {
    pub fn new(job: &Job, opts: &UnwarpOptions) -> Result<Unwarper, Error> {
        for (name, v) in [
            ("tolerance", opts.tolerance),
            ("max-segment", opts.max_segment),
            ("flow", opts.flow.factor),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::Option {
                    name,
                    value: v.to_string(),
                    allowed: "a positive number",
                });
            }
        }
        if !opts.z_offset.is_finite() {
            return Err(Error::Option {
                name: "z-offset",
                value: opts.z_offset.to_string(),
                allowed: "a finite number (mm)",
            });
        }
        if let Some([f0, zr]) = opts.flow.ramp {
            if !(f0.is_finite() && f0 > 0.0 && zr.is_finite() && zr > 0.0) {
                return Err(Error::Option {
                    name: "ramp",
                    value: format!("{f0},{zr}"),
                    allowed: "f0,z_ramp with f0 > 0 and z_ramp > 0 mm",
                });
            }
        }
        // build once to validate the job's warp
        job.warp.clone().build(&job.model_bbox)?;
        let emitter = opts
            .emitter()
            .map_err(|error| UnwarpError::Machine { line: None, error })?;
        Ok(Unwarper {
            emitter: Some(emitter),
            job: job.clone(),
            opts: opts.clone(),
            scanner: Some(Scanner::new(job)),
            reader: Reader::new(ReadOptions::default()),
            core: None,
            finished: false,
        })
    }

    /// Pass 1: feed a chunk.
    pub fn scan(&mut self, chunk: &[u8]) -> Result<(), Error> {
        match self.scanner.as_mut() {
            Some(s) => Ok(s.push(chunk)?),
            None => Err(UnwarpError::Order {
                expected: "scan before end_scan",
            }
            .into()),
        }
    }

    /// End of pass 1: registration. Writes the output header.
    pub fn end_scan(&mut self) -> Result<Registration, Error> {
        let scanner = self
            .scanner
            .take()
            .ok_or(UnwarpError::Order { expected: "scan" })?;
        let reg = scanner.finish(&self.job, self.opts.offset)?;
        let mut params = self.job.warp.clone();
        let warp = params.build(&self.job.model_bbox)?;
        let [dx, dy, _] = reg.translation;
        let shift = match self.opts.place {
            Some([px, py]) if px.is_finite() && py.is_finite() => DVec3::new(px - dx, py - dy, 0.0),
            Some(place) => return Err(UnwarpError::BadPlace { place }.into()),
            None => DVec3::ZERO,
        };
        mandrel_check(
            &self.job,
            self.opts.machine.as_ref(),
            [dx + shift.x, dy + shift.y, self.opts.z_offset],
        )?;
        let b = reg.gcode_bbox;
        let mut core = Core {
            job: self.job.clone(),
            warp,
            opts: self.opts.clone(),
            reg: reg.clone(),
            dx,
            dy,
            shift,
            out: Vec::with_capacity(1 << 16),
            emit: self.emitter.take().ok_or(UnwarpError::Order {
                expected: "end_scan only once:",
            })?,
            emit_error: None,
            slicer_e: 0.0,
            cur: None,
            pending: None,
            retracted: 0.0,
            grid: travel::HeightGrid::new((b.min + shift).truncate(), (b.max + shift).truncate()),
            inside: false,
            done_region: false,
            min_nz: 1.0,
            e_relative: false,
            report: UnwarpReport {
                translation: reg.translation,
                residual: reg.residual,
                model_to_output: [dx + shift.x, dy + shift.y, self.opts.z_offset],
                skirt: if self.opts.drop_skirt {
                    "dropped".into()
                } else {
                    "flat".into()
                },
                ..UnwarpReport::default()
            },
            toolpath: Vec::new(),
            stack: Vec::new(),
            pieces: Vec::new(),
        };
        core.header();
        self.core = Some(core);
        Ok(reg)
    }

    /// Pass 2: feed a chunk (the same bytes again, from the start).
    pub fn push(&mut self, chunk: &[u8]) -> Result<(), Error> {
        let core = self.core.as_mut().ok_or(UnwarpError::Order {
            expected: "end_scan",
        })?;
        let r = self
            .reader
            .push::<UnwarpError>(chunk, &mut |l, s| core.line(&l, s));
        r.map_err(Error::from)
    }

    /// Drain the output written so far.
    pub fn take_output(&mut self) -> Vec<u8> {
        // hand over the buffer and start a new one of the same capacity (no regrowth)
        self.core
            .as_mut()
            .map(|c| {
                let cap = c.out.capacity();
                std::mem::replace(&mut c.out, Vec::with_capacity(cap))
            })
            .unwrap_or_default()
    }

    /// Drain the toolpath collected so far (`collect_toolpath`).
    pub fn take_toolpath(&mut self) -> Vec<ToolPoint> {
        self.core
            .as_mut()
            .map(|c| std::mem::take(&mut c.toolpath))
            .unwrap_or_default()
    }

    /// End of pass 2; drain the output after this.
    pub fn finish(&mut self) -> Result<UnwarpReport, Error> {
        if self.finished {
            return Err(UnwarpError::Order {
                expected: "finish only once:",
            }
            .into());
        }
        let core = self.core.as_mut().ok_or(UnwarpError::Order {
            expected: "end_scan",
        })?;
        self.reader
            .finish::<UnwarpError>(&mut |l, s| core.line(&l, s))?;
        if core.inside && !core.done_region {
            core.end_region();
        }
        core.report.largest_tilt_deg =
            crate::num::deg(crate::num::acos(core.min_nz.clamp(-1.0, 1.0)));
        if let Some(e) = core.emit_error.take() {
            return Err(e.into());
        }
        core.counted(|c| c.emit.finish(&mut c.out));
        core.report.machine = core.emit.machine_report();
        self.finished = true;
        Ok(core.report.clone())
    }
}

/// The result of [`unwarp`].
#[derive(Clone, Debug)]
pub struct UnwarpOutput {
    pub gcode: Vec<u8>,
    pub report: UnwarpReport,
    pub registration: Registration,
    pub toolpath: Vec<ToolPoint>,
}

/// One-shot unwarp of a whole G-code in memory.
pub fn unwarp(gcode: &[u8], job: &Job, opts: &UnwarpOptions) -> Result<UnwarpOutput, Error> {
    let mut u = Unwarper::new(job, opts)?;
    u.scan(gcode)?;
    let registration = u.end_scan()?;
    u.push(gcode)?;
    let report = u.finish()?;
    Ok(UnwarpOutput {
        gcode: u.take_output(),
        report,
        registration,
        toolpath: u.take_toolpath(),
    })
}

impl Core {
    fn nl(&mut self) {
        self.out.push(b'\n');
        self.report.lines_out += 1;
    }

    fn header(&mut self) {
        let m = self.report.model_to_output;
        let lines = [
            format!(
                "; generated by warpslice {} (non-planar unwarp of a planar slicer's G-code)",
                env!("CARGO_PKG_VERSION")
            ),
            format!("; warpslice job = {}", self.job.to_json_line()),
            format!(
                "; warpslice registration: translation {} {} 0, residual {:.4} mm{}",
                fmt(m[0]),
                fmt(m[1]),
                self.reg.residual,
                if self.reg.overridden {
                    " (given with --offset)"
                } else {
                    ""
                }
            ),
            format!(
                "; warpslice model_to_output = {} {} {}",
                fmt(m[0]),
                fmt(m[1]),
                fmt(m[2])
            ),
        ];
        for l in lines {
            self.out.extend_from_slice(l.as_bytes());
            self.nl();
        }
        self.counted(|c| c.emit.header(&mut c.out));
    }

    /// Run `f` (which writes to `out`) and count the lines it wrote.
    fn counted<R>(&mut self, f: impl FnOnce(&mut Core) -> R) -> R {
        let start = self.out.len();
        let r = f(self);
        self.report.lines_out += self.out[start..].iter().filter(|&&b| b == b'\n').count() as u64;
        r
    }

    /// Keep the first emitter error, naming the G-code line.
    fn keep_error(&mut self, r: Result<(), MachineError>) {
        if let Err(error) = r {
            if self.emit_error.is_none() {
                self.emit_error = Some(UnwarpError::Machine {
                    line: Some(self.report.lines_in),
                    error,
                });
            }
        }
    }

    fn line(&mut self, line: &Line<'_>, state: &State) -> Result<(), UnwarpError> {
        self.line_inner(line, state)?;
        match self.emit_error.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    fn line_inner(&mut self, line: &Line<'_>, state: &State) -> Result<(), UnwarpError> {
        self.report.lines_in = line.number;
        self.e_relative = state.e_relative;
        let n = line.number;
        let in_region = n >= self.reg.region[0] && n <= self.reg.region[1];
        if in_region && !self.inside {
            self.inside = true;
            if state.inch {
                return Err(UnwarpError::Inches { line: n });
            }
            let p = state_position_before(line, state);
            self.cur = Some((p, DVec3::Z));
            // the firmware's E is the slicer's at this point (absolute files: E words continue
            // from it)
            self.emit.reset_e(self.slicer_e);
            let r = self.counted(|c| c.emit.begin_region(&mut c.out, p, DVec3::Z));
            self.keep_error(r);
        }
        if !in_region && self.inside && !self.done_region {
            self.end_region();
        }
        // The slicer's own E position (for re-synchronising absolute E after the region).
        for m in line.moves {
            self.slicer_e += m.e;
        }
        if let Command::SetPosition { e: Some(v), .. } = line.command {
            self.slicer_e = v;
        }
        if !self.inside || self.done_region {
            self.passthrough(line.raw);
            return Ok(());
        }
        match line.command {
            Command::Positioning { relative: true } => {
                return Err(UnwarpError::RelativePositioning { line: n })
            }
            Command::Units { inch: true } => return Err(UnwarpError::Inches { line: n }),
            Command::SetPosition { xyz: true, .. } => {
                return Err(UnwarpError::AxisReset { line: n })
            }
            Command::SetPosition { e: Some(v), .. } => {
                self.emit.reset_e(v);
                self.passthrough(line.raw);
            }
            Command::Move { .. } => {
                if state.positioning_relative {
                    return Err(UnwarpError::RelativePositioning { line: n });
                }
                for m in line.moves {
                    self.piece(n, m, state.e_relative)?;
                }
            }
            _ => self.passthrough(line.raw),
        }
        Ok(())
    }

    fn passthrough(&mut self, raw: &[u8]) {
        self.emit.raw(&mut self.out, raw);
        self.report.lines_out += 1;
    }

    /// Hand a point to the emitter (counting the lines it writes) and keep it.
    fn emit_point(&mut self, tp: ToolPoint, relative: bool) {
        if self.emit_error.is_some() {
            return;
        }
        let r = self.counted(|c| c.emit.point(&mut c.out, &tp, relative));
        self.keep_error(r);
        if !tp.travel || tp.e == 0.0 {
            self.cur = Some((tp.p, tp.n));
        }
        if self.opts.collect_toolpath {
            self.toolpath.push(tp);
        }
    }

    fn kind(&self, line: u64, m: &Move) -> Kind {
        let flat = !m.feature.is_object() || (!self.reg.typed && self.reg.in_skirt_run(line));
        if flat {
            return if self.opts.drop_skirt {
                Kind::Dropped
            } else {
                Kind::Flat
            };
        }
        if self.job.anchor.is_some() && m.layer == self.reg.first_layer {
            return Kind::Dropped;
        }
        Kind::Object
    }

    /// G-code point → model frame.
    fn to_model(&self, g: DVec3) -> DVec3 {
        let q = DVec3::new(g.x - self.dx, g.y - self.dy, g.z - self.job.stl_z_offset);
        self.warp.inverse(q)
    }

    fn model_to_output(&self, p: DVec3) -> DVec3 {
        DVec3::new(
            p.x + self.dx + self.shift.x,
            p.y + self.dy + self.shift.y,
            p.z + self.opts.z_offset,
        )
    }

    fn map_point(&self, kind: Kind, g: DVec3) -> (DVec3, DVec3) {
        match kind {
            Kind::Object => {
                let p = self.to_model(g);
                let n = self.warp.tool_axis(p);
                (self.model_to_output(DVec3::new(p.x, p.y, p.z.max(0.0))), n)
            }
            _ => (
                DVec3::new(
                    g.x + self.shift.x,
                    g.y + self.shift.y,
                    g.z + self.opts.z_offset,
                ),
                DVec3::Z,
            ),
        }
    }

    fn piece(&mut self, line: u64, m: &Move, relative: bool) -> Result<(), UnwarpError> {
        let moved = (m.to - m.from).length_squared() > 0.0;
        if !moved {
            if m.e == 0.0 {
                // a feed-only G1: keep the feed modal state ours
                return Ok(());
            }
            if m.e > 0.0 {
                if let Some(p) = self.pending.as_mut() {
                    p.unretract += m.e;
                    p.unretract_f = m.f;
                    return Ok(());
                }
            }
            self.retracted = (self.retracted - m.e).max(0.0);
            self.write_e_only(m.e, m.f, relative);
            return Ok(());
        }
        if m.e <= 0.0 {
            if m.e < 0.0 {
                // a wipe: retract in place
                self.retracted -= m.e;
                self.write_e_only(m.e, m.f, relative);
            }
            let p = self.pending.get_or_insert(Pending {
                f: m.f,
                unretract: 0.0,
                unretract_f: m.f,
            });
            p.f = m.f;
            return Ok(());
        }
        // An extrusion.
        self.report.e_in += m.e;
        let kind = self.kind(line, m);
        if kind == Kind::Dropped {
            if self.job.anchor.is_some()
                && m.feature.is_object()
                && (self.reg.typed || !self.reg.in_skirt_run(line))
            {
                self.report.e_anchor += m.e;
            } else {
                self.report.e_skirt += m.e;
            }
            // the head does not go there: what follows starts with a travel
            self.pending.get_or_insert(Pending {
                f: m.f,
                unretract: 0.0,
                unretract_f: m.f,
            });
            return Ok(());
        }
        let (start, n0) = self.map_point(kind, m.from);
        self.travel_to(start, n0, relative);
        match kind {
            Kind::Flat => {
                self.report.e_skirt += m.e;
                let (end, n1) = self.map_point(kind, m.to);
                let e = m.e * self.opts.flow.at(end.z);
                // a skirt found by geometry (no ;TYPE:) is named as such in the toolpath
                let feature = if m.feature.is_object() {
                    Feature::Skirt
                } else {
                    m.feature
                };
                self.write_extrusion(end, n1, e, m, feature, relative, false);
            }
            Kind::Object => self.object_piece(m, relative),
            Kind::Dropped => {}
        }
        Ok(())
    }

    fn object_piece(&mut self, m: &Move, relative: bool) {
        let (from, to) = (m.from, m.to);
        let p0 = self.to_model(from);
        let mut stack = std::mem::take(&mut self.stack);
        let mut pieces = std::mem::take(&mut self.pieces);
        pieces.clear();
        {
            let map = |t: f64| self.to_model(from.lerp(to, t));
            segment::split(
                &map,
                p0,
                self.opts.tolerance,
                self.opts.max_segment,
                &mut stack,
                &mut pieces,
            );
        }
        if pieces.len() > 1 {
            self.report.moves_split += 1;
        }
        let h = self.job.layer_height;
        let (mut t0, mut a) = (0.0, p0);
        for &(t1, b) in &pieces {
            let mid = (a + b) * 0.5;
            let det = self.warp.jacobian_det(mid);
            let mut e = m.e * (t1 - t0) / det * self.opts.flow.at(mid.z.max(0.0));
            if b.z < 0.0 {
                self.report.clamped_points += 1;
                e *= ((h + b.z) / h).clamp(0.0, 1.0);
            }
            let n = self.warp.tool_axis(b);
            let out = self.model_to_output(DVec3::new(b.x, b.y, b.z.max(0.0)));
            self.write_extrusion(out, n, e, m, m.feature, relative, true);
            t0 = t1;
            a = b;
        }
        self.stack = stack;
        self.pieces = pieces;
    }

    fn write_e_only(&mut self, e: f64, f: f64, relative: bool) {
        let (p, n) = self.cur.unwrap_or((DVec3::ZERO, DVec3::Z));
        self.emit_point(
            ToolPoint {
                p,
                n,
                e,
                f,
                layer: 0,
                feature: Feature::Unknown,
                travel: true,
            },
            relative,
        );
    }

    #[allow(clippy::too_many_arguments)]
    fn write_extrusion(
        &mut self,
        p: DVec3,
        n: DVec3,
        e: f64,
        m: &Move,
        feature: Feature,
        relative: bool,
        object: bool,
    ) {
        self.report.e_out += e;
        self.report.segments_out += 1;
        if object && n.z < self.min_nz {
            // the angle itself is taken once, at the end (acos is monotonic)
            self.min_nz = n.z;
        }
        if let Some((a, _)) = self.cur {
            self.grid.mark_segment(a, p);
        }
        self.emit_point(
            ToolPoint {
                p,
                n,
                e,
                f: m.f,
                layer: m.layer,
                feature,
                travel: false,
            },
            relative,
        );
    }

    fn write_travel(&mut self, p: DVec3, n: DVec3, f: f64) {
        self.emit_point(
            ToolPoint {
                p,
                n,
                e: 0.0,
                f,
                layer: 0,
                feature: Feature::Unknown,
                travel: true,
            },
            true,
        );
    }

    /// Go to `target` (output frame) if not there: straight, or retract–lift–move–descend.
    fn travel_to(&mut self, target: DVec3, n: DVec3, relative: bool) {
        let pending = self.pending.take();
        let Some((cur, cur_n)) = self.cur else {
            self.write_travel(target, n, pending.map_or(DEFAULT_TRAVEL_FEED, |p| p.f));
            return;
        };
        let f = pending.map_or(DEFAULT_TRAVEL_FEED, |p| p.f);
        if (target - cur).length() > LENGTH_EPSILON {
            match travel::plan(&self.grid, cur, target, self.opts.travel_clearance) {
                travel::TravelPlan::Direct => self.write_travel(target, n, f),
                travel::TravelPlan::Lift(z) => {
                    self.report.lifts += 1;
                    let add = self.retracted <= LENGTH_EPSILON && self.opts.retract_length > 0.0;
                    if add {
                        self.report.retracts_added += 1;
                        self.write_e_only(-self.opts.retract_length, RETRACT_FEED, relative);
                    }
                    self.write_travel(DVec3::new(cur.x, cur.y, z), cur_n, f);
                    self.write_travel(DVec3::new(target.x, target.y, z), n, f);
                    self.write_travel(target, n, f);
                    if add {
                        self.write_e_only(self.opts.retract_length, RETRACT_FEED, relative);
                    }
                }
            }
        }
        if let Some(p) = pending {
            if p.unretract > 0.0 {
                self.retracted = (self.retracted - p.unretract).max(0.0);
                self.write_e_only(p.unretract, p.unretract_f, relative);
            }
        }
    }

    /// Leave the region: lift clear of the part and re-synchronise absolute E.
    fn end_region(&mut self) {
        self.done_region = true;
        if let Some(p) = self.pending.take() {
            if p.unretract > 0.0 {
                // the slicer pushed filament back at the end of a travel that leads out of the
                // region: keep it, in place
                self.write_e_only(p.unretract, p.unretract_f, true);
            }
        }
        if let Some((cur, n)) = self.cur {
            let (_, top) = self.grid.clearance_needed(cur, cur);
            let z = top.max(cur.z) + self.opts.travel_clearance;
            if z > cur.z {
                self.write_travel(DVec3::new(cur.x, cur.y, z), n, DEFAULT_TRAVEL_FEED);
            }
        }
        if self.emit_error.is_none() {
            let r = self.counted(|c| c.emit.end_region(&mut c.out));
            self.keep_error(r);
        }
        if !self.e_relative && (self.emit.current_e() - self.slicer_e).abs() > extrusion::E_QUANTUM
        {
            let line = format!(
                "G92 E{} ; warpslice: back to the slicer's E",
                fmt_e(self.slicer_e)
            );
            self.passthrough(line.as_bytes());
            self.emit.reset_e(self.slicer_e);
        }
    }
}

/// Largest distance between a cylindrical job's layer axis and a lathe's mandrel axis, mm.
pub const MANDREL_AXIS_TOLERANCE: f64 = 0.01;

/// A cylindrical job on a `lathe-a` machine: the warp's axis (model frame, moved to the output
/// by `model_to_output`) must be the mandrel's, or the layers are wound round the wrong line.
fn mandrel_check(
    job: &Job,
    machine: Option<&MachineSpec>,
    m2o: [f64; 3],
) -> Result<(), UnwarpError> {
    use crate::machine::spec::Kinematics;
    use crate::warp::WarpSpec;
    let (Some(spec), WarpSpec::Cylindrical { axis, .. }) = (machine, &job.warp.spec) else {
        return Ok(());
    };
    let Kinematics::LatheA(lathe) = &spec.kinematics else {
        return Ok(());
    };
    let warp = [axis[0] + m2o[1], axis[1] + m2o[2]];
    let mandrel = [lathe.axis_y_mm, lathe.axis_z_mm];
    if (warp[0] - mandrel[0]).hypot(warp[1] - mandrel[1]) > MANDREL_AXIS_TOLERANCE {
        return Err(UnwarpError::MandrelMismatch {
            machine: spec.name.clone(),
            warp,
            mandrel,
        });
    }
    Ok(())
}

/// Where the head was before `line` (its first move's start, or the state's position).
fn state_position_before(line: &Line<'_>, state: &State) -> DVec3 {
    line.moves.first().map_or(state.position, |m| m.from)
}

/// Full precision (shortest round-trip), `-0` written as `0`.
fn fmt(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v}")
    }
}

fn fmt_e(v: f64) -> String {
    let mut b = Vec::new();
    push_e(&mut b, v);
    String::from_utf8(b).unwrap_or_default()
}
