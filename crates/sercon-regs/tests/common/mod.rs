//! A plain-memory `SerconBus` for the tests: registers and RAM store what is written,
//! except 27H, whose reads pop a queue (RFIFO) and whose writes push another (TFIFO).
#![allow(dead_code)]

use sercon_regs::{SerconBus, Variant};

pub struct MemBus {
    pub variant: Variant,
    pub regs: [u16; 64],
    pub ram: Vec<u16>,
    pub rfifo: std::collections::VecDeque<u16>,
    pub tfifo: Vec<u16>,
    pub register_reads: usize,
    pub ram_reads: usize,
}

impl MemBus {
    pub fn new(variant: Variant) -> Self {
        MemBus {
            variant,
            regs: [0; 64],
            ram: vec![0; usize::from(variant.ram_words())],
            rfifo: Default::default(),
            tfifo: Vec::new(),
            register_reads: 0,
            ram_reads: 0,
        }
    }
}

impl SerconBus for MemBus {
    fn read_register(&mut self, address: u8) -> u16 {
        self.register_reads += 1;
        let a = usize::from(address & 0x3F);
        if a == 0x27 {
            return self.rfifo.pop_front().unwrap_or(0);
        }
        self.regs[a]
    }
    fn write_register(&mut self, address: u8, value: u16) {
        let a = usize::from(address & 0x3F);
        if a == 0x27 {
            self.tfifo.push(value);
        } else {
            self.regs[a] = value;
        }
    }
    fn read_ram(&mut self, address: u16) -> u16 {
        self.ram_reads += 1;
        self.ram[usize::from(address & self.variant.ram_address_mask())]
    }
    fn write_ram(&mut self, address: u16, value: u16) {
        let a = usize::from(address & self.variant.ram_address_mask());
        self.ram[a] = value;
    }
}
