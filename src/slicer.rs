//! Driving the real planar slicers installed on this machine (native only).
//! PLACEHOLDER until the infra branch lands: same API, minimal body.

use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlicerKind {
    PrusaSlicer,
    Slic3r,
    CuraEngine,
}

impl std::str::FromStr for SlicerKind {
    type Err = SlicerError;
    fn from_str(s: &str) -> Result<Self, SlicerError> {
        match s {
            "prusaslicer" => Ok(SlicerKind::PrusaSlicer),
            "slic3r" => Ok(SlicerKind::Slic3r),
            "curaengine" => Ok(SlicerKind::CuraEngine),
            _ => Err(SlicerError::Unknown(s.to_string())),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EMode {
    Relative,
    Absolute,
}

#[derive(Clone, Debug)]
pub struct SliceOptions {
    pub slicer: SlicerKind,
    pub e_mode: EMode,
    pub layer_height: f64,
    pub extra_args: Vec<String>,
}

#[derive(Clone, Debug)]
pub struct SliceReport {
    pub executable: PathBuf,
}

#[derive(Debug)]
#[non_exhaustive]
pub enum SlicerError {
    Unknown(String),
    Failed(String),
}

impl std::fmt::Display for SlicerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SlicerError::Unknown(s) => write!(f, "unknown slicer {s}"),
            SlicerError::Failed(s) => write!(f, "slicer failed: {s}"),
        }
    }
}
impl std::error::Error for SlicerError {}

pub fn slice(stl: &Path, out: &Path, opts: &SliceOptions) -> Result<SliceReport, SlicerError> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/tools/slice.sh");
    let name = match opts.slicer {
        SlicerKind::PrusaSlicer => "prusaslicer",
        SlicerKind::Slic3r => "slic3r",
        SlicerKind::CuraEngine => "curaengine",
    };
    let m = if opts.e_mode == EMode::Relative { "rel" } else { "abs" };
    let st = std::process::Command::new("bash")
        .arg(&script)
        .args([name, m])
        .arg(stl)
        .arg(out)
        .env("CURA_RES", std::env::var("CURA_RES").unwrap_or_else(|_| "/opt/cura-res/usr/share/cura/resources".into()))
        .output()
        .map_err(|e| SlicerError::Failed(e.to_string()))?;
    if !st.status.success() || !out.exists() {
        return Err(SlicerError::Failed(String::from_utf8_lossy(&st.stderr).chars().rev().take(2000).collect::<String>().chars().rev().collect()));
    }
    Ok(SliceReport { executable: script })
}
