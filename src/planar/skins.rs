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
//! - bridge_i = I_i ∩ grow(I_i ∩ open(S_i − S_{i−1}), M) (i ≥ 1): what lies over air — the
//!   layer's part the layer below does not hold, opened by w/10 to drop slivers of rounding —
//!   grown [`BRIDGE_MARGIN`] into the infill region to anchor it, PrusaSlicer 2.5's bottom
//!   bridges (`detect_surfaces_type`, `process_external_surfaces` with its 3 mm
//!   `EXTERNAL_INFILL_MARGIN`): "Bridge infill", printed at bridge flow; it takes precedence
//!   over top, solid and sparse;
//! - solid_i = I_i − sparse_i − top_i − bridge_i: the other solid layers ("Solid infill").

use super::region::{difference, intersection, offset, Region};

/// How far a bridge grows from the part over air into the infill region, mm (PrusaSlicer
/// 2.5's `EXTERNAL_INFILL_MARGIN`): its threads end on material, not at the edge of the air.
pub const BRIDGE_MARGIN: f64 = 3.0;

/// The opening (shrink, then grow back) of the part over air before a bridge is found there,
/// as a fraction of the line width (PrusaSlicer's `detect_surfaces_type`: a tenth of the
/// external perimeter's width): slivers left by slicing a sloped side are not bridges.
pub const BRIDGE_OPENING_PER_WIDTH: f64 = 0.1;

/// How one layer's infill region divides.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skins {
    /// Open to the air above: top solid infill.
    pub top: Region,
    /// Other solid infill (bottom surfaces and the layers within T or B of a surface).
    pub solid: Region,
    /// Sparse infill.
    pub sparse: Region,
    /// Over air: bridge infill.
    pub bridge: Region,
}

/// The skins of layer `i` of `slices` (every layer's region) with infill region `inner`, line
/// width `w`.
pub fn skins(slices: &[Region], inner: &Region, i: usize, top: u32, bottom: u32, w: f64) -> Skins {
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
    let bridge = match (i.checked_sub(1).and_then(|j| slices.get(j)), slices.get(i)) {
        (Some(below), Some(here)) if !inner.is_empty() => {
            let o = BRIDGE_OPENING_PER_WIDTH * w;
            let air = offset(&offset(&difference(here, below), -o), o);
            let over_air = intersection(inner, &air);
            if over_air.is_empty() {
                Region::new()
            } else {
                intersection(inner, &offset(&over_air, BRIDGE_MARGIN))
            }
        }
        _ => Region::new(),
    };
    let (top_skin, sparse) = if bridge.is_empty() {
        (top_skin, sparse)
    } else {
        (difference(&top_skin, &bridge), difference(&sparse, &bridge))
    };
    let solid = difference(&difference(&difference(inner, &sparse), &top_skin), &bridge);
    Skins {
        top: top_skin,
        solid,
        sparse,
        bridge,
    }
}
