//! Noise suppression: dropping insignificant curvature extrema, persistence style.
//!
//! The candidate sequence `n_0 (start), n_1, …, n_m (end)` describes `|κ|` completely: it is
//! monotonic between consecutive nodes. Simplification repeats two steps until nothing changes:
//!
//! 1. **Keep turning points only.** A node whose `|κ|` lies between its neighbours' (inclusive)
//!    is not an extremum (`|κ|` is monotonic through it): drop it. Afterwards interior nodes
//!    alternate between maxima and minima of `|κ|` (inflections are minima with `|κ| ≈ 0`).
//! 2. **Cancel the least significant pair.** Among neighbouring pairs that are insignificant
//!    (see [`Significance`]), take the one with the smallest `| |κ_a| − |κ_b| |` and remove it:
//!    both nodes when both are interior (a max/min pair, a bump of `|κ|`), or only the interior
//!    one when its partner is the start or end (a tiny bump at an end of the curve). An
//!    inflection next to a free end of the stroke is such a bump too when the stretch beyond it
//!    bends by less than the tolerance; the end's curvature is then taken as zero
//!    ([`SplitOptions::free_ends`](super::SplitOptions::free_ends)).
//!
//! Taking the smallest difference first is the rule of topological persistence: a bump is only
//! cancelled after every smaller bump inside it, so what remains between two surviving nodes
//! deviates from monotonic by at most one insignificant difference. The start and end always
//! survive, so the result never loses the curve's extent.

use super::candidates::Node;

/// Two pairs whose curvature differences agree to this fraction of the larger magnitude are a
/// tie: a few hundred ulps, far below any real difference and far above rounding.
const PERSISTENCE_TIE: f64 = 1e-12;

/// When two neighbouring nodes' curvature magnitudes differ insignificantly:
/// `|a − b| < max(relative · max(a, b), floor)`, or, with a tolerance and both nodes of one
/// curvature sign, when the bump they bound changes the curve by less than it:
/// `|a − b|·ℓ²/8 < tolerance` for nodes `ℓ` apart in arc length. (A curvature change `δκ` spread over a stretch `ℓ` whose ends are held moves its middle
/// by about `δκ·ℓ²/8`, the sagitta of the bend: below the fitting tolerance the samples cannot
/// tell the bump from no bump.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Significance {
    /// [`SplitOptions::extremum_relative`](super::SplitOptions::extremum_relative).
    pub relative: f64,
    /// `κ_straight` (see [`SplitOptions`](super::SplitOptions)).
    pub floor: f64,
    /// [`SplitOptions::tolerance`](super::SplitOptions::tolerance); 0 disables the test.
    pub tolerance: f64,
    /// [`SplitOptions::free_ends`](super::SplitOptions::free_ends).
    pub free_ends: (bool, bool),
}

impl Significance {
    /// Whether nodes `a` and `b` differ insignificantly; `end_inflection` when one of them is
    /// an end of the curve and the other an inflection.
    pub(crate) fn insignificant(&self, a: &Node, b: &Node, end_inflection: bool) -> bool {
        let (ka, kb) = (a.magnitude(), b.magnitude());
        let difference = (ka - kb).abs();
        if difference < (self.relative * ka.max(kb)).max(self.floor) {
            return true;
        }
        // Only a bump within one curvature sign: cancelling a pair that involves an inflection
        // (κ = 0 exactly) would leave a span whose curvature changes sign. Except between an
        // inflection and an end of the curve: |κ| is monotonic between them, so a stretch there
        // that bends by less than the tolerance is straight as far as the samples can tell,
        // and the sign it shows is the noise's (a curve drawn into a flat end, κ → 0, had an
        // inflection found a few samples before its end and a tangle of segments fitted there).
        let same_sign = a.kappa * b.kappa > 0.0 || end_inflection;
        let ell = (b.s - a.s).abs();
        same_sign && self.tolerance > 0.0 && difference * ell * ell / 8.0 < self.tolerance
    }
}

/// Step 1: drops every interior node whose `|κ|` is between its neighbours' (inclusive).
pub(crate) fn keep_turning_points(nodes: &mut Vec<Node>) {
    let n = nodes.len();
    if n < 3 {
        return;
    }
    let mut kept = 1;
    for i in 1..n - 1 {
        let previous = nodes[kept - 1].magnitude();
        let value = nodes[i].magnitude();
        let next = nodes[i + 1].magnitude();
        let monotonic_through =
            (previous <= value && value <= next) || (previous >= value && value >= next);
        if !monotonic_through {
            nodes[kept] = nodes[i];
            kept += 1;
        }
    }
    nodes[kept] = nodes[n - 1];
    nodes.truncate(kept + 1);
}

/// Steps 1 and 2 repeated until no insignificant pair is left.
pub(crate) fn simplify(nodes: &mut Vec<Node>, significance: &Significance) {
    loop {
        keep_turning_points(nodes);
        let Some(last) = nodes.len().checked_sub(1) else {
            return;
        };
        if last < 2 {
            return;
        }
        // (difference, first index to remove, how many, the end whose curvature becomes 0)
        let mut best: Option<(f64, usize, usize, Option<usize>)> = None;
        for i in 0..last {
            // The pair's interior node, when the other is a free end of the curve.
            let interior = if i == 0 && significance.free_ends.0 {
                Some(&nodes[1])
            } else if i + 1 == last && significance.free_ends.1 {
                Some(&nodes[i])
            } else {
                None
            };
            let end_inflection = interior.is_some_and(|n| n.kappa == 0.0);
            if !significance.insignificant(&nodes[i], &nodes[i + 1], end_inflection) {
                continue;
            }
            let (a, b) = (nodes[i].magnitude(), nodes[i + 1].magnitude());
            let removal = if i == 0 {
                (1, 1)
            } else if i + 1 == last {
                (i, 1)
            } else {
                (i, 2)
            };
            let difference = (a - b).abs();
            // Equal differences (a symmetric bump, up to rounding) go to the earlier pair, so
            // rounding never picks which one survives.
            let tie = PERSISTENCE_TIE * a.max(b);
            if best.is_none_or(|(d, _, _, _)| difference < d - tie) {
                let end = end_inflection.then_some(if i == 0 { 0 } else { last });
                best = Some((difference, removal.0, removal.1, end));
            }
        }
        let Some((_, first, count, end)) = best else {
            return;
        };
        // An end past a cancelled inflection is straight as far as the samples tell: its
        // curvature is taken as zero, so that the span before it falls to zero there instead of
        // turning back up to the noise's sign (which no single segment can follow).
        if let Some(end) = end {
            nodes[end].kappa = 0.0;
        }
        nodes.drain(first..first + count);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nodes(values: &[f64]) -> Vec<Node> {
        values
            .iter()
            .enumerate()
            .map(|(i, &kappa)| Node {
                u: i as f64,
                piece: 0,
                t: 0.0,
                kappa,
                s: i as f64,
            })
            .collect()
    }

    fn values(nodes: &[Node]) -> Vec<f64> {
        nodes.iter().map(|n| n.kappa).collect()
    }

    #[test]
    fn monotonic_runs_collapse() {
        let mut n = nodes(&[1.0, 2.0, 3.0, 2.0, 2.0, 1.0, 5.0]);
        keep_turning_points(&mut n);
        assert_eq!(values(&n), [1.0, 3.0, 1.0, 5.0]);
        let mut flat = nodes(&[0.0, 0.0, 0.0, 0.0]);
        keep_turning_points(&mut flat);
        assert_eq!(values(&flat), [0.0, 0.0]);
        // Signs do not matter, magnitudes do: an inflection (0) between two lobes is a minimum.
        let mut s = nodes(&[0.5, 1.0, 0.0, -1.0, -0.5]);
        keep_turning_points(&mut s);
        assert_eq!(values(&s), [0.5, 1.0, 0.0, -1.0, -0.5]);
    }

    #[test]
    fn small_bump_is_cancelled_large_kept() {
        let sig = Significance {
            relative: 0.05,
            floor: 1e-3,
            tolerance: 0.0,
            free_ends: (false, false),
        };
        // 1.0 → 2.0 (max) → 1.96 (min, 2 % below) → 1.99 (max) → 0.5: the 1.96/1.99 pair goes.
        let mut n = nodes(&[1.0, 2.0, 1.96, 1.99, 0.5]);
        simplify(&mut n, &sig);
        assert_eq!(values(&n), [1.0, 2.0, 0.5]);
        // A 30 % dip is real.
        let mut m = nodes(&[1.0, 2.0, 1.4, 2.0, 0.5]);
        simplify(&mut m, &sig);
        assert_eq!(values(&m), [1.0, 2.0, 1.4, 2.0, 0.5]);
    }

    #[test]
    fn bump_at_an_end_is_cancelled() {
        let sig = Significance {
            relative: 0.05,
            floor: 1e-3,
            tolerance: 0.0,
            free_ends: (false, false),
        };
        let mut n = nodes(&[1.0, 1.02, 3.0, 2.0]);
        simplify(&mut n, &sig);
        assert_eq!(values(&n), [1.0, 3.0, 2.0]);
    }

    #[test]
    fn wiggles_around_zero_are_cancelled_by_the_floor() {
        let sig = Significance {
            relative: 0.05,
            floor: 1e-2,
            tolerance: 0.0,
            free_ends: (false, false),
        };
        // A near-straight stretch: inflections (0) and tiny lobes (±1e-3) between two real lobes.
        let mut n = nodes(&[0.2, 1.0, 0.0, -1e-3, 0.0, 2e-3, 0.0, -1e-3, 0.0, 1.5, 0.3]);
        simplify(&mut n, &sig);
        let v = values(&n);
        assert_eq!(v.len(), 5, "{v:?}");
        assert_eq!([v[0], v[1], v[3], v[4]], [0.2, 1.0, 1.5, 0.3]);
        assert!(v[2].abs() < 1e-2);
    }

    #[test]
    fn smallest_first_keeps_alternation() {
        // Nested bumps: 1 → 5 → 4.9 → 5.05 → 3 → 3.1 → 1 with 5 % relative: the 3/3.1 pair and the
        // 4.9/5.05 pair are both noise; 5 and 5.05 merge into one maximum.
        let sig = Significance {
            relative: 0.05,
            floor: 0.0,
            tolerance: 0.0,
            free_ends: (false, false),
        };
        let mut n = nodes(&[1.0, 5.0, 4.9, 5.05, 3.0, 3.1, 1.0]);
        simplify(&mut n, &sig);
        let v = values(&n);
        assert_eq!(v.len(), 3, "{v:?}");
        assert!(v[1] >= 5.0);
    }

    #[test]
    fn a_bump_the_tolerance_cannot_resolve_is_cancelled() {
        // A 20 % dip between two maxima (1.0 → 0.8 → 1.0, 0.5 length units each side):
        // δκ·ℓ²/8 = 0.2·0.25/8 = 0.00625. Kept with a tolerance of 0.005, cancelled with 0.01.
        let at = |s: f64, kappa: f64| Node {
            u: s,
            piece: 0,
            t: 0.0,
            kappa,
            s,
        };
        let bump = [
            at(0.0, 0.5),
            at(1.0, 1.0),
            at(1.5, 0.8),
            at(2.0, 1.0),
            at(3.0, 0.2),
        ];
        for (tolerance, expected) in [(0.005, 5), (0.01, 3)] {
            let sig = Significance {
                relative: 0.05,
                floor: 1e-3,
                tolerance,
                free_ends: (false, false),
            };
            let mut n = bump.to_vec();
            simplify(&mut n, &sig);
            assert_eq!(n.len(), expected, "tolerance {tolerance}: {:?}", values(&n));
        }
    }
}
