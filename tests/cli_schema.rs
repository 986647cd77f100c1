//! The CLI's warp and unwarp flags are the core's parameter schema (`describe`): every
//! parameter appears as its flag with its default, a flag of another warp is refused, and a
//! parameter left out takes the schema's default in the job the CLI writes.
#![cfg(not(target_arch = "wasm32"))] // native only: files, processes and the real slicers

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

            let line =
                line_of(h, p.flag).unwrap_or_else(|| panic!("{} missing from:\n{h}", p.flag));
            if let Some(t) = default_text(p) {
                // the help of a flag may wrap onto the next lines, up to the next flag (the
                // flag where it starts a line: another flag's help may name it)
                let text = h
                    .split(&format!("\n      {} ", p.flag))
                    .nth(1)
                    .and_then(|rest| rest.split("\n      --").next())
                    .unwrap_or_default();
                assert!(
                    text.contains(&format!("[default: {t}]")),
                    "{}: default {t} not in '{line}…'",
                    p.flag
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 40, "{checked}");
    for w in d.warps {
        assert!(warp_help.contains(w.formula), "{}", w.name);
    }
}

#[test]
fn a_flag_of_another_warp_is_refused() {
    let dir = std::env::temp_dir().join(format!("warpslice-cli-schema-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stl = dir.join("cube.stl");
    assert!(cli(&["example", "cube", "-o", stl.to_str().unwrap()]).0);
    let out = dir.join("w.stl");
    let (ok, _, err) = cli(&[
        "warp",
        stl.to_str().unwrap(),
        "--warp",
        "curved",
        "--angle",
        "45",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("--angle is not a parameter of the curved warp (it is for conic, belt)"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
}

#[test]
fn parameters_left_out_take_the_schema_defaults() {
    let dir = std::env::temp_dir().join(format!("warpslice-cli-defaults-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stl = dir.join("cube.stl");
    assert!(cli(&["example", "cube", "-o", stl.to_str().unwrap()]).0);
    for (warp, want) in [
        (
            "spherical",
            r#"{"kind":"spherical","radius":10.0,"center":[0.0,0.0,-10.0]}"#,
        ),
        (
            "cylindrical",
            r#"{"kind":"cylindrical","radius":10.0,"axis":[0.0,-10.0]}"#,
        ),
        (
            "conic",
            r#"{"kind":"conic","angle":30.0,"direction":"outward","center":[0.0,0.0]}"#,
        ),
        ("belt", r#"{"kind":"belt","angle":30.0,"toward":[0.0,1.0]}"#),
    ] {
        let out = dir.join(format!("{warp}.stl"));
        let (ok, _, err) = cli(&[
            "warp",
            stl.to_str().unwrap(),
            "--warp",
            warp,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{warp}: {err}");
        let text = std::fs::read_to_string(dir.join(format!("{warp}.job.json"))).unwrap();
        let job: serde_json::Value = serde_json::from_str(&text).unwrap();
        let want: serde_json::Value = serde_json::from_str(want).unwrap();
        assert_eq!(job["warp"]["spec"], want, "{warp}");
    }
}

#[test]
fn every_check_parameter_is_a_flag_of_check_with_its_default() {
    let d = warpslice::describe::describe().unwrap();
    let (ok, help, _) = cli(&["check", "--help"]);
    assert!(ok);
    assert!(!d.check_options.is_empty());
    for p in d.check_options {
        let line =
            line_of(&help, p.flag).unwrap_or_else(|| panic!("{} missing from:\n{help}", p.flag));
        assert!(
            line.contains(p.help.split(':').next().unwrap_or(p.help)),
            "{line}"
        );
        if let Some(t) = default_text(p) {
            let text = help
                .split(&format!("{} ", p.flag))
                .nth(1)
                .and_then(|rest| rest.split("\n      --").next())
                .unwrap_or_default();
            assert!(
                text.contains(&format!("[default: {t}]")),
                "{}: {text}",
                p.flag
            );
        }
    }
    for flag in ["--machine", "--json"] {
        assert!(
            line_of(&help, flag).is_some(),
            "{flag} missing from:\n{help}"
        );
    }
}

/// The flags of `suggest`, `overhangs` and `warp --suggested` are the core's `suggest::PARAMS`
/// (`describe().suggest_options`), each with its default.
#[test]
fn every_suggest_parameter_is_a_flag_of_suggest_with_its_default() {
    let d = warpslice::describe::describe().unwrap();
    assert!(!d.suggest_options.is_empty());
    let (ok, suggest_help, _) = cli(&["suggest", "--help"]);
    assert!(ok);
    let (ok, overhangs_help, _) = cli(&["overhangs", "--help"]);
    assert!(ok);
    let (ok, warp_help, _) = cli(&["warp", "--help"]);
    assert!(ok);
    for p in d.suggest_options {
        let mut helps = vec![&suggest_help];
        if p.key == "overhang_angle" {
            helps.extend([&overhangs_help, &warp_help]);
        }
        if p.key == "families" {
            helps.push(&warp_help);
        }
        for h in helps {
            let text = h
                .split(&format!("{} ", p.flag))
                .nth(1)
                .and_then(|rest| rest.split("\n      --").next())
                .unwrap_or_else(|| panic!("{} missing from:\n{h}", p.flag));
            if let Some(t) = default_text(p) {
                assert!(
                    text.contains(&format!("[default: {t}]")),
                    "{}: {text}",
                    p.flag
                );
            }
        }
    }
    for flag in ["--machine", "--json"] {
        assert!(line_of(&suggest_help, flag).is_some(), "{flag}");
    }
    for flag in ["--suggested", "--machine"] {
        assert!(line_of(&warp_help, flag).is_some(), "{flag}");
    }
}

/// `suggest --json` is an array, best first, of objects with `flags` and
/// `overhang_area_mm2`; `warp --suggested 1` writes the job of the first one's warp, and
/// `warp` with its flags writes the same warp.
#[test]
fn suggest_json_lists_flags_that_warp_accepts_and_suggested_applies_them() {
    let dir = std::env::temp_dir().join(format!("warpslice-cli-suggest-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stl = dir.join("part.stl");
    let s = stl.to_str().unwrap();
    assert!(cli(&["example", "overhang", "-o", s]).0);
    let (ok, out, err) = cli(&[
        "suggest",
        s,
        "--machine",
        "pax-5axis",
        "--top",
        "3",
        "--json",
    ]);
    assert!(ok, "{err}");
    let list: serde_json::Value = serde_json::from_str(&out).unwrap();
    let list = list.as_array().expect("an array");
    assert!(!list.is_empty() && list.len() <= 3, "{out}");
    let areas: Vec<f64> = list
        .iter()
        .map(|e| e["overhang_area_mm2"].as_f64().expect("overhang_area_mm2"))
        .collect();
    assert!(
        areas.windows(2).all(|w| w[0] <= w[1]),
        "not best first: {areas:?}"
    );
    let flags = list[0]["flags"].as_str().expect("flags").to_string();
    let by_n = dir.join("by-n.stl");
    let (ok, _, err) = cli(&[
        "warp",
        s,
        "--suggested",
        "1",
        "--machine",
        "pax-5axis",
        "-o",
        by_n.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let by_flags = dir.join("by-flags.stl");
    let mut args = vec!["warp", s];
    args.extend(flags.split_whitespace());
    args.extend(["-o", by_flags.to_str().unwrap()]);
    let (ok, _, err) = cli(&args);
    assert!(ok, "{flags}: {err}");
    let job = |p: &std::path::Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p.with_extension("job.json")).unwrap())
            .unwrap()
    };
    assert_eq!(job(&by_n)["warp"], job(&by_flags)["warp"], "{flags}");
    assert_eq!(job(&by_n)["warp"]["spec"], list[0]["warp"]["spec"]);
    // out of the list: a named error
    let (ok, _, err) = cli(&[
        "warp",
        s,
        "--suggested",
        "99",
        "--machine",
        "pax-5axis",
        "-o",
        by_n.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("--suggested 99"), "{err}");
    // `overhangs --json` has a flag per facet, planar and warped
    let mut args = vec!["overhangs", s, "--json"];
    args.extend(flags.split_whitespace());
    let (ok, out, err) = cli(&args);
    assert!(ok, "{err}");
    let r: serde_json::Value = serde_json::from_str(&out).unwrap();
    let n = r["triangles"].as_u64().unwrap() as usize;
    assert_eq!(r["planar_facets"].as_array().unwrap().len(), n);
    assert_eq!(r["warped_facets"].as_array().unwrap().len(), n);
    assert!(
        (r["warped"]["area_mm2"].as_f64().unwrap() - areas[0]).abs() < 1e-9,
        "{out}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
