//! The experiments' progress on stderr: a bar (hidden when stderr is not a terminal), a spinner
//! for phases of unknown length, and warnings printed above the bar.

use std::sync::OnceLock;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use strider_experiments::progress::Progress;

/// A progress bar drawn with `template` once the work's length is known.
pub struct Bar {
    bar: ProgressBar,
    spinner: OnceLock<ProgressBar>,
}

impl Bar {
    /// A bar with an `indicatif` template (a spinner style when the template is refused).
    pub fn new(template: &str) -> Self {
        let bar = ProgressBar::hidden();
        bar.set_style(
            ProgressStyle::with_template(template)
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        Self {
            bar,
            spinner: OnceLock::new(),
        }
    }
}

impl Progress for Bar {
    fn start(&self, total: u64) {
        self.bar.set_length(total);
        self.bar.set_draw_target(ProgressDrawTarget::stderr());
    }

    fn at(&self, done: u64, message: &str) {
        self.bar.set_position(done);
        self.bar.set_message(message.to_string());
    }

    fn inc(&self) {
        self.bar.inc(1);
    }

    fn phase(&self, message: &str) {
        self.bar.finish_and_clear();
        let spinner = self.spinner.get_or_init(|| {
            let s = ProgressBar::new_spinner();
            s.enable_steady_tick(Duration::from_millis(200));
            s
        });
        spinner.set_message(message.to_string());
    }

    fn warn(&self, text: &str) {
        self.bar.suspend(|| eprintln!("warning: {text}"));
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
        if let Some(s) = self.spinner.get() {
            s.finish_and_clear();
        }
    }
}
