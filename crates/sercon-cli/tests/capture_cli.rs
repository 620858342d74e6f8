//! `sercon capture decode` / `transcript` against the real line captures in
//! `../shared/captures/` (README there: Beckhoff FC7502 master, four TC2000R drives, phase 0 to
//! 4), and against files that are not captures.

// A failed unwrap here is a failed test (clippy.toml allows it in #[test] fns; helpers too).
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::process::Command;

fn captures_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/captures");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: {} is absent; the capture tests need the shared real-data folder",
            dir.display()
        );
        None
    }
}

fn sercon(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_sercon"))
        .args(args)
        .output()
        .expect("run sercon");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn json_lines(s: &str) -> Vec<serde_json::Value> {
    s.lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect()
}

/// Captures README: the file header's telegram count (8429 and 9632) equals the telegrams the
/// signal holds, every one with a valid FCS; MSTs step through phases 0, 1, 2, 3, 4.
#[test]
fn decode_counts_fcs_and_phases() {
    let Some(dir) = captures_dir() else { return };
    for (name, count) in [
        ("tc2000r-phaseup.nrzi", 8429),
        ("tc2000r-phaseup-2.nrzi", 9632),
    ] {
        let path = dir.join(name);
        let (ok, out, err) = sercon(&["capture", "decode", "--json", path.to_str().unwrap()]);
        assert!(ok, "{name}: {err}");
        let v = json_lines(&out);
        assert_eq!(v.len(), count, "{name}");
        let mut phases = Vec::new();
        for (i, t) in v.iter().enumerate() {
            assert_eq!(t["index"], i);
            assert_eq!(t["fcs_ok"], true, "{name} #{i}");
            assert!(t["bit"].as_u64().is_some());
            let kind = t["kind"].as_str().unwrap();
            assert!(
                kind == "MST" || kind == "MDT",
                "{name} #{i}: master sends MST and MDT only"
            );
            if kind == "MST" {
                assert_eq!(t["address"], 255, "sercos-telegrams.md: MST ADR = 255");
                let p = t["phase"].as_u64().unwrap();
                if phases.last() != Some(&p) {
                    phases.push(p);
                }
            }
        }
        assert_eq!(phases, [0, 1, 2, 3, 4], "{name}: phase sequence");
        // Bit offsets only grow.
        assert!(
            v.windows(2)
                .all(|w| w[0]["bit"].as_u64() < w[1]["bit"].as_u64())
        );
    }
}

/// The text form names each telegram and ends with a summary.
#[test]
fn decode_text_summary() {
    let Some(dir) = captures_dir() else { return };
    let path = dir.join("tc2000r-phaseup.nrzi");
    let (ok, out, _) = sercon(&["capture", "decode", path.to_str().unwrap()]);
    assert!(ok);
    let last = out.lines().last().unwrap();
    assert!(
        last.starts_with(
            "8429 telegrams: 4277 MST, 4152 MDT, 0 AT; 8429 with a valid FCS, 0 in error"
        ),
        "{last}"
    );
    assert!(last.ends_with("phases 0 → 1 → 2 → 3 → 4"), "{last}");
    // Phase 1: the master addresses drive 1 with control word 0001H (MHS only).
    assert!(out.contains("MDT     1  control 0001H (MHS)  service 0000H  FCS ok"));
}

fn transcript(name: &str) -> Option<Vec<serde_json::Value>> {
    let dir = captures_dir()?;
    let path = dir.join(name);
    let (ok, out, err) = sercon(&["capture", "transcript", "--json", path.to_str().unwrap()]);
    assert!(ok, "{err}");
    Some(json_lines(&out))
}

fn writes<'a>(v: &'a [serde_json::Value], drive: u64, idn: &str) -> Vec<&'a serde_json::Value> {
    v.iter()
        .filter(|e| e["op"] == "write" && e["drive"] == drive && e["idn"] == idn)
        .collect()
}

/// Hand-checked against the capture's MDTs and sercos-telegrams.md (control word bits 5–0):
/// in phase 2 the master writes the cycle times (S-0-0001, S-0-0002 = 2000 µs, the 2 ms
/// cycle of sercos-facts.md), each drive's AT start time S-0-0006, the MDT record position
/// S-0-0009 (1, 9, 17, 25: four 8-byte records after ADR) and length S-0-0010 = 32, telegram
/// type 7 (S-0-0015) with configuration lists S-0-0016 / S-0-0024 as variable-length data
/// (current length, maximum length in bytes, then IDNs: sercos-facts.md).
#[test]
fn transcript_phase2_writes() {
    let Some(v) = transcript("tc2000r-phaseup.nrzi") else {
        return;
    };
    let order: Vec<&str> = v
        .iter()
        .filter(|e| e["op"] == "write" && e["drive"] == 1 && e["phase"] == 2)
        .map(|e| e["idn"].as_str().unwrap())
        .collect();
    // Issue order of the master's phase-2 writes (DEVELOPERS issue "host software").
    assert_eq!(
        &order[..11],
        [
            "S-0-0001", "S-0-0002", "S-0-0006", "S-0-0089", "S-0-0008", "S-0-0007", "S-0-0009",
            "S-0-0010", "S-0-0015", "S-0-0016", "S-0-0024"
        ]
    );
    let one = |d, idn| writes(&v, d, idn)[0]["words"].clone();
    assert_eq!(one(1, "S-0-0001"), serde_json::json!([2000]));
    assert_eq!(one(1, "S-0-0002"), serde_json::json!([2000]));
    assert_eq!(one(1, "S-0-0006"), serde_json::json!([92]));
    assert_eq!(one(2, "S-0-0006"), serde_json::json!([336]));
    for (d, pos) in [(1, 1), (2, 9), (3, 17), (4, 25)] {
        assert_eq!(one(d, "S-0-0009"), serde_json::json!([pos]), "drive {d}");
        assert_eq!(one(d, "S-0-0010"), serde_json::json!([32]));
        assert_eq!(one(d, "S-0-0015"), serde_json::json!([7]));
        // S-0-0016: 6 of 6 bytes: S-0-0011, S-0-0051, P-0-0019 (8013H).
        assert_eq!(
            one(d, "S-0-0016"),
            serde_json::json!([6, 6, 11, 51, 0x8013])
        );
        // S-0-0024: 2 of 2 bytes: S-0-0036.
        assert_eq!(one(d, "S-0-0024"), serde_json::json!([2, 2, 36]));
    }
    let e = writes(&v, 1, "S-0-0001")[0];
    assert_eq!(
        (e["phase"].as_u64(), e["element"].as_u64()),
        (Some(2), Some(7))
    );
    // Reads carry the element; the capture holds the master's side only.
    assert!(v.iter().any(|e| e["op"] == "read"
        && e["idn"] == "S-0-0003"
        && e["element"] == 3
        && e["phase"] == 2));
}

/// Procedure commands (sercos-facts.md: write 3 = set and enable, 0 = cancel): S-0-0099 and
/// S-0-0127 in phase 2 through unicast MDTs, S-0-0128 in phase 3 through the broadcast MDT
/// records found at the S-0-0009 offsets.
#[test]
fn transcript_procedure_commands() {
    for name in ["tc2000r-phaseup.nrzi", "tc2000r-phaseup-2.nrzi"] {
        let Some(v) = transcript(name) else { return };
        for d in 1..=4 {
            for (idn, phase) in [("S-0-0099", 2), ("S-0-0127", 2), ("S-0-0128", 3)] {
                let w: Vec<_> = writes(&v, d, idn)
                    .iter()
                    .map(|e| (e["phase"].clone(), e["words"].clone()))
                    .collect();
                assert!(
                    w.contains(&(serde_json::json!(phase), serde_json::json!([3]))),
                    "{name}: drive {d} {idn} set in phase {phase}: {w:?}"
                );
                assert!(
                    w.iter().any(|(_, words)| *words == serde_json::json!([0])),
                    "{name} {idn} cancelled"
                );
            }
        }
        let phases: Vec<u64> = v.iter().map(|e| e["phase"].as_u64().unwrap()).collect();
        assert!(
            phases.windows(2).all(|p| p[0] <= p[1]),
            "{name}: phases never go back"
        );
    }
}

fn run_on_bytes(bytes: &[u8], sub: &str) -> (bool, String, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("input.nrzi");
    std::fs::write(&path, bytes).unwrap();
    sercon(&["capture", sub, path.to_str().unwrap()])
}

fn assert_clean_failure((ok, out, err): (bool, String, String), what: &str) {
    assert!(!ok, "{what}: must fail");
    assert!(out.is_empty(), "{what}: nothing on stdout, got {out:?}");
    assert_eq!(
        err.lines().count(),
        1,
        "{what}: one error line, got {err:?}"
    );
    assert!(err.starts_with("sercon: "), "{what}: {err}");
    assert!(!err.contains("panicked"), "{what}: {err}");
}

#[test]
fn bad_files_give_one_clear_error_line() {
    for sub in ["decode", "transcript"] {
        assert_clean_failure(run_on_bytes(&[], sub), "empty file");
        assert_clean_failure(run_on_bytes(&[0x20], sub), "one byte");
        // Pseudo-random bytes (a fixed LCG, so the test is deterministic).
        let mut x: u32 = 12345;
        let random: Vec<u8> = (0..100_000)
            .map(|_| {
                x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
                (x >> 16) as u8
            })
            .collect();
        assert_clean_failure(run_on_bytes(&random, sub), "random file");
    }
    let (ok, _, err) = sercon(&["capture", "decode", "/nonexistent/file.nrzi"]);
    assert!(
        !ok && err.contains("cannot read /nonexistent/file.nrzi"),
        "{err}"
    );
}

#[test]
fn truncated_capture_is_refused_unless_forced() {
    let Some(dir) = captures_dir() else { return };
    let bytes = std::fs::read(dir.join("tc2000r-phaseup.nrzi")).unwrap();
    let half = &bytes[..bytes.len() / 2];
    let r = run_on_bytes(half, "decode");
    assert!(r.2.contains("declares 8429 telegrams"), "{}", r.2);
    assert_clean_failure(r, "truncated capture");
    // --force decodes what is there.
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("half.nrzi");
    std::fs::write(&p, half).unwrap();
    let (ok, out, _) = sercon(&["capture", "decode", "--force", p.to_str().unwrap()]);
    assert!(ok);
    assert!(out.lines().count() > 4000);
}
