//! Fault schedules as users write them on the command line, and back: a
//! time is `ROUND` or `ROUND+SECONDS` (simulated seconds after that slot
//! starts), so a fault can fall inside a round, mid-chain.
//!
//! - `--kill R@T`: robot R crashes at T;
//! - `--freeze R@T[:T2]`: robot R freezes at T (and thaws at T2);
//! - `--slow R@T:MS`: from T on, robot R reacts MS milliseconds late;
//! - `--kill-random K`: K distinct robots crash at times drawn from the seed.

use super::{micros, seconds, Fault, FaultKind, Time};
use crate::rng::derive;

/// Rounds `--kill-random` draws from (1 to this).
pub const RANDOM_ROUNDS: u32 = 20;
/// `--kill-random` draws the offset in a round below this (s): the
/// exchange and most choice chains.
pub const RANDOM_OFFSET_S: f64 = 1.0;

/// `ROUND` or `ROUND+SECONDS`.
pub fn parse_when(s: &str) -> Result<(u32, Time), String> {
    let (r, off) = match s.split_once('+') {
        Some((r, o)) => (r, Some(o)),
        None => (s, None),
    };
    let round = r.trim().parse::<u32>().map_err(|_| format!("round `{}` is not a whole number", r.trim()))?;
    let offset = match off {
        None => 0,
        Some(o) => {
            let v: f64 = o.trim().parse().map_err(|_| format!("offset `{}` is not a number of seconds", o.trim()))?;
            if !v.is_finite() || !(0.0..=3600.0).contains(&v) {
                return Err(format!("offset `{}` must be between 0 and 3600 seconds", o.trim()));
            }
            micros(v)
        }
    };
    Ok((round, offset))
}

fn robot_at<'a>(s: &'a str, shape: &str) -> Result<(usize, &'a str), String> {
    let (r, rest) = s.split_once('@').ok_or_else(|| format!("`{s}`: expected {shape}"))?;
    let robot = r.trim().parse().map_err(|_| format!("`{s}`: robot `{}` is not a number", r.trim()))?;
    Ok((robot, rest))
}

/// `ROBOT@ROUND[+S]`: a crash.
pub fn parse_kill(s: &str) -> Result<Fault, String> {
    let (robot, when) = robot_at(s, "ROBOT@ROUND[+SECONDS], e.g. 3@5 or 3@5+0.2")?;
    let (round, offset) = parse_when(when).map_err(|e| format!("`{s}`: {e}"))?;
    Ok(Fault { robot, round, offset, kind: FaultKind::Crash })
}

/// `ROBOT@ROUND[+S][:ROUND[+S]]`: a freeze, and its thaw if given.
pub fn parse_freeze(s: &str) -> Result<Vec<Fault>, String> {
    let (robot, rest) = robot_at(s, "ROBOT@ROUND[+SECONDS][:WAKE_ROUND[+SECONDS]], e.g. 2@4:9")?;
    let (from, to) = match rest.split_once(':') {
        Some((a, b)) => (a, Some(b)),
        None => (rest, None),
    };
    let (round, offset) = parse_when(from).map_err(|e| format!("`{s}`: {e}"))?;
    let mut out = vec![Fault { robot, round, offset, kind: FaultKind::Freeze }];
    if let Some(t) = to {
        let (r2, o2) = parse_when(t).map_err(|e| format!("`{s}`: wake {e}"))?;
        if (r2, o2) <= (round, offset) {
            return Err(format!("`{s}`: the wake must come after the freeze"));
        }
        out.push(Fault { robot, round: r2, offset: o2, kind: FaultKind::Thaw });
    }
    Ok(out)
}

/// `ROBOT@ROUND[+S]:MS`: from then on, the robot reacts MS milliseconds late.
pub fn parse_slow(s: &str) -> Result<Fault, String> {
    let (robot, rest) = robot_at(s, "ROBOT@ROUND[+SECONDS]:MS, e.g. 1@0:300")?;
    let (when, ms) = rest.rsplit_once(':').ok_or_else(|| format!("`{s}`: expected ROBOT@ROUND[+SECONDS]:MS"))?;
    let (round, offset) = parse_when(when).map_err(|e| format!("`{s}`: {e}"))?;
    let ms: u64 =
        ms.trim().parse().map_err(|_| format!("`{s}`: `{}` is not a whole number of milliseconds", ms.trim()))?;
    if ms > 3_600_000 {
        return Err(format!("`{s}`: at most an hour late"));
    }
    Ok(Fault { robot, round, offset, kind: FaultKind::Slow(ms * 1000) })
}

/// `MS[:JITTER_MS]` of `--delay`.
pub fn parse_delay(s: &str) -> Result<(Time, Time), String> {
    let ms = |t: &str| -> Result<Time, String> {
        let v: f64 = t.trim().parse().map_err(|_| format!("`{}` is not a number of milliseconds", t.trim()))?;
        if !v.is_finite() || !(0.0..=60_000.0).contains(&v) {
            return Err(format!("`{}` must be between 0 and 60000 ms", t.trim()));
        }
        Ok(micros(v / 1000.0))
    };
    match s.split_once(':') {
        Some((d, j)) => Ok((ms(d)?, ms(j)?)),
        None => Ok((ms(s)?, 0)),
    }
}

fn when(round: u32, offset: Time) -> String {
    if offset == 0 {
        round.to_string()
    } else {
        format!("{round}+{}", seconds(offset))
    }
}

/// The command-line arguments that give these faults, for reproducers.
/// A thaw follows its freeze in the same argument.
pub fn to_args(faults: &[Fault]) -> Vec<String> {
    let mut out = Vec::new();
    for (k, f) in faults.iter().enumerate() {
        let at = when(f.round, f.offset);
        match f.kind {
            FaultKind::Crash => out.push(format!("--kill {}@{at}", f.robot)),
            FaultKind::Freeze => {
                let thaw = faults[k + 1..].iter().find(|g| g.robot == f.robot && g.kind == FaultKind::Thaw);
                let wake = thaw.map(|g| format!(":{}", when(g.round, g.offset))).unwrap_or_default();
                out.push(format!("--freeze {}@{at}{wake}", f.robot));
            }
            FaultKind::Thaw => {}
            FaultKind::Slow(t) => out.push(format!("--slow {}@{at}:{}", f.robot, t / 1000)),
        }
    }
    out
}

/// `k` distinct robots of `robots`, none of `taken`, crashing at rounds
/// 1..=[`RANDOM_ROUNDS`] and offsets below [`RANDOM_OFFSET_S`], drawn from
/// `seed` (the same seed, the same schedule).
pub fn kill_random(seed: u64, robots: usize, k: usize, taken: &[usize]) -> Result<Vec<Fault>, String> {
    let mut pool: Vec<usize> = (0..robots).filter(|r| !taken.contains(r)).collect();
    if k > pool.len() {
        return Err(format!("--kill-random {k}: only {} robots are left to kill", pool.len()));
    }
    let mut out = Vec::with_capacity(k);
    for i in 0..k {
        // A partial Fisher-Yates shuffle driven by the seed.
        let j = i + (derive(seed, 0x6b69_6c6c_0000 + i as u64) % (pool.len() - i) as u64) as usize;
        pool.swap(i, j);
        let round = 1 + (derive(seed, 0x726f_756e_0000 + i as u64) % RANDOM_ROUNDS as u64) as u32;
        let offset = derive(seed, 0x6f66_6673_0000 + i as u64) % micros(RANDOM_OFFSET_S);
        out.push(Fault { robot: pool[i], round, offset, kind: FaultKind::Crash });
    }
    Ok(out)
}

/// Checks a schedule against the run: robots exist, one failure (crash or
/// freeze) per robot.
pub fn check(faults: &[Fault], robots: usize) -> Result<(), String> {
    let mut failing = Vec::new();
    for f in faults {
        if f.robot >= robots {
            return Err(format!("robot {} does not exist: the run has {robots} robots (0..{robots})", f.robot));
        }
        if matches!(f.kind, FaultKind::Crash | FaultKind::Freeze) {
            if failing.contains(&f.robot) {
                return Err(format!("robot {} is given more than one failure", f.robot));
            }
            failing.push(f.robot);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faults_parse_and_print_back() {
        assert_eq!(parse_kill("3@5").unwrap(), Fault { robot: 3, round: 5, offset: 0, kind: FaultKind::Crash });
        assert_eq!(parse_kill("3@5+0.25").unwrap().offset, 250_000);
        assert!(
            parse_kill("3").is_err()
                && parse_kill("a@5").is_err()
                && parse_kill("3@x").is_err()
                && parse_kill("3@5+-1").is_err()
        );
        let fr = parse_freeze("2@4:9+0.5").unwrap();
        assert_eq!(fr.len(), 2);
        assert_eq!(fr[1], Fault { robot: 2, round: 9, offset: 500_000, kind: FaultKind::Thaw });
        assert!(parse_freeze("2@4:4").is_err() && parse_freeze("2@4+1:4+0.5").is_err());
        assert_eq!(parse_slow("1@0:300").unwrap().kind, FaultKind::Slow(300_000));
        assert!(parse_slow("1@0").is_err());
        assert_eq!(parse_delay("5:2.5").unwrap(), (5000, 2500));
        assert!(parse_delay("-1").is_err());
        let all = vec![parse_kill("3@5+0.25").unwrap(), fr[0], fr[1], parse_slow("1@2:40").unwrap()];
        let args = to_args(&all);
        assert_eq!(args, vec!["--kill 3@5+0.25", "--freeze 2@4:9+0.5", "--slow 1@2:40"]);
    }

    #[test]
    fn random_kills_are_reproducible_distinct_and_in_range() {
        let a = kill_random(9, 13, 5, &[0]).unwrap();
        assert_eq!(a, kill_random(9, 13, 5, &[0]).unwrap());
        assert_ne!(a, kill_random(10, 13, 5, &[0]).unwrap());
        let mut robots: Vec<usize> = a.iter().map(|f| f.robot).collect();
        robots.sort_unstable();
        robots.dedup();
        assert_eq!(robots.len(), 5);
        assert!(a.iter().all(|f| f.robot != 0 && (1..=RANDOM_ROUNDS).contains(&f.round) && f.offset < 1_000_000));
        assert!(kill_random(9, 13, 13, &[0]).is_err());
        assert!(check(&a, 13).is_ok());
        assert!(check(&[a[0], a[0]], 13).is_err());
        assert!(check(&a, 3).is_err() || a.iter().all(|f| f.robot < 3));
    }
}
