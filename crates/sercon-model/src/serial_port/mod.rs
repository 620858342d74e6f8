//! The serial port: transmitter, receiver and repeater of the serial interface (410B §1, §2;
//! §4.1 1H, 2H, 3H.14–15, 4H.0–1; 816 §2.3), and the line interface through which a ring
//! simulation connects chips ([`LineSegment`]).
//!
//! Readings the documents leave open are in `docs/spec-notes.md`, "Serial port".

mod coded_frames;
mod line_events;
mod line_interface;
mod port_config;
mod quiet_pins;
mod receiver;
mod rx_log;
mod segment;
mod transmitter;

use sercon_regs::Variant;
use sercos_wire::time::{BitRate, Duration, Instant};

use crate::chip::earliest;
use crate::config::Straps;
pub use segment::{Codings, FrameHint, LineSegment, LineSignal, Shared};

use line_events::{Change, LineEvents};
use port_config::{PortConfig, TxMode};
use quiet_pins::PinLine;
pub(crate) use receiver::FrameSink;
use receiver::{Receiver, Sinks};
use transmitter::Transmitter;

/// Bit times without an edge on the receive data after which FIBBR (2H.13) is set
/// (`docs/spec-notes.md`, "Serial port"): more than four times the longest edge-free run of a
/// valid NRZI signal (the six 1s of a flag).
pub const FIBBR_BIT_TIMES: u64 = 32;

/// Data bits of the pre-frame sync word sent before an own telegram when PRESYNC (1H.8) = 1:
/// a 16-bit word of data 0s, i.e. 16 bit times of the NRZI square wave
/// (`docs/spec-notes.md`, "Serial port").
pub const PRESYNC_BITS: u64 = 16;

/// Bit times (of the received signal) the repeater needs from input to output for clock and
/// data regeneration (`docs/spec-notes.md`, "Serial port").
pub const REPEATER_LATENCY_BITS: u64 = 2;

/// Frames kept for [`crate::Chip::take_rx_frames`] (the newest; older ones are dropped).
pub const RX_LOG_FRAMES: usize = 4096;

/// A telegram the receiver saw, known as soon as its line segment was handed to the chip.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RxFrame {
    /// First bit of the opening flag.
    pub start: Instant,
    /// End of the closing flag (or of the bit that broke the frame).
    pub end: Instant,
    /// Telegram bytes (ADR and data, FCS stripped); for a broken frame, the whole bytes
    /// received.
    pub bytes: Vec<u8>,
    /// The frame ended with a flag and its FCS matched.
    pub fcs_ok: bool,
}

/// A frame sink whose frames go to the receive log first (`SerialPort::line_input`).
struct Logged<'a, F: FrameSink> {
    log: &'a mut rx_log::RxLog,
    frames: &'a mut F,
}

impl<F: FrameSink> FrameSink for Logged<'_, F> {
    #[inline(always)]
    fn take(&mut self, frame: HeardFrame) {
        self.log.push(&frame);
        self.frames.take(frame);
    }
}

/// A frame as the receiver hands it to the telegram processor and the receive log: an
/// [`RxFrame`] whose bytes are shared. A telegram with a [`FrameHint`] shares the sender's
/// bytes (no copy per receiver and log); a decoded one owns its own.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct HeardFrame {
    /// First bit of the opening flag.
    pub(crate) start: Instant,
    /// End of the closing flag (or of the bit that broke the frame).
    pub(crate) end: Instant,
    /// Telegram bytes (ADR and data, FCS stripped); for a broken frame, the whole bytes
    /// received.
    pub(crate) bytes: Shared<[u8]>,
    /// The frame ended with a flag and its FCS matched.
    pub(crate) fcs_ok: bool,
}

/// The serial port of one chip.
#[derive(Debug, Clone)]
pub(crate) struct SerialPort {
    cfg: PortConfig,
    tx: Transmitter,
    rx: Receiver,
    events: LineEvents,
    /// The receive log (the newest [`RX_LOG_FRAMES`]).
    rx_log: rx_log::RxLog,
    /// Level at pin IDLE (410B §2, active low); while the pins are quiet, before the
    /// changes `events` keeps (`LineEvents::quiet_level`).
    idle: bool,
    /// Level at pin REACTN (410B §2, active low), as `idle`.
    reactn: bool,
    /// 410B §4.1 2H.13 FIBBR.
    fibbr: bool,
    /// 410B §4.1 2H.12 RDIST.
    rdist: bool,
    /// [`SerialPort::next_loud_event_at`] with the pins as loud as `events` keeps them,
    /// kept where its inputs change (the line events pushed and taken, FIBBR's deadline set
    /// and cleared: `line_input`, `transmit`, `step`, `apply_pin_levels`, `set_pins_loud`),
    /// so that the chip's event loop, which asks at every turn, reads a field
    /// ([`SerialPort::next_loud_event`]; debug builds compare with the computation).
    loud: Option<Instant>,
}

/// The status a change altered, for the chip to report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Applied {
    /// FIBBR went from 0 to 1 (410B §4.1 4H.1 INT_FIBBR).
    pub(crate) fibbr_rose: bool,
    /// RDIST went from 0 to 1 (410B §4.1 4H.0 INT_RDIST).
    pub(crate) rdist_rose: bool,
}

/// What [`SerialPort::line_input`] found.
#[derive(Debug, Clone, Copy)]
#[must_use]
pub(crate) struct LineInput {
    /// The segment took back frames reported before ([`SerialPort::take_retracted`]).
    pub(crate) retracted: bool,
    /// The receiver took it the filler-to-filler way (`Receiver::filler_to_filler`: a hinted
    /// telegram reported whole, its implied filler after it): no decoder runs after it
    /// ([`SerialPort::decoding`] is `false`; 410B §4.1 2H.13, the filler's edges).
    pub(crate) short: bool,
}

impl SerialPort {
    /// The port at `at` with the registers 1H and 2H as given.
    pub(crate) fn new(
        variant: Variant,
        straps: &Straps,
        sclk_hz: u64,
        regs: (u16, u16),
        at: Instant,
    ) -> Self {
        let cfg = PortConfig::decode(variant, straps, sclk_hz, regs.0, regs.1);
        let timeout = cfg
            .bit_time
            .unwrap_or(BitRate::Mbit2.bit_time())
            .saturating_mul(FIBBR_BIT_TIMES);
        let mut port = SerialPort {
            cfg,
            tx: Transmitter::default(),
            rx: Receiver::new(at, timeout),
            events: LineEvents::default(),
            rx_log: rx_log::RxLog::default(),
            idle: true,
            reactn: true,
            fibbr: false,
            rdist: false,
            loud: None,
        };
        port.start_background(at);
        port.refresh_loud();
        port
    }

    /// New register values at `now`.
    pub(crate) fn reconfigure(
        &mut self,
        variant: Variant,
        straps: &Straps,
        sclk_hz: u64,
        regs: (u16, u16),
        now: Instant,
    ) {
        let cfg = PortConfig::decode(variant, straps, sclk_hz, regs.0, regs.1);
        let old = self.cfg;
        self.cfg = cfg;
        if cfg.tx_mode != old.tx_mode
            || cfg.bit_time != old.bit_time
            || cfg.polrxd != old.polrxd
            || cfg.poltxd != old.poltxd
        {
            self.start_background(now);
        }
    }

    /// The bit time the transmitter uses: its own, or with an external bit clock the one of
    /// the received signal (410B §2 RxC: with the repeater on, RxC clocks the transmitter too).
    fn tx_bit_time(&self) -> Option<Duration> {
        self.cfg.bit_time.or(self.rx.last_bit_time())
    }

    /// Starts the background signal of the current transmitter mode at `at`.
    fn start_background(&mut self, at: Instant) {
        let level = self.tx.level_at(at);
        let bt = self.tx_bit_time();
        let steady = |signal| LineSegment::steady(at, bt.unwrap_or(Duration::ZERO), signal, level);
        // 410B §4.1 1H.9 POLTXD: a transmitter set to "light on when TxD = 1" inverts the
        // light of the line interface's transceiver (spec-notes "Serial port").
        let light = |on: bool| {
            if on != self.cfg.poltxd {
                LineSignal::Light
            } else {
                LineSignal::Dark
            }
        };
        let seg = match (self.cfg.tx_mode, bt) {
            // 410B §2 TxD1: high impedance; the fibre is dark.
            (TxMode::Off, _) => steady(LineSignal::Dark),
            // 410B §2 TM0: "continuous signal light".
            (TxMode::ContinuousLight, _) => steady(light(true)),
            // No bit clock: no filler (spec-notes "Serial port").
            (TxMode::ZeroBitStream | TxMode::Filler, None) => steady(light(false)),
            // 410B §2 TM1: "zero bit stream"; sercos-facts: filler between telegrams.
            (TxMode::ZeroBitStream | TxMode::Filler, Some(_)) => steady(LineSignal::Filler),
            (TxMode::Repeat, _) => match self
                .rx
                .last_segment_at_level()
                .and_then(|s| s.from_instant(at))
            {
                Some(current) => self.forwarded(current),
                None => steady(LineSignal::Dark),
            },
        };
        self.tx.push_background(seg);
    }

    /// What the repeater makes of a received segment: regenerated (no distortion), delayed by
    /// the repeater latency, inverted when POLRXD and POLTXD differ.
    fn forwarded(&self, seg: LineSegment) -> LineSegment {
        let latency = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        let mut out = seg.delayed(latency);
        out.distorted = false;
        if self.cfg.polrxd != self.cfg.poltxd {
            out = out.inverted();
        }
        out
    }

    /// Receives one segment of the line input; each frame it completes goes to the log and
    /// then to `frames`, in order. Returns whether the segment took back frames reported
    /// before (it cut their bits, `Receiver::take_retracted`; [`SerialPort::take_retracted`]
    /// names them): a frame of such a start reported now replaces one; and whether the
    /// receiver took it the filler-to-filler way ([`LineInput::short`]).
    ///
    /// `AT_LEVEL` (`Chip::line_input_at_level`): a telegram is first taken to the level the
    /// line is at (inverted when [`receiver::Receiver::off_line_level`]).
    pub(crate) fn line_input<const AT_LEVEL: bool, F: FrameSink>(
        &mut self,
        mut seg: LineSegment,
        frames: &mut F,
    ) -> LineInput {
        let mut inverted = AT_LEVEL && self.rx.off_line_level(&seg);
        // 410B §1: "The slaves regenerate and repeat their received data"; 1H.3 REPON.
        // The copy is queued before the receiver takes `seg`: the receiver reads nothing of
        // the transmitter, nor the transmitter of the receiver (queued before the input as
        // after it; no `Option` of a copy kept across the input).
        if self.cfg.tx_mode == TxMode::Repeat {
            // The copy is of the telegram at the line's level: taken there first. Else the
            // receiver takes it as it came, inverted (`Receiver::input`: no branch on the
            // level on its short path).
            if inverted {
                seg.invert();
                inverted = false;
            }
            if self.tx.carried_forwarding && self.cfg.polrxd == self.cfg.poltxd {
                // A copy the user carries is only followed: its hint is never read (a
                // resume cuts it; spec-notes "Followed copies"), so it is not copied; not
                // inverted (the polarities agree), it is built where it is queued (the
                // receiver reads nothing of the transmitter: queued before the input as
                // after it).
                // With `AT_LEVEL`, `seg` starts from the level the receiver's last segment
                // leaves at its start (above).
                let follows = if AT_LEVEL {
                    self.rx.last_segment().map(|s| s.start)
                } else {
                    None
                };
                self.tx.push_carried(&seg, REPEATER_LATENCY_BITS, follows);
            } else if self.tx.carried_forwarding {
                let fwd = self.forwarded(seg.without_hint());
                self.tx.push_forwarded(fwd);
            } else {
                let fwd = self.forwarded(seg.clone());
                self.tx.push_forwarded(fwd);
            }
        }
        let mut sink = Logged {
            log: &mut self.rx_log,
            frames,
        };
        let short = self.rx.input::<AT_LEVEL, _>(
            seg,
            inverted,
            &self.cfg,
            Sinks {
                events: &mut self.events,
                frames: &mut sink,
            },
        );
        // The filler-to-filler path leaves FIBBR's deadline unset and schedules only
        // REACTN's pulse (410B §2 REACTN), which counts as a loud event only while the pins
        // are loud: the kept bound stands (debug builds compare it at every read).
        if !short || self.events.pins_loud() {
            self.refresh_loud();
        }
        LineInput {
            retracted: !short && self.rx.has_retracted(),
            short,
        }
    }

    /// Whether the receiver decodes bits ([`receiver::Receiver::decoding`]).
    #[inline]
    pub(crate) fn decoding(&self) -> bool {
        self.rx.decoding()
    }

    /// The frame the receiver has in progress at the end of the bits received
    /// ([`receiver::Receiver::frame_in_progress`]): its start, its bytes so far and where it
    /// ends unless more bits come first.
    pub(crate) fn frame_in_progress(&self) -> Option<(Instant, &[u8], Instant)> {
        self.rx.frame_in_progress()
    }

    /// The starts of the frames the last [`SerialPort::line_input`] took back (when it
    /// returned `true`), in order; the receive log has forgotten them.
    #[cold]
    #[inline(never)]
    pub(crate) fn take_retracted(&mut self) -> Vec<Instant> {
        let taken = self.rx.take_retracted();
        for (start, replaced) in &taken {
            self.rx_log.retract(*start, *replaced);
        }
        taken.into_iter().map(|(start, _)| start).collect()
    }

    /// Whether the chip's own last telegram is still going out at `at`
    /// ([`Transmitter::own_busy_at`]).
    pub(crate) fn own_busy_at(&self, at: Instant) -> bool {
        self.tx.own_busy_at(at)
    }

    /// Queues an own telegram at `at`; returns when its last bit leaves, `None` when nothing
    /// is sent (transmitter off, test mode, no bit clock, telegram not encodable).
    pub(crate) fn transmit(&mut self, at: Instant, telegram: &[u8]) -> Option<Instant> {
        if !self.cfg.sends_telegrams() {
            return None;
        }
        let bt = self.tx_bit_time()?;
        let placed = self.tx.transmit(at, bt, self.cfg.presync, telegram)?;
        // 410B §2 IDLE: "When transmitting own data IDLE is 0."
        self.events.push_own_idle(placed.start, placed.end);
        // Loud pins: both changes are in time order, the start first; quiet: neither counts.
        if self.events.pins_loud() {
            self.loud = earliest(self.loud, Some(placed.start));
        }
        debug_assert_eq!(self.loud, self.compute_loud());
        Some(placed.end)
    }

    /// The receive line's light level at `t` as the last segment received decides it.
    pub(crate) fn received_level_at(&self, t: Instant) -> Option<bool> {
        self.rx.level_at(t)
    }

    /// Whether the last segment received carries bits (a telegram), not a steady signal.
    pub(crate) fn last_input_is_bits(&self) -> bool {
        self.rx
            .last_segment()
            .is_some_and(|s| matches!(s.signal, LineSignal::Bits(_)))
    }

    /// `Chip::last_input_bits_end`.
    pub(crate) fn last_input_bits_end(&self) -> Option<Instant> {
        self.rx
            .last_segment()
            .filter(|s| matches!(s.signal, LineSignal::Bits(_)))
            .and_then(|s| s.end())
    }

    /// `Chip::line_steady_after_last_input`.
    pub(crate) fn line_steady_after_last_input(&self) -> bool {
        self.rx
            .last_segment()
            .is_some_and(|s| matches!(s.signal, LineSignal::Bits(_)) && !s.then_filler)
    }

    /// Whether the repeater's copies of the received signal are released as output
    /// (`Chip::set_forward_output`).
    pub(crate) fn set_forward_output(&mut self, on: bool) {
        self.tx.carried_forwarding = !on;
    }

    /// Whether what is received goes out again as it comes (1H.3 REPON, the copies released,
    /// `Chip::set_forward_output`): the output then follows the input.
    pub(crate) fn output_follows_input(&self) -> bool {
        self.cfg.tx_mode == TxMode::Repeat && !self.tx.carried_forwarding
    }

    /// Own telegrams carry the filler resumed after them (`Chip::set_implied_filler`).
    pub(crate) fn set_implied_filler(&mut self, on: bool) {
        self.tx.implied_filler = on;
    }

    /// Whether [`SerialPort::take_output`] at `now` would hand anything over.
    pub(crate) fn output_due(&self, now: Instant) -> bool {
        self.tx.next_release_at().is_some_and(|t| t <= now) || !self.tx.nothing_released()
    }

    /// Releases the output segments that start at or before `now` and moves them to `out`.
    pub(crate) fn take_output(&mut self, now: Instant, out: &mut Vec<LineSegment>) {
        if !self.output_due(now) {
            // Most turns of an event loop: nothing to hand over.
            return;
        }
        self.tx.release(now);
        self.tx.take_released(out);
    }

    /// [`SerialPort::take_output`] by [`Transmitter::release_own_first`]: for a take that
    /// mostly finds the one own telegram queued and nothing else (a ring master's).
    pub(crate) fn take_output_own_first(&mut self, now: Instant, out: &mut Vec<LineSegment>) {
        if !self.output_due(now) {
            return;
        }
        self.tx.release_own_first(now);
        self.tx.take_released(out);
    }

    /// When the next not yet released output segment starts.
    pub(crate) fn next_output_at(&self) -> Option<Instant> {
        self.tx.next_release_at()
    }

    /// The instant the next own output segment starts (not a queued background segment).
    pub(crate) fn next_own_output_at(&self) -> Option<Instant> {
        self.tx.next_own_release_at()
    }

    /// The next own output or background segment not carried
    /// (`Transmitter::next_uncarried_release_at`).
    pub(crate) fn next_uncarried_output_at(&self) -> Option<Instant> {
        self.tx.next_uncarried_release_at()
    }

    /// The one own telegram queued and nothing else (`Transmitter::sole_own`).
    #[inline(always)]
    pub(crate) fn sole_own_output(&self) -> Option<(Instant, Instant, Duration)> {
        self.tx.sole_own()
    }

    /// Starts of the queued background output segments, in order.
    pub(crate) fn background_output_starts(&self) -> impl Iterator<Item = Instant> + '_ {
        self.tx.background_starts()
    }

    /// Moves the received frames to the end of `out`.
    pub(crate) fn take_rx_frames(&mut self, out: &mut Vec<RxFrame>) {
        self.rx_log.take(out);
    }

    /// Keeps the receive log or not.
    pub(crate) fn set_rx_log(&mut self, on: bool) {
        self.rx_log.set_on(on);
    }

    /// The instant of the next change the chip applies in time order: FIBBR and RDIST
    /// (and FIBBR's timeout), and IDLE / REACTN too when `pins_loud` (their pins traced).
    pub(crate) fn next_loud_event_at(&self, pins_loud: bool) -> Option<Instant> {
        match (self.events.next_loud_at(pins_loud), self.rx.fibbr_deadline) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// [`SerialPort::next_loud_event_at`] with the pins as loud as the line events keep
    /// them: the kept bound (`loud`).
    #[inline]
    pub(crate) fn next_loud_event(&self) -> Option<Instant> {
        debug_assert_eq!(self.loud, self.compute_loud());
        self.loud
    }

    /// `loud` from what it keeps.
    fn compute_loud(&self) -> Option<Instant> {
        self.next_loud_event_at(self.events.pins_loud())
    }

    /// Sets `loud` afresh after a change of the line events or FIBBR's deadline.
    fn refresh_loud(&mut self) {
        self.loud = self.compute_loud();
    }

    /// Applies the IDLE / REACTN changes at or before `t` (pin levels only).
    #[inline]
    pub(crate) fn apply_pin_levels(&mut self, t: Instant) {
        // Quiet with a short list (every advance of a chip ends here): only the instant the
        // quiet changes count up to moves, the levels stand.
        if !self
            .events
            .apply_quiet_pins_unfolded(t, (self.idle, self.reactn))
        {
            self.apply_pin_levels_in_full(t);
        }
    }

    /// [`SerialPort::apply_pin_levels`] when the pins are loud or the quiet changes are
    /// folded.
    #[inline(never)]
    fn apply_pin_levels_in_full(&mut self, t: Instant) {
        // Quiet: the changes up to `t` count from now on (`SerialPort::idle`).
        self.apply_quiet_pins(t);
        if !self.events.pins_loud() {
            return;
        }
        while let Some((_, change)) = self.events.pop_pin_until(t) {
            // `if let`s, not a `match` (a jump table, whose indirect jump mispredicts as
            // REACTN and IDLE changes alternate; docs/performance.md, session 5). Only
            // pin-level changes are in that queue.
            if let Change::Reactn(l) = change {
                self.reactn = l;
            } else if let Change::Idle(l) = change {
                self.idle = l;
            }
        }
        self.refresh_loud();
    }

    /// The instant of the next scheduled status change (including FIBBR's timeout).
    pub(crate) fn next_event_at(&self) -> Option<Instant> {
        let deadline = self.rx.fibbr_deadline;
        match (self.events.next_at(), deadline) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Applies the changes due at or before `t`, the earliest first; stops after one instant
    /// and returns it with what changed, or `None` when nothing is due.
    ///
    /// With `pins_loud` false, IDLE / REACTN changes do not count as an instant of their
    /// own (they are applied with the next status change, or by
    /// [`SerialPort::apply_pin_levels`]).
    pub(crate) fn step(&mut self, t: Instant, pins_loud: bool) -> Option<(Instant, Applied)> {
        let next = if pins_loud {
            self.next_event_at()
        } else {
            self.next_loud_event_at(false)
        };
        let at = next.filter(|a| *a <= t)?;
        // Quiet IDLE / REACTN changes up to `at` count from here on, as the loud ones below.
        self.apply_quiet_pins(at);
        let mut applied = Applied {
            fibbr_rose: false,
            rdist_rose: false,
        };
        if self.rx.fibbr_deadline == Some(at) {
            self.rx.deadline_fired();
            applied.fibbr_rose |= !self.fibbr;
            self.fibbr = true;
        }
        while let Some((_, change)) = self.events.pop_until(at) {
            match change {
                Change::Idle(l) => self.idle = l,
                Change::Reactn(l) => self.reactn = l,
                Change::Fibbr(v) => {
                    applied.fibbr_rose |= v && !self.fibbr;
                    self.fibbr = v;
                }
                Change::Rdist(v) => {
                    applied.rdist_rose |= v && !self.rdist;
                    self.rdist = v;
                }
            }
        }
        self.refresh_loud();
        Some((at, applied))
    }

    /// The quiet IDLE / REACTN changes up to `t` count from now on
    /// (`LineEvents::apply_quiet_pins`; loud ones are applied in time order).
    fn apply_quiet_pins(&mut self, t: Instant) {
        let mut levels = (self.idle, self.reactn);
        self.events.apply_quiet_pins(t, &mut levels);
        (self.idle, self.reactn) = levels;
    }

    /// Level at pin IDLE.
    pub(crate) fn idle(&self) -> bool {
        self.pin_level(PinLine::Idle, self.idle)
    }

    /// Level at pin REACTN.
    pub(crate) fn reactn(&self) -> bool {
        self.pin_level(PinLine::Reactn, self.reactn)
    }

    /// The level of `pin` (`applied`: its level as last applied).
    fn pin_level(&self, pin: PinLine, applied: bool) -> bool {
        if self.events.pins_loud() {
            applied
        } else {
            self.events.quiet_level(pin, applied)
        }
    }

    /// Keeps IDLE / REACTN changes in time order, to be applied one instant at a time
    /// (`loud`: one of the pins IDLE, TxD, REACTN is traced), or only as their levels are
    /// asked for.
    pub(crate) fn set_pins_loud(&mut self, loud: bool) {
        let mut levels = (self.idle, self.reactn);
        self.events.set_pins_loud(loud, &mut levels);
        (self.idle, self.reactn) = levels;
        self.refresh_loud();
    }

    /// Whether IDLE / REACTN changes are kept in time order ([`SerialPort::set_pins_loud`]).
    pub(crate) fn pins_loud(&self) -> bool {
        self.events.pins_loud()
    }

    /// 410B §4.1 2H.13 FIBBR.
    pub(crate) fn fibbr(&self) -> bool {
        self.fibbr
    }

    /// 410B §4.1 2H.12 RDIST.
    pub(crate) fn rdist(&self) -> bool {
        self.rdist
    }

    /// Level at pin L_ERRN (410B §2, active low; §4.1 2H.14–15 LMODE).
    pub(crate) fn lerrn(&self) -> bool {
        self.cfg.lmode.pin_level(self.rdist, self.fibbr)
    }
}
