//! A bounded sample of pass 1's object extrusions, layer by layer, for the fine registration
//! ([`super::refine`]). Memory stays bounded whatever the file's size: at most
//! [`SAMPLE_CAP`] segments are kept; when more come, every other kept layer is dropped and
//! only every `stride`-th layer is taken from then on (the stride doubles each time).

use glam::DVec2;

/// Most extrusion segments kept in the sample (≈ 40 bytes each).
pub const SAMPLE_CAP: usize = 200_000;

/// One extruding segment in G-code XY (mm), the source line and whether the slicer typed it
/// an outer wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seg {
    /// Start, G-code frame, mm.
    pub a: DVec2,
    /// End, G-code frame, mm.
    pub b: DVec2,
    /// 1-based source line.
    pub line: u64,
}

/// The segments of one slicer layer.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LayerSample {
    /// The slicer's layer index.
    pub layer: u32,
    /// z of the layer's extrusions (the first one's), G-code frame, mm.
    pub z: f64,
    /// Its object extrusions.
    pub segs: Vec<Seg>,
}

/// The sample (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct Sample {
    layers: Vec<LayerSample>,
    stride: u32,
    count: usize,
}

impl Sample {
    /// An empty sample.
    pub fn new() -> Sample {
        Sample {
            layers: Vec::new(),
            stride: 1,
            count: 0,
        }
    }

    /// Keep an object extrusion of `layer` at height `z` from `a` to `b` (G-code XY).
    pub fn push(&mut self, layer: u32, z: f64, a: DVec2, b: DVec2, line: u64) {
        if !layer.is_multiple_of(self.stride) {
            return;
        }
        match self.layers.last_mut() {
            Some(l) if l.layer == layer => l.segs.push(Seg { a, b, line }),
            _ => self.layers.push(LayerSample {
                layer,
                z,
                segs: vec![Seg { a, b, line }],
            }),
        }
        self.count += 1;
        while self.count > SAMPLE_CAP && self.stride < u32::MAX / 2 {
            self.stride *= 2;
            let stride = self.stride;
            self.layers.retain(|l| l.layer % stride == 0);
            self.count = self.layers.iter().map(|l| l.segs.len()).sum();
        }
    }

    /// The layers kept, in file order.
    pub fn layers(&self) -> &[LayerSample] {
        &self.layers
    }

    /// Drop the segments of these source-line ranges (skirt runs found by geometry) and of
    /// lines before `first` (extrusions before the first `;TYPE:` in a typed file).
    pub fn retain_lines(&mut self, first: u64, skirt: &[[u64; 2]]) {
        for l in &mut self.layers {
            l.segs.retain(|s| {
                s.line >= first && !skirt.iter().any(|r| r[0] <= s.line && s.line <= r[1])
            });
        }
        self.layers.retain(|l| !l.segs.is_empty());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sample_stays_under_its_cap_and_keeps_every_stride_th_layer() {
        let mut s = Sample::new();
        for layer in 0..2_000u32 {
            for i in 0..1_000 {
                let a = DVec2::new(i as f64, 0.0);
                s.push(layer, layer as f64 * 0.2, a, a + DVec2::X, 1);
            }
        }
        let n: usize = s.layers().iter().map(|l| l.segs.len()).sum();
        assert!(n <= SAMPLE_CAP, "{n}");
        assert!(s.layers().len() >= 100, "{}", s.layers().len());
        let stride = s.layers()[1].layer - s.layers()[0].layer;
        assert!(s
            .layers()
            .windows(2)
            .all(|w| w[1].layer - w[0].layer == stride));
    }
}
