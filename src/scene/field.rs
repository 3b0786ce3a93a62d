//! `fluid.flow` of `type = "field"`: the keys, the files (one, a list with times, or a `.pvd`
//! collection) and the [`Field`] they make. Errors name the key and, for a file, the file.

use super::error::Invalid;
use super::error::check;
use super::error::fmt::num;
use super::ranges::{SPEED, TIME};
use super::schema::{DataSpec, FieldSpec, OutsideSpec, Vec3Spec};
use super::table::{Place, Table};
use crate::fluid::field::read::{self, Loaded, Request};
use crate::fluid::field::{Axisymmetric, DataAt, Field, FieldInfo, Grid, Outside, Snapshot};
use crate::fluid::{Flow, SharedField};
use std::path::{Path, PathBuf};
use std::sync::Arc;

impl Table<Flow> for FieldSpec {
    const WHAT: &'static str = "a field flow";
    fn build(self, at: &Place, base: &Path) -> Result<Flow, Invalid> {
        build_field(&self, at, base)
    }
}

/// Builds a field flow; files are read relative to `base`.
fn build_field(f: &FieldSpec, at: &Place, base: &Path) -> Result<Flow, Invalid> {
    let k = |field: &str| at.k(field);
    let axisymmetric = f.axisymmetric.unwrap_or(false);
    if !axisymmetric {
        for (key, there) in [("point", f.point.is_some()), ("axis", f.axis.is_some())] {
            if there {
                return Err(Invalid::new(k(key), "only with axisymmetric = true (the table's axis)"));
            }
        }
    }
    // The snapshots: (file key, path, time).
    let mut entries: Vec<(String, PathBuf, f64)> = Vec::new();
    match (&f.file, &f.files) {
        (Some(_), Some(_)) => {
            return Err(Invalid::new(
                k("files"),
                "give either file (one file or a .pvd) or files with times, not both",
            ));
        }
        (None, None) => {
            return Err(Invalid::new(
                k("file"),
                "missing: a field flow needs file (a VTK file or a .pvd) or files",
            ));
        }
        (Some(file), None) => {
            if f.times.is_some() {
                return Err(Invalid::new(k("times"), "only with files = [...] (a .pvd gives its own times)"));
            }
            let path = base.join(file);
            if path.extension().and_then(|e| e.to_str()) == Some("pvd") {
                for (i, (name, time)) in
                    read_pvd(&path).map_err(|m| Invalid::new(k("file"), m))?.into_iter().enumerate()
                {
                    let dir = path.parent().unwrap_or(Path::new(""));
                    entries.push((format!("{} (data set {i} of {file})", k("file")), dir.join(name), time));
                }
            } else {
                entries.push((k("file"), path, 0.0));
            }
        }
        (None, Some(files)) => {
            let times = f.times.as_ref().ok_or_else(|| {
                Invalid::new(k("times"), "missing: files need their times (s), one per file, increasing")
            })?;
            if times.len() != files.len() || files.is_empty() {
                return Err(Invalid::new(
                    k("times"),
                    format!("needs one time per file: {} files, {} times", files.len(), times.len()),
                ));
            }
            for (i, (file, &t)) in files.iter().zip(times).enumerate() {
                let t = check::finite(&format!("{}[{i}]", k("times")), t)?;
                entries.push((format!("{}[{i}]", k("files")), base.join(file), t));
            }
        }
    }
    for (i, w) in entries.windows(2).enumerate() {
        if w[1].2 <= w[0].2 {
            let key = if f.files.is_some() { format!("{}[{}]", k("times"), i + 1) } else { k("file") };
            return Err(Invalid::new(
                key,
                format!(
                    "the snapshots' times must increase: {} at {} s comes after {} at {} s",
                    w[1].1.display(),
                    num(w[1].2),
                    w[0].1.display(),
                    num(w[0].2)
                ),
            ));
        }
    }
    let period = match f.period {
        None => None,
        Some(p) => {
            let p = check::positive_in(&k("period"), p, &TIME)?;
            let span = entries[entries.len() - 1].2 - entries[0].2;
            if entries.len() < 2 || p <= span {
                return Err(Invalid::new(
                    k("period"),
                    format!(
                        "must exceed the series' span ({} s from the first snapshot to the last) and needs two \
                         snapshots or more, got {} s",
                        num(span),
                        num(p)
                    ),
                ));
            }
            Some(p)
        }
    };
    let frame = if axisymmetric {
        let point = check::point(&k("point"), f.point.unwrap_or(Vec3Spec([0.0; 3])))?;
        let axis = check::direction(&k("axis"), f.axis.unwrap_or(Vec3Spec([0.0, 0.0, 1.0])))?;
        Some(Axisymmetric { point, axis })
    } else {
        None
    };
    let request = Request {
        array: f.array.as_deref(),
        data: f.data.map(|d| match d {
            DataSpec::Point => DataAt::Point,
            DataSpec::Cell => DataAt::Cell,
        }),
        axisymmetric,
    };
    let mut first: Option<Loaded> = None;
    let mut snapshots = Vec::new();
    for (key, path, time) in &entries {
        let mut loaded = read::load(path, request).map_err(|e| Invalid::new(key.clone(), e.to_string()))?;
        if let Some(f0) = &first
            && !same_grid(&f0.grid, &loaded.grid)
        {
            return Err(Invalid::new(
                key.clone(),
                format!(
                    "{}: its grid differs from {}'s: every snapshot of a series must be on the same grid",
                    path.display(),
                    entries[0].1.display()
                ),
            ));
        }
        let fastest = loaded.values.iter().map(|v| v.length()).fold(0.0, f64::max);
        if fastest > SPEED.max {
            return Err(Invalid::new(
                key.clone(),
                format!(
                    "{}: a velocity of {} m/s is beyond the speeds the engine takes (≤ {} m/s)",
                    path.display(),
                    num(fastest),
                    num(SPEED.max)
                ),
            ));
        }
        snapshots.push(Snapshot { time: *time, values: std::mem::take(&mut loaded.values) });
        if first.is_none() {
            first = Some(loaded);
        }
    }
    let Some(first) = first else {
        return Err(Invalid::new(k("file"), "the collection names no data set"));
    };
    let info = FieldInfo {
        files: entries.iter().map(|e| e.1.clone()).collect(),
        format: first.format.to_string(),
        array: format!(
            "\"{}\" ({} data)",
            first.array,
            match first.data {
                DataAt::Point => "point",
                DataAt::Cell => "cell",
            }
        ),
        ..FieldInfo::default()
    };
    let outside = match f.outside.unwrap_or(OutsideSpec::Error) {
        OutsideSpec::Error => Outside::Error,
        OutsideSpec::Zero => Outside::Zero,
        OutsideSpec::Nearest => Outside::Nearest,
    };
    let field = Field::new(first.grid, snapshots, period, outside, frame, info);
    Ok(Flow::Field(SharedField(Arc::new(field))))
}

/// Whether two snapshots' grids are the same (same nodes, same cells).
fn same_grid(a: &Grid, b: &Grid) -> bool {
    match (a, b) {
        (Grid::Structured(a), Grid::Structured(b)) => {
            a.axes.iter().zip(&b.axes).all(|(x, y)| x.nodes == y.nodes)
        }
        (Grid::Unstructured(a), Grid::Unstructured(b)) => a.nodes == b.nodes && a.tets == b.tets,
        _ => false,
    }
}

/// The largest `.pvd` collection read (bytes): one line per snapshot, so 16 MiB is some
/// 100 000 snapshots; a larger file is a wrong path ([`crate::files`]).
pub const PVD_FILE_CAP: u64 = 16 << 20;

/// The data sets of a ParaView collection (`.pvd`): each `<DataSet timestep="…" file="…"/>`,
/// file and time, in the order given. Read with an XML parser, as ParaView reads it: a
/// commented-out data set is not one, attribute values are unescaped, and any character may be
/// in a name.
fn read_pvd(path: &Path) -> Result<Vec<(String, f64)>, String> {
    use quick_xml::events::Event;
    let shown = path.display();
    let bytes = crate::files::read(path, PVD_FILE_CAP, "a .pvd collection").map_err(|p| match p {
        crate::files::FileProblem::Io(e) => format!("{shown}: cannot read the collection: {e}"),
        other => format!("{shown}: {other}"),
    })?;
    let mut reader = quick_xml::Reader::from_reader(bytes.as_slice());
    let mut out = Vec::new();
    let mut collection = false;
    loop {
        let at = reader.buffer_position();
        let event = reader
            .read_event()
            .map_err(|e| format!("{shown}: is not well-formed XML near byte {at}: {e}"))?;
        let e = match &event {
            Event::Start(e) | Event::Empty(e) => e,
            Event::Eof => break,
            _ => continue,
        };
        match e.local_name().as_ref() {
            b"Collection" => collection = true,
            b"DataSet" => {
                let i = out.len();
                let mut file = None;
                let mut time = None;
                for a in e.attributes() {
                    let a =
                        a.map_err(|err| format!("{shown}: data set {i} has a malformed attribute: {err}"))?;
                    let value = a
                        .unescape_value()
                        .map_err(|err| {
                            format!("{shown}: data set {i} has an attribute that cannot be read: {err}")
                        })?
                        .into_owned();
                    match a.key.local_name().as_ref() {
                        b"file" => file = Some(value),
                        b"timestep" => time = Some(value),
                        _ => {}
                    }
                }
                let file = file.ok_or_else(|| format!("{shown}: data set {i} has no file"))?;
                let time = match time {
                    Some(t) => t.trim().parse::<f64>().ok().filter(|t| t.is_finite()).ok_or_else(|| {
                        format!("{shown}: data set {i} ({file}) has timestep \"{t}\", not a finite number")
                    })?,
                    None => return Err(format!("{shown}: data set {i} ({file}) has no timestep")),
                };
                out.push((file, time));
            }
            _ => {}
        }
    }
    if !collection {
        return Err(format!("{shown}: not a ParaView collection (no <Collection>)"));
    }
    if out.is_empty() {
        return Err(format!("{shown}: the collection names no data set"));
    }
    Ok(out)
}
