//! The warp and unwarp flags, built from the core's own description of its parameters
//! (`warpslice::warp::WARPS`, `pipeline::WARP_OPTION_PARAMS`, `unwarp::PARAMS`,
//! `machine::options::PARAMS`): flag, type, range hint, default and help all come from there,
//! and the values go into the same JSON options object the web page sends, read by the core's
//! serde types. Nothing of the core's tables is copied here.

use clap::builder::PossibleValuesParser;
use clap::{Arg, ArgAction, ArgMatches, Command};
use serde_json::{Map, Value};
use warpslice::pipeline::{UnwarpSettings, WarpOptions, WARP_OPTION_PARAMS};
use warpslice::schema::{Param, ParamDefault, ParamType};
use warpslice::warp::WARPS;

use crate::args::{machine_spec, pair, triple};

/// The arg id of a flag (`--max-edge` → `max-edge`).
fn id(p: &Param) -> &'static str {
    p.flag.trim_start_matches("--")
}

fn default_text(d: &ParamDefault) -> Option<String> {
    let list = |v: &[f64]| v.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
    match d {
        ParamDefault::None => None,
        ParamDefault::Number(v) => Some(v.to_string()),
        ParamDefault::Text(t) => Some((*t).to_string()),
        ParamDefault::Bool(b) => Some(b.to_string()),
        ParamDefault::Pair(v) => Some(list(v)),
        ParamDefault::Triple(v) => Some(list(v)),
    }
}

/// The help line: the core's help, the unit, the range, the default, and (for warp
/// parameters) the warps that take it.
fn help(p: &Param, warps: &[&str]) -> String {
    let mut h = String::new();
    if !warps.is_empty() {
        h.push_str(&format!("{}: ", warps.join("/")));
    }
    h.push_str(p.help);
    if !p.unit.is_empty() {
        h.push_str(&format!(" [{}]", p.unit));
    }
    match (p.min, p.max) {
        (Some(a), Some(b)) => h.push_str(&format!(
            " ({a} {} x {} {b})",
            lt(p.min_exclusive),
            lt(p.max_exclusive)
        )),
        (Some(a), None) => h.push_str(&format!(
            " ({} {a})",
            if p.min_exclusive { ">" } else { "≥" }
        )),
        (None, Some(b)) => h.push_str(&format!(
            " ({} {b})",
            if p.max_exclusive { "<" } else { "≤" }
        )),
        (None, None) => {}
    }
    if let Some(d) = default_text(&p.default) {
        h.push_str(&format!(" [default: {d}]"));
    }
    h
}

fn lt(exclusive: bool) -> &'static str {
    if exclusive {
        "<"
    } else {
        "≤"
    }
}

/// The clap argument of a parameter (no clap default: the schema's default is applied when
/// the options object is built, so a flag given is told from one left out).
fn arg(p: &Param, warps: &[&str]) -> Arg {
    let a = Arg::new(id(p)).long(id(p)).help(help(p, warps));
    match p.ty {
        ParamType::Number => a
            .value_parser(clap::value_parser!(f64))
            .allow_negative_numbers(true)
            .value_name("NUMBER"),
        ParamType::Pair => a
            .value_parser(pair)
            .allow_hyphen_values(true)
            .value_name("A,B"),
        ParamType::Triple => a
            .value_parser(triple)
            .allow_hyphen_values(true)
            .value_name("X,Y,Z"),
        ParamType::Choice => a.value_parser(PossibleValuesParser::new(p.choices.iter().copied())),
        ParamType::Text => a.allow_hyphen_values(true).value_name("TEXT"),
        ParamType::Choices => a
            .value_parser(PossibleValuesParser::new(p.choices.iter().copied()))
            .value_delimiter(',')
            .action(ArgAction::Append)
            .value_name("A,B,…"),
        ParamType::Bool => a.action(ArgAction::SetTrue),
    }
}

/// Add `p` unless the command already has the flag (`--tolerance` of `run` serves both steps).
pub(crate) fn add(cmd: Command, p: &Param, warps: &[&str]) -> Command {
    if cmd.get_arguments().any(|a| a.get_id() == id(p)) {
        cmd
    } else {
        cmd.arg(arg(p, warps))
    }
}

/// The value given for `p`, else its default, as JSON (`None`: left out, optional).
fn value(m: &ArgMatches, p: &Param) -> Option<Value> {
    let given = match p.ty {
        ParamType::Number => m.get_one::<f64>(id(p)).map(|v| Value::from(*v)),
        ParamType::Pair => m
            .get_one::<[f64; 2]>(id(p))
            .map(|v| Value::from(v.to_vec())),
        ParamType::Triple => m
            .get_one::<[f64; 3]>(id(p))
            .map(|v| Value::from(v.to_vec())),
        ParamType::Choice | ParamType::Text => {
            m.get_one::<String>(id(p)).map(|v| Value::from(v.as_str()))
        }
        ParamType::Choices => m
            .get_many::<String>(id(p))
            .map(|v| Value::from(v.map(String::as_str).collect::<Vec<_>>())),
        ParamType::Bool => m.get_flag(id(p)).then_some(Value::Bool(true)),
    };
    given.or_else(|| p.default.to_json())
}

/// Put `v` at the (dotted) key `key` of `obj`.
fn insert(obj: &mut Map<String, Value>, key: &str, v: Value) {
    match key.split_once('.') {
        Some((head, rest)) => {
            let inner = obj
                .entry(head.to_string())
                .or_insert_with(|| Value::Object(Map::new()));
            if let Value::Object(o) = inner {
                insert(o, rest, v);
            }
        }
        None => {
            obj.insert(key.to_string(), v);
        }
    }
}

pub(crate) fn invalid(message: String) -> clap::Error {
    clap::Error::raw(clap::error::ErrorKind::ValueValidation, message + "\n")
}

/// `--warp` and every warp's parameters, and the warp step's options. With `OPTIONAL`
/// (`overhangs`, `warp --suggested N`) `--warp` may be left out: `given` is then false and
/// `options.warp` holds the first warp's defaults, for the caller to replace.
#[derive(Debug)]
pub struct WarpArgs<const OPTIONAL: bool = false> {
    /// The options the flags ask for.
    pub options: WarpOptions,
    /// Whether `--warp` was given.
    pub given: bool,
}

impl<const OPTIONAL: bool> clap::Args for WarpArgs<OPTIONAL> {
    fn augment_args(cmd: Command) -> Command {
        let names: Vec<&str> = WARPS.iter().map(|w| w.name).collect();
        let mut cmd = cmd.arg(
            Arg::new("warp")
                .long("warp")
                .required(!OPTIONAL)
                .value_parser(PossibleValuesParser::new(names))
                .help(
                    WARPS
                        .iter()
                        .map(|w| format!("{}: {} ({}; seed {})", w.name, w.help, w.formula, w.seed))
                        .collect::<Vec<_>>()
                        .join("\n"),
                ),
        );
        // every flag once, its help naming the warps that take it
        for w in WARPS {
            for p in w.params {
                let takers: Vec<&str> = WARPS
                    .iter()
                    .filter(|o| o.params.iter().any(|q| q.flag == p.flag))
                    .map(|o| o.name)
                    .collect();
                cmd = add(cmd, p, &takers);
            }
        }
        for p in WARP_OPTION_PARAMS {
            cmd = add(cmd, p, &[]);
        }
        cmd
    }
    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

/// `--warp` left out (allowed with `WarpArgs<true>`).
fn name_given_none(m: &ArgMatches) -> bool {
    m.get_one::<String>("warp").is_none()
}

impl<const OPTIONAL: bool> clap::FromArgMatches for WarpArgs<OPTIONAL> {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let given = m.get_one::<String>("warp");
        let name: &str = match given {
            Some(name) => name.as_str(),
            None if OPTIONAL => WARPS[0].name,
            None => return Err(invalid("--warp is required".into())),
        };
        let info = WARPS
            .iter()
            .find(|w| w.name == name)
            .ok_or_else(|| invalid(format!("unknown warp {name}")))?;
        // a flag of another warp is a mistake, not something to ignore
        for other in WARPS {
            for p in other.params {
                let given = m.value_source(id(p)) == Some(clap::parser::ValueSource::CommandLine);
                if given && name_given_none(m) {
                    return Err(invalid(format!(
                        "{} is a warp parameter: give --warp too",
                        p.flag
                    )));
                }
                if given && !info.params.iter().any(|q| q.flag == p.flag) {
                    let takers: Vec<&str> = WARPS
                        .iter()
                        .filter(|o| o.params.iter().any(|q| q.flag == p.flag))
                        .map(|o| o.name)
                        .collect();
                    return Err(invalid(format!(
                        "{} is not a parameter of the {} warp (it is for {}); the {} warp takes {}",
                        p.flag,
                        info.name,
                        takers.join(", "),
                        info.name,
                        info.params
                            .iter()
                            .map(|q| q.flag)
                            .collect::<Vec<_>>()
                            .join(" ")
                    )));
                }
            }
        }
        let mut spec = Map::new();
        spec.insert("kind".into(), Value::from(info.name));
        for p in info.params {
            if let Some(v) = value(m, p) {
                insert(&mut spec, p.key, v);
            }
        }
        let mut obj = Map::new();
        let mut warp = Map::new();
        for p in WARP_OPTION_PARAMS {
            if let Some(v) = value(m, p) {
                if p.key == "base" {
                    warp.insert("base".into(), v);
                } else {
                    insert(&mut obj, p.key, v);
                }
            }
        }
        // --layer-thickness computes the layer height: both given is a contradiction
        let on_line = |key: &str| {
            WARP_OPTION_PARAMS.iter().any(|p| {
                p.key == key
                    && m.value_source(id(p)) == Some(clap::parser::ValueSource::CommandLine)
            })
        };
        if on_line("layer_thickness") && on_line("layer_height") {
            return Err(invalid(
                "give --layer-height (the slicer's vertical layer height) or --layer-thickness (along the tool axis; the layer height is computed from it), not both".into(),
            ));
        }
        if on_line("thickness_at_tilt") && !on_line("layer_thickness") {
            return Err(invalid(
                "--thickness-at-tilt goes with --layer-thickness (it says where that thickness holds)".into(),
            ));
        }
        warp.insert("spec".into(), Value::Object(spec));
        obj.insert("warp".into(), Value::Object(warp));
        let options =
            WarpOptions::from_json_value(Value::Object(obj)).map_err(|e| invalid(e.to_string()))?;
        Ok(WarpArgs {
            options,
            given: given.is_some(),
        })
    }
    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

/// The unwarp step's flags (its own and the machine's, `--machine PRESET|FILE.json`); with
/// `RUN` (for `warpslice run`) without `--offset`, whose flag the warp's `--offset` holds
/// there (the placement is always found in `run`).
#[derive(Debug)]
pub struct UnwarpArgs<const RUN: bool> {
    /// The settings the flags ask for.
    pub settings: UnwarpSettings,
}

fn unwarp_params(run: bool) -> impl Iterator<Item = &'static Param> {
    warpslice::unwarp::PARAMS
        .iter()
        .chain(warpslice::machine::options::PARAMS)
        .filter(move |p| !(run && p.key == "offset"))
}

impl<const RUN: bool> clap::Args for UnwarpArgs<RUN> {
    fn augment_args(cmd: Command) -> Command {
        let mut cmd = cmd;
        for p in unwarp_params(RUN) {
            cmd = add(cmd, p, &[]);
        }
        cmd.arg(
            Arg::new("machine")
                .long("machine")
                .value_name("PRESET|FILE.json")
                .help(format!(
                    "write a 4/5-axis machine's axes: a preset ({}) or a machine JSON file (docs/machines.md)",
                    warpslice::machine::preset_names().join(", ")
                )),
        )
    }
    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

impl<const RUN: bool> clap::FromArgMatches for UnwarpArgs<RUN> {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let mut obj = Map::new();
        for p in unwarp_params(RUN) {
            if let Some(v) = value(m, p) {
                insert(&mut obj, p.key, v);
            }
        }
        if let Some(arg) = m.get_one::<String>("machine") {
            let spec = machine_spec(arg).map_err(invalid)?;
            let v = serde_json::to_value(&spec).map_err(|e| invalid(e.to_string()))?;
            obj.insert("machine".into(), v);
        }
        let settings: UnwarpSettings =
            serde_json::from_value(Value::Object(obj)).map_err(|e| invalid(e.to_string()))?;
        Ok(UnwarpArgs { settings })
    }
    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

/// `warpslice check`'s flags besides the file and `--machine` (`warpslice::check::options::PARAMS`).
#[derive(Debug)]
pub struct CheckArgs {
    /// The options the flags ask for.
    pub options: warpslice::check::CheckOptions,
}

impl clap::Args for CheckArgs {
    fn augment_args(cmd: Command) -> Command {
        let mut cmd = cmd;
        for p in warpslice::check::options::PARAMS {
            cmd = add(cmd, p, &[]);
        }
        cmd
    }
    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

/// The options object the flags of `params` give (each left out takes its default), read by
/// the core's serde type `T`.
pub(crate) fn options_of<'a, T: serde::de::DeserializeOwned>(
    m: &ArgMatches,
    params: impl Iterator<Item = &'a Param>,
) -> Result<T, clap::Error> {
    let mut obj = Map::new();
    for p in params {
        if let Some(v) = value(m, p) {
            insert(&mut obj, p.key, v);
        }
    }
    serde_json::from_value(Value::Object(obj)).map_err(|e| invalid(e.to_string()))
}

impl clap::FromArgMatches for CheckArgs {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let options = options_of(m, warpslice::check::options::PARAMS.iter())?;
        Ok(CheckArgs { options })
    }
    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}
