//! Progress of long work, the one way every stage reports it.
//!
//! - On a terminal: an `indicatif` bar per running stage (items done of total, elapsed,
//!   ETA), one line each under a shared [`MultiProgress`], as cargo shows crates.
//! - Otherwise (CI, `| tee`, a log file): one ticker thread prints a plain line
//!   `[  123.4 s] ltc-ggx: ltc fit: 1200/4096 (29 %), ETA 290 s` for every running study
//!   that has been silent for [`DUE`], so no running study is silent for more than
//!   [`PERIOD`] — so a slow item still gets its line — and a last line when a stage that
//!   printed ends. Stages that end within the period print nothing.
//!
//! A study registers itself for its whole run ([`Progress::study`]: "running, N s"); the
//! stages started on its thread are its own, and the study's silence is measured from the
//! last line of any of them, so a run of short stages that each end unprinted cannot add
//! up to a long silence. The line, when due, is that of the study's latest busy stage (its
//! numbers), else the study's own. A stage started outside a study (or on a worker thread)
//! is due its line on its own silence.

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::cell::Cell;
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// The longest a running study stays silent when stderr is not a terminal.
pub const PERIOD: Duration = Duration::from_secs(10);

/// How often the ticker wakes.
const TICK: Duration = Duration::from_millis(500);

/// The silence after which the ticker prints: [`PERIOD`] less two ticks, so the line
/// comes within the period even when a wake-up runs a tick late.
pub const DUE: Duration = Duration::from_millis(9000);

thread_local! {
    /// The study running on this thread (its entry's id), set by [`Progress::study`].
    static OWNER: Cell<Option<u64>> = const { Cell::new(None) };
}

/// One line on stderr stamped with the seconds since the process's first line
/// (`crate::report::stage` is this). Said on a study's thread, it counts as that study's
/// line: the study's silence starts again.
pub fn stamp(msg: &str) {
    emit(msg);
    if let Some(id) = OWNER.get() {
        if let Ok(mut p) = plain().lock() {
            if let Some(e) = p.running.get_mut(&id) {
                e.last = Instant::now();
            }
        }
    }
}

/// [`stamp`]'s line alone (what the ticker and a stage's end print, with the stages'
/// lock held).
fn emit(msg: &str) {
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
    /// The study whose thread started this stage.
    owner: Option<u64>,
}

#[derive(Default)]
struct Plain {
    next_id: u64,
    running: BTreeMap<u64, Entry>,
}

impl Plain {
    fn insert(
        &mut self,
        label: String,
        total: u64,
        done: Arc<AtomicU64>,
        owner: Option<u64>,
        now: Instant,
    ) -> u64 {
        let id = self.next_id;
        self.next_id += 1;
        self.running.insert(
            id,
            Entry {
                label,
                total,
                done,
                start: now,
                last: now,
                printed: false,
                owner,
            },
        );
        id
    }

    /// Print (through `sink`) a line for every running study, and every stage of no
    /// running study, silent for `period` at `now`.
    fn tick(&mut self, now: Instant, period: Duration, sink: &dyn Fn(&str)) {
        let studies: Vec<u64> = self
            .running
            .iter()
            .filter(|(_, e)| e.total == 0)
            .map(|(&id, _)| id)
            .collect();
        for &study in &studies {
            // the study's silence: since the last line of the study or any of its stages
            if !due(self.running[&study].last, now, period) {
                continue;
            }
            // the latest busy stage speaks for the study (its numbers), else the study
            let speaker = self
                .running
                .iter()
                .filter(|(_, e)| e.owner == Some(study))
                .max_by_key(|(&id, e)| (e.start, id))
                .map_or(study, |(&id, _)| id);
            if let Some(e) = self.running.get_mut(&speaker) {
                let done = e.done.load(Ordering::Relaxed);
                sink(&line(&e.label, done, e.total, now - e.start, false));
                e.printed = true;
                e.last = now;
            }
            if let Some(e) = self.running.get_mut(&study) {
                e.last = now;
            }
        }
        for e in self.running.values_mut() {
            let orphan = e.owner.is_none_or(|o| !studies.contains(&o));
            if e.total > 0 && orphan && due(e.last, now, period) {
                let done = e.done.load(Ordering::Relaxed);
                sink(&line(&e.label, done, e.total, now - e.start, false));
                e.last = now;
                e.printed = true;
            }
        }
    }

    /// End stage `id` at `now`: its last line if it printed one (which counts as its
    /// study's line too). A study itself ends without one: its runner says "done in".
    fn end(&mut self, id: u64, now: Instant, sink: &dyn Fn(&str)) {
        let Some(e) = self.running.remove(&id) else {
            return;
        };
        if e.printed && e.total > 0 {
            let done = e.done.load(Ordering::Relaxed);
            sink(&line(&e.label, done, e.total, now - e.start, true));
            if let Some(o) = e.owner.and_then(|o| self.running.get_mut(&o)) {
                o.last = now;
            }
        }
    }
}

fn plain() -> &'static Mutex<Plain> {
    static P: OnceLock<Mutex<Plain>> = OnceLock::new();
    P.get_or_init(|| {
        // the ticker: wakes every TICK, prints what is due
        std::thread::spawn(|| loop {
            std::thread::sleep(TICK);
            tick(Instant::now(), DUE, &emit);
        });
        Mutex::new(Plain::default())
    })
}

/// Print (through `sink`) what is due at `now` (see [`Plain::tick`]).
fn tick(now: Instant, period: Duration, sink: &dyn Fn(&str)) {
    if let Ok(mut p) = plain().lock() {
        p.tick(now, period, sink);
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
    /// For a study: the thread's study before it, restored when it ends.
    outer: Option<Option<u64>>,
}

impl Progress {
    /// A stage of `total` items (0: unknown, shown as "running"), the current study's
    /// when started on its thread.
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
                outer: None,
            };
        }
        let owner = OWNER.get();
        let id = plain()
            .lock()
            .ok()
            .map(|mut p| p.insert(label, total, done.clone(), owner, Instant::now()));
        Progress {
            done,
            bar: None,
            id,
            outer: None,
        }
    }

    /// A study, for its whole run: "running, N s", and the owner of every stage started
    /// on this thread until it ends.
    pub fn study(name: impl Into<String>) -> Progress {
        let mut p = Progress::new(name, 0);
        if let Some(id) = p.id {
            p.outer = Some(OWNER.replace(Some(id)));
        }
        p
    }

    /// `k` more items done.
    pub fn inc(&self, k: u64) {
        self.done.fetch_add(k, Ordering::Relaxed);
        if let Some(b) = &self.bar {
            b.inc(k);
        }
    }

    /// Run `f` (which prints) with this stage's bar out of the way on a terminal.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        match &self.bar {
            Some(_) => bars().suspend(f),
            None => f(),
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
        if let Some(outer) = self.outer.take() {
            OWNER.set(outer);
        }
        if let Some(id) = self.id {
            if let Ok(mut p) = plain().lock() {
                p.end(id, Instant::now(), &emit);
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

    /// Drive `p` on a synthetic clock from `t0` in ticks of [`TICK`] for `secs`, running
    /// `events(p, t)` before each tick; returns every line with its time in seconds.
    fn drive(
        p: &mut Plain,
        t0: Instant,
        secs: f64,
        mut events: impl FnMut(&mut Plain, f64, &dyn Fn(&str)),
    ) -> Vec<(f64, String)> {
        let seen = std::cell::RefCell::new(Vec::new());
        let t = Cell::new(0.0);
        let sink = |s: &str| seen.borrow_mut().push((t.get(), s.to_string()));
        while t.get() <= secs {
            events(p, t.get(), &sink);
            p.tick(t0 + Duration::from_secs_f64(t.get()), DUE, &sink);
            t.set(t.get() + TICK.as_secs_f64());
        }
        seen.into_inner()
    }

    /// The longest silence from 0 to `end` between the lines at `times`.
    fn longest_silence(times: &[f64], end: f64) -> f64 {
        let mut last = 0.0f64;
        let mut worst = 0.0f64;
        for &t in times.iter().chain([&end]) {
            worst = worst.max(t - last);
            last = t;
        }
        worst
    }

    #[test]
    fn short_stages_in_a_row_cannot_silence_a_study() {
        // a study of ten 6-second stages, each ending before its own line would be due:
        // the study still gets a line within every period (the old per-stage rule left it
        // silent for up to a stage plus a period)
        let t0 = Instant::now();
        let mut p = Plain::default();
        let done = || Arc::new(AtomicU64::new(0));
        let study = p.insert("study".into(), 0, done(), None, t0);
        let mut stage: Option<u64> = None;
        let lines = drive(&mut p, t0, 60.0, |p, t, sink| {
            let at = t0 + Duration::from_secs_f64(t);
            if t % 6.0 == 0.0 {
                if let Some(id) = stage.take() {
                    p.end(id, at, sink);
                }
                if t < 60.0 {
                    let label = format!("study: stage {}", t / 6.0);
                    stage = Some(p.insert(label, 4, done(), Some(study), at));
                }
            }
        });
        let times: Vec<f64> = lines.iter().map(|l| l.0).collect();
        let worst = longest_silence(&times, 60.0);
        assert!(
            worst <= (DUE + TICK).as_secs_f64() && worst < PERIOD.as_secs_f64(),
            "{worst} s: {lines:?}"
        );
        // the lines carry the busy stage's numbers, not "running"
        assert!(
            lines.iter().all(|l| l.1.starts_with("study: stage ")),
            "{lines:?}"
        );
        assert!(lines.len() >= 6, "{lines:?}");
    }

    #[test]
    fn a_study_without_a_busy_stage_says_it_is_running() {
        let t0 = Instant::now();
        let mut p = Plain::default();
        p.insert("ltc-ggx".into(), 0, Arc::new(AtomicU64::new(0)), None, t0);
        let lines = drive(&mut p, t0, 20.0, |p, t, sink| {
            // the study ends at 20 s, after its lines: no "running" line as it ends
            if t == 20.0 {
                let id = *p.running.keys().next().unwrap();
                p.end(id, t0 + Duration::from_secs(20), sink);
            }
        });
        let texts: Vec<&str> = lines.iter().map(|l| l.1.as_str()).collect();
        assert_eq!(texts, ["ltc-ggx: running, 9 s", "ltc-ggx: running, 18 s"]);
        assert!(p.running.is_empty());
    }

    #[test]
    fn a_printed_stages_end_line_restarts_its_studys_silence() {
        let t0 = Instant::now();
        let mut p = Plain::default();
        let study = p.insert("s".into(), 0, Arc::new(AtomicU64::new(0)), None, t0);
        let stage = p.insert(
            "s: long".into(),
            8,
            Arc::new(AtomicU64::new(3)),
            Some(study),
            t0,
        );
        let lines = drive(&mut p, t0, 30.0, |p, t, sink| {
            // the stage ends at 12 s, after its line at 9 s: its end line is the study's
            if t == 12.0 {
                p.end(stage, t0 + Duration::from_secs(12), sink);
            }
        });
        let times: Vec<f64> = lines.iter().map(|l| l.0).collect();
        // 9 s (the stage), its end at 12 s, then 12 + 9 = 21 s (the study), then 30 s
        assert_eq!(times, [9.0, 12.0, 21.0, 30.0], "{lines:?}");
        assert!(
            lines[0].1.starts_with("s: long: 3/8 (38 %), ETA"),
            "{lines:?}"
        );
        assert_eq!(lines[1].1, "s: long: 3/8 (38 %), ETA 20 s");
        assert_eq!(lines[2].1, "s: running, 21 s");
    }

    #[test]
    fn a_stage_of_no_study_keeps_its_own_period() {
        let t0 = Instant::now();
        let mut p = Plain::default();
        p.insert("verify".into(), 10, Arc::new(AtomicU64::new(5)), None, t0);
        // its study is gone: it speaks for itself too
        p.insert(
            "orphan".into(),
            10,
            Arc::new(AtomicU64::new(1)),
            Some(999),
            t0,
        );
        let lines = drive(&mut p, t0, 10.0, |_, _, _| {});
        let texts: Vec<&str> = lines.iter().map(|l| l.1.as_str()).collect();
        assert_eq!(texts.len(), 2, "{texts:?}");
        assert!(texts[0].starts_with("verify: 5/10 (50 %)"), "{texts:?}");
        assert!(texts[1].starts_with("orphan: 1/10 (10 %)"), "{texts:?}");
    }

    #[test]
    fn a_studys_stages_are_its_own_on_its_thread_only() {
        if std::io::stderr().is_terminal() {
            return; // bars, not lines, on a terminal
        }
        let owner_of = |p: &Progress| {
            let id = p.id.expect("registered");
            plain().lock().unwrap().running[&id].owner
        };
        let study = Progress::study("unit-test study");
        let sid = study.id;
        assert!(sid.is_some());
        let inner = Progress::new("unit-test study: stage", 3);
        assert_eq!(owner_of(&inner), sid);
        // another thread's stage belongs to no study
        let other = std::thread::spawn(|| {
            let q = Progress::new("unit-test other", 3);
            let id = q.id.expect("registered");
            let o = plain().lock().unwrap().running[&id].owner;
            o
        })
        .join()
        .unwrap();
        assert_eq!(other, None);
        drop(inner);
        drop(study);
        // the study ended: the thread owns nothing again
        let after = Progress::new("unit-test after", 1);
        assert_eq!(owner_of(&after), None);
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
