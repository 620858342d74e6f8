//! A node's own clock: the mapping between the simulation's time and the time of one node's
//! crystal (MCLK), with a frequency error in parts per billion that a fault may change.
//!
//! Each node's controller model runs in its own time (DESIGN.md: time is injected): a node
//! whose MCLK is `e` ppm fast sees `t · (1 + e·10⁻⁶)` where the simulation is at `t`. Slaves
//! therefore really have to synchronise to the MST (410B §4.1 0CH: a slave's cycle follows the
//! received MST). The line's bit times are not scaled (`docs/spec-notes.md`, "Ring simulation").

use sercos_wire::time::Instant;

/// Parts per billion in one.
const PPB: i128 = 1_000_000_000;

/// Largest frequency error accepted, in ppb (±10 %, far beyond any crystal).
pub const MAX_ERROR_PPB: i64 = 100_000_000;

/// One piece of the mapping: from `global` (= `local`) on, the clock runs with `ppb`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Piece {
    global: u64,
    local: u64,
    ppb: i64,
}

/// The piecewise linear mapping between simulation time and a node's local time.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeClock {
    pieces: Vec<Piece>,
    /// Local time equals simulation time at every instant (kept with `pieces`: the
    /// simulation converts times several times per event, and most clocks are exact).
    identity: bool,
}

impl NodeClock {
    /// A clock with a constant error of `ppb` parts per billion (clamped to
    /// ±[`MAX_ERROR_PPB`]) from time 0, where both times are 0.
    pub fn new(ppb: i64) -> Self {
        let ppb = ppb.clamp(-MAX_ERROR_PPB, MAX_ERROR_PPB);
        NodeClock {
            pieces: vec![Piece {
                global: 0,
                local: 0,
                ppb,
            }],
            identity: ppb == 0,
        }
    }

    /// The error in effect at simulation time `t`, in ppb.
    pub fn error_ppb_at(&self, t: Instant) -> i64 {
        self.piece_global(t.as_picos()).ppb
    }

    /// From simulation time `t` on (not before the last change), the clock runs with `ppb`.
    /// A `t` before the last change is taken as that change's time.
    pub fn set_error_ppb(&mut self, t: Instant, ppb: i64) {
        let last = self.pieces.last().map_or(0, |p| p.global);
        let g = t.as_picos().max(last);
        let local = self.to_local(Instant::from_picos(g)).as_picos();
        self.pieces.push(Piece {
            global: g,
            local,
            ppb: ppb.clamp(-MAX_ERROR_PPB, MAX_ERROR_PPB),
        });
        self.identity = self
            .pieces
            .iter()
            .all(|p| p.ppb == 0 && p.local == p.global);
    }

    /// Whether local time equals simulation time at every instant (no error ever set).
    pub fn is_identity(&self) -> bool {
        self.identity
    }

    fn piece_global(&self, g: u64) -> Piece {
        self.piece_where(|p| p.global <= g)
    }

    fn piece_local(&self, l: u64) -> Piece {
        self.piece_where(|p| p.local <= l)
    }

    /// The last piece that has begun by `begun` (the first one if none has).
    fn piece_where(&self, begun: impl Fn(&Piece) -> bool) -> Piece {
        self.pieces
            .iter()
            .rev()
            .find(|p| begun(p))
            .or(self.pieces.first())
            .copied()
            .unwrap_or(Piece {
                global: 0,
                local: 0,
                ppb: 0,
            })
    }

    /// The node's local time at simulation time `t` (rounded down).
    #[inline]
    pub fn to_local(&self, t: Instant) -> Instant {
        if self.identity {
            return t;
        }
        self.to_local_pieces(t)
    }

    /// [`NodeClock::to_local`] through the pieces (kept out of line: most clocks are exact).
    #[inline(never)]
    fn to_local_pieces(&self, t: Instant) -> Instant {
        let g = t.as_picos();
        let p = self.piece_global(g);
        if p.ppb == 0 {
            return Instant::from_picos(p.local.saturating_add(g.saturating_sub(p.global)));
        }
        let dg = i128::from(g.saturating_sub(p.global));
        let dl = dg * (PPB + i128::from(p.ppb)) / PPB;
        Instant::from_picos(clamp_u64(i128::from(p.local) + dl))
    }

    /// The first simulation time at which the node's local time has reached `local`.
    #[inline]
    pub fn to_global(&self, local: Instant) -> Instant {
        if self.identity {
            return local;
        }
        self.to_global_pieces(local)
    }

    /// [`NodeClock::to_global`] through the pieces (kept out of line).
    #[inline(never)]
    fn to_global_pieces(&self, local: Instant) -> Instant {
        let l = local.as_picos();
        let p = self.piece_local(l);
        if p.ppb == 0 {
            return Instant::from_picos(p.global.saturating_add(l.saturating_sub(p.local)));
        }
        let dl = i128::from(l.saturating_sub(p.local));
        let rate = PPB + i128::from(p.ppb);
        // Smallest dg with floor(dg · rate / PPB) >= dl.
        let dg = (dl * PPB + rate - 1) / rate.max(1);
        Instant::from_picos(clamp_u64(i128::from(p.global) + dg))
    }
}

fn clamp_u64(v: i128) -> u64 {
    u64::try_from(v.max(0)).unwrap_or(u64::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_is_the_first_instant() {
        for ppb in [0, 50_000, -50_000, 1, -1, MAX_ERROR_PPB, -MAX_ERROR_PPB] {
            let mut c = NodeClock::new(ppb);
            c.set_error_ppb(Instant::from_picos(7_000_000), -ppb / 2);
            for l in [
                0u64,
                1,
                999,
                62_500,
                6_999_999,
                7_000_001,
                1_000_000_000_000,
            ] {
                let g = c.to_global(Instant::from_picos(l));
                assert!(c.to_local(g).as_picos() >= l, "{ppb} {l}");
                if g.as_picos() > 0 {
                    assert!(c.to_local(Instant::from_picos(g.as_picos() - 1)).as_picos() < l);
                }
            }
        }
    }

    /// The identity shortcut holds exactly while every piece is exact: a clock set to 0 ppm
    /// stays exact; one that ran off by a drift does not come back by a later 0 ppm.
    #[test]
    fn identity_only_while_every_piece_is_exact() {
        let t = Instant::from_picos(123_456_789);
        let mut c = NodeClock::new(0);
        c.set_error_ppb(Instant::from_picos(1_000), 0);
        assert!(c.is_identity());
        assert_eq!((c.to_local(t), c.to_global(t)), (t, t));
        c.set_error_ppb(Instant::from_picos(2_000_000), 50_000);
        c.set_error_ppb(Instant::from_picos(90_000_000), 0);
        assert!(!c.is_identity());
        assert_ne!(c.to_local(t), t);
        assert!(!NodeClock::new(1).is_identity());
    }

    #[test]
    fn a_fast_clock_runs_ahead() {
        let c = NodeClock::new(100_000); // 100 ppm
        assert_eq!(
            c.to_local(Instant::from_picos(1_000_000_000)).as_picos(),
            1_000_100_000
        );
    }
}
