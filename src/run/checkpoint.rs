//! Checkpoints: a run's whole state at a step boundary, written to a file from which
//! `wetbounce resume` continues it exactly (docs/output.md, "Checkpoints").
//!
//! A checkpoint holds everything the next step reads — the [`World`] (every particle column in
//! memory order, the features' columns with them, lasting contacts with their warm starts,
//! wall contacts, the neighbour list, each injector's counters and whole generator state, the
//! clock), what the run has recorded (lost particles, outlet removals), where the run loop
//! stands (the output frame it steps towards), each output file's length and the summary's
//! statistics ([`SinkMark`]) — and the scene's text, so that the scene is rebuilt from the
//! checkpoint alone.
//!
//! The file is an envelope of fixed layout (all numbers little-endian) around the payload:
//!
//! | bytes | what |
//! | --- | --- |
//! | 0–7 | magic `WBCKPT\r\n` |
//! | 8–11 | format version (`u32`, [`FORMAT_VERSION`]) |
//! | 12–27 | wetbounce version that wrote it (ASCII, NUL-padded) |
//! | 28–59 | SHA-256 of the scene's text |
//! | 60–67 | steps taken (`u64`) |
//! | 68–75 | simulated time (`f64`, s) |
//! | 76–83 | payload length (`u64`, bytes) |
//! | 84–87 | CRC-32 of the payload (`u32`) |
//! | 88– | payload: [`Saved`] in postcard 1.x, compressed with zstd |
//!
//! The versioning rule: any change to [`Saved`] or to what it holds (a field added, removed,
//! reordered or retyped anywhere in the world) is a new format version; a file of another
//! version is refused with both numbers, never read on a guess.

use crate::fluid::field::OutsideField;
use crate::output::{SinkMark, Statistics};
use crate::pipeline::outlets::Removal;
use crate::pipeline::{LostParticle, World};
use serde::{Deserialize, Serialize};
use sha2::Digest;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The first 8 bytes of every checkpoint. The `\r\n` shows a file mangled by a text-mode
/// transfer as not a checkpoint.
pub const MAGIC: [u8; 8] = *b"WBCKPT\r\n";

/// The format this build writes and reads (the envelope's bytes 8–11). 3: the history memory
/// stores the modes that forget their start within a step folded into two numbers per
/// component (`effects::Fold`: 28 stored modes at the defaults and Δt = 8.77 µs, where version 2
/// stored all 37), so a version-2 memory means something else. 2: the memory held by
/// component and the kernel's slow tail lumped (37 modes with the defaults, 55 in version 1).
pub const FORMAT_VERSION: u32 = 3;

/// Bytes before the payload.
pub const HEADER_LEN: usize = 88;

/// The extension of checkpoint files.
pub const EXTENSION: &str = "wbck";

/// The largest checkpoint read (bytes): 10⁷ particles with the history memory's 37 modes
/// unfolded are ~9 GB before compression.
pub const CHECKPOINT_CAP: u64 = 64 << 30;

/// Where the run loop stands: the output frame it steps towards, the frames written, the lost
/// particles already handed to the sinks.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct RunPosition {
    /// The output frame the steps go towards: frame `k` at `k · output_interval`.
    pub k: u64,
    /// Output frames written.
    pub frames: u64,
    /// Lost particles already handed to the sinks.
    pub lost_reported: u64,
    /// Whether frame `k` is written (the loop stands at it) or the steps are on their way to it.
    pub at_frame: bool,
    /// Wall-clock seconds the run had taken up to the checkpoint (all its parts).
    pub wall_time: f64,
}

impl RunPosition {
    /// The index `k` of the first multiple `k · interval` after `time` (by more than round-off):
    /// the output frame (or checkpoint) a run at `time` steps towards.
    pub fn next_index(time: f64, interval: f64) -> u64 {
        (time / interval * (1.0 + 1e-12)).floor() as u64 + 1
    }
}

/// The scene a checkpoint was taken of: its file (absolute, so that its meshes and fields are
/// found from anywhere) and its text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SavedScene {
    /// The scene file, absolute.
    pub path: PathBuf,
    /// The scene file as the run was given it (what `summary.json` and the MCAP name).
    pub given: PathBuf,
    /// The scene's text.
    pub source: String,
    /// The output interval the run used (s): the scene's, or `--output-interval`.
    pub output_interval: f64,
    /// The output formats, by name.
    pub formats: Vec<String>,
    /// The files' stem.
    pub stem: String,
    /// Largest particle count drawn as spheres in the MCAP (`usize::MAX`: every count).
    pub max_spheres: usize,
}

/// The payload of a checkpoint.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Saved {
    /// The scene and how the run writes it.
    pub scene: SavedScene,
    /// What a step changes.
    pub world: World,
    /// Particles taken out because their state became non-finite.
    pub lost: Vec<LostParticle>,
    /// What each outlet removed.
    pub removed: Vec<Vec<Removal>>,
    /// A particle found outside a field whose outside is an error.
    pub left_field: Option<OutsideField>,
    /// Where the run loop stands.
    pub position: RunPosition,
    /// Each sink's mark: the files' lengths, the summary's statistics.
    pub sinks: Vec<SinkMark>,
}

impl Saved {
    /// The statistics among the sinks' marks (the summary's), if the run kept them.
    pub fn statistics(&self) -> Option<&Statistics> {
        self.sinks.iter().find_map(|m| match m {
            SinkMark::Statistics(s) => Some(s),
            _ => None,
        })
    }
}

/// What is wrong with a checkpoint file; every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// Not readable.
    #[error("{path}: cannot read the checkpoint: {problem}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        problem: String,
    },
    /// Not a checkpoint at all.
    #[error("{path}: not a wetbounce checkpoint (it does not begin with the bytes WBCKPT)")]
    NotACheckpoint {
        /// The file.
        path: PathBuf,
    },
    /// Another format version.
    #[error(
        "{path}: checkpoint format version {found} (written by wetbounce {writer}); this wetbounce \
         ({}) reads version {FORMAT_VERSION} only",
        env!("CARGO_PKG_VERSION")
    )]
    Version {
        /// The file.
        path: PathBuf,
        /// Its version.
        found: u32,
        /// The wetbounce version that wrote it.
        writer: String,
    },
    /// Shorter than its header says.
    #[error("{path}: the checkpoint is truncated: {found} bytes, its header says {expected}")]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Bytes the header says the file has.
        expected: u64,
        /// Bytes it has.
        found: u64,
    },
    /// The payload's checksum does not match.
    #[error(
        "{path}: the checkpoint is corrupted: its payload's CRC-32 is {found:08x}, its header says \
         {expected:08x}"
    )]
    Corrupted {
        /// The file.
        path: PathBuf,
        /// The checksum in the header.
        expected: u32,
        /// The payload's.
        found: u32,
    },
    /// The payload does not decode (a bug, or a file forged with a valid checksum).
    #[error("{path}: the checkpoint's payload does not decode: {problem}")]
    Decode {
        /// The file.
        path: PathBuf,
        /// Why.
        problem: String,
    },
    /// The scene differs from the one checkpointed in a key that may not change.
    #[error("{path}: {problem}")]
    Scene {
        /// The checkpoint.
        path: PathBuf,
        /// What differs (the key, and both values).
        problem: String,
    },
    /// Cannot be written.
    #[error("{path}: cannot write the checkpoint: {problem}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        problem: String,
    },
}

/// The SHA-256 of a scene's text.
pub fn scene_hash(source: &str) -> [u8; 32] {
    sha2::Sha256::digest(source.as_bytes()).into()
}

/// The file's bytes: the envelope around `saved`.
pub fn encode(saved: &Saved) -> Result<Vec<u8>, String> {
    encode_with(saved, (saved.world.steps, saved.world.time), &saved.scene.source)
}

/// The envelope around `payload` (a [`Saved`], or its borrowed twin with the same fields in the
/// same order), taken after `steps` steps at `time` (s) of the scene whose text is `source`.
pub fn encode_with(
    payload: &impl Serialize,
    (steps, time): (u64, f64),
    source: &str,
) -> Result<Vec<u8>, String> {
    let plain = postcard::to_stdvec(payload).map_err(|e| e.to_string())?;
    let payload = zstd::bulk::compress(&plain, 3).map_err(|e| e.to_string())?;
    let mut bytes = Vec::with_capacity(HEADER_LEN + payload.len());
    bytes.extend_from_slice(&MAGIC);
    bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    let mut version = [0u8; 16];
    let v = env!("CARGO_PKG_VERSION").as_bytes();
    version[..v.len().min(16)].copy_from_slice(&v[..v.len().min(16)]);
    bytes.extend_from_slice(&version);
    bytes.extend_from_slice(&scene_hash(source));
    bytes.extend_from_slice(&steps.to_le_bytes());
    bytes.extend_from_slice(&time.to_le_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    bytes.extend_from_slice(&payload);
    Ok(bytes)
}

/// The header's fields, read without decoding the payload.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// Format version.
    pub version: u32,
    /// The wetbounce version that wrote it.
    pub writer: String,
    /// SHA-256 of the scene's text.
    pub scene_hash: [u8; 32],
    /// Steps taken.
    pub steps: u64,
    /// Simulated time (s).
    pub time: f64,
}

/// Reads the checkpoint at `path`: its header and its payload, each check failing with what
/// differs.
pub fn read(path: &Path) -> Result<(Header, Saved), CheckpointError> {
    let bytes = crate::files::read(path, CHECKPOINT_CAP, "a checkpoint")
        .map_err(|e| CheckpointError::Read { path: path.to_path_buf(), problem: e.to_string() })?;
    decode(path, &bytes)
}

/// [`read`] of a checkpoint's bytes; `path` names it in the errors.
pub fn decode(path: &Path, bytes: &[u8]) -> Result<(Header, Saved), CheckpointError> {
    let path = path.to_path_buf();
    if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
        return Err(CheckpointError::NotACheckpoint { path });
    }
    let u64_at =
        |at: usize| bytes.get(at..at + 8).map(|b| u64::from_le_bytes(b.try_into().unwrap_or([0; 8])));
    let truncated = |expected: u64| CheckpointError::Truncated {
        path: path.clone(),
        expected,
        found: bytes.len() as u64,
    };
    let version = bytes
        .get(8..12)
        .map(|b| u32::from_le_bytes(b.try_into().unwrap_or([0; 4])))
        .ok_or_else(|| truncated(HEADER_LEN as u64))?;
    let writer = bytes
        .get(12..28)
        .map(|b| String::from_utf8_lossy(b).trim_end_matches('\0').to_string())
        .ok_or_else(|| truncated(HEADER_LEN as u64))?;
    if version != FORMAT_VERSION {
        return Err(CheckpointError::Version { path, found: version, writer });
    }
    if bytes.len() < HEADER_LEN {
        return Err(truncated(HEADER_LEN as u64));
    }
    let mut scene_hash = [0u8; 32];
    scene_hash.copy_from_slice(&bytes[28..60]);
    let steps = u64_at(60).unwrap_or(0);
    let time = f64::from_bits(u64_at(68).unwrap_or(0));
    let len = u64_at(76).unwrap_or(0);
    let expected_crc = u32::from_le_bytes(bytes[84..88].try_into().unwrap_or([0; 4]));
    let total = (HEADER_LEN as u64).saturating_add(len);
    if (bytes.len() as u64) < total {
        return Err(truncated(total));
    }
    let payload = &bytes[HEADER_LEN..total as usize];
    let crc = crc32fast::hash(payload);
    if crc != expected_crc || bytes.len() as u64 != total {
        return Err(CheckpointError::Corrupted { path, expected: expected_crc, found: crc });
    }
    let decode_error = |problem: String| CheckpointError::Decode { path: path.clone(), problem };
    // The payload is at most the file's size times zstd's largest ratio; the frame says its size.
    let size = zstd::zstd_safe::get_frame_content_size(payload)
        .ok()
        .flatten()
        .ok_or_else(|| decode_error("the zstd frame does not say its size".into()))?;
    if size > CHECKPOINT_CAP {
        return Err(decode_error(format!("it would decompress to {size} bytes")));
    }
    let plain = zstd::bulk::decompress(payload, size as usize).map_err(|e| decode_error(e.to_string()))?;
    let saved: Saved = postcard::from_bytes(&plain).map_err(|e| decode_error(e.to_string()))?;
    if scene_hash != self::scene_hash(&saved.scene.source) {
        return Err(decode_error("the scene's text does not match the header's hash".into()));
    }
    Ok((Header { version, writer, scene_hash, steps, time }, saved))
}

/// The file of the checkpoint taken after `steps` steps in `folder`: `checkpoint-<steps>.wbck`.
pub fn path_in(folder: &Path, steps: u64) -> PathBuf {
    folder.join(format!("checkpoint-{steps:012}.{EXTENSION}"))
}

/// Writes a checkpoint's `bytes` ([`encode_with`]) to `path` in `folder` ([`write_file`]),
/// then removes all but the newest `keep` checkpoints of the folder.
pub fn write_and_prune(folder: &Path, path: &Path, bytes: &[u8], keep: usize) -> Result<(), CheckpointError> {
    let failed = |problem: String| CheckpointError::Write { path: path.to_path_buf(), problem };
    std::fs::create_dir_all(folder).map_err(|e| failed(e.to_string()))?;
    write_file(path, bytes).map_err(|e| failed(e.to_string()))?;
    let mut all = list(folder);
    all.retain(|p| p != path);
    let excess = (all.len() + 1).saturating_sub(keep.max(1));
    for old in all.iter().take(excess) {
        let _ = std::fs::remove_file(old);
    }
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file beside it (`.partial`), synced, then
/// renamed: a run killed while writing leaves the file it had before, never half of one.
pub fn write_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(".partial");
    let temporary = path.with_file_name(name);
    let written = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&temporary)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&temporary, path)?;
        // The rename itself reaches the disk with the folder's entry.
        if let Some(dir) = path.parent()
            && let Ok(dir) =
                std::fs::File::open(if dir.as_os_str().is_empty() { Path::new(".") } else { dir })
        {
            let _ = dir.sync_all();
        }
        Ok(())
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

/// The checkpoints in `folder`, oldest (fewest steps) first.
pub fn list(folder: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(folder) else { return Vec::new() };
    let mut found: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension().is_some_and(|x| x == EXTENSION)
                && p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("checkpoint-"))
        })
        .collect();
    found.sort();
    found
}
