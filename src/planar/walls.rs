//! Perimeters by inward offsetting, and the region left inside them for infill.
//!
//! With extrusion width w, layer height h and line spacing `s = w − h·(1 − π/4)`
//! ([`super::Settings::spacing`], PrusaSlicer's `Flow::spacing`), perimeter i (0: external) of
//! an island runs along the island's boundary offset inward by
//! `d_i = w/2 + i·s`: the external line's outer edge lies on the mesh's surface, each next line
//! touches the one outside it. Each perimeter fills a band `s` wide around its line, so the
//! infill region is the island offset inward by `d_{N−1} + s/2 = (w − s)/2 + N·s`, and the
//! lines side by side fill the layer's area
//! (`Σ length·s·h` = area·h, the solid check's volume model). An island narrower than its N
//! perimeters gets those that fit, and the infill region inside them (N = the fitted count):
//! a middle strip narrower than a line is still filled, by the infill's short lines.
//!
//! What of an island no external perimeter reaches (parts narrower than a line: a 0.35 mm
//! shell, a 0.2 mm fin, an island too thin for any wall) is printed as thin walls
//! ([`super::thin`]), one line along its middle.

use super::region::{offset, Contour, Region};
use super::thin::{self, ThinLine};

/// The perimeters and the infill region of one layer.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Walls {
    /// Per island: `perimeters[i]` are the closed lines of perimeter i (0: external).
    pub islands: Vec<Vec<Vec<Contour>>>,
    /// What is left inside the innermost perimeters, for skins and infill.
    pub inner: Region,
    /// Thin walls: lines along the middle of the parts narrower than a line.
    pub thin: Vec<ThinLine>,
    /// Thin parts too narrow or too short to print ([`thin::Thin::unprinted`]).
    pub thin_unprinted: usize,
}

/// Perimeters of `region` (a layer's union) for `perimeters` walls of width `w` and spacing `s`.
pub fn walls(region: &Region, perimeters: u32, w: f64, s: f64) -> Walls {
    let mut out = Walls::default();
    for shape in region {
        let island: Region = vec![shape.clone()];
        let mut lines = Vec::new();
        // the island's opening by w/2: what the external perimeter and the lines inside cover
        let mut opening = Region::new();
        for i in 0..perimeters {
            let d = w / 2.0 + f64::from(i) * s;
            let ring = offset(&island, -d);
            if ring.is_empty() {
                break;
            }
            if i == 0 {
                opening = offset(&ring, w / 2.0);
            }
            lines.push(ring.into_iter().flatten().collect::<Vec<Contour>>());
        }
        if perimeters > 0 {
            let t = thin::thin_walls(&island, &opening, w);
            out.thin.extend(t.lines);
            out.thin_unprinted += t.unprinted;
        }
        if perimeters > 0 && lines.is_empty() {
            continue;
        }
        // inside the perimeters that fit: an island too narrow for all of them (a 1 mm plate
        // fits one line a side, not two) leaves its middle to the infill, not empty
        let fitted = lines.len() as f64;
        let inner = offset(&island, -((w - s) / 2.0 + fitted * s));
        out.inner.extend(inner);
        out.islands.push(lines);
    }
    out
}
