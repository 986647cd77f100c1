//! The CLI's warp and unwarp flags are the core's parameter schema (`describe`): every
//! parameter appears as its flag with its default, a flag of another warp is refused, and a
//! parameter left out takes the schema's default in the job the CLI writes.

use std::process::Command;

use warpslice::schema::{Param, ParamDefault};

fn cli(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .args(args)
        .output()
        .expect("run warpslice");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn default_text(p: &Param) -> Option<String> {
    let list = |v: &[f64]| v.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
    match p.default {
        ParamDefault::None => None,
        ParamDefault::Number(v) => Some(v.to_string()),
        ParamDefault::Text(t) => Some(t.to_string()),
        ParamDefault::Bool(b) => Some(b.to_string()),
        ParamDefault::Pair(v) => Some(list(&v)),
        ParamDefault::Triple(v) => Some(list(&v)),
    }
}

/// The help line of `flag` in a `--help` text.
fn line_of<'a>(help: &'a str, flag: &str) -> Option<&'a str> {
    help.lines()
        .find(|l| l.trim_start().starts_with(&format!("{flag} ")))
}

#[test]
fn every_schema_parameter_is_a_flag_with_its_default() {
    let d = warpslice::describe::describe().unwrap();
    let (ok, warp_help, _) = cli(&["warp", "--help"]);
    assert!(ok);
    let (ok, unwarp_help, _) = cli(&["unwarp", "--help"]);
    assert!(ok);
    let (ok, run_help, _) = cli(&["run", "--help"]);
    assert!(ok);
    let mut checked = 0;
    let warp_params = d
        .warps
        .iter()
        .flat_map(|w| w.params.iter())
        .chain(d.warp_options);
    for (p, helps) in warp_params.map(|p| (p, [&warp_help, &run_help])).chain(
        d.unwarp_options
            .iter()
            .map(|p| (p, [&unwarp_help, &run_help])),
    ) {
        for (i, h) in helps.iter().enumerate() {
            // `run` finds the placement itself: its --offset is the warp's (a number)
            let unwarp_offset = p.key == "offset" && p.ty == warpslice::schema::ParamType::Pair;
            if i == 1 && unwarp_offset {
                continue;
            }

