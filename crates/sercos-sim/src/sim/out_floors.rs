//! How far each node's output line is taken (simulation time): the floors below which a
//! forwarded segment cannot start (`Node::put_out`), and the pass of a slave telegram through
//! a run of plain repeaters (410B §1: "The slaves regenerate and repeat their received
//! data") in constant time.
//!
//! Through plain repeaters a segment only gains the fibre delay and the repeater latency at
//! every hop, unless a repeater's output is still taken (its floor): at repeater `m` it
//! starts at `max(start(m−1) + hop(m), floor(m))` and leaves the floor at that plus its
//! length. Measured against the prefix sums `Q(m)` of the hops, `start(m) − Q(m)` is the
//! running maximum of the entry offset and every `floor − Q` passed, and the floors it
//! leaves are that plus its length. So when the floors over a run are one offset above `Q`
//! (as every pass that was not held up leaves them), a pass is two comparisons: the floors
//! are kept as that offset over the run ([`Uniform`]) and written out only when a single
//! floor is read or written through [`OutFloors::get`] / [`OutFloors::set`] or a pass
//! covers part of the run.
//!
//! The highest `floor − Q` of the repeaters is kept as well (the ceiling; dropped by every
//! write and found again when asked for, once per master telegram at most): a segment
//! entering at or above it is held up nowhere, so a master's telegram round the ring, later
//! than everything before it, leaves the floors one offset above `Q` without a floor read
//! hop by hop ([`OutFloors::free_sweep`]).

use std::ops::Range;

use sercos_wire::time::{Duration, Instant};

/// Sums above this are left to the hop-by-hop walk (which saturates where the prefix sums
/// would not).
const SAFE_PS: i128 = 1 << 62;

/// A segment at the entrance of a run: its start, its length (zero for a steady signal)
/// and the repeater latency it gains at every hop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Crossing {
    /// Start at the output of the node before the run.
    pub(super) start: Instant,
    /// Length.
    pub(super) len: Duration,
    /// Repeater latency.
    pub(super) lat: Duration,
}

/// Floors `from..to` are `prefix + offset` (not written to `floors`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Uniform {
    from: usize,
    to: usize,
    offset: i128,
}

/// The uniform run of [`OutFloors`] from slave `next` up to the master, kept by a caller
/// that sends the slaves' telegrams through one after the other
/// ([`OutFloors::open_through`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Through {
    /// The slave whose telegram comes next (the run's first floor).
    pub(super) next: usize,
    /// The run's floors over the prefix sums.
    offset: i128,
    /// The prefix sum of the last repeater.
    q_out: i128,
    /// The repeater latency the prefix sums are for.
    pub(super) lat: Duration,
}

/// The output floors of every node, some of them kept as one offset over a run.
#[derive(Debug, Clone, Default)]
pub(super) struct OutFloors {
    floors: Vec<Instant>,
    /// Delay of the fibre into each node (ps).
    delays: Vec<u64>,
    /// `prefix[m]`: the hops (fibre delay into `i` plus latency) of nodes `1..=m`.
    prefix: Vec<i128>,
    /// The latency `prefix` was summed with.
    prefix_lat: Option<Duration>,
    uniform: Option<Uniform>,
    /// The highest `floor(m) − prefix[m]` over every repeater `m ≥ 1` (`None`: not known
    /// since the last write, [`OutFloors::ceiling`]): a segment entering at node 1's fibre
    /// at or above it (measured against `prefix`) is held up at no floor
    /// ([`OutFloors::free_sweep`]).
    ceiling: Option<i128>,
}

impl OutFloors {
    /// Debug builds: a copy of the floors with `t`'s run written back as the uniform run
    /// from `from` to `to` at `offset` (what `close_through` would leave), to compare a
    /// step of a run sent through with the general `set` and `pass`.
    #[cfg(debug_assertions)]
    fn with_run(&self, from: usize, to: usize, offset: i128) -> Self {
        let mut f = self.clone();
        f.uniform = Some(Uniform { from, to, offset });
        f
    }

    /// `n` floors at time zero; `fibre_into[m]` is the delay of the fibre into node `m`.
    pub(super) fn new(n: usize, fibre_into: impl Iterator<Item = Duration>) -> Self {
        OutFloors {
            floors: vec![Instant::ZERO; n],
            delays: fibre_into.map(Duration::as_picos).collect(),
            prefix: Vec::new(),
            prefix_lat: None,
            uniform: None,
            ceiling: None,
        }
    }

    /// Node `m`'s floor.
    pub(super) fn get(&self, m: usize) -> Option<Instant> {
        if let Some(u) = self.uniform
            && u.from <= m
            && m < u.to
        {
            let v = self.prefix.get(m)? + u.offset;
            return u64::try_from(v).ok().map(Instant::from_picos);
        }
        self.floors.get(m).copied()
    }

    /// Sets node `m`'s floor. In a uniform run, the floors before `m` are written out and
    /// the run goes on after it (a ring's writes come in ring order: usually none).
    pub(super) fn set(&mut self, m: usize, v: Instant) {
        if let Some(u) = self.uniform
            && u.from <= m
            && m < u.to
        {
            self.write_range(u, u.from, m);
            self.uniform = (m + 1 < u.to).then_some(Uniform { from: m + 1, ..u });
        }
        if let Some(f) = self.floors.get_mut(m) {
            *f = v;
        }
        if m > 0 {
            self.ceiling = None;
        }
    }

    /// Writes the uniform run out to `floors`.
    fn write_out(&mut self) {
        if let Some(u) = self.uniform.take() {
            self.write_range(u, u.from, u.to);
        }
    }

    /// Writes floors `a..b` of `u` out.
    fn write_range(&mut self, u: Uniform, a: usize, b: usize) {
        for m in a..b {
            if let (Some(f), Some(q)) = (self.floors.get_mut(m), self.prefix.get(m)) {
                *f = Instant::from_picos(u64::try_from(q + u.offset).unwrap_or(0));
            }
        }
    }

    /// The prefix sums for `lat` (the uniform run, summed with another latency, is written
    /// out first).
    fn use_lat(&mut self, lat: Duration) {
        if self.prefix_lat == Some(lat) {
            return;
        }
        self.write_out();
        let lat = i128::from(lat.as_picos());
        let mut sum = 0i128;
        self.prefix.clear();
        for (m, d) in self.delays.iter().enumerate() {
            if m > 0 {
                sum += i128::from(*d) + lat;
            }
            self.prefix.push(sum);
        }
        self.prefix_lat = Some(Duration::from_picos(u64::try_from(lat).unwrap_or(0)));
        self.ceiling = None;
    }

    /// The ceiling (found again if a write dropped it: the uniform run's offset and the
    /// floors written out).
    fn ceiling(&mut self) -> i128 {
        if let Some(c) = self.ceiling {
            return c;
        }
        let n = self.floors.len();
        let c = match self.uniform {
            Some(u) => self
                .highest(1..u.from.max(1))
                .max(u.offset)
                .max(self.highest(u.to.max(1)..n)),
            None => self.highest(1..n),
        };
        self.ceiling = Some(c);
        c
    }

    /// The ceiling after slave `j`'s floor was set to `left` (`q_in`: its prefix sum) and
    /// the floors of the repeaters after it, one run before, were raised to `run_offset`
    /// over the hops (a telegram sent through, 410B §1: they repeat it by their hops): the
    /// run's new offset is at or above its old one, which the ceiling counted, so the
    /// ceiling is the old one, `left`'s offset and `run_offset`, whichever is highest.
    /// Unknown before (or `j` the master, whose floor it does not count): unknown after.
    #[inline]
    fn raise_ceiling(&mut self, j: usize, left: Instant, q_in: i128, run_offset: i128) {
        self.ceiling = match self.ceiling {
            Some(c) if j > 0 => Some(c.max(i128::from(left.as_picos()) - q_in).max(run_offset)),
            _ => None,
        };
    }

    /// Debug builds: the ceiling kept is the one found again from the floors of `f` (a
    /// copy of these floors with every run written back).
    #[cfg(debug_assertions)]
    fn debug_check_ceiling(&self, mut f: Self) {
        if let Some(kept) = self.ceiling {
            f.ceiling = None;
            debug_assert_eq!(Some(kept), Some(f.ceiling()), "the ceiling kept");
        }
    }

    /// The highest `floor(m) − prefix[m]` over `run` (floors written out; `i128::MIN` for
    /// none).
    fn highest(&self, run: Range<usize>) -> i128 {
        let (Some(f), Some(q)) = (self.floors.get(run.clone()), self.prefix.get(run)) else {
            return i128::MIN;
        };
        f.iter()
            .zip(q)
            .map(|(f, q)| i128::from(f.as_picos()) - q)
            .max()
            .unwrap_or(i128::MIN)
    }

    /// Carries `seg` from the output of node `run.start − 1` through the plain repeaters
    /// `run` (`plain`: their fibre delays, as `Simulation::plain_hop` keeps them), raising
    /// their floors; returns its start after the last of them and whether a floor held it
    /// up anywhere. `walk` is the hop-by-hop reference (used when the run's floors are not
    /// one offset).
    pub(super) fn pass(
        &mut self,
        plain: &[u64],
        run: Range<usize>,
        seg: Crossing,
        walk: impl FnOnce(&[u64], &mut [Instant], Instant) -> (Instant, usize),
    ) -> (Instant, bool) {
        let Crossing { start, len, lat } = seg;
        let (first, end) = (run.start, run.end);
        if self.prefix_lat != Some(lat) {
            self.use_lat(lat);
        }
        let (Some(q_in), Some(q_out)) = (
            first.checked_sub(1).and_then(|i| self.prefix.get(i)),
            end.checked_sub(1).and_then(|i| self.prefix.get(i)),
        ) else {
            return (start, false);
        };
        let (q_in, q_out) = (*q_in, *q_out);
        let len_ps = i128::from(len.as_picos());
        let offset = i128::from(start.as_picos()) - q_in;
        if let Some(u) = self.uniform
            && u.from <= first
            && end <= u.to
        {
            // Held up at the first floor (they are all one offset above the hops) or not
            // at all, and then one offset above the hops itself.
            let reached = offset.max(u.offset);
            let out = reached + q_out;
            if out + len_ps < SAFE_PS {
                let new = Uniform {
                    from: first,
                    to: end,
                    offset: reached + len_ps,
                };
                self.debug_check(plain, first..end, seg, out, new);
                // Floors outside the run keep the old offset.
                self.write_range(u, u.from, first);
                self.write_range(u, end, u.to);
                self.uniform = Some(new);
                self.ceiling = None;
                return (
                    Instant::from_picos(u64::try_from(out).unwrap_or(0)),
                    u.offset > offset,
                );
            }
        }
        self.write_out();
        let Some(floors) = self.floors.get_mut(first..end) else {
            return (start, false);
        };
        let (out, run) = walk(plain, floors, start);
        // Each floor it leaves is its running maximum of the entry offset and the floors
        // passed, plus its length (module notes).
        self.ceiling = None;
        let out_ps = i128::from(out.as_picos());
        let held = run == end.saturating_sub(first) && out_ps - q_out != offset;
        // Not held up anywhere: the floors are one offset over the run now.
        if run == end.saturating_sub(first) && out_ps - q_out == offset && out_ps + len_ps < SAFE_PS
        {
            self.uniform = Some(Uniform {
                from: first,
                to: end,
                offset: offset + len_ps,
            });
        }
        (out, held)
    }

    /// A slave's own telegram put out by node `j` and carried through the plain repeaters
    /// `j + 1..to` (their fibre delays `plain`): [`OutFloors::set`] of `j`'s floor to
    /// `left` then [`OutFloors::pass`] of `seg` (which enters at `j`'s output) in one step,
    /// where both run inside the uniform run (410B §1: the repeaters repeat it by their
    /// hops). Returns `j`'s floor before, the segment's start after the run and whether a
    /// floor held it up; `None` (nothing changed) where the uniform run does not cover
    /// `j..to`, the prefix sums are for another latency or a sum could saturate: then the
    /// caller sets and passes as usual. Debug builds compare it with `set` and `pass`.
    #[inline]
    pub(super) fn send_through(
        &mut self,
        j: usize,
        left: Instant,
        plain: &[u64],
        to: usize,
        seg: Crossing,
    ) -> Option<(Instant, Instant, bool)> {
        let u = self.uniform?;
        if self.prefix_lat != Some(seg.lat) || u.from > j || to > u.to || j + 1 >= to {
            return None;
        }
        let (Some(q_in), Some(q_out)) = (self.prefix.get(j), self.prefix.get(to - 1)) else {
            return None;
        };
        let (q_in, q_out) = (*q_in, *q_out);
        let before = u64::try_from(q_in + u.offset).ok()?;
        let offset = i128::from(seg.start.as_picos()) - q_in;
        let reached = offset.max(u.offset);
        let len_ps = i128::from(seg.len.as_picos());
        let out = reached + q_out;
        if out + len_ps >= SAFE_PS {
            return None;
        }
        #[cfg(debug_assertions)]
        let general = {
            debug_assert_eq!(self.get(j), Some(Instant::from_picos(before)), "floor {j}");
            let mut f = self.clone();
            f.set(j, left);
            let got = f.pass(plain, j + 1..to, seg, |_, _, s| (s, 0));
            (f, got)
        };
        #[cfg(not(debug_assertions))]
        let _ = plain;
        // `set`: the floors before `j` written out, `j`'s its own.
        self.write_range(u, u.from, j);
        if let Some(f) = self.floors.get_mut(j) {
            *f = left;
        }
        // `pass`: one offset above the hops after it (floors after the run keep the old).
        self.write_range(u, to, u.to);
        self.uniform = Some(Uniform {
            from: j + 1,
            to,
            offset: reached + len_ps,
        });
        self.raise_ceiling(j, left, q_in, reached + len_ps);
        let got = (
            Instant::from_picos(u64::try_from(out).unwrap_or(0)),
            u.offset > offset,
        );
        #[cfg(debug_assertions)]
        {
            let (f, want) = general;
            debug_assert_eq!(got, want, "a telegram sent through in one step");
            for m in 0..self.floors.len() {
                debug_assert_eq!(self.get(m), f.get(m), "floor {m} after a send-through");
            }
            self.debug_check_ceiling(self.clone());
        }
        Some((Instant::from_picos(before), got.0, got.1))
    }

    /// Opens [`Through`]: the slaves' own telegrams from node `from` on, one slave after
    /// the other in ring order, each sent through every repeater after it up to the master
    /// (node 0, after the last floor) with latency `lat`, as [`OutFloors::send_through`]
    /// sends each (410B §1: the repeaters repeat them by their hops), the uniform run kept
    /// by the caller between them. `None` (nothing changed) unless the uniform run covers
    /// `from` up to the last floor and the prefix sums are for `lat`. The floors before
    /// `from` are written out; the floors from the run's next slave on are read only through
    /// [`OutFloors::close_through`], which hands the run back.
    #[inline]
    pub(super) fn open_through(&mut self, from: usize, lat: Duration) -> Option<Through> {
        let u = self.uniform?;
        let to = self.floors.len();
        if self.prefix_lat != Some(lat) || u.from > from || u.to != to || from + 1 >= to {
            return None;
        }
        let q_out = *self.prefix.get(to - 1)?;
        self.write_range(u, u.from, from);
        self.uniform = None;
        // The floors keep their values (the run's are kept in `Through`): so does the
        // ceiling, kept by every telegram sent through the run.
        Some(Through {
            next: from,
            offset: u.offset,
            q_out,
            lat,
        })
    }

    /// [`OutFloors::send_through`] of the telegram of slave `t.next` (starting at `start`,
    /// `len` long, `left` its end) within `t`: its floor set to `left`, the telegram carried
    /// through the repeaters after it, the run after it one offset above the hops. Returns
    /// `send_through`'s figures; `None` (nothing changed) for the last slave (no repeater
    /// after it) or where a sum could saturate: then the caller closes `t` and goes the
    /// general way. Debug builds compare it with `set` and `pass`.
    #[inline]
    pub(super) fn through_next(
        &mut self,
        t: &mut Through,
        left: Instant,
        start: Instant,
        len: Duration,
        plain: &[u64],
    ) -> Option<(Instant, Instant, bool)> {
        let j = t.next;
        let to = self.floors.len();
        if j + 1 >= to {
            return None;
        }
        let q_in = *self.prefix.get(j)?;
        let before = u64::try_from(q_in + t.offset).ok()?;
        let offset = i128::from(start.as_picos()) - q_in;
        let reached = offset.max(t.offset);
        let len_ps = i128::from(len.as_picos());
        let out = reached + t.q_out;
        if out + len_ps >= SAFE_PS {
            return None;
        }
        #[cfg(debug_assertions)]
        let general = {
            let mut f = self.with_run(j, to, t.offset);
            debug_assert_eq!(f.get(j), Some(Instant::from_picos(before)), "floor {j}");
            f.set(j, left);
            let seg = Crossing {
                start,
                len,
                lat: t.lat,
            };
            let got = f.pass(plain, j + 1..to, seg, |_, _, s| (s, 0));
            (f, got)
        };
        #[cfg(not(debug_assertions))]
        let _ = plain;
        if let Some(f) = self.floors.get_mut(j) {
            *f = left;
        }
        let got = (
            Instant::from_picos(u64::try_from(out).unwrap_or(0)),
            t.offset > offset,
        );
        t.next = j + 1;
        t.offset = reached + len_ps;
        // The ceiling kept is the run's at its opening: the floor's old offset, dropped,
        // was at most `t.offset`, which only rises; the floor's new one is at most the
        // offset the telegram leaves after it (`reached` is at least its start's), unless
        // `left` is past the telegram's end. So the ceiling now is the kept one and
        // `t.offset`, the higher ([`OutFloors::close_through`]).
        if left > start.saturating_add(len) {
            self.ceiling = None;
        }
        #[cfg(debug_assertions)]
        {
            let (f, want) = general;
            debug_assert_eq!(got, want, "a telegram sent through in a run of them");
            let mine = self.with_run(t.next, to, t.offset);
            for m in 0..to {
                debug_assert_eq!(mine.get(m), f.get(m), "floor {m} in a run sent through");
            }
            let kept = self.ceiling;
            let mut now = mine;
            now.ceiling = kept.map(|c| c.max(t.offset));
            now.debug_check_ceiling(now.clone());
        }
        Some((Instant::from_picos(before), got.0, got.1))
    }

    /// [`OutFloors::set`] of the last slave's floor to `left` (its telegram goes straight
    /// into the master: no repeater after it) within `t`, which it ends. Returns the floor
    /// before; `None` (nothing changed) when `t.next` is not the last slave or that floor
    /// is not an instant. Debug builds compare it with `set`.
    #[inline]
    pub(super) fn through_last(&mut self, t: &mut Through, left: Instant) -> Option<Instant> {
        let j = t.next;
        let to = self.floors.len();
        if j + 1 != to {
            return None;
        }
        let q = *self.prefix.get(j)?;
        let before = u64::try_from(q + t.offset).ok()?;
        #[cfg(debug_assertions)]
        let general = {
            let mut f = self.with_run(j, to, t.offset);
            debug_assert_eq!(f.get(j), Some(Instant::from_picos(before)), "floor {j}");
            f.set(j, left);
            f
        };
        if let Some(f) = self.floors.get_mut(j) {
            *f = left;
        }
        t.next = to;
        // The ceiling kept (the run's at its opening, `OutFloors::through_next`) and the
        // offsets dropped since, each at most the floor's old one (`t.offset`), which may
        // have been the highest: kept only where the new one is at or above it.
        let left_offset = i128::from(left.as_picos()) - q;
        self.ceiling = self
            .ceiling
            .filter(|_| j > 0 && left_offset >= t.offset)
            .map(|c| c.max(left_offset));
        #[cfg(debug_assertions)]
        {
            for m in 0..to {
                debug_assert_eq!(
                    self.floors.get(m),
                    general.get(m).as_ref(),
                    "floor {m} after the last slave's telegram in a run"
                );
            }
            // Every floor written out (the run is empty now).
            self.debug_check_ceiling(self.clone());
        }
        Some(Instant::from_picos(before))
    }

    /// Hands the run of `t` back ([`OutFloors::open_through`]): the floors from its next
    /// slave on one offset above the hops, as the last [`OutFloors::through_next`] left them.
    #[inline]
    pub(super) fn close_through(&mut self, t: Through) {
        let to = self.floors.len();
        self.uniform = (t.next < to).then_some(Uniform {
            from: t.next,
            to,
            offset: t.offset,
        });
        // The ceiling kept through the run and its floors' offset (`through_next`).
        if t.next < to {
            self.ceiling = self.ceiling.map(|c| c.max(t.offset));
        }
        #[cfg(debug_assertions)]
        self.debug_check_ceiling(self.clone());
    }

    /// Starts a sweep: a segment carried hop by hop through repeaters in ring order (a
    /// master's segment round a plain ring), whose floors are read and written one by one
    /// ([`OutFloors::swept`], [`OutFloors::sweep_set`]) and kept as one run at its end where
    /// they are one offset above the hops ([`OutFloors::close_sweep`]). The uniform run is
    /// written out and the prefix sums taken for `lat`.
    #[inline]
    pub(super) fn open_sweep(&mut self, lat: Duration) {
        if self.prefix_lat != Some(lat) {
            self.use_lat(lat);
        }
        self.write_out();
    }

    /// Node `m`'s floor in a sweep.
    #[inline]
    pub(super) fn swept(&self, m: usize) -> Option<Instant> {
        debug_assert!(self.uniform.is_none(), "a floor read in a sweep");
        self.floors.get(m).copied()
    }

    /// Sets node `m`'s floor in a sweep.
    #[inline]
    pub(super) fn sweep_set(&mut self, m: usize, v: Instant) {
        debug_assert!(self.uniform.is_none(), "a floor set in a sweep");
        if let Some(f) = self.floors.get_mut(m) {
            *f = v;
        }
        self.ceiling = None;
    }

    /// Ends a sweep through `run`; `uniform`: its segment, of one length, was held up at
    /// no floor but the first's and every repeater is on the simulation's clock. Then
    /// every floor of the run is its start there plus that length, one offset above the
    /// hops (module notes), and the run is kept so where no sum saturated.
    pub(super) fn close_sweep(&mut self, run: Range<usize>, uniform: bool) {
        debug_assert!(self.uniform.is_none(), "a sweep closed twice");
        if run.is_empty() {
            return;
        }
        let (Some(q), Some(f), Some(last)) = (
            self.prefix.get(run.start),
            self.floors.get(run.start),
            run.end.checked_sub(1).and_then(|i| self.floors.get(i)),
        ) else {
            return;
        };
        if !uniform || i128::from(last.as_picos()) >= SAFE_PS {
            return;
        }
        let offset = i128::from(f.as_picos()) - q;
        if cfg!(debug_assertions) {
            for m in run.clone() {
                let want = self.prefix.get(m).map(|q| q + offset);
                let got = self.floors.get(m).map(|f| i128::from(f.as_picos()));
                debug_assert_eq!(want, got, "floor {m} after a sweep");
            }
        }
        self.uniform = Some(Uniform {
            from: run.start,
            to: run.end,
            offset,
        });
    }

    /// A sweep through `run` held up at no floor: `seg` enters it (at the output of node
    /// `run.start − 1`) at or above every floor's offset over the hops (the ceiling), so at
    /// each repeater it starts by the hops alone and leaves the floor one offset above them
    /// (module notes): the floors are kept as that run at once and none is read or written
    /// hop by hop. Returns whether it was so (`false`: nothing changed, sweep hop by hop).
    pub(super) fn free_sweep(&mut self, run: Range<usize>, seg: Crossing) -> bool {
        let Crossing { start, len, lat } = seg;
        let (first, end) = (run.start, run.end);
        if self.prefix_lat != Some(lat) || first == 0 {
            return false;
        }
        let c = self.ceiling();
        let (Some(q_in), Some(q_out)) = (
            self.prefix.get(first - 1),
            end.checked_sub(1).and_then(|i| self.prefix.get(i)),
        ) else {
            return false;
        };
        let offset = i128::from(start.as_picos()) - q_in;
        let len_ps = i128::from(len.as_picos());
        if offset < c || first >= end || offset + q_out + len_ps >= SAFE_PS {
            return false;
        }
        let new = Uniform {
            from: first,
            to: end,
            offset: offset + len_ps,
        };
        self.debug_check_free(run, seg, new);
        if let Some(u) = self.uniform {
            // Floors outside the run keep the old offset.
            self.write_range(u, u.from, first.min(u.to));
            self.write_range(u, end.max(u.from), u.to);
        }
        self.uniform = Some(new);
        // Every repeater's floor is the run's now (found again otherwise).
        self.ceiling = (first == 1 && end == self.floors.len()).then_some(new.offset);
        true
    }

    /// Debug builds: the ceiling is the highest floor over the hops, and a free sweep is held up nowhere and
    /// leaves the floors the hop-by-hop walk leaves.
    fn debug_check_free(&self, run: Range<usize>, seg: Crossing, new: Uniform) {
        if cfg!(debug_assertions) {
            let highest = (1..self.floors.len())
                .filter_map(|m| Some(i128::from(self.get(m)?.as_picos()) - self.prefix.get(m)?))
                .max()
                .unwrap_or(i128::MIN);
            debug_assert_eq!(self.ceiling, Some(highest), "the ceiling");
            let mut at = seg.start;
            for m in run {
                let (Some(d), Some(f)) = (self.delays.get(m), self.get(m)) else {
                    continue;
                };
                at = at
                    .saturating_add(Duration::from_picos(*d))
                    .saturating_add(seg.lat);
                debug_assert!(at >= f, "a free sweep held up at {m}");
                let left = self.prefix.get(m).map(|q| q + new.offset);
                debug_assert_eq!(
                    left,
                    Some(i128::from(at.saturating_add(seg.len).as_picos())),
                    "floor {m} after a free sweep"
                );
            }
        }
    }

    /// Debug builds: the constant-time pass gives what the walk gives.
    fn debug_check(
        &self,
        plain: &[u64],
        run: Range<usize>,
        seg: Crossing,
        out: i128,
        new: Uniform,
    ) {
        if cfg!(debug_assertions) {
            let Crossing { start, len, lat } = seg;
            let (first, end) = (run.start, run.end);
            let mut floors: Vec<Instant> = (first..end).filter_map(|m| self.get(m)).collect();
            let mut at = start;
            for (d, f) in plain.iter().zip(floors.iter_mut()) {
                at = at
                    .saturating_add(Duration::from_picos(*d))
                    .saturating_add(lat)
                    .max(*f);
                *f = at.saturating_add(len);
            }
            debug_assert_eq!(i128::from(at.as_picos()), out, "pass through a uniform run");
            for (m, f) in (first..end).zip(&floors) {
                let want = self.prefix.get(m).map(|q| q + new.offset);
                debug_assert_eq!(want, Some(i128::from(f.as_picos())), "floor {m}");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::test_lcg::Lcg;

    /// The hop-by-hop reference of a pass (`Node::put_out` on the fast path at every hop).
    fn reference(
        delays: &[u64],
        floors: &mut [Instant],
        start: Instant,
        lat: Duration,
        len: Duration,
    ) -> (Instant, usize) {
        let mut at = start;
        for (d, f) in delays.iter().zip(floors.iter_mut()) {
            at = at
                .saturating_add(Duration::from_picos(*d))
                .saturating_add(lat)
                .max(*f);
            *f = at.saturating_add(len);
        }
        (at, delays.len())
    }

    /// Passes, sweeps, single floors read and written and runs of slaves' telegrams sent
    /// through in random order (runs anywhere, telegrams held up by earlier ones, steady
    /// signals, two latencies): the same starts and
    /// floors as plain floors walked hop by hop; many passes take the constant-time way.
    #[test]
    fn same_as_walking_every_hop() {
        let mut uniform_passes = 0;
        let mut free_sweeps = 0;
        let mut sent_through = 0;
        let mut in_runs = 0;
        for seed in 0..200 {
            let mut rng = Lcg(seed);
            let n = 2 + rng.next(12) as usize;
            let delays: Vec<u64> = (0..n).map(|_| 1_000 + rng.next(50_000)).collect();
            let mut fast = OutFloors::new(n, delays.iter().map(|d| Duration::from_picos(*d)));
            let mut slow = vec![Instant::ZERO; n];
            let mut now = 0u64;
            for step in 0..300 {
                now += rng.next(40_000);
                match rng.next(7) {
                    0 => {
                        let m = rng.next(n as u64) as usize;
                        let v = Instant::from_picos(now + rng.next(90_000));
                        fast.set(m, v);
                        slow[m] = v;
                    }
                    1 => {
                        // A sweep (a master's telegram hop by hop, `propagate_master_plain`).
                        let first = 1 + rng.next(n as u64 - 1) as usize;
                        let end = first + 1 + rng.next((n - first) as u64) as usize;
                        let lat = Duration::from_picos(125_000);
                        let len = Duration::from_picos(rng.next(3) * rng.next(200_000));
                        // Often well after the floors (a master's next telegram).
                        now += rng.next(2) * 1_000_000;
                        let mut at = Instant::from_picos(now);
                        let crossing = Crossing {
                            start: at,
                            len,
                            lat,
                        };
                        if fast.free_sweep(first..end, crossing) {
                            free_sweeps += 1;
                            for m in first..end {
                                at = at
                                    .saturating_add(Duration::from_picos(delays[m]))
                                    .saturating_add(lat);
                                assert!(at >= slow[m], "seed {seed} step {step} free sweep {m}");
                                slow[m] = at.saturating_add(len);
                            }
                        } else {
                            let mut uniform = true;
                            fast.open_sweep(lat);
                            for m in first..end {
                                at = at
                                    .saturating_add(Duration::from_picos(delays[m]))
                                    .saturating_add(lat);
                                let floor = fast.swept(m);
                                assert_eq!(
                                    floor,
                                    Some(slow[m]),
                                    "seed {seed} step {step} sweep {m}"
                                );
                                if at < slow[m] {
                                    at = slow[m];
                                    uniform &= m == first;
                                }
                                slow[m] = at.saturating_add(len);
                                fast.sweep_set(m, slow[m]);
                            }
                            fast.close_sweep(first..end, uniform);
                        }
                    }
                    5 => {
                        // A slave's own telegram: its floor set, then passed on through the
                        // repeaters after it (`send_on_plain`), in one step where it may be.
                        // Often at the uniform run's start and up to the master, as the ATs
                        // go one after the other round a ring.
                        let j = match fast.uniform {
                            Some(u) if u.from >= 1 && u.from < n && rng.next(2) == 0 => u.from,
                            _ => 1 + rng.next(n as u64 - 1) as usize,
                        };
                        let to = if rng.next(2) == 0 {
                            n
                        } else {
                            j + 1 + rng.next((n - j) as u64) as usize
                        };
                        let start = Instant::from_picos(now);
                        let len = Duration::from_picos(rng.next(3) * rng.next(200_000));
                        let lat =
                            Duration::from_picos(if rng.next(20) == 0 { 250_000 } else { 125_000 });
                        // Now and then a floor set past the telegram's end (the ceiling kept counts it).
                        let left = start
                            .saturating_add(len)
                            .saturating_add(Duration::from_picos(
                                rng.next(4) / 3 * rng.next(300_000),
                            ));
                        let plain = delays.get(j + 1..to).unwrap_or(&[]);
                        let seg = Crossing { start, len, lat };
                        let before = slow[j];
                        slow[j] = left;
                        let want = reference(plain, &mut slow[j + 1..to], start, lat, len);
                        if let Some((floor, got, held)) = fast.send_through(j, left, plain, to, seg)
                        {
                            sent_through += 1;
                            assert_eq!(floor, before, "seed {seed} step {step} floor before");
                            assert_eq!(got, want.0, "seed {seed} step {step} sent through");
                            let free = plain.iter().fold(start, |a, d| {
                                a.saturating_add(Duration::from_picos(*d))
                                    .saturating_add(lat)
                            });
                            assert_eq!(held, got > free, "seed {seed} step {step} held");
                        } else {
                            assert_eq!(fast.get(j), Some(before), "seed {seed} step {step}");
                            fast.set(j, left);
                            if j + 1 < to {
                                let (got, _) = fast.pass(plain, j + 1..to, seg, |p, f, s| {
                                    reference(p, f, s, lat, len)
                                });
                                assert_eq!(got, want.0, "seed {seed} step {step}");
                            }
                        }
                    }
                    6 => {
                        // The slaves' telegrams one after the other in ring order, from
                        // slave `from` to the last, each up to the master
                        // (`send_all_plain`), with the uniform run kept between them where it
                        // may be (`open_through`), else each set and passed on.
                        let from = match fast.uniform {
                            Some(u) if u.from >= 1 && u.from < n && rng.next(4) != 0 => u.from,
                            _ => 1 + rng.next(n as u64 - 1) as usize,
                        };
                        let lat =
                            Duration::from_picos(if rng.next(20) == 0 { 250_000 } else { 125_000 });
                        let mut run = fast.open_through(from, lat);
                        for j in from..n {
                            now += rng.next(30_000);
                            let start = Instant::from_picos(now);
                            let len = Duration::from_picos(rng.next(3) * rng.next(200_000));
                            // Now and then a floor set past the telegram's end (the run's ceiling kept
                            // is dropped then), or the run left before its end (closed with
                            // floors in it).
                            let left =
                                start
                                    .saturating_add(len)
                                    .saturating_add(Duration::from_picos(
                                        rng.next(8) / 7 * rng.next(300_000),
                                    ));
                            let plain = delays.get(j + 1..n).unwrap_or(&[]);
                            let before = slow[j];
                            slow[j] = left;
                            let want = reference(plain, &mut slow[j + 1..n], start, lat, len);
                            let got = match run.as_mut().filter(|_| rng.next(10) != 0) {
                                Some(t) if j + 1 < n => fast
                                    .through_next(t, left, start, len, plain)
                                    .map(|(f, out, held)| (f, Some((out, held)))),
                                Some(t) => fast.through_last(t, left).map(|f| (f, None)),
                                None => None,
                            };
                            if let Some((floor, passed)) = got {
                                in_runs += 1;
                                assert_eq!(floor, before, "seed {seed} step {step} run {j}");
                                if let Some((out, held)) = passed {
                                    assert_eq!(out, want.0, "seed {seed} step {step} run {j}");
                                    let free = plain.iter().fold(start, |a, d| {
                                        a.saturating_add(Duration::from_picos(*d))
                                            .saturating_add(lat)
                                    });
                                    assert_eq!(held, out > free, "seed {seed} step {step} held");
                                }
                                continue;
                            }
                            if let Some(t) = run.take() {
                                fast.close_through(t);
                            }
                            assert_eq!(fast.get(j), Some(before), "seed {seed} step {step}");
                            fast.set(j, left);
                            if j + 1 < n {
                                let seg = Crossing { start, len, lat };
                                let (got, _) = fast.pass(plain, j + 1..n, seg, |p, f, s| {
                                    reference(p, f, s, lat, len)
                                });
                                assert_eq!(got, want.0, "seed {seed} step {step} run {j}");
                            }
                        }
                        if let Some(t) = run.take() {
                            fast.close_through(t);
                        }
                    }
                    _ => {
                        let first = 1 + rng.next(n as u64 - 1) as usize;
                        let end = first + 1 + rng.next((n - first) as u64) as usize;
                        let start = Instant::from_picos(now);
                        let len = Duration::from_picos(rng.next(3) * rng.next(200_000));
                        let lat =
                            Duration::from_picos(if rng.next(20) == 0 { 250_000 } else { 125_000 });
                        let plain = &delays[first..end];
                        if fast.uniform.is_some_and(|u| u.from <= first && end <= u.to) {
                            uniform_passes += 1;
                        }
                        let want = reference(plain, &mut slow[first..end], start, lat, len);
                        let seg = Crossing { start, len, lat };
                        let (got, held) = fast.pass(plain, first..end, seg, |p, f, s| {
                            reference(p, f, s, lat, len)
                        });
                        assert_eq!(got, want.0, "seed {seed} step {step}");
                        // Held up anywhere: later than the hops alone bring it.
                        let free = plain.iter().fold(start, |a, d| {
                            a.saturating_add(Duration::from_picos(*d))
                                .saturating_add(lat)
                        });
                        assert_eq!(held, got > free, "seed {seed} step {step}");
                    }
                }
                for (m, want) in slow.iter().enumerate() {
                    assert_eq!(
                        fast.get(m),
                        Some(*want),
                        "seed {seed} step {step} floor {m}"
                    );
                }
            }
        }
        assert!(uniform_passes > 1_000, "{uniform_passes}");
        assert!(free_sweeps > 1_000, "{free_sweeps}");
        assert!(sent_through > 300, "{sent_through}");
        assert!(in_runs > 1_000, "{in_runs}");
    }
}
