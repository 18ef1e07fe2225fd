//! A zenoh run's credentials: the folder `gridswarm credentials` writes
//! (and a zenoh run on one machine makes for itself), and what the world
//! and a robot read from it. One certificate authority per folder
//! (`ca.pem`, its key `ca.key` kept only to sign more); the world's
//! certificate (`world.pem`, `world.key`, common name [`WORLD_NAME`],
//! valid for the host names it is reached at, usable only to serve); one
//! certificate per robot (`robot-K.pem`, `robot-K.key`, common name
//! [`robot_name`], usable only as a client). The world admits a robot by
//! its certificate's common name, so a robot's key speaks for that robot
//! only ([`crate::net`]'s access control).
//!
//! It never reads a key itself: zenoh does. It only checks, before zenoh
//! sees them, that the files are there and that a private key is readable
//! by its owner alone (a key others can read is no secret, as for ssh).

use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// The world certificate's common name.
pub const WORLD_NAME: &str = "gridswarm-world";

/// Robot `k`'s certificate's common name, the subject the world's access
/// control knows it by.
pub fn robot_name(k: usize) -> String {
    format!("robot-{k}")
}

/// Whose certificate a process presents.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Holder {
    World,
    Robot(usize),
}

/// A credentials folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Credentials {
    pub dir: PathBuf,
}

impl Credentials {
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Credentials { dir: dir.into() }
    }

    /// The authority's certificate, which every process trusts.
    pub fn ca(&self) -> PathBuf {
        self.dir.join("ca.pem")
    }

    /// The authority's key (only `gridswarm credentials` uses it).
    pub fn ca_key(&self) -> PathBuf {
        self.dir.join("ca.key")
    }

    /// `holder`'s certificate and private key.
    pub fn of(&self, holder: Holder) -> (PathBuf, PathBuf) {
        let stem = match holder {
            Holder::World => "world".to_string(),
            Holder::Robot(k) => robot_name(k),
        };
        (self.dir.join(format!("{stem}.pem")), self.dir.join(format!("{stem}.key")))
    }

    /// Checks that `holder`'s files and the authority's certificate are
    /// there and that the key is the owner's alone; the error names the
    /// file and what to do.
    pub fn check(&self, holder: Holder) -> Result<(), String> {
        let (cert, key) = self.of(holder);
        for f in [self.ca(), cert] {
            regular(&f, holder)?;
        }
        let mode = regular(&key, holder)?;
        if mode & 0o077 != 0 {
            return Err(format!(
                "`{}` can be read by other users (mode {:04o}): a private key must be its owner's alone (chmod 600 it)",
                key.display(),
                mode & 0o7777
            ));
        }
        Ok(())
    }
}

/// The mode of `f` if it is a regular file (symlinks followed: a
/// folder of links to the files is fine).
fn regular(f: &Path, holder: Holder) -> Result<u32, String> {
    let whose = match holder {
        Holder::World => "the world's".to_string(),
        Holder::Robot(k) => format!("robot {k}'s"),
    };
    match std::fs::metadata(f) {
        Ok(m) if m.is_file() => Ok(m.mode()),
        Ok(_) => Err(format!("`{}` is not a file", f.display())),
        Err(e) => Err(format!(
            "cannot read {whose} credentials `{}`: {e} (`gridswarm credentials --out DIR --robots N` makes them)",
            f.display()
        )),
    }
}

#[cfg(test)]
mod tests {
    use std::os::unix::fs::PermissionsExt;

    use super::*;

    #[test]
    fn a_key_others_can_read_is_refused_and_a_missing_file_named() {
        let dir = std::env::temp_dir().join(format!("gs-creds-test-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir(&dir).unwrap();
        let c = Credentials::new(&dir);
        let err = c.check(Holder::Robot(3)).unwrap_err();
        assert!(err.contains("ca.pem") && err.contains("robot 3's"), "{err}");
        let (cert, key) = c.of(Holder::Robot(3));
        for f in [c.ca(), cert, key.clone()] {
            std::fs::write(&f, "x").unwrap();
        }
        std::fs::set_permissions(&key, std::fs::Permissions::from_mode(0o644)).unwrap();
        let err = c.check(Holder::Robot(3)).unwrap_err();
        assert!(err.contains("robot-3.key") && err.contains("mode 0644"), "{err}");
        std::fs::set_permissions(&key, std::fs::Permissions::from_mode(0o600)).unwrap();
        assert_eq!(c.check(Holder::Robot(3)), Ok(()));
        assert!(c.check(Holder::World).unwrap_err().contains("world.pem"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
