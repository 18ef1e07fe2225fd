//! The three claims the paper makes about Fig. 7, checked on a sweep's
//! table of mean search times. Each claim is given a plain, fixed criterion
//! (stated in its output) and is evaluated only when the sweep holds the
//! algorithms and robot counts it needs. Nothing here feeds back into the
//! runs: the claims are measured, never tuned for.
//!
//! Every criterion is a test against the sampling error of the means, so
//! that a verdict says what the sample shows rather than which way the
//! noise fell: a claim holds when the sample shows it beyond the 95%
//! intervals, fails when the sample shows the opposite beyond them, and is
//! otherwise not decidable at the sample size ([`Verdict::Undecided`]),
//! with the smallest difference the sample could have detected.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt::Write as _;

use gridswarm::policy::Policy;
use serde::Serialize;
use serde_json::json;

use crate::robots::compress;
use crate::stats::{CellStats, RunRecord};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Holds,
    Fails,
    /// Neither shown nor refuted beyond the 95% intervals: more runs are needed.
    Undecided,
    NotEvaluated,
}

impl Verdict {
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Holds => "HOLDS",
            Verdict::Fails => "DOES NOT HOLD",
            Verdict::Undecided => "NOT DECIDABLE at this sample size",
            Verdict::NotEvaluated => "not evaluated",
        }
    }

    /// One letter, for tables of many verdicts: H, F, U, or - (not evaluated).
    pub fn letter(self) -> char {
        match self {
            Verdict::Holds => 'H',
            Verdict::Fails => 'F',
            Verdict::Undecided => 'U',
            Verdict::NotEvaluated => '-',
        }
    }

    /// Fails where any part fails, holds where every part holds, else undecided.
    pub fn all(parts: impl IntoIterator<Item = Verdict>) -> Verdict {
        let (mut any_fail, mut all_hold) = (false, true);
        for v in parts {
            any_fail |= v == Verdict::Fails;
            all_hold &= v == Verdict::Holds;
        }
        if any_fail {
            Verdict::Fails
        } else if all_hold {
            Verdict::Holds
        } else {
            Verdict::Undecided
        }
    }
}

/// z of the two-sided 95% interval.
const Z95: f64 = 1.96;
/// z of 80% power: a true difference of `(Z95 + Z80) * se` is found beyond
/// the 95% interval four times in five.
const Z80: f64 = 0.8416;

/// One claim's outcome: the verdict, the rule that gave it, and the numbers.
#[derive(Clone, Debug, Serialize)]
pub struct ClaimResult {
    pub id: &'static str,
    pub statement: &'static str,
    pub criterion: &'static str,
    pub verdict: Verdict,
    /// Human-readable evidence, one line each.
    pub lines: Vec<String>,
    /// The same evidence as data, for `summary.json`.
    pub data: serde_json::Value,
}

/// Fig. 7's ordering, slowest first.
const ORDER: [Policy; 4] = [Policy::Lfp, Policy::Ru, Policy::Sequential, Policy::Repulsive];

/// The robot counts of claim (b).
const RU_SLOWER_FROM: usize = 9;
const RU_SLOWER_TO: usize = 13;

/// Claim (c): the first third of the range must fall at least this many
/// times faster per added robot than the last third (beyond the intervals).
const SHARP_FACTOR: f64 = 3.0;

#[derive(Clone, Copy)]
struct Cell {
    mean: f64,
    /// Half-width of the 95% interval; 0 when unknown (one completed run).
    ci: f64,
}

/// How a slower-claimed algorithm compares with a faster-claimed one at one
/// robot count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cmp {
    /// Slower beyond the 95% interval of the difference: the claim's way.
    Slower,
    /// The difference lies inside the interval: a tie, neither way.
    Tie,
    /// Faster beyond the interval: the claim is reversed.
    Faster,
}

impl Cmp {
    /// The claim's way: holds; reversed: fails; a tie: undecided.
    fn verdict(self) -> Verdict {
        match self {
            Cmp::Slower => Verdict::Holds,
            Cmp::Tie => Verdict::Undecided,
            Cmp::Faster => Verdict::Fails,
        }
    }

    fn word(self) -> &'static str {
        match self {
            Cmp::Slower => "holds",
            Cmp::Tie => "tie",
            Cmp::Faster => "fails",
        }
    }
}

/// The mean difference slow - fast and its 95% half-width, paired run by
/// run when both cells have per-run times (the sweep's runs share seeds
/// across algorithms), else from the two cells' own intervals.
#[derive(Clone, Copy, Debug)]
struct Diff {
    mean: f64,
    ci: f64,
    /// Runs paired; 0 when the comparison was not paired.
    paired: usize,
    /// Paired, and every run gave both the same time: the two algorithms
    /// coincide here (one robot: RU, (1)&(3) and (1),(2)&(3)).
    identical: bool,
}

impl Diff {
    /// The smallest true difference this sample would have shown beyond the
    /// 95% interval with 80% power: what a tie rules out.
    fn detectable(self) -> f64 {
        self.ci / Z95 * (Z95 + Z80)
    }

    /// `+12.3 +- 4.5 s`, and for a tie what it rules out.
    fn text(self) -> String {
        let base = format!("{:+.1} +- {:.1} s", self.mean, self.ci);
        match self.cmp() {
            Cmp::Tie if self.identical => format!("{base}, identical runs"),
            Cmp::Tie => format!("{base}, could detect {:.1} s", self.detectable()),
            _ => base,
        }
    }

    fn cmp(self) -> Cmp {
        if self.mean > self.ci {
            Cmp::Slower
        } else if self.mean < -self.ci {
            Cmp::Faster
        } else {
            Cmp::Tie
        }
    }
}

/// Cells with at least one completed run, by (algorithm, robots).
struct Table {
    cells: HashMap<(Policy, usize), Cell>,
    /// Search time of each run by run index, `None` when it did not complete.
    times: HashMap<(Policy, usize), Vec<Option<f64>>>,
    /// Every robot count with at least one such cell, ascending.
    counts: Vec<usize>,
}

impl Table {
    fn new(cells: &[CellStats], runs: &[&[RunRecord]]) -> Self {
        let mut times = HashMap::new();
        for (c, rs) in cells.iter().zip(runs) {
            let t = rs.iter().map(|r| r.complete.then_some(r.search_time_s)).collect();
            times.insert((c.algorithm, c.robots), t);
        }
        let cells: HashMap<(Policy, usize), Cell> = cells
            .iter()
            .filter_map(|c| {
                c.mean_search_time_s.map(|m| ((c.algorithm, c.robots), Cell { mean: m, ci: c.ci95_s.unwrap_or(0.0) }))
            })
            .collect();
        let counts: BTreeSet<usize> = cells.keys().map(|&(_, r)| r).collect();
        Table { cells, times, counts: counts.into_iter().collect() }
    }

    fn has(&self, p: Policy, r: usize) -> bool {
        self.cells.contains_key(&(p, r))
    }

    /// The cell; only called after [`Table::has`].
    fn at(&self, p: Policy, r: usize) -> Cell {
        self.cells[&(p, r)]
    }

    fn counts_of(&self, p: Policy) -> Vec<usize> {
        self.counts.iter().copied().filter(|&r| self.has(p, r)).collect()
    }

    /// `slow` against `fast` at `r` robots; only called after [`Table::has`]
    /// for both.
    fn diff(&self, slow: Policy, fast: Policy, r: usize) -> Diff {
        if let (Some(a), Some(b)) = (self.times.get(&(slow, r)), self.times.get(&(fast, r))) {
            let d: Vec<f64> = a.iter().zip(b).filter_map(|(x, y)| Some((*x)? - (*y)?)).collect();
            if d.len() >= 2 {
                let n = d.len() as f64;
                let mean = d.iter().sum::<f64>() / n;
                let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
                let identical = d.iter().all(|&x| x == 0.0);
                return Diff { mean, ci: Z95 * (var / n).sqrt(), paired: d.len(), identical };
            }
        }
        let (s, f) = (self.at(slow, r), self.at(fast, r));
        Diff { mean: s.mean - f.mean, ci: (s.ci * s.ci + f.ci * f.ci).sqrt(), paired: 0, identical: false }
    }
}

/// Evaluates the three claims on a sweep's cells; `runs[i]` are the runs of
/// `cells[i]` by run index (empty when unknown: comparisons are then
/// unpaired). A difference inside the 95% interval of its comparison is a
/// tie, which neither upholds nor breaks an ordering claim.
pub fn evaluate(cells: &[CellStats], runs: &[&[RunRecord]]) -> Vec<ClaimResult> {
    let t = Table::new(cells, runs);
    let present: Vec<Policy> = {
        let mut v: Vec<Policy> = Vec::new();
        for c in cells {
            if !v.contains(&c.algorithm) {
                v.push(c.algorithm);
            }
        }
        v
    };
    vec![ordering(&t, &present), ru_slower(&t, &present), sharp_then_slow(&t, &present)]
}

/// Why a claim about `needed` cannot be evaluated on a sweep of `present`:
/// the algorithms it lacks (`any`: it needs only one of them).
fn lacking(needed: &[Policy], present: &[Policy], any: bool) -> Option<String> {
    let missing: Vec<&str> = needed.iter().filter(|p| !present.contains(p)).map(|p| p.name()).collect();
    let short = if any { missing.len() == needed.len() } else { !missing.is_empty() };
    let all = if any && missing.len() > 1 { "every one of " } else { "" };
    short.then(|| format!("  the sweep lacks {all}{}", missing.join(", ")))
}

fn not_evaluated(id: &'static str, statement: &'static str, criterion: &'static str, why: String) -> ClaimResult {
    ClaimResult {
        id,
        statement,
        criterion,
        verdict: Verdict::NotEvaluated,
        lines: vec![why.clone()],
        data: json!({ "reason": why.trim() }),
    }
}

/// Where the full ordering stands at one robot count.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
enum Order {
    /// Every neighbouring pair in order beyond its interval.
    InOrder,
    /// Some pair reversed beyond its interval.
    Broken,
    /// No pair reversed, some tied: the sample cannot tell.
    Open,
    /// Two neighbours coincide run for run (one robot): not counted.
    Coincide,
}

fn ordering(t: &Table, present: &[Policy]) -> ClaimResult {
    const ID: &str = "a";
    const STATEMENT: &str = "generally LFP > RU > (1)&(3) > (1),(2)&(3) in mean search time";
    const CRITERION: &str =
        "at a robot count with completed runs of all four algorithms, the ordering is in order when \
                             every neighbouring pair is in order beyond the 95% interval of its difference (paired run \
                             by run), broken when some pair is reversed beyond it, and open otherwise (ties); a count \
                             where two neighbours coincide run for run (one robot) is not counted. The claim holds \
                             when the ordering is in order at more than half of the counted robot counts, fails when \
                             it could not be even if every open count were in order, and is not decidable otherwise";
    if let Some(why) = lacking(&ORDER, present, false) {
        return not_evaluated(ID, STATEMENT, CRITERION, why);
    }
    let full_counts: Vec<usize> = t.counts.iter().copied().filter(|&r| ORDER.iter().all(|&p| t.has(p, r))).collect();
    if full_counts.is_empty() {
        return not_evaluated(
            ID,
            STATEMENT,
            CRITERION,
            "  no robot count has completed runs of all four algorithms".into(),
        );
    }
    let mut lines = Vec::new();
    let mut per_count = Vec::new();
    let mut by: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for &r in &full_counts {
        let m: Vec<f64> = ORDER.iter().map(|&p| t.at(p, r).mean).collect();
        let diffs: Vec<Diff> = ORDER.windows(2).map(|w| t.diff(w[0], w[1], r)).collect();
        let order = if diffs.iter().any(|d| d.identical) {
            Order::Coincide
        } else if diffs.iter().all(|d| d.cmp() == Cmp::Slower) {
            Order::InOrder
        } else if diffs.iter().any(|d| d.cmp() == Cmp::Faster) {
            Order::Broken
        } else {
            Order::Open
        };
        let pairs: Vec<String> = ORDER
            .windows(2)
            .zip(&diffs)
            .filter(|(_, d)| d.cmp() != Cmp::Slower)
            .map(|(pp, d)| {
                let sep = if d.cmp() == Cmp::Faster { "<" } else { "~" };
                format!("{} {sep} {} ({})", pp[0].paper_label(), pp[1].paper_label(), d.text())
            })
            .collect();
        let word = match order {
            Order::InOrder => "in order",
            Order::Broken => "broken",
            Order::Open => "open",
            Order::Coincide => "not counted, algorithms coincide",
        };
        by.entry(word).or_default().push(r);
        let values: Vec<String> = ORDER.iter().zip(&m).map(|(p, v)| format!("{} {v:.1}", p.paper_label())).collect();
        let detail = if pairs.is_empty() { String::new() } else { format!(": {}", pairs.join("; ")) };
        lines.push(format!("  {r:>3} robot{}: {}  {word}{detail}", if r == 1 { " " } else { "s" }, values.join(" | ")));
        per_count.push(json!({
            "robots": r,
            "means_s": ORDER.iter().zip(&m).map(|(p, v)| (p.name(), *v)).collect::<BTreeMap<_, _>>(),
            "order": order,
            "diffs_s": diffs.iter().map(|d| json!({"mean": d.mean, "ci95": d.ci, "detectable": d.detectable()})).collect::<Vec<_>>(),
        }));
    }
    let n_of = |w: &str| by.get(w).map_or(0, Vec::len);
    let (held, open, broken) = (n_of("in order"), n_of("open"), n_of("broken"));
    let counted = held + open + broken;
    let list = |w: &str| by.get(w).map(|v| compress(v)).unwrap_or_else(|| "none".into());
    pair_lines(t, &mut lines);
    // Last: the one line the terminal shows (`render_short`).
    lines.push(format!(
        "  in order at {held}/{counted} counted robot counts ({}), open at {open} ({}), broken at {broken} ({})",
        list("in order"),
        list("open"),
        list("broken")
    ));
    let verdict = match counted {
        0 => Verdict::NotEvaluated,
        n if 2 * held > n => Verdict::Holds,
        n if 2 * (held + open) <= n => Verdict::Fails,
        _ => Verdict::Undecided,
    };
    ClaimResult {
        id: ID,
        statement: STATEMENT,
        criterion: CRITERION,
        verdict,
        lines,
        data: json!({ "robot_counts": full_counts, "in_order_at": by.get("in order"), "open_at": by.get("open"),
            "broken_at": by.get("broken"), "per_count": per_count }),
    }
}

/// Each neighbouring pair of the ordering over every robot count, for the
/// evidence of claim (a).
fn pair_lines(t: &Table, lines: &mut Vec<String>) {
    for w in ORDER.windows(2) {
        let (slow, fast) = (w[0], w[1]);
        let both: Vec<usize> = t.counts.iter().copied().filter(|&r| t.has(slow, r) && t.has(fast, r)).collect();
        let of = |c: Cmp| both.iter().filter(|&&r| t.diff(slow, fast, r).cmp() == c).count();
        lines.push(format!(
            "  {} > {}: at {}/{} robot counts, tied at {}, reversed at {} (95% interval of the difference)",
            slow.paper_label(),
            fast.paper_label(),
            of(Cmp::Slower),
            both.len(),
            of(Cmp::Tie),
            of(Cmp::Faster),
        ));
    }
}

fn ru_slower(t: &Table, present: &[Policy]) -> ClaimResult {
    const ID: &str = "b";
    const STATEMENT: &str = "RU > LFP in mean search time for 9 to 13 robots";
    const CRITERION: &str =
        "at each robot count from 9 to 13 in the sweep, RU - LFP paired run by run: the claim holds \
                             when RU is slower beyond the 95% interval of the difference at every one, fails when it \
                             is faster beyond it at any one, and is not decidable otherwise (ties, with the \
                             difference the sample could have detected with 80% power)";
    if let Some(why) = lacking(&[Policy::Ru, Policy::Lfp], present, false) {
        return not_evaluated(ID, STATEMENT, CRITERION, why);
    }
    let counts: Vec<usize> =
        (RU_SLOWER_FROM..=RU_SLOWER_TO).filter(|&r| t.has(Policy::Ru, r) && t.has(Policy::Lfp, r)).collect();
    if counts.is_empty() {
        return not_evaluated(
            ID,
            STATEMENT,
            CRITERION,
            "  no robot count from 9 to 13 has completed runs of both RU and LFP".into(),
        );
    }
    let mut lines = Vec::new();
    let mut per_count = Vec::new();
    let mut outcomes = Vec::new();
    for &r in &counts {
        let (ru, lfp) = (t.at(Policy::Ru, r), t.at(Policy::Lfp, r));
        let d = t.diff(Policy::Ru, Policy::Lfp, r);
        let c = d.cmp();
        outcomes.push(c.verdict());
        lines.push(format!(
            "  {r:>3} robot{}: RU {:.1} vs LFP {:.1} (RU - LFP = {}): {}",
            if r == 1 { "" } else { "s" },
            ru.mean,
            lfp.mean,
            d.text(),
            c.word()
        ));
        per_count.push(json!({ "robots": r, "ru_s": ru.mean, "lfp_s": lfp.mean, "diff_s": d.mean, "ci95_s": d.ci,
            "detectable_s": d.detectable(), "paired_runs": d.paired, "outcome": c.word() }));
    }
    if counts.len() < RU_SLOWER_TO - RU_SLOWER_FROM + 1 {
        lines.push(format!("  only robot counts {} of 9-13 are in the sweep", compress(&counts)));
    }
    let of = |v: Verdict| outcomes.iter().filter(|&&x| x == v).count();
    let (held, tied) = (of(Verdict::Holds), of(Verdict::Undecided));
    lines.push(format!("  holds at {held}/{} robot counts, tied at {tied}", counts.len()));
    ClaimResult {
        id: ID,
        statement: STATEMENT,
        criterion: CRITERION,
        verdict: Verdict::all(outcomes),
        lines,
        data: json!({ "per_count": per_count, "holds_at": held, "ties": tied, "counts": counts.len() }),
    }
}

/// A drop rate in words: a negative drop is a rise.
fn slope(drop: Estimate) -> String {
    if drop.value >= 0.0 {
        format!("falls {:.1} +- {:.1} s/robot", drop.value, drop.ci)
    } else {
        format!("rises {:.1} +- {:.1} s/robot", -drop.value, drop.ci)
    }
}

/// A linear combination of cell means with its 95% half-width: the cells
/// of different robot counts have their own seeds, so their means are
/// independent and the variance is the weighted sum of theirs.
#[derive(Clone, Copy, Debug)]
struct Estimate {
    value: f64,
    ci: f64,
}

impl Estimate {
    /// `sum of w * mean(p, r)` over `terms` (a robot count may appear twice).
    fn of(t: &Table, p: Policy, terms: &[(usize, f64)]) -> Self {
        let mut w: BTreeMap<usize, f64> = BTreeMap::new();
        for &(r, x) in terms {
            *w.entry(r).or_default() += x;
        }
        let value = w.iter().map(|(&r, x)| x * t.at(p, r).mean).sum();
        let var: f64 = w.iter().map(|(&r, x)| (x * t.at(p, r).ci / Z95).powi(2)).sum();
        Estimate { value, ci: Z95 * var.sqrt() }
    }

    /// Above zero beyond the interval: holds; below: fails; else undecided.
    fn sign(self) -> Verdict {
        if self.value > self.ci {
            Verdict::Holds
        } else if self.value < -self.ci {
            Verdict::Fails
        } else {
            Verdict::Undecided
        }
    }
}

/// Mean drop of the search time per added robot between two robot counts,
/// as the weights of an [`Estimate`].
fn drop_terms(from: usize, to: usize) -> [(usize, f64); 2] {
    let k = 1.0 / (to - from) as f64;
    [(from, k), (to, -k)]
}

fn sharp_then_slow(t: &Table, present: &[Policy]) -> ClaimResult {
    const ID: &str = "c";
    const STATEMENT: &str = "every curve falls sharply at first, then slowly";
    const CRITERION: &str = "per algorithm, over the sweep's robot range [lo, hi]: `first` is the mean drop in search \
                             time per added robot from lo to the last count <= lo + (hi-lo)/3, `last` the drop from the \
                             first count >= hi - (hi-lo)/3 to hi, each with the 95% interval from its cells' intervals \
                             (the cells' runs are independent). An algorithm passes when first > 0, first - 3 last > 0 \
                             beyond their intervals and last is not below 0 beyond its interval (a rise is not a slow \
                             fall); it fails when any of the three is on the wrong side beyond its interval, and is \
                             undecided otherwise. The claim holds when every evaluated algorithm passes, fails when \
                             one fails, and is not decidable otherwise";
    // Fig. 7's curves only: the baselines from outside the paper make no such claim.
    if let Some(why) = lacking(&ORDER, present, true) {
        return not_evaluated(ID, STATEMENT, CRITERION, why);
    }
    let mut lines = Vec::new();
    let mut per_alg = Vec::new();
    let mut outcomes = Vec::new();
    for &p in present.iter().filter(|p| ORDER.contains(p)) {
        let counts = t.counts_of(p);
        let (Some(&lo), Some(&hi)) = (counts.first(), counts.last()) else {
            lines.push(format!("  {}: not evaluated (no completed runs)", p.paper_label()));
            continue;
        };
        let third = (hi - lo) as f64 / 3.0;
        let first_end = counts.iter().copied().filter(|&r| r as f64 <= lo as f64 + third).max().unwrap_or(lo);
        let last_start = counts.iter().copied().filter(|&r| r as f64 >= hi as f64 - third).min().unwrap_or(hi);
        if first_end <= lo || last_start >= hi || first_end > last_start {
            lines.push(format!(
                "  {}: not evaluated (robot counts {} too few to split into thirds)",
                p.paper_label(),
                compress(&counts)
            ));
            continue;
        }
        let first = Estimate::of(t, p, &drop_terms(lo, first_end));
        let last = Estimate::of(t, p, &drop_terms(last_start, hi));
        let mut sharper: Vec<(usize, f64)> = drop_terms(lo, first_end).to_vec();
        sharper.extend(drop_terms(last_start, hi).map(|(r, w)| (r, -SHARP_FACTOR * w)));
        let sharper = Estimate::of(t, p, &sharper);
        // The paper's claim is of a fall: a curve that rises again in the
        // last third does not "fall slowly", however sharp its first third.
        let not_rising = match last.sign() {
            Verdict::Fails => Verdict::Fails,
            _ => Verdict::Holds,
        };
        let outcome = Verdict::all([first.sign(), sharper.sign(), not_rising]);
        outcomes.push(outcome);
        lines.push(format!(
            "  {}: {lo}->{first_end} robots {}; {last_start}->{hi} robots {}; first - 3 last = {:.1} +- {:.1}: {}",
            p.paper_label(),
            slope(first),
            slope(last),
            sharper.value,
            sharper.ci,
            match outcome {
                Verdict::Holds => "holds",
                Verdict::Fails => "fails",
                _ => "undecided",
            }
        ));
        per_alg.push(json!({
            "algorithm": p.name(), "first": [lo, first_end], "first_drop_s_per_robot": first.value,
            "first_ci95": first.ci, "last": [last_start, hi], "last_drop_s_per_robot": last.value,
            "last_ci95": last.ci, "first_minus_3_last": sharper.value, "first_minus_3_last_ci95": sharper.ci,
            "outcome": outcome,
        }));
    }
    let verdict = if outcomes.is_empty() { Verdict::NotEvaluated } else { Verdict::all(outcomes.iter().copied()) };
    if !outcomes.is_empty() {
        let passed = outcomes.iter().filter(|&&v| v == Verdict::Holds).count();
        lines.push(format!("  holds for {passed}/{} algorithms", outcomes.len()));
    }
    ClaimResult {
        id: ID,
        statement: STATEMENT,
        criterion: CRITERION,
        verdict,
        lines,
        data: json!({ "per_algorithm": per_alg }),
    }
}

/// One line per claim: its verdict and the evidence's last line (the count
/// it rests on), for the terminal; [`render`] has the details.
pub fn render_short(claims: &[ClaimResult]) -> String {
    let mut out = String::new();
    for c in claims {
        let last = c.lines.last().map(|l| l.trim()).unwrap_or("");
        let _ = writeln!(out, "Claim ({}) {}: {} ({last})", c.id, c.statement, c.verdict.word());
    }
    out += "details: claims.txt, or --verbose\n";
    out
}

/// The claims as text, for the terminal and `claims.txt`.
pub fn render(claims: &[ClaimResult]) -> String {
    let mut out = String::new();
    for c in claims {
        let _ = writeln!(out, "Claim ({}) {}: {}", c.id, c.statement, c.verdict.word());
        if c.verdict != Verdict::NotEvaluated {
            let _ = writeln!(out, "  criterion: {}", c.criterion);
        }
        for l in &c.lines {
            let _ = writeln!(out, "{l}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(p: Policy, r: usize, mean: f64) -> CellStats {
        CellStats {
            algorithm: p,
            robots: r,
            runs: 10,
            completed_runs: 10,
            mean_search_time_s: Some(mean),
            std_search_time_s: Some(1.0),
            ci95_s: Some(0.5),
            mean_rounds: Some(1.0),
            mean_collisions: Some(0.0),
            median_search_time_s: Some(mean),
            mean_targets_found: 9.0,
            metrics: Default::default(),
        }
    }

    /// A paper-like table: curves falling like 1 / r^1.5, with RU stepping
    /// above LFP from 9 robots on (its collisions) and still falling after.
    fn paperlike() -> Vec<CellStats> {
        let mut v = Vec::new();
        for r in 1..=13usize {
            let f = 1.0 / (r as f64).powf(1.5);
            let lfp = 4000.0 * f + 100.0;
            let ru = 3000.0 * f + if r >= 9 { 150.0 } else { 0.0 } + 50.0;
            v.push(cell(Policy::Lfp, r, lfp));
            v.push(cell(Policy::Ru, r, ru));
            v.push(cell(Policy::Sequential, r, 2000.0 * f + 20.0));
            v.push(cell(Policy::Repulsive, r, 1500.0 * f + 10.0));
        }
        v
    }

    fn by_id<'a>(c: &'a [ClaimResult], id: &str) -> &'a ClaimResult {
        c.iter().find(|x| x.id == id).unwrap()
    }

    #[test]
    fn paperlike_table_passes_all() {
        let c = evaluate(&paperlike(), &[]);
        let text = render(&c);
        assert_eq!(by_id(&c, "a").verdict, Verdict::Holds, "{text}");
        assert_eq!(by_id(&c, "b").verdict, Verdict::Holds, "{text}");
        assert_eq!(by_id(&c, "c").verdict, Verdict::Holds, "{text}");
        assert!(text.contains("in order at 8/13 counted robot counts (1-8)"), "{text}");
        assert!(text.contains("LFP > RU: at 8/13 robot counts, tied at 0, reversed at 5"), "{text}");
        assert!(text.contains("holds at 5/5 robot counts, tied at 0"), "{text}");
        assert!(text.contains("holds for 4/4 algorithms"), "{text}");
    }

    #[test]
    fn a_rise_in_the_last_third_fails_c() {
        let mut v = paperlike();
        for c in &mut v {
            if c.algorithm == Policy::Ru && c.robots >= 9 {
                c.mean_search_time_s = Some(c.mean_search_time_s.unwrap() + 30.0 * c.robots as f64);
            }
        }
        let c = evaluate(&v, &[]);
        assert_eq!(by_id(&c, "c").verdict, Verdict::Fails, "{}", render(&c));
        assert!(render(&c).contains("9->13 robots rises"), "{}", render(&c));
    }

    #[test]
    fn swapped_order_fails_a() {
        let mut v = paperlike();
        for c in &mut v {
            if c.algorithm == Policy::Repulsive {
                c.mean_search_time_s = Some(c.mean_search_time_s.unwrap() * 10.0);
            }
        }
        let c = evaluate(&v, &[]);
        let a = by_id(&c, "a");
        assert_eq!(a.verdict, Verdict::Fails);
        assert!(
            render(&c).contains("(1)&(3) > (1),(2)&(3): at 0/13 robot counts, tied at 0, reversed at 13"),
            "{}",
            render(&c)
        );
    }

    #[test]
    fn b_fails_when_ru_faster_somewhere() {
        let mut v = paperlike();
        for c in &mut v {
            if c.algorithm == Policy::Ru && c.robots == 11 {
                c.mean_search_time_s = Some(1.0);
            }
        }
        let c = evaluate(&v, &[]);
        assert_eq!(by_id(&c, "b").verdict, Verdict::Fails);
        assert!(by_id(&c, "b").lines.iter().any(|l| l.contains("11 robots") && l.ends_with("fails")));
    }

    fn runs(times: &[f64]) -> Vec<RunRecord> {
        let run = |&t: &f64| RunRecord {
            seed: 0,
            search_time_s: t,
            rounds: 1,
            collisions: 0,
            targets_found: 1,
            complete: true,
            ..Default::default()
        };
        times.iter().map(run).collect()
    }

    #[test]
    fn paired_differences_inside_the_interval_are_ties() {
        // RU is 1 s slower than LFP on average at 9-13 robots, but by +-40 s
        // from run to run: paired, that is a tie, not a holding claim, and
        // not a failure either.
        let mut v = paperlike();
        let mut per_run: Vec<Vec<f64>> = Vec::new();
        for c in &mut v {
            let m = c.mean_search_time_s.unwrap();
            let noise = |k: usize| if k % 2 == 0 { 40.0 } else { -40.0 };
            let t: Vec<f64> = if c.algorithm == Policy::Ru && c.robots >= 9 {
                (0..10).map(|k| 500.0 + noise(k) + 1.0).collect()
            } else if c.algorithm == Policy::Lfp && c.robots >= 9 {
                (0..10).map(|k| 500.0 + if k % 4 < 2 { 0.0 } else { 0.5 }).collect()
            } else {
                vec![m; 10]
            };
            c.mean_search_time_s = Some(t.iter().sum::<f64>() / 10.0);
            per_run.push(t);
        }
        let recs: Vec<Vec<RunRecord>> = per_run.iter().map(|t| runs(t)).collect();
        let refs: Vec<&[RunRecord]> = recs.iter().map(|r| r.as_slice()).collect();
        let c = evaluate(&v, &refs);
        let b = by_id(&c, "b");
        assert!(b.lines.iter().filter(|l| l.ends_with(": tie")).count() == 5, "{}", render(&c));
        assert_eq!(b.verdict, Verdict::Undecided, "ties neither uphold nor break the claim: {}", render(&c));
        // A tie says what it rules out: 40 s of noise a run over 10 runs.
        assert!(b.lines[0].contains("could detect"), "{}", b.lines[0]);
        // Identical runs (one robot: RU and (1)&(3) coincide) tie exactly.
        let same = runs(&[10.0, 20.0, 30.0]);
        let t = Table::new(&[cell(Policy::Ru, 1, 20.0), cell(Policy::Sequential, 1, 20.0)], &[&same, &same]);
        let d = t.diff(Policy::Ru, Policy::Sequential, 1);
        assert_eq!((d.cmp(), d.paired, d.identical), (Cmp::Tie, 3, true));
    }

    #[test]
    fn linear_fall_fails_c() {
        // Linear: the same drop per robot everywhere, so not "sharp then slow".
        let v: Vec<CellStats> = (1..=13).map(|r| cell(Policy::Repulsive, r, 1000.0 - 50.0 * r as f64)).collect();
        let c = evaluate(&v, &[]);
        let cc = by_id(&c, "c");
        assert_eq!(cc.verdict, Verdict::Fails, "{}", render(&c));
        assert!(
            cc.lines[0].contains("1->5 robots falls 50.0 +- 0.2 s/robot; 9->13 robots falls 50.0"),
            "{}",
            cc.lines[0]
        );
    }

    #[test]
    fn missing_algorithms_or_counts_are_not_evaluated() {
        // Robots 1-3 of two algorithms: (a) lacks algorithms, (b) lacks
        // counts 9-13, (c) has too few counts for thirds.
        let v: Vec<CellStats> =
            (1..=3).flat_map(|r| [cell(Policy::Ru, r, 10.0 / r as f64), cell(Policy::Lfp, r, 20.0)]).collect();
        let c = evaluate(&v, &[]);
        for id in ["a", "b"] {
            assert_eq!(by_id(&c, id).verdict, Verdict::NotEvaluated, "{id}");
        }
        // 1..3: thirds are [1, 1.67] and [2.33, 3]: no second count in the first.
        assert_eq!(by_id(&c, "c").verdict, Verdict::NotEvaluated);
        let text = render(&c);
        assert!(text.contains("the sweep lacks sequential, repulsive"), "{text}");
        assert!(text.contains("not evaluated"), "{text}");
        // Only baselines from outside the paper: (c) says why too.
        let v: Vec<CellStats> = (1..=13).map(|r| cell(Policy::Frontier, r, 100.0 / r as f64)).collect();
        let c = evaluate(&v, &[]);
        let why = &by_id(&c, "c").lines;
        assert_eq!(by_id(&c, "c").verdict, Verdict::NotEvaluated);
        assert_eq!(why, &["  the sweep lacks every one of lfp, ru, sequential, repulsive"], "{}", render(&c));
    }

    #[test]
    fn cells_without_completed_runs_are_skipped() {
        let mut v = paperlike();
        for c in &mut v {
            if c.algorithm == Policy::Lfp && c.robots == 2 {
                c.completed_runs = 0;
                c.mean_search_time_s = None;
            }
        }
        let c = evaluate(&v, &[]);
        assert!(render(&c).contains("in order at 7/12"), "{}", render(&c));
    }

    #[test]
    fn ties_leave_a_and_c_undecided() {
        // The ordering in order at 6 of 13 counts and tied at 2: it might
        // hold, it might not. Wide intervals leave (c) undecided too.
        let mut v = paperlike();
        for c in &mut v {
            if c.algorithm == Policy::Lfp && (c.robots == 7 || c.robots == 8) {
                c.mean_search_time_s = Some(c.mean_search_time_s.unwrap() - 17.0);
                c.ci95_s = Some(100.0);
            }
        }
        let c = evaluate(&v, &[]);
        let a = by_id(&c, "a");
        assert_eq!(a.verdict, Verdict::Undecided, "{}", render(&c));
        assert!(render(&c).contains("in order at 6/13 counted robot counts (1-6), open at 2 (7-8)"), "{}", render(&c));
        let wide: Vec<CellStats> = (1..=13)
            .map(|r| CellStats { ci95_s: Some(2000.0), ..cell(Policy::Repulsive, r, 1500.0 / (r as f64).powf(1.5)) })
            .collect();
        let c = evaluate(&wide, &[]);
        assert_eq!(by_id(&c, "c").verdict, Verdict::Undecided, "{}", render(&c));
    }

    #[test]
    fn a_count_where_algorithms_coincide_is_not_counted() {
        // One robot: RU, (1)&(3) and (1),(2)&(3) give the same runs.
        let same = runs(&[10.0, 20.0, 30.0]);
        let slow = runs(&[40.0, 50.0, 61.0]);
        let cells = [
            cell(Policy::Lfp, 1, 50.3),
            cell(Policy::Ru, 1, 20.0),
            cell(Policy::Sequential, 1, 20.0),
            cell(Policy::Repulsive, 1, 20.0),
        ];
        let c = evaluate(&cells, &[&slow, &same, &same, &same]);
        let a = by_id(&c, "a");
        assert_eq!(a.verdict, Verdict::NotEvaluated, "{}", render(&c));
        assert!(a.lines[0].contains("not counted, algorithms coincide"), "{}", a.lines[0]);
    }
}
