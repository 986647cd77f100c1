//! The options of `warpslice check` (CLI flags and the wasm options JSON, described in
//! [`PARAMS`] so both are built from it).

use serde::{Deserialize, Serialize};

use crate::machine::Flavour;
use crate::schema::{Param, ParamDefault, ParamType};

/// Findings kept in the report's list by default (every finding is counted).
pub const DEFAULT_MAX_FINDINGS: usize = 1000;

/// What `check` is asked.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CheckOptions {
    /// The firmware that reads the file (its move-length rule times the moves); `None`: the
    /// machine's, else RepRapFirmware.
    pub flavour: Option<Flavour>,
    /// Findings listed in the report (all are counted). A whole number; JSON `1000.0` is
    /// accepted as written by a form or the CLI's number flags.
    #[serde(deserialize_with = "count")]
    pub max_findings: usize,
    /// Keep the tip path (the preview's points; `CheckStream::take_path`).
    pub path: bool,
    /// Leave the collision check out (reach, speeds, time, E and tilt only): the swept check is
    /// the costly part on a large file.
    pub skip_collisions: bool,
}

impl Default for CheckOptions {
    fn default() -> CheckOptions {
        CheckOptions {
            flavour: None,
            max_findings: DEFAULT_MAX_FINDINGS,
            path: false,
            skip_collisions: false,
        }
    }
}

/// The check's parameters (the CLI's flags besides the file and `--machine`).
pub const PARAMS: &[Param] = &[
    Param::number("flavour", "--flavour", "Firmware")
        .choices(&["reprapfirmware", "marlin", "klipper"])
        .optional()
        .help("the firmware that reads the file: its move-length rule times each move (default: the machine's, else reprapfirmware)"),
    Param::number("max_findings", "--max-findings", "Findings listed")
        .range(Some(0.0), None, (false, false))
        .step(1.0)
        .default(ParamDefault::Number(DEFAULT_MAX_FINDINGS as f64))
        .help("findings listed in the report (every finding is counted)"),
    Param::number("skip_collisions", "--skip-collisions", "Skip collisions")
        .of(ParamType::Bool)
        .default(ParamDefault::Bool(false))
        .help("check reach and axis speeds only, not the head's collisions with the print and the bed (the costly part on a large file)"),
];

/// `max_findings`: a count ([`crate::schema::count`]).
fn count<'de, D: serde::Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
    crate::schema::count(d, "max_findings")
}
