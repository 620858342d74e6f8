//! What the master is told: chip, line, cycle, drives and the cyclic data of each telegram.

use sercon_regs::Variant;
use sercon_regs::ram::header::Buffering;
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Idn;
use sercos_wire::time::{BitRate, Duration};

use crate::ram_layout::{DEFAULT_SERVICE_BUFFER_WORDS, MdtContainers};
use crate::service_channel::ContainerSlot;
use crate::timing::{MdtPlacement, TimingRules};

/// S-0-0015 value "telegram type 7: configured by S-0-0016 and S-0-0024" (sercos-facts.md,
/// "Timing parameters" table: "0–6 standard, 7 configured").
pub const TELEGRAM_TYPE_CONFIGURED: u16 = 7;

/// The cyclic data of the standard telegram types 0-6 (S-0-0015, sercos-facts.md "Timing
/// parameters": "0–6 standard"; contents as the drive manuals give them, the table of
/// `sercos_drive::telegram_layout`, which uses this one): the MDT's command IDNs and the
/// AT's feedback IDNs, in record order; `None` for 7 (configured) and above.
///
/// | type | MDT | AT |
/// |---|---|---|
/// | 0 | – | – |
/// | 1 | S-0-0080 torque command | – |
/// | 2 | S-0-0036 velocity command | S-0-0040 velocity feedback |
/// | 3 | S-0-0036 velocity command | S-0-0051 position feedback |
/// | 4 | S-0-0047 position command | S-0-0051 position feedback |
/// | 5 | S-0-0047, S-0-0036 | S-0-0051, S-0-0040 |
/// | 6 | S-0-0036 velocity command | – |
pub fn standard_telegram(telegram_type: u16) -> Option<(Vec<Idn>, Vec<Idn>)> {
    let (mdt, at): (&[u16], &[u16]) = match telegram_type {
        0 => (&[], &[]),
        1 => (&[80], &[]),
        2 => (&[36], &[40]),
        3 => (&[36], &[51]),
        4 => (&[47], &[51]),
        5 => (&[47, 36], &[51, 40]),
        6 => (&[36], &[]),
        _ => return None,
    };
    let idns = |list: &[u16]| list.iter().map(|&raw| Idn::from_raw(raw)).collect();
    Some((idns(mdt), idns(at)))
}

/// The master's configuration. [`MasterConfig::capture_ring`] reproduces the captures'
/// master (Beckhoff FC7502 with four drives, `../shared/captures/README.md`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MasterConfig {
    /// The controller the driver expects (checked against register VERSION, 816 §2.11.1.1).
    pub variant: Variant,
    /// MCLK in Hz; the predivider is set to `f_MCLK / 1 MHz − 1` (410B §4.1 0EH).
    pub mclk_hz: u32,
    /// The line's bit rate (set through ENTSBAUD/SWBAUD/SWBAUD16 for SCLK = 64 MHz, 816
    /// §2.3.1 table).
    pub bit_rate: BitRate,
    /// S-0-0002, communication cycle time tScyc, µs (TSCYC0/1, 410B §4.1 0FH/10H).
    #[doc(alias = "S-0-0002")]
    pub cycle_us: u32,
    /// S-0-0001, NC cycle time, µs (a whole multiple of tScyc).
    #[doc(alias = "S-0-0001")]
    pub nc_cycle_us: u32,
    /// The drives' addresses in the order of their ATs (at most eight: one service
    /// container each, 410B §4.2 SCPT0-7).
    pub drives: Vec<DriveAddress>,
    /// S-0-0015, the telegram type written to every drive: 7 (configured, the data given
    /// by the two lists, which are written as S-0-0016 and S-0-0024) or a standard type 0-6
    /// whose lists must be [`standard_telegram`]'s ([`MasterConfig::set_telegram_type`]).
    #[doc(alias = "S-0-0015")]
    pub telegram_type: u16,
    /// S-0-0016, the AT configuration list (feedback IDNs, in order).
    #[doc(alias = "S-0-0016")]
    pub at_list: Vec<Idn>,
    /// S-0-0024, the MDT configuration list (command IDNs, in order).
    #[doc(alias = "S-0-0024")]
    pub mdt_list: Vec<Idn>,
    /// Buffering of the cyclic data in phases 3-4 (410B §4.2.1 DMA/DBUF). With DMA the
    /// driver moves the data through the FIFOs at 27H once per cycle (410B §4.1) and plans
    /// the MDT right after the ATs (spec-notes "Master DMA layout").
    pub buffering: Buffering,
    /// How the phase 3-4 MDT's records are held: one transmit container per drive, or one
    /// for every record, whose drives' service channel the host then runs itself in phases
    /// 3-4 (410B §4.2.2; [`crate::service_channel::HostRunChannel`]).
    pub mdt_containers: MdtContainers,
    /// When the phase 3-4 layout of `buffering` and `mdt_containers` does not fit the RAM,
    /// use DMA with one MDT container for every record (the layout that holds 254 drives in
    /// the SERCON816), shrinking the service-container buffers if even that needs it;
    /// `true` by default.
    pub layout_fallback: bool,
    /// Gap and MDT placement for the timing plan.
    pub timing_rules: TimingRules,
    /// Cycles the ring must be seen closed in phase 0 before phase 1.
    pub phase0_cycles: u32,
    /// Rounds of phase 1 (one MDT to every drive per round).
    pub phase1_rounds: u32,
    /// Rounds of phase 1 after which a drive that never answered is reported missing.
    pub detect_rounds: u32,
    /// Cycles in a row without any AT in phases 3-4 after which the MST is taken as lost.
    pub mst_loss_cycles: u32,
    /// Time limit of one service-channel request (injected time, never a clock).
    pub service_timeout: Duration,
    /// Polls of a procedure command's status before it is reported as failing.
    pub command_polls: u32,
    /// Words of each service container's buffer (410B §4.2.4 BUFLEN).
    pub service_buffer_words: u16,
    /// Stay in phase 2 once the phase-2 configuration is written (and S-0-0127 passed)
    /// instead of going on to phase 3, serving [`Master::submit_service`] requests there
    /// (for tools that write parameters protected from phase 3 on); `false` by default.
    ///
    /// [`Master::submit_service`]: super::Master::submit_service
    pub hold_in_phase2: bool,
    /// With more drives than service containers, run the phase-2 work of up to eight
    /// drives at once, one per container (410B §4.2.4 SCPT0-7), the MDT of each cycle
    /// going to one of them in turn; `true` by default. Up to eight drives phase 2 always
    /// runs one drive after the other, as the captures' master does (spec-notes "Driver
    /// master", parallel phase 2).
    pub parallel_phase2: bool,
}

impl MasterConfig {
    /// A master of `variant` for `drives` at `bit_rate` and `cycle_us`, with the captures'
    /// telegram configuration (type 7, S-0-0016 = [S-0-0011, S-0-0051, P-0-0019], S-0-0024
    /// = [S-0-0036]) and single buffering.
    pub fn new(
        variant: Variant,
        bit_rate: BitRate,
        cycle_us: u32,
        drives: Vec<DriveAddress>,
    ) -> MasterConfig {
        MasterConfig {
            variant,
            mclk_hz: match variant {
                Variant::Sercon410b => 20_000_000,
                Variant::Sercon816 => 32_000_000,
            },
            bit_rate,
            cycle_us,
            nc_cycle_us: cycle_us,
            drives,
            telegram_type: TELEGRAM_TYPE_CONFIGURED,
            // The captures' master writes these lists (`sercon capture transcript`).
            at_list: vec![Idn::from_raw(11), Idn::from_raw(51), Idn::from_raw(0x8013)],
            mdt_list: vec![Idn::from_raw(36)],
            buffering: Buffering::Double,
            mdt_containers: MdtContainers::PerDrive,
            layout_fallback: true,
            timing_rules: TimingRules {
                min_gap_us: 2,
                mdt_placement: MdtPlacement::EndOfCycle,
            },
            phase0_cycles: 10,
            phase1_rounds: 2,
            detect_rounds: 4,
            mst_loss_cycles: 3,
            service_timeout: Duration::from_micros(400 * u64::from(cycle_us.max(1))),
            command_polls: 100,
            service_buffer_words: DEFAULT_SERVICE_BUFFER_WORDS,
            hold_in_phase2: false,
            parallel_phase2: true,
        }
    }

    /// Sets S-0-0015 to `telegram_type`: a standard type 0-6 sets the two lists to its
    /// data ([`standard_telegram`]), 7 keeps the lists as they are. `false` (and nothing
    /// changed) for a type above 7 (sercos-facts.md: "0–6 standard, 7 configured").
    pub fn set_telegram_type(&mut self, telegram_type: u16) -> bool {
        if telegram_type == TELEGRAM_TYPE_CONFIGURED {
            self.telegram_type = telegram_type;
            return true;
        }
        let Some((mdt, at)) = standard_telegram(telegram_type) else {
            return false;
        };
        self.telegram_type = telegram_type;
        self.mdt_list = mdt;
        self.at_list = at;
        true
    }

    /// Whether the telegram type and the two lists agree: type 7 with any lists, a
    /// standard type with its own (sercos-facts.md S-0-0015).
    pub(crate) fn telegram_type_ok(&self) -> bool {
        if self.telegram_type == TELEGRAM_TYPE_CONFIGURED {
            return true;
        }
        standard_telegram(self.telegram_type)
            .is_some_and(|(mdt, at)| mdt == self.mdt_list && at == self.at_list)
    }

    /// The captures' ring: SERCON816, 2 Mbit/s, 2 ms, drives 1-4.
    pub fn capture_ring() -> MasterConfig {
        let drives = (1..=4).filter_map(DriveAddress::new).collect();
        MasterConfig::new(Variant::Sercon816, BitRate::Mbit2, 2000, drives)
    }

    /// A service-container slot check: the buffer length as [`ContainerSlot`] takes it.
    pub(crate) fn slot_buffer_ok(&self) -> bool {
        ContainerSlot::new(self.variant, 0, 0, self.service_buffer_words).is_ok()
    }
}
