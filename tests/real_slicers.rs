//! The core issue's acceptance matrix with the real slicers installed on this machine
//! (PrusaSlicer, Slic3r, CuraEngine; `scripts/setup.sh` installs them): for each slicer ×
//! {relative E, absolute E} × the five acceptance warps on the generated parts; and every
//! corpus model marked `accept` × the five warps, each case with one slicer and E mode in
//! turn (so every slicer and E mode meets every model; the full product would take an hour on
//! the 2-core CI machine, dominated by the 100 mm rear case; `WARPSLICE_FULL_MATRIX=1` runs
//! it): warp → slice → unwarp, then
//! checks a–e (tests/common). A warp that the acceptance requires to be refused (the base
//! blend on a model wider than its monotonicity limit) must be refused, naming the limit.
//!
//! A missing slicer fails the test; with `WARPSLICE_ALLOW_SKIP=1` (local runs only) it prints
//! how many cases it skipped and why.
#![cfg(not(target_arch = "wasm32"))]

mod common;

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use warpslice::pipeline::warp_model;
use warpslice::slicer::{self, EMode, SliceOptions, SlicerKind};
use warpslice::unwarp::{unwarp, UnwarpOptions};

/// Threads per test function (the tests themselves run in parallel too).
const THREADS: usize = 1;

fn tmpdir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("warpslice-it-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Run every case; return (passed, failures).
fn matrix(kind: SlicerKind, e_mode: EMode, models: &[(String, Vec<u8>)], tag: &str, rotate: Option<usize>) {
    if models.is_empty() {
        println!("SKIPPED {tag}: no models (../shared/corpus/stl/INDEX.txt not found next to the repository)");
        return;
    }
    if let Err(e) = slicer::available(kind) {
        let n = models.len() * common::acceptance_warps().len();
        if std::env::var("WARPSLICE_ALLOW_SKIP").as_deref() == Ok("1") {
            println!("SKIPPED {n} cases of {kind:?}: {e}");
            return;
        }
        panic!("{kind:?} is needed for this test: {e}");
    }
    let dir = tmpdir(tag);
    let nw = common::acceptance_warps().len();
    // WARPSLICE_FULL_MATRIX=1: every corpus case with every slicer × E mode (≈ 6× longer)
    let rotate = if std::env::var("WARPSLICE_FULL_MATRIX").as_deref() == Ok("1") { None } else { rotate };
    let cases: Vec<(usize, usize)> = (0..models.len())
        .flat_map(|m| (0..nw).map(move |w| (m, w)))
        .filter(|&(m, w)| rotate.is_none_or(|k| (m * nw + w) % COMBOS == k))
        .collect();
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let table = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..THREADS {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(&(mi, wi)) = cases.get(i) else { break };
                let (name, bytes) = &models[mi];
                let (wname, params) = &common::acceptance_warps()[wi];
                let r = run_case(kind, e_mode, bytes, params, &dir.join(format!("{i}")));
                match r {
                    Ok(Err(why)) => table.lock().unwrap().push(format!("{name:40} {wname:15} refused as required: {why}")),
                    Ok(Ok(st)) => table.lock().unwrap().push(format!(
                        "{name:40} {wname:15} pts {:7} layer-dev {:.4} outside {:.3} E out {:.1} expected {:.1} slicer {:.1} (anchor {:.1}) min-z {:.3} clamped {}",
                        st.points, st.worst_layer_distance, st.worst_outside, st.e_out, st.e_expected, st.e_in, st.e_anchor, st.min_z, st.clamped
                    )),
                    Err(e) => failures.lock().unwrap().push(format!("{name} × {wname}: {e}")),
                }
            });
        }
    });
    let _ = std::fs::remove_dir_all(&dir);
    let mut table = table.into_inner().unwrap();
    table.sort();
    println!("{kind:?} {e_mode:?}: {} cases passed", table.len());
    for l in &table {
        println!("  {l}");
    }
    let failures = failures.into_inner().unwrap();
    assert!(failures.is_empty(), "{kind:?} {e_mode:?}: {} of {} cases failed:\n{}", failures.len(), cases.len(), failures.join("\n"));
}

fn run_case(
    kind: SlicerKind,
    e_mode: EMode,
    bytes: &[u8],
    params: &warpslice::warp::WarpParams,
    stem: &std::path::Path,
) -> Result<Result<common::CaseStats, &'static str>, String> {
    let (model, _) = warpslice::mesh::read_stl(bytes).map_err(|e| e.to_string())?;
    let w = warp_model(bytes, &common::warp_options(params));
    if common::must_refuse(params, &model) {
        return match w {
            Err(e) if e.to_string().contains("largest allowed") => Ok(Err("the base blend's limit is named")),
            Err(e) => Err(format!("refused, but without naming the limit: {e}")),
            Ok(_) => Err("the base blend folds the layers over on this model but the warp was not refused".into()),
        };
    }
    let w = w.map_err(|e| format!("warp: {e}"))?;
    let stl = stem.with_extension("stl");
    let gcode = stem.with_extension("gcode");
    std::fs::write(&stl, &w.stl).map_err(|e| e.to_string())?;
    let so = SliceOptions { slicer: kind, e_mode, ..SliceOptions::default() };
    slicer::slice(&stl, &gcode, &so).map_err(|e| format!("slice: {e}"))?;
    let input = std::fs::read(&gcode).map_err(|e| e.to_string())?;
    let out = match unwarp(&input, &w.job, &UnwarpOptions { collect_toolpath: true, ..UnwarpOptions::default() }) {
        Ok(out) => out,
        // a model thinner than a line width: the slicer printed nothing of it, and unwarp
        // must say so by name
        Err(e) if common::object_extrusions(&input) == 0 && e.to_string().contains("no object extrusions") => {
            return Ok(Err("the slicer printed nothing of the model; named error"));
        }
        Err(e) => return Err(format!("unwarp: {e}")),
    };
    let _ = std::fs::remove_file(&stl);
    let _ = std::fs::remove_file(&gcode);
    common::check_unwarp(&model, &w.job, &input, &out).map(Ok)
}

/// Slicer × E-mode combinations the corpus cases rotate through.
const COMBOS: usize = 6;

macro_rules! matrix_tests {
    ($($name:ident: $kind:expr, $mode:expr, $models:expr, $rotate:expr;)*) => {$(
        #[test]
        fn $name() {
            matrix($kind, $mode, &$models, stringify!($name), $rotate);
        }
    )*};
}

matrix_tests! {
    prusaslicer_relative_generated: SlicerKind::PrusaSlicer, EMode::Relative, common::generated_models(), None;
    prusaslicer_absolute_generated: SlicerKind::PrusaSlicer, EMode::Absolute, common::generated_models(), None;
    slic3r_relative_generated: SlicerKind::Slic3r, EMode::Relative, common::generated_models(), None;
    slic3r_absolute_generated: SlicerKind::Slic3r, EMode::Absolute, common::generated_models(), None;
    curaengine_relative_generated: SlicerKind::CuraEngine, EMode::Relative, common::generated_models(), None;
    curaengine_absolute_generated: SlicerKind::CuraEngine, EMode::Absolute, common::generated_models(), None;
    prusaslicer_relative_corpus: SlicerKind::PrusaSlicer, EMode::Relative, common::corpus_accept(), Some(0);
    prusaslicer_absolute_corpus: SlicerKind::PrusaSlicer, EMode::Absolute, common::corpus_accept(), Some(1);
    slic3r_relative_corpus: SlicerKind::Slic3r, EMode::Relative, common::corpus_accept(), Some(2);
    slic3r_absolute_corpus: SlicerKind::Slic3r, EMode::Absolute, common::corpus_accept(), Some(3);
    curaengine_relative_corpus: SlicerKind::CuraEngine, EMode::Relative, common::corpus_accept(), Some(4);
    curaengine_absolute_corpus: SlicerKind::CuraEngine, EMode::Absolute, common::corpus_accept(), Some(5);
}
