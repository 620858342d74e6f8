//! pcap and pcapng captures of the telegrams seen on the ring, for Wireshark.
//!
//! Link type USER0 (147); each packet is the pseudo-header of
//! [`link_header`](super::link_header) followed by the telegram bytes. Timestamps are in
//! nanoseconds (pcap: the nanosecond magic A1B23C4DH; pcapng: `if_tsresol` 9), counted from
//! the start of the simulation, so a capture opens at 1970-01-01; the exact picosecond time is
//! in the pseudo-header. Modelled on smoltcp's `phy/pcap_writer.rs` (DESIGN.md).

use std::borrow::Cow;
use std::io::Write;
use std::time::Duration;

use pcap_file::DataLink;
use pcap_file::pcap::{PcapHeader, PcapPacket, PcapWriter};
use pcap_file::pcapng::PcapNgWriter;
use pcap_file::pcapng::blocks::enhanced_packet::EnhancedPacketBlock;
use pcap_file::pcapng::blocks::interface_description::{
    InterfaceDescriptionBlock, InterfaceDescriptionOption,
};

use super::link_header::{HEADER_LEN, LinkHeader};
use super::record::{SegmentId, TraceRecord};
use super::{TraceError, TraceSink};

/// Snapshot length: the longest frame the line decoder accepts (4096 bytes between the
/// flags, sercos-wire `line::MAX_FRAME_BYTES`) plus the pseudo-header fits well below it.
const SNAPLEN: u32 = 65_535;

/// The capture packet for a record: pseudo-header and bytes, into `buffer`.
fn fill_packet(record: &TraceRecord<'_>, buffer: &mut Vec<u8>) -> Result<u32, TraceError> {
    buffer.clear();
    buffer.extend_from_slice(&LinkHeader::of(record).to_bytes());
    buffer.extend_from_slice(record.bytes());
    u32::try_from(buffer.len()).map_err(|_| TraceError::TooLong { len: buffer.len() })
}

/// The capture timestamp: whole nanoseconds since the start of the simulation.
fn timestamp(record: &TraceRecord<'_>) -> Duration {
    Duration::from_nanos(record.time.since_start().as_nanos())
}

/// A classic pcap file of the records on one segment (or on all).
#[derive(Debug)]
pub struct PcapTrace<W: Write> {
    writer: PcapWriter<W>,
    segment: Option<SegmentId>,
    buffer: Vec<u8>,
    packets: u64,
}

impl<W: Write> PcapTrace<W> {
    /// Writes the pcap file header to `out`; records on `segment` (all segments with `None`)
    /// will follow.
    pub fn new(out: W, segment: Option<SegmentId>) -> Result<Self, TraceError> {
        let header = PcapHeader {
            datalink: DataLink::USER0,
            snaplen: SNAPLEN,
            ts_resolution: pcap_file::TsResolution::NanoSecond,
            endianness: pcap_file::Endianness::Little,
            ..PcapHeader::default()
        };
        Ok(PcapTrace {
            writer: PcapWriter::with_header(out, header)?,
            segment,
            buffer: Vec::with_capacity(HEADER_LEN + 64),
            packets: 0,
        })
    }

    /// Packets written so far.
    pub fn packets(&self) -> u64 {
        self.packets
    }

    /// Flushes and returns the output.
    pub fn finish(self) -> Result<W, TraceError> {
        let mut out = self.writer.into_writer();
        out.flush()?;
        Ok(out)
    }
}

impl<W: Write> TraceSink for PcapTrace<W> {
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError> {
        if self
            .segment
            .is_some_and(|segment| segment != record.segment)
        {
            return Ok(());
        }
        let len = fill_packet(record, &mut self.buffer)?;
        self.writer
            .write_packet(&PcapPacket::new(timestamp(record), len, &self.buffer))?;
        self.packets += 1;
        Ok(())
    }
}

/// A pcapng file with one interface per segment, described when the segment first shows up
/// (interface name `segment N`, `if_speed` the bit rate when known).
pub struct PcapNgTrace<W: Write> {
    writer: PcapNgWriter<W>,
    segment: Option<SegmentId>,
    interfaces: Vec<SegmentId>,
    buffer: Vec<u8>,
    packets: u64,
}

impl<W: Write> core::fmt::Debug for PcapNgTrace<W> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PcapNgTrace")
            .field("segment", &self.segment)
            .field("interfaces", &self.interfaces)
            .field("packets", &self.packets)
            .finish_non_exhaustive()
    }
}

impl<W: Write> PcapNgTrace<W> {
    /// Writes the section header to `out`; records on `segment` (all segments with `None`)
    /// will follow.
    pub fn new(out: W, segment: Option<SegmentId>) -> Result<Self, TraceError> {
        Ok(PcapNgTrace {
            writer: PcapNgWriter::with_endianness(out, pcap_file::Endianness::Little)?,
            segment,
            interfaces: Vec::new(),
            buffer: Vec::with_capacity(HEADER_LEN + 64),
            packets: 0,
        })
    }

    /// Packets written so far.
    pub fn packets(&self) -> u64 {
        self.packets
    }

    /// Flushes the output.
    pub fn flush(&mut self) -> Result<(), TraceError> {
        Ok(self.writer.get_mut().flush()?)
    }

    /// Flushes and returns the output.
    pub fn finish(self) -> Result<W, TraceError> {
        let mut out = self.writer.into_inner();
        out.flush()?;
        Ok(out)
    }

    /// The interface number of a segment, describing it first if it is new.
    fn interface(&mut self, record: &TraceRecord<'_>) -> Result<u32, TraceError> {
        let index = match self.interfaces.iter().position(|&s| s == record.segment) {
            Some(index) => index,
            None => {
                let mut options = vec![
                    InterfaceDescriptionOption::IfName(Cow::Owned(format!(
                        "segment {}",
                        record.segment
                    ))),
                    // Nanosecond timestamps: if_tsresol = 10^-9.
                    InterfaceDescriptionOption::IfTsResol(9),
                ];
                if let Some(rate) = record.bit_rate {
                    options.push(InterfaceDescriptionOption::IfSpeed(rate.bits_per_second()));
                }
                self.writer.write_pcapng_block(InterfaceDescriptionBlock {
                    linktype: DataLink::USER0,
                    snaplen: SNAPLEN,
                    options,
                })?;
                self.interfaces.push(record.segment);
                self.interfaces.len() - 1
            }
        };
        u32::try_from(index).map_err(|_| TraceError::TooLong { len: index })
    }
}

impl<W: Write> TraceSink for PcapNgTrace<W> {
    fn record(&mut self, record: &TraceRecord<'_>) -> Result<(), TraceError> {
        if self
            .segment
            .is_some_and(|segment| segment != record.segment)
        {
            return Ok(());
        }
        let interface_id = self.interface(record)?;
        let len = fill_packet(record, &mut self.buffer)?;
        self.writer.write_pcapng_block(EnhancedPacketBlock {
            interface_id,
            timestamp: timestamp(record),
            original_len: len,
            data: Cow::Borrowed(&self.buffer),
            options: Vec::new(),
        })?;
        self.packets += 1;
        Ok(())
    }
}
