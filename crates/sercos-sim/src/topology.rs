//! Topologies: the fibre ring of 410B Fig. 3 and the RS-485 bus of Fig. 4.

use sercos_wire::time::Duration;

/// Propagation delay of light in a fibre, per metre (default; `docs/spec-notes.md`).
pub const DEFAULT_DELAY_PER_METRE: Duration = Duration::from_nanos(5);

/// One fibre of the ring.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fibre {
    /// Length in metres.
    pub length_m: u32,
    /// Delay per metre.
    pub delay_per_m: Duration,
}

impl Fibre {
    /// A fibre of `m` metres at 5 ns/m.
    pub fn metres(m: u32) -> Self {
        Fibre {
            length_m: m,
            delay_per_m: DEFAULT_DELAY_PER_METRE,
        }
    }

    /// The propagation delay from end to end.
    pub fn delay(&self) -> Duration {
        self.delay_per_m.saturating_mul(u64::from(self.length_m))
    }
}

/// How the nodes are connected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Topology {
    /// 410B §1, Fig. 3: master TX → slave 1 → … → slave n → master RX. `fibres[k]` runs
    /// from node k's transmitter to node k + 1's receiver (the last one back to the master);
    /// it is trace segment k.
    Ring {
        /// One per node.
        fibres: Vec<Fibre>,
    },
    /// 410B §1, Fig. 4: every node hears every transmitter after `delay`; a node drives the
    /// bus only while it sends an own telegram; overlapping transmissions are garbled. The
    /// bus is trace segment 0.
    Bus {
        /// Propagation delay between any two nodes.
        delay: Duration,
    },
}

impl Topology {
    /// A ring of `nodes` nodes joined by fibres of `m` metres.
    pub fn ring(nodes: usize, m: u32) -> Self {
        Topology::Ring {
            fibres: vec![Fibre::metres(m); nodes],
        }
    }
}
