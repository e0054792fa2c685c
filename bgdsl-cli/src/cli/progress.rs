//! The progress bar of runs and sweeps (on stderr, only when it is a terminal, and
//! only once a run has taken more than a moment); it passes the interrupt of
//! [`crate::interrupt`] on to runs as a stop request.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::catalog::Observer;

/// How long a run goes before its bar appears.
const GRACE: Duration = Duration::from_millis(300);

/// An [`Observer`] that draws a progress bar and passes Ctrl-C on as a stop request.
#[derive(Debug)]
pub struct Progress {
    bar: ProgressBar,
    terminal: bool,
    shown: AtomicBool,
    /// When the current run or sweep started, and its time span.
    run: Mutex<(Instant, f64, f64)>,
}

impl Default for Progress {
    fn default() -> Self {
        Self::new()
    }
}

impl Progress {
    /// A progress bar on stderr (hidden unless stderr is a terminal).
    pub fn new() -> Self {
        let bar = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::hidden());
        Progress {
            bar,
            terminal: std::io::stderr().is_terminal(),
            shown: AtomicBool::new(false),
            run: Mutex::new((Instant::now(), 0.0, 1.0)),
        }
    }

    fn style(&self, template: &str) {
        if let Ok(style) = ProgressStyle::with_template(template) {
            self.bar.set_style(style.progress_chars("=> "));
        }
    }

    /// Shows the bar once the run has taken longer than [`GRACE`].
    fn maybe_show(&self, started: Instant) {
        if self.terminal && !self.shown.load(Ordering::Relaxed) && started.elapsed() > GRACE {
            self.shown.store(true, Ordering::Relaxed);
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    fn started(&self) -> Instant {
        self.run
            .lock()
            .map(|r| r.0)
            .unwrap_or_else(|_| Instant::now())
    }
}

impl Observer for Progress {
    fn run_started(&self, t0: f64, t_end: f64) {
        if let Ok(mut run) = self.run.lock() {
            *run = (Instant::now(), t0, t_end);
        }
        self.style("{elapsed:>4} [{wide_bar}] {percent:>3}% {msg}");
        self.bar.set_length(1000);
        self.bar.set_position(0);
    }

    fn sample(&self, t: f64) {
        let (started, t0, t_end) =
            self.run
                .lock()
                .map(|r| *r)
                .unwrap_or((Instant::now(), 0.0, 1.0));
        let fraction = ((t - t0) / (t_end - t0)).clamp(0.0, 1.0);
        self.bar.set_position((fraction * 1000.0) as u64);
        self.maybe_show(started);
        if self.shown.load(Ordering::Relaxed) {
            self.bar.set_message(format!("t = {t:.3} s of {t_end} s"));
        }
    }

    fn run_finished(&self) {
        self.bar.finish_and_clear();
    }

    fn sweep_started(&self, points: usize) {
        if let Ok(mut run) = self.run.lock() {
            run.0 = Instant::now();
        }
        self.style("{elapsed:>4} [{wide_bar}] {pos}/{len} runs");
        self.bar.set_length(points as u64);
        self.bar.set_position(0);
    }

    fn point_done(&self) {
        self.bar.inc(1);
        self.maybe_show(self.started());
        if self.bar.length() == Some(self.bar.position()) {
            self.bar.finish_and_clear();
        }
    }

    fn stop_requested(&self) -> bool {
        crate::interrupt::requested()
    }
}
