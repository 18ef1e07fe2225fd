//! The text of a random map, `random:SEED[,key=value...]`, and its checked
//! options. The canonical form ([`Spec::name`]) lists only the options that
//! differ from the defaults, in a fixed order, so two spellings of one map
//! get one name.

use std::fmt::Write as _;

use crate::lattice::LatticeKind;
use crate::params::Params;
use crate::scenario::limits::{self, Extent};
use crate::scenario::ScenarioError;

/// What precedes the seed.
pub const PREFIX: &str = "random:";

/// The option list for error messages and `--help`.
pub const SYNTAX: &str = "random:SEED[,size=WxH][,density=F][,passage=M][,targets=N][,robots=N][,break=ID]";

const DEFAULT_SIZE: (f64, f64) = (20.0, 16.0);
/// A little more than the `paper` map's 8%.
const DEFAULT_DENSITY: f64 = 0.15;
/// Wider than `W_pass = 1.6` at the default parameters, as the `paper` map's
/// narrowest gap: equality cases are left to `cave`.
const DEFAULT_PASSAGE: f64 = 2.0;
/// With `break=3.1.3`: the one passage's width when `passage` is not given,
/// well under `W_pass` yet still wide enough for a lattice row at the walls'
/// alignment, so the map stays searchable.
pub const DEFAULT_NARROW: f64 = 1.0;
const DEFAULT_TARGETS: usize = 9;
const DEFAULT_ROBOTS: usize = 3;
const SIZE_RANGE: (f64, f64) = (8.0, 400.0);
const MAX_DENSITY: f64 = 0.4;
/// Targets are spread by a best-of-candidates rule, quadratic in their number.
const MAX_COUNT: usize = 1000;

/// An assumption a map may break on purpose: those that a map or the ranges
/// can break alone (`r_safe > r_rob` is a parse error for every scenario).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Break {
    /// 2.4: `r_so < a + r_safe`.
    Sonar,
    /// 2.5: `r_c < 2a + r_safe - r_rob`.
    Radio,
    /// 3.1.1: `r_st < a + r_safe`.
    Laser,
    /// 3.1.2: a bay too sharp for any vertex to see its apex.
    Pocket,
    /// 3.1.3: one passage narrower than `W_pass`.
    Passage,
}

impl Break {
    pub const ALL: [Break; 5] = [Break::Sonar, Break::Radio, Break::Laser, Break::Pocket, Break::Passage];

    /// The id [`crate::assumptions::Check`] gives it.
    pub fn id(self) -> &'static str {
        match self {
            Break::Sonar => "2.4",
            Break::Radio => "2.5",
            Break::Laser => "3.1.1",
            Break::Pocket => "3.1.2",
            Break::Passage => "3.1.3",
        }
    }

    /// The checks a map breaking this must fail, and only those: a pocket
    /// no vertex sees is a stretch of `Ad` no vertex covers, so 3.1.2 always
    /// takes `coverage` with it.
    pub fn failing(self) -> &'static [&'static str] {
        match self {
            Break::Pocket => &["3.1.2", "coverage"],
            Break::Sonar => &["2.4"],
            Break::Radio => &["2.5"],
            Break::Laser => &["3.1.1"],
            Break::Passage => &["3.1.3"],
        }
    }
}

/// A random map's options, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    pub seed: u64,
    /// Width and height of the area's bounding rectangle (m), before the
    /// walls snap to the lattice.
    pub size: (f64, f64),
    /// Share of the area the obstacles cover.
    pub density: f64,
    /// Narrowest gap the obstacles leave (m); with `break=3.1.3`, the width
    /// of the one passage that breaks it.
    pub passage: f64,
    pub targets: usize,
    pub robots: usize,
    pub breaks: Option<Break>,
}

/// `W_pass` at the parameters random maps use (assumptions.rs, 3.1.3).
pub fn w_pass() -> f64 {
    let p = Params::default();
    p.a + 2.0 * p.r_safe
}

fn num(text: &str, key: &str, v: &str) -> Result<f64, ScenarioError> {
    v.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| ScenarioError::new(text, None, key, format!("must be a number, got `{v}`")))
}

fn count(text: &str, key: &str, v: &str) -> Result<usize, ScenarioError> {
    v.parse::<usize>().ok().filter(|&n| (1..=MAX_COUNT).contains(&n)).ok_or_else(|| {
        ScenarioError::new(text, None, key, format!("must be a whole number from 1 to {MAX_COUNT}, got `{v}`"))
    })
}

fn size(text: &str, v: &str) -> Result<(f64, f64), ScenarioError> {
    let bad = || {
        ScenarioError::new(
            text,
            None,
            "size",
            format!("must be WxH in metres, each {} to {}, e.g. 30x20; got `{v}`", SIZE_RANGE.0, SIZE_RANGE.1),
        )
    };
    let (w, h) = v.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h) = (w.trim().parse::<f64>().map_err(|_| bad())?, h.trim().parse::<f64>().map_err(|_| bad())?);
    let ok = |x: f64| x.is_finite() && (SIZE_RANGE.0..=SIZE_RANGE.1).contains(&x);
    if ok(w) && ok(h) {
        Ok((w, h))
    } else {
        Err(bad())
    }
}

fn parse_break(text: &str, v: &str) -> Result<Break, ScenarioError> {
    Break::ALL.into_iter().find(|b| b.id() == v).ok_or_else(|| {
        let ids: Vec<&str> = Break::ALL.iter().map(|b| b.id()).collect();
        ScenarioError::new(text, None, "break", format!("must be one of {}, got `{v}`", ids.join(", ")))
    })
}

impl Spec {
    /// Parses `random:SEED[,key=value...]`; `text` must start with [`PREFIX`].
    pub fn parse(text: &str) -> Result<Spec, ScenarioError> {
        let body = text.strip_prefix(PREFIX).unwrap_or(text);
        let mut parts = body.split(',').map(str::trim);
        let seed_text = parts.next().unwrap_or("");
        let seed = seed_text.parse::<u64>().map_err(|_| {
            ScenarioError::new(text, None, "seed", format!("must be a whole number >= 0, got `{seed_text}` ({SYNTAX})"))
        })?;
        let mut s = Spec {
            seed,
            size: DEFAULT_SIZE,
            density: DEFAULT_DENSITY,
            passage: f64::NAN,
            targets: DEFAULT_TARGETS,
            robots: DEFAULT_ROBOTS,
            breaks: None,
        };
        let mut passage = None;
        let mut seen: Vec<String> = Vec::new();
        for part in parts {
            let (key, v) = part
                .split_once('=')
                .map(|(k, v)| (k.trim(), v.trim()))
                .ok_or_else(|| ScenarioError::new(text, None, "", format!("`{part}` is not key=value ({SYNTAX})")))?;
            if seen.iter().any(|k| k == key) {
                return Err(ScenarioError::new(text, None, key, "given twice"));
            }
            seen.push(key.to_string());
            match key {
                "size" => s.size = size(text, v)?,
                "density" => {
                    s.density = num(text, key, v)?;
                    if !(0.0..=MAX_DENSITY).contains(&s.density) {
                        return Err(ScenarioError::new(
                            text,
                            None,
                            key,
                            format!("must be 0 to {MAX_DENSITY}, got {v}"),
                        ));
                    }
                }
                "passage" => {
                    let p = num(text, key, v)?;
                    if !(p > 0.0 && p <= 20.0) {
                        return Err(ScenarioError::new(text, None, key, format!("must be > 0 and <= 20 m, got {v}")));
                    }
                    passage = Some(p);
                }
                "targets" => s.targets = count(text, key, v)?,
                "robots" => s.robots = count(text, key, v)?,
                "break" => s.breaks = Some(parse_break(text, v)?),
                _ => {
                    return Err(ScenarioError::new(
                        text,
                        None,
                        key,
                        format!(
                            "unknown option; the options are size, density, passage, targets, robots, break ({SYNTAX})"
                        ),
                    ))
                }
            }
        }
        s.passage = s.check_passage(text, passage)?;
        s.admit(text)?;
        Ok(s)
    }

    /// The scenario admission limits on the options, before any map is
    /// drawn: the frame of the area asked for (its walls move out by less
    /// than a grid side when they snap), with its targets and robots. The
    /// map drawn is checked again, obstacles included ([`crate::scenario::limits::admit`]).
    fn admit(&self, text: &str) -> Result<(), ScenarioError> {
        let a = Params::default().a;
        let (width, height) = (self.size.0 + 2.0 * a, self.size.1 + 2.0 * a);
        let extent = Extent { width, height, a, kind: LatticeKind::Triangular };
        let err = |field: &'static str| move |m: String| ScenarioError::new(text, None, field, m);
        limits::check_size(&extent, limits::pieces(4, 0, self.targets)).map_err(err("size"))?;
        limits::check_robots(self.robots, extent.frame_vertices()).map_err(err("robots"))
    }

    /// The passage width, checked against `W_pass`: a map asked to hold
    /// every assumption cannot have a narrower one, and one asked to break
    /// 3.1.3 cannot break it with a wider one.
    fn check_passage(&self, text: &str, given: Option<f64>) -> Result<f64, ScenarioError> {
        let w = w_pass();
        match (self.breaks, given) {
            (Some(Break::Passage), None) => Ok(DEFAULT_NARROW),
            (Some(Break::Passage), Some(p)) if p >= w => Err(ScenarioError::new(
                text,
                None,
                "passage",
                format!("with break=3.1.3 it is the narrow passage's width and must be below W_pass = {w}, got {p}"),
            )),
            (_, None) => Ok(DEFAULT_PASSAGE),
            (Some(Break::Passage), Some(p)) => Ok(p),
            (_, Some(p)) if p < w => Err(ScenarioError::new(
                text,
                None,
                "passage",
                format!("{p} is below W_pass = a + 2 r_safe = {w} (Assumption 3.1.3); add break=3.1.3 to break it on purpose"),
            )),
            (_, Some(p)) => Ok(p),
        }
    }

    /// The canonical text: the seed, then each option that differs from its
    /// default, in the order of [`SYNTAX`].
    pub fn name(&self) -> String {
        let mut s = format!("{PREFIX}{}", self.seed);
        if self.size != DEFAULT_SIZE {
            let _ = write!(s, ",size={}x{}", self.size.0, self.size.1);
        }
        if self.density != DEFAULT_DENSITY {
            let _ = write!(s, ",density={}", self.density);
        }
        let default_passage = if self.breaks == Some(Break::Passage) { DEFAULT_NARROW } else { DEFAULT_PASSAGE };
        if self.passage != default_passage {
            let _ = write!(s, ",passage={}", self.passage);
        }
        if self.targets != DEFAULT_TARGETS {
            let _ = write!(s, ",targets={}", self.targets);
        }
        if self.robots != DEFAULT_ROBOTS {
            let _ = write!(s, ",robots={}", self.robots);
        }
        if let Some(b) = self.breaks {
            let _ = write!(s, ",break={}", b.id());
        }
        s
    }

    /// The same options with another seed (map `k` of `--maps`).
    pub fn with_seed(&self, seed: u64) -> Spec {
        Spec { seed, ..self.clone() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_names() {
        let s = Spec::parse("random:5").unwrap();
        assert_eq!((s.seed, s.size, s.passage, s.breaks), (5, (20.0, 16.0), 2.0, None));
        assert_eq!(s.name(), "random:5");
        let s = Spec::parse("random:7, break=3.1.2 ,size=30x20,density=0.2,passage=2.5").unwrap();
        assert_eq!(s.name(), "random:7,size=30x20,density=0.2,passage=2.5,break=3.1.2");
        assert_eq!(Spec::parse(&s.name()).unwrap(), s);
        let n = Spec::parse("random:1,break=3.1.3").unwrap();
        assert_eq!((n.passage, n.name().as_str()), (DEFAULT_NARROW, "random:1,break=3.1.3"));
    }

    #[test]
    fn bad_options_are_named() {
        let e = |t: &str| Spec::parse(t).unwrap_err().to_string();
        assert!(e("random:x").contains("seed: must be a whole number"), "{}", e("random:x"));
        assert!(e("random:1,size=3x20").contains("size: must be WxH"));
        assert!(e("random:1,size=30").contains("size: must be WxH"));
        assert!(e("random:1,density=0.9").contains("density: must be 0 to 0.4"));
        assert!(e("random:1,passage=1").contains("add break=3.1.3"));
        assert!(e("random:1,passage=2,break=3.1.3").contains("must be below W_pass"));
        assert!(e("random:1,break=9").contains("break: must be one of 2.4, 2.5, 3.1.1, 3.1.2, 3.1.3"));
        assert!(e("random:1,colour=red").contains("colour: unknown option"));
        assert!(e("random:1,targets=0").contains("targets: must be a whole number from 1"));
        assert!(e("random:1,size=30x20,size=20x20").contains("size: given twice"));
        assert!(e("random:1,size").contains("is not key=value"));
    }
}
