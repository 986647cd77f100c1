//! Compiles every machine preset in `presets/*.json` into the crate (so presets work in wasm,
//! with no filesystem): writes `$OUT_DIR/presets.rs` with `PRESETS: &[(&str, &str)]`, the
//! file stem and the JSON text, in name order. A new preset is a new file; nothing to register.

use std::path::Path;

fn main() {
    // read at run time (cargo sets it for the build script): a build script compiled in another
    // checkout sharing the target directory must not read that checkout's presets
    let root = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let dir = Path::new(&root).join("presets");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("presets/ is part of the crate")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .collect();
    names.sort();
    let mut out = String::from("/// The presets in `presets/` (name, JSON text), in name order.\n");
    out.push_str("const PRESETS: &[(&str, &str)] = &[\n");
    for n in &names {
        println!(
            "cargo:rerun-if-changed={}",
            dir.join(format!("{n}.json")).display()
        );
        out.push_str(&format!(
            "    ({n:?}, include_str!(concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/presets/{n}.json\"))),\n"
        ));
    }
    out.push_str("];\n");
    let dest = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("presets.rs");
    std::fs::write(dest, out).expect("OUT_DIR is writable");
}
