//! The unwarp step: G-code and job → non-planar G-code, 3-axis or a machine's axes. The
//! machine is chosen here and handed to the unwarp as its emitter.

use serde::{Deserialize, Serialize};

use super::checked_unwarp::CheckedUnwarper;
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

/// [`unwarp`], registered to the bead against the job's warped STL when it is given. The
/// output goes through the collision check ([`CheckedUnwarper`]).
pub fn unwarp_with_stl(
    gcode: &[u8],
    job: &Job,
    settings: &UnwarpSettings,
    stl: Option<&[u8]>,
) -> Result<UnwarpOutput, Error> {
    let mut u = CheckedUnwarper::new(job, settings, stl)?;
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
    let mut u = CheckedUnwarper::new(job, settings, stl)?;
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
    // refused: what was written stays a partial file, the caller reports the error
    let report = u.finish()?;
    out.write_all(&u.take_output()).map_err(out_err)?;
    out.flush().map_err(out_err)?;
    Ok(report)
}
