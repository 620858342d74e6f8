//! The receive log behind [`crate::Chip::take_rx_frames`]: the newest
//! [`RX_LOG_FRAMES`](super::RX_LOG_FRAMES) frames, their bytes kept in one ring of bytes so
//! that logging a frame allocates nothing; a frame's own `Vec` is made only when the log is
//! taken.

use std::collections::VecDeque;

use sercos_wire::time::Instant;

use super::{RX_LOG_FRAMES, RxFrame};

/// One logged frame; its bytes are the next `len` bytes of the ring.
#[derive(Debug, Clone, Copy)]
struct Record {
    start: Instant,
    end: Instant,
    len: usize,
    fcs_ok: bool,
}

/// The receive log.
#[derive(Debug, Clone, Default)]
pub(crate) struct RxLog {
    records: VecDeque<Record>,
    bytes: VecDeque<u8>,
}

impl RxLog {
    /// Logs `frame`, dropping the oldest when the log is full.
    pub(crate) fn push(&mut self, frame: &RxFrame) {
        if self.records.len() >= RX_LOG_FRAMES
            && let Some(old) = self.records.pop_front()
        {
            let n = old.len.min(self.bytes.len());
            self.bytes.drain(..n);
        }
        self.bytes.extend(frame.bytes.iter().copied());
        self.records.push_back(Record {
            start: frame.start,
            end: frame.end,
            len: frame.bytes.len(),
            fcs_ok: frame.fcs_ok,
        });
    }

    /// Moves the logged frames, oldest first, to the end of `out`.
    pub(crate) fn take(&mut self, out: &mut Vec<RxFrame>) {
        out.reserve(self.records.len());
        for r in self.records.drain(..) {
            let n = r.len.min(self.bytes.len());
            out.push(RxFrame {
                start: r.start,
                end: r.end,
                bytes: self.bytes.drain(..n).collect(),
                fcs_ok: r.fcs_ok,
            });
        }
        self.bytes.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            log.push(f);
        }
        let mut out = Vec::new();
        log.take(&mut out);
        assert_eq!(out, frames);
        log.take(&mut out);
        assert_eq!(out.len(), frames.len(), "taken once");

        let mut log = RxLog::default();
        let many = RX_LOG_FRAMES + 5;
        for i in 0..many {
            log.push(&frame((i % 251) as u8));
        }
        let mut out = Vec::new();
        log.take(&mut out);
        assert_eq!(out.len(), RX_LOG_FRAMES);
        let want: Vec<RxFrame> = (5..many).map(|i| frame((i % 251) as u8)).collect();
        assert_eq!(out, want);
    }
}
