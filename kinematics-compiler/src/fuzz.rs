//! Seeded mutations of valid definitions, for robustness tests: the macro
//! must answer every one with code or a spanned error, and the code it
//! accepts must compile.

use quote::quote;

/// The seeded generator of the mutations.
struct Rng(fastrand::Rng);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0.usize(..n.max(1))
    }
}

/// The crank-rocker four-bar with a coupler point, as a user writes it.
pub fn four_bar() -> proc_macro2::TokenStream {
    quote! {
        /// Crank-rocker four-bar with a coupler point.
        pub struct FourBar {
            params   { a, b, c, d, p, beta }
            drivers  { phi }
            unknowns { th3, th4 }
            points {
                B = polar(a, phi);
                C = vec2(d, 0.0) + polar(c, th4);
                P = B + polar(p, th3 + beta);
            }
            loops { B + polar(b, th3) == C; }
        }
    }
}

/// Valid definitions the mutations start from.
pub fn definitions() -> Vec<proc_macro2::TokenStream> {
    vec![
        four_bar(),
        quote! {
            pub struct RRtrRrt {
                params { ab, ac, cd, de }
                drivers  { phi }
                unknowns { s, phi3, x_e, phi4 }
                points {
                    B = vec2(0.0, ac) + polar(ab, phi);
                    D = -polar(cd, phi3);
                    E = vec2(x_e, 0.0);
                }
                loops {
                    B == polar(s, phi3);
                    D + polar(de, phi4) == E;
                }
            }
        },
        quote! {
            pub struct Rssr {
                params { a, b, c, d, l }
                drivers { phi }
                unknowns { psi }
                frames {
                    crank = rot_y(phi) * t7(0.0, 0.0, l);
                    out = t3(-d, 0.0, 0.0, psi) * screw(vec3(0.0, 0.0, 1.0), psi, 0.0);
                }
                points {
                    A = vec3(-a * cos(phi), 0.0, a * sin(phi));
                    B = out * vec3(-c, 0.0, 0.0);
                    C = crank * rot(vec3(1.0, 1.0, 0.0), phi) * cross(A, B);
                }
                constraints { norm(B - A) == b; }
                joints { links: 4, R: 2, S: 2, passive: 1 }
            }
        },
        quote! {
            struct Scalar {
                params { r, k }
                drivers { t }
                unknowns { y }
                constraints { powi(y, 2) + atan2(t, r) * dot(vec2(1.0, 2.0), vec2(y, t)) == sqrt(k) / ln(2.0) + norm(vec2(t, -y)) + vec2(t, y).x; }
            }
        },
    ]
}

/// One random edit somewhere in the token tree: delete, duplicate or swap a
/// token, or replace it with a token from a fixed vocabulary.
fn mutate(ts: proc_macro2::TokenStream, rng: &mut Rng) -> proc_macro2::TokenStream {
    use proc_macro2::{Delimiter, Group, Ident, Literal, Punct, Spacing, Span, TokenTree};
    let mut tokens: Vec<TokenTree> = ts.into_iter().collect();
    if tokens.is_empty() {
        return proc_macro2::TokenStream::new();
    }
    let i = rng.below(tokens.len());
    if let TokenTree::Group(g) = &tokens[i] {
        if rng.below(3) > 0 {
            let inner = mutate(g.stream(), rng);
            let mut ng = Group::new(g.delimiter(), inner);
            ng.set_span(g.span());
            tokens[i] = TokenTree::Group(ng);
            return tokens.into_iter().collect();
        }
    }
    let vocabulary = |rng: &mut Rng| -> TokenTree {
        let words = [
            "polar", "vec2", "sin", "a", "phi", "th3", "B", "pi", "x", "y", "powi", "norm",
            "loops", "params", "struct", "unknowns", "cross", "dot", "atan2", "zz",
        ];
        match rng.below(6) {
            0 => TokenTree::Literal(Literal::f64_unsuffixed(1.5)),
            1 => TokenTree::Literal(Literal::i64_unsuffixed(2)),
            2 => TokenTree::Punct(Punct::new(
                ['+', '-', '*', '/', '=', ';', ',', '.'][rng.below(8)],
                Spacing::Alone,
            )),
            3 => TokenTree::Group(Group::new(
                Delimiter::Parenthesis,
                proc_macro2::TokenStream::new(),
            )),
            _ => TokenTree::Ident(Ident::new(words[rng.below(words.len())], Span::call_site())),
        }
    };
    match rng.below(4) {
        0 => {
            tokens.remove(i);
        }
        1 => {
            let t = tokens[i].clone();
            tokens.insert(i, t);
        }
        2 if i + 1 < tokens.len() => tokens.swap(i, i + 1),
        _ => tokens[i] = vocabulary(rng),
    }
    tokens.into_iter().collect()
}

/// Base definitions with `bodies` and `loads` sections (and a
/// `sensitivities` one): masses, inertias, gravity, springs and dampers,
/// and loads of the coordinates, their rates (`rate(…)`) and the time
/// (`time`), for the mutations to move around.
pub fn dynamics_definitions() -> Vec<proc_macro2::TokenStream> {
    vec![
        quote! {
            pub struct DynFourBar {
                params   { a, b, c, d, m3, k, t0 }
                drivers  { phi }
                unknowns { th3, th4 }
                points {
                    G2 = polar(a / 2.0, phi);
                    G3 = polar(a, phi) + polar(b / 2.0, th3);
                    G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
                    P0 = vec2(0.05, 0.15);
                }
                loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
                bodies {
                    crank(mass = 0.3, center = G2, angle = phi, inertia = 2.0e-3);
                    coupler(mass = m3, center = G3, angle = th3, inertia = 6.0e-4);
                    rocker(mass = 0.4, center = G4, angle = th4, inertia = 3.5e-4);
                }
                sensitivities { m3, k }
                loads {
                    gravity(vec2(0.0, -9.81));
                    force(phi, t0 * (1.0 - rate(phi) / 60.0) * sin(time));
                    torque(rocker, -0.01 * rate(th4));
                    force(G3, vec2(0.1 * time, 0.0));
                    spring(P0, G3, stiffness = k, free_length = 0.10, damping = 2.0);
                }
            }
        },
        quote! {
            pub struct DynEngine {
                params   { a, b, m4, p }
                drivers  { phi }
                unknowns { th, x }
                points   { G3 = polar(a, phi) + polar(b / 2.0, th); C = vec2(x, 0.0); }
                loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
                bodies {
                    rod(mass = 0.5, center = G3, angle = th, inertia = 1.7e-3);
                    piston(mass = m4, center = C);
                }
                loads {
                    force(C, vec2(-p * powi(0.2 / x, 2) * (1.0 + time), 0.0));
                    force(x, -3.0 * rate(x));
                }
            }
        },
    ]
}

/// `count` mutants (one to three random edits each) of the base
/// definitions, reproducible from `seed`.
pub fn mutants(seed: u64, count: usize) -> Vec<proc_macro2::TokenStream> {
    mutants_of(&definitions(), seed, count)
}

/// `count` mutants of `bases`, as [`mutants`] makes them.
pub fn mutants_of(
    bases: &[proc_macro2::TokenStream],
    seed: u64,
    count: usize,
) -> Vec<proc_macro2::TokenStream> {
    let mut rng = Rng(fastrand::Rng::with_seed(seed));
    (0..count)
        .map(|case| {
            let mut ts = bases[case % bases.len()].clone();
            for _ in 0..=rng.below(3) {
                ts = mutate(ts, &mut rng);
            }
            ts
        })
        .collect()
}

/// The expansions of the accepted mutants, each in a module of its own, and
/// their number as `ACCEPTED_MUTANTS`.
// Used by the `fuzz` feature's macro.
#[cfg_attr(not(feature = "fuzz"), allow(dead_code))]
pub fn accepted_expansions(seed: u64, count: usize) -> proc_macro2::TokenStream {
    accepted_expansions_of(&definitions(), seed, count)
}

/// [`accepted_expansions`] of the mutants of `bases`.
// Used by the `fuzz` feature's macro.
#[cfg_attr(not(feature = "fuzz"), allow(dead_code))]
pub fn accepted_expansions_of(
    bases: &[proc_macro2::TokenStream],
    seed: u64,
    count: usize,
) -> proc_macro2::TokenStream {
    let mut out = proc_macro2::TokenStream::new();
    let mut accepted = 0usize;
    for (k, ts) in mutants_of(bases, seed, count).into_iter().enumerate() {
        let code = crate::expand(ts);
        if code.to_string().contains("compile_error") {
            continue;
        }
        accepted += 1;
        let name = quote::format_ident!("accepted_{}", k);
        out.extend(quote! {
            #[allow(dead_code, unused, clippy::all, clippy::pedantic)]
            mod #name { #code }
        });
    }
    out.extend(quote! {
        /// Number of accepted mutants expanded above.
        pub const ACCEPTED_MUTANTS: usize = #accepted;
    });
    out
}
