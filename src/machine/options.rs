//! The machine options of the unwarp step (`--machine`, `--feed`, `--flavour`) and the emitter
//! they ask for.

use serde::{Deserialize, Serialize};

use super::{FeedMode, Flavour, MachineEmitter, MachineError, MachineSpec};
use crate::emit::{Cartesian, Emitter};
use crate::schema::{Param, ParamDefault, ParamType};

/// `--machine`, `--feed`, `--flavour`: which emitter writes the unwarped toolpath. In the
/// options JSON these keys sit beside the unwarp's own (see [`crate::pipeline::UnwarpSettings`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MachineOptions {
    /// `--machine`: write the machine's axes instead of 3-axis G-code. In JSON a machine
    /// object or a preset name (`"machine": "pax-5axis"`).
    #[serde(deserialize_with = "machine_from_json")]
    pub machine: Option<MachineSpec>,
    /// `--feed`: how F is written for a machine.
    pub feed: FeedMode,
    /// `--flavour`: the firmware (overrides the machine's).
    pub flavour: Option<Flavour>,
    /// `--no-collision-check` (**unsafe**): skip the collision check, which otherwise sweeps the
    /// machine's head along every output move against the material printed so far and the bed
    /// (`crate::collision`) and refuses the file on a collision (`machine.collision`). The check
    /// is on by default for every machine output.
    pub no_collision_check: bool,
    /// `--allow-collisions`: write the file and list every finding (in the report and as
    /// comments at its end) instead of refusing it (`machine.collision`).
    pub allow_collisions: bool,
}

/// `machine` in the options JSON: `null`, a preset name or a machine object.
fn machine_from_json<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<MachineSpec>, D::Error> {
    use serde::de::Error as _;
    match Option::<serde_json::Value>::deserialize(d)? {
        None | Some(serde_json::Value::Null) => Ok(None),
        Some(serde_json::Value::String(name)) => {
            super::preset(&name).map(Some).map_err(D::Error::custom)
        }
        Some(v @ serde_json::Value::Object(_)) => {
            MachineSpec::from_json(&v.to_string(), "unwarp options 'machine'")
                .map(Some)
                .map_err(D::Error::custom)
        }
        Some(other) => Err(D::Error::custom(format!(
            "machine must be a preset name or a machine object, not {other}"
        ))),
    }
}

impl MachineOptions {
    /// Whether the collision check runs: a machine output without `no_collision_check`.
    pub fn checks_collisions(&self) -> bool {
        self.machine.is_some() && !self.no_collision_check
    }

    /// The emitter these options ask for: 3-axis, or the machine's.
    pub fn emitter(&self) -> Result<Box<dyn Emitter>, MachineError> {
        Ok(match &self.machine {
            None => Box::new(Cartesian::new()),
            Some(spec) => Box::new(MachineEmitter::new(spec, self.flavour, self.feed)?),
        })
    }
}

/// The machine options as the CLI and the page show them ([`crate::describe`]); `machine`
/// itself is a preset name or a machine object (the page's machine select and JSON box).
pub const PARAMS: &[Param] = &[
    Param::number("feed", "--feed", "Feed mode")
        .choices(&["tip", "xyz", "all-axes", "inverse-time"])
        .default(ParamDefault::Text("tip"))
        .help("how F is written for a machine: tip (each move takes tip length / tip feed by the firmware's own move-length rule), xyz (F = tip feed), all-axes (scaled for rotary degrees counted like mm), or G93 inverse time (RepRapFirmware 3.5.0 and later)"),
    Param::number("flavour", "--flavour", "Firmware")
        .choices(&["reprapfirmware", "marlin", "klipper"])
        .optional()
        .help("the firmware the output is for (default: the machine's, else reprapfirmware)"),
    Param::number("no_collision_check", "--no-collision-check", "Skip the collision check (unsafe)")
        .of(ParamType::Bool)
        .default(ParamDefault::Bool(false))
        .help("UNSAFE: do not sweep the machine's head (its JSON \"head\", else an E3D-V6-class hotend) along every move against the printed material and the bed; by default a collision refuses the file"),
    Param::number("allow_collisions", "--allow-collisions", "Allow collisions")
        .of(ParamType::Bool)
        .default(ParamDefault::Bool(false))
        .help("write the file even when the head collides, and list every collision found (report and comments at the end of the file)"),
];
