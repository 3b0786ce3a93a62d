//! The one rule for every file the engine reads (a scene, a mesh, a flow field, a `.pvd`
//! collection, a `.pvtu` piece, a recording to recover): it must be a regular file, and no
//! larger than a cap its reader names. A device (`/dev/zero`, `/dev/urandom`) would be read
//! forever, a fifo would block, a folder cannot be read; a file far beyond what such a file
//! holds is a wrong path (a disk image, a log), and reading it whole would take the memory of
//! the run. Both are told from the file's metadata before a byte is read, and the read itself
//! stops at the cap should the file grow (or be swapped) in between.

use std::io::Read;
use std::path::Path;

/// Why a file was not read.
#[derive(Debug, thiserror::Error)]
pub enum FileProblem {
    /// The operating system's error (no such file, no permission, not UTF-8 text).
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// A device, a fifo, a socket or a folder.
    #[error("is not a regular file (a device, a fifo or a folder)")]
    NotRegular,
    /// Beyond the cap.
    #[error("is {}, beyond the {} {what} may have", size(*bytes), size(*cap))]
    TooLarge {
        /// The file's size (bytes), or the cap + 1 if it grew while read.
        bytes: u64,
        /// The cap (bytes).
        cap: u64,
        /// What the file is, for the message (`a mesh file`).
        what: &'static str,
    },
}

/// A size in bytes as people read it: `512 MiB`, `64 KiB`, `300 bytes`.
pub fn size(bytes: u64) -> String {
    if bytes >= 1 << 20 && bytes.is_multiple_of(1 << 20) || bytes >= 16 << 20 {
        format!("{} MiB", bytes >> 20)
    } else if bytes >= 1 << 10 && bytes.is_multiple_of(1 << 10) || bytes >= 16 << 10 {
        format!("{} KiB", bytes >> 10)
    } else {
        format!("{bytes} bytes")
    }
}

/// Checks `path` against the rule (a regular file of at most `cap` bytes, `what` naming it in
/// the message) from its metadata, without opening it (opening a fifo blocks); its size.
/// Symbolic links are followed: a link to a regular file is that file.
pub fn check(path: &Path, cap: u64, what: &'static str) -> Result<u64, FileProblem> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(FileProblem::NotRegular);
    }
    if meta.len() > cap {
        return Err(FileProblem::TooLarge { bytes: meta.len(), cap, what });
    }
    Ok(meta.len())
}

/// Reads `path` whole under the rule of [`check`].
pub fn read(path: &Path, cap: u64, what: &'static str) -> Result<Vec<u8>, FileProblem> {
    let len = check(path, cap, what)?;
    let file = std::fs::File::open(path)?;
    // The path may have been swapped for a device since the check: the handle's own metadata.
    if !file.metadata()?.is_file() {
        return Err(FileProblem::NotRegular);
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(cap.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap {
        return Err(FileProblem::TooLarge { bytes: bytes.len() as u64, cap, what });
    }
    Ok(bytes)
}

/// [`read`] as UTF-8 text.
pub fn read_text(path: &Path, cap: u64, what: &'static str) -> Result<String, FileProblem> {
    String::from_utf8(read(path, cap, what)?).map_err(|e| {
        FileProblem::Io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("it is not UTF-8 text (byte {} is not)", e.utf8_error().valid_up_to()),
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_folders_and_files_beyond_the_cap_are_refused_before_reading() {
        for device in ["/dev/zero", "/dev/urandom", "/dev/null"] {
            if Path::new(device).exists() {
                assert!(matches!(read(Path::new(device), 1 << 20, "a file"), Err(FileProblem::NotRegular)));
            }
        }
        let dir = tempfile::tempdir().unwrap();
        assert!(matches!(read(dir.path(), 1 << 20, "a file"), Err(FileProblem::NotRegular)));
        let f = dir.path().join("f");
        std::fs::write(&f, [0u8; 100]).unwrap();
        assert_eq!(read(&f, 100, "a file").unwrap().len(), 100);
        let e = read(&f, 99, "a field file").unwrap_err();
        assert_eq!(e.to_string(), "is 100 bytes, beyond the 99 bytes a field file may have");
    }

    #[test]
    fn sizes_are_written_in_the_unit_that_reads_best() {
        assert_eq!(size(512 << 20), "512 MiB");
        assert_eq!(size(64 << 10), "64 KiB");
        assert_eq!(size(1000), "1000 bytes");
        assert_eq!(size((20 << 20) + 5), "20 MiB");
    }
}
