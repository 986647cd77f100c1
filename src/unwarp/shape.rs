//! The shape check: the G-code must have been sliced from this job's warped STL.
//!
//! Registration matches boxes; two warps of one model can have the same box (a 31° or 29.5°
//! cone on a 30° G-code, an inward cone on an outward one, a centre moved by 0.5 mm) and a
//! wrong `--offset` skips the match. A planar slicer prints layer k's beads inside the warped
//! mesh's cross-section at the layer's mid-height z_k − h_k/2 (h_k = z_k − z_{k−1}, the slicer's
//! own layer height, read from the file). So every object extrusion point g of a right G-code
//! maps back into the part:
//!
//! p = T⁻¹(g_x − dx, g_y − dy, z_k − h_k/2 − stl_z_offset) ∈ the model's bounding box,
//!
//! one-sided: a feature the slicer did not print (thinner than a line) takes nothing away. The
//! check measures how far p lies outside the box, per face: in x and y directly (mm, model
//! frame); on the bottom and top faces in z, where a warped layer tilted by θ (tool axis n:
//! tan θ = |n_xy| / n_z) turns a distance d normal to the surface into d / cos θ and an outline
//! shifted by δ in the layer into δ · tan θ. Allowed: [`SHAPE_TOLERANCE_NORMAL`] (d) and
//! [`SHAPE_TOLERANCE_OUTLINE`] (δ). A point beyond half a layer refuses at once; points beyond
//! the tolerance are counted and more than [`SHAPE_OUTLIERS`] refuse at the end
//! (`unwarp.shape-mismatch`, naming the worst point, its line and the face).
//!
//! Measured on the corpus 20 mm box, conic 30° outward, 0.2 mm layers (worst overshoot of any
//! point, mm, bottom/top; negative: inside): the right job −0.07/−0.04 (PrusaSlicer),
//! −0.10/−0.01 (Slic3r), −0.11/−0.11 (CuraEngine); a 31° job +0.19…+0.21 on the bottom; a 29.5°
//! job +0.045…+0.15 on the top; the centre moved 0.5 mm +0.17…+0.26; the inward cone +7.4.
//!
//! **By cross-section.** The box is larger than most parts' cross-sections, so on a non-box
//! model a wrong job can stay inside it. With the warped mesh at hand (the CLI reads the STL
//! beside the job; `run` and the page have it), each point is also compared with the mesh's
//! cut at its layer's mid-height ([`super::section`]): g − (dx, dy) must lie inside the cut or
//! within [`SECTION_TOLERANCE`] of it (support material, printed outside the part by design,
//! is left out). **Measured and reported, not yet refusing** (`shape_section_margin_mm`,
//! [`ShapeCheck::section_worst`]). The points up to 1 mm outside that CuraEngine's files of
//! boxes on a curved warp showed were this cut's: a layer's mid-height exactly on a row of the
//! subdivided walls' vertices lost the walls (fixed 2026-11-27; the cubes' margins are now
//! −0.24 mm). It refuses once a full real-slicer matrix has measured the margins of every
//! right job (Slic3r's gear wheel: −0.049 mm before the fix).

use glam::DVec3;

use crate::job::Job;
use crate::toolpath::Feature;
use crate::warp::Warp;

use super::section::Sections;

/// Distance (normal to the warped surface) a printed point may lie outside the part, mm: the
/// warped STL's chord tolerance (0.01, [`crate::tolerance::DEFAULT_TOLERANCE`]), the slicers'
/// resolution (0.005, [`crate::tolerance::SLICER_RESOLUTION`]) and the G-code's 3-decimal
/// rounding, with room.
pub const SHAPE_TOLERANCE_NORMAL: f64 = 0.02;
/// How far a slicer may move a layer's outline outward in the layer (its polygon
/// simplification: CuraEngine's `meshfix_maximum_deviation` is 0.025 mm), mm.
pub const SHAPE_TOLERANCE_OUTLINE: f64 = 0.03;
/// Points beyond the tolerance (but within half a layer) that are taken as a slicer's
/// oddities; more refuse the G-code.
pub const SHAPE_OUTLIERS: u64 = 5;
/// How far outside the warped mesh's cut at the layer's mid-height a printed point may lie,
/// mm: the slicers' outline simplification ([`SHAPE_TOLERANCE_OUTLINE`]) and the G-code's
/// rounding and the slicers' resolution ([`SHAPE_TOLERANCE_NORMAL`]). Bead centres lie about
/// half a line width (0.2 mm) inside the cut.
pub const SECTION_TOLERANCE: f64 = SHAPE_TOLERANCE_NORMAL + SHAPE_TOLERANCE_OUTLINE;

/// The faces of the model's box, as the error names them.
pub const FACES: [&str; 7] = [
    "beyond the part's −x side",
    "beyond the part's +x side",
    "beyond the part's −y side",
    "beyond the part's +y side",
    "below the part's bottom",
    "above the part's top",
    "outside the warped mesh's cross-section at the layer's mid-height",
];
/// The index of the cross-section in [`FACES`].
pub const SECTION_FACE: usize = 6;

/// The worst point found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Finding {
    /// 1-based G-code line.
    pub line: u64,
    /// The G-code point, mm.
    pub gcode: DVec3,
    /// Its model-frame point (at the layer's mid-height), mm.
    pub model: DVec3,
    /// How far outside, mm (along the face's axis).
    pub overshoot: f64,
    /// How far it may be there, mm.
    pub allowed: f64,
    /// Index into [`FACES`].
    pub face: usize,
    /// The slicer's layer index.
    pub layer: u32,
}

/// The running check.
#[derive(Clone, Debug, Default)]
pub struct ShapeCheck {
    /// Current layer index, its top z and the previous layer's top z (G-code frame).
    layer: Option<(u32, f64, Option<f64>)>,
    /// Points beyond the tolerance.
    pub beyond: u64,
    /// The point with the largest overshoot beyond its allowance (negative: inside with room).
    pub worst: Option<Finding>,
    /// The warped mesh's cuts, when the mesh was given.
    sections: Option<Sections>,
    /// The largest distance outside the cut less its allowance over the points checked by
    /// cross-section, mm.
    pub section_margin: Option<f64>,
    /// Points beyond the cut's tolerance (reported, not refused).
    pub section_beyond: u64,
    /// The worst point outside the cut.
    pub section_worst: Option<Finding>,
}

impl ShapeCheck {
    /// The check against the box, and against the cross-sections of `mesh` (the job's warped
    /// mesh, STL frame) when given.
    pub fn new(mesh: Option<&crate::mesh::Mesh>) -> ShapeCheck {
        ShapeCheck {
            sections: mesh.map(Sections::new),
            ..ShapeCheck::default()
        }
    }

    /// Check the object extrusion point `g` (G-code frame) of layer `layer` at line `line`,
    /// of `feature`; `(dx, dy)` is the STL → G-code translation. Returns the finding when the
    /// point lies beyond half a layer outside the part's box.
    #[allow(clippy::too_many_arguments)]
    pub fn point(
        &mut self,
        warp: &dyn Warp,
        job: &Job,
        (dx, dy): (f64, f64),
        layer: u32,
        line: u64,
        g: DVec3,
        feature: Feature,
    ) -> Option<Finding> {
        let (_, top, prev) = match self.layer {
            Some((l, top, prev)) if l == layer => (l, top, prev),
            Some((_, top, _)) => {
                let s = (layer, g.z, Some(top));
                self.layer = Some(s);
                s
            }
            None => {
                let s = (layer, g.z, None);
                self.layer = Some(s);
                s
            }
        };
        let h = match prev {
            Some(p) if top > p => (top - p).min(2.0 * job.layer_height),
            _ => job.layer_height,
        };
        let q = DVec3::new(g.x - dx, g.y - dy, g.z - 0.5 * h - job.stl_z_offset);
        let p = warp.inverse(q);
        if !p.is_finite() {
            return None;
        }
        let b = job.model_bbox;
        let over = [
            b.min.x - p.x,
            p.x - b.max.x,
            b.min.y - p.y,
            p.y - b.max.y,
            b.min.z - p.z,
            p.z - b.max.z,
        ];
        let n = warp.tool_axis(p);
        let cos = n.z.abs().max(1e-6);
        let tan = n.truncate().length() / cos;
        let z_allowed = SHAPE_TOLERANCE_NORMAL / cos + SHAPE_TOLERANCE_OUTLINE * tan;
        let xy_allowed = SHAPE_TOLERANCE_NORMAL + SHAPE_TOLERANCE_OUTLINE;
        let mut gross = None;
        // the cut at the layer's mid-height (G-code z is the STL's: the slicer puts the
        // warped STL's lowest point on the bed); support is printed outside the part
        let support = matches!(feature, Feature::Support | Feature::SupportInterface);
        let zmid = g.z - 0.5 * h;
        let q = glam::DVec2::new(g.x - dx, g.y - dy);
        let cut = match self.sections.as_mut() {
            Some(s) if !support => Some(s.signed_distance(zmid, q)),
            _ => None,
        };
        if let Some(d) = cut {
            let m = d - SECTION_TOLERANCE;
            self.section_margin = Some(self.section_margin.map_or(m, |w| w.max(m)));
            if m > 0.0 {
                self.section_beyond += 1;
                if self
                    .section_worst
                    .is_none_or(|w| m > w.overshoot - w.allowed)
                {
                    self.section_worst = Some(Finding {
                        line,
                        gcode: g,
                        model: DVec3::new(q.x, q.y, zmid),
                        overshoot: d,
                        allowed: SECTION_TOLERANCE,
                        face: SECTION_FACE,
                        layer,
                    });
                }
            }
        }
        // measured, not yet refusing: CuraEngine's curved-warp files of a box have points up to
        // 1 mm outside the cut, unexplained (the slicer's or this cut's); until that is
        // understood only the box refuses
        let faces = over.iter().copied().enumerate();
        for (face, o) in faces {
            let allowed = match face {
                SECTION_FACE => SECTION_TOLERANCE,
                4 | 5 => z_allowed,
                _ => xy_allowed,
            };
            let model = if face == SECTION_FACE {
                DVec3::new(q.x, q.y, zmid)
            } else {
                p
            };
            let f = Finding {
                line,
                gcode: g,
                model,
                overshoot: o,
                allowed,
                face,
                layer,
            };
            if self
                .worst
                .is_none_or(|w| o - allowed > w.overshoot - w.allowed)
            {
                self.worst = Some(f);
            }
            if o <= allowed {
                continue;
            }
            self.beyond += 1;
            // a point outside the cut only counts (CuraEngine prints a lone point up to 1 mm
            // out of its cut on curved warps, as its oddities beyond the box are counted)
            if face != SECTION_FACE && o > 0.5 * h + allowed && gross.is_none() {
                gross = Some(f);
            }
        }
        gross
    }

    /// The largest overshoot less its allowance, mm (negative: every point inside with this
    /// much room; `None` before any point).
    pub fn margin(&self) -> Option<f64> {
        self.worst.map(|w| w.overshoot - w.allowed)
    }

    /// The finding that refuses the G-code at its end: more than [`SHAPE_OUTLIERS`] points
    /// beyond the tolerance.
    pub fn verdict(&self) -> Option<(Finding, u64)> {
        match self.worst {
            Some(w) if self.beyond > SHAPE_OUTLIERS => Some((w, self.beyond)),
            _ => None,
        }
    }
}
