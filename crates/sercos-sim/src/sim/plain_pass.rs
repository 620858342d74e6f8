//! Slave telegrams through runs of plain repeaters (fast path): by fibre delays and repeater
//! latencies (410B §1: "The slaves regenerate and repeat their received data"), in constant
//! time where the run's output floors are one offset above the hops ([`super::out_floors`]),
//! and the filler behind a telegram without a pass of its own.
//!
//! A slave resumes its background (the filler) at the very end of its own AT, so the filler
//! enters the run exactly one telegram length after the AT. If no output floor of the run
//! changed since the AT's pass, the filler reaches every repeater exactly one telegram
//! length after the AT's start there, which is where the AT left that repeater's output
//! floor: at repeater m, with the AT at `a(m) = max(a(m−1) + hop, floor)` and the floor
//! left at `a(m) + len`, the filler gives `max(a(m−1) + len + hop, a(m) + len) = a(m) + len`
//! and leaves the floor there. So its pass changes no floor and ends `len` after the AT's
//! end of the run: the simulation keeps the AT's pass ([`PlainPass`]) and answers at once.

use sercon_model::serial_port::{LineSegment, REPEATER_LATENCY_BITS};
use sercos_wire::time::{Duration, Instant};

use super::out_floors::Crossing;
use super::{NOT_PLAIN, Simulation};

/// A pass through a run of plain repeaters whose output floors still stand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct PlainPass {
    /// The fibre it entered the run on (`*cur` of [`Simulation::pass_plain`]).
    pub(super) entry: usize,
    /// Its start at that fibre's entrance.
    pub(super) start_in: Instant,
    /// Its length (zero for a steady signal).
    pub(super) len: Duration,
    /// The repeater latency it was carried with.
    pub(super) lat: Duration,
    /// Its start after the run.
    pub(super) start_out: Instant,
    /// Repeaters in the run.
    pub(super) run: usize,
}

/// Carries a segment starting at `start` (`len` long) through the plain repeaters whose
/// fibre delays are `plain` (up to the first [`NOT_PLAIN`]), raising `floors` as
/// `Node::put_out` does on the fast path; returns its start after them and their number.
fn walk(
    plain: &[u64],
    floors: &mut [Instant],
    mut start: Instant,
    lat: Duration,
    len: Duration,
) -> (Instant, usize) {
    let mut run = 0;
    for (p, floor) in plain.iter().zip(floors.iter_mut()) {
        if *p == NOT_PLAIN {
            break;
        }
        start = start
            .saturating_add(Duration::from_picos(*p))
            .saturating_add(lat)
            .max(*floor);
        // `Node::put_out` on the fast path: the line is taken to the telegram's end
        // (a steady signal: to its start).
        *floor = start.saturating_add(len);
        run += 1;
    }
    (start, run)
}

impl Simulation {
    /// Carries a slave's telegram or filler, at the entrance of fibre `*cur`, through the
    /// plain repeaters after it (`plain_hop`), exactly as the per-hop loop of
    /// [`Simulation::propagate`] would (clean fibre, no delivery, identity clock, output
    /// floor), leaving `*cur` at the last of them.
    pub(super) fn pass_plain(&mut self, cur: &mut usize, seg: &mut LineSegment) {
        let end = seg.end();
        self.pass_plain_ending(cur, seg, end);
    }

    /// [`Simulation::pass_plain`] of `seg` ending at `end` (`LineSegment::end`, found by the
    /// caller).
    #[inline]
    pub(super) fn pass_plain_ending(
        &mut self,
        cur: &mut usize,
        seg: &mut LineSegment,
        end: Option<Instant>,
    ) {
        debug_assert_eq!(end, seg.end(), "the segment's end");
        let first = *cur + 1;
        let lat = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
        let len = end.map_or(Duration::ZERO, |e| e.saturating_duration_since(seg.start));
        if end.is_none()
            && let Some(last) = self.plain_pass
            && last.entry == *cur
            && last.lat == lat
            && seg.start == last.start_in.saturating_add(last.len)
        {
            // The filler right behind the last pass (module notes).
            let out = last.start_out.saturating_add(last.len);
            self.debug_check_follower(*cur, seg.start, lat, out, last.run);
            *cur += last.run;
            seg.start = out;
            seg.distorted = false;
            return;
        }
        let stop = self.run_end.get(first).copied().unwrap_or(first);
        let run = stop.saturating_sub(first);
        let Some(plain) = self.plain_hop.get(first..stop) else {
            return;
        };
        if run == 0 {
            return;
        }
        let crossing = Crossing {
            start: seg.start,
            len,
            lat,
        };
        let (start, held) = self
            .out_floors
            .pass(plain, first..stop, crossing, |p, f, s| {
                walk(p, f, s, lat, len)
            });
        if held && end.is_some() {
            // A telegram held behind another at a repeater's output (`repeat_out`).
            self.stats.fast_path_collisions += 1;
        }
        // Kept only where no sum saturated (then the module notes' algebra holds).
        self.plain_pass = start
            .as_picos()
            .checked_add(len.as_picos())
            .map(|_| PlainPass {
                entry: *cur,
                start_in: seg.start,
                len,
                lat,
                start_out: start,
                run,
            });
        *cur += run;
        seg.start = start;
        seg.distorted = false;
    }

    /// The output floors of nodes `written` were written elsewhere
    /// ([`Simulation::floor_written`] of each).
    pub(super) fn floors_written(&mut self, written: std::ops::Range<usize>) {
        if self
            .plain_pass
            .is_some_and(|p| written.start <= p.entry + p.run && p.entry + 1 < written.end)
        {
            self.plain_pass = None;
        }
    }

    /// An output floor of node `k` was written elsewhere: the last pass no longer stands if
    /// `k` is in its run.
    pub(super) fn floor_written(&mut self, k: usize) {
        if self
            .plain_pass
            .is_some_and(|p| k > p.entry && k <= p.entry + p.run)
        {
            self.plain_pass = None;
        }
    }

    /// Debug builds: a filler answered from the last pass gets what its own pass would give
    /// (the same start after the same run, and no floor changed).
    pub(super) fn debug_check_follower(
        &self,
        cur: usize,
        start: Instant,
        lat: Duration,
        out: Instant,
        run: usize,
    ) {
        if cfg!(debug_assertions) {
            let first = cur + 1;
            let plain = self.plain_hop.get(first..).unwrap_or(&[]);
            let floors: Vec<Instant> = (first..self.plain_hop.len())
                .filter_map(|m| self.out_floors.get(m))
                .collect();
            let mut walked = floors.clone();
            let got = walk(plain, &mut walked, start, lat, Duration::ZERO);
            debug_assert_eq!(got, (out, run), "filler behind a pass");
            debug_assert_eq!(walked, floors, "a filler behind a pass changes no floor");
        }
    }
}
