//! Travels and turns that clear the whole head, not just the tip (issue 10 §2, "travels that
//! clear the whole head"; §5: "an RTN rotate-around whose nozzle sweeps the part at 1 mm lift",
//! "a B head tilted 45° beside a 20 mm wall").
//!
//! Each case prints material through the machine emitter while marking the unwarp's height grid
//! as the unwarp does, then makes the move under test (a rotate-around the emitter makes on its
//! own, or a travel planned by `unwarp::travel::plan` with the emitter's head profile). The
//! judge is the independent helper `tests/common/collide.rs` (its own G-code reading, forward
//! kinematics `tests/common/fk.rs`, bead points and point-in-solid tests of the machine file's
//! head parts): no head part may meet printed material or the bed on any line of the move. Each
//! case also shows that the tip's old rule (a 1 mm lift, or the printed top + 1 mm) does
//! collide there, so the scene tests something.

mod common;

use common::collide::confirm;
use glam::{DVec2, DVec3};
use warpslice::emit::clearance::HeadProfile;
use warpslice::emit::Emitter;
use warpslice::machine::{preset, FeedMode, MachineEmitter, MachineSpec};
use warpslice::toolpath::{Feature, ToolPoint};
use warpslice::unwarp::travel::{plan, HeadClearance, HeightGrid, TravelPlan};

/// Line width and layer height of the hand-built material, mm (written as `;WIDTH:` and
/// `;HEIGHT:` for the helper).
const W: f64 = 1.0;
const H: f64 = 1.0;

/// A machine emitter fed by hand, with the height grid the unwarp would keep beside it.
struct Print {
    em: MachineEmitter,
    grid: HeightGrid,
    out: Vec<u8>,
    at: Option<DVec3>,
    layer: u32,
}

impl Print {
    fn new(spec: &MachineSpec) -> Print {
        let mut em = MachineEmitter::new(spec, None, FeedMode::Xyz).expect("emitter");
        let mut out = Vec::new();
        em.begin_region(&mut out, DVec3::new(0.0, 0.0, 60.0), DVec3::Z)
            .expect("region");
        for l in ["M83", &format!(";WIDTH:{W}"), &format!(";HEIGHT:{H}")] {
            em.raw(&mut out, l.as_bytes());
        }
        Print {
            em,
            grid: HeightGrid::new(DVec2::new(-20.0, -20.0), DVec2::new(120.0, 120.0)),
            out,
            at: None,
            layer: 0,
        }
    }

    fn lines(&self) -> usize {
        self.out.iter().filter(|&&b| b == b'\n').count()
    }

    /// Go to `p` with tool axis `n` (a travel, or an extrusion of 0.05 mm of filament per mm);
    /// the output lines it wrote (1-based).
    fn go(&mut self, p: DVec3, n: DVec3, extrude: bool) -> std::ops::Range<usize> {
        let first = self.lines() + 1;
        let e = match (extrude, self.at) {
            (true, Some(a)) => {
                self.grid.mark_segment(a, p);
                0.05 * (p - a).length()
            }
            _ => 0.0,
        };
        let tp = ToolPoint {
            p,
            n,
            e,
            f: 1800.0,
            layer: self.layer,
            feature: Feature::Unknown,
            travel: !extrude,
            line: 0,
        };
        self.em
            .point_over(&mut self.out, &tp, true, &self.grid)
            .expect("reachable");
        self.at = Some(p);
        first..self.lines() + 1
    }

    fn layer_change(&mut self) {
        self.layer += 1;
        self.em.raw(&mut self.out, b";LAYER_CHANGE");
    }

    fn text(&self) -> String {
        String::from_utf8(self.out.clone()).unwrap()
    }
}

/// The head parts of the machine file, and "bed".
fn parts(spec: &MachineSpec) -> Vec<String> {
    spec.head()
        .unwrap()
        .parts
        .iter()
        .map(|p| p.name().to_string())
        .collect()
}

/// Every finding of the independent helper on `lines` of `gcode`, any head part, material or bed.
fn collisions(spec: &MachineSpec, gcode: &str, lines: &[usize]) -> Vec<String> {
    let mut found = Vec::new();
    for &l in lines {
        for part in parts(spec) {
            for obstacle in ["material", "bed"] {
                if let Ok(why) = confirm(spec, gcode, l, &part, obstacle) {
                    found.push(format!("line {l}: {}", why.what));
                }
            }
        }
    }
    found
}

/// Z word of a G-code line.
fn z_of(line: &str) -> f64 {
    line.split_whitespace()
        .find_map(|w| w.strip_prefix('Z'))
        .and_then(|v| v.parse().ok())
        .expect("a Z word")
}

/// RTN tool axis leaning 45° towards azimuth `phi_deg` (Slicer4RTN: A = φ + 90°).
fn rtn_axis(phi_deg: f64) -> DVec3 {
    let (t, p) = (45f64.to_radians(), phi_deg.to_radians());
    DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

#[test]
fn rtn_rotate_around_beside_a_taller_part_lifts_until_the_whole_head_clears_it() {
    let spec = preset("rtn-slicer4rtn").unwrap();
    let mut g = Print::new(&spec);
    // a pad 10 × 10 mm, 6 layers of 1 mm (top at z = 6, its face at y = 10.5), printed leaning
    // towards +Y (A = 179)
    let lean = rtn_axis(89.0);
    for k in 1..=6 {
        g.layer_change();
        let z = k as f64 * H;
        for i in 0..=10 {
            let x = i as f64 * W;
            g.go(DVec3::new(x, 0.0, z), lean, false);
            g.go(DVec3::new(x, 10.0, z), lean, true);
        }
    }
    // beside it, 4 mm lower, print across the seam: A 179 → −179 the long way through A = 0,
    // where the head leans towards −Y, the pad
    g.layer_change();
    g.go(DVec3::new(5.0, 12.5, 20.0), lean, false);
    g.go(DVec3::new(5.0, 12.5, 2.0), lean, false);
    g.go(DVec3::new(5.0, 12.5, 2.0), rtn_axis(89.9), true);
    g.go(DVec3::new(5.3, 12.5, 2.0), rtn_axis(90.1), true);
    g.go(DVec3::new(5.6, 12.5, 2.0), rtn_axis(91.0), true);
    let rep = g.em.report();
    assert_eq!(rep.rotate_arounds, 1, "{rep:?}");
    let text = g.text();
    let all: Vec<&str> = text.lines().collect();
    let turn: Vec<usize> = (0..all.len())
        .filter(|&i| all[i].ends_with("; rotate-around"))
        .map(|i| i + 1)
        .collect();
    assert_eq!(turn.len(), 3, "lift, turn, set down: {turn:?}");
    let found = collisions(&spec, &text, &turn);
    assert!(found.is_empty(), "the rotate-around collides: {found:?}");

    // the same turn at the tip's old 1 mm lift sweeps the nozzle into the pad (the scene is one
    // that needs more): lines `turn[0]` and `turn[1]` lowered to 1 mm above the path
    let on_path = z_of(all[turn[0] - 2]);
    let lift = z_of(all[turn[0] - 1]) - on_path;
    assert!(lift > 1.5, "lifted {lift} mm");
    let mut low: Vec<String> = all.iter().map(|l| l.to_string()).collect();
    for &l in &turn[..2] {
        let z = z_of(&low[l - 1]);
        low[l - 1] = low[l - 1].replace(&format!("Z{z:.3}"), &format!("Z{:.3}", z - lift + 1.0));
    }
    let low = low.join("\n");
    let found = collisions(&spec, &low, &turn);
    assert!(
        found
            .iter()
            .any(|f| f.starts_with(&format!("line {}", turn[1]))),
        "a 1 mm lift should sweep the pad: {found:?}"
    );
}

/// The B head preset without its collision clip (so it may tilt 45° near the bed).
fn b_head_unclipped() -> MachineSpec {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/presets/fullcontrol-prusa-b.json"
    ))
    .unwrap();
    assert!(text.contains("\"clip\": true"));
    MachineSpec::from_json(&text.replace("\"clip\": true", "\"clip\": false"), "b.json").unwrap()
}

/// Print a wall at x = 50 (y 30…50, 20 layers of 1 mm: top at 20) with the head vertical, then
/// stand at (25, 40, 15) tilted 45° towards +X (the heater block's long side down towards +X).
fn wall_and_start(spec: &MachineSpec) -> (Print, DVec3) {
    let mut g = Print::new(spec);
    for k in 1..=20 {
        g.layer_change();
        let z = k as f64 * H;
        g.go(DVec3::new(50.0, 30.0, z), DVec3::Z, false);
        g.go(DVec3::new(50.0, 50.0, z), DVec3::Z, true);
    }
    let b45 = DVec3::new(45f64.to_radians().sin(), 0.0, 45f64.to_radians().cos());
    g.go(DVec3::new(15.0, 40.0, 40.0), DVec3::Z, false);
    g.go(DVec3::new(25.0, 40.0, 40.0), b45, false);
    g.go(DVec3::new(25.0, 40.0, 15.0), b45, false);
    (g, b45)
}

/// The travel as the unwarp writes it (`unwarp::core`, `travel_to`): up, across, down.
fn lifted_travel(g: &mut Print, a: DVec3, b: DVec3, n: DVec3, z: f64) -> Vec<usize> {
    let mut lines = Vec::new();
    lines.extend(g.go(DVec3::new(a.x, a.y, z), n, false));
    lines.extend(g.go(DVec3::new(b.x, b.y, z), n, false));
    lines.extend(g.go(b, n, false));
    lines
}

#[test]
fn b_head_tilted_45_degrees_travels_over_a_20_mm_wall_with_the_whole_head_clear() {
    let spec = b_head_unclipped();
    // tip 15 mm up at both ends (the B head's Z reaches down to −2.5: Z = z + 46 cos B − 46)
    let (a, b) = (DVec3::new(25.0, 40.0, 15.0), DVec3::new(75.0, 40.0, 15.0));
    let tilt = 45f64.to_radians();

    let (mut g, n) = wall_and_start(&spec);
    let profile: HeadProfile = g.em.head_profile().expect("a machine has a head profile");
    let head = HeadClearance {
        profile: &profile,
        tilt,
        turn: 0.0,
    };
    let TravelPlan::Lift(z) = plan(&g.grid, a, b, 1.0, Some(head)) else {
        panic!("the travel crosses the wall: it must lift");
    };
    let lines = lifted_travel(&mut g, a, b, n, z);
    let text = g.text();
    let found = collisions(&spec, &text, &lines);
    assert!(found.is_empty(), "lift to {z}: {found:?}");

    // the tip's rule alone lifts to the wall's top + 1 mm, where the heater block (its long
    // side 9.9 mm below the tip at 45°) crosses the wall
    let (mut g, n) = wall_and_start(&spec);
    let TravelPlan::Lift(z_tip) = plan(&g.grid, a, b, 1.0, None) else {
        panic!("the travel crosses the wall: it must lift");
    };
    assert!((z_tip - 21.0).abs() < 1e-9, "{z_tip}");
    assert!(z > z_tip + 5.0, "head lift {z} vs tip lift {z_tip}");
    let lines = lifted_travel(&mut g, a, b, n, z_tip);
    let text = g.text();
    let found = collisions(&spec, &text, &lines);
    assert!(
        found.iter().any(|f| f.contains("heater-block")),
        "the tip's lift should put the block into the wall: {found:?}"
    );
}
