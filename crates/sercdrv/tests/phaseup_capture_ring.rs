//! End to end: the master and four emulated drives at 2 Mbit/s and 2 ms (the captures' ring,
//! `../shared/captures/README.md`) go from phase 0 to phase 4.

mod master_support;

use master_support::*;
use sercdrv::master::{MasterConfig, Progress};

// sercos-telegrams.md: phases 0-4; captures README: the master brings four drives to phase 4.
#[test]
fn four_drives_reach_phase_4() {
    let cfg = MasterConfig::capture_ring();
    let mut ring = ring(cfg, standard_drives(4), Vec::new());
    let took = ring.run_to_phase(4, 3000);
    let status = ring.master.borrow().status();
    assert!(took.is_some(), "status {status:#?}");
    assert_eq!(status.progress, Progress::Cyclic);
}
