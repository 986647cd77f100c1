//! The collision check (issue 10 §2, §5) on hand-built machine G-code, one case per finding;
//! each asserts the exact output line (1-based) reported and the part, and checks the depth
//! against geometry computed here, independently of the engine: closed-form lowest points of
//! the posed solids (cone generator, box edge) and a point-in-solid scan of vertical lines.
//!
//! Cases: the tip plunging through printed material (cartesian); a B head tilted 45° beside a
//! 20 mm wall, the heater block crossing the wall with the tip clear; an RTN rotate-around
//! whose turn sweeps the nozzle into a part at 1 mm lift; the B head's heater block reaching
//! the bed at 25° near the plate's edge (and not beyond it); a clean file (a printed pad)
//! reporting nothing; the lathe refused by name.

#[path = "common/check_files.rs"]
mod check_files;
#[path = "common/synthetic.rs"]
mod synthetic;

use check_files::{
    bhead_axes, bhead_bed_case, bhead_wall_case, clean_pad_case, plunge_case, rotary_pad as pad,
    rtn_rotate_around_case, Lines as Gcode, WallCase,
};

use warpslice::collision::{check_gcode, refusal, CONTACT_TOLERANCE_MM};
use warpslice::emit::CollisionFinding;
use warpslice::error::Coded;
use warpslice::machine::{preset, MachineSpec};

fn findings(gcode: &str, spec: &MachineSpec) -> Vec<CollisionFinding> {
    check_gcode(gcode.as_bytes(), spec).expect("check").0
}

fn only_line(f: &[CollisionFinding]) -> Vec<u64> {
    let mut l: Vec<u64> = f.iter().map(|f| f.line).collect();
    l.dedup();
    l
}

#[test]
fn clean_pad_reports_nothing() {
    let spec = preset("cartesian").unwrap();
    let f = findings(&clean_pad_case(), &spec);
    assert!(f.is_empty(), "a clean print reported {f:?}");
}

#[test]
fn tip_plunging_through_printed_material_is_found_on_its_line() {
    let spec = preset("cartesian").unwrap();
    // a pad with its top at 2.0 mm, the nozzle plunged to Z 1 at its middle
    let (text, plunge, retreat) = plunge_case();
    let f = findings(&text, &spec);
    // the plunge, and the way back out (it starts inside the pad)
    assert_eq!(only_line(&f), vec![plunge, retreat], "{f:?}");
    let n = f.iter().find(|f| f.part == "nozzle").expect("the nozzle");
    assert_eq!((n.obstacle.as_str(), n.layer), ("material", 10));
    // the flat tip sits 1 mm below the top of the pad (layer 10, the current layer). The
    // contact rule (src/collision/contact.rs, written here from its formula): a vertical line
    // at horizontal distance ρ ≤ 0.5 from the axis is contact up to the surface
    // z = tip + (ρ + w/2)·tan 30°, and the current layer's beads may be pressed by one layer
    // height (0.2): depth(ρ) = 2.0 − (1.0 + (ρ + 0.225)·tan 30°) − 0.2. The engine's columns
    // are cell centres, the nearest at most half a cell diagonal (0.1414 mm) from the tip
    let depth = |rho: f64| 2.0 - (1.0 + (rho + 0.225) * 30f64.to_radians().tan()) - 0.2;
    assert!(
        n.depth_mm <= depth(0.0) + 1e-9 && n.depth_mm >= depth(0.1415) - 1e-9,
        "{n:?}: depth at the axis {}, at the nearest cell centre {}",
        depth(0.0),
        depth(0.1415)
    );
    let e = refusal("cartesian", &f).expect("refused");
    assert_eq!(e.code(), "machine.collision");
    let msg = e.to_string();
    assert!(
        msg.contains(&format!("output line {plunge} (layer 10; no input line"))
            && msg.contains("nozzle"),
        "{msg}"
    );
    // a machine G-code checked alone has no slicer's line
    assert!(f.iter().all(|f| f.input_line.is_none()), "{f:?}");
}

/// B head (seed 000, r = 46 mm): tip of written axes (X, Y, Z, B), the docs' formula.
fn bhead_tip(x: f64, y: f64, z: f64, b_deg: f64) -> [f64; 3] {
    let (r, b) = (46.0, b_deg.to_radians());
    [x - r * b.sin(), y, z - r * b.cos() + r]
}

/// Whether q is inside the default head's heater block posed by the B head at tip `t`, tilt B:
/// the box x ∈ [−6, 14], y ∈ [−8, 8], z ∈ [4.5, 16] of the tool frame R_y(B).
fn in_bhead_block(q: [f64; 3], t: [f64; 3], b_deg: f64) -> bool {
    let b = b_deg.to_radians();
    let d = [q[0] - t[0], q[1] - t[1], q[2] - t[2]];
    // R_y(B)ᵀ d
    let lx = b.cos() * d[0] - b.sin() * d[2];
    let lz = b.sin() * d[0] + b.cos() * d[2];
    (-6.0..=14.0).contains(&lx) && (-8.0..=8.0).contains(&d[1]) && (4.5..=16.0).contains(&lz)
}

#[test]
fn b_head_tilted_beside_a_wall_crosses_it_with_the_block_while_the_tip_is_clear() {
    let spec = preset("fullcontrol-prusa-b").unwrap();
    // a wall 20 mm high at x = 50; the head tilted to −45° (leaning towards −X, the wall) far
    // from it, then the approach: tip at x = 57
    let WallCase {
        text,
        approach,
        retreat,
        x_near,
        z: z_w,
        b,
    } = bhead_wall_case();
    let f = findings(&text, &spec);
    assert_eq!(only_line(&f), vec![approach, retreat], "{f:?}");
    let mut parts: Vec<&str> = f
        .iter()
        .filter(|f| f.line == approach)
        .map(|f| f.part.as_str())
        .collect();
    parts.sort();
    // the nozzle cone stays 0.6 mm off the wall; the block and the heat sink cross it
    assert_eq!(parts, vec!["heat-sink", "heater-block"], "{f:?}");
    let tip = bhead_tip(x_near, 40.0, z_w, b);
    assert!((tip[0] - 57.0).abs() < 1e-3 && (tip[2] - 10.0).abs() < 1e-3);
    // the tip stays 6.8 mm or more from the wall's face: clear. The block: over the approach
    // (tip x from 80 down to 57, B fixed), scan the wall's vertical lines (x across its
    // width; the block spans y 32…48, inside the wall) for where they enter the block below
    // the wall's top
    let mut oracle: f64 = 0.0;
    let mut tx = 57.0;
    while tx <= 80.0 {
        let mut x = 49.8;
        while x <= 50.2 {
            let mut z = 0.0;
            while z < 20.0 {
                if in_bhead_block([x, 40.0, z], [tx, 40.0, tip[2]], b) {
                    oracle = oracle.max(20.0 - z);
                    break;
                }
                z += 0.002;
            }
            x += 0.05;
        }
        tx += 0.05;
    }
    assert!(
        oracle > 1.0,
        "the oracle's block must cross the wall: {oracle}"
    );
    let blk = f
        .iter()
        .find(|f| f.part == "heater-block")
        .expect("the block");
    assert_eq!(blk.obstacle, "material");
    // the engine samples cell centres (0.2 mm) of the wall and poses 0.2 mm apart; the scan
    // 0.05 mm steps: the depth changes at most 1 mm per mm of either
    assert!(
        blk.depth_mm <= oracle + 0.06 && blk.depth_mm >= oracle - 0.3,
        "engine {} vs oracle {oracle}",
        blk.depth_mm
    );
}

#[test]
fn b_head_reaches_the_bed_at_low_tilt_near_the_plate_edge() {
    // the preset's plate: x ∈ [0, 250]; tip 0.3 mm above it, B = 25° leaning towards +X
    let spec = preset("fullcontrol-prusa-b").unwrap();
    let b: f64 = 25.0;
    let check = |px: f64| {
        let (text, down) = bhead_bed_case(px, b);
        (findings(&text, &spec), down)
    };
    // the block's bottom edge (z = 4.5 in the tool frame) at tool x: world x = p + x cos B +
    // 4.5 sin B, z = 0.3 − x sin B + 4.5 cos B; its lowest point over the plate is where x
    // is largest with world x ≤ 250 (or x = 14, the block's end)
    let (sb, cb) = (b.to_radians().sin(), b.to_radians().cos());
    let lowest_over_plate = |px: f64| {
        let lx = ((250.0 - px - 4.5 * sb) / cb).min(14.0);
        0.3 - lx * sb + 4.5 * cb
    };
    for px in [100.0, 236.0] {
        let (f, down) = check(px);
        let oracle = -lowest_over_plate(px);
        assert!(
            oracle > 0.5,
            "the oracle must reach into the bed at x = {px}: {oracle}"
        );
        let bed: Vec<_> = f.iter().filter(|f| f.obstacle == "bed").collect();
        assert_eq!(bed.len(), 1, "{f:?}");
        assert_eq!((bed[0].line, bed[0].part.as_str()), (down, "heater-block"));
        // cell centres: at most half a cell (0.1 mm) short of the edge, slope tan 25°
        // (+0.001: the written axes' 3 decimals move the tip by up to 0.0005 mm per axis)
        assert!(
            bed[0].depth_mm <= oracle + 1e-3 && bed[0].depth_mm >= oracle - 0.1 * sb / cb - 1e-6,
            "x = {px}: engine {} vs oracle {oracle}",
            bed[0].depth_mm
        );
    }
    // near the plate's edge the block hangs beyond it: less depth than in the middle, and at
    // x = 241 the part of it that is low enough is beyond the edge
    assert!(-lowest_over_plate(236.0) < -lowest_over_plate(100.0));
    assert!(lowest_over_plate(241.0) > CONTACT_TOLERANCE_MM);
    let (f, _) = check(241.0);
    assert!(f.is_empty(), "{f:?}");
    // the same pose leaning the other way (the block's short side, 6 mm) clears the bed:
    // 0.3 − 6 sin 25° + 4.5 cos 25° > 0
    assert!(0.3 - 6.0 * sb + 4.5 * cb > CONTACT_TOLERANCE_MM);
    let (text, _) = bhead_bed_case(100.0, -b);
    let f = findings(&text, &spec);
    assert!(f.is_empty(), "{f:?}");
}

#[test]
fn rtn_rotate_around_sweeps_the_nozzle_into_the_part_at_1_mm_lift() {
    // rtn-slicer4rtn: A = φ + 90° (φ the azimuth of the lean, tip → nozzle); A = 179 leans
    // the head to +Y (away from the pad), the turn to A = −179 the long way passes A = 0,
    // the lean to −Y, towards the pad
    let spec = preset("rtn-slicer4rtn").unwrap();
    // the pad's top at 6.0 mm, its face at y = 10.225; the tip 2.225 mm beside it at z = 2
    let (text, lift, turn, descend) = rtn_rotate_around_case();
    let f = findings(&text, &spec);
    assert_eq!(
        only_line(&f),
        vec![turn],
        "lift {lift}, descend {descend}: {f:?}"
    );
    let n = f.iter().find(|f| f.part == "nozzle").expect("the nozzle");
    // closed form at A = 0 (lean −Y): the nozzle (45° tilt, 15° half-angle, tip radius 0.2)
    // has its lowest generator rising at 30° from the tip's low edge, 0.141 mm below and
    // before the tip; the pad's column at horizontal distance d = 2.125 mm from the tip is
    // entered at z = 3 − 0.141 + (d − 0.141)·tan 30°
    let e = 0.2 * std::f64::consts::FRAC_1_SQRT_2;
    let z_in = 3.0 - e + (2.125 - e) * 30f64.to_radians().tan();
    // the contact rule (src/collision/contact.rs, from its formula): the entry point is far
    // above the contact surface s ≤ (ρ + w/2)·tan 30° (tool axis (0, −sin 45°, cos 45°)), so
    // the whole overlap counts, less the layer height the current layer's beads (layer 30)
    // may be pressed by (0.2 mm)
    let q = glam::DVec3::new(0.0, -2.125, z_in - 3.0);
    let axis = glam::DVec3::new(0.0, -45f64.to_radians().sin(), 45f64.to_radians().cos());
    let (s_q, rho_q) = (
        axis.dot(q),
        (q.length_squared() - axis.dot(q).powi(2)).sqrt(),
    );
    assert!(s_q > (rho_q + 0.225) * 30f64.to_radians().tan() + 1.0);
    let at_lean = 6.0 - z_in - 0.2;
    // the deepest over the turn is at least that one (sampled within 0.2 mm of it); at most
    // the pad's top minus the flat's lowest point, less the layer height
    assert!(
        n.depth_mm >= at_lean - 0.12 && n.depth_mm <= 6.0 - (3.0 - e) - 0.2 + 1e-9,
        "engine {} vs closed form {at_lean}",
        n.depth_mm
    );
    assert_eq!(n.layer, 30);
}

#[test]
fn lathe_is_refused_by_name() {
    let spec = preset("lathe-a").unwrap();
    let e = check_gcode(b"G1 X0 Z0 A0\n", &spec).unwrap_err();
    assert_eq!(e.code(), "machine.collision-unsupported");
}

#[test]
fn machine_file_head_and_bed_parse_and_misspelt_keys_are_refused() {
    let ok = r#"{"name":"t","kind":"cartesian","head":{"parts":[{"shape":"cone","name":"nozzle","tip_radius_mm":0.4,"half_angle_deg":30,"length_mm":5}]},"bed":{"shape":"disc","center":[0,0],"radius_mm":50}}"#;
    let s = MachineSpec::from_json(ok, "t.json").expect("parses");
    assert_eq!(s.head().unwrap().parts[0].name(), "nozzle");
    let bad = ok.replace("half_angle_deg", "half_angel_deg");
    let e = MachineSpec::from_json(&bad, "t.json").unwrap_err();
    assert!(e.to_string().contains("half_angel_deg"), "{e}");
    let neg = ok.replace("\"length_mm\":5", "\"length_mm\":-5");
    let e = MachineSpec::from_json(&neg, "t.json")
        .unwrap()
        .head()
        .unwrap_err();
    assert_eq!(e.code(), "machine.bad-spec");
    assert!(e.to_string().contains("nozzle"), "{e}");
}

#[test]
fn a_vertical_nozzle_riding_a_30_degree_slope_is_contact_not_collision() {
    // the false positive of the first version (issue 10): a 3-axis nozzle printing a layer
    // that rises 30° in +X, lines along Y side by side, each layer once uphill and once
    // downhill (so the face meets both the bead below and the uphill neighbour it just laid);
    // the nozzle's flat face rides the beads (contact rule, src/collision/contact.rs), the
    // cone and the heater block (4.5 mm up, 14 mm towards +X: the slope is 0.58 mm per mm, the
    // pad only 3 mm wide) stay clear
    let spec = preset("cartesian").unwrap();
    let t30 = 30f64.to_radians().tan();
    // `low`: how far below the slope the last layer is printed, mm; its first line's number
    let slope = |low: f64| {
        let mut g = Gcode::default();
        g.add("M83");
        g.add(";WIDTH:0.45");
        g.add(";HEIGHT:0.2");
        g.add("G1 Z5");
        let xs: Vec<f64> = (0..7).map(|i| 10.0 + 0.45 * i as f64).collect();
        let mut first = 0;
        for k in 1..=6 {
            g.add(";LAYER_CHANGE");
            let order: Vec<f64> = if k % 2 == 0 {
                xs.iter().rev().copied().collect()
            } else {
                xs.clone()
            };
            for x in order {
                let dz = if k == 6 { low } else { 0.0 };
                let z = 0.2 * k as f64 + (x - 10.0) * t30 - dz;
                g.add(&format!("G1 X{x:.3} Y10 Z{:.3}", z + 1.0));
                let l = g.add(&format!("G1 Z{z:.3}"));
                if k == 6 && first == 0 {
                    first = l;
                }
                g.add("G1 Y30 E1");
                g.add(&format!("G1 Z{:.3}", z + 1.0));
            }
        }
        (g.0, first)
    };
    let (text, _) = slope(0.0);
    let f = findings(&text, &spec);
    assert!(f.is_empty(), "a 30° slope reported {f:?}");
    // the last layer printed 0.6 mm too low: its first descent pushes the tip 0.4 mm into the
    // layer below (more than the contact surface's (w/2)·tan 30° = 0.13 mm straight under
    // the face): found on that line
    let (text, first) = slope(0.6);
    let f = findings(&text, &spec);
    assert_eq!(
        f.first().map(|f| (f.line, f.part.as_str())),
        Some((first, "nozzle")),
        "{f:?}"
    );
}

/// The collision check is on by default: a machine output that collides is refused naming the
/// first finding's output line, with no flag or with `--check-collisions` (accepted, the same);
/// with `--allow-collisions` it is written and lists every finding as comments at its end, the
/// same findings as the library's check of the written file. The part: the conic 20 mm cube
/// (30° outward) on the cartesian preset, whose heater block (14 mm towards +X, 4.5 mm up)
/// meets the cone's rising layers.
#[test]
fn the_cli_refuses_a_colliding_machine_output_by_default_and_allow_collisions_lists_them() {
    let w = synthetic::conic_cube();
    let dir = std::env::temp_dir().join(format!("warpslice-collision-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (gcode, job, out) = (
        dir.join("in.gcode"),
        dir.join("job.json"),
        dir.join("out.gcode"),
    );
    std::fs::write(&gcode, synthetic::gcode(&w.job, true, 1.0)).unwrap();
    std::fs::write(&job, w.job.to_json_pretty()).unwrap();
    let run = |extra: &[&str]| {
        let _ = std::fs::remove_file(&out);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
            .arg("unwarp")
            .arg(&gcode)
            .arg("--job")
            .arg(&job)
            .args(["--machine", "cartesian", "-o"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let spec = preset("cartesian").unwrap();
    // --allow-collisions: written, every finding listed
    let (ok, err) = run(&["--allow-collisions"]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    let listed: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("; warpslice collision: "))
        .collect();
    // the library's check of the file as written, before the listed comments
    let body: String = text
        .lines()
        .filter(|l| !l.starts_with("; warpslice collision: "))
        .map(|l| format!("{l}\n"))
        .collect();
    let f = findings(&body, &spec);
    assert!(!f.is_empty(), "the conic cube's heater block must collide");
    assert_eq!(listed.len(), f.len(), "{listed:?}");
    for (l, f) in listed.iter().zip(&f) {
        assert!(
            l.starts_with(&format!(
                "; warpslice collision: line {} layer {}: {} into {}",
                f.line, f.layer, f.part, f.obstacle
            )),
            "{l} vs {f:?}"
        );
    }
    // the default, and --check-collisions (accepted, the same): refused, naming the first
    // finding, and no file written
    for extra in [&[][..], &["--check-collisions"][..]] {
        let (ok, err) = run(extra);
        assert!(!ok, "a colliding output was written with {extra:?}");
        assert!(!out.exists(), "a refused output was left with {extra:?}");
        assert!(
            err.contains(&format!(
                "output line {} (layer {}; from input line ",
                f[0].line, f[0].layer
            )) && err.contains(&format!("): the {} goes", f[0].part))
                && err.contains("--allow-collisions"),
            "{extra:?}: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The A/B table (open5x-ab, A about +X) tilts the part; in the part frame the fixed head
/// leans by A with its heater block's long side (machine X) level and its 16 mm side across.
/// With the tool axis n = (0, sin A, cos A) and the head's x axis the machine's X, the tool
/// frame's y axis is n × x = (0, cos A, −sin A): the block's bottom face (4.5 mm above the
/// tip along n) has its lowest edge at y = +8 mm, at `tip_z − 8 sin A + 4.5 cos A`.
/// Before the table had a head frame, the block was checked as the 16.1 mm cylinder about n
/// that contains it, which reaches `tip_z − 16.1 sin A + 4.5 cos A`: into the bed from 15.6°.
#[test]
fn ab_table_head_frame_places_the_heater_block_so_a_20_degree_tilt_clears_the_bed_and_40_does_not()
{
    let spec = preset("open5x-ab").unwrap();
    let machine = spec.build().unwrap();
    let tip_z = 1.0;
    let run = |a_deg: f64| {
        let (s, c) = (a_deg.to_radians().sin(), a_deg.to_radians().cos());
        let n = glam::DVec3::new(0.0, s, c);
        let axes = |z: f64| {
            let a = machine
                .inverse(glam::DVec3::new(0.0, 0.0, z), n, None)
                .unwrap();
            format!(
                "G1 X{:.4} Y{:.4} Z{:.4} A{:.4} B{:.4}",
                a[0], a[1], a[2], a[3], a[4]
            )
        };
        let mut g = Gcode::default();
        g.add(&axes(20.0));
        let down = g.add(&axes(tip_z));
        (findings(&g.0, &spec), down, tip_z - 8.0 * s + 4.5 * c)
    };
    // 20°: the box clears the bed by 1.49 mm, its bounding cylinder would not
    let (f, _, lowest) = run(20.0);
    assert!(lowest > 1.0, "{lowest}");
    assert!(tip_z - 16.1 * 20f64.to_radians().sin() + 4.5 * 20f64.to_radians().cos() < 0.0);
    assert!(
        f.is_empty(),
        "a 20° table tilt 1 mm above the bed reported {f:?}"
    );
    // 40°: the block's edge is 0.70 mm into the bed
    let (f, down, lowest) = run(40.0);
    let bed: Vec<_> = f.iter().filter(|f| f.obstacle == "bed").collect();
    assert!(!bed.is_empty(), "a 40° tilt reported nothing");
    assert!(
        bed.iter()
            .all(|f| f.line == down && f.part == "heater-block"),
        "{bed:?}"
    );
    let depth = bed.iter().map(|f| f.depth_mm).fold(0.0, f64::max);
    assert!(
        (depth - -lowest).abs() < 0.02,
        "engine depth {depth} vs the block's lowest edge {lowest}"
    );
}

/// The RTN's fixed 45° nozzle printing flat layers, lines side by side across its lean (the
/// false findings of note 7: the first version's bead top followed the tilted face, `n × d`
/// rising 45° across the bead, so one edge of every bead stood 0.225·sin 45° = 0.16 mm above
/// the tip and the next line's nozzle "collided" with it). For each lean azimuth φ (tool axis
/// `(sin 45° cos φ, sin 45° sin φ, cos 45°)`, axes from the machine's inverse), a pad of 4
/// layers of 0.2 mm, lines along X stepped 0.45 mm in Y, printed back and forth (serpentine,
/// the step extruded) or each towards +X after a travel at the layer's height, and each layer
/// started by a travel across the one below rising to its height (PrusaSlicer's flat layers
/// have no lifts: the old model's findings were on such travels). The layer is flat: a bead's top
/// is the tip's height across its whole width (checked on the height field, 3 mm inside the
/// pad), and no move collides.
#[test]
fn rtn_45_degree_nozzle_printing_flat_layers_side_by_side_reports_no_collision() {
    use warpslice::collision::material::{cell_of, CELL_MM};
    use warpslice::collision::Walker;
    let spec = preset("rtn-slicer4rtn").unwrap();
    let machine = spec.build().unwrap();
    for phi_deg in [-90.0f64, 0.0, 90.0, 180.0] {
        for serpentine in [true, false] {
            let (s, c) = (45f64.to_radians().sin(), 45f64.to_radians().cos());
            let phi = phi_deg.to_radians();
            let n = glam::DVec3::new(s * phi.cos(), s * phi.sin(), c);
            let mut prev: Option<Vec<f64>> = None;
            let mut g = Gcode::default();
            let mut to = |g: &mut Gcode, p: [f64; 3], e: Option<f64>| {
                let a = machine
                    .inverse(glam::DVec3::from_array(p), n, prev.as_deref())
                    .unwrap();
                let e = e.map(|e| format!(" E{e:.4}")).unwrap_or_default();
                g.add(&format!(
                    "G1 X{:.3} Y{:.3} Z{:.3} A{:.3}{e}",
                    a[0], a[1], a[2], a[3]
                ));
                prev = Some(a);
            };
            g.add("M83");
            g.add(";WIDTH:0.45");
            g.add(";HEIGHT:0.2");
            to(&mut g, [100.0, 100.0, 10.0], None);
            let lines = 22;
            let top = 0.8;
            for k in 1..=4 {
                let z = 0.2 * k as f64;
                g.add(";LAYER_CHANGE");
                for i in 0..lines {
                    let y = 100.0 + 0.45 * i as f64;
                    let (x0, x1) = if serpentine && i % 2 == 1 {
                        (110.0, 100.0)
                    } else {
                        (100.0, 110.0)
                    };
                    // the step to the next line: extruded (serpentine) or a travel at the
                    // layer's height, as PrusaSlicer's flat layers give it (no lift); the
                    // layer's first line starts with a travel across the layer below
                    to(&mut g, [x0, y, z], (serpentine && i > 0).then_some(0.02));
                    to(&mut g, [x1, y, z], Some(0.4));
                }
            }
            let y_end = 100.0 + 0.45 * (lines - 1) as f64;
            to(&mut g, [100.0, y_end, top + 1.0], None);
            let mut w = Walker::new(&spec).unwrap();
            w.push(g.0.as_bytes()).unwrap();
            let (f, checker) = w.finish().unwrap();
            assert!(
                f.is_empty(),
                "φ = {phi_deg}°, serpentine {serpentine}: {f:?}"
            );
            // every cell 3 mm inside the pad: the top layer's height (f32)
            let m = checker.material();
            for j in cell_of(103.0)..=cell_of(106.0) {
                for i in cell_of(103.0)..=cell_of(107.0) {
                    let h = m.height(i, j);
                    assert!(
                        (h - top).abs() < 1e-5,
                        "φ = {phi_deg}°, serpentine {serpentine}: the bead top at ({:.1}, {:.1}) is {h}, not the layer's {top}",
                        (i as f64 + 0.5) * CELL_MM,
                        (j as f64 + 0.5) * CELL_MM
                    );
                }
            }
        }
    }
}

/// The checker's findings with and without its speed bounds ([`Walker::exhaustive`]: every
/// cell under every part at every pose): the same lines, parts, obstacles and depths.
fn bounded_and_exhaustive(gcode: &str, spec: &MachineSpec) -> Vec<CollisionFinding> {
    use warpslice::collision::Walker;
    let run = |exhaustive: bool| {
        let mut w = Walker::new(spec).unwrap();
        w.exhaustive(exhaustive);
        w.push(gcode.as_bytes()).unwrap();
        w.finish().unwrap().0
    };
    let (fast, slow) = (run(false), run(true));
    assert_eq!(
        fast.len(),
        slow.len(),
        "bounded {fast:?}\nexhaustive {slow:?}"
    );
    for (a, b) in fast.iter().zip(&slow) {
        assert_eq!(
            (a.line, a.layer, &a.part, &a.obstacle),
            (b.line, b.layer, &b.part, &b.obstacle),
            "bounded {a:?} vs exhaustive {b:?}"
        );
        assert!(
            (a.depth_mm - b.depth_mm).abs() < 1e-9,
            "bounded {a:?} vs exhaustive {b:?}"
        );
    }
    fast
}

/// Law: the speed bounds lose no finding and change no depth. Files: the plunge into a pad
/// (cartesian), the B head tilted beside a wall, the RTN rotate-around into a pad, the RTN
/// printing flat layers across its lean, the B head's block on the bed, and the conic 20 mm
/// cube's machine output on the cartesian and PAX presets (written by the CLI; the heater
/// block meets the cone's rising layers).
#[test]
fn speed_bounds_give_the_same_findings_as_the_exhaustive_check() {
    let mut cases: Vec<(&str, String)> = Vec::new();
    let mut g = Gcode::default();
    pad(&mut g, (10.0, 14.0), (10.0, 14.0), 6, "");
    g.add("G1 Z10");
    g.add("G1 X12 Y12");
    g.add("G1 Z0.6");
    g.add("G1 X13 Y13 Z0.8");
    cases.push(("cartesian", g.0));
    let mut g = Gcode::default();
    pad(&mut g, (0.0, 4.0), (0.0, 4.0), 10, " A179");
    g.add("G1 Z20 A179");
    g.add("G1 X2 Y6.225 A179");
    g.add("G1 Z0.5 A179");
    g.add("G1 A-179");
    g.add("G1 X2 Y2 Z2.5 A-90 E0.5");
    cases.push(("rtn-slicer4rtn", g.0));
    let mut g = Gcode::default();
    g.add("M83");
    g.add(";WIDTH:0.45");
    for k in 1..=30 {
        g.add(";LAYER_CHANGE");
        g.add(&format!("G1 X50 Y35 Z{:.3} B0", 0.2 * k as f64));
        g.add("G1 X50 Y45 E1");
    }
    g.add("G1 Z20");
    let (x, z) = bhead_axes(60.0, 3.0, -45.0);
    g.add(&format!("G1 X{:.3} Y40 Z{z:.3} B-45", x + 20.0));
    let (x, _) = bhead_axes(53.0, 3.0, -45.0);
    g.add(&format!("G1 X{x:.3} Y40 Z{z:.3} B-45"));
    let (x, z) = bhead_axes(100.0, 0.3, 25.0);
    g.add(&format!("G1 X{x:.3} Y100 Z{z:.3} B25"));
    cases.push(("fullcontrol-prusa-b", g.0));
    let mut total = 0;
    for (preset_name, text) in &cases {
        let f = bounded_and_exhaustive(text, &preset(preset_name).unwrap());
        assert!(!f.is_empty(), "{preset_name}: the case must find something");
        total += f.len();
    }
    // machine outputs of the conic cube, through the CLI
    let w = synthetic::conic_cube_of(8.0);
    let dir = std::env::temp_dir().join(format!("warpslice-collision-law-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (gcode, job) = (dir.join("in.gcode"), dir.join("job.json"));
    std::fs::write(&gcode, synthetic::gcode(&w.job, true, 1.0)).unwrap();
    std::fs::write(&job, w.job.to_json_pretty()).unwrap();
    for machine in ["cartesian", "pax-5axis", "rtn-slicer4rtn"] {
        let out = dir.join(format!("{machine}.gcode"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
            .arg("unwarp")
            .arg(&gcode)
            .arg("--job")
            .arg(&job)
            .args(["--machine", machine, "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(&out).unwrap();
        // the exhaustive check is slow: the file up to its fourth finding (a walk's findings
        // before a line do not depend on the lines after it), or its first 3000 lines
        let spec = preset(machine).unwrap();
        let upto = findings(&text, &spec)
            .get(3)
            .map_or(3000, |f| f.line as usize);
        let head: String = text.lines().take(upto).map(|l| format!("{l}\n")).collect();
        total += bounded_and_exhaustive(&head, &spec).len();
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(total > 5, "{total} findings in all");
}

/// A collision finding of the unwarp names the output line and the slicer's input line (issue
/// 10 §2). The conic 8 mm cube's synthetic G-code on the cartesian preset, with a plunge
/// inserted at the start of layer 20: a travel to the cone's axis (100, 100), where the warp
/// moves nothing, then a vertical extrusion 1 mm down into the 19 layers below, and back up to
/// the layer. Its input line is where it was inserted; its output line is the written file's one
/// extruding line to X100 Y100 exactly (found in the text, not from the engine: the layers'
/// lines cross the axis at Y100.2); the finding listed for that output line names that input
/// line.
#[test]
fn an_unwarp_collision_names_its_output_line_and_the_slicers_input_line() {
    let w = synthetic::conic_cube_of(8.0);
    let g = synthetic::gcode(&w.job, true, 1.0);
    let layer = 20;
    let z = 0.2 * layer as f64;
    let (g, first) = synthetic::insert_after(
        &g,
        " F600\n",
        layer,
        &format!(
            "G1 X100 Y100 F1235\nG1 Z{:.3} E0.03 F1234\nG1 Z{z:.3} F1236\n",
            z - 1.0
        ),
    );
    let plunge_in = first as u64 + 1;
    assert!(g.lines().nth(first).unwrap().contains("F1234"));
    let dir =
        std::env::temp_dir().join(format!("warpslice-collision-lines-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (gcode, job, out) = (
        dir.join("in.gcode"),
        dir.join("job.json"),
        dir.join("out.gcode"),
    );
    std::fs::write(&gcode, &g).unwrap();
    std::fs::write(&job, w.job.to_json_pretty()).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .arg("unwarp")
        .arg(&gcode)
        .arg("--job")
        .arg(&job)
        .args([
            "--machine",
            "cartesian",
            "--check-collisions",
            "--allow-collisions",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    let plunge_out: Vec<u64> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with("G1 X100 Y100 Z") && l.contains(" E"))
        .map(|(i, _)| i as u64 + 1)
        .collect();
    assert_eq!(
        plunge_out.len(),
        1,
        "the plunge's output line: {plunge_out:?}"
    );
    let listed = format!(
        "; warpslice collision: line {} layer {layer}: nozzle into material",
        plunge_out[0]
    );
    let l = text
        .lines()
        .find(|l| l.starts_with(&listed))
        .unwrap_or_else(|| panic!("no finding on the plunge's line: {listed}"));
    assert!(l.ends_with(&format!(" (input line {plunge_in})")), "{l}");
    let _ = std::fs::remove_dir_all(&dir);
}
