//! Value tests of every warp × direction × base at hand-computed points (issue 17).
//!
//! Every expected value is written here from the README's warp table and the seeds (000 Eqs.
//! 1–2, 002 conic/belt/mandrel/sphere), never by calling the crate's warp math: the crate is
//! reached only through its public API (`WarpParams { spec, base }.build(&bbox)` and the
//! `Warp` trait's `forward`, `inverse`, `tool_axis`, `jacobian_det`). Where a value has a
//! short closed form it is also written out as a number, so a reader can check it by hand.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use warpslice::error::Coded;
use warpslice::mesh::Aabb;
use warpslice::warp::{Direction, Warp, WarpParams, WarpSpec};

/// Largest difference allowed between a position (mm) computed here and the crate's: both
/// evaluate the same closed form in f64 on numbers below 100 mm, so they agree to ~1e-13;
/// 1e-9 mm is far below any wrong formula (the smallest error planted moves a value by 0.1 mm).
const VALUE_TOL: f64 = 1e-9;
/// Largest difference allowed per component of the unit tool axis (dimensionless), and of
/// det J: both are ratios of the same closed forms, equal to ~1e-15.
const AXIS_TOL: f64 = 1e-10;
/// The tool axis's tolerance where the crate takes ∇g by central differences (a field with
/// `abs`): their rounding error ε·|g|/h is ~10⁻⁹ for |g| ≈ 5 mm at h = 10⁻⁶ mm.
const NUMERIC_AXIS_TOL: f64 = 1e-8;
/// det J tolerance (dimensionless); see [`AXIS_TOL`].
const DET_TOL: f64 = 1e-10;
/// How well `inverse(forward(p))` must give back `p`, mm: the base blend's inverse is solved
/// iteratively to 1e-12 mm in z' (`INVERSE_SOLVE_TOLERANCE`), every other inverse is closed.
const INVERSE_TOL: f64 = 1e-9;
/// Tolerance of the finite-difference check of our own spherical and cylindrical det J
/// derivations (central differences with step [`FD_STEP`]: error O(step²·T''') ≈ 1e-8).
const FD_TOL: f64 = 1e-6;
/// Step of those central differences, mm.
const FD_STEP: f64 = 1e-4;
/// At a mid-blend point checked against the smoothstep, a linear ramp must miss the value by at
/// least this (mm), so that the point tells the two apart (it misses by 0.09375·|g|).
const LINEAR_RAMP_GAP: f64 = 0.005;

/// The model-frame bounding box every warp is built for: 24 × 16 × 30 mm, centred in XY.
fn bbox() -> Aabb {
    Aabb {
        min: DVec3::new(-12.0, -8.0, 0.0),
        max: DVec3::new(12.0, 8.0, 30.0),
    }
}

fn build(spec: WarpSpec, base: Option<[f64; 2]>) -> Box<dyn Warp> {
    let mut p = WarpParams { spec, base };
    match p.build(&bbox()) {
        Ok(w) => w,
        Err(e) => panic!("{e}"),
    }
}

fn close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got}, want {want} (diff {:e} > {tol:e})",
        got - want
    );
}

fn close3(what: &str, got: DVec3, want: DVec3, tol: f64) {
    for (i, c) in ["x", "y", "z"].iter().enumerate() {
        close(&format!("{what}.{c}"), got[i], want[i], tol);
    }
}

/// The unit vector of `v` (our own normalisation).
fn unit(v: [f64; 3]) -> DVec3 {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    DVec3::new(v[0] / l, v[1] / l, v[2] / l)
}

fn sign(d: Direction) -> f64 {
    match d {
        Direction::Outward => 1.0,
        Direction::Inward => -1.0,
    }
}

fn tan_deg(a: f64) -> f64 {
    (a * std::f64::consts::PI / 180.0).tan()
}

/// A shear warp's height g(x, y) and its gradient, written from the README's table.
/// Returns (g, ∂g/∂x, ∂g/∂y).
type Height = Box<dyn Fn(f64, f64) -> (f64, f64, f64)>;

/// README: curved, T_z = z + s·c·(x+a)²/(w/2+|a|).
fn curved_g(s: f64, d: Direction, a: f64, w: f64) -> Height {
    let k = s * sign(d) / (w / 2.0 + a.abs());
    Box::new(move |x, _| (k * (x + a) * (x + a), 2.0 * k * (x + a), 0.0))
}

/// README: tilted, T_z = z + s·c·|x+a| (on the crease the tool axis is vertical).
fn tilted_g(s: f64, d: Direction, a: f64) -> Height {
    let k = s * sign(d);
    Box::new(move |x, _| {
        let u = x + a;
        let slope = if u > 0.0 {
            k
        } else if u < 0.0 {
            -k
        } else {
            0.0
        };
        (k * u.abs(), slope, 0.0)
    })
}

/// README: conic, T_z = z ± r·tan α about `center` (+ outward); the apex gets a vertical axis.
fn conic_g(alpha: f64, d: Direction, c: [f64; 2]) -> Height {
    let k = sign(d) * tan_deg(alpha);
    Box::new(move |x, y| {
        let (dx, dy) = (x - c[0], y - c[1]);
        let r = (dx * dx + dy * dy).sqrt();
        if r == 0.0 {
            (0.0, 0.0, 0.0)
        } else {
            (k * r, k * dx / r, k * dy / r)
        }
    })
}

/// README: belt, T_z = z + (d·(x, y))·tan α with d the unit `toward`.
fn belt_g(alpha: f64, toward: [f64; 2]) -> Height {
    let l = (toward[0] * toward[0] + toward[1] * toward[1]).sqrt();
    let (kx, ky) = (
        toward[0] / l * tan_deg(alpha),
        toward[1] / l * tan_deg(alpha),
    );
    Box::new(move |x, y| (kx * x + ky * y, kx, ky))
}

/// README / CurviSlicer base blend: w(z) = 0 below z0, 1 above z1, smoothstep 3t² − 2t³
/// between (t = (z − z0)/(z1 − z0)), and its derivative dw/dz.
fn smoothstep(base: Option<[f64; 2]>, z: f64) -> (f64, f64) {
    let Some([z0, z1]) = base else {
        return (1.0, 0.0);
    };
    let t = (z - z0) / (z1 - z0);
    if t <= 0.0 {
        (0.0, 0.0)
    } else if t >= 1.0 {
        (1.0, 0.0)
    } else {
        (
            3.0 * t * t - 2.0 * t * t * t,
            (6.0 * t - 6.0 * t * t) / (z1 - z0),
        )
    }
}

/// Check a shear warp at `p` against T_z = z + w(z)·g(x, y): the position, the inverse, the
/// unit tool axis ∇T_z/|∇T_z| = (w·g_x, w·g_y, 1 + w'·g)/|…| and det J = ∂T_z/∂z = 1 + w'·g.
fn check_shear(what: &str, warp: &dyn Warp, g: &Height, base: Option<[f64; 2]>, p: DVec3) {
    check_shear_to(what, warp, g, base, p, AXIS_TOL);
}

/// [`check_shear`] with the tool axis compared to `axis_tol`.
fn check_shear_to(
    what: &str,
    warp: &dyn Warp,
    g: &Height,
    base: Option<[f64; 2]>,
    p: DVec3,
    axis_tol: f64,
) {
    let (gv, gx, gy) = g(p.x, p.y);
    let (w, dw) = smoothstep(base, p.z);
    let want = DVec3::new(p.x, p.y, p.z + w * gv);
    let at = format!("{what} at {p}");
    close3(&format!("{at}: forward"), warp.forward(p), want, VALUE_TOL);
    close3(
        &format!("{at}: inverse"),
        warp.inverse(want),
        p,
        INVERSE_TOL,
    );
    let n = unit([w * gx, w * gy, 1.0 + dw * gv]);
    close3(&format!("{at}: tool axis"), warp.tool_axis(p), n, axis_tol);
    close(
        &format!("{at}: det J"),
        warp.jacobian_det(p),
        1.0 + dw * gv,
        DET_TOL,
    );
}

/// Points spread over the bbox, off every symmetry line.
const POINTS: [[f64; 3]; 6] = [
    [5.0, 3.0, 4.0],
    [-9.0, -6.5, 12.5],
    [11.0, -7.0, 0.5],
    [-2.25, 7.5, 27.0],
    [0.75, 0.0, 9.0],
    [-11.5, 2.0, 18.0],
];

fn check_all(what: &str, spec: WarpSpec, g: Height) {
    let w = build(spec, None);
    for p in POINTS {
        check_shear(what, w.as_ref(), &g, None, DVec3::from_array(p));
    }
}

const DIRS: [Direction; 2] = [Direction::Outward, Direction::Inward];

// ---- curved (seed 000 Eq. 1) ----

/// s = 0.3, a = 2, width 0 → w = the bbox's 24 mm, so w/2 + |a| = 14 and at x = 5 (x + a = 7)
/// g = 0.3·49/14 = 1.05 mm: T_z = 4 + 1.05 outward, 4 − 1.05 inward; the tool axis is
/// (±0.3, 0, 1)/√1.09 (∂g/∂x = 2·0.3·7/14 = 0.3).
#[test]
fn curved_outward_and_inward_with_offset_take_the_width_from_the_bbox() {
    for d in DIRS {
        let c = sign(d);
        let spec = WarpSpec::Curved {
            strength: 0.3,
            direction: d,
            offset: 2.0,
            width: 0.0,
        };
        let w = build(spec.clone(), None);
        let p = DVec3::new(5.0, 3.0, 4.0);
        close(
            "curved T_z at x = 5",
            w.forward(p).z,
            4.0 + c * 1.05,
            VALUE_TOL,
        );
        close3(
            "curved axis at x = 5",
            w.tool_axis(p),
            DVec3::new(c * 0.287_347_885_566_345_4, 0.0, 0.957_826_285_221_151_3),
            AXIS_TOL,
        );
        // x = −9 is as far from the vertex (x = −2) on the other side: same height, mirrored axis
        let q = DVec3::new(-9.0, -3.0, 4.0);
        close(
            "curved T_z at x = −9",
            w.forward(q).z,
            4.0 + c * 1.05,
            VALUE_TOL,
        );
        close(
            "curved axis.x at x = −9",
            w.tool_axis(q).x,
            -c * 0.287_347_885_566_345_4,
            AXIS_TOL,
        );
        // the vertex x = −a is flat
        let v = DVec3::new(-2.0, 1.0, 6.0);
        close("curved T_z at the vertex", w.forward(v).z, 6.0, VALUE_TOL);
        close3(
            "curved axis at the vertex",
            w.tool_axis(v),
            DVec3::Z,
            AXIS_TOL,
        );
        close("curved det J", w.jacobian_det(p), 1.0, DET_TOL);
        check_all("curved a=2 w=bbox", spec, curved_g(0.3, d, 2.0, 24.0));
    }
}

/// A negative offset with an explicit width: a = −3, w = 30 → w/2 + |a| = 18 (a wrong
/// w/2 + a would give 12); at x = 9 (x + a = 6) g = 0.3·36/18 = 0.6 mm.
#[test]
fn curved_negative_offset_uses_its_absolute_value_and_the_given_width() {
    for d in DIRS {
        let spec = WarpSpec::Curved {
            strength: 0.3,
            direction: d,
            offset: -3.0,
            width: 30.0,
        };
        let w = build(spec.clone(), None);
        close(
            "curved T_z at x = 9",
            w.forward(DVec3::new(9.0, 0.0, 2.0)).z,
            2.0 + sign(d) * 0.6,
            VALUE_TOL,
        );
        check_all("curved a=−3 w=30", spec, curved_g(0.3, d, -3.0, 30.0));
    }
}

// ---- tilted (seed 000 Eq. 2) ----

/// s = 0.2 at x = 10 (a = 0): +2 mm outward, −2 mm inward; the tool axis leans toward +x
/// outward ((0.2, 0, 1)/√1.04) and toward −x inward.
#[test]
fn tilted_sign_and_size_outward_and_inward() {
    for d in DIRS {
        let c = sign(d);
        let spec = WarpSpec::Tilted {
            strength: 0.2,
            direction: d,
            offset: 0.0,
        };
        let w = build(spec.clone(), None);
        let p = DVec3::new(10.0, 4.0, 5.0);
        close(
            "tilted T_z at x = 10",
            w.forward(p).z,
            5.0 + c * 2.0,
            VALUE_TOL,
        );
        close(
            "tilted T_z at x = −10",
            w.forward(DVec3::new(-10.0, 4.0, 5.0)).z,
            5.0 + c * 2.0,
            VALUE_TOL,
        );
        let n = w.tool_axis(p);
        close3(
            "tilted axis at x = 10",
            n,
            DVec3::new(c * 0.2, 0.0, 1.0) / 1.04f64.sqrt(),
            AXIS_TOL,
        );
        assert!(
            n.x * c > 0.0,
            "outward tilts the tool toward +x on the +x side"
        );
        close("tilted det J", w.jacobian_det(p), 1.0, DET_TOL);
        check_all("tilted a=0", spec, tilted_g(0.2, d, 0.0));
    }
}

/// a = 3: the crease is at x = −3, where T_z = z and the tool axis is vertical; at x = −7
/// (|x + a| = 4) g = ±0.8 mm.
#[test]
fn tilted_crease_moves_with_the_offset_and_has_a_vertical_axis() {
    for d in DIRS {
        let spec = WarpSpec::Tilted {
            strength: 0.2,
            direction: d,
            offset: 3.0,
        };
        let w = build(spec.clone(), None);
        let crease = DVec3::new(-3.0, 5.0, 7.0);
        close(
            "tilted T_z on the crease",
            w.forward(crease).z,
            7.0,
            VALUE_TOL,
        );
        close3(
            "tilted axis on the crease",
            w.tool_axis(crease),
            DVec3::Z,
            AXIS_TOL,
        );
        close(
            "tilted T_z at x = −7",
            w.forward(DVec3::new(-7.0, 0.0, 7.0)).z,
            7.0 + sign(d) * 0.8,
            VALUE_TOL,
        );
        check_all("tilted a=3", spec, tilted_g(0.2, d, 3.0));
    }
}

// ---- conic (seed 002) ----

/// α = 30° about (3, −2): at (7, 1) r = 5, so T_z = z ± 5·tan 30° = z ± 2.8868 mm. Outward
/// (README: z' = z + g, g ≥ 0 growing away from the centre): the layer surfaces
/// z = k·h − r·tan α fall outward and the tool axis (sin α·(4, 3)/5, cos α) = (0.4, 0.3, 0.866)
/// tilts outward; inward the reverse.
#[test]
fn conic_off_centre_outward_falls_and_tilts_outward_inward_the_reverse() {
    for d in DIRS {
        let c = sign(d);
        let spec = WarpSpec::Conic {
            angle: 30.0,
            direction: d,
            center: [3.0, -2.0],
        };
        let w = build(spec.clone(), None);
        let p = DVec3::new(7.0, 1.0, 5.0);
        let want = if c > 0.0 {
            7.886_751_345_948_129
        } else {
            2.113_248_654_051_871
        };
        close("conic T_z at r = 5", w.forward(p).z, want, VALUE_TOL);
        let n = w.tool_axis(p);
        close3(
            "conic axis at r = 5",
            n,
            DVec3::new(c * 0.4, c * 0.3, 0.75f64.sqrt()),
            AXIS_TOL,
        );
        // same layer (T_z) farther out ⇒ lower z outward, higher inward
        let near = DVec3::new(4.0, -2.0, 5.0);
        let far = DVec3::new(9.0, -2.0, 5.0);
        let rise = w.forward(far).z - w.forward(near).z;
        close(
            "conic rise from r = 1 to r = 6",
            rise,
            c * 5.0 * tan_deg(30.0),
            VALUE_TOL,
        );
        // the radial component of the tool axis: outward > 0
        let radial = w.tool_axis(far).x;
        assert!(radial * c > 0.0, "{d:?}: radial tool component {radial}");
        let apex = DVec3::new(3.0, -2.0, 4.0);
        close("conic T_z at the apex", w.forward(apex).z, 4.0, VALUE_TOL);
        close3(
            "conic axis at the apex",
            w.tool_axis(apex),
            DVec3::Z,
            AXIS_TOL,
        );
        close("conic det J", w.jacobian_det(p), 1.0, DET_TOL);
        check_all("conic 30° (3,−2)", spec, conic_g(30.0, d, [3.0, -2.0]));
    }
}

// ---- belt (seed 002 --axis=3) ----

/// α = 20° toward (3, 4), i.e. d = (0.6, 0.8): at (5, −2) d·(x, y) = 1.4, T_z = z + 1.4·tan 20°
/// = 3 + 0.50956 mm; the tool axis is (d·sin α, cos α).
#[test]
fn belt_uses_the_unit_toward_direction() {
    let spec = WarpSpec::Belt {
        angle: 20.0,
        toward: [3.0, 4.0],
    };
    let w = build(spec.clone(), None);
    let p = DVec3::new(5.0, -2.0, 3.0);
    close(
        "belt T_z",
        w.forward(p).z,
        3.509_558_327_972_683_4,
        VALUE_TOL,
    );
    let (s, c) = (20f64.to_radians().sin(), 20f64.to_radians().cos());
    close3(
        "belt axis",
        w.tool_axis(p),
        DVec3::new(0.6 * s, 0.8 * s, c),
        AXIS_TOL,
    );
    // d·(x, y) = −4 at (−2, −3.5): the planes fall toward d
    close(
        "belt T_z behind",
        w.forward(DVec3::new(-2.0, -3.5, 3.0)).z,
        3.0 - 4.0 * tan_deg(20.0),
        VALUE_TOL,
    );
    close("belt det J", w.jacobian_det(p), 1.0, DET_TOL);
    check_all("belt 20° (3,4)", spec, belt_g(20.0, [3.0, 4.0]));
}

// ---- cylindrical (seed 002 mandrel) ----

/// Our own cylindrical T: axis ∥ X through (y, z) = (ay, az), d = (y − ay, z − az), ρ = |d|,
/// θ = atan2(d_y, d_z): T = (x, R·θ, ρ − R).
fn cylinder_t(r: f64, ay: f64, az: f64, p: DVec3) -> DVec3 {
    let (dy, dz) = (p.y - ay, p.z - az);
    DVec3::new(p.x, r * dy.atan2(dz), (dy * dy + dz * dz).sqrt() - r)
}

/// det of the Jacobian of `t` at `p` by central differences (checks our derivations).
fn fd_det(t: &dyn Fn(DVec3) -> DVec3, p: DVec3) -> f64 {
    let col = |e: DVec3| (t(p + e * FD_STEP) - t(p - e * FD_STEP)) / (2.0 * FD_STEP);
    glam::DMat3::from_cols(col(DVec3::X), col(DVec3::Y), col(DVec3::Z)).determinant()
}

/// R = 7 about the axis through (y, z) = (1, −10): at d = (6, 8) ρ = 10 so T_z = 3, y' = 7·atan2(6, 8)
/// = 4.5045, det J = R/ρ = 0.7 and the axis is radial (0, 0.6, 0.8); at d = (−5, 12) ρ = 13,
/// T_z = 6, det J = 7/13.
#[test]
fn cylindrical_layers_are_coaxial_with_det_r_over_rho() {
    let (r, ay, az) = (7.0, 1.0, -10.0);
    let w = build(
        WarpSpec::Cylindrical {
            radius: r,
            axis: [ay, az],
        },
        None,
    );
    let cases = [
        (
            DVec3::new(5.0, 7.0, -2.0),
            DVec3::new(5.0, 4.504_507_761_552_991, 3.0),
            0.7,
            DVec3::new(0.0, 0.6, 0.8),
        ),
        (
            DVec3::new(-3.0, -4.0, 2.0),
            DVec3::new(-3.0, -2.763_537_837_898_330_6, 6.0),
            7.0 / 13.0,
            DVec3::new(0.0, -5.0 / 13.0, 12.0 / 13.0),
        ),
    ];
    for (p, t, det, n) in cases {
        close3(
            "cylindrical T (hand)",
            cylinder_t(r, ay, az, p),
            t,
            VALUE_TOL,
        );
        close(
            "cylindrical det J (our derivation vs our T)",
            fd_det(&|q| cylinder_t(r, ay, az, q), p),
            det,
            FD_TOL,
        );
        close3("cylindrical forward", w.forward(p), t, VALUE_TOL);
        close3("cylindrical inverse", w.inverse(t), p, INVERSE_TOL);
        close("cylindrical det J", w.jacobian_det(p), det, DET_TOL);
        close3("cylindrical tool axis", w.tool_axis(p), n, AXIS_TOL);
    }
}

// ---- spherical (seed 002, 5-axis) ----

/// Our own spherical T (the definition in `src/warp/spherical.rs`'s doc: the azimuthal-
/// equidistant map of the sphere of radius R about its top): v = p − c, ρ = |v|, polar angle
/// φ from +Z, azimuth λ: T = (R·φ·cos λ, R·φ·sin λ, ρ − R).
fn sphere_t(r: f64, c: DVec3, p: DVec3) -> DVec3 {
    let v = p - c;
    let rho = v.length();
    let s = (v.x * v.x + v.y * v.y).sqrt();
    let phi = s.atan2(v.z);
    let lambda = v.y.atan2(v.x);
    DVec3::new(r * phi * lambda.cos(), r * phi * lambda.sin(), rho - r)
}

/// det J derived by hand: in spherical coordinates (ρ, φ, λ) the model volume element is
/// ρ²·sin φ dρ dφ dλ; T sends it to polar coordinates (r' = R·φ, λ) in x'y' and z' = ρ − R,
/// whose volume element is r' dr' dλ dz' = R·φ · R dφ · dλ · dρ. So
/// det J = R²·φ / (ρ²·sin φ), and → R²/ρ² on the top axis (φ/sin φ → 1).
fn sphere_det(r: f64, c: DVec3, p: DVec3) -> f64 {
    let v = p - c;
    let rho = v.length();
    let s = (v.x * v.x + v.y * v.y).sqrt();
    if s == 0.0 {
        return r * r / (rho * rho);
    }
    let phi = s.atan2(v.z);
    r * r * phi / (rho * rho * phi.sin())
}

/// R = 5 about c = (1, 2, −5). At v = (6, 0, 8): ρ = 10, φ = atan2(6, 8) = 0.6435,
/// T = (5φ, 0, 5) = (3.2176, 0, 5), det J = 25·φ/(100·0.6) = 0.26813, axis (0.6, 0, 0.8).
/// At v = (2, −3, 6): ρ = 7, T_z = 2, axis v/7. On the top axis v = (0, 0, 8): T = (0, 0, 3),
/// det J = 25/64.
#[test]
fn spherical_layers_are_concentric_with_the_hand_derived_det() {
    let r = 5.0;
    let c = DVec3::new(1.0, 2.0, -5.0);
    let w = build(
        WarpSpec::Spherical {
            radius: r,
            center: c.to_array(),
        },
        None,
    );
    // the literal values of the first and the pole point
    let p = c + DVec3::new(6.0, 0.0, 8.0);
    close3(
        "spherical T (hand)",
        sphere_t(r, c, p),
        DVec3::new(3.217_505_543_966_421_7, 0.0, 5.0),
        VALUE_TOL,
    );
    close(
        "spherical det (hand)",
        sphere_det(r, c, p),
        0.268_125_461_997_201_83,
        VALUE_TOL,
    );
    let pole = c + DVec3::new(0.0, 0.0, 8.0);
    close(
        "spherical det at the pole (hand)",
        sphere_det(r, c, pole),
        25.0 / 64.0,
        1e-15,
    );
    for v in [
        DVec3::new(6.0, 0.0, 8.0),
        DVec3::new(2.0, -3.0, 6.0),
        DVec3::new(-4.0, 1.5, 3.0),
        DVec3::new(0.0, 0.0, 8.0),
    ] {
        let p = c + v;
        let t = sphere_t(r, c, p);
        let det = sphere_det(r, c, p);
        if v.x != 0.0 || v.y != 0.0 {
            // our derivation against our own T (off the pole, where atan2(y, x) is smooth)
            close(
                "spherical det J (our derivation vs our T)",
                fd_det(&|q| sphere_t(r, c, q), p),
                det,
                FD_TOL,
            );
        }
        close3("spherical forward", w.forward(p), t, VALUE_TOL);
        close3("spherical inverse", w.inverse(t), p, INVERSE_TOL);
        close("spherical det J", w.jacobian_det(p), det, DET_TOL);
        close3(
            "spherical tool axis",
            w.tool_axis(p),
            v / v.length(),
            AXIS_TOL,
        );
    }
}

// ---- the base blend (CurviSlicer): z' = z + w(z)·g ----

/// The blend used below: flat under z = 1, fully warped above z = 21.
const BASE: [f64; 2] = [1.0, 21.0];

/// Every shear warp × direction with `--base 1,21`, at z = 0.5 (flat: T_z = z, vertical axis),
/// z = 25 (full warp), and mid-blend at t = ¼ (z = 6) and t = ¾ (z = 16), where the smoothstep
/// gives w = 0.15625 and 0.84375 while a linear ramp would give 0.25 and 0.75, and
/// w′ = 6t(1 − t)/20 = 0.05625 (linear: 0.05). The tool axis is ∇(z + w(z)·g) =
/// (w·g_x, w·g_y, 1 + w′·g) normalised, det J = 1 + w′·g.
#[test]
fn base_blend_is_flat_below_full_above_and_smoothstep_between_for_every_shear_warp() {
    let mut cases: Vec<(String, WarpSpec, Height)> = Vec::new();
    for d in DIRS {
        cases.push((
            format!("curved {d:?}"),
            WarpSpec::Curved {
                strength: 0.3,
                direction: d,
                offset: 2.0,
                width: 0.0,
            },
            curved_g(0.3, d, 2.0, 24.0),
        ));
        cases.push((
            format!("tilted {d:?}"),
            WarpSpec::Tilted {
                strength: 0.2,
                direction: d,
                offset: 3.0,
            },
            tilted_g(0.2, d, 3.0),
        ));
        cases.push((
            format!("conic {d:?}"),
            WarpSpec::Conic {
                angle: 30.0,
                direction: d,
                center: [3.0, -2.0],
            },
            conic_g(30.0, d, [3.0, -2.0]),
        ));
    }
    cases.push((
        "belt".into(),
        WarpSpec::Belt {
            angle: 20.0,
            toward: [3.0, 4.0],
        },
        belt_g(20.0, [3.0, 4.0]),
    ));
    for (name, spec, g) in cases {
        let w = build(spec, Some(BASE));
        for [x, y, _] in POINTS {
            let (gv, _, _) = g(x, y);
            // below z0: flat
            let below = DVec3::new(x, y, 0.5);
            close(
                &format!("{name} below z0"),
                w.forward(below).z,
                0.5,
                VALUE_TOL,
            );
            close3(
                &format!("{name} axis below z0"),
                w.tool_axis(below),
                DVec3::Z,
                AXIS_TOL,
            );
            // above z1: the full warp
            let above = DVec3::new(x, y, 25.0);
            close(
                &format!("{name} above z1"),
                w.forward(above).z,
                25.0 + gv,
                VALUE_TOL,
            );
            for (z, ws, lin) in [(6.0, 0.15625, 0.25), (16.0, 0.84375, 0.75)] {
                let p = DVec3::new(x, y, z);
                let got = w.forward(p).z;
                close(
                    &format!("{name} mid-blend at z = {z}"),
                    got,
                    z + ws * gv,
                    VALUE_TOL,
                );
                if gv.abs() > 0.05 {
                    assert!(
                        (got - (z + lin * gv)).abs() > LINEAR_RAMP_GAP,
                        "{name}: a linear ramp gives the same value at {p}"
                    );
                }
            }
            for z in [0.5, 1.0, 6.0, 11.0, 16.0, 21.0, 25.0] {
                check_shear(&name, w.as_ref(), &g, Some(BASE), DVec3::new(x, y, z));
            }
        }
    }
}

/// One mid-blend point worked out to the last digit: tilted s = 0.2 outward, a = 0, x = 10
/// (g = 2 mm, ∂g/∂x = 0.2), base 1,21, z = 6 (t = ¼): T_z = 6 + 0.15625·2 = 6.3125 (a linear
/// ramp: 6.5); ∇T_z = (0.15625·0.2, 0, 1 + 0.05625·2) = (0.03125, 0, 1.1125), so the axis is
/// (0.028079, 0, 0.999606) and det J = 1.1125.
#[test]
fn base_blend_mid_point_by_hand() {
    let w = build(
        WarpSpec::Tilted {
            strength: 0.2,
            direction: Direction::Outward,
            offset: 0.0,
        },
        Some(BASE),
    );
    let p = DVec3::new(10.0, 0.0, 6.0);
    close("T_z", w.forward(p).z, 6.3125, VALUE_TOL);
    close3(
        "axis",
        w.tool_axis(p),
        DVec3::new(0.028_078_812_146_709_78, 0.0, 0.999_605_712_422_868_2),
        AXIS_TOL,
    );
    close("det J", w.jacobian_det(p), 1.1125, DET_TOL);
    close3(
        "inverse",
        w.inverse(DVec3::new(10.0, 0.0, 6.3125)),
        p,
        INVERSE_TOL,
    );
}

/// The cylindrical and spherical warps are not shears and refuse `--base` by its code.
#[test]
fn base_blend_is_refused_by_the_warps_that_are_not_shears() {
    for spec in [
        WarpSpec::Cylindrical {
            radius: 7.0,
            axis: [0.0, -7.0],
        },
        WarpSpec::Spherical {
            radius: 5.0,
            center: [0.0, 0.0, -5.0],
        },
    ] {
        let mut p = WarpParams {
            spec,
            base: Some(BASE),
        };
        let e = p.build(&bbox()).map(|_| ()).unwrap_err();
        assert_eq!(e.code(), "warp.base-not-supported", "{e}");
    }
}

/// Found by the wasm error tests: a misspelt key of the warp spec (`"angel"`) was dropped
/// silently and the default angle used. Unknown keys are refused everywhere in the warp options,
/// naming the key.
#[test]
fn a_misspelt_warp_key_is_refused_by_name() {
    use warpslice::pipeline::WarpOptions;
    let good = r#"{"warp": {"spec": {"kind": "conic", "angle": 30}}}"#;
    assert!(WarpOptions::from_json(good).is_ok());
    for (bad, key) in [
        (
            r#"{"warp": {"spec": {"kind": "conic", "angel": 30}}}"#,
            "angel",
        ),
        (
            r#"{"warp": {"spec": {"kind": "conic", "angle": 30}, "bace": [0, 1]}}"#,
            "bace",
        ),
        (
            r#"{"warp": {"spec": {"kind": "conic", "angle": 30}}, "max_egde": 2}"#,
            "max_egde",
        ),
    ] {
        let e = WarpOptions::from_json(bad).unwrap_err();
        assert!(e.to_string().contains(key), "{bad}: {e}");
        assert_eq!(e.code(), "options.invalid");
    }
}

// ---- field (issue 15 item 3b: g typed as an expression of x, y) ----

/// The typed field against g and ∇g written here as Rust closures (the crate parses the text
/// with exmex and differentiates it symbolically, or by central differences for `abs`): a
/// sine ripple, a paraboloid and a skewed roof, with and without the base blend. At
/// (5, 3): ripple g = 2·sin 1·cos(3/7) = 2·0.84147·0.90956 = 1.5307 mm.
#[test]
fn field_expressions_warp_as_their_hand_written_heights() {
    let ripple: Height = Box::new(|x, y| {
        (
            2.0 * (x / 5.0).sin() * (y / 7.0).cos(),
            0.4 * (x / 5.0).cos() * (y / 7.0).cos(),
            -2.0 / 7.0 * (x / 5.0).sin() * (y / 7.0).sin(),
        )
    });
    let paraboloid: Height =
        Box::new(|x, y| (0.01 * (x * x + 2.0 * y * y) - 1.0, 0.02 * x, 0.04 * y));
    let roof: Height = Box::new(|x, y| {
        let s = if x > 1.0 { 1.0 } else { -1.0 };
        (-0.25 * (x - 1.0).abs() + 0.1 * y, -0.25 * s, 0.1)
    });
    close("ripple at (5, 3)", ripple(5.0, 3.0).0, 1.5307, 1e-4);
    for (expr, g, axis_tol) in [
        ("2*sin(x/5)*cos(y/7)", ripple, AXIS_TOL),
        ("0.01*(x^2 + 2*y^2) - 1", paraboloid, AXIS_TOL),
        ("-0.25*abs(x - 1) + 0.1*y", roof, NUMERIC_AXIS_TOL),
    ] {
        for base in [None, Some([1.0, 25.0])] {
            let w = build(
                WarpSpec::Field {
                    expr: expr.into(),
                    grid: None,
                    over: None,
                },
                base,
            );
            for p in POINTS {
                check_shear_to(expr, w.as_ref(), &g, base, DVec3::from_array(p), axis_tol);
            }
        }
    }
}

/// Each bad field gets its own stable code: text that does not parse, a name other than x
/// and y, a value that is not finite over the footprint (the bbox is x ∈ [−12, 12]), a slope
/// past tan 80° ≈ 5.67, and text nested or long enough to exhaust a stack (refused before the
/// parser recurses).
#[test]
fn bad_field_expressions_get_named_codes() {
    // nested past MAX_EXPRESSION_DEPTH (32), longer than MAX_EXPRESSION_LEN (1000)
    let deep = format!("{}x{}", "(".repeat(40), ")".repeat(40));
    let long = "x+".repeat(600) + "x";
    for (expr, code) in [
        ("2*sin(x/5", "warp.expression-unparsable"),
        ("x + t", "warp.expression-unknown-variable"),
        ("ln(x)", "warp.field-not-finite"),
        ("0.1*sqrt(x)", "warp.field-not-finite"),
        ("6*y", "warp.field-too-steep"),
        (deep.as_str(), "warp.expression-unparsable"),
        (long.as_str(), "warp.expression-unparsable"),
    ] {
        let mut p = WarpParams {
            spec: WarpSpec::Field {
                expr: expr.to_string(),
                grid: None,
                over: None,
            },
            base: None,
        };
        let err = p.build(&bbox()).expect_err(expr);
        assert_eq!(err.code(), code, "{expr}: {err}");
        assert!(err.to_string().contains(expr), "{err} should quote {expr}");
    }
    // 5.6·y is within the limit
    let mut p = WarpParams {
        spec: WarpSpec::Field {
            expr: "5.6*y".into(),
            grid: None,
            over: None,
        },
        base: None,
    };
    assert!(p.build(&bbox()).is_ok());
}
