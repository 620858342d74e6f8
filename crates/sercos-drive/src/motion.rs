//! The axis: a first-order velocity loop with position integrated from velocity.
//!
//! The documents give no drive dynamics; the model is the plausible minimum
//! (docs/spec-notes.md, "Emulated drive"): velocity follows its command with time constant
//! τ (P-0-0001), v(t+dt) = v_cmd + (v − v_cmd)·e^(−dt/τ); position control closes a
//! proportional loop (Kv) around it; with torque removed the motor coasts down with a
//! longer time constant. Time is injected (`sercos_wire::time`), never read.

use sercos_wire::time::{Duration, Instant};

/// The longest step integrated at once; longer spans are cut into steps of this size so that
/// the position loop stays stable.
const MAX_STEP: Duration = Duration::from_micros(250);
/// Position loop gain Kv in 1/s.
const POSITION_GAIN: f64 = 20.0;
/// How many times slower a motor without torque coasts down than the velocity loop.
const COAST_FACTOR: f64 = 20.0;
/// rpm to degrees per second.
const DEG_PER_S_PER_RPM: f64 = 6.0;

/// What the drive controls, from the operation mode (S-0-0032…S-0-0035).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControlMode {
    /// Mode 1: torque control (S-0-0080); modelled as velocity proportional to torque.
    Torque,
    /// Mode 2: velocity control (S-0-0036).
    Velocity,
    /// Modes 3 and 4: position control with feedback 1 or 2 (S-0-0047).
    Position,
}

impl ControlMode {
    /// The mode from an operation-mode value: bits 2–0 1 torque, 2 velocity, 3 or 4
    /// position (higher bits, e.g. "without lag", are ignored); `None` otherwise.
    pub fn from_operation_mode(mode: i128) -> Option<ControlMode> {
        match mode & 0b111 {
            1 => Some(ControlMode::Torque),
            2 => Some(ControlMode::Velocity),
            3 | 4 => Some(ControlMode::Position),
            _ => None,
        }
    }
}

/// What the axis is told to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AxisCommand {
    /// No torque: the motor coasts down (drive off or disabled, or a class 1 error).
    Coast,
    /// Drive halt: decelerate under control to standstill and hold.
    Halt,
    /// Follow a velocity in rpm.
    Velocity(f64),
    /// Follow a position in degrees.
    Position(f64),
}

/// The simulated axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    time_constant: Duration,
    velocity_rpm: f64,
    position_deg: f64,
    now: Instant,
    command: AxisCommand,
}

impl Axis {
    /// An axis at rest at position 0, at time `now`, with velocity time constant `tau`
    /// (at least 1 µs).
    pub fn new(now: Instant, tau: Duration) -> Axis {
        Axis {
            time_constant: tau.max(Duration::from_micros(1)),
            velocity_rpm: 0.0,
            position_deg: 0.0,
            now,
            command: AxisCommand::Coast,
        }
    }

    /// The velocity in rpm.
    pub fn velocity_rpm(&self) -> f64 {
        self.velocity_rpm
    }

    /// The position in degrees.
    pub fn position_deg(&self) -> f64 {
        self.position_deg
    }

    /// The time the axis has been advanced to.
    pub fn now(&self) -> Instant {
        self.now
    }

    /// The command being followed.
    pub fn command(&self) -> AxisCommand {
        self.command
    }

    /// Sets the command followed from now on.
    pub fn set_command(&mut self, command: AxisCommand) {
        self.command = command;
    }

    /// Sets the velocity time constant (at least 1 µs).
    pub fn set_time_constant(&mut self, tau: Duration) {
        self.time_constant = tau.max(Duration::from_micros(1));
    }

    /// Integrates the motion up to `now`; earlier times are ignored.
    pub fn advance_to(&mut self, now: Instant) {
        while self.now < now {
            let step = now.saturating_duration_since(self.now).min(MAX_STEP);
            self.step(step.as_secs_f64());
            self.now += step;
        }
    }

    fn step(&mut self, dt: f64) {
        let tau = self.time_constant.as_secs_f64();
        let (target, tau) = match self.command {
            AxisCommand::Coast => (0.0, tau * COAST_FACTOR),
            AxisCommand::Halt => (0.0, tau),
            AxisCommand::Velocity(v) => (v, tau),
            AxisCommand::Position(p) => (
                POSITION_GAIN * (p - self.position_deg) / DEG_PER_S_PER_RPM,
                tau,
            ),
        };
        let before = self.velocity_rpm;
        let decay = (-dt / tau).exp();
        let after = target + (before - target) * decay;
        // Exact integral of the exponential approach over the step.
        let travelled_rpm_s = target * dt + (before - target) * tau * (1.0 - decay);
        self.velocity_rpm = if after.is_finite() { after } else { 0.0 };
        let delta = travelled_rpm_s * DEG_PER_S_PER_RPM;
        if delta.is_finite() {
            self.position_deg += delta;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn velocity_reaches_63_percent_after_one_time_constant() {
        // First-order lag: 1 − e^(−1) ≈ 0.632 after τ.
        let mut axis = Axis::new(Instant::ZERO, Duration::from_millis(5));
        axis.set_command(AxisCommand::Velocity(1000.0));
        axis.advance_to(Instant::ZERO + Duration::from_millis(5));
        assert!(
            (axis.velocity_rpm() - 632.12).abs() < 0.1,
            "{}",
            axis.velocity_rpm()
        );
        axis.advance_to(Instant::ZERO + Duration::from_millis(100));
        assert!((axis.velocity_rpm() - 1000.0).abs() < 0.01);
        assert!(axis.position_deg() > 0.0);
    }

    #[test]
    fn position_loop_settles() {
        let mut axis = Axis::new(Instant::ZERO, Duration::from_millis(5));
        axis.set_command(AxisCommand::Position(90.0));
        axis.advance_to(Instant::ZERO + Duration::from_secs(2));
        assert!(
            (axis.position_deg() - 90.0).abs() < 0.01,
            "{}",
            axis.position_deg()
        );
        assert!(axis.velocity_rpm().abs() < 0.1);
    }

    #[test]
    fn coasting_is_slower_than_halting() {
        let mut coast = Axis::new(Instant::ZERO, Duration::from_millis(5));
        coast.set_command(AxisCommand::Velocity(1000.0));
        coast.advance_to(Instant::ZERO + Duration::from_millis(100));
        let mut halt = coast.clone();
        coast.set_command(AxisCommand::Coast);
        halt.set_command(AxisCommand::Halt);
        let later = Instant::ZERO + Duration::from_millis(110);
        coast.advance_to(later);
        halt.advance_to(later);
        assert!(halt.velocity_rpm() < coast.velocity_rpm());
        assert!(halt.velocity_rpm() >= 0.0);
    }
}
