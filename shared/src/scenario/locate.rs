//! Where things are in a scenario file: field paths such as
//! `obstacles[1].circle.radius` to byte spans and back, and byte offsets to
//! `line:col`. Errors must name the field and the line, but toml's own errors
//! only carry a span, and semantic checks run on plain values with no span at
//! all; one spanned tree of the document serves both directions.

use std::ops::Range;

use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use toml::Spanned;

/// The shape of a TOML document with the span of every key and value.
#[derive(Debug)]
pub(crate) enum Node {
    Table(Vec<(Spanned<String>, Spanned<Node>)>),
    Array(Vec<Spanned<Node>>),
    Scalar,
}

impl<'de> Deserialize<'de> for Node {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Node;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("any TOML value")
            }
            fn visit_bool<E>(self, _: bool) -> Result<Node, E> {
                Ok(Node::Scalar)
            }
            fn visit_i64<E>(self, _: i64) -> Result<Node, E> {
                Ok(Node::Scalar)
            }
            fn visit_u64<E>(self, _: u64) -> Result<Node, E> {
                Ok(Node::Scalar)
            }
            fn visit_f64<E>(self, _: f64) -> Result<Node, E> {
                Ok(Node::Scalar)
            }
            fn visit_str<E>(self, _: &str) -> Result<Node, E> {
                Ok(Node::Scalar)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> Result<Node, A::Error> {
                let mut items = Vec::new();
                while let Some(x) = a.next_element()? {
                    items.push(x);
                }
                Ok(Node::Array(items))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut a: A) -> Result<Node, A::Error> {
                let mut entries = Vec::new();
                loop {
                    // toml hands a datetime over as a private one-key map whose
                    // key cannot be spanned; a datetime is a leaf for our purpose.
                    let key = match a.next_key::<Spanned<String>>() {
                        Ok(Some(k)) => k,
                        Ok(None) => break,
                        Err(_) => return Ok(Node::Scalar),
                    };
                    entries.push((key, a.next_value()?));
                }
                Ok(Node::Table(entries))
            }
        }
        d.deserialize_any(V)
    }
}

fn contains(span: &Range<usize>, at: usize) -> bool {
    span.start <= at && at < span.end.max(span.start + 1)
}

impl Node {
    /// The dotted path of the innermost key or value at byte `at`, if any.
    pub(crate) fn path_at(&self, at: usize) -> Option<String> {
        let mut path = String::new();
        let mut node = self;
        loop {
            let next = match node {
                Node::Table(entries) => entries.iter().find_map(|(k, v)| {
                    if contains(&k.span(), at) {
                        push_key(&mut path, k.get_ref());
                        Some(None)
                    } else if contains(&v.span(), at) {
                        push_key(&mut path, k.get_ref());
                        Some(Some(v.get_ref()))
                    } else {
                        None
                    }
                }),
                Node::Array(items) => items.iter().enumerate().find(|(_, v)| contains(&v.span(), at)).map(|(i, v)| {
                    path.push_str(&format!("[{i}]"));
                    Some(v.get_ref())
                }),
                Node::Scalar => None,
            };
            match next {
                Some(Some(child)) => node = child,
                _ => break,
            }
        }
        (!path.is_empty()).then_some(path)
    }

    /// The path of the value whose span is exactly `span` (`Some("")` for
    /// the whole document): toml reports a missing field at its table.
    pub(crate) fn path_with_span(&self, span: &Range<usize>) -> Option<String> {
        let mut path = String::new();
        let mut node = self;
        loop {
            let next = match node {
                Node::Table(entries) => entries
                    .iter()
                    .find(|(_, v)| contains(&v.span(), span.start) && v.span().end >= span.end)
                    .map(|(k, v)| {
                        push_key(&mut path, k.get_ref());
                        v
                    }),
                Node::Array(items) => items
                    .iter()
                    .enumerate()
                    .find(|(_, v)| contains(&v.span(), span.start) && v.span().end >= span.end)
                    .map(|(i, v)| {
                        path.push_str(&format!("[{i}]"));
                        v
                    }),
                Node::Scalar => None,
            };
            match next {
                Some(v) if v.span() == *span => return Some(path),
                Some(v) => node = v.get_ref(),
                None => return path.is_empty().then_some(path),
            }
        }
    }

    /// The span of the value at `path` (`a.b[2].c`), or of the deepest part
    /// of it that exists, so that an error about a defaulted field still
    /// points at its table.
    pub(crate) fn span_of(&self, path: &str) -> Option<Range<usize>> {
        let mut node = self;
        let mut best = None;
        for seg in segments(path) {
            let child = match (node, seg) {
                (Node::Table(entries), Seg::Key(key)) => {
                    entries.iter().find(|(k, _)| k.get_ref() == key).map(|(_, v)| v)
                }
                (Node::Array(items), Seg::Index(i)) => items.get(i),
                _ => None,
            };
            match child {
                Some(c) => {
                    best = Some(c.span());
                    node = c.get_ref();
                }
                None => break,
            }
        }
        best
    }
}

fn push_key(path: &mut String, key: &str) {
    if !path.is_empty() {
        path.push('.');
    }
    path.push_str(key);
}

enum Seg<'a> {
    Key(&'a str),
    Index(usize),
}

fn segments(path: &str) -> Vec<Seg<'_>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, rest) = part.split_once('[').map_or((part, ""), |(k, r)| (k, r));
        if !key.is_empty() {
            out.push(Seg::Key(key));
        }
        for idx in rest.split('[') {
            if let Ok(i) = idx.trim_end_matches(']').parse() {
                out.push(Seg::Index(i));
            }
        }
    }
    out
}

/// 1-based line and column (in characters) of byte offset `at`.
pub(crate) fn line_col(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let before = &text[..floor_char_boundary(text, at)];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

fn floor_char_boundary(text: &str, mut at: usize) -> usize {
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = "name = 'x'\n[[obstacles]]\npolygon = [[1, 2], [3, 4]]\n[[obstacles]]\ncircle = { center = [1, 2], radius = -1 }\n";

    #[test]
    fn paths_and_spans_round_trip() {
        let tree: Node = toml::from_str(DOC).unwrap();
        let span = tree.span_of("obstacles[1].circle.radius").unwrap();
        assert_eq!(&DOC[span.clone()], "-1");
        assert_eq!(tree.path_at(span.start).as_deref(), Some("obstacles[1].circle.radius"));
        let span = tree.span_of("obstacles[0].polygon[1]").unwrap();
        assert_eq!(&DOC[span.clone()], "[3, 4]");
        assert_eq!(line_col(DOC, span.start), (3, 20));
        // A missing leaf falls back to its table.
        let span = tree.span_of("obstacles[1].circle.nothing").unwrap();
        assert!(DOC[span].starts_with("{ center"));
    }
}
