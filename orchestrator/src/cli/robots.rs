//! Robot-count lists on the command line: `1-13`, `5`, or `1,3,5` (and
//! mixtures such as `1-3,8`).

use std::fmt::Write as _;
use std::str::FromStr;

/// Sorted, distinct robot counts, each at least 1.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RobotCounts(pub Vec<usize>);

/// Large enough for any scenario the project ships, small enough that a typo
/// such as `1-1300` fails at once instead of after hours.
pub const MAX_ROBOTS: usize = 1000;

impl FromStr for RobotCounts {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let mut out = Vec::new();
        for part in s.split(',') {
            let part = part.trim();
            if part.is_empty() {
                return Err(format!("bad robot counts `{s}`: empty item"));
            }
            let (lo, hi) = match part.split_once('-') {
                Some((a, b)) => (count(a, s)?, count(b, s)?),
                None => {
                    let n = count(part, s)?;
                    (n, n)
                }
            };
            if lo > hi {
                return Err(format!("bad robot range `{part}`: {lo} is greater than {hi}"));
            }
            out.extend(lo..=hi);
        }
        out.sort_unstable();
        out.dedup();
        Ok(RobotCounts(out))
    }
}

fn count(text: &str, whole: &str) -> Result<usize, String> {
    let n: usize = text
        .trim()
        .parse()
        .map_err(|_| format!("bad robot counts `{whole}`: `{}` is not a whole number", text.trim()))?;
    if n == 0 {
        return Err(format!("bad robot counts `{whole}`: at least 1 robot is needed"));
    }
    if n > MAX_ROBOTS {
        return Err(format!("bad robot counts `{whole}`: at most {MAX_ROBOTS} robots"));
    }
    Ok(n)
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
        for bad in ["0", "5-2", "", "1,", "a", "1-", "-3", "0-4", "1-100000", "2.5"] {
            assert!(p(bad).is_err(), "{bad:?} accepted");
        }
        assert!(p("5-2").unwrap_err().contains("5 is greater than 2"));
    }
}
