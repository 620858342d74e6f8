//! End-to-end test of `sercon script`: runs the shipped example on the binary, reads the VCD
//! back and checks CON_CLK and DIV_CLK edges at the programmed times (410B §4.1 0CH.5, 1AH,
//! 1BH: CON_CLK active from TINT0 to TINT1; 1EH–20H: DIV_CLK first pulse at TDIVCLK, then
//! every DTDIVCLK, NDIVCLK pulses, 1 µs wide (410B §2 DIV_CLK)).

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::Command;

fn sercon() -> Command {
    Command::new(env!("CARGO_BIN_EXE_sercon"))
}

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/scripts/con_clk_div_clk.scr")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sercon-script-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// Minimal VCD reader for 1-bit wires: name → list of (time, level), and the timescale line.
fn read_vcd(text: &str) -> (String, HashMap<String, Vec<(u64, bool)>>) {
    let mut names: HashMap<String, String> = HashMap::new(); // id → name
    let mut timescale = String::new();
    let mut out: HashMap<String, Vec<(u64, bool)>> = HashMap::new();
    let mut t = 0u64;
    for line in text.lines().map(str::trim) {
        let words: Vec<&str> = line.split_whitespace().collect();
        if line.starts_with("$timescale") {
            timescale = words.get(1..3).map(|w| w.join(" ")).unwrap_or_default();
        } else if line.starts_with("$var") {
            if let (Some(id), Some(name)) = (words.get(3), words.get(4)) {
                names.insert((*id).to_owned(), (*name).to_owned());
            }
        } else if let Some(ts) = line.strip_prefix('#') {
            t = ts.parse().expect("timestamp");
        } else if let Some(rest) = line.strip_prefix(['0', '1']) {
            if let Some(name) = names.get(rest) {
                out.entry(name.clone())
                    .or_default()
                    .push((t, line.starts_with('1')));
            }
        }
    }
    (timescale, out)
}

fn rises(edges: &[(u64, bool)]) -> Vec<u64> {
    edges.iter().skip(1).filter(|e| e.1).map(|e| e.0).collect()
}
fn falls(edges: &[(u64, bool)]) -> Vec<u64> {
    edges.iter().skip(1).filter(|e| !e.1).map(|e| e.0).collect()
}

#[test]
fn example_writes_con_clk_and_div_clk_at_the_programmed_times() {
    let vcd = tmp("con_clk_div_clk.vcd");
    let out = sercon()
        .arg("script")
        .arg(example())
        .args(["--variant", "816", "--mclk-mhz", "32", "--timescale", "ns"])
        .args(["--pins", "CON_CLK,DIV_CLK,INT0"])
        .arg("--vcd")
        .arg(&vcd)
        .output()
        .expect("sercon runs");
    assert!(
        out.status.success(),
        "sercon script failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&vcd).expect("VCD written");
    let (timescale, wires) = read_vcd(&text);
    assert_eq!(timescale, "1 ns");
    let con = wires.get("CON_CLK").expect("CON_CLK wire");
    let div = wires.get("DIV_CLK").expect("DIV_CLK wire");
    // Initial levels at time 0: both outputs inactive (1-active polarity, reset).
    assert_eq!(con.first(), Some(&(0, false)));
    assert_eq!(div.first(), Some(&(0, false)));

    // The script programs a 1000 µs cycle, CON_CLK from 100 µs to 300 µs, DIV_CLK at 50 µs
    // then every 200 µs, 4 pulses, and runs 3 cycles.
    let con_up = rises(con);
    let con_down = falls(con);
    assert_eq!(con_up.len(), 3, "CON_CLK rises: {con_up:?}");
    assert_eq!(con_down.len(), 3, "CON_CLK falls: {con_down:?}");
    // The cycle starts on the first µs tick after CYCSTART (t = 0): within 1 µs.
    let start = con_up[0] - 100_000;
    assert!(start <= 1_000, "first cycle starts at {start} ns");
    for k in 0..3u64 {
        let c = start + k * 1_000_000;
        assert_eq!(con_up[k as usize], c + 100_000, "TINT0 in cycle {k}");
        assert_eq!(con_down[k as usize], c + 300_000, "TINT1 in cycle {k}");
    }
    let div_up = rises(div);
    let div_down = falls(div);
    assert_eq!(div_up.len(), 12, "DIV_CLK rises: {div_up:?}");
    for (i, (&up, &down)) in div_up.iter().zip(&div_down).enumerate() {
        let k = i as u64 / 4;
        let n = i as u64 % 4;
        assert_eq!(
            up,
            start + k * 1_000_000 + 50_000 + n * 200_000,
            "DIV_CLK pulse {i}"
        );
        assert_eq!(down - up, 1_000, "DIV_CLK pulse {i} is 1 µs wide");
    }
}

#[test]
fn errors_name_file_and_line() {
    let script = tmp("bad.scr");
    std::fs::write(&script, "write TSCYC0 1000\nwrite NOSUCHREG 1\n").expect("write");
    let out = sercon()
        .arg("script")
        .arg(&script)
        .output()
        .expect("sercon runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.scr:2"), "{err}");
    assert!(err.contains("NOSUCHREG"), "{err}");
}

#[test]
fn failed_expect_is_an_error_with_values() {
    let script = tmp("expect.scr");
    std::fs::write(
        &script,
        "# 816 §2.11.1.1: VERSION = 0010H\nexpect VERSION 0x0010\nexpect VERSION 0x0002\n",
    )
    .expect("write");
    let out = sercon()
        .arg("script")
        .arg(&script)
        .output()
        .expect("sercon runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("expect.scr:3"), "{err}");
    assert!(err.contains("0x0010"), "{err}");
}

#[test]
fn read_prints_the_value() {
    let script = tmp("read.scr");
    std::fs::write(&script, "read VERSION\n").expect("write");
    let out = sercon()
        .args(["script", "--variant", "410b"])
        .arg(&script)
        .output()
        .expect("sercon runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // ERRATA "0H VERSION": 0002H on the SERCON410B.
    assert!(String::from_utf8_lossy(&out.stdout).contains("= 0x0002"));
}
