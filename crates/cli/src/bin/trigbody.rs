//! The `trigbody` command: everything happens in [`trigbody::run`].

fn main() -> std::process::ExitCode {
    std::process::ExitCode::from(trigbody::run(std::env::args_os()))
}
