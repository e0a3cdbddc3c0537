//! `step` and `step_with`: assembly from the previous pose and analysis in
//! one pass. Newton's common path runs inline, with the driver-only part of
//! Φ and Φ_u hoisted out of the loop and the sines and cosines of the
//! unknown angles carried between iterates; the values the analysis needs
//! are kept from the last (converged) evaluation instead of recomputed.

use std::collections::HashMap;

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::ext::IdentExt;
use syn::Ident;

use super::newton::{driver_frontier, unknown_trig, used_later};
use super::print::{bind, bind_given};
use super::{guards, Ctx};
use crate::cse::schedule;
use crate::ir::Id;

/// The stepping methods.
pub(super) fn step(cx: &Ctx<'_>) -> TokenStream {
    let (g, pp, allow) = (cx.g(), &cx.pp, &cx.allow);
    let inline_core = cx.inline_core();
    let nd = cx.nd;
    let id = &cx.id;
    let (coords, motion, coord) = (&id.coords, &id.motion, &id.coord);
    let q = &id.q;
    let q_drivers = &q[..nd];
    let (qd_drivers, qdd_drivers) = (&id.qd[..nd], &id.qdd[..nd]);
    let c_drivers = &coord[..nd];
    let leaf = cx.leaf();
    let newton_roots = cx.newton_roots();
    let [vel_stage, acc_stage, pt_stage] = cx.analysis_stages();
    let sched = schedule(
        g,
        &[
            driver_frontier(g, &newton_roots, cx.model.drivers),
            newton_roots.clone(),
            vel_stage.clone(),
            acc_stage.clone(),
            pt_stage.clone(),
        ],
    );
    let (pr, lets) = bind(g, &sched, &leaf);
    let hoisted = &lets[0];
    // The values the analysis reuses are kept from the last evaluation.
    let (solve, nt) = newton_solve(
        cx,
        &sched,
        &pr,
        &lets[1],
        &[&vel_stage, &acc_stage, &pt_stage],
        false,
        Judge {
            assess: quote!(fast.assess_closing(&phi, &__weights, options)),
            polish: quote!(false),
        },
    );
    let tail = cx.analysis_tail(
        &pr,
        [&lets[2], &lets[3], &lets[4]],
        &quote!(#coords { #( #coord: #q ),* }),
        &quote!(#pp::closed::max_abs(&__phi)),
    );
    let inputs = guards::inputs(cx, "start", true);
    let scaling = cx.scaling();
    let ne = cx.ne;
    let nm = cx.nm();
    let na = cx.na();
    let ndt = cx.driver_trig().len();
    let param_trig_init = if cx.closed_path() {
        quote!(self.__param_trig())
    } else {
        quote!([])
    };
    let step_body = if cx.closed_path() {
        quote! {
            let mut modes = [::core::primitive::f64::NAN; #nm];
            let mut angles = Self::__seeded(start);
            let mut dtrig = [[::core::primitive::f64::NAN; 3]; #ndt];
            let pt = self.__param_trig();
            let (r, a) = (rates.into_array(), accelerations.into_array());
            match self.__step_closed(start, r, a, options, &scaling, &mut modes, &mut angles, &pt, &mut dtrig) {
                ::core::result::Result::Err(e @ #pp::Error::WrongBranch { .. }) => self.__step_other_branch(
                    e, start, r, a, options, &scaling, &mut modes, &mut angles, &pt, &mut dtrig,
                ),
                r => r,
            }
        }
    } else {
        quote! {
            let mut carry = [[0.0f64, 0.0f64, ::core::primitive::f64::NAN]; #nt];
            self.__step_core(start, rates, accelerations, options, &scaling, &mut carry)
        }
    };
    let stepper = &id.stepper;
    let state = format_ident!("{}StepState", id.name.unraw());
    let stepper_doc = format!(
        "A stepping handle: checks `options` and the parameters once, evaluates the scaling \
         of the equations once (unless it depends on the drivers), and carries the sines and \
         cosines of the solved pose from one [`{stepper}::step`] to the next (those of the \
         drivers rotated by each step's increment, refreshed every 16 steps; those of the \
         unknowns every 64). The way to run a simulation."
    );
    let pose_core = pose_core(cx);
    // Whether the scaling must be evaluated at each step: a term scale that
    // holds a driver (a slider driver outside a sine or cosine).
    let driver_scaled = cx.scales.full.iter().any(|&r| {
        g.depends_on(
            r,
            &|l| matches!(l, crate::ir::Leaf::Q(j) if j < cx.model.drivers),
        )
    });
    quote! {
        /// Assembles at the drivers of `start` from its unknowns (as
        /// [`Self::assemble`]) and analyses the motion there (as
        /// [`Self::analyze`]), in one pass: the last Newton evaluation's
        /// sines, cosines and Jacobian are reused, not recomputed. The
        /// step of a simulation that advances the drivers.
        ///
        /// # Errors
        /// As [`Self::assemble`] and [`Self::analyze`].
        pub fn step(
            &self,
            start: &#coords,
            rates: impl #pp::DriverValues<#nd>,
            accelerations: impl #pp::DriverValues<#nd>,
        ) -> #pp::Result<#motion, #pp::Error> {
            self.__step(start, rates, accelerations, &#pp::Options::DEFAULT)
        }

        /// [`Self::step`] with explicit solver options.
        ///
        /// # Errors
        /// As [`Self::step`], and invalid options.
        pub fn step_with(
            &self,
            start: &#coords,
            rates: impl #pp::DriverValues<#nd>,
            accelerations: impl #pp::DriverValues<#nd>,
            options: &#pp::Options,
        ) -> #pp::Result<#motion, #pp::Error> {
            self.__step(start, rates, accelerations, options)
        }

        /// The body of [`Self::step`] and [`Self::step_with`]: inlined
        /// into each, so that with the default options their checks fold
        /// away at compile time.
        #[doc(hidden)]
        #[inline(always)]
        fn __step(
            &self,
            start: &#coords,
            rates: impl #pp::DriverValues<#nd>,
            accelerations: impl #pp::DriverValues<#nd>,
            options: &#pp::Options,
        ) -> #pp::Result<#motion, #pp::Error> {
            options.validate()?;
            self.validate()?;
            let scaling = self.__scaling(&[#(start.#c_drivers),*])?;
            #step_body
        }

        /// The scaling of the equations (`kinematics_core::solve::Scaling`)
        /// at the drivers `d`.
        #[doc(hidden)]
        #[inline(always)]
        #allow
        fn __scaling(
            &self,
            d: &[f64; #nd],
        ) -> #pp::Result<#pp::Scaling<#ne>, #pp::Error> {
            let [#(#q_drivers),*] = *d;
            #scaling
            ::core::result::Result::Ok(__scaling)
        }

        /// A step from `start` with options, parameters and scaling
        /// already checked, and the sines and cosines of the unknown
        /// angles carried in `carry` as (sin, cos, argument): on return,
        /// those of the solution (or a NaN argument, to compute afresh).
        #[doc(hidden)]
        #inline_core
        #allow
        #[allow(unused_assignments)]
        fn __step_core(
            &self,
            start: &#coords,
            rates: impl #pp::DriverValues<#nd>,
            accelerations: impl #pp::DriverValues<#nd>,
            options: &#pp::Options,
            __scaling: &#pp::Scaling<#ne>,
            carry: &mut [[f64; 3]; #nt],
        ) -> #pp::Result<#motion, #pp::Error> {
            let [#(#qd_drivers),*] = rates.into_array();
            let [#(#qdd_drivers),*] = accelerations.into_array();
            #inputs
            let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
            let __weights = __scaling.weights(options);
            #hoisted
            #solve
            #tail
        }

        #pose_core

        #[doc = #stepper_doc]
        ///
        /// # Errors
        /// Invalid options or parameters.
        pub fn stepper(&self, options: &#pp::Options) -> #pp::Result<#stepper<'_>, #pp::Error> {
            ::core::result::Result::Ok(#stepper {
                mechanism: self,
                state: self.__step_state(options)?,
            })
        }

        /// A fresh stepping state (`options` and the parameters checked).
        #[doc(hidden)]
        pub fn __step_state(&self, options: &#pp::Options) -> #pp::Result<#state, #pp::Error> {
            options.validate()?;
            self.validate()?;
            let scaling = if #driver_scaled {
                ::core::option::Option::None
            } else {
                ::core::option::Option::Some(self.__scaling(&[0.0f64; #nd])?)
            };
            ::core::result::Result::Ok(#state {
                options: *options,
                scaling,
                carry: [[0.0f64, 0.0f64, ::core::primitive::f64::NAN]; #nt],
                modes: [::core::primitive::f64::NAN; #nm],
                angles: [[::core::primitive::f64::NAN; 3]; #na],
                param_trig: #param_trig_init,
                dtrig: [[::core::primitive::f64::NAN; 3]; #ndt],
                since_refresh: 0,
            })
        }
    }
}

/// The stepping handle's type and its `step` (items beside the mechanism's
/// impl).
pub(super) fn stepper_items(cx: &Ctx<'_>) -> TokenStream {
    let (pp, nd, ne) = (&cx.pp, cx.nd, cx.ne);
    let id = &cx.id;
    let (name, coords, motion, stepper) = (&id.name, &id.coords, &id.motion, &id.stepper);
    let c_drivers = &id.coord[..nd];
    let nt = unknown_trig(cx.g(), &cx.newton_roots(), cx.model.drivers).len();
    let nm = cx.nm();
    let na = cx.na();
    let npt = cx.param_trig().len();
    let ndt = cx.driver_trig().len();
    let vis = &cx.def.vis;
    let pose_t = cx.pose_type();
    let state = format_ident!("{}StepState", name.unraw());
    let call = if cx.closed_path() {
        quote! {
            let (r, a) = (rates.into_array(), accelerations.into_array());
            let (options, angles, pt) = (&self.options, &mut self.angles, &self.param_trig);
            let dtrig = &mut self.dtrig;
            match mechanism.__step_closed(start, r, a, options, &scaling, &mut self.modes, angles, pt, dtrig) {
                ::core::result::Result::Err(e @ #pp::Error::WrongBranch { .. }) => mechanism.__step_other_branch(
                    e, start, r, a, options, &scaling, &mut self.modes, angles, pt, dtrig,
                ),
                r => r,
            }
        }
    } else {
        quote!(mechanism.__step_core(
            start,
            rates,
            accelerations,
            &self.options,
            &scaling,
            &mut self.carry
        ))
    };
    let pose_call = if cx.closed_path() {
        quote! {
            let (options, pt) = (&self.options, &self.param_trig);
            match mechanism.__assemble_closed(
                start, options, &scaling, &mut self.modes, &mut self.angles, pt, &mut self.dtrig, false,
            ) {
                ::core::result::Result::Err(e @ #pp::Error::WrongBranch { .. }) => {
                    mechanism.__assemble_other_branch(e, start, options, &scaling, &mut self.modes, pt)
                }
                r => r,
            }
        }
    } else {
        quote!(mechanism.__pose_core(start, &self.options, &scaling, &mut self.carry, false))
    };
    let modes_fn = if cx.closed_path() {
        let modes = format_ident!("{}Modes", name.unraw());
        quote! {
            /// The assembly modes the steps follow: those of the first
            /// step's guess, kept from step to step (a closed-form block
            /// changes mode only through a limit position). `None` before
            /// the first step.
            #[must_use]
            pub fn modes(&self) -> ::core::option::Option<#modes> {
                if self.state.modes.iter().any(|m| m.is_nan()) {
                    ::core::option::Option::None
                } else {
                    ::core::option::Option::Some(#modes::__from_signs(&self.state.modes))
                }
            }

            /// Makes the following steps assemble in `modes` instead of
            /// the modes of the guess.
            pub fn set_modes(&mut self, modes: &#modes) {
                self.state.modes = modes.__signs();
            }
        }
    } else {
        TokenStream::new()
    };
    let doc = format!(
        "A stepping handle of [`{name}`], made by [`{name}::stepper`]: options, parameters and \
         the scaling of the equations checked once, and the sines and cosines of each solved \
         pose carried to the next step."
    );
    let pose_doc = format!(
        "As [`{stepper}::step`], positions only: assembles at the drivers of `start` from the \
         previous step's state (its assembly modes and the sines and cosines of its pose) and \
         returns the pose with its points' positions, its conditioning, the sign of det Φ_u and \
         the residual, with no velocity or acceleration computed. The step of a sweep of positions \
         ([`SweepBuilder::poses`](::kinematics_core::sweep::SweepBuilder::poses))."
    );
    let step_doc = format!(
        "As [`{name}::step`] from `start` (the drivers and a guess of the unknowns, usually the \
         previous step's pose with the drivers advanced), without checking the options and the \
         parameters again, and starting Newton–Raphson from the sines and cosines of the \
         previous solution."
    );
    quote! {
        #[doc = #doc]
        #[derive(Debug, Clone)]
        #vis struct #stepper<'m> {
            mechanism: &'m #name,
            state: #state,
        }

        /// What a stepper carries from one step to the next (the
        /// `Mechanism::StepState` of a sweep).
        #[doc(hidden)]
        #[derive(Debug, Clone)]
        #vis struct #state {
            options: #pp::Options,
            scaling: ::core::option::Option<#pp::Scaling<#ne>>,
            carry: [[f64; 3]; #nt],
            modes: [f64; #nm],
            angles: [[f64; 3]; #na],
            param_trig: [f64; #npt],
            dtrig: [[f64; 3]; #ndt],
            since_refresh: u32,
        }

        impl #stepper<'_> {
            #[doc = #step_doc]
            ///
            /// # Errors
            /// As the mechanism's `step`.
            #[inline]
            pub fn step(
                &mut self,
                start: &#coords,
                rates: impl #pp::DriverValues<#nd>,
                accelerations: impl #pp::DriverValues<#nd>,
            ) -> #pp::Result<#motion, #pp::Error> {
                self.state.__step(self.mechanism, start, rates, accelerations)
            }

            #[doc = #pose_doc]
            ///
            /// # Errors
            /// As the mechanism's `assemble`.
            #[inline]
            pub fn pose(&mut self, start: &#coords) -> #pp::Result<#pose_t, #pp::Error> {
                self.state.__pose(self.mechanism, start)
            }

            #modes_fn
        }

        impl #state {
            /// The stepper's step, for `mechanism`.
            #[doc(hidden)]
            #[inline(always)]
            pub fn __step(
                &mut self,
                mechanism: &#name,
                start: &#coords,
                rates: impl #pp::DriverValues<#nd>,
                accelerations: impl #pp::DriverValues<#nd>,
            ) -> #pp::Result<#motion, #pp::Error> {
                let scaling = self.__refresh(mechanism, start)?;
                #call
            }

            /// The stepper's positions-only step, for `mechanism`.
            #[doc(hidden)]
            #[inline(always)]
            pub fn __pose(
                &mut self,
                mechanism: &#name,
                start: &#coords,
            ) -> #pp::Result<#pose_t, #pp::Error> {
                let scaling = self.__refresh(mechanism, start)?;
                #pose_call
            }

            /// Counts a step, refreshing the carried sines and cosines now
            /// and then; the scaling at the drivers of `start`.
            #[inline(always)]
            fn __refresh(
                &mut self,
                mechanism: &#name,
                start: &#coords,
            ) -> #pp::Result<#pp::Scaling<#ne>, #pp::Error> {
                // Fresh sines and cosines now and then bound the drift of
                // the carried ones.
                self.since_refresh += 1;
                if self.since_refresh % 16 == 0 {
                    for d in &mut self.dtrig {
                        d[2] = ::core::primitive::f64::NAN;
                    }
                }
                if self.since_refresh >= 64 {
                    self.since_refresh = 0;
                    for c in &mut self.carry {
                        c[2] = ::core::primitive::f64::NAN;
                    }
                    for a in &mut self.angles {
                        a[2] = ::core::primitive::f64::NAN;
                    }
                }
                match self.scaling {
                    ::core::option::Option::Some(s) => ::core::result::Result::Ok(s),
                    ::core::option::Option::None => mechanism.__scaling(&[#(start.#c_drivers),*]),
                }
            }
        }
    }
}

/// The pieces of Newton's inline loop for a schedule whose first two
/// stages are the driver-only values and the Newton cone (Φ and Φ_u): the
/// sine and cosine of each unknown angle carried from one iterate to the
/// next (`sin_cos_after`), and the iteration's values with those nodes read
/// from the carried variables. The change of the argument is the
/// difference of its evaluated values, so that the carried values follow
/// the argument as evaluated in floating point (an offset of 1e20 rad
/// leaves u + γ unchanged by a small step in u).
struct FastLoop {
    /// Binds the carried values from `carry`.
    trig_setup: TokenStream,
    /// Updates them at the iterate.
    trig_eval: TokenStream,
    /// Each carried value as stored back into `carry`.
    trig_keep: Vec<TokenStream>,
    /// The number of carried sines and cosines.
    nt: usize,
    /// The iteration's values (stage 1 of the schedule).
    iterated: TokenStream,
}

impl FastLoop {
    fn new(cx: &Ctx<'_>, sched: &crate::cse::Schedule, pr: &super::print::Printer<'_>) -> Self {
        let (g, pp) = (cx.g(), &cx.pp);
        let leaf = cx.leaf();
        let mut given: HashMap<Id, Ident> = HashMap::new();
        let (mut trig_setup, mut trig_eval, mut trig_keep) =
            (TokenStream::new(), TokenStream::new(), Vec::new());
        let trig = unknown_trig(g, &cx.newton_roots(), cx.model.drivers);
        let nt = trig.len();
        for (n, t) in trig.into_iter().enumerate() {
            // The argument as an expression of u_k and values bound before
            // the iteration (the part free of unknowns is driver-only or
            // constant).
            let arg = pr.body(t.arg);
            let (sv, cv, av) = (
                format_ident!("__sin_{}", n),
                format_ident!("__cos_{}", n),
                format_ident!("__arg_{}", n),
            );
            given.extend(t.sin.map(|id| (id, sv.clone())));
            given.extend(t.cos.map(|id| (id, cv.clone())));
            // From the values carried in: the previous pose's (a
            // stepper's), or an argument of NaN, which computes afresh.
            trig_setup.extend(quote! {
                let [mut #sv, mut #cv, mut #av] = carry[#n];
            });
            trig_keep.push(quote!([#sv, #cv, #av]));
            trig_eval.extend(quote! {
                let __x = #arg;
                (#sv, #cv) = #pp::sin_cos_after(#sv, #cv, __x, __x - #av);
                #av = __x;
            });
        }
        let (_, fast_lets) = bind_given(g, sched, &leaf, given);
        Self {
            trig_setup,
            trig_eval,
            trig_keep,
            nt,
            iterated: fast_lets[1].clone(),
        }
    }
}

/// `__pose_core`: a positions-only step or assembly. Newton's common path
/// inline (Φ and Φ_u only), the general damped solver off it (and, with
/// `polish`, after it where the residual is above `solve::POLISH` times
/// the tolerance: `assemble` returns poses at round-off), then the
/// conditioning and the branch judged at the solution.
fn pose_core(cx: &Ctx<'_>) -> TokenStream {
    let (g, pp, allow) = (cx.g(), &cx.pp, &cx.allow);
    let inline_core = cx.inline_core();
    let (nd, ne) = (cx.nd, cx.ne);
    let id = &cx.id;
    let (coords, coord, q) = (&id.coords, &id.coord, &id.q);
    let q_drivers = &q[..nd];
    let c_drivers = &coord[..nd];
    let leaf = cx.leaf();
    let newton_roots = cx.newton_roots();
    // The points' positions after the solve, from the values of its last
    // evaluation that they use (kept in `cache`, as `__step_core` keeps
    // those of the analysis).
    let pos_stage: Vec<Id> = cx.d.pos.iter().flatten().copied().collect();
    let sched = schedule(
        g,
        &[
            driver_frontier(g, &newton_roots, cx.model.drivers),
            newton_roots.clone(),
            pos_stage.clone(),
        ],
    );
    let (pr, lets) = bind(g, &sched, &leaf);
    let hoisted = &lets[0];
    // Φ_u kept at the solution, for its conditioning and branch.
    let (solve, nt) = newton_solve(
        cx,
        &sched,
        &pr,
        &lets[1],
        &[&pos_stage],
        true,
        Judge {
            assess: quote! {
                if polish {
                    fast.assess(&phi, &__weights, options)
                } else {
                    fast.assess_closing(&phi, &__weights, options)
                }
            },
            polish: quote!(polish && #pp::FastNewton::unpolished(&__phi, &__weights, options)),
        },
    );
    let inputs = guards::inputs(cx, "start", false);
    let pose_ok = cx.pose_at_solution(&pr, &lets[2]);
    let pose_t = cx.pose_type();
    quote! {
        /// A positions-only step (or, with `polish`, an assembly) from
        /// `start`, with options, parameters and scaling already checked,
        /// the sines and cosines of the unknown angles carried in `carry`
        /// as in `__step_core`.
        #[doc(hidden)]
        #inline_core
        #allow
        #[allow(unused_assignments)]
        fn __pose_core(
            &self,
            start: &#coords,
            options: &#pp::Options,
            __scaling: &#pp::Scaling<#ne>,
            carry: &mut [[f64; 3]; #nt],
            polish: bool,
        ) -> #pp::Result<#pose_t, #pp::Error> {
            #inputs
            let [#(#q_drivers),*]: [f64; #nd] = [#(start.#c_drivers),*];
            let __weights = __scaling.weights(options);
            #hoisted
            #solve
            #pose_ok
        }
    }
}

/// How Newton's inline iteration judges its iterates: `assess`, the
/// expression giving each iterate's `Next`, and `polish`, a `bool`
/// expression of `__phi` for a converged pose to hand to the general
/// solver for polishing (see [`newton_solve`]).
struct Judge {
    assess: TokenStream,
    polish: TokenStream,
}

/// Newton's solve from the unknowns of `start` for a schedule whose
/// first stages are the driver-only values and the Newton cone (`iterated`:
/// its bindings under `pr`): the common path evaluated inline
/// (`FastNewton`), anything off it (damping, round-off, failure) handed to
/// the general solver from `start` again, which returns the failure from
/// the enclosing function. `assess` judges each iterate (`FastNewton::
/// assess_closing` for a step, which takes one more inline step from a
/// converged pose above round-off; `FastNewton::assess` for an assembly);
/// a converged pose for which `polish` (a `bool` expression of `__phi`)
/// holds is handed to the general solver, to be polished from there as
/// an assembly is. Binds the unknowns at the solution,
/// `__phi` (Φ there), the values of the last evaluation that the `later`
/// stages use and, with `keep_jac`, `jac` (Φ_u there), and updates
/// `carry`; also returns the number of carried sines and cosines.
fn newton_solve(
    cx: &Ctx<'_>,
    sched: &crate::cse::Schedule,
    pr: &super::print::Printer<'_>,
    iterated: &TokenStream,
    later: &[&Vec<Id>],
    keep_jac: bool,
    judge: Judge,
) -> (TokenStream, usize) {
    let Judge { assess, polish } = judge;
    let fast_loop = FastLoop::new(cx, sched, pr);
    let cached = used_later(cx.g(), sched, 1, &cx.newton_roots(), later);
    let cached_names: Vec<&Ident> = cached.iter().filter_map(|id| pr.names.get(id)).collect();
    let nc = cached_names.len();
    let keep = quote!(cache = [#(#cached_names),*];);
    let nnz = cx.blocks.nnz();
    let (declare_jac, keep_fast, keep_after, bind_jac) = if keep_jac {
        (
            quote!(let mut __jac = [0.0f64; #nnz];),
            quote!(#keep __jac = jac;),
            quote!(__jac = jac;),
            quote!(let jac = __jac;),
        )
    } else {
        let none = TokenStream::new;
        (none(), keep.clone(), none(), none())
    };
    let (d, pp) = (cx.d, &cx.pp);
    let ne = cx.ne;
    let id = &cx.id;
    let (q, c_unknowns) = (&id.q, &id.coord[cx.nd..]);
    let q_unknowns = &q[cx.nd..];
    let FastLoop {
        trig_setup,
        trig_eval,
        trig_keep,
        nt,
        iterated: iterated_fast,
    } = &fast_loop;
    let phi: Vec<_> = d.phi.iter().map(|&i| pr.element(i)).collect();
    let jac = cx.jac_array(pr);
    let newton_factor = cx.blocks.factor(pp, false, &|_| quote!(break false));
    let newton_step = cx.blocks.solve(&quote!(phi), false);
    let solver = cx.solver();
    let (done, restart) = (
        quote!(on_path && !(#polish)),
        quote! {
            if !on_path {
                u = [#(start.#c_unknowns),*];
            }
        },
    );
    let solve = quote! {
        let mut u = [#(start.#c_unknowns),*];
        let mut cache = [0.0f64; #nc];
        #declare_jac
        // Newton's common path, evaluated inline; anything off it
        // (damping, round-off, failure) goes to the general solver.
        let mut fast = #pp::FastNewton::new();
        let mut __phi = [0.0f64; #ne];
        #trig_setup
        let on_path = loop {
            let [#(#q_unknowns),*] = u;
            #trig_eval
            #iterated_fast
            let phi = [#(#phi),*];
            __phi = phi;
            let jac: [f64; #nnz] = #jac;
            #keep_fast
            match #assess {
                #pp::Next::Continue => {}
                #pp::Next::Converged => break true,
                #pp::Next::Fallback => break false,
            }
            #newton_factor
            fast.advance(&mut u, &#newton_step);
        };
        if #done {
            *carry = [#(#trig_keep),*];
        } else {
            *carry = [[0.0f64, 0.0f64, ::core::primitive::f64::NAN]; #nt];
            #restart
            let mut phi = [0.0f64; #ne];
            let mut jac = [0.0f64; #nnz];
            let solved = #pp::newton(&mut u, &mut phi, &mut jac, __scaling, options, |u, phi, jac| {
                let [#(#q_unknowns),*] = *u;
                #iterated
                *phi = [#(#phi),*];
                *jac = #jac;
                #keep
            }, #solver);
            if let ::core::result::Result::Err(f) = solved {
                let [#(#q_unknowns),*] = u;
                return ::core::result::Result::Err(#pp::describe(f, &Self::__NAMES, &[#(#q),*]));
            }
            __phi = phi;
            #keep_after
        }
        let [#(#q_unknowns),*] = u;
        let [#(#cached_names),*] = cache;
        #bind_jac
    };
    (solve, *nt)
}
