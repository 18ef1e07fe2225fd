//! `gridswarm credentials`: the certificates of a zenoh run across
//! machines, written to a new folder, and what to copy to which host.

use std::path::PathBuf;

use gridswarm::ipc::MAX_ROBOTS;
use gridswarm::transport::credentials::{Credentials, Holder};

use crate::error::Result;
use crate::run::credentials::{self, Order, LOOPBACK_NAMES};

#[derive(clap::Args, Debug, Clone)]
pub struct CredentialsArgs {
    /// The folder to make (mode 0700); it must not exist, or be empty.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Robots to make certificates for: robot-0 to robot-(N-1).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_ROBOTS as i64))]
    pub robots: u32,
    /// A host name or address the robots dial the world at (the world's
    /// certificate must name it); repeatable. localhost, 127.0.0.1 and ::1
    /// are always named.
    #[arg(long, value_name = "NAME")]
    pub host: Vec<String>,
    /// Days the certificates are valid.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=3650))]
    pub days: u32,
}

/// Makes the folder; returns what to tell the user.
pub fn run(a: &CredentialsArgs) -> Result<String> {
    let robots = a.robots as usize;
    credentials::create(&a.out, &Order { robots, hosts: &a.host, days: a.days })?;
    let c = Credentials::new(&a.out);
    let name = |p: PathBuf| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let (wc, wk) = c.of(Holder::World);
    let names: Vec<&str> = a.host.iter().map(String::as_str).chain(LOOPBACK_NAMES).collect();
    Ok(format!(
        "credentials for a world and {robots} robot(s) in {dir}, valid {days} day(s):\n  \
         the world's host: {ca} {wc} {wk} (the world's certificate names {names})\n  \
         robot K's host:   {ca} robot-K.pem robot-K.key (K from 0 to {last})\n\
         Every file is a secret but {ca}; the authority's key was not kept: no other certificate can join.\n",
        dir = a.out.display(),
        days = a.days,
        ca = name(c.ca()),
        wc = name(wc),
        wk = name(wk),
        names = names.join(", "),
        last = robots - 1,
    ))
}
