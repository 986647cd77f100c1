//! The warp each machine preset is tested with: one that suits its kinematics (shared by the
//! machine emitter's and the check's tests).

use warpslice::warp::{Direction, WarpSpec};

/// An outward cone of `angle` degrees about `center`.
pub fn conic(angle: f64, center: [f64; 2]) -> WarpSpec {
    WarpSpec::Conic {
        angle,
        direction: Direction::Outward,
        center,
    }
}

/// The warp each preset is tested with.
pub fn warp_for(preset: &str) -> WarpSpec {
    match preset {
        "cartesian" | "fullcontrol-prusa-b" => WarpSpec::Curved {
            strength: 0.3,
            direction: Direction::Outward,
            offset: 0.0,
            width: 0.0,
        },
        // the cone's apex is a singular point of the tool-axis field (its azimuth turns by
        // 180° across it): keep it outside the part
        "rtn-slicer4rtn" | "rotbot" | "rotbot-misaligned" => conic(45.0, [-15.0, 0.0]),
        "ratrig-vcore3-3z" => WarpSpec::Belt {
            angle: 20.0,
            toward: [0.0, 1.0],
        },
        // the mandrel of radius 20 mm under the part (the lathe's axis is moved there too)
        "lathe-a" => WarpSpec::Cylindrical {
            radius: 20.0,
            axis: [0.0, -20.0],
        },
        _ => conic(25.0, [-15.0, 0.0]),
    }
}
