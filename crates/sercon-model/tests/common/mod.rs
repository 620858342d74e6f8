//! Helpers shared by the integration tests of sercon-model.
#![allow(dead_code)]

use sercon_model::pins::PinEvent;
use sercon_model::serial_port::{FrameHint, LineSegment, LineSignal, Shared};
use sercon_model::{Chip, ChipConfig};
use sercos_wire::line::{BitVec, Coding, Encoder, LineConfig, Polarity};
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 0CH.5 ENCONCLK.
pub const CTRL0C_ENCONCLK: u16 = 1 << 5;
/// 410B §4.1 0CH.6 POLCONCLK.
pub const CTRL0C_POLCONCLK: u16 = 1 << 6;
/// 410B §4.1 0CH.8 ENCYCCLK.
pub const CTRL0C_ENCYCCLK: u16 = 1 << 8;
/// 410B §4.1 0CH.9 POLCYCCLK.
pub const CTRL0C_POLCYCCLK: u16 = 1 << 9;
/// 410B §4.1 0CH.10 CYCSTART.
pub const CTRL0C_CYCSTART: u16 = 1 << 10;
/// 410B §4.1 0CH.11 RDCNT.
pub const CTRL0C_RDCNT: u16 = 1 << 11;
/// 410B §4.1 0CH.0 MSTEN, 0CH.1 MSTMASTER.
pub const CTRL0C_MASTER: u16 = 0b11;

/// A SERCON816 at 32 MHz whose predivider makes 1 µs (MCLKDIV = 31).
pub fn chip816() -> Chip {
    let mut chip = Chip::new(ChipConfig::sercon816());
    sercon_regs::SerconBusExt::write(&mut chip, sercon_regs::Register::MclkDiv, 31);
    chip
}

/// A SERCON410B at 20 MHz (MCLKDIV resets to 19: 1 µs).
pub fn chip410() -> Chip {
    Chip::new(ChipConfig::sercon410b())
}

/// `n` µs after time 0.
pub fn us(n: u64) -> Instant {
    Instant::ZERO + Duration::from_micros(n)
}

/// `n` ns after time 0.
pub fn ns(n: u64) -> Instant {
    Instant::ZERO + Duration::from_nanos(n)
}

/// Drains the chip's pin events.
pub fn drain(chip: &mut Chip) -> Vec<PinEvent> {
    let mut v = Vec::new();
    chip.drain_pin_events(&mut v);
    v
}

/// A running SERCON816 (1 µs unit, 50 µs cycles, telegrams on, master or slave) whose RAM is
/// anything: `fill` rotated word by word everywhere, then `ram` from word 0 (the arbitrary
/// inputs of the property tests; 410B §4.2: whatever the RAM holds, the chip must run).
/// `reg25` is written to 25H (MSTTCHK, PHAS12, FLMDTADR) when given.
pub fn arbitrary_chip(ram: &[u16], fill: u16, master: bool, reg25: Option<u16>) -> Chip {
    use sercon_regs::{Register, SerconBus, SerconBusExt};
    let mut chip = Chip::new(ChipConfig::sercon816());
    chip.write(Register::MclkDiv, 31);
    for a in 0..2048u16 {
        chip.write_ram(a, fill.rotate_left(u32::from(a % 16)));
    }
    for (i, w) in (0u16..).zip(ram) {
        chip.write_ram(i, *w);
    }
    chip.write(Register::Tscyc0, 50);
    chip.write(Register::Phas, u16::from(fill as u8) | 0x0400);
    if let Some(r) = reg25 {
        chip.write(Register::Thrpt, r);
    }
    chip.write(Register::Jtrdel2, 3);
    chip.write(Register::Ctrl3, 1 << 8);
    chip.write(
        Register::Ctrl0C,
        if master {
            CTRL0C_MASTER | CTRL0C_CYCSTART
        } else {
            1
        },
    );
    chip
}

/// A telegram as the line carries it, with its hint, from `start` at 16 Mbit/s (816 §2.3.1,
/// 62.5 ns per bit) on a line dark before it.
pub fn hinted_frame(start: Instant, bytes: &[u8]) -> LineSegment {
    try_hinted_frame(start, bytes).expect("encodable")
}

/// [`hinted_frame`], `None` for bytes the line layer cannot carry (none, or too many).
pub fn try_hinted_frame(start: Instant, bytes: &[u8]) -> Option<LineSegment> {
    let mut enc = Encoder::new(LineConfig::new(Coding::Nrzi, Polarity::LightOnLow));
    let mut bits = BitVec::new();
    enc.encode(bytes, &mut bits).ok()?;
    Some(LineSegment {
        start,
        bit_time: Duration::from_picos(62_500),
        signal: LineSignal::Bits(Shared::new(bits)),
        level_before: false,
        hint: Some(Shared::new(FrameHint {
            telegram: Shared::from(bytes),
            offset: 0,
            coded: None,
        })),
        distorted: false,
        then_filler: false,
    })
}
