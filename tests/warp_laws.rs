//! Every warp obeys the laws (src/warp/laws.rs): inverse(forward(p)) within 1e-9 mm, the
//! Jacobian against finite differences, the tool axis against the numeric gradient.
#![cfg(not(target_arch = "wasm32"))]

use glam::DVec3;
use proptest::prelude::*;
use warpslice::mesh::Aabb;
use warpslice::warp::{laws, Direction, WarpParams, WarpSpec};

fn bbox() -> Aabb {
    Aabb {
        min: DVec3::new(-20.0, -15.0, 0.0),
        max: DVec3::new(20.0, 15.0, 30.0),
    }
}

/// Every warp of the core issue, with and without a base blend.
fn all_warps() -> Vec<WarpParams> {
    let specs = vec![
        WarpSpec::Curved {
            strength: 0.3,
            direction: Direction::Outward,
            offset: 0.0,
            width: 0.0,
        },
        WarpSpec::Curved {
            strength: 0.2,
            direction: Direction::Inward,
            offset: 4.0,
            width: 0.0,
        },
        WarpSpec::Tilted {
            strength: 0.2,
            direction: Direction::Outward,
            offset: 0.0,
        },
        WarpSpec::Tilted {
            strength: 0.5,
            direction: Direction::Inward,
            offset: -3.0,
        },
        WarpSpec::Conic {
            angle: 30.0,
            direction: Direction::Outward,
            center: [0.0, 0.0],
        },
        WarpSpec::Conic {
            angle: 30.0,
            direction: Direction::Inward,
            center: [2.0, -1.0],
        },
        WarpSpec::Belt {
            angle: 15.0,
            toward: [0.0, 1.0],
        },
        WarpSpec::Belt {
            angle: 40.0,
            toward: [1.0, 1.0],
        },
    ];
    let specs = specs.into_iter().chain(field_warps());
    let mut out = Vec::new();
    for s in specs {
        out.push(WarpParams {
            spec: s.clone(),
            base: None,
        });
        out.push(WarpParams {
            spec: s,
            base: Some([0.6, 40.0]),
        });
    }
    // not shears (no base blend); axis and centre kept away from the sampled box (their domain
    // excludes the axis / centre and the seam below it)
    for spec in non_shear_warps() {
        out.push(WarpParams { spec, base: None });
    }
    out
}

/// The cylindrical and spherical warps (seed 002).
fn non_shear_warps() -> Vec<WarpSpec> {
    vec![
        WarpSpec::Cylindrical {
            radius: 15.0,
            axis: [0.0, -20.0],
        },
        WarpSpec::Cylindrical {
            radius: 3.0,
            axis: [4.0, -6.0],
        },
        WarpSpec::Spherical {
            radius: 15.0,
            center: [0.0, 0.0, -20.0],
        },
        WarpSpec::Spherical {
            radius: 2.0,
            center: [5.0, -3.0, -5.0],
        },
    ]
}

/// Typed field warps (issue 15 item 3b): a sine ripple, a paraboloid (exact gradients from
/// exmex) and a roof (`abs`: central differences), g within ±3.5 mm over the box.
fn field_warps() -> Vec<WarpSpec> {
    [
        "2*sin(x/5)*cos(y/7)",
        "0.004*(x^2 + 2*y^2) - 1.5",
        "-0.1*abs(x - 3) + 0.05*y",
    ]
    .into_iter()
    .map(|e| WarpSpec::Field {
        expr: e.into(),
        grid: None,
        over: None,
    })
    .chain(fields_over_families())
    .collect()
}

/// A B-spline grid over the sampled box (knots every 5 mm from (−25, −20), 11 × 9) with
/// coefficients 0.4·sin(i)·cos(j/2) mm, as text.
fn ripple_grid() -> String {
    let c: Vec<String> = (0..9)
        .flat_map(|j| {
            (0..11).map(move |i| format!("{}", 0.4 * (i as f64).sin() * (j as f64 / 2.0).cos()))
        })
        .collect();
    format!("-25,-20,5,5,11,9:{}", c.join(","))
}

/// Fields on top of a family warp (g = g_family + g_field, `--over`): a ripple over an
/// outward cone (its apex at (2, −1) is a kink) and a B-spline over a belt.
fn fields_over_families() -> Vec<WarpSpec> {
    vec![
        WarpSpec::Field {
            expr: "0.3*sin(x/4)*cos(y/6)".into(),
            grid: None,
            over: Some("conic:angle=25:direction=outward:center=2,-1".into()),
        },
        WarpSpec::Field {
            expr: String::new(),
            grid: Some(ripple_grid()),
            over: Some("belt:angle=20:toward=-0.6,0.8".into()),
        },
    ]
}

/// Distance from the nearest kink of the warp's height function (crease, apex), mm.
fn kink_distance(spec: &WarpSpec, p: DVec3) -> f64 {
    match *spec {
        WarpSpec::Tilted { offset, .. } => (p.x + offset).abs(),
        WarpSpec::Conic { center, .. } => {
            ((p.x - center[0]).powi(2) + (p.y - center[1]).powi(2)).sqrt()
        }
        WarpSpec::Field { ref expr, .. } if expr.contains("abs(x - 3)") => (p.x - 3.0).abs(),
        WarpSpec::Field {
            over: Some(ref o), ..
        } if o.starts_with("conic") => ((p.x - 2.0).powi(2) + (p.y + 1.0).powi(2)).sqrt(),
        _ => f64::INFINITY,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]
    #[test]
    fn every_warp_obeys_the_laws(x in -20.0f64..20.0, y in -15.0f64..15.0, z in 0.0f64..30.0) {
        let p = DVec3::new(x, y, z);
        for mut params in all_warps() {
            let w = params.build(&bbox()).expect("valid warp");
            // derivative checks need to stay off kinks and the blend's ends (w'' jumps there)
            let near_blend_end = params.base.is_some_and(|[z0, z1]| (z - z0).abs() < 1e-3 || (z - z1).abs() < 1e-3);
            let smooth = kink_distance(&params.spec, p) > 1e-3 && !near_blend_end;
            if let Err(e) = laws::check_point(w.as_ref(), p, smooth) {
                prop_assert!(false, "{}", e);
            }
        }
    }
}

/// The field warp typed as the tilted warp's roof s·c·|x + a| and as the belt's plane
/// tan α·(d·(x, y)) warps, unwarps and tilts the tool exactly as those warps do (the seed warps'
/// own code is the oracle: a different parser, evaluator and derivative), with and without the
/// base blend.
#[test]
fn a_field_typed_as_a_roof_or_a_plane_equals_the_tilted_and_belt_warps() {
    let t30 = 30f64.to_radians().tan();
    let cases = [
        (
            WarpSpec::Tilted {
                strength: 0.3,
                direction: Direction::Inward,
                offset: 2.0,
            },
            "-0.3*abs(x + 2)".to_string(),
        ),
        (
            WarpSpec::Belt {
                angle: 30.0,
                toward: [0.6, 0.8],
            },
            format!("{t30}*(0.6*x + 0.8*y)"),
        ),
    ];
    for (seed, expr) in cases {
        for base in [None, Some([0.6, 40.0])] {
            let mut a = WarpParams {
                spec: seed.clone(),
                base,
            };
            let mut b = WarpParams {
                spec: WarpSpec::Field {
                    expr: expr.clone(),
                    grid: None,
                    over: None,
                },
                base,
            };
            assert_same_warp(&mut a, &mut b, &expr, [1e-12, 1e-9, 1e-7]);
        }
    }
}

#[test]
fn crease_and_apex_get_the_vertical_axis() {
    let mut t = WarpParams {
        spec: WarpSpec::Tilted {
            strength: 0.2,
            direction: Direction::Outward,
            offset: 2.0,
        },
        base: None,
    };
    let w = t.build(&bbox()).unwrap();
    assert_eq!(w.tool_axis(DVec3::new(-2.0, 3.0, 1.0)), DVec3::Z);
    let mut c = WarpParams {
        spec: WarpSpec::Conic {
            angle: 30.0,
            direction: Direction::Outward,
            center: [1.0, 1.0],
        },
        base: None,
    };
    let w = c.build(&bbox()).unwrap();
    assert_eq!(w.tool_axis(DVec3::new(1.0, 1.0, 5.0)), DVec3::Z);
}

#[test]
fn outward_tilts_the_tool_outward() {
    let mut c = WarpParams {
        spec: WarpSpec::Conic {
            angle: 30.0,
            direction: Direction::Outward,
            center: [0.0, 0.0],
        },
        base: None,
    };
    let w = c.build(&bbox()).unwrap();
    let n = w.tool_axis(DVec3::new(10.0, 0.0, 5.0));
    assert!(
        n.x > 0.0 && (n.x - 0.5).abs() < 1e-12 && (n.z - 0.75f64.sqrt()).abs() < 1e-12,
        "{n}"
    );
    let mut b = WarpParams {
        spec: WarpSpec::Belt {
            angle: 15.0,
            toward: [0.0, 1.0],
        },
        base: None,
    };
    let w = b.build(&bbox()).unwrap();
    let n = w.tool_axis(DVec3::new(3.0, 4.0, 5.0));
    assert!(
        (n.y - 15f64.to_radians().sin()).abs() < 1e-12 && n.x == 0.0,
        "{n}"
    );
}

#[test]
fn curved_matches_seed_000_eq_1() {
    // z' = z + s·c·(x+a)²/(w/2+|a|), w = 40 (bbox width), s = 0.3, a = 4, outward
    let mut p = WarpParams {
        spec: WarpSpec::Curved {
            strength: 0.3,
            direction: Direction::Outward,
            offset: 4.0,
            width: 0.0,
        },
        base: None,
    };
    let w = p.build(&bbox()).unwrap();
    let q = w.forward(DVec3::new(6.0, 1.0, 2.0));
    assert!((q.z - (2.0 + 0.3 * 100.0 / 24.0)).abs() < 1e-12, "{q}");
    assert!(matches!(p.spec, WarpSpec::Curved { width, .. } if width == 40.0));
}

/// Belt 15° with --base 0.6,10 is valid for parts up to ±23 mm from the centre
/// (1 + w′(z)·g > 0 needs |y|·tan 15° < 9.4/1.5).
#[test]
fn base_blend_monotonic_limit_belt_15() {
    let spec = WarpSpec::Belt {
        angle: 15.0,
        toward: [0.0, 1.0],
    };
    for (half, ok) in [(23.0, true), (23.3, true), (23.6, false), (30.0, false)] {
        let b = Aabb {
            min: DVec3::new(-5.0, -half, 0.0),
            max: DVec3::new(5.0, half, 20.0),
        };
        let mut p = WarpParams {
            spec: spec.clone(),
            base: Some([0.6, 10.0]),
        };
        assert_eq!(p.build(&b).is_ok(), ok, "half-width {half}");
    }
}

/// Belt 45° with --base 0.6,3 on a 20 mm cube must be refused, naming the limit.
#[test]
fn base_blend_refuses_belt_45_on_cube_naming_limit() {
    let b = Aabb {
        min: DVec3::new(-10.0, -10.0, 0.0),
        max: DVec3::new(10.0, 10.0, 20.0),
    };
    let mut p = WarpParams {
        spec: WarpSpec::Belt {
            angle: 45.0,
            toward: [0.0, 1.0],
        },
        base: Some([0.6, 3.0]),
    };
    let err = p.build(&b).unwrap_err();
    let msg = err.to_string();
    // tan α_max = 0.99·2.4/1.5/10 → α_max ≈ 8.996°
    let expected = (0.99f64 * 2.4 / 1.5 / 10.0).atan().to_degrees();
    assert!(msg.contains("largest allowed angle"), "{msg}");
    assert!(
        msg.contains(&format!("{expected:.3}")),
        "{msg} should name {expected:.3}"
    );
    // and the named limit is accepted
    let mut q = WarpParams {
        spec: WarpSpec::Belt {
            angle: expected,
            toward: [0.0, 1.0],
        },
        base: Some([0.6, 3.0]),
    };
    assert!(q.build(&b).is_ok());
}

#[test]
fn bad_parameters_are_named() {
    let mut p = WarpParams {
        spec: WarpSpec::Conic {
            angle: 90.0,
            direction: Direction::Outward,
            center: [0.0, 0.0],
        },
        base: None,
    };
    assert!(p.build(&bbox()).unwrap_err().to_string().contains("angle"));
    let mut p = WarpParams {
        spec: WarpSpec::Belt {
            angle: 10.0,
            toward: [0.0, 0.0],
        },
        base: None,
    };
    assert!(p.build(&bbox()).unwrap_err().to_string().contains("toward"));
    let mut p = WarpParams {
        spec: WarpSpec::Tilted {
            strength: f64::NAN,
            direction: Direction::Outward,
            offset: 0.0,
        },
        base: None,
    };
    assert!(p
        .build(&bbox())
        .unwrap_err()
        .to_string()
        .contains("strength"));
    let mut p = WarpParams {
        spec: WarpSpec::Belt {
            angle: 10.0,
            toward: [0.0, 1.0],
        },
        base: Some([5.0, 2.0]),
    };
    assert!(p.build(&bbox()).unwrap_err().to_string().contains("base"));
}

#[test]
fn cylindrical_and_spherical_layers_are_coaxial_cylinders_and_concentric_spheres() {
    let bb = bbox();
    // cylindrical: T_z = ρ − R, radial tool axis, det J = R/ρ, E scaled by ρ/R
    let mut c = WarpParams {
        spec: WarpSpec::Cylindrical {
            radius: 15.0,
            axis: [0.0, -20.0],
        },
        base: None,
    };
    let w = c.build(&bb).unwrap();
    let p = DVec3::new(3.0, 4.0, 1.0);
    let rho = (4.0f64.powi(2) + 21.0f64.powi(2)).sqrt();
    assert!((w.forward(p).z - (rho - 15.0)).abs() < 1e-12);
    assert!((w.tool_axis(p) - DVec3::new(0.0, 4.0, 21.0) / rho).length() < 1e-12);
    assert!((w.jacobian_det(p) - 15.0 / rho).abs() < 1e-12);
    // a slicer layer z' = k·h is a cylinder: its points keep ρ = R + k·h
    for y in [-10.0, 0.0, 7.0] {
        let q = w.inverse(DVec3::new(1.0, y, 0.6));
        assert!((((q.y).powi(2) + (q.z + 20.0).powi(2)).sqrt() - 15.6).abs() < 1e-12);
    }
    // spherical: T_z = |p − c| − R, radial tool axis
    let mut s = WarpParams {
        spec: WarpSpec::Spherical {
            radius: 15.0,
            center: [0.0, 0.0, -20.0],
        },
        base: None,
    };
    let w = s.build(&bb).unwrap();
    let p = DVec3::new(3.0, -4.0, 2.0);
    let v = p - DVec3::new(0.0, 0.0, -20.0);
    assert!((w.forward(p).z - (v.length() - 15.0)).abs() < 1e-12);
    assert!((w.tool_axis(p) - v.normalize()).length() < 1e-12);
    for (x, y) in [(0.0, 0.0), (5.0, -2.0), (-9.0, 3.0)] {
        let q = w.inverse(DVec3::new(x, y, 1.2)) - DVec3::new(0.0, 0.0, -20.0);
        assert!((q.length() - 16.2).abs() < 1e-12);
    }
    // the top pole is smooth
    laws::check_point(w.as_ref(), DVec3::new(0.0, 0.0, 5.0), true).unwrap();
}

#[test]
fn base_is_refused_for_the_non_shear_warps_and_bad_radii_are_named() {
    for spec in non_shear_warps() {
        let e = WarpParams {
            spec,
            base: Some([0.6, 3.0]),
        }
        .build(&bbox())
        .unwrap_err()
        .to_string();
        assert!(e.contains("does not take --base"), "{e}");
    }
    let e = WarpParams {
        spec: WarpSpec::Spherical {
            radius: 0.0,
            center: [0.0; 3],
        },
        base: None,
    }
    .build(&bbox())
    .unwrap_err()
    .to_string();
    assert!(e.contains("radius") && e.contains("> 0"), "{e}");
    let e = WarpParams {
        spec: WarpSpec::Cylindrical {
            radius: 5.0,
            axis: [f64::NAN, 0.0],
        },
        base: None,
    }
    .build(&bbox())
    .unwrap_err()
    .to_string();
    assert!(e.contains("axis"), "{e}");
}

/// A field with an all-zero grid over a family warp warps, unwarps and tilts the tool exactly
/// as the family warp alone (the family's own code is the oracle), with and without the base
/// blend: the fitted field's start is the family optimum itself.
#[test]
fn a_zero_field_over_a_family_warp_equals_the_family_warp() {
    let zero = format!("-25,-20,5,5,11,9:{}", vec!["0"; 99].join(","));
    let families = [
        WarpSpec::Conic {
            angle: 25.0,
            direction: Direction::Outward,
            center: [2.0, -1.0],
        },
        WarpSpec::Belt {
            angle: 20.0,
            toward: [-0.6, 0.8],
        },
        WarpSpec::Curved {
            strength: 0.2,
            direction: Direction::Inward,
            offset: 4.0,
            width: 40.0,
        },
        WarpSpec::Tilted {
            strength: 0.5,
            direction: Direction::Inward,
            offset: -3.0,
        },
    ];
    for family in families {
        let over = warpslice::warp::over::to_text(&family).unwrap();
        for base in [None, Some([0.6, 40.0])] {
            let mut a = WarpParams {
                spec: family.clone(),
                base,
            };
            let mut b = WarpParams {
                spec: WarpSpec::Field {
                    expr: String::new(),
                    grid: Some(zero.clone()),
                    over: Some(over.clone()),
                },
                base,
            };
            assert_same_warp(&mut a, &mut b, &over, [0.0, 1e-12, 0.0]);
        }
    }
}

/// Warps `a` and `b` move, unwarp and tilt the tool alike over a grid of the box: forward
/// within `tol[0]`, inverse within `tol[1]`, tool axis within `tol[2]` (mm, mm, unit vector);
/// `what` names the case.
fn assert_same_warp(a: &mut WarpParams, b: &mut WarpParams, what: &str, tol: [f64; 3]) {
    let (wa, wb) = (a.build(&bbox()).unwrap(), b.build(&bbox()).unwrap());
    for i in 0..=20 {
        for j in 0..=10 {
            for z in [0.0, 0.6, 7.3, 21.0, 30.0] {
                let p = DVec3::new(-20.0 + 2.0 * i as f64 + 0.01, -15.0 + 3.0 * j as f64, z);
                let (qa, qb) = (wa.forward(p), wb.forward(p));
                assert!((qa - qb).length() <= tol[0], "{what} at {p}: {qa} vs {qb}");
                let q = qa + DVec3::new(0.0, 0.0, 0.37);
                assert!(
                    (wa.inverse(q) - wb.inverse(q)).length() <= tol[1],
                    "{what} inverse at {q}"
                );
                let (na, nb) = (wa.tool_axis(p), wb.tool_axis(p));
                assert!(
                    (na - nb).length() <= tol[2],
                    "{what} tool axis at {p}: {na} vs {nb}"
                );
            }
        }
    }
}

/// A shear built for its height's own type (`Height::into_shear`, what `WarpParams::build`
/// returns: g and ∇g called directly) is the shear over `dyn Height` (`Shear::new` of the
/// spec's boxed height) bit for bit: forward, inverse, Jacobian, its determinant and the tool
/// axis, on every shear warp of `all_warps` with and without the base blend.
#[test]
fn a_shear_of_its_heights_own_type_is_the_dyn_shear_bit_for_bit() {
    use warpslice::warp::{BaseBlend, Shear, Warp};
    let mut shears = 0;
    for mut params in all_warps() {
        if !params.spec.is_shear() {
            continue;
        }
        let built = params.build(&bbox()).unwrap();
        let blend = params.base.map(|[z0, z1]| BaseBlend::new(z0, z1));
        let dynamic = Shear::new(params.spec.height().unwrap(), blend);
        let what = format!("{} base {:?}", params.spec.name(), params.base);
        for i in 0..=16 {
            for j in 0..=12 {
                for z in [0.0, 0.3, 0.6, 5.0, 22.7, 39.9, 45.0] {
                    let p = DVec3::new(-20.0 + 2.5 * i as f64 + 0.013, -15.0 + 2.5 * j as f64, z);
                    let bits = |v: DVec3| v.to_array().map(f64::to_bits);
                    assert_eq!(
                        bits(built.forward(p)),
                        bits(dynamic.forward(p)),
                        "{what}: forward at {p}"
                    );
                    assert_eq!(
                        bits(built.inverse(p)),
                        bits(dynamic.inverse(p)),
                        "{what}: inverse at {p}"
                    );
                    assert_eq!(
                        bits(built.tool_axis(p)),
                        bits(dynamic.tool_axis(p)),
                        "{what}: tool axis at {p}"
                    );
                    let (ja, jb) = (built.jacobian(p), dynamic.jacobian(p));
                    assert_eq!(
                        ja.to_cols_array().map(f64::to_bits),
                        jb.to_cols_array().map(f64::to_bits),
                        "{what}: Jacobian at {p}"
                    );
                    assert_eq!(
                        built.jacobian_det(p).to_bits(),
                        dynamic.jacobian_det(p).to_bits(),
                        "{what}: det J at {p}"
                    );
                }
            }
        }
        shears += 1;
    }
    assert!(shears >= 20, "{shears} shear warps compared");
}
