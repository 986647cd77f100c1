//! [`CheckedUnwarper`]: the streaming unwarp whose output goes through the collision check as
//! it is produced. Every way of unwarping a machine G-code (the one-shot [`super::unwarp`],
//! the file stream [`super::unwarp_stream`] and the browser's `UnwarpStream`) goes through it,
//! so this file alone decides whether the check runs (the walker), what its findings do (the
//! verdict: refuse with `machine.collision`, or list them) and how the file ends (the tail: the
//! finding comments, or the "NOT RUN" note).
//!
//! The walker ([`crate::collision::Walker`]) reads the output line by line whatever the chunks
//! it is fed in, so a streamed output is judged as the whole file is: the same findings, the
//! same refusal, the same bytes.

use super::unwarp_step::{unwarper_with_stl, UnwarpSettings};
use super::Error;
use crate::collision::Walker;
use crate::emit::CollisionFinding;
use crate::job::Job;
use crate::machine::MachineError;
use crate::mesh::Mesh;
use crate::register::Registration;
use crate::toolpath::ToolPoint;
use crate::unwarp::{UnwarpReport, Unwarper};

/// The streaming unwarp of [`Unwarper`] with the collision check on its output: `scan` every
/// chunk, `end_scan`, `push` every chunk again draining [`CheckedUnwarper::take_output`], then
/// `finish` and drain once more. The output handed out before `finish` has been walked; the
/// verdict comes at `finish` (a refusal leaves what was handed out a partial file: the caller
/// drops it).
pub struct CheckedUnwarper {
    inner: Unwarper,
    /// `allow_collisions`: findings are listed, not refused.
    allow: bool,
    /// The machine's name (the refusal's; empty for 3-axis output, which has no check).
    machine: String,
    /// The walker while the check runs; taken by `finish`.
    walker: Option<Walker>,
    /// The check could not run (the machine it cannot judge): the report's warnings.
    unsupported: Vec<String>,
    /// The file's last comment when a machine output is not checked (`check_collisions`
    /// off, or a machine the check cannot judge).
    note: Option<String>,
    /// Output walked and not yet taken.
    out: Vec<u8>,
    /// The walker's findings whose input line is filled in.
    resolved: usize,
}

impl std::fmt::Debug for CheckedUnwarper {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CheckedUnwarper")
            .field("machine", &self.machine)
            .field("checked", &self.walker.is_some())
            .finish()
    }
}

impl CheckedUnwarper {
    /// The unwarp for `settings` ([`super::unwarper`]), registered to the bead against the job's
    /// warped STL when it is given, with the collision check its machine options ask for.
    pub fn new(
        job: &Job,
        settings: &UnwarpSettings,
        stl: Option<&[u8]>,
    ) -> Result<CheckedUnwarper, Error> {
        let inner = unwarper_with_stl(job, settings, stl)?;
        let mut unsupported = Vec::new();
        let walker = walker(settings, &mut unsupported)?;
        let note = match (&settings.output.machine, &walker) {
            (Some(_), None) => Some(unchecked_note(&unsupported)),
            _ => None,
        };
        Ok(CheckedUnwarper {
            inner,
            allow: settings.output.allow_collisions,
            machine: settings
                .output
                .machine
                .as_ref()
                .map(|m| m.name.clone())
                .unwrap_or_default(),
            walker,
            unsupported,
            note,
            out: Vec::new(),
            resolved: 0,
        })
    }

    /// Register to the bead against the job's warped mesh ([`Unwarper::set_warped_mesh`]);
    /// before `end_scan`.
    pub fn set_warped_mesh(&mut self, mesh: Mesh) {
        self.inner.set_warped_mesh(mesh);
    }

    /// Pass 1: a chunk of the G-code.
    pub fn scan(&mut self, chunk: &[u8]) -> Result<(), Error> {
        Ok(self.inner.scan(chunk)?)
    }

    /// End of pass 1: the registration.
    pub fn end_scan(&mut self) -> Result<Registration, Error> {
        Ok(self.inner.end_scan()?)
    }

    /// Pass 2: the same chunk again; its output goes through the walker.
    pub fn push(&mut self, chunk: &[u8]) -> Result<(), Error> {
        self.inner.push(chunk)?;
        self.walk_output()
    }

    /// The output so far (drains it).
    pub fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.out)
    }

    /// The input line of output line `line` while the unwarp still holds it: a line not yet
    /// walked by the check. The walked lines' are forgotten once their findings have them, so
    /// the record stays the size of a chunk, not of the file (105 MB of G-code on pax-5axis:
    /// 239 → 63 MB peak, README "Speed and memory").
    pub fn input_line_of(&self, line: u64) -> Option<u64> {
        self.inner.input_line_of(line)
    }

    /// The toolpath collected so far (drains it; `collect_toolpath`).
    pub fn take_toolpath(&mut self) -> Vec<ToolPoint> {
        self.inner.take_toolpath()
    }

    /// End of pass 2: the last output walked, then the verdict — refused with
    /// `machine.collision` (the first finding, its input line named) unless `allow_collisions`;
    /// otherwise every finding is a comment at the end of the file and in the report's
    /// `machine.collisions`. Without the check, the file's last comment says it did not run.
    /// Drain [`CheckedUnwarper::take_output`] once more after it.
    pub fn finish(&mut self) -> Result<UnwarpReport, Error> {
        let mut report = self.inner.finish()?;
        self.walk_output()?;
        match self.walker.take() {
            Some(w) => {
                let (mut findings, _) = w.finish()?;
                // the last line, read by `finish`, may have found more
                name_input_lines(&self.inner, &mut findings[self.resolved..]);
                self.verdict(findings, &mut report)?;
            }
            None => {
                if let Some(note) = self.note.take() {
                    self.out.extend_from_slice(note.as_bytes());
                }
            }
        }
        report.warnings.append(&mut self.unsupported);
        Ok(report)
    }

    /// The unwarper's new output through the walker, kept for `take_output`.
    fn walk_output(&mut self) -> Result<(), Error> {
        let chunk = self.inner.take_output();
        if let Some(w) = self.walker.as_mut() {
            w.push(&chunk)?;
            // each new finding's input line now, while the emitter still holds it; a later
            // finding is on a line not yet read whole, so the emitter may forget the ones
            // before it (the record stays the size of a chunk, not of the file)
            let found = w.findings_mut();
            name_input_lines(&self.inner, &mut found[self.resolved..]);
            self.resolved = found.len();
            self.inner.forget_input_lines_before(w.lines_read() + 1);
        }
        if self.out.is_empty() {
            self.out = chunk;
        } else {
            self.out.extend_from_slice(&chunk);
        }
        Ok(())
    }

    /// Refuse, or list every finding (see [`CheckedUnwarper::finish`]).
    fn verdict(
        &mut self,
        findings: Vec<CollisionFinding>,
        report: &mut UnwarpReport,
    ) -> Result<(), Error> {
        if !self.allow {
            if let Some(e) = crate::collision::refusal(&self.machine, &findings) {
                return Err(e.into());
            }
        }
        for f in &findings {
            self.out.extend_from_slice(finding_comment(f).as_bytes());
        }
        if let Some(m) = report.machine.as_mut() {
            m.collisions_checked = true;
            m.collisions = findings;
        }
        Ok(())
    }
}

/// Each finding's input line, from the unwarp's record (while it still holds the line).
fn name_input_lines(inner: &Unwarper, findings: &mut [CollisionFinding]) {
    for f in findings {
        f.input_line = inner.input_line_of(f.line);
    }
}

/// The comment listing one finding at the end of an `allow_collisions` file.
fn finding_comment(f: &CollisionFinding) -> String {
    format!(
        "; warpslice collision: line {} layer {}: {} into {} by {:.3} mm at ({:.3}, {:.3}, {:.3}){}\n",
        f.line,
        f.layer,
        f.part,
        f.obstacle,
        f.depth_mm,
        f.at[0],
        f.at[1],
        f.at[2],
        f.input_line
            .map(|l| format!(" (input line {l})"))
            .unwrap_or_default()
    )
}

/// The last comment of a machine file the collision check did not run on (the options said
/// `check_collisions: false`, or the check cannot judge the machine: `unsupported`'s warning),
/// so the file itself says that nobody checked the head's clearance.
fn unchecked_note(unsupported: &[String]) -> String {
    let why = match unsupported.first() {
        Some(w) => w.clone(),
        None => "check_collisions is false in the options".to_string(),
    };
    format!("; warpslice collision check: NOT RUN ({why}): the head's clearance was not checked\n")
}

/// The collision check's walker when it runs (a machine output with `check_collisions`, the
/// default; see [`crate::collision`]). A machine the check cannot judge (the lathe: its layers
/// are not graphs over the bed) gets no check, and `unsupported` says so (the report's
/// warnings).
fn walker(
    settings: &UnwarpSettings,
    unsupported: &mut Vec<String>,
) -> Result<Option<Walker>, Error> {
    let Some(spec) = settings.output.machine.as_ref() else {
        return Ok(None);
    };
    if !settings.output.checks_collisions() {
        return Ok(None);
    }
    match Walker::new(spec) {
        Ok(mut w) => {
            // a refusal needs only the first finding
            w.stop_at_first(!settings.output.allow_collisions);
            Ok(Some(w))
        }
        Err(MachineError::CollisionUnsupported { machine, reason }) => {
            unsupported.push(format!(
                "machine {machine}: the collision check was not run: {reason}; check the head's clearance yourself"
            ));
            Ok(None)
        }
        Err(e) => Err(e.into()),
    }
}
