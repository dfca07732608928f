//! `trigbody.Model` (a model file in memory) and `trigbody.Part`.

use crate::arrays::{triangles_array, vec3_array};
use crate::curve::Curve;
use crate::value_error;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyFileExistsError, PyImportError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::io::Write;
use std::path::{Path, PathBuf};
use trigbody_core::{measure_body, Body, ModelMeasureOptions};
use trigbody_core::{Real, TessellationOptions, TrigCurve};
use trigbody_io::body_file::{body_of_model, model_of_body};
use trigbody_io::model::{merge_pieces, read_model, skin_pieces, write_model, Skin};

/// A body model: named parts of skinned trigonometric sections, the
/// transitions between them, the body's frame and height. Reads and
/// writes the model file of `trigbody reconstruct -o` byte for byte.
#[pyclass(frozen, module = "trigbody")]
#[derive(Debug, Clone)]
pub struct Model {
    pub inner: trigbody_io::model::Model,
}

impl Model {
    pub fn from_body(body: &Body) -> Model {
        Model {
            inner: model_of_body(body),
        }
    }

    fn bytes(&self) -> PyResult<Vec<u8>> {
        let mut bytes = Vec::new();
        write_model(&mut bytes, &self.inner).map_err(value_error)?;
        Ok(bytes)
    }
}

fn parse_model(bytes: &[u8], name: &str) -> PyResult<Model> {
    let inner = read_model(bytes).map_err(|e| value_error(format!("{name}: {e}")))?;
    if inner.parts.is_empty() {
        return Err(value_error(format!("{name}: the model has no parts")));
    }
    Ok(Model { inner })
}

/// Reads a model file (`trigbody reconstruct -o`, `trigbody loft`).
#[pyfunction]
pub fn load_model(py: Python<'_>, path: PathBuf) -> PyResult<Model> {
    let name = path.display().to_string();
    let bytes = py
        .detach(|| std::fs::read(&path))
        .map_err(|e| value_error(format!("{name}: {e}")))?;
    py.detach(|| parse_model(&bytes, &name))
}

/// A model from the bytes of a model file (`Model.to_bytes`, pickling).
#[pyfunction]
pub fn model_from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Model> {
    py.detach(|| parse_model(data, "model bytes"))
}

/// Writes `bytes` to `path` through a temporary file beside it, so a
/// failure never leaves half a file; an existing file is kept unless
/// `overwrite`.
fn write_new(path: &Path, bytes: &[u8], overwrite: bool) -> PyResult<()> {
    let shown = path.display();
    if !overwrite && path.exists() {
        return Err(PyFileExistsError::new_err(format!(
            "{shown}: already exists; pass overwrite=True to replace it"
        )));
    }
    let name = path
        .file_name()
        .map_or("model".into(), |n| n.to_string_lossy());
    let tmp = path.with_file_name(format!(".{name}.trigbody-{}.tmp", std::process::id()));
    let written = std::fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes).and_then(|()| f.sync_all()))
        .and_then(|()| std::fs::rename(&tmp, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        value_error(format!("{shown}: {e}"))
    })
}

#[pymethods]
impl Model {
    /// Writes the model file (the bytes `trigbody reconstruct -o` writes).
    #[pyo3(signature = (path, overwrite = false))]
    fn save(&self, py: Python<'_>, path: PathBuf, overwrite: bool) -> PyResult<()> {
        let bytes = self.bytes()?;
        py.detach(|| write_new(&path, &bytes, overwrite))
    }

    /// The model file's bytes.
    fn to_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        Ok(PyBytes::new(py, &self.bytes()?))
    }

    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let f = py
            .import("trigbody._trigbody")?
            .getattr("model_from_bytes")?;
        Ok((f, (self.to_bytes(py)?,)))
    }

    /// The unit of every coordinate (`"m"`, `"cm"`, `"mm"`).
    #[getter]
    fn units(&self) -> String {
        self.inner.units.clone()
    }

    /// Soles to head top in the model's unit (None for a loft).
    #[getter]
    fn height(&self) -> Option<Real> {
        self.inner.body.map(|b| b.height)
    }

    /// The parts, in file order (cavities last, with `cavity_of`).
    #[getter]
    fn parts(&self) -> Vec<Part> {
        self.inner
            .parts
            .iter()
            .map(|p| Part {
                name: p.name.clone(),
                cavity_of: p.cavity_of.clone(),
                curves: p.part.sections().to_vec(),
                knots: p.part.knots().to_vec(),
            })
            .collect()
    }

    /// The surface as one mesh: vertices `(N, 3)` float64 and triangles
    /// `(M, 3)` uint32, as `trigbody mesh --edge EDGE --skin SKIN` writes
    /// it (`edge` None: the default grid; `skin` "whole", "outer" or
    /// "closed", the one closed surface `trigbody mesh` writes by default).
    #[pyo3(signature = (edge = None, skin = "whole"))]
    fn tessellate<'py>(
        &self,
        py: Python<'py>,
        edge: Option<Real>,
        skin: &str,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let skin = match skin {
            "whole" => Skin::Whole,
            "outer" => Skin::Outer,
            "closed" => Skin::Closed,
            s => {
                return Err(value_error(format!(
                    "skin '{s}' is not 'whole', 'outer' or 'closed'"
                )))
            }
        };
        if let Some(e) = edge.filter(|e| !(e.is_finite() && *e > 0.0)) {
            return Err(value_error(format!("edge {e} is not a positive length")));
        }
        let options = TessellationOptions {
            target_edge: edge,
            ..TessellationOptions::default()
        };
        let mesh = py.detach(|| {
            let pieces = self
                .inner
                .tessellate_pieces(&options)
                .map_err(|e| e.to_string())?;
            let skinned = skin_pieces(&self.inner, pieces, skin).map_err(|e| e.to_string())?;
            Ok::<_, String>(merge_pieces(&skinned))
        });
        let mesh = mesh.map_err(value_error)?;
        Ok((
            vec3_array(py, &mesh.positions)?,
            triangles_array(py, &mesh.triangles)?,
        ))
    }

    /// The surface as a `trimesh.Trimesh` (needs the trimesh package).
    #[pyo3(signature = (edge = None, skin = "whole"))]
    fn to_trimesh<'py>(
        &self,
        py: Python<'py>,
        edge: Option<Real>,
        skin: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let trimesh = py.import("trimesh").map_err(|_| {
            PyImportError::new_err(
                "Model.to_trimesh needs the trimesh package: pip install trimesh",
            )
        })?;
        let (v, f) = self.tessellate(py, edge, skin)?;
        let kw = PyDict::new(py);
        kw.set_item("vertices", v)?;
        kw.set_item("faces", f)?;
        kw.set_item("process", false)?;
        trimesh.getattr("Trimesh")?.call((), Some(&kw))
    }

    /// The body's measurements from the model's curves, as `trigbody
    /// measure MODEL.json --json` reports them: `{name: value}` (stature,
    /// girths, lengths, breadth) plus `volume` and `surface_area`, in the
    /// model's unit.
    fn measure<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let model = self.inner.clone();
        let m = py
            .detach(|| {
                let body = body_of_model(model).map_err(|e| e.to_string())?;
                measure_body(&body, &ModelMeasureOptions::default()).map_err(|e| e.to_string())
            })
            .map_err(value_error)?;
        let d = PyDict::new(py);
        for x in &m.measurements {
            d.set_item(x.name, x.value)?;
        }
        d.set_item("volume", m.volume.model)?;
        d.set_item("surface_area", m.surface_area.model)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let names: Vec<&str> = self.inner.parts.iter().map(|p| p.name.as_str()).collect();
        format!("Model(units={:?}, parts={names:?})", self.inner.units)
    }
}

/// One part of a model: its sections (trigonometric curves, bottom or
/// root first) skinned into a surface.
#[pyclass(frozen, module = "trigbody")]
#[derive(Debug, Clone)]
pub struct Part {
    name: String,
    cavity_of: Option<String>,
    curves: Vec<TrigCurve>,
    knots: Vec<Real>,
}

#[pymethods]
impl Part {
    /// The part's name (`torso`, `head`, `left_arm`, ..., `head_cavity`).
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }

    /// For a cavity, the part it lies in; else None.
    #[getter]
    fn cavity_of(&self) -> Option<String> {
        self.cavity_of.clone()
    }

    /// The sections, as curves.
    #[getter]
    fn sections(&self) -> Vec<Curve> {
        self.curves
            .iter()
            .map(|c| Curve {
                curve: c.clone(),
                fit: None,
            })
            .collect()
    }

    /// Each section's position along the part (its knot), float64 (K,).
    #[getter]
    fn knots<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.knots)
    }

    /// Every section sampled at `n` equally spaced parameters: float64
    /// `(K, n, 3)`.
    #[pyo3(signature = (n = 64))]
    fn section_points<'py>(&self, py: Python<'py>, n: usize) -> PyResult<Bound<'py, PyAny>> {
        if n == 0 {
            return Err(value_error("n must be at least 1"));
        }
        let flat: Vec<f64> = self
            .curves
            .iter()
            .flat_map(|c| c.sample(n))
            .flat_map(|p| p.to_array())
            .collect();
        Ok(PyArray1::from_vec(py, flat)
            .reshape([self.curves.len(), n, 3])?
            .into_any())
    }

    fn __repr__(&self) -> String {
        format!("Part({:?}, sections={})", self.name, self.curves.len())
    }
}
