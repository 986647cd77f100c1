//! Parameter descriptions: how the core describes its options to the CLI's help and the web
//! page's forms ([`crate::describe`]), so that neither keeps a copy of the core's tables.
//!
//! Each warp's file lists its own parameters ([`Param`]); the option structs of the warp and
//! unwarp steps list theirs. A parameter names the JSON key it fills in the options object
//! (a dotted key is nested: `flow.factor`), its CLI flag, unit, range and default.

use serde::Serialize;

/// The value type of a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ParamType {
    /// One number.
    Number,
    /// One of [`Param::choices`].
    Choice,
    /// One or more of [`Param::choices`], comma-separated (`conic,belt`).
    Choices,
    /// On or off.
    Bool,
    /// Two numbers `a,b`.
    Pair,
    /// Three numbers `x,y,z`.
    Triple,
    /// Free text (the field warp's expression).
    Text,
}

/// A parameter's default value.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ParamDefault {
    /// No default: the parameter is off (optional) or derived (the help says from what).
    None,
    /// A number.
    Number(f64),
    /// A choice or text.
    Text(&'static str),
    /// On or off.
    Bool(bool),
    /// Two numbers.
    Pair([f64; 2]),
    /// Three numbers.
    Triple([f64; 3]),
}

impl ParamDefault {
    /// The default as a JSON value for an options object (`None`: no default).
    pub fn to_json(self) -> Option<serde_json::Value> {
        use serde_json::Value;
        match self {
            ParamDefault::None => None,
            ParamDefault::Number(v) => Some(Value::from(v)),
            ParamDefault::Text(t) => Some(Value::from(t)),
            ParamDefault::Bool(b) => Some(Value::Bool(b)),
            ParamDefault::Pair(v) => Some(Value::from(v.to_vec())),
            ParamDefault::Triple(v) => Some(Value::from(v.to_vec())),
        }
    }
}

/// One parameter of a warp or a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Param {
    /// The JSON key in the options object (dotted: nested).
    pub key: &'static str,
    /// The CLI flag.
    pub flag: &'static str,
    /// A short label for a form.
    pub label: &'static str,
    /// The value type.
    #[serde(rename = "type")]
    pub ty: ParamType,
    /// `mm`, `deg` or empty.
    pub unit: &'static str,
    /// Smallest allowed value (numbers), if any.
    pub min: Option<f64>,
    /// Largest allowed value (numbers), if any.
    pub max: Option<f64>,
    /// Whether `min` itself is excluded.
    pub min_exclusive: bool,
    /// Whether `max` itself is excluded.
    pub max_exclusive: bool,
    /// A sensible step for a form's spinner.
    pub step: Option<f64>,
    /// The default.
    pub default: ParamDefault,
    /// Whether the parameter may be left out (then it is off, or derived as the help says).
    pub optional: bool,
    /// The allowed values of a choice.
    pub choices: &'static [&'static str],
    /// One line of help (the CLI's and the page's).
    pub help: &'static str,
}

impl Param {
    /// A number parameter with no range, default 0, not optional.
    pub const fn number(key: &'static str, flag: &'static str, label: &'static str) -> Param {
        Param {
            key,
            flag,
            label,
            ty: ParamType::Number,
            unit: "",
            min: None,
            max: None,
            min_exclusive: false,
            max_exclusive: false,
            step: None,
            default: ParamDefault::None,
            optional: false,
            choices: &[],
            help: "",
        }
    }
    /// The same, of another type.
    pub const fn of(self, ty: ParamType) -> Param {
        Param { ty, ..self }
    }
    /// With a unit.
    pub const fn unit(self, unit: &'static str) -> Param {
        Param { unit, ..self }
    }
    /// With a range; `exclusive` = (min excluded, max excluded).
    pub const fn range(self, min: Option<f64>, max: Option<f64>, exclusive: (bool, bool)) -> Param {
        Param {
            min,
            max,
            min_exclusive: exclusive.0,
            max_exclusive: exclusive.1,
            ..self
        }
    }
    /// With a spinner step.
    pub const fn step(self, step: f64) -> Param {
        Param {
            step: Some(step),
            ..self
        }
    }
    /// With a default.
    pub const fn default(self, default: ParamDefault) -> Param {
        Param { default, ..self }
    }
    /// Optional (off when left out, or derived as the help says).
    pub const fn optional(self) -> Param {
        Param {
            optional: true,
            ..self
        }
    }
    /// A choice among `choices`.
    pub const fn choices(self, choices: &'static [&'static str]) -> Param {
        Param {
            ty: ParamType::Choice,
            choices,
            ..self
        }
    }
    /// With help text.
    pub const fn help(self, help: &'static str) -> Param {
        Param { help, ..self }
    }
}

/// What a warp says of itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WarpInfo {
    /// The CLI / JSON name (`kind`).
    pub name: &'static str,
    /// A title for a menu.
    pub title: &'static str,
    /// One line: what the layers look like and what it is for.
    pub help: &'static str,
    /// T_z in closed form (the README's table).
    pub formula: &'static str,
    /// The seed section it comes from.
    pub seed: &'static str,
    /// Whether it is a shear in z (det J = 1) and takes the `--base` blend.
    pub base: bool,
    /// Its parameters (keys of the warp spec object).
    pub params: &'static [Param],
}

/// A count given as a JSON number: a whole, non-negative number (`1000` or `1000.0`, as a
/// form or the CLI's number flags write it); `key` names it in the error.
pub fn count<'de, D: serde::Deserializer<'de>>(d: D, key: &str) -> Result<usize, D::Error> {
    use serde::Deserialize;
    let v = f64::deserialize(d)?;
    if v.is_finite() && v >= 0.0 && v.fract() == 0.0 && v <= u32::MAX as f64 {
        Ok(v as usize)
    } else {
        Err(serde::de::Error::custom(format!(
            "{key} is {v}: it must be a whole number ≥ 0"
        )))
    }
}
