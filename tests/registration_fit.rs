//! The fine registration's fit on constructed data (no slicer; runs under wasm too): walls
//! drawn a known inset inside a box's cross-sections and moved by a known translation are
//! found again, also with a side missing (a feature not printed), and a single wall is refused
//! as undetermined.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DVec2, DVec3};
use warpslice::error::Coded;
use warpslice::mesh::shapes::cuboid;
use warpslice::register::refine::refine;
use warpslice::register::sample::Sample;

const H: f64 = 0.2;
const INSET: f64 = 0.21;
const T: [f64; 2] = [57.3, 81.9];

/// Walls of a 20 × 30 mm box, `INSET` inside, moved by `T`, on 40 layers; `sides` picks which
/// of the four sides are printed.
fn walls(sides: [bool; 4]) -> Sample {
    let (x0, x1, y0, y1) = (-10.0 + INSET, 10.0 - INSET, -15.0 + INSET, 15.0 - INSET);
    let corners = [
        DVec2::new(x0, y0),
        DVec2::new(x1, y0),
        DVec2::new(x1, y1),
        DVec2::new(x0, y1),
    ];
    let t = DVec2::from_array(T);
    let mut s = Sample::new();
    for layer in 0..40u32 {
        let z = H * (layer + 1) as f64;
        for (i, &on) in sides.iter().enumerate() {
            if on {
                let (a, b) = (corners[i] + t, corners[(i + 1) % 4] + t);
                s.push(layer, z, a, b, 100 + layer as u64);
            }
        }
    }
    s
}

fn block() -> warpslice::mesh::Mesh {
    cuboid(DVec3::new(-10.0, -15.0, 0.0), DVec3::new(10.0, 15.0, 10.0))
}

#[test]
fn a_known_translation_and_inset_are_found_again() {
    let f = refine(&block(), &walls([true; 4]), H, &[[T[0] + 0.4, T[1] - 0.3]]).unwrap();
    assert!((f.translation[0] - T[0]).abs() < 1e-6, "{f:?}");
    assert!((f.translation[1] - T[1]).abs() < 1e-6, "{f:?}");
    assert!((f.inset - INSET).abs() < 1e-6, "{f:?}");
    assert!(f.rms < 1e-6 && f.layers > 10, "{f:?}");
}

#[test]
fn a_side_not_printed_does_not_move_the_fit() {
    // the +x side missing: the printed box is 0.2 mm short there, the walls still pin it
    let f = refine(
        &block(),
        &walls([true, false, true, true]),
        H,
        &[[T[0] - 0.5, T[1]]],
    )
    .unwrap();
    assert!((f.translation[0] - T[0]).abs() < 1e-6, "{f:?}");
    assert!((f.translation[1] - T[1]).abs() < 1e-6, "{f:?}");
}

#[test]
fn one_wall_alone_is_undetermined() {
    let e = refine(&block(), &walls([true, false, false, false]), H, &[T]).unwrap_err();
    assert_eq!(e.code(), "register.undetermined", "{e}");
}

#[test]
fn a_part_narrower_than_two_lines_is_undetermined() {
    // a 20 × 0.4 mm wall printed as one line down its middle
    let wall = cuboid(DVec3::new(-10.0, -0.2, 0.0), DVec3::new(10.0, 0.2, 10.0));
    let t = DVec2::from_array(T);
    let mut s = Sample::new();
    for layer in 0..40u32 {
        let z = H * (layer + 1) as f64;
        let (a, b) = (DVec2::new(-9.8, 0.0) + t, DVec2::new(9.8, 0.0) + t);
        s.push(layer, z, a, b, 100 + layer as u64);
    }
    // the line pins y only (its ends are no walls); a curved thin part (the corpus moon) pins
    // both but is caught as narrower than two lines (tests/real_slicers.rs)
    let e = refine(&wall, &s, H, &[T]).unwrap_err();
    assert_eq!(e.code(), "register.undetermined", "{e}");
}
