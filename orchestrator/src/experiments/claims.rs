//! The three claims the paper makes about Fig. 7, checked on a sweep's
//! table of mean search times. Each claim is given a plain, fixed criterion
//! (stated in its output) and is evaluated only when the sweep holds the
//! algorithms and robot counts it needs. Nothing here feeds back into the
//! runs: the claims are measured, never tuned for.

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
    NotEvaluated,
}

impl Verdict {
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Holds => "HOLDS",
            Verdict::Fails => "DOES NOT HOLD",
            Verdict::NotEvaluated => "not evaluated",
        }
    }
}

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
/// times faster per added robot than the last third.
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
}

impl Diff {
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
                return Diff { mean, ci: 1.96 * (var / n).sqrt(), paired: d.len() };
            }
        }
        let (s, f) = (self.at(slow, r), self.at(fast, r));
        Diff { mean: s.mean - f.mean, ci: (s.ci * s.ci + f.ci * f.ci).sqrt(), paired: 0 }
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

fn ordering(t: &Table, present: &[Policy]) -> ClaimResult {
    const ID: &str = "a";
    const STATEMENT: &str = "generally LFP > RU > (1)&(3) > (1),(2)&(3) in mean search time";
    const CRITERION: &str = "at a robot count with completed runs of all four algorithms, the ordering holds when no \
                             neighbouring pair is reversed beyond the 95% interval of its difference (paired run by run \
                             over the runs both completed; a difference inside the interval is a tie) and at least one \
                             pair is in order beyond it; the claim holds when the ordering holds at more than half of \
                             the robot counts where not every pair tied";
    if let Some(why) = lacking(&ORDER, present, false) {
        return not_evaluated(ID, STATEMENT, CRITERION, why);
    }
    let counts = &t.counts;
    let full_counts: Vec<usize> = counts.iter().copied().filter(|&r| ORDER.iter().all(|&p| t.has(p, r))).collect();
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
    let mut full_holds = Vec::new();
    let mut all_tied = Vec::new();
    for &r in &full_counts {
        let m: Vec<f64> = ORDER.iter().map(|&p| t.at(p, r).mean).collect();
        let cmps: Vec<Cmp> = ORDER.windows(2).map(|w| t.diff(w[0], w[1], r).cmp()).collect();
        let named = |want: Cmp, sep: &str| -> Vec<String> {
            ORDER
                .windows(2)
                .zip(&cmps)
                .filter(|(_, &c)| c == want)
                .map(|(pp, _)| format!("{} {sep} {}", pp[0].paper_label(), pp[1].paper_label()))
                .collect()
        };
        let (broken, ties) = (named(Cmp::Faster, "<"), named(Cmp::Tie, "~"));
        let undecided = cmps.iter().all(|&c| c == Cmp::Tie);
        let holds = broken.is_empty() && !undecided;
        if undecided {
            all_tied.push(r);
        } else if holds {
            full_holds.push(r);
        }
        let values: Vec<String> = ORDER.iter().zip(&m).map(|(p, v)| format!("{} {v:.1}", p.paper_label())).collect();
        let verdict = match (holds, ties.is_empty()) {
            _ if undecided => "every pair tied: no evidence either way".to_string(),
            (true, true) => "ordering holds".to_string(),
            (true, false) => format!("ordering holds, ties {}", ties.join(", ")),
            (false, _) => format!("fails: {}", broken.join(", ")),
        };
        lines.push(format!("  {r:>3} robot{}: {}  {verdict}", if r == 1 { " " } else { "s" }, values.join(" | ")));
        per_count.push(json!({
            "robots": r,
            "means_s": ORDER.iter().zip(&m).map(|(p, v)| (p.name(), *v)).collect::<BTreeMap<_, _>>(),
            "holds": holds,
            "ties": ties,
        }));
    }
    let decided = full_counts.len() - all_tied.len();
    lines.push(format!(
        "  full ordering holds at {}/{} robot counts ({}){}",
        full_holds.len(),
        decided,
        if full_holds.is_empty() { "none".to_string() } else { compress(&full_holds) },
        if all_tied.is_empty() {
            String::new()
        } else {
            format!("; every pair tied at {}, not counted", compress(&all_tied))
        }
    ));
    let mut pairs = Vec::new();
    for w in ORDER.windows(2) {
        let (slow, fast) = (w[0], w[1]);
        let both: Vec<usize> = counts.iter().copied().filter(|&r| t.has(slow, r) && t.has(fast, r)).collect();
        let of = |c: Cmp| both.iter().filter(|&&r| t.diff(slow, fast, r).cmp() == c).count();
        let (holds, ties, reversed) = (of(Cmp::Slower), of(Cmp::Tie), of(Cmp::Faster));
        lines.push(format!(
            "  {} > {}: at {holds}/{} robot counts, tied at {ties}, reversed at {reversed} (95% interval of the difference)",
            slow.paper_label(),
            fast.paper_label(),
            both.len(),
        ));
        pairs.push(json!({ "slower": slow.name(), "faster": fast.name(), "counts": both.len(), "holds": holds, "ties": ties, "reversed": reversed }));
    }
    let verdict = match decided {
        0 => Verdict::NotEvaluated,
        d if 2 * full_holds.len() > d => Verdict::Holds,
        _ => Verdict::Fails,
    };
    ClaimResult {
        id: ID,
        statement: STATEMENT,
        criterion: CRITERION,
        verdict,
        lines,
        data: json!({ "robot_counts": full_counts, "full_ordering_holds_at": full_holds, "all_tied_at": all_tied, "per_count": per_count, "pairs": pairs }),
    }
}

fn ru_slower(t: &Table, present: &[Policy]) -> ClaimResult {
    const ID: &str = "b";
    const STATEMENT: &str = "RU > LFP in mean search time for 9 to 13 robots";
    const CRITERION: &str = "holds when RU is nowhere faster than LFP beyond the 95% interval of the difference (paired \
                             run by run) at the robot counts from 9 to 13 in the sweep, and slower beyond it at least at \
                             one; a difference inside the interval is a tie";
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
    let (mut held, mut tied) = (0, 0);
    for &r in &counts {
        let (ru, lfp) = (t.at(Policy::Ru, r), t.at(Policy::Lfp, r));
        let d = t.diff(Policy::Ru, Policy::Lfp, r);
        let c = d.cmp();
        held += usize::from(c == Cmp::Slower);
        tied += usize::from(c == Cmp::Tie);
        lines.push(format!(
            "  {r:>3} robot{}: RU {:.1} vs LFP {:.1} (RU - LFP = {:+.1} +- {:.1} s): {}",
            if r == 1 { "" } else { "s" },
            ru.mean,
            lfp.mean,
            d.mean,
            d.ci,
            c.word()
        ));
        per_count.push(json!({ "robots": r, "ru_s": ru.mean, "lfp_s": lfp.mean, "diff_s": d.mean, "ci95_s": d.ci, "paired_runs": d.paired, "outcome": c.word() }));
    }
    if counts.len() < RU_SLOWER_TO - RU_SLOWER_FROM + 1 {
        lines.push(format!("  only robot counts {} of 9-13 are in the sweep", compress(&counts)));
    }
    lines.push(format!("  holds at {held}/{} robot counts, tied at {tied}", counts.len()));
    let reversed = counts.len() - held - tied;
    ClaimResult {
        id: ID,
        statement: STATEMENT,
        criterion: CRITERION,
        verdict: if reversed == 0 && held > 0 { Verdict::Holds } else { Verdict::Fails },
        lines,
        data: json!({ "per_count": per_count, "holds_at": held, "ties": tied, "counts": counts.len() }),
    }
}

/// A drop rate in words: a negative drop is a rise.
fn slope(drop: f64) -> String {
    if drop >= 0.0 {
        format!("falls {drop:.1} s/robot")
    } else {
        format!("rises {:.1} s/robot", -drop)
    }
}

/// Mean drop of the search time per added robot between two robot counts.
fn drop_rate(t: &Table, p: Policy, from: usize, to: usize) -> f64 {
    (t.at(p, from).mean - t.at(p, to).mean) / (to - from) as f64
}

fn sharp_then_slow(t: &Table, present: &[Policy]) -> ClaimResult {
    const ID: &str = "c";
    const STATEMENT: &str = "every curve falls sharply at first, then slowly";
    const CRITERION: &str = "per algorithm, over the sweep's robot range [lo, hi]: the mean drop in search time per \
                             added robot from lo to the last count <= lo + (hi-lo)/3 must be positive and at least 3 \
                             times the drop from the first count >= hi - (hi-lo)/3 to hi, which must itself be a fall \
                             (a rise is not a slow fall); the claim holds when every evaluated algorithm passes";
    // Fig. 7's curves only: the baselines from outside the paper make no such claim.
    if let Some(why) = lacking(&ORDER, present, true) {
        return not_evaluated(ID, STATEMENT, CRITERION, why);
    }
    let mut lines = Vec::new();
    let mut per_alg = Vec::new();
    let (mut evaluated, mut passed) = (0, 0);
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
        let first = drop_rate(t, p, lo, first_end);
        let last = drop_rate(t, p, last_start, hi);
        // The paper's claim is of a fall: a curve that rises again in the
        // last third does not "fall slowly", however sharp its first third.
        let holds = first > 0.0 && last >= 0.0 && first >= SHARP_FACTOR * last;
        evaluated += 1;
        passed += usize::from(holds);
        let ratio = if last > 0.0 { format!("ratio {:.1}", first / last) } else { "the last third rises".to_string() };
        lines.push(format!(
            "  {}: {lo}->{first_end} robots {}; {last_start}->{hi} robots {} ({ratio}): {}",
            p.paper_label(),
            slope(first),
            slope(last),
            if holds { "holds" } else { "fails" }
        ));
        per_alg.push(json!({
            "algorithm": p.name(), "first": [lo, first_end], "first_drop_s_per_robot": first,
            "last": [last_start, hi], "last_drop_s_per_robot": last, "holds": holds,
        }));
    }
    let verdict = match (evaluated, passed) {
        (0, _) => Verdict::NotEvaluated,
        (e, p) if e == p => Verdict::Holds,
        _ => Verdict::Fails,
    };
    if evaluated > 0 {
        lines.push(format!("  holds for {passed}/{evaluated} algorithms"));
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
        assert!(text.contains("full ordering holds at 8/13"), "{text}");
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
        assert!(render(&c).contains("the last third rises"));
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
        assert_eq!(b.verdict, Verdict::Fails, "all ties do not uphold the claim: {}", render(&c));
        // Identical runs (one robot: RU and (1)&(3) coincide) tie exactly.
        let same = runs(&[10.0, 20.0, 30.0]);
        let t = Table::new(&[cell(Policy::Ru, 1, 20.0), cell(Policy::Sequential, 1, 20.0)], &[&same, &same]);
        let d = t.diff(Policy::Ru, Policy::Sequential, 1);
        assert_eq!((d.cmp(), d.paired), (Cmp::Tie, 3));
    }

    #[test]
    fn linear_fall_fails_c() {
        // Linear: the same drop per robot everywhere, so not "sharp then slow".
        let v: Vec<CellStats> = (1..=13).map(|r| cell(Policy::Repulsive, r, 1000.0 - 50.0 * r as f64)).collect();
        let c = evaluate(&v, &[]);
        let cc = by_id(&c, "c");
        assert_eq!(cc.verdict, Verdict::Fails, "{}", render(&c));
        assert!(cc.lines[0].contains("1->5 robots falls 50.0 s/robot; 9->13 robots falls 50.0"), "{}", cc.lines[0]);
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
        assert!(render(&c).contains("full ordering holds at 7/12"), "{}", render(&c));
    }
}
