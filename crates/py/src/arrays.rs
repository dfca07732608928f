//! numpy arrays to and from the library's point and triangle lists: one
//! copy in (the library owns `Vec<Vec3>`), none out (numpy takes the
//! flattened `Vec` as its buffer).

use crate::value_error;
use numpy::ndarray::ArrayView2;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use trigbody_core::Vec3;

fn columns<T>(name: &str, a: &ArrayView2<'_, T>, n: usize) -> PyResult<()> {
    if a.ncols() != n {
        return Err(value_error(format!(
            "{name} must be an (N, {n}) array; got shape ({}, {})",
            a.nrows(),
            a.ncols()
        )));
    }
    Ok(())
}

/// The rows of an `(N, 3)` float64 array as points.
pub fn points3(a: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<Vec3>> {
    let v = a.as_array();
    columns("points", &v, 3)?;
    Ok(v.rows()
        .into_iter()
        .map(|r| Vec3::new(r[0], r[1], r[2]))
        .collect())
}

/// The rows of an `(M, 3)` uint32 array as triangles.
pub fn triangles(a: &PyReadonlyArray2<'_, u32>) -> PyResult<Vec<[u32; 3]>> {
    let v = a.as_array();
    columns("faces", &v, 3)?;
    Ok(v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect())
}

/// Points as an `(N, 3)` float64 array.
pub fn vec3_array<'py>(py: Python<'py>, points: &[Vec3]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = points.iter().flat_map(|p| p.to_array()).collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([points.len(), 3])?
        .into_any())
}

/// Triangles as an `(M, 3)` uint32 array.
pub fn triangles_array<'py>(py: Python<'py>, tris: &[[u32; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<u32> = tris.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([tris.len(), 3])?
        .into_any())
}
