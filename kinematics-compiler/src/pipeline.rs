//! The whole pipeline, as pure functions over `proc_macro2` tokens: the
//! front and middle end ([`compile`]: parse, checks, lowering,
//! differentiation, scaling, closed forms, sensitivities), and the Rust back
//! end over its result ([`expand`]).

use proc_macro2::TokenStream;

pub use crate::check::Mobility;
use crate::closed::{Closed, ClosedForm, Offset, Pattern};
use crate::ir::{Graph, Id, OpCount};
use crate::kinematics::{Derived, DerivedFrame};
use crate::lower::{CoordKind, Model};
use crate::parse::Definition;
use crate::scale::Scales;
use crate::sensitivity::Partials;
use crate::{check, closed, emit, kinematics, lower, names, parse, scale, sensitivity, validate};

/// How a block with no closed form is solved, in words.
pub(crate) const NEWTON: &str = "Newton–Raphson";

/// A checked, lowered and differentiated mechanism definition: the
/// expression graph and the roots each stage evaluates, what a back end
/// turns into code (the Rust back end into the items `mechanism!`
/// generates).
///
/// Every root is a node of [`Compiled::graph`], a directed acyclic graph
/// of arithmetic over the leaves: the parameters p, the coordinates
/// q = (d, u) (drivers d, then unknowns u), and their first and second
/// time derivatives.
pub struct Compiled {
    def: Definition,
    model: Model,
    derived: Derived,
    scales: Scales,
    closed: Vec<Closed>,
    offsets: Vec<Offset>,
    sensitivities: Option<Partials>,
    mobility: Option<Mobility>,
    dynamics: Option<crate::dynamics::Dynamics>,
    motion: Option<crate::motion::EquationsOfMotion>,
}

/// The kind of a coordinate: what its value measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An angle (rad).
    Angle,
    /// A length, or any other non-angular quantity.
    Length,
}

/// A point's position r, velocity v = dr/dt and acceleration a = d²r/dt²,
/// each as 2 or 3 roots (planar or spatial components).
pub struct PointRoots<'a> {
    /// The point's name.
    pub name: String,
    /// r.
    pub position: &'a [Id],
    /// v.
    pub velocity: &'a [Id],
    /// a.
    pub acceleration: &'a [Id],
}

/// One diagonal block of Φ_u in its block-triangular form: equations that
/// determine their unknowns once the blocks before have been solved.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    /// Its equations (rows of Φ_u, ascending).
    pub equations: Vec<usize>,
    /// Its unknowns (0-based among the unknowns).
    pub unknowns: Vec<usize>,
    /// The closed form that solves it, with its coefficients as roots of
    /// [`Compiled::graph`] (expressions of the parameters, the drivers and
    /// the unknowns of the blocks before), or `None` for Newton–Raphson.
    /// The unknowns are in the order of the form's results (the angle
    /// first for the RRT and RTR dyads).
    pub form: Option<ClosedForm<Id>>,
    /// How it is solved, in words, as a generated mechanism's `BLOCKS`
    /// says it: "closed form: …" or "Newton–Raphson".
    pub method: &'static str,
}

impl Block {
    /// Whether its closed form has two solutions (two assembly modes).
    #[must_use]
    pub fn has_modes(&self) -> bool {
        self.form.as_ref().is_some_and(ClosedForm::has_modes)
    }

    /// The closed form's coefficients in one list
    /// ([`ClosedForm::coefficients`]); empty for Newton–Raphson.
    #[must_use]
    pub fn coefficients(&self) -> Vec<Id> {
        self.form
            .as_ref()
            .map_or_else(Vec::new, ClosedForm::coefficients)
    }
}

/// A body frame's rotation R (row by row), angular velocity ω and
/// acceleration α in the ground frame, and its origin's position, velocity
/// and acceleration.
pub struct FrameRoots<'a> {
    /// The frame's name.
    pub name: String,
    /// The roots.
    pub roots: &'a DerivedFrame,
}

impl Compiled {
    /// The mechanism's name (the struct's).
    #[must_use]
    pub fn name(&self) -> String {
        self.def.name.to_string()
    }

    /// The expression graph every root belongs to.
    #[must_use]
    pub fn graph(&self) -> &Graph {
        &self.model.graph
    }

    /// The parameters' names, in declaration order (leaf `Param(i)` is the
    /// i-th).
    #[must_use]
    pub fn parameters(&self) -> Vec<String> {
        self.def.params.iter().map(|p| p.name.to_string()).collect()
    }

    /// Whether each parameter (in declaration order) is declared a length
    /// (`name: length`), which must be positive.
    #[must_use]
    pub fn length_parameters(&self) -> Vec<bool> {
        self.def.params.iter().map(|p| p.length).collect()
    }

    /// The coordinates' names and kinds: the drivers, then the unknowns,
    /// in declaration order (leaf `Q(j)` is the j-th).
    #[must_use]
    pub fn coordinates(&self) -> Vec<(String, Kind)> {
        self.def
            .drivers
            .iter()
            .chain(&self.def.unknowns)
            .zip(&self.model.kinds)
            .map(|(d, k)| {
                let kind = match k {
                    CoordKind::Angle => Kind::Angle,
                    CoordKind::Length => Kind::Length,
                };
                (d.name.to_string(), kind)
            })
            .collect()
    }

    /// Number of drivers.
    #[must_use]
    pub fn drivers(&self) -> usize {
        self.model.drivers as usize
    }

    /// Number of unknowns (and of scalar equations).
    #[must_use]
    pub fn unknowns(&self) -> usize {
        self.model.unknowns as usize
    }

    /// The residuals Φ_i(p, q) of the scalar loop-closure equations, with
    /// each equation's text as written.
    #[must_use]
    pub fn residuals(&self) -> Vec<(Id, &str)> {
        self.model
            .equations
            .iter()
            .map(|e| (e.residual, e.text.as_str()))
            .collect()
    }

    /// The Jacobian Φ_u = ∂Φ/∂u: row i, column k is ∂Φ_i/∂u_k.
    #[must_use]
    pub fn jacobian(&self) -> &[Vec<Id>] {
        &self.derived.jac
    }

    /// The right-hand side of the velocity equations Φ_u u' = −Φ_d d'.
    #[must_use]
    pub fn velocity_rhs(&self) -> &[Id] {
        &self.derived.vel_rhs
    }

    /// The right-hand side of the acceleration equations
    /// Φ_u u'' = −Φ_d d'' − γ, with γ the convective terms
    /// (d/dt (Φ_q) q' at fixed q'').
    #[must_use]
    pub fn acceleration_rhs(&self) -> &[Id] {
        &self.derived.acc_rhs
    }

    /// The term scale S_i of each equation: the sum of the magnitudes of
    /// its terms with the unknown lengths counted as 0 (a length that sets
    /// the size of Φ_i, so that |Φ_i| / S_i is a relative residual; 0 for
    /// an equation with no fixed term). Evaluated with the parameters and
    /// the drivers.
    #[must_use]
    pub fn term_scales(&self) -> &[Id] {
        &self.scales.fixed
    }

    /// The term scale of each equation with the unknown lengths counted
    /// as the characteristic length L (the largest of
    /// [`Compiled::term_scales`]), which the leaf `Param(n)` stands for, n
    /// the number of parameters: the row scales of Φ_u and the weights of
    /// the relative convergence test, as the generated code forms them.
    #[must_use]
    pub fn full_term_scales(&self) -> &[Id] {
        &self.scales.full
    }

    /// Whether each unknown is a length (in declaration order of the
    /// unknowns): its column of Φ_u is scaled by the characteristic length
    /// when the conditioning is judged.
    #[must_use]
    pub fn length_unknowns(&self) -> &[bool] {
        &self.scales.is_length
    }

    /// The Kutzbach–Gruebler mobility of the definition's `joints { … }`
    /// section (equal to the number of drivers, or the definition would
    /// not have compiled); `None` without the section.
    #[must_use]
    pub fn mobility(&self) -> Option<Mobility> {
        self.mobility
    }

    /// The masses and loads of the `bodies` and `loads` sections, when the
    /// definition has either.
    #[must_use]
    pub fn dynamics(&self) -> Option<&crate::dynamics::Dynamics> {
        self.dynamics.as_ref()
    }

    /// The equations of motion of the `bodies` and `loads` sections in
    /// the coordinates ([`crate::motion`]), where they are formed.
    #[must_use]
    pub fn equations_of_motion(&self) -> Option<&crate::motion::EquationsOfMotion> {
        self.motion.as_ref()
    }

    /// The partial derivatives behind the `sensitivities` section, when
    /// the definition has one.
    #[must_use]
    pub fn sensitivities(&self) -> Option<&Partials> {
        self.sensitivities.as_ref()
    }

    /// Whether det Φ_u is minus the product of the determinants of its
    /// diagonal blocks ([`Compiled::blocks`]): whether the blocks' rows
    /// and their unknowns, listed in block order, are permutations of
    /// opposite parity.
    #[must_use]
    pub fn blocks_flip_determinant(&self) -> bool {
        let rows: Vec<usize> = self.closed.iter().flat_map(|b| b.rows.clone()).collect();
        let cols: Vec<usize> = self.closed.iter().flat_map(|b| b.cols.clone()).collect();
        crate::emit::solve::parity(&rows) != crate::emit::solve::parity(&cols)
    }

    /// The diagonal blocks of Φ_u in solve order.
    #[must_use]
    pub fn blocks(&self) -> Vec<Block> {
        self.closed
            .iter()
            .map(|b| Block {
                equations: b.rows.clone(),
                unknowns: b.cols.clone(),
                form: b.pattern,
                method: b.pattern.as_ref().map_or(NEWTON, Pattern::describe),
            })
            .collect()
    }

    /// Every point of interest, in declaration order.
    #[must_use]
    pub fn points(&self) -> Vec<PointRoots<'_>> {
        self.def
            .points
            .iter()
            .enumerate()
            .map(|(k, p)| PointRoots {
                name: p.name.to_string(),
                position: &self.derived.pos[k],
                velocity: &self.derived.vel[k],
                acceleration: &self.derived.acc[k],
            })
            .collect()
    }

    /// Every body frame, in declaration order.
    #[must_use]
    pub fn frames(&self) -> Vec<FrameRoots<'_>> {
        self.def
            .frames
            .iter()
            .zip(&self.derived.frames)
            .map(|(f, roots)| FrameRoots {
                name: f.name.to_string(),
                roots,
            })
            .collect()
    }

    /// Floating-point operations of the Newton step (Φ and Φ_u) and of the
    /// analysis (both right-hand sides, points and frames): written out as
    /// trees, and after common-subexpression elimination.
    #[must_use]
    pub fn operation_counts(&self) -> [(&'static str, OpCount); 2] {
        kinematics::operation_counts(&self.model, &self.derived)
    }

    /// The Rust items `mechanism!` generates for this definition.
    #[must_use]
    pub fn to_rust(&self) -> TokenStream {
        emit::expand(
            &self.def,
            &self.model,
            &self.derived,
            &self.scales,
            &self.closed,
            &self.offsets,
            &emit::Optional {
                sensitivities: self.sensitivities.as_ref(),
                dynamics: self.dynamics.as_ref(),
                motion: self.motion.as_ref(),
            },
        )
    }
}

/// Why a definition did not compile: the errors, each spanned on the
/// offending tokens, and the parsed definition when parsing succeeded
/// (the macro emits stub types from it beside the errors).
struct Failure {
    def: Option<Box<Definition>>,
    error: syn::Error,
}

/// The front and middle end.
fn run(input: TokenStream) -> Result<Compiled, Failure> {
    crate::limits::check(&input).map_err(|error| Failure { def: None, error })?;
    let def: parse::Definition =
        syn::parse2(input).map_err(|error| Failure { def: None, error })?;
    let mut errors = names::Errors::default();
    let names = check::check(&def, &mut errors);
    let mut model = lower::lower(&def, &names, &mut errors);
    let mobility = check::check_mobility(&def, model.spatial, &mut errors);
    let mut dynamics = crate::dynamics::resolve(&def, &mut model, &mut errors);
    if errors.is_empty() {
        validate::validate(&def, &model, &mut errors);
    }
    if let Err(error) = errors.finish() {
        return Err(Failure {
            def: Some(Box::new(def)),
            error,
        });
    }
    let derived = kinematics::derive(&mut model);
    let scales = scale::scales(&mut model, def.params.len());
    let closed = closed::closed_blocks(&mut model, &derived.jac);
    let offsets = closed::offsets(&mut model);
    let sensitivities = def.sensitivities.as_ref().map(|(_, names)| {
        let params: Vec<u32> = names
            .iter()
            .filter_map(|n| def.params.iter().position(|p| p.name == *n))
            .filter_map(|k| u32::try_from(k).ok())
            .collect();
        sensitivity::partials(&mut model, &derived, &params)
    });
    if let (Some(d), Some(s)) = (dynamics.as_mut(), sensitivities.as_ref()) {
        let frames: Vec<(String, [crate::ir::Id; 15])> = def
            .frames
            .iter()
            .zip(&derived.frames)
            .map(|(f, d)| {
                let mut roots = [d.omega[0]; 15];
                let all = d.rotation.iter().flatten().chain(&d.omega).chain(&d.alpha);
                for (r, &id) in roots.iter_mut().zip(all) {
                    *r = id;
                }
                (syn::ext::IdentExt::unraw(&f.name).to_string(), roots)
            })
            .collect();
        d.partials = Some(crate::dynamics::partials(&mut model, d, &s.params, &frames));
    }
    let motion = dynamics
        .as_ref()
        .and_then(|d| crate::motion::equations(&def, &mut model, &derived, d));
    Ok(Compiled {
        def,
        model,
        derived,
        scales,
        closed,
        offsets,
        sensitivities,
        mobility,
        dynamics,
        motion,
    })
}

/// Compiles a definition, the tokens written inside `mechanism! { … }`.
///
/// # Errors
/// Every error the definition has, combined into one `syn::Error` (iterate
/// over it for each message and its span), worded as `mechanism!` reports
/// them.
pub fn compile(input: TokenStream) -> Result<Compiled, syn::Error> {
    run(input).map_err(|f| f.error)
}

/// What `mechanism!` expands to: the generated items for a valid
/// definition, or `compile_error!`s spanned on the offending tokens (with
/// stub types, so that uses of the mechanism elsewhere add no knock-on
/// errors).
#[must_use]
pub fn expand(input: TokenStream) -> TokenStream {
    match run(input) {
        Ok(compiled) => compiled.to_rust(),
        Err(Failure {
            def: Some(def),
            error,
        }) => emit::fallback(&def, error.into_compile_error()),
        Err(Failure { def: None, error }) => error.into_compile_error(),
    }
}

/// The operation counts of a definition (see [`Compiled::operation_counts`]),
/// or `None` if it has errors. Unlike [`compile`], stops after
/// differentiation.
#[must_use]
pub fn op_counts(input: TokenStream) -> Option<[(&'static str, OpCount); 2]> {
    crate::limits::check(&input).ok()?;
    let def: parse::Definition = syn::parse2(input).ok()?;
    let mut errors = names::Errors::default();
    let names = check::check(&def, &mut errors);
    let mut model = lower::lower(&def, &names, &mut errors);
    errors.finish().ok()?;
    let derived = kinematics::derive(&mut model);
    Some(kinematics::operation_counts(&model, &derived))
}
