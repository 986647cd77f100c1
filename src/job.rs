//! The job file: everything `unwarp` needs to map a slicer's G-code back.
//!
//! `warp` writes it next to the warped STL (`WARPED.job.json`); the same job drives `unwarp`
//! and is echoed on one line into every output G-code. Its `hash` (FNV-1a 64 over the
//! canonical JSON of every other field, 16 hex digits) is also written into the warped STL's
//! 80-byte header, so a warped STL is recognisable.

use serde::{Deserialize, Serialize};

use crate::mesh::Aabb;
use crate::warp::WarpParams;

/// Version of the job format; bumped when a field changes meaning.
pub const JOB_FORMAT: u32 = 1;

/// A warp job (all lengths mm).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Job {
    /// `warpslice` version that wrote the job.
    pub version: String,
    /// Job format ([`JOB_FORMAT`]).
    pub format: u32,
    /// Warp kind and parameters (resolved: the curved warp's width is filled in).
    pub warp: WarpParams,
    /// input frame + this = model frame (centre of the XY bbox at 0, lowest point at z = 0).
    pub input_to_model: [f64; 3],
    /// Model-frame bounding box of the input mesh.
    pub model_bbox: Aabb,
    /// STL z = T_z + `stl_z_offset`: the warped STL is lifted so that its lowest point (the
    /// anchor's underside when there is one) is at z = 0. x and y are not moved.
    pub stl_z_offset: f64,
    /// Bounding box of the warped part in STL coordinates (anchor excluded).
    pub warped_bbox: Aabb,
    /// Intended layer height (and anchor thickness), mm: the slicer's vertical layer height.
    pub layer_height: f64,
    /// With `--layer-thickness`: the layer thickness along the tool axis asked, mm
    /// ([`crate::warp::thickness`]; `layer_height` was computed from it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer_thickness: Option<f64>,
    /// With `--layer-thickness`: the tilt where that thickness holds, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness_at_tilt_deg: Option<f64>,
    /// Thickness of the removable anchor slab under the warped part, or `None` if the warped
    /// bottom is flat and needs none. The slicer's first layer holds only the anchor (and
    /// skirt/brim); unwarp drops the anchor's extrusions.
    pub anchor: Option<f64>,
    /// Subdivision: longest edge left unsplit before warping, mm.
    pub max_edge: f64,
    /// Subdivision: largest distance between a warped edge's chord and its warped midpoint, mm.
    pub tolerance: f64,
    /// What the subdivision achieved when a runaway guard stopped it before `max_edge` and
    /// `tolerance` held (absent: both hold).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subdivision_achieved: Option<crate::mesh::achieved::Achieved>,
    /// FNV-1a 64 of the input STL bytes, 16 hex digits.
    pub input_hash: String,
    /// FNV-1a 64 of this job's canonical JSON with `hash` empty, 16 hex digits.
    pub hash: String,
}

/// Why a job file cannot be used.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum JobError {
    /// Not valid job JSON (serde's message with line and column).
    Parse {
        /// serde_json's message, with the line and column of the problem.
        message: String,
    },
    /// The format is newer or older than this warpslice reads.
    Format {
        /// The `format` the job file holds.
        found: u32,
        /// The format this warpslice reads ([`JOB_FORMAT`]).
        expected: u32,
    },
    /// The warped STL given with the job is not the one written with it (its header names
    /// another job, or none).
    StlMismatch {
        /// What the STL's header says.
        header: String,
        /// This job's hash.
        job: String,
    },
    /// The hash does not match the content (the file was edited or damaged).
    Hash {
        /// The `hash` the job file holds (16 hex digits).
        found: String,
        /// The hash computed from the file's content (16 hex digits).
        computed: String,
    },
}

impl std::fmt::Display for JobError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            JobError::Parse { message } => write!(f, "the job file is not valid: {message}"),
            JobError::Format { found, expected } => write!(
                f,
                "the job file has format {found}, this warpslice reads format {expected}: warp the model again"
            ),
            JobError::StlMismatch { header, job } => write!(
                f,
                "the warped STL is not the one written with this job (its header says '{header}', the job is {job}): give the .stl that `warp` wrote next to this job file"
            ),
            JobError::Hash { found, computed } => write!(
                f,
                "the job file's hash {found} does not match its content ({computed}): it was edited or damaged; warp the model again"
            ),
        }
    }
}

impl std::error::Error for JobError {}

crate::error_codes!(JobError, ERROR_CODES, "job" {
    Parse => "job.parse", "the job file is not valid JSON of a job";
    Format => "job.format", "the job file's format is not the one this version reads";
    Hash => "job.hash", "the job file was edited or damaged";
    StlMismatch => "job.stl-mismatch", "the warped STL given is not this job's";
} wraps {});

impl Job {
    /// Compute and store the hash.
    pub fn seal(&mut self) {
        self.hash = self.compute_hash();
    }

    /// FNV-1a 64 of the canonical JSON with an empty hash field.
    pub fn compute_hash(&self) -> String {
        let mut copy = self.clone();
        copy.hash = String::new();
        let json = serde_json::to_string(&copy).unwrap_or_default();
        format!("{:016x}", fnv1a64(json.as_bytes()))
    }

    /// One line of JSON (for the output header).
    pub fn to_json_line(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }

    /// Pretty JSON (for the job file).
    pub fn to_json_pretty(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }

    /// Parse and check a job file.
    pub fn from_bytes(bytes: &[u8]) -> Result<Job, JobError> {
        match std::str::from_utf8(bytes) {
            Ok(text) => Job::from_json(text),
            Err(e) => Err(JobError::Parse {
                message: format!(
                    "it is not text (byte {} is not UTF-8: a binary file, e.g. the STL or an image?); give the .job.json that `warp` wrote next to the warped STL",
                    e.valid_up_to() + 1
                ),
            }),
        }
    }

    /// A job from its JSON text (see [`Job::from_bytes`]).
    pub fn from_json(text: &str) -> Result<Job, JobError> {
        let job: Job = serde_json::from_str(text).map_err(|e| JobError::Parse {
            message: e.to_string(),
        })?;
        if job.format != JOB_FORMAT {
            return Err(JobError::Format {
                found: job.format,
                expected: JOB_FORMAT,
            });
        }
        let computed = job.compute_hash();
        if computed != job.hash {
            return Err(JobError::Hash {
                found: job.hash.clone(),
                computed,
            });
        }
        Ok(job)
    }
}

/// FNV-1a, 64 bit.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}
