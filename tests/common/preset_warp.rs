//! The warp each machine preset is tested with: one that suits its kinematics (shared by the
//! machine emitter's and the check's tests).

use warpslice::machine::{preset, MachineSpec};
use warpslice::pipeline::{warp_model, WarpOptions, WarpOutput};
use warpslice::warp::{Direction, WarpParams, WarpSpec};

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

/// The machine of a preset as the tests use it (the lathe's mandrel 20 mm under the part, as
/// its warp wants).
pub fn spec_for(name: &str) -> MachineSpec {
    let mut spec = preset(name).unwrap();
    if let warpslice::machine::spec::Kinematics::LatheA(p) = &mut spec.kinematics {
        p.axis_z_mm = -20.0;
    }
    spec
}

/// The 6 mm cube warped with `name`'s warp (small, so every preset's unwarp stays quick).
pub fn warped_cube6(name: &str) -> WarpOutput {
    let mut m = warpslice::shapes::example("cube").unwrap();
    for v in &mut m.vertices {
        *v *= 0.3;
    }
    let stl = warpslice::mesh::write_stl(&m, "cube 6");
    warp_model(
        &stl,
        &WarpOptions::new(WarpParams {
            spec: warp_for(name),
            base: None,
        }),
    )
    .unwrap()
}
