//! Reading a tree file: only a regular file, and only up to a size.
//!
//! A path may name anything: a FIFO whose `open` blocks until a writer comes (forever, if
//! none does), `/dev/zero`, which never ends, or a file that grows while it is read. So the
//! kind and size are checked before the file is opened, the kind again on the opened
//! handle (the path may have been replaced meanwhile), and the read stops one byte past
//! the limit whatever the file does.

use std::fs::{File, Metadata};
use std::io::Read;
use std::path::Path;

use super::{LoadError, LoadErrorKind};

/// The largest file an [`XmlLoader`](super::XmlLoader) reads unless told otherwise
/// (32 MiB): a tree file of a few thousand nodes is a few hundred kilobytes.
pub const DEFAULT_MAX_FILE_BYTES: u64 = 32 << 20;

/// The text of the regular file at `path`, if it is at most `max_bytes` long and UTF-8;
/// errors name `path` (at line 1, column 1) and say what to do.
pub fn read_file(path: &Path, max_bytes: u64) -> Result<String, LoadError> {
    let shown = path.display().to_string();
    let error = |message: String| LoadError::at_file(LoadErrorKind::Io, &shown, message);
    let too_big = |size: &str| {
        LoadError::at_file(
            LoadErrorKind::TooLarge,
            &shown,
            format!(
                "the file is {size} bytes, more than the limit of {max_bytes}; raise the limit \
                 (XmlLoader::max_file_bytes) if the file is meant to be this big"
            ),
        )
    };
    let cannot_open = |e: std::io::Error| error(format!("cannot open the file: {e}"));
    let meta = std::fs::metadata(path).map_err(cannot_open)?;
    regular(&meta).map_err(&error)?;
    if meta.len() > max_bytes {
        return Err(too_big(&meta.len().to_string()));
    }
    let file = File::open(path).map_err(cannot_open)?;
    let meta = file.metadata().map_err(cannot_open)?;
    regular(&meta).map_err(&error)?;
    let mut bytes = Vec::new();
    // One byte more than allowed, to tell a file at the limit from one past it.
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| error(format!("cannot read the file: {e}")))?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_big("more than that (it grew while it was read)"));
    }
    String::from_utf8(bytes).map_err(|e| {
        error(format!(
            "cannot read the file: it is not UTF-8 text (at byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// `Ok` for a regular file; else what it is instead, as a message.
fn regular(meta: &Metadata) -> Result<(), String> {
    let kind = meta.file_type();
    if kind.is_file() {
        return Ok(());
    }
    let what = if kind.is_dir() {
        "a directory"
    } else {
        special_kind(&kind)
    };
    Err(format!(
        "not a regular file but {what}; give the path of a tree file"
    ))
}

#[cfg(unix)]
fn special_kind(kind: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_fifo() {
        "a FIFO"
    } else if kind.is_char_device() {
        "a character device"
    } else if kind.is_block_device() {
        "a block device"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_kind: &std::fs::FileType) -> &'static str {
    "a special file"
}
