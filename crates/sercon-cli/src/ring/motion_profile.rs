//! The motion the master commands in phase 4: a velocity sine per axis (S-0-0036, the MDT
//! list of the default telegram configuration), each axis a quarter period behind the one
//! before, so that every cycle carries new command values.

use sercos_wire::time::Duration;

/// S-0-0036 velocity command: 0.0001 rpm per unit (the emulated drive's scaling,
/// `sercos_drive::drive`, docs/spec-notes.md "Emulated drive").
const UNITS_PER_RPM: f64 = 10_000.0;

/// A velocity sine: `amplitude_rpm · sin(2π t / period + axis · π/2)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionProfile {
    /// Peak velocity, rpm.
    pub amplitude_rpm: f64,
    /// Period of the sine.
    pub period: Duration,
}

impl Default for MotionProfile {
    /// 1000 rpm peak, 2 s period.
    fn default() -> MotionProfile {
        MotionProfile {
            amplitude_rpm: 1000.0,
            period: Duration::from_secs(2),
        }
    }
}

impl MotionProfile {
    /// The velocity command (S-0-0036 units, 0.0001 rpm) of axis `axis` (0-based, ring order)
    /// at `t` after the start of phase 4.
    pub fn velocity_command(&self, axis: usize, t: Duration) -> i32 {
        let period = self.period.as_secs_f64();
        let angle = if period > 0.0 {
            std::f64::consts::TAU * t.as_secs_f64() / period
        } else {
            0.0
        };
        let shift = std::f64::consts::FRAC_PI_2 * (axis % 4) as f64;
        let rpm = self.amplitude_rpm * (angle + shift).sin();
        let units = (rpm * UNITS_PER_RPM).round();
        // Saturate to the 4-byte command (sercos-facts.md S-0-0036 is 4 bytes signed).
        units.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_with_quarter_shifts() {
        let p = MotionProfile::default();
        assert_eq!(p.velocity_command(0, Duration::from_picos(0)), 0);
        assert_eq!(p.velocity_command(1, Duration::from_picos(0)), 10_000_000);
        assert_eq!(
            p.velocity_command(0, Duration::from_millis(500)),
            10_000_000
        );
        assert_eq!(p.velocity_command(2, Duration::from_picos(0)), 0);
        // Successive 1 ms cycles give different values.
        let a = p.velocity_command(0, Duration::from_millis(10));
        let b = p.velocity_command(0, Duration::from_millis(11));
        assert_ne!(a, b);
    }

    #[test]
    fn saturates() {
        let p = MotionProfile {
            amplitude_rpm: 1e12,
            period: Duration::from_secs(1),
        };
        assert_eq!(p.velocity_command(1, Duration::from_picos(0)), i32::MAX);
    }
}
