//! Robot-count lists on the command line: `1-13`, `5`, or `1,3,5` (and
//! mixtures such as `1-3,8`).

use std::fmt::Write as _;
use std::str::FromStr;

/// Sorted, distinct robot counts, each at least 1.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RobotCounts(pub Vec<usize>);

/// The radio's id space ([`gridswarm::scenario::limits::MAX_ROBOTS`]):
/// whether a map has room for that many is the scenario's to say, when
/// robots are placed (an error naming how many vertices it has).
pub const MAX_ROBOTS: usize = gridswarm::scenario::limits::MAX_ROBOTS;
/// Counts one list may name, so that a typo such as `1-13000` fails at
/// once instead of after hours.
pub const MAX_COUNTS: usize = 1000;

impl FromStr for RobotCounts {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        counts(s, "robot counts", 1).map(RobotCounts)
    }
}

/// A list of counts (`1-3,8`), sorted and distinct, each in
/// `least..=MAX_ROBOTS`, at most [`MAX_COUNTS`] of them. Errors start with
/// `bad <what>`.
pub fn counts(s: &str, what: &str, least: usize) -> Result<Vec<usize>, String> {
    let count = |text: &str| -> Result<usize, String> {
        let n: usize =
            text.trim().parse().map_err(|_| format!("bad {what} `{s}`: `{}` is not a whole number", text.trim()))?;
        if n < least {
            return Err(format!("bad {what} `{s}`: at least {least} is needed"));
        }
        if n > MAX_ROBOTS {
            return Err(format!("bad {what} `{s}`: at most {MAX_ROBOTS} robots"));
        }
        Ok(n)
    };
    let mut out = Vec::new();
    for part in s.split(',') {
        let part = part.trim();
        if part.is_empty() {
            return Err(format!("bad {what} `{s}`: empty item"));
        }
        let (lo, hi) = match part.split_once('-') {
            Some((a, b)) => (count(a)?, count(b)?),
            None => (count(part)?, count(part)?),
        };
        if lo > hi {
            return Err(format!("bad {what} range `{part}`: {lo} is greater than {hi}"));
        }
        if hi - lo >= MAX_COUNTS || out.len() + (hi - lo + 1) > MAX_COUNTS {
            return Err(format!("bad {what} `{s}`: more than {MAX_COUNTS} counts"));
        }
        out.extend(lo..=hi);
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// Sorted counts in the command line's own form: `[1, 2, 3, 5]` -> `1-3,5`.
pub fn compress(counts: &[usize]) -> String {
    let mut out = String::new();
    let mut k = 0;
    while k < counts.len() {
        let mut e = k;
        while e + 1 < counts.len() && counts[e + 1] == counts[e] + 1 {
            e += 1;
        }
        if !out.is_empty() {
            out.push(',');
        }
        if e > k {
            let _ = write!(out, "{}-{}", counts[k], counts[e]);
        } else {
            let _ = write!(out, "{}", counts[k]);
        }
        k = e + 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> Result<Vec<usize>, String> {
        s.parse::<RobotCounts>().map(|r| r.0)
    }

    #[test]
    fn forms() {
        assert_eq!(p("1-13").unwrap(), (1..=13).collect::<Vec<_>>());
        assert_eq!(p("5").unwrap(), vec![5]);
        assert_eq!(p("5,1,3").unwrap(), vec![1, 3, 5]);
        assert_eq!(p("1-3,2,8").unwrap(), vec![1, 2, 3, 8]);
        assert_eq!(p(" 2 - 4 ").unwrap(), vec![2, 3, 4]);
    }

    #[test]
    fn compress_round_trips() {
        assert_eq!(compress(&[1, 2, 3, 5, 7, 8]), "1-3,5,7-8");
        assert_eq!(compress(&[4]), "4");
        assert_eq!(p(&compress(&[1, 2, 3, 5, 7, 8])).unwrap(), vec![1, 2, 3, 5, 7, 8]);
    }

    #[test]
    fn rejects() {
        for bad in ["0", "5-2", "", "1,", "a", "1-", "-3", "0-4", "1-100000", "1-2000", "2.5"] {
            assert!(p(bad).is_err(), "{bad:?} accepted");
        }
        assert!(p("5-2").unwrap_err().contains("5 is greater than 2"));
        assert!(p("65536").unwrap_err().contains("at most 65535 robots"));
    }

    #[test]
    fn big_teams_are_the_map_s_to_refuse() {
        assert_eq!(p("10000").unwrap(), vec![10000]);
        assert_eq!(counts("0-2", "killed", 0).unwrap(), vec![0, 1, 2]);
        assert!(counts("0-2", "killed", 1).unwrap_err().starts_with("bad killed"));
    }
}
