//! The `trigbody` command: everything happens in [`trigbody::run`], with
//! the signals caught ([`trigbody::catch_signals`]).

fn main() -> std::process::ExitCode {
    trigbody::catch_signals();
    std::process::ExitCode::from(trigbody::run(std::env::args_os()))
}
