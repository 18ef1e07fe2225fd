//! Links the `robot-agent` binary as a position-dependent executable.
//!
//! A run starts one agent per robot, so an agent's memory is multiplied by
//! up to 1,000. Linked as PIE, the loader relocates every pointer in the
//! binary's data at start: it reads all of `.rela.dyn` (about 0.5 MiB) and
//! writes every page of `.data.rel.ro` and the GOT (about 0.4 MiB), private
//! to each process. At a fixed address the linker resolves those pointers
//! once, and the pages stay shared, clean file pages. Only the binaries of
//! this package: the library and what links it are untouched.

fn main() {
    println!("cargo:rustc-link-arg-bins=-no-pie");
}
