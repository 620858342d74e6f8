//! The next observable instant, found by running a copy of the chip's state forward.

use crate::chip::Chip;
use crate::engine::DRIVEN;
use crate::pins::Pin;
use sercos_wire::time::Instant;

/// Full cycles a probe runs before concluding that nothing observable will happen:
/// after one full cycle the state repeats (flags only accumulate, CON_CLK's flip-flop
/// ends each cycle the same way), so three are plenty.
const PROBE_CYCLES: u32 = 3;

/// See [`Chip::next_deadline`].
pub(crate) fn next_deadline(chip: &Chip) -> Option<Instant> {
    let mut mask = 0u8;
    for (i, pin) in DRIVEN.iter().enumerate() {
        // Interrupt outputs and WDOGN are wired to a processor: always observable.
        if chip.traced.contains(*pin) || matches!(pin, Pin::Int0 | Pin::Int1 | Pin::Wdogn) {
            mask |= 1 << i;
        }
    }
    let mut probe = chip.engine.clone();
    let s = probe.s;
    let mut budget = PROBE_CYCLES;
    if chip.traced.contains(Pin::DivClk) && s.divclkmode {
        // 816 §2.7: a pulse every NDIVCLK cycles.
        budget += u32::from(s.ndivclk);
    }
    // The telegram processor's next event (a telegram, a window, an MST deadline) and,
    // while it runs, every cycle start (a master sends its MST there) are observable.
    let tp_tick = crate::telegram_processor::next_tick(chip);
    let tp_cycles = crate::telegram_processor::tp_enabled(chip) && s.sends_mst();
    let mut starts = 0u32;
    while let Some(step) = probe.step(tp_tick.unwrap_or(u64::MAX)) {
        if step.changed & mask != 0 || step.expired || (step.cycle_started && tp_cycles) {
            return Some(chip.clock.instant(step.tick));
        }
        if step.cycle_started {
            starts += 1;
            if starts > budget {
                break;
            }
        }
    }
    // Beyond the horizon only the watchdog can still act, unless MST starts keep
    // triggering it for ever.
    let retriggered = probe.cycle.run.is_some()
        && probe.cycle.continuous
        && probe.s.sends_mst()
        && probe.s.wdog_msten;
    if let Some(k) = tp_tick {
        // Nothing observable before the telegram processor's event (or the horizon).
        return Some(chip.clock.instant(k));
    }
    (probe.wd.running && !retriggered).then(|| chip.clock.instant(probe.wd.expiry))
}
