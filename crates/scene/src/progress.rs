//! Progress of long runs on stderr: an indicatif bar with ETA when stderr is a terminal, else a
//! plain line at most every [`PLAIN_EVERY`] (none for runs shorter than that; the environment
//! variable `NEARFIELD_PROGRESS_SECONDS` sets another interval), so logs of CI and scripts show
//! that a run is alive without filling up.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The interval of plain progress lines.
pub const PLAIN_EVERY: Duration = Duration::from_secs(5);

pub struct Progress {
    what: String,
    unit: &'static str,
    total: u64,
    bar: Option<ProgressBar>,
    every: Duration,
    plain: Mutex<Plain>,
}

struct Plain {
    start: Instant,
    last: Instant,
    done: u64,
    message: String,
}

impl Progress {
    /// Progress of `total` `unit`s of `what` (e.g. "render hbil", 1000, "frames"); `show` false
    /// draws nothing.
    pub fn new(what: &str, total: u64, unit: &'static str, show: bool) -> Self {
        let bar = (show && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::new(total);
            bar.set_style(
                ProgressStyle::with_template(&format!(
                    "{what} {{msg}} [{{bar:40}}] {{pos}}/{{len}} {unit}, {{elapsed}} elapsed, ETA {{eta}}"
                ))
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            bar
        });
        let now = Instant::now();
        Progress {
            what: if show {
                what.to_string()
            } else {
                String::new()
            },
            unit,
            total,
            bar,
            every: std::env::var("NEARFIELD_PROGRESS_SECONDS")
                .ok()
                .and_then(|s| s.parse::<f64>().ok())
                .filter(|s| s.is_finite() && *s >= 0.0)
                .map(Duration::from_secs_f64)
                .unwrap_or(PLAIN_EVERY),
            plain: Mutex::new(Plain {
                start: now,
                last: now,
                done: 0,
                message: String::new(),
            }),
        }
    }

    /// What is being worked on now (shown beside the bar and in plain lines).
    pub fn set_message(&self, message: &str) {
        if let Some(b) = &self.bar {
            b.set_message(message.to_string());
        }
        if let Ok(mut p) = self.plain.lock() {
            p.message = message.to_string();
        }
    }

    /// `n` more units done.
    pub fn inc(&self, n: u64) {
        if let Some(b) = &self.bar {
            b.inc(n);
            return;
        }
        if self.what.is_empty() {
            return;
        }
        let Ok(mut p) = self.plain.lock() else {
            return;
        };
        p.done += n;
        let now = Instant::now();
        if now.duration_since(p.last) >= self.every && p.done < self.total {
            p.last = now;
            let elapsed = now.duration_since(p.start).as_secs_f64();
            let eta = elapsed / p.done.max(1) as f64 * (self.total - p.done) as f64;
            let message = if p.message.is_empty() {
                String::new()
            } else {
                format!(" ({})", p.message)
            };
            eprintln!(
                "nearfield: {}{message}: {}/{} {}, {elapsed:.0} s elapsed, ETA {eta:.0} s",
                self.what, p.done, self.total, self.unit
            );
        }
    }

    /// Runs `f` (which prints) with the bar hidden, so that its lines do not tear the bar.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        match &self.bar {
            Some(b) => b.suspend(f),
            None => f(),
        }
    }

    /// Removes the bar (plain lines need no ending).
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
