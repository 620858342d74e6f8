//! `ring.toml`: a full description of a ring (example `examples/ring.toml`).
//!
//! ```toml
//! variant = "816"          # "816" or "410b"
//! baud = 16                # Mbit/s: 2, 4, 8, 16
//! cycle_us = 1000          # tScyc, S-0-0002
//! telegram_type = 7        # S-0-0015: 0-6 standard, 7 configured (default)
//! seconds = 3              # phase-4 operation (a number of seconds or "1500ms")
//! seed = 1
//! return_fibre_m = 10      # last drive → master
//! faults = ["break:3@2s..3s"]
//!
//! [[drive]]
//! address = 1
//! idn_file = "drive1.toml" # relative to this file; default: the standard catalogue
//! fibre_m = 10             # from the node before it
//!
//! [traces]
//! log = "ring.log"         # also vcd, pcap, transcript; relative to the working directory
//! log_segment = 0          # only this fibre in the log (also pcap_segment)
//! vcd = "ring.vcd"
//! vcd_pins = ["INT0", "TxD"]   # default INT0, INT1, CON_CLK, TxD
//! vcd_nodes = ["master", 2]    # default every node
//! ```
//!
//! Every error names the file, line and column (toml's spans), and what is wrong.

use std::fmt;
use std::path::{Path, PathBuf};

use sercon_regs::Variant;
use sercos_wire::time::BitRate;
use serde::Deserialize;
use toml::Spanned;

use super::fault_spec::{FaultSpec, NodeRef};
use super::spec::{DEFAULT_FIBRE_M, DriveSpec, RingSpec};
use super::time_text::parse_duration;

/// Why a ring configuration file was refused: `file:line:column: what`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct ConfigError {
    /// The file.
    pub path: PathBuf,
    /// Line, from 1 (0 when the file could not be read).
    pub line: usize,
    /// Column, from 1 (0 when the file could not be read).
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.path.display(),
            self.line,
            self.column,
            self.message
        )
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileRepr {
    variant: Option<Spanned<String>>,
    baud: Option<Spanned<i64>>,
    cycle_us: Option<Spanned<i64>>,
    telegram_type: Option<Spanned<i64>>,
    seconds: Option<Spanned<toml::Value>>,
    phase_up_limit: Option<Spanned<toml::Value>>,
    seed: Option<Spanned<i64>>,
    drives: Option<Spanned<i64>>,
    return_fibre_m: Option<Spanned<i64>>,
    #[serde(default)]
    faults: Vec<Spanned<String>>,
    #[serde(default)]
    drive: Vec<Spanned<DriveRepr>>,
    traces: Option<TracesRepr>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DriveRepr {
    address: Spanned<i64>,
    idn_file: Option<String>,
    fibre_m: Option<Spanned<i64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TracesRepr {
    log: Option<PathBuf>,
    log_segment: Option<Spanned<i64>>,
    vcd: Option<PathBuf>,
    vcd_pins: Option<Vec<Spanned<String>>>,
    vcd_nodes: Option<Vec<Spanned<toml::Value>>>,
    pcap: Option<PathBuf>,
    pcap_segment: Option<Spanned<i64>>,
    transcript: Option<PathBuf>,
}

/// Line and column (from 1, columns in characters) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset.min(text.len())).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Reads `path` into a ring description.
pub fn load_config(path: &Path) -> Result<RingSpec, ConfigError> {
    let text = std::fs::read_to_string(path).map_err(|e| ConfigError {
        path: path.to_path_buf(),
        line: 0,
        column: 0,
        message: format!("cannot read: {e}"),
    })?;
    parse_config(&text, path)
}

/// Parses TOML `text` (named `path` in errors; IDN files are relative to its folder).
pub fn parse_config(text: &str, path: &Path) -> Result<RingSpec, ConfigError> {
    let at = |offset: usize, message: String| {
        let (line, column) = line_column(text, offset);
        ConfigError {
            path: path.to_path_buf(),
            line,
            column,
            message,
        }
    };
    let file: FileRepr = toml::from_str(text).map_err(|e| {
        at(
            e.span().map_or(0, |s| s.start),
            e.message().trim().to_string(),
        )
    })?;
    let mut spec = RingSpec::default();
    let int = |v: &Spanned<i64>, lo: i64, hi: i64, what: &str| -> Result<i64, ConfigError> {
        let x = *v.get_ref();
        if (lo..=hi).contains(&x) {
            Ok(x)
        } else {
            Err(at(v.span().start, format!("{what} {x} is not {lo}-{hi}")))
        }
    };
    if let Some(v) = &file.variant {
        spec.variant = match v.get_ref().to_ascii_lowercase().as_str() {
            "816" | "sercon816" => Variant::Sercon816,
            "410b" | "sercon410b" => Variant::Sercon410b,
            other => {
                return Err(at(
                    v.span().start,
                    format!("variant {other:?}: expected \"816\" or \"410b\""),
                ));
            }
        };
    }
    if let Some(v) = &file.baud {
        spec.bit_rate = u32::try_from(*v.get_ref())
            .ok()
            .and_then(BitRate::from_mbit)
            .ok_or_else(|| {
                at(
                    v.span().start,
                    format!("baud {}: expected 2, 4, 8 or 16 (Mbit/s)", v.get_ref()),
                )
            })?;
    }
    if let Some(v) = &file.cycle_us {
        spec.cycle_us = int(v, 62, 65_000, "cycle_us")? as u32;
    }
    if let Some(v) = &file.telegram_type {
        // sercos-facts.md S-0-0015: 0-6 standard telegrams, 7 configured.
        spec.telegram_type = int(v, 0, 7, "telegram_type")? as u16;
    }
    let duration = |v: &Spanned<toml::Value>, what: &str| {
        let text = match v.get_ref() {
            toml::Value::Integer(i) => format!("{i}s"),
            toml::Value::Float(f) => format!("{f}s"),
            toml::Value::String(s) => s.clone(),
            _ => String::new(),
        };
        parse_duration(&text).ok_or_else(|| {
            at(
                v.span().start,
                format!("{what}: expected seconds (3, 1.5) or a time such as \"1500ms\""),
            )
        })
    };
    if let Some(v) = &file.seconds {
        spec.run_for = duration(v, "seconds")?;
    }
    if let Some(v) = &file.phase_up_limit {
        spec.phase_up_limit = duration(v, "phase_up_limit")?;
    }
    if let Some(v) = &file.seed {
        spec.seed = int(v, 0, i64::MAX, "seed")? as u64;
    }
    if let Some(v) = &file.return_fibre_m {
        spec.return_fibre_m = int(v, 0, 100_000, "return_fibre_m")? as u32;
    }
    let base = path.parent().unwrap_or(Path::new(""));
    match (&file.drives, file.drive.is_empty()) {
        (Some(n), true) => {
            let n = int(n, 1, sercdrv::master::MAX_DRIVES as i64, "drives")?;
            spec.drives = RingSpec::with_drives(n as u8);
        }
        (Some(n), false) => {
            return Err(at(
                n.span().start,
                "give either drives = N or [[drive]] tables, not both".into(),
            ));
        }
        (None, false) => {
            spec.drives = Vec::new();
            for d in &file.drive {
                let r = d.get_ref();
                let address = int(&r.address, 1, 254, "address")? as u8;
                if spec.drives.iter().any(|e| e.address == address) {
                    return Err(at(
                        r.address.span().start,
                        format!("drive address {address} appears twice"),
                    ));
                }
                let fibre_m = match &r.fibre_m {
                    Some(f) => int(f, 0, 100_000, "fibre_m")? as u32,
                    None => DEFAULT_FIBRE_M,
                };
                let idn_file = r.idn_file.as_ref().map(|f| base.join(f));
                if let Some(f) = &idn_file
                    && !f.is_file()
                {
                    return Err(at(
                        d.span().start,
                        format!("drive {address}: IDN file {} not found", f.display()),
                    ));
                }
                spec.drives.push(DriveSpec {
                    address,
                    idn_file,
                    fibre_m,
                });
            }
            if spec.drives.len() > sercdrv::master::MAX_DRIVES {
                let last = file.drive.last().map_or(0, |d| d.span().start);
                return Err(at(
                    last,
                    format!(
                        "{} drives: the master serves at most {}",
                        spec.drives.len(),
                        sercdrv::master::MAX_DRIVES
                    ),
                ));
            }
        }
        (None, true) => {}
    }
    for f in &file.faults {
        let fault: FaultSpec = f
            .get_ref()
            .parse()
            .map_err(|e: super::fault_spec::FaultSpecError| at(f.span().start, e.message))?;
        spec.faults.push(fault);
    }
    if let Some(t) = file.traces {
        // Fibres are checked against the ring's size with the options (`setup::validate`).
        let fibre = |v: &Option<Spanned<i64>>, what: &str| -> Result<Option<usize>, ConfigError> {
            v.as_ref()
                .map(|v| int(v, 0, 254, what).map(|k| k as usize))
                .transpose()
        };
        spec.traces.log_segment = fibre(&t.log_segment, "log_segment")?;
        spec.traces.pcap_segment = fibre(&t.pcap_segment, "pcap_segment")?;
        spec.traces.vcd_pins = t
            .vcd_pins
            .map(|pins| {
                pins.iter()
                    .map(|p| {
                        super::setup::pin_named(p.get_ref())
                            .map_err(|why| at(p.span().start, format!("vcd_pins: {why}")))
                    })
                    .collect::<Result<Vec<_>, _>>()
            })
            .transpose()?;
        spec.traces.vcd_nodes = t
            .vcd_nodes
            .map(|nodes| {
                nodes
                    .iter()
                    .map(|n| {
                        let text = match n.get_ref() {
                            toml::Value::String(s) => s.clone(),
                            other => other.to_string(),
                        };
                        text.parse::<NodeRef>()
                            .map_err(|e| at(n.span().start, format!("vcd_nodes: {e}")))
                    })
                    .collect::<Result<Vec<_>, _>>()
            })
            .transpose()?;
        spec.traces.log = t.log;
        spec.traces.vcd = t.vcd;
        spec.traces.pcap = t.pcap;
        spec.traces.transcript = t.transcript;
    }
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sercon_model::pins::Pin;

    fn err(text: &str) -> String {
        parse_config(text, Path::new("ring.toml"))
            .expect_err("refused")
            .to_string()
    }

    #[test]
    fn full_file() {
        let spec = parse_config(
            "variant = \"410b\"\nbaud = 4\ncycle_us = 2000\nseconds = 1.5\nseed = 7\n\
             faults = [\"break:2@1s..2s\"]\n[[drive]]\naddress = 5\nfibre_m = 30\n\
             [[drive]]\naddress = 2\n",
            Path::new("ring.toml"),
        )
        .expect("valid");
        assert_eq!(spec.variant, Variant::Sercon410b);
        assert_eq!(spec.bit_rate, BitRate::Mbit4);
        assert_eq!(spec.cycle_us, 2000);
        assert_eq!(spec.run_for, sercos_wire::time::Duration::from_millis(1500));
        assert_eq!(spec.seed, 7);
        assert_eq!(spec.drives.len(), 2);
        assert_eq!((spec.drives[0].address, spec.drives[0].fibre_m), (5, 30));
        assert_eq!(spec.drives[1].fibre_m, DEFAULT_FIBRE_M);
        assert_eq!(spec.faults.len(), 1);
        assert_eq!(
            spec.telegram_type,
            sercdrv::master::TELEGRAM_TYPE_CONFIGURED,
            "default: configured (7)"
        );
    }

    #[test]
    fn telegram_type_is_read_and_checked() {
        // sercos-facts.md S-0-0015: 0-6 standard, 7 configured.
        let spec = parse_config("telegram_type = 3\n", Path::new("ring.toml")).expect("valid");
        assert_eq!(spec.telegram_type, 3);
        assert_eq!(
            err("baud = 16\ntelegram_type = 8\n"),
            "ring.toml:2:17: telegram_type 8 is not 0-7"
        );
    }

    #[test]
    fn errors_name_line_and_column() {
        assert_eq!(
            err("baud = 16\ncycle_us = 5\n"),
            "ring.toml:2:12: cycle_us 5 is not 62-65000"
        );
        assert!(err("baud = 3\n").starts_with("ring.toml:1:8: baud 3"));
        assert!(err("seed = 1\nfaults = [\"break:x@1s\"]\n").starts_with("ring.toml:2:11: "));
        assert!(err("colour = 1\n").starts_with("ring.toml:1:1: unknown field"));
        assert!(err("baud = \n").starts_with("ring.toml:1:"));
        assert!(
            err("[[drive]]\naddress = 1\n[[drive]]\naddress = 1\n").starts_with("ring.toml:4:11: ")
        );
        assert!(err("drives = 2\n[[drive]]\naddress = 1\n").starts_with("ring.toml:1:10: "));
    }

    // Issue 5 "Traces": a VCD of chosen pins of chosen nodes; the fibres of the log and the
    // pcap, as the options give them.
    #[test]
    fn traces_choose_pins_nodes_and_fibres() {
        let spec = parse_config(
            "[traces]\nvcd = \"r.vcd\"\nvcd_pins = [\"int0\", \"TxD\"]\n\
             vcd_nodes = [\"master\", 3]\nlog_segment = 2\npcap_segment = 0\n",
            Path::new("ring.toml"),
        )
        .expect("valid");
        let t = &spec.traces;
        assert_eq!(t.vcd_pins, Some(vec![Pin::Int0, Pin::TxD]));
        assert_eq!(t.vcd_nodes, Some(vec![NodeRef::Master, NodeRef::Drive(3)]));
        assert_eq!((t.log_segment, t.pcap_segment), (Some(2), Some(0)));
        let none =
            parse_config("[traces]\nvcd = \"r.vcd\"\n", Path::new("ring.toml")).expect("valid");
        assert_eq!((none.traces.vcd_pins, none.traces.vcd_nodes), (None, None));
        assert!(
            err("[traces]\nvcd_pins = [\"INT0\", \"INT7\"]\n").starts_with(
                "ring.toml:2:21: vcd_pins: \"INT7\" is no pin of the chip (pins: INT0,"
            ),
            "{}",
            err("[traces]\nvcd_pins = [\"INT0\", \"INT7\"]\n")
        );
        assert_eq!(
            err("[traces]\nvcd_nodes = [1, 255]\n"),
            "ring.toml:2:17: vcd_nodes: \"255\" is neither a drive address (1-254) nor \"master\""
        );
        assert_eq!(
            err("[traces]\nlog_segment = -1\n"),
            "ring.toml:2:15: log_segment -1 is not 0-254"
        );
    }

    #[test]
    fn line_column_counts_characters() {
        assert_eq!(line_column("ab\ncµd", 6), (2, 3));
        assert_eq!(line_column("x", 99), (1, 2));
    }
}
