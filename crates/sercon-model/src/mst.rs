//! The master synchronisation telegram (MST): a master sends it with PHAS0 at each cycle
//! start and measures the ring delay when it comes back (410B §4.1 0AH, 11H TCYCDEL); a
//! slave receives it, takes the phase (0BH PHASREC, 4H.5 INT_PHAS0, 4H.6 INT_PHASERR),
//! checks its time (25H.10 MSTTCHK, 15H/16H JTSCYC1/2, 4H.7/8), counts misses (RAM word 10
//! NMSTERR, 4H.9 INT_MSTMIS) and synchronises its cycle to the MST's end, which is the
//! time reference for TRT (410B §4.2.1).

use crate::mclk::Due;
use sercon_regs::Register;
use sercon_regs::ram::NMSTERR;

use crate::chip::Chip;
use crate::telegram_processor::status::{
    INT_MSTEARLY, INT_MSTLATE, INT_MSTMIS, INT_PHAS0, INT_PHASERR, ProgErr,
};
use crate::telegram_processor::{self as tp, reg25};

/// Sends the MST at cycle-start tick `tick`; returns the tick of its end (the reference
/// for TRT).
// 410B §4.1 0AH PHAS0: "Phase for MST transmit (master)"; ERRATA "Telegrams": MST = ADR
// 255 and one data byte.
pub(crate) fn send_mst(chip: &mut Chip, tick: u64) -> u64 {
    let phas0 = (chip.engine.regs.stored(Register::Phas) & 0xFF) as u8;
    chip.tp.txbuf.clear();
    chip.tp.txbuf.extend_from_slice(&[255, phas0]);
    let at = chip.clock.instant(tick);
    if chip.serial.own_busy_at(at) {
        // The transmitter still sends the telegram before (a cycle shorter than what it
        // sends): the MST is not sent, a programming error as a transmit telegram due
        // before the previous one ended (17H PROGERR_FL bit 3; spec-notes "An MST due
        // while the transmitter is busy"). Queued behind it, MSTs would pile up without
        // end in a cycle shorter than an MST.
        tp::prog_error(chip, ProgErr::Overlap);
        return tick;
    }
    match tp::send_line(chip, at) {
        Some(end) => chip.clock.tick_at_or_after(end).max(tick),
        None => tick,
    }
}

/// An MST starts arriving at `tick`. A master measures the ring delay.
// 410B §4.1 11H TCYCDEL: "Time at which MST is received, ring delay (master)" — TCNT at
// the start of the returning MST (spec-notes "TCYCDEL").
pub(crate) fn mst_start(chip: &mut Chip, tick: u64) {
    if chip.engine.s.sends_mst() {
        chip.tp.tcycdel = chip.engine.tcnt_at(tick);
    }
}

/// Expected MST spacing in µs: the cycle time of the block of the last cycle, in progress
/// or ended on this very tick (410B §4.1 0FH/10H TSCYC0/1; spec-notes "MST window of the
/// last cycle").
fn tscyc_us(chip: &Chip) -> u64 {
    let block = chip.engine.cycle.last_block;
    u64::from(chip.engine.s.tscyc[usize::from(block & 1)])
}

/// An MST ended at `tick` (slave): phase, time check, cycle synchronisation.
// One call out of `Chip::advance_to` with the cycle's synchronisation, the block's start and
// its first header's load inlined into it, instead of three calls from inside it
// (docs/performance.md, session 30, slavesteps).
#[inline(never)]
pub(crate) fn mst_end(chip: &mut Chip, tick: u64, fcs_ok: bool, bytes: &[u8]) {
    let s = chip.engine.s;
    if !s.is_sercos_slave() || !fcs_ok {
        // A master only times its own MST; an errored MST counts as missing when its
        // window closes.
        return;
    }
    let phase = bytes.get(1).copied().unwrap_or(0);
    let period = chip.engine.pre.period().max(1);
    let (msttchk, _, _) = reg25(chip);
    let j1 = u64::from(chip.engine.regs.stored(Register::Jtscyc1));
    let j2 = u64::from(chip.engine.regs.stored(Register::Jtscyc2));
    let tscyc = tscyc_us(chip);
    if msttchk && let Some(last) = chip.tp.mst.last_end {
        // 25H.10 MSTTCHK with JTSCYC1/2 (spec-notes "MST window"): the MST must end
        // TSCYC − JTSCYC1 ..= TSCYC + JTSCYC2 µs after the previous one.
        let dt = chip.engine.pre.periods_in(tick.saturating_sub(last));
        if dt < tscyc.saturating_sub(j1) {
            chip.engine.flags.raise_lo(INT_MSTEARLY);
        } else if dt > tscyc.saturating_add(j2) || chip.tp.mst.missed_since {
            chip.engine.flags.raise_lo(INT_MSTLATE);
        }
    }
    chip.tp.mst.last_end = Some(tick);
    chip.tp.mst.missed_prev = false;
    chip.tp.mst.missed_since = false;
    // 410B §4.1 0BH PHASREC: "Phase information of received MST".
    chip.tp.phasrec = phase;
    if phase & 0x07 == 0 {
        // 410B §4.1 4H.5 INT_PHAS0: "Interrupt phase MST = 0" (phase bits 2-0).
        chip.engine.flags.raise_lo(INT_PHAS0);
    }
    let block = phase_block(chip, phase);
    if block.is_none() {
        chip.engine.flags.raise_lo(INT_PHASERR);
    }
    // The slave's cycle restarts at the MST's end (spec-notes "slave cycle").
    chip.engine
        .sync_cycle(tick, block.unwrap_or(u8::from(s.comblk0)));
    if let Some(block) = block
        && tp::tp_enabled(chip)
    {
        tp::start_block(chip, tick, block);
    }
    // The next MST is due one cycle later, at the latest JTSCYC2 after that: one cycle of the
    // block this MST started (spec-notes "MST window of the last cycle").
    let tscyc = tscyc_us(chip);
    chip.tp.mst.deadline =
        Due::from_option((tscyc > 0).then(|| window_close(tick, tscyc, j2, period)));
}

/// The last MCLK tick at which an MST may end and still be in time after an MST that
/// ended at `last`: while fewer than TSCYC + JTSCYC2 + 1 whole µs have passed. The chip
/// times the MST in whole µs of its time base, as the INT_MSTLATE check above does, so
/// an MST that moves by less than a µs (e.g. one stuffed bit more when the phase byte
/// changes) is still the MST of its cycle, not a missing one.
/// The block a slave starts at the end of an MST with `phase`: 410B §4.1 0AH PHAS0/PHAS1
/// "Phase for MST receive (slave)", 0CH.2-3 COMBLK0/1; any other phase starts none (and is
/// INT_PHASERR).
pub(crate) fn phase_block(chip: &Chip, phase: u8) -> Option<u8> {
    let phas = chip.engine.regs.stored(Register::Phas);
    let (phas0, phas1) = ((phas & 0xFF) as u8, (phas >> 8) as u8);
    if phase == phas0 {
        Some(u8::from(chip.engine.s.comblk0))
    } else if phase == phas1 {
        Some(u8::from(
            chip.engine.regs.stored(Register::Ctrl0C) & (1 << 3) != 0,
        ))
    } else {
        None
    }
}

// 410B §4.1 16H JTSCYC2 "Receive time window for MST 2" (µs, spec-notes "MST window")
// and §4.2 word 10 NMSTERR; spec-notes "MST window in whole µs" (task mst3).
fn window_close(last: u64, tscyc: u64, j2: u64, period: u64) -> u64 {
    last.saturating_add(
        tscyc
            .saturating_add(j2)
            .saturating_add(1)
            .saturating_mul(period),
    )
    .saturating_sub(1)
}

/// No MST arrived by the deadline at `tick` (slave).
// 410B §4.2 word 10 NMSTERR "Error counter MST"; 4H.9 INT_MSTMIS "MST missing twice".
pub(crate) fn deadline(chip: &mut Chip, tick: u64) {
    let n = tp::ram_word(chip, NMSTERR);
    tp::set_ram_word(chip, NMSTERR, n.saturating_add(1));
    if chip.tp.mst.missed_prev {
        chip.engine.flags.raise_lo(INT_MSTMIS);
    }
    chip.tp.mst.missed_prev = true;
    chip.tp.mst.missed_since = true;
    let period = chip.engine.pre.period().max(1);
    let tscyc = tscyc_us(chip).max(1);
    // A sum that saturated is no deadline (`Due`: never reached).
    chip.tp.mst.deadline = Due::from_raw(tick.saturating_add(tscyc.saturating_mul(period)));
}
