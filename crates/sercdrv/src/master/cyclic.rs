//! Cyclic data of phases 3-4: command values into each drive's MDT record, feedback values
//! out of its AT, by IDN, through the single or double buffer (410B §4.2.1 DBUF, VAL) or the
//! FIFOs at 27H (410B §4.2.1 DMA; §2 DMAREQR/DMAREQT; spec-notes "Master DMA layout").

use sercon_regs::ram::header::{Buffering, RxHeader, TxEnable, TxHeader};
use sercon_regs::{Ctrl3, Fifo, ProgerrFl, SerconBus, SerconBusExt, Variant};
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Idn;

use crate::ram_layout::ContainerPlace;
use crate::service_channel::DriveIndex;

/// Words of the control/status word and the service info before the cyclic data
/// (sercos-telegrams.md, "Data Record").
pub(crate) const RECORD_HEADER_WORDS: usize = 2;

/// Where one IDN sits in a record's cyclic data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Item {
    /// The IDN.
    pub idn: Idn,
    /// First word after the record header.
    pub offset: usize,
    /// Its words.
    pub words: usize,
}

/// Lays out `idns` of `words` each one after another (sercos-facts.md: the configuration
/// lists S-0-0016 / S-0-0024 give the order of the cyclic data).
pub(crate) fn items(idns: &[Idn], words: &[usize]) -> Vec<Item> {
    let mut offset = 0;
    idns.iter()
        .zip(words)
        .map(|(&idn, &words)| {
            let item = Item { idn, offset, words };
            offset += words;
            item
        })
        .collect()
}

/// One drive's cyclic data and where it lives.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct DriveCyclic {
    pub address: DriveAddress,
    /// Its record in the broadcast MDT (master transmit container).
    pub command: ContainerPlace,
    /// Its AT (master receive container) and the AT's receive header.
    pub feedback: ContainerPlace,
    pub at_header: u16,
    pub mdt_items: Vec<Item>,
    pub at_items: Vec<Item>,
    /// The record to send: control word, service info (filled by the chip), command data.
    pub record: Vec<u16>,
    /// The last AT received whole: status word, service info, feedback data.
    pub received: Vec<u16>,
    /// Whether the last AT was received without error.
    pub last_ok: bool,
    /// What buffers 0 and 1 of the MDT record hold as this image wrote them (empty:
    /// unknown, written in full next time).
    pub written: [Vec<u16>; 2],
}

/// The cyclic data of every drive.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct CyclicImage {
    pub variant: Variant,
    pub buffering: Buffering,
    /// The broadcast MDT's transmit header.
    pub mdt_header: u16,
    pub drives: Vec<DriveCyclic>,
    /// Indices of `drives` in the order of their AT receive headers in the chain (the
    /// order their words enter RFIFO).
    at_order: Vec<usize>,
    /// Indices of `drives` in the order of their MDT records (the order TFIFO takes them).
    mdt_order: Vec<usize>,
    /// Indices of `drives` by address.
    index: DriveIndex,
    /// Whether the AT's service info words are read (for a host-run service channel); with
    /// the chip's service containers the container takes them (410B §4.2.2 SVFL, §4.2.4;
    /// ERRATA "service info in a container") and they read as 0 in [`DriveCyclic::received`].
    pub read_service_info: bool,
    /// Word 0 of the MDT's transmit header as last read or written (VAL is the driver's).
    mdt_word0: Option<u16>,
    /// An AT's words while they are read (swapped into `received` when good).
    scratch: Vec<u16>,
}

/// 410B §4.2.1 receive header word 0 bit 13, RERR: "errored or not received".
const RERR: u16 = 1 << 13;

/// PROGERR_FL bit 4, DMA FIFO short or overrun (the model's reading of 17H, spec-notes
/// "Telegram processor and MST").
const PROGERR_DMA_FIFO: u16 = 1 << 4;

impl CyclicImage {
    /// The image of `drives`, the FIFO orders taken from their RAM places (headers and
    /// records are laid out in chain and telegram order).
    pub fn new(
        variant: Variant,
        buffering: Buffering,
        mdt_header: u16,
        drives: Vec<DriveCyclic>,
    ) -> CyclicImage {
        let mut at_order: Vec<usize> = (0..drives.len()).collect();
        at_order.sort_by_key(|&i| drives.get(i).map(|d| d.at_header));
        let mut mdt_order: Vec<usize> = (0..drives.len()).collect();
        mdt_order.sort_by_key(|&i| drives.get(i).map(|d| (d.command.control, d.command.data)));
        let index = DriveIndex::new(drives.iter().map(|d| d.address));
        CyclicImage {
            variant,
            buffering,
            mdt_header,
            drives,
            at_order,
            mdt_order,
            index,
            read_service_info: false,
            mdt_word0: None,
            scratch: Vec::new(),
        }
    }

    pub fn drive(&self, address: DriveAddress) -> Option<&DriveCyclic> {
        self.drives.get(self.index.get(address)?)
    }

    pub fn drive_mut(&mut self, address: DriveAddress) -> Option<&mut DriveCyclic> {
        let i = self.index.get(address)?;
        self.drives.get_mut(i)
    }

    /// Writes every drive's record for the next MDT. Double buffer: into the buffer the
    /// chip does not send, then VAL is turned to it (410B §4.2.1: for transmit headers VAL
    /// "Set by processor": data in buffer 0 (VAL = 0) or buffer 1 (VAL = 1) are valid; 816
    /// §2.10.1.2: VAL is read again at the start of the transmit telegram).
    ///
    /// Only words that differ from what the buffer holds are written: the chip never writes
    /// a transmit container's data words (it puts the service info into the telegram, not
    /// the RAM: ERRATA "service info in a container"), so a buffer holds what this image
    /// wrote last. When the buffer the chip sends already holds every record, nothing is
    /// written and VAL stays (spec-notes "Master accesses per cycle").
    pub fn write_commands<B: SerconBus + ?Sized>(&mut self, bus: &mut B) {
        if self.buffering == Buffering::Dma {
            self.write_fifo(bus);
            return;
        }
        let Some(word0) = self.mdt_word0(bus) else {
            return;
        };
        let sent = match self.buffering {
            Buffering::Double => u8::from(word0 & VAL != 0),
            _ => 0,
        };
        if self.drives.iter().all(|d| d.holds_record(sent)) {
            return;
        }
        let target = match self.buffering {
            Buffering::Double => 1 - sent,
            _ => 0,
        };
        for d in &mut self.drives {
            d.write_record(bus, target);
        }
        if self.buffering == Buffering::Double {
            // Only word 0 carries VAL; the other words are the driver's own.
            let word0 = if target == 1 {
                word0 | VAL
            } else {
                word0 & !VAL
            };
            bus.write_ram(self.mdt_header, word0);
            self.keep_mdt_word0(word0);
        }
    }

    /// Word 0 of the MDT's transmit header: read once, then the one this image wrote (410B
    /// §4.2.1 transmit header: VAL is "Set by processor"; the controller writes word 0 back
    /// only for EN = 1, "sets EN to 0 after the transmit telegram has been started", so
    /// then it is read every time). `None` if the word is no transmit header.
    fn mdt_word0<B: SerconBus + ?Sized>(&mut self, bus: &mut B) -> Option<u16> {
        if let Some(word0) = self.mdt_word0 {
            return Some(word0);
        }
        let word0 = bus.read_ram(self.mdt_header);
        TxHeader::from_words(self.variant, [word0, 0, 0, 0]).ok()?;
        self.keep_mdt_word0(word0);
        Some(word0)
    }

    fn keep_mdt_word0(&mut self, word0: u16) {
        let once = TxHeader::from_words(self.variant, [word0, 0, 0, 0])
            .is_ok_and(|h| h.en == TxEnable::Once);
        self.mdt_word0 = (!once).then_some(word0);
    }

    /// Reads every drive's AT: word 0 of its receive header (RERR, VAL, DMA/DBUF), then,
    /// if the AT came without error, its words once from the buffer VAL names. Returns how
    /// many ATs came without error.
    ///
    /// 410B §4.2.1 receive header VAL, double buffer: "data in buffer 0 (VAL = 0) or buffer
    /// 1 (VAL = 1) is valid. Modified by controller at beginning and end of receive
    /// telegrams": the controller fills the other buffer and turns VAL to it at the end, so
    /// the buffer VAL named is written again only by the telegram after the next one, a
    /// cycle later; it is read once, without a second look at VAL. Single buffer: the one
    /// buffer is written by the next AT itself, which clears VAL at its beginning, so word 0
    /// is read again after the words and the read repeated if VAL changed (spec-notes
    /// "Master accesses per cycle").
    pub fn read_feedback<B: SerconBus + ?Sized>(&mut self, bus: &mut B) -> usize {
        if self.buffering == Buffering::Dma {
            return self.read_fifo(bus);
        }
        let variant = self.variant;
        let mut ok = 0;
        let scratch = &mut self.scratch;
        // The service info follows the status word (sercos-telegrams.md "Data Record").
        let skip = if self.read_service_info {
            0..0
        } else {
            1..RECORD_HEADER_WORDS
        };
        for d in &mut self.drives {
            let mut good = false;
            let mut word0 = bus.read_ram(d.at_header);
            for _ in 0..3 {
                // Word 0 alone: its fields do not depend on the other words.
                let Ok(h) = RxHeader::from_words(variant, [word0, 0, 0, 0, 0]) else {
                    good = false;
                    break;
                };
                // 410B §4.2.1 RERR: "errored or not received": nothing to read.
                good = !h.rerr;
                if !good {
                    break;
                }
                let (buffer, check) = match h.buffering() {
                    Buffering::Double => (u8::from(h.val), false),
                    _ => (0, true),
                };
                let Some(start) = buffer_start(&d.feedback, buffer) else {
                    good = false;
                    break;
                };
                read_words(bus, start, d.feedback.len, skip.clone(), scratch);
                if !check {
                    break;
                }
                let again = bus.read_ram(d.at_header);
                if again & VAL == word0 & VAL {
                    break;
                }
                word0 = again;
            }
            d.last_ok = good;
            if good {
                ok += 1;
                std::mem::swap(&mut d.received, scratch);
            }
        }
        ok
    }
}

impl DriveCyclic {
    /// Whether buffer `buffer` of the MDT record holds [`DriveCyclic::record`] as written.
    fn holds_record(&self, buffer: u8) -> bool {
        self.written
            .get(usize::from(buffer))
            .is_some_and(|w| *w == self.record)
    }

    /// Writes the record into buffer `buffer`: the words that differ from what the buffer
    /// holds, or all of them if that is not known.
    fn write_record<B: SerconBus + ?Sized>(&mut self, bus: &mut B, buffer: u8) {
        let Some(start) = buffer_start(&self.command, buffer) else {
            return;
        };
        let Some(held) = self.written.get_mut(usize::from(buffer)) else {
            return;
        };
        if held.len() == self.record.len() {
            for ((a, old), new) in (0u16..).zip(held.iter_mut()).zip(&self.record) {
                if old != new {
                    bus.write_ram(start.wrapping_add(a), *new);
                    *old = *new;
                }
            }
        } else {
            bus.write_ram_words(start, &self.record);
            held.clone_from(&self.record);
        }
    }
}

impl CyclicImage {
    /// DMA: every drive's record, in telegram order, into TFIFO (410B §4.1 27H), while
    /// DMAREQT (3H.12) says the FIFO takes the next MDT's words; else nothing (the words
    /// would be dropped).
    fn write_fifo<B: SerconBus + ?Sized>(&self, bus: &mut B) {
        // 410B §2 DMAREQT: "becomes active when data can be written to the transmit FIFO".
        if !bus.read_reg::<Ctrl3>().contains(Ctrl3::DMAREQT) {
            return;
        }
        for d in self.mdt_order.iter().filter_map(|&i| self.drives.get(i)) {
            for &w in &d.record {
                bus.write_reg(Fifo(w));
            }
        }
    }

    /// DMA: the ATs received without error (RERR = 0) left their words in RFIFO in chain
    /// order (410B §4.1 27H; spec-notes "Master DMA layout"). Words left over (DMAREQR,
    /// 3H.13) or a FIFO fault (17H bit 4) mean the words may mix two cycles: the cycle's
    /// feedback is dropped, never torn. Returns how many ATs came whole.
    fn read_fifo<B: SerconBus + ?Sized>(&mut self, bus: &mut B) -> usize {
        let mut got: Vec<Option<Vec<u16>>> = vec![None; self.drives.len()];
        for &i in &self.at_order {
            let Some(d) = self.drives.get(i) else {
                continue;
            };
            if bus.read_ram(d.at_header) & RERR != 0 {
                continue;
            }
            let words = (0..d.feedback.len)
                .map(|_| bus.read_reg::<Fifo>().0)
                .collect();
            if let Some(slot) = got.get_mut(i) {
                *slot = Some(words);
            }
        }
        // 410B §2 DMAREQR: active while RFIFO holds words.
        let mut leftover = bus.read_reg::<Ctrl3>().contains(Ctrl3::DMAREQR);
        let fault = bus.read_reg::<ProgerrFl>().0 & PROGERR_DMA_FIFO != 0;
        if fault {
            // 410B §4.1 17H CLR_PROGERR_FL: write 1 to clear.
            bus.write_reg(ProgerrFl(PROGERR_DMA_FIFO));
        }
        if leftover || fault {
            // Drain what is left (at most one cycle's words) and drop the cycle.
            let limit: usize = self
                .drives
                .iter()
                .map(|d| usize::from(d.feedback.len))
                .sum();
            let mut drained = 0;
            while leftover && drained < limit {
                bus.read_reg::<Fifo>();
                drained += 1;
                leftover = bus.read_reg::<Ctrl3>().contains(Ctrl3::DMAREQR);
            }
            got.iter_mut().for_each(|g| *g = None);
        }
        let mut ok = 0;
        for (d, g) in self.drives.iter_mut().zip(got) {
            d.last_ok = g.is_some();
            if let Some(words) = g {
                ok += 1;
                d.received = words;
            }
        }
        ok
    }
}

/// 410B §4.2.1 header word 0 bit 10, VAL.
const VAL: u16 = 1 << 10;

fn buffer_start(place: &ContainerPlace, buffer: u8) -> Option<u16> {
    match (place.buffering, buffer) {
        (Buffering::Single, 0) | (Buffering::Double, 0) => Some(place.data),
        (Buffering::Double, 1) => place.data.checked_add(place.buffer_stride),
        _ => None,
    }
}

/// `len` words from `start` into `out` (its old contents dropped); the words at the
/// offsets in `skip` are not read and stand as 0.
fn read_words<B: SerconBus + ?Sized>(
    bus: &mut B,
    start: u16,
    len: u16,
    skip: std::ops::Range<usize>,
    out: &mut Vec<u16>,
) {
    out.clear();
    out.extend((0..len).map(|i| {
        if skip.contains(&usize::from(i)) {
            0
        } else {
            bus.read_ram(start.wrapping_add(i))
        }
    }));
}

/// The value of `item` in `record` (words low first), if the record holds it.
pub(crate) fn value_of(record: &[u16], item: &Item) -> Option<u64> {
    let start = RECORD_HEADER_WORDS + item.offset;
    let words = record.get(start..start + item.words)?;
    Some(
        words
            .iter()
            .enumerate()
            .fold(0u64, |acc, (i, w)| acc | (u64::from(*w) << (16 * i))),
    )
}

/// Puts `value` (words low first) into `record` at `item`.
pub(crate) fn put_value(record: &mut [u16], item: &Item, value: u64) -> bool {
    let start = RECORD_HEADER_WORDS + item.offset;
    let Some(words) = record.get_mut(start..start + item.words) else {
        return false;
    };
    for (i, w) in words.iter_mut().enumerate() {
        *w = (value >> (16 * i)) as u16;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    // sercos-telegrams.md "Data Record": control word, service info, then the data block.
    #[test]
    fn values_follow_the_record_header_in_list_order() {
        let list = items(&[Idn::from_raw(11), Idn::from_raw(51)], &[1, 2]);
        let mut record = vec![0u16; 5];
        assert!(put_value(&mut record, &list[1], 0x1234_5678));
        assert!(put_value(&mut record, &list[0], 0xABCD));
        assert_eq!(record, vec![0, 0, 0xABCD, 0x5678, 0x1234]);
        assert_eq!(value_of(&record, &list[1]), Some(0x1234_5678));
        assert!(!put_value(&mut record[..4], &list[1], 1));
    }
}
