//! Choice rules by name: the built-in ones, and those a program registers
//! before it parses its arguments. A registered rule is a
//! [`Policy::Custom`] holding an interned name, so `Policy` stays `Copy`
//! and travels by name (JSON setups, run files) between processes: a
//! process that only passes the policy on (the world-server) interns the
//! name without knowing the rule; the one that runs robots must have it.

use std::sync::{Once, RwLock};

use super::{escape::Escape, frontier::Frontier, repulsive::Repulsive, ru::Ru, sequential::Sequential, ChoiceRule};
use crate::policy::Policy;

/// Makes one robot's rule; called once per robot per run.
pub type Factory = fn() -> Box<dyn ChoiceRule>;

/// A custom rule's name, interned for the life of the process.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RuleName(u16);

struct Entry {
    name: &'static str,
    factory: Option<Factory>,
}

static CUSTOM: RwLock<Vec<Entry>> = RwLock::new(Vec::new());
static EXTRA_ONCE: Once = Once::new();

/// [`super::EXTRA`] registered, before any look-up.
fn with_extra() {
    EXTRA_ONCE.call_once(|| {
        for &(name, factory) in super::EXTRA {
            // A bad name in EXTRA is a programming error the tests catch.
            let _ = intern_with(name, Some(factory));
        }
    });
}

const MAX_NAME: usize = 32;

impl RuleName {
    pub fn as_str(self) -> &'static str {
        CUSTOM.read().unwrap_or_else(|e| e.into_inner())[self.0 as usize].name
    }
}

fn check_name(name: &str) -> Result<(), String> {
    let ok = !name.is_empty()
        && name.len() <= MAX_NAME
        && name.starts_with(|c: char| c.is_ascii_lowercase())
        && name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_' || c == '-');
    if !ok {
        return Err(format!(
            "bad algorithm name `{name}`: 1 to {MAX_NAME} characters a-z, 0-9, `_`, `-`, starting with a letter"
        ));
    }
    if Policy::ALL.iter().any(|p| p.name() == name) {
        return Err(format!("`{name}` is a built-in algorithm"));
    }
    Ok(())
}

/// The interned name `name`, added (with `factory`, if given) when new.
fn intern_with(name: &str, factory: Option<Factory>) -> Result<RuleName, String> {
    check_name(name)?;
    let mut all = CUSTOM.write().unwrap_or_else(|e| e.into_inner());
    if let Some(k) = all.iter().position(|e| e.name == name) {
        if factory.is_some() {
            all[k].factory = factory;
        }
        return Ok(RuleName(k as u16));
    }
    let k = u16::try_from(all.len()).map_err(|_| "too many algorithm names".to_string())?;
    all.push(Entry { name: Box::leak(name.to_owned().into_boxed_str()), factory });
    Ok(RuleName(k))
}

/// Makes `name` an algorithm of this process: `--algorithm NAME` and
/// scenario files accept it from now on, and robots built here run
/// `factory()`'s rule. Registering a name again replaces its factory.
pub fn register(name: &str, factory: Factory) -> Result<Policy, String> {
    with_extra();
    intern_with(name, Some(factory)).map(Policy::Custom)
}

/// `name` as a policy some other program runs (robots are built
/// elsewhere, e.g. by an agent binary that registered it).
pub fn announce(name: &str) -> Result<Policy, String> {
    with_extra();
    intern_with(name, None).map(Policy::Custom)
}

/// The custom policy named `name`, if registered or announced.
pub fn lookup(name: &str) -> Option<Policy> {
    with_extra();
    let all = CUSTOM.read().unwrap_or_else(|e| e.into_inner());
    all.iter().position(|e| e.name == name).map(|k| Policy::Custom(RuleName(k as u16)))
}

/// The names registered or announced so far, in order.
pub fn custom_names() -> Vec<&'static str> {
    with_extra();
    CUSTOM.read().unwrap_or_else(|e| e.into_inner()).iter().map(|e| e.name).collect()
}

/// Whether robots of `policy` can be built in this process.
pub fn runnable(policy: Policy) -> Result<(), String> {
    rule_for(policy).map(|_| ())
}

/// A fresh rule for one robot of `policy`.
pub fn rule_for(policy: Policy) -> Result<Box<dyn ChoiceRule>, String> {
    Ok(match policy {
        Policy::Repulsive => Box::new(Repulsive),
        Policy::Sequential => Box::new(Sequential),
        Policy::Ru => Box::new(Ru),
        Policy::Escape => Box::<Escape>::default(),
        Policy::Frontier => Box::<Frontier>::default(),
        Policy::Lfp => return Err("lfp does not move on the grid: it has no choice rule".into()),
        Policy::Oracle => {
            return Err("oracle is a centralized planner, not a robot program: it has no choice rule".into())
        }
        Policy::Custom(n) => {
            // Copied out, so a factory may itself use the registry.
            let factory = CUSTOM.read().unwrap_or_else(|e| e.into_inner())[n.0 as usize].factory;
            match factory {
                Some(f) => f(),
                None => {
                    return Err(format!(
                        "algorithm `{}` is not registered in this program (run a program that registers it, e.g. with --agent-bin)",
                        n.as_str()
                    ))
                }
            }
        }
    })
}

/// Intern `name` for deserialization: any well-formed name passes here;
/// whether it can run is checked where robots are built.
pub(crate) fn intern(name: &str) -> Result<RuleName, String> {
    with_extra();
    intern_with(name, None)
}
