//! The Klipper and Marlin outputs beyond their headers, through the CLI (`--flavour`), read by a
//! parser of its own (not the crate's `gcode` module):
//! - the flavour changes only what docs/machines.md says it changes (the `; warpslice machine =
//!   … <flavour>` line and the flavour's header block): every other line, every move included,
//!   is the RepRapFirmware output's;
//! - Klipper on `cartesian`: its moves carry no word but X Y Z E F, no G93,
//!   every F a positive mm/min number the firmware reads (no exponent), F = the slicer's feed
//!   (`--feed xyz`), and its object extrusions lie on the conic layer surfaces computed here in
//!   closed form (README: T_z = z + r·tan α), so the moves are right and not only equal;
//! - Klipper drives every machine: the header's `[manual_stepper]` / `MANUAL_STEPPER …
//!   GCODE_AXIS=` letters are the moves' extra letters, no `G92` on an extra axis, no `G93`;
//!   an axis lettered E is refused by name;
//! - Marlin on the 4/5-axis presets: the letters `#define AXISn_NAME` declares (n = 4, 5, …, in
//!   Marlin's A B C U V W) are exactly the extra letters the moves use, rotary or linear as
//!   docs/machines.md says, within the travel the header gives; on `pax-5axis` the A/B words,
//!   read with the documented kinematics n = (sin B cos φ, sin B sin φ, cos B), φ = A + 90°, give
//!   the conic warp's tool axis at the tip.
//!
//! The G-code is the synthetic slicer's (tests/common/synthetic.rs) for the job the CLI wrote:
//! no real slicer needed, so nothing here can skip.
#![cfg(not(target_arch = "wasm32"))]

#[path = "common/cli_part.rs"]
#[allow(dead_code)]
mod cli_part;
#[path = "common/synthetic.rs"]
#[allow(dead_code)]
mod synthetic;

use std::collections::BTreeSet;
use std::path::PathBuf;

use cli_part::{ok, run};
use warpslice::job::Job;

/// Layer height the CLI warps with (its default, the synthetic slicer's layers).
const H: f64 = 0.2;

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("warpslice-flavour-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// A warped 20 mm cube and the synthetic slicer's G-code of it.
struct Part {
    dir: PathBuf,
    gcode: PathBuf,
    job_path: PathBuf,
    job: Job,
}

fn part(tag: &str, warp: &[&str]) -> Part {
    let dir = tmpdir(tag);
    let p = |f: &str| dir.join(f).to_str().unwrap().to_string();
    ok(&["example", "cube", "-o", &p("cube.stl")]);
    let (cube, out) = (p("cube.stl"), p("W.stl"));
    let mut args = vec!["warp", cube.as_str()];
    args.extend_from_slice(warp);
    args.extend_from_slice(&["-o", out.as_str()]);
    ok(&args);
    let job_path = dir.join("W.job.json");
    let job = Job::from_json(&std::fs::read_to_string(&job_path).expect("the job")).unwrap();
    assert_eq!(job.layer_height, H);
    let gcode = dir.join("W.gcode");
    std::fs::write(&gcode, synthetic::gcode(&job, true, 1.0)).unwrap();
    Part {
        dir,
        gcode,
        job_path,
        job,
    }
}

impl Part {
    /// `unwarp` of the part's G-code to `name` with `extra` flags: the output path and the
    /// run's result.
    fn run_unwarp(&self, name: &str, extra: &[&str]) -> (PathBuf, std::process::Output) {
        let out = self.dir.join(name);
        let mut args = vec![
            "unwarp",
            self.gcode.to_str().unwrap(),
            "--job",
            self.job_path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = run(&args);
        (out, o)
    }
    /// `unwarp` with `extra` flags, placed where the synthetic slicer put the part (the warped
    /// bbox's centre, (0, 0) for these shears of the centred cube, on (100, 100)): no
    /// registration error in the layer-surface checks. The output text.
    fn unwarp(&self, name: &str, extra: &[&str]) -> String {
        // the collision check (on by default) is tested in collision_check.rs: these files are
        // about the firmware's words, and the default head meets the bed on their tilted parts
        let mut flags = vec!["--offset", "100,100", "--allow-collisions"];
        flags.extend_from_slice(extra);
        let (out, o) = self.run_unwarp(name, &flags);
        assert!(
            o.status.success(),
            "unwarp {flags:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        std::fs::read_to_string(out).unwrap()
    }
    /// `unwarp` that must be refused: its stderr.
    fn unwarp_err(&self, name: &str, extra: &[&str]) -> String {
        let (_, o) = self.run_unwarp(name, extra);
        assert!(!o.status.success(), "unwarp {extra:?} accepted");
        String::from_utf8_lossy(&o.stderr).into_owned()
    }
}

impl Drop for Part {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

// ── an independent reader ───────────────────────────────────────────────────────────────────

/// One G-code line: the command (`G1`, `M104`, …; None for a comment or blank line) and its
/// words (letter, number text).
struct Line<'a> {
    text: &'a str,
    cmd: Option<&'a str>,
    words: Vec<(char, &'a str)>,
}

fn lines(text: &str) -> Vec<Line<'_>> {
    text.lines()
        .map(|t| {
            let code = t.split(';').next().unwrap().trim();
            let mut toks = code.split_whitespace();
            let cmd = toks.next();
            let words = toks
                .map(|w| {
                    let mut c = w.chars();
                    (c.next().unwrap().to_ascii_uppercase(), c.as_str())
                })
                .collect();
            Line {
                text: t,
                cmd,
                words,
            }
        })
        .collect()
}

fn num(what: &str, v: &str) -> f64 {
    // what every firmware's parser reads: an optional sign, digits, an optional fraction
    let plain = {
        let d = v.strip_prefix('-').unwrap_or(v);
        let mut parts = d.splitn(2, '.');
        let int = parts.next().unwrap();
        let frac = parts.next();
        !int.is_empty()
            && int.chars().all(|c| c.is_ascii_digit())
            && frac.is_none_or(|f| !f.is_empty() && f.chars().all(|c| c.is_ascii_digit()))
    };
    assert!(plain, "{what}: '{v}' is not a plain decimal number");
    v.parse().unwrap()
}

const MOTION: &[&str] = &["G0", "G1", "G2", "G3"];

/// The flavour's own lines (the `; warpslice machine = …` line, then `; flavour …` and the
/// indented lines after it) and every other line.
fn split_flavour(text: &str) -> (Vec<&str>, Vec<&str>) {
    let mut own = Vec::new();
    let mut rest = Vec::new();
    let mut in_block = false;
    for l in text.lines() {
        if l.starts_with("; warpslice machine = ") {
            own.push(l);
        } else if l.starts_with("; flavour ") {
            in_block = true;
            own.push(l);
        } else if in_block && l.starts_with(";   ") {
            own.push(l);
        } else {
            in_block = false;
            rest.push(l);
        }
    }
    (own, rest)
}

/// The first line that differs between two outputs (for the assertion message).
fn same_rest(a: &[&str], b: &[&str], what: &str) {
    if let Some(k) = (0..a.len().max(b.len())).find(|&k| a.get(k) != b.get(k)) {
        panic!(
            "{what}: line {k} differs from the RepRapFirmware output's: {:?} vs {:?}",
            a.get(k),
            b.get(k)
        );
    }
}

/// `; warpslice model_to_output = dx dy dz`.
fn model_to_output(text: &str) -> [f64; 3] {
    let l = text
        .lines()
        .find_map(|l| l.strip_prefix("; warpslice model_to_output = "))
        .expect("the model_to_output header");
    let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
    [v[0], v[1], v[2]]
}

/// The F values of the motion lines of `text`.
fn feeds(text: &str) -> Vec<f64> {
    lines(text)
        .iter()
        .filter(|l| l.cmd.is_some_and(|c| MOTION.contains(&c)))
        .flat_map(|l| {
            l.words
                .iter()
                .filter(|w| w.0 == 'F')
                .map(|w| num(l.text, w.1))
        })
        .collect()
}

/// Every motion line of the output as absolute axis values (words carried over from the line
/// before), with its E and the `;TYPE:` it is in.
struct Move {
    axes: std::collections::BTreeMap<char, f64>,
    e: f64,
    feature: String,
}

fn moves(text: &str) -> Vec<Move> {
    let mut pos = std::collections::BTreeMap::new();
    let mut feature = String::new();
    let mut out = Vec::new();
    for l in lines(text) {
        if let Some(t) = l.text.strip_prefix(";TYPE:") {
            feature = t.to_string();
        }
        if l.cmd == Some("G92") {
            for (c, v) in &l.words {
                if *c != 'E' {
                    pos.insert(*c, num(l.text, v));
                }
            }
        }
        if !l.cmd.is_some_and(|c| MOTION.contains(&c)) {
            continue;
        }
        let mut e = 0.0;
        for (c, v) in &l.words {
            match c {
                'E' => e = num(l.text, v),
                'F' => {}
                _ => {
                    pos.insert(*c, num(l.text, v));
                }
            }
        }
        out.push(Move {
            axes: pos.clone(),
            e,
            feature: feature.clone(),
        });
    }
    out
}

/// The object's extrusions (relative E > 0, not skirt or brim) above the bed: README "never
/// below the bed", a point mapped below z = 0 is clamped to it (off its layer, E reduced); no
/// point is below it and the clamped ones are few (the bottom corner nearest the cone's apex).
fn object_extrusions(text: &str) -> Vec<Move> {
    let all: Vec<Move> = moves(text)
        .into_iter()
        .filter(|m| m.e > 0.0 && !m.feature.starts_with("Skirt") && !m.feature.is_empty())
        .collect();
    let z = |m: &Move| m.axes[&'Z'];
    assert!(
        all.iter().all(|m| z(m) >= 0.0),
        "an extrusion below the bed"
    );
    let clamped = all.iter().filter(|m| z(m) == 0.0).count();
    assert!(
        clamped * 20 < all.len(),
        "{clamped} of {} extrusions clamped to the bed",
        all.len()
    );
    all.into_iter().filter(|m| z(m) > 0.0).collect()
}

// ── Klipper ─────────────────────────────────────────────────────────────────────────────────

/// README: the outward cone about (cx, cy), T_z = z + r·tan α; the layer k of the warped STL is
/// T_z + stl_z_offset = k·h. Distance of a model-frame point from its layer surface, mm.
fn off_cone(p: [f64; 3], angle: f64, c: [f64; 2], stl_z_offset: f64) -> f64 {
    let k = angle.to_radians().tan();
    let r = ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2)).sqrt();
    let t = p[2] + r * k + stl_z_offset;
    let layer = (t / H).round() * H;
    (t - layer).abs() / (1.0 + k * k).sqrt()
}

#[test]
fn klipper_on_cartesian_writes_the_reprapfirmware_moves_with_only_x_y_z_e_f() {
    let part = part(
        "klipper",
        &["--warp", "conic", "--angle", "25", "--center", "-15,0"],
    );
    let input = std::fs::read_to_string(&part.gcode).unwrap();
    let input_feeds: BTreeSet<u64> = feeds(&input).iter().map(|f| f.to_bits()).collect();
    for feed in ["xyz", "all-axes"] {
        let rrf = part.unwarp(
            &format!("rrf-{feed}.gcode"),
            &["--machine", "cartesian", "--feed", feed],
        );
        let kl = part.unwarp(
            &format!("klipper-{feed}.gcode"),
            &[
                "--machine",
                "cartesian",
                "--flavour",
                "klipper",
                "--feed",
                feed,
            ],
        );
        let (own_r, rest_r) = split_flavour(&rrf);
        let (own_k, rest_k) = split_flavour(&kl);
        assert_eq!(
            own_r[0], "; warpslice machine = cartesian reprapfirmware",
            "the default flavour"
        );
        assert_eq!(
            own_k,
            [
                "; warpslice machine = cartesian klipper",
                "; flavour Klipper (3-axis)"
            ],
            "Klipper's header: the flavour and no axis mapping or travel"
        );
        same_rest(&rest_k, &rest_r, &format!("klipper --feed {feed}"));

        let ls = lines(&kl);
        let n_moves = ls
            .iter()
            .filter(|l| l.cmd.is_some_and(|c| MOTION.contains(&c)))
            .count();
        assert!(n_moves > 1000, "{n_moves} moves");
        for l in &ls {
            let Some(cmd) = l.cmd else { continue };
            assert!(
                !["G93", "G94"].contains(&cmd),
                "Klipper has no feed modes: {}",
                l.text
            );
            if MOTION.contains(&cmd) || cmd == "G92" {
                for (c, v) in &l.words {
                    assert!(
                        "XYZEF".contains(*c),
                        "Klipper reads X Y Z E F only: {}",
                        l.text
                    );
                    let x = num(l.text, v);
                    if *c == 'F' {
                        assert!(x > 0.0, "a positive feed: {}", l.text);
                    }
                }
            }
        }
        // F is mm/min: the slicer's feeds (--feed xyz: F = f; on cartesian all-axes is the same)
        let out_feeds: BTreeSet<u64> = feeds(&kl).iter().map(|f| f.to_bits()).collect();
        let new: Vec<f64> = out_feeds
            .difference(&input_feeds)
            .map(|b| f64::from_bits(*b))
            .collect();
        assert!(
            new.is_empty(),
            "--feed {feed}: feeds the slicer did not ask for: {new:?}"
        );

        // the moves themselves: object extrusions on the cone's layer surfaces
        let d = model_to_output(&kl);
        let ext = object_extrusions(&kl);
        assert!(ext.len() > 1000, "{} object extrusions", ext.len());
        let mut worst = 0.0f64;
        for m in &ext {
            let p = [
                m.axes[&'X'] - d[0],
                m.axes[&'Y'] - d[1],
                m.axes[&'Z'] - d[2],
            ];
            worst = worst.max(off_cone(p, 25.0, [-15.0, 0.0], part.job.stl_z_offset));
        }
        // 0.01 mm of splitting allowance is for chords; vertices are exact up to the 3-decimal
        // rounding of X Y Z
        assert!(
            worst < 0.002,
            "--feed {feed}: an extrusion vertex {worst} mm off its layer surface"
        );
    }
}

/// The same check fails for a wrong cone: the layer-surface check can fail.
#[test]
fn the_layer_surface_check_tells_a_wrong_warp() {
    let part = part(
        "klipper-wrong",
        &["--warp", "conic", "--angle", "25", "--center", "-15,0"],
    );
    let kl = part.unwarp(
        "klipper.gcode",
        &["--machine", "cartesian", "--flavour", "klipper"],
    );
    let d = model_to_output(&kl);
    let ext = object_extrusions(&kl);
    let worst = |angle: f64, c: [f64; 2]| {
        ext.iter()
            .map(|m| {
                let p = [
                    m.axes[&'X'] - d[0],
                    m.axes[&'Y'] - d[1],
                    m.axes[&'Z'] - d[2],
                ];
                off_cone(p, angle, c, part.job.stl_z_offset)
            })
            .fold(0.0, f64::max)
    };
    assert!(worst(25.0, [-15.0, 0.0]) < 0.002);
    assert!(
        worst(24.0, [-15.0, 0.0]) > 0.05,
        "{}",
        worst(24.0, [-15.0, 0.0])
    );
    assert!(
        worst(25.0, [-14.0, 0.0]) > 0.05,
        "{}",
        worst(25.0, [-14.0, 0.0])
    );
}

/// Klipper has no G93: a Klipper file must not switch to inverse time (refuse, or write mm/min).
#[test]
fn klipper_never_gets_inverse_time() {
    let part = part(
        "klipper-g93",
        &["--warp", "conic", "--angle", "25", "--center", "-15,0"],
    );
    let out = part.dir.join("klipper-it.gcode");
    let o = run(&[
        "unwarp",
        part.gcode.to_str().unwrap(),
        "--job",
        part.job_path.to_str().unwrap(),
        "--machine",
        "cartesian",
        "--flavour",
        "klipper",
        "--feed",
        "inverse-time",
        "-o",
        out.to_str().unwrap(),
    ]);
    if o.status.success() {
        let text = std::fs::read_to_string(out).unwrap();
        let g93 = lines(&text)
            .into_iter()
            .find(|l| l.cmd == Some("G93"))
            .map(|l| l.text.to_string());
        assert!(g93.is_none(), "a Klipper file with {g93:?}");
    } else {
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains("klipper") && e.contains("inverse-time"), "{e}");
    }
}

/// Mainline Marlin 2.1 has no G93 either (its feature request is open): refused, by name.
#[test]
fn marlin_never_gets_inverse_time() {
    let part = part(
        "marlin-g93",
        &["--warp", "conic", "--angle", "25", "--center", "-15,0"],
    );
    let e = part.unwarp_err(
        "marlin-it.gcode",
        &[
            "--machine",
            "pax-5axis",
            "--flavour",
            "marlin",
            "--feed",
            "inverse-time",
        ],
    );
    assert!(e.contains("Marlin 2.1 has no G93"), "{e}");
    // the same machine and feed for RepRapFirmware is written
    let text = part.unwarp(
        "rrf-it.gcode",
        &["--machine", "pax-5axis", "--feed", "inverse-time"],
    );
    assert!(lines(&text).iter().any(|l| l.cmd == Some("G93")));
}

/// (stepper name, axis letter) pairs.
type Steppers = Vec<(String, char)>;

/// Klipper's header for a machine with extra axes: the `[manual_stepper <name>]` sections and
/// the `MANUAL_STEPPER STEPPER=<name> GCODE_AXIS=<L> …` lines, per letter (the same name in
/// both), and whether the `INSTANTANEOUS_CORNER_VELOCITY` advice is there.
fn klipper_header(own: &[&str]) -> (Steppers, Steppers, bool) {
    let mut sections = Vec::new();
    let mut registered = Vec::new();
    let mut corner = false;
    for l in own {
        if let Some(t) = l.strip_prefix(";   [manual_stepper ") {
            let (name, rest) = t.split_once(']').expect("[manual_stepper name]");
            let letter = rest
                .split_once("; axis ")
                .and_then(|(_, r)| r.chars().next())
                .expect("; axis L");
            sections.push((name.to_string(), letter));
        } else if let Some(t) = l.strip_prefix(";   MANUAL_STEPPER STEPPER=") {
            let (name, rest) = t.split_once(' ').unwrap();
            let letter = rest
                .strip_prefix("GCODE_AXIS=")
                .and_then(|r| r.chars().next())
                .expect("GCODE_AXIS=L");
            assert!(
                l.contains("INSTANTANEOUS_CORNER_VELOCITY="),
                "the corner velocity is set where the axis is registered: {l}"
            );
            registered.push((name.to_string(), letter));
        } else if l.starts_with(";   INSTANTANEOUS_CORNER_VELOCITY: ") && l.contains("1 mm/s") {
            corner = true;
        }
    }
    (sections, registered, corner)
}

/// Klipper (mainline since 2025-05: extra axes registered with `MANUAL_STEPPER … GCODE_AXIS=`)
/// drives every machine: its header declares exactly the extra letters the moves use (in the
/// machine's order), with the corner-velocity advice (the default 1 mm/s); its `G92` sets X Y Z
/// E only, so no `G92` names an extra axis (RotBot's unlimited U is written unwrapped) and no
/// `G93` is written.
#[test]
fn klipper_drives_every_machine_through_manual_stepper_axes() {
    // about the part's centre: every perimeter turns the nozzle once around
    let conic45 = ["--warp", "conic", "--angle", "45", "--center", "0,0"];
    let cases: [(&str, &[&str]); 4] = [
        (
            "pax-5axis",
            &["--warp", "conic", "--angle", "25", "--center", "-15,0"],
        ),
        (
            "fullcontrol-prusa-b",
            &["--warp", "curved", "--strength", "0.3"],
        ),
        ("rotbot", &conic45),
        ("ratrig-vcore3-3z", &["--warp", "belt", "--angle", "20"]),
    ];
    for (preset, warp) in cases {
        let part = part(&format!("klipper-{preset}"), warp);
        let text = part.unwarp(
            &format!("{preset}-klipper.gcode"),
            &["--machine", preset, "--flavour", "klipper"],
        );
        let (own, _) = split_flavour(&text);
        assert_eq!(own[0], format!("; warpslice machine = {preset} klipper"));
        let (sections, registered, corner) = klipper_header(&own);
        let want: Vec<char> = documented_extra_axes(preset).iter().map(|a| a.0).collect();
        let letters = |v: &[(String, char)]| v.iter().map(|x| x.1).collect::<Vec<char>>();
        assert_eq!(letters(&sections), want, "{preset}: {own:?}");
        assert_eq!(
            sections, registered,
            "{preset}: the same steppers registered"
        );
        assert!(corner, "{preset}: no corner-velocity advice: {own:?}");
        let mut used = BTreeSet::new();
        let mut turned = 0.0f64;
        for l in lines(&text) {
            let Some(cmd) = l.cmd else { continue };
            assert!(cmd != "G93", "{preset}: Klipper has no G93: {}", l.text);
            if cmd == "G92" {
                for (c, _) in &l.words {
                    assert!(
                        "XYZE".contains(*c),
                        "{preset}: Klipper's G92 sets X Y Z E only: {}",
                        l.text
                    );
                }
            }
            if MOTION.contains(&cmd) {
                for (c, v) in &l.words {
                    let x = num(l.text, v);
                    if !"XYZEF".contains(*c) {
                        used.insert(*c);
                        if *c == 'U' && preset == "rotbot" {
                            turned = turned.max(x.abs());
                        }
                    }
                    if *c == 'F' {
                        assert!(x > 0.0, "{preset}: a positive feed: {}", l.text);
                    }
                }
            }
        }
        assert_eq!(
            used,
            want.iter().copied().collect(),
            "{preset}: letters used vs declared"
        );
        if preset == "rotbot" {
            // unwrapped: the perimeters about the cone's axis add up to more than one turn
            assert!(
                turned > 360.0,
                "rotbot U stays within {turned}°: was it reset?"
            );
        }
    }
}

/// A letter Klipper's G1 reads as something else (E: the extruder) cannot name an axis:
/// refused by name, as the inverse-time feed it has no G93 for.
#[test]
fn klipper_refuses_an_axis_named_e_by_name() {
    let part = part(
        "klipper-letter",
        &["--warp", "conic", "--angle", "25", "--center", "-15,0"],
    );
    let mut spec = warpslice::machine::preset("pax-5axis").unwrap();
    spec.axis_names = Some(["X", "Y", "Z", "E", "B"].map(String::from).to_vec());
    spec.flavour = None;
    // (the preset's feed limits name the letters it renames)
    spec.max_feed = None;
    let file = part.dir.join("pax-e.json");
    std::fs::write(&file, spec.to_json()).unwrap();
    let e = part.unwarp_err(
        "pax-e.gcode",
        &["--machine", file.to_str().unwrap(), "--flavour", "klipper"],
    );
    assert!(
        e.contains("flavour klipper refused") && e.contains("'E' is the extruder"),
        "{e}"
    );
}

// ── Marlin ──────────────────────────────────────────────────────────────────────────────────

/// docs/machines.md: each preset's extra letters, in the machine's axis order, and whether
/// they turn.
fn documented_extra_axes(preset: &str) -> &'static [(char, bool)] {
    match preset {
        "pax-5axis" => &[('A', true), ('B', true)],
        "fullcontrol-prusa-b" => &[('B', true)],
        "rotbot" => &[('U', true)],
        "ratrig-vcore3-3z" => &[('U', false), ('V', false)],
        _ => unreachable!(),
    }
}

/// Marlin's header: `#define AXIS<n>_NAME '<L>'   // rotary … | linear …` lines, and the travel
/// lines `axis L travel [min, max] deg|mm`.
#[allow(clippy::type_complexity)]
fn marlin_header(own: &[&str]) -> (Vec<(usize, char, bool)>, Vec<(char, f64, f64)>) {
    let mut defs = Vec::new();
    let mut travel = Vec::new();
    for l in own {
        if let Some(t) = l.strip_prefix(";   #define AXIS") {
            let (n, rest) = t.split_once("_NAME '").expect("AXISn_NAME 'L'");
            let letter = rest.chars().next().unwrap();
            assert!(rest[1..].starts_with("'   // "), "{l}");
            let rotary = rest.contains("// rotary");
            assert!(rotary || rest.contains("// linear"), "{l}");
            defs.push((n.parse().unwrap(), letter, rotary));
        } else if let Some(t) = l.strip_prefix(";   axis ") {
            let (letter, rest) = t.split_once(" travel [").expect("travel line");
            let (lo, rest) = rest.split_once(", ").unwrap();
            let (hi, _) = rest.split_once(']').unwrap();
            travel.push((
                letter.chars().next().unwrap(),
                lo.parse().unwrap(),
                hi.parse().unwrap(),
            ));
        }
    }
    (defs, travel)
}

#[test]
fn marlin_declares_exactly_the_letters_its_moves_use_and_moves_like_reprapfirmware() {
    let conic = ["--warp", "conic", "--angle", "25", "--center", "-15,0"];
    let cases: [(&str, &[&str]); 4] = [
        ("pax-5axis", &conic),
        (
            "fullcontrol-prusa-b",
            &["--warp", "curved", "--strength", "0.3"],
        ),
        (
            "rotbot",
            &["--warp", "conic", "--angle", "45", "--center", "-15,0"],
        ),
        ("ratrig-vcore3-3z", &["--warp", "belt", "--angle", "20"]),
    ];
    for (preset, warp) in cases {
        let part = part(&format!("marlin-{preset}"), warp);
        let rrf = part.unwarp(&format!("{preset}-rrf.gcode"), &["--machine", preset]);
        let marlin = part.unwarp(
            &format!("{preset}-marlin.gcode"),
            &["--machine", preset, "--flavour", "marlin"],
        );
        let (own_r, rest_r) = split_flavour(&rrf);
        let (own_m, rest_m) = split_flavour(&marlin);
        assert_eq!(
            own_r[0],
            format!("; warpslice machine = {preset} reprapfirmware")
        );
        assert_eq!(own_m[0], format!("; warpslice machine = {preset} marlin"));
        assert_eq!(
            own_m[1], "; flavour Marlin 2.1: extra axes are set in Configuration.h as",
            "{preset}"
        );
        same_rest(&rest_m, &rest_r, &format!("{preset} marlin"));

        // the declared letters: AXIS4_NAME, AXIS5_NAME, … in order, Marlin's letters, and the
        // documented ones
        let (defs, travel) = marlin_header(&own_m);
        let want = documented_extra_axes(preset);
        assert_eq!(defs.len(), want.len(), "{preset}: {own_m:?}");
        for (k, ((n, letter, rotary), (wl, wr))) in defs.iter().zip(want).enumerate() {
            assert_eq!(*n, k + 4, "{preset}: AXIS{n}_NAME in order");
            assert!(
                "ABCUVW".contains(*letter),
                "{preset}: Marlin letter {letter}"
            );
            assert_eq!((*letter, *rotary), (*wl, *wr), "{preset}: axis {letter}");
        }
        let declared: BTreeSet<char> = defs.iter().map(|d| d.1).collect();

        // the moves: their extra letters are exactly the declared ones
        let ls = lines(&marlin);
        let mut used = BTreeSet::new();
        for l in &ls {
            let Some(cmd) = l.cmd else { continue };
            if MOTION.contains(&cmd) || cmd == "G92" {
                for (c, v) in &l.words {
                    num(l.text, v);
                    if !"XYZEF".contains(*c) {
                        used.insert(*c);
                    }
                    if *c == 'F' {
                        assert!(
                            num(l.text, v) > 0.0,
                            "{preset}: a positive feed: {}",
                            l.text
                        );
                    }
                }
            }
        }
        assert_eq!(used, declared, "{preset}: letters used vs declared");

        // within the travel the header gives (3-decimal rounding)
        let ms = moves(&marlin);
        for (letter, lo, hi) in &travel {
            let vals: Vec<f64> = ms
                .iter()
                .filter_map(|m| m.axes.get(letter).copied())
                .collect();
            assert!(!vals.is_empty(), "{preset}: axis {letter} moves");
            let (mn, mx) = vals
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
            assert!(
                mn >= lo - 5e-4 && mx <= hi + 5e-4,
                "{preset}: axis {letter} in [{mn}, {mx}], travel [{lo}, {hi}]"
            );
        }
        if preset == "pax-5axis" {
            pax_axes_are_the_cones(&marlin, part.job.stl_z_offset);
        }
    }
}

/// pax-5axis (pivot-to-tip 0, Slicer4RTN's convention with rot_offset −90°): X Y Z is the tip,
/// n = (sin B cos φ, sin B sin φ, cos B) with φ = A − 180° + 90° = A − 90°. At every object extrusion vertex this must be the
/// outward cone's axis ∇T_z/|∇T_z| = (tan α·(x − cx)/r, tan α·(y − cy)/r, 1)/|…|.
fn pax_axes_are_the_cones(text: &str, stl_z_offset: f64) {
    let d = model_to_output(text);
    let k = 25f64.to_radians().tan();
    let mut worst_axis = 0.0f64;
    let mut worst_surface = 0.0f64;
    let ext = object_extrusions(text);
    assert!(ext.len() > 1000, "{}", ext.len());
    for m in &ext {
        let p = [
            m.axes[&'X'] - d[0],
            m.axes[&'Y'] - d[1],
            m.axes[&'Z'] - d[2],
        ];
        worst_surface = worst_surface.max(off_cone(p, 25.0, [-15.0, 0.0], stl_z_offset));
        let (a, b) = (m.axes[&'A'].to_radians(), m.axes[&'B'].to_radians());
        let phi = a - std::f64::consts::FRAC_PI_2;
        let n = [b.sin() * phi.cos(), b.sin() * phi.sin(), b.cos()];
        let (dx, dy) = (p[0] + 15.0, p[1]);
        let r = (dx * dx + dy * dy).sqrt();
        let g = [k * dx / r, k * dy / r, 1.0];
        let gl = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        let cos = (n[0] * g[0] + n[1] * g[1] + n[2] * g[2]) / gl;
        worst_axis = worst_axis.max(cos.clamp(-1.0, 1.0).acos().to_degrees());
    }
    assert!(
        worst_surface < 0.002,
        "pax: a vertex {worst_surface} mm off its layer"
    );
    // vertices get the field's axis; 0.1° is the interpolation bound, plus the 3-decimal
    // rounding of A and B
    assert!(
        worst_axis < 0.11,
        "pax: A/B give a tool axis {worst_axis}° from the cone's"
    );
}

#[test]
fn the_header_parsers_read_what_they_are_given() {
    let (own, rest) = split_flavour(
        "; a\n; warpslice machine = m marlin\n; flavour Marlin 2.1: x\n;   #define AXIS4_NAME 'U'   // linear, mm\n;   axis U travel [-1, 2] mm\nG1 X1\n;   not the header\n",
    );
    assert_eq!(own.len(), 4);
    assert_eq!(rest, ["; a", "G1 X1", ";   not the header"]);
    let (defs, travel) = marlin_header(&own);
    assert_eq!(defs, [(4, 'U', false)]);
    assert_eq!(travel, [('U', -1.0, 2.0)]);
    assert!(std::panic::catch_unwind(|| num("t", "1e-5")).is_err());
    assert!(std::panic::catch_unwind(|| num("t", "NaN")).is_err());
    assert!(std::panic::catch_unwind(|| num("t", "1.")).is_err());
    assert_eq!(num("t", "-0.25"), -0.25);
}
