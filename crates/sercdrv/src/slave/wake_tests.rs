//! Which bus accesses a wake costs: the driver reads what can have changed, not everything
//! (410B §4.1 3H–7H interrupts, §4.2.4 slave service container word 0 CMD_AT).

use sercon_regs::host::{HostProgram, Wake};
use sercon_regs::ram::service::sc_word_address;
use sercon_regs::{IntFlagsHi, IntFlagsLo, Register, SerconBus, Variant};
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::ServiceError;
use sercos_wire::telegram::{CommunicationPhase, StatusWord};
use sercos_wire::time::Instant;

use super::{CyclicLengths, DeviceRefusal, SlaveConfig, SlaveDevice, SlaveDriver};
use crate::idn_store::IdnStore;

/// One bus access, as the fake chip saw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Access {
    ReadReg(u8),
    WriteReg(u8),
    ReadRam(u16),
    WriteRam(u16),
}

/// Registers and RAM with the interrupt rules the driver relies on: 4H/5H write 1 to clear
/// (ERRATA "410B 4H/5H"), 3H.0 INTFL0 = an enabled flag is set (6H/7H, 410B §4.1).
struct FakeChip {
    regs: [u16; 64],
    ram: Vec<u16>,
    log: Vec<Access>,
    /// 5H flags raised when the driver clears 4H (an interrupt arriving while it serves).
    raise_hi_on_clear: u16,
}

impl FakeChip {
    fn new() -> FakeChip {
        let mut regs = [0u16; 64];
        // ERRATA "0H VERSION": 0002H on the 410B.
        regs[usize::from(Register::Version as u8)] = 0x0002;
        FakeChip {
            regs,
            ram: vec![0; usize::from(Variant::Sercon410b.ram_words())],
            log: Vec::new(),
            raise_hi_on_clear: 0,
        }
    }

    fn reg(&self, r: Register) -> u16 {
        self.regs.get(usize::from(r as u8)).copied().unwrap_or(0)
    }

    fn set_reg(&mut self, r: Register, v: u16) {
        if let Some(slot) = self.regs.get_mut(usize::from(r as u8)) {
            *slot = v;
        }
    }
}

impl SerconBus for FakeChip {
    fn read_register(&mut self, address: u8) -> u16 {
        self.log.push(Access::ReadReg(address));
        if address == Register::Ctrl3 as u8 {
            let requested = self.reg(Register::IntFlagsLo) & self.reg(Register::En0IntLo) != 0
                || self.reg(Register::IntFlagsHi) & self.reg(Register::En0IntHi) != 0;
            return (self.reg(Register::Ctrl3) & !1) | u16::from(requested);
        }
        self.regs.get(usize::from(address)).copied().unwrap_or(0)
    }

    fn write_register(&mut self, address: u8, value: u16) {
        self.log.push(Access::WriteReg(address));
        if address == Register::IntFlagsLo as u8 || address == Register::IntFlagsHi as u8 {
            if let Some(slot) = self.regs.get_mut(usize::from(address)) {
                *slot &= !value;
            }
            if address == Register::IntFlagsLo as u8 && value != 0 {
                let raise = std::mem::take(&mut self.raise_hi_on_clear);
                let hi = self.reg(Register::IntFlagsHi) | raise;
                self.set_reg(Register::IntFlagsHi, hi);
            }
        } else if let Some(slot) = self.regs.get_mut(usize::from(address)) {
            *slot = value;
        }
    }

    fn read_ram(&mut self, address: u16) -> u16 {
        self.log.push(Access::ReadRam(address));
        self.ram.get(usize::from(address)).copied().unwrap_or(0)
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        self.log.push(Access::WriteRam(address));
        if let Some(w) = self.ram.get_mut(usize::from(address)) {
            *w = value;
        }
    }
}

/// A store with no IDNs.
struct NoIdns;

impl IdnStore for NoIdns {
    fn read_element(&self, _idn: Idn, _element: Element) -> Result<Vec<u16>, ServiceError> {
        Err(ServiceError::IdnNotPresent)
    }
    fn write_element(&mut self, _: Idn, _: Element, _: &[u16]) -> Result<(), ServiceError> {
        Err(ServiceError::IdnNotPresent)
    }
    fn set_phase(&mut self, _phase: CommunicationPhase) {}
}

/// A device whose status word the test sets.
struct Device {
    status: u16,
    store: NoIdns,
}

impl SlaveDevice for Device {
    fn idn_store(&mut self) -> &mut dyn IdnStore {
        &mut self.store
    }
    fn cyclic_lengths(&self) -> Result<CyclicLengths, DeviceRefusal> {
        Ok(CyclicLengths::default())
    }
    fn enter_phase(&mut self, _: Instant, _: CommunicationPhase) -> Result<(), DeviceRefusal> {
        Ok(())
    }
    fn command_record(&mut self, _: Instant, _: &[u8]) -> Result<(), DeviceRefusal> {
        Ok(())
    }
    fn status_word(&mut self, _now: Instant) -> u16 {
        self.status
    }
    fn feedback_data(&mut self, _now: Instant, out: &mut Vec<u8>) {
        out.clear();
    }
}

fn started() -> (SlaveDriver<Device>, FakeChip) {
    let device = Device {
        status: 0,
        store: NoIdns,
    };
    let mut slave =
        SlaveDriver::new(SlaveConfig::new(Variant::Sercon410b, 3), device).expect("config");
    let mut chip = FakeChip::new();
    slave.wake(&mut chip, Instant::ZERO, Wake::Start);
    assert!(slave.failure().is_none(), "{:?}", slave.failure());
    chip.log.clear();
    (slave, chip)
}

const INT0_HIGH: Wake = Wake::Interrupt {
    int0: true,
    int1: false,
};

/// One end of block: INT_COMEND raised, the driver woken for INT0 going high.
fn end_of_block(slave: &mut SlaveDriver<Device>, chip: &mut FakeChip) {
    let lo = chip.reg(Register::IntFlagsLo) | IntFlagsLo::INT_COMEND.bits();
    chip.set_reg(Register::IntFlagsLo, lo);
    chip.log.clear();
    slave.wake(chip, Instant::ZERO, INT0_HIGH);
}

fn cmd_at(slave: &SlaveDriver<Device>, chip: &FakeChip) -> bool {
    let slot = slave.service_channel().slot();
    let word0 = sc_word_address(slot.variant(), slot.address(), 0);
    // 410B §4.2.4 slave word 0 bit 3: CMD_AT.
    chip.ram.get(usize::from(word0)).copied().unwrap_or(0) & (1 << 3) != 0
}

// 410B §4.1 3H.0-2, 6H/7H: all the driver's flags are on INT0, 1-active; INT0 low means
// none is set, so the wake for its fall reads nothing, while a wake for INT0 high reads the
// flags.
#[test]
fn int0_falling_costs_no_bus_access() {
    let (mut slave, mut chip) = started();
    slave.wake(
        &mut chip,
        Instant::ZERO,
        Wake::Interrupt {
            int0: false,
            int1: false,
        },
    );
    assert_eq!(chip.log, Vec::new());
    slave.wake(&mut chip, Instant::ZERO, INT0_HIGH);
    assert_eq!(
        chip.log,
        vec![
            Access::ReadReg(Register::IntFlagsLo as u8),
            Access::ReadReg(Register::IntFlagsHi as u8)
        ]
    );
}

// sercos-telegrams.md AT status word bit 5 goes out as CMD_AT (410B §4.2.4 slave word 0.3,
// ERRATA "service info in a container"): set and cleared as the status word says, the
// container's control words read and written only when the bit changes.
#[test]
fn cmd_at_follows_status_bit_5_and_is_written_only_on_change() {
    let (mut slave, mut chip) = started();
    let slot = *slave.service_channel().slot();
    let controls: Vec<u16> = (0..5)
        .map(|o| sc_word_address(slot.variant(), slot.address(), o))
        .collect();
    let touches_controls = |log: &[Access]| {
        log.iter().any(|a| match a {
            Access::ReadRam(x) | Access::WriteRam(x) => controls.contains(x),
            _ => false,
        })
    };
    end_of_block(&mut slave, &mut chip);
    assert!(!cmd_at(&slave, &chip));
    assert!(!touches_controls(&chip.log), "{:?}", chip.log);

    slave.device_mut().status = StatusWord::COMMAND_CHANGE;
    end_of_block(&mut slave, &mut chip);
    assert!(cmd_at(&slave, &chip));
    assert!(touches_controls(&chip.log));

    end_of_block(&mut slave, &mut chip);
    assert!(cmd_at(&slave, &chip));
    assert!(!touches_controls(&chip.log), "{:?}", chip.log);

    slave.device_mut().status = 0;
    end_of_block(&mut slave, &mut chip);
    assert!(!cmd_at(&slave, &chip));
}

// 410B §4.1 3H.0 INTFL0: a flag raised while the driver serves the block's end is seen by
// the one 3H read after the round and served in the same wake; with none, 4H/5H are read
// once only.
#[test]
fn flag_raised_while_serving_is_served_in_the_same_wake() {
    let (mut slave, mut chip) = started();
    let sc = IntFlagsHi::int_sc(slave.service_channel().slot().nsv())
        .expect("container 0-7")
        .bits();
    end_of_block(&mut slave, &mut chip);
    let flag_reads = |log: &[Access]| {
        log.iter()
            .filter(|a| **a == Access::ReadReg(Register::IntFlagsLo as u8))
            .count()
    };
    assert_eq!(flag_reads(&chip.log), 1);
    assert_eq!(
        chip.log.last(),
        Some(&Access::ReadReg(Register::Ctrl3 as u8))
    );

    chip.raise_hi_on_clear = sc;
    end_of_block(&mut slave, &mut chip);
    assert_eq!(chip.reg(Register::IntFlagsHi) & sc, 0, "INT_SC served");
    assert_eq!(flag_reads(&chip.log), 2);
}

/// The block-0 AT's status word address (single buffer: data word 0, 410B §4.2.2).
fn noncyclic_status_address(slave: &SlaveDriver<Device>) -> u16 {
    super::RecordPlaces::find(
        slave.noncyclic_layout(),
        crate::ram_layout::PhaseGroup::NonCyclic,
    )
    .expect("block 0 records")
    .at
    .data
}

// 410B §4.2.2: only the processor writes a transmit container's data words, so a
// single-buffered AT word is written when it changes, not every cycle; a new start (RAM
// written anew) writes it again.
#[test]
fn single_buffer_at_words_are_written_when_they_change() {
    let (mut slave, mut chip) = started();
    let status_at = noncyclic_status_address(&slave);
    let writes = |log: &[Access]| log.contains(&Access::WriteRam(status_at));
    slave.device_mut().status = 0x4000;
    end_of_block(&mut slave, &mut chip);
    assert!(writes(&chip.log));
    assert_eq!(chip.ram.get(usize::from(status_at)), Some(&0x4000));
    end_of_block(&mut slave, &mut chip);
    assert!(!writes(&chip.log), "{:?}", chip.log);
    slave.device_mut().status = 0x8000;
    end_of_block(&mut slave, &mut chip);
    assert!(writes(&chip.log));
    assert_eq!(chip.ram.get(usize::from(status_at)), Some(&0x8000));
    // A power-on (the chip's RAM lost) starts over: the status word is written again.
    chip.ram.fill(0);
    slave.wake(&mut chip, Instant::ZERO, Wake::PowerOn);
    end_of_block(&mut slave, &mut chip);
    assert_eq!(chip.ram.get(usize::from(status_at)), Some(&0x8000));
}

/// The block's end with PHASREC (0BH) = `phase`.
fn end_of_block_in(slave: &mut SlaveDriver<Device>, chip: &mut FakeChip, phase: u16) {
    chip.set_reg(Register::PhasRec, phase);
    end_of_block(slave, chip);
}

// 410B §4.1 0AH/0BH: PHASREC is read at the block's end while PHAS1 arms a step up, and the
// slave follows it; with nothing armed (PHAS1 = 0, here phase 2 without S-0-0127) it is not
// read, and a drop to phase 0 comes through INT_PHAS0 (4H.5).
#[test]
fn phasrec_is_read_only_while_a_step_is_armed() {
    let (mut slave, mut chip) = started();
    let phasrec_read = |log: &[Access]| log.contains(&Access::ReadReg(Register::PhasRec as u8));
    end_of_block_in(&mut slave, &mut chip, 1);
    assert!(phasrec_read(&chip.log));
    assert_eq!(slave.phase(), CommunicationPhase::Phase1);
    end_of_block_in(&mut slave, &mut chip, 2);
    assert_eq!(slave.phase(), CommunicationPhase::Phase2);
    end_of_block_in(&mut slave, &mut chip, 2);
    assert!(!phasrec_read(&chip.log), "{:?}", chip.log);
    assert_eq!(slave.phase(), CommunicationPhase::Phase2);
    let lo = chip.reg(Register::IntFlagsLo) | IntFlagsLo::INT_PHAS0.bits();
    chip.set_reg(Register::IntFlagsLo, lo);
    end_of_block_in(&mut slave, &mut chip, 0);
    assert_eq!(slave.phase(), CommunicationPhase::Phase0);
}
