//! The unwarp step: G-code and job → non-planar G-code, 3-axis or a machine's axes. The
//! machine is chosen here and handed to the unwarp as its emitter.

use serde::{Deserialize, Serialize};

use super::Error;
use crate::job::{Job, JobError};
use crate::machine::{MachineOptions, MachineSpec};
use crate::mesh::Mesh;
use crate::unwarp::{UnwarpOptions, UnwarpOutput, Unwarper};

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

/// The warped mesh of `job` from its STL bytes, checked to be this job's by the STL's header
/// (`warpslice job <hash> …`, written by [`super::warp_model`]).
pub fn warped_mesh(job: &Job, stl: &[u8]) -> Result<Mesh, Error> {
    let header: String = String::from_utf8_lossy(&stl[..stl.len().min(80)])
        .trim_end_matches('\0')
        .trim()
        .to_string();
    if !header.contains(&format!("warpslice job {}", job.hash)) {
        return Err(JobError::StlMismatch {
            header,
            job: job.hash.clone(),
        }
        .into());
    }
    Ok(crate::mesh::read_stl(stl)?.0)
}

/// [`unwarper`], registered to the bead against the warped STL when it is given
/// ([`Unwarper::set_warped_mesh`]).
pub fn unwarper_with_stl(
    job: &Job,
    settings: &UnwarpSettings,
    stl: Option<&[u8]>,
) -> Result<Unwarper, Error> {
    let mut u = unwarper(job, settings)?;
    if let Some(stl) = stl {
        u.set_warped_mesh(warped_mesh(job, stl)?);
    }
    Ok(u)
}

/// One-shot unwarp of a whole G-code in memory (see [`crate::unwarp`]).
pub fn unwarp(gcode: &[u8], job: &Job, settings: &UnwarpSettings) -> Result<UnwarpOutput, Error> {
    unwarp_with_stl(gcode, job, settings, None)
}

/// [`unwarp`], registered to the bead against the job's warped STL when it is given.
pub fn unwarp_with_stl(
    gcode: &[u8],
    job: &Job,
    settings: &UnwarpSettings,
    stl: Option<&[u8]>,
) -> Result<UnwarpOutput, Error> {
    let mut out = unwarper_with_stl(job, settings, stl)?.run(gcode)?;
    let mut unsupported = crate::unwarp::UnwarpReport::default();
    match walker(settings, &mut unsupported)? {
        Some(mut w) => {
            w.push(&out.gcode)?;
            let (findings, _) = w.finish()?;
            let spec = settings
                .output
                .machine
                .as_ref()
                .expect("a walker has a machine");
            apply_findings(settings, spec, findings, &mut out.gcode, &mut out.report)?;
        }
        None => out
            .gcode
            .extend_from_slice(unchecked_note(settings, &unsupported).as_bytes()),
    }
    out.report.warnings.extend(unsupported.warnings);
    Ok(out)
}

/// For a streamed unwarp whose caller runs the collision check on the written file itself (the
/// web worker, with `crate::check`'s code): what [`unwarp_with_stl`] adds when the check does
/// not run — the file's last comment and the report's warnings (the lathe: "not run"; the
/// options: `check_collisions: false`); nothing when the check runs.
pub fn unchecked_tail(settings: &UnwarpSettings) -> Result<(String, Vec<String>), Error> {
    let mut unsupported = crate::unwarp::UnwarpReport::default();
    Ok(match walker(settings, &mut unsupported)? {
        Some(_) => (String::new(), Vec::new()),
        None => (unchecked_note(settings, &unsupported), unsupported.warnings),
    })
}

/// The last comment of a machine file the collision check did not run on (the options said
/// `check_collisions: false`, or the check cannot judge the machine: `unsupported`'s warning),
/// so the file itself says that nobody checked the head's clearance; empty for 3-axis output.
fn unchecked_note(settings: &UnwarpSettings, unsupported: &crate::unwarp::UnwarpReport) -> String {
    if settings.output.machine.is_none() {
        return String::new();
    }
    let why = match unsupported.warnings.first() {
        Some(w) => w.clone(),
        None => "check_collisions is false in the options".to_string(),
    };
    format!("; warpslice collision check: NOT RUN ({why}): the head's clearance was not checked\n")
}

/// The collision check's walker when it runs (a machine output with `check_collisions`, the
/// default;
/// see [`crate::collision`]). A machine the check cannot judge (the lathe: its layers are not
/// graphs over the bed) gets no check, and the report says so in its warnings.
fn walker(
    settings: &UnwarpSettings,
    report: &mut crate::unwarp::UnwarpReport,
) -> Result<Option<crate::collision::Walker>, Error> {
    let Some(spec) = settings.output.machine.as_ref() else {
        return Ok(None);
    };
    if !settings.output.checks_collisions() {
        return Ok(None);
    }
    match crate::collision::Walker::new(spec) {
        Ok(mut w) => {
            // a refusal needs only the first finding
            w.stop_at_first(!settings.output.allow_collisions);
            Ok(Some(w))
        }
        Err(crate::machine::MachineError::CollisionUnsupported { machine, reason }) => {
            report.warnings.push(format!(
                "machine {machine}: the collision check was not run: {reason}; check the head's clearance yourself"
            ));
            Ok(None)
        }
        Err(e) => Err(e.into()),
    }
}

/// The collision check's verdict: refuse (`machine.collision`) unless `allow_collisions`;
/// otherwise every finding goes into the machine report and as a comment at the end of the
/// output.
fn apply_findings(
    settings: &UnwarpSettings,
    spec: &MachineSpec,
    findings: Vec<crate::emit::CollisionFinding>,
    out: &mut Vec<u8>,
    report: &mut crate::unwarp::UnwarpReport,
) -> Result<(), Error> {
    let mut findings = findings;
    if let Some(m) = report.machine.as_ref() {
        for f in &mut findings {
            f.input_line = m.input_lines.of(f.line);
        }
    }
    if !settings.output.allow_collisions {
        if let Some(e) = crate::collision::refusal(&spec.name, &findings) {
            return Err(e.into());
        }
    }
    for f in &findings {
        out.extend_from_slice(
            format!(
                "; warpslice collision: line {} layer {}: {} into {} by {:.3} mm at ({:.3}, {:.3}, {:.3}){}\n",
                f.line, f.layer, f.part, f.obstacle, f.depth_mm, f.at[0], f.at[1], f.at[2],
                f.input_line.map(|l| format!(" (input line {l})")).unwrap_or_default()
            )
            .as_bytes(),
        );
    }
    if let Some(m) = report.machine.as_mut() {
        m.collisions_checked = true;
        m.collisions = findings;
    }
    Ok(())
}

/// Read size of [`unwarp_stream`], bytes.
pub const STREAM_CHUNK: usize = 1 << 20;

/// The two-pass streaming unwarp over a source that can be read twice (a file): `open` gives
/// a fresh reader from the start, `out` takes the output as it is produced, `progress` is told
/// the bytes read (both passes count, so the total is twice the input's size). Memory stays
/// bounded by the chunk, the height grid and the longest line, whatever the file's size.
/// `name` names the source in I/O errors; `stl`, the job's warped STL, registers to the bead.
pub fn unwarp_stream<R: std::io::Read>(
    job: &Job,
    settings: &UnwarpSettings,
    stl: Option<&[u8]>,
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
    let mut u = unwarper_with_stl(job, settings, stl)?;
    let mut unsupported = crate::unwarp::UnwarpReport::default();
    let mut walker = walker(settings, &mut unsupported)?;
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
        let chunk = u.take_output();
        if let Some(w) = walker.as_mut() {
            w.push(&chunk)?;
        }
        out.write_all(&chunk).map_err(out_err)?;
        progress(n as u64);
    }
    let mut report = u.finish()?;
    let mut chunk = u.take_output();
    match (walker, settings.output.machine.as_ref()) {
        (Some(mut w), Some(spec)) => {
            w.push(&chunk)?;
            let (findings, _) = w.finish()?;
            // refused: what was written stays a partial file, the caller reports the error
            apply_findings(settings, spec, findings, &mut chunk, &mut report)?;
        }
        _ => chunk.extend_from_slice(unchecked_note(settings, &unsupported).as_bytes()),
    }
    report.warnings.extend(unsupported.warnings);
    out.write_all(&chunk).map_err(out_err)?;
    out.flush().map_err(out_err)?;
    Ok(report)
}
