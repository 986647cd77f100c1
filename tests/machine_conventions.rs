//! The rotary conventions of the rotating-nozzle presets pinned to their reference
//! implementations (issue 16), with numbers computed here from the references' own formulas,
//! never from warpslice's inverse:
//!
//! - **Slicer4RTN** (`rtn-slicer4rtn`, `pax-5axis`): Slicer4RTN's `slicer4rtn` script, subs
//!   `conicSpaceMapping` and `mapGcode` (read in the 0.4.4 source; issue 16 measured the same
//!   on 0.6.0's output): `rot = atan2(y − cy, x − cx)` in degrees (the point about the cone
//!   centre), `rot += 180` with `--mode=inside`; one revolution (`--rot-revolv=1`):
//!   `A = fmod(rot + 360 + rot_offset, 360) − 180`; unlimited (`--rot-revolv=0`):
//!   `A = rabs + rot_offset` with `rabs ≡ 180 + rot (mod 360)`; `--axis=5` also writes
//!   `B = --angle`. Default `--rot-offset=-90`. Its outside mode warps the model with `z + d`
//!   and maps the G-code back with `z − d` (d = r tan α): warpslice's `outward`; inside mode is
//!   `inward`.
//! - **RotBot** (`rotbot`): ZHAW's `Backtransformation_GCode.py` (RotBotSlicer/Transform),
//!   `compute_angle_radial`: `U = arctan2(y, x)` of the point (the cone on the G-code origin),
//!   `+ π` for an inward cone, in degrees, unwrapped next to the previous U
//!   (`compute_U_values`). Its outward cone is `z = z_layer − r`: warpslice's `outward`.
//!
//! Rotation values are compared modulo 360° (an unlimited axis may be on another turn), the
//! 5-axis head up to its equivalent branch `(A, B) ≡ (A + 180°, −B)`. The one-revolution axis
//! is compared as its firmware moves it: seed 002's prototype limits A with `M208 A-170 S1`
//! and `M208 A170 S0`, and RepRapFirmware clamps a move to those limits (`M564 S1`, its
//! default), so Slicer4RTN's A ∈ [−180°, 180°) becomes [`m208`] of it.

use glam::DVec3;
use warpslice::machine::{preset, Machine};

/// Slicer4RTN's default `--rot-offset`, degrees.
const S4RTN_ROT_OFFSET: f64 = -90.0;
/// The cone angle of the RTN presets (their fixed tilt) and of Slicer4RTN's default `--angle`.
const ANGLE: f64 = 45.0;
/// Agreement required, degrees.
const TOL: f64 = 0.01;

/// Perl's `fmod` (POSIX: the sign of the dividend).
fn fmod(a: f64, b: f64) -> f64 {
    a % b
}

/// Slicer4RTN's `rot` of a point about the cone centre (degrees), + 180 in inside mode.
fn s4rtn_rot(p: DVec3, c: [f64; 2], inside: bool) -> f64 {
    let rot = (p.y - c[1]).atan2(p.x - c[0]).to_degrees();
    if inside {
        rot + 180.0
    } else {
        rot
    }
}

/// Slicer4RTN, `--rot-revolv=1`: `fmod(rot + 360 + rot_offset, 360) − 180`.
fn s4rtn_single(p: DVec3, c: [f64; 2], inside: bool) -> f64 {
    fmod(s4rtn_rot(p, c, inside) + 360.0 + S4RTN_ROT_OFFSET, 360.0) - 180.0
}

/// Seed 002's RTN prototype: A limited to [−170°, 170°] (`M208 A-170 S1`, `M208 A170 S0`);
/// RepRapFirmware moves a target beyond a limit to the limit.
fn m208(a: f64) -> f64 {
    a.clamp(-170.0, 170.0)
}

/// Slicer4RTN, `--rot-revolv=0`: `rabs + rot_offset`, `rabs = rabs − fmod(rabs, 360) + 180 +
/// rot` (from rabs = 0: the first turn).
fn s4rtn_unlimited(p: DVec3, c: [f64; 2], inside: bool) -> f64 {
    let rabs = 0.0 - fmod(0.0, 360.0) + 180.0 + s4rtn_rot(p, c, inside);
    rabs + S4RTN_ROT_OFFSET
}

/// RotBot's `compute_angle_radial` (degrees), the cone centre moved to the origin.
fn rotbot_u(p: DVec3, c: [f64; 2], inward: bool) -> f64 {
    let mut angle = (p.y - c[1]).atan2(p.x - c[0]);
    if inward {
        angle += std::f64::consts::PI;
    }
    angle.to_degrees()
}

/// The tool axis warpslice asks for at `p` on a conic layer (angle α, centre c): the unit
/// gradient of T_z = z ± r tan α (docs/machines.md, README: the layer normal), leaning away from
/// the centre on an outward cone and towards it on an inward one.
fn cone_axis(p: DVec3, c: [f64; 2], inward: bool) -> DVec3 {
    let (dx, dy) = (p.x - c[0], p.y - c[1]);
    let r = dx.hypot(dy);
    let k = ANGLE.to_radians().tan() * if inward { -1.0 } else { 1.0 };
    DVec3::new(k * dx / r, k * dy / r, 1.0).normalize()
}

/// |a − b| modulo 360°, degrees in [0, 180].
fn mod360(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// Points on several azimuths about the centre, at a few radii and heights.
fn points(c: [f64; 2]) -> Vec<DVec3> {
    let mut v = Vec::new();
    for (i, az) in [
        0.0, 30.0, 90.0, 135.0, 179.0, 180.0, -150.0, -90.0, -45.0, -1.0,
    ]
    .into_iter()
    .enumerate()
    {
        let r = 3.0 + 4.0 * i as f64;
        let a = f64::to_radians(az);
        v.push(DVec3::new(
            c[0] + r * a.cos(),
            c[1] + r * a.sin(),
            0.5 + i as f64,
        ));
    }
    v
}

fn machine(name: &str) -> Box<dyn Machine> {
    preset(name).and_then(|s| s.build()).unwrap()
}

const CENTRES: [[f64; 2]; 3] = [[0.0, 0.0], [-15.0, 0.0], [12.5, -7.0]];

#[test]
fn rtn_slicer4rtn_writes_slicer4rtns_a_on_outward_and_inward_cones() {
    let m = machine("rtn-slicer4rtn");
    for c in CENTRES {
        for inward in [false, true] {
            for p in points(c) {
                let a = m.inverse(p, cone_axis(p, c, inward), None).unwrap();
                let want = m208(s4rtn_single(p, c, inward));
                assert!(
                    (a[3] - want).abs() < TOL,
                    "centre {c:?} inward {inward} at {p}: A = {} vs Slicer4RTN {want}",
                    a[3]
                );
                // the tip is written as is (no misalignment in the preset)
                assert!((DVec3::new(a[0], a[1], a[2]) - p).length() < 1e-12);
            }
        }
    }
}

#[test]
fn a_few_values_written_out() {
    // Outward cone about (0, 0): a point on +X (azimuth 0°) has A = 0 + 180 − 90 = 90°; on +Y
    // A = 180°, written by Slicer4RTN as −180° and moved by the firmware to −170° (seed 002's
    // M208 limit); on −X A = −90°; on −Y A = 0°. Inward: the opposite side. RotBot and the
    // 5-axis head have no such limit.
    let m = machine("rtn-slicer4rtn");
    let rb = machine("rotbot");
    let pax = machine("pax-5axis");
    let c = [0.0, 0.0];
    for (p, out_a, in_a, out_u) in [
        (DVec3::new(10.0, 0.0, 1.0), 90.0, -90.0, 0.0),
        (DVec3::new(0.0, 10.0, 1.0), -180.0, 0.0, 90.0),
        (DVec3::new(-10.0, 0.0, 1.0), -90.0, 90.0, 180.0),
        (DVec3::new(0.0, -10.0, 1.0), 0.0, -180.0, -90.0),
    ] {
        assert!(mod360(s4rtn_single(p, c, false), out_a) < 1e-9);
        assert!(mod360(s4rtn_single(p, c, true), in_a) < 1e-9);
        assert!(mod360(rotbot_u(p, c, false), out_u) < 1e-9);
        assert!((-180.0..180.0).contains(&s4rtn_single(p, c, false)));
        let a = m.inverse(p, cone_axis(p, c, false), None).unwrap()[3];
        assert!((a - m208(out_a)).abs() < 1e-9, "{p}: {a} vs {out_a}");
        let a = m.inverse(p, cone_axis(p, c, true), None).unwrap()[3];
        assert!((a - m208(in_a)).abs() < 1e-9, "{p}: {a} vs {in_a}");
        let u = rb.inverse(p, cone_axis(p, c, false), None).unwrap()[3];
        assert!(mod360(u, out_u) < 1e-9, "{p}: {u} vs {out_u}");
        let u = rb.inverse(p, cone_axis(p, c, true), None).unwrap()[3];
        assert!(
            mod360(u, out_u + 180.0) < 1e-9,
            "{p}: {u} vs {}",
            out_u + 180.0
        );
        let ab = pax.inverse(p, cone_axis(p, c, false), None).unwrap();
        assert!(
            mod360(ab[3], out_a) < 1e-9 && (ab[4] - 45.0).abs() < 1e-9,
            "{p}: {ab:?}"
        );
    }
}

#[test]
fn rtn_slicer4rtn_unlimited_revolution_writes_slicer4rtns_a() {
    // the preset with Slicer4RTN's --rot-revolv=0
    let json = preset("rtn-slicer4rtn")
        .unwrap()
        .to_json()
        .replace("\"single\"", "\"unlimited\"");
    let m = warpslice::machine::MachineSpec::from_json(&json, "unlimited")
        .and_then(|s| s.build())
        .unwrap();
    rotation_follows(m.as_ref(), "A", "Slicer4RTN", s4rtn_unlimited);
}

/// Walk every cone of [`CENTRES`], outward and inward, with `m` (each pose seeded by the
/// previous one) and compare its rotary axis (axis 3, `letter`) with the reference's value
/// modulo 360°.
fn rotation_follows(
    m: &dyn Machine,
    letter: &str,
    reference: &str,
    want: fn(DVec3, [f64; 2], bool) -> f64,
) {
    for c in CENTRES {
        for inward in [false, true] {
            let mut prev: Option<Vec<f64>> = None;
            for p in points(c) {
                let a = m
                    .inverse(p, cone_axis(p, c, inward), prev.as_deref())
                    .unwrap();
                let w = want(p, c, inward);
                assert!(
                    mod360(a[3], w) < TOL,
                    "centre {c:?} inward {inward} at {p}: {letter} = {} vs {reference} {w}",
                    a[3]
                );
                prev = Some(a);
            }
        }
    }
}

#[test]
fn rotbot_writes_rotbots_u_on_outward_and_inward_cones() {
    let m = machine("rotbot");
    rotation_follows(m.as_ref(), "U", "RotBot", rotbot_u);
}

#[test]
fn pax_5axis_writes_slicer4rtns_a_and_b() {
    let m = machine("pax-5axis");
    for c in CENTRES {
        for inward in [false, true] {
            let mut prev: Option<Vec<f64>> = None;
            for p in points(c) {
                let ab = m
                    .inverse(p, cone_axis(p, c, inward), prev.as_deref())
                    .unwrap();
                // Slicer4RTN --axis=5: A as the RTN (one revolution or not: modulo 360°),
                // B = --angle; (A, B) ≡ (A + 180°, −B)
                let want = s4rtn_single(p, c, inward);
                let same = mod360(ab[3], want) < TOL && (ab[4] - ANGLE).abs() < TOL;
                let flipped = mod360(ab[3], want + 180.0) < TOL && (ab[4] + ANGLE).abs() < TOL;
                assert!(
                    same || flipped,
                    "centre {c:?} inward {inward} at {p}: (A, B) = ({}, {}) vs Slicer4RTN ({want}, {ANGLE})",
                    ab[3],
                    ab[4]
                );
                if prev.is_none() {
                    assert!(same, "without a previous pose B ≥ 0: {ab:?}");
                }
                prev = Some(ab);
            }
        }
    }
}

/// The compass table of docs/machines.md: where the tool axis (tip → nozzle body) leans at each
/// rotation value, per preset.
#[test]
fn compass_directions_of_docs_machines_md() {
    // (preset, R at which the nozzle body leans to +X, +Y, −X, −Y)
    let table: [(&str, [f64; 4]); 3] = [
        ("rtn-slicer4rtn", [90.0, 180.0, -90.0, 0.0]),
        ("rotbot", [0.0, 90.0, 180.0, -90.0]),
        ("pax-5axis", [90.0, 180.0, -90.0, 0.0]),
    ];
    for (name, rs) in table {
        let m = machine(name);
        for (r, lean) in rs
            .into_iter()
            .zip([DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y])
        {
            let mut axes = vec![0.0, 0.0, 5.0, r];
            if name == "pax-5axis" {
                axes.push(45.0);
            }
            let (_, n) = m.forward(&axes).unwrap();
            let horizontal = DVec3::new(n.x, n.y, 0.0).normalize();
            assert!(
                (horizontal - lean).length() < 1e-9,
                "{name}: R = {r} leans to {horizontal}, docs say {lean}"
            );
        }
    }
}

/// A machine file without `rot_convention` (written before it existed) loads, with Slicer4RTN's
/// formula; `"rot_convention": "rotbot"` gives the earlier formula R = φ + rot_offset back.
#[test]
fn old_machine_files_load() {
    use warpslice::machine::MachineSpec;
    let old = r#"{"name":"old","kind":"rtn","axis_names":["X","Y","Z","A"],"tilt_deg":45.0,"rot_offset_deg":-90.0,"revolution":"single","e_parallel_mm":0.0,"e_perpendicular_mm":0.0}"#;
    let m = MachineSpec::from_json(old, "old").unwrap().build().unwrap();
    let p = DVec3::new(10.0, 0.0, 1.0);
    let n = cone_axis(p, [0.0, 0.0], false);
    assert!((m.inverse(p, n, None).unwrap()[3] - 90.0).abs() < 1e-9);
    let kept = old.replace(
        "\"rot_offset_deg\"",
        "\"rot_convention\":\"rotbot\",\"rot_offset_deg\"",
    );
    let m = MachineSpec::from_json(&kept, "old")
        .unwrap()
        .build()
        .unwrap();
    assert!((m.inverse(p, n, None).unwrap()[3] + 90.0).abs() < 1e-9);
    let bad = old.replace(
        "\"rot_offset_deg\"",
        "\"rot_convention\":\"slicer4RTN\",\"rot_offset_deg\"",
    );
    assert!(MachineSpec::from_json(&bad, "bad").is_err());
    let old_pax = r#"{"kind":"pax","pivot_to_tip_mm":0,"rot_offset_deg":-90,"max_tilt_deg":90}"#;
    let m = MachineSpec::from_json(old_pax, "old")
        .unwrap()
        .build()
        .unwrap();
    assert!((m.inverse(p, n, None).unwrap()[3] - 90.0).abs() < 1e-9);
}

/// The B head's sign against seed 000 §4.2.5: the pipeline of the seed writes
/// `b = rad2deg(arctan(f'(x)))` with f the curved transformation (Eq. 1, f'(x) =
/// s·c·2(x + a)/(x_max + a)), so on an outward dome (c = 1) B > 0 where x > 0; and Eq. 5 moves the
/// head by r·cos of the angle from the horizontal, r·sin B, towards the side the nozzle body
/// leans to (r = 46 mm, the preset's pivot-to-tip).
#[test]
fn b_head_sign_follows_seed_000() {
    let m = machine("fullcontrol-prusa-b");
    let (s, c, x_max, a): (f64, f64, f64, f64) = (0.3, 1.0, 10.0, 0.0);
    for x in [-8.0, -3.0, 2.0, 7.5] {
        let slope = s * c / (x_max + a) * 2.0 * (x + a);
        let b_seed = slope.atan().to_degrees();
        // the layer normal of z' = z + f(x): (f'(x), 0, 1)/|…|; above the collision clip's height
        let p = DVec3::new(x, 0.0, 60.0);
        let n = DVec3::new(slope, 0.0, 1.0).normalize();
        let axes = m.inverse(p, n, None).unwrap();
        assert!(
            (axes[3] - b_seed).abs() < TOL,
            "x = {x}: B = {} vs seed {b_seed}",
            axes[3]
        );
        let dx = 46.0 * b_seed.to_radians().sin();
        assert!(
            (axes[0] - (x + dx)).abs() < 1e-9,
            "x = {x}: X = {}",
            axes[0]
        );
    }
}
