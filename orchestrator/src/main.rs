//! `gridswarm`: the command line (`cli::command`), with the built-in
//! algorithms only.

use std::process::ExitCode;

fn main() -> ExitCode {
    gridswarm_orchestrator::main_with(&[])
}
