//! The core describes itself: every warp and its parameters, the options of both steps, the
//! machines and what each can do, the toolpath's feature names and every error code. The CLI's
//! help and the web page's forms and advice are built from this, so neither keeps a copy of
//! the core's tables ([`describe`] is the JSON the wasm export `describe()` returns).

use serde::Serialize;

use crate::error::ErrorCode;
use crate::machine::{Capabilities, MachineError};
use crate::schema::{Param, WarpInfo};
use crate::toolpath::Feature;

/// One machine as the page shows it: name, kind, flavour, axes and [`Capabilities`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MachineInfo {
    /// Preset name.
    pub name: String,
    /// The kinematics kind (`"kind"` of its JSON).
    pub kind: String,
    /// The firmware flavour it is written for.
    pub flavour: &'static str,
    /// Its axes in output order: `{ name, rotary, min, max, max_feed }` (min, max: the travel of
    /// a linear axis or the range of a rotary one; unbounded: `null`; max_feed mm/min or °/min,
    /// `null` without a limit).
    pub axes: Vec<serde_json::Value>,
    /// What it can do.
    #[serde(flatten)]
    pub capabilities: Capabilities,
    /// The preset's JSON object (a starting point for a custom machine).
    pub spec: serde_json::Value,
}

/// Everything the core says of itself.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Description {
    /// The crate version.
    pub version: &'static str,
    /// Every warp.
    pub warps: &'static [WarpInfo],
    /// The warp step's other parameters.
    pub warp_options: &'static [Param],
    /// The unwarp step's parameters (its own and the machine's).
    pub unwarp_options: Vec<Param>,
    /// The parameters of `warpslice check` besides the file and the machine.
    pub check_options: &'static [Param],
    /// The parameters of `warpslice suggest` besides the model and the machine (`overhangs`
    /// takes the first, the overhang angle).
    pub suggest_options: &'static [Param],
    /// Every shipped machine preset.
    pub machines: Vec<MachineInfo>,
    /// Feature names; the index is the feature number in the preview's toolpath buffer.
    pub features: Vec<&'static str>,
    /// Every error code.
    pub errors: Vec<ErrorCode>,
    /// The built-in slicer's settings with their defaults (keys: PrusaSlicer's option names;
    /// `docs/builtin-slicer.md` says what each means).
    pub slicer_settings: crate::planar::Settings,
}

/// Every error code of every area.
pub fn error_codes() -> Vec<ErrorCode> {
    let mut v = Vec::new();
    for list in [
        crate::mesh::ERROR_CODES,
        crate::warp::ERROR_CODES,
        crate::planar::ERROR_CODES,
        crate::job::ERROR_CODES,
        crate::gcode::ERROR_CODES,
        crate::register::ERROR_CODES,
        crate::unwarp::ERROR_CODES,
        crate::machine::ERROR_CODES,
        crate::calibrate::ERROR_CODES,
        crate::pipeline::ERROR_CODES,
        crate::check::ERROR_CODES,
        crate::suggest::ERROR_CODES,
    ] {
        v.extend_from_slice(list);
    }
    #[cfg(not(target_arch = "wasm32"))]
    v.extend_from_slice(crate::slicer::ERROR_CODES);
    v
}

/// What a machine spec says of itself.
pub fn machine_info(
    name: &str,
    spec: &crate::machine::MachineSpec,
) -> Result<MachineInfo, MachineError> {
    let finite = |v: f64| {
        if v.is_finite() {
            serde_json::json!(v)
        } else {
            serde_json::Value::Null
        }
    };
    let machine = spec.build()?;
    // the kinematic limits joined with the file's travel (linear axes) and largest feeds
    let axes = spec
        .axis_bounds(machine.limits())?
        .iter()
        .map(|l| {
            serde_json::json!({ "name": l.name, "rotary": l.rotary, "min": finite(l.min), "max": finite(l.max), "max_feed": finite(l.max_feed) })
        })
        .collect();
    let value = serde_json::to_value(spec).map_err(|e| MachineError::BadJson {
        source: name.to_string(),
        message: e.to_string(),
    })?;
    Ok(MachineInfo {
        name: name.to_string(),
        kind: value
            .get("kind")
            .and_then(|k| k.as_str())
            .unwrap_or_default()
            .to_string(),
        flavour: spec.flavour.unwrap_or_default().name(),
        axes,
        capabilities: machine.capabilities(),
        spec: value,
    })
}

/// The description (see the module documentation).
pub fn describe() -> Result<Description, MachineError> {
    let mut machines = Vec::new();
    for name in crate::machine::preset_names() {
        machines.push(machine_info(name, &crate::machine::preset(name)?)?);
    }
    let mut unwarp_options = crate::unwarp::PARAMS.to_vec();
    unwarp_options.extend_from_slice(crate::machine::options::PARAMS);
    Ok(Description {
        version: env!("CARGO_PKG_VERSION"),
        warps: crate::warp::WARPS,
        warp_options: crate::pipeline::WARP_OPTION_PARAMS,
        unwarp_options,
        check_options: crate::check::options::PARAMS,
        suggest_options: crate::suggest::PARAMS,
        machines,
        features: Feature::ALL.iter().map(|f| f.name()).collect(),
        errors: error_codes(),
        slicer_settings: crate::planar::Settings::default(),
    })
}

/// [`describe`] as JSON.
pub fn describe_json() -> Result<String, MachineError> {
    let d = describe()?;
    serde_json::to_string(&d).map_err(|e| MachineError::BadJson {
        source: "describe".into(),
        message: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_codes_are_unique_and_named_by_their_area() {
        let codes = error_codes();
        let mut seen = std::collections::HashSet::new();
        for c in &codes {
            assert!(seen.insert(c.code), "code {} twice", c.code);
            assert!(
                c.code.starts_with(&format!("{}.", c.area)),
                "{} not in area {}",
                c.code,
                c.area
            );
            assert!(!c.summary.is_empty());
        }
        assert!(codes.len() > 40, "{}", codes.len());
    }

    #[test]
    fn every_warp_spec_kind_is_described() {
        // WarpSpec's serde tags, read from a serialised value of each kind.
        let json = describe_json().unwrap();
        for kind in [
            "curved",
            "tilted",
            "conic",
            "belt",
            "cylindrical",
            "spherical",
            "field",
        ] {
            assert!(json.contains(&format!("\"name\":\"{kind}\"")), "{kind}");
        }
        let d = describe().unwrap();
        assert_eq!(d.machines.len(), crate::machine::preset_names().len());
    }
}
