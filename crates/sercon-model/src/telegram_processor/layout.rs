//! Whether the telegram processor's own RAM writes can change its header lists: the
//! *layout proof* the output bound rests on (`Chip::next_output_bound`).
//!
//! The bound walks the header lists ahead (410B §4.2.1: the headers are walked in list
//! order, PT) as the RAM holds them when asked. What the processor writes later could
//! change that walk only where it writes a word the walk, or a later walk, reads. It writes
//! (410B §4.2): the data a receive telegram brings into its containers' buffers (§4.2.2,
//! both buffers of a double buffer, VAL selecting), the service containers SCPTn points to
//! (§4.2.4, for receive and transmit containers with SVFL), its current header's own status
//! words (VAL, RERR in receive word 0, NERR in word 4, EN in transmit word 0), the end
//! marker's TEND word (§4.2.3) and NMSTERR (word 10). The walks read the headers (their
//! marker bits and PT), the containers' control words (which direct the stores) and the
//! pointer words 0–9 (COMPT0/1, SCPT0–7).
//!
//! When, over both lists (COMPT0 and COMPT1), no header or control word shares a word with
//! another, and none of the written words other than a header's own status words lies on a
//! read word, nothing the processor does rewrites its lists: a frame delivered ahead, whatever
//! it carries, cannot move the bound. The RAM then changes only by a host write, and a host
//! write to a word no walk reads keeps the proof. Otherwise (a receive container laid over a
//! header ahead, say: a programming error the chip still runs) the bound is not promised
//! and the chip is woken at its internal events.

use sercon_regs::Variant;
use sercon_regs::ram::header::{Header, HeaderKind};
use sercon_regs::ram::service::{SC_BUFFER_MAX_WORDS, SC_BUFFER_OFFSET};
use sercon_regs::ram::{COMPT0, COMPT1, FIXED_WORDS, NMSTERR, scpt};

use super::HeaderWord0;
use super::walk::{self, Containers};
use crate::chip::Chip;

/// The pointer words at the start of the RAM (410B §4.2: COMPT0/1 in words 0/1, SCPT0–7 in
/// words 2–9): read by every walk.
const POINTER_WORDS: u32 = NMSTERR as u32;

/// Every word a service container may write, counted from its SCPTn (control words and the
/// longest buffer, 410B §4.2.4).
const SC_SPAN: u32 = SC_BUFFER_OFFSET as u32 + SC_BUFFER_MAX_WORDS as u32;

/// A set of RAM words, one bit per word.
#[derive(Debug, Clone, Default)]
pub(crate) struct RamWords {
    bits: Vec<u64>,
}

impl RamWords {
    /// An empty set for `words` RAM words.
    fn new(words: u32) -> Self {
        RamWords {
            bits: vec![0; words.div_ceil(64) as usize],
        }
    }

    /// Whether any word of `from .. from + len` is in the set.
    pub(crate) fn any(&self, from: u32, len: u32) -> bool {
        let end = from.saturating_add(len);
        self.chunks(from, end)
            .map_while(|chunk| chunk)
            .any(|(bits, m)| bits & m != 0)
    }

    /// Whether every word of `from .. from + len` is in the set (none outside the RAM is).
    pub(crate) fn all(&self, from: u32, len: u32) -> bool {
        let Some(end) = from.checked_add(len) else {
            return false;
        };
        self.chunks(from, end)
            .all(|chunk| chunk.is_some_and(|(bits, m)| bits & m == m))
    }

    /// The words `from .. end` a set word at a time: its bits and the mask of the words in
    /// range; `None` for one outside the RAM (the last item then).
    fn chunks(&self, from: u32, end: u32) -> impl Iterator<Item = Option<(u64, u64)>> + '_ {
        let mut w = from;
        std::iter::from_fn(move || {
            if w >= end {
                return None;
            }
            let lo = w % 64;
            let n = (end - w).min(64 - lo);
            let bits = self.bits.get((w / 64) as usize).copied();
            w = if bits.is_some() { w + n } else { end };
            Some(bits.map(|b| (b, mask(lo, n))))
        })
    }

    /// Adds the words `from .. from + len` (those inside the RAM); `false` if any was in
    /// the set already.
    fn add(&mut self, from: u32, len: u32) -> bool {
        let end = from.saturating_add(len);
        let mut fresh = true;
        let mut w = from;
        while w < end {
            let Some(bits) = self.bits.get_mut((w / 64) as usize) else {
                break;
            };
            let lo = w % 64;
            let n = (end - w).min(64 - lo);
            let m = mask(lo, n);
            fresh &= *bits & m == 0;
            *bits |= m;
            w += n;
        }
        fresh
    }
}

/// `n` bits (1–64) from bit `lo`.
fn mask(lo: u32, n: u32) -> u64 {
    if n >= 64 {
        u64::MAX
    } else {
        ((1u64 << n) - 1) << lo
    }
}

/// What the processor may write for one header of a list.
struct Stores {
    /// Receive data buffers: (first word, words).
    data: Vec<(u32, u32)>,
    /// Service containers written (NSV).
    services: Vec<u8>,
    /// End markers' TEND words.
    tend: Vec<u32>,
}

/// The transmission blocks the chip may run with its registers as they are (bit n: block
/// n): the one running or about to start, the master's cycle block (410B §4.1 0CH.2
/// COMBLK0) and the blocks a slave's MST phases select (`mst::phase_block`: PHAS0 with
/// COMBLK0, PHAS1 with 0CH.3).
pub(crate) fn possible_blocks(chip: &Chip) -> u8 {
    let tp = &chip.tp;
    let mut blocks = 1u8 << u8::from(chip.engine.s.comblk0);
    if chip.engine.s.is_sercos_slave() {
        let phas1_block = chip.engine.regs.stored(sercon_regs::Register::Ctrl0C) & (1 << 3) != 0;
        blocks |= 1 << u8::from(phas1_block);
    }
    if let Some(b) = &tp.block {
        blocks |= 1 << (b.block & 1);
    }
    if let Some((_, b)) = tp.pending_block() {
        blocks |= 1 << (b & 1);
    }
    blocks
}

/// What [`prove`] found.
pub(crate) struct Proof {
    /// The processor's own writes leave its header lists as they are.
    pub(crate) holds: bool,
    /// The words the walks read (a host write elsewhere keeps the proof).
    pub(crate) read: RamWords,
    /// The proof may be kept until a host write to a read word or a change of the blocks;
    /// `false` when it was refused because a header the processor holds is not the RAM's
    /// ([`held_as_in_ram`]): that passes as the processor moves on, so it is found afresh.
    pub(crate) lasting: bool,
}

/// The layout proof of the chip's RAM as it is now for the header lists of `blocks`
/// ([`possible_blocks`]), with the words the walks read.
pub(crate) fn prove(chip: &Chip, blocks: u8) -> Proof {
    let (holds, read, lasting) = prove_lists(chip, blocks);
    Proof {
        holds,
        read,
        lasting,
    }
}

/// [`prove`]: (holds, read, lasting).
fn prove_lists(chip: &Chip, blocks: u8) -> (bool, RamWords, bool) {
    let variant = chip.cfg.variant;
    let mut read = RamWords::new(u32::from(variant.ram_words()));
    read.add(0, POINTER_WORDS);
    let mut stores = Stores {
        data: Vec::new(),
        services: Vec::new(),
        tend: Vec::new(),
    };
    let mut headers = RamWords::new(u32::from(variant.ram_words()));
    let mut ok = true;
    for compt in [COMPT0, COMPT1] {
        if blocks & (1 << compt) == 0 {
            continue;
        }
        let first = walk::word(&chip.ram, u32::from(compt)).unwrap_or(0);
        ok &= list(chip, first, &mut read, &mut headers, &mut stores);
        if !ok {
            return (false, read, true);
        }
    }
    if !held_as_in_ram(chip, &headers) {
        return (false, read, false);
    }
    let hits = |from: u32, len: u32| read.any(from, len);
    let clear = stores.data.iter().all(|&(from, len)| !hits(from, len))
        && stores.tend.iter().all(|&w| !hits(w, 1))
        && !hits(u32::from(NMSTERR), 1)
        && stores
            .services
            .iter()
            .all(|&nsv| service_clear(chip, variant, &read, nsv));
    (clear, read, true)
}

/// Whether the headers the processor holds are those the lists walked in the RAM (their
/// first words in `headers`): the current header, read into NTH when the telegram before it
/// started or its window closed and not read again (816 §2.10.1.2; its PT leads on, its
/// DBUF/DMA bits choose the words its containers store, 410B §4.2.1/§4.2.2), and the
/// receive header of a telegram still arriving (its containers are stored at its end with
/// its buffering as read). A host that rewrites such a header in the RAM (its PT, its
/// marker or buffering bits), or COMPT0/1 so that no list reaches it, leaves the processor
/// on a list the walks do not see: nothing is promised then.
fn held_as_in_ram(chip: &Chip, headers: &RamWords) -> bool {
    let variant = chip.cfg.variant;
    // Compared word by word (asked with every proof: no header decoded). Word 0: marker bits
    // 15-14 (00 receive, 01 transmit), DMA 8, DBUF 9; word 3: PT (410B §4.2.1).
    let same = |at: u16, marker: u16, pt: Option<u16>, dma: bool, dbuf: bool| {
        let word = |i: u32| walk::word(&chip.ram, u32::from(at) + i);
        let Some(w0) = word(0) else { return false };
        headers.any(u32::from(at), 1)
            && w0 & 0xC000 == marker
            && (w0 & (1 << 8) != 0) == dma
            && (w0 & (1 << 9) != 0) == dbuf
            && pt.is_none_or(|p| word(3).is_some_and(|w3| w3 & variant.pointer_mask() == p))
    };
    if let Some(super::RxNow {
        role: super::RxRole::Telegram { at, hdr },
        ..
    }) = &chip.tp.rx_now
        && !same(*at, RX_MARKER, None, hdr.dma(), hdr.dbuf())
    {
        return false;
    }
    match chip.tp.block.as_ref().and_then(|b| b.cur) {
        Some(super::Cur::Rx { at, hdr, .. }) => {
            same(at, RX_MARKER, Some(hdr.pt), hdr.dma(), hdr.dbuf())
        }
        Some(super::Cur::Tx { at, hdr, .. }) => {
            same(at, TX_MARKER, Some(hdr.pt), hdr.dma(), hdr.dbuf())
        }
        _ => true,
    }
}

/// Marker bits 15-14 of a receive header's word 0 (ERRATA "telegram header marker bits": 00).
const RX_MARKER: u16 = 0x0000;
/// Marker bits 15-14 of a transmit header's word 0 (01).
const TX_MARKER: u16 = 0x4000;

/// Walks the list from `first` as the processor would (410B §4.2.1: PT to PT, the end
/// marker or a header reached twice ending it, a bounded number of steps), adding what it
/// reads to `read` and what it may write to `stores`; `false` when two structures share a
/// word or a container walk fails (nothing is promised then).
fn list(
    chip: &Chip,
    first: u16,
    read: &mut RamWords,
    headers: &mut RamWords,
    stores: &mut Stores,
) -> bool {
    let variant = chip.cfg.variant;
    let mut ptr = first & variant.pointer_mask();
    for _ in 0..super::max_steps(chip) {
        let at = u32::from(ptr);
        if headers.any(at, 1) {
            // Reached before (from this list or the other): the walk ends or goes on as
            // it did then.
            return true;
        }
        let Ok(header) = walk::header_at(&chip.ram, variant, ptr) else {
            // The processor stops here with a programming error (410B §4.1 17H). What
            // decides that is the word with the marker bits (ERRATA "telegram header marker
            // bits": 10 is no structure; a kind that does not fit before the RAM's end): a
            // write over it, the host's or the processor's own (receive data, a header's
            // status word), can make a header of it and the list go on. It is read.
            headers.add(at, 1);
            return read.add(at, 1);
        };
        let (kind, words, next) = match header {
            Header::Receive(h) => (HeaderKind::Receive, 5, Some((h.pt, h.buffering()))),
            Header::Transmit(h) => (HeaderKind::Transmit, 4, Some((h.pt, h.buffering()))),
            Header::End(_) => (HeaderKind::EndMarker, 1, None),
        };
        headers.add(at, 1);
        if !read.add(at, words) {
            return false;
        }
        let Some((pt, buffering)) = next else {
            stores.tend.push(at + 1);
            return true;
        };
        let mut containers = Containers::new(&chip.ram, ptr, kind, buffering);
        for c in containers.by_ref() {
            if !read.add(c.at, c.data - c.at) {
                return false;
            }
            if kind == HeaderKind::Receive {
                // Both buffers of a double buffer (VAL selects which one is written).
                stores.data.push((c.data, c.control.data_words(buffering)));
            }
            if c.control.svfl {
                stores.services.push(c.control.nsv);
            }
        }
        if containers.error.is_some() {
            // The control words of the container that ended the walk decided it (LEN past
            // the RAM's end, 410B §4.2.2): a host write there lets the proof be made again.
            let (from, len) = containers.failed_words();
            read.add(from, len);
            return false;
        }
        ptr = pt & variant.pointer_mask();
    }
    true
}

/// Whether service container `nsv`'s words (from its SCPTn on, wrapping at the RAM's end,
/// `sc_word_address`) stay off every read word.
fn service_clear(chip: &Chip, variant: Variant, read: &RamWords, nsv: u8) -> bool {
    let pointer = scpt(nsv & 7).map_or(0, u32::from);
    let base = u32::from(walk::word(&chip.ram, pointer).unwrap_or(0) & variant.pointer_mask())
        & u32::from(variant.ram_address_mask());
    let ram = u32::from(variant.ram_words());
    let first = SC_SPAN.min(ram.saturating_sub(base));
    let wrapped = SC_SPAN - first;
    !read.any(base, first) && !read.any(0, wrapped)
}

// The fixed words end with NMSTERR (410B §4.2: "the first eleven words").
const _: () = assert!(FIXED_WORDS as u32 == POINTER_WORDS + 1);

#[cfg(test)]
mod tests {
    use super::RamWords;

    #[test]
    fn finds_and_adds_ranges_across_word_boundaries() {
        let mut w = RamWords::new(2048);
        assert!(!w.any(0, 2048));
        assert!(w.add(60, 10));
        assert!(w.any(69, 1));
        assert!(w.any(50, 11));
        assert!(!w.any(50, 10));
        assert!(!w.any(70, 100));
        assert!(w.add(128, 64));
        assert!(w.any(191, 1));
        assert!(!w.any(192, 1));
        assert!(!w.add(180, 20), "overlaps 128..192");
        // Outside the RAM: nothing added, nothing found, no panic.
        assert!(w.add(2040, 100));
        assert!(w.any(2047, 1));
        assert!(!w.any(4000, 10));
        assert!(!w.any(u32::MAX - 3, 10));
        assert!(w.add(u32::MAX - 3, 10));
        assert!(w.all(128, 64));
        assert!(w.all(60, 10));
        assert!(!w.all(59, 2), "59 is not in the set");
        assert!(!w.all(69, 2), "70 is not in the set");
        assert!(w.all(100, 0));
        assert!(!w.all(2047, 2), "2048 is outside the RAM");
        assert!(!w.all(u32::MAX - 3, 10));
    }
}
