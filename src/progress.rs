//! Progress of long work, the one way every stage reports it.
//!
//! - On a terminal: an `indicatif` bar per running stage (items done of total, elapsed,
//!   ETA), one line each under a shared [`MultiProgress`], as cargo shows crates.
//! - Otherwise (CI, `| tee`, a log file): one ticker thread prints, for every running
//!   stage that has been silent for [`PERIOD`], a plain line
//!   `[  123.4 s] ltc-ggx: fit 64² cells: 1200/4096 (29 %), ETA 290 s` — so a slow item
//!   still gets its line — and a last line when a stage that printed ends. Stages that
//!   end within the period print nothing.
//!
//! A study registers itself for its whole run ([`Progress::new`] with total 0: "running,
//! N s"), so a study between its maps is not silent either.

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// The longest a running stage stays silent when stderr is not a terminal.
pub const PERIOD: Duration = Duration::from_secs(10);

/// One line on stderr stamped with the seconds since the process's first line
/// (`crate::report::stage` is this).
pub fn stamp(msg: &str) {
    static START: OnceLock<Instant> = OnceLock::new();
    let t0 = START.get_or_init(Instant::now);
    let text = format!("[{:>7.1} s] {msg}", t0.elapsed().as_secs_f64());
    if std::io::stderr().is_terminal() {
        // above the bars, not through them
        if bars().println(&text).is_err() {
            eprintln!("{text}");
        }
    } else {
        eprintln!("{text}");
    }
}

/// The plain line of a stage: label, done/total, percent and ETA from the mean rate so
/// far; with total 0, "running" and the elapsed time. A stage whose items are all done
/// but which has not `ended` (its map still joining, or the work after its last item)
/// says so instead of "done".
pub fn line(label: &str, done: u64, total: u64, elapsed: Duration, ended: bool) -> String {
    let t = elapsed.as_secs_f64();
    if total == 0 {
        return format!("{label}: running, {t:.0} s");
    }
    let pct = 100.0 * done.min(total) as f64 / total as f64;
    let eta = if done == 0 {
        ", ETA —".to_string()
    } else if done < total {
        format!(", ETA {:.0} s", t * (total - done) as f64 / done as f64)
    } else if ended {
        format!(", done in {t:.1} s")
    } else {
        format!(", every item done, still running at {t:.0} s")
    };
    format!("{label}: {done}/{total} ({pct:.0} %){eta}")
}

/// Whether a stage silent since `last` is due a line at `now`.
pub fn due(last: Instant, now: Instant, period: Duration) -> bool {
    now.saturating_duration_since(last) >= period
}

struct Entry {
    label: String,
    total: u64,
    done: Arc<AtomicU64>,
    start: Instant,
    last: Instant,
    printed: bool,
}

struct Plain {
    next_id: u64,
    running: BTreeMap<u64, Entry>,
}

fn plain() -> &'static Mutex<Plain> {
    static P: OnceLock<Mutex<Plain>> = OnceLock::new();
    P.get_or_init(|| {
        // the ticker: wakes every second, prints what is due
        std::thread::spawn(|| loop {
            std::thread::sleep(Duration::from_secs(1));
            tick(Instant::now(), PERIOD, &stamp);
        });
        Mutex::new(Plain {
            next_id: 0,
            running: BTreeMap::new(),
        })
    })
}

/// Print (through `sink`) a line for every running stage due at `now`.
fn tick(now: Instant, period: Duration, sink: &dyn Fn(&str)) {
    let Ok(mut p) = plain().lock() else { return };
    // a study's own "running" line gives way to the lines of its maps
    let busy: Vec<String> = p
        .running
        .values()
        .filter(|e| e.total > 0)
        .map(|e| e.label.clone())
        .collect();
    for e in p.running.values_mut() {
        let inner = e.total == 0
            && busy
                .iter()
                .any(|b| b.starts_with(&format!("{}: ", e.label)));
        if inner {
            e.last = now;
            continue;
        }
        if due(e.last, now, period) {
            let done = e.done.load(Ordering::Relaxed);
            sink(&line(&e.label, done, e.total, now - e.start, false));
            e.last = now;
            e.printed = true;
        }
    }
}

fn bars() -> &'static MultiProgress {
    static M: OnceLock<MultiProgress> = OnceLock::new();
    M.get_or_init(|| MultiProgress::with_draw_target(ProgressDrawTarget::stderr()))
}

/// A running stage; ends when dropped (or [`Progress::finish`]).
pub struct Progress {
    done: Arc<AtomicU64>,
    bar: Option<ProgressBar>,
    id: Option<u64>,
}

impl Progress {
    /// A stage of `total` items (0: unknown, shown as "running").
    pub fn new(label: impl Into<String>, total: u64) -> Progress {
        let label = label.into();
        let done = Arc::new(AtomicU64::new(0));
        if std::io::stderr().is_terminal() {
            let bar = bars().add(ProgressBar::new(total));
            let style = if total == 0 {
                ProgressStyle::with_template("{spinner} {msg}: running, {elapsed}")
            } else {
                ProgressStyle::with_template("{msg}: {bar:30} {pos}/{len} ({percent} %), ETA {eta}")
            };
            if let Ok(s) = style {
                bar.set_style(s);
            }
            bar.set_message(label);
            if total == 0 {
                bar.enable_steady_tick(Duration::from_millis(250));
            }
            return Progress {
                done,
                bar: Some(bar),
                id: None,
            };
        }
        let now = Instant::now();
        let id = plain().lock().ok().map(|mut p| {
            let id = p.next_id;
            p.next_id += 1;
            p.running.insert(
                id,
                Entry {
                    label,
                    total,
                    done: done.clone(),
                    start: now,
                    last: now,
                    printed: false,
                },
            );
            id
        });
        Progress {
            done,
            bar: None,
            id,
        }
    }

    /// `k` more items done.
    pub fn inc(&self, k: u64) {
        self.done.fetch_add(k, Ordering::Relaxed);
        if let Some(b) = &self.bar {
            b.inc(k);
        }
    }

    /// End the stage (the same as dropping it).
    pub fn finish(self) {}
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
            bars().remove(&b);
        }
        if let Some(id) = self.id {
            if let Ok(mut p) = plain().lock() {
                if let Some(e) = p.running.remove(&id) {
                    if e.printed {
                        let done = e.done.load(Ordering::Relaxed);
                        stamp(&line(&e.label, done, e.total, e.start.elapsed(), true));
                    }
                }
            }
        }
    }
}

/// CPU seconds this process has spent so far, user + system over every thread
/// (`getrusage(RUSAGE_SELF)`); `None` where the OS does not say.
pub fn process_cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        // SAFETY: getrusage writes one plain struct that we own; a zeroed rusage is valid
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) } != 0 {
            return None;
        }
        let s = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        Some(s(u.ru_utime) + s(u.ru_stime))
    }
    #[cfg(not(unix))]
    {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_say_done_total_and_eta() {
        let s = Duration::from_secs;
        assert_eq!(
            line("fit", 0, 4096, s(3), false),
            "fit: 0/4096 (0 %), ETA —"
        );
        assert_eq!(
            line("fit", 1024, 4096, s(10), false),
            "fit: 1024/4096 (25 %), ETA 30 s"
        );
        assert_eq!(
            line("fit", 4096, 4096, s(40), true),
            "fit: 4096/4096 (100 %), done in 40.0 s"
        );
        assert_eq!(
            line("ltc-ggx", 0, 0, s(61), false),
            "ltc-ggx: running, 61 s"
        );
        // every item done, the stage not ended: not "done"
        assert_eq!(
            line("fit", 4096, 4096, s(100), false),
            "fit: 4096/4096 (100 %), every item done, still running at 100 s"
        );
    }

    #[test]
    fn a_silent_stage_gets_its_line_when_due_and_not_before() {
        if std::io::stderr().is_terminal() {
            return; // bars, not lines, on a terminal
        }
        let p = Progress::new("unit-test stage", 8);
        p.inc(2);
        let seen = Mutex::new(Vec::new());
        let sink = |s: &str| seen.lock().unwrap().push(s.to_string());
        let now = Instant::now();
        // not yet due: nothing from this stage
        tick(now, Duration::from_secs(3600), &sink);
        assert!(!seen
            .lock()
            .unwrap()
            .iter()
            .any(|l| l.starts_with("unit-test stage")));
        // a period later (a synthetic clock, no waiting): its line, with its numbers
        tick(
            now + Duration::from_secs(3601),
            Duration::from_secs(3600),
            &sink,
        );
        let lines = seen.lock().unwrap().clone();
        let mine: Vec<&String> = lines
            .iter()
            .filter(|l| l.starts_with("unit-test stage"))
            .collect();
        assert_eq!(mine.len(), 1, "{lines:?}");
        assert!(
            mine[0].starts_with("unit-test stage: 2/8 (25 %), ETA"),
            "{}",
            mine[0]
        );
        p.finish();
    }

    #[test]
    fn a_stage_is_due_a_line_once_per_period() {
        let t0 = Instant::now();
        let p = Duration::from_secs(10);
        assert!(!due(t0, t0 + Duration::from_millis(9999), p));
        assert!(due(t0, t0 + p, p));
        // a clock that went backwards is never due
        assert!(!due(t0 + p, t0, p));
    }
}
