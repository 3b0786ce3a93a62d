//! Scene errors: every one names the file, the key path and the bad value.

use std::path::PathBuf;

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{file}: cannot read the scene file: {source}")]
    Read {
        /// The scene file.
        file: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is not valid TOML, or a value has the wrong type, or a key is missing or unknown.
    #[error("{file}: {key}: {message}")]
    Parse {
        /// The scene file.
        file: PathBuf,
        /// Dotted key path (`kinds[0].density`); `(top level)` for the whole file.
        key: String,
        /// What is wrong, with the line and column.
        message: String,
    },
    /// A value is out of range, an unknown name, or inconsistent with the rest of the scene.
    #[error("{file}: {key}: {message}")]
    Invalid {
        /// The scene file.
        file: PathBuf,
        /// Dotted key path.
        key: String,
        /// What is wrong, with the bad value.
        message: String,
    },
}

impl SceneError {
    /// The key path the error is about.
    pub fn key(&self) -> &str {
        match self {
            SceneError::Read { .. } => "",
            SceneError::Parse { key, .. } | SceneError::Invalid { key, .. } => key,
        }
    }
}

/// Collects the key and message of a validation failure; the loader adds the file.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Invalid {
    pub key: String,
    pub message: String,
}

impl Invalid {
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        Invalid { key: key.into(), message: message.into() }
    }
}

/// Checks of the scene's fields, each returning the value or an [`Invalid`] naming `key`.
pub(crate) mod check {
    use super::Invalid;
    use glam::DVec3;

    /// A key that the entry's `type` (`what`: "a plane", "a box injector region") needs.
    pub fn required<T>(key: &str, v: Option<T>, what: &str) -> Result<T, Invalid> {
        v.ok_or_else(|| Invalid::new(key, format!("missing: required for {what}")))
    }

    /// A key that the entry's `type` does not have.
    pub fn forbid(key: &str, present: bool, what: &str) -> Result<(), Invalid> {
        if present { Err(Invalid::new(key, format!("not a key of {what}"))) } else { Ok(()) }
    }

    /// Rejects the first key of the table at `key` that is present but not `allowed` for its
    /// `type` (`what`), listing the allowed ones. The one check of every table whose keys
    /// depend on its type (flows, walls, injector regions and sizes, outlets).
    pub fn only(key: &str, present: &[(&str, bool)], allowed: &[&str], what: &str) -> Result<(), Invalid> {
        let Some((extra, _)) = present.iter().find(|(name, here)| *here && !allowed.contains(name)) else {
            return Ok(());
        };
        let keys = if allowed.is_empty() {
            "it has no other keys".to_string()
        } else {
            format!("its keys are: {}", allowed.join(", "))
        };
        Err(Invalid::new(format!("{key}.{extra}"), format!("not a key of {what}; {keys}")))
    }

    pub fn finite(key: &str, v: f64) -> Result<f64, Invalid> {
        if v.is_finite() { Ok(v) } else { Err(Invalid::new(key, format!("must be finite, got {v}"))) }
    }

    pub fn positive(key: &str, v: f64) -> Result<f64, Invalid> {
        finite(key, v)?;
        if v > 0.0 { Ok(v) } else { Err(Invalid::new(key, format!("must be > 0, got {v}"))) }
    }

    pub fn non_negative(key: &str, v: f64) -> Result<f64, Invalid> {
        finite(key, v)?;
        if v >= 0.0 { Ok(v) } else { Err(Invalid::new(key, format!("must be >= 0, got {v}"))) }
    }

    pub fn in_range(key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, Invalid> {
        finite(key, v)?;
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(Invalid::new(key, format!("must be between {lo} and {hi}, got {v}")))
        }
    }

    pub fn vector(key: &str, v: [f64; 3]) -> Result<DVec3, Invalid> {
        let d = DVec3::from(v);
        if d.is_finite() {
            Ok(d)
        } else {
            Err(Invalid::new(key, format!("must have finite components, got {v:?}")))
        }
    }

    pub fn direction(key: &str, v: [f64; 3]) -> Result<DVec3, Invalid> {
        let d = vector(key, v)?;
        let len = d.length();
        if len > 0.0 {
            Ok(d / len)
        } else {
            Err(Invalid::new(key, format!("must be a non-zero vector, got {v:?}")))
        }
    }
}
