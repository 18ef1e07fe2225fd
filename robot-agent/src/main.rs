//! `robot-agent`: the built-in choice rules' agent (see the library).

fn main() -> std::process::ExitCode {
    robot_agent::main_with(&[])
}
