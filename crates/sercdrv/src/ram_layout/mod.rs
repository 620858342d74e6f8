//! The dual-port RAM layout of a master or slave: transmission blocks, telegram headers, data
//! containers, service containers and end markers (410B §4.2), with the words to write and a
//! map of where everything lives.
//!
//! Order in the RAM: the 11 fixed words (COMPT0/1, SCPT0-7, NMSTERR; 410B §4.2 table A10-1),
//! then the service containers, then one header chain per transmission block given, each in
//! the order its telegrams go on the line, ending in an end marker; a block not given points
//! at a shared end marker so that every chain the chip may follow ends properly.

mod allocator;
mod budget;
mod error;

pub use budget::{MasterBudget, MdtContainers};
pub use error::RamLayoutError;

use allocator::Allocator;
use sercon_regs::Variant;
use sercon_regs::ram::container::{ContainerControl, RxContainer, TxContainer};
use sercon_regs::ram::header::{Buffering, EndMarker, HeaderKind, RxHeader, TxEnable, TxHeader};
use sercon_regs::ram::service::{SC_BUFFER_MAX_WORDS, SC_CONTROL_WORDS, ScMaster, ScSlave};
use sercon_regs::ram::{COMPT0, COMPT1, FIXED_WORDS, SCPT0};
use sercos_wire::time::BitRate;

use crate::timing::{CycleTiming, RECORD_HEADER_BYTES, TelegramSlot};

/// Number of service containers (410B §4.2: SCPT0-7).
pub const SERVICE_CONTAINERS: u8 = 8;

/// Default service-container buffer: the two length words of variable-length data
/// (sercos-facts.md, "current length, maximum length") and a 60-byte text, 32 words.
pub const DEFAULT_SERVICE_BUFFER_WORDS: u16 = 2 + 30;

/// Broadcast address (sercos-telegrams.md: ADR 255 in the MDT of phases 3-4).
const BROADCAST: u8 = 255;

/// Which end of the ring the chip serves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The master: sends MST and MDT, receives every AT.
    Master,
    /// A slave with its address: receives MDT, sends its AT.
    Slave {
        /// The drive address, 1-254.
        address: u8,
    },
}

/// Which communication phases a transmission block serves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PhaseGroup {
    /// Phases 0-2: MST, one MDT to one drive and one AT per cycle, service channel only
    /// (sercos-telegrams.md: "During Phase 2, the Data Block ... has a length of 0").
    NonCyclic,
    /// Phases 3-4: broadcast MDT with one record per drive, one AT per drive.
    Cyclic,
}

/// What to lay out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RamLayoutRequest<'a> {
    /// The controller.
    pub variant: Variant,
    /// Master or slave.
    pub role: Role,
    /// The phase group each transmission block serves: index 0 is COMPT0, 1 is COMPT1
    /// (410B §4.1 0CH COMBLK0/1 select the block per phase).
    pub blocks: [Option<PhaseGroup>; 2],
    /// The cycle's timing.
    pub timing: &'a CycleTiming,
    /// Buffering of the cyclic data (phases 3-4); phases 0-2 always use a single buffer.
    pub buffering: Buffering,
    /// Words of each service container's buffer (shared by the write and read windows).
    pub service_buffer_words: u16,
}

impl<'a> RamLayoutRequest<'a> {
    /// The usual request: block 0 for phases 0-2, block 1 for phases 3-4, single buffer,
    /// 32-word service buffers.
    pub fn new(variant: Variant, role: Role, timing: &'a CycleTiming) -> Self {
        RamLayoutRequest {
            variant,
            role,
            blocks: [Some(PhaseGroup::NonCyclic), Some(PhaseGroup::Cyclic)],
            timing,
            buffering: Buffering::Single,
            service_buffer_words: DEFAULT_SERVICE_BUFFER_WORDS,
        }
    }
}

/// What a region of the RAM holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegionKind {
    /// COMPT0/1, SCPT0-7, NMSTERR.
    FixedWords,
    /// A service container (control words and buffer).
    ServiceContainer,
    /// A telegram header.
    Header,
    /// A data container (control words and data).
    DataContainer,
    /// An end marker.
    EndMarker,
}

/// A run of words holding one structure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    /// First word address.
    pub start: u32,
    /// Number of words.
    pub words: u32,
    /// What it holds.
    pub kind: RegionKind,
}

/// One word to write: (word address, value).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RamWrite {
    /// Word address in the RAM.
    pub address: u16,
    /// The word.
    pub word: u16,
}

/// Where a data container lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContainerPlace {
    /// Address of control word 0 (LEN, SVFL, NSV, SCMASTER, LASTDC).
    pub control: u16,
    /// Address of the first data word of buffer 0 (the control or status word of the
    /// record); buffer 1 follows at `data + buffer_stride` with double buffering;
    /// meaningless with DMA.
    pub data: u16,
    /// Data words of the record (the container's LEN, or the record's share of a container
    /// holding every drive's record, [`MdtContainers::Single`]).
    pub len: u16,
    /// Words from buffer 0 to buffer 1 of the record: the LEN of the container holding it
    /// (410B §4.2.2: double buffer, buffer 1 follows buffer 0).
    pub buffer_stride: u16,
    /// Where the data lives.
    pub buffering: Buffering,
    /// The service container serving this record (SVFL = 1, NSV), if any.
    pub nsv: Option<u8>,
}

impl ContainerPlace {
    /// Address of the first cyclic data word (after control/status word and service info)
    /// in `buffer` (0 or 1), or `None` with DMA or for buffer 1 without double buffering.
    pub fn cyclic_data(&self, buffer: u8) -> Option<u16> {
        let header_words = (RECORD_HEADER_BYTES / 2) as u16;
        match (self.buffering, buffer) {
            (Buffering::Single, 0) | (Buffering::Double, 0) => self.data.checked_add(header_words),
            (Buffering::Double, 1) => self
                .data
                .checked_add(self.buffer_stride)
                .and_then(|a| a.checked_add(header_words)),
            _ => None,
        }
    }
}

/// One telegram header and its containers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TelegramPlace {
    /// Address of header word 0.
    pub header: u16,
    /// Receive or transmit.
    pub kind: HeaderKind,
    /// ADR of the header.
    pub adr: u8,
    /// TRT, µs after the end of MST.
    pub trt: u16,
    /// Its data containers in order.
    pub containers: Vec<ContainerPlace>,
}

/// One transmission block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlockMap {
    /// 0 or 1.
    pub block: u8,
    /// The phases it serves.
    pub group: PhaseGroup,
    /// Its telegrams in chain order.
    pub telegrams: Vec<TelegramPlace>,
    /// Address of its end marker.
    pub end_marker: u16,
}

/// Where one drive's cyclic data lives (phases 3-4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriveRam {
    /// The drive's address.
    pub address: u8,
    /// Its MDT record (master: transmit container; slave: receive container).
    pub command: ContainerPlace,
    /// Its AT record (master: receive container; slave: transmit container).
    pub feedback: ContainerPlace,
}

/// A service container.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ServicePlace {
    /// Its number, NSV (0-7).
    pub nsv: u8,
    /// SCPTn: address of control word 0.
    pub address: u16,
    /// Words of the buffer, which starts at offset 5 from `address`.
    pub buffer_words: u16,
    /// The drive it serves in phases 3-4 (master), or the slave's own address.
    pub drive: Option<u8>,
}

/// The map the driver uses after writing the layout.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RamMap {
    /// The transmission blocks laid out.
    pub blocks: Vec<BlockMap>,
    /// Cyclic data per drive (empty without a phase 3-4 block; one entry for a slave).
    pub drives: Vec<DriveRam>,
    /// The service containers.
    pub service_containers: Vec<ServicePlace>,
    /// The end marker that a block without a phase group points at.
    pub idle_end_marker: Option<u16>,
}

impl RamMap {
    /// The RAM of drive `address`'s cyclic data.
    pub fn drive(&self, address: u8) -> Option<&DriveRam> {
        self.drives.iter().find(|d| d.address == address)
    }

    /// The service container serving drive `address` in phases 3-4.
    pub fn service_container_of(&self, address: u8) -> Option<&ServicePlace> {
        self.service_containers
            .iter()
            .find(|s| s.drive == Some(address))
    }
}

/// The finished layout.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RamLayout {
    /// The controller.
    pub variant: Variant,
    /// Words to write, in order: fixed words, service containers, then the blocks.
    pub writes: Vec<RamWrite>,
    /// Every structure placed, for checks.
    pub regions: Vec<Region>,
    /// Where everything lives.
    pub map: RamMap,
    /// Words used, from address 0.
    pub words_used: u32,
}

/// Builds the layout or says why it does not fit; a master's phase 3-4 MDT gets one
/// transmit container per drive ([`MdtContainers::PerDrive`]).
pub fn build(req: &RamLayoutRequest<'_>) -> Result<RamLayout, RamLayoutError> {
    build_with(req, MdtContainers::PerDrive)
}

/// Builds the layout with the master's phase 3-4 MDT records held as `mdt` says (a slave
/// ignores it). With [`MdtContainers::Single`] one transmit container holds every record
/// (410B §4.2.2: a container's data follow each other in the telegram) and no phase 3-4
/// data container names a service container: the host runs the drives' service channel
/// in phases 3-4 itself (spec-notes "Master DMA layout").
pub fn build_with(
    req: &RamLayoutRequest<'_>,
    mdt: MdtContainers,
) -> Result<RamLayout, RamLayoutError> {
    check(req)?;
    let mut alloc = Allocator::starting_at(0);
    let fixed = alloc.place(RegionKind::FixedWords, u32::from(FIXED_WORDS));
    alloc.zero(fixed, u32::from(FIXED_WORDS));

    let services = place_service_containers(req, &mut alloc);
    for (i, s) in services.iter().enumerate() {
        // 410B §4.2: SCPTn holds the address of service container n.
        alloc.write_words(u32::from(SCPT0) + i as u32, &[u16_of(s.1)]);
    }

    let mut blocks = Vec::new();
    let mut drives = Vec::new();
    let mut idle_end_marker = None;
    for (block, group) in req.blocks.iter().enumerate() {
        let compt = if block == 0 { COMPT0 } else { COMPT1 };
        match group {
            Some(group) => {
                let start = alloc.used();
                // 410B §4.2: COMPTn, start of transmission block n.
                alloc.write_words(u32::from(compt), &[u16_of(start)]);
                let (map, mut found) = place_block(req, mdt, &mut alloc, block as u8, *group)?;
                blocks.push(map);
                // A second phase 3-4 block repeats the drives; the map keeps the first.
                if drives.is_empty() {
                    drives.append(&mut found);
                }
            }
            None => {
                let end = *idle_end_marker.get_or_insert_with(|| {
                    u16_of(
                        alloc.place_words(RegionKind::EndMarker, &EndMarker::default().to_words()),
                    )
                });
                alloc.write_words(u32::from(compt), &[end]);
            }
        }
    }

    let needed = alloc.used();
    let available = u32::from(req.variant.ram_words());
    if needed > available {
        return Err(RamLayoutError::DoesNotFit {
            variant: req.variant,
            needed,
            available,
        });
    }
    let service_containers = services
        .iter()
        .enumerate()
        .map(|(i, &(drive, address))| ServicePlace {
            nsv: i as u8,
            address: u16_of(address),
            buffer_words: req.service_buffer_words,
            drive,
        })
        .collect();
    Ok(RamLayout {
        variant: req.variant,
        writes: alloc
            .writes
            .iter()
            .map(|&(address, word)| RamWrite {
                address: u16_of(address),
                word,
            })
            .collect(),
        regions: alloc.regions,
        map: RamMap {
            blocks,
            drives,
            service_containers,
            idle_end_marker,
        },
        words_used: needed,
    })
}

/// An address known to be below the RAM size (checked before it is handed out) as `u16`.
fn u16_of(address: u32) -> u16 {
    u16::try_from(address).unwrap_or(u16::MAX)
}

fn check(req: &RamLayoutRequest<'_>) -> Result<(), RamLayoutError> {
    // 816 §2.3.1 / 410B §3.4.2: the 410B runs at 2 and 4 Mbit/s, the 816 adds 8 and 16.
    let rate = req.timing.bit_rate;
    if req.variant == Variant::Sercon410b && matches!(rate, BitRate::Mbit8 | BitRate::Mbit16) {
        return Err(RamLayoutError::BitRateNotSupported {
            variant: req.variant,
            rate,
        });
    }
    // 410B §4.2.4: 8-bit buffer pointers, offsets 5..=255 from the container (spec-notes).
    if req.service_buffer_words == 0 || req.service_buffer_words > SC_BUFFER_MAX_WORDS {
        return Err(RamLayoutError::ServiceBufferSize {
            words: req.service_buffer_words,
            max: SC_BUFFER_MAX_WORDS,
        });
    }
    if let Role::Slave { address } = req.role {
        if req.timing.drive(address).is_none() {
            return Err(RamLayoutError::UnknownDrive { address });
        }
    }
    Ok(())
}

/// Places the service containers: a slave one (NSV 0), a master one per drive for the first
/// eight drives (NSV 0-7). Returns (drive served, address) per NSV.
fn place_service_containers(
    req: &RamLayoutRequest<'_>,
    alloc: &mut Allocator,
) -> Vec<(Option<u8>, u32)> {
    let served: Vec<Option<u8>> = match req.role {
        Role::Slave { address } => vec![Some(address)],
        Role::Master => req
            .timing
            .drives
            .iter()
            .take(usize::from(SERVICE_CONTAINERS))
            .map(|d| Some(d.address))
            .collect(),
    };
    let scmaster = req.role == Role::Master;
    let words = SC_CONTROL_WORDS as u32 + u32::from(req.service_buffer_words);
    served
        .into_iter()
        .map(|drive| {
            let start = alloc.place(RegionKind::ServiceContainer, words);
            // 410B §4.2.4: the control words' coding depends on SCMASTER.
            let control = if scmaster {
                ScMaster::default().to_words()
            } else {
                ScSlave::default().to_words()
            };
            alloc.write_words(start, &control);
            alloc.zero(
                start + SC_CONTROL_WORDS as u32,
                u32::from(req.service_buffer_words),
            );
            (drive, start)
        })
        .collect()
}

/// One telegram to place: header fields and containers (LEN, POS for receive, drive, NSV).
struct TelegramSpec {
    kind: HeaderKind,
    adr: u8,
    achk: bool,
    en: TxEnable,
    slot: TelegramSlot,
    buffering: Buffering,
    containers: Vec<ContainerSpec>,
}

struct ContainerSpec {
    len: u16,
    pos: u16,
    nsv: Option<u8>,
    drive: Option<u8>,
    command: bool,
    /// The drives' records one after another in this container (drive, words), for a
    /// container holding every MDT record ([`MdtContainers::Single`]).
    parts: Vec<(u8, u16)>,
}

fn record_words(bytes: u16) -> u16 {
    bytes.div_ceil(2)
}

/// The telegrams of one block, in line order.
fn block_telegrams(
    req: &RamLayoutRequest<'_>,
    mdt: MdtContainers,
    group: PhaseGroup,
) -> Vec<TelegramSpec> {
    let t = req.timing;
    // One MDT container for all records: no record's service info comes from a service
    // container in phases 3-4 (spec-notes "Master DMA layout").
    let host_run = req.role == Role::Master && mdt == MdtContainers::Single;
    let nsv_of = |address: u8| -> Option<u8> {
        match req.role {
            Role::Slave { .. } => Some(0),
            Role::Master if host_run && group == PhaseGroup::Cyclic => None,
            Role::Master => t
                .drives
                .iter()
                .take(usize::from(SERVICE_CONTAINERS))
                .position(|d| d.address == address)
                .map(|i| i as u8),
        }
    };
    let service_words = record_words(RECORD_HEADER_BYTES as u16);
    let one = |len: u16, nsv: Option<u8>, drive: Option<u8>, command: bool| ContainerSpec {
        len,
        pos: 0,
        nsv,
        drive,
        command,
        parts: Vec::new(),
    };
    match (req.role, group) {
        (Role::Master, PhaseGroup::NonCyclic) => {
            let first = t.drives.first().map_or(0, |d| d.address);
            vec![
                // Phases 0-2: the AT of whichever drive was addressed; ACHK = 0 stores the
                // received address in ADR (410B §4.2.1).
                TelegramSpec {
                    kind: HeaderKind::Receive,
                    adr: 0,
                    achk: false,
                    en: TxEnable::Off,
                    slot: t.noncyclic.at,
                    buffering: Buffering::Single,
                    containers: vec![one(service_words, Some(0), None, false)],
                },
                TelegramSpec {
                    kind: HeaderKind::Transmit,
                    adr: first,
                    achk: false,
                    en: TxEnable::Continuous,
                    slot: t.noncyclic.mdt,
                    buffering: Buffering::Single,
                    containers: vec![one(service_words, Some(0), None, true)],
                },
            ]
        }
        (Role::Master, PhaseGroup::Cyclic) => {
            let mut out: Vec<TelegramSpec> = t
                .drives
                .iter()
                .map(|d| TelegramSpec {
                    kind: HeaderKind::Receive,
                    adr: d.address,
                    achk: true,
                    en: TxEnable::Off,
                    slot: d.at,
                    buffering: req.buffering,
                    containers: vec![one(
                        record_words(d.at_record_bytes),
                        nsv_of(d.address),
                        Some(d.address),
                        false,
                    )],
                })
                .collect();
            // Transmit containers have no POS: their data follow each other in the
            // telegram (410B §4.2.2), in S-0-0009 order.
            let containers = match mdt {
                MdtContainers::PerDrive => t
                    .drives
                    .iter()
                    .map(|d| {
                        one(
                            record_words(d.mdt_record_bytes),
                            nsv_of(d.address),
                            Some(d.address),
                            true,
                        )
                    })
                    .collect(),
                MdtContainers::Single => {
                    let parts: Vec<(u8, u16)> = t
                        .drives
                        .iter()
                        .map(|d| (d.address, record_words(d.mdt_record_bytes)))
                        .collect();
                    let len = parts.iter().map(|p| p.1).fold(0u16, u16::saturating_add);
                    vec![ContainerSpec {
                        parts,
                        ..one(len, None, None, true)
                    }]
                }
            };
            out.push(TelegramSpec {
                kind: HeaderKind::Transmit,
                adr: BROADCAST,
                achk: false,
                en: TxEnable::Continuous,
                slot: t.mdt,
                buffering: req.buffering,
                containers,
            });
            out
        }
        (Role::Slave { address }, PhaseGroup::NonCyclic) => vec![
            // 410B §4.2.1 EN = 3: the AT goes out only after an MDT with our address
            // (PHAS12 = 1, FLMDTADR = 1).
            TelegramSpec {
                kind: HeaderKind::Transmit,
                adr: address,
                achk: false,
                en: TxEnable::OnAddress,
                slot: t.noncyclic.at,
                buffering: Buffering::Single,
                containers: vec![one(service_words, Some(0), Some(address), false)],
            },
            TelegramSpec {
                kind: HeaderKind::Receive,
                adr: address,
                achk: true,
                en: TxEnable::Off,
                slot: t.noncyclic.mdt,
                buffering: Buffering::Single,
                containers: vec![one(service_words, Some(0), Some(address), true)],
            },
        ],
        (Role::Slave { address }, PhaseGroup::Cyclic) => {
            let Some(d) = t.drive(address) else {
                return Vec::new();
            };
            vec![
                TelegramSpec {
                    kind: HeaderKind::Transmit,
                    adr: address,
                    achk: false,
                    en: TxEnable::Continuous,
                    slot: d.at,
                    buffering: req.buffering,
                    containers: vec![one(
                        record_words(d.at_record_bytes),
                        Some(0),
                        Some(address),
                        false,
                    )],
                },
                TelegramSpec {
                    kind: HeaderKind::Receive,
                    adr: BROADCAST,
                    achk: true,
                    en: TxEnable::Off,
                    slot: t.mdt,
                    buffering: req.buffering,
                    // 410B §4.2.2: POS in words from the first data word; S-0-0009 counts
                    // bytes from ADR, the first record at 1.
                    containers: vec![ContainerSpec {
                        len: record_words(d.mdt_record_bytes),
                        pos: d.mdt_offset.saturating_sub(1) / 2,
                        nsv: Some(0),
                        drive: Some(address),
                        command: true,
                        parts: Vec::new(),
                    }],
                },
            ]
        }
    }
}

fn container_words(kind: HeaderKind, buffering: Buffering, len: u16) -> u32 {
    let control = match kind {
        HeaderKind::Receive => RxContainer::CONTROL_WORDS,
        _ => TxContainer::CONTROL_WORDS,
    } as u32;
    control + buffering.data_words(len)
}

/// Places one transmission block; returns its map and the drives' cyclic containers.
fn place_block(
    req: &RamLayoutRequest<'_>,
    mdt: MdtContainers,
    alloc: &mut Allocator,
    block: u8,
    group: PhaseGroup,
) -> Result<(BlockMap, Vec<DriveRam>), RamLayoutError> {
    let scmaster = req.role == Role::Master;
    let mut telegrams = Vec::new();
    let mut commands: Vec<(u8, ContainerPlace)> = Vec::new();
    let mut feedbacks: Vec<(u8, ContainerPlace)> = Vec::new();
    for spec in block_telegrams(req, mdt, group) {
        for c in &spec.containers {
            // 410B §4.2.2: LEN is bits 9-0 of control word 0.
            if c.len > CONTAINER_LEN_MAX {
                return Err(RamLayoutError::ContainerTooLong {
                    words: c.len,
                    max: CONTAINER_LEN_MAX,
                });
            }
        }
        let header_words = spec.kind.words() as u32;
        let total: u32 = header_words
            + spec
                .containers
                .iter()
                .map(|c| container_words(spec.kind, spec.buffering, c.len))
                .sum::<u32>();
        let start = alloc.place(RegionKind::Header, header_words);
        // 410B §4.2.1: PT points to the next header or the end marker, which follows the
        // containers directly (ERRATA "data containers").
        let pt = u16_of(start + total);
        let trt = u16_of(spec.slot.start_us);
        let tlen = u16_of(spec.slot.data_words());
        let dma = spec.buffering == Buffering::Dma;
        let dbuf = spec.buffering == Buffering::Double;
        let header: Vec<u16> = match spec.kind {
            HeaderKind::Receive => RxHeader {
                adr: spec.adr,
                dma,
                dbuf,
                achk: spec.achk,
                trt,
                tlen,
                pt,
                ..RxHeader::default()
            }
            .to_words(req.variant)
            .to_vec(),
            _ => TxHeader {
                adr: spec.adr,
                dma,
                dbuf,
                en: spec.en,
                trt,
                tlen,
                pt,
                ..TxHeader::default()
            }
            .to_words(req.variant)
            .to_vec(),
        };
        alloc.write_words(start, &header);
        let count = spec.containers.len();
        let mut places = Vec::with_capacity(count);
        for (i, c) in spec.containers.iter().enumerate() {
            let words = container_words(spec.kind, spec.buffering, c.len);
            let at = alloc.place(RegionKind::DataContainer, words);
            // 410B §4.2.2: LEN, SVFL, NSV, SCMASTER, LASTDC on the last container.
            let control = ContainerControl {
                len: c.len,
                svfl: c.nsv.is_some(),
                nsv: c.nsv.unwrap_or(0),
                scmaster,
                lastdc: i + 1 == count,
            };
            let control_words = match spec.kind {
                HeaderKind::Receive => {
                    alloc.write_words(
                        at,
                        &RxContainer {
                            control,
                            pos: c.pos,
                        }
                        .to_words(),
                    );
                    RxContainer::CONTROL_WORDS as u32
                }
                _ => {
                    alloc.write_words(at, &TxContainer { control }.to_words());
                    TxContainer::CONTROL_WORDS as u32
                }
            };
            alloc.zero(at + control_words, words - control_words);
            let place = ContainerPlace {
                control: u16_of(at),
                data: u16_of(at + control_words),
                len: c.len,
                buffer_stride: c.len,
                buffering: spec.buffering,
                nsv: c.nsv,
            };
            if group == PhaseGroup::Cyclic {
                // One container for every record: each drive's record at its offset.
                let mut offset = 0u16;
                for &(drive, len) in &c.parts {
                    commands.push((
                        drive,
                        ContainerPlace {
                            data: place.data.saturating_add(offset),
                            len,
                            ..place
                        },
                    ));
                    offset = offset.saturating_add(len);
                }
            }
            if let (Some(drive), PhaseGroup::Cyclic) = (c.drive, group) {
                if c.command {
                    commands.push((drive, place));
                } else {
                    feedbacks.push((drive, place));
                }
            }
            places.push(place);
        }
        telegrams.push(TelegramPlace {
            header: u16_of(start),
            kind: spec.kind,
            adr: spec.adr,
            trt,
            containers: places,
        });
    }
    // 410B §4.2.3: TEND, when the last telegram of the block has ended.
    let tend = match group {
        PhaseGroup::NonCyclic => req.timing.noncyclic.mdt.end_us(),
        PhaseGroup::Cyclic => req.timing.tend_us(),
    };
    let end = alloc.place_words(
        RegionKind::EndMarker,
        &EndMarker {
            reserved: 0,
            tend: u16_of(tend),
        }
        .to_words(),
    );
    let drives = commands
        .iter()
        .filter_map(|&(address, command)| {
            feedbacks
                .iter()
                .find(|f| f.0 == address)
                .map(|&(_, feedback)| DriveRam {
                    address,
                    command,
                    feedback,
                })
        })
        .collect();
    Ok((
        BlockMap {
            block,
            group,
            telegrams,
            end_marker: u16_of(end),
        },
        drives,
    ))
}

/// Largest LEN of a data container (410B §4.2.2: LEN, bits 9-0).
const CONTAINER_LEN_MAX: u16 = (1 << ContainerControl::LEN_BITS) - 1;
