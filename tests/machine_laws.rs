//! The machine laws (round trip on the grid, continuity on paths) for every shipped preset and
//! for non-default variants (pivot offsets, misalignment, calibrated table axes, wobble).

use warpslice::machine::{laws, preset, preset_names, Machine, MachineSpec};

fn check(m: &dyn Machine) {
    let r = laws::check_round_trip(m).unwrap_or_else(|e| panic!("{e}"));
    let c = laws::check_paths(m).unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "{}: round trip {} points, worst {:.3e} mm {:.3e} rad; paths {} points, worst {:.3e} mm {:.3e} rad, rotary step {:.3}°",
        m.name(),
        r.points,
        r.worst_position_mm,
        r.worst_angle_rad,
        c.points,
        c.worst_position_mm,
        c.worst_angle_rad,
        c.worst_rotary_step_deg
    );
    assert!(r.points > 100 && c.points > 1000);
    let near = laws::check_nearest(m).unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "{}: nearest axis {} points, worst excess {:.3}°",
        m.name(),
        near.points,
        near.worst_angle_rad.to_degrees()
    );
    assert!(near.points > 100);
    let f = laws::check_fixed_pose(m).unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "{}: fixed pose {} points, worst {:.3e} mm {:.3e} rad",
        m.name(),
        f.points,
        f.worst_position_mm,
        f.worst_angle_rad
    );
    assert_eq!(
        f.points > 0,
        m.linear_at_fixed_pose(),
        "{}: the fixed-pose law found no segment to check",
        m.name()
    );
    let h = laws::check_head_frame(m).unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "{}: head frame {} frames, worst orthonormality {:.3e}, z {:.3e} rad, x turn {:.3}°/step",
        m.name(),
        h.points,
        h.worst_position_mm,
        h.worst_angle_rad,
        h.worst_rotary_step_deg
    );
    let b = laws::check_interpolation_bound(m).unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "{}: closed-form bound on {} pieces, largest sampled error / bound {:.3} (tip), {:.3} (axis)",
        m.name(),
        b.points,
        b.worst_position_mm,
        b.worst_angle_rad
    );
}

/// The machine kinds with a closed-form interpolation bound give one on most short pieces of
/// the law (else the law checks nothing and the interpolation check samples everything).
#[test]
fn closed_form_bounds_are_given_where_proven() {
    for name in [
        "cartesian",
        "pax-5axis",
        "rtn-slicer4rtn",
        "rotbot",
        "fullcontrol-prusa-b",
        "open5x-ab",
        "ratrig-vcore3-3z",
    ] {
        let m = preset(name)
            .and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{e}"));
        let b = laws::check_interpolation_bound(m.as_ref()).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            b.points > 500,
            "{name}: only {} pieces had a closed-form bound",
            b.points
        );
    }
}

fn spec(json: &str) -> Box<dyn Machine> {
    MachineSpec::from_json(json, "test")
        .and_then(|s| s.build())
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_preset_obeys_the_laws() {
    for name in preset_names() {
        let m = preset(name)
            .and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{e}"));
        check(m.as_ref());
        // The collision check places the heater block with the head frame; only the lathe
        // (refused by the collision check) may lack one.
        assert!(
            name == "lathe-a" || laws::check_head_frame(m.as_ref()).unwrap().points > 100,
            "{name}: no head frame"
        );
    }
}

#[test]
fn variants_obey_the_laws() {
    for json in [
        r#"{"name":"cart-clamped","kind":"cartesian","max_tilt_deg":30}"#,
        r#"{"name":"b-noclip","kind":"b-head","clip":false,"b_limit_deg":90}"#,
        r#"{"name":"rotbot-misaligned","kind":"rtn","revolution":"unlimited","axis_names":["X","Y","Z","U"],"e_parallel_mm":0.3,"e_perpendicular_mm":-0.2}"#,
        r#"{"name":"rtn-single-misaligned","kind":"rtn","e_parallel_mm":0.1,"e_perpendicular_mm":0.25,"tilt_deg":30}"#,
        r#"{"name":"pax-offset","kind":"pax","pivot_to_tip_mm":35,"rot_offset_deg":-90,"max_tilt_deg":100}"#,
        r#"{"name":"pax-offset-90","kind":"pax","pivot_to_tip_mm":35,"max_tilt_deg":90}"#,
        r#"{"name":"open5x-calibrated","kind":"ab-table","a_pos":[3,-1.2,-40.5],"a_dir":[0.9998,0.012,-0.008],"b_pos":[0.4,0.7,0],"b_dir":[0.004,-0.006,1],"part_offset":[0,0,12],"z_wobble_mm":0.13}"#,
        r#"{"name":"open5x-wobble","kind":"ab-table","z_wobble_mm":-0.13,"b_pos":[0,0,5],"a_pos":[0,0,-30]}"#,
        r#"{"name":"r-theta-0","kind":"r-theta","pivot_to_tip_mm":0}"#,
        r#"{"name":"lathe-offset","kind":"lathe-a","axis_y_mm":10,"axis_z_mm":60}"#,
        r#"{"name":"lathe-y","kind":"lathe-a","axis_y_mm":-5,"axis_z_mm":40,"with_y":true}"#,
        r#"{"name":"three-z-small","kind":"three-z","balls_xy":[[0,0],[200,0],[100,180]],"ball_z_mm":-20,"slot_angles_deg":[30,150,-90],"max_tilt_deg":20,"build_volume_mm":[200,180,100]}"#,
        r#"{"name":"three-z-skew","kind":"three-z","balls_xy":[[0,0],[250,20],[120,220]],"ball_z_mm":-30,"slot_angles_deg":[10,170,-80],"max_tilt_deg":25,"build_volume_mm":[220,200,120],"rail_travel_mm":[60,20]}"#,
    ] {
        check(spec(json).as_ref());
    }
}

/// xorshift64*: a fixed pseudo-random sequence (no dependency, same on every run).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Any previous pose (far away, other branch, rotary axes several turns away where unlimited)
/// still gives the exact pose: the branch choice never breaks the round trip.
#[test]
fn any_previous_pose_keeps_the_round_trip() {
    use glam::DVec3;
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for name in preset_names() {
        let m = preset(name).and_then(|s| s.build()).unwrap();
        let ws = m.workspace();
        let pose = |rng: &mut Rng| {
            let p = ws.min + (ws.max - ws.min) * DVec3::new(rng.next(), rng.next(), rng.next());
            let t = ws.max_tilt_deg.min(180.0) * rng.next();
            (p, laws::axis(t, 360.0 * rng.next() - 180.0))
        };
        for _ in 0..2000 {
            let (p0, n0) = pose(&mut rng);
            let mut prev = m.inverse(p0, n0, None).unwrap();
            for (k, l) in m.limits().iter().enumerate() {
                if l.rotary && l.max.is_infinite() {
                    prev[k] += 360.0 * ((rng.next() * 7.0).floor() - 3.0);
                }
            }
            let (p, n) = pose(&mut rng);
            let a = m.inverse(p, n, Some(&prev)).unwrap();
            let (q, nq) = m.forward(&a).unwrap();
            let want = m.realised_axis(p, n);
            let err = warpslice::num::angle_between(nq, want) - m.branch_freedom(p, n);
            assert!(
                (q - p).length() < 1e-9,
                "{name}: {p} {n} prev {prev:?} → {a:?} gives {q}"
            );
            assert!(
                err < 1e-9,
                "{name}: {p} {n} prev {prev:?} → {a:?} gives axis {nq}, want {want}"
            );
            for (k, l) in m.limits().iter().enumerate() {
                if l.rotary && l.max.is_infinite() {
                    assert!(
                        (a[k] - prev[k]).abs() <= 180.0 + 1e-9,
                        "{name}: axis {} not unwrapped next to {}: {}",
                        l.name,
                        prev[k],
                        a[k]
                    );
                }
            }
        }
    }
}
