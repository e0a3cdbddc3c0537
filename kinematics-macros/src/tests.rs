//! Tests of the whole expansion.

use quote::quote;

fn four_bar() -> proc_macro2::TokenStream {
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

#[test]
fn four_bar_expansion_snapshot() {
    let tokens = super::expand(four_bar());
    let file: syn::File = syn::parse2(tokens).expect("the expansion is valid Rust");
    insta::assert_snapshot!(prettyplease::unparse(&file));
}

#[test]
fn four_bar_operation_count_after_cse() {
    let [(_, newton), (_, analysis)] = super::op_counts(four_bar()).expect("valid definition");
    let (newton_tree, newton_shared) = (newton.tree, newton.shared as u64);
    let (analysis_tree, analysis_shared) = (analysis.tree, analysis.shared as u64);
    println!("residual and Jacobian: {newton_tree} operations as trees, {newton_shared} after CSE");
    println!("analysis: {analysis_tree} operations as trees, {analysis_shared} after CSE");
    assert!(newton_shared <= newton_tree);
    // The analysis (Jacobian, both right-hand sides, three points with their
    // velocities and accelerations) repeats sin/cos and products heavily as
    // trees; sharing must remove most of it.
    assert!(
        analysis_shared * 2 < analysis_tree,
        "expected CSE to at least halve the work: {analysis_shared} of {analysis_tree}"
    );
}

#[test]
fn errors_come_back_as_compile_errors_not_panics() {
    let out = super::expand(quote! {
        struct M {
            params { a }
            drivers { phi }
            unknowns { x }
            constraints { x * polar(a, phi) == 1.0 }
        }
    });
    let text = out.to_string();
    assert!(text.contains("compile_error"), "{text}");
}

/// A small seeded generator for the mutation test.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        usize::try_from(self.next() % (n.max(1) as u64)).unwrap_or(0)
    }
}

fn definitions() -> Vec<proc_macro2::TokenStream> {
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
            struct Scalar {
                params { r, k }
                drivers { t }
                unknowns { y }
                constraints { powi(y, 2) + atan2(t, r) * dot(vec2(1.0, 2.0), vec2(y, t)) == sqrt(k) / ln(2.0) + norm(vec2(t, -y)).x; }
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

#[test]
fn mutated_definitions_give_code_or_errors_never_a_panic() {
    let mut rng = Rng(0xF00D);
    let bases = definitions();
    let mut errors = 0;
    let mut accepted = 0;
    for case in 0..3000 {
        let mut ts = bases[case % bases.len()].clone();
        for _ in 0..=rng.below(3) {
            ts = mutate(ts, &mut rng);
        }
        let input = ts.to_string();
        let out = std::panic::catch_unwind(|| super::expand(ts))
            .unwrap_or_else(|_| panic!("the macro panicked on: {input}"));
        let text = out.to_string();
        if text.contains("compile_error") {
            errors += 1;
        } else {
            // Accepted definitions must expand to valid Rust.
            syn::parse2::<syn::File>(out)
                .unwrap_or_else(|e| panic!("invalid expansion ({e}) of: {input}"));
            accepted += 1;
        }
    }
    println!("{errors} rejected with errors, {accepted} accepted");
    // Both outcomes must be exercised for the test to mean anything.
    assert!(errors > 1000 && accepted > 30, "{errors} / {accepted}");
}
