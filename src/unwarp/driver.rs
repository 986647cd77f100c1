//! The streaming driver: two passes over the same bytes.

use glam::DVec3;

use super::core::Core;
use super::{travel, UnwarpError, UnwarpOptions, UnwarpReport};
use crate::emit::Emitter;
use crate::gcode::{ReadOptions, Reader};
use crate::job::Job;
use crate::mesh::Mesh;
use crate::register::{Registration, Scanner};
use crate::toolpath::{Thinning, ToolPoint};

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
    /// The warped mesh of this job, for the fine registration.
    warped_mesh: Option<Mesh>,
}

impl Unwarper {
    /// Start an unwarp of a G-code sliced from `job`'s warped STL; `emitter` writes the
    /// output (3-axis or a machine's axes; see [`crate::pipeline`]).
    pub fn new(
        job: &Job,
        opts: &UnwarpOptions,
        emitter: Box<dyn Emitter>,
    ) -> Result<Unwarper, UnwarpError> {
        opts.validate_for(job)?;
        // build once to validate the job's warp
        job.warp.clone().build(&job.model_bbox)?;
        Ok(Unwarper {
            emitter: Some(emitter),
            job: job.clone(),
            opts: opts.clone(),
            scanner: Some(Scanner::new(job)),
            reader: Reader::new(ReadOptions::default()),
            core: None,
            finished: false,
            warped_mesh: None,
        })
    }

    /// Register against the warped mesh of this job (its STL, as written by the warp step),
    /// to the bead instead of by bounding boxes: see [`crate::register::refine`]. Call before
    /// [`Unwarper::end_scan`].
    pub fn set_warped_mesh(&mut self, mesh: Mesh) {
        self.warped_mesh = Some(mesh);
    }

    /// Both passes over a whole G-code in memory.
    pub fn run(mut self, gcode: &[u8]) -> Result<super::UnwarpOutput, UnwarpError> {
        self.scan(gcode)?;
        let registration = self.end_scan()?;
        self.push(gcode)?;
        let report = self.finish()?;
        Ok(super::UnwarpOutput {
            gcode: self.take_output(),
            report,
            registration,
            toolpath: self.take_toolpath(),
        })
    }

    /// Pass 1: feed a chunk.
    pub fn scan(&mut self, chunk: &[u8]) -> Result<(), UnwarpError> {
        match self.scanner.as_mut() {
            Some(s) => Ok(s.push(chunk)?),
            None => Err(UnwarpError::Order {
                expected: "scan before end_scan",
            }),
        }
    }

    /// End of pass 1: registration. Writes the output header.
    pub fn end_scan(&mut self) -> Result<Registration, UnwarpError> {
        let scanner = self
            .scanner
            .take()
            .ok_or(UnwarpError::Order { expected: "scan" })?;
        let reg =
            scanner.finish_with_mesh(&self.job, self.opts.offset, self.warped_mesh.as_ref())?;
        // the shape check compares the extrusions with the mesh's cross-sections too
        let mesh = self.warped_mesh.take();
        let mut params = self.job.warp.clone();
        let warp = params.build(&self.job.model_bbox)?;
        let [dx, dy, _] = reg.translation;
        let shift = match self.opts.place {
            Some([px, py]) if px.is_finite() && py.is_finite() => DVec3::new(px - dx, py - dy, 0.0),
            Some(place) => return Err(UnwarpError::BadPlace { place }),
            None => DVec3::ZERO,
        };
        let model_to_output = DVec3::new(dx + shift.x, dy + shift.y, self.opts.z_offset);
        let mut emit = self.emitter.take().ok_or(UnwarpError::Order {
            expected: "end_scan only once:",
        })?;
        emit.check_job(&self.job, model_to_output)
            .map_err(|error| UnwarpError::Emit { line: None, error })?;
        // the travel planner's grid covers everything printed (the object, and a skirt, brim or
        // wipe tower beside it: issue 12 item 4)
        let mut b = reg.gcode_bbox;
        if !reg.printed_bbox.is_empty() {
            b.include(reg.printed_bbox.min);
            b.include(reg.printed_bbox.max);
        }
        let head = emit.head_profile();
        let mut core = Core {
            job: self.job.clone(),
            warp,
            opts: self.opts.clone(),
            reg: reg.clone(),
            dx,
            dy,
            shift,
            out: Vec::with_capacity(1 << 16),
            emit,
            emit_error: None,
            shape: super::shape::ShapeCheck::new(mesh.as_ref()),
            slicer_e: 0.0,
            cur: None,
            pending: None,
            held: Vec::new(),
            held_bytes: Vec::new(),
            lost: None,
            fw_retracted: false,
            printed_top: f64::NEG_INFINITY,
            retracted: 0.0,
            grid: travel::HeightGrid::new((b.min + shift).truncate(), (b.max + shift).truncate()),
            head,
            inside: false,
            done_region: false,
            min_nz: 1.0,
            e_relative: false,
            report: UnwarpReport {
                translation: reg.translation,
                residual: reg.residual,
                fit: reg.fit,
                model_to_output: model_to_output.to_array(),
                warnings: UnwarpReport::end_warnings(&reg),
                skirt: if self.opts.drop_skirt {
                    "dropped".into()
                } else {
                    "flat".into()
                },
                ..UnwarpReport::default()
            },
            toolpath: Vec::new(),
            thinning: Thinning::new(self.opts.toolpath_every),
            stack: Vec::new(),
            pieces: Vec::new(),
            convert_outside: false,
            known: [false; 3],
            outside_pose: None,
            keep: [false; 3],
        };
        let moved = shift != DVec3::ZERO || self.opts.z_offset != 0.0;
        core.convert_outside = core.emit.converts_outside(moved);
        core.header();
        self.core = Some(core);
        // pass 2 expands arcs only inside the region: the lines outside pass through verbatim
        self.reader = Reader::new(ReadOptions {
            arcs_in: Some(reg.region),
            ..ReadOptions::default()
        });
        Ok(reg)
    }

    /// Pass 2: feed a chunk (the same bytes again, from the start).
    pub fn push(&mut self, chunk: &[u8]) -> Result<(), UnwarpError> {
        let core = self.core.as_mut().ok_or(UnwarpError::Order {
            expected: "end_scan",
        })?;
        self.reader
            .push::<UnwarpError>(chunk, &mut |l, s| core.line(&l, s))
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

    /// The input line of output line `line` (1-based), where the emitter records them
    /// ([`crate::emit::Emitter::input_line_of`]).
    pub fn input_line_of(&self, line: u64) -> Option<u64> {
        self.core.as_ref()?.emit.input_line_of(line)
    }

    /// No later [`Unwarper::input_line_of`] asks for an output line before `line`.
    pub fn forget_input_lines_before(&mut self, line: u64) {
        if let Some(c) = self.core.as_mut() {
            c.emit.forget_input_lines_before(line);
        }
    }

    /// Drain the toolpath collected so far (`collect_toolpath`).
    pub fn take_toolpath(&mut self) -> Vec<ToolPoint> {
        self.core
            .as_mut()
            .map(|c| std::mem::take(&mut c.toolpath))
            .unwrap_or_default()
    }

    /// End of pass 2; drain the output after this.
    pub fn finish(&mut self) -> Result<UnwarpReport, UnwarpError> {
        if self.finished {
            return Err(UnwarpError::Order {
                expected: "finish only once:",
            });
        }
        let core = self.core.as_mut().ok_or(UnwarpError::Order {
            expected: "end_scan",
        })?;
        self.reader
            .finish::<UnwarpError>(&mut |l, s| core.line(&l, s))?;
        if core.inside && !core.done_region {
            core.end_region();
        }
        let err = core.emit_error.take();
        core.report.largest_tilt_deg =
            crate::num::deg(crate::num::acos(core.min_nz.clamp(-1.0, 1.0)));
        if let Some(e) = err {
            return Err(e);
        }
        core.report.shape_margin_mm = core.shape.margin().unwrap_or(0.0);
        core.report.shape_outliers = core.shape.beyond;
        core.report.shape_section_margin_mm = core.shape.section_margin;
        if let Some((finding, beyond)) = core.shape.verdict() {
            return Err(UnwarpError::ShapeMismatch { finding, beyond });
        }
        core.counted(|c| c.emit.finish(&mut c.out));
        core.report.machine = core.emit.machine_report();
        if let Some(w) = core
            .report
            .machine
            .as_ref()
            .and_then(UnwarpReport::dropped_tilt_warning)
        {
            core.report.warnings.push(w);
        }
        self.finished = true;
        Ok(core.report.clone())
    }
}
