//! Perceptual colormaps for scalar fields on a surface (distance maps).
//!
//! A colormap sends a number `t ∈ [0, 1]` to a colour. A *perceptual* one
//! changes lightness steadily with `t`, so equal steps in value look like
//! equal steps in colour, the order of values can be read off a greyscale
//! print, and the map is legible to the common forms of colour blindness.

use trigbody_core::Real;

/// An RGB colour, 8 bits per channel, sRGB-encoded.
pub type Rgb = [u8; 3];

/// The colormaps the renderer knows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Colormap {
    /// Viridis (van der Walt & Smith, 2015; released CC0 with matplotlib):
    /// dark blue-violet → teal → green → yellow, lightness rising
    /// monotonically. The default.
    #[default]
    Viridis,
    /// Grey ramp from black to white (lightness only), for prints.
    Grey,
}

/// Viridis sampled at ten equally spaced `t = 0, 1/9, …, 1`; between the
/// samples the map is interpolated linearly in sRGB. Ten samples keep every
/// interpolated colour within a few levels of the full 256-entry table,
/// well below what a reader can tell apart on a surface.
const VIRIDIS: [Rgb; 10] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x28, 0x78],
    [0x3e, 0x4a, 0x89],
    [0x31, 0x68, 0x8e],
    [0x26, 0x82, 0x8e],
    [0x1f, 0x9e, 0x89],
    [0x35, 0xb7, 0x79],
    [0x6d, 0xcd, 0x59],
    [0xb4, 0xde, 0x2c],
    [0xfd, 0xe7, 0x25],
];

impl Colormap {
    /// The colour at `t`, clamped to `[0, 1]`; NaN gives the colour at 0.
    pub fn color(self, t: Real) -> Rgb {
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        match self {
            Colormap::Viridis => interpolate(&VIRIDIS, t),
            Colormap::Grey => {
                let v = (t * 255.0).round() as u8;
                [v, v, v]
            }
        }
    }
}

/// Piecewise-linear interpolation through equally spaced `stops`.
fn interpolate(stops: &[Rgb], t: Real) -> Rgb {
    let last = stops.len() - 1;
    let x = t * last as Real;
    let i = (x.floor() as usize).min(last.saturating_sub(1));
    let f = x - i as Real;
    let (a, b) = (stops[i], stops[(i + 1).min(last)]);
    let mix = |a: u8, b: u8| (a as Real + (b as Real - a as Real) * f).round() as u8;
    [mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2])]
}

/// Relative luminance of an sRGB colour (ITU-R BT.709 weights on the
/// linearized channels), in `[0, 1]`.
pub fn luminance(c: Rgb) -> Real {
    let lin = |v: u8| {
        let s = v as Real / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * lin(c[0]) + 0.7152 * lin(c[1]) + 0.0722 * lin(c[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_samples() {
        assert_eq!(Colormap::Viridis.color(0.0), VIRIDIS[0]);
        assert_eq!(Colormap::Viridis.color(1.0), VIRIDIS[9]);
        assert_eq!(Colormap::Viridis.color(5.0 / 9.0), VIRIDIS[5]);
        assert_eq!(Colormap::Viridis.color(-3.0), VIRIDIS[0]);
        assert_eq!(Colormap::Viridis.color(7.0), VIRIDIS[9]);
        assert_eq!(Colormap::Viridis.color(Real::NAN), VIRIDIS[0]);
    }

    #[test]
    fn lightness_rises_monotonically() {
        for map in [Colormap::Viridis, Colormap::Grey] {
            let mut previous = -1.0;
            for i in 0..=200 {
                let l = luminance(map.color(i as Real / 200.0));
                assert!(l >= previous, "{map:?} at {i}: {l} < {previous}");
                previous = l;
            }
        }
    }
}
