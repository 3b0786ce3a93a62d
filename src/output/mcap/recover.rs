//! `wetbounce recover`: the readable part of a cut MCAP rewritten as a valid file.
//!
//! An MCAP is readable by the standard readers only once it is closed: its summary and footer
//! come last. A run killed outright (SIGKILL, a power cut) or stopped by a full disk leaves a
//! file without them; since the sink closes a chunk at every frame, every frame but the last
//! is whole in it. This reads the file from the start with the `mcap` crate's linear reader —
//! which needs no footer — checks each chunk's CRC before taking any of its messages, stops at
//! the first record that is cut or damaged, and writes every schema, channel, message, metadata
//! and attachment read before it into a new file, closed properly.

use crate::output::file::OutputFile;
use mcap::records::{MessageHeader, Record};
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};
use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};

/// What [`recover`] read back and wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Recovered {
    /// Messages written to the new file.
    pub messages: u64,
    /// Log time (ns) of the last message written, if any.
    pub last_log_time: Option<u64>,
    /// Metadata records written (wetbounce writes two: `scene` and `wetbounce`).
    pub metadata: u64,
    /// Why reading stopped before the end of the data, or `None` when the input was complete
    /// (its data section ended properly: nothing was lost).
    pub cut: Option<String>,
}

/// Why [`recover`] could not write a file: each names the file.
#[derive(Debug, thiserror::Error)]
pub enum RecoverError {
    /// The input could not be opened or read.
    #[error("{}: cannot read: {source}", path.display())]
    Read {
        /// The input file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The input does not start as an MCAP file does.
    #[error("{}: not an MCAP file ({reason})", path.display())]
    NotMcap {
        /// The input file.
        path: PathBuf,
        /// What the reader said.
        reason: String,
    },
    /// The output could not be written.
    #[error("{}: {message}", path.display())]
    Write {
        /// The output file.
        path: PathBuf,
        /// What went wrong, with the OS error.
        message: String,
    },
}

/// Reads `input` as far as it is whole and writes what it holds to `output` as a closed MCAP
/// (zstd chunks, with summary and footer). The messages keep their channels, log times and
/// sequence numbers, in the order of the input.
///
/// A recovery that fails leaves no output file (a 0-byte or partial file would pass for a
/// recovered one: issue 25, finding 13).
pub fn recover(input: &Path, output: &Path) -> Result<Recovered, RecoverError> {
    // Only a file this call created (or truncated) is removed: an input refused before the
    // output is touched leaves whatever was at that path.
    let mut created = false;
    let result = recover_into(input, output, &mut created);
    if result.is_err() && created && !same_file(input, output) {
        let _ = std::fs::remove_file(output);
    }
    result
}

/// How many times its compressed size a chunk may claim to inflate to. zstd on a frame's
/// numbers gains 2–10×; a length field that says more is a damaged or hostile file, and is
/// refused before its buffer is allocated (a 140-byte file whose chunk claimed 2^63 bytes made
/// `recover` allocate 2 GB).
const MAX_INFLATION: u64 = 64;

fn recover_into(input: &Path, output: &Path, created: &mut bool) -> Result<Recovered, RecoverError> {
    let read_err = |source| RecoverError::Read { path: input.to_path_buf(), source };
    // A regular file, of any size (the reader streams it): a device would be read forever, a
    // fifo would block ([`crate::files`]).
    crate::files::check(input, u64::MAX, "a recording").map_err(|problem| match problem {
        crate::files::FileProblem::Io(source) => read_err(source),
        other => read_err(std::io::Error::other(other.to_string())),
    })?;
    let mut file = std::fs::File::open(input).map_err(read_err)?;
    // Creating the output truncates it: were it the input (by another name, a link), the file
    // to recover would be lost.
    if same_file(input, output) {
        return Err(RecoverError::Write {
            path: output.to_path_buf(),
            message: format!("is the input, {}; name another file", input.display()),
        });
    }
    let length = file.metadata().map_err(read_err)?.len();
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            // The end magic, summary and footer are what a cut file lacks.
            .with_skip_end_magic(true)
            // A chunk whose bytes do not match its CRC (zeros left by a power cut) gives none
            // of its messages.
            .with_prevalidate_chunk_crcs(true)
            // A length field that cannot be (the placeholder of the chunk being written when the
            // run was killed is 2^64 - 1) is an error, not an allocation of that size. A record
            // is at most the file's length (checked at each read request below), a chunk's
            // decompressed content at most MAX_INFLATION times the file and at most 4 GiB (a
            // frame of 10^7 particles is 0.5 GB).
            .with_record_length_limit(
                usize::try_from(length.saturating_mul(MAX_INFLATION).clamp(1 << 20, 1 << 32))
                    .unwrap_or(usize::MAX),
            ),
    );
    let mut consumed: u64 = 0;

    let out_file = OutputFile::create(output, 1 << 20)
        .map_err(|e| RecoverError::Write { path: output.to_path_buf(), message: e.message })?;
    *created = true;
    let first_error = out_file.first_error();
    let write_err = |e: &dyn std::fmt::Display| RecoverError::Write {
        path: output.to_path_buf(),
        message: format!("cannot write: {}", first_error.get().cloned().unwrap_or_else(|| e.to_string())),
    };
    let mut writer: Option<mcap::Writer<OutputFile>> = None;
    let mut out_file = Some(out_file);
    // Schema and channel ids of the input, mapped to those of the output.
    let mut schemas: HashMap<u16, u16> = HashMap::new();
    let mut channels: HashMap<u16, u16> = HashMap::new();
    let mut recovered = Recovered { messages: 0, last_log_time: None, metadata: 0, cut: None };
    let mut first_record = true;
    let mut data_end = false;

    while let Some(event) = reader.next_event() {
        let (opcode, data) = match event {
            Ok(LinearReadEvent::ReadRequest(need)) => {
                // More than the file still holds: a record whose length field lies (or a cut
                // file). Stop here, before the reader allocates a buffer of that size.
                let left = length.saturating_sub(consumed);
                if need as u64 > left {
                    if first_record {
                        return Err(RecoverError::NotMcap {
                            path: input.to_path_buf(),
                            reason: format!("it ends after {length} bytes"),
                        });
                    }
                    recovered.cut = Some(format!(
                        "a record needs {need} more bytes at byte {consumed}, the file has {left} left"
                    ));
                    break;
                }
                let n = file.read(reader.insert(need)).map_err(read_err)?;
                consumed += n as u64;
                reader.notify_read(n);
                continue;
            }
            Ok(LinearReadEvent::Record { opcode, data }) => (opcode, data),
            Err(e) if first_record => {
                return Err(RecoverError::NotMcap { path: input.to_path_buf(), reason: e.to_string() });
            }
            Err(e) => {
                recovered.cut = Some(e.to_string());
                break;
            }
        };
        let record = match mcap::parse_record(opcode, data) {
            Ok(r) => r,
            Err(e) => {
                recovered.cut = Some(e.to_string());
                break;
            }
        };
        if first_record {
            first_record = false;
            let Record::Header(header) = &record else {
                return Err(RecoverError::NotMcap {
                    path: input.to_path_buf(),
                    reason: "its first record is not a header".into(),
                });
            };
            let options = mcap::WriteOptions::new()
                .compression(Some(mcap::Compression::Zstd))
                .profile(header.profile.clone())
                .library(format!("wetbounce {} recover", env!("CARGO_PKG_VERSION")));
            if let Some(file) = out_file.take() {
                writer = Some(options.create(file).map_err(|e| write_err(&e))?);
            }
            continue;
        }
        let Some(w) = writer.as_mut() else { break };
        match record {
            Record::Schema { header, data } => {
                let id = w.add_schema(&header.name, &header.encoding, &data).map_err(|e| write_err(&e))?;
                schemas.insert(header.id, id);
            }
            Record::Channel(c) => {
                let schema = match c.schema_id {
                    0 => 0,
                    id => match schemas.get(&id) {
                        Some(&s) => s,
                        None => {
                            recovered.cut = Some(format!("channel {} names an unknown schema {id}", c.id));
                            break;
                        }
                    },
                };
                let id = w
                    .add_channel(schema, &c.topic, &c.message_encoding, &c.metadata)
                    .map_err(|e| write_err(&e))?;
                channels.insert(c.id, id);
            }
            Record::Message { header, data } => {
                let Some(&channel_id) = channels.get(&header.channel_id) else {
                    recovered.cut = Some(format!("a message names an unknown channel {}", header.channel_id));
                    break;
                };
                w.write_to_known_channel(&MessageHeader { channel_id, ..header }, &data)
                    .map_err(|e| write_err(&e))?;
                recovered.messages += 1;
                recovered.last_log_time = Some(header.log_time);
            }
            Record::Metadata(m) => {
                w.write_metadata(&m).map_err(|e| write_err(&e))?;
                recovered.metadata += 1;
            }
            Record::Attachment { header, data, .. } => {
                let attachment = mcap::Attachment {
                    log_time: header.log_time,
                    create_time: header.create_time,
                    name: header.name,
                    media_type: header.media_type,
                    data,
                };
                w.attach(&attachment).map_err(|e| write_err(&e))?;
            }
            // The data section is over: the rest is the input's own summary.
            Record::DataEnd(_) => {
                data_end = true;
                break;
            }
            _ => {}
        }
    }
    // A file cut between two records ends without an error, but without its data end too.
    if !data_end && recovered.cut.is_none() {
        recovered.cut = Some("the file ends before its data section does".into());
    }
    // A file cut inside its header (or empty) has no records at all.
    let Some(mut w) = writer else {
        return Err(RecoverError::NotMcap {
            path: input.to_path_buf(),
            reason: recovered.cut.unwrap_or_default(),
        });
    };
    w.finish().map_err(|e| write_err(&e))?;
    w.into_inner().sync().map_err(|e| write_err(&e))?;
    Ok(recovered)
}

/// Whether `a` and `b` name one file (`b` need not exist).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(a), Ok(b)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return a.dev() == b.dev() && a.ino() == b.ino();
        }
    }
    matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}
