//! The built-in slicer one layer at a time: [`Slicing::step`] does one unit of work and says how
//! far it is, so a caller can show progress per layer and stop between layers (the web worker's
//! progress bar and Cancel); [`super::slice`] is the same steps run to the end.
//!
//! A mesh of n layers takes 2n steps: steps 1…n cut layer k = step − 1 ([`super::section`],
//! united by [`super::region::union_loops`]); steps n+1…2n write layer k = step − n − 1 (walls,
//! skins, which need the cuts of the layers above and below, infill, travel, G-code). The
//! placed mesh is dropped after the last cut. The bytes do not depend on how the steps are
//! driven: the state between steps is the whole state of the one-shot slicer.

use super::region::{self, offset, Region};
use super::{
    gcode_out, infill, layer_top, order, section, skins, travel, walls, Path, PlanarError, Role,
    Settings, SliceReport, Sliced,
};
use crate::mesh::Mesh;

/// How far a [`Slicing`] is: `done` of `total` steps (2 per layer: cut, then written).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Progress {
    /// Steps done.
    pub done: usize,
    /// Steps in all (twice the number of layers).
    pub total: usize,
    /// Layers of the mesh.
    pub layers: usize,
}

impl Progress {
    /// Whether every step is done ([`Slicing::finish`] returns the file at once).
    pub fn is_done(&self) -> bool {
        self.done >= self.total
    }
}

/// A slice in progress (see the module documentation).
pub struct Slicing {
    s: Settings,
    /// The mesh centred on `center`; `None` once every layer is cut.
    mesh: Option<Mesh>,
    /// The mesh's lowest point, mm.
    base: f64,
    /// Number of layers.
    layers: usize,
    /// The cross-sections cut so far, layer by layer.
    slices: Vec<Region>,
    /// Per cut layer: its top above the bed and its height, mm.
    heights: Vec<(f64, f64)>,
    /// Layers written so far.
    written: usize,
    writer: gcode_out::Writer,
    /// Where the nozzle is, for nearest-neighbour ordering.
    at: [f64; 2],
    report: SliceReport,
}

impl Slicing {
    /// Validate `settings`, centre `mesh` on `settings.center`, count its layers and write the
    /// start G-code (`header` in its first comment lines). A mesh too thin for one layer is
    /// [`PlanarError::NothingToPrint`].
    pub fn new(mesh: &Mesh, settings: &Settings, header: &str) -> Result<Slicing, PlanarError> {
        settings.validate()?;
        let s = *settings;
        let bbox = mesh.bbox();
        let centre = bbox.center();
        let shift = glam::DVec3::new(s.center[0] - centre.x, s.center[1] - centre.y, 0.0);
        let mut placed = mesh.clone();
        placed.translate(shift);
        let bbox = placed.bbox();
        let (base, top) = (bbox.min.z, bbox.max.z);
        // layer k is cut at mid-height, base + z_k − h_k/2; the layers are those cut below the top
        let layers = (0..)
            .take_while(|&k| base + layer_top(&s, k) - layer_height(&s, k) / 2.0 < top)
            .count();
        if layers == 0 {
            return Err(PlanarError::NothingToPrint { layers: 0 });
        }
        let settings_json = serde_json::to_string(&s).unwrap_or_default();
        // not "; warpslice …": that prefix marks the lines the unwarp and the machine output
        // add, which readers of the unwarped file (and the matrix's check e) set apart from the
        // input's
        let writer = gcode_out::Writer::new(
            &s,
            &format!("{header}\nbuilt-in planar slicer of warpslice, settings: {settings_json}"),
        );
        Ok(Slicing {
            s,
            mesh: Some(placed),
            base,
            layers,
            slices: Vec::with_capacity(layers),
            heights: Vec::with_capacity(layers),
            written: 0,
            writer,
            at: [bbox.min.x, bbox.min.y],
            report: SliceReport {
                shift: [shift.x, shift.y],
                ..SliceReport::default()
            },
        })
    }

    /// How far it is.
    pub fn progress(&self) -> Progress {
        Progress {
            done: self.slices.len() + self.written,
            total: 2 * self.layers,
            layers: self.layers,
        }
    }

    /// Do the next step (nothing once all are done). After the last cut, a mesh with nothing
    /// to print in any layer is [`PlanarError::NothingToPrint`].
    pub fn step(&mut self) -> Result<Progress, PlanarError> {
        if self.slices.len() < self.layers {
            self.cut_next();
            if self.slices.len() == self.layers {
                self.mesh = None;
                if self.slices.iter().all(|r| r.is_empty()) {
                    return Err(PlanarError::NothingToPrint {
                        layers: self.layers,
                    });
                }
            }
        } else if self.written < self.layers {
            self.write_next();
        }
        Ok(self.progress())
    }

    /// Run the steps left and return the G-code and its report.
    pub fn finish(mut self) -> Result<Sliced, PlanarError> {
        while !self.step()?.is_done() {}
        let mut report = self.report;
        report.layers = self.layers;
        report.filament_mm = self.writer.filament_mm;
        report.volume_mm3 = self.writer.filament_mm * self.s.filament_area();
        report.retractions = self.writer.retractions;
        Ok(Sliced {
            gcode: self.writer.finish(),
            report,
        })
    }

    /// 1. The cross-section of the next layer.
    fn cut_next(&mut self) {
        let Some(mesh) = self.mesh.as_ref() else {
            return;
        };
        let (s, k) = (&self.s, self.slices.len());
        let (z, h) = (layer_top(s, k), layer_height(s, k));
        let sec = section::section(mesh, self.base + z - h / 2.0);
        self.report.repaired_loops += sec.repaired;
        self.report.dropped_chains += sec.dropped;
        let loops: Vec<region::Contour> = sec
            .loops
            .iter()
            .map(|l| region::simplify_closed(l, region::RESOLUTION))
            .collect();
        self.slices.push(region::union_loops(&loops));
        self.heights.push((z, h));
    }

    /// 2.–5. The next layer's walls, skins, infill and G-code.
    fn write_next(&mut self) {
        let (s, k) = (self.s, self.written);
        let slice = &self.slices[k];
        let (z, h) = self.heights[k];
        let sp = s.spacing(h);
        let walls = walls::walls(slice, s.perimeters, s.extrusion_width, sp);
        self.report.thin_walls += walls.thin.len();
        self.report.thin_wall_mm += walls.thin.iter().map(|t| t.length()).sum::<f64>();
        self.report.thin_unprinted += walls.thin_unprinted;
        let sk = skins::skins(
            &self.slices,
            &walls.inner,
            k,
            s.top_solid_layers,
            s.bottom_solid_layers,
            s.extrusion_width,
        );
        // the external perimeters' lines, which travels go round (avoid_crossing_perimeters)
        let lines: Vec<region::Contour> = if s.avoid_crossing_perimeters {
            offset(slice, -s.extrusion_width / 2.0)
                .into_iter()
                .flatten()
                .collect()
        } else {
            Vec::new()
        };
        let (w, at) = (&mut self.writer, &mut self.at);
        w.layer(z, h);
        let print = |w: &mut gcode_out::Writer, p: &Path, v: f64| {
            if let (Some(from), Some(&to)) = (w.position(), p.points.first()) {
                w.travel_via(&travel::route(&lines, from, to));
            }
            w.path(p, h, v);
        };
        let first = k == 0;
        let speed = |v: f64| if first { s.first_layer_speed } else { v };
        if first {
            for p in order::nearest_neighbour(first_layer_extras(slice, &s, h), at) {
                print(w, &p, speed(s.perimeter_speed));
            }
        }
        for group in perimeter_groups(&walls, h, s.external_perimeters_first) {
            for p in order::nearest_neighbour(group, at) {
                print(w, &p, speed(s.perimeter_speed));
            }
        }
        let angle = s.fill_angle + if k % 2 == 1 { 90.0 } else { 0.0 };
        let fills = [
            (Role::SolidInfill, &sk.solid, sp),
            (Role::TopSolidInfill, &sk.top, sp),
            (
                Role::InternalInfill,
                &sk.sparse,
                if s.fill_density > 0.0 {
                    sp / (s.fill_density / 100.0)
                } else {
                    0.0
                },
            ),
        ];
        // bridges first (PrusaSlicer prints them before the layer's other infill), at the
        // round thread's cross-section and spacing, in the layer's fill direction
        let bridge_section = s.bridge_area();
        let bridges: Vec<Path> = infill::rectilinear(&sk.bridge, angle, s.bridge_spacing())
            .into_iter()
            .map(|l| Path {
                role: Role::BridgeInfill,
                points: l.to_vec(),
                closed: false,
                section: vec![bridge_section; 2],
            })
            .collect();
        for p in order::nearest_neighbour(bridges, at) {
            print(w, &p, speed(s.bridge_speed));
        }
        for (role, region, pitch) in fills {
            let lines: Vec<Path> = infill::rectilinear(region, angle, pitch)
                .into_iter()
                .map(|l| Path {
                    role,
                    points: l.to_vec(),
                    closed: false,
                    section: Vec::new(),
                })
                .collect();
            for p in order::nearest_neighbour(lines, at) {
                print(w, &p, speed(s.infill_speed));
            }
        }
        self.written += 1;
    }
}

/// Height of layer `k`, mm: `first_layer_height` for the first, `layer_height` after.
fn layer_height(s: &Settings, k: usize) -> f64 {
    if k == 0 {
        s.first_layer_height
    } else {
        s.layer_height
    }
}

/// Perimeter loops in print order groups: inner ones first (innermost first) and the external
/// one last, or the reverse with `external_first`. The thin walls (of layer height `h`) go
/// with the external perimeters: they are the part's outer surface too.
fn perimeter_groups(walls: &walls::Walls, h: f64, external_first: bool) -> Vec<Vec<Path>> {
    let levels = walls
        .islands
        .iter()
        .map(Vec::len)
        .max()
        .unwrap_or(0)
        .max(usize::from(!walls.thin.is_empty()));
    let mut groups: Vec<Vec<Path>> = (0..levels)
        .map(|i| {
            let role = if i == 0 {
                Role::ExternalPerimeter
            } else {
                Role::Perimeter
            };
            walls
                .islands
                .iter()
                .filter_map(|isl| isl.get(i))
                .flatten()
                .map(|c| order::loop_path(role, c.clone()))
                .collect()
        })
        .collect();
    if let Some(external) = groups.first_mut() {
        external.extend(walls.thin.iter().map(|t| Path {
            role: Role::ExternalPerimeter,
            points: t.points.clone(),
            closed: t.closed,
            section: t.thickness.iter().map(|t| t * h).collect(),
        }));
    }
    if !external_first {
        groups.reverse();
    }
    groups
}

/// Brim loops (outward from the first layer, `brim_width` wide) and skirt loops
/// (`skirt_distance` beyond the first layer and brim), outer contours only.
fn first_layer_extras(first: &Region, s: &Settings, h: f64) -> Vec<Path> {
    let (wd, sp) = (s.extrusion_width, s.spacing(h));
    let mut paths = Vec::new();
    let brim_loops = (s.brim_width / sp).ceil() as usize;
    for j in 0..brim_loops {
        let ring = offset(first, wd / 2.0 + j as f64 * sp);
        paths.extend(
            ring.iter()
                .filter_map(|shape| shape.first())
                .map(|outer| order::loop_path(Role::Brim, outer.clone())),
        );
    }
    // the brim's outer edge, from the part's
    let brim_edge = match brim_loops {
        0 => 0.0,
        n => wd + (n - 1) as f64 * sp,
    };
    for j in 0..s.skirts as usize {
        let ring = offset(
            first,
            brim_edge + s.skirt_distance + wd / 2.0 + j as f64 * sp,
        );
        paths.extend(
            ring.iter()
                .filter_map(|shape| shape.first())
                .map(|outer| order::loop_path(Role::Skirt, outer.clone())),
        );
    }
    paths
}
