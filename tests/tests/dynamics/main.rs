//! Inverse dynamics (`kinematics_core::dynamics`) against independent
//! computations written here: the exact closed form of a slider-crank's
//! gas-force torque, Newton–Euler solves of a slider-crank engine and of a
//! four-bar with gravity (every body's equations of motion, the joint
//! forces and the driving torque as unknowns, with the kinematics in
//! closed form or from the rigid-body formulas), the energy balance over a
//! cycle at varying speed, and the power against finite differences of
//! the energy for spatial mechanisms (an RSSR and a six-axis arm with
//! inertia tensors).

// A test harness: a failed step should stop it.
#![allow(missing_docs, clippy::expect_used, clippy::panic)]

use std::f64::consts::TAU;

use kinematics_core::dynamics::{Body, Dynamics, Joint, Spring, GROUND};
use kinematics_core::nalgebra::{DMatrix, DVector, Vector3};
use kinematics_core::{mechanism, Error};

mod compiled;
mod descriptions;
mod efforts;
mod energy;
mod events;
mod forward;
mod press;
mod reactions;
mod sections;
mod timed;
mod trajectory;
