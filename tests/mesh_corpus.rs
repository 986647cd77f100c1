//! The real-model corpus (`../shared/corpus/stl`, third-party, not in the repository):
//! every `accept` model loads with exactly the triangle / open / non-manifold / degenerate
//! counts and bounding box listed in INDEX.txt; every `broken/` model gives a named error or
//! loads with its defect reported; nothing panics. Skipped (with a printed reason) when the
//! corpus is absent.
#![cfg(not(target_arch = "wasm32"))] // native only: proptest, files and processes

use std::path::PathBuf;

#[path = "common/skip.rs"]
mod skip;

use warpslice::mesh::{read_stl, MeshError, MeshReport, StlFormat};

/// Bounding boxes in INDEX.txt are printed with two decimals.
const BBOX_TOLERANCE: f64 = 0.01;

fn corpus_dir() -> Option<PathBuf> {
    let rel = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/stl");
    [rel, PathBuf::from("/work/shared/corpus/stl")]
        .into_iter()
        .find(|d| d.join("INDEX.txt").is_file())
}

#[derive(Debug)]
struct Entry {
    file: String,
    format: String,
    triangles: usize,
    /// (min, max), absent for files listed without counts
    bbox: Option<([f64; 3], [f64; 3])>,
    open: Option<usize>,
    nonmanifold: Option<usize>,
    degenerate: Option<usize>,
    accept: bool,
}

fn triple(s: &str) -> [f64; 3] {
    let v: Vec<f64> = s
        .trim_matches(['[', ']'])
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

fn count(cols: &[&str], key: &str) -> Option<usize> {
    cols.iter()
        .find_map(|c| c.strip_prefix(key))
        .map(|v| v.parse().unwrap())
}

fn entries(dir: &std::path::Path) -> Vec<Entry> {
    let text = std::fs::read_to_string(dir.join("INDEX.txt")).unwrap();
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let cols: Vec<&str> = l.split('\t').collect();
            let bbox = cols
                .get(3)
                .and_then(|b| b.split_once(".."))
                .map(|(a, b)| (triple(a), triple(b)));
            Entry {
                file: cols[0].to_string(),
                format: cols[1].to_string(),
                triangles: cols[2].parse().unwrap(),
                bbox,
                open: count(&cols, "open="),
                nonmanifold: count(&cols, "nonmanifold="),
                degenerate: count(&cols, "degenerate="),
                accept: cols.last().unwrap().trim() == "accept",
            }
        })
        .collect()
}

fn format_name(f: StlFormat) -> &'static str {
    match f {
        StlFormat::Ascii => "ascii",
        StlFormat::Binary => "binary",
        StlFormat::BinarySolidHeader => "binary(solid-hdr)",
    }
}

/// Compare a loaded model with its INDEX line; returns the differences.
fn mismatches(e: &Entry, r: &MeshReport) -> Vec<String> {
    let mut out = Vec::new();
    if format_name(r.format) != e.format {
        out.push(format!("format {:?} (listed {})", r.format, e.format));
    }
    if r.triangles != e.triangles {
        out.push(format!(
            "triangles {} (listed {})",
            r.triangles, e.triangles
        ));
    }
    for (name, got, want) in [
        ("open", r.open_edges, e.open),
        ("nonmanifold", r.nonmanifold_edges, e.nonmanifold),
        ("degenerate", r.degenerate, e.degenerate),
    ] {
        if let Some(want) = want {
            if got != want {
                out.push(format!("{name} {got} (listed {want})"));
            }
        }
    }
    if let Some((lo, hi)) = e.bbox {
        let got = [r.bbox.min.to_array(), r.bbox.max.to_array()];
        for (g, w) in got.iter().zip([lo, hi]) {
            for k in 0..3 {
                if (g[k] - w[k]).abs() > BBOX_TOLERANCE {
                    out.push(format!("bbox {:?} (listed {:?}..{:?})", got, lo, hi));
                }
            }
        }
    }
    out
}

#[test]
fn corpus_accept_models_match_index() {
    let Some(dir) = corpus_dir() else {
        skip::skip_or_fail(
            "the corpus",
            "no ../shared/corpus/stl/INDEX.txt next to the crate and no /work/shared",
        );
        return;
    };
    let mut failures = Vec::new();
    let mut n = 0;
    for e in entries(&dir).iter().filter(|e| e.accept) {
        let bytes = std::fs::read(dir.join(&e.file)).unwrap();
        match read_stl(&bytes) {
            Ok((mesh, r)) => {
                assert_eq!(mesh.triangles.len(), r.triangles);
                let m = mismatches(e, &r);
                if !m.is_empty() {
                    failures.push(format!("{}: {}", e.file, m.join(", ")));
                }
            }
            Err(err) => failures.push(format!("{}: refused: {err}", e.file)),
        }
        n += 1;
    }
    assert!(n >= 10, "only {n} accept models listed");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn corpus_broken_models_are_refused_by_name_or_reported() {
    let Some(dir) = corpus_dir() else {
        skip::skip_or_fail(
            "the corpus",
            "no ../shared/corpus/stl/INDEX.txt next to the crate and no /work/shared",
        );
        return;
    };
    let mut n = 0;
    for e in entries(&dir)
        .iter()
        .filter(|e| e.file.starts_with("broken/"))
    {
        let bytes = std::fs::read(dir.join(&e.file)).unwrap();
        let result = std::panic::catch_unwind(|| read_stl(&bytes));
        let result = result.unwrap_or_else(|_| panic!("{}: read_stl panicked", e.file));
        match result {
            Err(err) => {
                // a named error with a message that says something
                assert!(err.to_string().len() > 10, "{}: {err:?}", e.file);
                println!("{}: refused: {err}", e.file);
            }
            Ok((_, r)) => {
                let reported = r.open_edges > 0
                    || r.nonmanifold_edges > 0
                    || r.degenerate > 0
                    || r.zero_normals > 0
                    || r.flipped_normals > 0
                    || !r.warnings.is_empty();
                assert!(
                    reported,
                    "{}: loaded with no defect reported: {r:?}",
                    e.file
                );
                if e.triangles > 0 {
                    let m = mismatches(e, &r);
                    assert!(m.is_empty(), "{}: {}", e.file, m.join(", "));
                }
                println!("{}: loaded, reported {r:?}", e.file);
            }
        }
        n += 1;
    }
    assert!(n >= 5, "only {n} broken models listed");
}

/// The specific outcomes chosen for the broken models (a change here is a behaviour change).
#[test]
fn corpus_broken_models_specific_outcomes() {
    let Some(dir) = corpus_dir() else {
        println!("SKIPPED: corpus absent");
        return;
    };
    let read = |f: &str| read_stl(&std::fs::read(dir.join("broken").join(f)).unwrap());
    assert_eq!(read("sm_empty.stl").unwrap_err(), MeshError::Empty);
    // header says 66 (0x42) facets, the file holds 4 whole records
    assert_eq!(
        read("sm_incorrectFaceCounter.bin.stl").unwrap_err(),
        MeshError::FaceCountMismatch {
            header_count: 66,
            bytes_for: 4
        }
    );
    let (_, r) = read("sm_missingEndsolid.ascii.stl").unwrap();
    assert!(r.warnings.iter().any(|w| w.contains("endsolid")), "{r:?}");
    let (_, r) = read("sm_missingFace.ascii.stl").unwrap();
    assert_eq!((r.triangles, r.open_edges), (3, 3));
    let (_, r) = read("sm_wrongHeader.bin.stl").unwrap();
    assert_eq!(r.format, StlFormat::BinarySolidHeader);
    assert!(r.warnings.iter().any(|w| w.contains("solid")), "{r:?}");
    let (_, r) = read("sm_wrongNormals.ascii.stl").unwrap();
    assert_eq!(r.zero_normals, 4);
}

/// stl_io as an independent oracle: same facets in the same order, same coordinates.
#[test]
fn corpus_agrees_with_stl_io() {
    let Some(dir) = corpus_dir() else {
        println!("SKIPPED: corpus absent");
        return;
    };
    for e in entries(&dir).iter().filter(|e| e.accept) {
        let mut bytes = std::fs::read(dir.join(&e.file)).unwrap();
        let (mesh, r) = read_stl(&bytes).unwrap();
        if r.format == StlFormat::BinarySolidHeader {
            // stl_io decides by the first word: hide it so that it reads the binary
            bytes[..5].copy_from_slice(b"xxxxx");
        }
        let theirs = stl_io::read_stl(&mut std::io::Cursor::new(bytes)).unwrap();
        assert_eq!(theirs.faces.len(), mesh.triangles.len(), "{}", e.file);
        for (f, t) in theirs.faces.iter().zip(&mesh.triangles) {
            for (&i, &j) in f.vertices.iter().zip(t) {
                let a = theirs.vertices[i].0;
                let b = mesh.vertices[j as usize];
                assert_eq!(
                    [a[0] as f64, a[1] as f64, a[2] as f64],
                    b.to_array(),
                    "{}",
                    e.file
                );
            }
        }
    }
}
