//! Reading a scenario file from disk, bounded: only a regular file, and at
//! most [`MAX_FILE_BYTES`] of it (issue 23). `--scenario /dev/zero` read
//! until memory ran out, and a FIFO blocked the command forever; both are
//! refused before a byte is read.

use std::io::Read;
use std::os::unix::fs::OpenOptionsExt;

/// The largest scenario file read (1 MB): every built-in is a few KB, and
/// a 400 x 400 m `random:` map written out is about 300 KB. Every check
/// behind admission is bounded for a file of this size (docs/scenario-format.md).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// The largest map image read (64 MB): a 4096 x 4096 PGM is 16 MB, its
/// plain (P2) form up to 4 bytes a pixel; the pixels themselves are
/// bounded by `occupancy::MAX_IMAGE_PIXELS` before any is stored.
pub const MAX_IMAGE_BYTES: u64 = 64 << 20;

/// Why a file could not be read, as the tail of the error's message.
pub fn read(path: &str) -> Result<String, String> {
    let bytes = read_bytes(path, "scenario file", MAX_FILE_BYTES, "MAX_FILE_BYTES")?;
    String::from_utf8(bytes).map_err(|e| format!("cannot read scenario file: not UTF-8 text ({e})"))
}

/// At most `max` bytes of the regular file `path` (`what` and the limit's
/// `name` for the message), or why not.
pub(crate) fn read_bytes(path: &str, what: &str, max: u64, name: &str) -> Result<Vec<u8>, String> {
    // O_NONBLOCK: opening a FIFO with no writer returns at once instead
    // of waiting for one; the type is then checked on what was opened, so
    // the file cannot be swapped between a check and the open.
    let cannot = |e: &dyn std::fmt::Display| format!("cannot read {what}: {e}");
    let file =
        std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK).open(path).map_err(|e| cannot(&e))?;
    let meta = file.metadata().map_err(|e| cannot(&e))?;
    if !meta.is_file() {
        return Err(cannot(&format!("it is {}, not a regular file", kind(&meta))));
    }
    let too_big = |len: &str| cannot(&format!("it is {len} bytes, above the limit {name} = {max} bytes ({})", mb(max)));
    if meta.len() > max {
        return Err(too_big(&meta.len().to_string()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // A file that grows after the stat is still cut at the limit.
    (&file).take(max + 1).read_to_end(&mut bytes).map_err(|e| cannot(&e))?;
    if bytes.len() as u64 > max {
        return Err(too_big("by now more than that"));
    }
    Ok(bytes)
}

fn mb(bytes: u64) -> String {
    format!("{} MB", bytes >> 20)
}

fn kind(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_dir() {
        "a folder"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_fifos_and_folders_are_refused_before_reading() {
        let e = read("/dev/zero").unwrap_err();
        assert!(e.contains("a character device, not a regular file"), "{e}");
        let e = read("/").unwrap_err();
        assert!(e.contains("a folder"), "{e}");
        let dir = std::env::temp_dir().join(format!("gridswarm-fifo-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("scenario.toml");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        // No writer: a blocking open would wait forever.
        let e = read(fifo.to_str().unwrap()).unwrap_err();
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(e.contains("a FIFO, not a regular file"), "{e}");
    }

    #[test]
    fn a_file_over_the_limit_is_refused_naming_it() {
        let dir = std::env::temp_dir().join(format!("gridswarm-big-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("big.toml");
        let mut text = "# padding\n".repeat((MAX_FILE_BYTES as usize) / 10 + 1);
        std::fs::write(&path, &text).unwrap();
        let e = read(path.to_str().unwrap()).unwrap_err();
        assert!(e.contains("MAX_FILE_BYTES = 1048576 bytes (1 MB)"), "{e}");
        text.truncate(MAX_FILE_BYTES as usize);
        std::fs::write(&path, &text).unwrap();
        assert_eq!(read(path.to_str().unwrap()).unwrap().len() as u64, MAX_FILE_BYTES);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
