//! Motors: a torque (or force) on a driver's coordinate that depends on
//! its speed, as a catalogue gives it.

/// The torque–speed curve of a motor acting on a coordinate (a torque in
/// N·m about an angle, or a force in N along a length, positive in the
/// direction the coordinate grows), added with
/// [`DynamicsBuilder::motor`](crate::dynamics::DynamicsBuilder::motor).
///
/// ```
/// use kinematics_core::dynamics::Motor;
/// // A DC motor: 2 N·m at stall, no torque at 300 rad/s.
/// let dc = Motor::dc(2.0, 300.0);
/// assert_eq!(dc.torque(150.0), 1.0);
/// // An induction motor with 4-pole synchronous speed 157 rad/s: the
/// // Kloss curve's largest torque, 30 N·m, at a slip of 0.2.
/// let im = Motor::induction(30.0, 157.0, 0.2);
/// assert!((im.torque(157.0 * 0.8) - 30.0).abs() < 1e-12);
/// assert_eq!(im.torque(157.0), 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motor {
    /// A DC motor at constant voltage: T = T_s (1 − ω/ω₀), the stall
    /// torque T_s falling linearly to zero at the no-load speed ω₀ (and
    /// braking past it).
    Dc {
        /// T_s, the torque at standstill.
        stall_torque: f64,
        /// ω₀, the speed at which the torque is zero.
        no_load_speed: f64,
    },
    /// An induction motor by Kloss's formula: with the slip
    /// s = 1 − ω/ω_s, T = 2 T_b s s_b / (s² + s_b²), the breakdown torque
    /// T_b at the breakdown slip s_b, zero at the synchronous speed ω_s
    /// and 2 T_b s_b / (1 + s_b²) at standstill.
    Induction {
        /// T_b, the largest torque.
        breakdown_torque: f64,
        /// ω_s, the speed of the rotating field.
        synchronous_speed: f64,
        /// s_b, the slip of the largest torque.
        breakdown_slip: f64,
    },
    /// A constant torque, whatever the speed.
    Constant(f64),
}

impl Motor {
    /// A DC motor of stall torque `stall_torque` and no-load speed
    /// `no_load_speed`.
    #[must_use]
    pub fn dc(stall_torque: f64, no_load_speed: f64) -> Self {
        Motor::Dc {
            stall_torque,
            no_load_speed,
        }
    }

    /// An induction motor by Kloss's formula.
    #[must_use]
    pub fn induction(breakdown_torque: f64, synchronous_speed: f64, breakdown_slip: f64) -> Self {
        Motor::Induction {
            breakdown_torque,
            synchronous_speed,
            breakdown_slip,
        }
    }

    /// The torque at the speed `speed` (rad/s, or m/s along a length).
    #[must_use]
    pub fn torque(&self, speed: f64) -> f64 {
        match *self {
            Motor::Dc {
                stall_torque,
                no_load_speed,
            } => stall_torque * (1.0 - speed / no_load_speed),
            Motor::Induction {
                breakdown_torque,
                synchronous_speed,
                breakdown_slip,
            } => {
                let s = 1.0 - speed / synchronous_speed;
                2.0 * breakdown_torque * s * breakdown_slip
                    / (s * s + breakdown_slip * breakdown_slip)
            }
            Motor::Constant(t) => t,
        }
    }

    /// What is wrong with the constants, if anything.
    pub(crate) fn invalid(&self) -> Option<&'static str> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        match *self {
            Motor::Dc {
                stall_torque,
                no_load_speed,
            } => (!finite(&[stall_torque, no_load_speed])
                || no_load_speed == 0.0
                || stall_torque * no_load_speed < 0.0)
                .then_some(
                    "its stall torque and no-load speed must be finite, the speed not 0, and \
                     of one sign (a motor turning backwards has both negative)",
                ),
            Motor::Induction {
                breakdown_torque,
                synchronous_speed,
                breakdown_slip,
            } => (!finite(&[breakdown_torque, synchronous_speed, breakdown_slip])
                || synchronous_speed == 0.0
                || breakdown_slip <= 0.0
                || breakdown_torque * synchronous_speed < 0.0)
                .then_some(
                    "its breakdown torque, synchronous speed and breakdown slip must be \
                     finite, the speed not 0, the slip positive, and the torque and the \
                     speed of one sign (both negative for a field turning backwards)",
                ),
            Motor::Constant(t) => (!t.is_finite()).then_some("its torque must be finite"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Motor;

    #[test]
    fn kloss_curve_peaks_at_the_breakdown_slip() {
        let m = Motor::induction(30.0, 100.0, 0.25);
        let t = |slip: f64| m.torque(100.0 * (1.0 - slip));
        assert!((t(0.25) - 30.0).abs() < 1e-12);
        assert!(t(0.24) < 30.0 && t(0.26) < 30.0);
        // At standstill: 2 T_b s_b / (1 + s_b²).
        assert!((t(1.0) - 2.0 * 30.0 * 0.25 / (1.0 + 0.0625)).abs() < 1e-12);
        // Past synchronous speed it brakes.
        assert!(t(-0.1) < 0.0);
        assert!(Motor::induction(1.0, 100.0, 0.0).invalid().is_some());
        assert!(Motor::dc(1.0, 0.0).invalid().is_some());
        // A torque against its own speed would run away.
        assert!(Motor::dc(2.0, -100.0).invalid().is_some());
        assert!(Motor::induction(60.0, -157.0, 0.2).invalid().is_some());
        assert!(Motor::dc(-2.0, -100.0).invalid().is_none());
        assert!(Motor::Constant(2.0).invalid().is_none());
    }
}
