//! `gridswarm experiment --grids`: the grid-selection argument of Sec. 3,
//! measured. On one map, at the same side `a` and the same ranges, each
//! lattice gives its own `Va`; this reports how much of `Ad` is detected
//! once every vertex of `Va` has been visited, i.e. the best any search on
//! that lattice can do.

use std::fmt::Write as _;
use std::path::PathBuf;

use gridswarm::lattice::LatticeKind;
use serde::Serialize;

use gridswarm::scenario::Scenario;

use crate::contract;
use crate::error::Result;
use crate::report::{self, Block, Report, Section, Table};
use crate::staging::Staging;
use crate::{output, routes};

#[derive(Clone, Debug)]
pub struct GridsOptions {
    pub scenario: String,
    pub out: PathBuf,
}

#[derive(Clone, Debug, Serialize)]
pub struct GridRow {
    pub grid: &'static str,
    pub degree: usize,
    pub frame_vertices: usize,
    pub accessible: usize,
    pub va: usize,
    /// Samples of `Ad` within `r_st` of some vertex of `Va`, over all samples.
    pub detected_fraction: f64,
    /// The undetected part of `Ad` in m² (samples times cell area).
    pub undetected_area_m2: f64,
}

/// Raster cells of side `a / RASTER_DIVISIONS`: fine enough that a missed
/// sliver a few centimetres wide shows up.
pub const RASTER_DIVISIONS: f64 = 20.0;

/// Where `experiment --grids` writes unless told: not the sweep's folder.
pub const DEFAULT_OUT: &str = "grids-out";

pub fn run(opts: &GridsOptions) -> Result<(Vec<GridRow>, String)> {
    let base = contract::load_scenario(&opts.scenario)?;
    let stage = Staging::begin(&opts.out)?;
    let dir = stage.path().to_path_buf();
    let h = base.params.a / RASTER_DIVISIONS;
    let mut rows = Vec::new();
    let mut pictures = Vec::new();
    for kind in LatticeKind::ALL {
        let mut scenario = base.clone();
        scenario.grid = kind;
        let world = scenario.world();
        let starts = contract::start_vertices(&scenario, &world, scenario.robots)?;
        let va = world.reachable_from(&starts);
        let va_positions: Vec<_> =
            va.iter().enumerate().filter(|(_, &b)| b).map(|(v, _)| world.grid.position(v as u32)).collect();
        let raster = world.raster(h);
        let mut hit = raster.unmarked();
        let detected: usize = va_positions.iter().map(|&c| raster.mark(&mut hit, c, scenario.params.r_st)).sum();
        let fraction = if raster.samples() == 0 { 1.0 } else { detected as f64 / raster.samples() as f64 };
        let holes: Vec<_> = raster.unmarked_samples(&hit).collect();
        let title =
            format!("{}: {} lattice, {} undetected samples (red) of Ad; grey: Va", base.name, kind.name(), holes.len());
        pictures.push((kind.name(), routes::holes_svg(&world, &va_positions, &holes, &title)));
        rows.push(GridRow {
            grid: kind.name(),
            degree: world.grid.degree(),
            frame_vertices: world.grid.len(),
            accessible: world.accessible_vertices().count(),
            va: va_positions.len(),
            detected_fraction: fraction,
            undetected_area_m2: (1.0 - fraction) * raster.samples() as f64 * h * h,
        });
    }
    output::write_text(&dir.join("grids.csv"), &csv(&rows))?;
    let p = &base.params;
    let mut text = format!(
        "scenario {}: a = {} m, r_safe = {} m, r_st = {} m, start vertices of {} robots as the scenario \
         places them; raster cell {h} m\n",
        crate::output::shown(&base.name),
        p.a,
        p.r_safe,
        p.r_st,
        base.robots
    );
    let _ = writeln!(
        text,
        "{:<11} {:>6} {:>9} {:>10} {:>7} {:>17} {:>18}",
        "grid", "degree", "vertices", "accessible", "|Va|", "detected fraction", "undetected (m^2)"
    );
    for r in &rows {
        let _ = writeln!(
            text,
            "{:<11} {:>6} {:>9} {:>10} {:>7} {:>17.6} {:>18.4}",
            r.grid, r.degree, r.frame_vertices, r.accessible, r.va, r.detected_fraction, r.undetected_area_m2
        );
    }
    // Every raster sample detected: the lattice leaves no hole in Ad even
    // when every robot does its best (Sec. 3's argument for triangles).
    let complete: Vec<&str> = rows.iter().filter(|r| r.detected_fraction >= 1.0).map(|r| r.grid).collect();
    let _ = writeln!(
        text,
        "lattices on which visiting all of Va detects every raster sample of Ad: {}",
        if complete.is_empty() { "none".to_string() } else { complete.join(", ") }
    );
    text += "vertices: the lattice's frame over the area\n\
             accessible: in Ad and at least r_safe from every wall and obstacle\n\
             |Va|: accessible and reachable from the starts over traversable edges (what a search can visit)\n\
             detected fraction: share of raster samples of Ad within r_st of a vertex of Va\n";
    // Every file written, in order, is said: the table, one picture per
    // lattice, the page.
    let mut written = vec!["grids.csv".to_string()];
    for (name, svg) in &pictures {
        let file = format!("grids-{name}.svg");
        output::write_text(&dir.join(&file), svg)?;
        written.push(file);
    }
    let mut page = grids_report(&base, h, &rows, &text, pictures);
    let record = crate::provenance::Record {
        scenario_arg: Some(&opts.scenario),
        parameters: serde_json::json!({ "params": base.params, "raster_side_m": h }),
        seeds: serde_json::Value::Null,
        starts: serde_json::json!({ "rule": "fixed" }),
    };
    crate::provenance::stamp(&dir, &mut page, &record)?;
    written.push(crate::provenance::FILE.into());
    output::write_text(&dir.join("grids.html"), &report::render(&page))?;
    written.push("grids.html".into());
    stage.commit()?;
    for file in written {
        let _ = writeln!(text, "wrote {}", opts.out.join(file).display());
    }
    Ok((rows, text))
}

/// `grids.html`: the comparison table and the setup, on one page (named
/// apart from the Fig. 7 sweep's `report.html`, which may share the directory).
fn grids_report(base: &Scenario, h: f64, rows: &[GridRow], text: &str, pictures: Vec<(&str, String)>) -> Report {
    let table = Table {
        header: ["grid", "degree", "frame vertices", "accessible", "|Va|", "detected fraction", "undetected (m²)"]
            .map(String::from)
            .to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                vec![
                    r.grid.to_string(),
                    r.degree.to_string(),
                    r.frame_vertices.to_string(),
                    r.accessible.to_string(),
                    r.va.to_string(),
                    format!("{:.6}", r.detected_fraction),
                    format!("{:.4}", r.undetected_area_m2),
                ]
            })
            .collect(),
    };
    let mut params = vec![
        ("scenario".to_string(), base.name.clone()),
        ("robots (start vertices)".to_string(), base.robots.to_string()),
        ("raster cell (m)".to_string(), h.to_string()),
    ];
    params.extend(report::params_of("params", &serde_json::to_value(base.params).expect("params serialise")));
    Report {
        title: format!("Lattice comparison (Sec. 3): {} scenario", crate::output::shown(&base.name)),
        subtitle: "How much of Ad is detected once every vertex of Va is visited, on each lattice at the same a".into(),
        sections: vec![
            Section::new("Detected fraction by lattice", vec![Block::Table(table)]),
            Section::new(
                "Where each lattice leaves Ad undetected",
                pictures
                    .into_iter()
                    .map(|(name, svg)| Block::Figure {
                        svg,
                        caption: format!(
                            "{name}: red squares are raster samples of Ad farther than r_st from every vertex of Va \
                             (the area no search on this lattice can detect); also in grids-{name}.svg"
                        ),
                    })
                    .collect(),
            ),
            Section::new("As printed", vec![Block::Pre(text.to_string())]),
            Section::new("Parameters", vec![Block::Params(params)]),
        ],
    }
}

pub fn csv(rows: &[GridRow]) -> String {
    let mut s = String::from("grid,degree,frame_vertices,accessible,va,detected_fraction,undetected_area_m2\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:.6},{:.6}",
            r.grid, r.degree, r.frame_vertices, r.accessible, r.va, r.detected_fraction, r.undetected_area_m2
        );
    }
    s
}
