//! Emission: straight-line Rust for the scheduled expressions, and the
//! generated types and impls, one file per generated item:
//!
//! * `types`: the parameters struct, the coordinates, the motion;
//! * `assemble`: `assemble`, `assemble_with`;
//! * `step`: `step`, `step_with` and their inlined body;
//! * `analyze`: `analyze`, `analyze_with` and their inlined body;
//! * `evaluate`: `residual`, `point_positions`, `frame_rotations` and the
//!   helpers behind the `Mechanism` impl;
//! * `mechanism_impl`: the `Mechanism` impl;
//! * `closed`, `closed_step`, `closed_solve`: `BLOCKS`, the modes type, and
//!   the closed-form assembly and step (`assemble_in`, `assemble_all`);
//! * `fallback`: the types and stubs emitted beside a definition's errors;
//!
//! and the pieces they share: `print` (expressions and `let`s), `solve`
//! (block solves, checks at a solution, scaling), `newton` (what the
//! iteration hoists and carries), `guards` (input and output checks).
//!
//! The generated code reaches the runtime only through absolute paths
//! (`::kinematics_core::__private::…` and `::core::…`).

mod analyze;
mod assemble;
mod closed;
mod closed_solve;
mod closed_step;
mod dynamics;
mod evaluate;
mod fallback;
mod guards;
mod mechanism_impl;
mod newton;
mod print;
mod scopes;
mod sensitivity;
pub(crate) mod solve;
mod step;
mod types;

pub use fallback::fallback;

use proc_macro2::TokenStream;
use quote::quote;
use syn::ext::IdentExt;

use crate::ir::{Graph, Id, Leaf};
use crate::kinematics::{operation_counts, Derived};
use crate::lower::Model;
use crate::parse::Definition;
use crate::scale::Scales;
use print::Printer;
use solve::BlockSolve;
use types::{types, Idents};

/// Everything the emitters of the generated items share.
struct Ctx<'a> {
    def: &'a Definition,
    model: &'a Model,
    d: &'a Derived,
    scales: &'a Scales,
    /// The blocks of Φ_u in solve order, with their closed forms.
    closed: &'a [crate::closed::Closed],
    /// sin and cos of unknown angles plus parameter-only offsets.
    offsets: &'a [crate::closed::Offset],
    id: Idents,
    /// `::kinematics_core::__private`.
    pp: TokenStream,
    /// The lints straight-line code may trip by construction: long literals
    /// of exact constants, many similar temporaries, long bodies, and
    /// coordinates a given function does not need.
    allow: TokenStream,
    nd: usize,
    nu: usize,
    ne: usize,
    np: usize,
    nf: usize,
    blocks: BlockSolve,
}

impl<'a> Ctx<'a> {
    fn new(
        def: &'a Definition,
        model: &'a Model,
        d: &'a Derived,
        scales: &'a Scales,
        closed: &'a [crate::closed::Closed],
        offsets: &'a [crate::closed::Offset],
    ) -> Self {
        Ctx {
            def,
            model,
            d,
            scales,
            closed,
            offsets,
            id: Idents::new(def),
            pp: quote!(::kinematics_core::__private),
            allow: quote!(#[allow(unused_variables, clippy::unreadable_literal, clippy::similar_names, clippy::too_many_lines, clippy::too_many_arguments, clippy::many_single_char_names, clippy::excessive_precision, clippy::approx_constant, clippy::needless_late_init, unused_assignments)]),
            nd: model.drivers as usize,
            nu: model.unknowns as usize,
            ne: model.equations.len(),
            np: model.points.len(),
            nf: d.frames.len(),
            blocks: BlockSolve::new(&model.graph, &d.jac, &scales.is_length),
        }
    }

    fn g(&self) -> &'a Graph {
        &self.model.graph
    }

    /// Φ_u's entries, all of them.
    fn jac_flat(&self) -> Vec<Id> {
        self.d.jac.iter().flatten().copied().collect()
    }

    /// Φ and Φ_u: what a Newton iteration evaluates.
    fn newton_roots(&self) -> Vec<Id> {
        self.d.phi.iter().chain(&self.jac_flat()).copied().collect()
    }

    /// The analysis in three stages: Φ_u and −Φ_d d'; −Φ_d d'' − γ; every
    /// point's and frame's motion.
    fn analysis_stages(&self) -> [Vec<Id>; 3] {
        let d = self.d;
        let vel: Vec<Id> = self
            .jac_flat()
            .into_iter()
            .chain(d.vel_rhs.iter().copied())
            .collect();
        let points: Vec<Id> = d
            .pos
            .iter()
            .chain(&d.vel)
            .chain(&d.acc)
            .flatten()
            .copied()
            .chain(d.frames.iter().flat_map(|f| {
                f.rotation
                    .iter()
                    .chain(&f.origin)
                    .flatten()
                    .chain(&f.omega)
                    .chain(&f.alpha)
                    .copied()
                    .collect::<Vec<_>>()
            }))
            .collect();
        [vel, d.acc_rhs.clone(), points]
    }

    /// A 2-D or 3-D vector of expressions.
    fn vector(&self, pr: &Printer<'_>, c: &[Id]) -> TokenStream {
        let pp = &self.pp;
        let e: Vec<_> = c.iter().map(|&i| pr.expr(i)).collect();
        if c.len() == 3 {
            quote!(#pp::Vector3::new(#(#e),*))
        } else {
            quote!(#pp::Vector2::new(#(#e),*))
        }
    }

    /// A 3×3 matrix of expressions.
    fn matrix(&self, pr: &Printer<'_>, m: &[[Id; 3]; 3]) -> TokenStream {
        let pp = &self.pp;
        let e: Vec<_> = m.iter().flatten().map(|&i| pr.expr(i)).collect();
        quote!(#pp::Matrix3::new(#(#e),*))
    }

    /// The array of Φ_u's nonzero entries under `pr`'s names.
    fn jac_array(&self, pr: &Printer<'_>) -> TokenStream {
        let full: Vec<Vec<TokenStream>> = self
            .d
            .jac
            .iter()
            .map(|row| row.iter().map(|&i| pr.element(i)).collect())
            .collect();
        self.blocks.array(&full)
    }

    /// Every point's `PointMotion` under `pr`'s names.
    fn points_of(&self, pr: &Printer<'_>) -> Vec<TokenStream> {
        let (d, pp) = (self.d, &self.pp);
        (0..self.np)
            .map(|k| {
                let (p, v, a) = (
                    self.vector(pr, &d.pos[k]),
                    self.vector(pr, &d.vel[k]),
                    self.vector(pr, &d.acc[k]),
                );
                quote!(#pp::PointMotion { position: #p, velocity: #v, acceleration: #a })
            })
            .collect()
    }

    /// Every frame's `FrameState` under `pr`'s names.
    fn frames_of(&self, pr: &Printer<'_>) -> Vec<TokenStream> {
        let pp = &self.pp;
        self.d
            .frames
            .iter()
            .map(|f| {
                let r = self.matrix(pr, &f.rotation);
                let [o, od, odd] = &f.origin;
                let (o, od, odd) = (
                    self.vector(pr, o),
                    self.vector(pr, od),
                    self.vector(pr, odd),
                );
                let (w, al) = (self.vector(pr, &f.omega), self.vector(pr, &f.alpha));
                quote!(#pp::FrameState {
                    rotation: #r,
                    origin: #o,
                    velocity: #od,
                    acceleration: #odd,
                    angular_velocity: #w,
                    angular_acceleration: #al,
                })
            })
            .collect()
    }

    /// The type of a positions-only solve's result, `Pose<Coords,
    /// Positions>`.
    fn pose_type(&self) -> TokenStream {
        let (pp, coords) = (&self.pp, &self.id.coords);
        let positions = quote::format_ident!("{}Positions", self.id.name.unraw());
        quote!(#pp::Pose<#coords, #positions>)
    }

    /// The end of a positions-only solve: Φ_u's blocks factored at the
    /// solution (`jac`, with the coordinates and `__phi` bound), the
    /// conditioning and branch checked, and the `Pose` returned, with the
    /// points' positions `d.pos` printed by `pr` (`points`: their values'
    /// bindings).
    fn pose_at_solution(&self, pr: &Printer<'_>, points: &TokenStream) -> TokenStream {
        let pp = &self.pp;
        let (coords, coord, q) = (&self.id.coords, &self.id.coord, &self.id.q);
        let positions = quote::format_ident!("{}Positions", self.id.name.unraw());
        let names = self.def.points.iter().map(|p| &p.name);
        let values = self.d.pos.iter().map(|c| self.vector(pr, c));
        let at_solution = self.factor_at_solution();
        quote! {
            // The singularity and the branch are judged at the solution.
            #at_solution
            #points
            ::core::result::Result::Ok(#pp::Pose {
                q: #coords { #( #coord: #q ),* },
                points: #positions { #( #names: #values, )* },
                conditioning: __conditioning,
                det_sign: __det_sign,
                residual: #pp::closed::max_abs(&__phi),
            })
        }
    }

    /// The factorisation of Φ_u's blocks at a solution, with the
    /// conditioning and branch checks (binding `__conditioning` and
    /// `__det_sign`), returning the error from the enclosing function.
    /// The coordinates are gathered once into `__at` for the errors, so
    /// that the code stays linear in the number of blocks.
    fn factor_at_solution(&self) -> TokenStream {
        let (pp, q) = (&self.pp, &self.id.q);
        let fail = |f: TokenStream| quote!(return ::core::result::Result::Err(#pp::describe(#f, &Self::__NAMES, &__at)););
        let factor = self.blocks.factor(pp, true, &fail);
        let check = self.blocks.check(pp, &fail);
        quote! {
            let __at = [#(#q),*];
            #factor
            #check
        }
    }

    /// The inlining of the large generated functions (the solves and the
    /// analysis): always inlined into their callers for a model of a few
    /// loops, where that lets the compiler fold the checks of each caller
    /// into them; never for a large model (more than
    /// [`LARGE_MODEL`] unknowns), where each caller's copy would multiply
    /// the compile time and the code size.
    fn inline_core(&self) -> TokenStream {
        if self.nu > LARGE_MODEL {
            quote!(#[inline(never)])
        } else {
            quote!(#[inline(always)])
        }
    }

    /// The binding of `__scaling` from the parameters and the bound
    /// drivers, returning an overflow from the enclosing function.
    fn scaling(&self) -> TokenStream {
        let (pp, q_drivers) = (&self.pp, &self.id.q[..self.nd]);
        let leaf = self.id.leaf();
        solve::scaling_code(
            self.g(),
            self.scales,
            &leaf,
            self.id.params.len(),
            pp,
            &quote!(return ::core::result::Result::Err(#pp::describe(f, &Self::__NAMES, &[#(#q_drivers),*]));),
        )
    }

    /// The linear solve handed to the general Newton solver: Φ_u x = rhs
    /// through the factored blocks, at the last evaluation's `jac`.
    fn solver(&self) -> TokenStream {
        let (pp, nu, nnz) = (&self.pp, self.nu, self.blocks.nnz());
        let factor = self.blocks.factor(
            pp,
            true,
            &|f| quote!(return ::core::result::Result::Err(#f);),
        );
        let solve = self.blocks.solve(&quote!(*rhs), true);
        quote! {
            |jac: &[f64; #nnz], rhs: &[f64; #nu]| -> ::core::result::Result<[f64; #nu], #pp::Failure> {
                #factor
                ::core::result::Result::Ok(#solve)
            }
        }
    }

    /// The analysis once the coordinates are bound, under `pr`'s names and
    /// with its three stages' `lets` (velocity, acceleration, points): Φ_u
    /// factored and checked at the solution, u' and u'' solved block by
    /// block, every point's and frame's motion, and the motion (its `q`
    /// field given) checked and returned.
    fn analysis_tail(
        &self,
        pr: &Printer<'_>,
        lets: [&TokenStream; 3],
        q_field: &TokenStream,
        residual: &TokenStream,
    ) -> TokenStream {
        let (d, nd, nnz) = (self.d, self.nd, self.blocks.nnz());
        let id = &self.id;
        let (coords, motion, coord) = (&id.coords, &id.motion, &id.coord);
        let (qd, qdd) = (&id.qd, &id.qdd);
        let (qd_unknowns, qdd_unknowns) = (&qd[nd..], &qdd[nd..]);
        let [velocity, acceleration, points] = lets;
        let jac = self.jac_array(pr);
        let vel_rhs: Vec<_> = d.vel_rhs.iter().map(|&i| pr.element(i)).collect();
        let acc_rhs: Vec<_> = d.acc_rhs.iter().map(|&i| pr.element(i)).collect();
        let vel_solve = self.blocks.solve(&quote!([#(#vel_rhs),*]), true);
        let acc_solve = self.blocks.solve(&quote!([#(#acc_rhs),*]), true);
        let point_states = self.points_of(pr);
        let frame_states = self.frames_of(pr);
        let check_rates = guards::solved_rates(self);
        // Every output component, for the check that all are finite.
        let terms: Vec<TokenStream> = d
            .pos
            .iter()
            .zip(&d.vel)
            .zip(&d.acc)
            .flat_map(|((p, v), a)| p.iter().chain(v).chain(a))
            .chain(d.frames.iter().flat_map(|f| {
                f.rotation
                    .iter()
                    .flatten()
                    .chain(f.origin.iter().flatten())
                    .chain(&f.omega)
                    .chain(&f.alpha)
            }))
            .map(|&i| pr.expr(i))
            .collect();
        let check_outputs = guards::outputs(self, &terms, &point_states, &frame_states);
        let at_solution = self.factor_at_solution();
        quote! {
            #velocity
            let jac: [f64; #nnz] = #jac;
            #at_solution
            let [#(#qd_unknowns),*] = #vel_solve;
            #acceleration
            let [#(#qdd_unknowns),*] = #acc_solve;
            #check_rates
            #points
            #check_outputs
            ::core::result::Result::Ok(#motion {
                q: #q_field,
                qd: #coords { #( #coord: #qd ),* },
                qdd: #coords { #( #coord: #qdd ),* },
                points: [#(#point_states),*],
                frames: [#(#frame_states),*],
                conditioning: __conditioning,
                det_sign: __det_sign,
                residual: #residual,
            })
        }
    }

    /// The leaf printer of the generated code (`self.a`, `q_phi`, …).
    fn leaf(&self) -> impl Fn(Leaf) -> TokenStream + '_ {
        self.id.leaf()
    }
}

/// The number of unknowns above which a model counts as large (see
/// `Ctx::inline_core`).
const LARGE_MODEL: usize = 32;

/// What the optional sections of a definition add to its expansion.
pub struct Optional<'a> {
    /// The partial derivatives of the `sensitivities` section.
    pub sensitivities: Option<&'a crate::sensitivity::Partials>,
    /// The masses and loads of the `bodies` and `loads` sections.
    pub dynamics: Option<&'a crate::dynamics::Dynamics>,
    /// Their equations of motion in the coordinates, where formed.
    pub motion: Option<&'a crate::motion::EquationsOfMotion>,
}

/// The full expansion of a checked model.
pub fn expand(
    def: &Definition,
    model: &Model,
    d: &Derived,
    scales: &Scales,
    closed: &[crate::closed::Closed],
    offsets: &[crate::closed::Offset],
    optional: &Optional<'_>,
) -> TokenStream {
    let cx = Ctx::new(def, model, d, scales, closed, offsets);
    let sensitivities = sensitivity::sensitivities(&cx, optional.sensitivities);
    let dynamics = dynamics::dynamics(&cx, optional.dynamics);
    let types = types(def, &cx.id, Some(&model.kinds), model.point_dim);
    let (name, pp, nd, nu, ne, np, nf) = (&cx.id.name, &cx.pp, cx.nd, cx.nu, cx.ne, cx.np, cx.nf);
    let coord_names: Vec<String> = cx.id.coord.iter().map(|c| c.unraw().to_string()).collect();
    let params = &cx.id.params;
    let param_names: Vec<String> = params.iter().map(|p| p.unraw().to_string()).collect();
    let npar = params.len();
    let eq_names: Vec<&str> = model.equations.iter().map(|e| e.text.as_str()).collect();
    let counts = {
        let [(n0, n), (a0, a)] = operation_counts(model, d);
        let (nt, ns, at, as_) = (n.tree, n.shared, a.tree, a.shared);
        quote!([(#n0, #nt, #ns), (#a0, #at, #as_)])
    };
    let validate = guards::validate(&cx);
    let assemble = assemble::assemble(&cx);
    let step = step::step(&cx);
    let stepper = step::stepper_items(&cx);
    let analyze = analyze::analyze(&cx);
    let evaluate = evaluate::evaluate(&cx);
    let mechanism_impl =
        mechanism_impl::mechanism_impl(&cx, dynamics::motion(&cx, optional.motion));
    let blocks = closed::blocks_const(&cx);
    let modes = closed::modes_type(&cx);
    let closed_methods = closed_step::closed_methods(&cx);
    let shallow = if cx.g().len() > scopes::LARGE_GRAPH {
        scopes::shallow
    } else {
        core::convert::identity
    };
    shallow(quote! {
        #types

        #modes

        impl #name {
            /// Number of drivers (prescribed inputs).
            pub const DRIVERS: usize = #nd;
            /// Number of unknowns (solved joint variables).
            pub const UNKNOWNS: usize = #nu;
            /// Number of scalar loop-closure equations.
            pub const EQUATIONS: usize = #ne;
            /// Number of points of interest.
            pub const POINTS: usize = #np;
            /// Number of body frames.
            pub const FRAMES: usize = #nf;
            /// The parameters' names, in declaration order (those of
            /// [`Self::parameter_values`]).
            pub const PARAMETERS: [&'static str; #npar] = [#(#param_names),*];

            /// The parameters' values, in declaration order (named by
            /// [`Self::PARAMETERS`]).
            #[must_use]
            pub fn parameter_values(&self) -> [f64; #npar] {
                [#(self.#params),*]
            }
            /// Floating-point operations of the generated code: for the Newton
            /// step and for the analysis, the count if every expression were
            /// written out as a tree, then the count after common-subexpression
            /// elimination (what the emitted code evaluates).
            #[doc(hidden)]
            pub const __OPERATION_COUNTS: [(&'static str, u64, usize); 2] = #counts;
            #[doc(hidden)]
            const __NAMES: #pp::Names = #pp::Names {
                coordinates: &[#(#coord_names),*],
                drivers: #nd,
                equations: &[#(#eq_names),*],
            };

            #blocks

            #validate
            #assemble
            #closed_methods
            #step
            #analyze
            #evaluate
        }

        #stepper

        #mechanism_impl

        #sensitivities

        #dynamics
    })
}
