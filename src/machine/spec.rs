//! Machine descriptions (JSON) and the presets shipped in `presets/`.
//!
//! A machine JSON is one object: `name`, optional `axis_names` (output letters, in the
//! machine's axis order), `kind` (which kinematics) and that kind's parameters (any omitted
//! parameter takes its default). Kinds: `cartesian`, `b-head`, `rtn`, `pax`, `ab-table`,
//! `three-z`, `r-theta`, `lathe-a`. Presets are compiled in with `include_str!` so they work in
//! wasm; [`preset`] loads one by name, [`MachineSpec::from_json`] parses a user's file.

use serde::{Deserialize, Serialize};

use super::abtable::{AbTable, AbTableParams};
use super::bhead::{BHead, BHeadParams};
use super::cartesian::{Cartesian, CartesianParams};
use super::lathe::{Lathe, LatheParams};
use super::pax::{Pax, PaxParams};
use super::rtheta::{RTheta, RThetaParams};
use super::rtn::{Rtn, RtnParams};
use super::threez::{ThreeZ, ThreeZParams};
use super::{Machine, MachineError};

/// The kinematics of a machine and its parameters (JSON tag `kind`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Kinematics {
    /// 3-axis, vertical nozzle.
    Cartesian(CartesianParams),
    /// Head tilting about Y (FullControl Prusa B).
    BHead(BHeadParams),
    /// Rotating tilted nozzle (Slicer4RTN, RotBot).
    Rtn(RtnParams),
    /// 5-axis head (PAX).
    Pax(PaxParams),
    /// A/B rotary table (Open5x).
    AbTable(AbTableParams),
    /// Triple-Z tilting bed (RatRig V-Core 3).
    ThreeZ(ThreeZParams),
    /// Polar printer with tilting nozzle (Core R-Theta).
    RTheta(RThetaParams),
    /// Rotating mandrel about X.
    LatheA(LatheParams),
}

impl Kinematics {
    /// Default axis letters.
    pub fn default_axis_names(&self) -> &'static [&'static str] {
        if let Kinematics::LatheA(p) = self {
            return if p.with_y {
                &["X", "Y", "Z", "A"]
            } else {
                &["X", "Z", "A"]
            };
        }
        match self {
            Kinematics::Cartesian(_) => &["X", "Y", "Z"],
            Kinematics::BHead(_) => &["X", "Y", "Z", "B"],
            Kinematics::Rtn(_) => &["X", "Y", "Z", "A"],
            Kinematics::Pax(_) => &["X", "Y", "Z", "A", "B"],
            Kinematics::AbTable(_) => &["X", "Y", "Z", "A", "B"],
            Kinematics::ThreeZ(_) => &["X", "Y", "Z", "U", "V"],
            Kinematics::RTheta(_) => &["X", "C", "Z", "B"],
            Kinematics::LatheA(_) => &["X", "Y", "Z", "A"],
        }
    }
}

/// A machine description.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MachineSpec {
    /// Name used in messages and file headers.
    #[serde(default)]
    pub name: String,
    /// Output letters in axis order (defaults per kind).
    #[serde(default)]
    pub axis_names: Option<Vec<String>>,
    /// Firmware flavour of the output (default RepRapFirmware).
    #[serde(default)]
    pub flavour: Option<super::Flavour>,
    /// Kinematics and parameters.
    #[serde(flatten)]
    pub kinematics: Kinematics,
}

/// The presets shipped in `presets/` (name, JSON text).
const PRESETS: &[(&str, &str)] = &[
    ("cartesian", include_str!("../../presets/cartesian.json")),
    (
        "fullcontrol-prusa-b",
        include_str!("../../presets/fullcontrol-prusa-b.json"),
    ),
    (
        "rtn-slicer4rtn",
        include_str!("../../presets/rtn-slicer4rtn.json"),
    ),
    ("rotbot", include_str!("../../presets/rotbot.json")),
    ("pax-5axis", include_str!("../../presets/pax-5axis.json")),
    ("open5x-ab", include_str!("../../presets/open5x-ab.json")),
    (
        "ratrig-vcore3-3z",
        include_str!("../../presets/ratrig-vcore3-3z.json"),
    ),
    (
        "core-r-theta",
        include_str!("../../presets/core-r-theta.json"),
    ),
    ("lathe-a", include_str!("../../presets/lathe-a.json")),
];

/// Names of the shipped presets.
pub fn preset_names() -> Vec<&'static str> {
    PRESETS.iter().map(|(n, _)| *n).collect()
}

/// The shipped preset `name`.
pub fn preset(name: &str) -> Result<MachineSpec, MachineError> {
    match PRESETS.iter().find(|(n, _)| *n == name) {
        Some((n, text)) => MachineSpec::from_json(text, &format!("preset {n}")),
        None => Err(MachineError::UnknownPreset {
            name: name.to_string(),
            known: preset_names().into_iter().map(String::from).collect(),
        }),
    }
}

impl MachineSpec {
    /// Parse a machine JSON; `source` names it in errors (file path or preset).
    pub fn from_json(text: &str, source: &str) -> Result<MachineSpec, MachineError> {
        let bad = |message: String| MachineError::BadJson {
            source: source.to_string(),
            message,
        };
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
        let mut spec: MachineSpec =
            serde_json::from_value(value.clone()).map_err(|e| bad(e.to_string()))?;
        // A misspelt parameter would silently take its default: refuse fields the kind does not
        // have (serde's deny_unknown_fields does not work through `flatten`).
        let known = serde_json::to_value(&spec).map_err(|e| bad(e.to_string()))?;
        if let (Some(given), Some(known)) = (value.as_object(), known.as_object()) {
            if let Some(k) = given.keys().find(|k| !known.contains_key(*k)) {
                let mut names: Vec<&String> = known.keys().collect();
                names.sort();
                return Err(bad(format!(
                    "unknown field '{k}' for kind '{}'; known fields: {}",
                    given.get("kind").and_then(|v| v.as_str()).unwrap_or("?"),
                    names
                        .iter()
                        .map(|s| s.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
        }
        if spec.name.is_empty() {
            spec.name = source.to_string();
        }
        Ok(spec)
    }

    /// Resolve a `--machine` argument: a preset name, or (when it ends in `.json` or contains a
    /// path separator) a file read with `read` (the caller's filesystem access; none in wasm).
    pub fn from_arg(
        arg: &str,
        read: impl FnOnce(&str) -> Result<String, String>,
    ) -> Result<MachineSpec, MachineError> {
        if arg.ends_with(".json") || arg.contains('/') || arg.contains('\\') {
            let text = read(arg).map_err(|message| MachineError::BadJson {
                source: arg.to_string(),
                message: format!("cannot read the file: {message}"),
            })?;
            MachineSpec::from_json(&text, arg)
        } else {
            preset(arg)
        }
    }

    /// A machine given as text where no file can be read (the web page): a machine JSON
    /// object (starts with `{`) or a preset name.
    pub fn from_name_or_json(text: &str) -> Result<MachineSpec, MachineError> {
        let t = text.trim();
        if t.starts_with('{') {
            MachineSpec::from_json(t, "machine JSON")
        } else {
            preset(t)
        }
    }

    /// The JSON text of this spec.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// The axis letters (given or default), checked for count.
    pub fn axis_names(&self) -> Result<Vec<String>, MachineError> {
        let defaults = self.kinematics.default_axis_names();
        match &self.axis_names {
            None => Ok(defaults.iter().map(|s| s.to_string()).collect()),
            Some(v) if v.len() == defaults.len() && v.iter().all(|s| !s.trim().is_empty()) => {
                Ok(v.clone())
            }
            Some(v) => Err(MachineError::BadSpec {
                machine: self.name.clone(),
                message: format!(
                    "axis_names has {} non-empty letters {:?}, expected {} (like {:?})",
                    v.len(),
                    v,
                    defaults.len(),
                    defaults
                ),
            }),
        }
    }

    /// Build the machine.
    pub fn build(&self) -> Result<Box<dyn Machine>, MachineError> {
        let names = self.axis_names()?;
        let n = &self.name;
        Ok(match &self.kinematics {
            Kinematics::Cartesian(p) => Box::new(Cartesian::new(n, &names, p.clone())),
            Kinematics::BHead(p) => Box::new(BHead::new(n, &names, p.clone())?),
            Kinematics::Rtn(p) => Box::new(Rtn::new(n, &names, p.clone())?),
            Kinematics::Pax(p) => Box::new(Pax::new(n, &names, p.clone())?),
            Kinematics::AbTable(p) => Box::new(AbTable::new(n, &names, p.clone())?),
            Kinematics::ThreeZ(p) => Box::new(ThreeZ::new(n, &names, p.clone())?),
            Kinematics::RTheta(p) => Box::new(RTheta::new(n, &names, p.clone())?),
            Kinematics::LatheA(p) => Box::new(Lathe::new(n, &names, p.clone())?),
        })
    }
}
