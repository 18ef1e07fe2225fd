//! Step lengths of a Levy flight by Mantegna's method (R. N. Mantegna, "Fast,
//! accurate algorithm for numerical simulation of Levy stable stochastic
//! processes", Phys. Rev. E 49, 1994): `s = |u| / |v|^(1/beta)` with
//! `u ~ N(0, sigma_u^2)` and `v ~ N(0, 1)`, whose tail follows the Levy
//! law `P(s > x) ~ x^-beta`.

use rand::Rng;
use rand_distr::StandardNormal;

/// A Mantegna sampler for one exponent `beta` (meaningful in `(0, 2)`).
#[derive(Clone, Copy, Debug)]
pub(super) struct Mantegna {
    sigma_u: f64,
    inv_beta: f64,
}

impl Mantegna {
    pub(super) fn new(beta: f64) -> Self {
        let num = gamma(1.0 + beta) * (std::f64::consts::PI * beta / 2.0).sin();
        let den = gamma((1.0 + beta) / 2.0) * beta * 2f64.powf((beta - 1.0) / 2.0);
        let sigma_u = (num / den).abs().powf(1.0 / beta);
        Mantegna { sigma_u: if sigma_u.is_finite() { sigma_u } else { 1.0 }, inv_beta: 1.0 / beta }
    }

    /// One heavy-tailed magnitude; `+inf` when `v` happens to be 0, which the
    /// caller's clamp turns into the longest flight.
    pub(super) fn sample<R: Rng>(&self, rng: &mut R) -> f64 {
        let u: f64 = rng.sample::<f64, _>(StandardNormal) * self.sigma_u;
        let v: f64 = rng.sample(StandardNormal);
        let s = u.abs() / v.abs().powf(self.inv_beta);
        // 0/0 only when both draws are exactly 0.
        if s.is_nan() {
            0.0
        } else {
            s
        }
    }
}

/// Gamma function by the Lanczos approximation (g = 7, 9 terms), about 15
/// significant digits on the positive reals; std has no stable `gamma`.
pub(super) fn gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection formula.
        return std::f64::consts::PI / ((std::f64::consts::PI * x).sin() * gamma(1.0 - x));
    }
    let x = x - 1.0;
    let mut acc = C[0];
    for (k, c) in C.iter().enumerate().skip(1) {
        acc += c / (x + k as f64);
    }
    let t = x + G + 0.5;
    (2.0 * std::f64::consts::PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * acc
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn gamma_known_values() {
        assert!((gamma(1.0) - 1.0).abs() < 1e-13);
        assert!((gamma(5.0) - 24.0).abs() < 1e-11);
        assert!((gamma(0.5) - std::f64::consts::PI.sqrt()).abs() < 1e-13);
        assert!((gamma(2.5) - 1.329_340_388_179_137).abs() < 1e-13);
        assert!((gamma(1.25) - 0.906_402_477_055_477).abs() < 1e-13);
    }

    #[test]
    fn mantegna_sigma_for_beta_1_5() {
        // The textbook value for beta = 1.5.
        assert!((Mantegna::new(1.5).sigma_u - 0.696_574_502_557_697_7).abs() < 1e-9);
    }

    #[test]
    fn mantegna_tail_is_heavy() {
        // P(s > x) ~ x^-beta: from x = 4 to x = 16 the survival should fall by
        // about 4^1.5 = 8 (a Gaussian tail would fall by orders of magnitude).
        let m = Mantegna::new(1.5);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let n = 400_000;
        let (mut over4, mut over16) = (0usize, 0usize);
        for _ in 0..n {
            let s = m.sample(&mut rng);
            over4 += (s > 4.0) as usize;
            over16 += (s > 16.0) as usize;
        }
        let ratio = over4 as f64 / over16 as f64;
        assert!(over16 > 500 && ratio > 5.0 && ratio < 12.0, "{over4} {over16} {ratio}");
    }
}
