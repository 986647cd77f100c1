//! The house's one-way data flow, checked: every `crate::…` path in `src/` (code, not comments)
//! must point to a module on an earlier line of the layer list written in `src/lib.rs`, so the
//! top-level modules form no cycle. The list is read from `lib.rs` itself (the documentation is
//! the rule), and every `pub mod` of `lib.rs` must be on it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const SRC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/src");

/// The layer list: the lines of the ```text block under "## Layers" in lib.rs, each a layer
/// number and module names.
fn layers(lib_rs: &str) -> Result<BTreeMap<String, usize>, String> {
    let start = lib_rs
        .find("## Layers")
        .ok_or("src/lib.rs has no '## Layers' section")?;
    let block = &lib_rs[start..];
    let open = block
        .find("```text")
        .ok_or("no ```text block under ## Layers")?;
    let body = &block[open + 7..];
    let close = body.find("```").ok_or("unclosed ```text block")?;
    let mut out = BTreeMap::new();
    for line in body[..close].lines() {
        let line = line.trim_start_matches("//!").trim();
        let mut words = line.split_whitespace();
        let Some(first) = words.next() else { continue };
        let layer: usize = first
            .parse()
            .map_err(|_| format!("layer line '{line}' does not start with its number"))?;
        for m in words {
            if out.insert(m.to_string(), layer).is_some() {
                return Err(format!("module {m} is listed twice"));
            }
        }
    }
    Ok(out)
}

/// `pub mod x;` / `mod x;` declarations of lib.rs.
fn declared_modules(lib_rs: &str) -> BTreeSet<String> {
    lib_rs
        .lines()
        .map(str::trim)
        .filter(|l| !l.starts_with("//"))
        .filter_map(|l| {
            let l = l.strip_prefix("pub ").unwrap_or(l);
            let name = l.strip_prefix("mod ")?.strip_suffix(';')?;
            Some(name.trim().to_string())
        })
        .collect()
}

/// The code of a file without its `//` comments (doc comments may name any module).
fn code_only(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level modules a piece of code names through `crate::` (incl. `crate::{a, b::c}`).
fn crate_refs(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + 7..];
        if let Some(group) = after.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    out.insert(name);
                }
            }
        } else {
            let name: String = after
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.insert(name);
            }
        }
        rest = after;
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// module → the modules it uses, for every top-level module declared in lib.rs.
fn graph(declared: &BTreeSet<String>) -> BTreeMap<String, BTreeSet<String>> {
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut files = Vec::new();
    rust_files(Path::new(SRC), &mut files);
    for f in files {
        let rel = f.strip_prefix(SRC).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if !declared.contains(&module) {
            continue; // lib.rs itself, the binary's files
        }
        let text = std::fs::read_to_string(&f).unwrap();
        let refs = crate_refs(&code_only(&text));
        let e = g.entry(module.clone()).or_default();
        for r in refs {
            if r != module && declared.contains(&r) {
                e.insert(r);
            }
        }
    }
    g
}

/// Every use that does not go to an earlier layer.
fn violations(
    g: &BTreeMap<String, BTreeSet<String>>,
    layer: &BTreeMap<String, usize>,
) -> Vec<String> {
    let mut v = Vec::new();
    for (m, uses) in g {
        let Some(&lm) = layer.get(m) else {
            v.push(format!("module {m} is not on the layer list in src/lib.rs"));
            continue;
        };
        for u in uses {
            match layer.get(u) {
                Some(&lu) if lu < lm => {}
                Some(&lu) => v.push(format!(
                    "{m} (layer {lm}) uses {u} (layer {lu}): only earlier layers may be used"
                )),
                None => v.push(format!("{u} is not on the layer list")),
            }
        }
    }
    v
}

/// A cycle among the modules, if any (depth-first search).
fn find_cycle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        m: &str,
        g: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(m.to_string(), 1);
        stack.push(m.to_string());
        for u in g.get(m).into_iter().flatten() {
            match state.get(u.as_str()).copied().unwrap_or(0) {
                1 => {
                    let i = stack.iter().position(|s| s == u).unwrap();
                    let mut c = stack[i..].to_vec();
                    c.push(u.clone());
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(u, g, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(m.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in g.keys() {
        if state.get(m.as_str()).copied().unwrap_or(0) == 0 {
            let mut stack = Vec::new();
            if let Some(c) = visit(m, g, &mut state, &mut stack) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn modules_use_only_earlier_layers_and_form_no_cycle() {
    let lib = std::fs::read_to_string(format!("{SRC}/lib.rs")).unwrap();
    let layer = layers(&lib).unwrap();
    let declared = declared_modules(&lib);
    for m in &declared {
        assert!(
            layer.contains_key(m),
            "src/lib.rs declares module {m} but its layer list does not place it"
        );
    }
    let g = graph(&declared);
    assert!(g.len() >= 20, "only {} modules found under src/", g.len());
    let v = violations(&g, &layer);
    assert!(v.is_empty(), "{}", v.join("\n"));
    assert_eq!(find_cycle(&g), None);
}

/// The checker itself catches what it is for: a planted back edge (unwarp → pipeline, the
/// cycle this house once had) is reported both as a layer violation and as a cycle.
#[test]
fn checker_catches_a_planted_cycle() {
    let lib = std::fs::read_to_string(format!("{SRC}/lib.rs")).unwrap();
    let layer = layers(&lib).unwrap();
    let mut g = graph(&declared_modules(&lib));
    assert!(g["pipeline"].contains("unwarp"));
    g.get_mut("unwarp").unwrap().insert("pipeline".into());
    let v = violations(&g, &layer);
    assert!(
        v.iter()
            .any(|s| s.starts_with("unwarp (layer") && s.contains("uses pipeline")),
        "{v:?}"
    );
    let c = find_cycle(&g).expect("the planted cycle is found");
    assert!(c.contains(&"unwarp".to_string()) && c.contains(&"pipeline".to_string()));
}

#[test]
fn crate_paths_are_read_from_code_not_comments() {
    let code = code_only(
        "use crate::{mesh, warp::Warp};\n/// see [`crate::wasm`]\nlet x = crate::num::deg(1.0); // crate::pipeline\n",
    );
    let r = crate_refs(&code);
    assert_eq!(
        r.into_iter().collect::<Vec<_>>(),
        ["mesh", "num", "warp"].map(String::from).to_vec()
    );
}
