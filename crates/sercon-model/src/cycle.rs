//! Communication cycles: start by CYCSTART / CYC_CLK after TCYCSTART, NCYC cycles of
//! TSCYC0/1 µs, transmission-block selection, COMACT/COMBLK and their interrupts
//! (410B §4.1 3H.6-7, 4H.2-4, 0CH, 0FH–14H).

use std::sync::Arc;

use crate::cycle_plan::{CyclePlan, next_match};
use crate::engine::Engine;
use crate::interrupts::{INT_COMBLK0, INT_COMBLK1, INT_COMEND, INT_DIVCLK};

/// The communication cycle in progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Run {
    /// Reference point: at MCLK tick `ref_tick` the cycle was `ref_e` µs old; the
    /// following µs ticks of the predivider add one each.
    pub(crate) ref_tick: u64,
    /// See [`Run::ref_tick`].
    pub(crate) ref_e: u64,
    /// Offset at which the cycle ends (TCNT reaches TSCYC of its block).
    pub(crate) len: u64,
    /// Transmission block processed (0 or 1), 410B §4.1 3H.7 COMBLK.
    pub(crate) block: u8,
    /// TCNTST latched at the cycle start.
    pub(crate) tcntst: u16,
    /// Next plan entry to process.
    pub(crate) cursor: usize,
    /// DIVCLKMODE = 1: this cycle has the DIV_CLK pulse.
    pub(crate) pulse_cycle: bool,
}

/// Sequencing state of the timing control.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct CycleState {
    /// The cycle in progress (410B §4.1 3H.6 COMACT = 1 while `Some`).
    pub(crate) run: Option<Run>,
    /// Tick at which a triggered sequence of cycles starts (after TCYCSTART).
    pub(crate) pending: Option<u64>,
    /// Cycles still to run after the current one ends (NCYC > 0).
    pub(crate) cycles_left: u8,
    /// NCYC = 0: cycles repeat until the next trigger or reset (spec-notes "NCYC = 0").
    pub(crate) continuous: bool,
    /// TCNT while no cycle runs (it holds its last value).
    pub(crate) tcnt_hold: u16,
    /// Transmission block of the last cycle started, running or ended (the MST window's
    /// TSCYC, spec-notes "MST window of the last cycle").
    pub(crate) last_block: u8,
}

impl Engine {
    /// The MCLK tick at which offset `e` of `run` falls.
    // Inlined: a slave's MST end (`crate::mst::mst_end`, the short cycle sync's quiet end)
    // makes no call of its own but this one (docs/performance.md, session 30).
    #[inline(always)]
    pub(crate) fn e_tick(&self, run: &Run, e: u64) -> u64 {
        if e <= run.ref_e {
            run.ref_tick
        } else {
            let first = self.pre.tick_after(run.ref_tick);
            first.saturating_add((e - run.ref_e - 1).saturating_mul(self.pre.period()))
        }
    }

    /// The offset of `run` at MCLK tick `tick` (µs ticks counted up to and including it).
    pub(crate) fn e_at(&self, run: &Run, tick: u64) -> u64 {
        let first = self.pre.tick_after(run.ref_tick);
        if tick < first {
            run.ref_e
        } else {
            run.ref_e + 1 + self.pre.periods_in(tick - first)
        }
    }

    /// TCNT at tick `tick` (410B §4.1 11H RDCNT → 12H TCNTLT).
    pub(crate) fn tcnt_at(&self, tick: u64) -> u16 {
        debug_assert!(
            self.quiet_end().is_none_or(|q| q >= tick),
            "quiet end skipped"
        );
        match &self.cycle.run {
            // spec-notes "TCNT": loaded with TCNTST at the cycle start, +1 per µs.
            Some(run) => (u64::from(run.tcntst) + self.e_at(run, tick)) as u16,
            None => self.cycle.tcnt_hold,
        }
    }

    /// The tick of the next cycle start (the running cycle's end, 410B §4.1 10H/12H TSCYC, or
    /// a triggered start pending): no earlier than the first of [`Engine::cycle_ticks`].
    pub(crate) fn next_cycle_start(&self) -> Option<u64> {
        let run_end = self.cycle.run.as_ref().map(|run| self.e_tick(run, run.len));
        run_end.into_iter().chain(self.cycle.pending).min()
    }

    /// The MCLK tick of the running cycle's end when that end is *quiet*, which
    /// [`Engine::next_tick`] leaves out: it is all that is left of the cycle (every plan
    /// entry before it done, no DIV_CLK pulse running, no triggered start pending) and it
    /// changes nothing but the cycle state itself: no INT_COMEND (the telegram processor
    /// runs, MSTEN or ENTMT: spec-notes "INT_COMEND"), no next cycle (NCYC counted down to
    /// this one, 410B §4.1 0CH.12-15; a slave's cycle synchronised by an MST, 410B §4.2.1
    /// TRT). Such an end moves no pin and raises no flag, so it is no event of its own:
    /// whatever reads the cycle state at or after it (the telegram processor's next step,
    /// the timing control's next step, the end of an advance) applies it first
    /// ([`Engine::end_quietly`]; spec-notes "Quiet cycle ends").
    pub(crate) fn quiet_end(&self) -> Option<u64> {
        self.cycle_ticks().1
    }

    /// The next tick of the cycle machinery (pending start, plan entry, pulse end, end; a
    /// quiet end is none) and [`Engine::quiet_end`], in one go.
    pub(crate) fn cycle_ticks(&self) -> (Option<u64>, Option<u64>) {
        let Some(run) = self.cycle.run.as_ref() else {
            return (self.cycle.pending, None);
        };
        let mut e = run.len;
        if let Some(entry) = self.plan.entries.get(run.cursor) {
            e = e.min(entry.e);
        }
        let tick = if let Some(until) = self.outputs.divclk_until {
            self.e_tick(run, e.min(until))
        } else {
            let tick = self.e_tick(run, e);
            if e == run.len
                && self.quiet_ends
                && !self.cycle.continuous
                && self.cycle.cycles_left <= 1
                && self.cycle.pending.is_none()
                && (self.s.msten || self.regs.stored(sercon_regs::Register::Ctrl3) & (1 << 8) != 0)
                // u64::MAX stands for "none" in the event loop (and is never reached).
                && tick != u64::MAX
            {
                return (None, Some(tick));
            }
            tick
        };
        match self.cycle.pending {
            Some(p) => (Some(tick.min(p)), None),
            None => (Some(tick), None),
        }
    }

    /// Applies the quiet end at tick `end` ([`Engine::quiet_end`]): the running cycle ends
    /// naturally, as its own step at `end` would end it (debug builds run that step on a
    /// copy and compare): TCNT holds TSCYC's match, one cycle fewer is left, and nothing
    /// else changes (no flag, no pulse, no next cycle). The next tick stands (the end was
    /// not part of it).
    pub(crate) fn end_quietly(&mut self, end: u64) {
        debug_assert_eq!(self.quiet_end(), Some(end), "not a quiet end");
        #[cfg(debug_assertions)]
        let general = {
            let mut g = self.clone();
            g.quiet_ends = false;
            let step = g.step_general(end);
            (g, step)
        };
        if let Some(run) = self.cycle.run.take() {
            // 410B §4.1 12H: TCNT stops at the end's offset, `len` (`end` is below
            // u64::MAX, so `e_tick` did not saturate: `e_at(end)` is `len`, or the
            // reference offset when a rebase at the end itself put it there).
            self.cycle.tcnt_hold = (u64::from(run.tcntst) + run.len.max(run.ref_e)) as u16;
            self.cycle.cycles_left = self.cycle.cycles_left.saturating_sub(1);
        }
        if let Some((next, _)) = self.next_memo {
            self.next_memo = Some((next, u64::MAX));
        }
        #[cfg(debug_assertions)]
        {
            let (mut g, step) = general;
            assert_eq!(
                step,
                crate::engine::Step {
                    tick: end,
                    changed: 0,
                    expired: false,
                    cycle_started: false
                },
                "a quiet end is no event"
            );
            g.quiet_ends = self.quiet_ends;
            g.next_memo = self.next_memo;
            assert_eq!(&g, self, "quiet end against the end's own step");
            if let Some(memo) = self.next_memo {
                assert_eq!(
                    memo,
                    (crate::mclk::Due::from_option(self.next_tick()), u64::MAX),
                    "quiet end memo"
                );
            }
        }
    }

    /// Timing control triggered at tick `at` (CYCSTART or a CYC_CLK edge): the predivider
    /// is reloaded with MCLKST and cycles start TCYCSTART µs later.
    // 410B §4.1 0CH.8/10 "Trigger timing control after TCYCSTART"; 14H TCYCSTART.
    pub(crate) fn trigger(&mut self, at: u64) {
        self.rebase(at);
        self.pre.reload(at, self.s.mclkst);
        let delay = u64::from(self.s.tcycstart);
        let start = if delay == 0 {
            at
        } else {
            let first = self.pre.tick_after(at);
            first.saturating_add((delay - 1).saturating_mul(self.pre.period()))
        };
        // spec-notes "retrigger": a later trigger replaces a pending one.
        self.cycle.pending = Some(start);
    }

    /// Moves the running cycle's reference point to tick `at` (before the predivider's
    /// phase or period changes).
    pub(crate) fn rebase(&mut self, at: u64) {
        debug_assert!(
            self.quiet_end().is_none_or(|q| q >= at),
            "quiet end skipped"
        );
        if let Some(run) = self.cycle.run {
            let e = self.e_at(&run, at);
            if let Some(r) = self.cycle.run.as_mut() {
                r.ref_tick = at;
                r.ref_e = e;
            }
        }
    }

    /// The timing registers changed at tick `at` while a cycle may run: the comparators
    /// see the new values from the next µs on (spec-notes "timing registers written
    /// mid-cycle").
    pub(crate) fn replan_running(&mut self, at: u64) {
        debug_assert!(
            self.quiet_end().is_none_or(|q| q >= at),
            "quiet end skipped"
        );
        self.plan_key = None;
        let Some(run) = self.cycle.run else { return };
        let done = self.e_at(&run, at);
        let tscyc = self.tscyc(run.block);
        // The comparator can only match a TCNT value still to come.
        let len = next_match(tscyc, run.tcntst, done);
        self.ensure_plan(run.tcntst, len);
        let cursor = self.plan.first_after(done);
        if let Some(r) = self.cycle.run.as_mut() {
            r.len = len;
            r.cursor = cursor;
        }
        if let Some(until) = self.outputs.divclk_until {
            self.outputs.divclk_until = Some(until.min(len));
        }
    }

    fn tscyc(&self, block: u8) -> u16 {
        // 410B §4.1 0FH/10H: TSCYC0 for transmission block 0, TSCYC1 for block 1.
        if block == 0 {
            self.s.tscyc[0]
        } else {
            self.s.tscyc[1]
        }
    }

    fn ensure_plan(&mut self, tcntst: u16, len: u64) {
        if self.plan_key != Some((tcntst, len)) {
            self.plan = Arc::new(CyclePlan::build(&self.s, tcntst, len));
            self.plan_key = Some((tcntst, len));
        }
    }

    /// Processes everything the cycle machinery has at tick `tick`; returns whether a
    /// cycle started.
    pub(crate) fn process_cycle_tick(&mut self, tick: u64) -> bool {
        let mut started = false;
        if self.cycle.pending == Some(tick) {
            self.cycle.pending = None;
            if self.cycle.run.is_some() {
                // spec-notes "retrigger": the cycle in progress is cut short.
                self.end_cycle(tick, false);
            }
            self.start_cycle(tick, true);
            started = true;
        }
        if let Some(run) = self.cycle.run {
            if let Some(until) = self.outputs.divclk_until
                && self.e_tick(&run, until) == tick
            {
                // 410B §4.1 1EH/1FH: DIV_CLK pulses last one µs (spec-notes).
                self.outputs.divclk_until = None;
            }
            let mut cursor = run.cursor;
            while let Some(entry) = self.plan.entries.get(cursor).copied() {
                if entry.e >= run.len || self.e_tick(&run, entry.e) != tick {
                    break;
                }
                self.apply_entry(&run, entry);
                cursor += 1;
            }
            if let Some(r) = self.cycle.run.as_mut() {
                r.cursor = cursor;
            }
            if self.e_tick(&run, run.len) == tick {
                // The next cycle (if any) starts here and applies its offset-0 entries.
                self.end_cycle(tick, true);
                started |= self.cycle.run.is_some();
            }
        }
        started
    }

    fn apply_entry(&mut self, run: &Run, entry: crate::cycle_plan::PlanEntry) {
        self.flags.raise_hi(entry.set_hi);
        if let Some(level) = entry.conclk {
            self.outputs.conclk_set = level;
        }
        // 816 §2.7: in DIVCLKMODE = 1 only the chosen cycles pulse.
        if entry.divclk_pulse && (!self.s.divclkmode || run.pulse_cycle) {
            // 410B §4.1 5H.13 INT_DIVCLK: set with each DIV_CLK pulse (spec-notes).
            self.flags.raise_hi(INT_DIVCLK);
            self.outputs.divclk_until = Some((entry.e + 1).min(run.len));
        }
    }

    /// Starts a communication cycle at tick `at`; `fresh` when started by a trigger
    /// (NCYC is loaded), not by the end of the previous cycle.
    pub(crate) fn start_cycle(&mut self, at: u64, fresh: bool) {
        // 410B §4.1 0CH.2: the master sends PHAS0, so block COMBLK0 is processed
        // (spec-notes "block selection"); the slave's choice by PHAS1 comes with MSTs.
        self.start_cycle_block(at, fresh, u8::from(self.s.comblk0));
    }

    /// Starts a communication cycle processing transmission block `block` (0 or 1).
    pub(crate) fn start_cycle_block(&mut self, at: u64, fresh: bool, block: u8) {
        let block = block & 1;
        let tcntst = self.s.tcntst;
        let len = next_match(self.tscyc(block), tcntst, 0);
        self.ensure_plan(tcntst, len);
        if fresh {
            // 410B §4.1 0CH.12-15 NCYC: cycles per trigger.
            self.cycle.continuous = self.s.ncyc == 0;
            self.cycle.cycles_left = self.s.ncyc;
        }
        // 816 §2.7: DIVCLKMODE = 1 pulses once every NDIVCLK cycles, first in the first.
        let mut pulse_cycle = false;
        if self.s.divclkmode && self.s.ndivclk != 0 {
            pulse_cycle = self.outputs.divclk_countdown == 0;
            self.outputs.divclk_countdown = if pulse_cycle {
                self.s.ndivclk - 1
            } else {
                self.outputs.divclk_countdown - 1
            };
        }
        self.outputs.divclk_until = None;
        let start = self.plan.start;
        // The run is read again only by the debug comparison below.
        #[cfg_attr(not(debug_assertions), allow(unused_variables))]
        let run = self.begin_run(at, len, block, tcntst, pulse_cycle);
        // 816 §2.6.5: in master mode the MST start triggers the watchdog (WDOG_MSTEN).
        if self.s.sends_mst() && self.s.wdog_msten {
            self.wd.trigger(at, self.s.twdog, self.pre.period());
        }
        #[cfg(debug_assertions)]
        let general = {
            let mut g = self.clone();
            g.apply_start_entries(run);
            g
        };
        // The plan's offset-0 entries taken together (`CyclePlan::start`), as
        // `Engine::apply_start_entries` applies them one by one (debug builds compare):
        // 410B §4.1 1AH–1DH / 5H.9-12 INT_TIMEn at TINTn = TCNTST, 0CH.5 CON_CLK set at
        // TINT0 and reset at TINT1; 1EH–20H a DIV_CLK pulse (with INT_DIVCLK, 5H.13) at
        // TDIVCLK = TCNTST, in DIVCLKMODE = 1 only in the chosen cycles (816 §2.7).
        self.flags.raise_hi(start.set_hi);
        if let Some(level) = start.conclk {
            self.outputs.conclk_set = level;
        }
        if start.divclk_pulse && (!self.s.divclkmode || pulse_cycle) {
            self.flags.raise_hi(INT_DIVCLK);
            self.outputs.divclk_until = Some(1.min(len));
        }
        #[cfg(debug_assertions)]
        assert_eq!(&general, self, "a cycle start's entries in one go");
    }

    /// Begins the cycle of block `block` (0 or 1, `len` µs long, TCNT from `tcntst`, the DIV_CLK
    /// pulse in it when `pulse_cycle`) at tick `at`, with the plan's cursor after the entries
    /// at offset 0 (the caller applies those, `CyclePlan::start`), and raises INT_COMBLK0/1
    /// (410B §4.1 4H.2/3 "start transmission block 0/1"). Returns the run.
    #[inline]
    fn begin_run(&mut self, at: u64, len: u64, block: u8, tcntst: u16, pulse_cycle: bool) -> Run {
        self.flags
            .raise_lo(if block == 0 { INT_COMBLK0 } else { INT_COMBLK1 });
        let run = Run {
            ref_tick: at,
            ref_e: 0,
            len,
            block,
            tcntst,
            cursor: self.plan.start.count,
            pulse_cycle,
        };
        self.cycle.run = Some(run);
        self.cycle.last_block = block;
        run
    }

    /// Applies the plan's entries at offset 0 one by one to the cycle `run` just started
    /// (its cursor still at 0 there), leaving the cursor after them: the general path of
    /// [`Engine::start_cycle_block`]'s, kept for comparing.
    #[cfg(debug_assertions)]
    fn apply_start_entries(&mut self, mut run: Run) {
        run.cursor = 0;
        self.cycle.run = Some(run);
        let mut cursor = 0;
        while let Some(entry) = self.plan.entries.get(cursor).copied() {
            if entry.e != 0 || entry.e >= run.len {
                break;
            }
            self.apply_entry(&run, entry);
            cursor += 1;
        }
        if let Some(r) = self.cycle.run.as_mut() {
            r.cursor = cursor;
        }
    }

    /// Ends the running cycle at tick `at`; `natural` when TCNT reached TSCYC (the next
    /// cycle then follows at once if NCYC allows), not when a new trigger cut it short.
    pub(crate) fn end_cycle(&mut self, at: u64, natural: bool) {
        let Some(run) = self.cycle.run.take() else {
            return;
        };
        // spec-notes "INT_COMEND": the block ends with its cycle unless the telegram
        // processor runs (MSTEN or ENTMT), which ends it at the end marker.
        let entmt = self.regs.stored(sercon_regs::Register::Ctrl3) & (1 << 8) != 0;
        if !(self.s.msten || entmt) {
            self.flags.raise_lo(INT_COMEND);
        }
        self.outputs.divclk_until = None;
        self.cycle.tcnt_hold = (u64::from(run.tcntst) + self.e_at(&run, at)) as u16;
        if natural {
            let more = if self.cycle.continuous {
                true
            } else {
                self.cycle.cycles_left = self.cycle.cycles_left.saturating_sub(1);
                self.cycle.cycles_left > 0
            };
            if more && self.cycle.pending != Some(at) {
                self.start_cycle(at, false);
            }
        }
    }
}

impl Engine {
    /// A slave's cycle restarts at tick `at`, the end of a received MST, with block
    /// `block`; it runs one cycle (TSCYC) unless the next MST comes first.
    ///
    /// When the previous cycle has ended (on an intact ring at the MST's own tick, quietly)
    /// and no start is pending, the new cycle is started the short way
    /// ([`Engine::sync_after_end`]), which keeps the memo of the next ticks when the start
    /// moves no pin but INT0 / INT1; otherwise the memo is dropped (spec-notes "Short cycle
    /// syncs").
    // 410B §4.2.1 TRT "after end of MST": the MST synchronises the slave (spec-notes
    // "slave cycle").
    // Inlined into its one call, `crate::mst::mst_end` (docs/performance.md, session 30).
    #[inline(always)]
    pub(crate) fn sync_cycle(&mut self, at: u64, block: u8) {
        // A quiet end before `at` was applied before the telegram processor's step.
        debug_assert!(
            self.quiet_end().is_none_or(|q| q >= at),
            "quiet end skipped"
        );
        // `crate::mst::mst_end` synchronises SERCOS slaves only (410B §4.2.1 TRT).
        debug_assert!(!self.s.sends_mst(), "a master's cycle synchronised");
        if self.short_syncs
            && self.cycle.run.is_none()
            && self.cycle.pending.is_none()
            && self.sync_after_end(at, block)
        {
            return;
        }
        self.sync_general(at, block);
    }

    /// [`Engine::sync_cycle`] the general way: the running cycle (if any) cut short, a new
    /// one started from the settings, the memo of the next ticks dropped.
    fn sync_general(&mut self, at: u64, block: u8) {
        self.next_memo = None;
        self.cycle.pending = None;
        if self.cycle.run.is_some() {
            self.end_cycle(at, false);
        }
        self.start_cycle_block(at, true, block);
        self.cycle.continuous = false;
        self.cycle.cycles_left = 1;
    }

    /// [`Engine::sync_cycle`] when no cycle runs and no start is pending (the previous
    /// cycle ended, on an intact ring quietly on the MST's own tick): what
    /// [`Engine::start_cycle_block`] and the slave's one-cycle count leave, done directly
    /// when nothing but the block's length and plan decide it (the plan built for TCNTST
    /// and that length, so it stands; DIVCLKMODE's countdown not in use; no watchdog
    /// trigger, which only a master's start gives). Returns false, having changed nothing,
    /// when that is not so.
    ///
    /// The memo of the next ticks stays valid when the new cycle's only event is its end
    /// (no plan entry after offset 0, no DIV_CLK pulse) and that end is quiet, with the
    /// same next tick as before (the watchdog's: no cycle tick before or after): it then
    /// holds that end; and the start then leaves CON_CLK, DIV_CLK and WDOGN as they were,
    /// so only INT0 / INT1 can change (`Chip::advance_to` settles those after the
    /// processor's steps). Otherwise the memo is dropped, as the general way does. Debug
    /// builds run the general way on a copy and compare the whole engine.
    #[inline(always)]
    fn sync_after_end(&mut self, at: u64, block: u8) -> bool {
        // 410B §4.1 0FH/10H: the block's TSCYC; TCNT starts at TCNTST (spec-notes "TCNT").
        let block = block & 1;
        let tcntst = self.s.tcntst;
        let len = next_match(self.tscyc(block), tcntst, 0);
        // 816 §2.7 DIVCLKMODE = 1 counts cycles: the general way.
        if self.plan_key != Some((tcntst, len)) || (self.s.divclkmode && self.s.ndivclk != 0) {
            return false;
        }
        #[cfg(debug_assertions)]
        let general = {
            let mut g = self.clone();
            g.sync_general(at, block);
            g
        };
        let start = self.plan.start;
        let run = self.begin_run(at, len, block, tcntst, false);
        // The slave runs this one cycle unless the next MST comes first (410B §4.2.1 TRT).
        self.cycle.continuous = false;
        self.cycle.cycles_left = 1;
        // The offset-0 entries as `start_cycle_block` applies them (`CyclePlan::start`;
        // DIVCLKMODE = 0 or NDIVCLK = 0 here).
        self.flags.raise_hi(start.set_hi);
        let pulse = start.divclk_pulse && !self.s.divclkmode;
        if pulse {
            self.flags.raise_hi(INT_DIVCLK);
        }
        let conclk = start.conclk.unwrap_or(self.outputs.conclk_set);
        // No pulse runs without a cycle (`end_cycle`, `end_quietly`).
        debug_assert_eq!(self.outputs.divclk_until, None);
        let moves_outputs = pulse || conclk != self.outputs.conclk_set;
        self.outputs.conclk_set = conclk;
        self.outputs.divclk_until = pulse.then(|| 1.min(len));
        self.next_memo = match self.next_memo {
            Some((next, _))
                if !moves_outputs && self.quiet_ends && self.plan.entries.len() == start.count =>
            {
                // The end is the only event: quiet (the slave's last cycle, MSTEN set,
                // nothing pending: `Engine::cycle_ticks`) unless it saturated.
                let end = self.e_tick(&run, len);
                (end != u64::MAX).then_some((next, end))
            }
            _ => None,
        };
        #[cfg(debug_assertions)]
        {
            let mut g = general;
            g.next_memo = self.next_memo;
            assert_eq!(&g, self, "a short cycle sync against the general one");
            if let Some(memo) = self.next_memo {
                assert_eq!(memo, self.next_ticks_due(), "a short cycle sync's memo");
                // CON_CLK, DIV_CLK and WDOGN as they were (INT0 / INT1 are settled later).
                let mut levels = self.compute_levels();
                levels[..2].copy_from_slice(&self.levels[..2]);
                assert_eq!(levels, self.levels, "a short cycle sync moved a pin");
            }
        }
        true
    }
}
