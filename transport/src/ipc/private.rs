//! A run's iceoryx2 files, out of other local users' reach (see SECURITY.md).
//!
//! iceoryx2 0.10 leaves two holes on a machine with several users; a run
//! closes both before its first node exists.
//!
//! - **The root folder.** iceoryx2 keeps node and service files under one
//!   root folder, `/tmp/iceoryx2/` for every user by default: the first
//!   user to create it (mode 0750) locks every other user out ("cannot
//!   create node: InternalError"). Each run has its own root,
//!   [`run_root`], that [`prepare_root`] creates mode 0700 and refuses, with
//!   the folder and its owner named, if someone else owns it or a folder
//!   above it.
//! - **The node counter.** Every node creation opens or creates
//!   `/dev/shm/<prefix><type hash>_node.<version>.global_mgmt`, and iceoryx2
//!   makes it world-writable on purpose: `GlobalManagementSegment::open_or_create`
//!   (iceoryx2 0.10.0, `src/node/global_management_segment.rs`) asks for
//!   `enable_global_access(true)`, and the POSIX shared-memory storage
//!   (iceoryx2-cal 0.10.0, `src/dynamic_storage/posix_shared_memory.rs`)
//!   then `fchmod`s it to 0666, which no umask and no configuration key
//!   changes (iceoryx2 #1810 "Make mgmt segment globally accessible", so
//!   that users can share one counter; the `dev_permissions` feature of
//!   #1341 only widens modes, and #906 puts per-file permissions on the
//!   roadmap). Whoever truncates or overwrites it makes every later node
//!   creation fail (`UnableToGenerateUniqueNodeId`). A chmod after
//!   iceoryx2 made it would leave a window in which another user opens it
//!   and keeps the descriptor, so [`guard_node_counter`] makes it first,
//!   complete and mode 0600, and iceoryx2 only ever opens it.

use std::fs::{self, DirBuilder, OpenOptions};
use std::io::{self, Read, Write};
use std::os::unix::fs::{DirBuilderExt, MetadataExt, OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// iceoryx2 writes paths of up to 255 bytes (and panics past that); its
/// longest under the root is about 130 bytes more than the root itself.
pub const MAX_ROOT_BYTES: usize = 100;

/// The node counter file's name after the run's prefix, for iceoryx2 0.10.0:
/// the base64url SHA-1 of the counter's type name, `_node`, the version
/// and `.global_mgmt`. A test checks iceoryx2 still uses exactly this file.
const NODE_COUNTER_NAME: &str = "9204dd183d1c4d8e1ff592a30766ffa6765aa8b5_node.0_10_0.global_mgmt";

/// The counter file's content as iceoryx2 0.10.0 lays it out: the package
/// version (`major << 32 | minor << 16 | patch`, 0 while uninitialised),
/// then the `u32` counter, padded to 16 bytes.
const NODE_COUNTER_VERSION: u64 = 10 << 16;
const NODE_COUNTER_BYTES: usize = 16;

/// iceoryx2's root folder for the run with this prefix: its own folder in
/// `/dev/shm`, where the sweep of dead runs finds its files by prefix
/// ([`super::files`]). In memory, not under the temporary
/// directory: iceoryx2 syncs every service's and node's static file to
/// disk when it makes it (about 1.3 ms each on this machine's disk, against
/// 0.02 ms in memory), and a run of 1,000 robots makes over 2,000.
pub fn run_root(prefix: &str) -> PathBuf {
    Path::new("/dev/shm").join(format!("gridswarm-{prefix}iceoryx2"))
}

/// The node counter file of the run with this prefix.
pub fn node_counter_path(prefix: &str) -> PathBuf {
    Path::new("/dev/shm").join(format!("{prefix}{NODE_COUNTER_NAME}"))
}

/// The effective uid of this process.
fn my_uid() -> u32 {
    // SAFETY: geteuid has no preconditions and cannot fail.
    unsafe { libc::geteuid() }
}

/// `uid N (name)`, or `uid N` if the user database has no name for it.
pub fn describe_uid(uid: u32) -> String {
    match user_name(uid) {
        Some(name) => format!("uid {uid} ({name})"),
        None => format!("uid {uid}"),
    }
}

fn user_name(uid: u32) -> Option<String> {
    let mut buf = vec![0u8; 4096];
    // SAFETY: an all-zero passwd is a valid out-parameter for getpwuid_r.
    let mut pw: libc::passwd = unsafe { std::mem::zeroed() };
    let mut found: *mut libc::passwd = std::ptr::null_mut();
    // SAFETY: every pointer is valid for the call; buf outlives the use of pw's strings.
    let rc = unsafe { libc::getpwuid_r(uid, &mut pw, buf.as_mut_ptr().cast(), buf.len(), &mut found) };
    if rc != 0 || found.is_null() || pw.pw_name.is_null() {
        return None;
    }
    // SAFETY: getpwuid_r succeeded, so pw_name is a NUL-terminated string inside buf.
    let name = unsafe { std::ffi::CStr::from_ptr(pw.pw_name) };
    Some(name.to_string_lossy().into_owned())
}

/// Checks that `root` may hold a run's files, creating it (mode 0700) if
/// missing: every folder above it belongs to this user or root and is not
/// writable by everyone without the sticky bit, and `root` itself is a
/// folder of this user that nobody else can enter.
pub fn prepare_root(root: &Path) -> Result<(), String> {
    let bytes = root.as_os_str().len();
    if bytes > MAX_ROOT_BYTES {
        return Err(format!(
            "iceoryx2's root folder {} is {bytes} bytes long, more than the {MAX_ROOT_BYTES} iceoryx2's paths leave room for",
            root.display()
        ));
    }
    let what = format!("iceoryx2's root folder {}", root.display());
    for above in root.ancestors().skip(1).filter(|a| !a.as_os_str().is_empty()) {
        check_above(above, &what)?;
    }
    // The run's other files (run file, setups, report) are in a folder in
    // the temporary directory: the same holds for the folders above it.
    let tmp = std::env::temp_dir();
    let what = format!("the run's folder in {}", tmp.display());
    for above in tmp.ancestors().filter(|a| !a.as_os_str().is_empty()) {
        check_above(above, &what)?;
    }
    match DirBuilder::new().mode(0o700).create(root) {
        Ok(()) => {}
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
        Err(e) => {
            return Err(format!("cannot create iceoryx2's root folder {}: {e}{}", root.display(), parent_owner(root)))
        }
    }
    check_root(root)
}

/// `; <parent> belongs to <owner>, mode <mode>`, to say why a folder could not be made there.
fn parent_owner(path: &Path) -> String {
    let Some(parent) = path.parent() else { return String::new() };
    match fs::metadata(parent) {
        Ok(m) => format!("; {} belongs to {}, mode {:o}", parent.display(), describe_uid(m.uid()), m.mode() & 0o7777),
        Err(_) => String::new(),
    }
}

/// A folder above `what` (a folder of the run): another user who owns it,
/// or anyone if all may write it and it is not sticky, could rename the
/// run's folder away and put theirs.
fn check_above(dir: &Path, what: &str) -> Result<(), String> {
    let m = fs::metadata(dir).map_err(|e| format!("cannot inspect {} (above {what}): {e}", dir.display()))?;
    if m.uid() != my_uid() && m.uid() != 0 {
        return Err(format!(
            "the folder {} above {what} belongs to {}, not to this user ({}) or root: that user could replace the run's files; set TMPDIR to a folder of yours",
            dir.display(),
            describe_uid(m.uid()),
            describe_uid(my_uid())
        ));
    }
    if m.mode() & 0o002 != 0 && m.mode() & 0o1000 == 0 {
        return Err(format!(
            "the folder {} above {what} is writable by every user and not sticky (mode {:o}): set TMPDIR to a folder of yours",
            dir.display(),
            m.mode() & 0o7777
        ));
    }
    Ok(())
}

fn check_root(root: &Path) -> Result<(), String> {
    let m = fs::symlink_metadata(root)
        .map_err(|e| format!("cannot inspect iceoryx2's root folder {}: {e}", root.display()))?;
    if m.uid() != my_uid() {
        return Err(format!(
            "iceoryx2's root folder {} belongs to {}, not to this user ({}): that user could read or replace the run's files; remove it",
            root.display(),
            describe_uid(m.uid()),
            describe_uid(my_uid())
        ));
    }
    if !m.is_dir() {
        return Err(format!("iceoryx2's root folder {} is not a folder", root.display()));
    }
    if m.mode() & 0o077 != 0 {
        // Ours, only too open (made by hand, or by an older gridswarm): close it.
        fs::set_permissions(root, fs::Permissions::from_mode(0o700))
            .map_err(|e| format!("cannot make iceoryx2's root folder {} private: {e}", root.display()))?;
    }
    Ok(())
}

/// Makes the run's node counter file, mode 0600 and already initialised,
/// unless a process of the run did; then checks that the file there is
/// this user's and private. It is written under a temporary name and
/// hard-linked into place, so nobody ever sees it half-written and only
/// one process of the run makes it.
pub fn guard_node_counter(prefix: &str) -> Result<(), String> {
    static SEQ: AtomicU32 = AtomicU32::new(0);
    let path = node_counter_path(prefix);
    let seq = SEQ.fetch_add(1, Ordering::Relaxed);
    let tmp = Path::new("/dev/shm").join(format!("{prefix}counter-{}-{seq}.tmp", std::process::id()));
    let made = write_private(&tmp, &node_counter_bytes()).and_then(|()| fs::hard_link(&tmp, &path));
    let _ = fs::remove_file(&tmp);
    match made {
        Ok(()) => {}
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
        Err(e) => return Err(format!("cannot create the run's node counter {}: {e}", path.display())),
    }
    check_private_file(&path)
}

fn node_counter_bytes() -> [u8; NODE_COUNTER_BYTES] {
    let mut b = [0u8; NODE_COUNTER_BYTES];
    b[..8].copy_from_slice(&NODE_COUNTER_VERSION.to_ne_bytes());
    b
}

/// Creates `path` (it must not exist) with mode 0600 and writes `bytes`.
fn write_private(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f =
        OpenOptions::new().write(true).create_new(true).mode(0o600).custom_flags(libc::O_NOFOLLOW).open(path)?;
    f.write_all(bytes)
}

/// A file of the run must be this user's, and nobody else's to read or write.
fn check_private_file(path: &Path) -> Result<(), String> {
    let m = fs::symlink_metadata(path).map_err(|e| format!("cannot inspect {}: {e}", path.display()))?;
    if !m.is_file() || m.uid() != my_uid() || m.mode() & 0o077 != 0 {
        return Err(format!(
            "the run's file {} belongs to {} with mode {:o}, not to this user ({}) alone: another user may be interfering with the run",
            path.display(),
            describe_uid(m.uid()),
            m.mode() & 0o7777,
            describe_uid(my_uid())
        ));
    }
    Ok(())
}

/// How many nodes iceoryx2 has counted in the run's node counter file:
/// at least one once a node of the run exists, if iceoryx2 used the file
/// [`guard_node_counter`] made.
pub fn nodes_counted(prefix: &str) -> Result<u32, String> {
    let path = node_counter_path(prefix);
    let mut b = [0u8; NODE_COUNTER_BYTES];
    fs::File::open(&path)
        .and_then(|mut f| f.read_exact(&mut b))
        .map_err(|e| format!("cannot read the run's node counter {}: {e}", path.display()))?;
    Ok(u32::from_ne_bytes([b[8], b[9], b[10], b[11]]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_root_is_made_private_and_a_foreign_one_is_refused() {
        let dir = std::env::temp_dir().join(format!("gs-private-test-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir(&dir).unwrap();
        let root = dir.join("root");
        prepare_root(&root).unwrap();
        assert_eq!(fs::metadata(&root).unwrap().mode() & 0o777, 0o700);
        fs::set_permissions(&root, fs::Permissions::from_mode(0o755)).unwrap();
        prepare_root(&root).unwrap();
        assert_eq!(fs::metadata(&root).unwrap().mode() & 0o777, 0o700, "an open root of ours is closed");
        let open = dir.join("open");
        fs::create_dir(&open).unwrap();
        fs::set_permissions(&open, fs::Permissions::from_mode(0o777)).unwrap();
        let err = prepare_root(&open.join("root")).unwrap_err();
        assert!(err.contains(&format!("{} above", open.display())) && err.contains("not sticky"), "{err}");
        let err = prepare_root(&dir.join("missing").join("root")).unwrap_err();
        assert!(err.contains("cannot inspect") && err.contains("missing"), "{err}");
        let long = dir.join("x".repeat(MAX_ROOT_BYTES));
        assert!(prepare_root(&long).unwrap_err().contains("bytes long"));
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn uids_are_named() {
        assert_eq!(describe_uid(0), "uid 0 (root)");
        assert_eq!(describe_uid(u32::MAX - 3), format!("uid {}", u32::MAX - 3));
    }

    #[test]
    fn the_counter_is_made_once_private_and_a_stranger_is_refused() {
        let prefix = format!("gs{}x{:06x}_", std::process::id(), 0xc0c0);
        let path = node_counter_path(&prefix);
        guard_node_counter(&prefix).unwrap();
        guard_node_counter(&prefix).unwrap();
        let m = fs::metadata(&path).unwrap();
        assert_eq!((m.mode() & 0o777, m.len()), (0o600, NODE_COUNTER_BYTES as u64));
        assert_eq!(nodes_counted(&prefix), Ok(0));
        fs::set_permissions(&path, fs::Permissions::from_mode(0o666)).unwrap();
        let err = guard_node_counter(&prefix).unwrap_err();
        assert!(err.contains("mode 666") && err.contains(&path.display().to_string()), "{err}");
        fs::remove_file(&path).unwrap();
        assert_eq!(super::super::run_files(&prefix), Vec::<PathBuf>::new(), "no temporary file left");
    }
}
