//! A minimal SVG line plot (no dependencies): panels with a framed data box, min/max tick labels
//! and polylines. Numbers are written with `format!` (deterministic on every target).

use core::fmt::Write;

/// One polyline of a panel, in data coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// The vertices as [x, y] in data units, drawn in order.
    pub points: Vec<[f64; 2]>,
    /// SVG colour, e.g. `"green"`.
    pub color: String,
    /// Legend text.
    pub label: String,
}

/// One panel: title, axis labels, curves; `equal` keeps one data unit the same length on both
/// axes (a top view).
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Heading drawn above the panel (XML-escaped when rendered).
    pub title: String,
    /// Label of the horizontal axis, with its unit.
    pub x_label: String,
    /// Label of the vertical axis, with its unit.
    pub y_label: String,
    /// The polylines drawn in the panel's data box.
    pub curves: Vec<Curve>,
    /// Same scale on both axes (one data unit is as long in x as in y), for top views.
    pub equal: bool,
}

/// Panel size in pixels.
const W: f64 = 460.0;
const H: f64 = 400.0;
const MARGIN: f64 = 60.0;

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Render panels side by side.
pub fn render(panels: &[Panel]) -> String {
    let total_w = W * panels.len().max(1) as f64;
    let mut s = String::new();
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{total_w}\" height=\"{H}\" viewBox=\"0 0 {total_w} {H}\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (k, p) in panels.iter().enumerate() {
        panel(&mut s, p, W * k as f64);
    }
    s.push_str("</svg>\n");
    s
}

fn panel(s: &mut String, p: &Panel, x0: f64) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for c in &p.curves {
        for q in &c.points {
            if q[0].is_finite() && q[1].is_finite() {
                for k in 0..2 {
                    lo[k] = lo[k].min(q[k]);
                    hi[k] = hi[k].max(q[k]);
                }
            }
        }
    }
    if !(lo[0] <= hi[0]) {
        lo = [0.0, 0.0];
        hi = [1.0, 1.0];
    }
    for k in 0..2 {
        let pad = ((hi[k] - lo[k]) * 0.05).max(1e-6);
        lo[k] -= pad;
        hi[k] += pad;
    }
    let (bw, bh) = (W - 1.5 * MARGIN, H - 2.0 * MARGIN);
    let mut sx = bw / (hi[0] - lo[0]);
    let mut sy = bh / (hi[1] - lo[1]);
    if p.equal {
        let m = sx.min(sy);
        sx = m;
        sy = m;
    }
    let bx = x0 + MARGIN;
    let by = MARGIN;
    let px = |x: f64| bx + (x - lo[0]) * sx;
    let py = |y: f64| by + bh - (y - lo[1]) * sy;
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"20\" font-size=\"13\">{}</text>",
        bx,
        esc(&p.title)
    );
    let _ = writeln!(
        s,
        "<rect x=\"{bx:.1}\" y=\"{by:.1}\" width=\"{bw:.1}\" height=\"{bh:.1}\" fill=\"none\" stroke=\"#888\"/>"
    );
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\">{:.4}</text><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{:.4}</text>",
        bx,
        by + bh + 14.0,
        lo[0],
        bx + bw,
        by + bh + 14.0,
        hi[0]
    );
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{:.4}</text><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{:.4}</text>",
        bx - 4.0,
        by + bh,
        lo[1],
        bx - 4.0,
        by + 10.0,
        hi[1]
    );
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
        bx + bw / 2.0,
        by + bh + 30.0,
        esc(&p.x_label)
    );
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" transform=\"rotate(-90 {:.1} {:.1})\" text-anchor=\"middle\">{}</text>",
        bx - 40.0,
        by + bh / 2.0,
        bx - 40.0,
        by + bh / 2.0,
        esc(&p.y_label)
    );
    for (i, c) in p.curves.iter().enumerate() {
        let mut d = String::new();
        for q in c
            .points
            .iter()
            .filter(|q| q[0].is_finite() && q[1].is_finite())
        {
            let _ = write!(d, "{:.2},{:.2} ", px(q[0]), py(q[1]));
        }
        let _ = writeln!(
            s,
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"/>",
            d.trim_end(),
            esc(&c.color)
        );
        let ly = by + bh + 44.0 + 0.0 * i as f64;
        let lx = bx + 150.0 * i as f64;
        let _ = writeln!(
            s,
            "<line x1=\"{lx:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{}\" stroke-width=\"2\"/><text x=\"{:.1}\" y=\"{ly:.1}\">{}</text>",
            ly - 4.0,
            lx + 20.0,
            ly - 4.0,
            esc(&c.color),
            lx + 24.0,
            esc(&c.label)
        );
    }
}
