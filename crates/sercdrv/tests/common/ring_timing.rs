//! Drive-parameter and timing-request set-ups the sercdrv tests share: the integration
//! tests take them through `tests/common/mod.rs`, the crate's own unit tests include this
//! file by `#[path]`. The includer names the timing module `timing` (`use sercdrv::timing;`
//! or `use crate::timing;`).

use super::timing::{
    CycleTiming, DriveParameters, TimingError, TimingRequest, TimingRules, plan_cycle,
};
use sercos_wire::time::BitRate;

/// Drive `address` with the tests' usual times (t1min 20, tATMT 20, t5 50, tMTSY 10,
/// tMTSG 10 µs: S-0-0003/4/5/88/90) and `at_data` / `mdt_data` cyclic bytes.
pub fn drive(address: u8, at_data: u16, mdt_data: u16) -> DriveParameters {
    DriveParameters {
        address,
        t1min_us: 20,
        t_atmt_us: 20,
        t5_us: 50,
        t_mtsy_us: 10,
        t_mtsg_us: 10,
        at_data_bytes: at_data,
        mdt_data_bytes: mdt_data,
    }
}

/// Drives 1 to `n`, all as [`drive`].
pub fn drives_alike(n: u8, at_data: u16, mdt_data: u16) -> Vec<DriveParameters> {
    (1..=n).map(|a| drive(a, at_data, mdt_data)).collect()
}

/// A request at `rate` with cycle and NC cycle `cycle` µs (S-0-0002, S-0-0001) and the
/// default rules.
pub fn request(rate: BitRate, cycle: u32, drives: Vec<DriveParameters>) -> TimingRequest {
    TimingRequest {
        bit_rate: rate,
        cycle_time_us: cycle,
        nc_cycle_time_us: cycle,
        drives,
        rules: TimingRules::default(),
    }
}

/// The plan of a ring of `n` drives alike ([`drives_alike`], [`request`]).
pub fn plan_alike(
    rate: BitRate,
    cycle: u32,
    n: u8,
    at_data: u16,
    mdt_data: u16,
) -> Result<CycleTiming, TimingError> {
    plan_cycle(&request(rate, cycle, drives_alike(n, at_data, mdt_data)))
}
