//! The collision check of a streamed unwarp (issue 10 §2, §4): the file stream
//! (`pipeline::unwarp_stream`, the CLI's path) and the streaming state the browser drives
//! (`pipeline::CheckedUnwarper`, under the wasm `UnwarpStream`) judge their output as the
//! one-shot unwarp does. With `allow_collisions` the streamed file is the one-shot's byte for
//! byte, findings listed at its end; without it both refuse with the same `machine.collision`
//! message. The case: the synthetic slicer's 16 mm cube (infill lines 4 mm apart: a small
//! file, 4000-odd findings) warped conic 30° outward, on the cartesian preset, whose default
//! heater block (14 mm towards +X, 4.5 mm up) meets the cone's rising layers (as in
//! tests/collision_check.rs, where the cube is 20 mm).
//!
//! The oracles do not come from the code under test: the listed findings are counted against
//! a fresh whole-file walk of the written body (`collision::check_gcode`, not the stream's
//! chunked walker, nor its verdict), and the first one — the refusal's — is re-found by the
//! independent helper `tests/common/collide.rs` (its own G-code reading, kinematics and solids).

mod common;

#[path = "common/synthetic.rs"]
mod synthetic;

use std::io::Read;

use common::collide::confirm;
use warpslice::error::Coded;
use warpslice::job::Job;
use warpslice::machine::{preset, MachineOptions};
use warpslice::pipeline::{unwarp, unwarp_stream, CheckedUnwarper, Error, UnwarpSettings};

/// The first characters of every finding comment at the end of an `allow_collisions` file.
const LISTED: &str = "; warpslice collision: line ";

/// A reader that hands out at most `step` bytes per read: the file stream then pushes the
/// G-code in chunks that cut its lines anywhere (its own read size is 1 MB, more than the case).
struct Trickle<'a> {
    data: &'a [u8],
    at: usize,
    step: usize,
}

impl Read for Trickle<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.step.min(buf.len()).min(self.data.len() - self.at);
        buf[..n].copy_from_slice(&self.data[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// The case: (job, slicer G-code).
fn case() -> (Job, Vec<u8>) {
    let w = synthetic::conic_cube_of(16.0);
    let g = synthetic::gcode(&w.job, true, 4.0).into_bytes();
    (w.job, g)
}

fn settings(allow: bool) -> UnwarpSettings {
    UnwarpSettings {
        output: MachineOptions {
            machine: Some(preset("cartesian").unwrap()),
            allow_collisions: allow,
            ..MachineOptions::default()
        },
        ..UnwarpSettings::default()
    }
}

/// `pipeline::unwarp_stream` reading `step` bytes at a time: the output and the report.
fn file_stream(
    job: &Job,
    g: &[u8],
    s: &UnwarpSettings,
    step: usize,
) -> (Vec<u8>, Result<warpslice::unwarp::UnwarpReport, Error>) {
    let mut out = Vec::new();
    let r = unwarp_stream(
        job,
        s,
        None,
        "case.gcode",
        || {
            Ok(Trickle {
                data: g,
                at: 0,
                step,
            })
        },
        &mut out,
        |_| {},
    );
    (out, r)
}

/// `CheckedUnwarper` driven as the browser's worker drives it (scan, end_scan, push and drain
/// every `step` bytes, finish, drain).
fn browser_stream(
    job: &Job,
    g: &[u8],
    s: &UnwarpSettings,
    step: usize,
) -> Result<(Vec<u8>, warpslice::unwarp::UnwarpReport), Error> {
    let mut u = CheckedUnwarper::new(job, s, None)?;
    for c in g.chunks(step) {
        u.scan(c)?;
    }
    u.end_scan()?;
    let mut out = Vec::new();
    for c in g.chunks(step) {
        u.push(c)?;
        out.extend(u.take_output());
    }
    let r = u.finish()?;
    out.extend(u.take_output());
    Ok((out, r))
}

/// The file's body (every line but the listed findings) and the listed lines.
fn split(text: &str) -> (String, Vec<&str>) {
    let body = text
        .lines()
        .filter(|l| !l.starts_with(LISTED))
        .map(|l| format!("{l}\n"))
        .collect();
    (
        body,
        text.lines().filter(|l| l.starts_with(LISTED)).collect(),
    )
}

#[test]
fn streamed_allow_collisions_output_is_the_one_shots_bytes_with_every_finding_listed() {
    let (job, g) = case();
    let s = settings(true);
    let whole = unwarp(&g, &job, &s).expect("allow_collisions writes the file");
    let text = String::from_utf8(whole.gcode.clone()).unwrap();

    // the oracle: a fresh walk of the written body, whole
    let (body, listed) = split(&text);
    assert!(
        text.ends_with(&listed.iter().map(|l| format!("{l}\n")).collect::<String>()),
        "the findings are listed at the end of the file"
    );
    let spec = preset("cartesian").unwrap();
    let (found, _) = warpslice::collision::check_gcode(body.as_bytes(), &spec).unwrap();
    assert!(
        found.len() >= 2,
        "the case must have several findings: {found:?}"
    );
    assert_eq!(listed.len(), found.len(), "one comment per finding");
    for (l, f) in listed.iter().zip(&found) {
        assert!(
            l.starts_with(&format!(
                "{LISTED}{} layer {}: {} into {} by {:.3} mm",
                f.line, f.layer, f.part, f.obstacle, f.depth_mm
            )),
            "{l} vs {f:?}"
        );
    }
    let first = &found[0];
    let c = confirm(
        &spec,
        &body,
        first.line as usize,
        &first.part,
        &first.obstacle,
    )
    .unwrap_or_else(|e| panic!("the first finding {first:?} is not re-found: {e}"));
    assert!(c.depth_mm > 0.0, "{}", c.what);

    let m = whole.report.machine.as_ref().expect("a machine report");
    assert!(m.collisions_checked);
    assert_eq!(m.collisions.len(), found.len());

    // the streams: every read size gives the one-shot's bytes and findings
    for step in [7, 4093, g.len()] {
        let (out, r) = file_stream(&job, &g, &s, step);
        let r = r.unwrap_or_else(|e| panic!("file stream, reads of {step} B: {e}"));
        assert!(
            out == whole.gcode,
            "file stream, reads of {step} B: {} B, the one-shot {} B",
            out.len(),
            whole.gcode.len()
        );
        assert_eq!(
            r, whole.report,
            "file stream, reads of {step} B: the report"
        );
        let (out, r) = browser_stream(&job, &g, &s, step)
            .unwrap_or_else(|e| panic!("browser stream, chunks of {step} B: {e}"));
        assert!(
            out == whole.gcode,
            "browser stream, chunks of {step} B: {} B, the one-shot {} B",
            out.len(),
            whole.gcode.len()
        );
        assert_eq!(
            r, whole.report,
            "browser stream, chunks of {step} B: the report"
        );
    }
}

#[test]
fn streamed_unwarp_refuses_a_collision_with_the_one_shots_message() {
    let (job, g) = case();
    let one_shot = match unwarp(&g, &job, &settings(false)) {
        Ok(_) => panic!("the one-shot unwarp wrote a colliding file"),
        Err(e) => e,
    };
    assert_eq!(one_shot.code(), "machine.collision", "{one_shot}");
    // the refusal names the first finding the allowed file lists (line, layer, part, input line)
    let allowed = unwarp(&g, &job, &settings(true)).unwrap();
    let first = &allowed.report.machine.as_ref().unwrap().collisions[0];
    let message = one_shot.to_string();
    assert!(
        message.contains(&format!(
            "output line {} (layer {}; from input line {}): the {} goes {:.3} mm into the",
            first.line,
            first.layer,
            first.input_line.expect("an input line"),
            first.part,
            first.depth_mm
        )),
        "{message} vs {first:?}"
    );
    for step in [7, 4093, g.len()] {
        let (_, r) = file_stream(&job, &g, &settings(false), step);
        match r {
            Ok(_) => panic!("file stream, reads of {step} B: wrote a colliding file"),
            Err(e) => {
                assert_eq!(e.code(), "machine.collision");
                assert_eq!(e.to_string(), message, "file stream, reads of {step} B");
            }
        }
        match browser_stream(&job, &g, &settings(false), step) {
            Ok(_) => panic!("browser stream, chunks of {step} B: wrote a colliding file"),
            Err(e) => {
                assert_eq!(e.code(), "machine.collision");
                assert_eq!(e.to_string(), message, "browser stream, chunks of {step} B");
            }
        }
    }
}

/// After a streamed unwarp the browser checks the written file for reach and speeds only
/// (`skip_collisions`: the unwarp walked it already) and hands the check the unwarp's
/// collisions (`CheckStream::finish_with_collisions`): the report is the full check's of the
/// same file — counts, the list in its order (also when `max_findings` cuts it), the parts, the
/// warnings — but for the input lines the unwarp knows and the samples it does not count.
#[test]
fn a_check_given_the_unwarps_collisions_reports_as_the_full_check_of_the_file() {
    use warpslice::check::{check, CheckOptions, CheckStream};
    let (job, g) = case();
    let out = unwarp(&g, &job, &settings(true)).unwrap();
    let found = &out.report.machine.as_ref().unwrap().collisions;
    // checked for the same machine with a slow Z (the head and so the collisions unchanged):
    // speed findings on the conic layers' moves, between and on the collisions' lines
    let mut spec = preset("cartesian").unwrap();
    spec.max_feed = Some([("Z".to_string(), 120.0)].into_iter().collect());
    for max_findings in [CheckOptions::default().max_findings, 7, 1] {
        let full = check(
            &out.gcode,
            &spec,
            &CheckOptions {
                max_findings,
                ..CheckOptions::default()
            },
        )
        .unwrap();
        assert_eq!(full.counts.collision as usize, found.len());
        assert!(full.counts.speed > 0, "speed findings too");
        let mut s = CheckStream::new(
            &spec,
            &CheckOptions {
                max_findings,
                skip_collisions: true,
                ..CheckOptions::default()
            },
        )
        .unwrap();
        s.push(&out.gcode).unwrap();
        let (mut merged, _) = s.finish_with_collisions(found).unwrap();
        for f in &mut merged.findings {
            if let Some(c) = f.collision.as_mut() {
                assert!(
                    c.input_line.is_some(),
                    "the unwarp's finding has its input line"
                );
                c.input_line = None;
            }
        }
        merged.collision_samples = full.collision_samples;
        assert_eq!(merged, full, "max_findings {max_findings}");
    }
}

/// The input line of every output line is known while the check has not walked it, and
/// forgotten once it has: after each chunk the record reaches back no further than the
/// chunk's first line (the whole-file record took 176 MB of the pax-5axis run of the web
/// tier's 105 MB G-code), while every finding still names its input line (the tests above).
#[test]
fn the_input_lines_of_walked_output_are_forgotten_chunk_by_chunk() {
    let (job, g) = case();
    let s = settings(true);
    let mut u = CheckedUnwarper::new(&job, &s, None).unwrap();
    for c in g.chunks(4096) {
        u.scan(c).unwrap();
    }
    u.end_scan().unwrap();
    let (mut lines, mut checked) = (0u64, 0);
    for c in g.chunks(4096) {
        u.push(c).unwrap();
        let out = u.take_output();
        let before = lines;
        lines += out.iter().filter(|&&b| b == b'\n').count() as u64;
        if lines > before + 1 {
            // the chunk's last line is still held, its first ones before it are not
            assert!(
                u.input_line_of(lines).is_some(),
                "output line {lines}, the last written, has no input line"
            );
            if before > 1 {
                assert_eq!(
                    u.input_line_of(before - 1),
                    None,
                    "output line {} (walked before this chunk) is still held",
                    before - 1
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 5, "only {checked} chunks checked");
    u.finish().unwrap();
}
