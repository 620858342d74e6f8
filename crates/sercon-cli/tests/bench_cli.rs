//! `sercon bench`: the JSON line of a ring scenario (issue 5: at least scenario, slaves,
//! bit_rate_mbit, cycle_us, phase, sim_s, wall_s, rtf) and `--repeat`, which reports the
//! fastest of several runs with the median real-time factor.

mod cli_support;

use cli_support::sercon;

/// `sercon bench` on the smallest ring scenario for 8 simulated ms, then `more`.
fn ring_n8(more: &[&'static str]) -> Vec<&'static str> {
    let mut args = vec!["bench", "--scenario", "ring-n8", "--sim-ms", "8"];
    args.extend_from_slice(more);
    args
}

/// Runs `sercon args…`, which must succeed with exactly one JSON object on one line.
fn one_json(args: &[&str]) -> serde_json::Value {
    let out = sercon(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1, "{text}");
    serde_json::from_str(lines[0]).expect("one JSON object per line")
}

/// What `sercon bench` calls the build of the `sercon` under test.
fn expected_build() -> &'static str {
    if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    }
}

#[test]
fn one_run_prints_the_issue_fields() {
    let v = one_json(&ring_n8(&["--json"]));
    assert_eq!(v["scenario"], "ring-n8");
    assert_eq!(v["slaves"], 8);
    assert_eq!(v["bit_rate_mbit"], 16);
    assert_eq!(v["cycle_us"], 4000);
    assert_eq!(v["phase"], 4);
    assert!((v["sim_s"].as_f64().unwrap_or(0.0) - 0.008).abs() < 1e-9);
    assert!(v["wall_s"].as_f64().is_some_and(|w| w > 0.0));
    assert!(v["rtf"].as_f64().is_some_and(|r| r > 0.0));
    // One run: nothing about runs.
    assert!(v.get("runs").is_none());
    // The figures say what build made them (the tests' `sercon` is built with the tests'
    // profile).
    assert_eq!(v["build"], expected_build());
}

#[test]
fn the_text_names_the_build_first() {
    let out = sercon(&ring_n8(&[]));
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let first = format!("{} build", expected_build());
    assert_eq!(text.lines().next(), Some(first.as_str()), "{text}");
    assert!(text.contains("ring-n8"), "{text}");
}

#[test]
fn repeat_reports_the_fastest_run_and_the_median() {
    let v = one_json(&ring_n8(&["--repeat", "3", "--json"]));
    assert_eq!(v["runs"], 3);
    let (rtf, median) = (
        v["rtf"].as_f64().unwrap_or(0.0),
        v["rtf_median"].as_f64().unwrap_or(f64::MAX),
    );
    // The fastest run has the highest real-time factor (the JSON rounds to 3 decimals).
    assert!(rtf + 0.001 >= median, "{rtf} < {median}");
    let text = sercon(&ring_n8(&["--repeat", "2"]));
    assert!(text.status.success());
    assert!(String::from_utf8_lossy(&text.stdout).contains("fastest of 2 runs"));
}

#[test]
fn a_run_is_warmed_up_unless_asked_not_to() {
    // The default: 20 wall ms of whole cycles before the measurement, at least one.
    let v = one_json(&ring_n8(&["--json"]));
    assert!(v["warm_up_cycles"].as_u64().is_some_and(|c| c >= 1), "{v}");
    let v = one_json(&ring_n8(&["--json", "--warm-up-ms", "0"]));
    assert_eq!(v["warm_up_cycles"], 0);
    // The measured simulated time is the same either way.
    assert!((v["sim_s"].as_f64().unwrap_or(0.0) - 0.008).abs() < 1e-9);
    for bad in ["-1", "x", "60001"] {
        let arg = format!("--warm-up-ms={bad}");
        let out = sercon(&["bench", "--scenario", "ring-n8", &arg]);
        assert!(!out.status.success(), "{bad}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("--warm-up-ms"),
            "{bad}"
        );
        assert!(out.stdout.is_empty(), "{bad}");
    }
}

#[test]
fn a_repeat_of_zero_is_refused_with_a_message() {
    let out = sercon(&["bench", "--scenario", "ring-n8", "--repeat", "0"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--repeat"));
    assert!(out.stdout.is_empty());
}

/// Runs `sercon args…` with its stdout a pipe whose reading end is closed at once (`sercon …
/// | head -0`): the output ends quietly, without a panic, and the exit status is the run's.
fn with_stdout_closed(args: &[&str]) -> std::process::Output {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_sercon"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sercon starts");
    drop(child.stdout.take());
    child.wait_with_output().expect("sercon ends")
}

#[test]
fn a_closed_stdout_ends_the_output_quietly() {
    // Text and JSON, several scenarios: the first line already finds the pipe closed.
    for json in [false, true] {
        let mut args = vec!["bench", "--stack", "ring", "--sim-ms", "4"];
        if json {
            args.push("--json");
        }
        let out = with_stdout_closed(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{err}");
        assert!(out.status.success(), "{err}");
    }
    let out = with_stdout_closed(&["ring", "--drives", "1", "--seconds", "0.3"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(out.status.success(), "{err}");
}

// An unknown scenario is refused with the names there are; a name of the other stack says so.
#[test]
fn an_unknown_scenario_is_refused_with_the_names_there_are() {
    let out = sercon(&["bench", "--scenario", "ring-32", "--sim-ms", "1"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    for name in [
        "\"ring-32\"",
        "ring-8",
        "ring-n32",
        "ring-n128",
        "ring-254",
        "stack-8",
        "stack-n<n>",
    ] {
        assert!(err.contains(name), "{name} in {err}");
    }
    let out = sercon(&[
        "bench",
        "--stack",
        "ring",
        "--scenario",
        "stack-8",
        "--sim-ms",
        "1",
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--stack full"));
}

/// A full-stack scenario's line: the ring fields, its phase-up and the host accesses that
/// waited while the ring ran along (spec-notes "A host's bus time"): a master and a drive
/// woken by the same telegrams work side by side, so some of their accesses wait every
/// cycle.
#[test]
fn a_full_stack_line_carries_the_phase_up_and_the_host_waits() {
    let v = one_json(&[
        "bench",
        "--stack",
        "full",
        "--scenario",
        "stack-n1",
        "--sim-ms",
        "8",
        "--json",
    ]);
    assert_eq!(v["scenario"], "stack-n1");
    assert_eq!(v["stack"], "full");
    assert_eq!(v["slaves"], 1);
    assert_eq!(v["phase"], 4);
    assert!(v["phaseup_sim_s"].as_f64().is_some_and(|s| s > 0.0));
    let waits = v["host_waits_per_cycle"]
        .as_f64()
        .expect("host_waits_per_cycle");
    assert!(waits > 0.0 && waits < 1000.0, "{waits}");
}
