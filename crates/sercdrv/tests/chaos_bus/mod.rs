//! A bus whose every read is arbitrary (`mod chaos_bus;`), for the drivers' "no panic from
//! input" property tests: registers from a pseudo-random stream, RAM initialised at random and
//! then holding what the driver writes (410B §4.1 registers, §4.2 RAM as a faulty chip or the
//! far end of the line could leave them).
#![allow(dead_code)]

use sercon_regs::{SerconBus, Variant};

/// See the module notes.
pub struct ChaosBus {
    state: u64,
    /// The RAM as the driver reads and writes it.
    pub ram: Vec<u16>,
}

impl ChaosBus {
    /// A bus of `variant`'s RAM size, every word drawn from the stream of `seed`.
    pub fn new(seed: u64, variant: Variant) -> ChaosBus {
        let mut bus = ChaosBus {
            state: seed.max(1),
            ram: Vec::new(),
        };
        bus.ram = (0..variant.ram_words()).map(|_| bus.next()).collect();
        bus
    }

    /// The next word of the stream (xorshift64*).
    pub fn next(&mut self) -> u16 {
        self.state ^= self.state >> 12;
        self.state ^= self.state << 25;
        self.state ^= self.state >> 27;
        (self.state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 48) as u16
    }
}

impl SerconBus for ChaosBus {
    fn read_register(&mut self, _address: u8) -> u16 {
        self.next()
    }
    fn write_register(&mut self, _address: u8, _value: u16) {}
    fn read_ram(&mut self, address: u16) -> u16 {
        self.ram.get(usize::from(address)).copied().unwrap_or(0)
    }
    fn write_ram(&mut self, address: u16, value: u16) {
        if let Some(w) = self.ram.get_mut(usize::from(address)) {
            *w = value;
        }
    }
}

/// A [`ChaosBus`] whose VERSION register (0H) answers as `variant`'s does (ERRATA "0H
/// VERSION": 0002H on the 410B, 0010H on the 816), so that a driver gets past its
/// initialisation and meets arbitrary flags, status and RAM after it.
pub struct Versioned(pub ChaosBus, pub Variant);

impl SerconBus for Versioned {
    fn read_register(&mut self, address: u8) -> u16 {
        if address == 0 {
            match self.1 {
                Variant::Sercon816 => 0x0010,
                Variant::Sercon410b => 0x0002,
            }
        } else {
            self.0.read_register(address)
        }
    }
    fn write_register(&mut self, a: u8, v: u16) {
        self.0.write_register(a, v)
    }
    fn read_ram(&mut self, a: u16) -> u16 {
        self.0.read_ram(a)
    }
    fn write_ram(&mut self, a: u16, v: u16) {
        self.0.write_ram(a, v)
    }
}
