//! A master and a slave service container joined by a stand-in for the telegram processor
//! and the line: each cycle the master's MDT record goes to the slave's `on_receive` and the
//! slave's AT record back to the master's (410B §4.2.4; ERRATA "service info in a
//! container"). The MDT is handed over before the AT so that a step can complete in one
//! cycle; on a real ring the AT of cycle k answers the MDT of cycle k − 1.
#![allow(dead_code)]

use sercon_model::service_container::{
    ScInterrupts, ScMode, ScOutcome, Variant, on_cycle, on_receive, on_transmit,
};
use sercon_regs::ram::service::{NInfo, ScMaster, ScSlave};

/// NSV of the master's container and where SCPT points.
pub const MASTER_NSV: u8 = 2;
/// Start of the master's service container.
pub const MASTER_SC: u16 = 0x100;
/// NSV of the slave's container.
pub const SLAVE_NSV: u8 = 5;
/// Start of the slave's service container.
pub const SLAVE_SC: u16 = 0x300;
/// Buffer offset (regs reading: the buffer follows the five control words).
pub const BUF: u8 = 5;
/// Host bits of the control word / status word that must survive (drive on, enable…).
pub const MDT_HOST_BITS: u16 = 0xE000;
/// Host bits of the AT status word (ready to operate).
pub const AT_HOST_BITS: u16 = 0xC000;

/// What happened in one cycle.
#[derive(Debug, Clone)]
pub struct CycleLog {
    pub mdt: Vec<u16>,
    pub at: Vec<u16>,
    pub master_tx: ScOutcome,
    pub slave_rx: ScOutcome,
    pub slave_tx: ScOutcome,
    pub master_rx: ScOutcome,
    pub master_cycle: ScOutcome,
}

impl CycleLog {
    /// Interrupt bits raised on the master side this cycle.
    pub fn master_raised(&self) -> ScInterrupts {
        self.master_tx.raised | self.master_rx.raised | self.master_cycle.raised
    }

    /// Interrupt bits raised on the slave side this cycle.
    pub fn slave_raised(&self) -> ScInterrupts {
        self.slave_rx.raised | self.slave_tx.raised
    }
}

/// Two RAMs and the line between them.
pub struct Link {
    pub variant: Variant,
    pub master: Vec<u16>,
    pub slave: Vec<u16>,
    /// Info words per record after the first word (SERCOS II has one; up to 4 here).
    pub info_len: usize,
    pub hs_timeout: u8,
    pub busy_timeout: u8,
    /// The next MDT arrives with a bad FCS.
    pub corrupt_mdt: bool,
    /// The next AT arrives with a bad FCS.
    pub corrupt_at: bool,
    /// The slave sends no AT at all (drive gone).
    pub slave_silent: bool,
}

impl Link {
    /// Zeroed RAMs with SCPTn set and both containers idle (HS equal, one info word).
    pub fn new(variant: Variant) -> Link {
        let words = usize::from(variant.ram_words());
        let mut master = vec![0u16; words];
        let mut slave = vec![0u16; words];
        master[2 + usize::from(MASTER_NSV)] = MASTER_SC;
        slave[2 + usize::from(SLAVE_NSV)] = SLAVE_SC;
        let mut link = Link {
            variant,
            master,
            slave,
            info_len: 4,
            hs_timeout: 0,
            busy_timeout: 0,
            corrupt_mdt: false,
            corrupt_at: false,
            slave_silent: false,
        };
        // Idle master: M_BUSY = 1 until a transfer is set up.
        let mut m = link.master_sc();
        m.m_busy = true;
        link.set_master_sc(m);
        link
    }

    pub fn master_sc(&self) -> ScMaster {
        ScMaster::from_words(words5(&self.master, MASTER_SC))
    }

    pub fn set_master_sc(&mut self, m: ScMaster) {
        put5(&mut self.master, MASTER_SC, m.to_words());
    }

    pub fn slave_sc(&self) -> ScSlave {
        ScSlave::from_words(words5(&self.slave, SLAVE_SC))
    }

    pub fn set_slave_sc(&mut self, s: ScSlave) {
        put5(&mut self.slave, SLAVE_SC, s.to_words());
    }

    /// Word at `offset` of the master's container.
    pub fn master_word(&self, offset: u8) -> u16 {
        self.master[usize::from(MASTER_SC) + usize::from(offset)]
    }

    /// Word at `offset` of the slave's container.
    pub fn slave_word(&self, offset: u8) -> u16 {
        self.slave[usize::from(SLAVE_SC) + usize::from(offset)]
    }

    /// The master's buffer words `from..=to`.
    pub fn master_buffer(&self, from: u8, len: usize) -> Vec<u16> {
        let start = usize::from(MASTER_SC) + usize::from(from);
        self.master[start..start + len].to_vec()
    }

    /// The slave's buffer words.
    pub fn slave_buffer(&self, from: u8, len: usize) -> Vec<u16> {
        let start = usize::from(SLAVE_SC) + usize::from(from);
        self.slave[start..start + len].to_vec()
    }

    pub fn fill_master_buffer(&mut self, from: u8, data: &[u16]) {
        let start = usize::from(MASTER_SC) + usize::from(from);
        self.master[start..start + data.len()].copy_from_slice(data);
    }

    pub fn fill_slave_buffer(&mut self, from: u8, data: &[u16]) {
        let start = usize::from(SLAVE_SC) + usize::from(from);
        self.slave[start..start + data.len()].copy_from_slice(data);
    }

    /// The master's host sets up a write of `data` to `element` (410B §4.2.4 master table:
    /// ELEM_MDT, L/S_MDT = 1, SETEND, NINFO_WRITE, WRDATPT/WRDATLAST, M_BUSY = 0).
    pub fn master_write(&mut self, element: u8, data: &[u16], ninfo: u8) {
        self.fill_master_buffer(BUF, data);
        let mut m = self.master_sc();
        m.elem_mdt = element;
        m.ls_mdt = true;
        m.setend = true;
        m.ninfo_write = NInfo::from_count(ninfo).expect("1-4");
        m.pointers.wrdatpt = BUF;
        m.pointers.wrdatlast = BUF + u8::try_from(data.len()).expect("fits") - 1;
        clear_master_ints(&mut m);
        m.m_busy = false;
        self.set_master_sc(m);
    }

    /// The master's host sets up a read of `len` words of `element` into the read buffer at
    /// `at` (L/S_MDT = 0, RDDATPT/RDDATLAST, NINFO_READ).
    pub fn master_read(&mut self, element: u8, at: u8, len: u8, ninfo: u8, setend: bool) {
        let mut m = self.master_sc();
        m.elem_mdt = element;
        m.ls_mdt = false;
        m.setend = setend;
        m.ninfo_read = NInfo::from_count(ninfo).expect("1-4");
        m.pointers.rddatpt = at;
        m.pointers.rddatlast = at + len - 1;
        clear_master_ints(&mut m);
        m.m_busy = false;
        self.set_master_sc(m);
    }

    /// One communication cycle through the three entry points.
    pub fn cycle(&mut self) -> CycleLog {
        let v = self.variant;
        let mut mdt = vec![0u16; 1 + self.info_len];
        mdt[0] = MDT_HOST_BITS;
        let master_tx = on_transmit(&mut self.master, v, MASTER_NSV, ScMode::Master, &mut mdt);
        let mdt_ok = !std::mem::take(&mut self.corrupt_mdt);
        let slave_rx = on_receive(&mut self.slave, v, SLAVE_NSV, ScMode::Slave, &mdt, mdt_ok);
        let mut at = vec![0u16; 1 + self.info_len];
        at[0] = AT_HOST_BITS;
        let slave_tx = on_transmit(&mut self.slave, v, SLAVE_NSV, ScMode::Slave, &mut at);
        let at_ok = !std::mem::take(&mut self.corrupt_at);
        let master_rx = if self.slave_silent {
            ScOutcome::default()
        } else {
            on_receive(&mut self.master, v, MASTER_NSV, ScMode::Master, &at, at_ok)
        };
        let master_cycle = on_cycle(
            &mut self.master,
            v,
            MASTER_NSV,
            ScMode::Master,
            self.hs_timeout,
            self.busy_timeout,
        );
        let slave_cycle = on_cycle(&mut self.slave, v, SLAVE_NSV, ScMode::Slave, 9, 9);
        assert_eq!(
            slave_cycle,
            ScOutcome::default(),
            "slave containers do not count"
        );
        CycleLog {
            mdt,
            at,
            master_tx,
            slave_rx,
            slave_tx,
            master_rx,
            master_cycle,
        }
    }
}

pub fn clear_master_ints(m: &mut ScMaster) {
    m.int_err = false;
    m.int_end_wrbuf = false;
    m.int_end_rdbuf = false;
    m.int_sc_err = false;
    m.int_hs_timeout = false;
    m.int_busy_timeout = false;
    m.int_cmd = false;
}

fn words5(ram: &[u16], at: u16) -> [u16; 5] {
    let a = usize::from(at);
    [ram[a], ram[a + 1], ram[a + 2], ram[a + 3], ram[a + 4]]
}

fn put5(ram: &mut [u16], at: u16, words: [u16; 5]) {
    let a = usize::from(at);
    ram[a..a + 5].copy_from_slice(&words);
}

/// A tiny drive: the slave's microprocessor reacting to its container's interrupts
/// (410B §4.2.4 slave table), holding parameter elements by element number.
#[derive(Debug, Default)]
pub struct Drive {
    /// Element 1 last written (the IDN).
    pub idn: u16,
    /// Element data by element number (0-7).
    pub elements: [Vec<u16>; 8],
    /// Error code to report on the next write end (ERR_AT).
    pub refuse_with: Option<u16>,
    /// Don't react to INT_ELEM_CHANGE (to let the busy timeout run).
    pub asleep: bool,
    /// Interrupts seen, in order.
    pub seen: Vec<ScInterrupts>,
}

impl Drive {
    /// Handles the container's interrupt bits, then clears them (as the host does).
    pub fn react(&mut self, link: &mut Link) {
        let mut s = link.slave_sc();
        if self.asleep {
            return;
        }
        if s.int_elem_change {
            self.seen.push(ScInterrupts::INT_ELEM_CHANGE);
            s.int_elem_change = false;
            s.err_at = false;
            if s.ls {
                // A write begins: the read buffer takes it from its start.
                s.pointers.rddatpt = BUF;
                s.pointers.rddatlast = 255;
            } else {
                // A read begins: offer the element's data in the write buffer.
                let data = self.elements[usize::from(s.elem)].clone();
                link.fill_slave_buffer(BUF, &data);
                s.pointers.wrdatpt = BUF;
                s.pointers.wrdatlast = BUF + u8::try_from(data.len()).expect("fits") - 1;
            }
            s.busy_at = false;
        }
        if s.int_end_mdt {
            self.seen.push(ScInterrupts::INT_END_MDT);
            s.int_end_mdt = false;
            if s.ls {
                let len = usize::from(s.pointers.rddatpt - BUF);
                let data = link.slave_buffer(BUF, len);
                if let Some(code) = self.refuse_with {
                    s.err_at = true;
                    link.fill_slave_buffer(BUF, &[code]);
                    s.pointers.wrdatpt = BUF;
                    s.pointers.wrdatlast = BUF;
                } else if s.elem == 1 {
                    self.idn = data.first().copied().unwrap_or(0);
                } else {
                    self.elements[usize::from(s.elem)] = data;
                }
                s.pointers.rddatpt = BUF;
                s.busy_at = false;
            }
        }
        if s.int_end_rdbuf {
            self.seen.push(ScInterrupts::INT_END_RDBUF);
            s.int_end_rdbuf = false;
        }
        link.set_slave_sc(s);
    }
}

/// Runs cycles (the drive reacting after each) until `done` or `limit` cycles; returns the
/// logs.
pub fn run(
    link: &mut Link,
    drive: &mut Drive,
    limit: usize,
    mut done: impl FnMut(&CycleLog, &Link) -> bool,
) -> Vec<CycleLog> {
    let mut logs = Vec::new();
    for _ in 0..limit {
        let log = link.cycle();
        drive.react(link);
        let stop = done(&log, link);
        logs.push(log);
        if stop {
            return logs;
        }
    }
    panic!("no end after {limit} cycles: {:?}", link.master_sc());
}

/// Bytes as SERCOS words, low byte first, padded with 0.
pub fn bytes_to_words(bytes: &[u8]) -> Vec<u16> {
    bytes
        .chunks(2)
        .map(|c| u16::from(c[0]) | u16::from(*c.get(1).unwrap_or(&0)) << 8)
        .collect()
}

/// A variable-length string (sercos-facts.md: current length, maximum length, then the
/// bytes).
pub fn variable_length(text: &[u8], max: u16) -> Vec<u16> {
    let mut words = vec![u16::try_from(text.len()).expect("short"), max];
    words.extend(bytes_to_words(text));
    words
}
