//! The machine options of the unwarp step (`--machine`, `--feed`, `--flavour`) and the emitter
//! they ask for.

use serde::{Deserialize, Serialize};

use super::{FeedMode, Flavour, MachineEmitter, MachineError, MachineSpec};
use crate::emit::{Cartesian, Emitter};
use crate::schema::{Param, ParamDefault, ParamType};

/// `--machine`, `--feed`, `--flavour`: which emitter writes the unwarped toolpath. In the
/// options JSON these keys sit beside the unwarp's own (see [`crate::pipeline::UnwarpSettings`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    /// `--check-collisions` (**the default**, issue 10 §2): sweep the machine's head along every
    /// output move against the material printed so far and the bed (`crate::collision`) and
    /// refuse the file on a collision (`machine.collision`). Every refusal of the real-slicer
    /// matrix is confirmed by the independent test helper (`tests/common/collide.rs`). The
    /// options JSON may still say `false` (a caller that checks the file itself, e.g. with
    /// `warpslice check`); the written file then says in its last comment that it was not
    /// checked. The CLI has no flag to switch it off.
    pub check_collisions: bool,
    /// `--allow-collisions`: write the file and list every finding (in the report and as
    /// comments at its end) instead of refusing it (`machine.collision`).
    pub allow_collisions: bool,
    /// `--interpolation LIN,ANG`: the largest deviation of the firmware's linear interpolation
    /// in machine space from the intended path, tip mm and tool-axis degrees (default 0.02,
    /// 0.1; seed 001 §4.5's worst case for its 1 mm / 1° spacing: 0.05,0.01).
    pub interpolation: Option<[f64; 2]>,
    /// `--interpolation-caps MM,DEG`: also split every output move longer than MM of tip travel
    /// or turning the tool axis by more than DEG (seed 001 §4.5 recommends 1,1).
    pub interpolation_caps: Option<[f64; 2]>,
}

impl Default for MachineOptions {
    /// No machine (3-axis output); for a machine: tip feed, its own flavour, the collision
    /// check on and refusing, the default interpolation bounds.
    fn default() -> Self {
        MachineOptions {
            machine: None,
            feed: FeedMode::default(),
            flavour: None,
            check_collisions: true,
            allow_collisions: false,
            interpolation: None,
            interpolation_caps: None,
        }
    }
}

/// The range `--interpolation` and `--interpolation-caps` accept for each of their two numbers
/// (mm or degrees): above zero, and at most this — a bound wider than the paper's 1 mm / 1°
/// caps by a factor of ten would not bound anything the printer does.
pub const INTERPOLATION_MAX: f64 = 10.0;
/// The smallest value they accept: below the G-code's 3-decimal resolution (0.001 mm) a bound
/// cannot be met by any written move.
pub const INTERPOLATION_MIN: f64 = 0.001;

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
    /// The firmware configuration these options' output needs (`--config-out`, wasm
    /// `firmware_config`): `None` for 3-axis output; the flavour's refusal when it cannot
    /// drive the machine with this feed (as the emitter refuses the G-code).
    pub fn firmware_config(&self) -> Result<Option<super::config::FirmwareConfig>, MachineError> {
        self.machine
            .as_ref()
            .map(|spec| super::config::for_spec(spec, self.flavour, self.feed))
            .transpose()
    }

    /// Whether the collision check runs: a machine output with `check_collisions`.
    pub fn checks_collisions(&self) -> bool {
        self.machine.is_some() && self.check_collisions
    }

    /// The emitter these options ask for: 3-axis, or the machine's.
    pub fn emitter(&self) -> Result<Box<dyn Emitter>, MachineError> {
        let bounds = self.bounds()?;
        Ok(match &self.machine {
            None => Box::new(Cartesian::new()),
            Some(spec) => Box::new(
                MachineEmitter::new(spec, self.flavour, self.feed)?
                    .with_bounds(bounds)
                    .with_input_lines(self.checks_collisions()),
            ),
        })
    }

    /// The interpolation bounds these options ask for ([`super::tessellate::DEFAULT_BOUNDS`]
    /// with `--interpolation` and `--interpolation-caps`); a value outside
    /// [[`INTERPOLATION_MIN`], [`INTERPOLATION_MAX`]] is [`MachineError::BadOption`].
    pub fn bounds(&self) -> Result<super::tessellate::Bounds, MachineError> {
        let check = |name: &'static str, v: Option<[f64; 2]>| -> Result<(), MachineError> {
            match v {
                Some([a, b])
                    if ![a, b].iter().all(|x| {
                        x.is_finite() && (INTERPOLATION_MIN..=INTERPOLATION_MAX).contains(x)
                    }) =>
                {
                    Err(MachineError::BadOption {
                        name,
                        value: format!("{a},{b}"),
                        allowed: "two numbers mm,degrees, each from 0.001 to 10 (seed 001's: --interpolation 0.05,0.01 --interpolation-caps 1,1)",
                    })
                }
                _ => Ok(()),
            }
        };
        check("interpolation", self.interpolation)?;
        check("interpolation-caps", self.interpolation_caps)?;
        let mut b = super::tessellate::DEFAULT_BOUNDS;
        if let Some([mm, deg]) = self.interpolation {
            b.max_position_mm = mm;
            b.max_angle_deg = deg;
        }
        if let Some([mm, deg]) = self.interpolation_caps {
            b.max_step_mm = Some(mm);
            b.max_step_deg = Some(deg);
        }
        Ok(b)
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
    Param::number("check_collisions", "--check-collisions", "Check collisions")
        .of(ParamType::Bool)
        .default(ParamDefault::Bool(true))
        .help("on by default (the flag is accepted and changes nothing): sweep the machine's head (its JSON \"head\", else an E3D-V6-class hotend) along every move against the printed material and the bed; refuse the file on a collision (machine.collision: output line, input line, layer, head part, depth); --allow-collisions writes it and lists every finding"),
    Param::number("interpolation", "--interpolation", "Interpolation bound mm,deg")
        .of(ParamType::Pair)
        .optional()
        .help("largest deviation of the firmware's machine-space interpolation from the path, tip mm and tool-axis degrees (default 0.02,0.1; seed 001 §4.5's worst case for 1 mm / 1° spacing: 0.05,0.01)"),
    Param::number("interpolation_caps", "--interpolation-caps", "Move caps mm,deg")
        .of(ParamType::Pair)
        .optional()
        .help("also split every machine move longer than mm of tip travel or turning the tool by more than deg (seed 001 §4.5 recommends 1,1)"),
    Param::number("allow_collisions", "--allow-collisions", "Allow collisions")
        .of(ParamType::Bool)
        .default(ParamDefault::Bool(false))
        .help("write the file even when the head collides, and list every collision found (report and comments at the end of the file) instead of refusing it"),
];
