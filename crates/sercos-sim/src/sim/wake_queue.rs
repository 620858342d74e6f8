//! The simulation's own queue: at most one pending wake per node, kept in an indexed binary
//! heap (a new wake moves the node's entry up or down instead of leaving a cancelled key
//! behind), and the fault events, all known when the simulation is built, in one sorted list.
//!
//! It hands out events in exactly the order of the general [`crate::event_queue::EventQueue`]
//! with fault `i` as component `i` and node `j` as component `m + j` (`m` faults; DESIGN.md:
//! the same configuration gives the same run): earlier time first; at the same time the
//! lower component, so every fault before every node (a fault at an instant applies before
//! what the nodes do then); a fault's start before its end. A node has
//! one wake at a time, so (time, node) is unique and no sequence number is needed.
//!
//! A node wake handed out by [`WakeQueue::pop_until`] stays at the heap's root until the
//! next operation: the simulation almost always sets that node's next wake first, and a
//! new key at the root is one sift down, where taking the root out and inserting the new
//! key again cost a sift down and a sift up. Any other operation takes it out first.
//!
//! Parked wakes ([`WakeQueue::park`], the placeholders of `Simulation::park`) are kept out of
//! the heap, one time per node, with a lower bound of their smallest key: every slave of an
//! intact ring is parked again after each telegram of the master, before its placeholder
//! is reached, so a heap entry would be moved per slave and pass for nothing. The bound is
//! made exact (one scan of the nodes) only when it could come before the heap's first key
//! or is asked for; events come out in the same (time, node) order as with one heap.

use sercos_wire::time::Instant;

use super::Ev;

/// `pos` of a node without a pending wake.
const ABSENT: u32 = u32::MAX;

/// `parked` entry of a node without a parked wake, and `parked_min` without any.
const NOT_PARKED: Key = Key::MAX;

/// A heap entry: the wake's time in ps above the node's index, so that one comparison orders
/// by (time, node).
type Key = u128;

fn key(t: Instant, node: u32) -> Key {
    (u128::from(t.as_picos()) << 32) | u128::from(node)
}

fn key_time(k: Key) -> u64 {
    // The upper bits hold a u64: nothing is cut off.
    (k >> 32) as u64
}

fn key_node(k: Key) -> u32 {
    // The lower 32 bits are the node.
    k as u32
}

/// Node wakes and fault events in the simulation's deterministic order.
#[derive(Debug, Clone, Default)]
pub(super) struct WakeQueue {
    /// Min-heap of (time, node) keys.
    heap: Vec<Key>,
    /// Where each node's entry is in `heap` ([`ABSENT`] without one).
    pos: Vec<u32>,
    /// Fault events sorted by (time, fault, start before end).
    faults: Vec<(u64, Ev)>,
    /// The next fault event not yet handed out.
    next_fault: usize,
    /// A node whose wake [`WakeQueue::pop_until`] handed out while its entry still sits at
    /// the heap's root (see the module notes).
    popped: Option<usize>,
    /// Each node's parked wake as its key ([`NOT_PARKED`] without one); a node has a heap
    /// entry or a parked wake or neither.
    parked: Vec<Key>,
    /// No parked key is smaller ([`NOT_PARKED`]: no node is parked).
    parked_min: Key,
    /// `parked_min` is a parked node's key (or [`NOT_PARKED`] with none parked).
    parked_exact: bool,
}

impl WakeQueue {
    /// A queue for `nodes` nodes and the given fault events (time, `FaultStart`/`FaultEnd`),
    /// listed per fault in the order they were scheduled.
    pub(super) fn new(nodes: usize, faults: Vec<(Instant, Ev)>) -> Self {
        let mut faults: Vec<(u64, Ev)> =
            faults.into_iter().map(|(t, e)| (t.as_picos(), e)).collect();
        // Stable: a fault's start (listed first) stays before its end at the same time.
        faults.sort_by_key(|(t, e)| {
            (
                *t,
                match e {
                    Ev::FaultStart(i) | Ev::FaultEnd(i) => *i,
                    Ev::Node(_) => 0,
                },
            )
        });
        WakeQueue {
            heap: Vec::with_capacity(nodes),
            pos: vec![ABSENT; nodes],
            faults,
            next_fault: 0,
            popped: None,
            parked: vec![NOT_PARKED; nodes],
            parked_min: NOT_PARKED,
            parked_exact: true,
        }
    }

    /// Takes node `j`'s parked wake, if any (the bound stays a bound).
    #[inline]
    fn unpark(&mut self, j: usize) {
        if let Some(p) = self.parked.get_mut(j)
            && *p != NOT_PARKED
        {
            if *p == self.parked_min {
                self.parked_exact = false;
            }
            *p = NOT_PARKED;
        }
    }

    /// The smallest parked key, made exact by a scan if it was only a bound.
    fn parked_first(&mut self) -> Key {
        if !self.parked_exact {
            self.parked_min = self.parked.iter().copied().min().unwrap_or(NOT_PARKED);
            self.parked_exact = true;
        }
        self.parked_min
    }

    /// The first key of the heap and the parked wakes (the parked bound made exact when it
    /// could come first), and whether it is a parked one.
    #[inline]
    fn first_wake(&mut self) -> Option<(Key, bool)> {
        let heap = self.heap.first().copied().unwrap_or(NOT_PARKED);
        if self.parked_min >= heap {
            // Every parked key is above the heap's first (`NOT_PARKED`: none parked).
            return (heap != NOT_PARKED).then_some((heap, false));
        }
        let parked = self.parked_first();
        if parked < heap {
            Some((parked, true))
        } else {
            (heap != NOT_PARKED).then_some((heap, false))
        }
    }

    /// Sets node `j`'s one pending wake to `at` as a parked one (replacing any other): kept
    /// out of the heap (module notes).
    pub(super) fn park(&mut self, j: usize, at: Instant) {
        let Ok(node) = u32::try_from(j) else {
            return;
        };
        let k = key(at, node);
        if self.popped == Some(j) {
            self.popped = None;
            self.remove_entry(j);
        } else {
            self.settle_popped();
            if self.pos.get(j).is_some_and(|p| *p != ABSENT) {
                self.remove_entry(j);
            }
        }
        let Some(p) = self.parked.get_mut(j) else {
            return;
        };
        if *p == self.parked_min {
            self.parked_exact = false;
        }
        *p = k;
        if k < self.parked_min {
            // Below every parked key (and below the bound): the smallest.
            self.parked_min = k;
            self.parked_exact = true;
        }
    }

    /// Takes out the entry of a node handed out by `pop_until`, if still there.
    #[inline]
    fn settle_popped(&mut self) {
        if let Some(j) = self.popped.take() {
            self.remove_entry(j);
        }
    }

    /// The time of the next event, if any (tests: the order against the general queue).
    #[cfg(test)]
    pub(super) fn peek_time(&mut self) -> Option<Instant> {
        self.settle_popped();
        let wake = self.first_wake().map(|(k, _)| key_time(k));
        let fault = self.faults.get(self.next_fault).map(|e| e.0);
        let t = match (wake, fault) {
            (Some(a), Some(b)) => a.min(b),
            (a, b) => a.or(b)?,
        };
        Some(Instant::from_picos(t))
    }

    /// The time of the next node wake, if any.
    pub(super) fn peek_wake_time(&mut self) -> Option<Instant> {
        self.settle_popped();
        self.first_wake()
            .map(|(k, _)| Instant::from_picos(key_time(k)))
    }

    /// The time of the next fault event, if any.
    pub(super) fn peek_fault_time(&self) -> Option<Instant> {
        self.faults
            .get(self.next_fault)
            .map(|e| Instant::from_picos(e.0))
    }

    /// Takes the next event if it happens at or before `limit`.
    pub(super) fn pop_until(&mut self, limit: Instant) -> Option<(Instant, Ev)> {
        self.settle_popped();
        let limit = limit.as_picos();
        let wake = self.first_wake().filter(|(k, _)| key_time(*k) <= limit);
        let fault = self
            .faults
            .get(self.next_fault)
            .copied()
            .filter(|e| e.0 <= limit);
        match (wake, fault) {
            // At the same time every fault (component i) comes before any node (m + j): a
            // fault at `t` applies before what the nodes do at `t` (spec-notes "Faults: exact
            // accounting", same-instant rule).
            (Some((k, parked)), f) if f.is_none_or(|f| key_time(k) < f.0) => {
                let j = key_node(k) as usize;
                if parked {
                    // The smallest parked key: the bound stays a bound.
                    if let Some(p) = self.parked.get_mut(j) {
                        *p = NOT_PARKED;
                    }
                    self.parked_exact = false;
                } else {
                    // Left at the root until the next operation (module notes).
                    self.popped = Some(j);
                }
                Some((Instant::from_picos(key_time(k)), Ev::Node(j)))
            }
            (_, Some((t, e))) => {
                self.next_fault += 1;
                Some((Instant::from_picos(t), e))
            }
            _ => None,
        }
    }

    /// Sets node `j`'s one pending wake to `at` (replacing any earlier one).
    pub(super) fn set(&mut self, j: usize, at: Instant) {
        self.unpark(j);
        if self.popped == Some(j) {
            // Its entry is at the root: the new key moves down from there (or stays).
            self.popped = None;
        } else {
            self.settle_popped();
        }
        let (Some(p), Ok(node)) = (self.pos.get(j).copied(), u32::try_from(j)) else {
            return;
        };
        let k = key(at, node);
        if p == ABSENT {
            let i = self.heap.len();
            self.heap.push(k);
            self.sift_up(i, k);
        } else if let Some(&old) = self.heap.get(p as usize) {
            if k < old {
                self.sift_up(p as usize, k);
            } else {
                self.sift_down(p as usize, k);
            }
        }
    }

    /// Removes node `j`'s pending wake, if any.
    pub(super) fn remove(&mut self, j: usize) {
        self.unpark(j);
        if self.popped == Some(j) {
            self.popped = None;
        } else {
            self.settle_popped();
        }
        self.remove_entry(j);
    }

    /// Removes node `j`'s entry from the heap, if it has one.
    fn remove_entry(&mut self, j: usize) {
        let Some(p) = self.pos.get_mut(j) else {
            return;
        };
        if *p == ABSENT {
            return;
        }
        let i = *p as usize;
        *p = ABSENT;
        let Some(last) = self.heap.pop() else {
            return;
        };
        if i < self.heap.len() {
            // The former last entry fills the gap at `i`: it may belong above or below.
            if self.heap.get(i).is_some_and(|gone| last < *gone) {
                self.sift_up(i, last);
            } else {
                self.sift_hole_down(i, last);
            }
        }
    }

    /// Puts `k` at `i` and records it.
    fn put(&mut self, i: usize, k: Key) {
        if let Some(slot) = self.heap.get_mut(i) {
            *slot = k;
        }
        if let Some(p) = self.pos.get_mut(key_node(k) as usize) {
            // `i` indexes the heap, which holds at most one entry per node (`u32` many).
            *p = i as u32;
        }
    }

    /// Moves `k`, to be placed at `i`, up past larger parents.
    fn sift_up(&mut self, i: usize, k: Key) {
        self.sift_up_to(i, k, 0);
    }

    /// Moves `k`, to be placed at `i`, up past larger parents but not above `top`.
    #[inline]
    fn sift_up_to(&mut self, mut i: usize, k: Key, top: usize) {
        while i > top {
            let parent = (i - 1) / 2;
            match self.heap.get(parent).copied() {
                Some(pk) if k < pk => {
                    self.put(i, pk);
                    i = parent;
                }
                _ => break,
            }
        }
        self.put(i, k);
    }

    /// The smaller child of `i` and its key, `None` at a leaf.
    #[inline]
    fn smaller_child(&self, i: usize) -> Option<(usize, Key)> {
        let l = 2 * i + 1;
        let &lk = self.heap.get(l)?;
        Some(match self.heap.get(l + 1) {
            Some(&rk) if rk < lk => (l + 1, rk),
            _ => (l, lk),
        })
    }

    /// Moves `k`, to be placed at `i`, down past smaller children (a wake moved a little
    /// later stays near where it was).
    fn sift_down(&mut self, mut i: usize, k: Key) {
        while let Some((c, ck)) = self.smaller_child(i) {
            if ck >= k {
                break;
            }
            self.put(i, ck);
            i = c;
        }
        self.put(i, k);
    }

    /// Places `k` (the heap's former last entry) at `i` or below: the hole at `i` first
    /// goes down to a leaf along the smaller children (one comparison a level), then `k`
    /// rises from there (it came from the bottom and rarely rises far).
    fn sift_hole_down(&mut self, mut i: usize, k: Key) {
        let start = i;
        while let Some((c, ck)) = self.smaller_child(i) {
            self.put(i, ck);
            i = c;
        }
        self.sift_up_to(i, k, start);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::event_queue::{ComponentId, EventQueue};
    use crate::sim::test_lcg::Lcg;

    /// The wake queue gives the same events in the same order as the general event queue
    /// used the way the simulation used it (one wake per node, cancel and reschedule).
    #[test]
    fn same_order_as_the_general_event_queue() {
        for seed in 0..40 {
            let mut rng = Lcg(seed);
            let nodes = 1 + rng.next(20) as usize;
            let mut general: EventQueue<Ev> = EventQueue::new();
            let mut fault_events = Vec::new();
            for i in 0..rng.next(4) as usize {
                let at = Instant::from_picos(rng.next(50));
                // Faults first at the same time: components 0..4, nodes after them.
                let target = ComponentId(i as u32);
                general.schedule(at, target, Ev::FaultStart(i)).ok();
                fault_events.push((at, Ev::FaultStart(i)));
                if rng.next(2) == 0 {
                    let end = Instant::from_picos(at.as_picos() + rng.next(3));
                    general.schedule(end, target, Ev::FaultEnd(i)).ok();
                    fault_events.push((end, Ev::FaultEnd(i)));
                }
            }
            let mut wakes = WakeQueue::new(nodes, fault_events);
            let mut handles = vec![None; nodes];
            let mut now = 0u64;
            for _ in 0..400 {
                if rng.next(3) == 0 {
                    let limit = Instant::from_picos(now + rng.next(10));
                    let a = general.pop_until(limit).map(|e| (e.time, e.payload));
                    let b = wakes.pop_until(limit);
                    assert_eq!(a, b, "seed {seed}");
                    if let Some((t, Ev::Node(j))) = a {
                        handles[j] = None;
                        now = t.as_picos();
                    } else if let Some((t, _)) = a {
                        now = t.as_picos();
                    }
                } else {
                    let j = rng.next(nodes as u64) as usize;
                    if let Some(h) = handles[j].take() {
                        general.cancel(h);
                    }
                    if rng.next(5) == 0 {
                        wakes.remove(j);
                    } else {
                        let at = Instant::from_picos(now + rng.next(30));
                        handles[j] = general
                            .schedule(at, ComponentId(4 + j as u32), Ev::Node(j))
                            .ok();
                        // Parked or in the heap: the same order either way.
                        if rng.next(2) == 0 {
                            wakes.park(j, at);
                        } else {
                            wakes.set(j, at);
                        }
                    }
                }
                assert_eq!(general.peek_time(), wakes.peek_time(), "seed {seed}");
            }
        }
    }

    /// A node handed out by `pop_until` has no wake any more, whatever comes next: a new
    /// wake for it (moved down from the root), another node's wake, a removal, a peek.
    #[test]
    fn a_popped_node_has_no_wake_left() {
        let t = Instant::from_picos;
        let mut q = WakeQueue::new(4, Vec::new());
        for (j, at) in [(0, 5), (1, 7), (2, 6), (3, 9)] {
            q.set(j, t(at));
        }
        assert_eq!(q.pop_until(t(100)), Some((t(5), Ev::Node(0))));
        // Its new wake goes past two others.
        q.set(0, t(8));
        assert_eq!(q.pop_until(t(100)), Some((t(6), Ev::Node(2))));
        // Another node's wake first: node 2's old entry must not come back.
        q.set(1, t(6));
        assert_eq!(q.peek_time(), Some(t(6)));
        assert_eq!(q.pop_until(t(100)), Some((t(6), Ev::Node(1))));
        // Removing the popped node, then popping on.
        q.remove(1);
        assert_eq!(q.pop_until(t(100)), Some((t(8), Ev::Node(0))));
        assert_eq!(q.peek_wake_time(), Some(t(9)));
        assert_eq!(q.pop_until(t(8)), None);
        assert_eq!(q.pop_until(t(9)), Some((t(9), Ev::Node(3))));
        assert_eq!(q.pop_until(t(100)), None);
        assert_eq!(q.peek_time(), None);
    }
}
