//! The status file, a test aid: with `NENDO_STATUS_FILE=PATH` the window rewrites PATH
//! (atomically, at most four times a second) with one JSON object — the session, each
//! device's status, whether the hand is drawn and how many contacts it has made, whether the
//! clutch holds it and how far the contact in progress moved the clay, and the device
//! samples' latency figure (`latency`: CPU side and presented, median and p95, in ms, over every
//! sample and — `newest_…` — over each frame's newest sample; `null`
//! before the first sample shown).

use std::time::{Duration, Instant};

use super::*;

impl LiveInput {
    /// Rewrites the status file ([`STATUS_FILE_ENV`]): at most four times a second, or now
    /// with `force`.
    pub(super) fn write_status(&mut self, force: bool) {
        let Some(path) = self.status_file.clone() else {
            return;
        };
        let due = self
            .status_written
            .is_none_or(|t| t.elapsed() >= Duration::from_millis(250));
        if !(force || due) {
            return;
        }
        self.status_written = Some(Instant::now());
        let session = match &self.session {
            None => "none",
            Some(s) if s.replay.is_some() => "replay",
            Some(_) => "devices",
        };
        let devices: Vec<serde_json::Value> = self
            .device_status()
            .map(|(d, _, _)| d)
            .unwrap_or_default()
            .iter()
            .map(|d| {
                serde_json::json!({
                    "role": d.role.name(),
                    "state": state_name(d.state),
                    "rate_hz": (d.rate_hz * 10.0).round() / 10.0,
                    "samples": d.samples,
                    "last_error": d.last_error,
                    "faults": d.faults,
                    "rejected": d.rejected,
                    "watchdog_trips": d.watchdog_trips,
                    "disconnects": d.disconnects,
                })
            })
            .collect();
        let hand_drawn = self
            .driver
            .as_ref()
            .is_some_and(|d| d.hand_loop().pose().is_some());
        let ms = |d: std::time::Duration| (d.as_secs_f64() * 1e5).round() / 100.0;
        let latency = self.latency.summary().map(|l| {
            serde_json::json!({
                "samples": l.samples,
                "cpu_median_ms": ms(l.cpu.median),
                "cpu_p95_ms": ms(l.cpu.p95),
                "presented_median_ms": l.presented.map(|p| ms(p.median)),
                "presented_p95_ms": l.presented.map(|p| ms(p.p95)),
                "newest_cpu_median_ms": ms(l.newest.median),
                "newest_cpu_p95_ms": ms(l.newest.p95),
                "newest_presented_median_ms": l.newest_presented.map(|p| ms(p.median)),
                "newest_presented_p95_ms": l.newest_presented.map(|p| ms(p.p95)),
            })
        });
        let line = serde_json::json!({
            "session": session,
            "devices": devices,
            "hand_drawn": hand_drawn,
            "contacts": self.contacts,
            "clutched": self.clutched(),
            "clay_moved": self.feedback().and_then(|f| f.moved()).map(|m| m.0),
            "latency": latency,
        });
        let text = format!("{line}\n");
        if let Err(e) = nendo_file::write_bytes(&path, text.as_bytes()) {
            self.message = Some(format!("{STATUS_FILE_ENV}: {}", e.reason()));
            self.status_file = None;
        }
    }
}
