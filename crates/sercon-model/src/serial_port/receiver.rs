//! The receiver: decodes the line input into telegrams, drives REACTN and watches the signal
//! for FIBBR (no edges) and RDIST (distortion) (410B §2 RxD, REACTN, L_ERRN; §4.1 1H.7 POLRXD,
//! 1H.12 RXDNRZ, 2H.12 RDIST, 2H.13 FIBBR).

use sercos_wire::line::{Coding, Decoded, Decoder, LineConfig, LineError, Polarity};
use std::cell::Cell;

use sercos_wire::time::{Duration, Instant};

use super::line_events::{Change, LineEvents};
use super::port_config::PortConfig;
use super::segment::Shared;
use super::segment::{FrameHint, LineSegment, LineSignal, drop_in_line};
use super::{FIBBR_BIT_TIMES, HeardFrame};
use crate::reciprocal::Reciprocal;
use crate::serial_settings::RxdCoding;

/// Line bits of a flag (the opening flag is complete 8 bits after its first bit).
const FLAG_BITS: u64 = 8;

/// Bit times after the last bit received by which a steady line ends a frame in progress:
/// the seventh 1 aborts it (HDLC; ERRATA "Telegrams"), found with the eighth bit time.
const ABORT_BIT_TIMES: u64 = 8;

/// A decoder that continues over contiguous bit segments.
#[derive(Debug, Clone)]
struct Running {
    decoder: Decoder,
    /// Instant of bit position 0.
    base: Instant,
    bit_time: Duration,
    /// Where the next contiguous segment would start.
    next_start: Instant,
    /// Set when this decoder took up a telegram cut inside by the next segment
    /// ([`Receiver::resume_cut`]): frames starting before this instant had their REACTN
    /// fall scheduled already.
    resumed_at: Option<Instant>,
    /// The start of the last segment decoded, and the decoder as it was there (for
    /// [`Receiver::resume_cut`] of that segment).
    seg_start: Instant,
    before: Option<Decoder>,
}

/// The receiver's state.
#[derive(Debug, Clone, Default)]
pub(crate) struct Receiver {
    /// The last segment received (the line's signal from its start on).
    last: Option<LineSegment>,
    /// `last` was kept as it came, from the level other than the line's: the line's levels
    /// are its levels negated (NRZI decodes it the same, 410B §4.1 1H.12 RXDNRZ = 0). Only
    /// [`Receiver::filler_to_filler`] sets it (no branch on the level on its path); every
    /// other change of `last` takes it to the line's level first ([`Receiver::settle_last`]).
    last_inverted: bool,
    /// The level `last` gives at an instant, as last asked for (`Receiver::level_at`): a
    /// simulation asks for the level at the start of the segment it is about to hand over,
    /// and taking that segment needs it again. Cleared whenever `last` changes.
    level_memo: Cell<Option<(Instant, bool)>>,
    /// Boxed: an implied filler sets it aside and back (a pointer, not the decoder).
    running: Option<Box<Running>>,
    /// FIBBR rises here unless an edge comes first.
    pub(crate) fibbr_deadline: Option<Instant>,
    /// FIBBR as it will be after every scheduled change.
    fibbr_future: bool,
    /// The last segment is filler: edges continue until the next segment.
    open_filler: bool,
    /// An explicit filler segment as the receiver was before it (`Receiver::input_one`):
    /// a segment starting at the filler's own start replaces it before any bit of it came
    /// (410B §4.1 2H.13 counts edges on the line; a filler of no bit time has none).
    filler_before: Option<FillerBefore>,
    /// FIBBR timeout of the last configuration.
    timeout: Duration,
    /// The implied filler of the last segment ([`LineSegment::then_filler`]), taken at
    /// once, and how to take it back if the next segment starts no later than the filler
    /// (then there was none).
    implied: Option<ImpliedFiller>,
    /// `implied` and `timeout` are not written yet: they are the ones the filler of
    /// `ready` gives ([`Receiver::filler_to_filler`] leaves them to
    /// [`Receiver::write_implied`], before anything reads them: the general path, a FIBBR
    /// deadline, the comparisons of debug builds). `implied` holds an older record of a
    /// filler without a decoder meanwhile (what `decoding` and `frame_in_progress` read of
    /// it is the same).
    implied_unwritten: bool,
    /// The receiver's own part of [`Receiver::is_filler_to_filler`], kept as the state
    /// changes ([`Receiver::compute_ready`]): where the implied filler running starts, the
    /// bit time of the segment it follows and the level its bits leave the line at, when the
    /// receiver is in that state.
    ready: Option<Ready>,
    /// The starts of frames reported earlier that the last input took back
    /// ([`Receiver::resume_cut`]; [`Receiver::take_retracted`]), each with whether a frame
    /// of that start that replaces it has been reported since.
    retracted: Vec<(Instant, bool)>,
}

/// The implied filler of the last telegram runs ([`Receiver::compute_ready`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Ready {
    /// Where the filler starts (the end of the bits).
    at: Instant,
    /// The bit time of the telegram, and of its filler, in picoseconds (≥ 1), as its
    /// reciprocal: the filler's level at the next telegram's start is a division by it, one
    /// per telegram received, and a 64-bit `div` takes a dozen clocks (docs/performance.md,
    /// session 32).
    bit_time: Reciprocal,
    /// The level the telegram's last bit leaves the line at
    /// ([`LineSegment::level_after_bits`]).
    level: bool,
}

impl Ready {
    /// The line's level at `t` after the filler's start: the level at its start, toggled by
    /// every bit time of the filler begun (the filler's edges, [`LineSegment::level_at`];
    /// sercos-facts: filler between telegrams, 410B §4.1 2H.13 "Filler signal").
    #[inline(always)]
    fn level_at(&self, t: Instant) -> bool {
        let elapsed = t.saturating_duration_since(self.at).as_picos();
        let begun = self.bit_time.div_ceil(elapsed);
        self.level ^ (begun & 1 == 1)
    }
}

/// The reciprocal of bit time `bt` (a division: out of the filler-to-filler path's line,
/// which takes the one kept).
#[cold]
fn reciprocal_of(bt: Duration) -> Reciprocal {
    Reciprocal::new(bt.as_picos())
}

/// The receiver as it was before it took an explicit filler segment starting at `at`
/// whose first edge scheduled no FIBBR change (the explicit counterpart of
/// [`ImpliedFiller`], which also undoes what its filler scheduled).
#[derive(Debug, Clone, Copy)]
struct FillerBefore {
    at: Instant,
    fibbr_deadline: Option<Instant>,
    level: bool,
}

/// The receiver as it was before it took an implied filler, and what that scheduled.
#[derive(Debug, Clone)]
struct ImpliedFiller {
    /// Where the filler starts (the end of the bits).
    at: Instant,
    fibbr_deadline: Option<Instant>,
    fibbr_future: bool,
    running: Option<Box<Running>>,
    /// The RDIST change the filler scheduled at `at`, if it scheduled one (its value).
    rdist: Option<bool>,
}

impl ImpliedFiller {
    /// The FIBBR / RDIST changes the filler scheduled (`Receiver::take_implied_filler`),
    /// found again from what it kept: RDIST at its start, and what its first edge
    /// scheduled (`Receiver::edge`): FIBBR rising at a deadline passed before it, falling
    /// at it.
    fn scheduled(&self) -> [Option<(Instant, Change)>; 3] {
        let rises = self
            .fibbr_deadline
            .filter(|d| *d <= self.at && !self.fibbr_future);
        [
            self.rdist.map(|v| (self.at, Change::Rdist(v))),
            rises.map(|d| (d, Change::Fibbr(true))),
            (self.fibbr_future || rises.is_some()).then_some((self.at, Change::Fibbr(false))),
        ]
    }
}

/// Takes each frame the receiver decodes as soon as it is decoded (built in place: no list
/// in between). A closure is one; the chip's own sink is a type whose `take` is built into
/// the receiver's short path (`Receiver::filler_to_filler`) rather than called.
pub(crate) trait FrameSink {
    /// Takes one frame.
    fn take(&mut self, frame: HeardFrame);
}

impl<F: FnMut(HeardFrame)> FrameSink for F {
    #[inline(always)]
    fn take(&mut self, frame: HeardFrame) {
        self(frame);
    }
}

/// Where decoded frames go.
pub(crate) struct Sinks<'a, F: FrameSink> {
    pub(crate) events: &'a mut LineEvents,
    /// Takes every frame as soon as it is decoded (built in place: no list in between).
    pub(crate) frames: &'a mut F,
}

impl Receiver {
    /// A receiver whose line has been dark since `at`.
    pub(crate) fn new(at: Instant, timeout: Duration) -> Self {
        Receiver {
            fibbr_deadline: Some(at.saturating_add(timeout)),
            timeout,
            ..Receiver::default()
        }
    }

    /// The bit time of the last segment received.
    pub(crate) fn last_bit_time(&self) -> Option<Duration> {
        self.last.as_ref().map(|s| s.bit_time)
    }

    /// The last segment received, as far as its start, kind, end and implied filler go
    /// (its levels may be the line's negated, [`Receiver::last_inverted`]: read them through
    /// [`Receiver::level_at`] or [`Receiver::last_segment_at_level`]).
    pub(crate) fn last_segment(&self) -> Option<&LineSegment> {
        self.last.as_ref()
    }

    /// The last segment received, at the line's level ([`Receiver::settle_last`] first).
    pub(crate) fn last_segment_at_level(&mut self) -> Option<&LineSegment> {
        self.settle_last();
        self.last.as_ref()
    }

    /// Takes the last segment to the line's level when it was kept from the other
    /// ([`Receiver::last_inverted`]): the levels read are the same.
    #[inline]
    fn settle_last(&mut self) {
        if self.last_inverted {
            self.last_inverted = false;
            if let Some(last) = self.last.as_mut() {
                last.invert();
            }
        }
    }

    /// The receive line's light level at `t` as the last segment received decides it
    /// (`None` before any), remembered for taking a segment that starts at `t`.
    #[inline]
    pub(crate) fn level_at(&self, t: Instant) -> Option<bool> {
        if let Some((at, level)) = self.level_memo.get()
            && at == t
        {
            return Some(level);
        }
        // Kept from the other level (`last_inverted`): every level is the other.
        let level = self.last.as_ref()?.level_at(t) ^ self.last_inverted;
        self.level_memo.set(Some((t, level)));
        Some(level)
    }

    /// Whether `seg` is a telegram whose `level_before` is not the level
    /// [`Receiver::level_at`] gives at its start: taken to the level the line is at, it is
    /// inverted (NRZI decodes it the same, 410B §4.1 1H.12 RXDNRZ = 0). While the last
    /// telegram's implied filler runs from before `seg` the level is found from the filler's
    /// start ([`Receiver::ready`]); else it is the one [`Receiver::level_at`] finds, and
    /// remembers for taking the segment.
    #[inline(always)]
    pub(crate) fn off_line_level(&self, seg: &LineSegment) -> bool {
        if !matches!(seg.signal, LineSignal::Bits(_)) {
            return false;
        }
        // The usual case (an intact ring): the last telegram's implied filler runs, from
        // before `seg`; its level there is found from the filler's start (`Ready::level_at`,
        // the level the last segment gives, debug-checked) without the segment's bits.
        if let Some(r) = self.ready
            && r.at < seg.start
        {
            let level = r.level_at(seg.start);
            debug_assert_eq!(Some(level), self.level_at(seg.start), "the filler's level");
            return level != seg.level_before;
        }
        self.level_at(seg.start)
            .is_some_and(|level| level != seg.level_before)
    }

    /// Writes `implied` and `timeout` as [`Receiver::filler_to_filler`] left them to be
    /// written (`implied_unwritten`): the record of the running filler of `ready` (410B §4.1
    /// 2H.13: the FIBBR deadline the bits' last edge set, a bit time before the filler's
    /// start, which the filler's first edge cleared; nothing else scheduled) and the FIBBR
    /// timeout at its bit time.
    #[inline]
    fn write_implied(&mut self) {
        if !self.implied_unwritten {
            return;
        }
        self.implied_unwritten = false;
        let Some(r) = self.ready else {
            debug_assert!(false, "an unwritten implied filler without its filler");
            return;
        };
        let bit_time = Duration::from_picos(r.bit_time.divisor());
        self.timeout = bit_time.saturating_mul(FIBBR_BIT_TIMES);
        let fibbr_deadline = Some(
            r.at.saturating_sub_bits(bit_time)
                .saturating_add(self.timeout),
        );
        if let Some(u) = self.implied.as_mut() {
            // The record of a filler without a decoder (`ready`), written over in place:
            // nothing of it to drop.
            debug_assert!(u.running.is_none());
            u.at = r.at;
            u.fibbr_deadline = fibbr_deadline;
            u.fibbr_future = false;
            u.rdist = None;
        } else {
            self.implied = Some(ImpliedFiller {
                at: r.at,
                fibbr_deadline,
                fibbr_future: false,
                running: None,
                rdist: None,
            });
        }
    }

    /// The FIBBR deadline has passed without an edge: FIBBR is now set.
    pub(crate) fn deadline_fired(&mut self) {
        self.write_implied();
        self.fibbr_deadline = None;
        self.fibbr_future = true;
        // FIBBR is set: no filler runs (410B §4.1 2H.13).
        self.ready = None;
    }

    /// [`Receiver::ready`] from the state: the implied filler of the last segment runs (an
    /// undistorted telegram that carried it at a bit time above 0, no decoder running before
    /// or after it), with no FIBBR deadline nor rise pending.
    fn compute_ready(&self) -> Option<Ready> {
        let last = self.last.as_ref()?;
        // The implied filler's start and whether it runs without a decoder: an unwritten
        // record's are `ready`'s (`write_implied`).
        let (at, plain) = match (self.implied_unwritten, self.ready, self.implied.as_ref()) {
            (true, Some(r), _) => (r.at, true),
            (false, _, Some(implied)) => (implied.at, implied.running.is_none()),
            _ => return None,
        };
        (self.open_filler
            && !self.fibbr_future
            && self.running.is_none()
            && plain
            && last.then_filler
            && !last.distorted
            && last.bit_time.as_picos() > 0)
            .then(|| Ready {
                at,
                bit_time: Reciprocal::new(last.bit_time.as_picos()),
                level: last.level_at(at) ^ self.last_inverted,
            })
    }

    /// An edge of the receive signal at `t`.
    fn edge(&mut self, t: Instant, events: &mut LineEvents) {
        if let Some(d) = self.fibbr_deadline
            && d <= t
            && !self.fibbr_future
        {
            // 410B §4.1 2H.13 FIBBR: "No edges on receive data".
            events.push(d, Change::Fibbr(true));
            self.fibbr_future = true;
        }
        if self.fibbr_future {
            // 410B §4.1 2H.13: "Filler signal or data is received".
            events.push(t, Change::Fibbr(false));
            self.fibbr_future = false;
        }
        self.fibbr_deadline = Some(t.saturating_add(self.timeout));
    }

    /// Takes one segment of the line input (light levels) at or after the previous one.
    /// A segment with an implied filler is taken as the two segments it stands for
    /// ([`LineSegment::split_filler`]); when the next segment starts no later than that
    /// filler, the filler is taken back first, so the receiver ends as if it had never come.
    ///
    /// Returns whether [`Receiver::filler_to_filler`] took it: then FIBBR's deadline stays
    /// unset and no FIBBR / RDIST change was scheduled (only REACTN's pulse).
    ///
    /// `AT_LEVEL`: `seg` was taken to the line's level ([`Receiver::off_line_level`]), so the
    /// level the filler-to-filler path needs is known to be its `level_before` whenever a
    /// segment was received before (debug builds check it).
    ///
    /// `inverted`: `seg` is to be taken inverted (to the line's level,
    /// [`Receiver::off_line_level`]; only with `AT_LEVEL`). The filler-to-filler path keeps
    /// it as it came, with [`Receiver::last_inverted`] set, rather than branch on it.
    pub(crate) fn input<const AT_LEVEL: bool, F: FrameSink>(
        &mut self,
        mut seg: LineSegment,
        inverted: bool,
        cfg: &PortConfig,
        sinks: Sinks<'_, F>,
    ) -> bool {
        debug_assert!(AT_LEVEL || !inverted, "inverted only at the line's level");
        let Sinks { events, frames } = sinks;
        if self.is_filler_to_filler::<AT_LEVEL>(&seg, inverted, cfg, events) {
            #[cfg(debug_assertions)]
            let expected = {
                let mut at_level = seg.clone();
                if inverted {
                    at_level.invert();
                }
                // The general path's state, and the level the telegram taken to the line's
                // level leaves (the filler's, `Ready::level`).
                (
                    self.general_outcome(&at_level, cfg, events),
                    at_level.level_after_bits(),
                )
            };
            self.filler_to_filler(seg, inverted, events, frames);
            #[cfg(debug_assertions)]
            debug_assert_eq!(
                expected,
                (
                    (self.digest(), events.digest()),
                    self.ready.map(|r| r.level)
                ),
                "the filler-to-filler path differs from the general one"
            );
            return true;
        }
        if inverted {
            seg.invert();
        }
        self.input_general(seg, cfg, events, frames);
        false
    }

    /// [`Receiver::input`] of any segment.
    fn input_general<F: FrameSink>(
        &mut self,
        seg: LineSegment,
        cfg: &PortConfig,
        events: &mut LineEvents,
        frames: &mut F,
    ) {
        self.settle_last();
        self.write_implied();
        if let Some(undo) = self.implied.take()
            && seg.start <= undo.at
        {
            // What the filler scheduled from this segment's start on did not happen. A FIBBR
            // rise before it (the bits' last edge more than FIBBR_BIT_TIMES before) did, with
            // or without the filler (410B §4.1 2H.13): it stays, and FIBBR is set.
            let mut rose = false;
            for entry in undo.scheduled().iter().rev().flatten() {
                if entry.0 >= seg.start {
                    events.unschedule_status(*entry);
                } else if entry.1 == Change::Fibbr(true) {
                    rose = true;
                }
            }
            if rose {
                self.fibbr_deadline = None;
                self.fibbr_future = true;
            } else {
                self.fibbr_deadline = undo.fibbr_deadline;
                self.fibbr_future = undo.fibbr_future;
            }
            self.running = undo.running;
            self.open_filler = false;
            if let Some(last) = self.last.as_mut() {
                last.then_filler = false;
                self.level_memo.set(None);
            }
        }
        let implied = seg.then_filler && matches!(seg.signal, LineSignal::Bits(_));
        let end = seg.end();
        self.input_one(seg, cfg, events, frames);
        if implied && let Some(at) = end {
            self.take_implied_filler(at, cfg, events);
        }
        self.ready = self.compute_ready();
    }

    /// Whether `seg` is the usual input of an intact ring, which [`Receiver::filler_to_filler`]
    /// takes: a telegram the sender coded ([`LineSegment::hint`], NRZI from the level the
    /// line is at, at the receiver's bit rate, undistorted) with its implied filler, while
    /// the implied filler of the previous one runs (no FIBBR deadline nor rise pending, no
    /// decoder running, RDIST settled low). The general path then schedules nothing but
    /// REACTN and changes only what `filler_to_filler` sets: the FIBBR deadlines it computes
    /// on the way lie more than one bit time past each edge (410B §4.1 2H.13, FIBBR after
    /// [`FIBBR_BIT_TIMES`] without an edge) and every RDIST change it asks for is the value
    /// RDIST already has (2H.12).
    ///
    /// `AT_LEVEL`: `seg` was taken to the line's level
    /// ([`Receiver::off_line_level`]); with `ready` set a segment
    /// was received before, so `level_at` gives a level and `seg` starts from it: the
    /// level's check is left out (debug builds make it).
    fn is_filler_to_filler<const AT_LEVEL: bool>(
        &self,
        seg: &LineSegment,
        inverted: bool,
        cfg: &PortConfig,
        events: &LineEvents,
    ) -> bool {
        const { assert!(FIBBR_BIT_TIMES > 1) };
        debug_assert_eq!(self.ready, self.compute_ready());
        debug_assert!(
            !AT_LEVEL
                || self.ready.is_none()
                || !matches!(seg.signal, LineSignal::Bits(_))
                || self.level_at(seg.start) == Some(seg.level_before ^ inverted),
            "a segment taken to the line's level starts from another"
        );
        let bt = seg.bit_time;
        // The receiver's part (`compute_ready`): the previous telegram's implied filler runs,
        // from before `seg`, at `seg`'s bit rate (not 0).
        self.ready
            .is_some_and(|r| r.at < seg.start && r.bit_time.divisor() == bt.as_picos())
            && seg.then_filler
            && !seg.distorted
            && seg.hint.is_some()
            && matches!(&seg.signal, LineSignal::Bits(b) if !b.is_empty())
            && cfg.rx_coding == RxdCoding::Nrzi
            && cfg.bit_time.is_none_or(|own| own == bt)
            && (AT_LEVEL || self.level_at(seg.start) == Some(seg.level_before))
            && events.rdist_at_end_if_last(seg.start) == Some(false)
    }

    /// [`Receiver::input`] of a segment [`Receiver::is_filler_to_filler`] accepts, with only
    /// the changes the general path makes: the frame (and its REACTN pulse), the segment
    /// kept, and its implied filler taken with what taking it back needs.
    #[inline(always)]
    fn filler_to_filler<F: FrameSink>(
        &mut self,
        seg: LineSegment,
        inverted: bool,
        events: &mut LineEvents,
        frames: &mut F,
    ) {
        // A filler has edges every bit time: no deadline while one runs.
        debug_assert!(self.fibbr_deadline.is_none());
        let bt = seg.bit_time;
        let end = seg.end().unwrap_or(seg.start);
        let mut level = None;
        if let Some(hint) = &seg.hint {
            deliver_hinted(&seg, hint, end, events, frames);
            // The sender's coding (`FrameHint::coded`) knows where its bits leave the line.
            if let LineSignal::Bits(b) = &seg.signal {
                level = hint.end_level(b, seg.level_before);
            }
        }
        // A telegram (`is_filler_to_filler`): its bits' last level is there.
        let level = level.unwrap_or_else(|| seg.level_after_bits().unwrap_or(seg.level_before));
        debug_assert_eq!(
            level,
            seg.level_after_bits().unwrap_or(seg.level_before),
            "the level after the bits"
        );
        // Taken inverted (`inverted`), its bits leave the line at the other level; it is kept
        // as it came, its levels read negated (`last_inverted`).
        let level = level ^ inverted;
        // The segment kept before is dropped by its parts (its drop glue went out of line).
        if let Some(old) = self.last.replace(seg) {
            drop_in_line(old);
        }
        self.last_inverted = inverted;
        self.level_memo.set(None);
        // The state `compute_ready` finds: this telegram's implied filler runs. Its record
        // for taking it back (the previous one's written over: `ready` is one without a
        // decoder) and the FIBBR timeout at its bit time are what `ready` gives: written
        // when read (`write_implied`).
        debug_assert!(self.implied.as_ref().is_some_and(|u| u.running.is_none()));
        self.implied_unwritten = true;
        // `is_filler_to_filler`: the last telegram's filler ran at this bit time, so its
        // reciprocal is the one kept (no division here; the division only if that ever
        // failed to hold in a release build).
        debug_assert!(
            self.ready.is_some(),
            "filler to filler without a running filler"
        );
        let bit_time = match self.ready {
            Some(r) => r.bit_time,
            None => reciprocal_of(bt),
        };
        self.ready = Some(Ready {
            at: end,
            bit_time,
            level,
        });
    }

    /// The receiver's and `events`' state after the general path took `seg` (a check of
    /// [`Receiver::filler_to_filler`] in debug builds).
    #[cfg(debug_assertions)]
    fn general_outcome(
        &self,
        seg: &LineSegment,
        cfg: &PortConfig,
        events: &LineEvents,
    ) -> (String, String) {
        let mut rx = self.clone();
        let mut ev = events.clone();
        let mut frames = |_f: HeardFrame| {};
        rx.input_general(seg.clone(), cfg, &mut ev, &mut frames);
        (rx.digest(), ev.digest())
    }

    /// What the receiver's state says, for comparisons in debug builds and tests.
    #[cfg(any(test, debug_assertions))]
    fn digest(&self) -> String {
        if self.implied_unwritten {
            // What is there once written (`write_implied`).
            let mut written = self.clone();
            written.write_implied();
            return written.digest();
        }
        format!(
            "{:?} {:?} {} {} {:?} {:?}",
            self.last
                .as_ref()
                .map(|l| (l.start, l.then_filler, l.bit_time)),
            self.fibbr_deadline,
            self.fibbr_future,
            self.open_filler,
            self.timeout,
            self.implied.as_ref().map(|u| (
                u.at,
                u.fibbr_deadline,
                u.fibbr_future,
                u.running.is_some(),
                u.rdist
            )),
        ) + if self.running.is_some() {
            " running"
        } else {
            ""
        }
    }

    /// Takes the filler implied after the last segment (a bits segment ending at `at`,
    /// kept as `last` with its `then_filler`) as [`Receiver::input_one`] takes a
    /// [`LineSignal::Filler`] segment starting at `at` from the line's level, and keeps what
    /// it changed for taking it back.
    fn take_implied_filler(&mut self, at: Instant, cfg: &PortConfig, events: &mut LineEvents) {
        let Some(last) = &self.last else {
            return;
        };
        let mismatch = cfg.bit_time.is_some_and(|bt| bt != last.bit_time);
        let distorted = last.distorted || mismatch;
        let fibbr_deadline = self.fibbr_deadline;
        let fibbr_future = self.fibbr_future;
        let running = self.running.take();
        // 410B §4.1 2H.12 RDIST, as for any segment (dropped when RDIST has that value).
        let before = events.status_len();
        events.push(at, Change::Rdist(distorted));
        let rdist = (events.status_len() > before).then_some(distorted);
        // Filler: the light changes at the start of every bit time, from the line's level
        // (its first edge at `at`); no FIBBR while it lasts (410B §4.1 2H.13).
        self.edge(at, events);
        self.fibbr_deadline = None;
        self.open_filler = true;
        self.implied = Some(ImpliedFiller {
            at,
            fibbr_deadline,
            fibbr_future,
            running,
            rdist,
        });
    }

    /// Takes one segment without implied filler.
    fn input_one<F: FrameSink>(
        &mut self,
        seg: LineSegment,
        cfg: &PortConfig,
        events: &mut LineEvents,
        frames: &mut F,
    ) {
        let own_bt = cfg.bit_time.unwrap_or(seg.bit_time);
        self.timeout = own_bt.saturating_mul(FIBBR_BIT_TIMES);
        let mut prev_level = self.level_at(seg.start).unwrap_or(false);
        // A filler replaced at its own start never was on the line (no bit of it, no edge):
        // the receiver goes on as before it, so that a sender's filler cut at once by the
        // next segment (a repeater's copy dropped for what came after it, 410B §1) leaves
        // FIBBR's deadline where the last real edge put it (2H.13), not cleared.
        if let Some(before) = self.filler_before.take()
            && self.open_filler
            && before.at == seg.start
            && self.last.as_ref().is_some_and(|l| l.start == seg.start)
        {
            self.fibbr_deadline = before.fibbr_deadline;
            self.open_filler = false;
            prev_level = before.level;
        }
        if let Some(end) = self.last.as_ref().and_then(LineSegment::end)
            && end > seg.start
        {
            // A collision: the new segment cuts the previous one. A coded telegram cut on its
            // own bit grid is decoded on from the cut (`resume_cut`: the line shows its bits
            // up to there, then the new ones); otherwise what the receiver made of the cut
            // part is void (frames already reported stay reported).
            let resumed = self.resume_cut(&seg, cfg);
            events.cancel_receive_from(seg.start);
            self.fibbr_future = events.last_fibbr().unwrap_or(self.fibbr_future);
            if !resumed {
                self.running = None;
                events.push(seg.start, Change::Reactn(true));
            }
        }
        if self.open_filler {
            // The filler's last edge before this segment (an implied filler starts where
            // its bits end).
            if let Some(last) = &self.last {
                let from = if last.then_filler {
                    last.end().unwrap_or(last.start)
                } else {
                    last.start
                };
                let bt = last.bit_time.as_picos().max(1);
                let elapsed = seg.start.saturating_duration_since(from).as_picos();
                let begun = elapsed.div_ceil(bt);
                if begun > 0 {
                    let t =
                        from.saturating_add(Duration::from_picos((begun - 1).saturating_mul(bt)));
                    self.fibbr_deadline = Some(t.saturating_add(self.timeout));
                }
            }
            self.open_filler = false;
        }
        // A receiver whose bit clock differs from the sender's samples off the bit grid: the
        // edges count, the data does not (spec-notes "Serial port": rate mismatch is RDIST).
        let mismatch = cfg.bit_time.is_some_and(|bt| bt != seg.bit_time);
        let distorted = seg.distorted || mismatch;
        // A bits segment of no bits carries no signal (a steady hold after a telegram whose
        // implied filler did not come): nothing to measure.
        let empty = matches!(&seg.signal, LineSignal::Bits(b) if b.is_empty());
        // 410B §4.1 2H.12 RDIST: "Receive data over distortion limit" while such a signal lasts.
        if !empty {
            events.push(seg.start, Change::Rdist(distorted));
        }
        match &seg.signal {
            LineSignal::Dark | LineSignal::Light => {
                let level = matches!(seg.signal, LineSignal::Light);
                if level != prev_level {
                    self.edge(seg.start, events);
                }
                self.running = None;
            }
            LineSignal::Filler => {
                let first = if seg.level_before == prev_level {
                    seg.start
                } else {
                    seg.start.saturating_add(seg.bit_time)
                };
                // Its first edge schedules no FIBBR change (none pending, no deadline passed
                // by then): then a segment at its start can take it back whole.
                if !self.fibbr_future && self.fibbr_deadline.is_none_or(|d| d > first) {
                    self.filler_before = Some(FillerBefore {
                        at: seg.start,
                        fibbr_deadline: self.fibbr_deadline,
                        level: prev_level,
                    });
                }
                self.edge(first, events);
                // Edges every bit time: no FIBBR while the filler lasts.
                self.fibbr_deadline = None;
                self.open_filler = true;
                self.running = None;
            }
            LineSignal::Bits(_) => {
                let end = seg.end().unwrap_or(seg.start);
                if distorted && !empty {
                    events.push(end, Change::Rdist(false));
                }
                let hinted = seg.hint.as_ref().filter(|_| {
                    cfg.rx_coding == RxdCoding::Nrzi
                        && !mismatch
                        && seg.level_before == prev_level
                        && self.running.as_ref().is_none_or(|r| !r.decoder.in_frame())
                });
                if let Some(hint) = hinted {
                    // The hint's telegram: its flags start and end with a 0, an edge in NRZI,
                    // and no valid NRZI signal goes FIBBR_BIT_TIMES without one.
                    // Inside it an edge comes at least every seven bit times (flags, bit
                    // stuffing), so FIBBR cannot rise before its last edge.
                    self.edge(seg.start, events);
                    self.fibbr_deadline = Some(
                        end.saturating_sub_bits(seg.bit_time)
                            .saturating_add(self.timeout),
                    );
                    deliver_hinted(&seg, hint, end, events, frames);
                    self.running = None;
                } else {
                    self.scan_edges(&seg, prev_level, events);
                    if mismatch {
                        self.running = None;
                    } else {
                        // Handed on here, in decoding order, their REACTN changes scheduled
                        // by `decode` (410B §2 REACTN; the frame sink neither reads nor
                        // changes `events`, so the order of the two is free): with the sink
                        // passed to no call, the chip's sink (`Chip::line_input`) needs no
                        // place in memory on the hinted path, whose frame it takes in line.
                        for f in self.decode(&seg, prev_level, cfg, events) {
                            frames.take(f);
                        }
                    }
                }
            }
        }
        self.last = Some(seg);
        self.level_memo.set(None);
    }

    /// Reports the edges of an explicit bit segment.
    // Out of line: a telegram with a hint (no fault on its way) takes neither; kept out
    // of the delivery path's code (docs/performance.md, session 5).
    #[inline(never)]
    fn scan_edges(&mut self, seg: &LineSegment, prev_level: bool, events: &mut LineEvents) {
        let LineSignal::Bits(bits) = &seg.signal else {
            return;
        };
        let mut level = prev_level;
        let mut t = seg.start;
        for b in bits.bits().iter() {
            if b != level {
                self.edge(t, events);
                level = b;
            }
            t = t.saturating_add(seg.bit_time);
        }
    }

    /// Decodes an explicit bit segment, continuing the previous one if it is contiguous;
    /// returns the frames it completed, in order, for the caller to hand on, their REACTN
    /// changes scheduled.
    // Out of line: a telegram with a hint (no fault on its way) takes neither; kept out
    // of the delivery path's code (docs/performance.md, session 5).
    #[inline(never)]
    fn decode(
        &mut self,
        seg: &LineSegment,
        prev_level: bool,
        cfg: &PortConfig,
        events: &mut LineEvents,
    ) -> Vec<HeardFrame> {
        let LineSignal::Bits(bits) = &seg.signal else {
            return Vec::new();
        };
        let contiguous = self
            .running
            .as_ref()
            .is_some_and(|r| r.next_start == seg.start && r.bit_time == seg.bit_time);
        if !contiguous {
            self.running = Some(Box::new(Running {
                decoder: Decoder::new(rx_line_config(cfg.rx_coding, cfg.polrxd, prev_level)),
                base: seg.start,
                bit_time: seg.bit_time,
                next_start: seg.start,
                resumed_at: None,
                seg_start: seg.start,
                before: None,
            }));
        }
        let Some(run) = self.running.as_mut() else {
            return Vec::new();
        };
        run.before = Some(run.decoder.clone());
        run.seg_start = seg.start;
        let (base, bt) = (run.base, run.bit_time);
        let at = |pos: u64| base.saturating_add(bt.saturating_mul(pos));
        let mut found = Vec::new();
        run.decoder.push(bits.bits(), |d| {
            let frame = match d {
                Decoded::Telegram(f) => HeardFrame {
                    start: at(f.start),
                    end: at(f.end),
                    bytes: Shared::from(f.bytes),
                    fcs_ok: true,
                },
                Decoded::Error { error, received } => HeardFrame {
                    start: at(error.start()),
                    end: at(error_end(&error)),
                    bytes: Shared::from(received),
                    fcs_ok: false,
                },
            };
            found.push(frame);
        });
        run.next_start = seg.end().unwrap_or(seg.start);
        let resumed_at = run.resumed_at;
        for f in &found {
            if let Some(r) = self.retracted.iter_mut().find(|r| r.0 == f.start) {
                r.1 = true;
            }
            if resumed_at.is_some_and(|c| f.start < c) {
                // The telegram taken up at a cut (`resume_cut`): its REACTN fall was
                // scheduled when it first came (410B §2 REACTN); only its end is new.
                events.push(f.end, Change::Reactn(true));
            } else {
                schedule_reactn(f, bt, events);
            }
        }
        found
    }

    /// Whether a decoder runs over the bits received (bits a fault touched, a cut telegram
    /// taken up, a rate mismatch), or ran until the implied filler after them: only then can
    /// a frame be in progress at the end of them ([`Receiver::frame_in_progress`]). A hinted
    /// telegram is reported whole when it comes.
    #[inline]
    pub(crate) fn decoding(&self) -> bool {
        self.running.is_some() || self.implied.as_ref().is_some_and(|u| u.running.is_some())
    }

    /// The frame being decoded from the bits received so far, whose end the line still to
    /// come decides (a telegram whose closing flag a fault broke, or one taken up at a cut):
    /// the first bit of its opening flag, its whole bytes so far (ADR first) and where it
    /// ends unless more bits come first: a steady line after the bits aborts it with the
    /// seventh 1 ([`ABORT_BIT_TIMES`] after them; HDLC), an implied filler after them ends
    /// the decoding where it starts (as an explicit filler segment does).
    pub(crate) fn frame_in_progress(&self) -> Option<(Instant, &[u8], Instant)> {
        let (run, end) = match (self.running.as_deref(), &self.implied) {
            (Some(run), _) => (
                run,
                run.next_start
                    .saturating_add(run.bit_time.saturating_mul(ABORT_BIT_TIMES)),
            ),
            (
                None,
                Some(ImpliedFiller {
                    at,
                    running: Some(run),
                    ..
                }),
            ) => (&**run, *at),
            (None, _) => return None,
        };
        let (pos, bytes) = run.decoder.frame_in_progress()?;
        Some((
            run.base.saturating_add(run.bit_time.saturating_mul(pos)),
            bytes,
            end,
        ))
    }

    /// The starts of the frames the last input took back (in order), each with whether
    /// that input reported a frame of the same start that replaces it (the frame the line
    /// showed for the telegram it cut, [`Receiver::resume_cut`]; not yet reported while
    /// that telegram's frame goes on).
    pub(crate) fn take_retracted(&mut self) -> Vec<(Instant, bool)> {
        std::mem::take(&mut self.retracted)
    }

    /// Whether the last input took frames back ([`Receiver::take_retracted`]).
    #[inline]
    pub(crate) fn has_retracted(&self) -> bool {
        !self.retracted.is_empty()
    }

    /// `seg` starts inside the last segment. When that one was bits the receiver decoded
    /// from their start (a coded telegram taken whole: [`LineSegment::hint`], NRZI at the
    /// receiver's bit rate, no decoder running; or bits decoded, [`Running::before`]) and
    /// `seg` is bits of their bit time, the line showed the last segment's bits up to
    /// `seg`'s start and `seg`'s from there (the RS-485 bus of 410B Fig. 4, where another
    /// driver garbles a telegram in progress; a repeater's own telegram cutting one it
    /// repeats, 410B §1): the decoder is set up as it stood at the cut (off the bit grid:
    /// at the end of the bit the cut falls in, `seg`'s bits taken on the grid from there),
    /// so that `seg` continues what it was decoding, and the frames reported from the last
    /// segment that end after the cut are taken back ([`Receiver::take_retracted`]).
    /// Returns whether it did so.
    #[cold]
    #[inline(never)]
    fn resume_cut(&mut self, seg: &LineSegment, cfg: &PortConfig) -> bool {
        let Some(last) = self.last.as_ref() else {
            return false;
        };
        let (LineSignal::Bits(bits), LineSignal::Bits(_)) = (&last.signal, &seg.signal) else {
            return false;
        };
        let bt = last.bit_time;
        let offset = seg.start.saturating_duration_since(last.start).as_picos();
        if cfg.rx_coding != RxdCoding::Nrzi
            || cfg.bit_time.is_some_and(|own| own != bt)
            || last.distorted
            || seg.bit_time != bt
            || seg.start < last.start
            || bt.as_picos() == 0
            || seg.level_before != last.level_at(seg.start)
        {
            return false;
        }
        // Off the grid (a repeater's own telegram cutting one it repeats, 410B §1: the two
        // come from different clocks), the bit the cut falls in counts whole and the new
        // bits follow on the grid, as the DPLL, locked to the old bits, samples them (the
        // RS-485 bus lays a second driver's bits onto the line's grid likewise).
        let cut_bits = offset.div_ceil(bt.as_picos());
        let Some(prefix) = usize::try_from(cut_bits)
            .ok()
            .and_then(|k| bits.bits().slice(0, k.min(bits.bits().len())))
        else {
            return false;
        };
        // The decoder as it stood at the last segment's start, and the instant its bit
        // positions count from (a coded telegram: a fresh decoder, as the hinted path
        // reported its frame, `deliver_hinted`).
        let (before, base) = match (&last.hint, self.running.as_deref()) {
            (Some(_), None) => (
                Decoder::new(rx_line_config(
                    RxdCoding::Nrzi,
                    cfg.polrxd,
                    last.level_before,
                )),
                last.start,
            ),
            (_, Some(r))
                if r.seg_start == last.start
                    && Some(r.next_start) == last.end()
                    && r.bit_time == bt =>
            {
                match &r.before {
                    Some(d) => (d.clone(), r.base),
                    None => return false,
                }
            }
            _ => return false,
        };
        let at = |pos: u64| base.saturating_add(bt.saturating_mul(pos));
        // The cut on the grid: the end of the bit it falls in.
        let cut_at = last.start.saturating_add(bt.saturating_mul(cut_bits));
        // What the last segment reported, those frames ending after the cut taken back.
        let mut taken_back = Vec::new();
        before.clone().push(bits.bits(), |d| {
            let (start, end) = match &d {
                Decoded::Telegram(f) => (f.start, f.end),
                Decoded::Error { error, .. } => (error.start(), error_end(error)),
            };
            if at(end) > cut_at {
                taken_back.push((at(start), false));
            }
        });
        let mut decoder = before;
        // Frames ending before the cut stay as they were reported.
        decoder.push(prefix, |_| {});
        self.running = Some(Box::new(Running {
            decoder,
            base,
            bit_time: bt,
            next_start: seg.start,
            resumed_at: Some(seg.start),
            seg_start: seg.start,
            before: None,
        }));
        self.retracted = taken_back;
        true
    }
}

/// The bit after the end of a frame in error (the closing flag, or the bit that broke it).
fn error_end(error: &LineError) -> u64 {
    match *error {
        LineError::FcsMismatch { end, .. }
        | LineError::TooShort { end, .. }
        | LineError::NotWholeBytes { end, .. } => end,
        LineError::Abort { at, .. } | LineError::TooLong { at, .. } => at.saturating_add(1),
    }
}

/// Schedules REACTN for `frame` and hands it on.
// 410B §2 REACTN: "Indicates that the serial receiver is receiving a telegram": low from the
// recognised opening flag to the end of the frame (spec-notes "Serial port").
// Inlined: the frame is built by the caller and moved on to the processor's queue; as a call of
// its own it was read back just after being written (a store-forwarding stall, pair3).
#[inline(always)]
fn deliver<F: FrameSink>(
    frame: HeardFrame,
    bit_time: Duration,
    events: &mut LineEvents,
    frames: &mut F,
) {
    schedule_reactn(&frame, bit_time, events);
    frames.take(frame);
}

/// Schedules REACTN's pulse for `frame` (410B §2 REACTN, as [`deliver`]).
#[inline(always)]
fn schedule_reactn(frame: &HeardFrame, bit_time: Duration, events: &mut LineEvents) {
    let low = frame
        .start
        .saturating_add(bit_time.saturating_mul(FLAG_BITS))
        .min(frame.end);
    events.push_reactn_pulse(low, frame.end);
}

/// Hands the telegram of `seg`'s `hint`, ending at `end`, to the processor with its REACTN
/// pulse.
#[inline(always)]
fn deliver_hinted<F: FrameSink>(
    seg: &LineSegment,
    hint: &FrameHint,
    end: Instant,
    events: &mut LineEvents,
    frames: &mut F,
) {
    let start = seg
        .start
        .saturating_add(seg.bit_time.saturating_mul(hint.offset));
    // The hint's bytes are the telegram's: shared, not copied.
    let frame = HeardFrame {
        start,
        end,
        bytes: hint.telegram.clone(),
        fcs_ok: true,
    };
    deliver(frame, seg.bit_time, events, frames);
}

/// The decoder configuration for light-level input.
///
/// NRZ: the data bit is the chip's "light on", i.e. the light level when POLRXD = 0 and its
/// inverse when POLRXD = 1 (the line interface carries light as a transceiver for POLRXD = 0
/// delivers it). NRZI: only the level before the first bit matters, the line's `prev_level`.
fn rx_line_config(coding: RxdCoding, polrxd: bool, prev_level: bool) -> LineConfig {
    match coding {
        RxdCoding::Nrz => LineConfig::new(
            Coding::Nrz,
            if polrxd {
                Polarity::LightOnLow
            } else {
                Polarity::LightOnHigh
            },
        ),
        RxdCoding::Nrzi => LineConfig::new(
            Coding::Nrzi,
            if prev_level {
                Polarity::LightOnLow
            } else {
                Polarity::LightOnHigh
            },
        ),
    }
}

/// `Instant` minus one bit time.
trait SubBits {
    fn saturating_sub_bits(self, bt: Duration) -> Instant;
}

impl SubBits for Instant {
    fn saturating_sub_bits(self, bt: Duration) -> Instant {
        Instant::from_picos(self.as_picos().saturating_sub(bt.as_picos()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::serial_port::port_config::TxMode;
    use crate::serial_settings::LErrnMode;
    use proptest::prelude::*;

    const BT: Duration = Duration::from_picos(62_500);

    /// The receiver's own bit time: none (external clock), the sender's, or another (410B
    /// §4.1 2H.12: a rate mismatch is distortion).
    fn cfg(own: u8) -> PortConfig {
        PortConfig {
            bit_time: match own % 3 {
                0 => None,
                1 => Some(BT),
                _ => Some(BT.saturating_mul(2)),
            },
            tx_mode: TxMode::Repeat,
            presync: false,
            polrxd: false,
            poltxd: false,
            rx_coding: RxdCoding::Nrzi,
            lmode: LErrnMode::FibbrOrRdist,
        }
    }

    /// One input: what it carries, where it starts after the previous one's bits end (in
    /// bit times; negative: before that end), its length in bits, whether its level is the
    /// line's, and the receiver's own bit time then (`cfg`).
    type Step = (u8, i64, u8, bool, u8);

    /// The instant `gap` bit times after `end` (before it when negative), at least 1 ps.
    fn start_after(end: Instant, gap: i64) -> Instant {
        Instant::from_picos(
            end.as_picos()
                .saturating_add_signed(gap.saturating_mul(BT.as_picos() as i64))
                .max(1),
        )
    }

    fn segment(kind: u8, start: Instant, len: u8, level_before: bool) -> LineSegment {
        let mut bits = sercos_wire::line::BitVec::new();
        for i in 0..u64::from(len).max(1) {
            bits.push(i % 3 == 0);
        }
        let hint = Some(Shared::new(FrameHint {
            telegram: Shared::from(&[1u8, 2, 3][..]),
            offset: 1,
            coded: None,
        }));
        let mut seg = LineSegment::bits(start, BT, bits, level_before);
        match kind {
            // A telegram with its implied filler: the usual input of an intact ring.
            0 | 1 => {
                seg.hint = hint;
                seg.then_filler = true;
            }
            // The same, distorted on its way (410B §4.1 2H.12 RDIST).
            2 => {
                seg.hint = hint;
                seg.then_filler = true;
                seg.distorted = true;
            }
            // A telegram without filler after it.
            3 => seg.hint = hint,
            4 => seg = LineSegment::steady(start, BT, LineSignal::Dark, level_before),
            _ => seg = LineSegment::steady(start, BT, LineSignal::Filler, level_before),
        }
        seg
    }

    /// Feeds `steps` to a receiver through [`Receiver::input`] and to another through the
    /// general path only, comparing both after each; returns how often the first took the
    /// filler-to-filler path.
    fn compare(steps: &[Step]) -> Result<u32, TestCaseError> {
        let timeout = BT.saturating_mul(FIBBR_BIT_TIMES);
        let mut fast = Receiver::new(Instant::ZERO, timeout);
        let mut general = Receiver::new(Instant::ZERO, timeout);
        let (mut ev_fast, mut ev_general) = (LineEvents::default(), LineEvents::default());
        let (mut got_fast, mut got_general) = (Vec::new(), Vec::new());
        let mut end = Instant::from_picos(1_000_000);
        let mut taken = 0;
        for &(kind, gap, len, keep_level, own) in steps {
            let cfg = cfg(own);
            let start = start_after(end, gap);
            let level = fast.level_at(start).unwrap_or(false);
            let seg = segment(kind, start, len, level == keep_level);
            taken += u32::from(fast.is_filler_to_filler::<false>(&seg, false, &cfg, &ev_fast));
            end = seg.end().unwrap_or(start);
            let mut sink = |f: HeardFrame| got_fast.push((f.start, f.end, f.bytes, f.fcs_ok));
            let sinks = Sinks {
                events: &mut ev_fast,
                frames: &mut sink,
            };
            fast.input::<false, _>(seg.clone(), false, &cfg, sinks);
            let mut sink = |f: HeardFrame| got_general.push((f.start, f.end, f.bytes, f.fcs_ok));
            general.input_general(seg, &cfg, &mut ev_general, &mut sink);
            prop_assert_eq!(fast.digest(), general.digest());
            prop_assert_eq!(ev_fast.digest(), ev_general.digest());
            prop_assert_eq!(&got_fast, &got_general);
        }
        Ok(taken)
    }

    /// Feeds `steps` to a receiver as `Chip::line_input_at_level` does (a telegram not at
    /// the line's level inverted, [`Receiver::off_line_level`], then [`Receiver::input`]
    /// with the level's check left out) and to another through the general path only, each
    /// telegram inverted there by the rule written out here (as the simulation did before
    /// the chip did it: the level the last segment gives at its start, when there is one);
    /// compares both after each step, the line's level after the segment included; returns
    /// how often the first took the filler-to-filler path and how often a telegram was
    /// inverted.
    fn compare_at_level(steps: &[Step]) -> Result<(u32, u32), TestCaseError> {
        let timeout = BT.saturating_mul(FIBBR_BIT_TIMES);
        let mut leveled = Receiver::new(Instant::ZERO, timeout);
        let mut general = Receiver::new(Instant::ZERO, timeout);
        let (mut ev_leveled, mut ev_general) = (LineEvents::default(), LineEvents::default());
        let (mut got_leveled, mut got_general) = (Vec::new(), Vec::new());
        let mut end = Instant::from_picos(1_000_000);
        let (mut taken, mut inverted) = (0, 0);
        for &(kind, gap, len, keep_level, own) in steps {
            let cfg = cfg(own);
            let start = start_after(end, gap);
            let level = general.level_at(start).unwrap_or(false);
            let seg = segment(kind, start, len, level == keep_level);
            end = seg.end().unwrap_or(start);
            let mut aligned = seg.clone();
            if matches!(seg.signal, LineSignal::Bits(_))
                && general
                    .level_at(start)
                    .is_some_and(|l| l != seg.level_before)
            {
                aligned = aligned.inverted();
                inverted += 1;
            }
            let off = leveled.off_line_level(&seg);
            taken += u32::from(leveled.is_filler_to_filler::<true>(&seg, off, &cfg, &ev_leveled));
            let mut sink = |f: HeardFrame| got_leveled.push((f.start, f.end, f.bytes, f.fcs_ok));
            let sinks = Sinks {
                events: &mut ev_leveled,
                frames: &mut sink,
            };
            leveled.input::<true, _>(seg, off, &cfg, sinks);
            let mut sink = |f: HeardFrame| got_general.push((f.start, f.end, f.bytes, f.fcs_ok));
            general.input_general(aligned, &cfg, &mut ev_general, &mut sink);
            prop_assert_eq!(leveled.digest(), general.digest());
            prop_assert_eq!(ev_leveled.digest(), ev_general.digest());
            prop_assert_eq!(&got_leveled, &got_general);
            for k in 0..3 {
                let t = end.saturating_add(BT.saturating_mul(k));
                prop_assert_eq!(leveled.level_at(t), general.level_at(t), "level at {:?}", t);
            }
        }
        Ok((taken, inverted))
    }

    proptest! {
        /// The receive level found once (`Chip::line_input_at_level`): a telegram taken to
        /// the line's level by the receiver, the level's check then left out of the
        /// filler-to-filler path, leaves the receiver, its changes and its frames as the
        /// general path leaves them with the telegram inverted beforehand.
        #[test]
        fn a_telegram_taken_at_the_line_level_is_the_one_inverted_before(
            steps in prop::collection::vec(
                (0u8..6, -40i64..120, 1u8..80, any::<bool>(), prop_oneof![4 => Just(1u8), 1 => 0u8..3]),
                1..40,
            ),
        ) {
            compare_at_level(&steps)?;
        }

        /// 410B §4.1 2H.12–13, §2 REACTN: the filler-to-filler path leaves the receiver, its
        /// scheduled changes and its frames exactly as the general path does, take-backs of
        /// the implied filler included (a segment starting before its start).
        #[test]
        fn the_filler_to_filler_path_is_the_general_path(
            steps in prop::collection::vec(
                (0u8..6, -40i64..120, 1u8..80, any::<bool>(), prop_oneof![4 => Just(1u8), 1 => 0u8..3]),
                1..40,
            ),
        ) {
            compare(&steps)?;
        }
    }

    /// An intact ring's input (telegrams with their filler, some bit times apart, then one
    /// cut short by the next) takes the path and agrees with the general one.
    #[test]
    fn an_intact_ring_takes_the_filler_to_filler_path() {
        for own in [0, 1] {
            let ring: Vec<Step> = (0..12)
                .map(|i| (0, 8 + i, 40, true, own))
                .chain([(0, -3, 30, true, own), (0, 10, 30, true, own)])
                .chain([(4, 200, 1, true, own), (0, 5, 30, true, own)])
                .collect();
            let taken = compare(&ring).unwrap_or_else(|e| panic!("{e}"));
            assert!(taken >= 10, "taken {taken} times");
        }
    }

    /// The filler-to-filler path leaves the implied filler's record and the FIBBR timeout
    /// unwritten (`implied_unwritten`); written (`Receiver::write_implied`) they are what the
    /// general path wrote, and the next input the general path takes (a telegram cut short
    /// by the next, which takes the filler back, 410B §4.1 2H.13) writes them before it
    /// reads them.
    #[test]
    fn an_unwritten_implied_filler_is_the_general_paths() {
        let cfg = cfg(1);
        let timeout = BT.saturating_mul(FIBBR_BIT_TIMES);
        let mut fast = Receiver::new(Instant::ZERO, timeout);
        let mut general = Receiver::new(Instant::ZERO, timeout);
        let (mut ev_fast, mut ev_general) = (LineEvents::default(), LineEvents::default());
        let mut end = Instant::from_picos(1_000_000);
        let mut unwritten = 0;
        for (i, gap) in [8, 9, 10, 11, -3, 10].into_iter().enumerate() {
            let start = start_after(end, gap);
            let level = fast.level_at(start).unwrap_or(false);
            let seg = segment(0, start, 30, level);
            end = seg.end().unwrap_or(start);
            let mut none = |_f: HeardFrame| {};
            let sinks = Sinks {
                events: &mut ev_fast,
                frames: &mut none,
            };
            let short = fast.input::<false, _>(seg.clone(), false, &cfg, sinks);
            general.input_general(seg, &cfg, &mut ev_general, &mut none);
            // The first telegram finds no filler running; the one cut short (gap -3) takes
            // the general path.
            assert_eq!(short, i != 0 && gap > 0, "step {i}");
            assert_eq!(fast.implied_unwritten, short, "step {i}");
            unwritten += u32::from(fast.implied_unwritten);
            let mut written = fast.clone();
            written.write_implied();
            assert!(!written.implied_unwritten);
            assert_eq!(written.digest(), general.digest(), "step {i}");
            assert_eq!(written.timeout, general.timeout, "step {i}");
        }
        assert_eq!(unwritten, 4);
    }

    /// The level of a running implied filler found from its start (`Ready::level_at`, used
    /// by [`Receiver::off_line_level`] when the segment starts after the filler's start)
    /// is the one the last segment gives, at every instant around the filler's start and
    /// the bits before it; the telegrams taken by the general path and by the
    /// filler-to-filler path.
    #[test]
    fn the_running_fillers_level_is_the_last_segments() {
        let cfg = cfg(1);
        let timeout = BT.saturating_mul(FIBBR_BIT_TIMES);
        let (mut short, mut ready, mut checked) = (0, 0, 0);
        for len in [1u8, 2, 3, 7, 16, 31] {
            for level_before in [false, true] {
                let mut rx = Receiver::new(Instant::ZERO, timeout);
                let mut events = LineEvents::default();
                let mut start = Instant::from_picos(1_000_000);
                for _ in 0..4 {
                    let mut seg = segment(0, start, len, level_before);
                    // Taken from the line's level (as `Chip::line_input_at_level` does).
                    if rx
                        .last
                        .as_ref()
                        .is_some_and(|l| l.level_at(start) != level_before)
                    {
                        seg.invert();
                    }
                    let end = seg.end().unwrap_or(start);
                    let mut sink = |_f: HeardFrame| {};
                    let sinks = Sinks {
                        events: &mut events,
                        frames: &mut sink,
                    };
                    short += u32::from(rx.input::<false, _>(seg, false, &cfg, sinks));
                    ready += u32::from(rx.ready.is_some());
                    // From half the bits back to 12 bit times past the bits, by thirds of a
                    // bit time.
                    let from = end.as_picos() - u64::from(len) * BT.as_picos() / 2;
                    for k in 0..(u64::from(len) * 3 / 2 + 36) {
                        let t = Instant::from_picos(from + k * BT.as_picos() / 3);
                        let line = rx.last.as_ref().map(|l| l.level_at(t));
                        for lb in [false, true] {
                            let probe = segment(0, t, 4, lb);
                            let expected = line.is_some_and(|l| l != lb);
                            assert_eq!(rx.off_line_level(&probe), expected, "at {t:?}");
                            checked += 1;
                        }
                    }
                    start = end.saturating_add(BT.saturating_mul(5 + u64::from(len % 2)));
                }
            }
        }
        assert!(short >= 24, "filler to filler {short} times");
        assert!(ready >= 24, "a filler running {ready} times");
        assert!(checked > 1000);
    }

    /// An intact ring's telegrams, every other one from the other level (as a fast path that
    /// leaves out segments hands them over): taken at the line's level, each inverted one
    /// still takes the filler-to-filler path, and all agree with the general path.
    #[test]
    fn telegrams_from_the_other_level_take_the_filler_to_filler_path_inverted() {
        for own in [0, 1] {
            let ring: Vec<Step> = (0..12)
                .map(|i| (0, 8 + i, 40, i % 2 == 0, own))
                .chain([(0, -3, 30, false, own), (0, 10, 30, false, own)])
                .chain([(4, 200, 1, true, own), (0, 5, 30, false, own)])
                .collect();
            let (taken, inverted) = compare_at_level(&ring).unwrap_or_else(|e| panic!("{e}"));
            assert!(taken >= 10, "taken {taken} times");
            assert!(inverted >= 6, "inverted {inverted} times");
        }
    }
}
