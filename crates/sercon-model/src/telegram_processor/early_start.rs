//! Telegrams taken at their start before their end has come (HDLC; 410B §4.2.1 TCHK, ACHK;
//! 816 §2.10.1.2; spec-notes "A telegram's start is taken before its end has come").
//!
//! The receiver reports a frame whole, once its closing flag or an abort has come
//! (`serial_port::receiver`). A telegram whose bits a fault touched, or one taken up at a
//! cut, may still be open at the end of the bits received, its end decided by the line still
//! to come. The real chip has it in progress from its opening flag on and takes its start
//! once its address is in: it judges it against the receive window then and reads the next
//! header (816 §2.10.1.2). Decided only when the frame was reported, the start depended on
//! whether the chip had been brought past the window's close before that line reached it.
//!
//! So such a frame is queued at once with what is known of it (its start, its bytes so far),
//! ending in error where a steady line after the bits received would abort it; the telegram
//! processor takes its start at its own tick as any other. Its report, when it comes, gives
//! its end ([`take_report`]); more bits that leave it open move its end on; a frame the
//! receiver stops decoding without a report (the line went on with filler, dark or bits after
//! a gap) ends in error where that line began ([`follow`]).

use sercos_wire::time::Instant;

use super::TelegramProcessor;
use crate::chip::Chip;
use crate::mclk::MclkClock;
use crate::serial_port::{HeardFrame, Shared};

/// A frame taken at its start before its end had come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct EarlyFrame {
    /// Its start: the receiver was still decoding it at the end of the bits received.
    pub(crate) start: Instant,
    /// The end the chip gave it, queued or in progress: where a steady line after the bits
    /// received would abort it. `None` for a start taken or queued before (a frame reported
    /// and taken back at a cut), whose end comes with its report.
    pub(crate) end: Option<Instant>,
}

/// ADR of the MST (410B §4.2): an MST's role is decided from its length (ADR 255 and one
/// byte, ERRATA "Telegrams"), which only its end tells, so it is never taken early.
const MST_ADR: u8 = 255;

/// The receiver reported `f`, a frame the processor took early (`tp.early`): it gives that
/// frame its end. Queued still, the report takes its place; in progress, the frame ends as
/// the report ends; decided already (not for this chip), the report is dropped. Returns
/// whether the processor's next tick may have moved (its memos are then stale).
#[cold]
#[inline(never)]
// The frame comes in its parts: a frame handed by value to a call out of line is kept in
// memory by its caller on every path, the usual one too, where its move into the queue then
// waits on the stores that built it (store forwarding; docs/performance.md, session 32).
pub(crate) fn take_report(
    tp: &mut TelegramProcessor,
    clock: &MclkClock,
    tick: u64,
    (start, end): (Instant, Instant),
    bytes: Shared<[u8]>,
    fcs_ok: bool,
) -> bool {
    let f = HeardFrame {
        start,
        end,
        bytes,
        fcs_ok,
    };
    let early_end = tp.early.take().and_then(|e| e.end);
    if let Some(slot) = queued_early(tp, f.start, early_end).and_then(|i| tp.rx_queue.get_mut(i)) {
        *slot = (tick, f);
        return false;
    }
    if let Some(now) = in_progress(tp, f.start) {
        let end_tick = clock.tick_at_or_after(f.end).max(tick);
        now.end_as(f, end_tick);
        return true;
    }
    if tp.rx_queue.iter().any(|(_, q)| q.start == f.start) {
        // An earlier report of that start queued (taken back at a cut, `take_back_frame`):
        // it decides at its start, this one gives its end.
        tp.replacing.retain(|r| r.start != f.start);
        tp.replacing.push(f);
    }
    false
}

/// After a line input that started at `at`: the frame the receiver has in progress at the
/// end of the bits received is queued early, ending in error where the line after those bits
/// ends it unless more bits come first (`Receiver::frame_in_progress`); one taken early
/// before that the receiver still decodes gets that end anew; one it no longer has (and did
/// not report) is dropped if not taken, or ends in error at `at`. Returns whether the
/// processor's queue or frame in progress changed.
#[cold]
#[inline(never)]
pub(crate) fn follow(chip: &mut Chip, at: Instant) -> bool {
    let pending = chip
        .serial
        .frame_in_progress()
        .filter(|(_, bytes, _)| bytes.first().is_some_and(|adr| *adr != MST_ADR))
        .map(|(start, bytes, end)| (start, Shared::<[u8]>::from(bytes), end));
    let mut changed = false;
    match (chip.tp.early, pending) {
        (None, None) => {}
        (Some(e), Some((start, _, end))) if e.start == start => {
            // Still being decoded: it ends no earlier than the bits now received allow.
            changed = set_end(chip, start, end);
        }
        (early, pending) => {
            if let Some(e) = early {
                chip.tp.early = None;
                drop_early(chip, e, at);
                changed = true;
            }
            if let Some((start, bytes, end)) = pending {
                let mut taken = EarlyFrame { start, end: None };
                // A start taken or queued already (a frame reported before and taken back at
                // a cut): its end comes with its report, or in error when the receiver drops
                // it.
                if chip.tp.last_taken.is_none_or(|t| t < start)
                    && !chip.tp.rx_queue.iter().any(|(_, f)| f.start == start)
                {
                    let tick = chip.clock.tick_at_or_after(start);
                    let frame = HeardFrame {
                        start,
                        end,
                        bytes,
                        fcs_ok: false,
                    };
                    chip.tp.on_rx_frame(tick, frame);
                    taken.end = Some(end);
                }
                chip.tp.early = Some(taken);
                changed = true;
            }
        }
    }
    if changed {
        chip.rx_queue_changed();
    }
    changed
}

/// The frame taken early at `start`, still being decoded, ends at `end` now (more bits came,
/// or a filler after them ends it): the one queued early (found by the end it was given), or
/// the frame in progress of that start. Returns whether anything changed.
fn set_end(chip: &mut Chip, start: Instant, end: Instant) -> bool {
    let Some(early) = chip.tp.early.as_mut() else {
        return false;
    };
    let old = early.end.replace(end);
    if old == Some(end) {
        return false;
    }
    if let Some((_, f)) =
        queued_early(&chip.tp, start, old).and_then(|i| chip.tp.rx_queue.get_mut(i))
    {
        f.end = end;
        return true;
    }
    let end_tick = chip.clock.tick_at_or_after(end);
    if let Some(now) = in_progress(&mut chip.tp, start) {
        now.end_tick = end_tick;
        return true;
    }
    false
}

/// The frame queued early (`early`) that the receiver stopped decoding without a report
/// ends in error at `at`, where the line that ended it began (no later than the end it had),
/// whether the chip has taken its start or not: a chip that had not reached it takes it as
/// one that had (its start was known when it was queued). A line cut before its start never
/// had it.
fn drop_early(chip: &mut Chip, early: EarlyFrame, at: Instant) {
    let EarlyFrame { start, end } = early;
    if let Some(i) = queued_early(&chip.tp, start, end) {
        let q = &mut chip.tp.rx_queue;
        // Cut before it began (a cut is handed over before the chip reaches it): the line
        // never had it.
        if at <= start {
            q.remove(i);
        } else if let Some((_, f)) = q.get_mut(i) {
            f.end = f.end.min(at);
        }
        return;
    }
    let end_tick = chip.clock.tick_at_or_after(at);
    if let Some(now) = in_progress(&mut chip.tp, start) {
        now.end_tick = end_tick.min(now.end_tick);
        now.fcs_ok = false;
    }
}

/// Where in the queue the frame taken early at `start` waits: the one given the end `end`
/// (`None`: none was queued early).
fn queued_early(tp: &TelegramProcessor, start: Instant, end: Option<Instant>) -> Option<usize> {
    let end = end?;
    tp.rx_queue
        .iter()
        .position(|(_, f)| f.start == start && f.end == end)
}

/// The frame in progress, when it is the one that started at `start`.
fn in_progress(tp: &mut TelegramProcessor, start: Instant) -> Option<&mut super::RxNow> {
    if tp.last_taken == Some(start) {
        tp.rx_now.as_mut()
    } else {
        None
    }
}
