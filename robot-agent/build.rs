//! Links the `robot-agent` binary so that one agent's memory stays small:
//! a run starts one per robot, up to 1,000 on one machine.
//!
//! - At a fixed address (`-no-pie`). Linked as a PIE, the loader relocates
//!   every pointer in the binary's data at start: it reads all of
//!   `.rela.dyn` (about 0.5 MiB) and writes every page of `.data.rel.ro`
//!   and the GOT (about 0.4 MiB), private to each process. At a fixed
//!   address the linker resolves them once and the pages stay shared.
//! - The code an iceoryx2 agent runs, packed together (`hot-symbols.txt`,
//!   made by `scripts/agent-hot-symbols.sh`). The kernel maps a binary's
//!   pages 64 KiB at a time around each one executed, and the agent's
//!   functions lie scattered among zenoh's, clap's and toml's: about 0.9
//!   MiB of code run kept 3.2 MiB of text resident in every agent. A stale
//!   list only loses some of the gain: lld skips names it does not find.
//!   Only with lld, Rust's default linker on x86_64 Linux, which alone of
//!   the usual linkers reads that list.
//!
//! Only this package's binaries: the library and programs that link it
//! (`main_with`) are linked the default way.

use std::path::Path;

fn main() {
    println!("cargo:rustc-link-arg-bins=-no-pie");
    let list = Path::new(env!("CARGO_MANIFEST_DIR")).join("hot-symbols.txt");
    println!("cargo:rerun-if-changed={}", list.display());
    println!("cargo:rerun-if-changed=build.rs");
    if links_with_lld() && list.is_file() {
        println!("cargo:rustc-link-arg-bins=-Wl,--symbol-ordering-file={}", list.display());
        println!("cargo:rustc-link-arg-bins=-Wl,--no-warn-symbol-ordering");
    }
}

/// Whether the binary is linked by rust-lld: the default for
/// x86_64-unknown-linux-gnu since Rust 1.90, unless the flags choose a linker.
fn links_with_lld() -> bool {
    let flags = std::env::var("CARGO_ENCODED_RUSTFLAGS").unwrap_or_default();
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let minor = std::process::Command::new(rustc)
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|v| v.split_whitespace().nth(1)?.split('.').nth(1)?.parse::<u32>().ok());
    std::env::var("TARGET").as_deref() == Ok("x86_64-unknown-linux-gnu")
        && !flags.contains("link")
        && minor.is_some_and(|m| m >= 90)
}
