//! The data container of a header, walked once under the layout proof and kept for a receive
//! telegram's store and a transmit telegram's assembly (ring-8: −1.1 % instructions a cycle).
//!
//! A container walk reads the containers' control words (410B §4.2.2: LEN, LASTDC and the
//! buffering's data words lead to the next container; POS) from the word after the header on
//! (ERRATA "data containers"). While the layout proof holds (`telegram_processor::layout`),
//! the processor's own writes land on no word the proof read other than a header's status
//! words, and a host write to a word it read drops the proof (`Chip::write_ram`). So a walk
//! whose control words all lie in the proof's read words is the walk the RAM gives for as
//! long as that same proof stands: kept with the proof's number (`Chip::layout_epoch`, a
//! new one for every proof found or dropped), used only while the number is the same.
//!
//! Only walks of one container are kept (the usual telegram: ERRATA "data containers",
//! LASTDC = 1 on the first).

use sercon_regs::ram::header::{Buffering, HeaderKind};

use super::status::ProgErr;
use super::walk::Container;
#[cfg(debug_assertions)]
use super::walk::Containers;
use crate::chip::Chip;

/// The kept walks of one chip.
#[derive(Debug, Clone, Default)]
pub(crate) struct WalkMemo {
    /// Per RAM word: the index in `walks` of the walk from a header there (0: none).
    index: Vec<u16>,
    /// The kept walks; the first is none ([`NONE`]).
    walks: Vec<Kept>,
}

/// One kept walk.
#[derive(Debug, Clone, Copy)]
struct Kept {
    /// The layout proof it was kept under (`Chip::layout_epoch`).
    epoch: u64,
    /// The header's kind and the buffering it was walked with ([`key`]).
    key: u8,
    /// Its one container.
    container: Container,
}

/// What a walk depends on besides the RAM: the header's kind (receive containers have two
/// control words, transmit one, 410B §4.2.2) and its buffering (410B §4.2.1 DMA, DBUF: the
/// data words between containers); never 0.
const fn key(kind: HeaderKind, buffering: Buffering) -> u8 {
    let k = match kind {
        HeaderKind::Receive => 0,
        HeaderKind::Transmit => 1,
        HeaderKind::EndMarker => 2,
    };
    let b = match buffering {
        Buffering::Single => 0,
        Buffering::Double => 1,
        Buffering::Dma => 2,
    };
    1 + 3 * k + b
}

/// No walk: the first of `WalkMemo::walks`, whose key no header's matches.
const NONE: Kept = Kept {
    epoch: 0,
    key: 0,
    container: Container {
        at: 0,
        control: sercon_regs::ram::container::ContainerControl::from_word(0),
        pos: 0,
        data: 0,
    },
};

/// The one container of the header at `at` (of `kind`, walked with `buffering`) as kept,
/// if it is.
#[inline]
pub(super) fn kept(
    chip: &Chip,
    at: u16,
    kind: HeaderKind,
    buffering: Buffering,
) -> Option<Container> {
    let memo = &chip.tp.walk_memo;
    let k = *memo
        .walks
        .get(usize::from(*memo.index.get(usize::from(at))?))?;
    if k.key != key(kind, buffering) || k.epoch != chip.layout_epoch.get() {
        return None;
    }
    #[cfg(debug_assertions)]
    {
        // The general path: a fresh walk.
        let mut walk = Containers::new(&chip.ram, at, kind, buffering);
        let fresh: Vec<Container> = walk.by_ref().collect();
        debug_assert_eq!(walk.error, None, "kept walk at {at}: the RAM's fails");
        debug_assert_eq!(fresh, [k.container], "kept walk at {at}: stale");
        debug_assert!(
            matches!(chip.layout.get(), Some((true, _))),
            "kept walk at {at} without the layout proof"
        );
    }
    Some(k.container)
}

/// Keeps the walk `list` from the header at `at` (`error`: what ended it early) if it has
/// one container, the layout proof holds and read its control words.
#[inline(never)]
pub(super) fn keep(
    chip: &mut Chip,
    at: u16,
    kind: HeaderKind,
    buffering: Buffering,
    list: &[Container],
    error: Option<ProgErr>,
) {
    let ([container], None) = (list, error) else {
        return;
    };
    if !matches!(chip.layout.get(), Some((true, _))) {
        return;
    }
    // 410B §4.2.2: receive containers have two control words (LEN/flags, POS), transmit
    // containers one; read by the proof when its lists reach the header (`layout::list`).
    if !chip
        .layout_read
        .borrow()
        .all(container.at, container.data - container.at)
    {
        return;
    }
    let epoch = chip.layout_epoch.get();
    let ram_words = chip.ram.len();
    let memo = &mut chip.tp.walk_memo;
    if memo.walks.is_empty() || memo.walks.len() > ram_words || memo.index.len() != ram_words {
        // The first walk, or as many as the RAM has words (walks kept under earlier proofs
        // and replaced): started afresh.
        memo.index.clear();
        memo.index.resize(ram_words, 0);
        memo.walks.clear();
        memo.walks.push(NONE);
    }
    let kept = Kept {
        epoch,
        key: key(kind, buffering),
        container: *container,
    };
    let (Some(i), Ok(n)) = (
        memo.index.get_mut(usize::from(at)),
        u16::try_from(memo.walks.len()),
    ) else {
        return;
    };
    match memo.walks.get_mut(usize::from(*i)) {
        // The header's walk replaced in its place.
        Some(w) if *i != 0 => *w = kept,
        _ => {
            *i = n;
            memo.walks.push(kept);
        }
    }
}
