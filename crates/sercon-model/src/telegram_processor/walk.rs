//! Reading the header chain and the data containers out of the RAM, bounded: whatever the
//! RAM holds, every walk ends (410B §4.2.1–§4.2.3, ERRATA "Dual-port RAM").

use sercon_regs::Variant;
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{Buffering, EndMarker, Header, HeaderKind, RxHeader, TxHeader};

use super::status::ProgErr;

/// The RAM word at `addr`, `None` outside the RAM.
pub(crate) fn word(ram: &[u16], addr: u32) -> Option<u16> {
    usize::try_from(addr).ok().and_then(|a| ram.get(a)).copied()
}

/// The `len` RAM words from `addr`, `None` unless all of them are inside the RAM.
pub(crate) fn words(ram: &[u16], addr: u32, len: usize) -> Option<&[u16]> {
    let from = usize::try_from(addr).ok()?;
    ram.get(from..from.checked_add(len)?)
}

/// The `len` RAM words from `addr` for writing, `None` unless all are inside the RAM.
pub(crate) fn words_mut(ram: &mut [u16], addr: u32, len: usize) -> Option<&mut [u16]> {
    let from = usize::try_from(addr).ok()?;
    ram.get_mut(from..from.checked_add(len)?)
}

/// Writes `value` at `addr`; outside the RAM nothing happens.
pub(crate) fn set_word(ram: &mut [u16], addr: u32, value: u16) {
    if let Some(w) = usize::try_from(addr).ok().and_then(|a| ram.get_mut(a)) {
        *w = value;
    }
}

/// Decodes the structure a header pointer points at.
// ERRATA "telegram header marker bits": 00 receive, 01 transmit, 11 end marker; 10 is no
// structure at all, which the model reports as a list without end marker.
#[inline]
pub(crate) fn header_at(ram: &[u16], variant: Variant, addr: u16) -> Result<Header, ProgErr> {
    let start = usize::from(addr);
    let words = ram.get(start..).ok_or(ProgErr::OutsideRam)?;
    let w0 = words.first().copied().ok_or(ProgErr::OutsideRam)?;
    let kind = HeaderKind::classify(w0).map_err(|_| ProgErr::NoEndMarker)?;
    // The structure's words as a fixed array, decoded by its kind's own decoder:
    // `Header::decode` would classify word 0 again and check the length through a
    // `Result` of its own (410B §4.2.1 receive / transmit header, §4.2.3 end marker).
    let header = match kind {
        HeaderKind::Receive => RxHeader::from_words(variant, fixed(words)?).map(Header::Receive),
        HeaderKind::Transmit => TxHeader::from_words(variant, fixed(words)?).map(Header::Transmit),
        HeaderKind::EndMarker => EndMarker::from_words(fixed(words)?).map(Header::End),
    }
    .map_err(|_| ProgErr::OutsideRam);
    debug_assert_eq!(
        header,
        if words.len() < kind.words() {
            Err(ProgErr::OutsideRam)
        } else {
            Header::decode(variant, words).map_err(|_| ProgErr::OutsideRam)
        },
        "header_at: the kind's decoder differs from Header::decode"
    );
    header
}

/// A header's words, classified by their marker bits but not decoded: what [`header_at`]
/// reads, for the caller to decode where it stores the header (`load`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum HeaderWords {
    /// A receive header's 5 words (410B §4.2.1).
    Receive([u16; 5]),
    /// A transmit header's 4 words (410B §4.2.1).
    Transmit([u16; 4]),
    /// An end marker (410B §4.2.3); its words are read when it is processed.
    End,
}

/// The words of the structure a header pointer points at, with [`header_at`]'s errors:
/// the same classification and bounds, without building a [`Header`] (debug builds decode
/// the words and compare with `header_at`).
// ERRATA "telegram header marker bits": 00 receive, 01 transmit, 11 end marker; 10 is no
// structure at all, which the model reports as a list without end marker.
#[inline]
pub(crate) fn header_words(
    ram: &[u16],
    variant: Variant,
    addr: u16,
) -> Result<HeaderWords, ProgErr> {
    let found = (|| {
        let words = ram.get(usize::from(addr)..).ok_or(ProgErr::OutsideRam)?;
        let w0 = words.first().copied().ok_or(ProgErr::OutsideRam)?;
        let kind = HeaderKind::classify(w0).map_err(|_| ProgErr::NoEndMarker)?;
        // 410B §4.2.1 receive header 5 words, transmit header 4; §4.2.3 end marker 2.
        match kind {
            HeaderKind::Receive => fixed(words).map(HeaderWords::Receive),
            HeaderKind::Transmit => fixed(words).map(HeaderWords::Transmit),
            HeaderKind::EndMarker => fixed::<2>(words).map(|_| HeaderWords::End),
        }
    })();
    #[cfg(debug_assertions)]
    {
        // The general path: `header_at` (itself compared with `Header::decode`).
        let same = match (found, header_at(ram, variant, addr)) {
            (Ok(HeaderWords::Receive(w)), Ok(Header::Receive(h))) => {
                RxHeader::from_words(variant, w) == Ok(h)
            }
            (Ok(HeaderWords::Transmit(w)), Ok(Header::Transmit(h))) => {
                TxHeader::from_words(variant, w) == Ok(h)
            }
            (Ok(HeaderWords::End), Ok(Header::End(_))) => true,
            (Err(a), Err(b)) => a == b,
            _ => false,
        };
        debug_assert!(same, "header_words: differs from header_at at {addr}");
    }
    #[cfg(not(debug_assertions))]
    let _ = variant;
    found
}

/// The first `N` words of `words`; a structure that does not fit reaches past the RAM's
/// end.
fn fixed<const N: usize>(words: &[u16]) -> Result<[u16; N], ProgErr> {
    words
        .get(..N)
        .and_then(|w| <[u16; N]>::try_from(w).ok())
        .ok_or(ProgErr::OutsideRam)
}

/// One data container as the walk found it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Container {
    /// Word address of control word 0.
    pub(crate) at: u32,
    /// Control word 0 (LEN, SVFL, NSV, SCMASTER, LASTDC).
    pub(crate) control: ContainerControl,
    /// POS (receive containers only; 0 for transmit containers).
    pub(crate) pos: u16,
    /// Word address of the first data word (buffer 0).
    pub(crate) data: u32,
}

impl Container {
    /// Word address of the buffer holding data for `val` (double buffer: VAL = 0 buffer 0,
    /// VAL = 1 buffer 1; single buffer: the one buffer).
    // 410B §4.2.2 / ERRATA "container words": buffer 0 then buffer 1.
    pub(crate) fn buffer(&self, buffering: Buffering, val: bool) -> u32 {
        match buffering {
            Buffering::Double if val => self.data + u32::from(self.control.len),
            _ => self.data,
        }
    }
}

/// Iterator over the data containers following a header, ending after LASTDC = 1.
///
/// Bounded by the RAM: a container must start inside the RAM and its words must fit, and
/// there are at most as many containers as RAM words. A violation ends the walk with the
/// error in [`Containers::error`].
pub(crate) struct Containers<'r> {
    ram: &'r [u16],
    next: u32,
    control_words: u32,
    buffering: Buffering,
    left: usize,
    done: bool,
    /// What ended the walk early, if anything.
    pub(crate) error: Option<ProgErr>,
}

impl<'r> Containers<'r> {
    /// The containers of a header at `header_at` with `header_words` words.
    // ERRATA "data containers": a header is followed directly by its containers; receive
    // containers have two control words (LEN/flags, POS), transmit containers one.
    pub(crate) fn new(
        ram: &'r [u16],
        header_at: u16,
        kind: HeaderKind,
        buffering: Buffering,
    ) -> Self {
        let (header_words, control_words) = match kind {
            HeaderKind::Receive => (5, 2),
            _ => (4, 1),
        };
        Containers {
            ram,
            next: u32::from(header_at) + header_words,
            control_words,
            buffering,
            left: ram.len(),
            done: matches!(kind, HeaderKind::EndMarker),
            error: None,
        }
    }
}

impl Containers<'_> {
    /// The control words of the container the walk stopped at (the one that ended it when
    /// [`Containers::error`] is set): (first word, count).
    pub(crate) fn failed_words(&self) -> (u32, u32) {
        (self.next, self.control_words)
    }
}

impl Iterator for Containers<'_> {
    type Item = Container;

    fn next(&mut self) -> Option<Container> {
        if self.done {
            return None;
        }
        if self.left == 0 {
            self.done = true;
            self.error = Some(ProgErr::ContainerOverrun);
            return None;
        }
        self.left -= 1;
        let at = self.next;
        let (Some(w0), Some(pos)) = (
            word(self.ram, at),
            if self.control_words == 2 {
                word(self.ram, at + 1)
            } else {
                Some(0)
            },
        ) else {
            self.done = true;
            self.error = Some(ProgErr::OutsideRam);
            return None;
        };
        let control = ContainerControl::from_word(w0);
        let data = at + self.control_words;
        let end = data + control.data_words(self.buffering);
        if end as usize > self.ram.len() {
            self.done = true;
            self.error = Some(ProgErr::OutsideRam);
            return None;
        }
        self.next = end;
        // 410B §4.2.2 LASTDC: "Last data container of the telegram".
        self.done = control.lastdc;
        Some(Container {
            at,
            control,
            pos,
            data,
        })
    }
}
