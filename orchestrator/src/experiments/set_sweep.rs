//! `gridswarm experiment --set KEY=V1,V2,...`: the Fig. 7 sweep once per
//! combination of the swept values ([`settings`]), each exactly as the
//! plain sweep runs it on a scenario holding those values, written as one
//! set of files with a column per swept key. Every combination uses the
//! same run seeds and starts (common random numbers), so a difference
//! between two combinations comes from the values alone. It never changes
//! how one sweep runs or what a sweep without `--set` writes.

use std::time::Instant;

use serde_json::{json, Value};

use gridswarm::policy::Policy;

use crate::error::{Error, Result};
use crate::experiment::{fig_title, provenance_of, results_csv, ExperimentOptions, Part, Sweep, Times};
use crate::maps::Map;
use crate::report::{self, Block, Report, Section, Table};
use crate::settings::{self, Setting};
use crate::staging::Staging;
use crate::{output, provenance};

/// One combination: its values (one per setting) and its sweep.
struct Combo {
    values: Vec<String>,
    part: Part,
}

impl Combo {
    /// `t_wait=1, turn=uniform`: the combination as a heading.
    fn name(&self, set: &[Setting]) -> String {
        set.iter().zip(&self.values).map(|(s, v)| format!("{}={v}", s.key)).collect::<Vec<_>>().join(", ")
    }
}

/// Runs every combination on `maps` (the scenario as loaded) and writes
/// the files of the whole grid. Every combination is checked before the
/// first run, so a bad value fails at once.
/// `started` is the command's start, for the wall time it prints.
pub fn run(opts: &ExperimentOptions, algorithms: &[Policy], maps: &[Map], started: Instant) -> Result<(Sweep, String)> {
    if opts.maps.is_some() {
        return Err(Error::Usage("--set cannot be combined with --maps yet: sweep one map at a time".into()));
    }
    settings::check(&opts.set, &maps[0].scenario)?;
    let mut grid = Vec::new();
    for c in settings::combinations(&opts.set) {
        let values: Vec<String> = opts.set.iter().zip(&c).map(|(s, &i)| s.values[i].clone()).collect();
        let pairs: Vec<(&str, &str)> =
            opts.set.iter().zip(&values).map(|(s, v)| (s.key.as_str(), v.as_str())).collect();
        let set: Vec<Map> = maps
            .iter()
            .map(|m| Ok(Map { scenario: settings::apply(&m.scenario, &pairs)?, ..*m }))
            .collect::<Result<_>>()?;
        grid.push((values, set));
    }
    let stage = Staging::begin(&opts.out)?;
    let combos: Vec<Combo> = grid
        .iter()
        .map(|(values, set)| Ok(Combo { values: values.clone(), part: Part::compute(opts, algorithms, set)? }))
        .collect::<Result<_>>()?;
    let runs: usize = combos.iter().map(|c| c.part.records.len()).sum();
    let wall_time_s: f64 = combos.iter().map(|c| c.part.wall_time_s).sum();
    let figures = (1..=combos.len()).map(|i| format!("fig7-{i}.svg")).collect::<Vec<_>>();
    let text = format!(
        "scenario {}, {} runs per cell, base seed {}, {} combinations of {} (parameters in summary.json)\n{}{}\n{}",
        output::shown(&maps[0].scenario.name),
        opts.runs,
        opts.seed,
        combos.len(),
        keys(&opts.set).join(", "),
        report::keyed_text_table(&terminal_table(&opts.set, &combos), opts.set.len() + 2),
        combos[0].part.refs.note(),
        combos.iter().map(|c| format!("{}:\n{}", c.name(&opts.set), c.part.shown_claims(opts))).collect::<String>(),
    );
    let out = &stage.path().to_path_buf();
    let write = || -> Result<()> {
        output::write_text(
            &out.join("results.csv"),
            &tagged(&opts.set, &combos, |p| results_csv(&p.cells, &[], &p.refs)),
        )?;
        output::write_text(&out.join("runs.csv"), &tagged(&opts.set, &combos, Part::runs_csv))?;
        let mut svgs = Vec::new();
        for (c, f) in combos.iter().zip(&figures) {
            let title = format!("{} ({})", fig_title(&c.part.scenario, opts, maps.len()), c.name(&opts.set));
            let svg = c.part.svg(out, &title)?;
            output::write_text(&out.join(f), &svg)?;
            svgs.push(svg);
        }
        let claims: String = combos
            .iter()
            .map(|c| {
                format!("== {} ==\n{}\n{}\n", c.name(&opts.set), c.part.setup(opts, maps), c.part.claims_text(opts))
            })
            .collect();
        output::write_text(&out.join("claims.txt"), &claims)?;
        let mut summary = summary(opts, maps, &combos);
        summary[provenance::KEY] = provenance_of(opts, &summary)?;
        output::write_json(&out.join("summary.json"), &summary)?;
        let page = page(opts, &summary, &combos, &svgs, (runs, wall_time_s));
        output::write_text(&out.join("report.html"), &report::render(&page))
    };
    write().and_then(|()| stage.commit()).inspect_err(|_| print!("{text}"))?;
    // Timed once the files are written: the whole command's wall time.
    let times = Times { command_s: started.elapsed().as_secs_f64(), runs_s: wall_time_s };
    let text = format!(
        "{text}{runs} runs; {times} on {} threads; wrote results.csv, runs.csv, {}, claims.txt, \
         summary.json, report.html in {}\n",
        rayon::current_num_threads(),
        match figures.len() {
            1 => figures[0].clone(),
            n => format!("{} .. {}", figures[0], figures[n - 1]),
        },
        opts.out.display()
    );
    let sweep = Sweep {
        cells: combos.iter().flat_map(|c| c.part.cells.clone()).collect(),
        claims: combos.iter().flat_map(|c| c.part.claims.clone()).collect(),
        wall_time_s,
        robot_rounds: combos.iter().map(|c| c.part.robot_rounds).sum(),
    };
    Ok((sweep, text))
}

fn keys(set: &[Setting]) -> Vec<String> {
    set.iter().map(|s| s.key.clone()).collect()
}

/// A CSV of every combination: `csv`'s header once, each row with the
/// combination's values appended, one column per key. A CSV field never
/// holds a line break here, so a line is a row.
fn tagged(set: &[Setting], combos: &[Combo], csv: impl Fn(&Part) -> String) -> String {
    let mut s = String::new();
    for (i, c) in combos.iter().enumerate() {
        let text = csv(&c.part);
        let mut lines = text.lines();
        let header = lines.next().unwrap_or_default();
        if i == 0 {
            s += &format!("{header},{}\n", keys(set).join(","));
        }
        let tag = c.values.iter().map(|v| csv_field(v)).collect::<Vec<_>>().join(",");
        for l in lines {
            s += &format!("{l},{tag}\n");
        }
    }
    s
}

/// A value as one CSV field: quoted when it holds a quote or a line break.
fn csv_field(v: &str) -> String {
    if v.contains(['"', '\n', '\r']) {
        format!("\"{}\"", v.replace('"', "\"\""))
    } else {
        v.to_string()
    }
}

/// The terminal's table: the swept values, then the plain sweep's columns.
fn terminal_table(set: &[Setting], combos: &[Combo]) -> Table {
    let f = |x: Option<f64>, d: usize| x.map(|v| format!("{v:.d$}")).unwrap_or_else(|| "-".into());
    let mut header = keys(set);
    header.extend(["algorithm", "robots", "done", "mean_s", "ci95_s", "rounds", "collisions"].map(String::from));
    header.extend([combos[0].part.refs.x_oracle_name(), "bound_s", "x_bound"].map(String::from));
    let rows = combos
        .iter()
        .flat_map(|c| {
            c.part.cells.iter().map(|x| {
                let mut row = c.values.clone();
                row.extend([
                    x.algorithm.name().to_string(),
                    x.robots.to_string(),
                    format!("{}/{}", x.completed_runs, x.runs),
                    f(x.mean_search_time_s, 1),
                    f(x.ci95_s, 1),
                    f(x.mean_rounds, 1),
                    f(x.mean_collisions, 2),
                    f(c.part.refs.x_oracle(x), 2),
                    f(c.part.refs.bound(x), 1),
                    f(c.part.refs.x_bound(x), 2),
                ]);
                row
            })
        })
        .collect();
    Table { header, rows }
}

/// The value as the scenario read it (a number stays a number).
fn typed(part: &Part, key: &str) -> Value {
    let params = serde_json::to_value(part.scenario.params).expect("params serialise");
    let lfp = serde_json::to_value(crate::contract::lfp_params(&part.scenario)).expect("lfp params serialise");
    params.get(key).or_else(|| lfp.get(key)).cloned().unwrap_or(Value::Null)
}

/// summary.json: the plain sweep's keys, with `params` and `lfp` those of
/// the scenario as loaded, every cell tagged with its combination's values,
/// and each combination's own parameters, claims and references.
fn summary(opts: &ExperimentOptions, maps: &[Map], combos: &[Combo]) -> Value {
    let mut s = combos[0].part.summary(opts);
    s["params"] = json!(maps[0].scenario.params);
    s["lfp"] = json!(crate::contract::lfp_params(&maps[0].scenario));
    s["set"] = json!(opts.set.iter().map(|x| json!({"key": x.key, "values": x.values})).collect::<Vec<_>>());
    s["set_note"] = json!(
        "each combination of the --set values is the whole sweep on the scenario with those values in its \
        [params] or [lfp]; every combination has the same run seeds and starts (common random numbers)"
    );
    let tag =
        |c: &Combo| opts.set.iter().map(|x| (x.key.clone(), typed(&c.part, &x.key))).collect::<serde_json::Map<_, _>>();
    s["cells"] = json!(combos
        .iter()
        .flat_map(|c| c.part.cells.iter().map(move |x| {
            let mut v = json!(x);
            v.as_object_mut().expect("a cell is an object").extend(tag(c));
            v
        }))
        .collect::<Vec<_>>());
    s["combinations"] = json!(combos
        .iter()
        .map(|c| {
            let one = c.part.summary(opts);
            json!({
                "set": tag(c),
                "params": one["params"],
                "lfp": one["lfp"],
                "claims": one["claims"],
                "oracle_reference_s": one["oracle_reference_s"],
                "references": one["references"],
                "sensitivity": one["sensitivity"],
                "max_rounds": one["max_rounds"],
                "round_budget": one["round_budget"],
            })
        })
        .collect::<Vec<_>>());
    // A swept `a` changes Va and so the budget: each combination has its own.
    s["max_rounds"] = json!(combos.iter().map(|c| c.part.budgets.max()).max());
    for k in ["claims", "oracle_reference_s", "references", "sensitivity", "round_budget"] {
        if let Some(o) = s.as_object_mut() {
            o.remove(k);
        }
    }
    s
}

/// report.html: one results table over the grid, then each combination's
/// figure and claims, its parameters and the provenance.
fn page(opts: &ExperimentOptions, summary: &Value, combos: &[Combo], svgs: &[String], ran: (usize, f64)) -> Report {
    let mut results = Table::default();
    for c in combos {
        let t = report::cells_table(&c.part.cells, &c.part.refs);
        if results.header.is_empty() {
            results.header = keys(&opts.set).into_iter().chain(t.header).collect();
        }
        results.rows.extend(t.rows.into_iter().map(|r| c.values.iter().cloned().chain(r).collect()));
    }
    let mut sections = vec![Section::new(
        "Results",
        vec![
            Block::Text(format!(
                "One row per combination of {}, algorithm and robot count; every combination ran on the same seeds \
                 and starts. × oracle: {}. {}",
                keys(&opts.set).join(", "),
                crate::experiment::ORACLE_NOTE,
                combos[0].part.refs.note().trim_end()
            )),
            Block::Table(results),
        ],
    )];
    for (c, svg) in combos.iter().zip(svgs) {
        let mut blocks = vec![Block::Figure {
            svg: svg.clone(),
            caption: "Mean simulated search time of the completed runs against the number of robots, with 95% \
                      confidence intervals."
                .into(),
        }];
        let note = c.part.incomplete_note();
        if !note.trim().is_empty() {
            blocks.push(Block::Text(note.trim().to_string()));
        }
        blocks.push(Block::Claims(c.part.claims.iter().map(report::Claim::from).collect()));
        sections.push(Section::new(c.name(&opts.set), blocks));
    }
    let mut setup = report::params_of("params", &summary["params"]);
    setup.extend(report::params_of("lfp", &summary["lfp"]));
    sections.push(Section::new("Parameters of the scenario as loaded (before --set)", vec![Block::Params(setup)]));
    sections.push(provenance::section(&summary[provenance::KEY]));
    Report {
        title: format!(
            "Fig. 7 sweep over {}: {} scenario",
            keys(&opts.set).join(", "),
            summary["scenario"].as_str().unwrap_or("?")
        ),
        subtitle: format!(
            "{} combinations, {} runs per cell, base seed {}; the {} runs took {:.2} s of wall time on {} threads",
            combos.len(),
            opts.runs,
            opts.seed,
            ran.0,
            ran.1,
            rayon::current_num_threads()
        ),
        sections,
    }
}
