//! Going on from a checkpoint: the scene rebuilt from the checkpoint's text (or from a new file
//! that changes only what may change), the simulation restored, and, when the resumed run
//! writes to another folder, the files of the run so far carried there.

use super::checkpoint::{self, CheckpointError, Header, Saved};
use crate::output::SinkMark;
use crate::pipeline::Simulation;
use crate::scene::{LoadOptions, Scene};
use std::path::{Path, PathBuf};

/// The keys a scene may change between a checkpoint and its resumption: the run's length, its
/// output interval and its checkpoints. Any other change would make the resumed run another
/// run than the one checkpointed.
pub const CHANGEABLE_KEYS: &[&str] = &["simulation.duration", "simulation.output_interval", "checkpoint"];

/// A checkpoint read and its run rebuilt: the scene (its duration and output interval those of
/// the new file, if one was given) and the simulation where the checkpoint left it.
pub struct Resumed {
    /// The checkpoint's header.
    pub header: Header,
    /// The checkpoint's payload, its world moved into `sim`.
    pub saved: Saved,
    /// The scene, rebuilt.
    pub scene: Scene,
    /// The simulation at the checkpoint.
    pub sim: Simulation,
}

/// Reads the checkpoint at `path` and rebuilds its run; with `new_scene`, the scene is that
/// file's, which may differ from the checkpointed one only in [`CHANGEABLE_KEYS`] (a longer
/// duration: the run goes on further). Every refusal names the file and what differs.
pub fn resume(path: &Path, new_scene: Option<&Path>) -> Result<Resumed, CheckpointError> {
    let (header, mut saved) = checkpoint::read(path)?;
    let scene_error = |problem: String| CheckpointError::Scene { path: path.to_path_buf(), problem };
    let (scene_path, source) = match new_scene {
        None => (saved.scene.path.clone(), saved.scene.source.clone()),
        Some(new) => {
            let text = crate::files::read_text(new, crate::scene::SCENE_FILE_CAP, "a scene file")
                .map_err(|e| scene_error(format!("{}: {e}", new.display())))?;
            scene_change(&saved.scene.source, &text)
                .map_err(|e| scene_error(format!("{}: {e}", new.display())))?;
            (std::path::absolute(new).unwrap_or_else(|_| new.to_path_buf()), text)
        }
    };
    // The run was accepted when it started; its checks of length and memory are not made again.
    let options = LoadOptions { allow_long_run: true, allow_large_memory: true };
    let scene = Scene::from_str_with(&source, &scene_path, options)
        .map_err(|e| scene_error(format!("the scene no longer loads: {e}")))?;
    if scene.duration < saved.world.time {
        return Err(scene_error(format!(
            "simulation.duration = {} s is before the checkpoint's time, {} s",
            scene.duration, saved.world.time
        )));
    }
    if scene.setup.injectors.len() != saved.world.injection.len()
        || scene.setup.outlets.len() != saved.removed.len()
    {
        return Err(scene_error("the scene's injectors or outlets are not the checkpoint's".into()));
    }
    let world = std::mem::take(&mut saved.world);
    let record = (std::mem::take(&mut saved.lost), std::mem::take(&mut saved.removed), saved.left_field);
    let sim = Simulation::restore(scene.setup.clone(), world, record).map_err(|e| CheckpointError::Read {
        path: path.to_path_buf(),
        problem: format!("this machine cannot give the memory of the run: {e}"),
    })?;
    if let Some(new) = new_scene {
        saved.scene.given = new.to_path_buf();
    }
    saved.scene.path = scene_path;
    saved.scene.source = source;
    Ok(Resumed { header, saved, scene, sim })
}

/// Checks that `new` (a scene's text) differs from `old` only in [`CHANGEABLE_KEYS`]; the first
/// other difference is an error naming its key and both values.
pub fn scene_change(old: &str, new: &str) -> Result<(), String> {
    let parse = |text: &str, which: &str| {
        text.parse::<toml::Table>().map_err(|e| format!("the {which} scene is not TOML: {e}"))
    };
    let (mut old, mut new) = (parse(old, "checkpointed")?, parse(new, "new")?);
    for key in CHANGEABLE_KEYS {
        for t in [&mut old, &mut new] {
            remove_key(t, key);
        }
    }
    match first_difference("", &toml::Value::Table(old), &toml::Value::Table(new)) {
        None => Ok(()),
        Some((key, a, b)) => Err(format!(
            "`{key}` differs from the checkpointed scene ({a} there, {b} here); only {} may change \
             when a run is resumed",
            CHANGEABLE_KEYS.join(", ")
        )),
    }
}

fn remove_key(table: &mut toml::Table, dotted: &str) {
    match dotted.split_once('.') {
        None => {
            table.remove(dotted);
        }
        Some((head, rest)) => {
            if let Some(toml::Value::Table(t)) = table.get_mut(head) {
                remove_key(t, rest);
            }
        }
    }
}

/// The first key (dotted, arrays by index) where `a` and `b` differ, with both values (`absent`
/// when one has no such key).
fn first_difference(at: &str, a: &toml::Value, b: &toml::Value) -> Option<(String, String, String)> {
    let join = |k: &str| if at.is_empty() { k.to_string() } else { format!("{at}.{k}") };
    let show = |v: Option<&toml::Value>| v.map_or("absent".to_string(), |v| v.to_string());
    match (a, b) {
        (toml::Value::Table(x), toml::Value::Table(y)) => {
            let keys = x.keys().chain(y.keys().filter(|k| !x.contains_key(*k)));
            for k in keys {
                match (x.get(k), y.get(k)) {
                    (Some(u), Some(v)) => {
                        if let Some(d) = first_difference(&join(k), u, v) {
                            return Some(d);
                        }
                    }
                    (u, v) => return Some((join(k), show(u), show(v))),
                }
            }
            None
        }
        (toml::Value::Array(x), toml::Value::Array(y)) => {
            for i in 0..x.len().max(y.len()) {
                let key = format!("{at}[{i}]");
                match (x.get(i), y.get(i)) {
                    (Some(u), Some(v)) => {
                        if let Some(d) = first_difference(&key, u, v) {
                            return Some(d);
                        }
                    }
                    (u, v) => return Some((key, show(u), show(v))),
                }
            }
            None
        }
        _ if a == b => None,
        _ => Some((at.to_string(), a.to_string(), b.to_string())),
    }
}

/// The output folder of the run a checkpoint was written by: checkpoints go to
/// `OUT/checkpoints/`.
pub fn run_folder(checkpoint: &Path) -> PathBuf {
    let dir = checkpoint.parent().unwrap_or(Path::new("."));
    match dir.file_name() {
        Some(n) if n == "checkpoints" => dir.parent().unwrap_or(Path::new(".")).to_path_buf(),
        _ => dir.to_path_buf(),
    }
}

/// Copies the files of the run so far from `from` to `to` as far as the checkpoint knew them
/// (each CSV file and the ParaView collection up to its mark, its frames, the MCAP parts), so
/// that the resumed run in `to` goes on from them. Nothing is copied when both are one folder.
pub fn carry_outputs(from: &Path, to: &Path, saved: &Saved) -> std::io::Result<()> {
    let same = std::fs::canonicalize(from).ok() == std::fs::canonicalize(to).ok();
    if same {
        return Ok(());
    }
    std::fs::create_dir_all(to)?;
    let stem = &saved.scene.stem;
    let prefix = |name: &str, bytes: u64| -> std::io::Result<()> {
        use std::io::{Read, Write};
        let mut source = std::fs::File::open(from.join(name))?.take(bytes);
        let mut target = std::fs::File::create(to.join(name))?;
        std::io::copy(&mut source, &mut target)?;
        target.flush()
    };
    for mark in &saved.sinks {
        match mark {
            SinkMark::File { name, bytes } => prefix(name, *bytes)?,
            SinkMark::Vtk { tail_at, frames, walls_written } => {
                let pvd = format!("{stem}.pvd");
                // The collection up to its closing tags, which the resumed run writes after its
                // next entry (`VtkSink::resume` cuts after them).
                prefix(&pvd, tail_at + crate::output::vtk::PVD_TAIL.len() as u64)?;
                let frames_dir = format!("{stem}_vtk");
                std::fs::create_dir_all(to.join(&frames_dir))?;
                for k in 0..*frames {
                    let name = format!("{frames_dir}/particles_{k:06}.vtp");
                    std::fs::copy(from.join(&name), to.join(&name))?;
                }
                if *walls_written {
                    let walls = format!("{stem}_walls.vtp");
                    std::fs::copy(from.join(&walls), to.join(&walls))?;
                }
            }
            SinkMark::Parts { format, parts, .. } => {
                for part in 1..=*parts {
                    let name = crate::output::part_file(stem, part, format);
                    if from.join(&name).is_file() {
                        std::fs::copy(from.join(&name), to.join(&name))?;
                    }
                }
            }
            SinkMark::Statistics(_) => {}
        }
    }
    // The Foxglove layout the first part's MCAP wrote at its first frame (a resumed MCAP part
    // writes none: the run's layout is that one).
    let layout = crate::output::mcap::layout::file_name(stem);
    if from.join(&layout).is_file() {
        std::fs::copy(from.join(&layout), to.join(&layout))?;
    }
    Ok(())
}
