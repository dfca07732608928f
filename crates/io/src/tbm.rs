//! The compact binary model file (`.tbm`, docs/model-format.md "The
//! compact binary model"): the same model as the JSON file in fewer numbers
//! and bytes, within a stated error bound.
//!
//! * **Frames in 3 numbers.** A section's plane is predicted from the one
//!   before: its normal is stored as two small components `(p, q)` in the
//!   previous section's axes, its offset as the height `h` of the plane
//!   above the previous curve's centre, and its in-plane axes are the
//!   previous ones projected onto the new plane (a discrete
//!   rotation-minimizing frame). The rotation and the in-plane offset
//!   between the fitted frame and this one are carried by the
//!   coefficients (an exact change of basis of the same world curve). Only
//!   each part's first frame is stored whole (9 numbers: its origin on the
//!   grid of `step`, its axes' components on the grid of `step / ρ`, the
//!   axes made orthonormal again on reading; version 1 stored them as
//!   doubles, 72 bytes a part that zstd hardly shrinks).
//! * **Quantized.** Coefficients and `h` on a uniform grid of `step`
//!   (model units), `p`, `q` of `step / ρ` (`ρ` the largest distance of a
//!   curve point from its section origin). Prediction is closed-loop (the
//!   encoder predicts from the decoded previous section), so errors do not
//!   accumulate along a part.
//! * **Entropy coded** with zstd: zig-zag varints grouped by kind and by
//!   coefficient index (small high harmonics together).
//!
//! The rest (part names, skinning options, caps, transitions, the body
//! frame) is the JSON document without its sections, compressed in the same
//! zstd frame; reading rebuilds the JSON document and validates it with the
//! JSON reader, so every check of that reader applies.

use crate::model::{model_of_value, model_record, Model, ModelError};
use serde_json::{json, Value};
use std::io::Read;
use thiserror::Error;
use trigbody_core::{Frame, Point3, Real, TrigCurve, Vec3};

/// The first bytes of every compact model file.
pub const TBM_MAGIC: &[u8; 3] = b"TBM";
/// The compact format version this build writes (and the newest it
/// reads; version 1, first frames as doubles, is read too).
pub const TBM_VERSION: u8 = 2;
/// The default quantization step, as a fraction of the body's height (or
/// of the section origins' bounding-box diagonal): 0.035 mm on 1.73 m.
pub const DEFAULT_RELATIVE_STEP: Real = 2e-5;
/// The largest decompressed payload a reader accepts (a guard against
/// corrupt sizes; a body model's payload is a few tens of kilobytes).
const MAX_PAYLOAD: u64 = 64 << 20;
/// The largest curve order a reader accepts.
const MAX_ORDER: u64 = 1024;

/// How [`encode_tbm`] quantizes and compresses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TbmOptions {
    /// Quantization step in the model's units. Default `None`:
    /// [`DEFAULT_RELATIVE_STEP`] × the body's height.
    pub step: Option<Real>,
    /// zstd compression level (1-22). Default 19.
    pub level: i32,
}

impl Default for TbmOptions {
    fn default() -> Self {
        TbmOptions {
            step: None,
            level: 19,
        }
    }
}

/// What [`encode_tbm`] wrote.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TbmStats {
    /// The file's size.
    pub bytes: usize,
    /// Numbers stored for the sections (frames and coefficients).
    pub section_numbers: usize,
    /// The quantization step (model units).
    pub step: Real,
    /// The stated bound on any section curve point's displacement (model
    /// units): the largest over the sections of the docs' formula.
    pub bound: Real,
    /// The largest displacement measured (256 samples per curve).
    pub max_error: Real,
    /// The order-0 entropy of the quantized integers, all in one alphabet,
    /// in bytes (what a static-model entropy coder would need at best,
    /// without its tables).
    pub entropy_bytes: Real,
    /// The same with one alphabet per stream kind and coefficient index
    /// (the conditional entropy; what per-index adaptive models approach).
    pub entropy_by_index_bytes: Real,
    /// The zstd-compressed skeleton and integers (the file less its header).
    pub zstd_bytes: usize,
}

/// What is wrong with a compact model file, or why a model cannot be
/// written compactly.
#[derive(Debug, Error)]
pub enum TbmError {
    /// The bytes do not start with `TBM`.
    #[error("not a compact trigbody model (the file does not start with \"TBM\")")]
    NotTbm,
    /// A version this build does not read.
    #[error("compact model version {0} is not supported (this build reads version {TBM_VERSION})")]
    UnknownVersion(u8),
    /// Truncated or damaged content.
    #[error("corrupt or truncated compact model: {0}")]
    Corrupt(String),
    /// The rebuilt model document is not a valid model.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A model the format cannot hold.
    #[error("cannot write part '{part}' compactly: {why}")]
    Unsupported {
        /// The part's name.
        part: String,
        /// Why.
        why: String,
    },
}

fn corrupt(what: impl Into<String>) -> TbmError {
    TbmError::Corrupt(what.into())
}

/// The previous section as the decoder knows it.
#[derive(Clone, Copy)]
struct State {
    centre: Point3,
    normal: Vec3,
    e1: Vec3,
}

impl State {
    fn of(frame: &Frame, a0: Real, b0: Real) -> Option<State> {
        Some(State {
            centre: frame.origin + frame.e1 * a0 + frame.e2 * b0,
            normal: frame.e1.cross(frame.e2).normalized()?,
            e1: frame.e1,
        })
    }

    fn e2(&self) -> Vec3 {
        self.normal.cross(self.e1)
    }

    /// The normal of components `p`, `q` along the previous axes.
    fn next_normal(&self, p: Real, q: Real) -> Option<Vec3> {
        let r2 = 1.0 - p * p - q * q;
        if !(r2 > 0.0) {
            return None;
        }
        (self.e1 * p + self.e2() * q + self.normal * r2.sqrt()).normalized()
    }

    /// The frame of normal `n` at height `h` above the previous centre,
    /// its axes the previous ones projected onto the plane.
    fn next_frame(&self, n: Vec3, h: Real) -> Option<Frame> {
        let e1 = (self.e1 - n * self.e1.dot(n)).normalized()?;
        let origin = self.centre + n * h;
        origin.is_finite().then(|| Frame {
            origin,
            e1,
            e2: n.cross(e1),
        })
    }
}

/// The coefficients of the same world curve in another frame of (nearly)
/// the same plane (the part out of `to`'s plane is dropped).
fn rebase(c: &TrigCurve, to: &Frame) -> (Vec<Real>, Vec<Real>) {
    let f = &c.frame;
    let (c11, c21, c12, c22) = (
        f.e1.dot(to.e1),
        f.e2.dot(to.e1),
        f.e1.dot(to.e2),
        f.e2.dot(to.e2),
    );
    let d = f.origin - to.origin;
    let (mut a, mut b) = (vec![0.0; c.a.len()], vec![0.0; c.b.len()]);
    a[0] = d.dot(to.e1) + c.a[0] * c11 + c.b[0] * c21;
    b[0] = d.dot(to.e2) + c.a[0] * c12 + c.b[0] * c22;
    for j in 1..=c.order() {
        let (ac, as_, bs, bc) = (c.a[2 * j - 1], c.a[2 * j], c.b[2 * j - 1], c.b[2 * j]);
        a[2 * j - 1] = c11 * ac + c21 * bc;
        a[2 * j] = c11 * as_ + c21 * bs;
        b[2 * j - 1] = c12 * as_ + c22 * bs;
        b[2 * j] = c12 * ac + c22 * bc;
    }
    (a, b)
}

/// One part's sections as integers: orders, the first frame, `(p, q, h)`
/// per later section, coefficients.
#[derive(Default)]
struct PartCode {
    orders: Vec<u64>,
    /// The first frame: origin on the grid of `step`, `e1`, `e2` on the
    /// grid of `angle`.
    first: [i64; 9],
    pqh: Vec<[i64; 3]>,
    a: Vec<Vec<i64>>,
    b: Vec<Vec<i64>>,
}

struct Steps {
    step: Real,
    angle: Real,
}

fn quantize(x: Real, step: Real) -> Option<i64> {
    let q = (x / step).round();
    (q.abs() < 4.0e15).then_some(q as i64)
}

fn dequantize(q: &[i64], step: Real) -> Vec<Real> {
    q.iter().map(|&i| i as Real * step).collect()
}

/// A part's first frame from its quantized numbers (version 2): the
/// origin, and the axes made orthonormal again (Gram-Schmidt, `e1`
/// first).
fn first_frame(q: &[i64; 9], s: &Steps) -> Option<Frame> {
    let v = |i: usize, step: Real| {
        Vec3::new(
            q[i] as Real * step,
            q[i + 1] as Real * step,
            q[i + 2] as Real * step,
        )
    };
    let e1 = v(3, s.angle).normalized()?;
    let e2 = v(6, s.angle);
    let e2 = (e2 - e1 * e2.dot(e1)).normalized()?;
    let origin = v(0, s.step);
    origin.is_finite().then_some(Frame { origin, e1, e2 })
}

/// The largest distance of a section's curve from its origin (upper bound
/// from the coefficients).
fn reach(c: &TrigCurve) -> Real {
    let x: Real = c.a.iter().map(|v| v.abs()).sum();
    let y: Real = c.b.iter().map(|v| v.abs()).sum();
    x.hypot(y)
}

fn max_displacement(a: &TrigCurve, b: &TrigCurve) -> Real {
    let (pa, pb) = (a.sample(256), b.sample(256));
    pa.iter()
        .zip(&pb)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, Real::max)
}

/// Encodes one part (closed loop), returning its code, its decoded curves'
/// largest measured displacement and the stated bound.
fn encode_part(
    name: &str,
    curves: &[TrigCurve],
    s: &Steps,
    rho: Real,
) -> Result<(PartCode, Real, Real), TbmError> {
    let unsupported = |why: String| TbmError::Unsupported {
        part: name.to_string(),
        why,
    };
    let q_all = |v: &[Real], k: usize| -> Result<Vec<i64>, TbmError> {
        v.iter()
            .map(|&x| quantize(x, s.step))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| unsupported(format!("section {k}: a coefficient is out of range")))
    };
    let mut code = PartCode::default();
    let (mut max_err, mut bound): (Real, Real) = (0.0, 0.0);
    let mut state: Option<State> = None;
    for (k, c) in curves.iter().enumerate() {
        code.orders.push(c.order() as u64);
        let frame = match state {
            None => {
                let f = c.frame;
                for (i, (v, step)) in [(f.origin, s.step), (f.e1, s.angle), (f.e2, s.angle)]
                    .iter()
                    .enumerate()
                {
                    for (j, x) in v.to_array().iter().enumerate() {
                        code.first[3 * i + j] = quantize(*x, *step).ok_or_else(|| {
                            unsupported("the first frame is out of range".to_string())
                        })?;
                    }
                }
                first_frame(&code.first, s)
                    .ok_or_else(|| unsupported("a degenerate first frame".to_string()))?
            }
            Some(st) => {
                let n = c.frame.e1.cross(c.frame.e2);
                if !(n.dot(st.normal) > 0.1) {
                    return Err(unsupported(format!(
                        "section {k} turns by more than 84° from the one before"
                    )));
                }
                let p = quantize(n.dot(st.e1), s.angle);
                let q = quantize(n.dot(st.e2()), s.angle);
                let (Some(p), Some(q)) = (p, q) else {
                    return Err(unsupported(format!("section {k}: normal out of range")));
                };
                let nn = st
                    .next_normal(p as Real * s.angle, q as Real * s.angle)
                    .ok_or_else(|| unsupported(format!("section {k}: degenerate normal")))?;
                let h = quantize((c.frame.origin - st.centre).dot(nn), s.step)
                    .ok_or_else(|| unsupported(format!("section {k}: plane out of range")))?;
                code.pqh.push([p, q, h]);
                st.next_frame(nn, h as Real * s.step)
                    .ok_or_else(|| unsupported(format!("section {k}: degenerate frame")))?
            }
        };
        let (a, b) = rebase(c, &frame);
        let (qa, qb) = (q_all(&a, k)?, q_all(&b, k)?);
        let decoded = TrigCurve {
            frame,
            a: dequantize(&qa, s.step),
            b: dequantize(&qb, s.step),
        };
        state = State::of(&frame, decoded.a[0], decoded.b[0]);
        if state.is_none() {
            return Err(unsupported(format!("section {k}: degenerate frame")));
        }
        code.a.push(qa);
        code.b.push(qb);
        max_err = max_err.max(max_displacement(c, &decoded));
        // The plane's offset and tilt: half a step and the normal's
        // rounding; the first frame's three coordinates and two rounded
        // axes (each component off by half a step) give up to √3 times.
        let tilt = if k == 0 {
            3f64.sqrt() * (s.step / 2.0 + s.angle * rho)
        } else {
            s.step / 2.0 + s.angle * rho
        };
        let coefficients = s.step / std::f64::consts::SQRT_2
            * (1.0 + std::f64::consts::SQRT_2 * c.order() as Real);
        bound = bound.max(tilt + coefficients);
    }
    Ok((code, max_err, bound))
}

/// Appends `v` as a LEB128 varint.
fn put_varint(out: &mut Vec<u8>, mut v: u64) {
    while v >= 0x80 {
        out.push((v as u8) | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

fn zigzag(v: i64) -> u64 {
    ((v << 1) ^ (v >> 63)) as u64
}

/// Integers to write, each with the stream (kind, index) it belongs to,
/// for the entropy estimates.
#[derive(Default)]
struct IntStream {
    bytes: Vec<u8>,
    symbols: Vec<(u32, i64)>,
}

impl IntStream {
    fn put(&mut self, stream: u32, v: i64) {
        put_varint(&mut self.bytes, zigzag(v));
        self.symbols.push((stream, v));
    }
}

/// Coefficient indices stored as the difference from the previous
/// section's (the first harmonic: the curve's ellipse, which changes
/// slowly along a part; the centre offset and higher harmonics are
/// residuals already, and a difference would double their spread).
const DELTA_INDICES: std::ops::RangeInclusive<usize> = 1..=2;

/// Columns of a part's coefficient lists: index 0 of every section, then
/// index 1 of those that have it, and so on; [`DELTA_INDICES`] as the
/// difference from the section before.
fn put_columns(out: &mut IntStream, lists: &[Vec<i64>], kind: u32) {
    let longest = lists.iter().map(Vec::len).max().unwrap_or(0);
    for i in 0..longest {
        let mut prev = 0i64;
        for l in lists.iter().filter(|l| l.len() > i) {
            let v = if DELTA_INDICES.contains(&i) {
                l[i] - prev
            } else {
                l[i]
            };
            prev = l[i];
            out.put(kind + 2 * i as u32, v);
        }
    }
}

fn entropy_bytes<K: std::hash::Hash + Eq>(keys: impl Iterator<Item = K>) -> Real {
    let mut counts = std::collections::HashMap::new();
    let mut n = 0usize;
    for k in keys {
        *counts.entry(k).or_insert(0usize) += 1;
        n += 1;
    }
    let bits: Real = counts
        .values()
        .map(|&c| -(c as Real) * (c as Real / n as Real).log2())
        .sum();
    bits / 8.0
}

/// The model's scale for the default step: the body's height, else the
/// diagonal of the section origins' bounding box.
fn model_scale(model: &Model) -> Real {
    if let Some(b) = &model.body {
        return b.height;
    }
    let origins: Vec<Point3> = model
        .parts
        .iter()
        .flat_map(|p| p.part.sections().iter().map(|c| c.frame.origin))
        .collect();
    trigbody_core::Aabb::from_points(&origins).map_or(1.0, |b| b.diagonal().max(1e-9))
}

/// The model as a compact file, with what was written.
pub fn encode_tbm(model: &Model, options: &TbmOptions) -> Result<(Vec<u8>, TbmStats), TbmError> {
    let step = options
        .step
        .unwrap_or(DEFAULT_RELATIVE_STEP * model_scale(model));
    if !(step.is_finite() && step > 0.0) {
        return Err(TbmError::Unsupported {
            part: "(all)".to_string(),
            why: format!("quantization step {step} is not a positive number"),
        });
    }
    let rho = model
        .parts
        .iter()
        .flat_map(|p| p.part.sections().iter().map(reach))
        .fold(step, Real::max);
    let steps = Steps {
        step,
        angle: step / rho,
    };
    let mut stats = TbmStats {
        step,
        ..TbmStats::default()
    };
    let mut codes = Vec::with_capacity(model.parts.len());
    for p in &model.parts {
        let (code, err, bound) = encode_part(&p.name, p.part.sections(), &steps, rho)?;
        stats.max_error = stats.max_error.max(err);
        stats.bound = stats.bound.max(bound);
        codes.push(code);
    }
    let mut skeleton = serde_json::to_value(model_record(model)).map_err(ModelError::Json)?;
    if let Some(Value::Array(parts)) = skeleton.get_mut("parts") {
        for p in parts {
            let n = p["sections"].as_array().map_or(0, Vec::len);
            p["sections"] = json!(n);
        }
    }
    let skeleton = serde_json::to_vec(&skeleton).map_err(ModelError::Json)?;
    let mut head = Vec::new();
    put_varint(&mut head, skeleton.len() as u64);
    head.extend_from_slice(&skeleton);
    head.extend_from_slice(&steps.step.to_le_bytes());
    head.extend_from_slice(&steps.angle.to_le_bytes());
    for c in &codes {
        c.orders.iter().for_each(|&o| put_varint(&mut head, o));
        c.first
            .iter()
            .for_each(|&v| put_varint(&mut head, zigzag(v)));
    }
    let mut ints = IntStream::default();
    for c in &codes {
        for pqh in &c.pqh {
            for (i, &v) in pqh.iter().enumerate() {
                ints.put(i as u32, v);
            }
        }
        put_columns(&mut ints, &c.a, 3);
        put_columns(&mut ints, &c.b, 4);
        stats.section_numbers += 9 + 3 * c.pqh.len();
        stats.section_numbers += c.a.iter().chain(&c.b).map(Vec::len).sum::<usize>();
    }
    stats.entropy_bytes = entropy_bytes(ints.symbols.iter().map(|s| s.1));
    // H(value | stream) = H(stream, value) − H(stream).
    stats.entropy_by_index_bytes = entropy_bytes(ints.symbols.iter().copied())
        - entropy_bytes(ints.symbols.iter().map(|s| s.0));
    head.extend_from_slice(&ints.bytes);
    let packed = zstd_frame(&head, options.level)
        .map_err(|e| corrupt(format!("zstd compression failed: {e}")))?;
    stats.zstd_bytes = packed.len();
    let mut out = Vec::with_capacity(packed.len() + 4);
    out.extend_from_slice(TBM_MAGIC);
    out.push(TBM_VERSION);
    out.extend_from_slice(&packed);
    stats.bytes = out.len();
    Ok((out, stats))
}

/// One zstd frame with its content checksum (a damaged file fails the
/// check instead of decoding into another model).
fn zstd_frame(data: &[u8], level: i32) -> std::io::Result<Vec<u8>> {
    use std::io::Write;
    let mut enc = zstd::stream::write::Encoder::new(Vec::new(), level)?;
    enc.include_checksum(true)?;
    enc.write_all(data)?;
    enc.finish()
}

/// A reader over the decompressed payload; every read is checked.
struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
}

impl Cursor<'_> {
    fn take(&mut self, n: usize, what: &str) -> Result<&[u8], TbmError> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.data.len())
            .ok_or_else(|| corrupt(format!("the file ends inside {what}")))?;
        let s = &self.data[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn varint(&mut self, what: &str) -> Result<u64, TbmError> {
        let mut v = 0u64;
        for shift in (0..64).step_by(7) {
            let byte = self.take(1, what)?[0];
            v |= u64::from(byte & 0x7f)
                .checked_shl(shift)
                .filter(|x| x >> shift == u64::from(byte & 0x7f))
                .ok_or_else(|| corrupt(format!("{what}: integer too large")))?;
            if byte & 0x80 == 0 {
                return Ok(v);
            }
        }
        Err(corrupt(format!("{what}: integer too long")))
    }

    fn int(&mut self, what: &str) -> Result<i64, TbmError> {
        let u = self.varint(what)?;
        Ok(((u >> 1) as i64) ^ -((u & 1) as i64))
    }

    fn f64(&mut self, what: &str) -> Result<Real, TbmError> {
        let b = self.take(8, what)?;
        Ok(Real::from_le_bytes(b.try_into().expect("8 bytes")))
    }

    fn left(&self) -> usize {
        self.data.len() - self.pos
    }
}

/// Reads `lists.len()` lists of the given lengths in column order (as
/// [`put_columns`] wrote them).
fn get_columns(cur: &mut Cursor, lens: &[usize], what: &str) -> Result<Vec<Vec<i64>>, TbmError> {
    let mut lists: Vec<Vec<i64>> = lens.iter().map(|&n| Vec::with_capacity(n)).collect();
    let longest = lens.iter().copied().max().unwrap_or(0);
    for i in 0..longest {
        let mut prev = 0i64;
        for (l, &n) in lists.iter_mut().zip(lens) {
            if n > i {
                let v = cur.int(what)?;
                let v = if DELTA_INDICES.contains(&i) {
                    prev.checked_add(v)
                        .ok_or_else(|| corrupt(format!("{what}: coefficient out of range")))?
                } else {
                    v
                };
                prev = v;
                l.push(v);
            }
        }
    }
    Ok(lists)
}

/// Rebuilds one part's section records (JSON values, as the JSON file
/// stores them).
fn decode_part(
    cur: &mut Cursor,
    part: usize,
    orders: &[usize],
    first: &Frame,
    s: &Steps,
) -> Result<Vec<Value>, TbmError> {
    let what = format!("part {part}");
    let pqh: Vec<[i64; 3]> = (1..orders.len())
        .map(|_| Ok([cur.int(&what)?, cur.int(&what)?, cur.int(&what)?]))
        .collect::<Result<_, TbmError>>()?;
    let lens: Vec<usize> = orders.iter().map(|&j| 2 * j + 1).collect();
    let a = get_columns(cur, &lens, &what)?;
    let b = get_columns(cur, &lens, &what)?;
    let mut out = Vec::with_capacity(orders.len());
    let mut state: Option<State> = None;
    for k in 0..orders.len() {
        let bad = || corrupt(format!("part {part}, section {k}: degenerate frame"));
        let frame = match state {
            None => *first,
            Some(st) => {
                let [p, q, h] = pqh[k - 1];
                let n = st
                    .next_normal(p as Real * s.angle, q as Real * s.angle)
                    .ok_or_else(bad)?;
                st.next_frame(n, h as Real * s.step).ok_or_else(bad)?
            }
        };
        let (ca, cb) = (dequantize(&a[k], s.step), dequantize(&b[k], s.step));
        state = Some(State::of(&frame, ca[0], cb[0]).ok_or_else(bad)?);
        out.push(json!({
            "frame": { "origin": frame.origin.to_array(), "e1": frame.e1.to_array(),
                       "e2": frame.e2.to_array() },
            "a": ca, "b": cb,
        }));
    }
    Ok(out)
}

/// Reads a compact model file's bytes.
pub fn decode_tbm(bytes: &[u8]) -> Result<Model, TbmError> {
    if bytes.len() < 3 || &bytes[..3] != TBM_MAGIC {
        return Err(TbmError::NotTbm);
    }
    let version = match bytes.get(3) {
        Some(&v) if v == 1 || v == TBM_VERSION => v,
        Some(&v) => return Err(TbmError::UnknownVersion(v)),
        None => return Err(corrupt("the file ends after its first 3 bytes")),
    };
    let mut payload = Vec::new();
    zstd::stream::read::Decoder::new(&bytes[4..])
        .map_err(|e| corrupt(format!("zstd: {e}")))?
        .take(MAX_PAYLOAD)
        .read_to_end(&mut payload)
        .map_err(|e| corrupt(format!("zstd: {e}")))?;
    let mut cur = Cursor {
        data: &payload,
        pos: 0,
    };
    let n = cur.varint("the skeleton's length")?;
    let skeleton = cur.take(
        usize::try_from(n).map_err(|_| corrupt("skeleton too long"))?,
        "the skeleton",
    )?;
    let mut doc: Value = serde_json::from_slice(skeleton)
        .map_err(|e| corrupt(format!("the skeleton is not JSON: {e}")))?;
    let steps = Steps {
        step: cur.f64("the quantization steps")?,
        angle: cur.f64("the quantization steps")?,
    };
    if !(steps.step.is_finite() && steps.step > 0.0 && steps.angle.is_finite() && steps.angle > 0.0)
    {
        return Err(corrupt(format!(
            "quantization steps {} and {} are not positive numbers",
            steps.step, steps.angle
        )));
    }
    let Some(Value::Array(parts)) = doc.get_mut("parts") else {
        return Err(corrupt("the skeleton has no \"parts\" list"));
    };
    // Orders and first frames of every part come first.
    let mut heads = Vec::with_capacity(parts.len());
    for (i, p) in parts.iter().enumerate() {
        let count = p["sections"]
            .as_u64()
            .filter(|&c| c as usize <= cur.left())
            .ok_or_else(|| corrupt(format!("part {i}: bad section count {}", p["sections"])))?;
        let orders = (0..count)
            .map(|_| {
                let o = cur.varint(&format!("part {i}'s orders"))?;
                (o <= MAX_ORDER)
                    .then_some(o as usize)
                    .ok_or_else(|| corrupt(format!("part {i}: order {o} is over {MAX_ORDER}")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let what = format!("part {i}'s first frame");
        let first = match (count, version) {
            (0, _) => Frame {
                origin: Point3::ZERO,
                e1: Vec3::X,
                e2: Vec3::Y,
            },
            (_, 1) => {
                let mut v = [0.0; 9];
                for x in v.iter_mut() {
                    *x = cur.f64(&what)?;
                }
                let v3 = |i: usize| Vec3::new(v[i], v[i + 1], v[i + 2]);
                Frame {
                    origin: v3(0),
                    e1: v3(3),
                    e2: v3(6),
                }
            }
            _ => {
                let mut q = [0i64; 9];
                for x in q.iter_mut() {
                    *x = cur.int(&what)?;
                }
                first_frame(&q, &steps).ok_or_else(|| corrupt(format!("{what} is degenerate")))?
            }
        };
        heads.push((orders, first));
    }
    for (i, (p, (orders, first))) in parts.iter_mut().zip(&heads).enumerate() {
        if orders.iter().map(|&j| 2 * j + 1).sum::<usize>() > cur.left() {
            return Err(corrupt(format!(
                "part {i}: the file ends inside its coefficients"
            )));
        }
        p["sections"] = Value::Array(decode_part(&mut cur, i, orders, first, &steps)?);
    }
    if cur.left() != 0 {
        return Err(corrupt(format!("{} bytes after the last part", cur.left())));
    }
    Ok(model_of_value(doc)?)
}

/// Whether `bytes` start like a compact model file.
pub fn is_tbm(bytes: &[u8]) -> bool {
    bytes.starts_with(TBM_MAGIC)
}

/// Either kind of model file, told apart by its first bytes.
pub fn read_any_model(bytes: &[u8]) -> Result<Model, TbmError> {
    if is_tbm(bytes) {
        decode_tbm(bytes)
    } else {
        Ok(crate::model::read_model(bytes)?)
    }
}
