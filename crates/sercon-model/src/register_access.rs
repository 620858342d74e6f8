//! Bus reads and writes of the control registers: status bits composed from the chip's
//! state, write-1-to-clear flags, write actions and their side effects.

use sercon_regs::Register;

use crate::chip::Chip;
use crate::settings::Settings;

/// A bus read of the register at word address `address` at the chip's current time.
/// Only a read of RFIFO changes the chip (410B §4.1 27H: it takes the oldest word of the
/// receive FIFO); any other read is [`peek`], and the chip's remembered next events stand.
pub(crate) fn read(chip: &mut Chip, address: u8) -> u16 {
    if !sercon_regs::register::read_has_effect(address) {
        return peek(chip, address);
    }
    // 410B §4.1 27H RFIFO: a read takes the oldest word of the receive FIFO (DMAREQR may
    // fall, 410B §2 pin 38).
    chip.touched();
    let before = chip.tp.fifo.state();
    let w = chip.tp.fifo.read();
    chip.dma_accessed(before);
    chip.engine.regs.read(address, w)
}

/// What a bus read of the register at `address` gives at the chip's current time, without
/// its effect: RFIFO's oldest word is shown, not taken (410B §4.1 27H); every other
/// register reads the same either way (410B §4.1: R/W bits read back, status bits show
/// the chip's state, flags are cleared by writes only).
pub(crate) fn peek(chip: &Chip, address: u8) -> u16 {
    let address = address & sercon_regs::register::REGISTER_ADDRESS_MASK;
    let status = match Register::from_address(address) {
        Some(Register::Fifo) => chip.tp.fifo.oldest(),
        Some(register) => status_bits(chip, register),
        None => 0,
    };
    chip.engine.regs.read(address, status)
}

fn bit(value: bool, n: u8) -> u16 {
    u16::from(value) << n
}

/// The chip-supplied (read-only and flag) bits of `register`; the access table keeps
/// only the bits that are status bits on the chip's variant.
fn status_bits(chip: &Chip, register: Register) -> u16 {
    let e = &chip.engine;
    let straps = &chip.cfg.straps;
    match register {
        // 410B §4.1 0H VERSION; 816 §2.11.1.1.
        Register::Version => chip.cfg.variant.version(),
        // 410B §4.1 1H.4 level at pin 28 (SREGEN; SBAUD16 on the 816), 1H.11 SBAUD.
        Register::Ctrl1 => bit(straps.sbaud16, 4) | bit(straps.sbaud, 11),
        // 410B §4.1 2H.10-11 levels at TM0-1; RDIST/FIBBR come with the serial interface.
        // 410B §4.1 2H.12 RDIST, 2H.13 FIBBR from the serial port's receiver.
        Register::Ctrl2 => {
            let (rdist, fibbr) = chip.receiver_status();
            bit(straps.tm0, 10) | bit(straps.tm1, 11) | bit(rdist, 12) | bit(fibbr, 13)
        }
        Register::Ctrl3 => {
            let run = e.cycle.run.as_ref();
            // 410B §4.1 3H.6 COMACT / 3H.7 COMBLK: the transmission block the telegram
            // processor works on while it runs, else the timing control's cycle.
            let (comact, comblk) = if crate::telegram_processor::tp_enabled(chip) {
                let b = crate::telegram_processor::comact(chip);
                (b.is_some(), b == Some(1))
            } else {
                (run.is_some(), run.is_some_and(|r| r.block == 1))
            };
            let tp = &chip.tp;
            let (idle, reactn) = chip.serial_pin_status();
            // 410B §4.1 3H.0 INTFL0, 3H.3 INTFL1, 3H.9 FLTMT, 3H.10 FLRWAIT, 3H.11 FLREC,
            // 3H.12 DMAREQT, 3H.13 DMAREQR; 3H.14 IDLE and 3H.15 REACTN read their
            // inactive (high) pin levels until the serial interface drives them.
            let (intfl0, intfl1) = chip.interrupt_requests();
            bit(intfl0, 0)
                | bit(intfl1, 3)
                | bit(comact, 6)
                | bit(comblk, 7)
                | bit(tp.tx_end.is_some(), 9)
                | bit(tp.flrwait, 10)
                | bit(tp.flrec, 11)
                | bit(tp.fifo.dmareqt(), 12)
                | bit(tp.fifo.dmareqr(), 13)
                | bit(idle, 14)
                | bit(reactn, 15)
        }
        // 410B §4.1 4H/5H: the interrupt flags.
        Register::IntFlagsLo => e.flags.lo(),
        Register::IntFlagsHi => e.flags.hi(),
        // 410B §4.1 0CH.4 level at CON_CLK, 0CH.7 level at CYC_CLK.
        Register::Ctrl0C => bit(e.outputs.conclk_level(&e.s), 4) | bit(chip.cyc_clk, 7),
        // 410B §4.1 12H TCNTLT.
        Register::Tcntlt => e.tcntlt,
        // 410B §4.1 0BH PHASREC 7-0, RECADR 15-8.
        Register::PhasRec => u16::from(chip.tp.phasrec) | u16::from(chip.tp.recadr) << 8,
        // 410B §4.1 11H TCYCDEL, 17H PROGERR_FL, 21H–26H header registers.
        Register::Tcycdel => chip.tp.tcycdel,
        Register::ProgerrFl => chip.tp.progerr,
        Register::Thtpt => chip.tp.thtpt,
        Register::Tht => chip.tp.tht,
        Register::Thwpt => chip.tp.thwpt,
        Register::Thw => chip.tp.thw,
        Register::Thrpt => chip.tp.thrpt & 0x03FF,
        Register::Thr => chip.tp.thr,
        // 816 §2.11.2 28H.0 WDOG_STAT, 28H.1 INT_WDOG, 28H.2 WDOUT_STAT, 28H.6 INT_RSCEND.
        Register::WdogCtrl => {
            bit(e.wd.running, 0)
                | bit(e.flags.wdog(), 1)
                | bit(e.wd.output_enabled, 2)
                | bit(e.flags.rscend(), 6)
        }
        _ => 0,
    }
}

/// A bus write of `value` to the register at word address `address` at the chip's
/// current time.
pub(crate) fn write(chip: &mut Chip, address: u8, value: u16) {
    if chip.in_reset {
        // RSTN low: the chip is held in reset and ignores the bus.
        return;
    }
    let at = chip.action_tick();
    let register = Register::from_address(address & sercon_regs::register::REGISTER_ADDRESS_MASK)
        .filter(|r| r.exists_on(chip.cfg.variant));
    let locked = chip.engine.locked_bits(register);
    let old = chip.engine.s;
    let req = chip.engine.regs.write(address, value, locked);
    let Some(register) = req.register else {
        return;
    };
    let e = &mut chip.engine;
    e.s = Settings::decode(&e.regs, chip.cfg.variant);
    apply_setting_changes(chip, &old, at);

    let e = &mut chip.engine;
    match register {
        // ERRATA "410B 4H/5H": writing 1 clears a flag, 0 leaves it.
        Register::IntFlagsLo => e.flags.clear_lo(req.clear),
        Register::IntFlagsHi => e.flags.clear_hi(req.clear),
        // 410B §4.1 17H CLR_PROGERR_FL: writing 1 clears a flag.
        Register::ProgerrFl => chip.tp.progerr &= !req.clear,
        // 410B §4.1 27H TFIFO: a write appends to the transmit FIFO.
        Register::Fifo => {
            let before = chip.tp.fifo.state();
            chip.tp.fifo.write(value);
            chip.dma_accessed(before);
        }
        Register::Ctrl1 if req.actions & (1 << 1) != 0 => {
            // 410B §4.1 1H.1 SWRST: "Reset by software".
            crate::reset::software_reset(chip);
            return;
        }
        Register::Ctrl0C => {
            if req.actions & (1 << 11) != 0 {
                // 410B §4.1 0CH.11 RDCNT: "Load TCNT to TCNTRD" (12H TCNTLT).
                e.tcntlt = e.tcnt_at(at);
            }
            if req.actions & (1 << 10) != 0 && !e.s.is_sercos_slave() {
                // 410B §4.1 0CH.10 CYCSTART: "Trigger timing control after TCYCSTART".
                e.trigger(at);
            }
        }
        Register::WdogCtrl => {
            // 816 §2.11.2 28H.1 CLR_INT_WDOG, 28H.6 CLR_RSCEND.
            if req.clear & (1 << 1) != 0 {
                e.flags.set_wdog(false);
            }
            if req.clear & (1 << 6) != 0 {
                e.flags.set_rscend(false);
            }
            if req.actions & (1 << 2) != 0 {
                // 816 §2.11.2 28H.2 WDOUT_SET: enables output WDOGN (until reset).
                e.wd.output_enabled = true;
            }
            if req.actions & 1 != 0 {
                // 816 §2.11.2 28H.0 WDOG_START.
                e.wd.start(at, e.s.twdog, e.pre.period());
            }
        }
        // 816 §2.6.4: "writing the value 42H to the control bits WDOG_TRIG (29H,7-0)";
        // any other value does nothing.
        Register::WdogTrig if req.actions & 0x00FF == 0x0042 => {
            e.wd.trigger(at, e.s.twdog, e.pre.period());
        }
        _ => {}
    }
    // 410B §4.1 1H, 2H: the serial port follows its settings from the write on.
    chip.serial_registers_changed();
    chip.settle();
}

/// Reacts to changed settings at tick `at`: a new predivider, new comparator values.
fn apply_setting_changes(chip: &mut Chip, old: &Settings, at: u64) {
    let e = &mut chip.engine;
    let new = e.s;
    if new.mclkdiv != old.mclkdiv {
        // 410B §4.1 0EH: a new predivider value changes the length of the µs.
        e.rebase(at);
        let old_period = e.pre.period();
        e.pre.set_divider(at, new.mclkdiv);
        e.wd.set_divider(at, old_period, e.pre.period());
    }
    if (new.ndivclk != old.ndivclk || new.divclkmode != old.divclkmode) && new.ndivclk != 0 {
        // 816 §2.7: "or after the first cycle when NDIVCLK is being programmed to a value
        // not equal zero": the next cycle has a pulse.
        e.outputs.divclk_countdown = 0;
    }
    let timing_changed = new.tscyc != old.tscyc
        || new.tint != old.tint
        || new.tdivclk != old.tdivclk
        || new.dtdivclk != old.dtdivclk
        || new.ndivclk != old.ndivclk
        || new.divclkmode != old.divclkmode;
    if timing_changed {
        e.replan_running(at);
    }
}
