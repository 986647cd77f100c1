//! The built-in slicer's settings: one serde struct whose keys are PrusaSlicer's option names
//! (PrusaSlicer's `PrintConfig.cpp` names and units: mm, mm/s, °C, percent for `fill_density`),
//! with the defaults of a 0.4 mm nozzle / 1.75 mm PLA profile. Unknown keys are refused
//! (`deny_unknown_fields`), so a misspelt key never silently keeps its default.

use serde::{Deserialize, Serialize};

use super::PlanarError;

/// Every setting of the built-in slicer. Lengths mm, speeds mm/s, temperatures °C.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// Height of every layer after the first, mm.
    pub layer_height: f64,
    /// Height of the first layer, mm.
    pub first_layer_height: f64,
    /// Number of perimeters (walls) per layer, ≥ 0.
    pub perimeters: u32,
    /// Sparse infill density, percent (0–100; 100 is solid).
    pub fill_density: f64,
    /// Infill direction of even layers, degrees from +X (odd layers: +90°).
    pub fill_angle: f64,
    /// Solid layers under every top surface.
    pub top_solid_layers: u32,
    /// Solid layers over every bottom surface.
    pub bottom_solid_layers: u32,
    /// Extrusion width of every line, mm (PrusaSlicer's default 0.45 for a 0.4 mm nozzle).
    pub extrusion_width: f64,
    /// Nozzle diameter, mm (bounds the extrusion width).
    pub nozzle_diameter: f64,
    /// Filament diameter, mm.
    pub filament_diameter: f64,
    /// Number of skirt loops on the first layer (0: none).
    pub skirts: u32,
    /// Gap between the skirt and the part's first layer, mm.
    pub skirt_distance: f64,
    /// Width of the brim around the first layer, mm (0: none).
    pub brim_width: f64,
    /// Nozzle temperature, °C.
    pub temperature: f64,
    /// Bed temperature, °C (0: no bed heating command).
    pub bed_temperature: f64,
    /// Speed of perimeters, mm/s.
    pub perimeter_speed: f64,
    /// Speed of infill (sparse and solid), mm/s.
    pub infill_speed: f64,
    /// Speed of travel moves, mm/s.
    pub travel_speed: f64,
    /// Speed of every extrusion on the first layer, mm/s.
    pub first_layer_speed: f64,
    /// Filament pulled back before a travel longer than
    /// [`super::order::RETRACT_BEFORE_TRAVEL`], mm (0: no retraction).
    pub retract_length: f64,
    /// Speed of the retraction and of the push-back, mm/s.
    pub retract_speed: f64,
    /// Print the external perimeter before the inner ones (default: after).
    pub external_perimeters_first: bool,
    /// Where the centre of the mesh's XY bounding box goes on the bed, mm (PrusaSlicer's
    /// `--center`; the default is the centre of the 200 × 200 mm bed PrusaSlicer and Slic3r
    /// centre parts on, so the built-in slicer's G-code is placed like theirs and a machine's
    /// travel limits see the same part position).
    pub center: [f64; 2],
    /// Relative E (`M83`, default) or absolute E (`M82`, reset by `G92 E0` at every layer).
    pub use_relative_e_distances: bool,
    /// Travel round a hole or a notch of the part, along the external perimeter, instead of
    /// across it ([`super::travel`]; PrusaSlicer's key and default: off, as the retraction
    /// before every travel over 2 mm already keeps ooze off the gap).
    pub avoid_crossing_perimeters: bool,
    /// Bridge flow: the round thread of a bridge has the diameter `nozzle_diameter ·
    /// √bridge_flow_ratio` (PrusaSlicer 2.5's "thick bridges", its default; 1 = the nozzle's).
    pub bridge_flow_ratio: f64,
    /// Speed of bridge infill, mm/s.
    pub bridge_speed: f64,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            layer_height: 0.2,
            first_layer_height: 0.2,
            perimeters: 2,
            fill_density: 20.0,
            fill_angle: 45.0,
            top_solid_layers: 5,
            bottom_solid_layers: 4,
            extrusion_width: 0.45,
            nozzle_diameter: 0.4,
            filament_diameter: 1.75,
            skirts: 1,
            skirt_distance: 2.0,
            brim_width: 0.0,
            temperature: 215.0,
            bed_temperature: 60.0,
            perimeter_speed: 45.0,
            infill_speed: 80.0,
            travel_speed: 150.0,
            first_layer_speed: 20.0,
            retract_length: 0.8,
            retract_speed: 35.0,
            external_perimeters_first: false,
            center: [100.0, 100.0],
            use_relative_e_distances: true,
            avoid_crossing_perimeters: false,
            bridge_flow_ratio: 1.0,
            bridge_speed: 60.0,
        }
    }
}

/// Gap between adjacent bridge threads, mm (PrusaSlicer's `BRIDGE_EXTRA_SPACING`).
pub const BRIDGE_EXTRA_SPACING: f64 = 0.05;

/// Largest extrusion width accepted, as a multiple of the nozzle diameter: wider lines are not
/// squeezed out of the nozzle's flat face (PrusaSlicer warns above about 2×).
pub const MAX_WIDTH_PER_NOZZLE: f64 = 2.5;

/// Largest |x| or |y| of `center`, mm (no bed reaches 10 m; the same bound as `--place`,
/// [`crate::tolerance::MAX_PLACEMENT_MM`]).
pub const MAX_CENTER: f64 = crate::tolerance::MAX_PLACEMENT_MM;

impl Settings {
    /// The defaults with both layer heights `h` (a warp's layer height: `warpslice run` and
    /// the page start from these).
    pub fn for_layers(h: f64) -> Settings {
        Settings {
            layer_height: h,
            first_layer_height: h,
            ..Settings::default()
        }
    }

    /// Settings from a JSON object (keys left out keep their defaults). Unknown keys and
    /// wrong types are [`PlanarError::SettingsJson`] with serde's message; values out of range
    /// are [`PlanarError::Setting`].
    pub fn from_json(text: &str) -> Result<Settings, PlanarError> {
        let mut s = Settings::default();
        s.apply_json(text)?;
        Ok(s)
    }

    /// Overwrite the keys a JSON object names (`--slicer-settings FILE`); the others keep
    /// their values.
    pub fn apply_json(&mut self, text: &str) -> Result<(), PlanarError> {
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| PlanarError::SettingsJson {
                message: e.to_string(),
            })?;
        let serde_json::Value::Object(given) = value else {
            return Err(PlanarError::SettingsJson {
                message: "the settings must be a JSON object of key: value pairs".to_string(),
            });
        };
        self.merge(given, "")
    }

    /// Set one value from `key=value` text (`--set fill_density=100`): the value is read as
    /// JSON (a number, `true`/`false`), the key must be one of the struct's.
    pub fn set(&mut self, assignment: &str) -> Result<(), PlanarError> {
        let (key, value) = assignment
            .split_once('=')
            .ok_or_else(|| PlanarError::Setting {
                key: assignment.to_string(),
                value: String::new(),
                allowed: "key=value, e.g. fill_density=100",
            })?;
        let (key, value) = (key.trim(), value.trim());
        let parsed: serde_json::Value =
            serde_json::from_str(value).map_err(|_| PlanarError::Setting {
                key: key.to_string(),
                value: value.to_string(),
                allowed: "a number or true/false",
            })?;
        let mut given = serde_json::Map::new();
        given.insert(key.to_string(), parsed);
        self.merge(given, &format!("--set {assignment}: "))
    }

    /// Overwrite the `given` keys through serde (unknown keys and wrong types refused by
    /// `deny_unknown_fields`), then validate; `self` is unchanged on error.
    fn merge(
        &mut self,
        given: serde_json::Map<String, serde_json::Value>,
        context: &str,
    ) -> Result<(), PlanarError> {
        let Ok(serde_json::Value::Object(mut map)) = serde_json::to_value(*self) else {
            return Err(PlanarError::SettingsJson {
                message: "the settings could not be written as JSON".to_string(),
            });
        };
        map.extend(given);
        let s: Settings = serde_json::from_value(serde_json::Value::Object(map)).map_err(|e| {
            PlanarError::SettingsJson {
                message: format!("{context}{e}"),
            }
        })?;
        s.validate()?;
        *self = s;
        Ok(())
    }

    /// Check every value's range; the first one out of range is the error.
    pub fn validate(&self) -> Result<(), PlanarError> {
        let bad = |key: &str, value: f64, allowed: &'static str| PlanarError::Setting {
            key: key.to_string(),
            value: value.to_string(),
            allowed,
        };
        // (key, value, whether 0 is allowed)
        let bounded_below = [
            ("layer_height", self.layer_height, false),
            ("first_layer_height", self.first_layer_height, false),
            ("extrusion_width", self.extrusion_width, false),
            ("nozzle_diameter", self.nozzle_diameter, false),
            ("filament_diameter", self.filament_diameter, false),
            ("perimeter_speed", self.perimeter_speed, false),
            ("infill_speed", self.infill_speed, false),
            ("travel_speed", self.travel_speed, false),
            ("first_layer_speed", self.first_layer_speed, false),
            ("retract_speed", self.retract_speed, false),
            ("bridge_flow_ratio", self.bridge_flow_ratio, false),
            ("bridge_speed", self.bridge_speed, false),
            ("skirt_distance", self.skirt_distance, true),
            ("brim_width", self.brim_width, true),
            ("temperature", self.temperature, true),
            ("bed_temperature", self.bed_temperature, true),
            ("retract_length", self.retract_length, true),
        ];
        for (k, v, zero_ok) in bounded_below {
            if !v.is_finite() || v < 0.0 || (v == 0.0 && !zero_ok) {
                let allowed = if zero_ok {
                    "a number ≥ 0"
                } else {
                    "a positive number"
                };
                return Err(bad(k, v, allowed));
            }
        }
        if !(self.fill_density.is_finite() && (0.0..=100.0).contains(&self.fill_density)) {
            return Err(bad(
                "fill_density",
                self.fill_density,
                "a percentage from 0 to 100",
            ));
        }
        if let Some(c) = self
            .center
            .iter()
            .find(|c| !c.is_finite() || c.abs() > MAX_CENTER)
        {
            return Err(bad("center", *c, "two finite numbers within ±10000 mm"));
        }
        if !self.fill_angle.is_finite() {
            return Err(bad(
                "fill_angle",
                self.fill_angle,
                "a finite angle in degrees",
            ));
        }
        for (k, h) in [
            ("layer_height", self.layer_height),
            ("first_layer_height", self.first_layer_height),
        ] {
            if h > self.nozzle_diameter {
                return Err(bad(k, h, "at most the nozzle_diameter"));
            }
        }
        if self.extrusion_width < self.layer_height.max(self.first_layer_height)
            || self.extrusion_width > MAX_WIDTH_PER_NOZZLE * self.nozzle_diameter
        {
            return Err(bad(
                "extrusion_width",
                self.extrusion_width,
                "at least the layer height and at most 2.5 × nozzle_diameter",
            ));
        }
        Ok(())
    }

    /// Centre-to-centre distance of two adjacent lines, mm: PrusaSlicer's `Flow::spacing`,
    /// `s = w − h·(1 − π/4)`, so that lines of the cross-section
    /// [`Settings::line_area`] side by side fill the layer exactly (s·h = area).
    pub fn spacing(&self, h: f64) -> f64 {
        self.extrusion_width - h * (1.0 - std::f64::consts::FRAC_PI_4)
    }

    /// Cross-section of one extruded line of width w and height h, mm²: PrusaSlicer's model
    /// (`Flow::mm3_per_mm`), a rectangle with semicircular ends,
    /// `A = (w − h)·h + π·(h/2)²`.
    pub fn line_area(&self, h: f64) -> f64 {
        let w = self.extrusion_width;
        (w - h) * h + std::f64::consts::PI * (h / 2.0) * (h / 2.0)
    }

    /// Diameter of a bridge's round thread, mm: `nozzle_diameter · √bridge_flow_ratio`
    /// (PrusaSlicer 2.5 `Flow::bridging_flow` with thick bridges).
    pub fn bridge_diameter(&self) -> f64 {
        self.nozzle_diameter * self.bridge_flow_ratio.sqrt()
    }

    /// Cross-section of a bridge line, mm²: the round thread, `π·d_b²/4`.
    pub fn bridge_area(&self) -> f64 {
        let d = self.bridge_diameter();
        std::f64::consts::PI * d * d / 4.0
    }

    /// Centre-to-centre distance of bridge lines, mm: `d_b + 0.05` (PrusaSlicer's
    /// `BRIDGE_EXTRA_SPACING`: threads laid side by side over air do not merge).
    pub fn bridge_spacing(&self) -> f64 {
        self.bridge_diameter() + BRIDGE_EXTRA_SPACING
    }

    /// Filament cross-section, mm²: `π·d²/4`.
    pub fn filament_area(&self) -> f64 {
        std::f64::consts::PI * self.filament_diameter * self.filament_diameter / 4.0
    }
}
