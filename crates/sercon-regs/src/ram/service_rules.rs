//! The pure rules over a service container's control words that both the controller model
//! and a host running containers in its own memory follow (410B §4.2.4): the buffer windows
//! given by the pointers, the master's acknowledgement rule, the start of a step and the
//! per-cycle count of an unacknowledged step. They read and change the decoded words only;
//! moving buffer words is left to the caller, which knows where the buffer lives.

use super::service::{ScMaster, ScPointers};

/// The present and last positions of one buffer of a service container (410B §4.2.4 words
/// 2 and 3: WRDATPT/WRDATLAST or RDDATPT/RDDATLAST).
///
/// A step moves NINFO words from the present position. Positions are offsets from SCPTn
/// (the buffer starts at offset 5, spec-notes "Registers"). A step is the *final* step of a
/// buffer when it covers the last position; positions after the last one are sent as 0 and
/// never stored (spec-notes "Service containers").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ScBufferWindow {
    /// WRDATPT / RDDATPT: present position.
    pub present: u8,
    /// WRDATLAST / RDDATLAST: last position.
    pub last: u8,
}

impl ScBufferWindow {
    /// Whether a step of `count` words from the present position reaches the last position
    /// (also when the present position is already past it).
    pub const fn is_final(self, count: u8) -> bool {
        self.present as u16 + count as u16 > self.last as u16
    }

    /// Whether the present position is past the last one (nothing left).
    pub const fn is_exhausted(self) -> bool {
        self.present > self.last
    }

    /// The present position after a step of `count` words; the 8-bit pointer stops at 255
    /// instead of wrapping to the start (spec-notes "Service containers").
    pub const fn advanced(self, count: u8) -> u8 {
        self.present.saturating_add(count)
    }

    /// The positions a step of `count` words covers, in order: `Some(offset)` inside the
    /// buffer (≤ last), `None` past the last position or past offset 255.
    pub fn positions(self, count: u8) -> impl Iterator<Item = Option<u8>> {
        (0..count).map(move |i| {
            let position = u16::from(self.present) + u16::from(i);
            u8::try_from(position).ok().filter(|p| *p <= self.last)
        })
    }
}

impl ScPointers {
    /// The write buffer: WRDATPT → WRDATLAST (410B §4.2.4 word 2). In both modes it holds
    /// what the container sends (spec-notes "Service containers").
    #[doc(alias = "WRDATPT")]
    pub const fn write_window(&self) -> ScBufferWindow {
        ScBufferWindow {
            present: self.wrdatpt,
            last: self.wrdatlast,
        }
    }

    /// The read buffer: RDDATPT → RDDATLAST (410B §4.2.4 word 3). In both modes it holds
    /// what the container receives (spec-notes "Service containers").
    #[doc(alias = "RDDATPT")]
    pub const fn read_window(&self) -> ScBufferWindow {
        ScBufferWindow {
            present: self.rddatpt,
            last: self.rddatlast,
        }
    }
}

/// Which timeout of 0DH an unacknowledged step reached (410B §4.1 0DH, 410B §4.2.4
/// INT_HS_TIMEOUT / INT_BUSY_TIMEOUT).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ScStepTimeout {
    /// HS_TIMEOUT: AHS differed from MHS for that many cycles (INT_HS_TIMEOUT).
    #[doc(alias = "INT_HS_TIMEOUT")]
    Handshake,
    /// BUSY_TIMEOUT: BUSY was set for that many cycles (INT_BUSY_TIMEOUT).
    #[doc(alias = "INT_BUSY_TIMEOUT")]
    Busy,
}

/// The AT's service bits a master-mode container takes (410B §4.2.4 HS_AT, BUSY_AT, ERR_AT,
/// CMD_AT; sercos-telegrams.md AT status word bits 0, 1, 2, 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ScAtBits {
    /// Bit 0: AHS, the slave's handshake toggle bit.
    pub ahs: bool,
    /// Bit 1: busy, step in progress.
    pub busy: bool,
    /// Bit 2: error in the service channel.
    pub error: bool,
    /// Bit 5: change bit commands.
    pub command_change: bool,
}

/// The interrupt a step raised when the AT's service bits were taken (410B §4.2.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ScAtInterrupt {
    /// INT_SC_ERR: the slave withdrew an acknowledgement.
    #[doc(alias = "INT_SC_ERR")]
    ScErr,
    /// INT_ERR: the slave reports an error.
    #[doc(alias = "INT_ERR")]
    Err,
    /// INT_END_WRBUF: the end of the write buffer is reached.
    #[doc(alias = "INT_END_WRBUF")]
    EndWrbuf,
    /// INT_END_RDBUF: the end of the read buffer is reached.
    #[doc(alias = "INT_END_RDBUF")]
    EndRdbuf,
}

/// What taking an AT's service bits did ([`ScMaster::take_at`]), for the caller to raise its
/// interrupts and move the info words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ScAtTaken {
    /// INT_CMD was set (CMD_AT went from 0 to 1).
    pub int_cmd: bool,
    /// The present step was acknowledged by this AT.
    pub handshake: bool,
    /// The step's interrupt, if it raised one.
    pub raised: Option<ScAtInterrupt>,
    /// Where the AT's info words go: the read buffer window and the word count (the window
    /// as it was before the step moved RDDATPT on).
    pub info_to: Option<(ScBufferWindow, u8)>,
}

impl ScMaster {
    /// The handshake rule: the present step is acknowledged when HS_AT equals HS_MDT and
    /// BUSY_AT is 0 (sercos-telegrams.md AT status word bits 0-1; reading of 410B §4.2.4
    /// HS_MDT/HS_AT, spec-notes "Service containers").
    pub const fn is_acknowledged(&self) -> bool {
        self.hs_at == self.hs_mdt && !self.busy_at
    }

    /// Whether the step about to go out (or in progress) is the last of the buffer in use:
    /// the write buffer with NINFO_WRITE for a write (L/S_MDT = 1), the read buffer with
    /// NINFO_READ for a read (410B §4.2.4; spec-notes "END_MDT and SETEND").
    pub const fn step_is_final(&self) -> bool {
        if self.ls_mdt {
            self.pointers
                .write_window()
                .is_final(self.ninfo_write.count())
        } else {
            self.pointers
                .read_window()
                .is_final(self.ninfo_read.count())
        }
    }

    /// Starts the next step if the present one is acknowledged and the microprocessor is
    /// not awaited; returns whether it did. Otherwise the present step is repeated.
    pub const fn start_step(&mut self) -> bool {
        // 410B §4.2.4 M_BUSY: "Service container waits for interaction of microprocessor";
        // while it is set no new step starts and the present step is repeated.
        if !self.is_acknowledged() || self.m_busy {
            return false;
        }
        // 410B §4.2.4 HS_MDT: handshake bit in MDT, toggled for every new step
        // (sercos-telegrams.md MDT control word bit 0: "A toggle bit").
        self.hs_mdt = !self.hs_mdt;
        // 410B §4.2.4 SETEND: "END_MDT is to be set" — on the step that reaches the end of
        // the buffer in use (spec-notes "Service containers").
        self.end_mdt = self.setend && self.step_is_final();
        // ERR_CNT counts the cycles of the present step (spec-notes).
        self.err_cnt = 0;
        self.busy_cnt = false;
        true
    }

    /// Takes the AT's service bits into the container and, when they acknowledge the present
    /// step, finishes it (410B §4.2.4 master table): INT_CMD on CMD_AT 0 → 1; INT_SC_ERR when
    /// an acknowledgement is withdrawn; on an acknowledged step INT_ERR with the error code
    /// kept at RDDATPT (not advanced), or WRDATPT / RDDATPT moved on by NINFO and
    /// INT_END_WRBUF / INT_END_RDBUF on the final step. M_BUSY is set with every interrupt
    /// the microprocessor must act on (spec-notes "Service containers").
    pub fn take_at(&mut self, at: ScAtBits) -> ScAtTaken {
        let mut taken = ScAtTaken::default();
        let was_acknowledged = self.is_acknowledged();
        // 410B §4.2.4 INT_CMD: "Slave has set command modification bit" (a 0 → 1 change).
        if at.command_change && !self.cmd_at {
            self.int_cmd = true;
            taken.int_cmd = true;
        }
        // 410B §4.2.4 HS_AT, BUSY_AT, ERR_AT, CMD_AT: taken from the AT.
        self.hs_at = at.ahs;
        self.busy_at = at.busy;
        self.err_at = at.error;
        self.cmd_at = at.command_change;
        let now_acknowledged = self.is_acknowledged();
        if was_acknowledged && !now_acknowledged {
            // 410B §4.2.4 INT_SC_ERR: protocol error — the slave withdrew an acknowledgement
            // although MHS did not change (spec-notes).
            self.int_sc_err = true;
            self.m_busy = true;
            taken.raised = Some(ScAtInterrupt::ScErr);
            return taken;
        }
        if was_acknowledged || !now_acknowledged {
            return taken;
        }
        taken.handshake = true;
        if at.error {
            // 410B §4.2.4 INT_ERR: slave reports error; the error code (the info words) is
            // kept in the read buffer at RDDATPT without advancing it (spec-notes).
            self.int_err = true;
            self.m_busy = true;
            taken.raised = Some(ScAtInterrupt::Err);
            taken.info_to = Some((self.pointers.read_window(), self.ninfo_read.count()));
            return taken;
        }
        if self.ls_mdt {
            // Write: the words at WRDATPT have arrived; move on by NINFO_WRITE.
            let window = self.pointers.write_window();
            let count = self.ninfo_write.count();
            self.pointers.wrdatpt = window.advanced(count);
            if window.is_final(count) {
                // 410B §4.2.4 INT_END_WRBUF: end of write buffer is reached.
                self.int_end_wrbuf = true;
                self.m_busy = true;
                taken.raised = Some(ScAtInterrupt::EndWrbuf);
            }
        } else {
            // Read: NINFO_READ info words of the AT go to the read buffer at RDDATPT.
            let window = self.pointers.read_window();
            let count = self.ninfo_read.count();
            taken.info_to = Some((window, count));
            self.pointers.rddatpt = window.advanced(count);
            if window.is_final(count) {
                // 410B §4.2.4 INT_END_RDBUF: end of read buffer is reached.
                self.int_end_rdbuf = true;
                self.m_busy = true;
                taken.raised = Some(ScAtInterrupt::EndRdbuf);
            }
        }
        taken
    }

    /// Counts one communication cycle of an unacknowledged step in ERR_CNT / BUSY_CNT and
    /// checks it against the timeouts of 0DH (in cycles, 0 = none). On reaching one it sets
    /// INT_HS_TIMEOUT or INT_BUSY_TIMEOUT and M_BUSY and says which.
    pub const fn count_cycle(&mut self, hs_timeout: u8, busy_timeout: u8) -> Option<ScStepTimeout> {
        if self.is_acknowledged() {
            return None;
        }
        // 410B §4.2.4 BUSY_CNT: the error counter counts differences of handshake (0) or
        // BUSY cycles (1); a change of kind restarts it (spec-notes).
        let counting_busy = self.busy_at;
        if self.busy_cnt != counting_busy {
            self.busy_cnt = counting_busy;
            self.err_cnt = 0;
        }
        // ERR_CNT stops at 255 (spec-notes).
        let previous = self.err_cnt;
        self.err_cnt = self.err_cnt.saturating_add(1);
        // 410B §4.1 0DH HS_TIMEOUT / BUSY_TIMEOUT, in cycles; 0 = no timeout (spec-notes).
        let limit = if counting_busy {
            busy_timeout
        } else {
            hs_timeout
        };
        if limit == 0 || self.err_cnt != limit || previous == limit {
            return None;
        }
        // 410B §4.2.4 M_BUSY is set with every interrupt the microprocessor must act on
        // (spec-notes).
        self.m_busy = true;
        if counting_busy {
            // 410B §4.2.4 INT_BUSY_TIMEOUT.
            self.int_busy_timeout = true;
            Some(ScStepTimeout::Busy)
        } else {
            // 410B §4.2.4 INT_HS_TIMEOUT.
            self.int_hs_timeout = true;
            Some(ScStepTimeout::Handshake)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ram::service::NInfo;

    fn window(present: u8, last: u8) -> ScBufferWindow {
        ScBufferWindow { present, last }
    }

    // 410B §4.2.4 words 2-3: a step of NINFO words is final when it covers the last position.
    #[test]
    fn a_step_is_final_when_it_covers_the_last_position() {
        assert!(!window(5, 8).is_final(3));
        assert!(window(5, 8).is_final(4));
        assert!(window(9, 8).is_final(1));
        assert!(window(255, 255).is_final(4));
    }

    // spec-notes "Service containers": pointers stop at 255 instead of wrapping.
    #[test]
    fn advancing_stops_at_255() {
        assert_eq!(window(5, 8).advanced(2), 7);
        assert_eq!(window(254, 255).advanced(4), 255);
        assert!(!window(8, 8).is_exhausted());
        assert!(window(9, 8).is_exhausted());
    }

    // spec-notes "Service containers": positions past the last one (or past 255) are None.
    #[test]
    fn positions_past_the_last_one_are_none() {
        // The first five items of a step's positions (`None` once the step is over).
        fn first_five(w: ScBufferWindow, count: u8) -> [Option<Option<u8>>; 5] {
            let mut it = w.positions(count);
            [it.next(), it.next(), it.next(), it.next(), it.next()]
        }
        assert_eq!(
            first_five(window(7, 8), 4),
            [Some(Some(7)), Some(Some(8)), Some(None), Some(None), None]
        );
        assert_eq!(
            first_five(window(254, 255), 3),
            [Some(Some(254)), Some(Some(255)), Some(None), None, None]
        );
    }

    // 410B §4.2.4 words 2-3: WRDATPT/WRDATLAST and RDDATPT/RDDATLAST.
    #[test]
    fn windows_follow_the_pointer_words() {
        let p = ScPointers {
            wrdatpt: 5,
            wrdatlast: 20,
            rddatpt: 6,
            rddatlast: 9,
        };
        assert_eq!(p.write_window(), window(5, 20));
        assert_eq!(p.read_window(), window(6, 9));
    }

    // 410B §4.2.4 HS_MDT/HS_AT, BUSY_AT: acknowledged when AHS = MHS and BUSY = 0.
    #[test]
    fn acknowledged_needs_equal_handshakes_and_no_busy() {
        let mut m = ScMaster::default();
        assert!(m.is_acknowledged());
        m.busy_at = true;
        assert!(!m.is_acknowledged());
        m.busy_at = false;
        m.hs_mdt = true;
        assert!(!m.is_acknowledged());
        m.hs_at = true;
        assert!(m.is_acknowledged());
    }

    // 410B §4.2.4 HS_MDT, M_BUSY, SETEND: a step starts only when acknowledged and not
    // M_BUSY; END_MDT on the step that reaches the end of the buffer in use.
    #[test]
    fn a_step_starts_only_when_acknowledged_and_not_m_busy() {
        let mut m = ScMaster {
            ls_mdt: true,
            setend: true,
            err_cnt: 3,
            ninfo_write: NInfo::from_code(1),
            pointers: ScPointers {
                wrdatpt: 5,
                wrdatlast: 6,
                rddatpt: 5,
                rddatlast: 5,
            },
            ..ScMaster::default()
        };
        assert!(m.start_step());
        assert!(m.hs_mdt && m.end_mdt);
        assert_eq!(m.err_cnt, 0);
        // Not acknowledged yet: the step is repeated.
        assert!(!m.start_step());
        assert!(m.hs_mdt);
        m.hs_at = true;
        m.m_busy = true;
        assert!(!m.start_step());
        m.m_busy = false;
        m.pointers.wrdatpt = 1;
        assert!(m.start_step());
        assert!(!m.hs_mdt && !m.end_mdt);
    }

    // 410B §4.1 0DH, 410B §4.2.4 ERR_CNT/BUSY_CNT: the timeout fires once, on reaching it.
    #[test]
    fn an_unacknowledged_step_times_out_once() {
        let mut m = ScMaster {
            hs_mdt: true,
            ..ScMaster::default()
        };
        assert_eq!(m.count_cycle(2, 0), None);
        assert_eq!(m.count_cycle(2, 0), Some(ScStepTimeout::Handshake));
        assert!(m.int_hs_timeout && m.m_busy);
        assert_eq!(m.count_cycle(2, 0), None);
        assert_eq!(m.err_cnt, 3);
        // BUSY restarts the count as BUSY cycles.
        m.hs_at = true;
        m.busy_at = true;
        assert_eq!(m.count_cycle(0, 1), Some(ScStepTimeout::Busy));
        assert!(m.busy_cnt && m.int_busy_timeout);
        assert_eq!(m.err_cnt, 1);
        // Acknowledged: nothing counts.
        m.busy_at = false;
        assert_eq!(m.count_cycle(1, 1), None);
        assert_eq!(m.err_cnt, 1);
    }

    // 410B §4.2.4 master table: an acknowledged read step stores NINFO_READ words at RDDATPT
    // and moves it on, INT_END_RDBUF with M_BUSY on the final one; a withdrawn
    // acknowledgement is INT_SC_ERR; an error answer keeps RDDATPT (INT_ERR).
    #[test]
    fn taking_the_at_finishes_or_flags_the_step() {
        let read = ScMaster {
            hs_mdt: true,
            ninfo_read: NInfo::from_code(1),
            pointers: ScPointers {
                wrdatpt: 5,
                wrdatlast: 5,
                rddatpt: 5,
                rddatlast: 6,
            },
            ..ScMaster::default()
        };
        let ack = ScAtBits {
            ahs: true,
            ..ScAtBits::default()
        };
        let mut m = read;
        let taken = m.take_at(ack);
        assert!(taken.handshake);
        assert_eq!(taken.info_to, Some((window(5, 6), 2)));
        assert_eq!(taken.raised, Some(ScAtInterrupt::EndRdbuf));
        assert!(m.int_end_rdbuf && m.m_busy);
        assert_eq!(m.pointers.rddatpt, 7);
        // Taking the same AT again changes nothing; taking it away is a protocol error.
        assert_eq!(m.take_at(ack), ScAtTaken::default());
        let withdrawn = m.take_at(ScAtBits::default());
        assert_eq!(withdrawn.raised, Some(ScAtInterrupt::ScErr));
        assert!(m.int_sc_err);
        // An error answer: the code goes to RDDATPT, which stays.
        let mut m = read;
        let taken = m.take_at(ScAtBits {
            error: true,
            command_change: true,
            ..ack
        });
        assert!(taken.int_cmd && m.int_cmd && m.cmd_at);
        assert_eq!(taken.raised, Some(ScAtInterrupt::Err));
        assert_eq!(taken.info_to, Some((window(5, 6), 2)));
        assert_eq!(m.pointers.rddatpt, 5);
    }
}
