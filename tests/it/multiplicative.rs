//! Multiplicative noise on the plant's matrices (seed 003 (3.1)): A(k) = Ā(k) + Σ ζ_i(k) A_i(k),
//! and likewise B, C, D, Cz, Dz, with one ζ shared by the matrices it names.
//!
//! - Dropouts are one instance: a Rademacher factor on C with C̄ = M = C/2 makes C(k) ∈ {0, C}
//!   with probability ½ each, the dropout plant with p = ½; its exact error, Λ = E[𝓕ᵀ𝓕] and
//!   |||F|||_a equal the dropout machinery's to rounding (1e-10 relative).
//! - The Monte Carlo agrees with the exact moments (which add Σ_i F_i Y F_iᵀ) per step (4.5σ) and in
//!   total (4σ), for Gaussian and uniform ζ, on a time-varying plant.
//! - Λ from the backward second-moment recursion gives the exact summed error as tr(Λ E[JJᵀ]), and
//!   Lemma 1's Riccati route gives the eigenvalues' |||F|||_a, with the factors' terms (1e-8).
//! - The designs that do not model multiplicative noise refuse such a plant, naming it.

use filterbench::analysis::anisotropy::{anisotropic_norm_from_eigenvalues, error_gram};
use filterbench::analysis::exact;
use filterbench::analysis::lemma1::Lemma1;
use filterbench::config;
use filterbench::model::plant::Pattern;
use filterbench::numerics::linalg::{block_diag, sym_eigen};

use crate::time_varying::{parse, plant_text};

const KALMAN: &str = "[[filters]]\nname = \"kalman\"\nfamily = \"kalman\"\n";
const SCENARIOS: &str = "[[scenarios]]\nname = \"nominal\"\n\n[[scenarios]]\nname = \"laplace\"\nshape = \"laplace\"\n";

/// A factor on A and C (shared ζ) and one on B alone, with `shape`.
fn factors(shape: &str) -> String {
    format!(
        "[[plant.multiplicative]]\nname = \"gust\"\nshape = \"{shape}\"\nA = [[0.1, 0.05], [0.0, 0.15]]\nC = [[0.3, 0.0]]\n\n\
         [[plant.multiplicative]]\nname = \"gain\"\nB = [[0.2, 0.0], [0.0, 0.1]]\n"
    )
}

#[test]
fn monte_carlo_matches_exact_with_multiplicative_noise() {
    for (pattern, shape) in [("filtering", "gaussian"), ("prediction", "uniform")] {
        let exp = parse(&plant_text(pattern, 40, false, &factors(shape), KALMAN, SCENARIOS));
        assert_eq!(exp.plant.factors.len(), 2);
        crate::exact_vs_mc::check(&exp);
    }
    // With dropouts as well (the two mechanisms together).
    let exp = parse(&plant_text(
        "prediction",
        40,
        false,
        &format!("arrival = 0.85\n{}", factors("gaussian")),
        KALMAN,
        SCENARIOS,
    ));
    crate::exact_vs_mc::check(&exp);
}

/// The plant text without its `C_steps` line (C constant).
pub(crate) fn no_c_steps(t: String) -> String {
    let start = t.find("C_steps").unwrap();
    let end = start + t[start..].find('\n').unwrap() + 1;
    format!("{}{}", &t[..start], &t[end..])
}

#[test]
fn dropouts_are_a_rademacher_factor_on_c() {
    // The constant C = [1, 0] (no C_steps): dropouts multiply it by λ ∈ {0, 1}; the factor plant
    // has C̄ = [½, 0] and M = [½, 0] with ζ = ±1.
    let dropout = parse(&no_c_steps(plant_text("prediction", 30, false, "arrival = 0.5", KALMAN, SCENARIOS)));
    let lambda = "[[plant.multiplicative]]\nname = \"lambda\"\nshape = \"rademacher\"\nC = [[0.5, 0.0]]\n";
    let factor = parse(
        &no_c_steps(plant_text("prediction", 30, false, lambda, KALMAN, SCENARIOS))
            .replace("C = [[1.0, 0.0]]", "C = [[0.5, 0.0]]"),
    );
    assert!(dropout.plant.arrival() == Some(0.5) && factor.plant.factors.len() == 1);
    for pattern in [Pattern::Prediction] {
        let real = filterbench::families::kalman::kalman(&dropout.plant, &dropout.nominal, pattern);
        let (a, b) = (
            exact::error(&dropout.plant, &real, &dropout.nominal),
            exact::error(&factor.plant, &real, &factor.nominal),
        );
        assert!(
            (a.total - b.total).abs() <= 1e-10 * a.total,
            "summed error: dropouts {} vs factor {}",
            a.total,
            b.total
        );
        for (k, (x, y)) in a.per_step.iter().zip(&b.per_step).enumerate() {
            assert!((x - y).abs() <= 1e-10 * x.max(1e-12), "step {k}: {x} vs {y}");
        }
        let (la, lb) = (error_gram(&dropout.plant, &real).unwrap(), error_gram(&factor.plant, &real).unwrap());
        assert!((&la - &lb).amax() <= 1e-10 * la.amax(), "Λ differs by {}", (&la - &lb).amax());
        for level in [0.0, 5.0] {
            let (na, nb) = (
                Lemma1::new(&dropout.plant, &real).unwrap().norm(level).unwrap().value,
                Lemma1::new(&factor.plant, &real).unwrap().norm(level).unwrap().value,
            );
            assert!((na - nb).abs() <= 1e-10 * na, "a = {level}: {na} vs {nb}");
        }
    }
}

/// tr(Λ E[JJᵀ]) is the exact summed error (no means: x0's mean and the known input are zero here),
/// and Lemma 1 gives the eigenvalues' |||F|||_a with multiplicative noise.
#[test]
fn lambda_and_lemma1_carry_the_factor_terms() {
    let exp = parse(&plant_text("prediction", 25, false, &factors("gaussian"), KALMAN, SCENARIOS));
    let real = filterbench::families::kalman::kalman(&exp.plant, &exp.nominal, Pattern::Prediction);
    let lambda = exact::second_moment_operator(&exp.plant, &real).unwrap();
    let w = exp.nominal.w();
    let blocks: Vec<_> =
        std::iter::once(exp.nominal.x0().clone()).chain((0..exp.plant.steps()).map(|_| w.clone())).collect();
    let j = block_diag(&blocks.iter().collect::<Vec<_>>());
    let via_lambda = (&lambda * &j).trace();
    let direct = exact::error(&exp.plant, &real, &exp.nominal).total;
    assert!((via_lambda - direct).abs() <= 1e-9 * direct, "tr(ΛJ) = {via_lambda} vs exact {direct}");
    let mu: Vec<f64> =
        sym_eigen(&error_gram(&exp.plant, &real).unwrap()).unwrap().0.into_iter().map(|m| m.max(0.0)).collect();
    let lemma = Lemma1::new(&exp.plant, &real).unwrap();
    for a in [0.0, 1.0, 20.0] {
        let (dense, riccati) = (anisotropic_norm_from_eigenvalues(&mu, a).unwrap().value, lemma.norm(a).unwrap().value);
        assert!((dense - riccati).abs() <= 1e-8 * dense, "a = {a}: eigenvalues {dense} vs Lemma 1 {riccati}");
    }
}

#[test]
fn designs_without_multiplicative_noise_refuse_it() {
    let cases = [
        ("prediction", "[[filters]]\nname = \"i\"\nfamily = \"intermittent\"\n", "multiplicative"),
        ("prediction", "[[filters]]\nname = \"h\"\nfamily = \"hinf\"\nlambda = \"min\"\n", "multiplicative"),
        ("filtering", "[[filters]]\nname = \"m\"\nfamily = \"minimax\"\n", "multiplicative"),
    ];
    for (pattern, filters, needle) in cases {
        // Refused when the file is loaded, by the one capability check (families::Supports).
        let text = plant_text(pattern, 10, true, &factors("gaussian"), filters, SCENARIOS);
        let err = config::parse("mult", "mult.toml", &text).err().expect("refused").to_string();
        assert!(err.contains(needle) && err.contains("does not design for"), "{err}");
    }
    let text = plant_text("prediction", 10, true, "[[plant.multiplicative]]\nname = \"empty\"\n", KALMAN, SCENARIOS);
    let err = filterbench::config::parse("m", "m.toml", &text).err().expect("refused").to_string();
    assert!(err.contains("plant.multiplicative[0]") && err.contains("at least one"), "{err}");
}
