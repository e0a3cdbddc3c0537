//! Mobility: the Kutzbach–Gruebler count of degrees of freedom.
//!
//! F = λ(n − j − 1) + Σfᵢ and the number of independent loops
//! L = j − n + 1, so that Σfᵢ = F + λL; λ = 3 for planar (and spherical)
//! motion, 6 for spatial motion. Joints are binary: a joint connecting k
//! links counts as k − 1 joints. The joint letters are those of the
//! `joints { … }` section of `mechanism!`.

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

/// A kind of kinematic pair and its relative freedoms fᵢ.
///
/// ```
/// use kinematics_core::mobility::JointKind;
/// assert_eq!((JointKind::R.freedoms(), JointKind::C.freedoms(), JointKind::S.freedoms()), (1, 2, 3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Revolute (pin), f = 1.
    R,
    /// Prismatic (slider), f = 1.
    P,
    /// Helical (screw), f = 1: translation tied to rotation by the lead.
    H,
    /// Cylindrical, f = 2.
    C,
    /// Universal (Hooke), f = 2.
    U,
    /// Spherical (ball), f = 3.
    S,
    /// Planar pair, f = 3.
    PL,
    /// A general pair with the given number of freedoms (for example a
    /// planar roll-and-slide contact, f = 2).
    General(u32),
}

impl JointKind {
    /// Relative freedoms fᵢ of the pair.
    ///
    /// ```
    /// use kinematics_core::mobility::JointKind;
    /// assert_eq!((JointKind::R.freedoms(), JointKind::C.freedoms(), JointKind::S.freedoms()), (1, 2, 3));
    /// ```
    #[must_use]
    pub fn freedoms(self) -> u32 {
        match self {
            JointKind::R | JointKind::P | JointKind::H => 1,
            JointKind::C | JointKind::U => 2,
            JointKind::S | JointKind::PL => 3,
            JointKind::General(f) => f,
        }
    }
}

/// The space a mechanism moves in, which fixes λ.
///
/// ```
/// use kinematics_core::mobility::Space;
/// assert_eq!((Space::Planar.lambda(), Space::Spatial.lambda()), (3, 6));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Space {
    /// Plane motion (or motion on a sphere): λ = 3.
    Planar,
    /// General spatial motion: λ = 6.
    Spatial,
}

impl Space {
    /// λ, the freedoms of an unconstrained body in this space.
    ///
    /// ```
    /// use kinematics_core::mobility::Space;
    /// assert_eq!((Space::Planar.lambda(), Space::Spatial.lambda()), (3, 6));
    /// ```
    #[must_use]
    pub fn lambda(self) -> i64 {
        match self {
            Space::Planar => 3,
            Space::Spatial => 6,
        }
    }
}

/// The result of a mobility count.
///
/// ```
/// use kinematics_core::mobility::{mobility, JointKind::*, Space};
/// // Slider-crank: 4 links, 3 revolutes and a prismatic pair.
/// let m = mobility(Space::Planar, 4, &[R, R, R, P]);
/// assert_eq!((m.freedom, m.loops), (1, 1));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mobility {
    /// λ.
    pub lambda: i64,
    /// Number of links n, the fixed link included.
    pub links: i64,
    /// Number of (binary) joints j.
    pub joints: i64,
    /// Σfᵢ.
    pub joint_freedoms: i64,
    /// F = λ(n − j − 1) + Σfᵢ.
    pub freedom: i64,
    /// Independent loops L = j − n + 1.
    pub loops: i64,
    /// Passive freedoms flagged by the user: a description and a count.
    pub passive: Vec<(String, i64)>,
}

impl Mobility {
    /// Flags `count` passive freedoms (for example the spin of a link
    /// between two spherical joints about its own axis): they are counted in
    /// F but do not affect the input–output motion.
    ///
    /// ```
    /// use kinematics_core::mobility::{mobility, JointKind::*, Space};
    /// // RSSR: F = 6(4 − 4 − 1) + 8 = 2, one of them the coupler's spin.
    /// let m = mobility(Space::Spatial, 4, &[R, S, S, R]).with_passive("coupler spin", 1);
    /// assert_eq!((m.freedom, m.effective()), (2, 1));
    /// ```
    #[must_use]
    pub fn with_passive(mut self, description: impl Into<String>, count: i64) -> Self {
        self.passive.push((description.into(), count));
        self
    }

    /// The freedoms that the drivers must supply: F minus the passive ones.
    ///
    /// ```
    /// use kinematics_core::mobility::{mobility, JointKind::*, Space};
    /// assert_eq!(mobility(Space::Planar, 4, &[R, R, R, R]).effective(), 1);
    /// ```
    #[must_use]
    pub fn effective(&self) -> i64 {
        self.freedom - self.passive.iter().map(|(_, c)| c).sum::<i64>()
    }
}

impl fmt::Display for Mobility {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "F = {}({} − {} − 1) + {} = {}",
            self.lambda, self.links, self.joints, self.joint_freedoms, self.freedom
        )?;
        for (what, count) in &self.passive {
            write!(f, "; {count} passive: {what}")?;
        }
        if !self.passive.is_empty() {
            write!(f, "; {} to be driven", self.effective())?;
        }
        write!(f, "; {} independent loop", self.loops)?;
        if self.loops != 1 {
            f.write_str("s")?;
        }
        Ok(())
    }
}

/// Kutzbach–Gruebler mobility of a mechanism of `links` links (fixed link
/// included) joined by `joints`: F = λ(n − j − 1) + Σfᵢ, L = j − n + 1.
///
/// ```
/// use kinematics_core::mobility::{mobility, JointKind::*, Space};
/// // Plane slider-crank: n = j = 4, Σf = 4.
/// let m = mobility(Space::Planar, 4, &[R, R, R, P]);
/// assert_eq!((m.freedom, m.loops), (1, 1));
/// ```
#[must_use]
pub fn mobility(space: Space, links: u32, joints: &[JointKind]) -> Mobility {
    let lambda = space.lambda();
    let n = i64::from(links);
    let j = i64::try_from(joints.len()).unwrap_or(i64::MAX);
    let sum: i64 = joints.iter().map(|k| i64::from(k.freedoms())).sum();
    Mobility {
        lambda,
        links: n,
        joints: j,
        joint_freedoms: sum,
        freedom: lambda * (n - j - 1) + sum,
        loops: j - n + 1,
        passive: Vec::new(),
    }
}
