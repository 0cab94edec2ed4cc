//! The design's types: the follow-ups of the menu ([`FollowUp`]), the settings, the
//! contenders and their chances, and the [`Plan`] a discrepancy run carries (plain data,
//! imported by the run's findings and by the design's own files).

use crate::discrepancy::candidate::Candidate;
use crate::discrepancy::observations::Observable;
use crate::discrepancy::simulate::GroupSetup;
use crate::generator::spec::WallSpec;
use serde::Serialize;

/// What a follow-up changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FollowUpKind {
    /// More specimens of a group, read as the first campaign read it.
    MoreSpecimens,
    /// Specimens of a group with the failure mechanism read (height, kind, start).
    Mechanism,
    /// Specimens of a group with both top measures read at more tilts.
    Monitors,
    /// Walls of another height (an extra group).
    Height,
    /// Walls of another length (an extra group).
    Length,
    /// Walls with the other end restraint (free ↔ rigid; an extra group).
    Restraint,
}

/// How a follow-up's walls differ from its group's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct WallEdit {
    /// Factor on the height (courses of the same law).
    pub height_factor: Option<f64>,
    /// Factor on the length.
    pub length_factor: Option<f64>,
    /// The other end restraint: `Some(true)` rigid ends (zone 0.05 m), `Some(false)` free.
    pub rigid_ends: Option<bool>,
}

/// One follow-up test.
#[derive(Debug, Clone, Serialize)]
pub struct FollowUp {
    /// What it is, e.g. `SBL walls 1.5 × taller (SBL_tall)`.
    pub name: String,
    /// Its kind.
    pub kind: FollowUpKind,
    /// The group its specimens belong to (an existing group, or the new one).
    pub group: String,
    /// The group of the first campaign it starts from.
    pub from_group: String,
    /// The observables read on each specimen (the kinds and starts: one of them is seen).
    pub observables: Vec<Observable>,
    /// The new group (walls of another height, length or restraint), if any.
    #[serde(skip)]
    pub new_group: Option<GroupSetup>,
    /// Its wall description (to write the follow-up study).
    #[serde(skip)]
    pub new_spec: Option<WallSpec>,
    /// How its walls differ.
    pub edit: WallEdit,
}

/// Settings of a design.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DesignSettings {
    /// Specimens of each follow-up: the budget every follow-up is compared at \[3\].
    pub specimens: usize,
    /// Simulated follow-ups per contender taken as the truth \[200\].
    pub replicates: usize,
    /// Bayesian-bootstrap draws of each simulated data set's weights \[200\].
    pub draws: usize,
    /// The probability of naming the cause alone a follow-up should reach; the report
    /// gives the fewest specimens that reach it \[0.8\].
    pub target: f64,
}

impl Default for DesignSettings {
    fn default() -> Self {
        DesignSettings { specimens: 3, replicates: 200, draws: 200, target: 0.8 }
    }
}

/// A model the design compares: its name, its prior weight and its held-out log score per
/// specimen of the first campaign (nats).
#[derive(Debug, Clone, Serialize)]
pub struct Contender {
    /// `baseline`, a candidate (`a`, `a+b`) or `scatter`.
    pub name: String,
    /// Its prior as a truth ([`super::contenders`]): the pseudo-BMA+ weight on the first
    /// campaign renormalized over the analysis's contenders to `1 − OUTSIDE_PRIOR`, or a
    /// share of [`super::OUTSIDE_PRIOR`] for a truth outside them.
    pub prior: f64,
    /// A truth outside the analysis's contenders (the pair of the best singles, an effect
    /// not ranked among them), its prior a share of [`super::OUTSIDE_PRIOR`].
    pub outside: bool,
    /// A pair of single effects that the analysis adds to its ranking only when it beats
    /// the best single (`stages::add_pairs`: the pairs of the best one-parameter effects,
    /// admitted when their held-out error is below the best single's less the gain
    /// margin), as the analysis's own pairs and the pair of the best singles are; a
    /// readings pair, which the analysis ranks always, is not one.
    pub pair: bool,
    /// The candidate the design built for it (a pair the analysis did not try), with its
    /// first-campaign fit; `None`: the analysis's own.
    #[serde(skip)]
    pub made: Option<std::sync::Arc<Made>>,
    /// Held-out log predictive density per specimen of the first campaign.
    #[serde(skip)]
    pub elpd: Vec<f64>,
    /// The same on the measures alone (collapse angles and displacements,
    /// [`crate::discrepancy::Observable::pins`]; `elpd` where nothing else is read).
    #[serde(skip)]
    pub elpd_measures: Vec<f64>,
}

/// The probability of the answer after a follow-up of `specimens` specimens.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Chance {
    /// Specimens of the follow-up.
    pub specimens: usize,
    /// Probability that the true cause is named alone: both tests of the tie check clear
    /// every other contender after every contender is refit on both campaigns
    /// ([`super::Problem::chances`]), the verdict's criterion.
    pub alone: f64,
    /// The Monte Carlo standard error of `alone`: the standard deviation of `alone` over
    /// bootstrap resamples of each truth's simulated follow-ups (the reversal rates, which
    /// all of a truth's follow-ups share, resampled with them).
    pub alone_se: f64,
    /// Probability that the true cause alone holds 90 % of the pseudo-BMA+ weight (the
    /// weights' concentration, reported beside the verdict's criterion).
    pub weights_alone: f64,
    /// Probability that the true cause is among the models that share the weight.
    pub right: f64,
    /// The probability of `alone` for each contender taken as the truth (contender order,
    /// the first [`Plan::truths`]).
    pub alone_by_truth: Vec<f64>,
    /// `[truth][contender]`: what stops each truth being named alone, contender by
    /// contender: one less the mean, over the truth's simulated follow-ups, of the
    /// probability that the tie check clears that contender (0 where it always clears, 1
    /// where it never does; 0 for the truth itself and for a pair the analysis would not
    /// rank in that follow-up, [`super::Problem::present`]). A follow-up in which the truth,
    /// a pair, is not ranked counts as cleared for every contender: it is not named alone,
    /// and no contender stops it.
    pub blocked_by: Vec<Vec<f64>>,
    /// `[truth][contender]`: the share of the truth's simulated follow-ups in which the
    /// data test of the tie check does not separate the contender from it (the held-out
    /// difference under [`crate::discrepancy::TieCheck::STANDARD_ERRORS`] standard errors on
    /// every observation and on the measures); the rest of `blocked_by` is the reversal
    /// test's.
    pub data_blocked_by: Vec<Vec<f64>>,
}

/// One follow-up, with its probabilities.
#[derive(Debug, Clone, Serialize)]
pub struct RankedFollowUp {
    /// The follow-up.
    pub followup: FollowUp,
    /// The probabilities at every specimen count of the ladder, fewest first.
    pub chances: Vec<Chance>,
    /// The probability at the budget (`DesignSettings::specimens`).
    pub at_budget: Chance,
    /// The fewest specimens of the ladder that reach `DesignSettings::target`, if any.
    pub to_target: Option<usize>,
    /// Forward runs this follow-up needed (0: the fitted surrogates sufficed).
    pub runs: usize,
    /// `[truth][key]` of the follow-up's keys (`followup.observables`): the contenders'
    /// disagreement on walls of a new kind that the follow-ups drawn from each truth carry
    /// (`Problem::disagreement`, in units of the key's predictive variance under the
    /// truth); empty for a follow-up of the first campaign's walls.
    pub disagreement: Vec<Vec<f64>>,
    /// Its place in the menu (0-based): names its random streams.
    pub menu_index: usize,
}

/// The chosen follow-up's probability of naming the cause alone, re-estimated at the
/// budget on simulated follow-ups independent of those that ranked the menu
/// ([`super::Stream::report`]): the maximum of the ranking's estimates is biased upward
/// even when each is unbiased (the optimizer's curse, Smith & Winkler 2006, *Management
/// Science* 52, 311–322); an estimate on fresh replicates is not.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reported {
    /// Specimens of the follow-up (the budget).
    pub specimens: usize,
    /// Fresh simulated follow-ups per truth.
    pub replicates: usize,
    /// The re-estimated probabilities at the budget (`alone`, `weights_alone`, `right`,
    /// by truth), the prior-weighted mean over the truths.
    pub chance: Chance,
    /// The Monte Carlo interval of `chance.alone`: the Wilson score interval
    /// ([`crate::stats::wilson`]) at [`Reported::LEVEL`] on the effective count `n_eff`.
    pub interval: (f64, f64),
    /// The effective count of the interval: the count whose binomial variance is the
    /// bootstrap's, `p (1 − p) / se²` (`p` = `chance.alone`, `se` = `chance.alone_se`),
    /// at most `replicates / Σ_t w_t²` (`w_t` the truths' normalized priors; Kish's
    /// effective sample size of a weighted mean of proportions each from `replicates`
    /// draws, Kish 1965, *Survey Sampling*), which it is where `p` is 0 or 1 or the
    /// bootstrap shows no spread. The reversal rates every follow-up of a truth shares
    /// make the replicates less than independent, so the count is usually the smaller.
    pub effective_replicates: f64,
    /// The ranking's own estimate at the budget (the selecting replicates), beside it.
    pub selected: f64,
    /// Whether the follow-up is likelier to mislead than to help: the probability that the
    /// truth leaves the models that share the weight after both campaigns (`1 − right`),
    /// where every truth is among them after the first (the contenders are those models),
    /// exceeds the probability that it is named alone (`alone`). Added data then moves the
    /// answer away from the truth more often than it settles on it; the report and the
    /// command say so beside the promise.
    pub misleads: bool,
}

impl Reported {
    /// The two-sided level of [`Reported::interval`].
    pub const LEVEL: f64 = 0.95;
}

/// The design: the contenders, the probability with no follow-up, and every follow-up
/// ranked best first.
#[derive(Debug, Clone, Serialize)]
pub struct Plan {
    /// The contenders, heaviest first: the first [`Plan::truths`] are taken as the truth,
    /// every one is refit and scored on every simulated follow-up.
    pub contenders: Vec<Contender>,
    /// How many contenders, the first, are taken as the truth.
    pub truths: usize,
    /// `[contender]`: the model discrepancy the first campaign shows beside it, carried into
    /// the follow-ups drawn from it ([`super::Inadequacy::own`]: the variance of a bias per key,
    /// in units of the key's predictive variance; 0: none).
    pub inadequacy: Vec<f64>,
    /// `[contender]`: the model discrepancy it carries to walls of a kind the first campaign
    /// did not test, beside `inadequacy` on a follow-up of new walls
    /// ([`super::Inadequacy::transfer`]: leave one group out; same units).
    pub transfer: Vec<f64>,
    /// Whether the first campaign already names the cause alone (the verdict names a cause
    /// and its tie holds no other model, [`crate::discrepancy::Analysis::named_alone`]).
    pub alone_now: bool,
    /// The follow-ups, best first.
    pub ranked: Vec<RankedFollowUp>,
    /// The settings.
    pub settings: DesignSettings,
    /// Forward runs made in all.
    pub runs: usize,
    /// The best follow-up's probability re-estimated on fresh replicates, with its
    /// interval: the promise the design reports (`None`: an empty menu).
    pub reported: Option<Reported>,
}

impl Plan {
    /// The best follow-up.
    pub fn best(&self) -> Option<&RankedFollowUp> {
        self.ranked.first()
    }

    /// The probability the design promises for its best follow-up: the re-estimate
    /// ([`Plan::reported`]), else the ranking's estimate at the budget.
    pub fn promise(&self) -> Option<f64> {
        self.reported.as_ref().map(|r| r.chance.alone).or_else(|| self.best().map(|b| b.at_budget.alone))
    }
}

/// A contender the design builds beside the analysis's pool (a pair of single effects the
/// analysis did not try): its candidate and its first-campaign fit (search coordinates).
#[derive(Debug, Clone)]
pub struct Made {
    /// The candidate (the additive surrogate of two single effects).
    pub candidate: Candidate,
    /// Its fit on the first campaign: the scan point of least summed score.
    pub x: Vec<f64>,
}
