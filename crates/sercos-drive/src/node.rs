//! The emulated drive as a node on the ring: the SERCDRV slave ([`sercdrv::slave`]) over
//! the node's SERCON, serving an [`EmulatedDrive`] and its [`IdnDatabase`]; a
//! [`HostProgram`] the ring simulator runs.
//!
//! ```no_run
//! use sercon_regs::Variant;
//! use sercos_drive::node::DriveNode;
//! # fn main() -> Result<(), sercos_drive::node::NodeError> {
//! let node = DriveNode::from_file(Variant::Sercon816, 3, "drive.toml".as_ref())?;
//! # let _ = node; Ok(()) }
//! ```

use std::path::Path;

use sercdrv::idn_store::IdnStore;
use sercdrv::slave::{
    CyclicLengths, DeviceRefusal, SlaveConfig, SlaveDevice, SlaveDriver, SlaveDriverEvent,
    SlaveError,
};
use sercon_regs::host::{HostProgram, Wake};
use sercon_regs::{SerconBus, Variant};
use sercos_wire::telegram::CommunicationPhase;
use sercos_wire::time::{BitRate, Instant};

use crate::config_file::{self, ConfigError};
use crate::database::IdnDatabase;
use crate::drive::EmulatedDrive;
use crate::procedure::BIT_RATE;
use crate::telegram_layout::{self, RECORD_HEADER_BYTES};

/// Why a drive node could not be made.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NodeError {
    /// The TOML IDN file could not be loaded.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The slave driver refused the configuration.
    #[error(transparent)]
    Slave(#[from] SlaveError),
    /// P-0-0002 holds no SERCOS bit rate (2, 4, 8 or 16 Mbit/s).
    #[error("P-0-0002 = {0} is not a bit rate of 2, 4, 8 or 16 Mbit/s")]
    BitRate(i128),
}

impl SlaveDevice for EmulatedDrive {
    fn idn_store(&mut self) -> &mut dyn IdnStore {
        self.database_mut()
    }

    fn cyclic_lengths(&self) -> Result<CyclicLengths, DeviceRefusal> {
        // sercos-facts.md S-0-0015/16/24: the telegram type gives the cyclic data.
        let layout =
            telegram_layout::layout(self.database()).map_err(|e| DeviceRefusal(e.to_string()))?;
        let bytes = |record: usize| {
            u16::try_from(record.saturating_sub(RECORD_HEADER_BYTES))
                .map_err(|_| DeviceRefusal(format!("record of {record} bytes")))
        };
        Ok(CyclicLengths {
            mdt_data_bytes: bytes(layout.mdt_record_len())?,
            at_data_bytes: bytes(layout.at_record_len())?,
        })
    }

    fn enter_phase(
        &mut self,
        now: Instant,
        phase: CommunicationPhase,
    ) -> Result<(), DeviceRefusal> {
        self.advance_to(now);
        self.set_phase(phase)
            .map_err(|e| DeviceRefusal(e.to_string()))
    }

    fn command_record(&mut self, now: Instant, record: &[u8]) -> Result<(), DeviceRefusal> {
        self.receive_mdt_record(now, record)
            .map_err(|e| DeviceRefusal(e.to_string()))
    }

    fn status_word(&mut self, now: Instant) -> u16 {
        self.advance_to(now);
        EmulatedDrive::status_word(self).raw()
    }

    fn feedback_data(&mut self, now: Instant, out: &mut Vec<u8>) {
        self.advance_to(now);
        self.write_at_cyclic_data(out);
    }
}

/// An emulated drive behind a SERCDRV slave: what runs on a drive's host processor.
#[derive(Debug)]
pub struct DriveNode {
    driver: SlaveDriver<EmulatedDrive>,
}

impl DriveNode {
    /// A drive at `address` on a `variant` with the variant's usual clocks
    /// ([`SlaveConfig::new`]) and the bit rate of its P-0-0002 (default 2 Mbit/s).
    pub fn new(
        variant: Variant,
        address: u8,
        database: IdnDatabase,
    ) -> Result<DriveNode, NodeError> {
        let mut config = SlaveConfig::new(variant, address);
        config.bit_rate = bit_rate_of(&database)?;
        DriveNode::with_config(config, database)
    }

    /// A drive with a full slave configuration (clocks, phase 0–2 cycle, buffering); the
    /// bit rate is the configuration's, and P-0-0002 is set to it (S-0-0127 times the MDT
    /// at the line's rate).
    pub fn with_config(
        config: SlaveConfig,
        mut database: IdnDatabase,
    ) -> Result<DriveNode, NodeError> {
        // spec-notes "Driver slave and drive node": the line's rate is a switch on the drive,
        // P-0-0002 shows it.
        let _ = database.set_internal(
            BIT_RATE,
            &sercos_wire::attribute::Value::Unsigned(u64::from(config.bit_rate.mbit())),
        );
        let drive = EmulatedDrive::new(database, Instant::ZERO);
        Ok(DriveNode {
            driver: SlaveDriver::new(config, drive)?,
        })
    }

    /// A drive whose IDNs come from the TOML file at `path` ([`config_file`]).
    pub fn from_file(variant: Variant, address: u8, path: &Path) -> Result<DriveNode, NodeError> {
        DriveNode::new(variant, address, config_file::load(path)?)
    }

    /// A drive whose IDNs come from TOML `text` (named `path` in errors).
    pub fn from_toml(
        variant: Variant,
        address: u8,
        text: &str,
        path: &Path,
    ) -> Result<DriveNode, NodeError> {
        DriveNode::new(variant, address, config_file::parse(text, path)?)
    }

    /// The slave driver.
    pub fn driver(&self) -> &SlaveDriver<EmulatedDrive> {
        &self.driver
    }

    /// The slave driver, mutable.
    pub fn driver_mut(&mut self) -> &mut SlaveDriver<EmulatedDrive> {
        &mut self.driver
    }

    /// The emulated drive.
    pub fn drive(&self) -> &EmulatedDrive {
        self.driver.device()
    }

    /// The emulated drive, mutable.
    pub fn drive_mut(&mut self) -> &mut EmulatedDrive {
        self.driver.device_mut()
    }

    /// The drive address.
    pub fn address(&self) -> u8 {
        self.driver.config().address
    }

    /// The phase the node follows.
    pub fn phase(&self) -> CommunicationPhase {
        self.driver.phase()
    }

    /// Takes the slave driver's events since the last call.
    pub fn take_events(&mut self) -> Vec<SlaveDriverEvent> {
        self.driver.take_events()
    }
}

impl HostProgram for DriveNode {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        self.driver.wake(bus, now, why)
    }
}

/// P-0-0002, the drive's bit rate in Mbit/s (spec-notes "emulated drive": the line's rate
/// is a switch on the drive), 2 when absent.
fn bit_rate_of(database: &IdnDatabase) -> Result<BitRate, NodeError> {
    let mbit = database.number(BIT_RATE).unwrap_or(2);
    u32::try_from(mbit)
        .ok()
        .and_then(BitRate::from_mbit)
        .ok_or(NodeError::BitRate(mbit))
}
