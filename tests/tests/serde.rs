//! Every public data type through JSON and back (feature `serde`): the
//! parameters, coordinates, motion and modes a definition generates when it
//! derives `Serialize` and `Deserialize`, sweeps with their samples and
//! stops, errors, options.
#![allow(clippy::expect_used, clippy::panic)]

use kinematics_core::closed::Mode;
use kinematics_core::sweep::{ChangePoints, Stop, StopReason, Sweep, Wrap};
use kinematics_core::{
    mechanism, Branch, Convergence, Error, FrameState, Input, Kind, Options, PointMotion, Role,
};
use kinematics_examples::{FourBar, FourBarCoords, FourBarModes, FourBarMotion};
use serde::de::DeserializeOwned;
use serde::Serialize;

/// `x` through JSON and back.
fn round_trip<T: Serialize + DeserializeOwned>(x: &T) -> T {
    let json = serde_json::to_string(x).expect("serializes");
    serde_json::from_str(&json).unwrap_or_else(|e| panic!("deserializes {json}: {e}"))
}

/// Asserts that `x` comes back equal.
fn same<T: Serialize + DeserializeOwned + PartialEq + std::fmt::Debug>(x: &T) {
    assert_eq!(&round_trip(x), x);
}

#[test]
fn generated_types_round_trip() {
    let m = FourBar::CRANK_ROCKER;
    same(&m);
    let pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    same(&pose);
    let motion: FourBarMotion = m.analyze(&pose, 10.0, 2.0).expect("analyses");
    same(&motion);
    same(&FourBarModes {
        th3_th4: Mode::Minus,
    });
    // Parameters read from a file-like JSON text, by name.
    let read: FourBar = serde_json::from_str(
        r#"{"a": 0.04, "b": 0.12, "c": 0.10, "d": 0.11, "p": 0.06, "beta": 0.5235987755982989}"#,
    )
    .expect("parameters");
    assert_eq!(read, m);
    // A missing parameter is an error naming it, not a default.
    let e = serde_json::from_str::<FourBar>(r#"{"a": 0.04}"#).expect_err("incomplete");
    assert!(e.to_string().contains("missing field `b`"), "{e}");
}

mechanism! {
    /// A crank and a spatial frame, with serde and another derive passed
    /// through to the parameters.
    #[derive(Default, serde::Serialize, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct Crank {
        params {
            /// Crank length.
            a
        }
        drivers {
            /// Crank angle.
            phi
        }
        unknowns { }
        frames { crank = rot_z(phi); }
        points { B = crank * vec3(a, 0.0, 0.0); }
    }
}

#[test]
fn attributes_pass_through_to_the_parameters() {
    // `Default` and the serde container attribute reach the struct.
    assert_eq!(Crank::default(), Crank { a: 0.0 });
    let e = serde_json::from_str::<Crank>(r#"{"a": 1.0, "b": 2.0}"#).expect_err("unknown field");
    assert!(e.to_string().contains("unknown field `b`"), "{e}");
    let m = Crank { a: 0.3 };
    same(&m);
    let s = m
        .analyze(&CrankCoords { phi: 0.4 }, 2.0, 0.5)
        .expect("analyses");
    same(&s);
    same(&s.frames[0]);
    same(&CrankCoords { phi: 1.0 });
}

#[test]
fn sweeps_samples_and_stops_round_trip() {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = m
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(36)
        .rpm(100.0)
        .run();
    let back: Sweep<FourBar> = round_trip(&s);
    assert_eq!(back.variable, "phi");
    assert_eq!(back.kind, s.kind);
    assert_eq!(back.samples.len(), s.samples.len());
    for (a, b) in back.samples.iter().zip(&s.samples) {
        assert_eq!((a.at, a.motion), (b.at, b.motion));
    }
    assert!(back.stop.is_none() && back.change_points == s.change_points);
    // A stopped sweep: the stop comes back with its reason.
    let short = FourBar {
        a: 0.05,
        b: 0.08,
        c: 0.06,
        d: 0.11,
        p: 0.0,
        beta: 0.0,
    };
    let start = short
        .assemble(&FourBarCoords {
            phi: 0.0,
            th3: 0.5,
            th4: 1.5,
        })
        .expect("assembles");
    let s = short.sweep(FourBar::PHI, &start).turn().run();
    let stop = s.stop.clone().expect("stops");
    same(&stop);
    let back: Sweep<FourBar> = round_trip(&s);
    assert_eq!(back.stop, s.stop);
    for reason in [
        StopReason::ChangePoint { from: 1.0, to: 2.0 },
        StopReason::Invalid(Error::InvalidOption {
            name: "to",
            value: f64::MAX,
            requirement: "must be given",
        }),
    ] {
        same(&Stop {
            variable: "phi",
            at: 1.5,
            reason,
        });
    }
}

#[test]
fn errors_and_options_round_trip() {
    let m = FourBar::CRANK_ROCKER;
    // Real errors, from the library.
    let far = FourBar { a: 1.0, ..m };
    let cannot = far
        .assemble(&FourBar::CRANK_ROCKER_GUESS)
        .expect_err("cannot close");
    assert!(matches!(cannot, Error::CannotAssemble { .. }));
    same(&cannot);
    let invalid = m
        .assemble_with(
            &FourBar::CRANK_ROCKER_GUESS,
            &Options {
                tolerance: -1.0,
                ..Options::DEFAULT
            },
        )
        .expect_err("a negative tolerance");
    assert!(matches!(invalid, Error::InvalidOption { .. }));
    same(&invalid);
    for e in [
        Error::Singular {
            unknown: "th4",
            conditioning: 1e-14,
            configuration: vec![("phi", 0.5), ("th3", 1.0)],
        },
        Error::NotConverged {
            iterations: 50,
            residual: 1e-3,
            relative: 1e-2,
            equation: "a fresh name, not in any definition",
            configuration: vec![("phi", 0.5)],
        },
        Error::Output {
            path: "/nowhere".to_owned(),
            detail: "denied".to_owned(),
        },
    ] {
        same(&e);
    }
    // A NaN or an infinity is not a JSON number (serde_json writes null, and
    // reads null back as an error, not as a number): an error about a
    // non-finite input serializes, and tells so.
    let e = Error::NonFinite {
        input: Input::DriverRate,
        name: "phi",
        value: f64::INFINITY,
    };
    let json = serde_json::to_string(&e).expect("serializes");
    assert!(
        json.contains("\"value\":null") && json.contains("\"DriverRate\""),
        "{json}"
    );
    same(&Options {
        tolerance: 1e-10,
        convergence: Convergence::Absolute,
        branch: Branch::Negative,
        ..Options::DEFAULT
    });
    same(&Wrap::Signed);
    same(&ChangePoints::Switch);
    same(&Kind::Length);
    same(&Role::Driver);
}

#[test]
fn point_and_frame_states_round_trip() {
    let m = FourBar::CRANK_ROCKER;
    let pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let motion = m.analyze(&pose, 10.0, 2.0).expect("analyses");
    let p: PointMotion<2> = *motion.point_p();
    same(&p);
    let crank = Crank { a: 0.3 };
    let s = crank
        .analyze(&CrankCoords { phi: 0.4 }, 2.0, 0.5)
        .expect("analyses");
    let f: FrameState = s.frames[0];
    same(&f);
}

#[test]
fn the_example_parameter_file_reads_as_the_crank_rocker() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/data/crank_rocker.json"
    ))
    .expect("the example's file");
    let m: FourBar = serde_json::from_str(&text).expect("parameters");
    assert_eq!(m, FourBar::CRANK_ROCKER);
}

#[test]
fn sensitivities_and_deviations_round_trip() {
    use kinematics_core::tolerance::{point_deviations, Deviation};
    use kinematics_examples::FourBarSensitivities;
    let m = FourBar::CRANK_ROCKER;
    let pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let motion = m.analyze(&pose, 10.0, 0.0).expect("analyses");
    let sens: FourBarSensitivities = m.sensitivities(&motion).expect("sensitivities");
    same(&sens);
    let s = m
        .sweep(FourBar::PHI, &pose)
        .turn()
        .steps(12)
        .rate(10.0)
        .run();
    let d: Vec<Deviation> =
        point_deviations(&m, &s, "P", &[("a", 1e-4), ("beta", 1e-3)]).expect("deviations");
    same(&d);
}
