//! Flow: keep the extruded volume right.
//!
//! The slicer meters filament for the warped geometry: a piece of a move that covers the
//! warped volume dV' gets E_in ∝ dV'. Unwarped, the same material fills dV = dV' / det J, so
//! E_out = E_in / det J (for the pure shears det J = 1: E does not change even though the
//! path length does — scaling by the length ratio, as Slicer4RTN and the RotBot scripts do,
//! over-extrudes on slopes).
//!
//! On top, seed 000 §4.3.2: a global `flow` factor and an optional `ramp` (f0, z_ramp): the
//! factor rises linearly from f0 at z = 0 to 1 at z = z_ramp (the thesis uses 0.80 over
//! 1.2 mm), evaluated at the height of the piece's midpoint above the bed.

use serde::{Deserialize, Serialize};

/// Flow settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Flow {
    /// Global factor (`--flow`).
    pub factor: f64,
    /// `--ramp f0,z_ramp`.
    pub ramp: Option<[f64; 2]>,
}

impl Default for Flow {
    fn default() -> Self {
        Flow {
            factor: 1.0,
            ramp: None,
        }
    }
}

impl Flow {
    /// The factor at height `z` above the bed (mm).
    pub fn at(&self, z: f64) -> f64 {
        let ramp = match self.ramp {
            Some([f0, zr]) if zr > 0.0 => f0 + (1.0 - f0) * (z / zr).clamp(0.0, 1.0),
            _ => 1.0,
        };
        self.factor * ramp
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_of_seed_000() {
        let f = Flow {
            factor: 1.0,
            ramp: Some([0.8, 1.2]),
        };
        assert!((f.at(0.0) - 0.8).abs() < 1e-12);
        assert!((f.at(0.6) - 0.9).abs() < 1e-12);
        assert!((f.at(5.0) - 1.0).abs() < 1e-12);
    }
}
