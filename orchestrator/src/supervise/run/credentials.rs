//! Makes a zenoh run's credentials ([`gridswarm::transport::credentials`]
//! says which files): a fresh certificate authority, the world's
//! certificate (server use only, naming the hosts robots dial) and one
//! client certificate per robot, every file mode 0600. `gridswarm
//! credentials` writes them for runs across machines; a zenoh run on one
//! machine makes its own in its private temporary folder. The authority's
//! key is used once here and never written: nobody can sign another
//! certificate for the run.

use std::fs::{self, OpenOptions};
use std::io::Write;
use std::os::unix::fs::{DirBuilderExt, OpenOptionsExt, PermissionsExt};
use std::path::Path;

use gridswarm::transport::credentials::{robot_name, Credentials, Holder, WORLD_NAME};
use rcgen::{
    BasicConstraints, CertificateParams, CertifiedIssuer, DnType, ExtendedKeyUsagePurpose, IsCa, KeyPair,
    KeyUsagePurpose,
};

use crate::error::{Error, Result};

/// Names a world on this machine is always reached at.
pub const LOOPBACK_NAMES: [&str; 3] = ["localhost", "127.0.0.1", "::1"];

/// What to make.
pub struct Order<'a> {
    pub robots: usize,
    /// Host names and addresses the world's certificate names, beside
    /// [`LOOPBACK_NAMES`].
    pub hosts: &'a [String],
    /// How long the certificates are valid, from an hour ago (clocks differ).
    pub days: u32,
}

/// Creates `dir` (mode 0700; it must not exist, or be empty) and writes
/// the credentials into it.
pub fn create(dir: &Path, order: &Order) -> Result<()> {
    let empty = fs::read_dir(dir).map(|mut d| d.next().is_none()).unwrap_or(false);
    if empty {
        fs::set_permissions(dir, fs::Permissions::from_mode(0o700)).map_err(Error::write(dir))?;
    } else {
        fs::DirBuilder::new().mode(0o700).create(dir).map_err(|source| Error::OutDir {
            path: dir.to_path_buf(),
            source: if source.kind() == std::io::ErrorKind::AlreadyExists {
                std::io::Error::other("it exists and is not empty: credentials are never overwritten")
            } else {
                source
            },
        })?;
    }
    write(dir, order)
}

/// Writes the credentials into the existing folder `dir`; no file may
/// exist already.
pub fn write(dir: &Path, order: &Order) -> Result<()> {
    let err = |e: rcgen::Error| Error::Run(format!("cannot make the certificates: {e}"));
    let c = Credentials::new(dir);
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs() as i64);
    let from = time::OffsetDateTime::from_unix_timestamp(now - 3600).map_err(|e| Error::Run(e.to_string()))?;
    let until = from + time::Duration::days(i64::from(order.days)) + time::Duration::hours(1);
    let params = |cn: &str, names: Vec<String>| -> Result<CertificateParams> {
        let mut p = CertificateParams::new(names).map_err(|e| Error::Usage(format!("--host: {e}")))?;
        p.distinguished_name.push(DnType::CommonName, cn);
        (p.not_before, p.not_after) = (from, until);
        Ok(p)
    };
    let mut ca = params("gridswarm run authority", Vec::new())?;
    ca.is_ca = IsCa::Ca(BasicConstraints::Constrained(0));
    ca.key_usages = vec![KeyUsagePurpose::KeyCertSign, KeyUsagePurpose::CrlSign];
    let ca = CertifiedIssuer::self_signed(ca, KeyPair::generate().map_err(err)?).map_err(err)?;
    secret(&c.ca(), &ca.pem())?;

    let names: Vec<String> = order.hosts.iter().cloned().chain(LOOPBACK_NAMES.map(String::from)).collect();
    let holders = std::iter::once((Holder::World, WORLD_NAME.to_string(), names))
        .chain((0..order.robots).map(|k| (Holder::Robot(k), robot_name(k), Vec::new())));
    for (holder, cn, names) in holders {
        let mut p = params(&cn, names)?;
        p.key_usages = vec![KeyUsagePurpose::DigitalSignature];
        // A robot's certificate cannot pass for the world's, nor the world's for a robot's.
        p.extended_key_usages = vec![match holder {
            Holder::World => ExtendedKeyUsagePurpose::ServerAuth,
            Holder::Robot(_) => ExtendedKeyUsagePurpose::ClientAuth,
        }];
        let key = KeyPair::generate().map_err(err)?;
        let cert = p.signed_by(&key, &ca).map_err(err)?;
        let (cert_path, key_path) = c.of(holder);
        secret(&cert_path, &cert.pem())?;
        secret(&key_path, &key.serialize_pem())?;
    }
    Ok(())
}

/// Writes a new file only its owner can read.
fn secret(path: &Path, text: &str) -> Result<()> {
    let mut f = OpenOptions::new().write(true).create_new(true).mode(0o600).open(path).map_err(Error::write(path))?;
    f.write_all(text.as_bytes()).map_err(Error::write(path))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_file_is_the_owners_and_a_folder_is_never_overwritten() {
        let dir = std::env::temp_dir().join(format!("gs-make-creds-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        let order = Order { robots: 3, hosts: &["10.0.0.1".into(), "world.lab".into()], days: 2 };
        create(&dir, &order).unwrap();
        assert_eq!(fs::metadata(&dir).unwrap().permissions().mode() & 0o777, 0o700);
        let mut files: Vec<String> =
            fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        files.sort();
        let expected = ["ca.pem", "robot-0.key", "robot-0.pem", "robot-1.key", "robot-1.pem", "robot-2.key"];
        assert_eq!(files[..6], expected, "no CA key is kept: {files:?}");
        assert_eq!(files.len(), 9, "{files:?}");
        for f in &files {
            assert_eq!(fs::metadata(dir.join(f)).unwrap().permissions().mode() & 0o777, 0o600, "{f}");
        }
        let c = Credentials::new(&dir);
        assert_eq!(c.check(Holder::World), Ok(()));
        assert_eq!(c.check(Holder::Robot(2)), Ok(()));
        assert!(fs::read_to_string(c.of(Holder::Robot(1)).1).unwrap().contains("PRIVATE KEY"));
        let again = create(&dir, &order).unwrap_err().to_string();
        assert!(again.contains("never overwritten"), "{again}");
        fs::remove_dir_all(&dir).unwrap();
    }
}
