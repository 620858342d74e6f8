//! The receive log behind [`crate::Chip::take_rx_frames`]: the newest
//! [`RX_LOG_FRAMES`] frames. A logged frame keeps its bytes shared with
//! the frame the receiver heard (for a telegram with a hint, the sender's own bytes), so
//! logging copies nothing; a frame's own `Vec` is made only when the log is taken.

use std::collections::VecDeque;

use sercos_wire::time::Instant;

use super::{HeardFrame, RX_LOG_FRAMES, RxFrame};

/// The receive log.
#[derive(Debug, Clone)]
pub(crate) struct RxLog {
    records: VecDeque<HeardFrame>,
    /// Frames are logged (`Chip::set_rx_log`).
    on: bool,
}

impl Default for RxLog {
    fn default() -> Self {
        RxLog {
            records: VecDeque::new(),
            on: true,
        }
    }
}

impl RxLog {
    /// Turns logging on or off; off forgets what was logged.
    pub(crate) fn set_on(&mut self, on: bool) {
        self.on = on;
        if !on {
            self.records.clear();
        }
    }

    /// Logs `frame`. Once an eighth more than [`RX_LOG_FRAMES`] are held, the oldest eighth
    /// is dropped in one go: dropping the oldest frame at every push read a record written
    /// thousands of frames ago, a cache miss per frame (`docs/performance.md`, "Controller
    /// pair", pair3), while one sweep over the records in order is cheap. [`RxLog::take`]
    /// gives the newest [`RX_LOG_FRAMES`] either way.
    ///
    /// Only the check whether the log is on is built into the caller (a simulation keeps it
    /// off, and every frame any receiver takes passes here).
    #[inline(always)]
    pub(crate) fn push(&mut self, frame: &HeardFrame) {
        if self.on {
            // The copy is made here, not in the call: a reference handed to a call out of
            // line would keep the caller's frame in memory, built field by field and then
            // copied whole into the processor's queue, a copy that waits on the stores
            // just made (store forwarding; docs/performance.md, session 32).
            self.push_on(frame.clone());
        }
    }

    /// [`RxLog::push`] while the log is on.
    #[inline(never)]
    fn push_on(&mut self, frame: HeardFrame) {
        if self.records.len() >= RX_LOG_FRAMES + RX_LOG_FRAMES / 8 {
            self.keep_newest(RX_LOG_FRAMES);
        }
        self.records.push_back(frame);
    }

    /// Forgets the frame starting at `start` that the receiver took back
    /// (`SerialPort::line_input`), if the log still holds it. With `replaced` the frame that
    /// replaces it (the same start) was logged after it: the earlier of the two goes.
    pub(crate) fn retract(&mut self, start: Instant, replaced: bool) {
        let mut same = self
            .records
            .iter()
            .enumerate()
            .rev()
            .filter(|(_, r)| r.start == start)
            .map(|(i, _)| i);
        if replaced {
            same.next();
        }
        if let Some(i) = same.next() {
            self.records.remove(i);
        }
    }

    /// Drops the oldest frames until at most `n` are left.
    fn keep_newest(&mut self, n: usize) {
        let excess = self.records.len().saturating_sub(n);
        self.records.drain(..excess);
    }

    /// Moves the logged frames (the newest [`RX_LOG_FRAMES`]), oldest first, to the end of
    /// `out`.
    pub(crate) fn take(&mut self, out: &mut Vec<RxFrame>) {
        self.keep_newest(RX_LOG_FRAMES);
        out.reserve(self.records.len());
        out.extend(self.records.drain(..).map(|r| RxFrame {
            start: r.start,
            end: r.end,
            bytes: r.bytes.to_vec(),
            fcs_ok: r.fcs_ok,
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::super::Shared;
    use super::*;
    use sercos_wire::time::Instant;

    fn heard(f: &RxFrame) -> HeardFrame {
        HeardFrame {
            start: f.start,
            end: f.end,
            bytes: Shared::from(f.bytes.as_slice()),
            fcs_ok: f.fcs_ok,
        }
    }

    fn frame(n: u8) -> RxFrame {
        RxFrame {
            start: Instant::from_picos(u64::from(n)),
            end: Instant::from_picos(u64::from(n) + 10),
            bytes: (0..n % 7).map(|i| i.wrapping_mul(n)).collect(),
            fcs_ok: n % 3 != 0,
        }
    }

    #[test]
    fn frames_come_back_as_logged_and_only_the_newest_are_kept() {
        let mut log = RxLog::default();
        let frames: Vec<RxFrame> = (0..20).map(frame).collect();
        for f in &frames {
            log.push(&heard(f));
        }
        let mut out = Vec::new();
        log.take(&mut out);
        assert_eq!(out, frames);
        log.take(&mut out);
        assert_eq!(out.len(), frames.len(), "taken once");

        // Just past the limit, past a compaction (an eighth over) and past several.
        for many in [
            RX_LOG_FRAMES + 5,
            RX_LOG_FRAMES + RX_LOG_FRAMES / 8 + 7,
            3 * RX_LOG_FRAMES + 1,
        ] {
            let mut log = RxLog::default();
            for i in 0..many {
                log.push(&heard(&frame((i % 251) as u8)));
            }
            let mut out = Vec::new();
            log.take(&mut out);
            assert_eq!(out.len(), RX_LOG_FRAMES);
            let want: Vec<RxFrame> = (many - RX_LOG_FRAMES..many)
                .map(|i| frame((i % 251) as u8))
                .collect();
            assert_eq!(out, want, "{many}");
        }
    }

    // Spec-notes "RS-485 bus": a frame the receiver took back leaves the log; the frame
    // that replaced it (logged after it, with the same start) stays.
    #[test]
    fn a_frame_taken_back_leaves_the_log_and_its_replacement_stays() {
        let (a, b, c) = (frame(4), frame(5), frame(8));
        let broken = RxFrame {
            fcs_ok: false,
            end: Instant::from_picos(99),
            ..b.clone()
        };
        for replaced in [false, true] {
            let mut log = RxLog::default();
            for f in [&a, &b, &c] {
                log.push(&heard(f));
            }
            if replaced {
                log.push(&heard(&broken));
            }
            log.retract(b.start, replaced);
            let mut out = Vec::new();
            log.take(&mut out);
            let want = if replaced {
                vec![a.clone(), c.clone(), broken.clone()]
            } else {
                vec![a.clone(), c.clone()]
            };
            assert_eq!(out, want, "replaced {replaced}");
        }
        // Taken from the log already: only the replacement is there, and it stays.
        let mut log = RxLog::default();
        log.push(&heard(&broken));
        log.retract(b.start, true);
        let mut out = Vec::new();
        log.take(&mut out);
        assert_eq!(out, vec![broken]);
    }

    #[test]
    fn a_log_turned_off_keeps_nothing() {
        let mut log = RxLog::default();
        log.push(&heard(&frame(1)));
        log.set_on(false);
        log.push(&heard(&frame(2)));
        let mut out = Vec::new();
        log.take(&mut out);
        assert!(out.is_empty(), "{out:?}");
        log.set_on(true);
        log.push(&heard(&frame(3)));
        log.take(&mut out);
        assert_eq!(out, vec![frame(3)]);
    }
}
