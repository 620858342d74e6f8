//! Why a simulation cannot be built or run.

use sercon_model::vcd_trace::VcdTraceError;

use crate::event_queue::ScheduleError;
use crate::trace::TraceError;

/// A simulation error.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A ring needs a master.
    #[error("no nodes")]
    NoNodes,
    /// More than 254 slaves (sercos-telegrams: addresses 1–254).
    #[error("{0} slaves; at most 254")]
    TooManySlaves(usize),
    /// One host program per node.
    #[error("{hosts} host programs for {nodes} nodes")]
    HostCount {
        /// Programs given.
        hosts: usize,
        /// Nodes configured.
        nodes: usize,
    },
    /// One fibre per node on a ring.
    #[error("{fibres} fibres for a ring of {nodes} nodes")]
    FibreCount {
        /// Fibres given.
        fibres: usize,
        /// Nodes configured.
        nodes: usize,
    },
    /// A fault or trace names a node or segment that does not exist.
    #[error("{what} {index} does not exist")]
    NoSuchTarget {
        /// "node" or "segment".
        what: &'static str,
        /// The index named.
        index: usize,
    },
    /// A controller configuration the model cannot run.
    #[error("node {node}: {source}")]
    Chip {
        /// The node.
        node: usize,
        /// Why.
        source: sercon_model::ConfigError,
    },
    /// A trace could not be written.
    #[error(transparent)]
    Trace(#[from] TraceError),
    /// The VCD could not be written.
    #[error(transparent)]
    Vcd(#[from] VcdTraceError),
    /// The event queue refused an event.
    #[error(transparent)]
    Schedule(#[from] ScheduleError),
    /// A static ring that cannot be laid out.
    #[error("static ring: {0}")]
    Layout(String),
    /// A host program never ended its wakes for long enough that the run could stop between
    /// them (`Simulation::run_until` returns with every host between wakes): the program's
    /// work takes all of its time.
    #[error(
        "node {node}: its host program was at work without a break from {from:?} to {to:?}; \
         a run stops only between a host's wakes (shorter work per wake, or a shorter bus \
         access time)"
    )]
    HostNeverIdle {
        /// The node.
        node: usize,
        /// Where the run was asked to stop.
        from: sercos_wire::time::Instant,
        /// Where it gave up waiting.
        to: sercos_wire::time::Instant,
    },
}
