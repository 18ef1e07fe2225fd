//! `report.html`: an experiment's plots, tables, parameters and claim checks
//! on one self-contained page (inline CSS and SVG, no script, no network).
//!
//! Every experiment builds a [`Report`] of sections and blocks and calls
//! [`render`]; the Fig. 7 sweep's is [`fig7`]. The failure and scaling
//! experiments are meant to reuse the same blocks, so all reports look alike.

use std::fmt::Write as _;

use serde_json::Value;

use crate::claims::{ClaimResult, Verdict};
use crate::routes::xml_escape;
use crate::stats::CellStats;

/// A page: a title, an optional line under it, and sections in order.
#[derive(Clone, Debug, Default)]
pub struct Report {
    pub title: String,
    pub subtitle: String,
    pub sections: Vec<Section>,
}

#[derive(Clone, Debug)]
pub struct Section {
    pub heading: String,
    pub blocks: Vec<Block>,
}

impl Section {
    pub fn new(heading: impl Into<String>, blocks: Vec<Block>) -> Self {
        Section { heading: heading.into(), blocks }
    }
}

#[derive(Clone, Debug)]
pub enum Block {
    /// A paragraph of plain text.
    Text(String),
    /// Preformatted text (terminal output, notes).
    Pre(String),
    /// An SVG document, inlined (an XML declaration is dropped); the caption is plain text.
    Figure {
        svg: String,
        caption: String,
    },
    Table(Table),
    /// Small pictures side by side, each an SVG document with a caption.
    Gallery(Vec<(String, String)>),
    /// Name and value pairs, e.g. the parameters of a run.
    Params(Vec<(String, String)>),
    /// Claim checks with their verdicts and evidence.
    Claims(Vec<Claim>),
    /// Links to files next to the report (relative paths), with a description.
    Files(Vec<(String, String)>),
}

/// A table of text cells; a column whose cells all read as numbers (or are
/// empty) is right-aligned.
#[derive(Clone, Debug, Default)]
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

/// One claim as a report shows it: what is claimed, by what rule, the
/// verdict and the numbers behind it.
#[derive(Clone, Debug)]
pub struct Claim {
    pub id: String,
    pub statement: String,
    pub criterion: String,
    pub verdict: Verdict,
    pub evidence: Vec<String>,
}

impl From<&ClaimResult> for Claim {
    fn from(c: &ClaimResult) -> Self {
        Claim {
            id: c.id.to_string(),
            statement: c.statement.to_string(),
            criterion: c.criterion.to_string(),
            verdict: c.verdict,
            evidence: c.lines.iter().map(|l| l.trim().to_string()).filter(|l| !l.is_empty()).collect(),
        }
    }
}

/// Name/value rows of a JSON object, nested objects flattened with dots
/// (`params.a`), in the object's order.
pub fn params_of(prefix: &str, v: &Value) -> Vec<(String, String)> {
    let mut out = Vec::new();
    match v {
        Value::Object(map) => {
            for (k, x) in map {
                let name = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
                out.extend(params_of(&name, x));
            }
        }
        Value::String(s) => out.push((prefix.to_string(), s.clone())),
        other => out.push((prefix.to_string(), other.to_string())),
    }
    out
}

const STYLE: &str = r#"
:root { font-family: system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif; color: #222; }
body { margin: 0; background: #f6f6f3; }
.page { max-width: 1100px; margin: 0 auto; padding: 24px 28px 48px; background: #fff; min-height: 100vh; box-sizing: border-box; }
h1 { font-size: 22px; margin: 0 0 4px; }
.subtitle { color: #666; font-size: 14px; margin-bottom: 18px; }
h2 { font-size: 17px; margin: 28px 0 10px; padding-bottom: 4px; border-bottom: 1px solid #e2e2dc; }
nav { font-size: 13px; margin: 0 0 8px; }
nav a { margin-right: 14px; color: #1f5f99; text-decoration: none; }
figure { margin: 8px 0; }
figure svg { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: 13px; color: #555; margin-top: 4px; }
.gallery { display: flex; flex-wrap: wrap; gap: 10px 16px; }
.gallery figure { margin: 0; max-width: 250px; }
.gallery svg { border: 1px solid #eee; }
table { border-collapse: collapse; font-size: 12px; margin: 6px 0; }
th, td { padding: 3px 4px; border-bottom: 1px solid #eee; text-align: left; }
td.num { white-space: nowrap; }
td.num.pm { white-space: normal; }
th { white-space: normal; vertical-align: bottom; }
th { background: #f3f3ef; font-weight: 600; position: sticky; top: 0; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr:hover td { background: #fafaf4; }
.scroll { max-height: 520px; overflow: auto; border: 1px solid #eee; display: inline-block; max-width: 100%; }
dl.params { display: grid; grid-template-columns: max-content auto; gap: 2px 18px; font-size: 13px; margin: 6px 0; }
dl.params dt { color: #555; font-family: ui-monospace, Menlo, Consolas, monospace; }
dl.params dd { margin: 0; font-family: ui-monospace, Menlo, Consolas, monospace; word-break: break-word; }
pre { background: #f7f7f4; border: 1px solid #eee; padding: 8px 10px; font-size: 12px; overflow-x: auto; }
.claim { border: 1px solid #e4e4de; border-left-width: 5px; border-radius: 3px; padding: 8px 12px; margin: 10px 0; }
.claim.holds { border-left-color: #2ca02c; }
.claim.fails { border-left-color: #d62728; }
.claim.not_evaluated { border-left-color: #aaa; }
.claim .head { font-weight: 600; }
.verdict { display: inline-block; font-size: 12px; font-weight: 700; padding: 1px 8px; border-radius: 10px; margin-left: 6px; color: #fff; }
.holds .verdict { background: #2ca02c; } .fails .verdict { background: #d62728; } .not_evaluated .verdict { background: #999; } .undecided .verdict { background: #e6a100; }
.claim .criterion { font-size: 13px; color: #555; margin: 4px 0; }
.claim ul { margin: 4px 0 0; padding-left: 18px; font-size: 13px; }
.claim li { font-family: ui-monospace, Menlo, Consolas, monospace; font-size: 12px; }
p { font-size: 14px; line-height: 1.45; }
ul.files { font-size: 13px; }
footer { margin-top: 36px; font-size: 12px; color: #888; }
"#;

fn is_number(s: &str) -> bool {
    let t = s.trim();
    t.is_empty()
        || t == "-"
        || t.trim_end_matches('%').parse::<f64>().is_ok()
        || t.split('/').all(|p| p.parse::<f64>().is_ok())
        || t.split(" ± ").all(|p| p.parse::<f64>().is_ok())
}

/// Drops what may precede the `<svg` element (XML declaration, doctype,
/// comments), which is not allowed inside HTML.
fn inline_svg(svg: &str) -> &str {
    svg.find("<svg").map(|k| &svg[k..]).unwrap_or(svg).trim_end()
}

fn anchor(heading: &str) -> String {
    let mut a: String =
        heading.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '-' }).collect();
    while a.contains("--") {
        a = a.replace("--", "-");
    }
    a.trim_matches('-').to_string()
}

fn render_table(s: &mut String, t: &Table) {
    let cols = t.header.len().max(t.rows.iter().map(Vec::len).max().unwrap_or(0));
    let numeric: Vec<bool> = (0..cols).map(|c| t.rows.iter().all(|r| r.get(c).is_none_or(|x| is_number(x)))).collect();
    let _ = writeln!(s, "<div class=\"scroll\"><table>");
    let _ = write!(s, "<thead><tr>");
    for h in &t.header {
        // A heading may break after a slash (`retrans./run`), so that
        // wide tables fit the page.
        let _ = write!(s, "<th>{}</th>", xml_escape(h).replace('/', "/<wbr>"));
    }
    let _ = writeln!(s, "</tr></thead>\n<tbody>");
    for row in &t.rows {
        let _ = write!(s, "<tr>");
        for (c, cell) in row.iter().enumerate() {
            // A value with its interval may break after the ±, so that a
            // wide table still fits the page.
            let class = match (numeric[c], cell.contains('±')) {
                (true, true) => " class=\"num pm\"",
                (true, false) => " class=\"num\"",
                _ => "",
            };
            let _ = write!(s, "<td{class}>{}</td>", xml_escape(cell));
        }
        let _ = writeln!(s, "</tr>");
    }
    let _ = writeln!(s, "</tbody></table></div>");
}

fn render_block(s: &mut String, b: &Block) {
    match b {
        Block::Text(t) => {
            let _ = writeln!(s, "<p>{}</p>", xml_escape(t));
        }
        Block::Pre(t) => {
            let _ = writeln!(s, "<pre>{}</pre>", xml_escape(t.trim_end()));
        }
        Block::Figure { svg, caption } => {
            let _ = writeln!(s, "<figure>\n{}", inline_svg(svg));
            if !caption.is_empty() {
                let _ = writeln!(s, "<figcaption>{}</figcaption>", xml_escape(caption));
            }
            let _ = writeln!(s, "</figure>");
        }
        Block::Table(t) => render_table(s, t),
        Block::Gallery(pictures) => {
            let _ = writeln!(s, "<div class=\"gallery\">");
            for (svg, caption) in pictures {
                let _ = writeln!(
                    s,
                    "<figure>\n{}\n<figcaption>{}</figcaption>\n</figure>",
                    inline_svg(svg),
                    xml_escape(caption)
                );
            }
            let _ = writeln!(s, "</div>");
        }
        Block::Params(rows) => {
            let _ = writeln!(s, "<dl class=\"params\">");
            for (k, v) in rows {
                let _ = writeln!(s, "<dt>{}</dt><dd>{}</dd>", xml_escape(k), xml_escape(v));
            }
            let _ = writeln!(s, "</dl>");
        }
        Block::Claims(claims) => {
            for c in claims {
                let class = match c.verdict {
                    Verdict::Holds => "holds",
                    Verdict::Fails => "fails",
                    Verdict::Undecided => "undecided",
                    Verdict::NotEvaluated => "not_evaluated",
                };
                let _ = writeln!(
                    s,
                    "<div class=\"claim {class}\"><div class=\"head\">Claim ({}) {}<span class=\"verdict\">{}</span></div>",
                    xml_escape(&c.id),
                    xml_escape(&c.statement),
                    xml_escape(c.verdict.word())
                );
                if c.verdict != Verdict::NotEvaluated {
                    let _ = writeln!(s, "<div class=\"criterion\">Criterion: {}</div>", xml_escape(&c.criterion));
                }
                if !c.evidence.is_empty() {
                    let _ = writeln!(s, "<ul>");
                    for l in &c.evidence {
                        let _ = writeln!(s, "<li>{}</li>", xml_escape(l));
                    }
                    let _ = writeln!(s, "</ul>");
                }
                let _ = writeln!(s, "</div>");
            }
        }
        Block::Files(files) => {
            let _ = writeln!(s, "<ul class=\"files\">");
            for (path, what) in files {
                let _ = writeln!(
                    s,
                    "<li><a href=\"{}\">{}</a>: {}</li>",
                    xml_escape(path),
                    xml_escape(path),
                    xml_escape(what)
                );
            }
            let _ = writeln!(s, "</ul>");
        }
    }
}

/// The page as one HTML document.
pub fn render(report: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n\
         <style>{STYLE}</style>\n</head>\n<body>\n<div class=\"page\">",
        xml_escape(&report.title)
    );
    let _ = writeln!(s, "<h1>{}</h1>", xml_escape(&report.title));
    if !report.subtitle.is_empty() {
        let _ = writeln!(s, "<div class=\"subtitle\">{}</div>", xml_escape(&report.subtitle));
    }
    if report.sections.len() > 1 {
        let _ = write!(s, "<nav>");
        for sec in &report.sections {
            let _ = write!(s, "<a href=\"#{}\">{}</a>", anchor(&sec.heading), xml_escape(&sec.heading));
        }
        let _ = writeln!(s, "</nav>");
    }
    for sec in &report.sections {
        let _ = writeln!(s, "<section id=\"{}\">\n<h2>{}</h2>", anchor(&sec.heading), xml_escape(&sec.heading));
        for b in &sec.blocks {
            render_block(&mut s, b);
        }
        let _ = writeln!(s, "</section>");
    }
    let _ = writeln!(
        s,
        "<footer>Written by gridswarm {}. Self-contained: this page loads nothing else.</footer>",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(s, "</div>\n</body>\n</html>");
    s
}

/// The results table of a Fig. 7 sweep, one row per (algorithm, robots).
pub fn cells_table(cells: &[CellStats], refs: &crate::refs::Refs) -> Table {
    let f = |x: Option<f64>, d: usize| x.map(|v| format!("{v:.d$}")).unwrap_or_else(|| "-".into());
    Table {
        header: [
            "algorithm",
            "label",
            "robots",
            "completed",
            "mean time (s)",
            "ci95 (s)",
            "std (s)",
            "median (s)",
            "mean rounds",
            "mean collisions",
            "mean targets found",
            if refs.estimate() { "× oracle (estimate)" } else { "× oracle" },
            "lower bound (s)",
            "× bound",
        ]
        .map(String::from)
        .to_vec(),
        rows: cells
            .iter()
            .map(|c| {
                vec![
                    c.algorithm.name().to_string(),
                    c.algorithm.paper_label().to_string(),
                    c.robots.to_string(),
                    format!("{}/{}", c.completed_runs, c.runs),
                    f(c.mean_search_time_s, 1),
                    f(c.ci95_s, 1),
                    f(c.std_search_time_s, 1),
                    f(c.median_search_time_s, 1),
                    f(c.mean_rounds, 1),
                    f(c.mean_collisions, 2),
                    format!("{:.2}", c.mean_targets_found),
                    f(refs.x_oracle(c), 2),
                    f(refs.bound(c), 1),
                    f(refs.x_bound(c), 2),
                ]
            })
            .collect(),
    }
}

/// The sweep's dependence on the paper's readings: a table of each
/// alternative reading against the scenario's own on the same runs; `None`
/// when the sweep has no algorithm with a switchable reading.
pub fn sensitivity_section(rows: &[crate::sensitivity::Row]) -> Option<Section> {
    if rows.is_empty() {
        return None;
    }
    let f = |x: Option<f64>| x.map(|v| format!("{v:.1}")).unwrap_or_else(|| "-".into());
    let table = Table {
        header: [
            "algorithm",
            "alternative reading",
            "robots",
            "runs",
            "scenario's reading (s)",
            "alternative (s)",
            "ratio",
        ]
        .map(String::from)
        .to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                let ratio = r.alternative_s.zip(r.scenario_s).map(|(a, b)| format!("{:.2}", a / b));
                vec![
                    r.algorithm.paper_label().to_string(),
                    r.reading.to_string(),
                    r.robots.to_string(),
                    r.runs.to_string(),
                    f(r.scenario_s),
                    f(r.alternative_s),
                    ratio.unwrap_or_else(|| "-".into()),
                ]
            })
            .collect(),
    };
    Some(Section::new(
        "Sensitivity to the readings",
        vec![
            Block::Text(format!(
                "Where the paper's text is ambiguous the scenario chooses a reading (docs/paper.md argues each \
                 default). For each baseline of this sweep with a switchable reading: its first {} runs per robot \
                 count (same seeds and starts; the first map) under the scenario's reading and under the \
                 alternative, mean search time of the completed runs.",
                rows[0].runs
            )),
            Block::Table(table),
        ],
    ))
}

/// What a Fig. 7 sweep ran and produced, for [`fig7`].
pub struct Fig7Inputs<'a> {
    /// The sweep's `summary.json` (its setup is read from it).
    pub summary: &'a Value,
    pub cells: &'a [CellStats],
    pub claims: &'a [ClaimResult],
    pub fig7_svg: &'a str,
    /// Cells cut short by the round limit, if any (one paragraph).
    pub incomplete_note: &'a str,
    pub wall_time_s: f64,
    pub threads: usize,
    pub runs_total: usize,
    /// The oracle's means and the lower bounds, the references of the
    /// "× oracle" and "× bound" columns.
    pub refs: &'a crate::refs::Refs,
    /// Sections after the results (the per-map spread of a sweep over maps).
    pub extra: Vec<Section>,
}

/// The Fig. 7 sweep's report.
pub fn fig7(x: &Fig7Inputs) -> Report {
    let s = x.summary;
    let get = |k: &str| match s.get(k) {
        Some(Value::String(t)) => t.clone(),
        Some(v) => v.to_string(),
        None => "?".into(),
    };
    let mut setup: Vec<(String, String)> = [
        "scenario",
        "grid",
        "situation",
        "algorithms",
        "robots",
        "runs",
        "seed",
        "seed_derivation",
        "max_rounds",
        "statistics",
    ]
    .iter()
    .filter(|k| s.get(**k).is_some())
    .map(|k| (k.to_string(), get(k)))
    .collect();
    setup.extend(params_of("params", s.get("params").unwrap_or(&Value::Null)));
    setup.extend(params_of("lfp", s.get("lfp").unwrap_or(&Value::Null)));

    let holds = x.claims.iter().filter(|c| c.verdict == Verdict::Holds).count();
    let evaluated = x.claims.iter().filter(|c| c.verdict != Verdict::NotEvaluated).count();
    let mut claims_blocks = vec![Block::Claims(x.claims.iter().map(Claim::from).collect())];
    if !x.incomplete_note.trim().is_empty() {
        claims_blocks.insert(0, Block::Text(x.incomplete_note.trim().to_string()));
    }
    let mut sections = vec![
        Section::new(
            "Mean search time",
            vec![Block::Figure {
                svg: x.fig7_svg.to_string(),
                caption: "Mean simulated search time of the completed runs against the number of robots, \
                          with 95% confidence intervals (as the paper's Fig. 7)."
                    .into(),
            }],
        ),
        Section::new("Claims", claims_blocks),
        Section::new(
            "Results",
            vec![
                Block::Table(cells_table(x.cells, x.refs)),
                Block::Text(format!(
                    "× oracle: the mean search time over the oracle's at the same robot count; the oracle is {}. {}",
                    crate::experiment::ORACLE_NOTE,
                    x.refs.note().trim_end()
                )),
            ],
        ),
    ];
    sections.extend(x.extra.iter().cloned());
    sections.push(Section::new("Parameters", vec![Block::Params(setup)]));
    sections.push(Section::new("Files", vec![Block::Files(files(s.get("maps").is_some()))]));
    let maps = s.get("maps").and_then(Value::as_array).map(Vec::len);
    Report {
        title: match maps {
            Some(k) => format!("Fig. 7 sweep: {k} random maps from {}", get("scenario")),
            None => format!("Fig. 7 sweep: {} scenario", get("scenario")),
        },
        subtitle: format!(
            "{} runs per cell{}, base seed {}, situation {}; the {} runs took {:.2} s of wall time on {} threads; \
             claims: {holds} of {evaluated} evaluated hold",
            get("runs"),
            if maps.is_some() { " and map" } else { "" },
            get("seed"),
            get("situation"),
            x.runs_total,
            x.wall_time_s,
            x.threads
        ),
        sections,
    }
}

/// The files a Fig. 7 sweep writes beside its report.
fn files(maps: bool) -> Vec<(String, String)> {
    let mut f = vec![
        ("results.csv", "the table above (map = all), and with several maps each map's cells, with the runs' metrics"),
        ("runs.csv", "every run: seed, time, rounds, collisions, targets, map, and its metrics"),
        ("coverage.csv", "each cell's coverage against time (the figure's curves)"),
    ];
    if maps {
        f.push(("maps.csv", "every map: its scenario name (to rerun it alone), draws, time to make, obstacles"));
    }
    f.extend([
        ("fig7.svg", "the figure"),
        ("claims.txt", "the claim checks as text"),
        ("summary.json", "everything above as JSON"),
    ]);
    f.into_iter().map(|(a, b)| (a.to_string(), b.to_string())).collect()
}

/// Widest line a terminal table may take: wider ones wrap on an 80-100
/// column terminal and become unreadable.
pub const TERMINAL_WIDTH: usize = 100;

/// A table for the terminal, columns aligned (the first left, the others
/// right). A table wider than [`TERMINAL_WIDTH`] is printed as several
/// narrower ones, each repeating the first column, so no line wraps.
pub fn text_table(t: &Table) -> String {
    keyed_text_table(t, 1)
}

/// [`text_table`] whose first `keys` columns (what identifies a row)
/// start every part, so that no part reads as rows of one key alone.
pub fn keyed_text_table(t: &Table, keys: usize) -> String {
    let cols = t.header.len();
    let keys = keys.clamp(1, cols.max(1));
    let width: Vec<usize> = (0..cols)
        .map(|c| t.rows.iter().map(|r| r[c].chars().count()).chain([t.header[c].chars().count()]).max().unwrap_or(0))
        .collect();
    let key_width: usize = width.iter().take(keys).sum::<usize>() + 2 * (keys.min(cols).saturating_sub(1));
    // Column groups after the keys, each fitting the width with them.
    let mut groups: Vec<Vec<usize>> = vec![Vec::new()];
    let mut used = key_width;
    for c in keys..cols {
        let last = groups.last_mut().expect("one group");
        if !last.is_empty() && used + 2 + width[c] > TERMINAL_WIDTH {
            groups.push(Vec::new());
            used = key_width;
        }
        groups.last_mut().expect("one group").push(c);
        used += 2 + width[c];
    }
    let mut s = String::new();
    for (g, group) in groups.iter().enumerate() {
        if g > 0 {
            s.push('\n');
        }
        for row in std::iter::once(&t.header).chain(&t.rows) {
            let cells: Vec<String> = (0..keys.min(cols))
                .chain(group.iter().copied())
                .map(|c| {
                    let x = &row[c];
                    let pad = " ".repeat(width[c].saturating_sub(x.chars().count()));
                    if c == 0 {
                        format!("{x}{pad}")
                    } else {
                        format!("{pad}{x}")
                    }
                })
                .collect();
            let _ = writeln!(s, "{}", cells.join("  ").trim_end());
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::policy::Policy;
    use serde_json::json;

    #[test]
    fn every_part_of_a_split_table_starts_with_its_keys() {
        let header: Vec<String> = ["loss", "robots", "retries"]
            .into_iter()
            .map(String::from)
            .chain((0..10).map(|c| format!("a wide column {c}")))
            .collect();
        let t = Table { header, rows: vec![(0..13).map(|c| format!("{c}")).collect()] };
        let text = keyed_text_table(&t, 3);
        let parts: Vec<&str> = text.split("\n\n").collect();
        assert!(parts.len() > 1, "{text}");
        for p in parts {
            let mut lines = p.lines();
            let head: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
            assert_eq!(&head[..3], ["loss", "robots", "retries"], "{text}");
            let row: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
            assert_eq!(&row[..3], ["0", "1", "2"], "{text}");
        }
        assert!(text.lines().all(|l| l.chars().count() <= TERMINAL_WIDTH), "{text}");
    }

    #[test]
    fn wide_tables_split_to_fit_a_terminal() {
        let header: Vec<String> = (0..12).map(|c| format!("column number {c}")).collect();
        let t = Table { header: header.clone(), rows: vec![(0..12).map(|c| c.to_string()).collect()] };
        let text = text_table(&t);
        assert!(text.lines().all(|l| l.chars().count() <= TERMINAL_WIDTH), "{text}");
        // Every column is still there, and each part starts with the first.
        for h in &header {
            assert!(text.contains(h.as_str()), "{h} missing: {text}");
        }
        let parts: Vec<&str> = text.split("\n\n").collect();
        assert!(parts.len() > 1 && parts.iter().all(|p| p.starts_with("column number 0")), "{text}");
        // A narrow table is one block.
        let narrow = Table { header: vec!["a".into(), "b".into()], rows: vec![vec!["1".into(), "2".into()]] };
        assert_eq!(text_table(&narrow), "a  b\n1  2\n");
    }

    #[test]
    fn escapes_text_and_inlines_svg() {
        let r = Report {
            title: "a <b> & c".into(),
            subtitle: String::new(),
            sections: vec![Section::new(
                "One",
                vec![
                    Block::Figure {
                        svg: "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\"><rect/></svg>\n"
                            .into(),
                        caption: "x < y".into(),
                    },
                    Block::Table(Table {
                        header: vec!["name".into(), "value".into()],
                        rows: vec![vec!["<i>".into(), "1.5".into()], vec!["b".into(), "".into()]],
                    }),
                    Block::Params(params_of("p", &json!({ "a": 1.0, "b": { "c": "d" } }))),
                ],
            )],
        };
        let html = render(&r);
        assert!(html.contains("<title>a &lt;b&gt; &amp; c</title>"));
        assert!(!html.contains("<?xml"));
        assert!(html.contains("<figure>\n<svg xmlns"));
        assert!(html.contains("<td>&lt;i&gt;</td><td class=\"num\">1.5</td>"));
        assert!(html.contains("<dt>p.b.c</dt><dd>d</dd>"));
        assert!(html.contains("<figcaption>x &lt; y</figcaption>"));
        assert!(!html.contains("<script"));
    }

    #[test]
    fn claims_show_their_verdicts() {
        let c = ClaimResult {
            id: "a",
            statement: "s",
            criterion: "c",
            verdict: Verdict::Fails,
            lines: vec!["  n = 3".into()],
            data: json!({}),
        };
        let html = render(&Report {
            title: "t".into(),
            subtitle: String::new(),
            sections: vec![Section::new("C", vec![Block::Claims(vec![Claim::from(&c)])])],
        });
        assert!(html.contains("class=\"claim fails\""));
        assert!(html.contains("DOES NOT HOLD"));
        assert!(html.contains("<li>n = 3</li>"));
    }

    #[test]
    fn table_of_cells() {
        let c = CellStats {
            algorithm: Policy::Ru,
            robots: 4,
            runs: 5,
            completed_runs: 4,
            mean_search_time_s: Some(100.0),
            std_search_time_s: None,
            ci95_s: None,
            mean_rounds: Some(10.0),
            mean_collisions: Some(0.5),
            median_search_time_s: Some(99.0),
            mean_targets_found: 9.0,
            metrics: Default::default(),
        };
        let t = cells_table(std::slice::from_ref(&c), &crate::refs::Refs::default());
        assert_eq!(t.rows[0][..5], ["ru", "RU", "4", "4/5", "100.0"].map(String::from));
        assert_eq!(t.rows[0][5], "-");
        assert_eq!(t.rows[0][11..], ["-", "-", "-"].map(String::from));
        // The oracle on 10 runs of the cells' 50: an estimate, and said so.
        let refs = crate::refs::Refs {
            oracle: [(4, 50.0)].into(),
            oracle_runs: 10,
            cell_runs: 50,
            bound: [((false, 4), 40.0)].into(),
        };
        let t = cells_table(&[c], &refs);
        assert_eq!(t.header[11], "× oracle (estimate)");
        assert_eq!(t.rows[0][11..], ["2.00", "40.0", "2.50"].map(String::from));
    }
}
