//! Shading (step 4 of the module docs of [`super`]): the surface colour
//! source, the Blinn-Phong shader and the sRGB conversions.

use super::{Projected, RenderError, RenderOptions, ShadeVertex, VertexValues};
use trigbody_core::{Mesh, Real};

/// Linear-light value of an sRGB channel.
pub(super) fn srgb_to_linear(v: u8) -> f32 {
    let s = v as f32 / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// Table for linear light → sRGB byte (4096 steps over `[0, 1]`).
pub(super) struct SrgbEncoder {
    table: Vec<u8>,
}

impl SrgbEncoder {
    const STEPS: usize = 4096;
    pub(super) fn new() -> Self {
        let table = (0..=Self::STEPS)
            .map(|i| {
                let l = i as f32 / Self::STEPS as f32;
                let s = if l <= 0.003_130_8 {
                    12.92 * l
                } else {
                    1.055 * l.powf(1.0 / 2.4) - 0.055
                };
                (s * 255.0).round().clamp(0.0, 255.0) as u8
            })
            .collect();
        SrgbEncoder { table }
    }
    #[inline]
    pub(super) fn encode(&self, l: f32) -> u8 {
        let i = (l.clamp(0.0, 1.0) * Self::STEPS as f32 + 0.5) as usize;
        self.table[i.min(Self::STEPS)]
    }
}

/// What colours the surface.
pub(super) enum Paint<'a> {
    Uniform([f32; 3]),
    Values {
        values: &'a [Real],
        min: Real,
        max: Real,
        /// The colormap in linear light, 256 entries.
        table: Vec<[f32; 3]>,
    },
}

/// sRGB grey level of the surface where a vertex has no value (NaN).
pub(super) const NO_VALUE_GREY: u8 = 150;

/// Shading constants of one render.
pub(super) struct Shader<'a> {
    pub(super) light: [f32; 3],
    pub(super) half: [f32; 3],
    pub(super) ambient: f32,
    pub(super) diffuse: f32,
    pub(super) specular: f32,
    pub(super) shininess: f32,
    pub(super) paint: Paint<'a>,
    pub(super) no_value: [f32; 3],
    /// [`RenderOptions::value_shading`] when painting values, else 1.
    pub(super) shading: f32,
    /// `n·H` below which the highlight `(n·H)^shininess` is under 10⁻⁴
    /// (skipped: it would not change an 8-bit colour).
    pub(super) highlight_cutoff: f32,
}

#[inline]
fn dot3(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn sub3(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn cross3(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Shader<'_> {
    /// Linear-light colour of triangle `t` at the sample-space point
    /// `(sx, sy)` (step 4 of the module docs).
    pub(super) fn shade(&self, mesh: &Mesh, p: &Projected, t: usize, sx: f32, sy: f32) -> [f32; 3] {
        let [i0, i1, i2] = mesh.triangles[t].map(|i| i as usize);
        // Barycentric coordinates from the float corners, clamped so a
        // pixel centre just outside the triangle does not extrapolate.
        let (v0, v1, v2) = (&p.shade[i0], &p.shade[i1], &p.shade[i2]);
        let (ax, ay) = (v0.x, v0.y);
        let (bx, by) = (v1.x, v1.y);
        let (cx, cy) = (v2.x, v2.y);
        let area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
        let mut l1 = ((cx - ax) * (sy - ay) - (cy - ay) * (sx - ax)) / -area;
        let mut l2 = ((bx - ax) * (sy - ay) - (by - ay) * (sx - ax)) / area;
        if !(l1.is_finite() && l2.is_finite()) {
            (l1, l2) = (1.0 / 3.0, 1.0 / 3.0);
        }
        l1 = l1.clamp(0.0, 1.0);
        l2 = l2.clamp(0.0, 1.0);
        let s = l1 + l2;
        if s > 1.0 {
            l1 /= s;
            l2 /= s;
        }
        let l0 = 1.0 - l1 - l2;
        let (n0, n1, n2) = (v0.normal, v1.normal, v2.normal);
        let mut n = [
            l0 * n0[0] + l1 * n1[0] + l2 * n2[0],
            l0 * n0[1] + l1 * n1[1] + l2 * n2[1],
            l0 * n0[2] + l1 * n1[2] + l2 * n2[2],
        ];
        // The face normal in camera space (y up, so screen y is negated).
        let corner = |v: &ShadeVertex| [v.x, -v.y, -v.depth];
        let (a, b, c) = (corner(v0), corner(v1), corner(v2));
        let g = cross3(sub3(b, a), sub3(c, a));
        let nsum = [
            n0[0] + n1[0] + n2[0],
            n0[1] + n1[1] + n2[1],
            n0[2] + n1[2] + n2[2],
        ];
        // The viewer is on the side of the plane where g·(0,0,1) = g_z
        // points; flip the normals if they point to the other side.
        if dot3(nsum, g) * g[2] < 0.0 {
            n = [-n[0], -n[1], -n[2]];
        }
        let len = dot3(n, n).sqrt();
        let n = if len > 1e-12 {
            [n[0] / len, n[1] / len, n[2] / len]
        } else {
            [0.0, 0.0, 1.0]
        };
        let albedo = match &self.paint {
            Paint::Uniform(c) => *c,
            Paint::Values {
                values,
                min,
                max,
                table,
            } => {
                let v = l0 as Real * values[i0] + l1 as Real * values[i1] + l2 as Real * values[i2];
                if v.is_nan() {
                    self.no_value
                } else {
                    let u = ((v - min) / (max - min)).clamp(0.0, 1.0);
                    table[(u * (table.len() - 1) as Real).round() as usize]
                }
            }
        };
        let lambert = dot3(n, self.light).max(0.0);
        let k = 1.0 - self.shading + self.shading * (self.ambient + self.diffuse * lambert);
        let spec = if self.specular > 0.0 {
            let nh = dot3(n, self.half);
            if nh > self.highlight_cutoff {
                self.shading * self.specular * nh.powf(self.shininess)
            } else {
                0.0
            }
        } else {
            0.0
        };
        [
            albedo[0] * k + spec,
            albedo[1] * k + spec,
            albedo[2] * k + spec,
        ]
    }
}

/// The surface colour source, with the values checked against the mesh.
pub(super) fn paint<'a>(
    mesh: &Mesh,
    values: Option<&VertexValues<'a>>,
    options: &RenderOptions,
) -> Result<Paint<'a>, RenderError> {
    let Some(v) = values else {
        return Ok(Paint::Uniform(options.color.map(srgb_to_linear)));
    };
    if v.values.len() != mesh.positions.len() {
        return Err(RenderError::ValueCount {
            values: v.values.len(),
            vertices: mesh.positions.len(),
        });
    }
    let (min, max) = v.range;
    if !(min.is_finite() && max.is_finite() && min < max && (max - min).is_finite()) {
        return Err(RenderError::BadRange { min, max });
    }
    let table = (0..256)
        .map(|i| v.colormap.color(i as Real / 255.0).map(srgb_to_linear))
        .collect();
    Ok(Paint::Values {
        values: v.values,
        min,
        max,
        table,
    })
}
