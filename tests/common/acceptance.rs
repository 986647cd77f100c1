//! The five warps of the acceptance matrix, shared by the native matrix (tests/common) and the
//! tests that also run under wasm (tests/planar_parity.rs includes this file by path).

use warpslice::warp::{Direction, WarpParams, WarpSpec};

/// The warps of the acceptance matrix: curved outward s = 0.3, tilted outward s = 0.2, conic
/// 30° outward, conic 30° inward, belt 15° with --base 0.6,10.
pub fn acceptance_warps() -> Vec<(&'static str, WarpParams)> {
    vec![
        (
            "curved-out-0.3",
            WarpParams {
                spec: WarpSpec::Curved {
                    strength: 0.3,
                    direction: Direction::Outward,
                    offset: 0.0,
                    width: 0.0,
                },
                base: None,
            },
        ),
        (
            "tilted-out-0.2",
            WarpParams {
                spec: WarpSpec::Tilted {
                    strength: 0.2,
                    direction: Direction::Outward,
                    offset: 0.0,
                },
                base: None,
            },
        ),
        (
            "conic-out-30",
            WarpParams {
                spec: WarpSpec::Conic {
                    angle: 30.0,
                    direction: Direction::Outward,
                    center: [0.0, 0.0],
                },
                base: None,
            },
        ),
        (
            "conic-in-30",
            WarpParams {
                spec: WarpSpec::Conic {
                    angle: 30.0,
                    direction: Direction::Inward,
                    center: [0.0, 0.0],
                },
                base: None,
            },
        ),
        (
            "belt-15-base",
            WarpParams {
                spec: WarpSpec::Belt {
                    angle: 15.0,
                    toward: [0.0, 1.0],
                },
                base: Some([0.6, 10.0]),
            },
        ),
    ]
}

/// The field warp of the real-slicer matrix (issue 15 item 3b): a typed ripple
/// g = 1.5·sin(x/6)·cos(y/8) mm (slopes ≤ 0.25·… ≈ 16°, within every preset's tilt), whose closed
/// form tests/common/closed.rs writes by hand. (Unused where this file is included by path.)
#[allow(dead_code)]
pub const FIELD_RIPPLE_EXPR: &str = "1.5*sin(x/6)*cos(y/8)";

/// The ripple field as a matrix warp.
#[allow(dead_code)]
pub fn field_ripple() -> (&'static str, WarpParams) {
    (
        "field-ripple",
        WarpParams {
            spec: WarpSpec::Field {
                expr: FIELD_RIPPLE_EXPR.into(),
                grid: None,
                over: None,
            },
            base: None,
        },
    )
}
