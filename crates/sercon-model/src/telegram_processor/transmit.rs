//! Transmit telegrams (410B §4.2.1 transmit header, §4.2.2 data containers; 816 §2.9,
//! §2.10.1).

use sercon_regs::Variant;
use sercon_regs::ram::header::{Buffering, HeaderKind, TxEnable};

use super::status::{INT_TEND, INT_TSTART, ProgErr};
use super::walk::{self, Containers};
use super::walk_memo;
use super::{Cur, HeaderWord0, TxHead, advance, entmt, prog_error, reg25, set_flmdtadr};
use crate::chip::Chip;
use crate::mclk::Due;
use crate::service_container::{self, ScMode};

/// A transmit header became current (read into NTH): a DMA telegram asks for its data.
// 410B §2 DMAREQT: "becomes active when data can be written to the transmit FIFO".
// Words written before (after the previous DMA transmit telegram took its words) are kept
// up to what this telegram needs (spec-notes "Master DMA layout").
pub(super) fn prepare(chip: &mut Chip, at: u16, hdr: &TxHead) {
    if hdr.buffering() != Buffering::Dma || hdr.en() == TxEnable::Off {
        chip.tp.fifo.tx.clear();
        chip.tp.fifo.tx_want = 0;
        return;
    }
    let want: usize = Containers::new(&chip.ram, at, HeaderKind::Transmit, Buffering::Dma)
        .map(|c| usize::from(c.control.len))
        .sum();
    let want = want.min(usize::from(hdr.tlen));
    chip.tp.fifo.tx.truncate(want);
    chip.tp.fifo.want_tx(want);
}

/// Whether the telegram is sent, by EN (410B §4.2.1: "not to be transmitted (EN = 0),
/// transmitted once (EN = 1), continuously (EN = 2) or transmitted only if the
/// previously received telegram contains the expected address (EN = 3) (PHAS12 = 1 and
/// FLMDTADR = 1)").
fn enabled(en: TxEnable, phas12: bool, flmdtadr: bool) -> bool {
    match en {
        TxEnable::Off => false,
        TxEnable::Once | TxEnable::Continuous => true,
        TxEnable::OnAddress => phas12 && flmdtadr,
    }
}

/// The transmit telegram of the header at `at` is due at `tick`; `nth` is the header as
/// read when it became current.
pub(super) fn start(chip: &mut Chip, tick: u64, at: u16, nth: TxHead) {
    let variant = chip.cfg.variant;
    let mut hdr = nth;
    if variant == Variant::Sercon816 {
        // 816 §2.10.1.2: "the VAL bit is read from the telegram header at start of a
        // transmit telegram again, all other data of the telegram header (ADR, DMA, DBUF
        // and EN) will NOT be read again." The 410B keeps the VAL of NTH.
        let w0 = walk::word(&chip.ram, u32::from(at)).unwrap_or(0);
        hdr = hdr.with_val(w0 & (1 << 10) != 0);
    }
    // The next header is read at the start of this telegram (816 §2.10.1.2, Figure 6:
    // "After start of a telegram the telegram header of the next expected telegram is
    // written into register NTH").
    let (_, phas12, flmdtadr) = reg25(chip);
    let send = entmt(chip) && enabled(hdr.en(), phas12, flmdtadr);
    if !send || tick < chip.tp.tx_busy_until {
        if send {
            // The transmitter is still busy with the previous telegram.
            prog_error(chip, ProgErr::Overlap);
        }
        chip.tp.fifo.tx_want = 0;
        advance(chip, tick, hdr.pt);
        return;
    }
    if hdr.en() == TxEnable::Once {
        // 410B §4.2.1 EN: "If EN is 1 the circuit sets EN to 0 after the transmit telegram
        // has been started"; the whole word 0 is written back, with the VAL last read
        // (816 §2.10.1.2; on the 410B that is NTH's VAL, overwriting a newer one).
        let w0 = hdr.with_en(TxEnable::Off).w0;
        walk::set_word(&mut chip.ram, u32::from(at), w0);
        super::output_bound::ram_written(chip, u32::from(at), 1);
    }
    if hdr.en() == TxEnable::OnAddress && variant == Variant::Sercon816 {
        // 816 §2.9.2: "the flag FLMDTADR is reset after starting to send a telegram when
        // initiated when the flag is set. Therefore sending AT's can occur only once."
        set_flmdtadr(chip, false);
    }
    assemble(chip, at, &hdr);
    let start = chip.clock.instant(tick);
    let end = match super::line_out::send(chip, start) {
        Some(end) => chip.clock.tick_at_or_after(end).max(tick),
        None => tick,
    };
    chip.tp.tx_busy_until = end;
    chip.tp.tx_end = Due::at(end);
    // 410B §4.1 21H THTPT / 22H THT: header of the transmitted telegram; 4H.10 INT_TSTART.
    chip.tp.thtpt = at;
    chip.tp.tht = walk::word(&chip.ram, u32::from(at)).unwrap_or(0);
    chip.engine.flags.raise_lo(INT_TSTART);
    if let Some(b) = chip.tp.block.as_mut() {
        b.last_end = b.last_end.max(end);
    }
    super::load(chip, tick, hdr.pt);
    // A transmit telegram after this one cannot start before this one has ended.
    if let Some(super::Block {
        cur: Some(Cur::Tx { start, .. }),
        ..
    }) = chip.tp.block
        && start < end
    {
        prog_error(chip, ProgErr::Overlap);
    }
}

/// Appends the `n` words of a container (`data`) to the telegram in `buf`, which holds
/// `words` data words of at most `tlen`: words past TLEN are not sent, a container overrun
/// (410B §4.2.1 TLEN); little-endian words (410B §4.2.2), written in one go.
fn append_words(
    buf: &mut Vec<u8>,
    data: impl Iterator<Item = u16>,
    n: usize,
    tlen: usize,
    words: &mut usize,
    overrun: &mut bool,
) {
    let take = n.min(tlen.saturating_sub(*words));
    *overrun |= take < n;
    let at = buf.len();
    buf.resize(at + 2 * take, 0);
    if let Some(dst) = buf.get_mut(at..) {
        for (d, w) in dst.chunks_exact_mut(2).zip(data) {
            d.copy_from_slice(&w.to_le_bytes());
        }
    }
    *words += take;
}

/// The `len` RAM words from `from`, those outside the RAM read as 0 (the walk keeps
/// containers inside).
fn words_or_zero(ram: &[u16], from: u32, len: usize) -> impl Iterator<Item = u16> + '_ {
    (0..len).map(move |i| walk::word(ram, from + i as u32).unwrap_or(0))
}

/// Builds ADR and the data words of the telegram in `chip.tp.txbuf`: the usual telegram
/// (one container kept under the layout proof, `walk_memo`, buffered in the RAM, no
/// service container) the short way ([`assemble_kept`]), any other the general way
/// ([`assemble_general`]). Debug builds assemble every short one the general way on a
/// copy of the chip too and compare the whole chip.
// 410B §4.2.1 ADR, TLEN ("Length of the telegram in data words (not including address)");
// §4.2.2: the data containers in order, from the valid buffer or the transmit FIFO.
fn assemble(chip: &mut Chip, at: u16, hdr: &TxHead) {
    let buffering = hdr.buffering();
    if buffering != Buffering::Dma
        && let Some(c) = walk_memo::kept(chip, at, HeaderKind::Transmit, buffering)
        && !c.control.svfl
    {
        #[cfg(debug_assertions)]
        let general = {
            let mut general = chip.clone();
            assemble_general(&mut general, at, hdr);
            general
        };
        assemble_kept(chip, &c, hdr);
        #[cfg(debug_assertions)]
        check_kept_assembly(chip, general);
        return;
    }
    assemble_general(chip, at, hdr);
}

/// [`assemble`] of a telegram whose one container `c` is kept (`walk_memo`: no walk error)
/// and holds no service container, buffered in the RAM (410B §4.2.1 DMA = 0): ADR, the
/// container's words from its valid buffer (410B §4.2.2, VAL/DBUF), at most TLEN of them
/// (more is a container overrun, 410B §4.2.1 TLEN), then 0 up to TLEN; the transmit FIFO
/// emptied and not wanted (410B §2 DMAREQT: no DMA telegram).
#[inline(always)]
fn assemble_kept(chip: &mut Chip, c: &walk::Container, hdr: &TxHead) {
    let tlen = usize::from(hdr.tlen);
    let len = usize::from(c.control.len);
    let take = len.min(tlen);
    let from = c.buffer(hdr.buffering(), hdr.val());
    // The buffer brought to the telegram's length (a slave's holds its AT of the same
    // length from the cycle before: nothing filled), every byte then written in place.
    let buf = &mut chip.tp.txbuf;
    let n = 1 + 2 * tlen;
    buf.truncate(n);
    buf.resize(n, 0);
    // `take` ≤ TLEN: both splits are inside the buffer.
    if let Some((adr, rest)) = buf.split_first_mut()
        && let Some((dst, tail)) = rest.split_at_mut_checked(2 * take)
    {
        *adr = hdr.adr();
        write_words(dst, &chip.ram, from, take);
        if !tail.is_empty() {
            // Containers shorter than TLEN: the rest of the telegram is sent as 0.
            tail.fill(0);
        }
    }
    chip.tp.fifo.tx.clear();
    chip.tp.fifo.want_tx(0);
    if take < len {
        prog_error(chip, ProgErr::ContainerOverrun);
    }
}

/// Writes the `len` RAM words from `from` into `dst` as little-endian bytes (410B §4.2.2),
/// those outside the RAM as 0 (`words_or_zero`).
#[inline(always)]
fn write_words(dst: &mut [u8], ram: &[u16], from: u32, len: usize) {
    match walk::words(ram, from, len) {
        Some(data) => {
            for (d, w) in dst.chunks_exact_mut(2).zip(data) {
                d.copy_from_slice(&w.to_le_bytes());
            }
        }
        None => {
            for (d, w) in dst.chunks_exact_mut(2).zip(words_or_zero(ram, from, len)) {
                d.copy_from_slice(&w.to_le_bytes());
            }
        }
    }
}

/// Debug builds: the chip after [`assemble_kept`] is `general`, the chip the general
/// assembly left, but for the containers' scratch list (which only the general walk fills).
#[cfg(debug_assertions)]
fn check_kept_assembly(chip: &Chip, mut general: Chip) {
    general.tp.containers = chip.tp.containers.clone();
    debug_assert_eq!(
        format!("{general:?}"),
        format!("{chip:?}"),
        "a kept container's telegram assembled the short way"
    );
}

/// [`assemble`] the general way: every container walked (or the kept one), from the
/// valid buffer or the transmit FIFO, service containers filled in.
fn assemble_general(chip: &mut Chip, at: u16, hdr: &TxHead) {
    let variant = chip.cfg.variant;
    let buffering = hdr.buffering();
    let tlen = usize::from(hdr.tlen);
    let mut buf = std::mem::take(&mut chip.tp.txbuf);
    let mut record = std::mem::take(&mut chip.tp.record);
    buf.clear();
    buf.push(hdr.adr());
    let mut words = 0usize;
    let mut overrun = false;
    let mut fifo_short = false;
    let (hs, busy) = {
        let w = chip.engine.regs.stored(sercon_regs::Register::ScTimeout);
        ((w & 0xFF) as u8, (w >> 8) as u8)
    };
    let mut list = std::mem::take(&mut chip.tp.containers);
    list.clear();
    let walk_error = match walk_memo::kept(chip, at, HeaderKind::Transmit, buffering) {
        // Walked before under the layout proof that still stands: the same container, no
        // walk error (`walk_memo`).
        Some(c) => {
            list.push(c);
            None
        }
        None => {
            let mut walk = Containers::new(&chip.ram, at, HeaderKind::Transmit, buffering);
            // One push per container (`extend` takes the generic path for this iterator: a
            // size hint and a capacity check per element).
            for c in walk.by_ref() {
                list.push(c);
            }
            let error = walk.error;
            walk_memo::keep(chip, at, HeaderKind::Transmit, buffering, &list, error);
            error
        }
    };
    for c in list.iter() {
        let len = usize::from(c.control.len);
        if buffering != Buffering::Dma && !c.control.svfl {
            // The usual container: its words go from the valid buffer straight into the
            // telegram (no record in between).
            let from = c.buffer(buffering, hdr.val());
            let ram = &chip.ram;
            match walk::words(ram, from, len) {
                Some(data) => {
                    append_words(
                        &mut buf,
                        data.iter().copied(),
                        len,
                        tlen,
                        &mut words,
                        &mut overrun,
                    );
                }
                None => {
                    let data = words_or_zero(ram, from, len);
                    append_words(&mut buf, data, len, tlen, &mut words, &mut overrun);
                }
            }
            continue;
        }
        record.clear();
        match buffering {
            Buffering::Dma => {
                for _ in 0..len {
                    match chip.tp.fifo.tx.pop_front() {
                        Some(w) => record.push(w),
                        None => {
                            fifo_short = true;
                            record.push(0);
                        }
                    }
                }
            }
            // A service container's record.
            _ => {
                let from = c.buffer(buffering, hdr.val());
                record.extend(words_or_zero(&chip.ram, from, len));
            }
        }
        if c.control.svfl {
            // 410B §4.2.2 SVFL/NSV/SCMASTER: the service container fills in the record's
            // service-channel bits and info words.
            let mode = ScMode::from_scmaster(c.control.scmaster);
            let nsv = c.control.nsv;
            if mode == ScMode::Master {
                let o = service_container::on_cycle(&mut chip.ram, variant, nsv, mode, hs, busy);
                raise_sc(chip, nsv, o.int_sc);
            }
            let o = service_container::on_transmit(&mut chip.ram, variant, nsv, mode, &mut record);
            raise_sc(chip, nsv, o.int_sc);
            super::output_bound::ram_rewritten(chip);
        }
        let n = record.len();
        append_words(
            &mut buf,
            record.iter().copied(),
            n,
            tlen,
            &mut words,
            &mut overrun,
        );
    }
    // Containers shorter than TLEN: the rest of the telegram is sent as 0.
    buf.resize(buf.len() + 2 * tlen.saturating_sub(words), 0);
    chip.tp.fifo.tx.clear();
    // The FIFO takes the words of this header's next telegram from now on: DMAREQT is
    // active again (410B §2 "becomes active when data can be written to the transmit
    // FIFO"; spec-notes "Master DMA layout").
    chip.tp.fifo.want_tx(if buffering == Buffering::Dma {
        list.iter()
            .map(|c| usize::from(c.control.len))
            .sum::<usize>()
            .min(tlen)
    } else {
        0
    });
    chip.tp.txbuf = buf;
    chip.tp.record = record;
    chip.tp.containers = list;
    if let Some(e) = walk_error {
        prog_error(chip, e);
    }
    if overrun {
        prog_error(chip, ProgErr::ContainerOverrun);
    }
    if fifo_short {
        prog_error(chip, ProgErr::DmaFifo);
    }
}

/// 410B §4.1 5H.0-7 INT_SC_n.
pub(super) fn raise_sc(chip: &mut Chip, nsv: u8, raised: bool) {
    if raised {
        chip.engine.flags.raise_hi(1 << (nsv & 7));
    }
}

/// The telegram being sent ended at `tick`: FLTMT falls, INT_TEND (410B §4.1 3H.9, 4H.11).
pub(super) fn end(chip: &mut Chip, tick: u64) {
    chip.tp.tx_end = Due::NONE;
    chip.engine.flags.raise_lo(INT_TEND);
    if let Some(b) = chip.tp.block.as_mut() {
        b.last_end = b.last_end.max(tick);
    }
}
