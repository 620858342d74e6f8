//! The DMA FIFOs RFIFO and TFIFO at 27H and their requests DMAREQR / DMAREQT
//! (410B §2 DMAREQR, DMAREQT, DMAACKRN, DMAACKTN; §4.1 1H.14 DMAMODE, 3H.12-13, 27H).

use std::collections::VecDeque;

/// Both DMA FIFOs.
#[derive(Debug, Clone, Default)]
pub(crate) struct DmaFifos {
    /// Received words of DMA containers (DMA = 1), read by the host at 27H.
    pub(crate) rx: VecDeque<u16>,
    /// The block (its MST-end tick) whose receive telegrams put the words in `rx`: RFIFO
    /// holds one block's DMA receive data (spec-notes "Master DMA layout").
    pub(crate) rx_block: Option<u64>,
    /// Words written by the host at 27H for the next DMA transmit telegram.
    pub(crate) tx: VecDeque<u16>,
    /// Words the current DMA transmit telegram needs (0 when none is pending); after a DMA
    /// transmit telegram took its words, the same count for the header's next telegram.
    pub(crate) tx_want: usize,
    /// DMAMODE = 1: the MCLK tick of the last DMAREQR pulse.
    pub(crate) pulse_r: Option<u64>,
    /// DMAMODE = 1: the MCLK tick of the last DMAREQT pulse.
    pub(crate) pulse_t: Option<u64>,
    /// Whether either FIFO ever held a word or was asked for one (sticky): until then the
    /// state is (0, 0, 0) and [`DmaFifos::unchanged_since`] reads nothing else. Set where a
    /// word is stored (`store_rx`) or wanted (`want_tx`); a host write needs a word wanted.
    pub(crate) used: bool,
}

/// The FIFO state the requests depend on: (RFIFO words, TFIFO words, words wanted).
pub(crate) type FifoState = (usize, usize, usize);

impl DmaFifos {
    /// 410B §2 DMAREQR: "becomes active if data from the receive FIFO can be read. At the
    /// beginning of the read operation of the last word of the receive FIFO, DMAREQR
    /// becomes inactive."
    pub(crate) fn dmareqr(&self) -> bool {
        !self.rx.is_empty()
    }

    /// 410B §2 DMAREQT: "becomes active when data can be written to the transmit FIFO.
    /// DMAREQT becomes inactive again at the beginning of the last write access".
    pub(crate) fn dmareqt(&self) -> bool {
        self.tx.len() < self.tx_want
    }

    /// The state the requests depend on, to see what an event changed.
    pub(crate) fn state(&self) -> FifoState {
        (self.rx.len(), self.tx.len(), self.tx_want)
    }

    /// The state to hand [`DmaFifos::unchanged_since`] after some steps: `None` while the
    /// FIFOs were never used (the state (0, 0, 0)), without reading them.
    #[inline]
    pub(crate) fn snapshot(&self) -> Option<FifoState> {
        self.used.then(|| self.state())
    }

    /// Whether the state is still `before` (a [`DmaFifos::snapshot`]): always while the
    /// FIFOs were never used.
    #[inline]
    pub(crate) fn unchanged_since(&self, before: Option<FifoState>) -> bool {
        debug_assert!(
            self.used || self.state() == (0, 0, 0),
            "FIFO used unnoticed"
        );
        !self.used || self.state() == before.unwrap_or_default()
    }

    /// The words the pending DMA transmit telegram needs (410B §2 DMAREQT), 0 for none.
    #[inline]
    pub(crate) fn want_tx(&mut self, want: usize) {
        self.used |= want != 0;
        self.tx_want = want;
    }

    /// DMAMODE = 1 (410B §4.1 1H.14: "DMAREQR/DMAREQT are pulses"): after a change of the
    /// FIFOs from `before`, a request that is active gets a pulse at MCLK tick `tick`: one
    /// pulse per word the DMA controller may move (spec-notes "Pulsed DMA requests").
    pub(crate) fn pulse_after(&mut self, before: FifoState, tick: u64) {
        if self.state() == before {
            return;
        }
        if self.dmareqr() {
            self.pulse_r = Some(tick);
        }
        if self.dmareqt() {
            self.pulse_t = Some(tick);
        }
    }

    /// A DMA receive telegram of block `block` stores its words: words of an earlier block
    /// still unread are an overrun (dropped; returns `true`). Words of the same block's
    /// earlier telegrams stay, in order (spec-notes "Master DMA layout").
    pub(crate) fn store_rx(&mut self, block: Option<u64>, words: &[u16]) -> bool {
        let overrun = !self.rx.is_empty() && self.rx_block != block;
        if overrun {
            self.rx.clear();
        }
        self.rx_block = block;
        self.used = true;
        self.rx.extend(words.iter().copied());
        overrun
    }

    /// A read of RFIFO (27H, or DMAACKRN = 0): the oldest word, 0 when empty.
    pub(crate) fn read(&mut self) -> u16 {
        self.rx.pop_front().unwrap_or(0)
    }

    /// The word a read of RFIFO would take now (0 when empty, as [`DmaFifos::read`]).
    pub(crate) fn oldest(&self) -> u16 {
        self.rx.front().copied().unwrap_or(0)
    }

    /// A write of TFIFO (27H, or DMAACKTN = 0). Words beyond what the pending telegram
    /// needs are dropped (the FIFO only takes data while DMAREQT asks for it), so a
    /// runaway writer cannot grow the model without bound.
    pub(crate) fn write(&mut self, value: u16) -> bool {
        if self.dmareqt() {
            self.tx.push_back(value);
            true
        } else {
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // 410B §4.1 27H RFIFO; spec-notes "Master DMA layout": one block's DMA receive data
    // stay in order; words of an earlier block still unread are an overrun.
    #[test]
    fn rfifo_holds_one_blocks_receive_data() {
        let mut f = DmaFifos::default();
        assert!(!f.store_rx(Some(10), &[1, 2]));
        assert!(!f.store_rx(Some(10), &[3]));
        assert_eq!(f.rx.iter().copied().collect::<Vec<_>>(), vec![1, 2, 3]);
        assert!(f.store_rx(Some(20), &[4]));
        assert_eq!(f.rx.iter().copied().collect::<Vec<_>>(), vec![4]);
        assert_eq!(f.read(), 4);
        assert!(!f.store_rx(Some(30), &[5]));
    }

    // The snapshot `Chip::advance_to` compares after the processor's steps: a FIFO never
    // used reads as (0, 0, 0) without being read; a stored word (410B §4.1 27H RFIFO) or a
    // wanted one (410B §2 DMAREQT) is a change from that, and the state is compared from
    // then on.
    #[test]
    fn a_snapshot_sees_the_first_word_stored_or_wanted() {
        let mut f = DmaFifos::default();
        let never = f.snapshot();
        assert_eq!(never, None);
        f.want_tx(0);
        assert!(f.unchanged_since(never));
        f.want_tx(2);
        assert!(!f.unchanged_since(never));
        let wanting = f.snapshot();
        assert!(f.write(7));
        assert!(!f.unchanged_since(wanting));
        let mut f = DmaFifos::default();
        assert!(!f.store_rx(Some(10), &[1]));
        assert!(!f.unchanged_since(never));
        let stored = f.snapshot();
        assert!(f.unchanged_since(stored));
        assert_eq!(f.read(), 1);
        assert!(!f.unchanged_since(stored));
    }
}
