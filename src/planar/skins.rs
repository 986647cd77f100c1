//! Top and bottom solid skins, by comparing a layer with the layers above and below it.
//!
//! With `S_j` the region of layer j (its whole cross-section), `I_i` the infill region of
//! layer i (inside its perimeters), T = `top_solid_layers` and B = `bottom_solid_layers`:
//!
//! - sparse_i = I_i ∩ (S_{i+1} ∩ … ∩ S_{i+T}) ∩ (S_{i−1} ∩ … ∩ S_{i−B}): what has at least T
//!   layers of part above it and B below it (a layer past the top or below the bed is empty,
//!   so the T topmost and B lowest layers are all solid);
//! - top_i = I_i − S_{i+1} (T > 0): the surface open to the air above, PrusaSlicer's
//!   "Top solid infill";
//! - solid_i = I_i − sparse_i − top_i: the other solid layers ("Solid infill").

use super::region::{difference, intersection, Region};

/// How one layer's infill region divides.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skins {
    /// Open to the air above: top solid infill.
    pub top: Region,
    /// Other solid infill (bottom surfaces and the layers within T or B of a surface).
    pub solid: Region,
    /// Sparse infill.
    pub sparse: Region,
}

/// The skins of layer `i` of `slices` (every layer's region) with infill region `inner`.
pub fn skins(slices: &[Region], inner: &Region, i: usize, top: u32, bottom: u32) -> Skins {
    let layer = |j: Option<usize>| j.and_then(|j| slices.get(j));
    let mut sparse = inner.clone();
    for k in 1..=top as usize {
        match layer(i.checked_add(k)) {
            Some(s) if !sparse.is_empty() => sparse = intersection(&sparse, s),
            _ => sparse.clear(),
        }
    }
    for k in 1..=bottom as usize {
        match layer(i.checked_sub(k)) {
            Some(s) if !sparse.is_empty() => sparse = intersection(&sparse, s),
            _ => sparse.clear(),
        }
    }
    let top_skin = if top > 0 {
        match layer(i.checked_add(1)) {
            Some(above) => difference(inner, above),
            None => inner.clone(),
        }
    } else {
        Region::new()
    };
    let solid = difference(&difference(inner, &sparse), &top_skin);
    Skins {
        top: top_skin,
        solid,
        sparse,
    }
}
