//! The steps on files (native only): what the CLI runs, and tests and benches with it.
//!
//! - [`warp_file`]: read an STL, warp it, write the warped STL and its job next to it
//!   (`part.warped.stl` + `part.warped.job.json`).
//! - [`unwarp_file`]: the two-pass streaming unwarp of a G-code file into an output file
//!   ([`super::unwarp_stream`]: memory bounded whatever the file's size).
//! - [`run`]: warp, slice with a real slicer ([`crate::slicer`]), unwarp; the intermediate files
//!   sit next to the output ([`RunFiles`]).
//! - [`run_with`]: the same with a real slicer or the built-in one ([`crate::planar`]).
//!
//! The caller sees each step through [`Observer`] (the CLI prints reports and a progress bar);
//! every I/O error names its file.

use std::path::{Path, PathBuf};

use super::{unwarp_stream, warp_model, Error, UnwarpSettings, WarpOptions, WarpOutput};
use crate::job::Job;
use crate::slicer::{SliceOptions, SliceReport};
use crate::unwarp::UnwarpReport;

/// What a caller wants to know while the steps run. Every method has a default that ignores it.
pub trait Observer {
    /// A step starts (`"warping"`, `"slicing"`, `"unwarping"`); `bytes` is the unwarp's total
    /// of bytes to read (both passes), 0 for the others.
    fn start(&mut self, _step: &str, _bytes: u64) {}
    /// The unwarp read `n` more bytes.
    fn advance(&mut self, _n: u64) {}
    /// The step that started last is over.
    fn finish(&mut self) {}
    /// The warp step wrote `stl` and `job`.
    fn warped(&mut self, _model: &Path, _out: &WarpOutput, _stl: &Path, _job: &Path) {}
    /// The slicer wrote `gcode`.
    fn sliced(&mut self, _stl: &Path, _gcode: &Path, _report: &SliceReport) {}
    /// The built-in slicer wrote `gcode`.
    fn sliced_builtin(&mut self, _stl: &Path, _gcode: &Path, _report: &crate::planar::SliceReport) {
    }
    /// The unwarp wrote `output`.
    fn unwarped(&mut self, _report: &UnwarpReport, _output: &Path) {}
}

/// An observer that ignores everything.
impl Observer for () {}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::Io {
        what: path.display().to_string(),
        message: e.to_string(),
    }
}

/// The job file that goes with a warped STL: `x.stl` → `x.job.json`.
pub fn job_path(stl: &Path) -> PathBuf {
    stl.with_extension("job.json")
}

/// The warped STL beside a job file (`x.job.json` → `x.stl`, as `warp` writes them) when it is
/// there and is this job's (its header names the job's hash): unwarp registers against it.
pub fn stl_beside(job_file: &Path, job: &Job) -> Option<PathBuf> {
    let name = job_file.file_name()?.to_str()?;
    let stem = name.strip_suffix(".job.json")?;
    let stl = job_file.with_file_name(format!("{stem}.stl"));
    let mut head = [0u8; 80];
    let mut f = std::fs::File::open(&stl).ok()?;
    std::io::Read::read_exact(&mut f, &mut head).ok()?;
    let head = String::from_utf8_lossy(&head);
    head.contains(&format!("warpslice job {}", job.hash))
        .then_some(stl)
}

/// Read a job file.
pub fn read_job(path: &Path) -> Result<Job, Error> {
    let bytes = std::fs::read(path).map_err(io(path))?;
    Ok(Job::from_bytes(&bytes)?)
}

/// An error's text with the file it concerns in front (I/O errors name theirs already).
pub fn in_file(path: &Path, e: &Error) -> String {
    match e {
        Error::Io { .. } => e.to_string(),
        _ => format!("{}: {e}", path.display()),
    }
}

/// Warp `model` into `output` (binary STL) and its job ([`job_path`]).
pub fn warp_file(
    model: &Path,
    opts: &WarpOptions,
    output: &Path,
    observer: &mut dyn Observer,
) -> Result<WarpOutput, Error> {
    let bytes = std::fs::read(model).map_err(io(model))?;
    observer.start("warping", 0);
    let out = warp_model(&bytes, opts)?;
    observer.finish();
    std::fs::write(output, &out.stl).map_err(io(output))?;
    let job = job_path(output);
    std::fs::write(&job, out.job.to_json_pretty()).map_err(io(&job))?;
    observer.warped(model, &out, output, &job);
    Ok(out)
}

/// Unwarp the G-code file `gcode` (sliced from `job`'s warped STL) into `output`; with the
/// warped STL `stl`, registered to the bead against it.
pub fn unwarp_file(
    gcode: &Path,
    job: &Job,
    settings: &UnwarpSettings,
    stl: Option<&Path>,
    output: &Path,
    observer: &mut dyn Observer,
) -> Result<UnwarpReport, Error> {
    let stl_bytes = match stl {
        Some(p) => Some(std::fs::read(p).map_err(io(p))?),
        None => None,
    };
    let len = std::fs::metadata(gcode).map_err(io(gcode))?.len();
    // written beside the output and renamed when complete: a refused or failed unwarp leaves
    // no (partial or empty) G-code under the output's name
    let partial = std::path::PathBuf::from(format!("{}.partial", output.display()));
    let file = std::fs::File::create(&partial).map_err(io(&partial))?;
    let mut out = std::io::BufWriter::new(file);
    observer.start("unwarping", 2 * len);
    let report = {
        let mut advance = |n: u64| observer.advance(n);
        unwarp_stream(
            job,
            settings,
            stl_bytes.as_deref(),
            &gcode.display().to_string(),
            || std::fs::File::open(gcode),
            &mut out,
            &mut advance,
        )
    };
    observer.finish();
    let done = report.and_then(|r| {
        out.into_inner()
            .map_err(|e| e.into_error())
            .and_then(|f| f.sync_all())
            .map_err(io(&partial))?;
        std::fs::rename(&partial, output).map_err(io(output))?;
        Ok(r)
    });
    let report = done.inspect_err(|_| {
        let _ = std::fs::remove_file(&partial);
    })?;
    observer.unwarped(&report, output);
    Ok(report)
}

/// The intermediate files of [`run`], next to the output.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunFiles {
    /// The warped STL (`out.warped.stl`); its job is [`job_path`] of it.
    pub warped: PathBuf,
    /// The slicer's G-code (`out.sliced.gcode`).
    pub sliced: PathBuf,
}

impl RunFiles {
    /// The files next to `output`.
    pub fn next_to(output: &Path) -> RunFiles {
        RunFiles {
            warped: output.with_extension("warped.stl"),
            sliced: output.with_extension("sliced.gcode"),
        }
    }
}

/// Which planar slicer [`run_with`] slices the warped STL with.
#[derive(Clone, Copy, Debug)]
pub enum SliceWith<'a> {
    /// A real slicer installed here ([`crate::slicer`]); its layer height is set to the warp's.
    Real(&'a SliceOptions),
    /// The built-in slicer ([`crate::planar`]); its layer heights must be the warp's
    /// ([`super::slice_builtin`]).
    Builtin(&'a crate::planar::Settings),
}

/// What [`run_with`]'s slicer reported.
enum Sliced {
    Real(SliceReport),
    Builtin(crate::planar::SliceReport),
}

/// Warp `model`, slice the warped STL with the real slicer `slice` (its layer height is the
/// warp's), unwarp into `output`.
pub fn run(
    model: &Path,
    warp: &WarpOptions,
    slice: &SliceOptions,
    settings: &UnwarpSettings,
    output: &Path,
    observer: &mut dyn Observer,
) -> Result<UnwarpReport, Error> {
    run_with(
        model,
        warp,
        SliceWith::Real(slice),
        settings,
        output,
        observer,
    )
}

/// Warp `model`, slice the warped STL with `slice` into [`RunFiles::sliced`], unwarp into
/// `output`.
pub fn run_with(
    model: &Path,
    warp: &WarpOptions,
    slice: SliceWith<'_>,
    settings: &UnwarpSettings,
    output: &Path,
    observer: &mut dyn Observer,
) -> Result<UnwarpReport, Error> {
    let files = RunFiles::next_to(output);
    let w = warp_file(model, warp, &files.warped, observer)?;
    observer.start("slicing", 0);
    let sliced = match slice {
        SliceWith::Real(opts) => {
            // the job's: computed from --layer-thickness when given
            let opts = SliceOptions {
                layer_height: w.job.layer_height,
                ..opts.clone()
            };
            crate::slicer::slice(&files.warped, &files.sliced, &opts)
                .map(Sliced::Real)
                .map_err(Error::from)
        }
        SliceWith::Builtin(s) => {
            // --layer-thickness computed the layers' height: the slice's layers are the job's
            let mut s = *s;
            if warp.layer_thickness.is_some() {
                s.layer_height = w.job.layer_height;
                s.first_layer_height = w.job.layer_height;
            }
            super::slice_builtin(&w.stl, &w.job, &s)
        }
        .and_then(|out| {
            std::fs::write(&files.sliced, &out.gcode).map_err(io(&files.sliced))?;
            Ok(Sliced::Builtin(out.report))
        }),
    };
    observer.finish();
    match sliced? {
        Sliced::Real(r) => observer.sliced(&files.warped, &files.sliced, &r),
        Sliced::Builtin(r) => observer.sliced_builtin(&files.warped, &files.sliced, &r),
    }
    unwarp_file(
        &files.sliced,
        &w.job,
        settings,
        Some(&files.warped),
        output,
        observer,
    )
}
