//! Thin walls: the parts of a layer narrower than one line, printed as one line along their
//! middle whose width follows the local thickness (PrusaSlicer's `thin_walls`).
//!
//! # Where
//! With line width w, the external perimeter of an island R runs on R eroded by w/2
//! (`E = offset(R, −w/2)`) and, with the lines inside it, covers the opening
//! `O = offset(E, +w/2)`: every point within w/2 of E. What no disc of diameter w fits in,
//! `R − O`, is thin. Of it, what is narrower than [`MIN_THIN_WIDTH`] is removed by a second
//! opening, by `MIN_THIN_WIDTH/2` (PrusaSlicer's `opening_ex(…, min_width/2)`); a thin shape
//! that vanishes there, or whose centre line is shorter than [`MIN_THIN_WIDTH`], is counted
//! and not printed ([`Thin::unprinted`]).
//!
//! # Centre line: the chordal axis
//! Each thin shape's contours, simplified to [`RESOLUTION`] (as the sections are) and split
//! so that no edge is longer than [`MAX_EDGE`], are the
//! constraint edges of a constrained Delaunay triangulation (`spade`). A triangle inside the
//! shape has one to three edges that are not on the boundary, its chords; the chordal axis
//! (Prasad, 1997) joins the midpoints of a triangle's chords: a sleeve (two chords) gives the
//! segment between their midpoints, a junction (three) joins the midpoints to its centroid, a
//! terminal (one) joins its chord's midpoint to its centroid. In a strip every chord runs from
//! one side to the other, and the midpoint of any segment between two parallel lines lies on
//! the line halfway between them: the axis of a strip of constant thickness is its middle line
//! exactly, whatever the triangles' shapes. An edge whose midpoint lies within
//! `MIN_THIN_WIDTH/4` of the boundary joins two points of one side, not the two sides (the
//! points of a split edge are collinear only to rounding, so slivers form along a side): it
//! is not a chord. A chord's midpoint is half the part's width, at least `MIN_THIN_WIDTH/2`,
//! from the sides. Branches shorter than w that end in a terminal
//! triangle (a corner's triangles) are dropped. A free end (a terminal triangle) is replaced
//! by the line's last direction carried on to the thin shape's boundary (PrusaSlicer's medial
//! axis extends its ends the same way), so a strip's line runs its whole length.
//!
//! # Width and flow
//! At a centre-line point p with unit tangent u (along its neighbours) the local thickness is
//! the strip's width across the line: `t(p) = r(p, n) + r(p, −n)`, with n ⟂ u and `r(p, d)`
//! the distance from p along d to R's own boundary (the cut against O is not a side); an
//! extended end takes its neighbour's thickness. The rays see a strip's width exactly but
//! not a bevelled end's or a junction's, and the profile is linear between points a chord
//! apart, so the profile of a shape's lines is then scaled so that `Σ ∫ t dl` is the shape's
//! area (by at most [`MAX_RESCALE`]); t is clamped to `[MIN_THIN_WIDTH, w]`.
//! As in PrusaSlicer's
//! thin walls (`thick_polyline_to_extrusion_paths`, width `t + h·(1 − π/4)`), the line's
//! spacing is the local thickness, so its cross-section is `t·h`
//! ([`super::Path::section`]): a segment between points of thickness t₀ and t₁ deposits
//! `h·(t₀ + t₁)/2` per mm, the strip's own area × h.

use std::collections::HashMap;

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::region::{
    area, contour_area, difference, line_crossing, offset, simplify_closed, Contour, Region, Shape,
    RESOLUTION,
};

/// The thinnest part printed as a thin wall, mm: narrower parts are left out (and counted).
/// PrusaSlicer's floor is a third of the nozzle (0.133 mm for 0.4 mm); 0.1 mm keeps the
/// 0.2 mm fins and 0.35 mm shells of the corpus well above it and drops the µm slivers the
/// polygon operations leave along every boundary.
pub const MIN_THIN_WIDTH: f64 = 0.1;

/// Longest boundary edge the triangulation sees, mm: longer edges are split, so a side has a
/// chord end at least every 0.2 mm and the centre line follows a curved strip of radius ρ to
/// within about `MAX_EDGE²/(8ρ)` (5 µm at ρ = 1 mm).
pub const MAX_EDGE: f64 = 0.2;

/// Points of a contour closer than this are one, mm: the polygon operations leave some pairs
/// a few nm apart, whose tiny edge would split the triangulation's strip in two.
pub const DUPLICATE: f64 = 1e-6;

/// Longest extension of a free end to the boundary, mm: the end's terminal triangle spans at
/// most a thin part's width (< a line) and a boundary edge ([`MAX_EDGE`]); a longer ray has
/// missed the end and is not followed.
pub const MAX_EXTENSION: f64 = 1.0;

/// Largest factor the thickness profile of a thin part's lines is scaled by so that they
/// fill its area (see the module documentation); a profile further off is kept as measured
/// (the axis missed part of the shape: the scale would not be a correction).
pub const MAX_RESCALE: f64 = 1.5;

/// One thin wall: a line along the middle of a thin part.
#[derive(Clone, Debug, PartialEq)]
pub struct ThinLine {
    /// Its points, mm; a closed line does not repeat its first point.
    pub points: Vec<[f64; 2]>,
    /// The local thickness at each point, mm (`MIN_THIN_WIDTH ≤ t ≤ w`).
    pub thickness: Vec<f64>,
    /// Whether it is a closed loop (a thin ring).
    pub closed: bool,
}

impl ThinLine {
    /// `∫ t dl`, mm²: the area its line fills (thickness linear along each segment).
    pub fn laid_area(&self) -> f64 {
        let n = self.points.len();
        let segs = if self.closed { n } else { n.saturating_sub(1) };
        (0..segs)
            .map(|i| {
                let j = (i + 1) % n;
                dist(self.points[i], self.points[j]) * (self.thickness[i] + self.thickness[j]) / 2.0
            })
            .sum()
    }

    /// Its length, mm.
    pub fn length(&self) -> f64 {
        let n = self.points.len();
        let segs = if self.closed { n } else { n.saturating_sub(1) };
        (0..segs)
            .map(|i| dist(self.points[i], self.points[(i + 1) % n]))
            .sum()
    }
}

/// The thin walls of one island.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Thin {
    /// The lines to print.
    pub lines: Vec<ThinLine>,
    /// Thin parts left out: narrower than [`MIN_THIN_WIDTH`] everywhere, or too short.
    pub unprinted: usize,
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

/// The thin walls of `island` (one shape) for line width `w`, given its opening by w/2
/// (`opening = offset(offset(island, −w/2), +w/2)`, empty when the island fits no line).
pub fn thin_walls(island: &Region, opening: &Region, w: f64) -> Thin {
    let mut out = Thin::default();
    // a cheap test first: most islands lose nothing to the opening
    if area(island) - area(opening) < MIN_THIN_WIDTH * MIN_THIN_WIDTH {
        return out;
    }
    let thin = difference(island, opening);
    let sides: Vec<([f64; 2], [f64; 2])> = island
        .iter()
        .flatten()
        .flat_map(|c| (0..c.len()).map(move |i| (c[i], c[(i + 1) % c.len()])))
        .collect();
    for shape in thin {
        let outer = shape.first().map_or(0.0, |c| contour_area(c));
        if outer < MIN_THIN_WIDTH * MIN_THIN_WIDTH {
            continue; // dust of the polygon operations, not a part
        }
        let kept = offset(
            &offset(&vec![shape], -MIN_THIN_WIDTH / 2.0),
            MIN_THIN_WIDTH / 2.0,
        );
        let before = out.lines.len();
        for s in &kept {
            let from = out.lines.len();
            let edges: Vec<([f64; 2], [f64; 2])> = s
                .iter()
                .flat_map(|c| (0..c.len()).map(move |i| (c[i], c[(i + 1) % c.len()])))
                .collect();
            for (line, free) in chordal_axis(s, w) {
                let closed = line.len() > 2 && line.first() == line.last();
                let mut points = line;
                if closed {
                    points.pop();
                }
                let ends = if closed {
                    [false; 2]
                } else {
                    extend_ends(&mut points, free, &edges)
                };
                let n = points.len();
                let mut thickness: Vec<f64> = (0..n)
                    .map(|i| {
                        let (a, b) = if closed {
                            (points[(i + n - 1) % n], points[(i + 1) % n])
                        } else {
                            (points[i.saturating_sub(1)], points[(i + 1).min(n - 1)])
                        };
                        across(points[i], a, b, &sides).clamp(MIN_THIN_WIDTH, w)
                    })
                    .collect();
                if n >= 2 {
                    if ends[0] {
                        thickness[0] = thickness[1];
                    }
                    if ends[1] {
                        thickness[n - 1] = thickness[n - 2];
                    }
                }
                let l = ThinLine {
                    points,
                    thickness,
                    closed,
                };
                if l.length() >= MIN_THIN_WIDTH {
                    out.lines.push(l);
                }
            }
            // the lines of this shape deposit its own area
            let lines = &mut out.lines[from..];
            let laid: f64 = lines.iter().map(ThinLine::laid_area).sum();
            let scale = area(&vec![s.clone()]) / laid;
            if (1.0 / MAX_RESCALE..=MAX_RESCALE).contains(&scale) {
                for l in lines {
                    for t in &mut l.thickness {
                        *t = (*t * scale).clamp(MIN_THIN_WIDTH, w);
                    }
                }
            }
        }
        if out.lines.len() == before {
            out.unprinted += 1;
        }
    }
    out
}

/// The width of the part across the line at `p` whose neighbours are `a` and `b`: the
/// distances from `p` to `sides` along both normals, added; twice the distance to the
/// nearest side when a normal meets none.
fn across(p: [f64; 2], a: [f64; 2], b: [f64; 2], sides: &[([f64; 2], [f64; 2])]) -> f64 {
    let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
    let l = ux.hypot(uy);
    if l > 0.0 {
        let n = [-uy / l, ux / l];
        if let (Some(r0), Some(r1)) = (ray(p, n, sides), ray(p, [-n[0], -n[1]], sides)) {
            return r0 + r1;
        }
    }
    2.0 * boundary_distance(p, sides)
}

/// The distance from `p` along the unit direction `d` to the first of `sides` it meets.
fn ray(p: [f64; 2], d: [f64; 2], sides: &[([f64; 2], [f64; 2])]) -> Option<f64> {
    let mut best: Option<f64> = None;
    for &(a, b) in sides {
        let Some((t, s)) = line_crossing(p, d, a, b) else {
            continue;
        };
        if t > 0.0 && (0.0..=1.0).contains(&s) && best.is_none_or(|b| t < b) {
            best = Some(t);
        }
    }
    best
}

/// Replace each free end of an open `line` (`free`: its first and last point end in a
/// terminal triangle) by the line's direction there carried on to the nearest of `edges`;
/// which ends were moved.
fn extend_ends(
    line: &mut Vec<[f64; 2]>,
    free: [bool; 2],
    edges: &[([f64; 2], [f64; 2])],
) -> [bool; 2] {
    let mut moved = [false; 2];
    for (end, &is_free) in free.iter().enumerate() {
        if !is_free || line.len() < 2 {
            continue;
        }
        if end == 0 {
            line.reverse();
        }
        // drop the terminal centroid when a chord midpoint before it gives the direction
        if line.len() >= 3 {
            line.pop();
        }
        let (p, q) = (line[line.len() - 2], line[line.len() - 1]);
        let l = dist(p, q);
        if l > 0.0 {
            let d = [(q[0] - p[0]) / l, (q[1] - p[1]) / l];
            // not across the part: a free end is at most a triangle from the boundary
            if let Some(t) = ray(q, d, edges).filter(|&t| t <= MAX_EXTENSION) {
                line.push([q[0] + t * d[0], q[1] + t * d[1]]);
                moved[end] = true;
            }
        }
        if end == 0 {
            line.reverse();
        }
    }
    moved
}

/// Distance from `p` to the nearest of `sides`, mm.
fn boundary_distance(p: [f64; 2], sides: &[([f64; 2], [f64; 2])]) -> f64 {
    sides
        .iter()
        .map(|&(a, b)| {
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l2 = dx * dx + dy * dy;
            let t = if l2 > 0.0 {
                (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            dist(p, [a[0] + t * dx, a[1] + t * dy])
        })
        .fold(f64::INFINITY, f64::min)
}

/// Whether `p` is inside `shape` (even–odd over its contours).
fn inside(p: [f64; 2], shape: &Shape) -> bool {
    let mut odd = false;
    for c in shape {
        for i in 0..c.len() {
            let (a, b) = (c[i], c[(i + 1) % c.len()]);
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if x > p[0] {
                    odd = !odd;
                }
            }
        }
    }
    odd
}

/// `c` without the points within [`DUPLICATE`] of the point kept before them, and with every
/// edge longer than [`MAX_EDGE`] split evenly.
fn densify(c: &Contour) -> Contour {
    let mut c = c.clone();
    c.dedup_by(|p, q| dist(*p, *q) < DUPLICATE);
    while c.len() > 1 && dist(c[0], c[c.len() - 1]) < DUPLICATE {
        c.pop();
    }
    let mut out = Vec::with_capacity(c.len());
    for i in 0..c.len() {
        let (a, b) = (c[i], c[(i + 1) % c.len()]);
        let n = (dist(a, b) / MAX_EDGE).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    out
}

/// The chordal axis of `shape` as polylines (a closed one repeats its first point), spurs
/// shorter than `spur` dropped (see the module documentation), each with whether its first
/// and last point are free ends (terminal triangles).
fn chordal_axis(shape: &Shape, spur: f64) -> Vec<(Vec<[f64; 2]>, [bool; 2])> {
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut edges = Vec::new();
    for contour in shape {
        let mut handles = Vec::new();
        let c = densify(&simplify_closed(contour, RESOLUTION));
        edges.extend((0..c.len()).map(|i| (c[i], c[(i + 1) % c.len()])));
        for p in c {
            match cdt.insert(Point2::new(p[0], p[1])) {
                Ok(h) => handles.push(h),
                Err(_) => return Vec::new(), // a non-finite or huge coordinate: nothing to print
            }
        }
        handles.dedup();
        while handles.len() > 1 && handles.first() == handles.last() {
            handles.pop();
        }
        for i in 0..handles.len() {
            let (a, b) = (handles[i], handles[(i + 1) % handles.len()]);
            if a != b {
                cdt.try_add_constraint(a, b);
            }
        }
    }
    let mut is_inside = vec![false; cdt.num_all_faces()];
    for f in cdt.inner_faces() {
        let [a, b, c] = f.positions();
        let centroid = [(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0];
        is_inside[f.fix().index()] = inside(centroid, shape);
    }
    // the axis graph: a node per chord midpoint and per junction or terminal centroid
    let mut nodes: Vec<[f64; 2]> = Vec::new();
    let mut chord_node: HashMap<usize, usize> = HashMap::new();
    let mut links: Vec<(usize, usize)> = Vec::new();
    let mut centroids = Vec::new();
    for f in cdt.inner_faces() {
        if !is_inside[f.fix().index()] {
            continue;
        }
        let mut chords = Vec::with_capacity(3);
        for e in f.adjacent_edges() {
            let u = e.as_undirected();
            let across = e.rev().face().as_inner().map(|g| g.fix().index());
            if cdt.is_constraint_edge(u.fix()) || !across.is_some_and(|g| is_inside[g]) {
                continue;
            }
            let (p, q) = (e.from().position(), e.to().position());
            let mid = [(p.x + q.x) / 2.0, (p.y + q.y) / 2.0];
            if boundary_distance(mid, &edges) < MIN_THIN_WIDTH / 4.0 {
                continue;
            }
            let id = *chord_node.entry(u.fix().index()).or_insert_with(|| {
                nodes.push(mid);
                nodes.len() - 1
            });
            chords.push(id);
        }
        match chords.as_slice() {
            [a, b] => links.push((*a, *b)),
            [_] | [_, _, _] => {
                let [a, b, c] = f.positions();
                nodes.push([(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0]);
                let centre = nodes.len() - 1;
                centroids.push(centre);
                links.extend(chords.iter().map(|&m| (centre, m)));
            }
            _ => {}
        }
    }
    let mut is_centroid = vec![false; nodes.len()];
    for c in centroids {
        is_centroid[c] = true;
    }
    chains(&nodes, &is_centroid, &links, spur)
}

/// The graph's edges as polylines between nodes of degree ≠ 2 (and its cycles, closed),
/// without the spurs: chains shorter than `spur` from a node of degree 1 to one of degree ≥ 3,
/// removed until none is left: a junction with a branch that is not a spur loses its spurs,
/// one whose branches are all spurs keeps the two longest (which then join into one line).
/// A centroid (`is_centroid`) inside a line is left out of it. With each, whether its ends are nodes of degree 1.
fn chains(
    nodes: &[[f64; 2]],
    is_centroid: &[bool],
    links: &[(usize, usize)],
    spur: f64,
) -> Vec<(Vec<[f64; 2]>, [bool; 2])> {
    let mut alive = vec![true; links.len()];
    loop {
        let (paths, at) = walk_all(nodes, links, &alive);
        let length =
            |p: &[usize]| -> f64 { p.windows(2).map(|s| dist(nodes[s[0]], nodes[s[1]])).sum() };
        // spurs by their junction: a junction with a longer branch loses all its spurs (it is
        // then a free end, or a bend of one line); one whose branches are all spurs keeps the
        // two longest as one line
        let mut by_junction: HashMap<usize, Vec<(f64, &Vec<usize>)>> = HashMap::new();
        let mut long_branch: HashMap<usize, bool> = HashMap::new();
        for (p, ks) in &paths {
            let (a, b) = (p[0], p[p.len() - 1]);
            let (d0, d1) = (at[a].len(), at[b].len());
            let l = length(p);
            for (j, other) in [(a, d1), (b, d0)] {
                if at[j].len() < 3 {
                    continue;
                }
                if other == 1 && l < spur {
                    by_junction.entry(j).or_default().push((l, ks));
                } else {
                    long_branch.insert(j, true);
                }
            }
        }
        let mut pruned = false;
        for (j, mut spurs) in by_junction {
            if !long_branch.contains_key(&j) {
                spurs.sort_by(|x, y| y.0.total_cmp(&x.0));
                spurs.drain(..spurs.len().min(2));
            }
            for (_, ks) in spurs {
                for &k in ks {
                    alive[k] = false;
                }
                pruned = true;
            }
        }
        if pruned {
            continue;
        }
        {
            return paths
                .into_iter()
                .map(|(p, _)| {
                    let (first, last) = (p[0], p[p.len() - 1]);
                    let free = [at[first].len() == 1, at[last].len() == 1];
                    // a junction's centroid left inside a line lies off its middle (up to a
                    // sixth of the width): the line runs straight between the chords there
                    let keep =
                        |&(i, &n): &(usize, &usize)| i == 0 || i == p.len() - 1 || !is_centroid[n];
                    let line = p.iter().enumerate().filter(keep).map(|(_, &n)| nodes[n]);
                    (line.collect(), free)
                })
                .collect();
        }
    }
}

/// Every chain of the `alive` links (node list and link list), and each node's alive links.
type Walked = (Vec<(Vec<usize>, Vec<usize>)>, Vec<Vec<usize>>);

/// The alive links of the graph walked into chains between nodes of degree ≠ 2, then its
/// cycles (a cycle's node list repeats its first node).
fn walk_all(nodes: &[[f64; 2]], links: &[(usize, usize)], alive: &[bool]) -> Walked {
    let mut at: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for (k, &(a, b)) in links.iter().enumerate() {
        if alive[k] {
            at[a].push(k);
            at[b].push(k);
        }
    }
    let mut used: Vec<bool> = alive.iter().map(|a| !a).collect();
    let other = |k: usize, n: usize| {
        if links[k].0 == n {
            links[k].1
        } else {
            links[k].0
        }
    };
    let walk = |start: usize, first: usize, used: &mut Vec<bool>| {
        let (mut path, mut ks, mut n, mut k) = (vec![start], Vec::new(), start, first);
        loop {
            used[k] = true;
            ks.push(k);
            n = other(k, n);
            path.push(n);
            if at[n].len() != 2 {
                break;
            }
            match at[n].iter().find(|&&j| !used[j]) {
                Some(&j) => k = j,
                None => break,
            }
        }
        (path, ks)
    };
    let mut out = Vec::new();
    for (n, ks) in at.iter().enumerate() {
        if ks.len() == 2 {
            continue;
        }
        for &k in ks {
            if !used[k] {
                out.push(walk(n, k, &mut used));
            }
        }
    }
    for k in 0..links.len() {
        if !used[k] {
            out.push(walk(links[k].0, k, &mut used));
        }
    }
    (out, at)
}
