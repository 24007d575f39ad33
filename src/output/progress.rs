//! A step counter for long runs: an `indicatif` bar on stderr when stderr is a terminal, and a
//! silent no-op otherwise (logs, CI, pipes stay clean).

use std::borrow::Cow;
use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar that draws only when stderr is a terminal.
#[derive(Debug, Clone)]
pub struct Progress {
    bar: Option<ProgressBar>,
}

impl Progress {
    /// A bar of `total_steps` steps with `label` as prefix; a no-op when stderr is not a
    /// terminal.
    pub fn new(total_steps: u64, label: &str) -> Self {
        if std::io::stderr().is_terminal() {
            Self::visible(total_steps, label)
        } else {
            Self::hidden()
        }
    }

    /// A bar that does nothing.
    pub fn hidden() -> Self {
        Progress { bar: None }
    }

    fn visible(total_steps: u64, label: &str) -> Self {
        let bar = ProgressBar::with_draw_target(Some(total_steps), ProgressDrawTarget::stderr());
        let style = ProgressStyle::with_template(
            "{prefix} [{elapsed_precise}] {wide_bar} {pos}/{len} ({per_sec}, eta {eta}) {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style);
        bar.set_prefix(label.to_string());
        Progress { bar: Some(bar) }
    }

    /// True when the bar is drawn.
    pub fn is_visible(&self) -> bool {
        self.bar.is_some()
    }

    /// Advances by `n` steps.
    pub fn inc(&self, n: u64) {
        if let Some(b) = &self.bar {
            b.inc(n);
        }
    }

    /// Sets the text shown after the bar.
    pub fn set_message(&self, msg: impl Into<Cow<'static, str>>) {
        if let Some(b) = &self.bar {
            b.set_message(msg);
        }
    }

    /// Finishes the bar, leaving it on screen.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish();
        }
    }
}
