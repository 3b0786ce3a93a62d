//! What a run will cost before it starts: the memory its particles take, and the bytes its
//! outputs write. Both are computed from counts in the scene file (no particle is placed, no
//! column allocated), so that `wetbounce check` can say what a run costs without paying it, and
//! loading can refuse a scene whose run cannot fit in the machine's memory before the scene
//! itself has allocated anything large.

use super::error::Invalid;
use super::schema::SceneFile;
use crate::fluid::Flow;

/// Heap bytes per particle of a running simulation without the history effect: the particle
/// columns, the end-of-step columns, the broad phase and the neighbour list, measured by
/// `tools/memory.rs` (`cargo run --release --bin memory -- 1000000`: 180 B at N = 10⁶),
/// rounded up for the scenes with spin columns and denser neighbour lists.
pub const ENGINE_BYTES_PER_PARTICLE: f64 = 256.0;

/// Bytes of one history mode of one particle: a `DVec3`.
const MODE_BYTES: f64 = 24.0;

/// Copies of the history memory a running simulation holds: the memory at the start of the
/// step (`Particles::memory`) and at its end (the step's scratch), swapped at commit.
const MEMORY_COPIES: f64 = 2.0;

/// Bytes written per particle and frame to `trajectories.csv`: a row of the time, the id, six
/// coordinates in shortest round-trip form and the state. Measured 59 B (one drop, x = y = 0,
/// `scenes/toluene_drop.toml`) and 86 B (10⁴ beads, `scenes/bench_dilute.toml` for 0.02 s);
/// rounded up for rows whose every coordinate has all its digits.
pub const CSV_ROW_BYTES: f64 = 100.0;
/// [`CSV_ROW_BYTES`] with the three spin columns of a scene with rotation: measured 120 B
/// (`scenes/settling_bed_friction.toml` for 0.2 s, 2000 beads settling), rounded up.
pub const CSV_ROW_SPIN_BYTES: f64 = 130.0;
/// Bytes written per particle and frame to the MCAP (zstd chunks of the point cloud, the
/// spheres, and the contacts on `/events` and `/event_log`): measured 83 B on the settling bed
/// (`scenes/settling_bed.toml`, 50.0 MB), 89 B on the column (`scenes/column.toml`, 65.7 MB
/// over 742,000 particle-frames), 2.4 B on the dilute lattice (zstd packs its regular
/// values); rounded up. A burst of contacts writes more (121 B over the first 0.2 s of a
/// 10⁴-bead bed, `tools/foxglove/size.sh`), but not for a whole run.
pub const MCAP_PARTICLE_BYTES: f64 = 90.0;
/// Bytes of an MCAP frame besides its particles (the frame's scene update, the walls'
/// entities): measured 480 B per frame on the one-drop scene.
pub const MCAP_FRAME_BYTES: f64 = 500.0;
/// Bytes written per particle and frame to the VTK frames (zlib-compressed base64 arrays):
/// measured 44 B on the settling bed, 10 B on the dilute lattice; rounded up.
pub const VTK_PARTICLE_BYTES: f64 = 50.0;
/// Bytes of a VTK frame without its particles (the `.vtp`'s XML, its line in the `.pvd`):
/// measured 2064 B per frame on the one-drop scene.
pub const VTK_FRAME_BYTES: f64 = 2100.0;

/// Output bytes past which `check` and `run` warn (10 GB).
pub const OUTPUT_WARNING_BYTES: f64 = 1e10;

/// The cost of a run, from counts.
#[derive(Debug, Clone, PartialEq)]
pub struct RunEstimate {
    /// Initial particles (from the file's `particles`, `lattice` and `random_fill`).
    pub initial_particles: f64,
    /// Most particles the run can hold: the initial ones and every particle the injectors
    /// can inject by the end (outlets and losses not counted: an upper bound).
    pub max_particles: f64,
    /// The key that contributes most particles (what to lower).
    pub key: String,
    /// History modes stored per particle, three numbers each (0 without the history effect;
    /// `MemoryKernel::stored_modes`).
    pub history_modes: usize,
    /// Bytes of a particle in the running simulation.
    pub bytes_per_particle: f64,
    /// Bytes of the flow field's velocity values (all snapshots), 0 for an analytic flow.
    pub field_bytes: f64,
    /// Particles summed over the run's frames (the rows of trajectories.csv): `frames ×
    /// initial` plus what the injectors have added by each frame.
    pub particle_frames: f64,
    /// Output frames.
    pub frames: f64,
}

impl RunEstimate {
    /// The same run with `modes` history modes stored per particle (the memory folded for a
    /// time step chosen after the estimate, `dt = "auto"`).
    pub fn with_history_modes(mut self, modes: usize) -> Self {
        self.bytes_per_particle += MEMORY_COPIES * MODE_BYTES * (modes as f64 - self.history_modes as f64);
        self.history_modes = modes;
        self
    }

    /// Bytes of memory of the run: particles at their most, and the flow field.
    pub fn memory_bytes(&self) -> f64 {
        self.max_particles * self.bytes_per_particle + self.field_bytes
    }

    /// Bytes the run writes to `trajectories.csv` (with the spin columns when `rotation`).
    pub fn csv_bytes(&self, rotation: bool) -> f64 {
        self.particle_frames * if rotation { CSV_ROW_SPIN_BYTES } else { CSV_ROW_BYTES }
    }

    /// Bytes the run writes to the MCAP.
    pub fn mcap_bytes(&self) -> f64 {
        self.particle_frames * MCAP_PARTICLE_BYTES + self.frames * MCAP_FRAME_BYTES
    }

    /// Bytes the run writes to the VTK frames.
    pub fn vtk_bytes(&self) -> f64 {
        self.particle_frames * VTK_PARTICLE_BYTES + self.frames * VTK_FRAME_BYTES
    }

    /// The same run with frames every `output_interval` (s) instead (`run --output-interval`).
    pub fn with_output_interval(&self, duration: f64, output_interval: f64, inputs: &EstimateInputs) -> Self {
        let (frames, particle_frames) = inputs.frames(duration, output_interval);
        RunEstimate { frames, particle_frames, ..self.clone() }
    }
}

/// What the particle-frame count needs besides the two times: the initial particles and each
/// injector's `(rate, start, stop)`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EstimateInputs {
    /// Initial particles.
    pub initial: f64,
    /// Each injector's rate (1/s) and the times it starts and stops injecting (s), clamped to
    /// the run.
    pub injectors: Vec<(f64, f64, f64)>,
}

impl EstimateInputs {
    /// Frames of a run of `duration` with frames every `output_interval` (the first at t = 0),
    /// and the particles summed over those frames.
    pub fn frames(&self, duration: f64, output_interval: f64) -> (f64, f64) {
        let frames = (duration / output_interval).floor() + 1.0;
        // Injected by frame time t: rate × (clamp(t, s, e) − s); summed over frames ≈ its
        // integral over the run divided by the interval (exact for a linear ramp up to one
        // frame's worth), plus the injected at the end for the first frame's rounding.
        let injected: f64 = self
            .injectors
            .iter()
            .map(|&(rate, s, e)| {
                let ramp = 0.5 * (e - s) * (e - s) + (e - s) * (duration - e);
                rate * (ramp / output_interval + (e - s))
            })
            .sum();
        (frames, frames * self.initial + injected)
    }
}

/// Counts the particles a scene file asks for, without placing any: `(initial, the key that
/// gives most, the inputs of the frame count)`. Values the loader will refuse later (a NaN
/// spacing, a negative rate) count as nothing here, so that the loader's own message comes.
pub(super) fn count_particles(file: &SceneFile, duration: f64) -> (f64, String, EstimateInputs) {
    let mut biggest = (file.particles.len() as f64, "particles".to_string());
    let mut note = |n: f64, key: String| {
        if n > biggest.0 {
            biggest = (n, key);
        }
        n
    };
    let mut initial = file.particles.len() as f64;
    for (i, l) in file.lattice.iter().enumerate() {
        let n = super::fill::lattice_counts(l.min.0.into(), l.max.0.into(), l.spacing);
        initial += note(n.x * n.y * n.z, format!("lattice[{i}].spacing"));
    }
    for (i, r) in file.random_fill.iter().enumerate() {
        initial += note(r.count as f64, format!("random_fill[{i}].count"));
    }
    let mut injectors = Vec::new();
    for (i, j) in file.injectors.iter().enumerate() {
        let rate = if j.rate.is_finite() && j.rate > 0.0 { j.rate } else { 0.0 };
        let start = if j.start.is_finite() { j.start.clamp(0.0, duration) } else { 0.0 };
        let stop = j.stop.filter(|s| s.is_finite()).unwrap_or(duration).clamp(start, duration);
        note(rate * (stop - start), format!("injectors[{i}].rate"));
        injectors.push((rate, start, stop));
    }
    (initial, biggest.1, EstimateInputs { initial, injectors })
}

/// The estimate of a scene file's run, once its physics (history modes) and flow are known.
pub(super) fn estimate(
    file: &SceneFile,
    (duration, output_interval): (f64, f64),
    history_modes: usize,
    flow: &Flow,
) -> (RunEstimate, EstimateInputs) {
    let (initial, key, inputs) = count_particles(file, duration);
    let injected: f64 = inputs.injectors.iter().map(|&(rate, s, e)| rate * (e - s)).sum();
    let walks = flow.field().is_some_and(|f| f.walks());
    let bytes_per_particle = ENGINE_BYTES_PER_PARTICLE
        + MEMORY_COPIES * MODE_BYTES * history_modes as f64
        + if walks { 4.0 } else { 0.0 };
    let field_bytes = flow
        .field()
        .map_or(0.0, |f| f.snapshots.iter().map(|s| s.values.len() as f64 * MODE_BYTES).sum::<f64>());
    let (frames, particle_frames) = inputs.frames(duration, output_interval);
    let estimate = RunEstimate {
        initial_particles: initial,
        max_particles: initial + injected,
        key,
        history_modes,
        bytes_per_particle,
        field_bytes,
        particle_frames,
        frames,
    };
    (estimate, inputs)
}

/// Bytes of memory available to a new process: `MemAvailable` of `/proc/meminfo` (Linux), or
/// `None` where it cannot be read (then nothing is refused).
pub fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    meminfo_available(&text)
}

/// `MemAvailable` (kB) of a `/proc/meminfo` text, in bytes.
fn meminfo_available(text: &str) -> Option<f64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// Refuses a run whose memory is over `available` bytes, naming the key that drives it.
pub(super) fn check_memory(e: &RunEstimate, available: Option<f64>) -> Result<(), Invalid> {
    let Some(available) = available else { return Ok(()) };
    let need = e.memory_bytes();
    if need <= available {
        return Ok(());
    }
    Err(Invalid::new(
        e.key.clone(),
        format!(
            "the run would need about {} of memory ({}), more than the {} this machine has available \
             (MemAvailable in /proc/meminfo); lower it, or allow it with `--allow-large-memory`",
            bytes(need),
            memory_breakdown(e),
            bytes(available)
        ),
    ))
}

/// What the memory is made of, in words: `up to 1000000 particles × 2.03 kB each, 1.78 kB of it
/// the history effect's 37 modes, twice`.
pub fn memory_breakdown(e: &RunEstimate) -> String {
    let history = if e.history_modes > 0 {
        format!(
            ", {} of it the history effect's {} modes, twice",
            bytes(MEMORY_COPIES * MODE_BYTES * e.history_modes as f64),
            e.history_modes
        )
    } else {
        String::new()
    };
    let field = if e.field_bytes > 0.0 {
        format!(", plus {} of flow field", bytes(e.field_bytes))
    } else {
        String::new()
    };
    format!(
        "up to {} particles × {} each{history}{field}",
        count(e.max_particles),
        bytes(e.bytes_per_particle)
    )
}

/// A count: whole below 10⁷ (`25000`), short above (`2.5e11`).
pub fn count(n: f64) -> String {
    let n = n.round();
    if n < 1e7 { format!("{n}") } else { super::error::fmt::approx(n) }
}

/// Free bytes, for an unprivileged user, of the file system that holds `path` (`statvfs`), or
/// `None` where it cannot be read (then nothing is refused).
#[cfg(unix)]
pub fn free_disk_space(path: &std::path::Path) -> Option<f64> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).ok()?;
    let mut st = std::mem::MaybeUninit::<libc::statvfs>::uninit();
    // SAFETY: `c` is a NUL-terminated path and `st` a buffer of the size statvfs writes; it is
    // read only when the call succeeds.
    let st = unsafe {
        if libc::statvfs(c.as_ptr(), st.as_mut_ptr()) != 0 {
            return None;
        }
        st.assume_init()
    };
    Some(st.f_bavail as f64 * st.f_frsize as f64)
}

/// Free bytes of the file system that holds `path`: not known off Unix.
#[cfg(not(unix))]
pub fn free_disk_space(_path: &std::path::Path) -> Option<f64> {
    None
}

/// A byte count in decimal units, 3 significant digits: `950 B`, `1.32 kB`, `17.6 GB`.
pub fn bytes(b: f64) -> String {
    const UNITS: [&str; 7] = ["B", "kB", "MB", "GB", "TB", "PB", "EB"];
    let mut v = b;
    let mut u = 0;
    while v >= 999.5 && u < UNITS.len() - 1 {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 {
        format!("{v:.0} B")
    } else {
        let prec = if v < 9.995 {
            2
        } else if v < 99.95 {
            1
        } else {
            0
        };
        format!("{v:.prec$} {}", UNITS[u])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts_are_written_with_three_digits_and_a_decimal_unit() {
        assert_eq!(bytes(950.0), "950 B");
        assert_eq!(bytes(1320.0), "1.32 kB");
        assert_eq!(bytes(17.6e9), "17.6 GB");
        assert_eq!(bytes(21e12), "21.0 TB");
        assert_eq!(bytes(999.6e6), "1.00 GB");
    }

    #[test]
    fn mem_available_is_read_in_bytes_from_a_meminfo_text() {
        let text = "MemTotal:       32768000 kB\nMemFree:  100 kB\nMemAvailable:   23582208 kB\n";
        assert_eq!(meminfo_available(text), Some(23582208.0 * 1024.0));
        assert_eq!(meminfo_available("MemTotal: 1 kB\n"), None);
    }
}
