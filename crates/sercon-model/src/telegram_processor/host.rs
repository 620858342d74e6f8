//! The chip's line-side and DMA entry points for simulators, harnesses and tests.

use super::{LineTelegram, RxTelegram};
use crate::chip::Chip;

impl Chip {
    /// Moves the telegrams this chip has sent so far (in order) to the end of `out`: what
    /// its transmitter put on the line, with exact start and end instants.
    pub fn drain_line_telegrams(&mut self, out: &mut Vec<LineTelegram>) {
        out.append(&mut self.tp.sent);
    }

    /// Hands the chip a telegram its receiver sees on the line. Deliver it ahead of
    /// time (before [`Chip::advance_to`] passes its start); it is processed at its start
    /// and end. A frame whose start has already passed is processed at once.
    pub fn receive_telegram(&mut self, telegram: RxTelegram) {
        self.tp.on_rx_frame(telegram);
        self.settle();
    }

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
