//! Hand latency: from a device sample's arrival on the port to the window frame that shows it.
//!
//! Every sample comes with its [`Arrival`] (the moment the port read that completed its bytes
//! returned, and the moment its frame entered the stream's channel: `nendo_devices::arrival`).
//! The window's frame carries the stamp on, and [`LatencyMeter`] marks each later step on the
//! same monotonic clock ([`Instant`]):
//!
//! | stage | from → to | what runs |
//! |---|---|---|
//! | `parse` | port read → channel | decode, calibration, merge, the trace's rounding (device thread) |
//! | `wait` | channel → taken by the window | the loop thread's inbox, and the window's frame coming round |
//! | `hand` | taken → its own hand-loop frame done | gate, One-Euro filter, kinematics, contact, deformation, regulation — of this sample and of those before it in the same window frame |
//! | `batch` | → the window frame's last sample done | the hand loop on the samples after it |
//! | `display` | → the display cache up to date | re-tessellation of the changed patches, seam heat (and the UI pass, for samples taken at the frame's start) |
//! | `render` | → the frame's `queue.submit` returned | scene, vertex upload, encoding, submission |
//! | `present` | submission → presentation | see below |
//!
//! The **CPU side** of a sample is `t_submit − t_read = parse + wait + hand + batch + display +
//! render` — the stages telescope, so they add up to it exactly. The **presented** latency is
//! `t_present − t_read`, with `t_present` the moment `queue.present` returned for that frame
//! (the window; the offscreen bench uses the moment the device reports the frame's work done).
//! Why `present()`'s return rather than the next frame's acquire: the next acquire also waits
//! for the next frame's own CPU work and for input, which would charge this frame with idle
//! time; `present()` returning is the last moment the program sees of this frame. On Mesa's
//! software Vulkan (lavapipe) under X11 the presentation engine waits for the rasteriser and
//! copies the image into the window before `present()` returns, so that moment is when the
//! frame is on screen; on a GPU with vsync (FIFO) it is when the image is queued, and the
//! scan-out follows within one refresh period.
//!
//! A sample that arrives while a frame is being drawn is shown by the next frame that is
//! submitted (a skipped frame — no surface texture — leaves its samples to the next one).
//!
//! **The frame's newest sample.** A frame draws one hand: the pose of the newest sample it
//! takes (the latest port read). Samples before it in the same frame are run through the hand
//! loop — their effect on the clay is in the frame — but no frame draws their pose; on a
//! software renderer, where a frame takes tens of milliseconds to rasterise, most samples are
//! such. The figure the target is on is therefore each frame's newest sample, arrival →
//! submission, as a tracker's motion-to-photon latency is counted; every sample's figure is
//! kept beside it. The window orders a frame so that this sample is fresh at submission
//! (`app::window`): (1) the samples that came meanwhile run through the hand loop at the
//! frame's start; (2) the UI pass; (3) the surface texture is acquired — the call that waits
//! for the previous frame's presentation; (4) the frame *latches* the input: with a device
//! session streaming, it waits at most [`LATCH_WAIT`] for one more sample
//! ([`crate::editor::Modeller::latch_devices`]), then (5) takes what came, refreshes the
//! display (the patches the hand changed, at their segment counts), encodes and submits;
//! (6) after the presentation it settles the display ([`crate::editor::Modeller::settle`]:
//! the continuity measure and stale segment counts once a contact is over, a full pass over
//! the patches), which the next frame draws. The waits in (3) and for (6) thus fall before
//! the take, not between the take and the submission, and the latched sample's CPU side is
//! `parse` + the wake-up + its own hand-loop frame + `display` + `render`:
//!
//! `t_submit − t_read(newest) ≈ t_parse + t_wake + t_hand(1 sample) + t_display + t_render`.
//!
//! The wait in (4) delays the frame by at most one device period (it ends when the next
//! sample arrives); without a device, or when the session has finished, there is none.
//!
//! The figure (the status bar, the status file, `nendo bench input`) is the median and the
//! 95th percentile over the last [`LATENCY_WINDOW`] samples shown, by the nearest-rank rule:
//! the `p`-quantile of `n` sorted values is the `⌈p·n⌉`-th.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use nendo_devices::Arrival;

/// How many of the latest samples shown the figure is over (two seconds of a 120 Hz tracker).
pub const LATENCY_WINDOW: usize = 240;

/// The longest a frame waits for a fresh device sample after acquiring its surface texture
/// (one period of a 100 Hz glove, with margin): the latch of the module docs, step (4).
pub const LATCH_WAIT: Duration = Duration::from_millis(12);

/// One sample's time in each stage (see the module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stages {
    /// Port read → the stream's channel.
    pub parse: Duration,
    /// Channel → taken by the window's frame.
    pub wait: Duration,
    /// Taken → its hand-loop frame done (with those before it in the window frame).
    pub hand: Duration,
    /// → the window frame's last sample done.
    pub batch: Duration,
    /// → the display cache up to date.
    pub display: Duration,
    /// → the frame's GPU submission returned.
    pub render: Duration,
}

impl Stages {
    /// The stages' names, in order.
    pub const NAMES: [&'static str; 6] = ["parse", "wait", "hand", "batch", "display", "render"];

    /// The stages in order.
    #[must_use]
    pub fn all(&self) -> [Duration; 6] {
        [
            self.parse,
            self.wait,
            self.hand,
            self.batch,
            self.display,
            self.render,
        ]
    }

    /// The CPU side: their sum, arrival → submission.
    #[must_use]
    pub fn cpu(&self) -> Duration {
        self.all().iter().sum()
    }
}

/// A sample shown by a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SampleLatency {
    /// When its bytes were read from the port.
    pub read: Instant,
    /// Its stages up to the submission.
    pub stages: Stages,
    /// Submission → presentation, once the frame was presented.
    pub present: Option<Duration>,
    /// Whether its hand-loop frame changed the surface.
    pub changed: bool,
    /// Whether it is the newest sample its frame shows (the latest port read among them):
    /// the pose the frame draws. The older ones' effect on the clay is in the frame too, but
    /// their pose is shown by no frame (see the module docs).
    pub newest: bool,
}

impl SampleLatency {
    /// Arrival → the frame's GPU submission.
    #[must_use]
    pub fn cpu(&self) -> Duration {
        self.stages.cpu()
    }

    /// Arrival → the frame's presentation, once presented.
    #[must_use]
    pub fn presented(&self) -> Option<Duration> {
        self.present.map(|p| self.cpu() + p)
    }
}

/// A median and a 95th percentile.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Quantiles {
    /// The median.
    pub median: Duration,
    /// The 95th percentile.
    pub p95: Duration,
}

impl Quantiles {
    /// Of these values (nearest rank); `None` for none.
    #[must_use]
    pub fn of(values: impl IntoIterator<Item = Duration>) -> Option<Self> {
        let mut v: Vec<Duration> = values.into_iter().collect();
        if v.is_empty() {
            return None;
        }
        v.sort_unstable();
        Some(Quantiles {
            median: nearest_rank(&v, 0.5),
            p95: nearest_rank(&v, 0.95),
        })
    }
}

/// The `p`-quantile of sorted, non-empty `v`: its `⌈p·n⌉`-th value.
fn nearest_rank(v: &[Duration], p: f64) -> Duration {
    let rank = (p * v.len() as f64).ceil() as usize;
    v[rank.clamp(1, v.len()) - 1]
}

/// The figure over the latest samples shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LatencySummary {
    /// Samples it is over.
    pub samples: usize,
    /// Of those, the ones that changed the surface.
    pub changed: usize,
    /// Arrival → submission, over every sample.
    pub cpu: Quantiles,
    /// Arrival → presentation, over the samples whose frame was presented.
    pub presented: Option<Quantiles>,
    /// Arrival → submission of each frame's newest sample (the pose it draws): the figure the
    /// target is on (see the module docs).
    pub newest: Quantiles,
    /// Arrival → presentation of each presented frame's newest sample.
    pub newest_presented: Option<Quantiles>,
    /// Each stage's median (these do not add up to the median of the sums).
    pub stage_medians: Stages,
}

impl LatencySummary {
    /// The status bar's text.
    #[must_use]
    pub fn line(&self) -> String {
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let shown = self.newest_presented.map_or_else(String::new, |p| {
            format!(", shown {:.1} / {:.1} ms", ms(p.median), ms(p.p95))
        });
        format!(
            "hand → frame: CPU {:.1} / {:.1} ms{shown} (median / p95 of each frame's newest \
             sample; of all {} samples: CPU {:.1} / {:.1} ms)",
            ms(self.newest.median),
            ms(self.newest.p95),
            self.samples,
            ms(self.cpu.median),
            ms(self.cpu.p95),
        )
    }
}

/// A sample taken by the window, not yet submitted.
#[derive(Debug, Clone, Copy)]
struct Pending {
    arrival: Arrival,
    taken: Instant,
    fed: Instant,
    batch_done: Instant,
    display: Option<Instant>,
    changed: bool,
}

/// The window's latency record (see the module docs): samples taken, marked at each step, and
/// the latest [`LatencyMeter::window`] shown.
#[derive(Debug, Clone)]
pub struct LatencyMeter {
    pending: Vec<Pending>,
    shown: VecDeque<SampleLatency>,
    /// Samples of the last submission still waiting for its presentation.
    unpresented: usize,
    window: usize,
    /// Samples shown since the meter started.
    total: u64,
}

impl Default for LatencyMeter {
    fn default() -> Self {
        Self::with_window(LATENCY_WINDOW)
    }
}

impl LatencyMeter {
    /// A meter keeping the latest `window` samples shown (at least one).
    #[must_use]
    pub fn with_window(window: usize) -> Self {
        LatencyMeter {
            pending: Vec::new(),
            shown: VecDeque::new(),
            unpresented: 0,
            window: window.max(1),
            total: 0,
        }
    }

    /// How many samples the figure is over.
    #[must_use]
    pub fn window(&self) -> usize {
        self.window
    }

    /// Forgets every sample (a new session).
    pub fn clear(&mut self) {
        *self = Self::with_window(self.window);
    }

    /// A window frame took samples at `taken`: each with its arrival, the moment its hand-loop
    /// frame was done and whether it changed the surface; the last was done at `done`.
    pub fn took(&mut self, taken: Instant, samples: &[(Arrival, Instant, bool)], done: Instant) {
        self.pending
            .extend(samples.iter().map(|&(arrival, fed, changed)| Pending {
                arrival,
                taken,
                fed,
                batch_done: done,
                display: None,
                changed,
            }));
    }

    /// The display cache was brought up to date at `at`.
    pub fn display_refreshed(&mut self, at: Instant) {
        for p in self.pending.iter_mut().filter(|p| p.display.is_none()) {
            p.display = Some(at);
        }
    }

    /// The frame was submitted to the GPU at `at`: the samples taken and displayed before are
    /// shown by it.
    pub fn submitted(&mut self, at: Instant) {
        let (shown, waiting): (Vec<Pending>, Vec<Pending>) = std::mem::take(&mut self.pending)
            .into_iter()
            .partition(|p| p.display.is_some());
        self.pending = waiting;
        self.unpresented = shown.len();
        // The frame's newest sample: the last of those with the latest port read.
        let newest = shown
            .iter()
            .enumerate()
            .max_by_key(|(_, p)| p.arrival.read)
            .map(|(i, _)| i);
        for (i, p) in shown.into_iter().enumerate() {
            let display = p.display.unwrap_or(at);
            // Each mark is no earlier than the one before it (a clock read on another thread
            // can only be earlier), so the stages telescope to `at − read`.
            let sent = p.arrival.sent.max(p.arrival.read);
            let taken = p.taken.max(sent);
            let fed = p.fed.max(taken);
            let batch_done = p.batch_done.max(fed);
            let display = display.max(batch_done);
            let submitted = at.max(display);
            let stages = Stages {
                parse: sent - p.arrival.read,
                wait: taken - sent,
                hand: fed - taken,
                batch: batch_done - fed,
                display: display - batch_done,
                render: submitted - display,
            };
            self.push(SampleLatency {
                read: p.arrival.read,
                stages,
                present: None,
                changed: p.changed,
                newest: Some(i) == newest,
            });
        }
    }

    /// The last submitted frame was presented at `at`.
    pub fn presented(&mut self, at: Instant) {
        let n = std::mem::take(&mut self.unpresented).min(self.shown.len());
        let start = self.shown.len() - n;
        for s in self.shown.range_mut(start..) {
            let submitted = s.read + s.cpu();
            s.present = Some(at.saturating_duration_since(submitted));
        }
    }

    fn push(&mut self, s: SampleLatency) {
        if self.shown.len() == self.window {
            self.shown.pop_front();
        }
        self.shown.push_back(s);
        self.total += 1;
    }

    /// The latest samples shown, oldest first.
    pub fn shown(&self) -> impl Iterator<Item = &SampleLatency> {
        self.shown.iter()
    }

    /// Samples shown since the meter started (also those fallen out of the window).
    #[must_use]
    pub fn total(&self) -> u64 {
        self.total
    }

    /// Samples taken and not yet submitted.
    #[must_use]
    pub fn pending(&self) -> usize {
        self.pending.len()
    }

    /// The figure over the latest samples shown; `None` before the first.
    #[must_use]
    pub fn summary(&self) -> Option<LatencySummary> {
        let cpu = Quantiles::of(self.shown.iter().map(SampleLatency::cpu))?;
        let stage = |i: usize| {
            Quantiles::of(self.shown.iter().map(|s| s.stages.all()[i]))
                .map_or(Duration::ZERO, |q| q.median)
        };
        let newest = || self.shown.iter().filter(|s| s.newest);
        Some(LatencySummary {
            newest: Quantiles::of(newest().map(SampleLatency::cpu)).unwrap_or(cpu),
            newest_presented: Quantiles::of(newest().filter_map(SampleLatency::presented)),
            samples: self.shown.len(),
            changed: self.shown.iter().filter(|s| s.changed).count(),
            cpu,
            presented: Quantiles::of(self.shown.iter().filter_map(SampleLatency::presented)),
            stage_medians: Stages {
                parse: stage(0),
                wait: stage(1),
                hand: stage(2),
                batch: stage(3),
                display: stage(4),
                render: stage(5),
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ms(x: u64) -> Duration {
        Duration::from_millis(x)
    }

    /// Injected delays (instants built from a base, nothing slept) come out as the stages, the
    /// CPU side and the presentation, exactly.
    #[test]
    fn injected_delays_come_out_stage_by_stage() {
        let t0 = Instant::now();
        let mut meter = LatencyMeter::default();
        let first = Arrival {
            read: t0,
            sent: t0 + ms(1),
        };
        let second = Arrival {
            read: t0 + ms(2),
            sent: t0 + ms(2),
        };
        meter.took(
            t0 + ms(4),
            &[(first, t0 + ms(5), true), (second, t0 + ms(7), false)],
            t0 + ms(7),
        );
        assert_eq!(meter.pending(), 2);
        meter.display_refreshed(t0 + ms(10));
        meter.submitted(t0 + ms(13));
        meter.presented(t0 + ms(30));
        let shown: Vec<_> = meter.shown().copied().collect();
        assert_eq!(shown.len(), 2);
        assert_eq!(
            shown[0].stages,
            Stages {
                parse: ms(1),
                wait: ms(3),
                hand: ms(1),
                batch: ms(2),
                display: ms(3),
                render: ms(3),
            }
        );
        assert_eq!(shown[0].cpu(), ms(13));
        assert_eq!(shown[1].cpu(), ms(11));
        assert_eq!(shown[1].stages.hand, ms(3));
        assert_eq!(shown[1].stages.batch, Duration::ZERO);
        assert_eq!(shown[0].presented(), Some(ms(30)));
        assert_eq!(shown[1].presented(), Some(ms(28)));
        let s = meter.summary().expect("a figure");
        assert_eq!((s.samples, s.changed), (2, 1));
        assert_eq!(s.cpu.median, ms(11));
        // The later port read is the frame's newest sample, the only one the newest figure has.
        assert_eq!((shown[0].newest, shown[1].newest), (false, true));
        assert_eq!((s.newest.median, s.newest.p95), (ms(11), ms(11)));
        assert_eq!(s.newest_presented.map(|p| p.median), Some(ms(28)));
        assert_eq!(s.cpu.p95, ms(13));
    }

    /// A sample taken after the display was refreshed waits for the next frame's submission;
    /// a frame never presented leaves its samples without a presented figure.
    #[test]
    fn samples_go_to_the_frame_that_shows_them() {
        let t0 = Instant::now();
        let mut meter = LatencyMeter::default();
        let a = Arrival::read_at(t0);
        meter.took(t0, &[(a, t0, false)], t0);
        meter.display_refreshed(t0 + ms(1));
        meter.took(t0 + ms(2), &[(a, t0 + ms(2), false)], t0 + ms(2));
        meter.submitted(t0 + ms(3));
        assert_eq!((meter.shown().count(), meter.pending()), (1, 1));
        meter.display_refreshed(t0 + ms(20));
        meter.submitted(t0 + ms(21));
        meter.presented(t0 + ms(25));
        let shown: Vec<_> = meter.shown().copied().collect();
        assert_eq!(shown[0].present, None);
        assert_eq!(shown[1].present, Some(ms(4)));
        let s = meter.summary().expect("a figure");
        assert_eq!(s.presented.map(|p| p.median), Some(shown[1].cpu() + ms(4)));
        // One sample per frame: each is its frame's newest, the newest figure is the same.
        assert_eq!((shown[0].newest, shown[1].newest), (true, true));
        assert_eq!(s.newest, s.cpu);
        assert_eq!(s.newest_presented, s.presented);
    }

    /// A frame that takes a backlog: only its latest port read is its newest sample, whatever
    /// order the samples were taken in, and the newest figure is over those alone.
    #[test]
    fn each_frame_has_one_newest_sample() {
        let t0 = Instant::now();
        let mut meter = LatencyMeter::with_window(usize::MAX);
        let at = |k: u64| Arrival {
            read: t0 + ms(k),
            sent: t0 + ms(k),
        };
        for frame in 0..3u64 {
            let base = 100 * frame;
            // A backlog of 40 ms taken at the frame's start, then one latched sample.
            meter.took(
                t0 + ms(base + 40),
                &[
                    (at(base + 30), t0 + ms(base + 40), true),
                    (at(base), t0 + ms(base + 41), true),
                ],
                t0 + ms(base + 42),
            );
            meter.took(
                t0 + ms(base + 50),
                &[(at(base + 50), t0 + ms(base + 50), true)],
                t0 + ms(base + 50),
            );
            meter.display_refreshed(t0 + ms(base + 51));
            meter.submitted(t0 + ms(base + 52));
        }
        let shown: Vec<_> = meter.shown().copied().collect();
        assert_eq!(shown.len(), 9);
        let newest: Vec<_> = shown.iter().filter(|s| s.newest).collect();
        assert_eq!(newest.len(), 3);
        assert!(newest.iter().all(|s| s.cpu() == ms(2)));
        let s = meter.summary().expect("a figure");
        assert_eq!((s.newest.median, s.newest.p95), (ms(2), ms(2)));
        assert_eq!(s.cpu.p95, ms(52));
        assert_eq!(s.newest_presented, None);
    }

    /// The figure follows the latest window: a run of slow frames raises the median and the
    /// 95th percentile by what was injected, and falls out again.
    #[test]
    fn the_figure_reflects_an_injected_delay_and_forgets_it() {
        let t0 = Instant::now();
        let mut meter = LatencyMeter::with_window(100);
        let frame = |meter: &mut LatencyMeter, k: u64, extra: u64| {
            let start = t0 + ms(100 * k);
            let arrival = Arrival {
                read: start,
                sent: start,
            };
            meter.took(start, &[(arrival, start, true)], start);
            meter.display_refreshed(start + ms(1));
            meter.submitted(start + ms(2 + extra));
            meter.presented(start + ms(10 + extra));
        };
        for k in 0..100 {
            frame(&mut meter, k, 0);
        }
        let calm = meter.summary().expect("a figure");
        assert_eq!((calm.cpu.median, calm.cpu.p95), (ms(2), ms(2)));
        for k in 100..110 {
            frame(&mut meter, k, 40);
        }
        let slow = meter.summary().expect("a figure");
        assert_eq!((slow.cpu.median, slow.cpu.p95), (ms(2), ms(42)));
        assert_eq!(slow.presented.map(|p| p.p95), Some(ms(50)));
        assert_eq!(slow.stage_medians.render, ms(1));
        for k in 110..210 {
            frame(&mut meter, k, 0);
        }
        let again = meter.summary().expect("a figure");
        assert_eq!(again.cpu.p95, ms(2));
        assert_eq!(meter.total(), 210);
    }
}
