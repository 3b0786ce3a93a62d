//! wetbounce from Python (PyO3): load a scene from a file or a dict, change its keys, check it,
//! step it or run it whole, read the particles as NumPy arrays and the events and summary as
//! pandas DataFrames, and write the CLI's output files. The Python package is `wetbounce`
//! (`python/wetbounce/`); this crate is its extension module, `wetbounce._wetbounce`.

mod convert;
mod errors;
mod scene;
mod sim;

use pyo3::prelude::*;

/// wetbounce's engine: particles bouncing on walls in a fluid (Legendre et al. 2006).
#[pymodule]
fn _wetbounce(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<scene::Scene>()?;
    m.add_class::<sim::Simulation>()?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("OutputError", py.get_type::<errors::OutputError>())?;
    m.add("STATE_NAMES", ("free", "held", "resting"))?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
