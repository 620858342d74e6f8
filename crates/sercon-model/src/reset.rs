//! Hardware reset (RSTN) and software reset (SWRST, 410B §4.1 1H.1).
//!
//! Both put every register back to its reset value (410B §4.1, values in bold), set
//! RSTFL (1H.0), stop the timing control and the watchdog and clear every interrupt flag
//! including INT_WDOG (816 §2.6: it "remains set until it is cleared by a reset").
//! The RAM keeps its contents. RSTN holds the chip in reset while low (bus writes are
//! ignored, nothing advances); SWRST is a reset pulse at the write (spec-notes "SWRST
//! vs RSTN").

use crate::chip::Chip;
use crate::engine::Engine;

/// Resets the chip's state at its current time; the predivider starts at `at`.
pub(crate) fn reset_state(chip: &mut Chip, at: u64) {
    // 816 §2.6.2: "Reset of these control bits through hardware, respectively software
    // reset has higher priority than reset through INT_WDOG": the reset values win.
    chip.engine = Engine {
        // A switch of the model, not a register: it survives the reset.
        quiet_ends: chip.engine.quiet_ends,
        short_syncs: chip.engine.short_syncs,
        ..Engine::after_reset(chip.cfg.variant, &chip.cfg.straps, at)
    };
    // The telegram processor stops; frames already on their way are still delivered.
    let queued = std::mem::take(&mut chip.tp.rx_queue);
    let replacing = std::mem::take(&mut chip.tp.replacing);
    chip.tp = Default::default();
    chip.tp.rx_queue = queued;
    chip.tp.replacing = replacing;
    // The serial port keeps its line; it follows the reset values of 1H and 2H.
    chip.serial_registers_changed();
}

/// RSTN changed to `level` at the chip's current time.
pub(crate) fn set_rstn(chip: &mut Chip, level: bool) {
    if level != chip.in_reset {
        // Already at that level.
        return;
    }
    let at = chip.action_tick();
    let before = chip.engine.levels;
    if level {
        // Leaving reset: the predivider starts counting from MCLKST here.
        chip.in_reset = false;
        reset_state(chip, at);
    } else {
        reset_state(chip, at);
        chip.in_reset = true;
    }
    let changed = chip.engine.update_levels_from(before);
    if changed != 0 {
        let now = chip.now;
        chip.emit(changed, now);
    }
}

/// Software reset written at the chip's current time (410B §4.1 1H.1 SWRST).
pub(crate) fn software_reset(chip: &mut Chip) {
    let at = chip.action_tick();
    let before = chip.engine.levels;
    reset_state(chip, at);
    let changed = chip.engine.update_levels_from(before);
    if changed != 0 {
        let now = chip.now;
        chip.emit(changed, now);
    }
}
