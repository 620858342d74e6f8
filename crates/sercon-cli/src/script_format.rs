//! The text format of `sercon script` files: one command per line, `#` starts a comment.
//!
//! ```text
//! # comment
//! write TSCYC0 1000        # register by datasheet name, "0CH"-style or 0x address
//! write 0x0c 0x0423        # numbers: decimal, 0x-hex, or datasheet-style hex with H (0CH)
//! ram 0x0100 0xABCD        # write a dual-port RAM word
//! read VERSION             # print a register
//! readram 0x0100           # print a RAM word
//! expect TCNTLT 0x0010     # fail unless the register reads this value
//! expect 3H 0x0001 mask 0x0001   # ... compare only the bits of the mask
//! expectram 0x0100 0xABCD  # fail unless the RAM word reads this value
//! wait 100us               # advance simulated time by a duration (ps, ns, us, ms, s)
//! until 2ms                # advance simulated time to an instant
//! cyc_clk 1                # drive the input pin CYC_CLK
//! rstn 0                   # drive the reset input RSTN (active low)
//! ```
//!
//! Durations may have a fraction down to picoseconds (`62.5ns`).

use sercon_regs::{Register, Variant};
use sercos_wire::time::Duration;

/// One command of a script.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Step {
    /// Write a control register (word address 0–3FH).
    Write {
        /// Word address.
        address: u8,
        /// Value.
        value: u16,
    },
    /// Write a RAM word.
    Ram {
        /// Word address.
        address: u16,
        /// Value.
        value: u16,
    },
    /// Read and print a control register.
    Read {
        /// Word address.
        address: u8,
    },
    /// Read and print a RAM word.
    ReadRam {
        /// Word address.
        address: u16,
    },
    /// Check a control register.
    Expect {
        /// Word address.
        address: u8,
        /// Expected value (under `mask`).
        value: u16,
        /// Bits compared.
        mask: u16,
    },
    /// Check a RAM word.
    ExpectRam {
        /// Word address.
        address: u16,
        /// Expected value.
        value: u16,
    },
    /// Advance simulated time by a duration.
    Wait(Duration),
    /// Advance simulated time to an instant (given as time since start).
    Until(Duration),
    /// Drive the CYC_CLK input.
    CycClk(bool),
    /// Drive the RSTN input.
    Rstn(bool),
}

/// A parsed line: its 1-based number and the command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Line {
    /// 1-based line number in the file.
    pub number: usize,
    /// The text of the command (comment stripped), for messages.
    pub text: String,
    /// The command.
    pub step: Step,
}

/// What is wrong with one line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParseError {
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub what: String,
}

impl std::fmt::Display for ParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "line {}: {}", self.line, self.what)
    }
}

impl std::error::Error for ParseError {}

/// Parses a whole script for `variant` (register names are checked against it).
pub fn parse(text: &str, variant: Variant) -> Result<Vec<Line>, ParseError> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let body = raw.split('#').next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let step = parse_line(body, variant).map_err(|what| ParseError { line: i + 1, what })?;
        out.push(Line {
            number: i + 1,
            text: body.to_owned(),
            step,
        });
    }
    Ok(out)
}

fn parse_line(body: &str, variant: Variant) -> Result<Step, String> {
    let words: Vec<&str> = body.split_whitespace().collect();
    let (cmd, args) = words.split_first().ok_or("empty line")?;
    let cmd = cmd.to_ascii_lowercase();
    let arity = |n: usize, usage: &str| -> Result<(), String> {
        if args.len() == n {
            Ok(())
        } else {
            Err(format!("`{cmd}` takes {n} argument(s): {usage}"))
        }
    };
    let arg = |i: usize| args.get(i).copied().unwrap_or("");
    match cmd.as_str() {
        "write" => {
            arity(2, "write REGISTER VALUE")?;
            Ok(Step::Write {
                address: register(arg(0), variant)?,
                value: word(arg(1))?,
            })
        }
        "ram" => {
            arity(2, "ram ADDRESS VALUE")?;
            Ok(Step::Ram {
                address: ram_address(arg(0), variant)?,
                value: word(arg(1))?,
            })
        }
        "read" => {
            arity(1, "read REGISTER")?;
            Ok(Step::Read {
                address: register(arg(0), variant)?,
            })
        }
        "readram" => {
            arity(1, "readram ADDRESS")?;
            Ok(Step::ReadRam {
                address: ram_address(arg(0), variant)?,
            })
        }
        "expect" => {
            let mask = match args.len() {
                2 => 0xFFFF,
                4 if arg(2).eq_ignore_ascii_case("mask") => word(arg(3))?,
                _ => return Err("usage: expect REGISTER VALUE [mask MASK]".into()),
            };
            Ok(Step::Expect {
                address: register(arg(0), variant)?,
                value: word(arg(1))?,
                mask,
            })
        }
        "expectram" => {
            arity(2, "expectram ADDRESS VALUE")?;
            Ok(Step::ExpectRam {
                address: ram_address(arg(0), variant)?,
                value: word(arg(1))?,
            })
        }
        "wait" => {
            arity(1, "wait DURATION (e.g. 100us)")?;
            Ok(Step::Wait(duration(arg(0))?))
        }
        "until" => {
            arity(1, "until TIME (e.g. 2ms)")?;
            Ok(Step::Until(duration(arg(0))?))
        }
        "cyc_clk" | "cycclk" => {
            arity(1, "cyc_clk 0|1")?;
            Ok(Step::CycClk(level(arg(0))?))
        }
        "rstn" => {
            arity(1, "rstn 0|1")?;
            Ok(Step::Rstn(level(arg(0))?))
        }
        _ => Err(format!(
            "unknown command `{cmd}` (write, ram, read, readram, expect, expectram, wait, until, \
             cyc_clk, rstn)"
        )),
    }
}

/// A number: decimal, `0x` hex, or datasheet-style hex ending in `H` (`0CH`, `0FFH`).
pub fn number(s: &str) -> Result<u64, String> {
    let bad = || format!("`{s}` is not a number (decimal, 0x1F or 1FH)");
    let clean = s.replace('_', "");
    if let Some(hex) = clean
        .strip_prefix("0x")
        .or_else(|| clean.strip_prefix("0X"))
    {
        u64::from_str_radix(hex, 16).map_err(|_| bad())
    } else if let Some(hex) = clean.strip_suffix(['h', 'H']) {
        u64::from_str_radix(hex, 16).map_err(|_| bad())
    } else {
        clean.parse::<u64>().map_err(|_| bad())
    }
}

fn word(s: &str) -> Result<u16, String> {
    let n = number(s)?;
    u16::try_from(n).map_err(|_| format!("value {s} does not fit in 16 bits"))
}

fn level(s: &str) -> Result<bool, String> {
    match s {
        "0" => Ok(false),
        "1" => Ok(true),
        _ => Err(format!("level `{s}` must be 0 or 1")),
    }
}

fn ram_address(s: &str, variant: Variant) -> Result<u16, String> {
    let n = number(s)?;
    // 410B §1: 1024 words; 816 §2.5: 2048 words.
    if n < u64::from(variant.ram_words()) {
        u16::try_from(n).map_err(|_| format!("RAM address {s} is too large"))
    } else {
        Err(format!(
            "RAM address {s} is beyond the {} words of the {variant:?}",
            variant.ram_words()
        ))
    }
}

/// Normalises a name for comparison: upper case, without `_`.
fn norm(s: &str) -> String {
    s.chars()
        .filter(|c| *c != '_')
        .map(|c| c.to_ascii_uppercase())
        .collect()
}

/// The names a register answers to: its Rust name, its datasheet name(s) and `xxH`.
fn names(r: Register) -> Vec<String> {
    let ds = r.datasheet_name();
    let mut v = vec![
        norm(&format!("{r:?}")),
        norm(ds),
        format!("{:X}H", r.address()),
    ];
    v.push(format!("{:02X}H", r.address()));
    v.extend(
        ds.split(['/', ' ', '(', ')'])
            .filter(|p| !p.is_empty() && *p != "…")
            .map(norm),
    );
    v
}

/// A register word address from a name (`TSCYC0`, `MCLKDIV`, `0CH`, `Ctrl1`) or a number
/// (`0x0c`, `12`; any address 0–3FH, also unused ones).
pub fn register(s: &str, variant: Variant) -> Result<u8, String> {
    let looks_numeric =
        s.starts_with("0x") || s.starts_with("0X") || s.bytes().all(|b| b.is_ascii_digit());
    if looks_numeric {
        let n = number(s)?;
        // 410B §2 (A15-0): A6-1 select the control registers, word addresses 00H–3FH.
        return u8::try_from(n)
            .ok()
            .filter(|a| *a <= 0x3F)
            .ok_or_else(|| format!("register address {s} is beyond 3FH"));
    }
    let want = norm(s);
    let hits: Vec<Register> = Register::ALL
        .into_iter()
        .filter(|r| names(*r).contains(&want))
        .collect();
    match hits.as_slice() {
        [] => Err(format!("unknown register `{s}`")),
        [r] if !r.exists_on(variant) => Err(format!(
            "register {} ({:02X}H) does not exist on the {variant:?}",
            r.datasheet_name(),
            r.address()
        )),
        [r] => Ok(r.address()),
        many => Err(format!(
            "register name `{s}` is ambiguous: {}; use the address (e.g. {:02X}H)",
            many.iter()
                .map(|r| format!("{:02X}H", r.address()))
                .collect::<Vec<_>>()
                .join(", "),
            many.first().map(|r| r.address()).unwrap_or(0)
        )),
    }
}

/// A duration: a number with an optional fraction and a unit `ps`, `ns`, `us`/`µs`, `ms`, `s`
/// (e.g. `62.5ns`, `100us`); exact to the picosecond.
pub fn duration(s: &str) -> Result<Duration, String> {
    let split = s
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '_'))
        .ok_or_else(|| format!("duration `{s}` needs a unit (ps, ns, us, ms, s)"))?;
    let (num, unit) = s.split_at(split);
    let scale: u64 = match unit {
        "ps" => 1,
        "ns" => 1_000,
        "us" | "µs" => 1_000_000,
        "ms" => 1_000_000_000,
        "s" => 1_000_000_000_000,
        _ => return Err(format!("unknown time unit `{unit}` (ps, ns, us, ms, s)")),
    };
    scaled_decimal(num, scale)
        .map(Duration::from_picos)
        .ok_or_else(|| format!("`{s}` is not a whole number of picoseconds or is too long"))
}

/// `num × scale` for a decimal `num` with an optional fraction, if exact and in range.
pub fn scaled_decimal(num: &str, scale: u64) -> Option<u64> {
    let num = num.replace('_', "");
    let (int, frac) = num.split_once('.').unwrap_or((&num, ""));
    if int.is_empty() && frac.is_empty() {
        return None;
    }
    let int_v: u64 = if int.is_empty() { 0 } else { int.parse().ok()? };
    let mut total = int_v.checked_mul(scale)?;
    let mut place = scale;
    for c in frac.chars() {
        let d = u64::from(c.to_digit(10)?);
        if place % 10 != 0 {
            // A digit below the resolution: only zeros are allowed.
            if d != 0 {
                return None;
            }
            continue;
        }
        place /= 10;
        total = total.checked_add(d.checked_mul(place)?)?;
    }
    Some(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(number("62"), Ok(62));
        assert_eq!(number("0x0c"), Ok(12));
        assert_eq!(number("0CH"), Ok(12));
        assert_eq!(number("0FFh"), Ok(255));
        assert!(number("zz").is_err());
        assert!(word("0x10000").is_err());
    }

    #[test]
    fn durations_exact_to_the_picosecond() {
        assert_eq!(duration("62.5ns"), Ok(Duration::from_picos(62_500)));
        assert_eq!(duration("100us"), Ok(Duration::from_micros(100)));
        assert_eq!(duration("2ms"), Ok(Duration::from_millis(2)));
        assert_eq!(duration("1.5s"), Ok(Duration::from_millis(1_500)));
        assert_eq!(
            duration("0.0005ns"),
            Err("`0.0005ns` is not a whole number of picoseconds or is too long".into())
        );
        assert!(duration("100").is_err());
        assert!(duration("100 parsecs").is_err());
        assert!(duration("99999999999999999999s").is_err());
        assert!(duration(".s").is_err());
    }

    #[test]
    fn register_names() {
        let v = Variant::Sercon816;
        assert_eq!(register("TSCYC0", v), Ok(0x0F));
        assert_eq!(register("tscyc0", v), Ok(0x0F));
        assert_eq!(register("MCLKDIV", v), Ok(0x0E));
        assert_eq!(register("0CH", v), Ok(0x0C));
        assert_eq!(register("1H", v), Ok(0x01));
        assert_eq!(register("Ctrl0C", v), Ok(0x0C));
        assert_eq!(register("0x3f", v), Ok(0x3F));
        assert_eq!(register("NDIVCLK", v), Ok(0x20));
        assert!(register("0x40", v).is_err());
        assert!(register("NOPE", v).is_err());
        // 816 §2.11.2: 28H–2AH are new on the 816.
        assert_eq!(register("TWDOG", v), Ok(0x2A));
        assert!(register("TWDOG", Variant::Sercon410b).is_err());
    }

    #[test]
    fn lines_and_errors() {
        let text = "# head\nwrite TSCYC0 62 # c\n\nwait 1ms\nexpect 3H 1 mask 1\nbogus 1\n";
        let err = parse(text, Variant::Sercon816).expect_err("line 6 is bad");
        assert_eq!(err.line, 6);
        assert!(err.what.contains("unknown command"));
        let ok = parse(&text.replace("bogus 1", "cyc_clk 1"), Variant::Sercon816).expect("parses");
        assert_eq!(ok.len(), 4);
        assert_eq!(ok[0].number, 2);
        assert_eq!(
            ok[0].step,
            Step::Write {
                address: 0x0F,
                value: 62
            }
        );
        assert_eq!(
            ok[2].step,
            Step::Expect {
                address: 3,
                value: 1,
                mask: 1
            }
        );
        assert!(parse("write TSCYC0", Variant::Sercon816).is_err());
        assert!(parse("ram 0x800 1", Variant::Sercon816).is_err());
        assert!(parse("ram 0x400 1", Variant::Sercon410b).is_err());
        assert!(parse("rstn 2", Variant::Sercon816).is_err());
    }
}
