//! The program on a node's host processor ([`HostProgram`], defined beside [`SerconBus`] in
//! `sercon-regs` so that the driver implements it without knowing the simulator): woken by the
//! controller's interrupt pins and by its own deadline, it reaches its chip only through
//! [`SerconBus`] ([`NodeBus`]), at the node's current time, each access costing a configurable
//! time. Times are the node's own (its clock may run fast or slow, [`crate::clock::NodeClock`]).
//! In a running [`crate::Simulation`] a program's wake waits at each access for the access's
//! bus time while the ring and the other hosts go on (spec-notes "A host's bus time"); a
//! program is written as plain code all the same.

use sercon_model::Chip;
use sercon_regs::SerconBus;
use sercos_wire::time::{Duration, Instant};

pub use sercon_regs::host::{HostProgram, Wake};

/// The host's access to its chip: [`SerconBus`] at the chip's current time; every access
/// then advances the chip by the access cost, as a real bus cycle takes time.
pub struct NodeBus<'a> {
    chip: &'a mut Chip,
    cost: Duration,
}

impl<'a> NodeBus<'a> {
    /// The bus of `chip` with `cost` per access.
    pub fn new(chip: &'a mut Chip, cost: Duration) -> Self {
        NodeBus { chip, cost }
    }

    /// The node's current time.
    pub fn now(&self) -> Instant {
        self.chip.now()
    }

    /// Lets `d` pass (a busy wait of the host).
    pub fn wait(&mut self, d: Duration) {
        let t = self.chip.now().saturating_add(d);
        self.chip.advance_to(t);
    }

    /// A DMA read of the receive FIFO (410B §2 DMAACKRN), costing one access.
    #[doc(alias = "DMAACKRN")]
    pub fn dma_read_receive(&mut self) -> u16 {
        let v = self.chip.dma_read_receive();
        self.spend();
        v
    }

    /// A DMA write of the transmit FIFO (410B §2 DMAACKTN), costing one access.
    #[doc(alias = "DMAACKTN")]
    pub fn dma_write_transmit(&mut self, value: u16) {
        self.chip.dma_write_transmit(value);
        self.spend();
    }

    fn spend(&mut self) {
        if self.cost > Duration::ZERO {
            let t = self.chip.now().saturating_add(self.cost);
            self.chip.advance_to(t);
        }
    }
}

impl SerconBus for NodeBus<'_> {
    fn read_register(&mut self, address: u8) -> u16 {
        let v = self.chip.read_register(address);
        self.spend();
        v
    }

    fn write_register(&mut self, address: u8, value: u16) {
        self.chip.write_register(address, value);
        self.spend();
    }

    fn read_ram(&mut self, address: u16) -> u16 {
        let v = self.chip.read_ram(address);
        self.spend();
        v
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        self.chip.write_ram(address, value);
        self.spend();
    }
}

/// A host that does nothing (a chip left at its reset state).
#[derive(Debug, Clone, Copy, Default)]
pub struct IdleHost;

impl HostProgram for IdleHost {
    fn wake(&mut self, _bus: &mut dyn SerconBus, _now: Instant, _why: Wake) -> Option<Instant> {
        None
    }
}

/// One host bus access of a [`StaticImageHost`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Access {
    /// Write a control register (410B §4.1).
    Register {
        /// Register address.
        address: u8,
        /// Value written.
        value: u16,
    },
    /// Write RAM words from `address` on (410B §4.2).
    Ram {
        /// First word address.
        address: u16,
        /// The words.
        words: Vec<u16>,
    },
}

/// A host that writes a fixed configuration (RAM image and registers) at start and after
/// every power-on, then idles: enough for a static ring (drivers come later).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct StaticImageHost {
    /// The accesses, in order.
    pub accesses: Vec<Access>,
}

impl HostProgram for StaticImageHost {
    fn wake(&mut self, bus: &mut dyn SerconBus, _now: Instant, why: Wake) -> Option<Instant> {
        if matches!(why, Wake::Start | Wake::PowerOn) {
            for a in &self.accesses {
                match a {
                    Access::Register { address, value } => bus.write_register(*address, *value),
                    Access::Ram { address, words } => {
                        for (i, w) in words.iter().enumerate() {
                            let Ok(i) = u16::try_from(i) else { break };
                            bus.write_ram(address.wrapping_add(i), *w);
                        }
                    }
                }
            }
        }
        None
    }

    /// Writes its image at start and power-on only.
    fn inert(&self) -> bool {
        true
    }
}
