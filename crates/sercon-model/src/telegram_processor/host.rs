//! The chip's DMA entry points for hosts, harnesses and tests (410B §2 DMAACKRN/DMAACKTN).

use crate::chip::Chip;

impl Chip {
    /// A DMA read cycle with DMAACKRN = 0: the oldest word of the receive FIFO
    /// (410B §2 DMAACKRN: "the receive FIFO is read, independent of the levels on A6-1
    /// and the chip select signals"); 0 when the FIFO is empty.
    #[doc(alias = "DMAACKRN")]
    pub fn dma_read_receive(&mut self) -> u16 {
        let w = self.tp.fifo.read();
        self.settle();
        w
    }

    /// A DMA write cycle with DMAACKTN = 0: `value` goes into the transmit FIFO
    /// (410B §2 pin 41, ERRATA "DMAACKTN"); ignored while DMAREQT is inactive.
    #[doc(alias = "DMAACKTN")]
    pub fn dma_write_transmit(&mut self, value: u16) {
        if !self.in_reset {
            self.tp.fifo.write(value);
        }
    }
}
