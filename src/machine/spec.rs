//! Machine descriptions (JSON) and the presets shipped in `presets/`.
//!
//! A machine JSON is one object: `name`, optional `axis_names` (output letters, in the
//! machine's axis order), `kind` (which kinematics) and that kind's parameters (any omitted
//! parameter takes its default). Kinds: `cartesian`, `b-head`, `rtn`, `pax`, `ab-table`,
//! `three-z`, `r-theta`, `lathe-a`. Presets are compiled in with `include_str!` so they work in
//! wasm; [`preset`] loads one by name, [`MachineSpec::from_json`] parses a user's file.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::{Machine, MachineError};

/// What every kind's parameter type does (each in its kind's file): the default axis letters
/// and building the machine.
pub trait Kind {
    /// Default axis letters, in the machine's axis order.
    fn default_axis_names(&self) -> &'static [&'static str];
    /// Build the machine named `name` with axis letters `axis_names`.
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError>;
}

/// `kinds! { Variant(module::Params) = "json-kind", … }` defines [`Kinematics`] (the JSON tag
/// `kind`) and its dispatch to [`Kind`] from one line per kind.
macro_rules! kinds {
    ($($variant:ident($params:ty) = $tag:literal,)*) => {
        /// The kinematics of a machine and its parameters (JSON tag `kind`).
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(tag = "kind")]
        #[non_exhaustive]
        pub enum Kinematics {
            $(
                #[doc = concat!("`\"kind\": \"", $tag, "\"`: see [`", stringify!($params), "`].")]
                #[serde(rename = $tag)]
                $variant($params),
            )*
        }

        impl Kinematics {
            /// Every kind's JSON name.
            pub const KINDS: &'static [&'static str] = &[$($tag),*];

            /// The kind's parameters.
            pub fn params(&self) -> &dyn Kind {
                match self {
                    $(Kinematics::$variant(p) => p,)*
                }
            }

            /// The kind's JSON name.
            pub fn kind_name(&self) -> &'static str {
                match self {
                    $(Kinematics::$variant(_) => $tag,)*
                }
            }
        }
    };
}

// The machine kinds: one line each (the kind's file holds everything else).
kinds! {
    Cartesian(super::cartesian::CartesianParams) = "cartesian",
    BHead(super::bhead::BHeadParams) = "b-head",
    Rtn(super::rtn::RtnParams) = "rtn",
    Pax(super::pax::PaxParams) = "pax",
    AbTable(super::abtable::AbTableParams) = "ab-table",
    ThreeZ(super::threez::ThreeZParams) = "three-z",
    RTheta(super::rtheta::RThetaParams) = "r-theta",
    LatheA(super::lathe::LatheParams) = "lathe-a",
}

impl Kinematics {
    /// Default axis letters.
    pub fn default_axis_names(&self) -> &'static [&'static str] {
        self.params().default_axis_names()
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
    /// The print head's solids in the tool frame, for the collision check (`null`: the kind's
    /// default, an E3D-V6-class hotend; see [`super::head`]).
    #[serde(default)]
    pub head: Option<super::head::HeadSpec>,
    /// The bed in the output frame, for the collision check (`null`: the kind's default; see
    /// [`super::head`]).
    #[serde(default)]
    pub bed: Option<super::head::BedSpec>,
    /// Travel `[min, max]` of linear axes, by axis letter, in machine coordinates (mm, raw
    /// values as written: the triple-Z bed's Z axes are its motor heights). An axis not listed is
    /// unlimited (files written before `travel` existed load unchanged). Rotary ranges are
    /// the kind's own parameters. See [`super::travel`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub travel: Option<BTreeMap<String, [f64; 2]>>,
    /// Largest feed of an axis, by axis letter: mm/min for a linear axis, °/min for a rotary
    /// one. An axis not listed has no limit (its moves are never counted as slowed). See
    /// [`super::travel`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_feed: Option<BTreeMap<String, f64>>,
    /// Rotary axes the firmware is configured to treat as linear (letters), e.g. Open5x's
    /// published Duet 2 configuration, which creates U and V without `R1`: their degrees then
    /// count in the firmware's move length like millimetres, and `--feed tip` computes F for
    /// that ([`super::config`], [`super::length_rule`]). `null`: every rotary axis is
    /// configured rotary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub firmware_linear_axes: Option<Vec<String>>,
    /// Kinematics and parameters.
    #[serde(flatten)]
    pub kinematics: Kinematics,
}

// The presets shipped in `presets/`: `PRESETS: &[(&str, &str)]` (name, JSON text), every
// `presets/*.json` in name order, compiled in (so they work in wasm) by build.rs.
include!(concat!(env!("OUT_DIR"), "/presets.rs"));

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

    /// The head (given, or the kind's default), checked.
    pub fn head(&self) -> Result<super::head::HeadSpec, MachineError> {
        let h = self
            .head
            .clone()
            .unwrap_or_else(|| super::head::HeadSpec::default_for(self.kinematics.kind_name()));
        h.validate(&self.name)?;
        Ok(h)
    }

    /// The bed (given, or the kind's default), checked.
    pub fn bed(&self) -> Result<super::head::BedSpec, MachineError> {
        let b = self
            .bed
            .clone()
            .unwrap_or_else(|| super::head::BedSpec::default_for(self.kinematics.kind_name()));
        b.validate(&self.name)?;
        Ok(b)
    }

    /// Build the machine (the `travel` and `max_feed` entries are checked too).
    pub fn build(&self) -> Result<Box<dyn Machine>, MachineError> {
        let names = self.axis_names()?;
        let machine = self.kinematics.params().build(&self.name, &names)?;
        self.axis_bounds(machine.limits())?;
        Ok(machine)
    }

    /// Every axis of the machine (whose kinematic limits are `limits`) with this file's travel
    /// and largest feed ([`super::travel::resolve`]).
    pub fn axis_bounds(
        &self,
        limits: &[super::AxisLimit],
    ) -> Result<Vec<super::travel::AxisBounds>, MachineError> {
        super::travel::resolve(
            &self.name,
            limits,
            self.travel.as_ref(),
            self.max_feed.as_ref(),
        )
    }
}
