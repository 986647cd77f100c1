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
        r#"{"name":"open5x-calibrated","kind":"ab-table","a_pos":[3,-1.2,-40.5],"a_dir":[0.9998,0.012,-0.008],"b_pos":[0.4,0.7,0],"b_dir":[0.004,-0.006,1],"part_offset":[0,0,12],"z_wobble_mm":0.13}"#,
        r#"{"name":"open5x-wobble","kind":"ab-table","z_wobble_mm":-0.13,"b_pos":[0,0,5],"a_pos":[0,0,-30]}"#,
        r#"{"name":"r-theta-0","kind":"r-theta","pivot_to_tip_mm":0}"#,
        r#"{"name":"lathe-offset","kind":"lathe-a","axis_y_mm":10,"axis_z_mm":60}"#,
        r#"{"name":"three-z-small","kind":"three-z","balls_xy":[[0,0],[200,0],[100,180]],"ball_z_mm":-20,"slot_angles_deg":[30,150,-90],"max_tilt_deg":20,"build_volume_mm":[200,180,100]}"#,
    ] {
        check(spec(json).as_ref());
    }
}
