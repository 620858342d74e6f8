//! The chip's time-driven state and its event loop: everything that changes with time,
//! advanced from event to event (never microsecond by microsecond).

use std::sync::Arc;

use sercon_regs::{Register, Variant};

use crate::Straps;
use crate::cycle::CycleState;
use crate::cycle_plan::CyclePlan;
use crate::interrupts::Flags;
use crate::pins::Pin;
use crate::register_file::RegisterFile;
use crate::settings::Settings;
use crate::time_base::Predivider;
use crate::timing_outputs::TimingOutputs;
use crate::watchdog::Watchdog;

/// The output pins the engine drives, in the order of [`Levels`].
pub(crate) const DRIVEN: [Pin; 5] = [Pin::Int0, Pin::Int1, Pin::ConClk, Pin::DivClk, Pin::Wdogn];

/// Electrical levels of the [`DRIVEN`] pins.
pub(crate) type Levels = [bool; 5];

/// What one step of the event loop did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Step {
    /// The MCLK tick processed.
    pub(crate) tick: u64,
    /// Which of the [`DRIVEN`] pins changed level (bit i = `DRIVEN[i]`).
    pub(crate) changed: u8,
    /// The watchdog expired at this tick.
    pub(crate) expired: bool,
    /// A communication cycle started at this tick.
    pub(crate) cycle_started: bool,
}

/// The whole time-dependent state of one chip except its RAM.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Engine {
    pub(crate) variant: Variant,
    pub(crate) regs: RegisterFile,
    pub(crate) s: Settings,
    pub(crate) pre: Predivider,
    pub(crate) cycle: CycleState,
    pub(crate) plan: Arc<CyclePlan>,
    /// `(TCNTST, length)` the plan was built for; `None` when settings changed since.
    pub(crate) plan_key: Option<(u16, u64)>,
    pub(crate) flags: Flags,
    pub(crate) outputs: TimingOutputs,
    pub(crate) wd: Watchdog,
    /// 410B §4.1 12H TCNTLT: TCNT latched by RDCNT.
    pub(crate) tcntlt: u16,
    pub(crate) levels: Levels,
    /// [`Engine::next_tick`] (as a [`crate::mclk::Due`], the event loop's form) and
    /// [`Engine::quiet_end`] (`u64::MAX` for none) as last computed; `None` after a change
    /// that may move them (a step, a cycle synchronised by an MST, anything from outside the
    /// chip).
    pub(crate) next_memo: Option<(crate::mclk::Due, u64)>,
    /// A quiet cycle end is no event of its own ([`Engine::quiet_end`]); off, every end is
    /// a step (a switch for comparing both, `Chip::set_quiet_cycle_ends`).
    pub(crate) quiet_ends: bool,
    /// A slave's cycle synchronised by an MST after its previous cycle ended takes the short
    /// way ([`Engine::sync_cycle`]); off, always the general one (a switch for comparing
    /// both, `Chip::set_short_cycle_syncs`).
    pub(crate) short_syncs: bool,
}

impl Engine {
    /// The state right after a reset released at tick `at`.
    // 410B §4.1: reset values; the predivider starts from MCLKST (spec-notes).
    pub(crate) fn after_reset(variant: Variant, straps: &Straps, at: u64) -> Self {
        let regs = RegisterFile::after_reset(variant, straps);
        let s = Settings::decode(&regs, variant);
        let mut engine = Engine {
            variant,
            regs,
            s,
            pre: Predivider::loaded(at, s.mclkdiv, s.mclkst, s.mclkdiv_bits),
            cycle: CycleState::default(),
            plan: Arc::new(CyclePlan::default()),
            plan_key: None,
            flags: Flags::default(),
            outputs: TimingOutputs::default(),
            wd: Watchdog::default(),
            tcntlt: 0,
            levels: [false; 5],
            next_memo: None,
            quiet_ends: true,
            short_syncs: true,
        };
        engine.levels = engine.compute_levels();
        engine
    }

    /// The levels of the driven pins as the state says now.
    pub(crate) fn compute_levels(&self) -> Levels {
        [
            self.flags.pin_level(&self.s, 0),
            self.flags.pin_level(&self.s, 1),
            self.outputs.conclk_level(&self.s),
            self.outputs.divclk_level(&self.s),
            self.wd.wdogn_level(),
        ]
    }

    /// Recomputes the levels; returns the bit mask of pins that changed.
    pub(crate) fn update_levels(&mut self) -> u8 {
        let new = self.compute_levels();
        let changed = mask(&self.levels) ^ mask(&new);
        self.levels = new;
        changed
    }

    /// [`Engine::update_levels`] after a change of the interrupt flags alone: INT0 and INT1
    /// follow the flags (410B §4.1 3H–9H), CONCLK, DIVCLK and WDOGN the timing outputs and
    /// the watchdog, which the flags do not move. Returns the bit mask of pins that changed.
    pub(crate) fn update_int_levels(&mut self) -> u8 {
        let mut changed = 0;
        for (n, level) in self.levels.iter_mut().take(2).enumerate() {
            let new = self.flags.pin_level(&self.s, n);
            if *level != new {
                *level = new;
                changed |= 1 << n;
            }
        }
        debug_assert_eq!(self.levels, self.compute_levels());
        changed
    }

    /// Recomputes the levels after a replacement of the state; returns the bit mask of
    /// pins whose level differs from `before`.
    pub(crate) fn update_levels_from(&mut self, before: Levels) -> u8 {
        self.levels = before;
        self.update_levels()
    }

    /// The next tick at which anything is scheduled (a quiet cycle end is not,
    /// [`Engine::quiet_end`]).
    pub(crate) fn next_tick(&self) -> Option<u64> {
        self.next_ticks().0
    }

    /// [`Engine::next_tick`] and [`Engine::quiet_end`] (`u64::MAX` for none).
    pub(crate) fn next_ticks(&self) -> (Option<u64>, u64) {
        let (c, quiet) = self.cycle_ticks();
        let w = self.wd.next_tick();
        let next = match (c, w) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        (next, quiet.unwrap_or(u64::MAX))
    }

    /// [`Engine::next_ticks`] with the next tick as a [`crate::mclk::Due`].
    pub(crate) fn next_ticks_due(&self) -> (crate::mclk::Due, u64) {
        let (next, quiet) = self.next_ticks();
        (crate::mclk::Due::from_option(next), quiet)
    }

    /// [`Engine::next_ticks_due`], remembered until the state changes (the event loop asks
    /// on every turn; most turns are the telegram processor's, which leave both alone).
    pub(crate) fn next_ticks_memo(&mut self) -> (crate::mclk::Due, u64) {
        if let Some(memo) = self.next_memo {
            debug_assert_eq!(memo, self.next_ticks_due(), "stale engine next tick");
            return memo;
        }
        let memo = self.next_ticks_due();
        self.next_memo = Some(memo);
        memo
    }

    /// Processes the next scheduled tick if it is at or before `limit`.
    pub(crate) fn step(&mut self, limit: u64) -> Option<Step> {
        let tick = self.next_tick()?;
        if tick > limit {
            return None;
        }
        Some(self.step_tick(tick))
    }

    /// Processes tick `tick`, which must be [`Engine::next_tick`]; a quiet cycle end before
    /// it ([`Engine::quiet_end`]) first.
    pub(crate) fn step_tick(&mut self, tick: u64) -> Step {
        let quiet = match self.next_memo {
            Some((_, quiet)) => quiet,
            None => self.quiet_end().unwrap_or(u64::MAX),
        };
        if quiet < tick {
            // At `tick` itself the cycle tick below ends the cycle the same way.
            self.end_quietly(quiet);
        }
        self.step_general(tick)
    }

    /// [`Engine::step_tick`] without the quiet end first: every event at `tick`, the cycle
    /// machinery's as scheduled in full.
    pub(crate) fn step_general(&mut self, tick: u64) -> Step {
        self.next_memo = None;
        // Cycle events first: an MST start at the expiry tick retriggers the watchdog
        // in time (spec-notes "same-tick order").
        let cycle_started = self.process_cycle_tick(tick);
        let release = self
            .pre
            .tick_after(tick)
            .saturating_add(2 * self.pre.period());
        let expired = self.wd.expire_at(tick, release);
        if expired {
            self.watchdog_expired();
        }
        self.wd.release_at(tick);
        let changed = self.update_levels();
        Step {
            tick,
            changed,
            expired,
            cycle_started,
        }
    }

    /// The effects of the watchdog going active.
    // 816 §2.6: "the interrupt flag INT_WDOG is set"; §2.6.2: ENTMT := 0, PHAS0 := 0H.
    fn watchdog_expired(&mut self) {
        self.flags.set_wdog(true);
        let c3 = self.regs.stored(Register::Ctrl3);
        self.regs.set_stored(Register::Ctrl3, c3 & !(1 << 8));
        let phas = self.regs.stored(Register::Phas);
        self.regs.set_stored(Register::Phas, phas & 0xFF00);
        self.s = Settings::decode(&self.regs, self.variant);
    }

    /// Bits of `register` a bus write may not change right now.
    // 816 §2.6.2: "These register bits can be programmed again by the bus interface only
    // after the status bit INT_WDOG is cleared."
    pub(crate) fn locked_bits(&self, register: Option<Register>) -> u16 {
        match register {
            Some(Register::Ctrl3) if self.flags.wdog() => 1 << 8,
            Some(Register::Phas) if self.flags.wdog() => 0x00FF,
            _ => 0,
        }
    }
}

/// The levels as a bit mask (bit `i` = pin `i` of [`DRIVEN`] high).
fn mask(levels: &Levels) -> u8 {
    levels
        .iter()
        .enumerate()
        .fold(0, |m, (i, l)| m | (u8::from(*l) << i))
}
