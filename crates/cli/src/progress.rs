//! A progress bar on stderr for long steps, for any command.
//!
//! ```text
//! reconstructing [##########··········] 7/15  skinning and refining: torso  0.3 s
//! ```
//!
//! Drawn only when stderr is a terminal (one line, redrawn in place with a
//! carriage return, at most every 40 ms or when the step changes, erased
//! when done); when stderr is a file or a pipe nothing is written, so logs
//! and scripted runs only see warnings and results. No dependency: the
//! line is plain text padded with spaces over the previous one.
//!
//! Use it with [`trigbody_core::reconstruct_with_progress`]:
//!
//! ```ignore
//! let mut bar = ProgressBar::new("reconstructing");
//! let result = reconstruct_with_progress(body, &opts, &mut |p| bar.update(p));
//! bar.finish();
//! ```

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};
use trigbody_core::Progress;

/// Cells of the bar.
const WIDTH: usize = 20;
/// Shortest time between two redraws of the same step.
const REDRAW: Duration = Duration::from_millis(40);

/// A one-line progress bar on stderr (see the module doc).
#[derive(Debug)]
pub struct ProgressBar {
    label: String,
    started: Instant,
    /// Whether to draw at all (stderr is a terminal).
    shown: bool,
    last_draw: Option<Instant>,
    last_stage: String,
    /// Characters of the line on screen (to blank it).
    drawn: usize,
}

impl ProgressBar {
    /// A bar labelled `label`, shown when stderr is a terminal.
    pub fn new(label: &str) -> ProgressBar {
        ProgressBar::with_terminal(label, std::io::stderr().is_terminal())
    }

    /// A bar that draws only when `shown` (for tests and callers that
    /// decide themselves).
    pub fn with_terminal(label: &str, shown: bool) -> ProgressBar {
        ProgressBar {
            label: label.to_string(),
            started: Instant::now(),
            shown,
            last_draw: None,
            last_stage: String::new(),
            drawn: 0,
        }
    }

    /// Shows `p` (throttled; a new step is always drawn).
    pub fn update(&mut self, p: Progress<'_>) {
        if !self.shown {
            return;
        }
        let now = Instant::now();
        let new_stage = p.stage != self.last_stage;
        if !new_stage && self.last_draw.is_some_and(|t| now - t < REDRAW) {
            return;
        }
        if new_stage {
            self.last_stage = p.stage.to_string();
        }
        self.last_draw = Some(now);
        let line = self.line(p, now - self.started);
        self.draw(&line);
    }

    /// The text of the bar for `p` after `elapsed`.
    pub fn line(&self, p: Progress<'_>, elapsed: Duration) -> String {
        let filled = (p.fraction() * WIDTH as f64).round() as usize;
        let filled = filled.min(WIDTH);
        format!(
            "{} [{}{}] {}/{}  {}  {:.1} s",
            self.label,
            "#".repeat(filled),
            "·".repeat(WIDTH - filled),
            p.done.min(p.total),
            p.total,
            p.stage,
            elapsed.as_secs_f64()
        )
    }

    fn draw(&mut self, line: &str) {
        let chars = line.chars().count();
        let pad = self.drawn.saturating_sub(chars);
        let mut err = std::io::stderr().lock();
        // A failed write to stderr is not worth failing the command for.
        let _ = write!(err, "\r{line}{}", " ".repeat(pad));
        let _ = err.flush();
        self.drawn = chars;
    }

    /// Erases the bar (the line is left empty for what follows).
    pub fn finish(&mut self) {
        if self.shown && self.drawn > 0 {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r{}\r", " ".repeat(self.drawn));
            let _ = err.flush();
            self.drawn = 0;
        }
    }
}

impl Drop for ProgressBar {
    fn drop(&mut self) {
        self.finish();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_shows_the_fraction_and_the_step() {
        let bar = ProgressBar::with_terminal("reconstructing", true);
        let p = Progress {
            stage: "sections: torso",
            done: 3,
            total: 12,
        };
        let line = bar.line(p, Duration::from_millis(300));
        assert_eq!(
            line,
            "reconstructing [#####···············] 3/12  sections: torso  0.3 s"
        );
        let end = Progress {
            stage: "done",
            done: 12,
            total: 12,
        };
        assert!(bar.line(end, Duration::ZERO).contains(&"#".repeat(WIDTH)));
    }

    #[test]
    fn hidden_bar_draws_nothing() {
        let mut bar = ProgressBar::with_terminal("x", false);
        bar.update(Progress {
            stage: "a",
            done: 0,
            total: 1,
        });
        assert_eq!(bar.drawn, 0);
        assert!(!bar.shown);
    }
}
