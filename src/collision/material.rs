//! The printed material: a height field over the output frame's XY plane.
//!
//! Every extrusion written so far is a bead of the line width whose top passes through the
//! tip's path and rises across it with the layer's cross slope, bounded by the tool face's
//! ([`super::bead`]). Each cell of
//! [`CELL_MM`] keeps the highest top over its centre; the material is taken as everything
//! below (a column): conservative under overhangs, exact above the printed surface, which is
//! where the head is (every warp's layers are graphs z(x, y) in the output frame; the lathe's
//! are not, and its check is refused).
//!
//! ## Layout (measured, see `examples/bench.rs`)
//! Sparse tiles of [`TILE`]² cells (12.8 mm), created on first deposit, each with the maximum
//! of the whole tile, of every group of [`GROUP`]² blocks (6.4 mm), of every [`BLOCK`]² block
//! (1.6 mm) and of every block's row (8 cells): a query skips a tile, group, block or row
//! whose highest material is below the solid's lowest point, or that the solid's bounds say
//! it cannot reach (`crate::collision::cull`). Heights are `f32` (6·10⁻⁵ mm at 1 m); memory
//! ≈ 35 kB per tile touched (heights and owners 16 KiB each, the row maxima 2 KiB; a full
//! 250 × 210 mm bed, 340 tiles: 12 MB), whatever the length of the file.

use std::collections::HashMap;

use glam::DVec3;

use super::bead::{across, Side};

/// Cell size of the height field, mm: half the thinnest line width the check is built for
/// (0.4 mm), so a flat bead covers at least two cell centres across its width.
pub const CELL_MM: f64 = 0.2;
/// Cells per tile side.
pub const TILE: usize = 64;
/// Cells per block side (a block keeps its maximum).
pub const BLOCK: usize = 8;
const BLOCKS: usize = TILE / BLOCK;
/// Blocks per group side (a group of GROUP² blocks, 6.4 mm, keeps its maximum too: a query
/// tests a group before its blocks, so a head part far above most of a tile's area is turned
/// away at once).
pub const GROUP: usize = 4;
const GROUPS: usize = BLOCKS / GROUP;

/// One tile of the height field.
struct Tile {
    h: Vec<f32>,
    /// The bead (1-based index in file order, 0: none) whose top is the cell's height.
    owner: Vec<u32>,
    block_max: [f32; BLOCKS * BLOCKS],
    group_max: [f32; GROUPS * GROUPS],
    /// The maximum of each block's row of BLOCK cells (`row_max[cj * BLOCKS + bi]`).
    row_max: Vec<f32>,
    max: f32,
}

impl Tile {
    /// Raise cell `k` (`cj·TILE + ci`) to `z` for bead `bead` if `z` is higher, with the
    /// maxima of its row, block, group and the tile.
    fn raise(&mut self, k: usize, z: f64, bead: u32) {
        let (ci, cj) = (k % TILE, k / TILE);
        let z = z as f32;
        let c = &mut self.h[k];
        if z > *c {
            *c = z;
            self.owner[k] = bead;
            let b = &mut self.block_max[(cj / BLOCK) * BLOCKS + ci / BLOCK];
            *b = b.max(z);
            let r = &mut self.row_max[cj * BLOCKS + ci / BLOCK];
            *r = r.max(z);
            let g = &mut self.group_max[(cj / (BLOCK * GROUP)) * GROUPS + ci / (BLOCK * GROUP)];
            *g = g.max(z);
            self.max = self.max.max(z);
        }
    }

    fn new() -> Tile {
        Tile {
            h: vec![f32::NEG_INFINITY; TILE * TILE],
            owner: vec![0; TILE * TILE],
            block_max: [f32::NEG_INFINITY; BLOCKS * BLOCKS],
            group_max: [f32::NEG_INFINITY; GROUPS * GROUPS],
            row_max: vec![f32::NEG_INFINITY; TILE * BLOCKS],
            max: f32::NEG_INFINITY,
        }
    }
}

/// A cell of the height field (integer coordinates: centre at `(i + ½, j + ½)·CELL_MM`).
pub type Cell = (i64, i64);

/// The hasher of tile keys: the two indices mixed by a multiply and a rotate (FxHash's step),
/// not SipHash: the keys are the program's own tile indices, not an attacker's, and a lookup
/// happens per tile per query (measured: SipHash was 2–3 % of a checked unwarp).
#[derive(Default, Clone, Copy)]
pub struct TileHasher(u64);

impl std::hash::Hasher for TileHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(*b as u64);
        }
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }
}

type Tiles = HashMap<(i64, i64), Tile, std::hash::BuildHasherDefault<TileHasher>>;

/// The height field of printed material.
#[derive(Default)]
pub struct Material {
    tiles: Tiles,
    /// Beads deposited.
    pub beads: u64,
    /// `(first bead, layer)` of every layer deposited, in file order (layers only grow).
    layer_starts: Vec<(u32, u32)>,
}

impl std::fmt::Debug for Material {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Material")
            .field("tiles", &self.tiles.len())
            .field("beads", &self.beads)
            .finish()
    }
}

/// The highest block maximum of `tile` over its blocks `bi0..=bi1` × `bj0..=bj1` (−∞: none
/// above −∞), returned as soon as it exceeds `stop`. The tile's own maximum stands for the
/// whole tile and a group's for a group the range holds whole: each is the maximum of the
/// same cells as its blocks' maxima (`Material::raise` raises all of them with the cell), so
/// the value is the blocks' maximum read one by one, from 1 instead of 64 values (a tile) or
/// 16 (a group).
fn blocks_max(tile: &Tile, [bi0, bi1, bj0, bj1]: [usize; 4], stop: f64) -> f64 {
    if bi0 == 0 && bj0 == 0 && bi1 == BLOCKS - 1 && bj1 == BLOCKS - 1 {
        return tile.max as f64;
    }
    let mut best = f64::NEG_INFINITY;
    if bi1 - bi0 + 1 < GROUP || bj1 - bj0 + 1 < GROUP {
        // no whole group in the range: the blocks themselves
        for bj in bj0..=bj1 {
            for bi in bi0..=bi1 {
                best = best.max(tile.block_max[bj * BLOCKS + bi] as f64);
            }
            if best > stop {
                return best;
            }
        }
        return best;
    }
    for gj in bj0 / GROUP..=bj1 / GROUP {
        let (rj0, rj1) = (bj0.max(gj * GROUP), bj1.min(gj * GROUP + GROUP - 1));
        for gi in bi0 / GROUP..=bi1 / GROUP {
            let (ri0, ri1) = (bi0.max(gi * GROUP), bi1.min(gi * GROUP + GROUP - 1));
            if rj1 - rj0 + 1 == GROUP && ri1 - ri0 + 1 == GROUP {
                best = best.max(tile.group_max[gj * GROUPS + gi] as f64);
            } else {
                for bj in rj0..=rj1 {
                    for bi in ri0..=ri1 {
                        best = best.max(tile.block_max[bj * BLOCKS + bi] as f64);
                    }
                }
            }
            if best > stop {
                return best;
            }
        }
    }
    best
}

/// The cell containing coordinate `v`.
pub fn cell_of(v: f64) -> i64 {
    (v / CELL_MM).floor() as i64
}

/// The centre coordinate of cell index `i`.
pub fn centre(i: i64) -> f64 {
    (i as f64 + 0.5) * CELL_MM
}

impl Material {
    /// An empty height field.
    pub fn new() -> Material {
        Material::default()
    }

    /// Tiles in use.
    pub fn tiles(&self) -> usize {
        self.tiles.len()
    }

    /// The material's top over cell (i, j), mm (−∞: none).
    pub fn height(&self, i: i64, j: i64) -> f64 {
        let (ti, tj) = (i.div_euclid(TILE as i64), j.div_euclid(TILE as i64));
        match self.tiles.get(&(ti, tj)) {
            None => f64::NEG_INFINITY,
            Some(t) => {
                let (ci, cj) = (
                    i.rem_euclid(TILE as i64) as usize,
                    j.rem_euclid(TILE as i64) as usize,
                );
                t.h[cj * TILE + ci] as f64
            }
        }
    }

    /// The layer of bead `bead` (1-based, as [`Material::for_cells_above`] gives it; 0: none).
    pub fn layer_of(&self, bead: u32) -> Option<u32> {
        if bead == 0 {
            return None;
        }
        let k = self.layer_starts.partition_point(|(b, _)| *b <= bead);
        k.checked_sub(1).map(|k| self.layer_starts[k].1)
    }

    /// What the material at (x, y) tells of the surface of layer `layer` there: the top of a
    /// bead of that layer, of an older one, or nothing ([`super::bead::Side`]).
    pub fn side_at(&self, x: f64, y: f64, layer: u32) -> Side {
        let (i, j) = (cell_of(x), cell_of(y));
        let (ti, tj) = (i.div_euclid(TILE as i64), j.div_euclid(TILE as i64));
        let Some(t) = self.tiles.get(&(ti, tj)) else {
            return Side::Unknown;
        };
        let k = j.rem_euclid(TILE as i64) as usize * TILE + i.rem_euclid(TILE as i64) as usize;
        let h = t.h[k] as f64;
        match self.layer_of(t.owner[k]) {
            Some(l) if l == layer => Side::Current(h),
            Some(l) if l < layer => Side::Older(h),
            _ => Side::Unknown,
        }
    }

    /// Deposit the bead of width `w` from tip `p0` to `p1` with cross slope `slope` (mm of z
    /// per mm along `h = ẑ × d_xy/|d_xy|`, [`super::bead`]) in layer `layer`: every cell whose
    /// centre is within `w/2` of the path (horizontally; never less than half a cell diagonal,
    /// so a vertical piece still marks the cells along it) is raised to
    /// `on_z + clamp((c − on)·h, ±w/2)·slope`, `on` the path's point nearest the centre. Its
    /// index is the new [`Material::beads`].
    pub fn deposit(&mut self, p0: DVec3, p1: DVec3, slope: f64, w: f64, layer: u32) {
        self.beads += 1;
        let bead = self.beads.min(u32::MAX as u64) as u32;
        if self.layer_starts.last().is_none_or(|(_, l)| *l != layer) {
            self.layer_starts.push((bead, layer));
        }
        let d = p1 - p0;
        let h = across(d).unwrap_or(glam::DVec2::ZERO);
        let half = 0.5 * w;
        let reach = if h == glam::DVec2::ZERO {
            CELL_MM * std::f64::consts::FRAC_1_SQRT_2
        } else {
            half.max(CELL_MM * std::f64::consts::FRAC_1_SQRT_2)
        };
        let dxy = d.truncate();
        let l2 = dxy.length_squared();
        let (lo, hi) = (p0.min(p1), p0.max(p1));
        // the tile of the last cell raised: the next cells are mostly in it (one hash lookup
        // per tile and row of cells, not per cell; a tile is still created only when a cell
        // of it is raised)
        let mut last: Option<((i64, i64), &mut Tile)> = None;
        for j in cell_of(lo.y - reach)..=cell_of(hi.y + reach) {
            for i in cell_of(lo.x - reach)..=cell_of(hi.x + reach) {
                let c = glam::DVec2::new(centre(i), centre(j));
                let t = if l2 > 0.0 {
                    ((c - p0.truncate()).dot(dxy) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let on = p0 + d * t;
                let off = c - on.truncate();
                if off.length() > reach {
                    continue;
                }
                let lambda = off.dot(h).clamp(-half, half);
                let key = (i.div_euclid(TILE as i64), j.div_euclid(TILE as i64));
                let k =
                    j.rem_euclid(TILE as i64) as usize * TILE + i.rem_euclid(TILE as i64) as usize;
                match &mut last {
                    Some((at, tile)) if *at == key => tile.raise(k, on.z + lambda * slope, bead),
                    _ => {
                        let tile = self.tiles.entry(key).or_insert_with(Tile::new);
                        tile.raise(k, on.z + lambda * slope, bead);
                        last = Some((key, tile));
                    }
                }
            }
        }
    }

    /// The tiles the rectangle `[x0, x1] × [y0, y1]` touches, each with the range of its
    /// blocks inside the rectangle (`bi0..=bi1`, `bj0..=bj1`); stops when `visit` says so.
    fn tiles_over(
        &self,
        (x0, y0, x1, y1): (f64, f64, f64, f64),
        mut visit: impl FnMut(&Tile, [usize; 4]) -> bool,
    ) -> bool {
        let (i0, i1, j0, j1) = (cell_of(x0), cell_of(x1), cell_of(y0), cell_of(y1));
        let t = TILE as i64;
        let b = BLOCK as i64;
        for tj in j0.div_euclid(t)..=j1.div_euclid(t) {
            for ti in i0.div_euclid(t)..=i1.div_euclid(t) {
                let Some(tile) = self.tiles.get(&(ti, tj)) else {
                    continue;
                };
                let blocks = [
                    ((i0 - ti * t).max(0) / b) as usize,
                    ((i1 - ti * t).min(t - 1) / b) as usize,
                    ((j0 - tj * t).max(0) / b) as usize,
                    ((j1 - tj * t).min(t - 1) / b) as usize,
                ];
                if visit(tile, blocks) {
                    return true;
                }
            }
        }
        false
    }

    /// An upper bound of the material's top over the rectangle `[x0, x1] × [y0, y1]`: the
    /// largest maximum of the blocks it touches (−∞: none). A move whose head part stays above
    /// it everywhere skips the part's cell scan (`crate::collision::sweep`).
    pub fn max_over(&self, rect: (f64, f64, f64, f64)) -> f64 {
        let mut best = f64::NEG_INFINITY;
        self.tiles_over(rect, |tile, blocks| {
            if (tile.max as f64) > best {
                best = best.max(blocks_max(tile, blocks, f64::INFINITY));
            }
            false
        });
        best
    }

    /// Whether some material over the rectangle `[x0, x1] × [y0, y1]` may be above `z`: the
    /// test `max_over(rect) > z`, answered from the tiles' maxima where they suffice and
    /// stopping at the first block above `z` (a head part far above the print, the usual case
    /// for the heater block and the heat sink, costs a few tile lookups).
    pub fn any_above(&self, rect: (f64, f64, f64, f64), z: f64) -> bool {
        self.tiles_over(rect, |tile, blocks| {
            (tile.max as f64) > z && blocks_max(tile, blocks, z) > z
        })
    }

    /// Visit every cell of the rectangle `[x0, x1] × [y0, y1]` whose material top exceeds
    /// `above`, skipping tiles, groups and blocks below it, groups and blocks for which
    /// `skip(centre, half_diagonal, top)` says the solid cannot reach their material (the
    /// centre and the half diagonal of the square seen from above, its highest top: `skip`
    /// must hold for any square and any `top` at least its cells'; a group is asked once, when
    /// its first block in the rectangle is reached, so the cells come in the same order as
    /// without groups), and in each row
    /// `y` of a block the cells whose centres lie outside `row(y, top)` (an x-interval;
    /// `None`: none of the row; `top` there is the highest top of the block's cells on that row);
    /// `visit(i, j, top, bead)` (the bead whose top it is).
    pub fn for_cells_above(
        &self,
        (x0, y0, x1, y1): (f64, f64, f64, f64),
        above: f64,
        mut skip: impl FnMut(glam::DVec2, f64, f64) -> bool,
        mut row: impl FnMut(f64, f64) -> Option<(f64, f64)>,
        mut visit: impl FnMut(i64, i64, f64, u32),
    ) {
        let (i0, i1, j0, j1) = (cell_of(x0), cell_of(x1), cell_of(y0), cell_of(y1));
        let t = TILE as i64;
        let b = BLOCK as i64;
        for tj in j0.div_euclid(t)..=j1.div_euclid(t) {
            for ti in i0.div_euclid(t)..=i1.div_euclid(t) {
                let Some(tile) = self.tiles.get(&(ti, tj)) else {
                    continue;
                };
                if (tile.max as f64) <= above {
                    continue;
                }
                // per group: may its cells give a finding (asked on its first block)
                let mut group_open: [Option<bool>; GROUPS * GROUPS] = [None; GROUPS * GROUPS];
                // the tile's blocks that meet the rectangle: block k spans cells
                // [k b, k b + b − 1] from the tile's first, so those from ⌊(i0 − ti t)/b⌋ to
                // ⌊(i1 − ti t)/b⌋ (clamped to the tile), in the same order
                let last = BLOCKS as i64 - 1;
                let (bj0, bj1) = (
                    (j0 - tj * t).div_euclid(b).max(0),
                    (j1 - tj * t).div_euclid(b).min(last),
                );
                let (bi0, bi1) = (
                    (i0 - ti * t).div_euclid(b).max(0),
                    (i1 - ti * t).div_euclid(b).min(last),
                );
                for bj in bj0..=bj1 {
                    let cj0 = tj * t + bj * b;
                    for bi in bi0..=bi1 {
                        let ci0 = ti * t + bi * b;
                        let top = tile.block_max[(bj * BLOCKS as i64 + bi) as usize] as f64;
                        if top <= above {
                            continue;
                        }
                        let (gi, gj) = (bi as usize / GROUP, bj as usize / GROUP);
                        let open = *group_open[gj * GROUPS + gi].get_or_insert_with(|| {
                            let gside = (b as usize * GROUP) as f64 * CELL_MM;
                            let c = glam::DVec2::new(
                                (ti * t) as f64 * CELL_MM + (gi as f64 + 0.5) * gside,
                                (tj * t) as f64 * CELL_MM + (gj as f64 + 0.5) * gside,
                            );
                            let gtop = tile.group_max[gj * GROUPS + gi] as f64;
                            !skip(c, 0.5 * gside * std::f64::consts::SQRT_2, gtop)
                        });
                        if !open {
                            continue;
                        }
                        let side = b as f64 * CELL_MM;
                        let c = glam::DVec2::new(
                            ci0 as f64 * CELL_MM + 0.5 * side,
                            cj0 as f64 * CELL_MM + 0.5 * side,
                        );
                        if skip(c, 0.5 * side * std::f64::consts::SQRT_2, top) {
                            continue;
                        }
                        for j in cj0.max(j0)..=(cj0 + b - 1).min(j1) {
                            let (mut lo, mut hi) = (ci0.max(i0), (ci0 + b - 1).min(i1));
                            // the row's own highest top bounds its cells more tightly
                            let rtop =
                                tile.row_max[(j - tj * t) as usize * BLOCKS + bi as usize] as f64;
                            if rtop <= above {
                                continue;
                            }
                            let Some((xa, xb)) = row(centre(j), rtop) else {
                                continue;
                            };
                            // the cells whose centres lie in [xa, xb]
                            if xa.is_finite() {
                                lo = lo.max((xa / CELL_MM - 0.5).ceil() as i64);
                            }
                            if xb.is_finite() {
                                hi = hi.min((xb / CELL_MM - 0.5).floor() as i64);
                            }
                            for i in lo..=hi {
                                let cj = (j - tj * t) as usize;
                                let ci = (i - ti * t) as usize;
                                let h = tile.h[cj * TILE + ci] as f64;
                                if h > above {
                                    visit(i, j, h, tile.owner[cj * TILE + ci]);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    /// Every bead [`Material::deposit`] lays (the tile of the last cell kept from cell to cell)
    /// raises exactly the cells the rule of its documentation names, to the value it names,
    /// and no other: after each bead every cell about it is compared, bit for bit, with the
    /// rule evaluated here (the cell centre's nearest point `q` on the path seen from above,
    /// within `max(w/2, half a cell diagonal)`; the top `q_z + clamp((c − q)·h, ±w/2)·slope`,
    /// kept where it is higher than the cell's). Beads of 0–9 mm across the corners of four
    /// tiles (negative indices too), some vertical; then every tile's row, block, group and
    /// tile maxima against its cells, and the count of tiles against those with a cell raised.
    #[test]
    fn a_bead_raises_exactly_the_cells_its_rule_names_across_tiles() {
        let mut rng = Lcg(77);
        let mut m = Material::new();
        let mut raised_tiles = std::collections::HashSet::new();
        let (mut raised, mut crossing) = (0, 0);
        for bead in 1..=400u32 {
            let a = rng.within(DVec3::new(-9.0, -9.0, 0.0), DVec3::new(9.0, 9.0, 2.0));
            let b = match bead % 10 {
                0 => a + DVec3::Z * rng.range(0.0, 0.3),
                _ => a + rng.within(DVec3::new(-6.0, -6.0, -0.2), DVec3::new(6.0, 6.0, 0.2)),
            };
            let (slope, w) = (rng.range(-0.5, 0.5), rng.range(0.3, 0.7));
            let (i0, i1) = (cell_of(a.x.min(b.x)) - 4, cell_of(a.x.max(b.x)) + 4);
            let (j0, j1) = (cell_of(a.y.min(b.y)) - 4, cell_of(a.y.max(b.y)) + 4);
            let before: Vec<f64> = (j0..=j1)
                .flat_map(|j| (i0..=i1).map(move |i| (i, j)))
                .map(|(i, j)| m.height(i, j))
                .collect();
            m.deposit(a, b, slope, w, 1 + bead / 50);
            let across_dir = across(b - a);
            let diag = CELL_MM * std::f64::consts::FRAC_1_SQRT_2;
            let within = across_dir.map_or(diag, |_| (0.5 * w).max(diag));
            let seg = (b - a).truncate();
            let mut tiles_hit = std::collections::HashSet::new();
            for (n, (i, j)) in (j0..=j1)
                .flat_map(|j| (i0..=i1).map(move |i| (i, j)))
                .enumerate()
            {
                let c = glam::DVec2::new(centre(i), centre(j));
                let s = if seg.length_squared() > 0.0 {
                    ((c - a.truncate()).dot(seg) / seg.length_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let q = a + (b - a) * s;
                let away = c - q.truncate();
                let old = before[n];
                let want = if away.length() <= within {
                    let side = away.dot(across_dir.unwrap_or(glam::DVec2::ZERO));
                    let top = (q.z + side.clamp(-0.5 * w, 0.5 * w) * slope) as f32;
                    if (top as f64) > old {
                        raised += 1;
                        tiles_hit.insert((i.div_euclid(TILE as i64), j.div_euclid(TILE as i64)));
                        raised_tiles.insert((i.div_euclid(TILE as i64), j.div_euclid(TILE as i64)));
                        top as f64
                    } else {
                        old
                    }
                } else {
                    old
                };
                let got = m.height(i, j);
                assert!(
                    got.to_bits() == want.to_bits(),
                    "bead {bead} from {a} to {b}: the cell ({i}, {j}) is {got}, the rule gives \
                     {want} (it was {old})"
                );
            }
            crossing += usize::from(tiles_hit.len() > 1);
        }
        assert_eq!(
            m.tiles(),
            raised_tiles.len(),
            "tiles made, tiles with a cell raised"
        );
        for tile in m.tiles.values() {
            let cell = |ci: usize, cj: usize| tile.h[cj * TILE + ci];
            let top = |cis: std::ops::Range<usize>, cjs: std::ops::Range<usize>| {
                cjs.flat_map(|cj| cis.clone().map(move |ci| (ci, cj)))
                    .map(|(ci, cj)| cell(ci, cj))
                    .fold(f32::NEG_INFINITY, f32::max)
            };
            assert_eq!(tile.max, top(0..TILE, 0..TILE), "the tile's maximum");
            for bj in 0..BLOCKS {
                for bi in 0..BLOCKS {
                    let (x, y) = (bi * BLOCK, bj * BLOCK);
                    let blk = top(x..x + BLOCK, y..y + BLOCK);
                    assert_eq!(tile.block_max[bj * BLOCKS + bi], blk, "block ({bi}, {bj})");
                    for cj in y..y + BLOCK {
                        assert_eq!(
                            tile.row_max[cj * BLOCKS + bi],
                            top(x..x + BLOCK, cj..cj + 1)
                        );
                    }
                }
            }
            for gj in 0..GROUPS {
                for gi in 0..GROUPS {
                    let (x, y) = (gi * BLOCK * GROUP, gj * BLOCK * GROUP);
                    let g = top(x..x + BLOCK * GROUP, y..y + BLOCK * GROUP);
                    assert_eq!(tile.group_max[gj * GROUPS + gi], g, "group ({gi}, {gj})");
                }
            }
        }
        assert!(
            raised > 10_000 && crossing > 40,
            "{raised} cells raised, {crossing} beads over more than one tile"
        );
    }

    /// [`Material::max_over`] is the largest top of the cells of the blocks the rectangle
    /// touches, found cell by cell through [`Material::height`] (no tile or block maximum):
    /// random beads over four tiles about the origin (negative indices too), random rectangles
    /// from a cell wide to several tiles (some holding whole groups and tiles, which are read
    /// from the group's and the tile's own maxima); and [`Material::any_above`] says whether
    /// that largest top is above a height drawn on either side of it.
    #[test]
    fn the_maximum_over_a_rectangle_is_the_highest_cell_of_the_blocks_it_touches_and_any_above_agrees(
    ) {
        let mut rng = Lcg(31);
        let mut m = Material::new();
        for layer in 1..=40 {
            let lo = DVec3::new(-12.0, -12.0, 0.0);
            let hi = DVec3::new(12.0, 12.0, 0.0);
            let a = rng.within(lo, hi) + DVec3::Z * (0.05 * layer as f64);
            let b = a + rng.within(DVec3::new(-6.0, -6.0, -0.5), DVec3::new(6.0, 6.0, 0.5));
            m.deposit(a, b, rng.range(-0.3, 0.3), rng.range(0.3, 0.6), layer);
        }
        let b = BLOCK as i64;
        let (mut wide, mut found, mut groups, mut tiles) = (0, 0, 0, 0);
        for k in 0..3000 {
            let side = [0.1, 1.0, 7.0, 14.0, 30.0][k % 5];
            let x0 = rng.range(-16.0, 14.0);
            let y0 = rng.range(-16.0, 14.0);
            let rect = (x0, y0, x0 + rng.range(0.0, side), y0 + rng.range(0.0, side));
            let (bi0, bi1) = (cell_of(rect.0).div_euclid(b), cell_of(rect.2).div_euclid(b));
            let (bj0, bj1) = (cell_of(rect.1).div_euclid(b), cell_of(rect.3).div_euclid(b));
            let mut brute = f64::NEG_INFINITY;
            for j in bj0 * b..(bj1 + 1) * b {
                for i in bi0 * b..(bi1 + 1) * b {
                    brute = brute.max(m.height(i, j));
                }
            }
            let got = m.max_over(rect);
            assert!(
                got == brute,
                "rect {rect:?}: max_over {got}, the blocks' cells {brute}"
            );
            // any_above: the same bound as a yes/no, on either side of it
            let z = if brute.is_finite() {
                brute + rng.range(-0.5, 0.5)
            } else {
                rng.range(-1.0, 3.0)
            };
            assert_eq!(
                m.any_above(rect, z),
                brute > z,
                "rect {rect:?}: any_above {z}, the blocks' cells' highest {brute}"
            );
            wide += usize::from(bi1 - bi0 >= 2 * GROUP as i64);
            found += usize::from(brute.is_finite());
            // a whole group (GROUP² blocks, aligned) or a whole tile inside the block range:
            // the cases read from the group's and the tile's own maxima
            let holds = |n: i64| {
                let whole = |a: i64, b: i64| (a + n - 1).div_euclid(n) * n + n - 1 <= b;
                whole(bi0, bi1) && whole(bj0, bj1)
            };
            groups += usize::from(holds(GROUP as i64) && brute.is_finite());
            tiles += usize::from(holds(BLOCKS as i64) && brute.is_finite());
        }
        assert!(
            wide > 300 && found > 1500 && groups > 200 && tiles > 50,
            "{wide} rectangles over eight blocks or more, {found} over material, {groups} holding \
             a whole group, {tiles} a whole tile"
        );
    }
}
