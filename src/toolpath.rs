//! The non-planar toolpath: what unwarp hands to the machines.
//!
//! Every point is in the **output frame** (mm), with the unit tool axis `n` pointing from the
//! tip into the nozzle (the layer normal ∇T_z/|∇T_z| mapped back; `(0,0,1)` for planar moves).

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// What the slicer said a move is (from `;TYPE:` comments, normalised across slicers).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[non_exhaustive]
pub enum Feature {
    /// No `;TYPE:` seen (Slic3r writes none) — taken to be part of the object.
    #[default]
    Unknown,
    /// The outermost perimeter (`External perimeter`, `Outer wall`, `WALL-OUTER`).
    OuterWall,
    /// Perimeters inside the outer one (`Perimeter`, `Inner wall`, `WALL-INNER`).
    InnerWall,
    /// Perimeters printed over air (`Overhang perimeter`, `Overhang wall`).
    OverhangWall,
    /// Sparse interior infill (`Internal infill`, `Sparse infill`, `FILL`).
    Infill,
    /// Solid interior infill (`Solid infill`, `Internal solid infill`, `SKIN`).
    SolidInfill,
    /// Solid infill of top surfaces (`Top solid infill`, `Top surface`).
    TopSolidInfill,
    /// Solid infill of bottom surfaces (`Bottom surface`).
    BottomSolidInfill,
    /// Infill spanning air between supports (`Bridge infill`, `Internal bridge infill`).
    Bridge,
    /// Extrusions filling gaps too narrow for a perimeter (`Gap fill`, `Gap infill`).
    GapFill,
    /// Low-flow passes smoothing a top surface (`Ironing`).
    Ironing,
    /// Support material (`Support material`, `SUPPORT`).
    Support,
    /// Dense support layers touching the part (`Support material interface`, roof, floor).
    SupportInterface,
    /// Loops around the part, not touching it (`Skirt`, `Skirt/Brim`, `SKIRT`); stays flat.
    Skirt,
    /// A flat rim attached to the part's first layer (`Brim`); stays flat.
    Brim,
    /// The purge tower of multi-material prints (`Wipe tower`, `PRIME-TOWER`); stays flat.
    WipeTower,
    /// Start/end or custom G-code extrusions (PrusaSlicer `;TYPE:Custom`, purge lines).
    Custom,
}

impl Feature {
    /// Normalise a `;TYPE:` label of PrusaSlicer, Slic3r/SuperSlicer, OrcaSlicer or Cura.
    pub fn from_type_label(label: &str) -> Feature {
        let l = label.trim();
        let lower = l.to_ascii_lowercase();
        match lower.as_str() {
            "external perimeter" | "outer wall" | "wall-outer" => Feature::OuterWall,
            "perimeter" | "inner wall" | "wall-inner" => Feature::InnerWall,
            "overhang perimeter" | "overhang wall" => Feature::OverhangWall,
            "internal infill" | "sparse infill" | "fill" | "infill" => Feature::Infill,
            "solid infill" | "internal solid infill" | "skin" => Feature::SolidInfill,
            "top solid infill" | "top surface" => Feature::TopSolidInfill,
            "bottom surface" => Feature::BottomSolidInfill,
            "bridge infill" | "internal bridge infill" | "internal bridge" | "bridge" => {
                Feature::Bridge
            }
            "gap fill" | "gap infill" => Feature::GapFill,
            "ironing" => Feature::Ironing,
            "support material" | "support" | "support-material" | "support transition" => {
                Feature::Support
            }
            "support material interface"
            | "support-interface"
            | "support interface"
            | "support-roof"
            | "support-floor" => Feature::SupportInterface,
            "skirt" | "skirt/brim" => Feature::Skirt,
            "brim" => Feature::Brim,
            "wipe tower" | "prime-tower" | "prime tower" => Feature::WipeTower,
            "custom" => Feature::Custom,
            _ => Feature::Unknown,
        }
    }

    /// Whether extrusions of this kind belong to the object (and are warped back).
    /// Skirt, brim, wipe tower and custom extrusions lie outside it and stay flat.
    pub fn is_object(self) -> bool {
        !matches!(
            self,
            Feature::Skirt | Feature::Brim | Feature::WipeTower | Feature::Custom
        )
    }

    /// Every feature, in discriminant order (`ALL[f as usize] == f`: the feature number in the
    /// web preview's toolpath buffer).
    pub const ALL: [Feature; 17] = [
        Feature::Unknown,
        Feature::OuterWall,
        Feature::InnerWall,
        Feature::OverhangWall,
        Feature::Infill,
        Feature::SolidInfill,
        Feature::TopSolidInfill,
        Feature::BottomSolidInfill,
        Feature::Bridge,
        Feature::GapFill,
        Feature::Ironing,
        Feature::Support,
        Feature::SupportInterface,
        Feature::Skirt,
        Feature::Brim,
        Feature::WipeTower,
        Feature::Custom,
    ];

    /// A short stable name (used in reports and the web preview).
    pub fn name(self) -> &'static str {
        match self {
            Feature::Unknown => "unknown",
            Feature::OuterWall => "outer-wall",
            Feature::InnerWall => "inner-wall",
            Feature::OverhangWall => "overhang-wall",
            Feature::Infill => "infill",
            Feature::SolidInfill => "solid-infill",
            Feature::TopSolidInfill => "top-solid-infill",
            Feature::BottomSolidInfill => "bottom-solid-infill",
            Feature::Bridge => "bridge",
            Feature::GapFill => "gap-fill",
            Feature::Ironing => "ironing",
            Feature::Support => "support",
            Feature::SupportInterface => "support-interface",
            Feature::Skirt => "skirt",
            Feature::Brim => "brim",
            Feature::WipeTower => "wipe-tower",
            Feature::Custom => "custom",
        }
    }
}

/// One point of the unwarped toolpath: the end of a straight segment from the previous point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToolPoint {
    /// Tool tip, output frame, mm.
    pub p: DVec3,
    /// Unit tool axis (tip → nozzle), output frame.
    pub n: DVec3,
    /// Filament pushed on the segment that ends here, mm (relative, ≥ 0 for extrusion,
    /// < 0 for a retraction).
    pub e: f64,
    /// Feed rate of the segment, mm/min (tool-tip speed, as the slicer programmed it).
    pub f: f64,
    /// The slicer's layer index (0-based). Non-planar layers share Z values: never group by Z.
    pub layer: u32,
    /// What the slicer said this segment is.
    pub feature: Feature,
    /// A non-extruding move (travel, lift, descent).
    pub travel: bool,
    /// The input G-code line (1-based, as an editor shows it) this point came from: the
    /// slicer's move, or the line being read when warpslice added the point (a lift, a
    /// descent, the end of the region); 0 when there is none (points built by hand).
    #[serde(default)]
    pub line: u64,
}

/// The decimation of a collected toolpath (`UnwarpOptions::toolpath_every`): of the points
/// seen in order, point i (0-based over the whole run) is kept when `i mod every = 0`, or when
/// its layer differs from the last kept point's, so a decimated preview still starts every
/// layer at its first point (the page's layer ranges stay exact). `every` 0 or 1 keeps all.
#[derive(Clone, Copy, Debug)]
pub struct Thinning {
    every: u64,
    seen: u64,
    last_layer: Option<u32>,
}

impl Thinning {
    /// Keep one point in `every` (0 and 1: every point).
    pub fn new(every: u32) -> Thinning {
        Thinning {
            every: u64::from(every.max(1)),
            seen: 0,
            last_layer: None,
        }
    }

    /// Whether the next point, on `layer`, is kept.
    pub fn keeps(&mut self, layer: u32) -> bool {
        let keep =
            self.seen.is_multiple_of(self.every) || self.last_layer.is_some_and(|l| l != layer);
        self.seen += 1;
        if keep {
            self.last_layer = Some(layer);
        }
        keep
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_features_are_listed_in_discriminant_order_with_unique_names() {
        let mut names = std::collections::HashSet::new();
        for (i, f) in Feature::ALL.iter().enumerate() {
            assert_eq!(*f as usize, i, "{f:?}");
            assert!(names.insert(f.name()), "{} twice", f.name());
        }
        // the last variant is the last of ALL: a variant added after it would be missing
        assert_eq!(Feature::Custom as usize + 1, Feature::ALL.len());
    }

    /// Against the rule said another way: point i is kept when i is a multiple of `every` or
    /// its layer is not the previous point's (the same thing, since the previous point's
    /// layer is always the last kept one's: a point on another layer is kept).
    #[test]
    fn thinning_keeps_every_nth_point_and_each_layers_first() {
        let mut rng = crate::test_rng::Lcg(0x2545_f491_4f6c_dd1d);
        for every in [0, 1, 2, 3, 7, 64] {
            let mut layer = 0u32;
            let layers: Vec<u32> = (0..5000)
                .map(|_| {
                    match (rng.unit() * 23.0) as u32 {
                        0 => layer += 1,
                        1 => layer = layer.saturating_sub(1), // a layer met again (a travel)
                        _ => {}
                    }
                    layer
                })
                .collect();
            let mut t = Thinning::new(every);
            let kept: Vec<usize> = (0..layers.len()).filter(|&i| t.keeps(layers[i])).collect();
            let n = every.max(1) as usize;
            let want: Vec<usize> = (0..layers.len())
                .filter(|&i| i % n == 0 || (i > 0 && layers[i] != layers[i - 1]))
                .collect();
            if let Some(i) = (0..kept.len().max(want.len())).find(|&i| kept.get(i) != want.get(i)) {
                panic!(
                    "every {every}: kept point {:?} where the rule keeps {:?} (the {i}th kept)",
                    kept.get(i),
                    want.get(i)
                );
            }
            if n > 1 {
                assert!(
                    kept.len() < layers.len() / 2 + layers.len() / 4,
                    "every {every}: {} of {}",
                    kept.len(),
                    layers.len()
                );
            }
        }
    }
}
