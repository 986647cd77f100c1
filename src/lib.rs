//! # warpslice
//!
//! Non-planar slicing by warping, after seeds 000 (B-axis pipeline), 001 (3Z tilting bed),
//! 002 (conic/tilted slicing, Slicer4RTN) and 004 (5-axis A/B table).
//!
//! The pipeline is the architecture; data flows one way:
//!
//! ```text
//!  STL bytes ─► mesh ─► subdivide ─► warp.forward ─► warped STL + job ──► (user's planar slicer)
//!                                                                               │
//!  G-code ◄─ machine.inverse ◄─ unwarp (segment, warp.inverse, E, travel) ◄─ register ◄─ gcode::read
//! ```
//!
//! ## Layers
//! Data flows one way. A module may use only modules on **earlier** lines of this list (modules
//! on one line are independent of each other); `tests/architecture.rs` reads this list and
//! fails on any `crate::` path that points sideways or back, and on any cycle:
//!
//! ```text
//! 0  test_rng
//! 1  error num schema tolerance
//! 2  mesh
//! 3  shapes warp planar
//! 4  anchor job overhang toolpath
//! 5  gcode surfaces
//! 6  register
//! 7  emit
//! 8  unwarp
//! 9  machine
//! 10 calibrate slicer collision
//! 11 pipeline check
//! 12 suggest
//! 13 describe
//! 14 wasm
//! ```
//!
//! `emit` (the [`emit::Emitter`] trait, E writing, the 3-axis emitter) sits below both `unwarp`
//! and `machine`: the unwarp computes the toolpath and hands it to an emitter it does not
//! know; a machine's emitter writes its axes; the `pipeline` picks which.
//!
//! ## Frames
//! - **input frame**: the STL as read.
//! - **model frame**: the input translated so that the centre of its XY bounding box is at
//!   (0, 0) and its lowest point at z = 0. Every warp is defined here.
//! - **slicing frame**: T(model frame) lifted so its lowest point (anchor included) is at z = 0;
//!   the warped STL is written in it.
//! - **slicer bed frame**: where the slicer put the warped mesh; [`register`] finds the shift.
//! - **output frame**: model frame + `model_to_output` (written into every output file).
//! - **machine frame**: axis values after a machine's inverse kinematics.
//!
//! ## Conventions
//! mm and degrees at every interface (CLI, JSON, G-code), radians inside; f64 throughout.
//! The tool axis `n` is the unit vector from the tip into the nozzle (up when printing planar).
//! "outward" means z' = z + g with g ≥ 0 growing away from the warp's centre.

#![warn(missing_docs)]

pub mod error;
pub mod num;
pub mod schema;
pub mod tolerance;

pub mod anchor;
pub mod calibrate;
pub mod check;
pub mod collision;
pub mod describe;
pub mod emit;
pub mod gcode;
pub mod job;
pub mod machine;
pub mod mesh;
pub mod overhang;
pub mod pipeline;
pub mod planar;
pub mod register;
pub mod shapes;
#[cfg(not(target_arch = "wasm32"))]
pub mod slicer;
pub mod suggest;
pub mod surfaces;
#[cfg(test)]
mod test_rng;
pub mod toolpath;
pub mod unwarp;
pub mod warp;

#[cfg(target_arch = "wasm32")]
pub mod wasm;
