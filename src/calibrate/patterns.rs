//! The test prints of seed 004 §6.2 and their base objects.
//!
//! Each test prints a line onto a base object (printed planar first, white in the thesis) with
//! 5-axis moves made by the machine's inverse kinematics; what the line looks like tells what is
//! miscalibrated. Part frame: the output frame of the machine (bed at z = 0, objects centred on
//! the B axis). The nozzle tip runs one layer height above the surface along its normal.
//!
//! | test | base object | line | axes |
//! |---|---|---|---|
//! | `a-position` (§6.2.1) | box 40 × 20 × 20 | x ∈ [−15, 15] at z = 15 on both faces y = ±10 | A = +90° / −90°, B = 0 |
//! | `a-orientation` (§6.2.2) | half cylinder R 20 along X, 30 long | the centred arc x = 0, ±60° over the top | A = arc angle, B = 0 |
//! | `b-position` (§6.2.3) | plate 50 × 20 × 2 | y = 0, x ∈ [−20, 20] on top | A = 0, B 0 → 720° |
//! | `b-orientation` (§6.2.4) | cylinder R 15, 20 high | around the side at z = 15, ±150° | A = 90°, B = arc angle |
//! | `integrated` (§6.2.5) | hemisphere R 20 | circle centre (10.72, 0) radius 8.98 projected from the top (surface tilt 5°–80°) | A and B together (inverse kinematics) |
//!
//! What to look for: a-position — both lines at the same height (a height difference is twice
//! the Y error of A_pos; unequal widths are a Z error); a-orientation — the line stays centred
//! (ends shifted sideways: A_dir turned about Z, α_{A,z}); b-position — a straight line (waves:
//! B_pos offset, see [`b_position_svg`], Fig. 6.16); b-orientation — a constant distance from
//! the top edge; integrated — a continuous line of even width that does not scar the surface.
//!
//! ## Moves
//! Points are spaced at most `step_mm` (tip) and `step_deg` (rotary axes) apart so the
//! firmware's linear axis interpolation stays within 0.02 mm of the path. Where the test
//! prescribes the rotary angles (all but the integrated test), the pose is solved with the
//! machine's inverse kinematics for the tool axis those angles give (`forward`), seeded with the
//! angles, and checked to keep them. Travel: lift `clearance` along the tool axis, up to a safe Z
//! (above anything the rotating part can reach), turn, come down. G-code: `G21 G90 M83`, `G0`/`G1`
//! with the machine's axis letters, relative E for a `line_width` × `layer_height` bead.

use core::str::FromStr;

use glam::DVec3;

use super::simulate::{self, Deviation, Pair, SimReport};
use super::{finite, CalibError};
use crate::gcode::write::{push_e, push_feed, push_mm};
use crate::machine::spec::Kinematics;
use crate::machine::{check_limits, Machine, MachineSpec};
use crate::mesh::{shapes::cuboid, Mesh};
use crate::num;

/// Largest allowed difference between a prescribed and a solved rotary angle, degrees.
pub const ANGLE_MATCH_DEG: f64 = 1e-6;
/// Points per path are doubled from this until the steps are small enough.
const MIN_POINTS: usize = 16;
/// At most this many points per path.
const MAX_POINTS: usize = 1 << 16;

/// The test prints.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TestKind {
    /// §6.2.1 `a-position`: lines on the box faces y = ±10 at A = ±90°, B = 0 (A_pos Y/Z error).
    APosition,
    /// §6.2.2 `a-orientation`: an arc over a half cylinder along X, A = arc angle (A_dir about Z).
    AOrientation,
    /// §6.2.3 `b-position`: a straight line on a plate while B turns 0 → 720° (B_pos offset).
    BPosition,
    /// §6.2.4 `b-orientation`: a line around a cylinder at A = 90°, B = arc angle (B_dir tilt).
    BOrientation,
    /// §6.2.5 `integrated`: a circle on a hemisphere with A and B from inverse kinematics.
    Integrated,
}

impl TestKind {
    /// All tests.
    pub const ALL: [TestKind; 5] = [
        TestKind::APosition,
        TestKind::AOrientation,
        TestKind::BPosition,
        TestKind::BOrientation,
        TestKind::Integrated,
    ];
    /// The CLI/JSON name.
    pub fn name(self) -> &'static str {
        match self {
            TestKind::APosition => "a-position",
            TestKind::AOrientation => "a-orientation",
            TestKind::BPosition => "b-position",
            TestKind::BOrientation => "b-orientation",
            TestKind::Integrated => "integrated",
        }
    }
    fn what_to_check(self) -> &'static str {
        match self {
            TestKind::APosition => "seed 004 §6.2.1: both lines must be at the same height (a difference is twice the Y error of the A axis position); unequal widths show a Z error",
            TestKind::AOrientation => "seed 004 §6.2.2: the line must stay centred on the cylinder; ends shifted sideways mean A_dir is turned about Z (correct with --a-z-correction)",
            TestKind::BPosition => "seed 004 §6.2.3: the line must be straight; waves mean the B axis position is off (compare with the simulated SVG)",
            TestKind::BOrientation => "seed 004 §6.2.4: the line must keep a constant distance from the top edge",
            TestKind::Integrated => "seed 004 §6.2.5: the circle must be continuous, of even width, and must not scar the surface",
        }
    }
}

impl FromStr for TestKind {
    type Err = CalibError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        TestKind::ALL
            .iter()
            .copied()
            .find(|k| k.name() == s)
            .ok_or_else(|| CalibError::BadInput {
                what: format!("test print '{s}'"),
                message: format!(
                    "unknown; one of {}",
                    TestKind::ALL.map(|k| k.name()).join(", ")
                ),
            })
    }
}

/// Print settings.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct PrintOptions {
    /// Tip height above the surface and bead height, mm.
    pub layer_height: f64,
    /// Bead width, mm.
    pub line_width: f64,
    /// Filament diameter, mm.
    pub filament_diameter: f64,
    /// Printing feed, mm/min.
    pub print_feed: f64,
    /// Travel feed, mm/min.
    pub travel_feed: f64,
    /// Lift along the tool axis before travels, mm.
    pub clearance: f64,
    /// Largest tip step between points, mm.
    pub step_mm: f64,
    /// Largest rotary step between points, degrees.
    pub step_deg: f64,
}

impl Default for PrintOptions {
    fn default() -> Self {
        PrintOptions {
            layer_height: 0.2,
            line_width: 0.4,
            filament_diameter: 1.75,
            print_feed: 600.0,
            travel_feed: 3000.0,
            clearance: 5.0,
            step_mm: 0.5,
            step_deg: 1.0,
        }
    }
}

impl PrintOptions {
    fn check(&self) -> Result<(), CalibError> {
        let v = [
            self.layer_height,
            self.line_width,
            self.filament_diameter,
            self.print_feed,
            self.travel_feed,
            self.clearance,
            self.step_mm,
            self.step_deg,
        ];
        finite("print options", &v)?;
        if v.iter().any(|x| *x <= 0.0) {
            return Err(CalibError::BadInput {
                what: "print options".to_string(),
                message: format!("every value must be > 0, got {self:?}"),
            });
        }
        Ok(())
    }
}

/// The surface a test draws on (part frame, mm), for checking: `distance` is the signed distance
/// from it (outside positive).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Surface {
    /// An axis-aligned box.
    Cuboid {
        /// Lowest corner of the box (part frame), mm.
        min: DVec3,
        /// Highest corner of the box (part frame), mm.
        max: DVec3,
    },
    /// A cylinder about the X axis (radial distance).
    CylinderX {
        /// Cylinder radius, mm (axis: the part frame's X axis).
        radius: f64,
    },
    /// A cylinder about the Z axis (radial distance).
    CylinderZ {
        /// Cylinder radius, mm (axis: the part frame's Z axis).
        radius: f64,
    },
    /// A sphere about the origin.
    Sphere {
        /// Sphere radius, mm (centre: the part frame's origin).
        radius: f64,
    },
}

impl Surface {
    /// Signed distance of `p` from the surface, mm (outside positive).
    pub fn distance(&self, p: DVec3) -> f64 {
        match *self {
            Surface::Cuboid { min, max } => {
                let c = (min + max) / 2.0;
                let h = (max - min) / 2.0;
                let q = (p - c).abs() - h;
                q.max(DVec3::ZERO).length() + q.x.max(q.y).max(q.z).min(0.0)
            }
            Surface::CylinderX { radius } => (p.y * p.y + p.z * p.z).sqrt() - radius,
            Surface::CylinderZ { radius } => (p.x * p.x + p.y * p.y).sqrt() - radius,
            Surface::Sphere { radius } => p.length() - radius,
        }
    }
}

/// One G-code move of a test print.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PrintMove {
    /// Axis values written (machine order).
    pub axes: Vec<f64>,
    /// Extruding.
    pub extrude: bool,
    /// The intended tip for moves along a path (part frame).
    pub tip: Option<DVec3>,
}

/// What a test print contains.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PrintReport {
    /// Number of moves in [`TestPrint::moves`] (travels and printing moves).
    pub moves: usize,
    /// Number of those moves that extrude.
    pub print_moves: usize,
    /// Printed length, mm.
    pub length_mm: f64,
    /// Filament, mm.
    pub e_mm: f64,
    /// Range [min, max] of the 4th axis (A) over the path points, degrees.
    pub a_range: [f64; 2],
    /// Range [min, max] of the 5th axis (B) over the path points, degrees.
    pub b_range: [f64; 2],
    /// Machine Z used for travels, mm.
    pub z_safe: f64,
}

/// A generated test print.
#[derive(Clone, Debug)]
pub struct TestPrint {
    /// Which test this is.
    pub kind: TestKind,
    /// The G-code.
    pub gcode: Vec<u8>,
    /// The base object (print it planar first).
    pub base: Mesh,
    /// The surface drawn on.
    pub surface: Surface,
    /// The intended tip paths (part frame), one polyline per line drawn.
    pub paths: Vec<Vec<DVec3>>,
    /// Every move written, in order.
    pub moves: Vec<PrintMove>,
    /// Counts, lengths and axis ranges of the G-code (see [`PrintReport`]).
    pub report: PrintReport,
}

/// How a path point's pose is found.
#[derive(Clone, Copy, Debug)]
enum How {
    /// Inverse kinematics for this tool axis.
    Normal,
    /// These rotary angles (A, B), degrees.
    Angles(f64, f64),
}

/// A path: s ∈ [0, 1] → (surface point, unit surface normal, how).
type PathFn = Box<dyn Fn(f64) -> (DVec3, DVec3, How)>;

const BOX_MIN: DVec3 = DVec3::new(-20.0, -10.0, 0.0);
const BOX_MAX: DVec3 = DVec3::new(20.0, 10.0, 20.0);
const HALF_CYL_R: f64 = 20.0;
const HALF_CYL_L: f64 = 30.0;
const PLATE_MIN: DVec3 = DVec3::new(-25.0, -10.0, 0.0);
const PLATE_MAX: DVec3 = DVec3::new(25.0, 10.0, 2.0);
const CYL_R: f64 = 15.0;
const CYL_H: f64 = 20.0;
const DOME_R: f64 = 20.0;
/// Segments of the round base objects (chord error R(1 − cos(π/n)) ≤ 0.004 mm for R 20).
const SEGMENTS: u32 = 180;

fn sc(deg: f64) -> (f64, f64) {
    let r = num::rad(deg);
    (num::sin(r), num::cos(r))
}

/// The integrated test's circle: centre (c, 0), radius r, so the dome's tilt runs 5°…80°.
fn integrated_circle() -> (f64, f64) {
    let lo = DOME_R * sc(5.0).0;
    let hi = DOME_R * sc(80.0).0;
    ((lo + hi) / 2.0, (hi - lo) / 2.0)
}

/// The base object of a test (part frame, on the bed), closed and outward.
pub fn base_object(kind: TestKind) -> Mesh {
    match kind {
        TestKind::APosition => cuboid(BOX_MIN, BOX_MAX),
        TestKind::AOrientation => half_cylinder_x(HALF_CYL_R, HALF_CYL_L, SEGMENTS / 2),
        TestKind::BPosition => cuboid(PLATE_MIN, PLATE_MAX),
        TestKind::BOrientation => crate::shapes::cylinder(CYL_R, CYL_H, SEGMENTS * 2),
        TestKind::Integrated => dome(DOME_R, SEGMENTS / 4, SEGMENTS * 2),
    }
}

/// The base object as binary STL bytes.
pub fn base_stl(kind: TestKind) -> Vec<u8> {
    crate::mesh::write_stl(
        &base_object(kind),
        &format!("warpslice calibration base object {}", kind.name()),
    )
}

/// `{y² + z² ≤ r², z ≥ 0, |x| ≤ len/2}`: `n ≥ 2` segments over the half circle.
fn half_cylinder_x(r: f64, len: f64, n: u32) -> Mesh {
    let n = n.max(2);
    // Profile (y, z), counter-clockwise seen from +X: from (r, 0) over the top to (−r, 0).
    let prof: Vec<(f64, f64)> = (0..=n)
        .map(|i| {
            let (s, c) = sc(180.0 * i as f64 / n as f64);
            (r * c, r * s)
        })
        .collect();
    let m = prof.len() as u32;
    let mut vertices = Vec::new();
    for x in [-len / 2.0, len / 2.0] {
        for &(y, z) in &prof {
            vertices.push(DVec3::new(x, y, z));
        }
    }
    let mut triangles = Vec::new();
    // Sides (the closing edge from (−r,0) back to (r,0) is the flat bottom).
    for i in 0..m {
        let j = (i + 1) % m;
        let (a0, a1, b0, b1) = (i, j, m + i, m + j);
        triangles.push([a0, a1, b1]);
        triangles.push([a0, b1, b0]);
    }
    // Caps: fans (the profile is convex). −X cap seen from −X is clockwise → reverse.
    for i in 1..m - 1 {
        triangles.push([0, i + 1, i]);
        triangles.push([m, m + i, m + i + 1]);
    }
    Mesh {
        vertices,
        triangles,
    }
}

/// A hemisphere of radius r on z = 0 (centre at the origin) with a flat bottom.
fn dome(r: f64, rings: u32, segments: u32) -> Mesh {
    let (rings, segments) = (rings.max(2), segments.max(3));
    let mut vertices = vec![DVec3::new(0.0, 0.0, r), DVec3::ZERO];
    for k in 1..=rings {
        let (s, c) = sc(90.0 * k as f64 / rings as f64);
        for j in 0..segments {
            let (sj, cj) = sc(360.0 * j as f64 / segments as f64);
            vertices.push(DVec3::new(r * s * cj, r * s * sj, r * c));
        }
    }
    let idx = |k: u32, j: u32| 2 + (k - 1) * segments + (j % segments);
    let mut triangles = Vec::new();
    for j in 0..segments {
        triangles.push([0, idx(1, j), idx(1, j + 1)]);
        for k in 1..rings {
            let (a, b, c, d) = (idx(k, j), idx(k, j + 1), idx(k + 1, j), idx(k + 1, j + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
        triangles.push([1, idx(rings, j + 1), idx(rings, j)]);
    }
    Mesh {
        vertices,
        triangles,
    }
}

fn surface(kind: TestKind) -> Surface {
    match kind {
        TestKind::APosition => Surface::Cuboid {
            min: BOX_MIN,
            max: BOX_MAX,
        },
        TestKind::AOrientation => Surface::CylinderX { radius: HALF_CYL_R },
        TestKind::BPosition => Surface::Cuboid {
            min: PLATE_MIN,
            max: PLATE_MAX,
        },
        TestKind::BOrientation => Surface::CylinderZ { radius: CYL_R },
        TestKind::Integrated => Surface::Sphere { radius: DOME_R },
    }
}

fn paths(kind: TestKind) -> Vec<PathFn> {
    match kind {
        TestKind::APosition => [(1.0, 90.0), (-1.0, -90.0)]
            .into_iter()
            .map(|(side, a): (f64, f64)| -> PathFn {
                Box::new(move |s| {
                    let y = if side > 0.0 { BOX_MAX.y } else { BOX_MIN.y };
                    (
                        DVec3::new(-15.0 + 30.0 * s, y, 15.0),
                        DVec3::Y * side,
                        How::Angles(a, 0.0),
                    )
                })
            })
            .collect(),
        TestKind::AOrientation => vec![Box::new(|s| {
            let phi = -60.0 + 120.0 * s;
            let (si, co) = sc(phi);
            let n = DVec3::new(0.0, si, co);
            (n * HALF_CYL_R, n, How::Angles(phi, 0.0))
        })],
        TestKind::BPosition => vec![Box::new(|s| {
            (
                DVec3::new(-20.0 + 40.0 * s, 0.0, PLATE_MAX.z),
                DVec3::Z,
                How::Angles(0.0, 720.0 * s),
            )
        })],
        TestKind::BOrientation => vec![Box::new(|s| {
            let beta = -150.0 + 300.0 * s;
            let (si, co) = sc(beta);
            let n = DVec3::new(si, co, 0.0);
            (
                n * CYL_R + DVec3::Z * (CYL_H - 5.0),
                n,
                How::Angles(90.0, beta),
            )
        })],
        TestKind::Integrated => vec![Box::new(|s| {
            let (c, r) = integrated_circle();
            let (si, co) = sc(360.0 * s);
            let (x, y) = (c + r * co, r * si);
            let z = (DOME_R * DOME_R - x * x - y * y).max(0.0).sqrt();
            let p = DVec3::new(x, y, z);
            (p, p / DOME_R, How::Normal)
        })],
    }
}

/// Solve one pose. `Angles`: tool axis from `forward` at the angles, inverse seeded with them,
/// angles checked.
fn solve(
    m: &dyn Machine,
    tip: DVec3,
    normal: DVec3,
    how: How,
    prev: Option<&[f64]>,
) -> Result<(Vec<f64>, DVec3), CalibError> {
    match how {
        How::Normal => Ok((m.inverse(tip, normal, prev)?, normal)),
        How::Angles(a, b) => {
            let seed = [0.0, 0.0, 0.0, a, b];
            let (_, n) = m.forward(&seed)?;
            let axes = m.inverse(tip, n, Some(&seed))?;
            if (axes[3] - a).abs() > ANGLE_MATCH_DEG || (axes[4] - b).abs() > ANGLE_MATCH_DEG {
                return Err(CalibError::BadInput {
                    what: format!("machine {}", m.name()),
                    message: format!(
                        "cannot hold the test's angles A = {a}°, B = {b}° at ({:.3}, {:.3}, {:.3}) (got {:.6}°, {:.6}°)",
                        tip.x, tip.y, tip.z, axes[3], axes[4]
                    ),
                });
            }
            Ok((axes, n))
        }
    }
}

struct Solved {
    tips: Vec<DVec3>,
    axes: Vec<Vec<f64>>,
    /// Tool axis at the first and last point (for lifting).
    n_first: DVec3,
    n_last: DVec3,
    how_first: How,
    how_last: How,
}

fn solve_path(m: &dyn Machine, f: &PathFn, opts: &PrintOptions) -> Result<Solved, CalibError> {
    let mut n = MIN_POINTS;
    loop {
        let mut tips = Vec::with_capacity(n + 1);
        let mut axes: Vec<Vec<f64>> = Vec::with_capacity(n + 1);
        let mut ns = Vec::with_capacity(n + 1);
        let mut hows = Vec::with_capacity(n + 1);
        for i in 0..=n {
            let (q, nn, how) = f(i as f64 / n as f64);
            let tip = q + nn * opts.layer_height;
            let prev = axes.last().map(|a| a.as_slice());
            let (a, real_n) = solve(m, tip, nn, how, prev)?;
            tips.push(tip);
            axes.push(a);
            ns.push(real_n);
            hows.push(how);
        }
        let fine = tips
            .windows(2)
            .all(|w| (w[1] - w[0]).length() <= opts.step_mm)
            && axes
                .windows(2)
                .all(|w| (3..w[0].len()).all(|k| (w[1][k] - w[0][k]).abs() <= opts.step_deg));
        if fine || n >= MAX_POINTS {
            return Ok(Solved {
                n_first: ns[0],
                n_last: ns[n],
                how_first: hows[0],
                how_last: hows[n],
                tips,
                axes,
            });
        }
        n *= 2;
    }
}

struct Writer<'m> {
    m: &'m dyn Machine,
    names: Vec<String>,
    out: Vec<u8>,
    moves: Vec<PrintMove>,
}

impl Writer<'_> {
    fn line(
        &mut self,
        rapid: bool,
        axes: &[f64],
        e: f64,
        f: f64,
        tip: Option<DVec3>,
    ) -> Result<(), CalibError> {
        check_limits(
            self.m.name(),
            self.m.limits(),
            axes,
            tip.unwrap_or(DVec3::ZERO),
        )?;
        self.out
            .extend_from_slice(if rapid { b"G0" } else { b"G1" });
        for (name, &v) in self.names.iter().zip(axes) {
            self.out.push(b' ');
            self.out.extend_from_slice(name.as_bytes());
            push_mm(&mut self.out, v);
        }
        if e > 0.0 {
            self.out.extend_from_slice(b" E");
            push_e(&mut self.out, e);
        }
        self.out.extend_from_slice(b" F");
        push_feed(&mut self.out, f);
        self.out.push(b'\n');
        self.moves.push(PrintMove {
            axes: axes.to_vec(),
            extrude: e > 0.0,
            tip,
        });
        Ok(())
    }
}

/// The machine's part offset and the distance between its axis lines (an `ab-table`).
fn table_geometry(spec: &MachineSpec) -> Result<(DVec3, f64, f64), CalibError> {
    match &spec.kinematics {
        Kinematics::AbTable(p) => {
            let o = super::origin::closest_approach(
                p.a_pos,
                p.a_dir.normalize_or_zero(),
                p.b_pos,
                p.b_dir.normalize_or_zero(),
            )?;
            let a_closest = p.a_pos + p.a_dir.normalize_or_zero() * o.0;
            let b_closest = p.b_pos + p.b_dir.normalize_or_zero() * o.1;
            Ok((p.part_offset, (a_closest - b_closest).length(), p.z_wobble_mm.abs()))
        }
        _ => Err(CalibError::BadInput {
            what: format!("machine {}", spec.name),
            message: "the test prints are for A/B tables (kind 'ab-table', e.g. the open5x-ab preset or a calibrated machine JSON)".to_string(),
        }),
    }
}

/// Generate a test print for the machine `spec` (an `ab-table`).
pub fn test_print(
    spec: &MachineSpec,
    kind: TestKind,
    opts: &PrintOptions,
) -> Result<TestPrint, CalibError> {
    opts.check()?;
    let (part_offset, d_axes, wobble) = table_geometry(spec)?;
    let machine = spec.build()?;
    let m: &dyn Machine = machine.as_ref();
    let base = base_object(kind);
    let r_bound = base
        .vertices
        .iter()
        .map(|v| (*v + part_offset).length())
        .fold(0.0, f64::max);
    let z_safe = r_bound + 2.0 * d_axes + 2.0 * opts.clearance + opts.layer_height + wobble;
    let solved = paths(kind)
        .iter()
        .map(|f| solve_path(m, f, opts))
        .collect::<Result<Vec<_>, _>>()?;
    let mut w = Writer {
        m,
        names: m.axis_names(),
        out: Vec::new(),
        moves: Vec::new(),
    };
    let head = format!(
        "; warpslice calibration test print: {} for machine {}\n; {}\n; base object: print it planar first (warpslice calibrate test-print --base); part frame: bed at z = 0, centred on the B axis\n; add your start G-code (homing, heating, tool selection) before this and your end G-code after it\nG21\nG90\nM83\n",
        kind.name(),
        m.name(),
        kind.what_to_check()
    );
    w.out.extend_from_slice(head.as_bytes());
    // Up first, alone, wherever the nozzle is: nothing turns or moves sideways near the part.
    if let Some(z) = w.names.get(2) {
        let mut up = format!("G0 {z}").into_bytes();
        push_mm(&mut up, z_safe);
        up.extend_from_slice(b" F");
        push_feed(&mut up, opts.travel_feed);
        up.push(b'\n');
        w.out.extend_from_slice(&up);
    }
    let e_per_mm = opts.line_width * opts.layer_height
        / (core::f64::consts::PI * (opts.filament_diameter / 2.0).powi(2));
    let mut rep = PrintReport {
        z_safe,
        a_range: [f64::INFINITY, f64::NEG_INFINITY],
        b_range: [f64::INFINITY, f64::NEG_INFINITY],
        ..PrintReport::default()
    };
    let safe = |a: &[f64]| {
        let mut v = a.to_vec();
        v[2] = z_safe;
        v
    };
    for s in &solved {
        let first = &s.axes[0];
        let approach_tip = s.tips[0] + s.n_first * opts.clearance;
        let (approach, _) = solve(m, approach_tip, s.n_first, s.how_first, Some(first))?;
        w.line(true, &safe(&approach), 0.0, opts.travel_feed, None)?;
        w.line(true, &approach, 0.0, opts.travel_feed, None)?;
        w.line(false, first, 0.0, opts.print_feed, Some(s.tips[0]))?;
        for i in 1..s.axes.len() {
            let len = (s.tips[i] - s.tips[i - 1]).length();
            let e = len * e_per_mm;
            w.line(false, &s.axes[i], e, opts.print_feed, Some(s.tips[i]))?;
            rep.length_mm += len;
            rep.e_mm += e;
        }
        for a in &s.axes {
            rep.a_range = [rep.a_range[0].min(a[3]), rep.a_range[1].max(a[3])];
            rep.b_range = [rep.b_range[0].min(a[4]), rep.b_range[1].max(a[4])];
        }
        let last = s.axes.len() - 1;
        let lift_tip = s.tips[last] + s.n_last * opts.clearance;
        let (lift, _) = solve(m, lift_tip, s.n_last, s.how_last, Some(&s.axes[last]))?;
        w.line(true, &lift, 0.0, opts.travel_feed, None)?;
        w.line(true, &safe(&lift), 0.0, opts.travel_feed, None)?;
    }
    // Back to A = 0 at the safe height (B stays: it may have turned several revolutions).
    if let Some(last) = w.moves.last().map(|m| m.axes.clone()) {
        let mut home = last;
        home[3] = 0.0;
        w.line(true, &home, 0.0, opts.travel_feed, None)?;
    }
    rep.moves = w.moves.len();
    rep.print_moves = w.moves.iter().filter(|m| m.extrude).count();
    w.out.extend_from_slice(
        format!(
            "; printed {:.2} mm of line, {:.4} mm of filament\n",
            rep.length_mm, rep.e_mm
        )
        .as_bytes(),
    );
    Ok(TestPrint {
        kind,
        gcode: w.out,
        base,
        surface: surface(kind),
        paths: solved.into_iter().map(|s| s.tips).collect(),
        moves: w.moves,
        report: rep,
    })
}

/// Fig. 6.16: the B position test printed by `spec` on a machine whose B axis is really
/// `b_offset` (mm) away → the simulation and its SVG (the error drawn `exaggerate` times).
pub fn b_position_svg(
    spec: &MachineSpec,
    b_offset: DVec3,
    opts: &PrintOptions,
    exaggerate: f64,
) -> Result<(SimReport, String), CalibError> {
    finite("B offset", &b_offset.to_array())?;
    let print = test_print(spec, TestKind::BPosition, opts)?;
    let truth = simulate::deviate(
        spec,
        &Deviation {
            b_offset,
            ..Deviation::default()
        },
    )?;
    let pair = Pair::new(spec, &truth)?;
    let (axes, tips): (Vec<Vec<f64>>, Vec<DVec3>) = print
        .moves
        .iter()
        .filter_map(|mv| mv.tip.map(|t| (mv.axes.clone(), t)))
        .unzip();
    let rep = simulate::simulate_axes(&pair, &axes, &tips)?;
    let svg = simulate::svg(
        &rep,
        &format!(
            "B position test, B off by ({}, {}) mm",
            b_offset.x, b_offset.y
        ),
        exaggerate,
    );
    Ok((rep, svg))
}
