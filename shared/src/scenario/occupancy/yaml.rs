//! The map_server YAML file: a flat list of `key: value` lines naming the
//! image and how to read it. Only the part of YAML that map_server files
//! use is read (comments, plain and quoted scalars, a flow list `[x, y, 0]`
//! or a block list of `- x` lines, `---`); anything else is an error that
//! says so, with its line. A full YAML parser was measured against this
//! (docs/scenario-format.md, "Occupancy-grid maps").

use std::collections::BTreeMap;

/// How the image's shades become occupancy (map_server's `mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Above `occupied_thresh` occupied, below `free_thresh` free, else unknown.
    Trinary,
    /// As trinary, but a pixel not fully opaque is unknown and alpha is not
    /// averaged in; shades between the thresholds are unknown here.
    Scale,
    /// The shade times 255 is the occupancy in percent (above 100: unknown).
    Raw,
}

/// What the YAML file says, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Meta {
    pub image: String,
    /// Metres per pixel.
    pub resolution: f64,
    /// The lower-left pixel's corner (x, y); yaw must be 0.
    pub origin: (f64, f64),
    pub negate: bool,
    pub occupied_thresh: f64,
    pub free_thresh: f64,
    pub mode: Mode,
}

/// A value as written, and its 1-based line.
#[derive(Clone, Debug)]
enum Value {
    Scalar(String),
    List(Vec<String>),
}

/// `(field, message, line)` of the first thing wrong.
pub type Fault = (String, String, Option<usize>);

fn fault(field: &str, message: impl Into<String>, line: Option<usize>) -> Fault {
    (field.to_string(), message.into(), line)
}

/// The scalar without its quotes (YAML's `'it''s'` and `"a\"b"` escapes).
fn unquote(s: &str) -> Result<String, String> {
    let s = s.trim();
    if let Some(inner) = s.strip_prefix('\'') {
        let inner = inner.strip_suffix('\'').ok_or("an unterminated 'quoted' string")?;
        return Ok(inner.replace("''", "'"));
    }
    if let Some(inner) = s.strip_prefix('"') {
        let inner = inner.strip_suffix('"').ok_or("an unterminated \"quoted\" string")?;
        return Ok(inner.replace("\\\"", "\"").replace("\\\\", "\\"));
    }
    Ok(s.to_string())
}

/// The line without a trailing comment (a `#` after a space, outside quotes).
fn strip_comment(line: &str) -> &str {
    let mut quote = None;
    let mut prev = ' ';
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), _) if c == q => quote = None,
            (None, '#') if prev.is_whitespace() => return &line[..i],
            _ => {}
        }
        prev = c;
    }
    line
}

fn flow_list(s: &str) -> Result<Vec<String>, String> {
    let inner =
        s.strip_prefix('[').and_then(|s| s.strip_suffix(']')).ok_or("a list must be [a, b, ...] on one line")?;
    if inner.trim().is_empty() {
        return Ok(Vec::new());
    }
    inner.split(',').map(unquote).collect()
}

/// The top-level keys and their values, each with its line.
fn entries(text: &str) -> Result<BTreeMap<String, (Value, usize)>, Fault> {
    let mut out: BTreeMap<String, (Value, usize)> = BTreeMap::new();
    let mut open: Option<String> = None;
    for (k, raw) in text.lines().enumerate() {
        let n = k + 1;
        let line = strip_comment(raw).trim_end();
        if line.trim().is_empty() || line == "---" || line == "..." {
            continue;
        }
        if let Some(item) = line.trim_start().strip_prefix("- ").or_else(|| (line.trim() == "-").then_some("")) {
            let Some(key) = &open else {
                return Err(fault("", "a list item `- ...` that follows no `key:`", Some(n)));
            };
            let item = unquote(item).map_err(|m| fault(key, m, Some(n)))?;
            if let Some((Value::List(items), _)) = out.get_mut(key) {
                items.push(item);
            }
            continue;
        }
        if line.starts_with(char::is_whitespace) {
            return Err(fault("", "an indented line; a map file is a flat list of `key: value` lines", Some(n)));
        }
        let Some((key, value)) = line.split_once(':') else {
            return Err(fault("", format!("`{}` is not a `key: value` line", line.trim()), Some(n)));
        };
        let key = unquote(key).map_err(|m| fault("", m, Some(n)))?;
        let value = value.trim();
        if out.contains_key(&key) {
            return Err(fault(&key, "given twice", Some(n)));
        }
        open = None;
        let v = if value.is_empty() {
            open = Some(key.clone());
            Value::List(Vec::new())
        } else if value.starts_with('[') {
            Value::List(flow_list(value).map_err(|m| fault(&key, m, Some(n)))?)
        } else if value.starts_with('{') || value.starts_with('&') || value.starts_with('*') || value.starts_with('|') {
            return Err(fault(&key, "maps, anchors and block strings are not read in a map file", Some(n)));
        } else {
            Value::Scalar(unquote(value).map_err(|m| fault(&key, m, Some(n)))?)
        };
        out.insert(key, (v, n));
    }
    Ok(out)
}

struct Doc(BTreeMap<String, (Value, usize)>);

impl Doc {
    fn line(&self, key: &str) -> Option<usize> {
        self.0.get(key).map(|(_, n)| *n)
    }

    fn scalar(&self, key: &str) -> Result<Option<(&str, usize)>, Fault> {
        match self.0.get(key) {
            None => Ok(None),
            Some((Value::Scalar(s), n)) => Ok(Some((s, *n))),
            Some((Value::List(_), n)) => Err(fault(key, "must be a single value, not a list", Some(*n))),
        }
    }

    fn required(&self, key: &str) -> Result<(&str, usize), Fault> {
        self.scalar(key)?.ok_or_else(|| fault(key, "missing (map_server requires it)", None))
    }

    fn number(&self, key: &str) -> Result<f64, Fault> {
        let (s, n) = self.required(key)?;
        number(s).ok_or_else(|| fault(key, format!("must be a number, got `{s}`"), Some(n)))
    }
}

fn number(s: &str) -> Option<f64> {
    let v: f64 = s.trim().parse().ok()?;
    v.is_finite().then_some(v)
}

/// Reads a map_server YAML file's text.
pub fn parse(text: &str) -> Result<Meta, Fault> {
    let doc = Doc(entries(text)?);
    let (image, _) = doc.required("image")?;
    if image.trim().is_empty() {
        return Err(fault("image", "is empty", doc.line("image")));
    }
    let resolution = doc.number("resolution")?;
    if !(resolution > 0.0) {
        return Err(fault(
            "resolution",
            format!("must be > 0 (metres per pixel), got {resolution}"),
            doc.line("resolution"),
        ));
    }
    let origin = origin(&doc)?;
    let occupied_thresh = doc.number("occupied_thresh")?;
    let free_thresh = doc.number("free_thresh")?;
    for (key, v) in [("occupied_thresh", occupied_thresh), ("free_thresh", free_thresh)] {
        if !(0.0..=1.0).contains(&v) {
            return Err(fault(key, format!("must be from 0 to 1, got {v}"), doc.line(key)));
        }
    }
    if free_thresh >= occupied_thresh {
        let m = format!("must be below occupied_thresh = {occupied_thresh}, got {free_thresh}");
        return Err(fault("free_thresh", m, doc.line("free_thresh")));
    }
    let (neg, n) = doc.required("negate")?;
    let negate = match neg.trim() {
        "0" | "false" | "False" | "FALSE" => false,
        "1" | "true" | "True" | "TRUE" => true,
        other => return Err(fault("negate", format!("must be 0 or 1 (or false, true), got `{other}`"), Some(n))),
    };
    let mode = match doc.scalar("mode")? {
        None => Mode::Trinary,
        Some((m, n)) => match m.trim() {
            "trinary" => Mode::Trinary,
            "scale" => Mode::Scale,
            "raw" => Mode::Raw,
            other => return Err(fault("mode", format!("must be trinary, scale or raw, got `{other}`"), Some(n))),
        },
    };
    Ok(Meta { image: image.to_string(), resolution, origin, negate, occupied_thresh, free_thresh, mode })
}

fn origin(doc: &Doc) -> Result<(f64, f64), Fault> {
    let Some((value, n)) = doc.0.get("origin") else {
        return Err(fault("origin", "missing (map_server requires it)", None));
    };
    let Value::List(items) = value else {
        return Err(fault("origin", "must be a list [x, y, yaw]", Some(*n)));
    };
    if items.len() != 3 {
        return Err(fault("origin", format!("must have 3 elements [x, y, yaw], got {}", items.len()), Some(*n)));
    }
    let mut v = [0.0; 3];
    for (k, s) in items.iter().enumerate() {
        v[k] = number(s)
            .ok_or_else(|| fault(&format!("origin[{k}]"), format!("must be a number, got `{s}`"), Some(*n)))?;
    }
    if v[2] != 0.0 {
        let m = format!("yaw {} is not read: only maps with yaw 0 are (a turned map would need turned walls)", v[2]);
        return Err(fault("origin[2]", m, Some(*n)));
    }
    Ok((v[0], v[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAVED: &str = "image: map.pgm\nmode: trinary\nresolution: 0.05\norigin: [-10, -10.5, 0]\nnegate: 0\n\
                         occupied_thresh: 0.65\nfree_thresh: 0.25\n";

    #[test]
    fn map_saver_output_and_block_lists_read_alike() {
        let m = parse(SAVED).unwrap();
        assert_eq!((m.image.as_str(), m.resolution, m.origin), ("map.pgm", 0.05, (-10.0, -10.5)));
        assert_eq!((m.negate, m.mode, m.free_thresh), (false, Mode::Trinary, 0.25));
        let block =
            "# a comment\n---\nimage: \"map.pgm\"  # here\nresolution: 0.05\norigin:\n  - -10\n  - -10.5\n  - 0.0\n\
                     negate: false\noccupied_thresh: 0.65\nfree_thresh: 0.25\n";
        assert_eq!(parse(block).unwrap(), m);
    }

    #[test]
    fn bad_fields_are_named_with_their_line() {
        let cases = [
            ("resolution: 0.05", "resolution: fast", "resolution", "must be a number, got `fast`", Some(3)),
            ("origin: [-10, -10.5, 0]", "origin: [1, 2]", "origin", "must have 3 elements", Some(4)),
            ("origin: [-10, -10.5, 0]", "origin: [1, 2, 0.5]", "origin[2]", "yaw 0.5 is not read", Some(4)),
            ("negate: 0", "negate: maybe", "negate", "must be 0 or 1", Some(5)),
            ("free_thresh: 0.25", "free_thresh: 0.7", "free_thresh", "below occupied_thresh", Some(7)),
            ("mode: trinary", "mode: fancy", "mode", "trinary, scale or raw", Some(2)),
            ("image: map.pgm", "image: ''", "image", "is empty", Some(1)),
            ("resolution: 0.05\n", "", "resolution", "missing", None),
            ("negate: 0", "negate: 0\nnegate: 1", "negate", "given twice", Some(6)),
            ("mode: trinary", "  mode: trinary", "", "an indented line", Some(2)),
            ("resolution: 0.05", "resolution: -1", "resolution", "must be > 0", Some(3)),
            ("resolution: 0.05", "resolution: inf", "resolution", "must be a number", Some(3)),
        ];
        for (from, to, field, message, line) in cases {
            let text = SAVED.replace(from, to);
            let (f, m, n) = parse(&text).unwrap_err();
            assert_eq!((f.as_str(), n), (field, line), "{to}: {m}");
            assert!(m.contains(message), "{to}: {m}");
        }
    }
}
