//! The chip's public line interface: segments in and out, received frames, and the serial
//! port's status changes applied in time order.

use sercon_regs::Register;
use sercos_wire::time::Instant;

use super::{FrameSink, HeardFrame, LineSegment, RxFrame, SerialPort};
use crate::chip::Chip;
use crate::pins::{Pin, PinEvent};

/// 410B §4.1 4H.0 INT_RDIST.
const INT_RDIST: u16 = 1 << 0;
/// 410B §4.1 4H.1 INT_FIBBR.
const INT_FIBBR: u16 = 1 << 1;

/// Serial-port instants [`Chip::serial_next_observable`] looks ahead.
const PROBE_STEPS: usize = 256;

impl Chip {
    /// Hands the chip one segment of its receive line (RxD), in light levels.
    ///
    /// Segments must come in order of their start, and before the chip is advanced past the
    /// start (later ones are taken as they come, their past part is not replayed). Received
    /// telegrams become [`RxFrame`]s at once ([`Chip::take_rx_frames`]); REACTN, FIBBR, RDIST
    /// and their interrupts follow when the chip's time reaches them. With the repeater on
    /// (1H.3 REPON) the segment is forwarded to the output.
    pub fn line_input(&mut self, seg: LineSegment) {
        self.line_input_with::<false>(seg);
    }

    /// [`Chip::line_input`] of a segment taken from the level the receive line is at: a
    /// telegram whose [`LineSegment::level_before`] is not the level
    /// [`Chip::received_level_at`] gives at its start is taken inverted
    /// ([`LineSegment::inverted`]; NRZI decodes it the same, 410B §4.1 1H.12 RXDNRZ = 0). A
    /// simulation that leaves out segments a receiver ignores hands its telegrams over so;
    /// the level is then found once, here, for the check and for taking the segment.
    // Inlined into the simulation's delivery: with the receiver's `inverted` flag LLVM
    // kept it out of line (+2.4 % instructions on ring-8).
    #[inline(always)]
    pub fn line_input_at_level(&mut self, seg: LineSegment) {
        self.line_input_with::<true>(seg);
    }

    /// [`Chip::line_input`], and with `AT_LEVEL` [`Chip::line_input_at_level`].
    #[inline(always)]
    fn line_input_with<const AT_LEVEL: bool>(&mut self, seg: LineSegment) {
        // A line input leaves the timing control alone; it adds frames for the telegram
        // processor (which can only make its next tick earlier) and changes for the serial
        // port (read from its queues, not cached).
        let now = self.now;
        // Whether nothing can be due at `now` after this input (then the advance to `now`
        // below would only return): the next instant is known, the segment starts after
        // `now` (how a conservative simulation hands segments over), so its status changes
        // do too, and so does every frame it completes (checked below: a frame may have
        // begun in an earlier segment).
        let quiet = seg.start > now && self.tp_next_known;
        // The telegram processor takes every frame the receiver saw (contract with tp), as
        // the receiver decodes it (no list in between: a frame is moved once).
        let at = seg.start;
        let mut sink = ToProcessor {
            clock: &self.clock,
            tp_next: &mut self.tp_next,
            tp: &mut self.tp,
            out_bound: &self.out_bound,
            settings: &self.engine.s,
            now,
            quiet,
            early_report: false,
        };
        let input = self.serial.line_input::<AT_LEVEL, _>(seg, &mut sink);
        let (mut quiet, early_report) = (sink.quiet, sink.early_report);
        if input.retracted {
            for start in self.serial.take_retracted() {
                crate::telegram_processor::take_back_frame(self, start);
            }
            quiet = false;
        }
        // A frame the receiver is still decoding is taken at its start before its end has
        // come (`telegram_processor::early_start`): only while a decoder runs (bits a fault
        // touched, a cut) or one was taken so. The filler-to-filler way leaves none running
        // (`LineInput::short`; checked in debug builds): the receiver is not asked then.
        debug_assert!(
            !input.short || !self.serial.decoding(),
            "a decoder runs after a filler-to-filler input"
        );
        if (self.tp.early.is_some() || (!input.short && self.serial.decoding()))
            && crate::telegram_processor::early_start::follow(self, at)
        {
            quiet = false;
        }
        if early_report {
            self.rx_queue_changed();
            quiet = false;
        }
        // The engine's pin levels (INT0/1, CONCLK, DIVCLK, WDOGN) do not depend on the
        // receiver or on queued frames: a line input changes none of them at once (its
        // status changes and interrupts follow in `advance_to`), so they are not recomputed.
        debug_assert_eq!(self.engine.levels, self.engine.compute_levels());
        if quiet {
            debug_assert!(
                self.next_internal().is_none_or(|n| n > now),
                "a line input ahead of time made something due at once"
            );
            return;
        }
        self.advance_to(now);
    }

    /// Moves the output segments (TxD, in light levels) that start at or before
    /// [`Chip::now`] to the end of `out`. A segment lasts until the next one starts; see
    /// [`LineSegment`].
    pub fn take_line_output(&mut self, out: &mut Vec<LineSegment>) {
        self.take_line_output_until(self.now, out);
    }

    /// [`Chip::take_line_output`] of the segments that start at or before `t` only (a chip
    /// run ahead of its simulation keeps the later ones until then).
    pub fn take_line_output_until(&mut self, t: Instant, out: &mut Vec<LineSegment>) {
        let t = t.min(self.now);
        self.serial.take_output(t, out);
    }

    /// [`Chip::take_line_output_until`] for a chip whose take is mostly its one own
    /// telegram and nothing else (a ring master's MST or MDT with the filler it implies,
    /// 410B §4.1 0CH, §4.2.1): the same segments and the same state, that case taken by a
    /// shorter way (debug builds compare it with the general release).
    pub fn take_own_line_output_until(&mut self, t: Instant, out: &mut Vec<LineSegment>) {
        let t = t.min(self.now);
        self.serial.take_output_own_first(t, out);
    }

    /// Whether [`Chip::take_line_output`] would hand anything over now (an output segment
    /// starts at or before [`Chip::now`]).
    pub fn line_output_due(&self) -> bool {
        self.line_output_due_at(self.now)
    }

    /// The one own telegram the chip has queued, from its first bit to the end of its last,
    /// with its bit time (`(start, end, bit time)`), when nothing else is queued to go out
    /// around it (no background segment; after it only the filler it implies,
    /// [`Chip::set_implied_filler`]): what [`Chip::take_line_output`] hands over once the
    /// chip is past its start.
    // Inlined with the two calls under it: a simulation asks it of every slave once a
    // cycle before it sends their ATs on (sercos-sim `early_route`), where the call and
    // its returned tuple cost more than the check (docs/performance.md, session 29).
    #[inline(always)]
    pub fn sole_queued_telegram(&self) -> Option<(Instant, Instant, sercos_wire::time::Duration)> {
        self.serial.sole_own_output()
    }

    /// Whether [`Chip::take_line_output_until`] at `t` would hand anything over.
    pub fn line_output_due_at(&self, t: Instant) -> bool {
        self.serial.output_due(t.min(self.now))
    }

    /// When the next output segment not yet given by [`Chip::take_line_output`] starts.
    pub fn next_line_output_at(&self) -> Option<Instant> {
        self.serial.next_output_at()
    }

    /// [`Chip::next_line_output_except`] with nothing expected: the next own output, or the
    /// next background segment the chip releases itself (not a copy the simulation carries,
    /// [`Chip::set_forward_output`]); found without a walk of the queue when it holds only
    /// such copies.
    pub fn next_line_output_unexpected(&self) -> Option<Instant> {
        let next = self.serial.next_uncarried_output_at();
        debug_assert_eq!(
            next,
            self.next_line_output_except(std::iter::empty()),
            "the next unexpected output"
        );
        next
    }

    /// When the next output segment not yet given by [`Chip::take_line_output`] starts,
    /// leaving out queued background segments (what the repeater forwards, 410B §1 "The
    /// slaves regenerate and repeat their received data", 1H.3 REPON, and the filler or
    /// steady signal of the transmit mode) whose starts are in `expected` (ascending, as a
    /// ring delivers them): a simulation that carries forwarded telegrams down the ring
    /// itself need not wake the chip for the copies it expects. Own telegrams and the
    /// background resumed after one always count.
    pub fn next_line_output_except<I>(&self, expected: I) -> Option<Instant>
    where
        I: IntoIterator<Item = Instant>,
    {
        let own = self.serial.next_own_output_at();
        let mut expected = expected.into_iter().peekable();
        let mut unexpected = None;
        for start in self.serial.background_output_starts() {
            while expected.next_if(|e| *e < start).is_some() {}
            if expected.next_if_eq(&start).is_none() {
                unexpected = Some(start);
                break;
            }
        }
        match (own, unexpected) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Moves the telegrams received so far to `out` (a log for tools and tests, kept to the
    /// newest [`super::RX_LOG_FRAMES`]; the telegram processor gets every frame anyway).
    pub fn take_rx_frames(&mut self, out: &mut Vec<RxFrame>) {
        self.serial.take_rx_frames(out);
    }

    /// Whether the chip keeps the receive log behind [`Chip::take_rx_frames`] (on after
    /// [`Chip::new`]). A simulation that never looks at it turns it off: every frame the
    /// receiver hears is then only handed to the telegram processor, nothing is kept or
    /// copied for the log. Turning it off forgets what was logged.
    pub fn set_rx_log(&mut self, on: bool) {
        self.serial.set_rx_log(on);
    }

    /// The light level of the receive line at `t` (≥ the last segment's start) as the last
    /// segment given to [`Chip::line_input`] decides it; `None` before the first. A
    /// simulation that leaves out segments a receiver ignores hands a telegram over from the
    /// level the receiver is at (NRZI decodes it the same either way).
    pub fn received_level_at(&self, t: Instant) -> Option<bool> {
        self.serial.received_level_at(t)
    }

    /// Whether the last segment given to [`Chip::line_input`] carries bits (a telegram), not
    /// a steady signal (filler, dark, light); `false` before the first.
    pub fn last_input_is_bits(&self) -> bool {
        self.serial.last_input_is_bits()
    }

    /// The end of the bits of the last segment given to [`Chip::line_input`], when it carries
    /// bits (a telegram); `None` for a steady signal or before the first.
    pub fn last_input_bits_end(&self) -> Option<Instant> {
        self.serial.last_input_bits_end()
    }

    /// Whether the receive line stays at one level after the last segment given to
    /// [`Chip::line_input`]: it carries bits and no filler after them
    /// ([`LineSegment::then_filler`]), so that without a further segment the receiver sees no
    /// edge from their end on (410B §4.1 2H.13 FIBBR) and the transmitter resumes no filler
    /// after an own telegram.
    pub fn line_steady_after_last_input(&self) -> bool {
        self.serial.line_steady_after_last_input()
    }

    /// Whether the repeater's copies of the received signal (410B §1 "The slaves regenerate
    /// and repeat their received data", 1H.3 REPON) appear in the line output (on after
    /// [`Chip::new`]). A simulation that carries every received segment down the ring itself
    /// turns it off: the chip still follows them (its line level, the background it resumes
    /// after an own telegram) but releases only its own telegrams, what resumes after one,
    /// and its filler and test signals. Applies to segments received from now on.
    pub fn set_forward_output(&mut self, on: bool) {
        self.serial.set_forward_output(on);
    }

    /// Whether own telegrams carry the idle filler resumed after them
    /// ([`LineSegment::then_filler`]; off after [`Chip::new`]). The line signal is the same
    /// either way; a simulation that turns it on carries one segment per telegram instead of
    /// two. It applies to telegrams released from now on.
    pub fn set_implied_filler(&mut self, on: bool) {
        self.serial.set_implied_filler(on);
    }

    /// Sends `telegram` (ADR and data, no FCS) from `at` (≥ [`Chip::now`]) as the telegram
    /// processor does, e.g. for a tool that uses the serial interface on its own (410B §1,
    /// "other real-time communications tasks"). Returns the instant the closing flag has
    /// left, or `None` when nothing is sent (transmitter off, a test mode, no bit clock, an
    /// empty or too long telegram).
    pub fn transmit_telegram(&mut self, at: Instant, telegram: &[u8]) -> Option<Instant> {
        let at = at.max(self.now);
        self.touched();
        let end = self.serial.transmit(at, telegram);
        self.settle_serial();
        end
    }

    /// Re-reads 1H and 2H into the serial port at [`Chip::now`] (after a register write or
    /// a reset).
    pub(crate) fn serial_registers_changed(&mut self) {
        self.touched();
        let lerrn = self.serial.lerrn();
        let regs = (
            self.engine.regs.stored(Register::Ctrl1),
            self.engine.regs.stored(Register::Ctrl2),
        );
        let (variant, straps, sclk, now) = (
            self.cfg.variant,
            self.cfg.straps,
            self.cfg.sclk_hz,
            self.now,
        );
        self.serial.reconfigure(variant, &straps, sclk, regs, now);
        if self.serial.lerrn() != lerrn {
            self.pin_event(Pin::LErrn, self.serial.lerrn(), now);
        }
    }

    /// Applies the serial port's changes due at or before [`Chip::now`].
    fn settle_serial(&mut self) {
        let now = self.now;
        while self.serial_step(now) {}
        self.serial.apply_pin_levels(now);
    }

    /// Applies the serial port's changes at its earliest instant if that is at or before
    /// `t`; returns whether there were any.
    pub(crate) fn serial_step(&mut self, t: Instant) -> bool {
        let before = (
            self.serial.idle(),
            self.serial.reactn(),
            self.serial.lerrn(),
        );
        let pins_loud = self.serial_pins_traced();
        let Some((at, applied)) = self.serial.step(t, pins_loud) else {
            return false;
        };
        if !self.in_reset {
            // 410B §4.1 4H.0 INT_RDIST "receive data distorted", 4H.1 INT_FIBBR "no receive
            // data": set when RDIST / FIBBR become 1.
            if applied.rdist_rose {
                self.engine.flags.raise_lo(INT_RDIST);
            }
            if applied.fibbr_rose {
                self.engine.flags.raise_lo(INT_FIBBR);
            }
        }
        let after = (
            self.serial.idle(),
            self.serial.reactn(),
            self.serial.lerrn(),
        );
        if after.0 != before.0 {
            self.pin_event(Pin::Idle, after.0, at);
            // TxD is traced as the envelope of the node's own transmission (spec-notes
            // "Serial port": TxD activity), not edge by edge: high while own data go out.
            self.pin_event(Pin::TxD, !after.0, at);
        }
        if after.1 != before.1 {
            self.pin_event(Pin::Reactn, after.1, at);
        }
        if after.2 != before.2 {
            self.pin_event(Pin::LErrn, after.2, at);
        }
        if applied.rdist_rose || applied.fibbr_rose {
            // Only a raised flag can change INT0/INT1 here (every other change of the
            // engine's state settles its pins where it happens).
            let changed = self.engine.update_levels();
            if changed != 0 {
                self.emit(changed, at);
            }
        }
        true
    }

    /// Records a level change of a serial-port pin if it is traced.
    fn pin_event(&mut self, pin: Pin, level: bool, at: Instant) {
        if self.traced.contains(pin) {
            self.events.push(PinEvent { at, pin, level });
        }
    }

    /// The level of a serial-port output pin (IDLE, REACTN, L_ERRN), if `pin` is one.
    pub(crate) fn serial_pin_level(&self, pin: Pin) -> Option<bool> {
        match pin {
            Pin::Idle => Some(self.serial.idle()),
            Pin::Reactn => Some(self.serial.reactn()),
            Pin::LErrn => Some(self.serial.lerrn()),
            // The envelope of own transmissions (see `serial_step`).
            Pin::TxD => Some(!self.serial.idle()),
            _ => None,
        }
    }

    /// The receiver's status bits for a read of 2H: (RDIST, FIBBR) (410B §4.1 2H.12-13).
    pub(crate) fn receiver_status(&self) -> (bool, bool) {
        let s: &SerialPort = &self.serial;
        (s.rdist(), s.fibbr())
    }

    /// The pin levels for a read of 3H: (IDLE, REACTN) (410B §4.1 3H.14-15). Each is found
    /// among the quiet pin changes when no serial-port pin is traced, so a read of 2H,
    /// which needs neither, does not ask for them.
    pub(crate) fn serial_pin_status(&self) -> (bool, bool) {
        let s: &SerialPort = &self.serial;
        (s.idle(), s.reactn())
    }

    /// Whether a serial-port pin (IDLE, TxD, REACTN) is traced: then its level changes
    /// are applied in time order like the status changes.
    fn serial_pins_traced(&self) -> bool {
        debug_assert_eq!(
            self.serial_pins_traced,
            self.traced.contains(Pin::Idle)
                || self.traced.contains(Pin::TxD)
                || self.traced.contains(Pin::Reactn)
        );
        self.serial_pins_traced
    }

    /// The next instant the serial port changes something the chip must apply in time
    /// order: FIBBR or RDIST (interrupts, L_ERRN), or a traced pin's level. Levels of
    /// untraced IDLE / REACTN are applied when the chip's time has passed them
    /// ([`Chip::serial_apply_pin_levels`]).
    pub(crate) fn serial_next_loud_event(&self) -> Option<Instant> {
        debug_assert_eq!(self.serial_pins_traced(), self.serial.pins_loud());
        self.serial.next_loud_event()
    }

    /// Applies the IDLE / REACTN level changes at or before `t`.
    pub(crate) fn serial_apply_pin_levels(&mut self, t: Instant) {
        self.serial.apply_pin_levels(t);
    }

    /// The next instant a serial-port change is observable: a traced pin (IDLE, REACTN,
    /// L_ERRN) changes, or an interrupt flag it sets changes INT0 or INT1. Found by running a
    /// copy of the port forward (at most [`PROBE_STEPS`] instants, then that instant).
    pub(crate) fn serial_next_observable(&self) -> Option<Instant> {
        let mut probe = self.serial.clone();
        let mut flags = self.engine.flags;
        let s = &self.engine.s;
        for _ in 0..PROBE_STEPS {
            let before = (probe.idle(), probe.reactn(), probe.lerrn());
            let ints = (flags.pin_level(s, 0), flags.pin_level(s, 1));
            let (at, applied) = probe.step(Instant::MAX, true)?;
            if !self.in_reset {
                if applied.rdist_rose {
                    flags.raise_lo(INT_RDIST);
                }
                if applied.fibbr_rose {
                    flags.raise_lo(INT_FIBBR);
                }
            }
            let after = (probe.idle(), probe.reactn(), probe.lerrn());
            let pins = [
                (Pin::Idle, before.0 != after.0),
                (Pin::TxD, before.0 != after.0),
                (Pin::Reactn, before.1 != after.1),
                (Pin::LErrn, before.2 != after.2),
            ];
            let traced = pins.iter().any(|(p, c)| *c && self.traced.contains(*p));
            if traced || ints != (flags.pin_level(s, 0), flags.pin_level(s, 1)) {
                return Some(at);
            }
        }
        probe.next_event_at()
    }
}

/// The chip's frame sink ([`Chip::line_input`]): the telegram processor takes every frame
/// the receiver decodes, as it is decoded (contract with tp), with what the chip keeps of
/// its next instants brought up to date. Its `take` is built into the receiver's paths
/// rather than called.
struct ToProcessor<'a> {
    clock: &'a crate::mclk::MclkClock,
    tp_next: &'a mut crate::mclk::Due,
    tp: &'a mut crate::telegram_processor::TelegramProcessor,
    out_bound: &'a std::cell::Cell<Option<Option<u64>>>,
    settings: &'a crate::settings::Settings,
    /// The chip's time.
    now: Instant,
    /// Nothing made due at `now` so far (`Chip::line_input`).
    quiet: bool,
    /// The report of a frame taken early came.
    early_report: bool,
}

impl FrameSink for ToProcessor<'_> {
    #[inline(always)]
    fn take(&mut self, f: HeardFrame) {
        let clock = self.clock;
        if self.tp.early.is_some_and(|e| e.start == f.start) {
            // The report of a frame taken early gives it its end.
            let tick = clock.tick_at_or_after(f.start);
            let HeardFrame {
                start,
                end,
                bytes,
                fcs_ok,
            } = f;
            self.early_report |= crate::telegram_processor::early_start::take_report(
                self.tp,
                clock,
                tick,
                (start, end),
                bytes,
                fcs_ok,
            );
            return;
        }
        if crate::telegram_processor::frame_is_mst(&f.bytes) && self.settings.is_sercos_slave() {
            // A slave's block starts with the MST it receives (410B §4.2.1 TRT): the output
            // bound is found afresh (a master's or a non-SERCOS chip's reads no MST it
            // receives, `telegram_processor::next_tx_bound`).
            self.out_bound.set(None);
        }
        let (tick, at) = clock.tick_and_instant_at_or_after(f.start);
        // While a frame is in progress the next starts at its end at the earliest
        // (`telegram_processor::first_frame_tick`), which the next ticks hold already.
        if self.tp.rx_now.is_none() {
            self.quiet &= at > self.now;
            // The processor's next tick is the earlier of its own and the first frame's
            // (and so is the core's, `Chip::kept_next_core`). Moved whether it holds or not
            // (`Chip::tp_next_known`, not asked here): when it does not, nothing reads it
            // before an advance writes it afresh, and `quiet` is false already.
            *self.tp_next = (*self.tp_next).min(crate::mclk::Due::at(tick));
        }
        self.tp.on_rx_frame(tick, f);
    }
}
