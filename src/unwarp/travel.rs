//! Travel moves: never map a travel's straight line point by point into the part.
//!
//! Seed 000 §4.3.1 (2): retract (if the slicer did not), lift to a safe height, move, descend,
//! unretract. The safe height is the highest point printed so far within reach of the straight
//! path plus a clearance, read from a coarse height grid of everything printed so far
//! ([`HeightGrid`]). A travel whose straight line already clears the grid by the clearance
//! (cells within [`NEAR_END_RADIUS`] of its ends excepted: that is where the nozzle just
//! printed or is about to print) goes straight.
//!
//! ## The whole head (issue 10 §2)
//! On a machine the emitter gives the head's clearance profile
//! ([`crate::emit::clearance::HeadProfile`]): a lifted travel then climbs to the higher of the
//! tip's height (printed top + clearance) and the height at which the head's profile, tilted as
//! far as either end's tool axis, clears every printed cell within its reach of the path by
//! [`HEAD_CLEARANCE_MM`] ([`HeightGrid::head_clear_z`]). The tool axis turns from the start's
//! to the end's during the move at that height (the lift and the descent keep their end's
//! pose). The bound assumes the tilt along the move stays within the ends' tilts (the B head,
//! RTN and PAX interpolate the tilt axis linearly). A travel that turns the tool axis by more
//! than [`TURN_IN_AIR_DEG`] goes straight only where the head clears at its height; any other
//! straight travel is judged by the tip's rule alone (the head's profile is conservative: a
//! tilted head at rest beside higher material already fails it, so it would lift them all).

use glam::{DVec2, DVec3};

use crate::emit::clearance::{segment_distance, HeadProfile, Printed, HEAD_CLEARANCE_MM};

/// Cell size of the height grid, mm.
pub const CELL: f64 = 1.0;
/// Cells closer than this to a travel's start or end are not obstacles (the nozzle's own
/// neighbourhood), mm.
pub const NEAR_END_RADIUS: f64 = 1.5;
/// Grid margin around everything printed (the part, a skirt, brim or wipe tower), mm.
pub const MARGIN: f64 = 20.0;
/// A straight travel may pass this little below the top of printed material, mm: the grid
/// holds nozzle-tip heights (bead tops), and a planar printer's travels graze the layer just
/// printed all the time.
pub const DIRECT_TRAVEL_SLACK: f64 = 0.05;

/// Cells a side of a [`HeightGrid`] block: the grid keeps each block's highest cell, so a
/// lift's head clearance skips whole blocks that cannot raise it ([`HeightGrid::head_clear_z`]).
pub const BLOCK: usize = 8;

/// How far below the height found so far a block's bound must be for the block to be skipped,
/// and how much nearer than its lower bound a block's distance is taken, mm: it covers the
/// rounding of the bound's own arithmetic (distances and the profile's floor of a few tens of
/// mm, a few ulps ≈ 1e-14 mm), so a skipped cell cannot change the result even in its last
/// bit.
pub const BLOCK_SKIP_SLACK_MM: f64 = 1e-9;

/// The highest printed z per XY cell (output frame).
#[derive(Clone, Debug)]
pub struct HeightGrid {
    origin: DVec2,
    nx: usize,
    ny: usize,
    h: Vec<f64>,
    /// The highest cell of each [`BLOCK`] × [`BLOCK`] block (row-major, `nx.div_ceil(BLOCK)`
    /// blocks a row).
    blocks: Vec<f64>,
}

impl HeightGrid {
    /// A grid over [min, max] (XY, output frame: the box of everything the region prints)
    /// plus [`MARGIN`]; at most 4096 cells a side (4 m at [`CELL`]).
    pub fn new(min: DVec2, max: DVec2) -> HeightGrid {
        let origin = min - DVec2::splat(MARGIN);
        let size = (max - min) + DVec2::splat(2.0 * MARGIN);
        let nx = ((size.x / CELL).ceil() as usize).clamp(1, 4096);
        let ny = ((size.y / CELL).ceil() as usize).clamp(1, 4096);
        HeightGrid {
            origin,
            nx,
            ny,
            h: vec![f64::NEG_INFINITY; nx * ny],
            blocks: vec![f64::NEG_INFINITY; nx.div_ceil(BLOCK) * ny.div_ceil(BLOCK)],
        }
    }

    fn cell_ij(&self, p: DVec2) -> Option<(usize, usize)> {
        let c = (p - self.origin) / CELL;
        if c.x < 0.0 || c.y < 0.0 {
            return None;
        }
        let (i, j) = (c.x as usize, c.y as usize);
        (i < self.nx && j < self.ny).then_some((i, j))
    }

    fn cell(&self, p: DVec2) -> Option<usize> {
        self.cell_ij(p).map(|(i, j)| j * self.nx + i)
    }

    /// Record a printed point.
    pub fn mark(&mut self, p: DVec3) {
        if let Some((i, j)) = self.cell_ij(p.truncate()) {
            let k = j * self.nx + i;
            if p.z > self.h[k] {
                self.h[k] = p.z;
                let b = (j / BLOCK) * self.nx.div_ceil(BLOCK) + i / BLOCK;
                if p.z > self.blocks[b] {
                    self.blocks[b] = p.z;
                }
            }
        }
    }

    /// Record a printed segment (sampled at half a cell).
    pub fn mark_segment(&mut self, a: DVec3, b: DVec3) {
        let n = (((b - a).truncate().length() / (0.5 * CELL)).ceil() as usize).max(1);
        for k in 0..=n {
            self.mark(a.lerp(b, k as f64 / n as f64));
        }
    }

    /// The highest obstacle above the straight line a → b (how far the grid reaches above
    /// the line, mm; ≤ 0 when clear), cells near the ends excepted; and the highest cell along
    /// the XY path, near ends included.
    pub fn clearance_needed(&self, a: DVec3, b: DVec3) -> (f64, f64) {
        let len = (b - a).truncate().length();
        let n = ((len / (0.5 * CELL)).ceil() as usize).max(1);
        let mut above = f64::NEG_INFINITY;
        let mut top = f64::NEG_INFINITY;
        for k in 0..=n {
            let t = k as f64 / n as f64;
            let p = a.lerp(b, t);
            // the cell and its 8 neighbours: the nozzle is wider than a point
            for dj in -1i32..=1 {
                for di in -1i32..=1 {
                    let q = p.truncate() + DVec2::new(di as f64, dj as f64) * CELL;
                    if let Some(c) = self.cell(q) {
                        let h = self.h[c];
                        top = top.max(h);
                        let near = (q - a.truncate()).length() < NEAR_END_RADIUS
                            || (q - b.truncate()).length() < NEAR_END_RADIUS;
                        if !near {
                            above = above.max(h - p.z);
                        }
                    }
                }
            }
        }
        (above, top)
    }
}

/// How to travel from `a` to `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TravelPlan {
    /// Straight line.
    Direct,
    /// Lift to z, move, descend.
    Lift(f64),
}

/// A travel whose tool axis turns by more than this between its ends turns in the air (lift,
/// turn, descend) unless the whole head clears the printed material at the travel's own height,
/// degrees: the B head's large B changes, an RTN or PAX head swinging to the other side of a
/// cone. A smaller turn (neighbouring points of a curved layer) is judged by the tip's rule.
pub const TURN_IN_AIR_DEG: f64 = 10.0;

/// The head a travel must clear: its profile, the largest tilt of the tool axis along the travel
/// (radians from +Z) and the angle between the tool axes at its ends (radians).
#[derive(Clone, Copy, Debug)]
pub struct HeadClearance<'a> {
    /// The head's profile.
    pub profile: &'a HeadProfile,
    /// The largest tilt along the travel.
    pub tilt: f64,
    /// The angle the tool axis turns by.
    pub turn: f64,
}

/// Plan a travel with `clearance` (mm) above the printed top for the tip, and with the whole
/// head clearing printed material by [`HEAD_CLEARANCE_MM`] when `head` is given (see the module
/// documentation): a travel goes straight when the tip's rule lets it and, if it turns the tool
/// axis by more than [`TURN_IN_AIR_DEG`], the head clears at the lower of its ends' heights;
/// otherwise it lifts to the higher of the tip's height and the head's.
pub fn plan(
    grid: &HeightGrid,
    a: DVec3,
    b: DVec3,
    clearance: f64,
    head: Option<HeadClearance<'_>>,
) -> TravelPlan {
    let (above, top) = grid.clearance_needed(a, b);
    let head_z = |h: &HeadClearance<'_>| {
        grid.head_clear_z(h.profile, a.truncate(), b.truncate(), 0.0, h.tilt) + HEAD_CLEARANCE_MM
    };
    let tip = top.max(a.z).max(b.z) + clearance;
    match head {
        None if above <= DIRECT_TRAVEL_SLACK => TravelPlan::Direct,
        None => TravelPlan::Lift(tip),
        Some(h) => {
            let turns = h.turn > crate::num::rad(TURN_IN_AIR_DEG);
            if above <= DIRECT_TRAVEL_SLACK && !turns {
                return TravelPlan::Direct;
            }
            let z = head_z(&h);
            if above <= DIRECT_TRAVEL_SLACK && z <= a.z.min(b.z) {
                TravelPlan::Direct
            } else {
                TravelPlan::Lift(tip.max(z))
            }
        }
    }
}

impl Printed for HeightGrid {
    /// Every marked cell within the head's reach (+ `pad` + half a cell's diagonal) of the
    /// segment, at the distance of its centre from the segment less `pad` and half a diagonal
    /// (a lower bound of the horizontal distance from any tip position within `pad` of the
    /// segment to any point of the cell). The cells of the segment's box grown by the reach,
    /// (|b − a| + 2R)·2R / CELL² for a reach R (≈ 35 mm for a 45° RTN head), are visited a
    /// [`BLOCK`] at a time, the blocks with the highest bound first: a block's cells give at
    /// most its highest cell less the floor at `dist(centre, segment) − half its diagonal`
    /// (triangle inequality; the floor does not decrease with the distance: a piece reaching
    /// farther covers a sub-interval of one reaching nearer), so once that bound is
    /// [`BLOCK_SKIP_SLACK_MM`] below the height found, no later block can raise it: the result
    /// is the maximum over every cell, bit for bit.
    fn head_clear_z(&self, profile: &HeadProfile, a: DVec2, b: DVec2, pad: f64, tilt: f64) -> f64 {
        let half_diag = CELL * std::f64::consts::FRAC_1_SQRT_2;
        let reach = profile.reach(tilt) + pad + half_diag;
        let lo = (a.min(b) - DVec2::splat(reach) - self.origin) / CELL;
        let hi = (a.max(b) + DVec2::splat(reach) - self.origin) / CELL;
        let clamp = |v: f64, n: usize| -> usize { v.floor().clamp(0.0, n as f64 - 1.0) as usize };
        if hi.x < 0.0 || hi.y < 0.0 || lo.x >= self.nx as f64 || lo.y >= self.ny as f64 {
            return f64::NEG_INFINITY;
        }
        let (i0, i1) = (clamp(lo.x, self.nx), clamp(hi.x, self.nx));
        let (j0, j1) = (clamp(lo.y, self.ny), clamp(hi.y, self.ny));
        let tilted = profile.at_tilt(tilt);
        let bnx = self.nx.div_ceil(BLOCK);
        // (bound, first and last cell of the block within the box)
        let mut blocks: Vec<(f64, [usize; 4])> = Vec::new();
        for bj in j0 / BLOCK..=j1 / BLOCK {
            for bi in i0 / BLOCK..=i1 / BLOCK {
                let top = self.blocks[bj * bnx + bi];
                if top == f64::NEG_INFINITY {
                    continue;
                }
                let (ci0, ci1) = ((bi * BLOCK).max(i0), (bi * BLOCK + BLOCK - 1).min(i1));
                let (cj0, cj1) = ((bj * BLOCK).max(j0), (bj * BLOCK + BLOCK - 1).min(j1));
                // the rectangle of the cell centres: every centre within its half diagonal
                let half = DVec2::new((ci1 - ci0) as f64, (cj1 - cj0) as f64) * (0.5 * CELL);
                let centre = self.origin
                    + (DVec2::new((ci0 + ci1) as f64, (cj0 + cj1) as f64) * 0.5 + 0.5) * CELL;
                let d = (segment_distance(centre, a, b)
                    - half.length()
                    - pad
                    - half_diag
                    - BLOCK_SKIP_SLACK_MM)
                    .max(0.0);
                let floor = tilted.floor(d);
                if floor.is_finite() {
                    blocks.push((top - floor, [ci0, ci1, cj0, cj1]));
                }
            }
        }
        blocks.sort_unstable_by(|x, y| y.0.total_cmp(&x.0));
        let mut z = f64::NEG_INFINITY;
        for (bound, [ci0, ci1, cj0, cj1]) in blocks {
            if bound + BLOCK_SKIP_SLACK_MM <= z {
                break;
            }
            for j in cj0..=cj1 {
                for i in ci0..=ci1 {
                    let top = self.h[j * self.nx + i];
                    if top == f64::NEG_INFINITY {
                        continue;
                    }
                    let c = self.origin + (DVec2::new(i as f64, j as f64) + 0.5) * CELL;
                    let d = (segment_distance(c, a, b) - pad - half_diag).max(0.0);
                    let floor = tilted.floor(d);
                    if floor.is_finite() {
                        z = z.max(top - floor);
                    }
                }
            }
        }
        z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn travel_over_a_printed_peak_lifts() {
        let mut g = HeightGrid::new(DVec2::new(-10.0, -10.0), DVec2::new(10.0, 10.0));
        g.mark_segment(DVec3::new(-1.0, 0.0, 8.0), DVec3::new(1.0, 0.0, 8.0));
        let a = DVec3::new(-8.0, 0.0, 2.0);
        let b = DVec3::new(8.0, 0.0, 2.0);
        assert_eq!(plan(&g, a, b, 1.0, None), TravelPlan::Lift(9.0));
        // a travel that passes well beside it goes straight
        let a2 = DVec3::new(-8.0, 8.0, 2.0);
        let b2 = DVec3::new(8.0, 8.0, 2.0);
        assert_eq!(plan(&g, a2, b2, 1.0, None), TravelPlan::Direct);
        // and so does one over it at the height of its top (a planar layer's travel)
        let a3 = DVec3::new(-8.0, 0.0, 8.0);
        let b3 = DVec3::new(8.0, 0.0, 8.0);
        assert_eq!(plan(&g, a3, b3, 1.0, None), TravelPlan::Direct);
    }

    /// A block 4.5…16 mm up the tool axis, 16 mm round, reaching 14 mm towards the descent.
    fn block() -> HeadProfile {
        HeadProfile {
            pieces: vec![crate::emit::clearance::ProfilePiece {
                name: "heater-block".into(),
                from_mm: 4.5,
                to_mm: 16.0,
                radius_mm: [16.0; 2],
                drop_mm: [14.0; 2],
            }],
            ..HeadProfile::default()
        }
    }

    /// The head clearance visited by blocks, highest bound first and skipping the rest, is the
    /// maximum over every cell of the box computed cell by cell (the module's formula written
    /// out), bit for bit: random printed columns and ridges, segments, pads and tilts, with a
    /// nozzle cone below the block profile.
    #[test]
    fn the_block_skipping_head_clearance_is_every_cells_maximum() {
        let mut rng = crate::test_rng::Lcg(17);
        let mut rnd = move || rng.unit();
        let mut p = block();
        p.pieces.push(crate::emit::clearance::ProfilePiece {
            name: "nozzle".into(),
            from_mm: 0.0,
            to_mm: 4.5,
            radius_mm: [0.5, 3.0],
            drop_mm: [0.5, 3.0],
        });
        let mut skipped_any = false;
        for case in 0..60 {
            let mut g = HeightGrid::new(DVec2::new(-40.0, -30.0), DVec2::new(35.0, 45.0));
            for _ in 0..(5 + case * 7) {
                let q = DVec3::new(rnd() * 80.0 - 42.0, rnd() * 80.0 - 32.0, rnd() * 30.0);
                if rnd() < 0.5 {
                    g.mark(q);
                } else {
                    let r = q + DVec3::new(rnd() * 20.0 - 10.0, rnd() * 20.0 - 10.0, 0.0);
                    g.mark_segment(q, r);
                }
            }
            for _ in 0..20 {
                let a = DVec2::new(rnd() * 70.0 - 35.0, rnd() * 70.0 - 25.0);
                let b = if rnd() < 0.3 {
                    a
                } else {
                    a + DVec2::new(rnd() * 40.0 - 20.0, rnd() * 40.0 - 20.0)
                };
                let (pad, tilt) = (rnd() * 2.0, rnd() * 1.6);
                let got = g.head_clear_z(&p, a, b, pad, tilt);
                // every cell of the grid within reach, one by one
                let half_diag = CELL * std::f64::consts::FRAC_1_SQRT_2;
                let mut want = f64::NEG_INFINITY;
                let mut cells = 0;
                for j in 0..g.ny {
                    for i in 0..g.nx {
                        let top = g.h[j * g.nx + i];
                        if top == f64::NEG_INFINITY {
                            continue;
                        }
                        let c = g.origin + (DVec2::new(i as f64, j as f64) + 0.5) * CELL;
                        let d = (segment_distance(c, a, b) - pad - half_diag).max(0.0);
                        let floor = p.floor(tilt, d);
                        if floor.is_finite() {
                            want = want.max(top - floor);
                            cells += 1;
                        }
                    }
                }
                assert_eq!(
                    got.to_bits(),
                    want.to_bits(),
                    "case {case}: {got} vs {want} ({cells} cells)"
                );
                skipped_any |= cells > 1 && want.is_finite();
            }
        }
        assert!(skipped_any);
    }

    #[test]
    fn a_column_beside_the_path_raises_the_head_not_the_tip() {
        let mut g = HeightGrid::new(DVec2::new(-30.0, -30.0), DVec2::new(30.0, 30.0));
        // a column 8 mm high 10 mm beside the travel's line (its cell spans x 10…11)
        g.mark(DVec3::new(10.5, 0.5, 8.0));
        // and a bump on the line itself, so the tip's rule lifts (to 2 + 1)
        g.mark_segment(DVec3::new(-0.5, -10.0, 2.0), DVec3::new(0.5, -10.0, 2.0));
        let (a, b) = (DVec3::new(0.0, -20.0, 1.0), DVec3::new(0.0, 20.0, 1.0));
        assert_eq!(plan(&g, a, b, 1.0, None), TravelPlan::Lift(3.0));
        let p = block();
        // vertical: the block's floor is 4.5 mm above the tip within 16 mm of it; the column's
        // cell is 10 − 0.71 mm from the line at the nearest: the tip must be at 8 − 4.5
        let z = g.head_clear_z(&p, a.truncate(), b.truncate(), 0.0, 0.0);
        assert!((z - 3.5).abs() < 1e-12, "{z}");
        let vertical = HeadClearance {
            profile: &p,
            tilt: 0.0,
            turn: 0.0,
        };
        assert_eq!(
            plan(&g, a, b, 1.0, Some(vertical)),
            TravelPlan::Lift(3.5 + HEAD_CLEARANCE_MM)
        );
        // tilted 30°: the block's long side 4.5·cos 30° − 14·sin 30° = −3.10 mm below the tip
        let t = crate::num::rad(30.0);
        let z = g.head_clear_z(&p, a.truncate(), b.truncate(), 0.0, t);
        let want = 8.0 - (4.5 * crate::num::cos(t) - 14.0 * crate::num::sin(t));
        assert!((z - want).abs() < 1e-12, "{z} vs {want}");
        // 16·sin 30° + 16 = 24 mm of reach: a column 25 mm away is out of it
        let mut far = HeightGrid::new(DVec2::new(-40.0, -30.0), DVec2::new(40.0, 30.0));
        far.mark(DVec3::new(25.71 + 0.5, 0.5, 8.0));
        assert_eq!(
            far.head_clear_z(&p, a.truncate(), b.truncate(), 0.0, t),
            f64::NEG_INFINITY
        );
    }

    #[test]
    fn a_travel_that_turns_the_head_lifts_where_the_head_would_not_clear() {
        let mut g = HeightGrid::new(DVec2::new(-30.0, -30.0), DVec2::new(30.0, 30.0));
        g.mark(DVec3::new(10.5, 0.5, 8.0));
        let (a, b) = (DVec3::new(0.0, -5.0, 2.0), DVec3::new(0.0, 5.0, 2.0));
        let p = block();
        let head = |turn_deg: f64| HeadClearance {
            profile: &p,
            tilt: crate::num::rad(30.0),
            turn: crate::num::rad(turn_deg),
        };
        // the tip's rule: straight (nothing on the line)
        assert_eq!(plan(&g, a, b, 1.0, None), TravelPlan::Direct);
        assert_eq!(plan(&g, a, b, 1.0, Some(head(5.0))), TravelPlan::Direct);
        let want = 8.0 - (4.5 * crate::num::cos(crate::num::rad(30.0)) - 7.0) + HEAD_CLEARANCE_MM;
        match plan(&g, a, b, 1.0, Some(head(TURN_IN_AIR_DEG + 1.0))) {
            TravelPlan::Lift(z) => assert!((z - want).abs() < 1e-12, "{z} vs {want}"),
            d => panic!("a turn beside the column went {d:?}"),
        }
        // the same turn far above the column goes straight
        let (a2, b2) = (a + DVec3::Z * 20.0, b + DVec3::Z * 20.0);
        assert_eq!(
            plan(&g, a2, b2, 1.0, Some(head(TURN_IN_AIR_DEG + 1.0))),
            TravelPlan::Direct
        );
    }
}
