//! Python values ↔ TOML values, and the dotted key paths of scene messages
//! (`kinds[0].density`, `simulation.duration`).

use pyo3::exceptions::{PyKeyError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use pyo3::{IntoPyObjectExt, PyResult};
use toml::{Table, Value};

/// A Python value as a TOML value: `bool`, `int`, `float`, `str`, a mapping with `str` keys
/// (a table), a list or tuple (an array); anything with `tolist()` (a NumPy array or scalar)
/// through that. `where_` names the key, for the error.
pub fn to_toml(obj: &Bound<'_, PyAny>, where_: &str) -> PyResult<Value> {
    // `bool` before `int`: in Python a bool is an int.
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(Value::Boolean(b.is_true()));
    }
    if obj.is_instance_of::<PyInt>() {
        return match obj.extract::<i64>() {
            Ok(i) => Ok(Value::Integer(i)),
            Err(_) => Err(PyTypeError::new_err(format!("{where_}: integer out of the 64-bit range"))),
        };
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(Value::Float(obj.extract::<f64>()?));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::String(s.to_str()?.to_owned()));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        return Ok(Value::Table(dict_to_table(d, where_)?));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, item) in obj.try_iter()?.enumerate() {
            out.push(to_toml(&item?, &format!("{where_}[{i}]"))?);
        }
        return Ok(Value::Array(out));
    }
    if obj.hasattr("tolist")? {
        return to_toml(&obj.call_method0("tolist")?, where_);
    }
    if obj.hasattr("items")? {
        let d = PyDict::new(obj.py());
        d.call_method1("update", (obj,))?;
        return Ok(Value::Table(dict_to_table(&d, where_)?));
    }
    let type_name = obj.get_type().name()?;
    Err(PyTypeError::new_err(format!(
        "{where_}: a scene value is a bool, int, float, str, dict or list, got {type_name}"
    )))
}

/// A dict with `str` keys as a TOML table, in the dict's order.
pub fn dict_to_table(d: &Bound<'_, PyDict>, where_: &str) -> PyResult<Table> {
    let mut t = Table::new();
    for (k, v) in d.iter() {
        let Ok(key) = k.extract::<String>() else {
            return Err(PyTypeError::new_err(format!("{where_}: scene keys are str, got {}", k.repr()?)));
        };
        let path = if where_.is_empty() { key.clone() } else { format!("{where_}.{key}") };
        // `None` means "not given", as a key left out of a file.
        if v.is_none() {
            continue;
        }
        t.insert(key, to_toml(&v, &path)?);
    }
    Ok(t)
}

/// A TOML value as a Python value (tables as dicts, arrays as lists, dates as strings).
pub fn to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    match v {
        Value::String(s) => s.into_bound_py_any(py),
        Value::Integer(i) => i.into_bound_py_any(py),
        Value::Float(f) => f.into_bound_py_any(py),
        Value::Boolean(b) => b.into_bound_py_any(py),
        Value::Datetime(d) => d.to_string().into_bound_py_any(py),
        Value::Array(a) => {
            let items = a.iter().map(|x| to_py(py, x)).collect::<PyResult<Vec<_>>>()?;
            Ok(PyList::new(py, items)?.into_any())
        }
        Value::Table(t) => Ok(table_to_py(py, t)?.into_any()),
    }
}

/// A TOML table as a Python dict.
pub fn table_to_py<'py>(py: Python<'py>, t: &Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in t {
        d.set_item(k, to_py(py, v)?)?;
    }
    Ok(d)
}

/// One step of a key path: a table's key or an array's index.
#[derive(Debug, Clone, PartialEq)]
enum Segment {
    Key(String),
    Index(usize),
}

/// `kinds[0].density` → `kinds`, `0`, `density`: the key paths of the scene's error messages.
fn parse_path(path: &str) -> PyResult<Vec<Segment>> {
    let bad = || {
        PyKeyError::new_err(format!(
            "{path}: not a key path like `simulation.duration` or `kinds[0].density`"
        ))
    };
    let mut out = Vec::new();
    for part in path.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if name.is_empty() {
            return Err(bad());
        }
        out.push(Segment::Key(name.to_owned()));
        while !rest.is_empty() {
            let close = rest.find(']').ok_or_else(bad)?;
            if !rest.starts_with('[') {
                return Err(bad());
            }
            let index = rest[1..close].trim().parse::<usize>().map_err(|_| bad())?;
            out.push(Segment::Index(index));
            rest = &rest[close + 1..];
        }
    }
    Ok(out)
}

/// The value at `path` in `doc`.
pub fn get<'a>(doc: &'a Table, path: &str) -> PyResult<&'a Value> {
    let segments = parse_path(path)?;
    let missing = || PyKeyError::new_err(format!("{path}: no such key in the scene"));
    let mut here: Option<&Value> = None;
    for s in &segments {
        here = Some(match (here, s) {
            (None, Segment::Key(k)) => doc.get(k).ok_or_else(missing)?,
            (Some(Value::Table(t)), Segment::Key(k)) => t.get(k).ok_or_else(missing)?,
            (Some(Value::Array(a)), Segment::Index(i)) => a.get(*i).ok_or_else(missing)?,
            _ => return Err(missing()),
        });
    }
    here.ok_or_else(missing)
}

/// Sets the value at `path` in `doc` (`None` removes the key). A missing key of a table is
/// created, with the tables on its way; an array index must exist, or be the array's length
/// (appends).
pub fn set(doc: &mut Table, path: &str, value: Option<Value>) -> PyResult<()> {
    let segments = parse_path(path)?;
    let missing = |what: &str| PyKeyError::new_err(format!("{path}: {what}"));
    let (last, parents) = segments.split_last().ok_or_else(|| missing("empty key path"))?;
    // Walk down with a table or an array in hand.
    enum Place<'a> {
        Table(&'a mut Table),
        Array(&'a mut Vec<Value>),
    }
    let mut here = Place::Table(doc);
    for (i, s) in parents.iter().enumerate() {
        let next_is_index = matches!(segments[i + 1], Segment::Index(_));
        let child: &mut Value = match (here, s) {
            (Place::Table(t), Segment::Key(k)) => t.entry(k.clone()).or_insert_with(|| {
                if next_is_index { Value::Array(Vec::new()) } else { Value::Table(Table::new()) }
            }),
            (Place::Array(a), Segment::Index(i)) => {
                let n = a.len();
                a.get_mut(*i).ok_or_else(|| missing(&format!("index {i} out of range ({n} entries)")))?
            }
            _ => return Err(missing("does not match the scene's structure")),
        };
        here = match child {
            Value::Table(t) => Place::Table(t),
            Value::Array(a) => Place::Array(a),
            _ => return Err(missing("goes through a value that is neither a table nor an array")),
        };
    }
    match (here, last, value) {
        (Place::Table(t), Segment::Key(k), Some(v)) => {
            t.insert(k.clone(), v);
        }
        (Place::Table(t), Segment::Key(k), None) => {
            t.remove(k);
        }
        (Place::Array(a), Segment::Index(i), v) => {
            let n = a.len();
            match v {
                Some(v) if *i < n => a[*i] = v,
                Some(v) if *i == n => a.push(v),
                None if *i < n => {
                    a.remove(*i);
                }
                _ => return Err(missing(&format!("index {i} out of range ({n} entries)"))),
            }
        }
        _ => return Err(missing("does not match the scene's structure")),
    }
    Ok(())
}
