//! The native half of the `trigbody` Python package (`trigbody._trigbody`):
//! curve fitting, reading meshes and scans, body reconstruction, model
//! files, tessellation and measurement, numpy in and numpy out. The Python
//! half (`python/trigbody/__init__.py`) checks dtypes and shapes and wraps
//! the report; `python -m trigbody` runs the command line itself (`cli`).
//!
//! Every long call releases the GIL (`Python::detach`), so threads (and
//! Dask's threaded workers) run bodies in parallel. Bad input raises
//! `ValueError` with the library's message, the one the CLI prints.

mod arrays;
mod curve;
mod model;

use arrays::{points3, vec3_array};
use curve::Curve;
use model::{Model, Part};
use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use trigbody_core::{
    fit_loop, fit_loop_2d, reconstruct as reconstruct_body, ReconstructOptions, Units,
};
use trigbody_core::{FitMode, FitOptions, Mesh, OrderChoice, PointCloud, Real, Vec2, Vec3};
use trigbody_io::body_file::report_json;
use trigbody_io::{read_geometry as read_file, Geometry, ReadOptions};

/// A `ValueError` with `e`'s message.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The order argument: `"auto"` or a positive whole number.
fn order_choice(order: &Bound<'_, PyAny>) -> PyResult<OrderChoice> {
    if let Ok(s) = order.extract::<String>() {
        if s.eq_ignore_ascii_case("auto") {
            return Ok(OrderChoice::Auto);
        }
        return Err(value_error(format!(
            "order '{s}' is neither a positive whole number nor 'auto'"
        )));
    }
    match order.extract::<usize>() {
        Ok(0) | Err(_) => Err(value_error(
            "the order must be 'auto' or a whole number of at least 1",
        )),
        Ok(j) => Ok(OrderChoice::Fixed(j)),
    }
}

/// Fits one closed loop of points, `(N, 2)` or `(N, 3)` float64, ordered
/// along the loop (see `trigbody.fit_curve`).
#[pyfunction]
#[pyo3(signature = (points, order, ea, em, smoothing = 0.0, noise = 0.0))]
fn fit_curve(
    py: Python<'_>,
    points: PyReadonlyArray2<'_, f64>,
    order: &Bound<'_, PyAny>,
    ea: Real,
    em: Real,
    smoothing: Real,
    noise: Real,
) -> PyResult<Curve> {
    let opts = FitOptions {
        order: order_choice(order)?,
        ea,
        em,
        smoothing,
        noise,
        ..FitOptions::default()
    };
    let view = points.as_array();
    let fit = match view.ncols() {
        2 => {
            let p: Vec<Vec2> = view
                .rows()
                .into_iter()
                .map(|r| Vec2::new(r[0], r[1]))
                .collect();
            py.detach(|| fit_loop_2d(&p, &opts))
        }
        3 => {
            let p = points3(&points)?;
            py.detach(|| fit_loop(&p, &opts))
        }
        n => {
            return Err(value_error(format!(
                "points must be an (N, 2) or (N, 3) array; got {n} columns"
            )))
        }
    }
    .map_err(value_error)?;
    Ok(Curve::from_fit(fit))
}

/// Reads a mesh (.obj, .ply, .stl) or scan (.ply points, .xyz): the
/// vertices `(N, 3)` float64, the triangles `(M, 3)` uint32 (None for a
/// scan) and the normals `(N, 3)` float64 (None when the file has none).
#[pyfunction]
#[allow(clippy::type_complexity)]
fn read_geometry<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<(Py<PyAny>, Option<Py<PyAny>>, Option<Py<PyAny>>)> {
    let g = py
        .detach(|| read_file(&path, &ReadOptions::default()))
        .map_err(value_error)?;
    let faces = match &g {
        Geometry::Mesh(m) => Some(arrays::triangles_array(py, &m.triangles)?.unbind()),
        Geometry::Points(_) => None,
    };
    let normals = match g.normals() {
        Some(n) => Some(vec3_array(py, n)?.unbind()),
        None => None,
    };
    Ok((vec3_array(py, g.positions())?.unbind(), faces, normals))
}

/// The options of [`reconstruct`] beyond the geometry.
#[derive(Debug, FromPyObject)]
#[pyo3(from_item_all)]
struct Options {
    units: String,
    up: Option<[Real; 3]>,
    front: Option<[Real; 3]>,
    spacing: Option<Real>,
    ea: Option<Real>,
    em: Option<Real>,
    prune: Option<Real>,
    scan_frames: Option<usize>,
    fit: Option<String>,
}

fn direction(name: &str, v: Option<[Real; 3]>) -> PyResult<Option<Vec3>> {
    v.map(|[x, y, z]| {
        Vec3::new(x, y, z)
            .normalized()
            .filter(|d| d.is_finite())
            .ok_or_else(|| value_error(format!("{name} {v:?} is not a direction")))
    })
    .transpose()
}

impl Options {
    fn reconstruct_options(&self) -> PyResult<ReconstructOptions> {
        let infer_units = self.units == "auto";
        let units = match infer_units {
            true => Units::default(),
            false => Units::from_symbol(&self.units).ok_or_else(|| {
                value_error(format!("units '{}' are not m, cm, mm or auto", self.units))
            })?,
        };
        let mut o = ReconstructOptions {
            units,
            infer_units,
            ..ReconstructOptions::default()
        };
        o.spacing = self.spacing.unwrap_or(o.spacing);
        o.fit.ea = self.ea.unwrap_or(o.fit.ea);
        o.fit.em = self.em.unwrap_or(o.fit.em);
        o.prune_tolerance = self.prune.unwrap_or(o.prune_tolerance);
        o.scan_frames = self.scan_frames.unwrap_or(o.scan_frames);
        if let Some(fit) = &self.fit {
            o.global_fit.mode = match fit.as_str() {
                "auto" => FitMode::Scans,
                "global" => FitMode::All,
                "none" => FitMode::Off,
                _ => {
                    return Err(value_error(format!(
                        "fit '{fit}' is not auto, global or none"
                    )))
                }
            };
        }
        o.segment.up = direction("up", self.up)?;
        o.segment.front = direction("front", self.front)?;
        Ok(o)
    }
}

/// Reconstructs a body from a mesh (`faces` given) or a scan (no faces):
/// the model, the report as the JSON text `trigbody reconstruct
/// --report` writes, and the seconds the library's `reconstruct` took
/// (what the Python call adds is the rest of the call's time).
#[pyfunction]
#[pyo3(signature = (vertices, faces, normals, options))]
fn reconstruct(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f64>,
    faces: Option<PyReadonlyArray2<'_, u32>>,
    normals: Option<PyReadonlyArray2<'_, f64>>,
    options: Options,
) -> PyResult<(Model, String, f64)> {
    let opts = options.reconstruct_options()?;
    let positions = points3(&vertices)?;
    let normals = normals.map(|n| points3(&n)).transpose()?;
    let geometry = match faces {
        Some(f) => {
            let mut m = Mesh::new(positions, arrays::triangles(&f)?).map_err(value_error)?;
            m.normals = normals;
            m.validate().map_err(value_error)?;
            Geometry::Mesh(m)
        }
        None => {
            let mut c = PointCloud::new(positions).map_err(value_error)?;
            c.normals = normals;
            c.validate().map_err(value_error)?;
            Geometry::Points(c)
        }
    };
    let (result, seconds) = py.detach(|| {
        let g = geometry.body();
        let started = std::time::Instant::now();
        let result = reconstruct_body(g, &opts);
        (result, started.elapsed().as_secs_f64())
    });
    let (body, report) = result.map_err(value_error)?;
    let mut text = serde_json::to_string_pretty(&report_json(&report)).map_err(value_error)?;
    text.push('\n');
    Ok((Model::from_body(&body), text, seconds))
}

/// Runs the `trigbody` command line on `args` (without the program name)
/// and returns its exit code: `python -m trigbody` is the CLI itself.
#[pyfunction]
fn cli(py: Python<'_>, args: Vec<String>) -> u8 {
    let argv: Vec<String> = std::iter::once("trigbody".to_string())
        .chain(args)
        .collect();
    py.detach(|| trigbody::run(argv))
}

/// The native module (`trigbody._trigbody`).
#[pymodule]
fn _trigbody(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(fit_curve, m)?)?;
    m.add_function(wrap_pyfunction!(read_geometry, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct, m)?)?;
    m.add_function(wrap_pyfunction!(model::load_model, m)?)?;
    m.add_function(wrap_pyfunction!(model::model_from_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(cli, m)?)?;
    m.add_class::<Curve>()?;
    m.add_class::<Model>()?;
    m.add_class::<Part>()?;
    Ok(())
}
