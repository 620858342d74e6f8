//! The master's service channel, rebuilt from the MDTs it sends.
//!
//! The service channel carries non-cyclic data one 16-bit word per step in the service-info
//! field of a drive's MDT data record, with the control word's bits 5–0 saying what the word
//! is (sercos-telegrams.md, MDT control word): bit 0 MHS, the master's handshake toggle; bit 1
//! read (0) / write (1); bit 2 last transmission; bits 5–3 the data block element.
//!
//! [`TranscriptBuilder`] follows that handshake per drive from the master's side only (which is
//! all a capture of the master's transmitter holds):
//!
//! * a new step begins when MHS toggles; a record repeated with the same MHS is the master
//!   waiting for the drive's AHS and is skipped;
//! * a write to element 1 opens an IDN (the word is the IDN);
//! * reads of an element run until a step with the last-transmission bit (one entry, however
//!   many steps);
//! * words written to an element are collected until the last-transmission bit;
//! * element 0 closes the channel.
//!
//! In phases 1–2 the records come from MDTs addressed to one drive; in phases 3–4 from the
//! broadcast MDT, at the byte offset the master wrote to each drive's S-0-0009 (counted from
//! the ADR byte, which is offset 0; the captures show offsets 1, 9, 17, 25 for four 8-byte
//! records, i.e. the first record directly after ADR — see docs/spec-notes.md).

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use crate::idn::{Element, Idn};
use crate::telegram::{ControlWord, MstPacket, Origin, TelegramKind, classify};

/// What a transcript entry did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize),
    serde(rename_all = "lowercase")
)]
pub enum ServiceOp {
    /// The master read an element (the data travels in the ATs, which a capture of the
    /// master's transmitter does not hold).
    Read,
    /// The master wrote words to an element.
    Write,
    /// The master opened an IDN and closed it again without reading or writing anything.
    Open,
}

/// One service-channel transaction of the master with one drive.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TranscriptEntry {
    /// Communication phase of the MST preceding the first step.
    pub phase: u8,
    /// Drive address (1–254).
    pub drive: u8,
    /// What the master did.
    pub op: ServiceOp,
    /// The IDN opened before the transaction (`None` if the master never opened one).
    pub idn: Option<Idn>,
    /// The data block element read or written.
    pub element: Element,
    /// Words written (empty for reads and opens).
    pub words: Vec<u16>,
    /// Handshake steps the transaction took.
    pub steps: u32,
    /// Whether the transaction ended with the last-transmission bit (false when it was broken
    /// off by a new element, a close or the end of the input).
    pub complete: bool,
    /// Index of the telegram that carried the first step (as given to the builder).
    pub first_telegram: u64,
}

/// A transaction being collected.
#[derive(Debug, Clone)]
struct Pending {
    phase: u8,
    write: bool,
    element: Element,
    words: Vec<u16>,
    steps: u32,
    first_telegram: u64,
}

/// Per-drive handshake state.
#[derive(Debug, Clone, Default)]
struct DriveChannel {
    /// MHS of the last step seen (`None` before the first record).
    last_mhs: Option<bool>,
    /// The open IDN, the phase and telegram it was opened in, and whether anything used it.
    open: Option<(Idn, u8, u64, bool)>,
    pending: Option<Pending>,
    /// S-0-0009 as written by the master: the record's byte offset in the broadcast MDT.
    mdt_position: Option<u16>,
}

/// Rebuilds the master's service channel from the MDT records it sends; see the module docs.
#[derive(Debug, Clone, Default)]
pub struct TranscriptBuilder {
    phase: u8,
    drives: BTreeMap<u8, DriveChannel>,
    out: Vec<TranscriptEntry>,
}

impl TranscriptBuilder {
    /// An empty builder, phase 0.
    pub fn new() -> Self {
        Self::default()
    }

    /// Notes the phase of an MST (bits 2–0 of its data byte).
    pub fn mst(&mut self, phase: u8) {
        self.phase = phase & 0b111;
    }

    /// The phase of the last MST seen.
    pub fn phase(&self) -> u8 {
        self.phase
    }

    /// The byte offset of `drive`'s record in the broadcast MDT, as the master wrote it to
    /// S-0-0009 (counted from the ADR byte), if the master has written it.
    pub fn mdt_position(&self, drive: u8) -> Option<u16> {
        self.drives.get(&drive).and_then(|d| d.mdt_position)
    }

    /// Feeds one MDT, given as its telegram bytes (ADR first, no FCS). `index` labels the
    /// telegram in the entries it produces. A unicast MDT is one drive's record; a broadcast
    /// MDT holds a record for each drive whose S-0-0009 the master has written. MDTs too short
    /// to hold a control word and service info are ignored.
    pub fn mdt(&mut self, telegram: &[u8], index: u64) {
        let Some(&adr) = telegram.first() else {
            return;
        };
        match adr {
            // sercos-telegrams.md: 0 = no station.
            0 => {}
            // sercos-telegrams.md: in phases 3–4 a broadcast MDT holds one record per drive.
            255 => {
                let located: Vec<(u8, usize)> = self
                    .drives
                    .iter()
                    .filter_map(|(d, ch)| ch.mdt_position.map(|p| (*d, usize::from(p))))
                    .collect();
                for (drive, offset) in located {
                    if let Some((cw, info)) = record_words(telegram, offset) {
                        self.record(drive, cw, info, index);
                    }
                }
            }
            // sercos-telegrams.md: in phases 0–2 an MDT carries one record for one drive.
            drive => {
                if let Some((cw, info)) = record_words(telegram, 1) {
                    self.record(drive, cw, info, index);
                }
            }
        }
    }

    /// Feeds one telegram sent by the master (telegram bytes, ADR first, no FCS): an MST sets
    /// the phase, an MDT is taken as by [`TranscriptBuilder::mdt`]; anything else is ignored.
    pub fn master_telegram(&mut self, telegram: &[u8], index: u64) {
        match classify(telegram, Origin::Master) {
            Ok(TelegramKind::Mst) => {
                if let Ok(p) = MstPacket::new_checked(telegram) {
                    self.mst(p.phase_bits());
                }
            }
            Ok(TelegramKind::Mdt) => self.mdt(telegram, index),
            _ => {}
        }
    }

    /// Feeds one drive's record: its control word and service-info word.
    pub fn record(&mut self, drive: u8, control: ControlWord, info: u16, index: u64) {
        let phase = self.phase;
        let ch = self.drives.entry(drive).or_default();
        let mhs = control.mhs();
        // sercos-telegrams.md, control word bit 0: MHS is a toggle bit; a record with an
        // unchanged MHS repeats the step while the master waits for the drive's handshake.
        if ch.last_mhs == Some(mhs) {
            return;
        }
        let first_ever = ch.last_mhs.is_none();
        ch.last_mhs = Some(mhs);
        if first_ever && control.data_block_element() == Element::ServiceChannelClosed {
            return;
        }
        let element = control.data_block_element();
        let write = control.write();
        let last = control.last_transmission();
        match element {
            // Element 0: "close service channel or break a transmission in progress".
            Element::ServiceChannelClosed => {
                flush(ch, drive, &mut self.out, false);
                close(ch, drive, &mut self.out);
            }
            // Element 1 written: "the service channel is closed for the previous IDN and
            // opened for a new IDN".
            Element::Idn if write => {
                flush(ch, drive, &mut self.out, false);
                close(ch, drive, &mut self.out);
                ch.open = Some((Idn::from_raw(info), phase, index, false));
            }
            _ => {
                let continues = ch
                    .pending
                    .as_ref()
                    .is_some_and(|p| p.element == element && p.write == write);
                if !continues {
                    flush(ch, drive, &mut self.out, false);
                    ch.pending = Some(Pending {
                        phase,
                        write,
                        element,
                        words: Vec::new(),
                        steps: 0,
                        first_telegram: index,
                    });
                }
                if let Some(p) = ch.pending.as_mut() {
                    p.steps = p.steps.saturating_add(1);
                    if write {
                        p.words.push(info);
                    }
                }
                if last {
                    flush(ch, drive, &mut self.out, true);
                }
            }
        }
    }

    /// Takes the entries completed so far, in the order they completed.
    pub fn take_entries(&mut self) -> Vec<TranscriptEntry> {
        core::mem::take(&mut self.out)
    }

    /// Ends the input: transactions still in progress are emitted as incomplete, and IDNs
    /// opened but never used as [`ServiceOp::Open`]. Returns every entry not yet taken.
    pub fn finish(mut self) -> Vec<TranscriptEntry> {
        let drives = core::mem::take(&mut self.drives);
        for (drive, mut ch) in drives {
            flush(&mut ch, drive, &mut self.out, false);
            close(&mut ch, drive, &mut self.out);
        }
        self.out
    }
}

/// The control word and service-info word of the record at byte `offset` of `telegram`
/// (ADR at offset 0), if the telegram holds them.
fn record_words(telegram: &[u8], offset: usize) -> Option<(ControlWord, u16)> {
    let w = telegram.get(offset..offset.checked_add(4)?)?;
    // ERRATA.md, telegrams: 16-bit words go low byte first.
    let cw = u16::from_le_bytes([w[0], w[1]]);
    let info = u16::from_le_bytes([w[2], w[3]]);
    Some((ControlWord::from_raw(cw), info))
}

/// Emits the pending transaction of `ch`, if any.
fn flush(ch: &mut DriveChannel, drive: u8, out: &mut Vec<TranscriptEntry>, complete: bool) {
    let Some(p) = ch.pending.take() else {
        return;
    };
    let idn = ch.open.as_mut().map(|(idn, _, _, used)| {
        *used = true;
        *idn
    });
    // sercos-facts.md, timing parameters: S-0-0009 is the position of the drive's record in
    // the MDT. Remember it so the drive's records can be found in the broadcast MDT.
    if p.write
        && complete
        && p.element == Element::OperationData
        && idn == Some(Idn::MDT_RECORD_POSITION)
    {
        if let Some(&pos) = p.words.first() {
            ch.mdt_position = Some(pos);
        }
    }
    out.push(TranscriptEntry {
        phase: p.phase,
        drive,
        op: if p.write {
            ServiceOp::Write
        } else {
            ServiceOp::Read
        },
        idn,
        element: p.element,
        words: p.words,
        steps: p.steps,
        complete,
        first_telegram: p.first_telegram,
    });
}

/// Closes the open IDN; one that was never used becomes an [`ServiceOp::Open`] entry.
fn close(ch: &mut DriveChannel, drive: u8, out: &mut Vec<TranscriptEntry>) {
    if let Some((idn, phase, index, used)) = ch.open.take() {
        if !used {
            out.push(TranscriptEntry {
                phase,
                drive,
                op: ServiceOp::Open,
                idn: Some(idn),
                element: Element::Idn,
                words: Vec::new(),
                steps: 1,
                complete: true,
                first_telegram: index,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unicast MDT: ADR, control word, service info (low bytes first).
    fn mdt(adr: u8, cw: u16, info: u16) -> [u8; 5] {
        let c = cw.to_le_bytes();
        let i = info.to_le_bytes();
        [adr, c[0], c[1], i[0], i[1]]
    }

    fn feed(b: &mut TranscriptBuilder, seq: &[(u8, u16, u16)]) {
        for (n, (adr, cw, info)) in seq.iter().enumerate() {
            b.mdt(&mdt(*adr, *cw, *info), n as u64);
        }
    }

    #[test]
    fn write_of_one_word_as_in_the_capture() {
        // The captures' phase-2 write of S-0-0001 = 2000 to drive 1: 0x0F opens (MHS 1,
        // write, last, element 1), 0x3E writes element 7 with last, 0x07 closes; every step
        // is sent twice or three times while the master waits for AHS.
        let mut b = TranscriptBuilder::new();
        b.mst(2);
        feed(
            &mut b,
            &[
                (1, 0x0000, 0x0080),
                (1, 0x000F, 0x0001),
                (1, 0x000F, 0x0001),
                (1, 0x003E, 2000),
                (1, 0x003E, 2000),
                (1, 0x0007, 2000),
                (1, 0x0007, 2000),
            ],
        );
        let e = b.finish();
        assert_eq!(e.len(), 1, "{e:?}");
        assert_eq!(e[0].op, ServiceOp::Write);
        assert_eq!(e[0].idn, Some(Idn::NC_CYCLE_TIME));
        assert_eq!(e[0].element, Element::OperationData);
        assert_eq!(e[0].words, [2000]);
        assert_eq!((e[0].phase, e[0].drive, e[0].complete), (2, 1, true));
    }

    #[test]
    fn reads_collapse_steps_and_lists_collect_words() {
        // Capture: S-0-0003 attribute read in two steps (0x18, 0x1D), operation data in one
        // (0x3C); then S-0-0024 written as a list: 0x3A, 0x3B, 0x3E (last) with words
        // 2, 2, 0x0024.
        let mut b = TranscriptBuilder::new();
        b.mst(2);
        feed(
            &mut b,
            &[
                (1, 0x0000, 0),
                (1, 0x000F, 0x0003),
                (1, 0x0018, 0x0003),
                (1, 0x001D, 0x0003),
                (1, 0x003C, 0x0003),
                (1, 0x0007, 0x0003),
                (1, 0x000E, 0x0018),
                (1, 0x003B, 2),
                (1, 0x003A, 2),
                (1, 0x003F, 0x0024),
                (1, 0x0006, 0x0024),
            ],
        );
        let e = b.finish();
        assert_eq!(e.len(), 3, "{e:?}");
        assert_eq!(
            (e[0].op, e[0].element, e[0].steps),
            (ServiceOp::Read, Element::Attribute, 2)
        );
        assert_eq!(e[0].idn, Some(Idn::from_raw(3)));
        assert_eq!(
            (e[1].op, e[1].element, e[1].steps),
            (ServiceOp::Read, Element::OperationData, 1)
        );
        assert_eq!(e[2].op, ServiceOp::Write);
        assert_eq!(e[2].idn, Some(Idn::from_raw(0x18)));
        assert_eq!(e[2].words, [2, 2, 0x0024]);
    }

    #[test]
    fn broadcast_records_follow_s0009() {
        let mut b = TranscriptBuilder::new();
        b.mst(2);
        // Drive 2 is told its record is at offset 5 (after drive 1's 4-byte record).
        feed(
            &mut b,
            &[(2, 0, 0), (2, 0x000F, 9), (2, 0x003E, 5), (2, 0x0007, 5)],
        );
        b.mst(4);
        // Broadcast MDT: drive 1's record (never positioned) at 1, drive 2's at 5.
        let mut t = [0u8; 9];
        t[0] = 255;
        t[5..7].copy_from_slice(&0x000Eu16.to_le_bytes());
        t[7..9].copy_from_slice(&0x0063u16.to_le_bytes());
        b.mdt(&t, 10);
        t[5..7].copy_from_slice(&0x003Fu16.to_le_bytes());
        t[7..9].copy_from_slice(&3u16.to_le_bytes());
        b.mdt(&t, 11);
        assert_eq!(b.mdt_position(2), Some(5));
        let e = b.finish();
        assert_eq!(e.len(), 2, "{e:?}");
        assert_eq!((e[1].phase, e[1].drive, e[1].op), (4, 2, ServiceOp::Write));
        assert_eq!(
            (e[1].idn, e[1].words.as_slice()),
            (Some(Idn::from_raw(0x63)), &[3u16][..])
        );
    }

    #[test]
    fn broken_transfers_are_incomplete_and_unused_opens_are_reported() {
        let mut b = TranscriptBuilder::new();
        b.mst(2);
        feed(
            &mut b,
            &[
                (3, 0, 0),
                (3, 0x000F, 0x0010),
                (3, 0x003A, 6),
                (3, 0x0001, 0), // element 0 breaks the transfer off
                (3, 0x000A, 0x0063),
                (3, 0x0007, 0x0063),
            ],
        );
        let e = b.finish();
        assert_eq!(e.len(), 2, "{e:?}");
        assert_eq!(
            (e[0].op, e[0].complete, e[0].words.as_slice()),
            (ServiceOp::Write, false, &[6u16][..])
        );
        assert_eq!(
            (e[1].op, e[1].idn),
            (ServiceOp::Open, Some(Idn::from_raw(0x63)))
        );
    }

    #[test]
    fn short_or_odd_telegrams_are_ignored() {
        let mut b = TranscriptBuilder::new();
        b.mdt(&[], 0);
        b.mdt(&[1, 2, 3], 1);
        b.mdt(&[0, 0x0F, 0, 1, 0], 2);
        b.mdt(&[255; 3], 3);
        assert!(b.finish().is_empty());
    }
}
