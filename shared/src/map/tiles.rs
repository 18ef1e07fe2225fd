//! A map's per-vertex parts -- visited, known, sensed edges -- in tiles of
//! [`TILE`] vertices that copies of the map share until one of them
//! changes a tile. A robot sends a copy of its map every slot and merges
//! every neighbour's: with 10,000 robots on a map of 40,000 vertices,
//! copying and merging whole maps was most of a run. Now a copy costs a
//! pointer per tile, and a merge skips every tile the two maps share and
//! takes the other's tile whole when its own holds nothing more (or the same), so tiles
//! that stopped changing end up shared by every robot that knows them.
//!
//! In-process, frames carry these tiles by reference; on the wire a map is
//! the same flat bitsets and bytes as ever ([`super::Map`]'s serde), and a
//! robot process builds its own tiles from them.

use std::rc::Rc;

/// Vertices per tile.
pub const TILE: usize = 256;
/// Words of one tile's bitset.
const BITS: usize = TILE / 64;
/// Words of one tile's edge masks (a byte per vertex).
const BYTES: usize = TILE / 8;
const VISITED: usize = 0;
const KNOWN: usize = BITS;
const OPEN: usize = 2 * BITS;
const WORDS: usize = 2 * BITS + BYTES;

/// One tile: visited bits, known bits, then a byte of edge masks per vertex.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Tile([u64; WORDS]);

impl Tile {
    const EMPTY: Tile = Tile([0; WORDS]);

    fn bit(&self, part: usize, k: usize) -> bool {
        self.0[part + k / 64] >> (k % 64) & 1 == 1
    }

    fn set_bit(&mut self, part: usize, k: usize, on: bool) {
        let (w, b) = (&mut self.0[part + k / 64], 1u64 << (k % 64));
        *w = if on { *w | b } else { *w & !b };
    }

    fn byte(&self, k: usize) -> u8 {
        (self.0[OPEN + k / 8] >> (k % 8 * 8)) as u8
    }

    fn or_byte(&mut self, k: usize, bits: u8) {
        self.0[OPEN + k / 8] |= (bits as u64) << (k % 8 * 8);
    }

    /// Whether `other` holds something this tile lacks, and whether this
    /// tile holds something `other` lacks (one pass over both).
    fn differences(&self, other: &Tile) -> (bool, bool) {
        let (mut more, mut less) = (0, 0);
        for (a, b) in self.0.iter().zip(&other.0) {
            more |= b & !a;
            less |= a & !b;
        }
        (more != 0, less != 0)
    }
}

thread_local! {
    /// The empty tile, one per thread (a run lives in one): merging it
    /// adds nothing, and most of a map is empty until late in a search.
    static EMPTY: Rc<Tile> = Rc::new(Tile::EMPTY);
}

fn empty() -> Rc<Tile> {
    EMPTY.with(Rc::clone)
}

/// The per-vertex parts of a map of `vertices` vertices.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Tiles {
    vertices: usize,
    tiles: Vec<Rc<Tile>>,
}

impl Tiles {
    /// Nothing known; every tile is the empty tile all maps share.
    pub fn new(vertices: usize) -> Self {
        Tiles { vertices, tiles: vec![empty(); vertices.div_ceil(TILE)] }
    }

    pub fn vertices(&self) -> usize {
        self.vertices
    }

    fn at(&self, v: usize) -> (&Tile, usize) {
        (&self.tiles[v / TILE], v % TILE)
    }

    /// The tile of `v`, this map's own from now on (copied if shared).
    fn at_mut(&mut self, v: usize) -> (&mut Tile, usize) {
        (Rc::make_mut(&mut self.tiles[v / TILE]), v % TILE)
    }

    pub fn visited(&self, v: usize) -> bool {
        self.tiles.get(v / TILE).is_some_and(|t| t.bit(VISITED, v % TILE))
    }

    pub fn known(&self, v: usize) -> bool {
        self.tiles.get(v / TILE).is_some_and(|t| t.bit(KNOWN, v % TILE))
    }

    pub fn open(&self, v: usize) -> u8 {
        let (t, k) = self.at(v);
        t.byte(k)
    }

    pub fn set_visited(&mut self, v: usize, on: bool) {
        if self.visited(v) != on {
            let (t, k) = self.at_mut(v);
            t.set_bit(VISITED, k, on);
        }
    }

    pub fn set_known(&mut self, v: usize, on: bool) {
        if self.known(v) != on {
            let (t, k) = self.at_mut(v);
            t.set_bit(KNOWN, k, on);
        }
    }

    pub fn or_open(&mut self, v: usize, bits: u8) {
        if self.open(v) | bits != self.open(v) {
            let (t, k) = self.at_mut(v);
            t.or_byte(k, bits);
        }
    }

    /// `self ∪= other`, tile by tile: shared tiles are skipped, and a tile
    /// of `other` that holds all of this one's replaces it (shared from
    /// then on). Maps of different sizes merge over the common tiles.
    pub fn merge(&mut self, other: &Tiles) {
        let empty = empty();
        for (mine, theirs) in self.tiles.iter_mut().zip(&other.tiles) {
            if Rc::ptr_eq(mine, theirs) || Rc::ptr_eq(theirs, &empty) {
                continue;
            }
            let (more, less) = mine.differences(theirs);
            // Equal tiles too: shared from now on, the next merge skips them.
            if !less {
                *mine = Rc::clone(theirs);
                continue;
            }
            if !more {
                continue;
            }
            let m = Rc::make_mut(mine);
            for (a, b) in m.0.iter_mut().zip(&theirs.0) {
                *a |= b;
            }
        }
    }

    /// Whether some known vertex is not visited.
    pub fn any_known_unvisited(&self) -> bool {
        self.tiles.iter().any(|t| (0..BITS).any(|w| t.0[KNOWN + w] & !t.0[VISITED + w] != 0))
    }

    /// The visited (or known) bitset's words, `vertices.div_ceil(64)` of them.
    pub fn words(&self, known: bool) -> impl Iterator<Item = u64> + '_ {
        let part = if known { KNOWN } else { VISITED };
        self.tiles.iter().flat_map(move |t| t.0[part..part + BITS].iter().copied()).take(self.vertices.div_ceil(64))
    }

    /// The edge masks, one byte per vertex.
    pub fn open_bytes(&self) -> impl Iterator<Item = u8> + '_ {
        (0..self.vertices).map(|v| self.open(v))
    }

    /// Tiles from flat bitsets and masks; `None` unless both bitsets have
    /// one word per 64 of `open`'s vertices and no bit past its end.
    pub fn from_flat(visited: &[u64], known: &[u64], open: &[u8]) -> Option<Self> {
        let vertices = open.len();
        let words = vertices.div_ceil(64);
        if visited.len() != words || known.len() != words {
            return None;
        }
        let past = |w: &[u64]| vertices % 64 != 0 && w.last().is_some_and(|&x| x >> (vertices % 64) != 0);
        if past(visited) || past(known) {
            return None;
        }
        let mut t = Tiles::new(vertices);
        for (k, slot) in t.tiles.iter_mut().enumerate() {
            let mut tile = Tile::EMPTY;
            for w in 0..BITS {
                tile.0[VISITED + w] = visited.get(k * BITS + w).copied().unwrap_or(0);
                tile.0[KNOWN + w] = known.get(k * BITS + w).copied().unwrap_or(0);
            }
            for (i, &b) in open.iter().skip(k * TILE).take(TILE).enumerate() {
                tile.or_byte(i, b);
            }
            if tile != Tile::EMPTY {
                *slot = Rc::new(tile);
            }
        }
        Some(t)
    }

    /// Whether a bit is set past the last vertex (a map made in memory).
    pub fn past_end(&self) -> bool {
        let Some(last) = self.tiles.last() else {
            return false;
        };
        let first = self.vertices - (self.tiles.len() - 1) * TILE;
        (first..TILE).any(|k| last.bit(VISITED, k) || last.bit(KNOWN, k) || last.byte(k) != 0)
    }

    /// Tiles held by this map alone (for tests of sharing).
    pub fn unshared(&self) -> usize {
        self.tiles.iter().filter(|t| Rc::strong_count(t) == 1).count()
    }

    /// Whether two maps hold the very same tile for vertex `v`.
    pub fn shares(&self, other: &Tiles, v: usize) -> bool {
        Rc::ptr_eq(&self.tiles[v / TILE], &other.tiles[v / TILE])
    }
}
