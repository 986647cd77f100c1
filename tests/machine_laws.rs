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
    let d = laws::check_start_drift(m).unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "{}: start drift {} checks, largest drift / bound {:.3}",
        m.name(),
        d.points,
        d.worst_angle_rad
    );
}

/// The machines whose realised tool axis is a closed form of the request away from a hold
/// (the B head, the rotating tilted nozzle) bound its drift at most grid poses, and the
/// machines that realise their requests (the triple-Z bed, the 5-axis head) skip the probe
/// from every solved start, so the tessellation skips the held-axis probe there (else law 7
/// checks nothing).
#[test]
fn start_drift_bounds_are_given_where_proven() {
    for (name, least) in [
        ("fullcontrol-prusa-b", 10_000),
        ("rtn-slicer4rtn", 10_000),
        ("rotbot", 10_000),
        ("ratrig-vcore3-3z", 1_000),
        ("pax-5axis", 1_000),
    ] {
        let m = preset(name)
            .and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{e}"));
        let d = laws::check_start_drift(m.as_ref()).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            d.points > least,
            "{name}: only {} start-drift checks",
            d.points
        );
    }
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
        r#"{"name":"b-clip-low","kind":"b-head","clip_b0_deg":10,"clip_z_mm":5}"#,
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

/// The rotating nozzle's bound where its single-revolution range clamps the rotation (rtn.rs
/// `clamped_error`): pieces on the 45° cone whose target rotation crosses the range's end
/// (the kink of the clamp) or stays beyond it in the shadow (the nozzle stopped there: no
/// error), checked against law 6's dense sampling of the firmware's path.
#[test]
fn the_rtn_bound_holds_where_the_range_clamps_the_rotation() {
    let m = preset("rtn-slicer4rtn")
        .and_then(|s| s.build())
        .unwrap_or_else(|e| panic!("{e}"));
    let tilt = 45f64.to_radians();
    let axis = |az_deg: f64| {
        let a = az_deg.to_radians();
        glam::DVec3::new(tilt.sin() * a.cos(), tilt.sin() * a.sin(), tilt.cos())
    };
    // R = φ + 180° − 90°: the range's end 170° is at φ = 80°, −170° at φ = 100°, the shadow's
    // middle at φ = 90°
    let (mut crossing_ratio, mut crossings, mut stopped) = (0.0f64, 0, 0);
    for k in 0..400 {
        let turn = [0.5, 1.0, 2.0, 4.0][k % 4];
        let step = (k / 12) as f64;
        let (az0, az1) = match k % 3 {
            // across 170° (and back), across −170°
            0 => (78.0 + step * 0.03, 78.0 + step * 0.03 + turn),
            1 => (102.0 - step * 0.03, 102.0 - step * 0.03 - turn),
            // in the shadow, short of its middle
            _ => (81.0 + step * 0.1, (81.0 + step * 0.1 + turn).min(89.0)),
        };
        let (p0, p1) = (
            glam::DVec3::new(10.0, 5.0, 2.0),
            glam::DVec3::new(10.4, 5.3, 2.05),
        );
        let (n0, n1) = (axis(az0), axis(az1));
        let a0 = m.inverse(p0, n0, None).unwrap();
        let a1 = m.inverse(p1, n1, Some(&a0)).unwrap();
        let Some((bp, ba)) = m.interpolation_bound((&a0, p0, n0), (&a1, p1, n1)) else {
            panic!("no bound from φ = {az0}° to {az1}° (axes {a0:?} → {a1:?})");
        };
        let (wp, wa) = laws::sampled_error(m.as_ref(), (&a0, p0, n0), (&a1, p1, n1))
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(
            wp <= bp && wa <= ba,
            "φ {az0}° → {az1}° (R {} → {}): sampled {wp:e} mm / {wa:e}° above the bound {bp:e} mm / {ba:e}°",
            a0[3],
            a1[3]
        );
        let crosses = (a0[3] - a1[3]).abs() > 1e-9;
        if k % 3 == 2 {
            // stopped at 170° all along: no error, and a bound of the rounding slack alone
            assert!(!crosses && ba < 1e-5, "φ {az0}° → {az1}°: bound {ba:e}°");
            stopped += 1;
        } else if crosses && wa > 1e-3 {
            crossings += 1;
            crossing_ratio = crossing_ratio.max(wa / ba);
        }
    }
    eprintln!(
        "rtn clamp: {crossings} pieces across a range end, largest sampled / bound {crossing_ratio:.3}; {stopped} stopped in the shadow"
    );
    assert!(crossings > 100 && stopped > 100);
    // within a factor 2 of the truth: the kink's bound halved fails
    assert!(crossing_ratio > 0.5);
}
