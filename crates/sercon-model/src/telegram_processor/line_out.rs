//! Handing telegrams to the line. Until the serial port model takes them, the frame's
//! duration is computed here exactly from its bit length at the selected bit rate, and the
//! telegram is kept for whoever carries it to the other chips ([`Chip::drain_line_telegrams`]).

use sercon_regs::Register;
use sercos_wire::line::frame_bit_len;
use sercos_wire::time::{Duration, Instant};

use super::LineTelegram;
use crate::chip::Chip;
use crate::serial_settings::bit_clock;

/// Duration of one line bit at the chip's current settings; `None` with an external bit
/// clock (410B SREGEN = 0), whose rate the chip does not know.
// 410B §2 SBAUD/SREGEN, §4.1 1H.6/1H.10; 816 §2.3.1 table.
fn bit_time(chip: &Chip) -> Option<Duration> {
    let c1 = chip.engine.regs.stored(Register::Ctrl1);
    bit_clock(chip.cfg.variant, &chip.cfg.straps, chip.cfg.sclk_hz, c1)
        .bit_time()
        .ok()
}

/// Sends `chip.tp.txbuf` starting at `at`; returns the instant after its closing flag,
/// `None` when nothing can be sent.
pub(super) fn send(chip: &mut Chip, at: Instant) -> Option<Instant> {
    let bit = bit_time(chip)?;
    // Exact line length: flags, ADR, data, FCS and the stuffed zeros (sercos-wire line).
    let bits = frame_bit_len(&chip.tp.txbuf);
    let end = at.checked_add(bit.saturating_mul(bits))?;
    let bytes = chip.tp.txbuf.clone();
    chip.tp.sent.push(LineTelegram {
        start: at,
        end,
        bytes,
    });
    Some(end)
}
