//! The core issue's acceptance matrix with the real slicers installed on this machine
//! (PrusaSlicer, Slic3r, CuraEngine; `scripts/setup.sh` installs them) and the built-in planar
//! slicer (`builtin`, issue 14: its default settings, checked exactly like the others): for
//! each slicer × {relative E, absolute E} × the five acceptance warps on the generated parts
//! (each case with one slicer and E mode, in turn: [`Rotate::Generated`]); and every
//! corpus model marked `accept` × the five warps, each
//! case with one slicer and E mode in turn (so every slicer and E mode meets every model; the
//! combinations shift by one each CI run, [`rotation`]), and the typed field on every other
//! corpus model, one case per corpus test ([`Rotate::CorpusWithField`]); the
//! full product, `WARPSLICE_FULL_MATRIX=1`, runs every generated case with every slicer and E
//! mode and all 768 corpus cases (the field on every model), over the suite's budget: see the
//! README for its time):
//! warp → slice → unwarp, then the independent checker of the written G-code
//! (tests/common/check.rs: placement, layer surfaces on vertices and chords, segment length, E
//! per class, travels, retractions, bed) and checks b and e of tests/common. A warp that the acceptance requires to
//! be refused (the base blend on a model wider than its monotonicity limit) must be refused,
//! naming the limit. Identical geometry in two corpus files (ASCII and binary copies) is sliced
//! once per test (see [`SliceCache`]).
//!
//! The machines issue's end-to-end test rides on the same cases: each case is unwarped again
//! with machine presets (three per generated case, two per corpus case, turned round so that
//! every slicer × E mode × warp meets every preset, and every corpus model every preset: see
//! [`Presets`]; the generated parts also with the warps the machines are paired with:
//! cylindrical for the lathe, spherical for the 5-axis head). The machine's extrusions must be
//! the core toolpath's (moved to where the preset places the part), and walking the machine
//! G-code with the forward kinematics must give back every toolpath tip within 0.01 mm and its
//! tool axis, where the machine can realise it, within 0.1° (tests/common/machine.rs, with the
//! tests' own forward kinematics, tests/common/fk.rs). A preset may refuse a case only with a
//! named limit error, and only when the core toolpath holds a pose beyond the machine file's
//! limits (computed in closed form by tests/common/fk.rs); every preset must print at
//! least one case of every matrix test it meets. The interpolation bound, sampled 100 times per
//! move, is checked on one real-slicer file per machine in tests/machine_emit.rs.
//!
//! A missing slicer fails the test; with `WARPSLICE_ALLOW_SKIP=1` (local runs only) it prints
//! how many cases it skipped and why. To reproduce one case: `WARPSLICE_CASES=model:warp,…`
//! (substrings; add `WARPSLICE_FULL_MATRIX=1` for a case outside the rotation) runs only those,
//! saying so, `WARPSLICE_PRESETS=all` (or `=a,b`) unwarps each case with those presets instead
//! of the rotation's, `WARPSLICE_KEEP_FAILED=DIR` keeps a failed machine case's G-code and toolpath, and
//! `WARPSLICE_DEBUG_WALK=1` prints the lines and toolpath points around a machine walk failure.
#![cfg(not(target_arch = "wasm32"))]

mod common;

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use glam::DVec3;
use warpslice::error::Coded;
use warpslice::machine::{preset, preset_names, MachineSpec};

use warpslice::pipeline::warp_model;
use warpslice::pipeline::{unwarp_with_stl, UnwarpSettings};
use warpslice::slicer::{self, EMode, SliceOptions, SlicerKind};
use warpslice::toolpath::ToolPoint;
use warpslice::unwarp::UnwarpOptions;
use warpslice::warp::{WarpParams, WarpSpec};

/// Threads per test function (the tests themselves run in parallel too).
const THREADS: usize = 1;

/// The slicers' bed centre, where PrusaSlicer, Slic3r and CuraEngine (`center_object`, a
/// 200 mm bed) centre the model's bounding box, mm.
const BED_CENTRE: [f64; 2] = [100.0, 100.0];

/// Two line widths of the slicers' 0.4 mm nozzle, mm.
const TWO_LINES: f64 = 0.9;

/// Whether the model's footprint is narrower than two lines in x or y (its own bounding box).
fn narrower_than_two_lines(model: &warpslice::mesh::Mesh) -> bool {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &v in &model.vertices {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (hi.x - lo.x).min(hi.y - lo.y) < TWO_LINES
}

fn tmpdir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("warpslice-it-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// One matrix test: the models, the warps, how the machine presets are chosen, and which of
/// its cases this test runs ([`Rotate`]).
struct Matrix<'a> {
    models: Vec<(String, Vec<u8>)>,
    warps: Vec<(&'a str, WarpParams)>,
    presets: Presets,
    rotate: Rotate,
}

/// Which cases i = m·warps + w of a matrix a test runs (`WARPSLICE_FULL_MATRIX=1`: all). Each
/// case runs with one slicer × E mode of the [`COMBOS`], shifted by the run's rotation r
/// ([`rotation`]): a run covers every case once, and consecutive runs (CI sets r from the code
/// commit count) give each case the next slicer and E mode, so that eight runs meet the
/// whole product.
#[derive(Clone, Copy)]
enum Rotate {
    /// The corpus: (i + r) mod [`COMBOS`] = slot — every model meets five of the eight slicer ×
    /// E-mode slots per run (its five warps), and the models together all of them.
    Corpus(usize),
    /// The generated parts: (m + w + r) mod [`COMBOS`] = slot for part m and warp w — every part
    /// meets every slicer in both E modes in every run (its eight warps), every warp five slots
    /// (three or four slicers) per run and all eight over the rotation. (Until 2026-11-28 each
    /// case ran with one slicer in both E modes: 80 case runs, about half of the matrix's
    /// time; now 40, for the suite's 30-minute budget.)
    Generated(usize),
    /// The corpus with the typed field last among its warps (issue 15: "field warps through
    /// the real-slicer matrix like every other warp, one slicer per model, rotating"): the
    /// other warps as [`Rotate::Corpus`] (i = m·(warps − 1) + w, so their cases keep their
    /// slots), and the field on every other model (m + r even: eight of the sixteen `accept`
    /// models, the other eight in the next run), model m in slot (m + r)/2 mod [`COMBOS`] — one
    /// case per corpus test, each model with one slicer, the slicers rotating over the models.
    /// `WARPSLICE_FULL_MATRIX=1` runs the field on every model with every slicer.
    CorpusWithField(usize),
}

/// The run's rotation r: `WARPSLICE_ROTATION` (a number; `scripts/test.sh` sets it to the
/// count of commits that change src/ or tests/, so each CI run after a code change shifts every
/// case to its next slicer × E mode), else 0.
fn rotation() -> usize {
    std::env::var("WARPSLICE_ROTATION")
        .ok()
        .and_then(|v| v.trim().parse::<usize>().ok())
        .unwrap_or(0)
}

impl Rotate {
    /// Whether case (part `m`, warp `w`) of a matrix with `nw` warps runs at rotation `r`.
    fn runs(self, m: usize, w: usize, nw: usize, r: usize) -> bool {
        match self {
            Rotate::Corpus(slot) => (m * nw + w + r) % COMBOS == slot,
            Rotate::Generated(slot) => (m + w + r) % COMBOS == slot,
            Rotate::CorpusWithField(slot) if w + 1 == nw => {
                (m + r).is_multiple_of(2) && ((m + r) / 2) % COMBOS == slot
            }
            Rotate::CorpusWithField(slot) => Rotate::Corpus(slot).runs(m, w, nw - 1, r),
        }
    }
}

/// How the machine presets of a case are chosen.
#[derive(Clone, Copy)]
enum Presets {
    /// Presets 3i, 3i + 1, 3i + 2 (mod 9) of case i = m·warps + w: for every warp the first
    /// three parts meet all nine, so every slicer × E mode × warp meets every preset.
    ThreeRound,
    /// Presets 2w + m and 2w + m + 1 (mod 9): the five warps of model m meet all nine, so
    /// every corpus model meets every preset.
    TwoByWarp,
}

/// The presets case (model `m`, warp `w`) is unwarped with again (`WARPSLICE_PRESETS=all` or
/// `=a,b` for a local run: those instead, saying so).
fn presets_for(how: Presets, m: usize, w: usize, warps: usize) -> Vec<&'static str> {
    let names = preset_names();
    if let Ok(only) = std::env::var("WARPSLICE_PRESETS") {
        println!("WARPSLICE_PRESETS={only}: these presets instead of the rotation's");
        return names
            .iter()
            .copied()
            .filter(|n| only == "all" || only.split(',').any(|o| o == *n))
            .collect();
    }
    let k = names.len();
    match how {
        Presets::ThreeRound => (0..3)
            .map(|j| names[(3 * (m * warps + w) + j) % k])
            .collect(),
        Presets::TwoByWarp => (0..2).map(|j| names[(2 * w + m + j) % k]).collect(),
    }
}

/// A preset that met at least this many cases of one matrix test must print one of them.
const MIN_CASES_TO_PRINT: usize = 3;

/// Slicer × E-mode combinations the corpus cases rotate through: the three real slicers and
/// the built-in one ([`Slicer`]), each with relative and absolute E.
const COMBOS: usize = 8;

/// The slicer of a matrix test: one of the real slicers installed on this machine, or the
/// core's own planar slicer (issue 14: `builtin`, the matrix's fourth slicer).
#[derive(Clone, Copy)]
enum Slicer {
    Real(SlicerKind),
    Builtin,
}

/// The slicer's name in the matrix's table ("PrusaSlicer", …, "Builtin").
impl std::fmt::Debug for Slicer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Slicer::Real(kind) => write!(f, "{kind:?}"),
            Slicer::Builtin => write!(f, "Builtin"),
        }
    }
}

impl From<SlicerKind> for Slicer {
    fn from(kind: SlicerKind) -> Slicer {
        Slicer::Real(kind)
    }
}

impl Slicer {
    /// Why the slicer cannot run here (the built-in one always can).
    fn unavailable(self) -> Option<String> {
        match self {
            Slicer::Real(kind) => slicer::available(kind).err().map(|e| e.to_string()),
            Slicer::Builtin => None,
        }
    }

    /// Slice the warped STL of `w` (already written to `stl`) into `gcode`.
    fn slice(
        self,
        w: &warpslice::pipeline::WarpOutput,
        stl: &std::path::Path,
        gcode: &std::path::Path,
        e_mode: EMode,
    ) -> Result<(), String> {
        match self {
            Slicer::Real(kind) => {
                let so = SliceOptions {
                    slicer: kind,
                    e_mode,
                    ..SliceOptions::default()
                };
                slicer::slice(stl, gcode, &so)
                    .map(drop)
                    .map_err(|e| format!("slice: {e}"))
            }
            Slicer::Builtin => slice_builtin_case(w, gcode, e_mode),
        }
    }
}

/// The built-in slicer on a case's warped STL: its default settings (PrusaSlicer's 0.45 mm
/// line, centred on [`BED_CENTRE`] like the real slicers), the job's layer height and the
/// case's E mode, written to `gcode`.
fn slice_builtin_case(
    w: &warpslice::pipeline::WarpOutput,
    gcode: &std::path::Path,
    e_mode: EMode,
) -> Result<(), String> {
    let settings = warpslice::planar::Settings {
        layer_height: w.job.layer_height,
        first_layer_height: w.job.layer_height,
        center: BED_CENTRE,
        use_relative_e_distances: e_mode == EMode::Relative,
        ..warpslice::planar::Settings::default()
    };
    let out = warpslice::pipeline::slice_builtin(&w.stl, &w.job, &settings)
        .map_err(|e| format!("slice (builtin): {e}"))?;
    std::fs::write(gcode, out.gcode).map_err(|e| e.to_string())
}

/// Run every case of one matrix test; print the table; fail with every failed case.
fn matrix(kind: impl Into<Slicer>, e_mode: EMode, tag: &str, mx: Matrix<'_>) {
    let kind = kind.into();
    let Matrix {
        models,
        warps,
        presets,
        rotate,
    } = mx;
    let (models, warps) = (&models[..], &warps[..]);
    if models.is_empty() {
        common::skip::skip_or_fail(
            tag,
            "no models (../shared/corpus/stl/INDEX.txt not found next to the repository)",
        );
        return;
    }
    if let Some(e) = kind.unavailable() {
        let n = models.len() * warps.len();
        common::skip::skip_or_fail(&format!("{n} cases of {kind:?}"), &e);
        return;
    }
    let dir = tmpdir(tag);
    let nw = warps.len();
    // WARPSLICE_FULL_MATRIX=1: every corpus case with every slicer × E mode (6× longer, over
    // the suite's budget)
    let full = std::env::var("WARPSLICE_FULL_MATRIX").as_deref() == Ok("1");
    let r = rotation();
    if !full {
        println!("{tag}: rotation {r} (WARPSLICE_ROTATION; WARPSLICE_FULL_MATRIX=1 runs every case with every slicer and E mode)");
    }
    let mut cases: Vec<(usize, usize)> = (0..models.len())
        .flat_map(|m| (0..nw).map(move |w| (m, w)))
        .filter(|&(m, w)| full || rotate.runs(m, w, nw, r))
        .collect();
    // WARPSLICE_CASES="model:warp,…" (local reproduction of one case; substrings): only those
    if let Ok(only) = std::env::var("WARPSLICE_CASES") {
        let all = cases.len();
        let wanted: Vec<(&str, &str)> = only
            .split(',')
            .map(|c| c.split_once(':').unwrap_or((c, "")))
            .collect();
        cases.retain(|&(m, w)| {
            wanted
                .iter()
                .any(|(mm, ww)| models[m].0.contains(mm) && warps[w].0.contains(ww))
        });
        println!(
            "{tag}: WARPSLICE_CASES={only}: running {} of {all} cases (the others were not run)",
            cases.len()
        );
    }
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let table = Mutex::new(Vec::new());
    // the shape check's margin of every accepted case (refused above 0)
    let margins = Mutex::new(Vec::new());
    let machines: Mutex<BTreeMap<&'static str, MachineTally>> = Mutex::new(BTreeMap::new());
    let slices = SliceCache::default();
    std::thread::scope(|s| {
        for _ in 0..THREADS {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(&(mi, wi)) = cases.get(i) else { break };
                let (name, bytes) = &models[mi];
                let (wname, params) = &warps[wi];
                let t0 = std::time::Instant::now();
                let presets = presets_for(presets, mi, wi, nw);
                let case = Case { kind, e_mode, presets, stem: dir.join(format!("{i}")), slices: &slices, label: format!("{name} × {wname}") };
                let r = run_case(&case, bytes, params, &machines);
                let secs = t0.elapsed().as_secs_f64();
                match r {
                    Ok(Err(why)) => table.lock().unwrap().push(format!("{name:40} {wname:15} refused as required: {why} ({secs:.1} s)")),
                    Ok(Ok(st)) => {
                        let c = &st.checked;
                        margins.lock().unwrap().push((st.shape_margin, format!("{name} × {wname}")));
                        table.lock().unwrap().push(format!(
                            "{name:40} {wname:15} pts {:7} reg {:.4} vertex {:.4} chord {:.4} longest {:.3} outside {:.3} E obj {:.1}/{:.1} flat {:.2}/{:.2} slicer {:.1} (anchor {:.1}) travels {} lifted {} clear {:.2} dip {:.3} min-z {:.3} clamped {} shape {:+.3} mm/0 (section {:+.3}; {} beyond, ≤ {}) ({secs:.1} s, slice {:.1} s)",
                            st.points, c.registration_error, c.worst_vertex, c.worst_chord, c.longest, st.worst_outside, c.e_object, c.e_object_expected, c.e_flat, c.e_flat_in, st.e_in, c.e_anchor, c.travels, c.lifted, c.lift_clearance, c.direct_dip, c.min_z, c.clamped, st.shape_margin, st.shape_section_margin.unwrap_or(f64::NAN), st.shape_outliers, warpslice::unwarp::shape::SHAPE_OUTLIERS, st.slice_secs
                        ))
                    }
                    Err(e) => failures.lock().unwrap().push(format!("{name} × {wname}: {e}")),
                }
                for e in machines.lock().unwrap().values_mut().filter_map(|t| t.failure.take()) {
                    failures.lock().unwrap().push(format!("{name} × {wname}: {e}"));
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
    let margins = margins.into_inner().unwrap();
    let lo = margins.iter().min_by(|a, b| a.0.total_cmp(&b.0));
    let hi = margins.iter().max_by(|a, b| a.0.total_cmp(&b.0));
    if let (Some(lo), Some(hi)) = (lo, hi) {
        println!(
            "{kind:?} {e_mode:?}: shape check margin (worst point outside the part less its allowance; refused above 0 mm) over {} cases: min {:+.3} mm ({}), max {:+.3} mm ({})",
            margins.len(),
            lo.0,
            lo.1,
            hi.0,
            hi.1
        );
    }
    let mut failures = failures.into_inner().unwrap();
    let machines = machines.into_inner().unwrap();
    println!("{kind:?} {e_mode:?}: machines (every case unwarped again with each preset)");
    for (name, t) in &machines {
        println!(
            "  {name:20} printed {:3} refused {:3} (named limit, unreachable pose confirmed), {:3} (collision, confirmed): worst tip {:.5} mm, axis {:.4}°, {} points, {} lines",
            t.printed, t.refused, t.collided, t.worst_tip, t.worst_axis, t.points, t.lines
        );
        // a preset that refuses everything at a named limit is broken; one that met only a case or two of this
        // test's rotation (eleven presets share the corpus slots) may have met only poses it
        // cannot reach, each refusal confirmed above, and prints in the generated tests
        // (a case refused by the collision check, confirmed, was written again without the
        // check and walked like a printed one: the default head meeting every cone of a test on
        // PAX or the 3Z bed is not a broken preset)
        if t.printed + t.collided == 0 && t.refused >= MIN_CASES_TO_PRINT && !table.is_empty() {
            failures.push(format!(
                "{name}: printed none of the cases (refused all {} at a named limit)",
                t.refused
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{kind:?} {e_mode:?}: {} failures in {} cases:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

/// Slicer G-code already made in this test, by the warped STL's triangles (the corpus holds the
/// same geometry as ASCII and binary, e.g. the gear wheel: the slicer is deterministic, so the
/// second file's cases reuse the first's slice and still run their own warp, unwarp and checks).
type SliceCache = Mutex<std::collections::HashMap<u64, std::path::PathBuf>>;

/// How one case is run.
struct Case<'a> {
    kind: Slicer,
    e_mode: EMode,
    /// The machine presets this case is unwarped with again.
    presets: Vec<&'static str>,
    stem: std::path::PathBuf,
    slices: &'a SliceCache,
    /// `model × warp`, for the machine outcomes printed per case.
    label: String,
}

/// FNV-1a of the triangles of a binary STL (the 80-byte header, which names the job, aside).
fn triangles_hash(stl: &[u8]) -> u64 {
    warpslice::job::fnv1a64(stl.get(80..).unwrap_or_default())
}

fn run_case(
    case: &Case<'_>,
    bytes: &[u8],
    params: &warpslice::warp::WarpParams,
    machines: &Mutex<BTreeMap<&'static str, MachineTally>>,
) -> Result<Result<common::CaseStats, &'static str>, String> {
    let (kind, e_mode, stem) = (case.kind, case.e_mode, case.stem.as_path());
    let (model, _) = warpslice::mesh::read_stl(bytes).map_err(|e| e.to_string())?;
    let w = warp_model(bytes, &common::warp_options(params));
    if common::must_refuse(params, &model) {
        return match w {
            Err(e) if e.to_string().contains("largest allowed") => {
                Ok(Err("the base blend's limit is named"))
            }
            Err(e) => Err(format!("refused, but without naming the limit: {e}")),
            Ok(_) => Err(
                "the base blend folds the layers over on this model but the warp was not refused"
                    .into(),
            ),
        };
    }
    let w = w.map_err(|e| format!("warp: {e}"))?;
    let stl = stem.with_extension("stl");
    let key = triangles_hash(&w.stl);
    let cached = case.slices.lock().unwrap().get(&key).cloned();
    let t0 = std::time::Instant::now();
    let gcode = match cached {
        Some(g) => g,
        None => {
            let gcode = stem.with_extension("gcode");
            std::fs::write(&stl, &w.stl).map_err(|e| e.to_string())?;
            kind.slice(&w, &stl, &gcode, e_mode)?;
            let _ = std::fs::remove_file(&stl);
            case.slices.lock().unwrap().insert(key, gcode.clone());
            gcode
        }
    };
    let slice_secs = t0.elapsed().as_secs_f64();
    let input = std::fs::read(&gcode).map_err(|e| e.to_string())?;
    let out = match unwarp_with_stl(
        &input,
        &w.job,
        &UnwarpOptions {
            collect_toolpath: true,
            ..UnwarpOptions::default()
        }
        .into(),
        Some(&w.stl),
    ) {
        Ok(out) => out,
        // a model thinner than a line width: the slicer printed nothing of it, and unwarp
        // must say so by name
        Err(e)
            if common::object_extrusions(&input) == 0
                && e.to_string().contains("no object extrusions") =>
        {
            return Ok(Err("the slicer printed nothing of the model; named error"));
        }
        // a part narrower than two lines (the corpus moon, 0.35 mm thick): the slicer prints a
        // line or two that cannot pin the placement to the bead, and unwarp must say so
        Err(e)
            if warpslice::error::Coded::code(&e) == "register.undetermined"
                && narrower_than_two_lines(&model) =>
        {
            return Ok(Err(
                "a part narrower than two lines: placement undetermined, named error",
            ));
        }
        Err(e) => return Err(format!("unwarp: {e}")),
    };
    // a whole file of any of the three slicers ends the print: no "cut short" warning
    // (issue 12 item 10 must not cry wolf)
    if !out.report.warnings.is_empty() {
        return Err(format!(
            "warnings on a whole file: {:?}",
            out.report.warnings
        ));
    }
    // the placement the slicers use, independent of warpslice's registration: the warped STL's
    // box centred on the bed centre (100, 100)
    let c = w.job.warped_bbox.center();
    let (warped, _) = warpslice::mesh::read_stl(&w.stl).map_err(|e| e.to_string())?;
    let defaults = UnwarpOptions::default();
    let expect = common::check::Expect {
        job: &w.job,
        warped: &warped,
        placement: glam::DVec2::new(BED_CENTRE[0] - c.x, BED_CENTRE[1] - c.y),
        max_segment: defaults.max_segment,
        tolerance: defaults.tolerance,
        clearance: defaults.travel_clearance,
    };
    let st = common::check_unwarp(&model, &w.job, &expect, &input, &out)?;
    // net E, and the E deposited by moves (push-backs after retractions left out: the machine
    // file may plan a travel differently, with or without a lift and its retraction)
    let core_e = (
        st.checked.e_totals.0,
        common::written::read(&out.gcode)?.extruded_by_moves(),
    );
    for &name in &case.presets {
        let r = machine_case(
            name,
            &input,
            &w.stl,
            &out.toolpath,
            out.report.model_to_output,
            core_e,
            &expect,
        );
        let mut tally = machines.lock().unwrap();
        let t = tally.entry(name).or_default();
        match r {
            Ok(MachineOutcome::Printed(m, checked)) => {
                println!("  {} × {name}: {checked}", case.label);
                t.printed += 1;
                t.walked(&m);
            }
            Ok(MachineOutcome::Unreachable) => t.refused += 1,
            Ok(MachineOutcome::Collided(m, c)) => {
                println!("  {} × {name}: refused, {c}", case.label);
                t.collided += 1;
                t.walked(&m);
            }
            Err(e) => t.failure = Some(format!("machine {name}: {e}")),
        }
    }
    Ok(Ok(common::CaseStats {
        slice_secs,
        shape_margin: out.report.shape_margin_mm,
        shape_outliers: out.report.shape_outliers,
        shape_section_margin: out.report.shape_section_margin_mm,
        ..st
    }))
}

impl MachineTally {
    /// A machine file walked against the core toolpath (written, or refused by the collision
    /// check and written again without it).
    fn walked(&mut self, m: &common::machine::Measured) {
        self.worst_tip = self.worst_tip.max(m.worst_tip);
        self.worst_axis = self.worst_axis.max(m.worst_axis);
        self.points += m.points;
        self.lines += m.lines;
    }
}

/// What the presets did over a matrix test.
#[derive(Default)]
struct MachineTally {
    printed: usize,
    refused: usize,
    /// Refused by the collision check, the first finding confirmed by the independent helper.
    collided: usize,
    worst_tip: f64,
    worst_axis: f64,
    points: usize,
    lines: usize,
    /// This case's failure (taken by the matrix loop after each case).
    failure: Option<String>,
}

/// Where a preset wants the part: machines whose rotations are about fixed lines get it there
/// (`--place`); the lathe's mandrel under the part, as the cylindrical warp's axis.
fn machine_setup(name: &str) -> (MachineSpec, Option<[f64; 2]>) {
    let mut spec = preset(name).expect("preset");
    if let warpslice::machine::spec::Kinematics::LatheA(p) = &mut spec.kinematics {
        p.axis_z_mm = -MANDREL_RADIUS;
    }
    let place = match name {
        "open5x-ab" | "open5x-prusa-uv" | "open5x-jubilee-bc" | "lathe-a" => Some([0.0, 0.0]),
        // off the polar centre (its singular point)
        "core-r-theta" => Some([60.0, 0.0]),
        _ => None,
    };
    (spec, place)
}

/// Unwarp `input` again with the preset `name` and walk its G-code against the core toolpath
/// (`core_m2o`: the core run's model_to_output; `expect`: the case, its job included).
/// `Unreachable`: refused with a named limit, and the core toolpath confirms a pose out of
/// reach; `Collided`: refused by the collision check, confirmed ([`confirm_collision`]).
fn machine_case(
    name: &str,
    input: &[u8],
    stl: &[u8],
    core: &[ToolPoint],
    core_m2o: [f64; 3],
    core_e: (f64, f64),
    expect: &common::check::Expect<'_>,
) -> Result<MachineOutcome, String> {
    let (spec, place) = machine_setup(name);
    // the machine file's kinematics and limits, in the tests' own closed forms
    let limits = common::machine::fk::Limits::from_spec(&spec)?;
    let axis_names = spec.axis_names().map_err(|e| e.to_string())?;
    // the core toolpath (slicer placement) moved to the preset's placement
    let shift = place.map_or(DVec3::ZERO, |[x, y]| {
        DVec3::new(x - core_m2o[0], y - core_m2o[1], 0.0)
    });
    let opts = UnwarpSettings::with_machine(
        UnwarpOptions {
            collect_toolpath: true,
            place,
            ..UnwarpOptions::default()
        },
        spec.clone(),
    );
    // refused by the collision check: the finding confirmed, and the same file written
    // without the check is walked below like a written one (the user's `--allow-collisions`
    // file: its path must be exact too)
    let (out, collided) = match unwarp_with_stl(input, expect.job, &opts, Some(stl)) {
        Ok(out) => (out, None),
        Err(e) if e.code() == "machine.collision" => {
            let (out, why) = confirm_collision(&e, &spec, &opts, input, expect.job, stl)?;
            (out, Some(why))
        }
        Err(e) => {
            let text = e.to_string();
            if !(text.contains("cannot be reached") || text.contains("outside its travel")) {
                return Err(format!("refused without a named limit: {text}"));
            }
            // independently: some pose of the core toolpath is beyond the machine file's limits
            // (tilt, rotary travel, reach, rails, linear travel: common::machine::fk::Limits) —
            // its travels too (a lifted travel over a tall part on the tilted triple-Z bed
            // takes a Z motor past its travel: PrusaSlicer rear case × conic-out-30), unless
            // the part is placed elsewhere (then the travels from the start G-code differ)
            let unreachable = core
                .iter()
                .filter(|t| !t.travel || place.is_none())
                .any(|t| limits.out_of_reach(t.p + shift, t.n).is_some());
            return if unreachable {
                Ok(MachineOutcome::Unreachable)
            } else {
                Err(format!(
                    "refused ({text}) although every pose of the toolpath is within the machine file's limits"
                ))
            };
        }
    };
    // the collision check is on by default: a written file passed it (or says why not)
    let checked = match collided {
        None => Ok(collision_clean(&out.report)?),
        Some(why) => Err(why),
    };
    let m2o = DVec3::from_array(out.report.model_to_output);
    if (m2o - DVec3::from_array(core_m2o) - shift).length() > 1e-9 {
        return Err(format!(
            "model_to_output {m2o} is not the core's {core_m2o:?} moved by {shift}"
        ));
    }
    // the machine's extrusions are the core toolpath's, moved by the placement (travels may
    // differ: a placed part starts with a travel from where the start G-code left the head)
    let ext = |t: &[ToolPoint]| t.iter().filter(|t| !t.travel).cloned().collect::<Vec<_>>();
    let (got, want) = (ext(&out.toolpath), ext(core));
    if got.len() != want.len() {
        return Err(format!(
            "{} extrusion points, the core toolpath has {}",
            got.len(),
            want.len()
        ));
    }
    let differs = |(a, b): &(&ToolPoint, &ToolPoint)| {
        (a.p - (b.p + shift)).length() > 1e-9 || a.n != b.n || a.e != b.e || a.layer != b.layer
    };
    if let Some((i, (a, b))) = got
        .iter()
        .zip(&want)
        .enumerate()
        .find(|(_, ab)| differs(ab))
    {
        return Err(format!(
            "extrusion point {i} differs from the core's: {a:?} vs {b:?} (+ {shift})"
        ));
    }
    // the written E (read with the tests' own reader: absolute or relative, G92 E, E shared
    // across tessellated pieces) is the 3-axis file's: net, and deposited by moves (a travel
    // planned differently adds or drops a retraction and its push-back: one lift fewer on
    // open5x-ab, CuraEngine ps_shape_cylinder × conic-in-30, with the part placed at 0,0),
    // within the 5-decimal rounding
    let written = common::written::read(&out.gcode)?;
    let e = (written.e_totals().0, written.extruded_by_moves());
    for (what, got, want) in [("net", e.0, core_e.0), ("extruded", e.1, core_e.1)] {
        if (got - want).abs() > MACHINE_E_TOLERANCE * want.abs().max(1.0) {
            return Err(format!(
                "{what} E written {got:.5} mm, the 3-axis file's {want:.5} mm"
            ));
        }
    }
    if name == "cartesian" {
        // the preset's file is 3-axis G-code: the independent checker reads it as written
        if place.is_none() {
            common::check::check(expect, input, &out.gcode)
                .map_err(|e| format!("the cartesian preset's file: {e}"))?;
        }
        return Ok(outcome(
            common::machine::Measured {
                points: core.len(),
                ..Default::default()
            },
            checked,
        ));
    }
    let text = String::from_utf8(out.gcode).map_err(|e| e.to_string())?;
    let lines = common::machine::parse(&text, &axis_names)?;
    let r = common::machine::check(&spec, &out.toolpath, &lines, 0);
    // WARPSLICE_KEEP_FAILED=DIR (local reproduction): the failed case's machine G-code and
    // toolpath are kept there
    if r.is_err() {
        keep_failed(name, &text, &out.toolpath);
    }
    r.map(|m| outcome(m, checked))
}

/// WARPSLICE_KEEP_FAILED=DIR (local reproduction): a failed case's machine G-code and toolpath
/// are kept there as `<preset>.gcode` and `<preset>.toolpath`.
fn keep_failed(name: &str, gcode: &str, toolpath: &[ToolPoint]) {
    if let Ok(dir) = std::env::var("WARPSLICE_KEEP_FAILED") {
        let stem = std::path::Path::new(&dir).join(name);
        let tp: Vec<String> = toolpath.iter().map(|t| format!("{t:?}")).collect();
        let kept = std::fs::create_dir_all(&dir)
            .and_then(|()| std::fs::write(stem.with_extension("gcode"), gcode))
            .and_then(|()| std::fs::write(stem.with_extension("toolpath"), tp.join("\n")));
        println!("{name}: failed case kept in {dir}: {kept:?}");
    }
}

/// A walked machine file's outcome: written (`Ok`: how the check went) or refused by the
/// collision check with its finding confirmed (`Err`: what was confirmed).
fn outcome(m: common::machine::Measured, checked: Result<String, String>) -> MachineOutcome {
    match checked {
        Ok(c) => MachineOutcome::Printed(m, c),
        Err(c) => MachineOutcome::Collided(m, c),
    }
}

/// What a preset did with a case.
enum MachineOutcome {
    /// Written; how the collision check went (clean, or why it did not run).
    Printed(common::machine::Measured, String),
    /// Refused with a named limit, a pose out of reach confirmed.
    Unreachable,
    /// Refused by the collision check, its first finding confirmed independently; the file
    /// written without the check walked like a written one.
    Collided(common::machine::Measured, String),
}

/// A written machine file passed the collision check (on by default): it ran and found
/// nothing, or the machine is one the check cannot judge and the report says so.
fn collision_clean(report: &warpslice::unwarp::UnwarpReport) -> Result<String, String> {
    let m = report.machine.as_ref().ok_or("no machine report")?;
    if m.collisions_checked {
        return match m.collisions.first() {
            None => Ok("clean (collision check: 0 findings)".into()),
            Some(f) => Err(format!("written with a collision finding: {f:?}")),
        };
    }
    report
        .warnings
        .iter()
        .find(|w| w.contains("collision check was not run"))
        .map(|w| format!("written, not checked: {w}"))
        .ok_or("written without the collision check (on by default) and without saying why".into())
}

/// The collision check (on by default) refused the file (`refusal`, `machine.collision`, its
/// first finding in it): the same file written without the check (`check_collisions: false`:
/// the moves are the same, the check only reads them; cheaper in the matrix than the full
/// listing of `allow_collisions`, which `tests/collision_check.rs` compares with the refusal)
/// and the finding confirmed by the independent helper (tests/common/collide.rs: the tests'
/// kinematics, bead points, the head's solids) on the same output line, the part in the same
/// obstacle, the depths within [`common::collide::DEPTH_TOLERANCE_MM`].
fn confirm_collision(
    refusal: &warpslice::pipeline::Error,
    spec: &MachineSpec,
    opts: &UnwarpSettings,
    input: &[u8],
    job: &warpslice::job::Job,
    stl: &[u8],
) -> Result<(warpslice::unwarp::UnwarpOutput, String), String> {
    let (f, total) = match refusal {
        warpslice::pipeline::Error::Machine(warpslice::machine::MachineError::Collision {
            finding,
            total,
            ..
        }) => (finding.as_ref().clone(), *total),
        other => return Err(format!("machine.collision without its finding: {other:?}")),
    };
    let mut unchecked = opts.clone();
    unchecked.output.check_collisions = false;
    let out = unwarp_with_stl(input, job, &unchecked, Some(stl))
        .map_err(|e| format!("refused ({refusal}), and without the check: {e}"))?;
    if !refusal
        .to_string()
        .contains(&format!("output line {} ", f.line))
    {
        return Err(format!(
            "the refusal ({refusal}) does not name its finding's line {}",
            f.line
        ));
    }
    let text = String::from_utf8_lossy(&out.gcode).into_owned();
    let (f, c, first) = match common::collide::confirm_or_miss(
        spec,
        &text,
        f.line as usize,
        &f.part,
        &f.obstacle,
    ) {
        Ok(c) => (f, c, String::new()),
        // shallower than the helper can see on that move: a deeper finding of the whole
        // listing (allow_collisions) is confirmed instead, or said to be below it too
        Err(m) if f.depth_mm <= m.unseen_mm => {
            let first = format!(
                "the first finding, line {} (input line {}), layer {}, {} into {}, {:.3} mm, is below the helper's resolution there ({:.3} mm: {}); ",
                f.line,
                f.input_line.map_or("-".into(), |l| l.to_string()),
                f.layer,
                f.part,
                f.obstacle,
                f.depth_mm,
                m.unseen_mm,
                m.why
            );
            let mut listing = opts.clone();
            listing.output.allow_collisions = true;
            let all = unwarp_with_stl(input, job, &listing, Some(stl))
                .map_err(|e| format!("refused ({refusal}), and with allow_collisions: {e}"))?;
            // the first finding twice as deep as the helper's resolution on the first's move
            // (early in the file: the helper walks the file up to it), else the deepest
            let listed = all
                .report
                .machine
                .as_ref()
                .map_or(&[][..], |m| &m.collisions[..]);
            let deepest = listed
                .iter()
                .find(|g| g.depth_mm > 2.0 * m.unseen_mm)
                .or_else(|| {
                    listed
                        .iter()
                        .max_by(|a, b| a.depth_mm.total_cmp(&b.depth_mm))
                })
                .ok_or(format!(
                    "refused ({refusal}), but allow_collisions lists no finding"
                ))?
                .clone();
            match common::collide::confirm_or_miss(spec, &text, deepest.line as usize, &deepest.part, &deepest.obstacle) {
                Ok(c) => (deepest, c, first),
                Err(d) if deepest.depth_mm <= d.unseen_mm => {
                    return Ok((out, format!(
                        "NOT re-found, below the helper's resolution: {first}the next, line {}, {:.3} mm, too ({:.3} mm: {})",
                        deepest.line, deepest.depth_mm, d.unseen_mm, d.why
                    )))
                }
                Err(d) => {
                    keep_failed(&spec.name, &text, &out.toolpath);
                    return Err(format!(
                        "refused ({refusal}): {first}the next finding, line {} ({} into {}, {:.3} mm), is not confirmed independently: {}",
                        deepest.line, deepest.part, deepest.obstacle, deepest.depth_mm, d.why
                    ));
                }
            }
        }
        Err(m) => {
            keep_failed(&spec.name, &text, &out.toolpath);
            return Err(format!(
                "refused ({refusal}), not confirmed independently: {}",
                m.why
            ));
        }
    };
    // a box checked as its enclosing cylinder (no head frame in the helper for this machine)
    // is a larger solid: its depth bounds the checker's from above only
    let short = f.depth_mm - c.depth_mm > common::collide::DEPTH_TOLERANCE_MM;
    let over = c.depth_mm - f.depth_mm > common::collide::DEPTH_TOLERANCE_MM && !c.enclosing;
    if short || over {
        return Err(format!(
            "refused ({refusal}): the helper finds the {} in the {} on line {} but {:.3} mm deep, the checker {:.3} mm",
            f.part, f.obstacle, f.line, c.depth_mm, f.depth_mm
        ));
    }
    let why = format!(
        "confirmed: at least {total} finding(s); {first}line {} (input line {}), layer {}, {} into {}: checker {:.3} mm, helper {:.3} mm{}",
        f.line,
        f.input_line.map_or("-".into(), |l| l.to_string()),
        f.layer,
        f.part,
        f.obstacle,
        f.depth_mm,
        c.depth_mm,
        if c.enclosing { " (boxes as enclosing cylinders)" } else { "" }
    );
    Ok((out, why))
}

/// A machine file's total E vs the 3-axis file's, relative: both write E with 5 decimals and
/// carry the rounding (absolute E, or the relative remainder), so they agree to ~1e-5 mm per
/// line; 1e-4 of the total catches any scaling or a lost piece.
const MACHINE_E_TOLERANCE: f64 = 1e-4;

/// Radius of the mandrel of the cylindrical warp cases (the lathe's axis is there), mm.
const MANDREL_RADIUS: f64 = 20.0;

/// The generated parts' warps: the acceptance five, the machines' pairings and a typed field
/// (issue 15).
fn generated_warps() -> Vec<(&'static str, WarpParams)> {
    let mut w = common::acceptance_warps();
    w.push(common::acceptance::field_ripple());
    w.push((
        "cylindrical-20",
        WarpParams {
            spec: WarpSpec::Cylindrical {
                radius: MANDREL_RADIUS,
                axis: [0.0, -MANDREL_RADIUS],
            },
            base: None,
        },
    ));
    w.push((
        "spherical-20",
        WarpParams {
            spec: WarpSpec::Spherical {
                radius: 20.0,
                center: [0.0, 0.0, -20.0],
            },
            base: None,
        },
    ));
    w
}

/// The generated parts for slicer × E-mode slot `slot` (0–7, as the corpus's).
fn generated<'a>(slot: usize) -> Matrix<'a> {
    Matrix {
        models: common::generated_models(),
        warps: generated_warps(),
        presets: Presets::ThreeRound,
        rotate: Rotate::Generated(slot),
    }
}

/// The corpus for slicer × E-mode slot `slot` (0–7): the acceptance warps and, last, the
/// typed field ([`Rotate::CorpusWithField`]).
fn corpus<'a>(slot: usize) -> Matrix<'a> {
    let mut warps = common::acceptance_warps();
    warps.push(common::acceptance::field_ripple());
    Matrix {
        models: common::corpus_accept(),
        warps,
        presets: Presets::TwoByWarp,
        rotate: Rotate::CorpusWithField(slot),
    }
}

macro_rules! matrix_tests {
    ($($name:ident: $kind:expr, $mode:expr, $matrix:expr;)*) => {$(
        #[test]
        fn $name() {
            matrix($kind, $mode, stringify!($name), $matrix);
        }
    )*};
}

matrix_tests! {
    prusaslicer_relative_generated: SlicerKind::PrusaSlicer, EMode::Relative, generated(0);
    prusaslicer_absolute_generated: SlicerKind::PrusaSlicer, EMode::Absolute, generated(1);
    slic3r_relative_generated: SlicerKind::Slic3r, EMode::Relative, generated(2);
    slic3r_absolute_generated: SlicerKind::Slic3r, EMode::Absolute, generated(3);
    curaengine_relative_generated: SlicerKind::CuraEngine, EMode::Relative, generated(4);
    curaengine_absolute_generated: SlicerKind::CuraEngine, EMode::Absolute, generated(5);
    prusaslicer_relative_corpus: SlicerKind::PrusaSlicer, EMode::Relative, corpus(0);
    prusaslicer_absolute_corpus: SlicerKind::PrusaSlicer, EMode::Absolute, corpus(1);
    slic3r_relative_corpus: SlicerKind::Slic3r, EMode::Relative, corpus(2);
    slic3r_absolute_corpus: SlicerKind::Slic3r, EMode::Absolute, corpus(3);
    curaengine_relative_corpus: SlicerKind::CuraEngine, EMode::Relative, corpus(4);
    curaengine_absolute_corpus: SlicerKind::CuraEngine, EMode::Absolute, corpus(5);
    builtin_relative_generated: Slicer::Builtin, EMode::Relative, generated(6);
    builtin_absolute_generated: Slicer::Builtin, EMode::Absolute, generated(7);
    builtin_relative_corpus: Slicer::Builtin, EMode::Relative, corpus(6);
    builtin_absolute_corpus: Slicer::Builtin, EMode::Absolute, corpus(7);
}
