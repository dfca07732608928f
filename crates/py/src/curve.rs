//! `trigbody.Curve`: one trigonometric cross-section curve.

use crate::arrays::vec3_array;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use trigbody_core::{LoopFit, Real, TrigCurve};
use trigbody_io::fit_json::loop_fit_json;

/// A closed planar curve `P(v) = o + x(v) e1 + y(v) e2`, `v` in `[0, 2π)`,
/// with `x(v) = a0 + Σ a_{2j-1} cos jv + a_{2j} sin jv` and
/// `y(v) = b0 + Σ b_{2j-1} sin jv + b_{2j} cos jv` (the paper's layout).
#[pyclass(frozen, module = "trigbody")]
#[derive(Debug, Clone)]
pub struct Curve {
    pub curve: TrigCurve,
    /// The fit that made it (None for a model's section).
    pub fit: Option<Box<FitSummary>>,
}

/// What a fit knows beyond the curve.
#[derive(Debug, Clone)]
pub struct FitSummary {
    ea: Real,
    em: Real,
    rms: Real,
    max: Real,
    met: bool,
    warnings: Vec<String>,
    /// The text `trigbody fit --json` prints for the same points.
    json: String,
}

impl Curve {
    pub fn from_fit(fit: LoopFit) -> Curve {
        let mut json = serde_json::to_string_pretty(&loop_fit_json(&fit)).unwrap_or_default();
        json.push('\n');
        let summary = FitSummary {
            ea: fit.errors.ea,
            em: fit.errors.em,
            rms: fit.errors.rms,
            max: fit.errors.max,
            met: fit.met,
            warnings: fit.warnings,
            json,
        };
        Curve {
            curve: fit.curve,
            fit: Some(Box::new(summary)),
        }
    }
}

/// Points `(M, 3)` of `c` at the parameters `v`.
pub fn evaluate<'py>(
    py: Python<'py>,
    c: &TrigCurve,
    v: &PyReadonlyArray1<'_, f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let v = v.as_array();
    let points: Vec<_> = v.iter().map(|&t| c.point(t)).collect();
    vec3_array(py, &points)
}

#[pymethods]
impl Curve {
    /// The order J (number of harmonics).
    #[getter]
    fn order(&self) -> usize {
        self.curve.order()
    }

    /// The x coefficients `a[0..=2J]` (float64).
    #[getter]
    fn a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.curve.a)
    }

    /// The y coefficients `b[0..=2J]` (float64).
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.curve.b)
    }

    /// The plane: `{"origin", "e1", "e2", "normal"}`, each a float64 (3,) array.
    #[getter]
    fn frame<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let f = &self.curve.frame;
        let d = PyDict::new(py);
        for (k, v) in [
            ("origin", f.origin),
            ("e1", f.e1),
            ("e2", f.e2),
            ("normal", f.normal()),
        ] {
            d.set_item(k, PyArray1::from_slice(py, &v.to_array()))?;
        }
        Ok(d)
    }

    /// The fit's errors at the input points, `{"ea", "em", "rms", "max"}`
    /// (E_a and E_M relative, rms and max in the points' unit); None for a
    /// model's section.
    #[getter]
    fn errors<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(f) = &self.fit else { return Ok(None) };
        let d = PyDict::new(py);
        for (k, v) in [("ea", f.ea), ("em", f.em), ("rms", f.rms), ("max", f.max)] {
            d.set_item(k, v)?;
        }
        Ok(Some(d))
    }

    /// Whether the fit met both tolerances (None for a model's section).
    #[getter]
    fn met(&self) -> Option<bool> {
        self.fit.as_ref().map(|f| f.met)
    }

    /// The fit's warnings (empty for a model's section).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.fit
            .as_ref()
            .map_or_else(Vec::new, |f| f.warnings.clone())
    }

    /// The fit as the JSON text `trigbody fit --json` prints.
    #[getter]
    fn fit_json(&self) -> Option<String> {
        self.fit.as_ref().map(|f| f.json.clone())
    }

    /// The perimeter, in the points' unit.
    #[getter]
    fn perimeter(&self) -> Real {
        self.curve.perimeter()
    }

    /// The enclosed area.
    #[getter]
    fn area(&self) -> Real {
        self.curve.area()
    }

    /// The points `(M, 3)` float64 at the parameters `v` (a 1-D array).
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        v: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        evaluate(py, &self.curve, &v)
    }

    fn __repr__(&self) -> String {
        format!(
            "Curve(order={}, perimeter={:.6})",
            self.curve.order(),
            self.curve.perimeter()
        )
    }
}
