//! The 8-bit bus with BYTEDIR (410B §2 pins BUSWIDTH 99, BYTEDIR 100, A0) and the latch
//! reading of `docs/spec-notes.md`.

mod common;

use common::MemBus;
use sercon_regs::Variant::Sercon410b;
use sercon_regs::{ByteBus, ByteDir, SerconBus};

#[test]
fn bytedir_0_addresses_the_low_byte_at_a0_0() {
    // 410B §2 BYTEDIR: 0 → A0 = 0 addresses the lower 8 bits (low byte first).
    let mut inner = MemBus::new(Sercon410b);
    inner.regs[0x0F] = 0x1234;
    let mut bus = ByteBus::new(inner, ByteDir::LowFirst);
    assert_eq!(bus.read_register_byte(0x1E), 0x34);
    assert_eq!(bus.read_register_byte(0x1F), 0x12);
}

#[test]
fn bytedir_1_addresses_the_high_byte_at_a0_0() {
    // 410B §2 BYTEDIR: 1 → A0 = 0 addresses the upper 8 bits (high byte first).
    let mut inner = MemBus::new(Sercon410b);
    inner.ram[0x100] = 0xABCD;
    let mut bus = ByteBus::new(inner, ByteDir::HighFirst);
    assert_eq!(bus.read_ram_byte(0x200), 0xAB);
    assert_eq!(bus.read_ram_byte(0x201), 0xCD);
    bus.write_ram_byte(0x202, 0x11);
    bus.write_ram_byte(0x203, 0x22);
    assert_eq!(bus.inner().ram[0x101], 0x1122);
}

#[test]
fn a_write_takes_effect_with_the_second_byte() {
    // Reading chosen (spec-notes): the first byte (A0 = 0) is latched; the second byte
    // (A0 = 1) writes the whole word.
    let mut bus = ByteBus::new(MemBus::new(Sercon410b), ByteDir::LowFirst);
    bus.write_register_byte(0x1E, 0x78);
    assert_eq!(
        bus.inner().regs[0x0F],
        0,
        "first byte alone changes nothing"
    );
    bus.write_register_byte(0x1F, 0x56);
    assert_eq!(bus.inner().regs[0x0F], 0x5678);
    // A lone second byte combines with the latch as it stands.
    bus.write_register_byte(0x21, 0x9A);
    assert_eq!(bus.inner().regs[0x10], 0x9A78);
}

#[test]
fn a_word_read_byte_by_byte_pops_rfifo_once() {
    // 410B §4.1 27H: reading RFIFO pops; the first byte reads the word, the second the latch.
    let mut inner = MemBus::new(Sercon410b);
    inner.rfifo.extend([0xBEEF, 0xCAFE]);
    let mut bus = ByteBus::new(inner, ByteDir::LowFirst);
    assert_eq!(bus.read_register_byte(0x4E), 0xEF);
    assert_eq!(bus.read_register_byte(0x4F), 0xBE);
    assert_eq!(bus.inner().rfifo.len(), 1);
    assert_eq!(bus.read_register(0x27), 0xCAFE);
}

#[test]
fn word_access_through_the_byte_bus_equals_direct_access() {
    for dir in [ByteDir::LowFirst, ByteDir::HighFirst] {
        let mut bus = ByteBus::new(MemBus::new(Sercon410b), dir);
        bus.write_register(0x13, 0xA55A);
        bus.write_ram(0x3FF, 0x0102);
        assert_eq!(bus.inner().regs[0x13], 0xA55A);
        assert_eq!(bus.inner().ram[0x3FF], 0x0102);
        assert_eq!(bus.read_register(0x13), 0xA55A);
        assert_eq!(bus.read_ram(0x3FF), 0x0102);
        assert_eq!(bus.bytedir(), dir);
        // Out-of-range addresses are masked, never a panic.
        let _ = bus.read_register(0xFF);
        let _ = bus.read_ram(0xFFFF);
    }
}
