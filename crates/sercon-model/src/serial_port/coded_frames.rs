//! The line bits of the telegrams sent lately, kept for reuse.
//!
//! A node sends mostly the same telegrams cycle after cycle (the MST every cycle, MDTs and
//! ATs whose data did not change), so the transmitter looks a telegram up here before it
//! encodes it: the same bytes with the same sync word on a line at the same level give the
//! same NRZI bits (410B §2 TxD: NRZI coding depends only on the data and the level before
//! the first bit), shared through a [`Shared`] count instead of being encoded and allocated again.

use sercos_wire::line::{BitVec, Coding, Encoder, LineConfig, Polarity, frame_bit_len};

use super::{Codings, FrameHint, PRESYNC_BITS, Shared};

/// Telegrams remembered (a master's MST and MDTs, a slave's ATs: a handful per cycle).
const ENTRIES: usize = 8;

/// One telegram and its coded forms.
#[derive(Debug, Clone)]
struct Entry {
    telegram: Shared<[u8]>,
    presync: bool,
    /// Line bits: sync word, flags, stuffed data and FCS.
    len: u64,
    /// Once coded: the hint of every segment of the telegram, with the bits from both
    /// levels ([`FrameHint::coded`], always set here) and the offset of the opening flag.
    hint: Option<Shared<FrameHint>>,
}

/// A telegram's line bits from one level and its hint (shared by the segments of the
/// telegram from either level).
#[derive(Debug, Clone)]
pub(crate) struct Coded {
    pub(crate) bits: Shared<BitVec>,
    pub(crate) hint: Shared<FrameHint>,
}

/// A telegram as [`CodedFrames::lookup`] finds it: coded before (its hint, with its bits
/// from both levels), or only its shared bytes (coded when it is released).
#[derive(Debug, Clone)]
pub(crate) enum Known {
    /// The hint of a telegram coded before ([`FrameHint::coded`] set).
    Coded(Shared<FrameHint>),
    /// The telegram's shared bytes.
    Bytes(Shared<[u8]>),
}

/// The telegrams sent lately (round robin).
#[derive(Debug, Clone, Default)]
pub(crate) struct CodedFrames {
    entries: Vec<Entry>,
    next: usize,
}

impl CodedFrames {
    /// `telegram` as remembered (its hint when it was coded before, else its shared bytes)
    /// and its length in line bits (with the sync word if `presync`).
    pub(crate) fn lookup(&mut self, telegram: &[u8], presync: bool) -> (Known, u64) {
        if let Some(e) = self
            .entries
            .iter()
            .find(|e| e.presync == presync && *e.telegram == *telegram)
        {
            let known = match &e.hint {
                Some(hint) => Known::Coded(hint.clone()),
                None => Known::Bytes(e.telegram.clone()),
            };
            return (known, e.len);
        }
        let sync = if presync { PRESYNC_BITS } else { 0 };
        let entry = Entry {
            telegram: Shared::from(telegram),
            presync,
            len: sync + frame_bit_len(telegram),
            hint: None,
        };
        let found = (Known::Bytes(entry.telegram.clone()), entry.len);
        if self.entries.len() < ENTRIES {
            self.entries.push(entry);
        } else if let Some(slot) = self.entries.get_mut(self.next) {
            *slot = entry;
            self.next = (self.next + 1) % ENTRIES;
        }
        found
    }

    /// The NRZI bits of `telegram` (as given by [`CodedFrames::lookup`]) on a line at
    /// light level `level` before the first bit and the telegram's hint: the offset of the
    /// opening flag and, when the telegram is remembered, its bits from both levels;
    /// `None` when it cannot be encoded. A telegram found coded takes its bits from its
    /// hint, without a search.
    // Inlined at every call: with the release's second own-telegram turn
    // (`Transmitter::release_merged_then_own`) LLVM kept it out of line, which cost more
    // than that turn saves.
    #[inline(always)]
    pub(crate) fn coded(
        &mut self,
        telegram: Known,
        presync: bool,
        len: u64,
        level: bool,
    ) -> Option<Coded> {
        let telegram = match telegram {
            Known::Coded(hint) => {
                let bits = hint.coded.as_ref()?.bits()[usize::from(level)].clone();
                debug_assert_eq!(
                    encode(&hint.telegram, presync, len, level).map(|(b, o)| ((*b).clone(), o)),
                    Some(((*bits).clone(), hint.offset)),
                    "a coded telegram's bits from its hint"
                );
                return Some(Coded { bits, hint });
            }
            Known::Bytes(telegram) => telegram,
        };
        let telegram = &telegram;
        let Some(entry) = self
            .entries
            .iter_mut()
            .find(|e| e.presync == presync && Shared::ptr_eq(&e.telegram, telegram))
        else {
            let (bits, offset) = encode(telegram, presync, len, level)?;
            let hint = Shared::new(FrameHint {
                telegram: telegram.clone(),
                offset,
                coded: None,
            });
            return Some(Coded { bits, hint });
        };
        let hint = match &entry.hint {
            Some(hint) => hint,
            None => entry
                .hint
                .insert(code_both(&entry.telegram, presync, len, level)?),
        };
        let bits = hint.coded.as_ref()?.bits()[usize::from(level)].clone();
        Some(Coded {
            bits,
            hint: hint.clone(),
        })
    }
}

/// The hint of `telegram` with its bits from both levels: encoded for `level`, and for
/// the other level inverted (NRZI from the other level gives every level the other way,
/// 410B §2 TxD: the coding depends only on the data and the level before the first bit),
/// with the opening flag at the same offset.
#[cold]
#[inline(never)]
fn code_both(
    telegram: &Shared<[u8]>,
    presync: bool,
    len: u64,
    level: bool,
) -> Option<Shared<FrameHint>> {
    let (this, offset) = encode(telegram, presync, len, level)?;
    let other = Shared::new(this.inverted());
    let coded = if level { [other, this] } else { [this, other] };
    Some(Shared::new(FrameHint {
        telegram: telegram.clone(),
        offset,
        coded: Some(Codings::new(coded)),
    }))
}

/// Encodes `telegram` for a line at light level `level` before its first bit.
fn encode(telegram: &[u8], presync: bool, len: u64, level: bool) -> Option<(Shared<BitVec>, u64)> {
    // NRZI only depends on the polarity for the level before the first bit (a dark line),
    // so the polarity whose dark level is `level` continues a line at `level`.
    let polarity = if level {
        Polarity::LightOnLow
    } else {
        Polarity::LightOnHigh
    };
    let mut enc = Encoder::new(LineConfig::new(Coding::Nrzi, polarity));
    let mut bits = BitVec::with_capacity(usize::try_from(len).ok()?);
    if presync {
        // 410B §4.1 1H.8 PRESYNC: "Pre-frame sync word" before the frame.
        enc.idle(PRESYNC_BITS, &mut bits).ok()?;
    }
    let offset = bits.len();
    enc.encode(telegram, &mut bits).ok()?;
    Some((Shared::new(bits), offset))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bits of a remembered telegram from the other level than `coded.bits`, checking
    /// that `coded.bits` are the hint's own.
    fn twin_of(coded: &Coded) -> Shared<BitVec> {
        let [low, high] = coded.hint.coded.clone().expect("remembered").bits().clone();
        if Shared::ptr_eq(&coded.bits, &low) {
            high
        } else {
            assert!(Shared::ptr_eq(&coded.bits, &high), "bits not the hint's");
            low
        }
    }

    /// The shared bytes of a telegram as found.
    fn bytes(known: &Known) -> &Shared<[u8]> {
        match known {
            Known::Coded(hint) => &hint.telegram,
            Known::Bytes(bytes) => bytes,
        }
    }

    /// 410B §2 TxD (NRZI): the twin, made by inverting, equals a fresh encoding from the
    /// other level, with and without the sync word, whichever level is asked for first.
    #[test]
    fn a_twin_is_the_encoding_from_the_other_level() {
        let mst = [255u8, 4];
        for presync in [false, true] {
            let mut c = CodedFrames::default();
            let (t, len) = c.lookup(&mst, presync);
            for level in [true, false, true, false] {
                // Found coded (after the first turn) and by its bytes: the same.
                let (known, _) = c.lookup(&mst, presync);
                let coded = c.coded(known, presync, len, level).expect("encodable");
                let by_bytes = c.coded(t.clone(), presync, len, level).expect("encodable");
                assert!(Shared::ptr_eq(&coded.bits, &by_bytes.bits));
                assert!(Shared::ptr_eq(&coded.hint, &by_bytes.hint));
                let (fresh, fresh_offset) = encode(&mst, presync, len, level).expect("encodable");
                assert_eq!(*coded.bits, *fresh, "presync {presync}, level {level}");
                assert_eq!(coded.hint.offset, fresh_offset);
                let twin = twin_of(&coded);
                let (other, _) = encode(&mst, presync, len, !level).expect("encodable");
                assert_eq!(*twin, *other, "presync {presync}, level {level}");
            }
        }
    }

    #[test]
    fn reused_bits_equal_fresh_ones_at_both_levels() {
        let mut c = CodedFrames::default();
        let mst = [255u8, 4];
        let (t, len) = c.lookup(&mst, false);
        for level in [false, true, false, true] {
            let coded = c.coded(t.clone(), false, len, level).expect("encodable");
            // Remembered coded from now on, with that hint.
            let (known, _) = c.lookup(&mst, false);
            assert!(matches!(&known, Known::Coded(h) if Shared::ptr_eq(h, &coded.hint)));
            let (fresh, fresh_offset) = encode(&mst, false, len, level).expect("encodable");
            assert_eq!(*coded.bits, *fresh);
            assert_eq!(coded.hint.offset, fresh_offset);
            assert_eq!(coded.bits.len(), len);
            // NRZI from the other level: every level the other way (the segment's twin).
            let twin = twin_of(&coded);
            assert_eq!(*twin, fresh.inverted());
        }
        // The same bytes share the first allocation; other bytes or a sync word do not.
        assert!(Shared::ptr_eq(bytes(&c.lookup(&mst, false).0), bytes(&t)));
        assert!(!Shared::ptr_eq(bytes(&c.lookup(&mst, true).0), bytes(&t)));
        assert_eq!(c.lookup(&mst, true).1, len + PRESYNC_BITS);
    }

    #[test]
    fn more_telegrams_than_entries_still_encode_right() {
        let mut c = CodedFrames::default();
        for n in 0..(3 * ENTRIES as u8) {
            let tel = [n, n.wrapping_mul(7), 0x7E];
            let (t, len) = c.lookup(&tel, false);
            let coded = c.coded(t, false, len, true).expect("encodable");
            assert_eq!(
                *coded.bits,
                *encode(&tel, false, len, true).expect("encodable").0
            );
        }
        assert_eq!(c.entries.len(), ENTRIES);
    }
}
