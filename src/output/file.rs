//! [`OutputFile`]: the file under every sink that writes one (CSV, MCAP), with the flushing
//! guarantee of docs/output.md and the first OS error kept for the message.

use super::OutputError;
use std::cell::Cell;
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::Path;
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

/// How often, at most, a flush also asks the OS to put the file on the disk (`fdatasync`):
/// syncing at every frame costs about a millisecond per file per frame here (1.3 ms on this
/// project's machine, more on a spinning disk), which would make a one-particle scene with a
/// frame per millisecond of simulated time a hundred times slower; once a second costs
/// nothing measurable and bounds what a power cut loses to about the last second.
pub const SYNC_INTERVAL: Duration = Duration::from_secs(1);

/// A buffered output file. [`Write::flush`] hands the buffer to the OS — what survives the
/// process being killed — and, when [`SYNC_INTERVAL`] has passed since the last time, syncs
/// the file's data to the disk — what survives a power cut. The first error of any write,
/// flush, seek or sync is kept ([`OutputFile::first_error`]): a writer above this one (the
/// MCAP writer) may answer later calls with an error of its own that hides the cause.
#[derive(Debug)]
pub struct OutputFile {
    inner: BufWriter<File>,
    last_sync: Cell<Instant>,
    first_error: Arc<OnceLock<String>>,
}

impl OutputFile {
    /// Creates (or truncates) the file at `path` with a buffer of `capacity` bytes.
    pub fn create(path: &Path, capacity: usize) -> Result<Self, OutputError> {
        let file = File::create(path).map_err(|e| OutputError::create(path, e))?;
        Ok(OutputFile {
            inner: BufWriter::with_capacity(capacity, file),
            last_sync: Cell::new(Instant::now()),
            first_error: Arc::new(OnceLock::new()),
        })
    }

    /// Opens `path`, written by an earlier part of the run, to append to it from `bytes` on:
    /// what followed is cut (written after the checkpoint the run goes on from). A file shorter
    /// than `bytes` is an error: it is not the file the checkpoint knew.
    pub fn append_at(path: &Path, bytes: u64, capacity: usize) -> Result<Self, OutputError> {
        let opened = (|| -> io::Result<File> {
            let file = std::fs::OpenOptions::new().write(true).open(path)?;
            let len = file.metadata()?.len();
            if len < bytes {
                return Err(io::Error::other(format!(
                    "it has {len} bytes, fewer than the {bytes} it had at the checkpoint"
                )));
            }
            file.set_len(bytes)?;
            let mut file = file;
            file.seek(SeekFrom::Start(bytes))?;
            Ok(file)
        })();
        let file =
            opened.map_err(|e| OutputError::new(path, format!("cannot go on from the checkpoint: {e}")))?;
        Ok(OutputFile {
            inner: BufWriter::with_capacity(capacity, file),
            last_sync: Cell::new(Instant::now()),
            first_error: Arc::new(OnceLock::new()),
        })
    }

    /// The length of a file written in sequence, what is still buffered included (bytes).
    pub fn length(&self) -> io::Result<u64> {
        Ok(self.inner.get_ref().metadata()?.len() + self.inner.buffer().len() as u64)
    }

    /// The first error this file met, as the OS said it (`No space left on device (os error
    /// 28)`); shared, so that it can be read while a writer above owns the file.
    pub fn first_error(&self) -> Arc<OnceLock<String>> {
        self.first_error.clone()
    }

    /// Flushes the buffer and syncs the file's data to the disk now, whatever the interval.
    pub fn sync(&mut self) -> io::Result<()> {
        self.inner.flush().map_err(|e| self.keep(e))?;
        self.sync_data()
    }

    /// Syncs what was flushed to the disk now (what [`Write::flush`] does once a second).
    pub fn sync_data(&self) -> io::Result<()> {
        self.last_sync.set(Instant::now());
        match self.inner.get_ref().sync_data() {
            // A special file (a pipe, /dev/null) has nothing to sync: not an error.
            Err(e) if matches!(e.kind(), io::ErrorKind::InvalidInput | io::ErrorKind::Unsupported) => Ok(()),
            r => r.map_err(|e| self.keep(e)),
        }
    }

    fn keep(&self, e: io::Error) -> io::Error {
        let _ = self.first_error.set(e.to_string());
        e
    }
}

impl Write for OutputFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.inner.write(buf).map_err(|e| self.keep(e))
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.inner.write_all(buf).map_err(|e| self.keep(e))
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush().map_err(|e| self.keep(e))?;
        if self.last_sync.get().elapsed() >= SYNC_INTERVAL {
            self.sync_data()?;
        }
        Ok(())
    }
}

impl Seek for OutputFile {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        if pos == SeekFrom::Current(0) {
            return self.stream_position();
        }
        self.inner.seek(pos).map_err(|e| self.keep(e))
    }

    /// The position without flushing the buffer (`BufWriter` flushes on every seek). The MCAP
    /// writer asks for it when it starts a chunk, and if that call fails it loses its file and
    /// panics on its next call; asked this way, a full disk fails a write instead, which it
    /// survives (it refuses later writes with an error).
    fn stream_position(&mut self) -> io::Result<u64> {
        let at = self.inner.get_mut().stream_position().map_err(|e| self.keep(e))?;
        Ok(at + self.inner.buffer().len() as u64)
    }
}

/// Writes `text` to `path` and syncs it to the disk; an error names `path` and the OS error,
/// and the file, which would hold a part of `text` or nothing, is removed.
pub fn write_file(path: &Path, text: &str) -> Result<(), OutputError> {
    let mut f = OutputFile::create(path, text.len().max(1))?;
    let written = f.write_all(text.as_bytes()).and_then(|()| f.sync());
    written.map_err(|e| {
        drop(f);
        let _ = std::fs::remove_file(path);
        OutputError::write(path, e)
    })
}
