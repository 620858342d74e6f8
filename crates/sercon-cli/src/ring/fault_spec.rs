//! Faults as the user writes them (`--fault` and the `[[fault]]` tables of `ring.toml`):
//!
//! | text | fault |
//! |---|---|
//! | `break:N@T1..T2` | the fibre into drive N (or `master`) is dark from T1, repaired at T2 |
//! | `break:N@T1` | the same, never repaired |
//! | `ber:RATE[:N][@T1[..T2]]` | bit errors with probability RATE per line bit on the fibre into N, or on every fibre |
//! | `power:N@T1[..T2]` | drive N is powered off at T1 and on again at T2 |
//! | `burst:N:BITS@T` | BITS inverted line bits in the first telegram entering N's fibre at T |
//! | `drift:N:PPM@T` | from T the MCLK of drive N (or `master`) runs PPM off |
//! | `distort:N@T1..T2` | the signal into N is distorted beyond the receiver's limit (410B §4.1 2H.12 RDIST) |
//!
//! `N` is a drive address or `master`; times are durations (`2s`, `1.5s`, `300ms`) counted
//! from the first time the master reaches phase 4; without a time a fault acts over the whole
//! phase-4 run.

use sercos_wire::time::Duration;

use super::time_text::{format_duration, parse_duration};

/// A node of the ring as the user names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NodeRef {
    /// The master.
    Master,
    /// The drive at this address.
    Drive(u8),
}

impl std::fmt::Display for NodeRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NodeRef::Master => f.write_str("master"),
            NodeRef::Drive(a) => write!(f, "drive {a}"),
        }
    }
}

impl std::str::FromStr for NodeRef {
    type Err = String;

    /// `master` or a drive address 1-254 (sercos-telegrams.md).
    fn from_str(text: &str) -> Result<NodeRef, String> {
        node(Some(&text))
    }
}

/// What goes wrong.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaultWhat {
    /// The fibre into `into` is dark.
    Break {
        /// The node whose receiver the fibre feeds.
        into: NodeRef,
    },
    /// Random bit errors on the fibre into `into`, or on every fibre.
    BitErrors {
        /// The fibre (by the node it feeds); `None`: every fibre.
        into: Option<NodeRef>,
        /// Probability that a line bit is inverted.
        rate: f64,
    },
    /// One burst of inverted bits in a telegram.
    Burst {
        /// The fibre (by the node it feeds).
        into: NodeRef,
        /// Line bits inverted.
        bits: u32,
    },
    /// The node loses power.
    Power {
        /// The node.
        node: NodeRef,
    },
    /// The node's MCLK runs off frequency.
    Drift {
        /// The node.
        node: NodeRef,
        /// Frequency error, ppm.
        ppm: f64,
    },
    /// The signal into `into` is distorted.
    Distortion {
        /// The fibre (by the node it feeds).
        into: NodeRef,
    },
}

/// A fault with its time, counted from the first time the master reaches phase 4.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultSpec {
    /// What.
    pub what: FaultWhat,
    /// Start.
    pub from: Duration,
    /// End (repair, power on, end of errors); `None`: until the end of the run.
    pub until: Option<Duration>,
    /// The text it was parsed from.
    pub text: String,
}

/// Why a fault text was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("fault {text:?}: {message}")]
pub struct FaultSpecError {
    /// The text.
    pub text: String,
    /// What is wrong.
    pub message: String,
}

impl std::str::FromStr for FaultSpec {
    type Err = FaultSpecError;

    fn from_str(text: &str) -> Result<FaultSpec, FaultSpecError> {
        parse(text).map_err(|message| FaultSpecError {
            text: text.to_string(),
            message,
        })
    }
}

const KINDS: &str = "break, ber, power, burst, drift, distort";

fn parse(text: &str) -> Result<FaultSpec, String> {
    let (body, time) = match text.split_once('@') {
        Some((b, t)) => (b, Some(t)),
        None => (text, None),
    };
    let (from, until) = match time {
        Some(t) => parse_span(t)?,
        None => (Duration::from_picos(0), None),
    };
    let mut parts = body.split(':');
    let kind = parts.next().unwrap_or_default();
    let args: Vec<&str> = parts.collect();
    let need = |n: usize, form: &str| {
        if args.len() == n {
            Ok(())
        } else {
            Err(format!("expected {form}"))
        }
    };
    let what = match kind {
        "break" => {
            need(1, "break:N@T1..T2")?;
            FaultWhat::Break {
                into: node(args.first())?,
            }
        }
        "ber" => {
            if args.is_empty() || args.len() > 2 {
                return Err("expected ber:RATE[:N][@T1..T2]".into());
            }
            let rate = args
                .first()
                .and_then(|r| r.parse::<f64>().ok())
                .filter(|r| r.is_finite() && *r > 0.0 && *r <= 1.0)
                .ok_or("the bit error rate must be a number in (0, 1], e.g. 1e-5")?;
            let into = match args.get(1) {
                Some(n) => Some(node(Some(n))?),
                None => None,
            };
            FaultWhat::BitErrors { into, rate }
        }
        "power" => {
            need(1, "power:N@T1..T2")?;
            let node = node(args.first())?;
            if node == NodeRef::Master {
                return Err("power faults act on drives (the run follows the master)".into());
            }
            if time.is_none() {
                return Err("a power fault needs a time: power:N@T1..T2".into());
            }
            FaultWhat::Power { node }
        }
        "burst" => {
            need(2, "burst:N:BITS@T")?;
            let bits = args
                .get(1)
                .and_then(|b| b.parse::<u32>().ok())
                .filter(|b| *b >= 1)
                .ok_or("BITS must be a whole number ≥ 1")?;
            FaultWhat::Burst {
                into: node(args.first())?,
                bits,
            }
        }
        "drift" => {
            need(2, "drift:N:PPM@T")?;
            let ppm = args
                .get(1)
                .and_then(|p| p.parse::<f64>().ok())
                .filter(|p| p.is_finite() && p.abs() <= 1e6)
                .ok_or("PPM must be a number within ±1000000")?;
            FaultWhat::Drift {
                node: node(args.first())?,
                ppm,
            }
        }
        "distort" => {
            need(1, "distort:N@T1..T2")?;
            FaultWhat::Distortion {
                into: node(args.first())?,
            }
        }
        other => return Err(format!("unknown fault kind {other:?} (known: {KINDS})")),
    };
    Ok(FaultSpec {
        what,
        from,
        until,
        text: text.to_string(),
    })
}

fn node(text: Option<&&str>) -> Result<NodeRef, String> {
    let text = text.copied().unwrap_or_default();
    if text == "master" {
        return Ok(NodeRef::Master);
    }
    // sercos-telegrams.md: drive addresses 1–254.
    match text.parse::<u8>() {
        Ok(a) if (1..=254).contains(&a) => Ok(NodeRef::Drive(a)),
        _ => Err(format!(
            "{text:?} is neither a drive address (1-254) nor \"master\""
        )),
    }
}

fn parse_span(text: &str) -> Result<(Duration, Option<Duration>), String> {
    let time = |t: &str| {
        parse_duration(t).ok_or_else(|| format!("{t:?} is not a time such as 2s, 1.5s or 300ms"))
    };
    match text.split_once("..") {
        Some((a, b)) => {
            let (a, b) = (time(a)?, time(b)?);
            if b <= a {
                return Err(format!(
                    "the end {} is not after the start {}",
                    format_duration(b),
                    format_duration(a)
                ));
            }
            Ok((a, Some(b)))
        }
        None => Ok((time(text)?, None)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(t: &str) -> FaultSpec {
        t.parse().expect("a valid fault")
    }

    #[test]
    fn the_issue_examples() {
        let f = p("break:3@2s..3s");
        assert_eq!(
            f.what,
            FaultWhat::Break {
                into: NodeRef::Drive(3)
            }
        );
        assert_eq!(
            (f.from, f.until),
            (Duration::from_secs(2), Some(Duration::from_secs(3)))
        );
        let f = p("ber:1e-5");
        assert_eq!(
            f.what,
            FaultWhat::BitErrors {
                into: None,
                rate: 1e-5
            }
        );
        assert_eq!((f.from, f.until), (Duration::from_picos(0), None));
        let f = p("power:2@1s..1.5s");
        assert_eq!(
            f.what,
            FaultWhat::Power {
                node: NodeRef::Drive(2)
            }
        );
        assert_eq!(f.until, Some(Duration::from_millis(1500)));
    }

    #[test]
    fn the_other_kinds() {
        assert_eq!(
            p("ber:1e-4:master@1s..2s").what,
            FaultWhat::BitErrors {
                into: Some(NodeRef::Master),
                rate: 1e-4
            }
        );
        assert_eq!(
            p("burst:2:8@1s").what,
            FaultWhat::Burst {
                into: NodeRef::Drive(2),
                bits: 8
            }
        );
        assert_eq!(
            p("drift:1:-50@0s").what,
            FaultWhat::Drift {
                node: NodeRef::Drive(1),
                ppm: -50.0
            }
        );
        assert_eq!(
            p("distort:4@1s..2s").what,
            FaultWhat::Distortion {
                into: NodeRef::Drive(4)
            }
        );
        assert_eq!(p("break:master@1s").until, None);
    }

    #[test]
    fn refusals_name_the_problem() {
        for (text, part) in [
            ("crash:1@1s", "unknown fault kind"),
            ("break:0@1s", "drive address"),
            ("break:255@1s", "drive address"),
            ("break:3@3s..2s", "not after the start"),
            ("break:3@2x", "not a time"),
            ("ber:2", "(0, 1]"),
            ("ber:nan", "(0, 1]"),
            ("power:2", "needs a time"),
            ("power:master@1s", "drives"),
            ("burst:2:0@1s", "BITS"),
            ("break:1:2@1s", "expected"),
        ] {
            let e = text.parse::<FaultSpec>().expect_err(text);
            assert!(e.to_string().contains(part), "{text}: {e}");
        }
    }
}
