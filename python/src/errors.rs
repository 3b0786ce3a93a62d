//! The exceptions: a scene's errors and the output files' errors, with the CLI's messages.

use pyo3::prelude::*;
use wetbounce::SceneError as EngineSceneError;
use wetbounce::output::OutputError as EngineOutputError;

pyo3::create_exception!(
    wetbounce,
    SceneError,
    pyo3::exceptions::PyValueError,
    "A scene that cannot be loaded: ``str(e)`` is the message ``wetbounce check`` prints, \
     ``FILE: KEY: what is wrong, with the value``; ``e.file``, ``e.key`` (``\"\"`` when the file \
     cannot be read) and ``e.message`` are its parts."
);

pyo3::create_exception!(
    wetbounce,
    OutputError,
    pyo3::exceptions::PyOSError,
    "An output file that cannot be written: ``str(e)`` names each failing file and the OS \
     error, one per line, as ``wetbounce run`` does; ``e.files`` lists the files."
);

/// A [`SceneError`] carrying the engine's message and its parts.
pub fn scene_error(e: &EngineSceneError) -> PyErr {
    let err = SceneError::new_err(e.to_string());
    Python::attach(|py| {
        let v = err.value(py);
        let (file, message) = match e {
            EngineSceneError::Read { file, source } => (file, source.to_string()),
            EngineSceneError::Parse { file, message, .. }
            | EngineSceneError::Invalid { file, message, .. } => (file, message.clone()),
        };
        // Setting attributes on a fresh exception instance cannot fail short of memory.
        let _ = v.setattr("file", file.display().to_string());
        let _ = v.setattr("key", e.key());
        let _ = v.setattr("message", message);
    });
    err
}

/// An [`OutputError`] naming every failing file.
pub fn output_error(errors: &[EngineOutputError]) -> PyErr {
    let text = errors.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n");
    let err = OutputError::new_err(text);
    Python::attach(|py| {
        let files: Vec<String> = errors.iter().map(|e| e.path.display().to_string()).collect();
        let _ = err.value(py).setattr("files", files);
    });
    err
}
