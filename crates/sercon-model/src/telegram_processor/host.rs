//! The chip's DMA entry points for hosts, harnesses and tests (410B §2 DMAACKRN/DMAACKTN).

use crate::chip::Chip;

impl Chip {
    /// A DMA read cycle with DMAACKRN = 0: the oldest word of the receive FIFO
    /// (410B §2 DMAACKRN: "the receive FIFO is read, independent of the levels on A6-1
    /// and the chip select signals"); 0 when the FIFO is empty.
    #[doc(alias = "DMAACKRN")]
    pub fn dma_read_receive(&mut self) -> u16 {
        self.touched();
        let before = self.tp.fifo.state();
        let w = self.tp.fifo.read();
        self.dma_accessed(before);
        self.settle();
        w
    }

    /// A DMA write cycle with DMAACKTN = 0: `value` goes into the transmit FIFO
    /// (410B §2 pin 41, ERRATA "DMAACKTN"); ignored while DMAREQT is inactive.
    #[doc(alias = "DMAACKTN")]
    pub fn dma_write_transmit(&mut self, value: u16) {
        self.touched();
        if !self.in_reset {
            let before = self.tp.fifo.state();
            self.tp.fifo.write(value);
            self.dma_accessed(before);
        }
    }

    /// After a FIFO access at [`Chip::now`]: with DMAMODE = 1 a request still active pulses
    /// again at the MCLK edge after the access (one pulse per word; spec-notes "Pulsed DMA
    /// requests").
    pub(crate) fn dma_accessed(&mut self, before: super::FifoState) {
        let tick = self.clock.tick_at_or_before(self.now).saturating_add(1);
        self.dma_changed(before, tick);
    }
}
