//! A recording's footer, added when a run ends normally.
//!
//! Recordings stream to their file without rerun's footer (the chunk
//! manifest the viewer seeks by and `rerun rrd verify` checks): the SDK's
//! encoder keeps the manifest in memory until the stream closes, so a long
//! run's memory would grow with its recording. When the run ends (normally or
//! by Ctrl-C), the file is read back message by message and written again,
//! with the footer, to a file beside it that then replaces it. Memory holds
//! one message and the manifest, which grows with the chunks and the
//! components (about 0.6 times the file's size on our recordings: 148 MB
//! for a 237 MB one), so a footer is added only to files of at most
//! [`FOOTER_MAX_BYTES`]; a longer run's file keeps streaming's flat memory
//! and opens without one (`rerun rrd optimize FILE -o OUT` compacts it and
//! adds one). A run killed before or during the rewrite leaves the streamed
//! file, which still opens (docs/recordings.md, "Footers").

use std::io::{BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

use rerun::external::re_log_encoding::{CrateVersion, DecoderApp, Encoder, EncodingOptions};

/// The largest recording a footer is added to (its rewrite then takes at
/// most about 170 MB beyond the run's memory).
pub const FOOTER_MAX_BYTES: u64 = 256 << 20;

/// What [`finish_file`] did.
#[derive(Debug)]
pub enum Footer {
    /// Added: the messages written again.
    Added(u64),
    /// Not added: the file (of this many bytes) is larger than the limit.
    TooLarge(u64),
}

/// Adds the footer to the recording at `path` when it is at most
/// `max_bytes` long ([`FOOTER_MAX_BYTES`] for runs).
pub fn finish_file(path: &Path, max_bytes: u64) -> Result<Footer, FooterError> {
    let size = std::fs::metadata(path)
        .map_err(|e| FooterError::Io(path.to_path_buf(), e))?
        .len();
    if size > max_bytes {
        return Ok(Footer::TooLarge(size));
    }
    add_footer(path).map(Footer::Added)
}

/// Why a footer could not be added (the streamed file is left as it was).
#[derive(Debug, thiserror::Error)]
pub enum FooterError {
    #[error("{0}: {1}")]
    Io(PathBuf, std::io::Error),
    #[error("{0}: reading it back: {1}")]
    Decode(PathBuf, String),
    #[error("{0}: writing it with its footer: {1}")]
    Encode(PathBuf, String),
}

/// Rewrites the recording at `path` with rerun's footer; returns the
/// messages written.
pub fn add_footer(path: &Path) -> Result<u64, FooterError> {
    let io = |e| FooterError::Io(path.to_path_buf(), e);
    let encode = |e: &dyn std::fmt::Display| FooterError::Encode(path.to_path_buf(), e.to_string());
    let input = std::fs::File::open(path).map_err(io)?;
    let mut name = path.as_os_str().to_owned();
    name.push(".with-footer");
    let temp = PathBuf::from(name);
    let written = (|| {
        let output = std::fs::File::create(&temp).map_err(io)?;
        let mut encoder = Encoder::new_eager(
            CrateVersion::LOCAL,
            EncodingOptions::PROTOBUF_COMPRESSED,
            BufWriter::new(output),
        )
        .map_err(|e| encode(&e))?;
        let mut n = 0u64;
        for msg in DecoderApp::decode_lazy(BufReader::new(input)) {
            let msg = msg.map_err(|e| FooterError::Decode(path.to_path_buf(), e.to_string()))?;
            encoder.append(&msg).map_err(|e| encode(&e))?;
            n += 1;
        }
        encoder.finish().map_err(|e| encode(&e))?;
        let mut w = encoder.into_inner().map_err(|e| encode(&e))?;
        w.flush().map_err(io)?;
        w.into_inner()
            .map_err(|e| io(e.into_error()))?
            .sync_all()
            .map_err(io)?;
        Ok(n)
    })();
    match written {
        Ok(n) => {
            std::fs::rename(&temp, path).map_err(io)?;
            Ok(n)
        }
        Err(e) => {
            let _ = std::fs::remove_file(&temp);
            Err(e)
        }
    }
}
