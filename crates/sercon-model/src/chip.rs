//! The chip: configuration, simulated time, output pins and the host bus.

use sercon_regs::SerconBus;
use sercos_wire::time::Instant;

use crate::config::ChipConfig;
use crate::engine::{DRIVEN, Engine};
use crate::mclk::{Due, MclkClock};
use crate::pins::{Pin, PinEvent, PinSet};

/// One SERCON410B or SERCON816, advanced in simulated time.
///
/// Time is injected (DESIGN.md): [`Chip::advance_to`] processes everything up to an
/// instant, [`Chip::next_deadline`] names the next instant at which something observable
/// happens, and every bus access ([`SerconBus`]) happens at [`Chip::now`].
#[derive(Debug, Clone)]
pub struct Chip {
    pub(crate) cfg: ChipConfig,
    pub(crate) clock: MclkClock,
    pub(crate) now: Instant,
    pub(crate) engine: Engine,
    pub(crate) ram: Vec<u16>,
    pub(crate) traced: PinSet,
    /// A serial-port pin (IDLE, TxD, REACTN) is traced: then its level changes are
    /// applied in time order like the status changes (kept with `traced`; asked on every
    /// turn of the event loop).
    pub(crate) serial_pins_traced: bool,
    pub(crate) events: Vec<PinEvent>,
    /// RSTN is low: the chip is held in reset.
    pub(crate) in_reset: bool,
    /// Level at input CYC_CLK (410B §4.1 0CH.7).
    pub(crate) cyc_clk: bool,
    /// The telegram processor and MST handling (410B §4.2).
    pub(crate) tp: crate::telegram_processor::TelegramProcessor,
    /// The serial port: transmitter, receiver, repeater (410B §1, §2).
    pub(crate) serial: crate::serial_port::SerialPort,
    /// The telegram processor's next tick, as [`Chip::advance_to`] left it, while
    /// `tp_next_known`; not to be read once anything from outside (a bus access, a pin, a
    /// DMA cycle) may have changed that. A line input keeps it up to date (it can only add
    /// frames). The first turn of
    /// [`Chip::advance_to`]'s loop, and every turn after a step of the timing control that
    /// started no cycle, reuse it instead of walking the processor's state again. With the
    /// timing control's next tick (its memo) it is the core's next tick
    /// ([`Chip::kept_next_core`]), which lets an advance with nothing due, and
    /// [`Chip::next_event_at`], skip recomputing every component's next tick; that one is
    /// not kept of its own (it was written at every advance and frame and read at few).
    /// The serial port's next change is not part of it: it is read from the port's queues,
    /// which every line input moves.
    pub(crate) tp_next: Due,
    /// Whether `tp_next` holds (a flag beside the word rather than an `Option` around it: a
    /// line input moves the word without asking, session 34's helper `optinstant`).
    pub(crate) tp_next_known: bool,
    /// Last traced levels of DMAREQR / DMAREQT in static mode, and the tick of the last
    /// traced pulse in pulsed mode (410B §2 pins 38, 39; §4.1 1H.14 DMAMODE).
    pub(crate) dma_trace: [(bool, Option<u64>); 2],
    /// The telegram-processor part of [`Chip::next_output_bound`] (the MCLK tick of the
    /// next possible own telegram or, for a master, cycle start), as last computed
    /// (`Some`, by [`Chip::next_output_bound`] or [`Chip::next_output_for_any_input`]);
    /// `None` once an advance that processed anything, a bus access or an MST a SERCOS
    /// slave received may have moved it. Other line inputs keep it: they only queue frames
    /// the bound ignores (a slave's block starts with an MST, 410B §4.2.1 TRT; a master's or
    /// a non-SERCOS chip's with its cycle start, 410B §4.1 0CH, whatever it receives) and
    /// serial-port changes, which the bound reads afresh. A simulation asks for the bound
    /// after every delivery; most deliveries then cost a load here instead of a walk.
    pub(crate) out_bound: std::cell::Cell<Option<Option<u64>>>,
    /// Whether the telegram processor's own writes leave its header lists as they are
    /// (`telegram_processor::layout`), as last found, with the blocks whose lists it covers
    /// (bit n: block n); `None`: to be found. The bound above is promised only then. A host
    /// write to a word the proof read drops it.
    pub(crate) layout: std::cell::Cell<Option<(bool, u8)>>,
    /// The words the walks read, as the layout proof found them.
    pub(crate) layout_read: std::cell::RefCell<crate::telegram_processor::RamWords>,
    /// The number of the layout proof as it is (one more for every proof found or dropped,
    /// [`Chip::set_layout`]): what the processor keeps under a proof is kept with its number
    /// (`telegram_processor::walk_memo`).
    pub(crate) layout_epoch: std::cell::Cell<u64>,
    /// [`Chip::advance_to`] takes a processor event right after the previous one when
    /// nothing lies between ([`Chip::set_chained_steps`]).
    pub(crate) chained_steps: bool,
    /// Chained steps on and neither DMAREQR nor DMAREQT traced (410B §2 pins 38, 39): the
    /// part of [`Chip::chains_to`]'s check that only the host changes, kept where it does
    /// ([`Chip::set_chained_steps`], [`Chip::set_traced_pins`]; [`Chain::may_chain_in`]).
    pub(crate) may_chain: bool,
}

/// What [`Chip::advance_to`]'s loop knows when it hands the telegram processor a step
/// (`telegram_processor::step`): enough for the processor to tell whether the loop would
/// take its next event at once after this one ([`Chip::chains_to`]), with no quiet cycle
/// end before it (spec-notes "Chained processor steps", "Quiet cycle ends"). A received
/// telegram whose end is that next event is then started and ended in one step
/// (`receive::frame_start`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Chain {
    /// The last MCLK tick of the advance.
    pub(crate) limit: u64,
    /// The timing control's next tick, if due by `limit` (it goes first at equal ticks).
    pub(crate) engine_tick: Due,
    /// The interrupt flags when the loop's turn began (`Flags::word`).
    pub(crate) flags: u64,
    /// The FIFO state when the loop's turn began (`DmaFifos::snapshot`).
    pub(crate) fifo: Option<crate::telegram_processor::FifoState>,
    /// The flag bits that move a pin (`Flags::word`: of 4H only the bits an enabled output
    /// carries, 410B §4.1 4H / 5H; the rest whole), worked out once a turn
    /// ([`Chain::carried_by`]): the settings stay as they are over a turn's steps (decoded
    /// again only at a bus write, 410B §4.1, or the watchdog's expiry, 816 §2.6.2, both
    /// outside the processor's steps; debug-asserted at every check).
    pub(crate) carried: u64,
}

impl Chain {
    /// No step may be joined to the next (a step outside the loop's chain).
    #[cfg(debug_assertions)]
    pub(crate) fn none(chip: &Chip) -> Chain {
        Chain {
            limit: 0,
            engine_tick: Due::NONE,
            flags: 0,
            fifo: None,
            carried: Chain::carried_by(chip),
        }
    }

    /// [`Chain::carried`] for `chip` as it is.
    #[inline]
    pub(crate) fn carried_by(chip: &Chip) -> u64 {
        // `Flags::word`: of 4H only the bits an enabled output carries, the rest whole.
        !u64::from(!chip.engine.s.int_out_lo)
    }

    /// [`Chip::may_chain`] for `chip` as it is.
    #[inline]
    pub(crate) fn may_chain_in(chip: &Chip) -> bool {
        chip.chained_steps && !chip.dma_pins_traced()
    }

    /// Whether the loop would take the processor's event at tick `e`, found next right
    /// after the step it handed over, at once ([`Chip::chains_to`]) with no quiet cycle
    /// end applied before it: the loop then takes the timing control's memo's quiet end
    /// (which a short cycle sync may have moved, `Engine::sync_cycle`) and applies it first
    /// when `e` is at or after it.
    #[inline]
    pub(crate) fn allows(&self, chip: &Chip, e: u64) -> bool {
        chip.chains_to(e, self).is_some_and(|quiet| e < quiet)
    }
}

impl Chip {
    /// A chip at time 0, as after RSTN. An invalid configuration (MCLK of 0 Hz, see
    /// [`ChipConfig::validate`]) runs with its MCLK clamped to 1 Hz ..= 1 THz.
    pub fn new(cfg: ChipConfig) -> Chip {
        let clock = MclkClock::new(cfg.mclk_hz);
        let engine = Engine::after_reset(cfg.variant, &cfg.straps, 0);
        let serial = crate::serial_port::SerialPort::new(
            cfg.variant,
            &cfg.straps,
            cfg.sclk_hz,
            (
                engine.regs.stored(sercon_regs::Register::Ctrl1),
                engine.regs.stored(sercon_regs::Register::Ctrl2),
            ),
            Instant::ZERO,
        );
        Chip {
            cfg,
            clock,
            now: Instant::ZERO,
            engine,
            // 410B §1: 1024 words; 816 §2.5: 2048 words. The RAM has no reset value
            // (spec-notes "RAM after power-up": 0).
            ram: vec![0; usize::from(cfg.variant.ram_words())],
            traced: PinSet::EMPTY,
            serial_pins_traced: false,
            events: Vec::new(),
            in_reset: false,
            cyc_clk: false,
            tp: Default::default(),
            serial,
            tp_next: Due::NONE,
            tp_next_known: false,
            dma_trace: [(false, None); 2],
            out_bound: std::cell::Cell::new(None),
            layout: std::cell::Cell::new(None),
            layout_read: Default::default(),
            layout_epoch: std::cell::Cell::new(0),
            chained_steps: true,
            // Chained steps on, no pin traced.
            may_chain: true,
        }
    }

    /// A chip at time 0 after checking the configuration.
    pub fn try_new(cfg: ChipConfig) -> Result<Chip, crate::ConfigError> {
        cfg.validate()?;
        Ok(Chip::new(cfg))
    }

    /// The configuration the chip was built with.
    pub fn config(&self) -> &ChipConfig {
        &self.cfg
    }

    /// The current simulated time.
    pub fn now(&self) -> Instant {
        self.now
    }

    /// Processes everything up to and including `t`; `t` before [`Chip::now`] does
    /// nothing.
    pub fn advance_to(&mut self, t: Instant) {
        if t < self.now {
            return;
        }
        if !self.in_reset {
            let limit = self.clock.tick_at_or_before(t);
            if self.tp_next_known {
                // The core's next tick (`Chip::kept_next_core`).
                let (engine_next, quiet) = self.engine.next_ticks_memo();
                let core = engine_next.min(self.tp_next);
                debug_assert_eq!(
                    core.get().map(|k| self.clock.instant(k)),
                    self.compute_next_core(),
                    "stale tp_next"
                );
                // Nothing due up to `t`: neither the core's next tick by `limit` (as the loop
                // below finds it) nor the serial port's next change (the port asked only when
                // the core has nothing due).
                let quiet_up_to_t =
                    core.after(limit) && self.serial_next_loud_event().is_none_or(|a| a > t);
                if quiet_up_to_t {
                    // Nothing due up to `t` but levels of untraced serial-port pins and a
                    // quiet cycle end.
                    self.serial_apply_pin_levels(t);
                    self.now = t;
                    if quiet <= limit && quiet != u64::MAX {
                        self.engine.end_quietly(quiet);
                    }
                    self.apply_quiet_events();
                    return;
                }
            }
            // Something is processed: the bound is found afresh.
            self.out_bound.set(None);
            // The next ticks as `Due`s (`u64::MAX` for none): minima and "due by `limit`"
            // without branches.
            let mut tp_next = if std::mem::take(&mut self.tp_next_known) {
                self.tp_next
            } else {
                crate::telegram_processor::next_due(self)
            };
            let mut quiet;
            let next_ticks = loop {
                debug_assert_eq!(
                    tp_next,
                    crate::mclk::Due::from_option(crate::telegram_processor::next_tick(self))
                );
                // The timing control goes first at equal ticks: a cycle start sends the
                // MST before the telegram processor's events of that tick. A quiet cycle end
                // (`quiet`, `u64::MAX` for none) is no event: it is applied before the
                // first step at or after it (spec-notes "Quiet cycle ends").
                let engine_next;
                (engine_next, quiet) = self.engine.next_ticks_memo();
                let engine_tick = engine_next.by(limit);
                let tp_tick = tp_next.by(limit);
                // The serial port's changes (exact instants) go before MCLK ticks at or
                // after them. They do not move the engine's or the processor's next tick,
                // so all of them before those ticks are applied in one go.
                // Their bound is found only when there is one (mostly none).
                if self.serial_next_loud_event().is_some() {
                    let bound = engine_tick.min(tp_tick).raw();
                    // tick_at_or_after(a) <= bound  <=>  a <= instant(bound): no division
                    // per check.
                    // No tick due (the loop's last turn): up to `t`, without the product.
                    let bound_at = if bound == u64::MAX {
                        t
                    } else {
                        self.clock.instant(bound).min(t)
                    };
                    self.serial_steps_up_to(bound_at, t);
                }
                // The timing control's tick when due and not after the processor's (none,
                // `u64::MAX`, is after every tick).
                match (engine_tick.get(), tp_tick.get()) {
                    (Some(e), _) if e <= tp_tick.raw() => {
                        let step = self.engine.step_tick(e);
                        let at = self.clock.instant(step.tick);
                        if step.changed != 0 {
                            self.emit(step.changed, at);
                        }
                        if step.cycle_started {
                            crate::telegram_processor::on_cycle_start(self, step.tick);
                            // The step settled every level; sending the MST and queueing
                            // the block leave the timing control alone: INT0 / INT1 only
                            // (debug-asserted against all levels).
                            let changed = self.engine.update_int_levels();
                            if changed != 0 {
                                self.emit(changed, at);
                            }
                            tp_next = crate::telegram_processor::next_due(self);
                        }
                        // Otherwise the step changed the timing control only: the
                        // processor's next tick stands.
                    }
                    (_, Some(first)) => {
                        let fifo = self.tp.fifo.snapshot();
                        let flags = self.engine.flags.word();
                        // The turn's constants, the chain check's among them (worked out
                        // once, not at every check).
                        let chain = Chain {
                            limit,
                            engine_tick,
                            flags,
                            fifo,
                            carried: Chain::carried_by(self),
                        };
                        let mut k = first;
                        loop {
                            if k >= quiet && quiet != u64::MAX {
                                // The memo's quiet end is none after it (`chains_to` hands
                                // that on).
                                self.engine.end_quietly(quiet);
                            }
                            #[cfg(debug_assertions)]
                            let general = (crate::telegram_processor::first_frame_tick(self)
                                == Some(k))
                            .then(|| self.clone());
                            // A received telegram's start and end may be one step
                            // (`Chain`): `k` is then its end.
                            #[cfg(debug_assertions)]
                            let started = k;
                            let next;
                            (k, next) = crate::telegram_processor::step(self, k, &chain);
                            #[cfg(debug_assertions)]
                            if k != started
                                && let Some(g) = general
                            {
                                self.check_joined_frame(g, started, k, &chain);
                            }
                            tp_next = match next {
                                Some(next) => next,
                                None => crate::telegram_processor::next_due(self),
                            };
                            // The processor's next event, when it comes before anything
                            // else this loop would take and the steps so far changed no pin
                            // level, is taken at once: the turn in between would only find
                            // it and settle nothing (spec-notes "Chained processor steps").
                            // The timing control's memo stands; a short cycle sync
                            // (`Engine::sync_cycle`, a slave's MST) put its new cycle's quiet
                            // end there.
                            match tp_next
                                .get()
                                .and_then(|e| self.chains_to(e, &chain).map(|q| (e, q)))
                            {
                                Some((e, q)) => {
                                    quiet = q;
                                    k = e;
                                }
                                None => break,
                            }
                        }
                        // Most steps leave the FIFOs alone, with no DMA pin traced: no call.
                        if !self.tp.fifo.unchanged_since(fifo) || self.dma_pins_traced() {
                            self.dma_changed(fifo.unwrap_or_default(), k);
                        }
                        // The engine's pin levels follow its interrupt flags, settings,
                        // timing outputs and watchdog. The processor reads the settings,
                        // raises flags, and changes the engine's timing only through
                        // `sync_cycle` (a slave's MST), which drops the engine's memo unless
                        // the new cycle moves no pin but INT0 / INT1: with neither, no level
                        // but those can have changed (most processor events).
                        if self.engine.next_memo.is_none() {
                            self.settle_tick(k);
                        } else if self.engine.flags.word() != flags {
                            // Flags only: INT0 / INT1 (the other levels stand).
                            let changed = self.engine.update_int_levels();
                            if changed != 0 {
                                let at = self.clock.instant(k);
                                self.emit(changed, at);
                            }
                        } else {
                            debug_assert_eq!(self.engine.levels, self.engine.compute_levels());
                        }
                        // Neither the processor nor the timing control has a tick due by
                        // `limit` (the usual end of an advance): the next turn would only
                        // apply the serial port's changes up to `t` and end; done here,
                        // without that turn (the timing control's next ticks and quiet cycle
                        // end found as that turn finds them first, memoised for it
                        // otherwise; spec-notes "Quiet cycle ends").
                        let (engine_next, q) = self.engine.next_ticks_memo();
                        // (`limit` is below u64::MAX but at an MCLK of 1 THz advanced
                        // to `Instant::MAX`: there, with neither tick, one turn more finds
                        // nothing due and ends the same way.)
                        if engine_next.after(limit) && tp_next.after(limit) {
                            quiet = q;
                            self.serial_steps_up_to(t, t);
                            break (engine_next, tp_next);
                        }
                    }
                    // Nothing changed since both were computed.
                    _ => break (engine_next, tp_next),
                }
            };
            if quiet <= limit && quiet != u64::MAX {
                self.engine.end_quietly(quiet);
            }
            // What is left up to `t` only sets levels of untraced pins (IDLE, REACTN).
            self.serial_apply_pin_levels(t);
            self.tp_next = next_ticks.1;
            self.tp_next_known = true;
            // The timing control's memo holds its next tick (`Chip::kept_next_core`).
            debug_assert!(
                self.engine
                    .next_memo
                    .is_some_and(|(next, _)| next == next_ticks.0),
                "the timing control's memo after an advance"
            );
            debug_assert_eq!(
                self.kept_next_core(),
                Some(self.compute_next_core()),
                "the core's next instant after an advance"
            );
            self.now = t;
            // The quiet events due by `limit` (spec-notes "Events nobody sees at once"), as
            // `Chip::apply_quiet_events` applies them but without asking `has_quiet_events`
            // first: with none pending this applies none.
            let pending =
                cfg!(debug_assertions) && crate::telegram_processor::has_quiet_events(self);
            if crate::telegram_processor::apply_quiet_events(self, limit) {
                debug_assert!(pending, "a quiet event applied that was not pending");
                self.quiet_events_applied();
            }
        }
        self.now = t;
    }

    /// Applies the serial port's loud changes due at or before `upto`, one instant at a time,
    /// in an advance to `t` (they go before MCLK ticks at or after them).
    #[inline]
    fn serial_steps_up_to(&mut self, upto: Instant, t: Instant) {
        while self.serial_next_loud_event().is_some_and(|a| a <= upto) && self.serial_step(t) {}
    }

    /// Whether [`Chip::advance_to`] may take the processor's next event at MCLK tick `e`
    /// right after its last step, skipping a turn of its loop: `e` is due by `limit` and
    /// before the timing control's next tick (`engine_tick`, first at equal ticks) and before
    /// any serial-port change the loop applies first, and the steps since the turn began
    /// (from interrupt flags `flags` and FIFO state `fifo`) changed no pin level: no flag an
    /// enabled interrupt output carries (`Settings::int_out_lo`, and the flags of 5H, WDOG
    /// and RSCEND unchanged), the timing control's memo kept (no `sync_cycle` dropped it),
    /// the FIFOs as they were with no DMA pin traced. The loop's settling after the last step
    /// then emits what the steps changed, at that step's tick, as the turns one by one would.
    /// The turn's state is `chain`'s (its constants worked out at the turn's start).
    /// Returns the memo's quiet cycle end (`u64::MAX` for none) when it may, `None`
    /// otherwise.
    #[inline]
    pub(crate) fn chains_to(&self, e: u64, chain: &Chain) -> Option<u64> {
        let Chain {
            limit,
            engine_tick,
            flags,
            fifo,
            carried,
        } = *chain;
        // Debug builds: the turn's constant and the kept switch are what they stand for.
        debug_assert_eq!(carried, Chain::carried_by(self), "stale Chain::carried");
        debug_assert_eq!(
            self.may_chain,
            Chain::may_chain_in(self),
            "stale Chip::may_chain"
        );
        // A kept memo still has the turn's next tick (a short cycle sync keeps it).
        debug_assert!(
            self.engine
                .next_memo
                .is_none_or(|(next, _)| next.by(limit) == engine_tick),
            "the timing control's next tick moved under a chain"
        );
        let (_, quiet) = self.engine.next_memo?;
        (self.may_chain
            && e <= limit
            && engine_tick.after(e)
            && (self.engine.flags.word() ^ flags) & carried == 0
            && self.tp.fifo.unchanged_since(fifo)
            && self
                .serial_next_loud_event()
                .is_none_or(|a| a > self.clock.instant(e)))
        .then_some(quiet)
    }

    /// Debug builds: a received telegram's start at `start` and end at `end` taken as one
    /// step (`Chain`) leave the chip as the general path does from `general` (the chip
    /// before that step): the start's step, the processor's next tick found to be `end`
    /// and chained to (no quiet cycle end before it), the end's step.
    #[cfg(debug_assertions)]
    fn check_joined_frame(&self, mut general: Chip, start: u64, end: u64, chain: &Chain) {
        // The settings are the same for both steps (no bus write between them).
        let none = Chain::none(&general);
        let (last, _) = crate::telegram_processor::step(&mut general, start, &none);
        debug_assert_eq!(last, start, "a step that may not join took two");
        debug_assert_eq!(
            crate::telegram_processor::next_tick(&general),
            Some(end),
            "a joined frame's end is the processor's next tick"
        );
        debug_assert!(
            chain.allows(&general, end),
            "a joined frame's end is chained to"
        );
        let (last, _) = crate::telegram_processor::step(&mut general, end, &none);
        debug_assert_eq!(last, end);
        debug_assert_eq!(
            format!("{general:?}"),
            format!("{self:?}"),
            "a received telegram's start and end in one step"
        );
    }

    /// [`Chip::advance_to`] for an instant before [`Chip::next_output_bound`] (a simulation
    /// running the chip ahead between its inputs): the telegram processor's part of that bound,
    /// found before, still holds after the advance, so it is kept instead of being walked for
    /// again. It holds because the processor walks its headers in list order (410B §4.2.1
    /// PT) and the walk that found the bound read what the processor reads on its way there,
    /// unless the processor itself wrote those words meanwhile (receive data or a service
    /// container laid over headers ahead: then the bound is found afresh) or ended the block
    /// early with a programming error (17H PROGERR_FL: likewise), or a block ended or began
    /// (a bound found while the block could still store was the conservative one, its end:
    /// found afresh, it may lie later). Debug builds check the kept bound against a fresh
    /// walk.
    pub fn advance_before_output(&mut self, t: Instant) {
        let memo = self.out_bound.get();
        let irregular = self.tp.irregular;
        let block = self.tp.block.map(|b| (b.block, b.ref_tick));
        self.tp.walk_overwritten.set(false);
        self.advance_to(t);
        if let Some(bound) = memo
            && !self.tp.walk_overwritten.get()
            && self.tp.irregular == irregular
            && self.tp.block.map(|b| (b.block, b.ref_tick)) == block
            && bound.is_none_or(|tick| self.clock.instant(tick) > t)
        {
            debug_assert_eq!(bound, self.output_bound_tick(), "kept out_bound");
            self.out_bound.set(memo);
        }
    }

    /// The instant of the next MCLK tick at which the engine or the telegram processor has
    /// something to do.
    fn compute_next_core(&self) -> Option<Instant> {
        let tick = match (
            self.engine.next_tick(),
            crate::telegram_processor::next_tick(self),
        ) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        // A tick of `u64::MAX` is none (`mclk::Due`: only a saturated sum at a 1 THz MCLK).
        crate::mclk::Due::from_option(tick)
            .get()
            .map(|k| self.clock.instant(k))
    }

    /// The next instant at which the engine, the telegram processor or the serial port
    /// has something to do (what [`Chip::advance_to`] would process).
    pub(crate) fn next_internal(&self) -> Option<Instant> {
        let core = match self.kept_next_core() {
            Some(kept) => kept,
            None => self.compute_next_core(),
        };
        earliest(core, self.serial_next_loud_event())
    }

    /// The instant of the next MCLK tick at which the timing control, the watchdog or the
    /// telegram processor has something to do, from what is kept (`Some`): the processor's
    /// next tick (`tp_next`) and the timing control's (its memo, or found afresh); `None`
    /// when the processor's is not kept. Debug builds compare it with the computation.
    fn kept_next_core(&self) -> Option<Option<Instant>> {
        if !self.tp_next_known {
            return None;
        }
        let tp = self.tp_next;
        let engine = match self.engine.next_memo {
            Some((next, _)) => next,
            None => Due::from_option(self.engine.next_tick()),
        };
        let core = engine.min(tp).get().map(|k| self.clock.instant(k));
        debug_assert_eq!(core, self.compute_next_core(), "stale tp_next");
        Some(core)
    }

    /// The telegram processor's queue of received frames or its frame in progress changed
    /// outside its own steps (a frame taken back, or taken before its end): its next tick,
    /// the next core instant and the output bound are found afresh.
    pub(crate) fn rx_queue_changed(&mut self) {
        self.tp_next_known = false;
        self.out_bound.set(None);
    }

    /// Something from outside changed the state: the cached next instant of the engine and
    /// the telegram processor is recomputed at the next advance.
    pub(crate) fn touched(&mut self) {
        self.tp_next_known = false;
        self.engine.next_memo = None;
        self.tp.tx_ahead.set(None);
        self.tp.block_ahead.set(None);
        self.out_bound.set(None);
    }

    /// The next instant after [`Chip::now`] at which something observable happens: a
    /// traced pin or an interrupt output (INT0, INT1, WDOGN) changes level, or the
    /// watchdog expires. `None` when nothing ever will without a bus access or an input.
    pub fn next_deadline(&self) -> Option<Instant> {
        if self.in_reset {
            return None;
        }
        let core = crate::deadline::next_deadline(self);
        match (core, self.serial_next_observable()) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Applies the telegram processor's events up to now that were no events of their own
    /// (no interrupt output shows them: `telegram_processor::apply_quiet_events`), at the end
    /// of every advance: whatever comes next (a bus access, a reset, a line input or a
    /// CYC_CLK edge at a tick the chip has reached) finds the state these events leave, as
    /// when they are events.
    /// (The end of [`Chip::advance_to`]'s loop applies them itself, with its last tick.)
    fn apply_quiet_events(&mut self) {
        if self.in_reset || !crate::telegram_processor::has_quiet_events(self) {
            return;
        }
        let tick = self.clock.tick_at_or_before(self.now);
        if crate::telegram_processor::apply_quiet_events(self, tick) {
            self.quiet_events_applied();
        }
    }

    /// After quiet events were applied: the processor's next tick stands (they were not in
    /// it), the output bound may not (the block may have ended). The walk ahead stands: a
    /// block's end leaves the list as it was (the end marker's TEND is a status word), and a
    /// later block finds its headers where this one did (`output_bound::TxAhead`).
    fn quiet_events_applied(&mut self) {
        self.out_bound.set(None);
    }

    /// The earliest instant after which the chip may change on its own (without a line
    /// input, a pin input or a bus access): its next internal event (timing control,
    /// watchdog, telegram processor, a serial-port change of FIBBR, RDIST or a traced pin)
    /// or the start of an output segment not yet released. `None` when nothing is
    /// scheduled. Level changes of untraced IDLE / REACTN pins are not events: the chip
    /// applies them when its time passes them.
    ///
    /// A simulation may use it as the lookahead of a conservative event loop: nothing this
    /// chip sends starts before this instant, so a chip `d` down the fibre can be advanced
    /// to just before `next_event_at() + d` without missing an input.
    pub fn next_event_at(&self) -> Option<Instant> {
        let output = self.serial.next_output_at();
        if self.in_reset {
            return output;
        }
        earliest(self.next_internal(), output)
    }

    /// [`Chip::next_event_at`] without the output: the chip's next internal event (timing
    /// control, watchdog, telegram processor, a serial-port change of FIBBR, RDIST or a
    /// traced pin), `None` in reset or when nothing is scheduled. With
    /// [`Chip::next_line_output_except`] a simulation can leave out the output segments it
    /// does not need to be woken for.
    pub fn next_internal_event_at(&self) -> Option<Instant> {
        if self.in_reset {
            return None;
        }
        self.next_internal()
    }

    /// A lower bound of the next instant at which the chip may do anything a simulation
    /// must see at once: start a telegram of its own, or change a pin its host or a trace
    /// could notice. With no pin traced, both interrupt outputs disabled (03H ENINT0/1,
    /// 410B §4.1) and the watchdog stopped, that is the telegram processor's next possible
    /// transmission (a slave's block starts with the MST it receives, a master's with its
    /// cycle start; 410B §4.2.1 TRT) or a serial-port change of FIBBR / RDIST; otherwise
    /// it is [`Chip::next_internal_event_at`]. Events before it (receive telegrams, windows,
    /// status) are processed when the chip is next advanced, with the same results.
    /// Output already queued is not part of it ([`Chip::next_line_output_at`]).
    pub fn next_output_bound(&self) -> Option<Instant> {
        if self.in_reset {
            return None;
        }
        let internal = self.next_internal()?;
        let s = &self.engine.s;
        if !self.traced.is_empty() || s.enint[0] || s.enint[1] || self.engine.wd.running {
            return Some(internal);
        }
        let tick = match self.out_bound.get() {
            // Found under the layout proof, which stands while it does (both go with a
            // host write; the blocks change only with a register write).
            Some(memo) => {
                debug_assert_eq!(memo, self.output_bound_tick(), "stale out_bound");
                debug_assert!(self.layout_proof(), "out_bound without the layout proof");
                memo
            }
            // The processor's own writes may rewrite its lists: nothing is promised.
            None if !self.layout_proof() => return Some(internal),
            None => {
                self.tp.walk_held.set(false);
                let tick = self.output_bound_tick();
                // A held block walk (its start, while the processor may still rewrite the
                // list) is not remembered: once the block starts, the walk is made and the
                // bound may lie later (spec-notes "Held block walks").
                if !self.tp.walk_held.get() {
                    self.out_bound.set(Some(tick));
                }
                tick
            }
        };
        let bound = earliest(
            tick.map(|k| self.clock.instant(k)),
            self.serial_next_loud_event(),
        )?;
        Some(bound.max(internal))
    }

    /// The earliest instant at which the chip may release line output whatever line input
    /// reaches it meanwhile; `None` when that is not promised. `Some(Instant::MAX)`: no
    /// output ahead.
    ///
    /// Promised for a chip that is not a SERCOS slave (a slave's block starts with the MST
    /// it receives, 410B §4.2.1 TRT) with its watchdog stopped, its receiver's copies not
    /// released (1H.3 REPON, [`Chip::set_forward_output`]) and the layout proof
    /// (`telegram_processor::layout`: its own writes cannot rewrite its header lists): then a
    /// received telegram only stores data and status, and the chip's next output is its next
    /// own telegram or cycle start (the telegram-processor part of
    /// [`Chip::next_output_bound`]) or an output it has already queued. A simulation may run
    /// the chips its output reaches up to that instant (plus the line's delay) without
    /// waiting for it.
    pub fn next_output_for_any_input(&self) -> Option<Instant> {
        if self.in_reset
            || self.engine.s.is_sercos_slave()
            || self.engine.wd.running
            || self.serial.output_follows_input()
            || !self.layout_proof()
        {
            return None;
        }
        self.tp.walk_held.set(false);
        let tx = crate::telegram_processor::next_tx_bound(self);
        // The same walk is the telegram-processor part of `Chip::next_output_bound` with
        // the timing control's next tick (`output_bound_tick`, 410B §4.1 0CH: a non-slave's
        // cycle start sends the MST or starts a block): remembered for it, as it remembers
        // it (under the layout proof, found above; not a held walk's).
        if self.out_bound.get().is_none() && !self.tp.walk_held.get() {
            let engine = match self.engine.next_memo {
                Some((next, _)) => next.get(),
                None => self.engine.next_tick(),
            };
            let bound = earliest_tick(tx, engine);
            debug_assert_eq!(bound, self.output_bound_tick(), "out_bound for any input");
            self.out_bound.set(Some(bound));
        }
        // 410B §4.1 0CH: the next cycle start sends the MST (the timing control's other
        // events in between only move pins).
        let tick = earliest_tick(tx, self.engine.next_cycle_start());
        let own = tick.map_or(Instant::MAX, |k| self.clock.instant(k));
        // What it has queued, but for the filler its last telegram implies (it sends
        // nothing, `Chip::set_implied_filler`).
        let queued = self.next_line_output_unexpected();
        Some(queued.map_or(own, |q| own.min(q)))
    }

    /// Whether the telegram processor's own writes leave its header lists as they are
    /// (`telegram_processor::layout`): found once, kept until a host write to a word the
    /// walks read.
    #[inline]
    pub(crate) fn layout_proof(&self) -> bool {
        if let Some((proof, 0b11)) = self.layout.get() {
            // Both blocks' lists covered: whichever may run.
            debug_assert_eq!(proof, self.fresh_layout_proof(0b11), "kept layout proof");
            return proof;
        }
        self.layout_proof_for_blocks()
    }

    /// [`Chip::layout_proof`] when the proof kept does not cover both blocks' lists.
    #[inline(never)]
    fn layout_proof_for_blocks(&self) -> bool {
        let memo = self.layout.get();
        let blocks = crate::telegram_processor::possible_blocks(self);
        if let Some((proof, proved)) = memo
            && proved & blocks == blocks
        {
            debug_assert_eq!(proof, self.fresh_layout_proof(proved), "kept layout proof");
            return proof;
        }
        // Both lists if they allow it (then no block the registers choose later needs a
        // proof of its own), else those that may run now.
        let both = crate::telegram_processor::prove_layout(self, 0b11);
        let (proof, proved) = if both.holds {
            (both, 0b11)
        } else {
            (
                crate::telegram_processor::prove_layout(self, blocks),
                blocks,
            )
        };
        if !proof.lasting {
            // Refused while a header the processor holds is not the RAM's: found afresh
            // until it is (spec-notes "The layout proof and the headers the processor
            // holds").
            self.set_layout(None);
            return false;
        }
        self.set_layout(Some((proof.holds, proved)));
        *self.layout_read.borrow_mut() = proof.read;
        proof.holds
    }

    /// Sets the layout proof, found or dropped: every change gets a new number
    /// ([`Chip::layout_epoch`]).
    pub(crate) fn set_layout(&self, layout: Option<(bool, u8)>) {
        self.layout.set(layout);
        self.layout_epoch
            .set(self.layout_epoch.get().wrapping_add(1));
    }

    /// The layout proof for the lists of `blocks` made afresh (debug builds check a kept
    /// one against it).
    fn fresh_layout_proof(&self, blocks: u8) -> bool {
        crate::telegram_processor::prove_layout(self, blocks).holds
    }

    /// The telegram-processor part of [`Chip::next_output_bound`]: the MCLK tick of the
    /// next possible own telegram, and for a master also its next cycle start.
    fn output_bound_tick(&self) -> Option<u64> {
        let tick = crate::telegram_processor::next_tx_bound(self);
        if self.engine.s.is_sercos_slave() {
            return tick;
        }
        // 410B §4.1 0CH: a master's (or a non-SERCOS) cycle start sends the MST or starts
        // a block.
        match (tick, self.engine.next_tick()) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Whether INT0 and INT1 request an interrupt now, whatever the pins' polarity: the bits
    /// 3H.0 INTFL0 and 3H.3 INTFL1 a read of 3H would give (410B §4.1), without the rest
    /// of that register.
    pub fn interrupt_requests(&self) -> (bool, bool) {
        let e = &self.engine;
        (e.flags.request(&e.s, 0), e.flags.request(&e.s, 1))
    }

    /// What a bus read of the register at word address `address` gives now
    /// ([`SerconBus::read_register`]), without its effect and without a bus access: a read of
    /// RFIFO (27H) shows the oldest word of the receive FIFO instead of taking it; any other
    /// register reads the same either way (410B §4.1: reads change nothing but RFIFO). For a
    /// simulation or a test that looks at a chip without being its host.
    pub fn peek_register(&self, address: u8) -> u16 {
        crate::register_access::peek(self, address)
    }

    /// Chooses which pins produce [`PinEvent`]s from now on.
    pub fn set_traced_pins(&mut self, pins: PinSet) {
        self.touched();
        self.traced = pins;
        self.may_chain = Chain::may_chain_in(self);
        self.serial_pins_traced =
            pins.contains(Pin::Idle) || pins.contains(Pin::TxD) || pins.contains(Pin::Reactn);
        self.serial.set_pins_loud(self.serial_pins_traced);
    }

    /// Whether [`Chip::advance_to`] may take the telegram processor's next event right
    /// after its previous one, without a turn of its event loop in between, when nothing
    /// can come between them and the first changed no pin level (on after [`Chip::new`]).
    /// Off, every event gets its own turn: the two read and emit the same (a switch for
    /// comparing them; spec-notes "Chained processor steps").
    pub fn set_chained_steps(&mut self, on: bool) {
        self.chained_steps = on;
        self.may_chain = Chain::may_chain_in(self);
    }

    /// Whether a quiet end of a communication cycle — one that leaves nothing but the cycle
    /// state changed: no flag, no pulse, no next cycle, typically a slave's cycle ending on
    /// the tick its next MST synchronises it — is applied where the state is next read
    /// instead of being an event of the timing control (on after [`Chip::new`]). Off, every
    /// cycle end is an event: the two read and emit the same (a switch for comparing them;
    /// spec-notes "Quiet cycle ends").
    pub fn set_quiet_cycle_ends(&mut self, on: bool) {
        self.touched();
        self.engine.quiet_ends = on;
    }

    /// Whether a slave's cycle synchronised by an MST after its previous cycle ended (on an
    /// intact ring, quietly on the MST's own tick) is started the short way, keeping what the
    /// chip remembers of the timing control's next ticks when the start moves no pin but
    /// INT0 / INT1 (on after [`Chip::new`]). Off, every MST starts the cycle the general way:
    /// the two read and emit the same (a switch for comparing them; spec-notes "Short cycle
    /// syncs").
    pub fn set_short_cycle_syncs(&mut self, on: bool) {
        self.touched();
        self.engine.short_syncs = on;
    }

    /// The pins currently traced.
    pub fn traced_pins(&self) -> PinSet {
        self.traced
    }

    /// Moves the pin events recorded so far (time-ordered) to the end of `out`.
    pub fn drain_pin_events(&mut self, out: &mut Vec<PinEvent>) {
        // A DMA pulse's falling edge is recorded one MCLK period ahead: keep the promise of
        // time order (stable, so same-instant events keep their order).
        if !self.events.is_sorted_by_key(|e| e.at) {
            self.events.sort_by_key(|e| e.at);
        }
        out.append(&mut self.events);
    }

    /// The electrical level of an output pin at [`Chip::now`]. Pins this model does not
    /// drive yet (IDLE, REACTN, L_ERRN, DMA requests, TxD) read their inactive level.
    pub fn pin_level(&self, pin: Pin) -> bool {
        match DRIVEN.iter().position(|p| *p == pin) {
            Some(i) => self.engine.levels.get(i).copied().unwrap_or(false),
            // 410B §2 DMAREQR/DMAREQT, active high; static, or pulses with 1H.14 DMAMODE.
            None if pin == Pin::DmaReqR => {
                self.dma_request(self.tp.fifo.dmareqr(), self.tp.fifo.pulse_r)
            }
            None if pin == Pin::DmaReqT => {
                self.dma_request(self.tp.fifo.dmareqt(), self.tp.fifo.pulse_t)
            }
            // 410B §2: IDLE, REACTN, L_ERRN (active low), driven by the serial port.
            None => self.serial_pin_level(pin).unwrap_or(true),
        }
    }

    /// The level of a DMA request pin whose request is `active`: static (1H.14 DMAMODE = 0)
    /// or one MCLK period high from the pulse at tick `pulse` (DMAMODE = 1).
    // 410B §4.1 1H.14 DMAMODE: "DMAREQR/DMAREQT are static signals" / "are pulses".
    fn dma_request(&self, active: bool, pulse: Option<u64>) -> bool {
        if !self.dma_pulsed() {
            return active;
        }
        let now = self.clock.tick_at_or_before(self.now);
        active && pulse == Some(now)
    }

    /// 410B §4.1 1H.14 DMAMODE = 1.
    pub(crate) fn dma_pulsed(&self) -> bool {
        self.engine.regs.stored(sercon_regs::Register::Ctrl1) & (1 << 14) != 0
    }

    /// After the FIFOs changed from `before` at MCLK tick `tick`: the pulses (DMAMODE = 1).
    pub(crate) fn dma_changed(&mut self, before: crate::telegram_processor::FifoState, tick: u64) {
        self.tp.fifo.pulse_after(before, tick);
        self.trace_dma_pins(tick);
    }

    /// Whether DMAREQR or DMAREQT is traced.
    fn dma_pins_traced(&self) -> bool {
        self.traced.contains(Pin::DmaReqR) || self.traced.contains(Pin::DmaReqT)
    }

    /// Pin events of DMAREQR / DMAREQT at MCLK tick `tick`, for the traced ones: the level in
    /// static mode, a pulse of one MCLK period in pulsed mode (410B §2 pins 38, 39, active
    /// high; §4.1 1H.14 DMAMODE; spec-notes "Pulsed DMA requests").
    fn trace_dma_pins(&mut self, tick: u64) {
        if !self.dma_pins_traced() {
            // Nothing to record (the common case: asked after every processor event).
            return;
        }
        let pulsed = self.dma_pulsed();
        let fifo = &self.tp.fifo;
        let pins = [
            (Pin::DmaReqR, fifo.dmareqr(), fifo.pulse_r),
            (Pin::DmaReqT, fifo.dmareqt(), fifo.pulse_t),
        ];
        for (i, (pin, active, pulse)) in pins.into_iter().enumerate() {
            let Some(trace) = self.dma_trace.get_mut(i) else {
                continue;
            };
            if !self.traced.contains(pin) {
                continue;
            }
            if pulsed {
                if active && pulse == Some(tick) && trace.1 != Some(tick) {
                    trace.1 = Some(tick);
                    let rise = self.clock.instant(tick);
                    let fall = self.clock.instant(tick.saturating_add(1));
                    self.events.push(PinEvent {
                        at: rise,
                        pin,
                        level: true,
                    });
                    self.events.push(PinEvent {
                        at: fall,
                        pin,
                        level: false,
                    });
                }
            } else if trace.0 != active {
                trace.0 = active;
                let at = self.clock.instant(tick);
                self.events.push(PinEvent {
                    at,
                    pin,
                    level: active,
                });
            }
        }
    }

    /// Records a change of the driven pins in `changed` at `at` for the traced ones.
    pub(crate) fn emit(&mut self, changed: u8, at: Instant) {
        for (i, pin) in DRIVEN.iter().enumerate() {
            if changed & (1 << i) != 0 && self.traced.contains(*pin) {
                let level = self.engine.levels.get(i).copied().unwrap_or(false);
                self.events.push(PinEvent {
                    at,
                    pin: *pin,
                    level,
                });
            }
        }
    }

    /// Emits the pin changes a state change at MCLK tick `tick` caused.
    fn settle_tick(&mut self, tick: u64) {
        let changed = self.engine.update_levels();
        if changed != 0 {
            let at = self.clock.instant(tick);
            self.emit(changed, at);
        }
    }

    /// The MCLK tick at which an action requested at [`Chip::now`] takes effect: the
    /// chip samples its inputs on the next MCLK edge.
    pub(crate) fn action_tick(&self) -> u64 {
        self.clock.tick_at_or_after(self.now)
    }

    /// After the state changed at `now`: emits the resulting pin changes at `now` and
    /// processes anything now due at or before `now`.
    pub(crate) fn settle(&mut self) {
        self.touched();
        let changed = self.engine.update_levels();
        if changed != 0 {
            self.emit(changed, self.now);
        }
        let now = self.now;
        self.advance_to(now);
    }

    /// Sets the level of input CYC_CLK at [`Chip::now`]; the selected edge triggers
    /// timing control when ENCYCCLK = 1.
    // 410B §4.1 0CH.7 CYC_CLK, 0CH.8 ENCYCCLK, 0CH.9 POLCYCCLK (0 = rising edge).
    pub fn set_cyc_clk(&mut self, level: bool) {
        if level == self.cyc_clk {
            return;
        }
        self.touched();
        self.cyc_clk = level;
        if self.in_reset {
            return;
        }
        let s = self.engine.s;
        let rising = level;
        if s.encycclk && rising != s.polcycclk && !s.is_sercos_slave() {
            let at = self.action_tick();
            self.engine.trigger(at);
            self.settle();
        }
    }

    /// Sets the level of the reset input RSTN at [`Chip::now`]: low holds the chip in
    /// reset, the rising edge releases it.
    pub fn set_rstn(&mut self, level: bool) {
        self.touched();
        crate::reset::set_rstn(self, level);
    }
}

impl SerconBus for Chip {
    fn read_register(&mut self, address: u8) -> u16 {
        // Only a read of RFIFO changes the chip (`register_access::read` then drops what
        // the chip remembers of its next events); any other read leaves it as it was.
        crate::register_access::read(self, address)
    }

    fn write_register(&mut self, address: u8, value: u16) {
        self.touched();
        crate::register_access::write(self, address, value);
    }

    fn read_ram(&mut self, address: u16) -> u16 {
        // 410B §2: A10-1 select the RAM word (816 §2.5: A11-1); higher bits are not decoded.
        let mask = self.cfg.variant.ram_address_mask();
        self.ram
            .get(usize::from(address & mask))
            .copied()
            .unwrap_or(0)
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        if self.in_reset {
            return;
        }
        let mask = self.cfg.variant.ram_address_mask();
        if let Some(word) = self.ram.get_mut(usize::from(address & mask)) {
            *word = value;
        }
        // The layout proof, made or refused, stands unless a word it read changed (a refusal
        // was decided by the words read up to it).
        if self.layout_read.borrow().any(u32::from(address & mask), 1) {
            self.set_layout(None);
        }
        // A header ahead may have changed: the output bound's remembered walks go (the
        // processor's next tick does not read the RAM; found by fuzz target bus_sequence).
        self.tp.tx_ahead.set(None);
        self.tp.block_ahead.set(None);
        self.out_bound.set(None);
    }
}

/// The earlier of two optional MCLK ticks.
#[inline]
fn earliest_tick(a: Option<u64>, b: Option<u64>) -> Option<u64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The earlier of two optional instants.
pub(crate) fn earliest(a: Option<Instant>, b: Option<Instant>) -> Option<Instant> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // `Chip::may_chain` is kept where the host changes what it stands for: chained steps
    // switched, DMAREQR / DMAREQT traced or not (410B §2 pins 38, 39). Fails when either
    // setter leaves it as it was.
    #[test]
    fn may_chain_follows_the_switch_and_the_traced_dma_pins() {
        let mut chip = Chip::new(ChipConfig::sercon410b());
        assert!(chip.may_chain);
        for on in [true, false, true] {
            chip.set_chained_steps(on);
            assert_eq!(chip.may_chain, Chain::may_chain_in(&chip));
            assert_eq!(chip.may_chain, on);
            for pins in [
                PinSet::of(&[Pin::DmaReqR]),
                PinSet::of(&[Pin::Int0]),
                PinSet::of(&[Pin::DmaReqT]),
                PinSet::EMPTY,
            ] {
                chip.set_traced_pins(pins);
                assert_eq!(chip.may_chain, Chain::may_chain_in(&chip));
                let dma = pins.contains(Pin::DmaReqR) || pins.contains(Pin::DmaReqT);
                assert_eq!(chip.may_chain, on && !dma);
            }
        }
    }
}
