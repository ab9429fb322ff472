//! Colour: 8-bit sRGB, CIELAB (D65) and the colour prototypes of the histogram descriptors.
//!
//! Prágr22 §4.2 shrinks each cell colour to one of nine prototypes (its Fig. 5B/E is not in the
//! text; decision 6 fixes them). A colour maps to the prototype nearest in CIELAB (ΔE76). The
//! Prágr23 8-bin histogram uses the first eight prototypes.

use serde::{Deserialize, Serialize};

/// An 8-bit sRGB colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Rgb8(pub [u8; 3]);

impl Rgb8 {
    /// A colour from its channels.
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        Self([r, g, b])
    }
}

/// A CIELAB colour (D65 white point): L in [0, 100], a and b roughly in [−128, 127].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Lab {
    /// Lightness.
    pub l: f32,
    /// Green (−) to red (+).
    pub a: f32,
    /// Blue (−) to yellow (+).
    pub b: f32,
}

impl Lab {
    /// ΔE76: Euclidean distance in CIELAB.
    pub fn delta_e76(self, o: Lab) -> f32 {
        let (dl, da, db) = (self.l - o.l, self.a - o.a, self.b - o.b);
        (dl * dl + da * da + db * db).sqrt()
    }
}

/// IEC 61966-2-1 decoding of one 8-bit channel to linear light.
fn srgb_decode(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// [`srgb_decode`] of every 8-bit value, built once: the decoding's `powf` was the bulk of
/// [`rgb_to_lab`], which runs for every map cell at every learning update.
static SRGB_LINEAR: std::sync::LazyLock<[f32; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|c| srgb_decode(c as u8)));

#[inline]
fn srgb_to_linear(c: u8) -> f32 {
    SRGB_LINEAR[c as usize]
}

#[inline]
fn lab_f(t: f32) -> f32 {
    const D: f32 = 6.0 / 29.0;
    if t > D * D * D {
        t.cbrt()
    } else {
        t / (3.0 * D * D) + 4.0 / 29.0
    }
}

/// Converts sRGB to CIELAB with the D65 reference white (IEC 61966-2-1, CIE 1976).
pub fn rgb_to_lab(c: Rgb8) -> Lab {
    let [r, g, b] = c.0.map(srgb_to_linear);
    let x = 0.412_456_4 * r + 0.357_576_1 * g + 0.180_437_5 * b;
    let y = 0.212_672_9 * r + 0.715_152_2 * g + 0.072_175 * b;
    let z = 0.019_333_9 * r + 0.119_192 * g + 0.950_304_1 * b;
    let (xn, yn, zn) = (0.950_47, 1.0, 1.088_83);
    let (fx, fy, fz) = (lab_f(x / xn), lab_f(y / yn), lab_f(z / zn));
    Lab {
        l: 116.0 * fy - 16.0,
        a: 500.0 * (fx - fy),
        b: 200.0 * (fy - fz),
    }
}

/// The nine colour prototypes of decision 6, in descriptor-bin order.
pub const COLOR_PROTOTYPES: [(&str, Rgb8); 9] = [
    ("white", Rgb8::new(240, 240, 240)),
    ("black", Rgb8::new(20, 20, 20)),
    ("gray", Rgb8::new(128, 128, 128)),
    ("red", Rgb8::new(190, 40, 40)),
    ("green", Rgb8::new(50, 150, 50)),
    ("blue", Rgb8::new(40, 70, 190)),
    ("brown", Rgb8::new(130, 90, 50)),
    ("yellow", Rgb8::new(220, 200, 50)),
    ("magenta", Rgb8::new(170, 60, 170)),
];

/// Maps colours to the nearest of the first `n` prototypes in CIELAB (ΔE76). Build once: it
/// caches the prototypes' Lab values.
#[derive(Clone, Debug)]
pub struct PrototypeQuantizer {
    labs: Vec<Lab>,
}

impl PrototypeQuantizer {
    /// A quantizer over the first `n` (1..=9) prototypes of [`COLOR_PROTOTYPES`].
    pub fn new(n: usize) -> Self {
        let n = n.clamp(1, COLOR_PROTOTYPES.len());
        Self {
            labs: COLOR_PROTOTYPES[..n]
                .iter()
                .map(|&(_, c)| rgb_to_lab(c))
                .collect(),
        }
    }
    /// Number of prototypes (histogram bins).
    pub fn bins(&self) -> usize {
        self.labs.len()
    }
    /// Index of the prototype nearest to `lab` (ties: the lower index).
    pub fn nearest_lab(&self, lab: Lab) -> usize {
        // Squared ΔE76: the same order without a square root per prototype.
        let mut best = (0, f32::INFINITY);
        for (k, p) in self.labs.iter().enumerate() {
            let (dl, da, db) = (lab.l - p.l, lab.a - p.a, lab.b - p.b);
            let d = dl * dl + da * da + db * db;
            if d < best.1 {
                best = (k, d);
            }
        }
        best.0
    }
    /// Index of the prototype nearest to `c`.
    pub fn nearest(&self, c: Rgb8) -> usize {
        self.nearest_lab(rgb_to_lab(c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn lab_reference_values() {
        // Reference values from the CIE definitions (D65): white, black, pure red.
        let w = rgb_to_lab(Rgb8::new(255, 255, 255));
        assert_abs_diff_eq!(w.l, 100.0, epsilon = 0.01);
        assert_abs_diff_eq!(w.a, 0.0, epsilon = 0.01);
        assert_abs_diff_eq!(w.b, 0.0, epsilon = 0.01);
        let k = rgb_to_lab(Rgb8::new(0, 0, 0));
        assert_abs_diff_eq!(k.l, 0.0, epsilon = 1e-4);
        let r = rgb_to_lab(Rgb8::new(255, 0, 0));
        assert_abs_diff_eq!(r.l, 53.24, epsilon = 0.05);
        assert_abs_diff_eq!(r.a, 80.09, epsilon = 0.05);
        assert_abs_diff_eq!(r.b, 67.20, epsilon = 0.05);
    }

    /// The table-driven conversion against a direct f64 evaluation of IEC 61966-2-1 and
    /// CIE 1976 over a lattice of colours (every channel value appears).
    #[test]
    fn lab_matches_a_direct_evaluation() {
        let lin = |c: u8| {
            let c = c as f64 / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        let f = |t: f64| {
            let d = 6.0 / 29.0;
            if t > d * d * d {
                t.cbrt()
            } else {
                t / (3.0 * d * d) + 4.0 / 29.0
            }
        };
        for r in (0..=255u8).step_by(3) {
            for (g, b) in [(r, 255 - r), (0, r), (r / 2, 17), (200, r)] {
                let (lr, lg, lb) = (lin(r), lin(g), lin(b));
                let x = 0.4124564 * lr + 0.3575761 * lg + 0.1804375 * lb;
                let y = 0.2126729 * lr + 0.7151522 * lg + 0.0721750 * lb;
                let z = 0.0193339 * lr + 0.1191920 * lg + 0.9503041 * lb;
                let (fx, fy, fz) = (f(x / 0.95047), f(y), f(z / 1.08883));
                let lab = rgb_to_lab(Rgb8::new(r, g, b));
                assert_abs_diff_eq!(lab.l as f64, 116.0 * fy - 16.0, epsilon = 1e-3);
                assert_abs_diff_eq!(lab.a as f64, 500.0 * (fx - fy), epsilon = 1e-3);
                assert_abs_diff_eq!(lab.b as f64, 200.0 * (fy - fz), epsilon = 1e-3);
            }
        }
    }

    #[test]
    fn prototypes_map_to_themselves() {
        let q = PrototypeQuantizer::new(9);
        for (k, &(_, c)) in COLOR_PROTOTYPES.iter().enumerate() {
            assert_eq!(q.nearest(c), k);
        }
        assert_eq!(q.nearest(Rgb8::new(60, 160, 60)), 4);
        assert_eq!(PrototypeQuantizer::new(8).bins(), 8);
    }
}
