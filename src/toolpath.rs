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
}
