//! `--set KEY=V1,V2,...`: the scenario keys a sweep varies, and the grid of
//! their combinations. A value is applied by writing it into the
//! scenario's own text (`[params]` or `[lfp]`) and reading the scenario
//! again, so a swept value is checked exactly as the same value in a
//! scenario file would be. It never runs anything.

use std::str::FromStr;

use gridswarm::scenario::Scenario;

use crate::error::{Error, Result};

/// One `--set`: a key and the values it takes, in the order given.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    pub key: String,
    pub values: Vec<String>,
}

impl FromStr for Setting {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let (key, values) =
            s.split_once('=').ok_or_else(|| format!("`{s}` is not KEY=V1,V2,... (e.g. t_wait=1,2,4)"))?;
        let key = key.trim().to_string();
        let values: Vec<String> = values.split(',').map(|v| v.trim().to_string()).collect();
        if key.is_empty() || values.iter().any(String::is_empty) {
            return Err(format!("`{s}`: the key and every value must be non-empty (e.g. t_wait=1,2,4)"));
        }
        for (i, v) in values.iter().enumerate() {
            if values[..i].contains(v) {
                return Err(format!("`{s}`: {key} is given the value {v} twice"));
            }
        }
        Ok(Setting { key, values })
    }
}

/// Which table of the scenario file holds `key`.
fn table_of(scenario: &Scenario, key: &str) -> Result<&'static str> {
    let keys = |v: serde_json::Value| v.as_object().map(|o| o.keys().cloned().collect::<Vec<_>>()).unwrap_or_default();
    let params = keys(serde_json::to_value(scenario.params).expect("params serialise"));
    let lfp = keys(serde_json::to_value(scenario.lfp).expect("lfp params serialise"));
    if params.iter().any(|k| k == key) {
        return Ok("params");
    }
    if lfp.iter().any(|k| k == key) {
        return Ok("lfp");
    }
    Err(Error::Usage(format!(
        "--set: `{key}` is no [params] or [lfp] key of a scenario (params: {}; lfp: {})",
        params.join(", "),
        lfp.join(", ")
    )))
}

/// Checks the keys: each known and given once.
pub fn check(settings: &[Setting], scenario: &Scenario) -> Result<()> {
    for (i, s) in settings.iter().enumerate() {
        table_of(scenario, &s.key)?;
        if settings[..i].iter().any(|t| t.key == s.key) {
            return Err(Error::Usage(format!("--set {} is given twice; list its values in one --set", s.key)));
        }
    }
    Ok(())
}

/// Every combination of the values, the first key varying slowest; each is
/// one value index per setting. No settings: one empty combination.
pub fn combinations(settings: &[Setting]) -> Vec<Vec<usize>> {
    settings.iter().fold(vec![Vec::new()], |done, s| {
        done.into_iter()
            .flat_map(|c| {
                (0..s.values.len()).map(move |v| {
                    let mut c = c.clone();
                    c.push(v);
                    c
                })
            })
            .collect()
    })
}

/// A value as the scenario file would hold it: a number, a boolean or
/// text, as TOML reads `KEY = V`; anything else is a string.
fn value(v: &str) -> toml::Value {
    toml::from_str::<toml::Table>(&format!("v = {v}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(v.to_string()))
}

/// `scenario` with each (key, value) set, checked as a scenario file is;
/// an error names the key and value that made it invalid.
pub fn apply(scenario: &Scenario, pairs: &[(&str, &str)]) -> Result<Scenario> {
    let mut s = scenario.clone();
    for &(key, v) in pairs {
        let table = table_of(&s, key)?;
        let mut doc: toml::Table = toml::from_str(&s.to_toml("")).expect("a scenario writes valid TOML");
        let t = doc.entry(table).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        t.as_table_mut().expect("[params] and [lfp] are tables").insert(key.to_string(), value(v));
        let text = toml::to_string(&doc).expect("a TOML table writes");
        let source = format!("--set {key}={v}");
        s = Scenario::parse(&text, &source).map_err(|e| Error::Usage(located(&e.to_string(), &source)))?;
    }
    Ok(s)
}

/// A scenario error about the written text, without the line and column
/// in that text, which the user never saw: `--set t_wait=soon: invalid type`.
fn located(message: &str, source: &str) -> String {
    let rest = message.strip_prefix(source).unwrap_or(message);
    let rest = rest.trim_start_matches(|c: char| c == ':' || c.is_ascii_digit()).trim_start();
    format!("{source}: {rest}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper() -> Scenario {
        Scenario::builtin("paper").unwrap()
    }

    #[test]
    fn settings_parse_and_make_a_grid() {
        let a: Setting = "t_wait=1, 2".parse().unwrap();
        assert_eq!(a.values, ["1", "2"]);
        let b: Setting = "turn=0.5,uniform,1".parse().unwrap();
        assert_eq!(combinations(&[a, b]), [[0, 0], [0, 1], [0, 2], [1, 0], [1, 1], [1, 2]]);
        assert_eq!(combinations(&[]), [Vec::<usize>::new()]);
        for bad in ["t_wait", "=1", "t_wait=", "t_wait=1,,2", "t_wait=1,1"] {
            assert!(bad.parse::<Setting>().is_err(), "{bad}");
        }
    }

    #[test]
    fn values_land_in_their_table_and_are_checked() {
        let s = apply(&paper(), &[("t_wait", "2"), ("turn", "uniform"), ("ru_collisions", "back-off")]).unwrap();
        assert_eq!(s.params.t_wait, 2.0);
        assert_eq!(s.lfp.turn, gridswarm::lfp::Turn::Uniform);
        assert_eq!(s.params.ru_collisions.name(), "back-off");
        let s = apply(&paper(), &[("turn", "0.5"), ("micro_steps", "4")]).unwrap();
        assert_eq!(s.lfp.turn, gridswarm::lfp::Turn::Sigma(0.5));
        assert_eq!((s.name.as_str(), s.targets.len()), ("paper", paper().targets.len()));
        assert_eq!(apply(&paper(), &[]).unwrap().to_toml(""), paper().to_toml(""));
        assert!(!apply(&paper(), &[("survivor_step", "false")]).unwrap().params.survivor_step);
        for (k, v) in [
            ("t_wait", "-1"),
            ("t_wait", "soon"),
            ("ru_collisions", "sometimes"),
            ("micro_steps", "0.5"),
            ("survivor_step", "sometimes"),
        ] {
            let e = apply(&paper(), &[(k, v)]).unwrap_err();
            assert!(
                matches!(&e, Error::Usage(m) if m.starts_with(&format!("--set {k}={v}: ")) && !m.contains(":1")),
                "{e}"
            );
        }
        let e = check(&["nope=1".parse().unwrap()], &paper()).unwrap_err();
        assert!(matches!(&e, Error::Usage(m) if m.contains("`nope`") && m.contains("t_wait")), "{e}");
        let twice = ["r_c=1".parse().unwrap(), "r_c=2".parse().unwrap()];
        assert!(check(&twice, &paper()).is_err());
    }
}
