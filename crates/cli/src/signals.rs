//! Ctrl-C, `kill` and a closed terminal (SIGINT, SIGTERM, SIGHUP) end the
//! command without leaving a hidden temporary beside an output: a thread
//! waits for the signal, removes the live temporaries (an existing output
//! stays as it was) and ends the process by the same signal, so a shell
//! sees the conventional status (130, 143, 129) and a script's loop stops.
//! A signal ignored when the process starts (SIGHUP under `nohup`, SIGINT
//! in a shell's background job) stays ignored.

/// Starts the waiting thread; without it (no signal support) the signals
/// keep their default action.
#[cfg(unix)]
pub fn catch() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let ignored = ignored_signals();
    let wanted: Vec<i32> = [SIGINT, SIGTERM, SIGHUP]
        .into_iter()
        .filter(|&s| ignored >> (s - 1) & 1 == 0)
        .collect();
    let Ok(mut signals) = signal_hook::iterator::Signals::new(wanted) else {
        return;
    };
    let spawned = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                // Held until the end: no writer makes or places a temporary.
                let _removed = trigbody_io::remove_temporaries();
                let _ = signal_hook::low_level::emulate_default_handler(signal);
                std::process::exit(128 + signal);
            }
        });
    drop(spawned);
}

#[cfg(not(unix))]
pub fn catch() {}

/// The signals this process ignores (bit `n - 1` for signal `n`), from
/// Linux's `/proc/self/status`; none where that cannot be read.
#[cfg(unix)]
fn ignored_signals() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find_map(|l| l.strip_prefix("SigIgn:"))?;
            u64::from_str_radix(line.trim(), 16).ok()
        })
        .unwrap_or(0)
}
