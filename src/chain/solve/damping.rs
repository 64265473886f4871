//! Levenberg–Marquardt damping: the multiple λ of the normal matrix's (floored) diagonal added
//! to a Gauss–Newton step, and how it moves between tries. Both of the chain's least-squares
//! loops, the G1 refinement and the smooth fit, take their damping from here; each names its
//! own [`DampingOptions`] (why they differ is said where they are defined).
//!
//! A step is tried with the current λ: a refused try (the cost rose, the system could not be
//! factored, the trial left what it must keep) raises λ and tries again, an accepted one lowers
//! it. Tries stop once λ reaches [`DampingOptions::max`]: the steps are then too short to
//! matter, and the solve has converged or is stuck.

/// How λ changes after a try.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum DampingRule {
    /// Marquardt's: λ times `growth` after a refused try; after an accepted one λ divided by
    /// `shrink`, never below `floor`.
    Marquardt {
        /// Factor of a refused try.
        growth: f64,
        /// Divisor of an accepted try.
        shrink: f64,
        /// Smallest λ.
        floor: f64,
    },
    /// Nielsen's (Madsen, Nielsen & Tingleff, "Methods for non-linear least squares problems",
    /// 2004, §3.2): after a refused try λ times ν, then ν doubled (ν starts at `growth`); after an
    /// accepted try whose cost fell by ρ times the decrease the linear model predicted, λ times
    /// max(1/3, 1 − (2ρ − 1)³) and ν back to `growth`. λ falls fast where the model predicts
    /// the step well and rises fast where one refusal follows another.
    Nielsen {
        /// ν after an accepted try.
        growth: f64,
    },
}

/// Where λ starts, where the tries stop, and how it moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DampingOptions {
    /// λ of the first try.
    pub initial: f64,
    /// Tries stop once λ reaches this (a try with λ below it is made).
    pub max: f64,
    /// How λ moves.
    pub rule: DampingRule,
}

/// The damping of one least-squares loop (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Damping {
    lambda: f64,
    /// Nielsen's ν (Marquardt's growth, fixed).
    nu: f64,
    options: DampingOptions,
}

impl Damping {
    /// The damping at its start.
    pub(crate) fn new(options: DampingOptions) -> Self {
        Damping {
            lambda: options.initial,
            nu: Self::reset_nu(options.rule),
            options,
        }
    }

    fn reset_nu(rule: DampingRule) -> f64 {
        match rule {
            DampingRule::Marquardt { growth, .. } | DampingRule::Nielsen { growth } => growth,
        }
    }

    /// The current λ.
    pub(crate) fn lambda(&self) -> f64 {
        self.lambda
    }

    /// Whether another try may be made (λ below [`DampingOptions::max`]).
    pub(crate) fn may_try(&self) -> bool {
        self.lambda < self.options.max
    }

    /// After a refused try: λ raised.
    pub(crate) fn refuse(&mut self) {
        self.lambda *= self.nu;
        if let DampingRule::Nielsen { .. } = self.options.rule {
            self.nu *= 2.0;
        }
    }

    /// After an accepted try whose cost fell by `gain` times the decrease its linear model
    /// predicted (Nielsen's rule reads it; Marquardt's does not): λ lowered.
    pub(crate) fn accept(&mut self, gain: f64) {
        match self.options.rule {
            DampingRule::Marquardt { shrink, floor, .. } => {
                self.lambda = (self.lambda / shrink).max(floor);
            }
            DampingRule::Nielsen { growth } => {
                self.lambda *= (1.0 - (2.0 * gain - 1.0).powi(3)).max(1.0 / 3.0);
                self.nu = growth;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NIELSEN: DampingOptions = DampingOptions {
        initial: 1e-2,
        max: 1e8,
        rule: DampingRule::Nielsen { growth: 2.0 },
    };

    const MARQUARDT: DampingOptions = DampingOptions {
        initial: 1e-2,
        max: 1e12,
        rule: DampingRule::Marquardt {
            growth: 10.0,
            shrink: 3.0,
            floor: 1e-12,
        },
    };

    /// Nielsen's refusals multiply λ by 2, 4, 8, ...: after k refusals λ = λ₀·2^{k(k+1)/2}.
    #[test]
    fn nielsen_refusals_grow_geometrically_faster() {
        let mut d = Damping::new(NIELSEN);
        for k in 1..=5 {
            d.refuse();
            let expected = 1e-2 * 2f64.powi(k * (k + 1) / 2);
            assert!((d.lambda() - expected).abs() <= 1e-12 * expected, "{k}");
        }
        // An accepted try resets ν: the next refusal doubles λ again.
        d.accept(1.0);
        let after = d.lambda();
        d.refuse();
        assert_eq!(d.lambda(), 2.0 * after);
    }

    /// Nielsen's acceptance: a perfect model (ρ = 1) divides λ by 3, ρ = 1/2 keeps it, a poor
    /// one (ρ → 0) keeps it near where it was (factor 2 at ρ = 0).
    #[test]
    fn nielsen_acceptance_follows_the_gain_ratio() {
        for (gain, factor) in [(1.0, 1.0 / 3.0), (0.5, 1.0), (0.0, 2.0)] {
            let mut d = Damping::new(NIELSEN);
            d.accept(gain);
            assert!((d.lambda() - 1e-2 * factor).abs() <= 1e-15, "{gain}");
        }
    }

    /// Marquardt's: ×10 on refusal, ÷3 on acceptance, floored; tries stop at the bound.
    #[test]
    fn marquardt_steps_and_bounds() {
        let mut d = Damping::new(MARQUARDT);
        d.refuse();
        assert_eq!(d.lambda(), 1e-2 * 10.0);
        d.accept(0.0);
        assert_eq!(d.lambda(), 1e-2 * 10.0 / 3.0);
        for _ in 0..40 {
            d.accept(1.0);
        }
        assert_eq!(d.lambda(), 1e-12);
        // The last try is made below the bound; the refusal after it reaches the bound.
        let mut last_tried = 0.0;
        while d.may_try() {
            last_tried = d.lambda();
            d.refuse();
        }
        assert!(
            last_tried < 1e12 && d.lambda() >= 1e12,
            "{last_tried} {}",
            d.lambda()
        );
        assert_eq!(d.lambda(), 10.0 * last_tried);
    }
}
