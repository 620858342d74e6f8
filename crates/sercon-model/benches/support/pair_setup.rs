//! The `ring_pair` bench's two chips: a SERCON816 master and one slave in phase 4 with an
//! 8-word MDT and an 8-word AT per cycle (410B §4.2.1–§4.2.3; 816 §2.3.1), in a given
//! shape. Used by `benches/ring_pair.rs` and `tests/pair_horizons.rs`.

use sercon_model::{Chip, ChipConfig};
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{EndMarker, RxHeader, TxEnable, TxHeader};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};

/// 410B §4.1 0CH.0 MSTEN, 0CH.1 MSTMASTER, 0CH.10 CYCSTART; 3H.8 ENTMT; 1H.3 REPON.
const MSTEN: u16 = 1 << 0;
const MSTMASTER: u16 = 1 << 1;
const CYCSTART: u16 = 1 << 10;
const ENTMT: u16 = 1 << 8;
const REPON: u16 = 1 << 3;

/// The shape of one pair: cycle, telegram times (in 0.5 µs units after the MST, 410B §4.2.1
/// TRT), fibre delay, and whether the master's repeater is on too (then each chip's output
/// depends on the other's at once, which the loop's "reply" bound covers).
#[derive(Debug, Clone, Copy)]
pub struct Shape {
    /// TSCYC0 in 0.5 µs units.
    pub tscyc: u16,
    /// The MDT's TRT.
    pub mdt_trt: u16,
    /// The AT's TRT.
    pub at_trt: u16,
    /// The fibre delay each way, ns.
    pub delay_ns: u64,
    /// The master's repeater is on too.
    pub master_repeats: bool,
}

impl Shape {
    /// The bench's pair: 62.5 µs cycle (TSCYC0 = 125), MDT 1 µs and AT 20 µs after the MST,
    /// 1 µs of fibre each way, the master ending the ring (no repeater).
    pub const BENCH: Shape = Shape {
        tscyc: 125,
        mdt_trt: 2,
        at_trt: 40,
        delay_ns: 1000,
        master_repeats: false,
    };
}

/// Any pair shape the property tests try: cycle 45–100 µs, MDT 0.5–15 µs and AT 15–40 µs
/// after the MST, 50 ns–4 µs of fibre, the master's repeater on or off.
// The bench does not use it.
#[allow(dead_code)]
pub fn any_shape() -> impl proptest::strategy::Strategy<Value = Shape> {
    use proptest::prelude::*;
    (90u16..200, 1u16..30, 30u16..80, 50u64..4000, any::<bool>()).prop_map(
        |(tscyc, mdt_trt, at_trt, delay_ns, master_repeats)| Shape {
            tscyc,
            mdt_trt,
            at_trt,
            delay_ns,
            master_repeats,
        },
    )
}

/// A SERCON816 at 16 Mbit/s (816 §2.3.1) with a 0.5 µs unit (410B §4.1 0EH MCLKDIV = 15).
fn chip(tscyc: u16) -> Chip {
    let mut c = Chip::new(ChipConfig::sercon816());
    c.write(Register::MclkDiv, 15);
    c.write(Register::Tscyc0, tscyc);
    c
}

fn control(len: u16) -> u16 {
    ContainerControl::new(len, false, 0, false, true).map_or(0, |c| c.to_word())
}

/// 410B §4.2.1 transmit header at `at`, one 8-word container (§4.2.2), data at `at + 5`.
fn tx_block(c: &mut Chip, at: u16, adr: u8, trt: u16, pt: u16) {
    let h = TxHeader {
        adr,
        en: TxEnable::Continuous,
        trt,
        tlen: 8,
        pt,
        ..TxHeader::default()
    };
    c.write_ram_words(at, &h.to_words(Variant::Sercon816));
    c.write_ram(at + 4, control(8));
    let data: Vec<u16> = (0..8).map(|i| 0x1000 * u16::from(adr & 0xF) + i).collect();
    c.write_ram_words(at + 5, &data);
}

/// 410B §4.2.1 receive header at `at` with one 8-word container.
fn rx_block(c: &mut Chip, at: u16, adr: u8, trt: u16, pt: u16) {
    let h = RxHeader {
        adr,
        achk: true,
        trt,
        tlen: 8,
        pt,
        ..RxHeader::default()
    };
    c.write_ram_words(at, &h.to_words(Variant::Sercon816));
    c.write_ram_words(at + 5, &[control(8), 0]);
}

/// The bench's master and slave in phase 4, in the given shape.
pub fn chips(shape: Shape) -> [Chip; 2] {
    let mut m = chip(shape.tscyc);
    let mut s = chip(shape.tscyc);
    m.write_ram(0, 16);
    tx_block(&mut m, 16, 255, shape.mdt_trt, 29);
    rx_block(&mut m, 29, 1, shape.at_trt, 44);
    m.write_ram_words(44, &EndMarker::default().to_words());
    s.write_ram(0, 16);
    rx_block(&mut s, 16, 255, shape.mdt_trt, 31);
    tx_block(&mut s, 31, 1, shape.at_trt, 44);
    s.write_ram_words(44, &EndMarker::default().to_words());
    s.write(Register::Phas, 0xFF04);
    s.write(Register::Ctrl3, ENTMT);
    s.write(Register::Ctrl0C, MSTEN);
    if !shape.master_repeats {
        let c1 = m.read(Register::Ctrl1);
        m.write(Register::Ctrl1, c1 & !REPON);
    }
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    [m, s]
}
