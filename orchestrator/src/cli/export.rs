//! `gridswarm export-map`: any scenario (built-in, file, `random:`, map)
//! written as a scenario file or as a ROS map_server map, and a map read
//! back at once, so that what was written is known to load.

use std::path::{Path, PathBuf};

use gridswarm::scenario::occupancy;

use crate::contract;
use crate::error::{Error, Result};
use crate::output::shown;

/// The two forms a scenario is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MapFormat {
    /// NAME.yaml, NAME.pgm and NAME.gridswarm.toml (targets, starts, parameters).
    Yaml,
    /// One scenario file.
    Toml,
}

/// What `export-map` was asked.
pub struct ExportOptions {
    pub scenario: String,
    pub format: MapFormat,
    /// The file to write (the YAML file for a map) [default: NAME.yaml or
    /// NAME.toml in the current folder].
    pub out: Option<PathBuf>,
    /// Pixel side (m) of a map [default: a / 10].
    pub resolution: Option<f64>,
}

/// A file name from a scenario's name: letters, digits, `-`, `_` and `.`.
fn file_stem(name: &str) -> String {
    let s: String =
        name.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect();
    if s.trim_matches('.').is_empty() {
        "scenario".into()
    } else {
        s
    }
}

/// Writes the scenario; the text says which files were written.
pub fn export(opts: &ExportOptions) -> Result<String> {
    let scenario = contract::load_scenario(&opts.scenario)?;
    let ext = match opts.format {
        MapFormat::Yaml => "yaml",
        MapFormat::Toml => "toml",
    };
    let out = opts.out.clone().unwrap_or_else(|| PathBuf::from(format!("{}.{ext}", file_stem(&scenario.name))));
    let name = shown(&scenario.name);
    match opts.format {
        MapFormat::Toml => {
            let text = scenario.to_toml(&format!("gridswarm export-map {}", shown(&opts.scenario)));
            std::fs::write(&out, text).map_err(Error::write(&out))?;
            Ok(format!("scenario `{name}` written to {}\n", out.display()))
        }
        MapFormat::Yaml => {
            let res = opts.resolution.unwrap_or(scenario.params.a * occupancy::DEFAULT_RESOLUTION_SIDES);
            let written = occupancy::write_map(&scenario, &out, res).map_err(Error::Input)?;
            let list = written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ");
            read_back(&out, &list)?;
            Ok(format!("scenario `{name}` written as a map with pixels of {res} m: {list}\n"))
        }
    }
}

/// Reads the map just written, as `--scenario` will: a target or start
/// that a pixel's step now covers is an error here, not at the next run.
fn read_back(yaml: &Path, list: &str) -> Result<()> {
    let path = yaml.to_string_lossy();
    contract::load_scenario(&path).map(|_| ()).map_err(|e| {
        Error::Scenario(format!(
            "wrote {list}, but it does not read back as a scenario ({e}); try a finer --resolution"
        ))
    })
}
