//! Runs the `sercon` binary for the `sercon idn` tests.

use std::process::Command;

/// What one run gave: exit code, stdout, stderr.
pub struct Run {
    pub code: i32,
    pub out: String,
    pub err: String,
}

/// Runs `sercon idn <args>`.
pub fn idn(args: &[&str]) -> Run {
    let output = Command::new(env!("CARGO_BIN_EXE_sercon"))
        .arg("idn")
        .args(args)
        .output()
        .expect("sercon runs");
    Run {
        code: output.status.code().unwrap_or(-1),
        out: String::from_utf8_lossy(&output.stdout).into_owned(),
        err: String::from_utf8_lossy(&output.stderr).into_owned(),
    }
}

/// A successful run's stdout (panics with stderr otherwise).
#[allow(dead_code)]
pub fn ok(args: &[&str]) -> String {
    let r = idn(args);
    assert_eq!(r.code, 0, "sercon idn {args:?} failed: {}", r.err);
    r.out
}

/// A failed run: its exit code and the one line it wrote on stderr.
#[allow(dead_code)]
pub fn fails(args: &[&str]) -> (i32, String) {
    let r = idn(args);
    assert_ne!(
        r.code, 0,
        "sercon idn {args:?} should fail; stdout: {}",
        r.out
    );
    assert!(r.out.is_empty(), "nothing on stdout: {}", r.out);
    let lines: Vec<&str> = r.err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one line on stderr: {}", r.err);
    assert!(r.err.starts_with("sercon: "), "{}", r.err);
    (r.code, lines.first().copied().unwrap_or("").to_string())
}
