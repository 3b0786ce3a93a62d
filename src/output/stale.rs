//! An earlier run's outputs in the folder a new run writes into: the files of formats this run
//! does not write, and the VTK frames past this run's, which a viewer would read as this run's
//! (a `.pvd` beside 1,001 frames of which it lists 11, an old MCAP beside the new CSV; issue 25,
//! finding 13).
//!
//! Only the names a run itself writes are touched: `<stem>.mcap` and
//! `<stem>_foxglove_layout.json`, `<stem>.rrd`,
//! `trajectories.csv`, `events.csv`, `<stem>.pvd`, `<stem>_walls.vtp` and, inside
//! `<stem>_vtk/`, the frames `particles_NNNNNN.vtp` (the folder itself once empty). A user's
//! own files in the folder are never removed.

use std::path::{Path, PathBuf};

/// What [`remove`] did: the paths removed, and one message per path that could not be.
#[derive(Debug, Default)]
pub struct Removed {
    /// Removed files (and the frames' folder when it was left empty).
    pub removed: Vec<PathBuf>,
    /// `PATH: cannot remove this output of an earlier run: CAUSE`, one per failure.
    pub failed: Vec<String>,
}

/// The name of a VTK frame as [`super::VtkSink`] writes it: `particles_` and six or more digits.
pub(crate) fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("particles_")
        .and_then(|rest| rest.strip_suffix(".vtp"))
        .is_some_and(|digits| digits.len() >= 6 && digits.bytes().all(|b| b.is_ascii_digit()))
}

/// Removes the frames an earlier run left in `frames_dir` (a VTK sink that starts writing there
/// calls it first, so its `.pvd` and its folder agree frame for frame).
pub(crate) fn remove_frames(frames_dir: &Path, into: &mut Removed) {
    let Ok(entries) = std::fs::read_dir(frames_dir) else { return };
    let mut frames: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter(|e| e.file_name().to_str().is_some_and(is_frame_name))
        .map(|e| e.path())
        .collect();
    frames.sort();
    for p in frames {
        remove_file(p, into);
    }
}

fn remove_file(p: PathBuf, into: &mut Removed) {
    match std::fs::remove_file(&p) {
        Ok(()) => into.removed.push(p),
        Err(e) => {
            into.failed.push(format!("{}: cannot remove this output of an earlier run: {e}", p.display()))
        }
    }
}

/// Removes from `out` the outputs of an earlier run of the scene `stem` that this run does not
/// write (`written`: the files this run's sinks created). Call it after the sinks are created,
/// so that a run that cannot start removes nothing. The frames of a VTK sink this run does write
/// were already cleared by the sink itself.
pub fn remove(out: &Path, stem: &str, written: &[PathBuf]) -> Removed {
    let mut result = Removed::default();
    let files = [
        format!("{stem}.mcap"),
        super::mcap::layout::file_name(stem),
        "trajectories.csv".into(),
        "events.csv".into(),
        format!("{stem}.rrd"),
        format!("{stem}.pvd"),
        format!("{stem}_walls.vtp"),
    ];
    for p in files.iter().map(|name| out.join(name)) {
        if !written.contains(&p) && p.is_file() {
            remove_file(p, &mut result);
        }
    }
    let pvd = out.join(format!("{stem}.pvd"));
    let frames_dir = out.join(format!("{stem}_vtk"));
    if !written.contains(&pvd) && frames_dir.is_dir() {
        remove_frames(&frames_dir, &mut result);
        // The folder only if nothing else is in it (a user's file stays, and so does the folder).
        if std::fs::remove_dir(&frames_dir).is_ok() {
            result.removed.push(frames_dir);
        }
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names_are_recognised_and_nothing_else() {
        assert!(is_frame_name("particles_000000.vtp"));
        assert!(is_frame_name("particles_1234567.vtp"));
        for other in [
            "particles_00000.vtp",
            "particles_00000a.vtp",
            "particles_000000.vtu",
            "mine.vtp",
            "particles_.vtp",
        ] {
            assert!(!is_frame_name(other), "{other}");
        }
    }

    #[test]
    fn only_the_runs_own_names_are_removed_and_a_users_file_keeps_its_folder() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path();
        for name in
            ["s.mcap", "trajectories.csv", "events.csv", "s.pvd", "s_walls.vtp", "notes.txt", "t.mcap"]
        {
            std::fs::write(out.join(name), "x").unwrap();
        }
        std::fs::create_dir(out.join("s_vtk")).unwrap();
        for name in ["particles_000000.vtp", "particles_000001.vtp", "mine.vtp"] {
            std::fs::write(out.join("s_vtk").join(name), "x").unwrap();
        }
        let written = vec![out.join("s.mcap")];
        let r = remove(out, "s", &written);
        assert!(r.failed.is_empty(), "{:?}", r.failed);
        for kept in ["s.mcap", "notes.txt", "t.mcap", "s_vtk/mine.vtp"] {
            assert!(out.join(kept).exists(), "{kept} was removed");
        }
        for gone in ["trajectories.csv", "events.csv", "s.pvd", "s_walls.vtp", "s_vtk/particles_000000.vtp"] {
            assert!(!out.join(gone).exists(), "{gone} was kept");
        }
        std::fs::remove_file(out.join("s_vtk/mine.vtp")).unwrap();
        std::fs::write(out.join("s_vtk/particles_000003.vtp"), "x").unwrap();
        let r = remove(out, "s", &written);
        assert!(r.removed.contains(&out.join("s_vtk")), "{:?}", r.removed);
    }
}
