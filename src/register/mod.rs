//! Registration: where did the slicer put the warped mesh?
//!
//! PrusaSlicer, Slic3r and CuraEngine all re-centre the model on their bed. Before unwarping,
//! warpslice finds the translation (dx, dy) from STL coordinates to G-code coordinates by
//! matching the bounding box of the object's extrusions to the warped mesh's bounding box
//! (`job.warped_bbox`): the centres are matched, and the residual is the largest half-difference
//! of the sizes (x, y) and the difference of the tops (z). Bead centres lie about half a line
//! width inside the mesh, so a good match has a residual of ~0.2 mm; the G-code of another
//! model — or of the unwarped model — is off by millimetres and refused
//! ([`MAX_REGISTRATION_RESIDUAL`]). z is not shifted: the warped STL is written with its lowest
//! point at z = 0 and every slicer puts it on the bed.
//!
//! **Which extrusions are the object's.** Skirt, brim, wipe tower and custom (purge)
//! extrusions are left out by their `;TYPE:` where the slicer writes it (PrusaSlicer,
//! CuraEngine). Slic3r writes none: there, on the first layer, an extrusion run (extruding moves
//! between two travels) whose bounding box holds every other run of that layer with a gap of at
//! least [`SKIRT_MIN_GAP`] is a skirt loop (repeatedly, for several loops). When the job has an
//! anchor, the whole first layer is the anchor's and is left out.
//!
//! **The warped region** runs from the first object extrusion to the last; the slicer's start
//! and end G-code (heating, homing, purge line, park) outside it passes through verbatim.
//! `;WARPSLICE_BEGIN` / `;WARPSLICE_END` lines override that rule.
//!
//! **Fine registration.** With the warped mesh at hand ([`Scanner::finish_with_mesh`]), the
//! bounding-box translation is the start of a fit of the printed walls to the mesh's
//! cross-sections ([`refine`]), accurate to a few hundredths of a millimetre and blind to
//! features the slicer did not print; its bead inset and RMS are reported ([`FitReport`]).
//!
//! This is pass 1 of the two-pass streaming unwarp; pass 2 is [`crate::unwarp`].

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::gcode::{Command, GcodeError, Line, ReadOptions, Reader, State};
use crate::job::Job;
use crate::mesh::{Aabb, Mesh};

pub mod clusters;
pub mod ending;
pub mod refine;
pub mod sample;

use crate::tolerance::MAX_REGISTRATION_RESIDUAL;
use sample::Sample;

/// Smallest gap between a skirt loop and everything else on the first layer, mm (Slic3r's
/// default skirt distance is 6 mm, PrusaSlicer's 2 mm; a brim touches the object and is not
/// found this way).
pub const SKIRT_MIN_GAP: f64 = 1.0;

/// Why registration failed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum RegisterError {
    /// The G-code has no object extrusions.
    NoExtrusions,
    /// The G-code's object does not match the warped mesh.
    Mismatch {
        /// Largest gap between the shifted G-code bbox and the mesh's (x, y sides; z top), mm.
        residual: f64,
        /// Size (x, y, z) of the G-code's object extrusions, mm.
        gcode_size: [f64; 3],
        /// Size (x, y, z) of the warped mesh (`job.warped_bbox`), mm.
        mesh_size: [f64; 3],
    },
    /// The G-code's object matches the warped mesh in X and Y but stops below its top, and the
    /// file looks cut short ([`ending`]): a truncated file, not another model.
    CutShort {
        /// Top of the G-code's object extrusions, mm.
        gcode_top: f64,
        /// Top of the warped mesh, mm.
        mesh_top: f64,
        /// What looks cut short.
        why: &'static str,
    },
    /// With an anchor, the slicer's first layer must be exactly the anchor's thickness.
    AnchorLayer {
        /// Z of the first extrusion: the slicer's first layer height, mm.
        first_layer_z: f64,
        /// The anchor's thickness from the job, mm.
        anchor: f64,
    },
    /// Without the warped mesh, the boxes cannot place the part: the slicer left part of the
    /// mesh unprinted along an axis (a feature thinner than a line), so the printed box is
    /// narrower than the mesh's by more than two bead insets and may sit anywhere in that slack.
    FeaturesDropped {
        /// "X" or "Y".
        axis: &'static str,
        /// Width of the object's extrusions along it, mm.
        printed: f64,
        /// Width of the warped mesh along it, mm.
        mesh: f64,
    },
    /// The object's extrusions are wider than the warped mesh: the G-code prints more than this
    /// model (two copies, a second model, or — in a file without feature labels — a wipe/prime
    /// tower or a brim that cannot be told from the part).
    MoreThanTheModel {
        /// Separate groups of object extrusions above the first layer ([`clusters`]).
        groups: usize,
        /// Whether the file labels its features (`;TYPE:` or `; FEATURE:`).
        typed: bool,
        /// Whether only the first layer is wider (a brim in an unlabelled file).
        first_layer_only: bool,
        /// Size (x, y) of the object's extrusions, mm.
        gcode_size: [f64; 2],
        /// Size (x, y) of the warped mesh, mm.
        mesh_size: [f64; 2],
    },
    /// The G-code cannot be read.
    Gcode(GcodeError),
    /// The fine registration cannot pin the placement (too little printed near the surface).
    Undetermined {
        /// Cut samples matched to a printed wall.
        matched: usize,
        /// Matches needed.
        needed: usize,
        /// Why.
        reason: &'static str,
    },
}

impl From<GcodeError> for RegisterError {
    fn from(e: GcodeError) -> Self {
        RegisterError::Gcode(e)
    }
}

impl std::fmt::Display for RegisterError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RegisterError::NoExtrusions => write!(
                f,
                "the G-code has no object extrusions: the slicer printed nothing of the model (is it thinner than a line width? \
                 then scale it up or enable thin walls), or this is not the G-code of the warped STL"
            ),
            RegisterError::Mismatch { residual, gcode_size, mesh_size } => write!(
                f,
                "this G-code does not match the warped model: its object is {:.2} × {:.2} × {:.2} mm but the warped mesh is \
                 {:.2} × {:.2} × {:.2} mm (residual {:.2} mm > {:.1} mm). Slice the warped STL written with this job (not the \
                 original model), or give the placement with --offset dx,dy",
                gcode_size[0], gcode_size[1], gcode_size[2], mesh_size[0], mesh_size[1], mesh_size[2], residual, MAX_REGISTRATION_RESIDUAL
            ),
            RegisterError::CutShort { gcode_top, mesh_top, why } => write!(
                f,
                "this G-code stops at z = {gcode_top:.2} mm but the warped mesh is {mesh_top:.2} mm tall, and the file looks cut short ({why}): export or copy the G-code again (a copy or download that did not finish?)"
            ),
            RegisterError::AnchorLayer { first_layer_z, anchor } => write!(
                f,
                "the slicer's first layer is at z = {first_layer_z:.3} mm but the warped STL's anchor is {anchor:.3} mm thick: \
                 set the first layer height to {anchor:.3} mm (or warp again with --layer-height {first_layer_z:.3}); \
                 if it is {anchor:.3} mm already, the slicer's Z offset is {:+.3} mm (PrusaSlicer: Printer Settings → General → Z offset): \
                 set it to 0 and lift the output with unwarp's --z-offset instead",
                first_layer_z - anchor
            ),
            RegisterError::FeaturesDropped { axis, printed, mesh } => write!(
                f,
                "the object's extrusions are {printed:.2} mm wide in {axis} but the warped mesh is {mesh:.2} mm: the slicer did not print {:.2} mm of it (a feature thinner than a line?), so the bounding boxes cannot place the part in {axis} (it may sit anywhere within {:.2} mm). Register against the warped STL written with this job (unwarp --stl WARPED.stl; the CLI uses the one beside the job by itself), or give the placement with --offset dx,dy",
                mesh - printed,
                (mesh - printed) - 2.0 * MAX_BOX_INSET,
            ),
            RegisterError::MoreThanTheModel { groups, typed, first_layer_only, gcode_size, mesh_size } => {
                let [gx, gy] = gcode_size;
                let [mx, my] = mesh_size;
                write!(f, "this G-code prints more than the warped model: its object is {gx:.2} × {gy:.2} mm but the warped mesh is {mx:.2} × {my:.2} mm")?;
                match (typed, first_layer_only, *groups) {
                    (true, _, n) if n >= 2 => write!(
                        f,
                        ": it prints {n} objects side by side (PrusaSlicer's --duplicate {n}, copies or other models on the plate). warpslice unwarps one object per file: slice the warped STL alone, one copy, and print copies as separate files"
                    ),
                    (true, _, _) => write!(
                        f,
                        ": slice the warped STL written with this job, alone"
                    ),
                    (false, true, _) => write!(
                        f,
                        " on its first layer only: a brim (the file has no feature labels — `;TYPE:` or `; FEATURE:` — to tell it from the part). Turn the brim off (the warped STL's anchor holds the part down) or export the G-code with feature labels"
                    ),
                    (false, false, n) => write!(
                        f,
                        ": it prints {n} separate things and has no feature labels (`;TYPE:` or `; FEATURE:`) to tell a wipe or prime tower, a brim or a second object from the part. Export the G-code with feature labels (PrusaSlicer, OrcaSlicer, Bambu Studio and Cura write them), or turn the tower and brim off and slice one object per file; --offset does not help: the extra extrusions would be bent as if they were the part"
                    ),
                }
            }
            RegisterError::Gcode(e) => e.fmt(f),
            RegisterError::Undetermined { matched, needed, reason } => write!(
                f,
                "the placement cannot be found to the bead from the printed walls: {reason} ({matched} matches, {needed} needed). Slice the warped STL of this job with its outer walls printed, or give the placement with --offset dx,dy"
            ),
        }
    }
}

impl std::error::Error for RegisterError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RegisterError::Gcode(e) => Some(e),
            _ => None,
        }
    }
}

crate::error_codes!(RegisterError, ERROR_CODES, "register" {
    NoExtrusions => "register.no-object-extrusions", "the G-code prints nothing of the model";
    Mismatch => "register.mismatch", "the G-code's object does not match the warped mesh";
    CutShort => "register.cut-short", "the G-code stops below the mesh's top and looks cut short";
    AnchorLayer => "register.anchor-layer", "the first layer height is not the anchor's thickness";
    Undetermined => "register.undetermined", "the printed walls do not pin the placement";
    FeaturesDropped => "register.features-dropped", "without the warped mesh, a feature the slicer did not print leaves the placement open";
    MoreThanTheModel => "register.more-than-the-model", "the G-code prints more than the model: copies, another object, or an unlabelled tower or brim";
} wraps { Gcode });

/// A run of consecutive extruding moves on the first layer (Slic3r skirt detection).
#[derive(Clone, Debug)]
struct Run {
    first_line: u64,
    last_line: u64,
    bbox: Aabb,
}

/// Pass 1 result: the translation and what pass 2 needs to know about the file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Registration {
    /// STL → G-code translation (dx, dy, 0), mm.
    pub translation: [f64; 3],
    /// Residual of the bounding-box match, mm.
    pub residual: f64,
    /// Whether the translation was given (`--offset`) rather than found.
    pub overridden: bool,
    /// Bounding box of the object's extrusions in G-code coordinates.
    pub gcode_bbox: Aabb,
    /// Bounding box of everything extruded from the region's start on (skirt, brim, a wipe or
    /// prime tower too), G-code coordinates: what a travel may meet.
    #[serde(default)]
    pub printed_bbox: Aabb,
    /// First and last line of the warped region (1-based, inclusive).
    pub region: [u64; 2],
    /// Line ranges (inclusive) of first-layer runs found to be skirt by geometry (files
    /// without `;TYPE:`).
    pub skirt_runs: Vec<[u64; 2]>,
    /// Whether the file carries `;TYPE:` comments.
    pub typed: bool,
    /// z of the first extrusion of the first layer, mm (G-code frame).
    pub first_layer_z: f64,
    /// The slicer's index of the first layer with an object extrusion (the anchor layer when
    /// the job has an anchor).
    pub first_layer: u32,
    /// Lines in the file.
    pub lines: u64,
    /// The fine registration, when the warped mesh was given.
    #[serde(default)]
    pub fit: Option<FitReport>,
    /// The file's last line had no line end: its number (a file cut short).
    #[serde(default)]
    pub unterminated_line: Option<u64>,
    /// No line after the region ends the print (heaters off, motors off, an end macro: see
    /// [`ending`]): the end G-code is missing, or the file was cut short.
    #[serde(default)]
    pub end_gcode_missing: bool,
    /// Object extrusions outside the `;WARPSLICE_BEGIN` / `;WARPSLICE_END` region: their count
    /// and the first one's line (`None`: none, or no markers).
    #[serde(default)]
    pub outside_markers: Option<[u64; 2]>,
}

/// What the fine registration found ([`refine`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    /// How far the printed outer walls sit inside the surface, mm (≈ half a line width).
    pub bead_inset_mm: f64,
    /// RMS of the walls' offsets from that inset, mm.
    pub rms_mm: f64,
    /// Cut samples matched to a printed wall.
    pub matched: usize,
    /// Layers used.
    pub layers: usize,
    /// How far the fit moved the bounding-box placement, mm.
    pub moved_mm: f64,
}

impl Registration {
    /// Whether source line `line` belongs to a skirt run found by geometry.
    pub fn in_skirt_run(&self, line: u64) -> bool {
        // runs are few (one per skirt loop); a linear scan is fine
        self.skirt_runs.iter().any(|r| r[0] <= line && line <= r[1])
    }
}

/// Extrusions gathered in pass 1 for one reading of the file (typed or untyped).
#[derive(Default)]
struct Acc {
    /// First extrusion line of any non-custom feature (start of the region).
    first_any: Option<u64>,
    /// First and last object-extrusion lines.
    first_obj: Option<u64>,
    last_obj: Option<u64>,
    /// Object extrusions above the first layer.
    bbox_upper: Aabb,
    /// Their footprints grouped into separate things ([`clusters`]).
    groups_upper: clusters::Clusters,
    /// Every extrusion counted (skirt, brim, wipe tower too; not the start G-code's purge).
    bbox_any: Aabb,
    /// Object extrusion runs on the first layer.
    runs0: Vec<Run>,
    in_run: bool,
    /// Object extrusions before any `;WARPSLICE_BEGIN` and after a `;WARPSLICE_END`: count
    /// and first line.
    before_begin: (u64, Option<u64>),
    after_end: (u64, Option<u64>),
    first_layer: Option<u32>,
    first_layer_z: Option<f64>,
}

impl Acc {
    /// An extrusion at `line`; `markers`: the `;WARPSLICE_BEGIN` / `_END` lines seen so far.
    fn extrusion(&mut self, line: u64, m: &crate::gcode::Move, markers: [Option<u64>; 2]) {
        if m.feature == crate::toolpath::Feature::Custom {
            self.in_run = false;
            return;
        }
        if self.first_any.is_none() {
            self.first_any = Some(line);
        }
        self.bbox_any.include(m.from);
        self.bbox_any.include(m.to);
        if !m.feature.is_object() {
            self.in_run = false;
            return;
        }
        if self.first_obj.is_none() {
            self.first_obj = Some(line);
        }
        let outside = match markers {
            [None, _] => Some(&mut self.before_begin),
            [_, Some(_)] => Some(&mut self.after_end),
            _ => None,
        };
        if let Some((n, first)) = outside {
            *n += 1;
            first.get_or_insert(line);
        }
        self.last_obj = Some(line);
        let first_layer = *self.first_layer.get_or_insert(m.layer);
        if self.first_layer_z.is_none() {
            self.first_layer_z = Some(m.to.z);
        }
        if m.layer == first_layer {
            if !self.in_run {
                self.runs0.push(Run {
                    first_line: line,
                    last_line: line,
                    bbox: Aabb::EMPTY,
                });
                self.in_run = true;
            }
            if let Some(r) = self.runs0.last_mut() {
                r.last_line = line;
                r.bbox.include(m.from);
                r.bbox.include(m.to);
            }
        } else {
            self.in_run = false;
            self.bbox_upper.include(m.from);
            self.bbox_upper.include(m.to);
            self.groups_upper.add(m.from.truncate(), m.to.truncate());
        }
    }
}

/// Pass 1: push the G-code in chunks, then [`Scanner::finish`].
///
/// In a file with `;TYPE:` comments, extrusions before the first of them (a purge line in the
/// start G-code) are not the object's: two readings are gathered side by side, untyped (every
/// extrusion) and typed (after the first `;TYPE:`), and `finish` keeps the one that applies.
pub struct Scanner {
    reader: Reader,
    anchor: bool,
    typed: bool,
    markers: [Option<u64>; 2],
    untyped: Acc,
    typed_acc: Acc,
    lines: u64,
    /// Object extrusions by layer, for the fine registration.
    sample: Sample,
    /// The first `;TYPE:` line.
    first_typed: Option<u64>,
    /// The last line that ends the print ([`ending::ends_print`]).
    last_end: Option<u64>,
}

impl Scanner {
    /// A pass-1 scanner for the G-code of `job`'s warped STL.
    pub fn new(job: &Job) -> Scanner {
        Scanner {
            reader: Reader::new(ReadOptions::default()),
            anchor: job.anchor.is_some(),
            typed: false,
            markers: [None, None],
            untyped: Acc::default(),
            typed_acc: Acc::default(),
            lines: 0,
            sample: Sample::new(),
            first_typed: None,
            last_end: None,
        }
    }

    fn line(&mut self, line: &Line<'_>, _state: &State) {
        self.lines = line.number;
        match line.command {
            Command::FeatureType(_) => {
                self.typed = true;
                self.first_typed.get_or_insert(line.number);
            }
            Command::RegionMarker { begin } => {
                let slot = if begin { 0 } else { 1 };
                if self.markers[slot].is_none() {
                    self.markers[slot] = Some(line.number);
                }
            }
            Command::Other if ending::ends_print(line.raw) => self.last_end = Some(line.number),
            _ => {}
        }
        for m in line.moves {
            if m.is_extrusion() {
                if m.feature.is_object() {
                    self.sample.push(
                        m.layer,
                        m.to.z,
                        m.from.truncate(),
                        m.to.truncate(),
                        line.number,
                    );
                }
                self.untyped.extrusion(line.number, m, self.markers);
                if self.typed {
                    self.typed_acc.extrusion(line.number, m, self.markers);
                }
            } else if m.from.truncate() != m.to.truncate() {
                self.untyped.in_run = false;
                self.typed_acc.in_run = false;
            }
        }
    }

    /// Feed a chunk of G-code.
    pub fn push(&mut self, chunk: &[u8]) -> Result<(), RegisterError> {
        let mut reader = std::mem::replace(&mut self.reader, Reader::new(ReadOptions::default()));
        let r = reader.push::<RegisterError>(chunk, &mut |l, s| {
            self.line(&l, s);
            Ok(())
        });
        self.reader = reader;
        r
    }

    /// End of pass 1: classify the first layer, match bounding boxes, check the residual.
    pub fn finish(
        self,
        job: &Job,
        offset: Option<[f64; 2]>,
    ) -> Result<Registration, RegisterError> {
        self.finish_with_mesh(job, offset, None)
    }

    /// [`Scanner::finish`], then (without `offset`, with the warped `mesh` of this job) the
    /// fine registration ([`refine`]).
    pub fn finish_with_mesh(
        mut self,
        job: &Job,
        offset: Option<[f64; 2]>,
        mesh: Option<&Mesh>,
    ) -> Result<Registration, RegisterError> {
        let mut reader = std::mem::replace(&mut self.reader, Reader::new(ReadOptions::default()));
        reader.finish::<RegisterError>(&mut |l, s| {
            self.line(&l, s);
            Ok(())
        })?;
        let unterminated_line = reader.unterminated_line();
        let acc = if self.typed {
            &self.typed_acc
        } else {
            &self.untyped
        };
        let (Some(first), Some(last)) = (acc.first_any, acc.last_obj) else {
            return Err(RegisterError::NoExtrusions);
        };
        let region = [
            self.markers[0].unwrap_or(first),
            self.markers[1].unwrap_or(last),
        ];
        let first_layer_z = acc.first_layer_z.unwrap_or(0.0);
        if let Some(a) = job.anchor {
            if (first_layer_z - a).abs() > ANCHOR_LAYER_TOLERANCE {
                return Err(RegisterError::AnchorLayer {
                    first_layer_z,
                    anchor: a,
                });
            }
        }
        let skirt = if self.typed {
            Vec::new()
        } else {
            skirt_runs(&acc.runs0)
        };
        let mut bbox = acc.bbox_upper;
        if !self.anchor {
            for r in &acc.runs0 {
                if !skirt.iter().any(|s| s[0] == r.first_line) {
                    bbox.include(r.bbox.min);
                    bbox.include(r.bbox.max);
                }
            }
        }
        if bbox.is_empty() {
            return Err(RegisterError::NoExtrusions);
        }
        let mesh_bbox = job.warped_bbox;
        if offset.is_none() {
            more_than_the_model(acc, bbox, mesh_bbox, self.typed)?;
        }
        let (mut dx, mut dy) = match offset {
            Some([x, y]) => (x, y),
            None => {
                let (gc, mc) = (bbox.center(), mesh_bbox.center());
                (gc.x - mc.x, gc.y - mc.y)
            }
        };
        let mut fit = None;
        if let (None, Some(mesh)) = (offset, mesh) {
            let first = if self.typed {
                self.first_typed.unwrap_or(0)
            } else {
                0
            };
            self.sample.retain_lines(first, &skirt);
            // the box's centres matched, or its sides (a feature the slicer did not print
            // shrinks the printed box on one side)
            let inset = 0.2;
            let g = bbox;
            let m = mesh_bbox;
            let xs = [dx, g.min.x - m.min.x - inset, g.max.x - m.max.x + inset];
            let ys = [dy, g.min.y - m.min.y - inset, g.max.y - m.max.y + inset];
            let starts: Vec<[f64; 2]> = xs
                .iter()
                .flat_map(|&x| ys.iter().map(move |&y| [x, y]))
                .collect();
            let f = refine::refine(mesh, &self.sample, job.layer_height, &starts)?;
            let moved = (f.translation[0] - dx).hypot(f.translation[1] - dy);
            [dx, dy] = f.translation;
            fit = Some(FitReport {
                bead_inset_mm: f.inset,
                rms_mm: f.rms,
                matched: f.matched,
                layers: f.layers,
                moved_mm: moved,
            });
        }
        let mesh = mesh_bbox;
        let (gs, ms) = (bbox.size(), mesh.size());
        let shifted_min = bbox.min - DVec3::new(dx, dy, 0.0);
        let shifted_max = bbox.max - DVec3::new(dx, dy, 0.0);
        let residual = [
            (shifted_min.x - mesh.min.x).abs(),
            (shifted_max.x - mesh.max.x).abs(),
            (shifted_min.y - mesh.min.y).abs(),
            (shifted_max.y - mesh.max.y).abs(),
            (bbox.max.z - mesh.max.z).abs(),
        ]
        .into_iter()
        .fold(0.0, f64::max);
        // with a fit, the walls matched the mesh (a box that differs is a feature the slicer
        // did not print); without one, the boxes must agree
        let end_gcode_missing = self.last_end.is_none_or(|l| l <= region[1]);
        if offset.is_none() && fit.is_none() && residual > MAX_REGISTRATION_RESIDUAL {
            // the sides agree and the top is low in a file that looks cut short: say so
            let xy = [
                (shifted_min.x - mesh.min.x).abs(),
                (shifted_max.x - mesh.max.x).abs(),
                (shifted_min.y - mesh.min.y).abs(),
                (shifted_max.y - mesh.max.y).abs(),
            ]
            .into_iter()
            .fold(0.0, f64::max);
            let why = if unterminated_line.is_some() {
                Some("its last line has no line end")
            } else if end_gcode_missing {
                Some("nothing after its last layer ends the print")
            } else {
                None
            };
            if let (true, Some(why)) = (
                xy <= MAX_REGISTRATION_RESIDUAL && bbox.max.z < mesh.max.z,
                why,
            ) {
                return Err(RegisterError::CutShort {
                    gcode_top: bbox.max.z,
                    mesh_top: mesh.max.z,
                    why,
                });
            }
            return Err(RegisterError::Mismatch {
                residual,
                gcode_size: gs.to_array(),
                mesh_size: ms.to_array(),
            });
        }
        // without the mesh the box's centre is the placement: it holds when the slicer printed
        // the mesh's whole width, inset by a bead on each side
        if offset.is_none() && fit.is_none() {
            for (axis, printed, mesh) in [("X", gs.x, ms.x), ("Y", gs.y, ms.y)] {
                if mesh - printed > 2.0 * MAX_BOX_INSET {
                    return Err(RegisterError::FeaturesDropped {
                        axis,
                        printed,
                        mesh,
                    });
                }
            }
        }
        Ok(Registration {
            translation: [dx, dy, 0.0],
            residual,
            overridden: offset.is_some(),
            gcode_bbox: bbox,
            printed_bbox: acc.bbox_any,
            region,
            skirt_runs: skirt,
            typed: self.typed,
            first_layer_z,
            first_layer: acc.first_layer.unwrap_or(0),
            lines: self.lines,
            fit,
            unterminated_line,
            end_gcode_missing,
            outside_markers: outside_markers(acc, self.markers),
        })
    }
}

/// The object extrusions `acc` found outside the region its `markers` set: (count, first line).
fn outside_markers(acc: &Acc, markers: [Option<u64>; 2]) -> Option<[u64; 2]> {
    let before = if markers[0].is_some() {
        acc.before_begin
    } else {
        (0, None)
    };
    let (after, first_after) = acc.after_end;
    let first = before.1.or(first_after)?;
    Some([before.0 + after, first])
}

/// How much wider than the warped mesh (x or y) the object's extrusions may be before the
/// G-code is taken to print more than the model, mm: twice [`MAX_REGISTRATION_RESIDUAL`], the
/// box match's own bound (the printed box is normally a bead narrower than the mesh's on each
/// side; copies, towers and brims add millimetres).
pub const MAX_EXTRA_WIDTH: f64 = 2.0 * MAX_REGISTRATION_RESIDUAL;

/// [`RegisterError::MoreThanTheModel`] when the object's box `bbox` is wider than the mesh's by
/// more than [`MAX_EXTRA_WIDTH`] and the extra is something beside the part: two or more
/// separate groups (copies, a tower), or in an unlabelled file a first layer wider than the
/// rest (a brim). One wider thing on every layer is another model ([`RegisterError::Mismatch`]).
fn more_than_the_model(
    acc: &Acc,
    bbox: Aabb,
    mesh: Aabb,
    typed: bool,
) -> Result<(), RegisterError> {
    let wider = |b: Aabb| {
        let (g, m) = (b.size(), mesh.size());
        g.x > m.x + MAX_EXTRA_WIDTH || g.y > m.y + MAX_EXTRA_WIDTH
    };
    if !wider(bbox) {
        return Ok(());
    }
    let groups = acc.groups_upper.count();
    let first_layer_only = !typed && !acc.bbox_upper.is_empty() && !wider(acc.bbox_upper);
    // one wider thing on every layer is another model: the box match names it
    if groups < 2 && !first_layer_only {
        return Ok(());
    }
    let (g, m) = (bbox.size(), mesh.size());
    Err(RegisterError::MoreThanTheModel {
        groups,
        typed,
        first_layer_only,
        gcode_size: [g.x, g.y],
        mesh_size: [m.x, m.y],
    })
}

/// Registration by boxes (no warped mesh): how far inside the mesh's side the object's
/// printed box may end, mm — half the widest line the slicers use with a 0.4 mm nozzle
/// (PrusaSlicer's 0.45 mm external perimeter, Slic3r's ≈ 0.48 mm) and 0.1 mm of room. A printed
/// box narrower than the mesh's by more than twice this left a feature unprinted: its centre is
/// not the mesh's ([`RegisterError::FeaturesDropped`]).
pub const MAX_BOX_INSET: f64 = 0.35;

/// How far the slicer's first layer z may be from the anchor thickness, mm.
pub const ANCHOR_LAYER_TOLERANCE: f64 = 0.02;

/// Slic3r skirt detection: repeatedly take the run whose bbox holds all other remaining runs
/// with a gap ≥ [`SKIRT_MIN_GAP`].
fn skirt_runs(runs: &[Run]) -> Vec<[u64; 2]> {
    let mut remaining: Vec<&Run> = runs.iter().collect();
    let mut skirts = Vec::new();
    loop {
        if remaining.len() < 2 {
            break;
        }
        let found = remaining.iter().position(|r| {
            remaining.iter().all(|o| {
                std::ptr::eq(*o, *r)
                    || (o.bbox.min.x - r.bbox.min.x >= SKIRT_MIN_GAP
                        && o.bbox.min.y - r.bbox.min.y >= SKIRT_MIN_GAP
                        && r.bbox.max.x - o.bbox.max.x >= SKIRT_MIN_GAP
                        && r.bbox.max.y - o.bbox.max.y >= SKIRT_MIN_GAP)
            })
        });
        match found {
            Some(i) => {
                let r = remaining.remove(i);
                skirts.push([r.first_line, r.last_line]);
            }
            None => break,
        }
    }
    skirts
}
