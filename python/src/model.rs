//! `Wall` (a wall description) and `Layout` (the blocks of one realization, or of a layout
//! file): the library's `generator::Wall` and `layout::{LayoutSpec, Layout}` behind Python
//! classes, blocks as NumPy arrays.

use crate::errors::{generator_error, guard, input_error, layout_error, Place};
use drystone::generator::{DistributionSource, WallSpec};
use drystone::prelude::{generate, Layout, LayoutSpec, Wall};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// A checked wall description (the TOML format of `studies/walls/*.toml`): geometry,
/// courses, blocks, arrangement, materials. SI units (m).
#[pyclass(module = "drystone", name = "Wall", frozen)]
pub struct PyWall {
    pub wall: Wall,
}

#[pymethods]
impl PyWall {
    /// Reads and checks a wall file (TOML). Named distributions are looked up in the
    /// nearest `distributions/` directory above the file.
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<PyWall> {
        py.detach(|| guard(|| Wall::from_file(&path).map(|wall| PyWall { wall }).map_err(|e| generator_error(&e))))
    }

    /// A wall from a dict with the keys of the TOML format (as `tomllib.load` gives it).
    /// `path` names the description in errors and is where named distributions are looked
    /// up from (default `./<dict>.toml`: the `distributions/` directory above the working
    /// directory).
    #[staticmethod]
    #[pyo3(signature = (spec, path = None))]
    fn from_dict(py: Python<'_>, spec: &Bound<'_, PyDict>, path: Option<PathBuf>) -> PyResult<PyWall> {
        let path = path.unwrap_or_else(|| PathBuf::from("<dict>.toml"));
        let text = to_json(py, spec.as_any())?;
        guard(|| {
            let spec: WallSpec = serde_json::from_str(&text).map_err(|e| {
                let m = e.to_string();
                input_error(format!("{}: {m}", path.display()), Place::default().with_file(&path).parsed(&m))
            })?;
            let source = DistributionSource::default_for(&path);
            spec.resolve(&path, &source).map(|wall| PyWall { wall }).map_err(|e| generator_error(&e))
        })
    }

    /// The description's name.
    #[getter]
    fn name(&self) -> String {
        self.wall.name.clone()
    }

    /// The file it came from.
    #[getter]
    fn source(&self) -> String {
        self.wall.source.display().to_string()
    }

    /// Wall length L (x), m.
    #[getter]
    fn length_m(&self) -> f64 {
        self.wall.length
    }

    /// Wall height H (z), m.
    #[getter]
    fn height_m(&self) -> f64 {
        self.wall.height
    }

    /// Base width B (y), m.
    #[getter]
    fn base_width_m(&self) -> f64 {
        self.wall.base_width
    }

    /// Top width b (y), m.
    #[getter]
    fn top_width_m(&self) -> f64 {
        self.wall.top_width
    }

    /// Realization `realization` of the wall from the master seed `seed`: the same layout
    /// bit for bit on every call (the streams of `rng_for(seed, realization, purpose)`).
    #[pyo3(signature = (seed, realization = 0))]
    fn generate(&self, py: Python<'_>, seed: u64, realization: u64) -> PyResult<PyLayout> {
        py.detach(|| {
            guard(|| {
                let g = generate(&self.wall, seed, realization).map_err(|e| generator_error(&e))?;
                let layout = g.check().map_err(|e| generator_error(&e))?;
                Ok(PyLayout { spec: g.layout, layout, seed: Some(seed), realization: Some(realization) })
            })
        })
    }

    fn __repr__(&self) -> String {
        let w = &self.wall;
        format!(
            "Wall(name={:?}, length_m={}, height_m={}, base_width_m={}, top_width_m={})",
            w.name, w.length, w.height, w.base_width, w.top_width
        )
    }
}

/// The blocks of a wall: convex polyhedra with their materials, restraints and monitor
/// points, in the table frame (x along the wall, y out of plane, z up; m).
#[pyclass(module = "drystone", name = "Layout", frozen)]
pub struct PyLayout {
    pub spec: LayoutSpec,
    pub layout: Layout,
    pub seed: Option<u64>,
    pub realization: Option<u64>,
}

impl PyLayout {
    fn from_spec(spec: LayoutSpec) -> PyResult<PyLayout> {
        let layout = spec.clone().resolve().map_err(|e| layout_error(&e))?;
        Ok(PyLayout { spec, layout, seed: None, realization: None })
    }
}

#[pymethods]
impl PyLayout {
    /// A layout from its JSON text (the `drystone generate` / `drystone tilt` format).
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<PyLayout> {
        guard(|| PyLayout::from_spec(LayoutSpec::from_json(text).map_err(|e| layout_error(&e))?))
    }

    /// Reads and checks a layout file (JSON).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<PyLayout> {
        guard(|| PyLayout::from_spec(LayoutSpec::from_file(&path).map_err(|e| layout_error(&e))?))
    }

    /// The layout as JSON text (pretty); `Layout.from_json(l.to_json())` is the same layout.
    fn to_json(&self) -> String {
        self.spec.to_json()
    }

    /// Writes the JSON to `path`.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        std::fs::write(&path, self.spec.to_json())
            .map_err(|e| crate::errors::DrystoneError::new_err(format!("{}: {e}", path.display())))
    }

    /// The layout's name.
    #[getter]
    fn name(&self) -> String {
        self.layout.name.clone()
    }

    /// The master seed it was generated from (None for a layout read from JSON).
    #[getter]
    fn seed(&self) -> Option<u64> {
        self.seed
    }

    /// The realization index it was generated as (None for a layout read from JSON).
    #[getter]
    fn realization(&self) -> Option<u64> {
        self.realization
    }

    fn __len__(&self) -> usize {
        self.layout.blocks.len()
    }

    /// Block ids, in layout order (length n).
    #[getter]
    fn block_ids(&self) -> Vec<String> {
        self.layout.blocks.iter().map(|b| b.id.clone()).collect()
    }

    /// The material name of every block (length n).
    #[getter]
    fn materials(&self) -> Vec<String> {
        self.layout.blocks.iter().map(|b| self.layout.material_names[b.material].clone()).collect()
    }

    /// The layout's materials as written: name, density (kg/m³), Kn and Ks (Pa/m),
    /// friction (degrees), cohesion and tensile strength (Pa).
    #[getter]
    fn material_table<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        from_json(py, &serde_json::to_string(&self.spec.materials).unwrap_or_default())
    }

    /// Course index of every block (0 at the base; None where the layout gives none).
    #[getter]
    fn courses(&self) -> Vec<Option<usize>> {
        self.layout.blocks.iter().map(|b| b.course).collect()
    }

    /// Whether each block is a wedge stone, bool array (n,).
    #[getter]
    fn wedge<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_vec(py, self.layout.blocks.iter().map(|b| b.wedge).collect())
    }

    /// Whether each block is fixed, bool array (n,).
    #[getter]
    fn fixed<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_vec(py, self.layout.blocks.iter().map(|b| b.fixed).collect())
    }

    /// The vertices of every block as written in the layout: a list of n float64 arrays of
    /// shape (v_i, 3), m, table frame.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let arrays: Vec<Bound<'py, PyArray2<f64>>> = self.spec.blocks.iter().map(|b| points(py, &b.vertices)).collect();
        PyList::new(py, arrays)
    }

    /// Every block's vertices stacked: float64 array (V, 3), m; `vertex_offsets[i]` ..
    /// `vertex_offsets[i + 1]` are block i's rows.
    #[getter]
    fn vertices_flat<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let all: Vec<[f64; 3]> = self.spec.blocks.iter().flat_map(|b| b.vertices.iter().copied()).collect();
        points(py, &all)
    }

    /// Row offsets of each block in `vertices_flat`, int64 array (n + 1,).
    #[getter]
    fn vertex_offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let mut o = vec![0i64];
        for b in &self.spec.blocks {
            o.push(o[o.len() - 1] + b.vertices.len() as i64);
        }
        PyArray1::from_vec(py, o)
    }

    /// Bounding box of the blocks, float64 array (2, 3): min and max corners, m.
    #[getter]
    fn bounds<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let b = self.layout.bounds();
        points(py, &[[b.min.x, b.min.y, b.min.z], [b.max.x, b.max.y, b.max.z]])
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<PyLayout>().is_ok_and(|o| o.get().spec.to_json() == self.spec.to_json())
    }

    fn __repr__(&self) -> String {
        format!("Layout(name={:?}, blocks={})", self.layout.name, self.layout.blocks.len())
    }
}

/// Points as a float64 array (n, 3).
fn points<'py>(py: Python<'py>, p: &[[f64; 3]]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = p.iter().flatten().copied().collect();
    // The shape matches the data by construction.
    Array2::from_shape_vec((p.len(), 3), flat).unwrap_or_else(|_| Array2::zeros((0, 3))).into_pyarray(py)
}

/// A Python object as JSON text (`json.dumps`), for the library's serde types.
pub fn to_json(py: Python<'_>, obj: &Bound<'_, PyAny>) -> PyResult<String> {
    let json = py.import("json")?;
    json.call_method1("dumps", (obj,))
        .and_then(|s| s.extract::<String>())
        .map_err(|e| input_error(format!("not representable as JSON: {e}"), Place::default()))
}

/// JSON text as a Python object (`json.loads`).
pub fn from_json<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}
