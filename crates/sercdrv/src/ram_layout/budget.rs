//! Word budget of a master's dual-port RAM (410B §4.2), computed from sizes alone: how many
//! words a ring of n drives needs, and the largest ring that fits. It answers "do 254 drives
//! fit?" before any timing plan exists, for one MDT transmit container per drive or one for
//! every record ([`build_with`](super::build_with) lays out both).
//!
//! The words counted are those [`build`](super::build) places for a master (checked against
//! it by tests): the 11 fixed words; one service container (5 control words + buffer) for
//! each of the first eight drives (410B §4.2 SCPT0-7); the phase 0-2 block (AT receive
//! header 5 + container 2 + service record 2, MDT transmit header 4 + container 1 + 2, end
//! marker 2); the phase 3-4 block (per drive an AT receive header 5 + container 2 + data,
//! the MDT transmit header 4 with its containers, end marker 2).

use sercon_regs::Variant;
use sercon_regs::ram::FIXED_WORDS;
use sercon_regs::ram::container::{RxContainer, TxContainer};
use sercon_regs::ram::header::{Buffering, EndMarker, RxHeader, TxHeader};
use sercon_regs::ram::service::SC_CONTROL_WORDS;

use super::{DEFAULT_SERVICE_BUFFER_WORDS, SERVICE_CONTAINERS};
use crate::timing::RECORD_HEADER_BYTES;

/// How the phase 3-4 MDT's records are held in the master's RAM.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MdtContainers {
    /// One transmit container per drive (what [`build`](super::build) lays out): each can
    /// carry its drive's service info from a service container (410B §4.2.2 SVFL, NSV).
    PerDrive,
    /// One transmit container for every record (410B §4.2.2: a container's data follow each
    /// other in the telegram, LEN up to the whole MDT): one control word instead of n, but
    /// no per-drive SVFL, so the host writes the drives' service info itself.
    Single,
}

/// Sizes of a master's RAM layout for rings of identical drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MasterBudget {
    /// The controller (1024 or 2048 words, 410B §4.2 / 816 §2.3).
    pub variant: Variant,
    /// Cyclic data bytes of each AT record after service info and status word.
    pub at_data_bytes: u16,
    /// Cyclic data bytes of each MDT record after service info and control word.
    pub mdt_data_bytes: u16,
    /// Buffering of the phase 3-4 data (410B §4.2.1 DMA/DBUF).
    pub buffering: Buffering,
    /// Words of each service container's buffer.
    pub service_buffer_words: u16,
    /// Service containers laid out (at most eight, one per drive up to eight).
    pub service_containers: u8,
    /// The phase 0-2 block is laid out (COMPT0); without it COMPT0 points at an end marker.
    pub noncyclic_block: bool,
    /// How the MDT's records are held.
    pub mdt: MdtContainers,
}

impl MasterBudget {
    /// The master driver's default layout (`MasterConfig::new`): double buffering, 32-word
    /// service buffers, eight service containers, both blocks, one MDT container per drive.
    pub fn master_default(variant: Variant, at_data_bytes: u16, mdt_data_bytes: u16) -> Self {
        MasterBudget {
            variant,
            at_data_bytes,
            mdt_data_bytes,
            buffering: Buffering::Double,
            service_buffer_words: DEFAULT_SERVICE_BUFFER_WORDS,
            service_containers: SERVICE_CONTAINERS,
            noncyclic_block: true,
            mdt: MdtContainers::PerDrive,
        }
    }

    /// Words needed for a ring of `drives` drives, from word 0.
    pub fn words_needed(&self, drives: u32) -> u32 {
        let record = |data: u16| (RECORD_HEADER_BYTES + u32::from(data)).div_ceil(2);
        let data = |len: u32| match self.buffering {
            Buffering::Single => len,
            Buffering::Double => 2 * len,
            Buffering::Dma => 0,
        };
        let rx = (RxHeader::WORDS + RxContainer::CONTROL_WORDS) as u32;
        let tx_header = TxHeader::WORDS as u32;
        let tx_container = TxContainer::CONTROL_WORDS as u32;
        let end = EndMarker::WORDS as u32;
        // 410B §4.2: SCPT0-7; the builder gives one container to each of the first eight
        // drives.
        let containers = drives.min(u32::from(self.service_containers.min(SERVICE_CONTAINERS)));
        let services =
            containers * (SC_CONTROL_WORDS as u32 + u32::from(self.service_buffer_words));
        // Phases 0-2: the service record only (sercos-telegrams.md: data block of length 0),
        // single buffered, one AT and one MDT.
        let service_record = RECORD_HEADER_BYTES.div_ceil(2);
        let noncyclic = if self.noncyclic_block {
            rx + service_record + tx_header + tx_container + service_record + end
        } else {
            end // the idle end marker COMPT0 points at
        };
        let ats = drives * (rx + data(record(self.at_data_bytes)));
        let mdt_data = drives * data(record(self.mdt_data_bytes));
        let mdt = tx_header
            + mdt_data
            + match self.mdt {
                MdtContainers::PerDrive => drives * tx_container,
                MdtContainers::Single => tx_container,
            };
        u32::from(FIXED_WORDS) + services + noncyclic + ats + mdt + end
    }

    /// Whether a ring of `drives` fits the variant's RAM.
    pub fn fits(&self, drives: u32) -> bool {
        self.words_needed(drives) <= u32::from(self.variant.ram_words())
    }

    /// The largest ring (0-254 drives, sercos-telegrams.md addresses 1-254) that fits.
    pub fn largest_ring(&self) -> u32 {
        // words_needed grows with the drives: the first that does not fit ends the search.
        (1..=254).take_while(|&n| self.fits(n)).last().unwrap_or(0)
    }
}

// The drive and timing set-ups the integration tests share (`tests/common`), for the tests
// below; the file names the timing module `timing`.
#[cfg(test)]
use crate::timing;
#[cfg(test)]
#[path = "../../tests/common/ring_timing.rs"]
#[allow(dead_code)]
mod ring_timing;

#[cfg(test)]
mod tests {
    use super::ring_timing::plan_alike;
    use super::*;
    use crate::ram_layout::{PhaseGroup, RamLayoutError, RamLayoutRequest, Role, build_with};
    use proptest::prelude::*;
    use sercos_wire::time::BitRate;

    /// What the builder places for a master ring of `n` identical drives: words used, or
    /// the words it would need when it refuses.
    fn built_words(b: &MasterBudget, n: u8) -> Option<u32> {
        let timing =
            plan_alike(BitRate::Mbit4, 65_000, n, b.at_data_bytes, b.mdt_data_bytes).ok()?;
        let mut req = RamLayoutRequest::new(b.variant, Role::Master, &timing);
        req.buffering = b.buffering;
        req.service_buffer_words = b.service_buffer_words;
        if !b.noncyclic_block {
            req.blocks = [None, Some(PhaseGroup::Cyclic)];
        }
        match build_with(&req, b.mdt) {
            Ok(layout) => Some(layout.words_used),
            Err(RamLayoutError::DoesNotFit { needed, .. }) => Some(needed),
            Err(_) => None,
        }
    }

    fn buffering() -> impl Strategy<Value = Buffering> {
        prop_oneof![
            Just(Buffering::Single),
            Just(Buffering::Double),
            Just(Buffering::Dma)
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(64)))]
        /// The budget counts exactly the words the builder places (410B §4.2 structures).
        #[test]
        fn budget_matches_the_builder(
            n in 1u8..=40,
            at in 0u16..=12,
            mdt in 0u16..=12,
            buffering in buffering(),
            sc in 1u16..=40,
            noncyclic in any::<bool>(),
            variant in prop_oneof![Just(Variant::Sercon410b), Just(Variant::Sercon816)],
            containers in prop_oneof![Just(MdtContainers::PerDrive), Just(MdtContainers::Single)],
        ) {
            let b = MasterBudget {
                variant,
                at_data_bytes: at,
                mdt_data_bytes: mdt,
                buffering,
                service_buffer_words: sc,
                service_containers: SERVICE_CONTAINERS,
                noncyclic_block: noncyclic,
                mdt: containers,
            };
            if let Some(words) = built_words(&b, n) {
                prop_assert_eq!(b.words_needed(u32::from(n)), words);
            }
        }
    }

    #[test]
    fn the_254_drive_refusal_figures_are_the_builders() {
        // The builder's refusals quoted in docs/spec-notes.md (4395 words; 2347 with DMA and
        // only the phase 3-4 block, 4 bytes each way, single buffer, 32-word buffers).
        let mut b = MasterBudget::master_default(Variant::Sercon816, 4, 4);
        b.buffering = Buffering::Single;
        assert_eq!(b.words_needed(254), 4395);
        b.buffering = Buffering::Dma;
        b.noncyclic_block = false;
        assert_eq!(b.words_needed(254), 2347);
    }

    #[test]
    fn per_drive_mdt_containers_never_fit_254_drives_in_the_816() {
        // 410B §4.2.1/§4.2.2: per drive at least an AT receive header (5) and container (2)
        // and an MDT transmit container (1): 254 × 8 = 2032 words, plus 11 fixed words, the
        // MDT header 4 and two end markers 2 + 2 = 2051 > 2048, even with DMA, no service
        // containers and no phase 0-2 block.
        let b = MasterBudget {
            variant: Variant::Sercon816,
            at_data_bytes: 0,
            mdt_data_bytes: 0,
            buffering: Buffering::Dma,
            service_buffer_words: 1,
            service_containers: 0,
            noncyclic_block: false,
            mdt: MdtContainers::PerDrive,
        };
        assert_eq!(b.words_needed(254), 2051);
        assert!(!b.fits(254));
        assert_eq!(b.largest_ring(), 253);
    }

    #[test]
    fn one_mdt_container_with_dma_fits_254_drives() {
        // 254 × (5 + 2) = 1778 AT words; MDT header 4 + one container 1; 11 fixed; phase
        // 0-2 block 18; end marker 2: 1814, leaving 234 words for the service containers:
        // eight of 5 + 24 words (232) fit, eight of 5 + 25 do not.
        let mut b = MasterBudget {
            variant: Variant::Sercon816,
            at_data_bytes: 8,
            mdt_data_bytes: 4,
            buffering: Buffering::Dma,
            service_buffer_words: 24,
            service_containers: SERVICE_CONTAINERS,
            noncyclic_block: true,
            mdt: MdtContainers::Single,
        };
        assert_eq!(b.words_needed(254), 1814 + 8 * 29);
        assert!(b.fits(254));
        b.service_buffer_words = 25;
        assert!(!b.fits(254));
        assert_eq!(b.largest_ring(), 253);
    }

    #[test]
    fn largest_rings_without_dma() {
        // The captures' telegram type: AT data 8 bytes (S-0-0011, S-0-0051, P-0-0019), MDT
        // data 4 bytes (S-0-0036). Double buffering (the master's default): per drive
        // 5 + 2 + 2 × 6 + 1 + 2 × 4 = 28 words; fixed part 11 + 8 × 37 + 18 + 4 + 2 = 331:
        // 331 + 28 × 61 = 2039 ≤ 2048.
        let double = MasterBudget::master_default(Variant::Sercon816, 8, 4);
        assert_eq!(double.largest_ring(), 61);
        assert_eq!(built_words(&double, 61), Some(double.words_needed(61)));
        assert_eq!(built_words(&double, 62), Some(double.words_needed(62)));
        assert!(!double.fits(62));
        // Single buffering: 18 words per drive, 95 drives (as the builder's own test).
        let single = MasterBudget {
            buffering: Buffering::Single,
            ..double
        };
        assert_eq!(single.largest_ring(), 95);
        // The 410B's 1024 words: 24 drives double buffered, 38 single.
        let small = MasterBudget::master_default(Variant::Sercon410b, 8, 4);
        assert_eq!(small.largest_ring(), 24);
        assert_eq!(
            MasterBudget {
                buffering: Buffering::Single,
                ..small
            }
            .largest_ring(),
            38
        );
    }
}
