//! A map's per-vertex parts -- visited, known, sensed edges -- in tiles of
//! [`TILE`] vertices that copies of the map share until one of them
//! changes a tile. A robot sends a copy of its map every slot and merges
//! every neighbour's: with 10,000 robots on a map of 40,000 vertices,
//! copying and merging whole maps was most of a run. Now a copy costs a
//! pointer per tile, and a merge skips every tile the two maps share and
//! takes the other's tile whole when its own holds nothing more (or the same), so tiles
//! that stopped changing end up shared by every robot that knows them.
//!
//! The edge masks are not in the tiles. A mask is what a robot senses
//! standing on a vertex, and that is physics: every map that holds a mask
//! for `v` holds the same byte. So a tile keeps one bit a vertex, "holds a
//! mask here", and the bytes live in a [`Masks`] table shared by a group
//! of maps (every map of an in-process run, see [`SharedMasks`]; in a robot
//! process, its own maps and those it decodes), read only under the map's
//! own bit. Tiles went from
//! 40 words to 12, and merging, which compares and ORs tiles, streams a
//! third of what it did. The table is a memo, not a channel: a map's
//! content is what it would be with a table of its own. Filling an entry
//! nobody holds changes no map; a map that needs another byte where one is
//! held (maps that disagree about physics: only made up, or hostile from
//! the wire) first takes a copy of the table for itself.
//!
//! In-process, frames carry these tiles by reference; on the wire a map is
//! the same flat bitsets and bytes as ever ([`super::Map`]'s serde), and a
//! robot process builds its own tiles from them.

use std::cell::{Cell, RefCell};
use std::rc::Rc;

use crate::bitset::Bitset;

/// Vertices per tile.
pub const TILE: usize = 256;
/// Words of one tile's bitset.
const BITS: usize = TILE / 64;
const VISITED: usize = 0;
const KNOWN: usize = BITS;
/// The vertices where the map holds an edge mask (in its [`Masks`]).
const MASKED: usize = 2 * BITS;
const WORDS: usize = 3 * BITS;
/// Tiles a merge compares before it acts on any (see [`Tiles::merge_batch`]).
const BATCH: usize = 16;

/// One tile: visited bits, known bits, masked bits.
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

    /// Offsets in the tile of the vertices it holds masks for.
    fn masked(&self) -> impl Iterator<Item = usize> + '_ {
        crate::bitset::ones(&self.0[MASKED..MASKED + BITS])
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

/// Edge masks, a byte a vertex (rounded up to whole tiles), shared by the
/// maps that hold this table. An entry means something to a map only where
/// the map's masked bit is set, and then it is never 0.
pub type Masks = Vec<Cell<u8>>;

fn masks(len: usize) -> Rc<Masks> {
    Rc::new(vec![Cell::new(0); len])
}

thread_local! {
    /// The empty tile, one per thread (a run lives in one): merging it
    /// adds nothing, and most of a map is empty until late in a search.
    static EMPTY: Rc<Tile> = Rc::new(Tile::EMPTY);
    /// The table new maps of this thread take, while a [`SharedMasks`] lives.
    static SHARED: RefCell<Option<Rc<Masks>>> = const { RefCell::new(None) };
}

/// Asks the processor to start loading `tile`, which a merge will compare
/// a few tiles later: its wait for memory then overlaps the others'.
fn prefetch(tile: &Rc<Tile>) {
    let p = Rc::as_ptr(tile).cast::<u8>();
    prefetch_addr(p);
    prefetch_addr(p.wrapping_add(64));
}

/// Asks for the cache line of `tile`'s reference count.
fn prefetch_count(tile: &Rc<Tile>) {
    // The counts sit just before the value, in the same allocation.
    prefetch_addr(Rc::as_ptr(tile).cast::<u8>().wrapping_sub(2 * size_of::<usize>()));
}

/// Tiles ahead of the one cloned that [`Tiles::clone_from`] asks for.
const AHEAD: usize = 8;

fn prefetch_addr(p: *const u8) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: a prefetch is a hint: it reads nothing the program sees
        // and never faults, whatever the address. SSE is part of every
        // x86_64 target.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p.cast()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

fn empty() -> Rc<Tile> {
    EMPTY.with(Rc::clone)
}

/// While alive, every map made or decoded on this thread for a grid of
/// its size shares one table of masks, so merging two of them moves no
/// mask byte and the masks cost a byte a vertex per run instead of per
/// robot. The in-process engine holds one for a run, a robot process one
/// for its life; it changes no map's content.
pub struct SharedMasks {
    before: Option<Rc<Masks>>,
}

impl SharedMasks {
    pub fn new(vertices: usize) -> Self {
        let table = masks(vertices.div_ceil(TILE) * TILE);
        SharedMasks { before: SHARED.with(|s| s.borrow_mut().replace(table)) }
    }
}

/// The table of this thread's [`SharedMasks`], if one lives and has `len` entries.
fn shared(len: usize) -> Option<Rc<Masks>> {
    SHARED.with(|s| s.borrow().as_ref().filter(|m| m.len() == len).map(Rc::clone))
}

impl Drop for SharedMasks {
    fn drop(&mut self) {
        SHARED.with(|s| *s.borrow_mut() = self.before.take());
    }
}

/// The per-vertex parts of a map of `vertices` vertices.
#[derive(Default)]
pub struct Tiles {
    /// As `u32`, beside `total`: a map travels by value in every frame,
    /// and a frame larger than 240 bytes made each move of one (a
    /// `Transmit`) a longer copy.
    vertices: u32,
    tiles: Vec<Rc<Tile>>,
    masks: Rc<Masks>,
    /// A bit a tile: its content may have changed since the last
    /// [`Tiles::forget_changes`] (a superset: never a change unmarked). A
    /// robot's sent map carries the changes since its previous one, so a
    /// receiver that merged that one merges only these
    /// ([`Tiles::merge_changes`]).
    changed: Bitset,
    /// Per tile, its visited and known words' bytes on the wire, kept as
    /// the tile changes: every map a robot sends is counted
    /// ([`Tiles::words_wire_len`]), and summing every word of every tile
    /// each time (tiles all over memory) cost more than the few words a
    /// change touches.
    lens: Box<[u8]>,
    /// The sum of `lens`: a send reads this, not every tile's length.
    total: u32,
}

/// A tile's visited and known words' bytes on the wire (at most 8 x 10).
fn tile_len(t: &Tile) -> u8 {
    t.0[..MASKED].iter().map(|&w| crate::protocol::varint_len(w) as u8).sum()
}

impl Clone for Tiles {
    fn clone(&self) -> Self {
        Tiles {
            vertices: self.vertices,
            tiles: self.tiles.clone(),
            masks: Rc::clone(&self.masks),
            changed: self.changed.clone(),
            lens: self.lens.clone(),
            total: self.total,
        }
    }

    /// Reuses this map's list of tiles: a robot copies its map into a spare every slot.
    fn clone_from(&mut self, source: &Self) {
        self.vertices = source.vertices;
        self.masks = Rc::clone(&source.masks);
        self.changed.clone_from(&source.changed);
        self.lens.clone_from(&source.lens);
        self.total = source.total;
        if self.tiles.len() != source.tiles.len() {
            self.tiles.clone_from(&source.tiles);
            return;
        }
        // Each tile's count changes, the old one's and the new one's: ask
        // for them ahead, as a merge does.
        for i in 0..self.tiles.len() {
            if let (Some(old), Some(new)) = (self.tiles.get(i + AHEAD), source.tiles.get(i + AHEAD)) {
                prefetch_count(old);
                prefetch_count(new);
            }
            self.tiles[i].clone_from(&source.tiles[i]);
        }
    }
}

impl PartialEq for Tiles {
    fn eq(&self, other: &Self) -> bool {
        let same = Rc::ptr_eq(&self.masks, &other.masks);
        self.vertices() == other.vertices()
            && self.tiles.len() == other.tiles.len()
            && self.tiles.iter().zip(&other.tiles).enumerate().all(|(i, (a, b))| {
                Rc::ptr_eq(a, b)
                    || (a == b && (same || a.masked().all(|k| self.mask(i * TILE + k) == other.mask(i * TILE + k))))
            })
    }
}

impl Eq for Tiles {}

impl std::fmt::Debug for Tiles {
    /// The content, as the flat fields would show it: the vertices of each set.
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let n = self.tiles.len() * TILE;
        let set = |on: fn(&Tiles, usize) -> bool| (0..n).filter(|&v| on(self, v)).collect::<Vec<_>>();
        f.debug_struct("Tiles")
            .field("vertices", &self.vertices())
            .field("visited", &set(Tiles::visited))
            .field("known", &set(Tiles::known))
            .field("open", &(0..n).filter_map(|v| Some((v, self.open(v))).filter(|o| o.1 != 0)).collect::<Vec<_>>())
            .finish()
    }
}

impl Tiles {
    /// Nothing known; every tile is the empty tile all maps share.
    pub fn new(vertices: usize) -> Self {
        let n = vertices.div_ceil(TILE);
        Tiles {
            vertices: u32::try_from(vertices).expect("a map of at most 2^32 vertices"),
            tiles: vec![empty(); n],
            masks: shared(n * TILE).unwrap_or_else(|| masks(n * TILE)),
            changed: Bitset::new(n),
            lens: vec![tile_len(&Tile::EMPTY); n].into_boxed_slice(),
            total: (n * usize::from(tile_len(&Tile::EMPTY))) as u32,
        }
    }

    #[inline]
    pub fn vertices(&self) -> usize {
        self.vertices as usize
    }

    /// The tile of `v`, this map's own from now on (copied if shared).
    fn at_mut(&mut self, v: usize) -> (&mut Tile, usize) {
        self.changed.set(v / TILE);
        (Rc::make_mut(&mut self.tiles[v / TILE]), v % TILE)
    }

    /// From now on, [`Tiles::changes`] counts from here.
    pub fn forget_changes(&mut self) {
        self.changed.clear_all();
    }

    /// Tiles whose content may have changed since [`Tiles::forget_changes`].
    pub fn changes(&self) -> usize {
        self.changed.count()
    }

    /// Makes this map, a copy `source` was equal to when it last forgot its
    /// changes, equal to `source` again: only the tiles changed since are
    /// copied (a robot's last copy sent, back from the receivers).
    pub fn copy_changes_from(&mut self, source: &Tiles) {
        if self.tiles.len() != source.tiles.len() {
            return self.clone_from(source);
        }
        self.masks = Rc::clone(&source.masks);
        for i in source.changed.iter() {
            self.tiles[i].clone_from(&source.tiles[i]);
            self.set_len(i, source.lens[i]);
        }
        self.changed.clone_from(&source.changed);
    }

    /// Whether tile `tile` is marked changed.
    pub fn changed(&self, tile: usize) -> bool {
        self.changed.get(tile)
    }

    pub fn visited(&self, v: usize) -> bool {
        self.tiles.get(v / TILE).is_some_and(|t| t.bit(VISITED, v % TILE))
    }

    pub fn known(&self, v: usize) -> bool {
        self.tiles.get(v / TILE).is_some_and(|t| t.bit(KNOWN, v % TILE))
    }

    /// The table's entry for `v`, whether or not this map holds it.
    fn mask(&self, v: usize) -> u8 {
        self.masks[v].get()
    }

    pub fn open(&self, v: usize) -> u8 {
        if self.tiles[v / TILE].bit(MASKED, v % TILE) {
            self.mask(v)
        } else {
            0
        }
    }

    pub fn set_visited(&mut self, v: usize, on: bool) {
        if self.visited(v) != on {
            self.set_bit(VISITED, v, on);
        }
    }

    pub fn set_known(&mut self, v: usize, on: bool) {
        if self.known(v) != on {
            self.set_bit(KNOWN, v, on);
        }
    }

    /// Sets `v`'s bit of `part` (visited or known), and the tile's length.
    fn set_bit(&mut self, part: usize, v: usize, on: bool) {
        let (t, k) = self.at_mut(v);
        let w = part + k / 64;
        let before = crate::protocol::varint_len(t.0[w]) as u8;
        t.set_bit(part, k, on);
        let after = crate::protocol::varint_len(t.0[w]) as u8;
        let len = &mut self.lens[v / TILE];
        *len = *len + after - before;
        self.total = self.total + u32::from(after) - u32::from(before);
    }

    /// Tile `i`'s length is `len` now.
    #[inline]
    fn set_len(&mut self, i: usize, len: u8) {
        self.total = self.total + u32::from(len) - u32::from(self.lens[i]);
        self.lens[i] = len;
    }

    pub fn or_open(&mut self, v: usize, bits: u8) {
        let had = self.open(v);
        if had | bits == had {
            return;
        }
        self.changed.set(v / TILE);
        self.set_mask(v, had | bits);
        if had == 0 {
            let (t, k) = self.at_mut(v);
            t.set_bit(MASKED, k, true);
        }
    }

    /// Makes the table's entry for `v` read `byte` (not 0). An entry
    /// nobody holds is 0 and may be filled in place; one that other maps
    /// may hold is changed in a copy of the table, this map's alone.
    fn set_mask(&mut self, v: usize, byte: u8) {
        let entry = self.mask(v);
        if entry == byte {
            return;
        }
        if entry != 0 && Rc::strong_count(&self.masks) > 1 {
            self.masks = Rc::new(Masks::clone(&self.masks));
        }
        self.masks[v].set(byte);
    }

    /// `self ∪= other`, tile by tile: shared tiles are skipped, and a tile
    /// of `other` that holds all of this one's replaces it (shared from
    /// then on). Maps of different sizes merge over the common tiles.
    pub fn merge(&mut self, other: &Tiles) {
        let n = self.tiles.len().min(other.tiles.len());
        // The other map's list of tiles is cold too.
        for t in other.tiles.iter().step_by(64 / size_of::<Rc<Tile>>()) {
            prefetch_addr(std::ptr::from_ref(t).cast());
        }
        self.merge_tiles(other, 0..n);
    }

    /// [`Tiles::merge`] of the tiles `other` marks changed, for a receiver
    /// that holds everything else of `other` already: it merged the map
    /// `other`'s changes count from and has lost nothing of it since (the
    /// caller knows, [`crate::robot::Robot`]). Same content as a whole
    /// merge, looking at a few tiles instead of all.
    pub fn merge_changes(&mut self, other: &Tiles) {
        if self.tiles.len() != other.tiles.len() {
            return self.merge(other);
        }
        self.merge_tiles(other, other.changed.iter());
    }

    /// Merges the tiles `at` (ascending, all below both lengths) of `other`.
    fn merge_tiles(&mut self, other: &Tiles, at: impl Iterator<Item = usize>) {
        let empty = empty();
        let mut at = at.peekable();
        let mut todo = [0; BATCH];
        while at.peek().is_some() {
            let mut k = 0;
            while k < BATCH {
                let Some(i) = at.next() else { break };
                let theirs = &other.tiles[i];
                if !Rc::ptr_eq(&self.tiles[i], theirs) && !Rc::ptr_eq(theirs, &empty) {
                    prefetch(&self.tiles[i]);
                    prefetch(theirs);
                    todo[k] = i;
                    k += 1;
                }
            }
            self.merge_batch(other, &todo[..k]);
        }
    }

    /// Merges the tiles `todo` of `other`, which differ from this map's.
    /// Every comparison comes before any decision, so the tiles, which
    /// are all over memory, are fetched together rather than one after
    /// another (this loop was mostly waiting for them).
    fn merge_batch(&mut self, other: &Tiles, todo: &[usize]) {
        if !Rc::ptr_eq(&self.masks, &other.masks) {
            // Another table: its bytes come over one by one (a robot
            // process merging a map it decoded), and the tile's masked
            // bits with them, so the words below agree on them.
            for &i in todo {
                for k in other.tiles[i].masked() {
                    let v = i * TILE + k;
                    self.or_open(v, other.mask(v));
                }
            }
        }
        let mut diff = [(false, false); BATCH];
        for (d, &i) in diff.iter_mut().zip(todo) {
            *d = self.tiles[i].differences(&other.tiles[i]);
        }
        for (&(more, less), &i) in diff.iter().zip(todo) {
            if more {
                self.changed.set(i);
            }
            let (mine, theirs) = (&mut self.tiles[i], &other.tiles[i]);
            // Equal tiles too: shared from now on, the next merge skips them.
            if !less {
                *mine = Rc::clone(theirs);
                self.set_len(i, other.lens[i]);
            } else if more {
                let mine = Rc::make_mut(mine);
                for (a, b) in mine.0.iter_mut().zip(&theirs.0) {
                    *a |= b;
                }
                let len = tile_len(mine);
                self.set_len(i, len);
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
        self.tiles.iter().flat_map(move |t| t.0[part..part + BITS].iter().copied()).take(self.vertices().div_ceil(64))
    }

    /// The bytes postcard takes for [`Tiles::words`]' words, the visited
    /// ones and the known ones, one varint each (a map's length on the
    /// wire, without encoding it).
    /// The tiles' lengths are kept summed: the last tile's words past
    /// the map's end are zeros, a byte each, and are not sent.
    #[inline]
    pub fn words_wire_len(&self) -> usize {
        let past = self.tiles.len() * BITS - self.vertices().div_ceil(64);
        self.total as usize - 2 * past
    }

    /// The edge masks, one byte per vertex, appended to `out`: 64 vertices
    /// at a time, a word of masked bits saying whether they are all zeros,
    /// all the table's bytes, or some of each (a robot process encodes its
    /// map this way every slot).
    pub fn open_bytes_into(&self, out: &mut Vec<u8>) {
        out.reserve(self.vertices());
        for (i, tile) in self.tiles.iter().enumerate() {
            for w in 0..BITS {
                let first = i * TILE + w * 64;
                if first >= self.vertices() {
                    return;
                }
                let n = (self.vertices() - first).min(64);
                let masked = tile.0[MASKED + w];
                let table = &self.masks[first..first + n];
                if masked == 0 {
                    out.resize(out.len() + n, 0);
                } else if masked == u64::MAX {
                    out.extend(table.iter().map(Cell::get));
                } else {
                    out.extend(table.iter().enumerate().map(|(k, c)| if masked >> k & 1 == 1 { c.get() } else { 0 }));
                }
            }
        }
    }

    /// Tiles from flat bitsets and masks, reading the thread's shared
    /// table if one is installed (a robot process: then merging what it
    /// decodes moves no mask byte) and agrees, else a table of their own;
    /// `None` unless both bitsets have one word per 64 of `open`'s
    /// vertices and no bit past its end.
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
        for k in 0..t.tiles.len() {
            let mut tile = Tile::EMPTY;
            for w in 0..BITS {
                tile.0[VISITED + w] = visited.get(k * BITS + w).copied().unwrap_or(0);
                tile.0[KNOWN + w] = known.get(k * BITS + w).copied().unwrap_or(0);
                let first = k * TILE + w * 64;
                let chunk = open.get(first..(first + 64).min(vertices)).unwrap_or(&[]);
                tile.0[MASKED + w] = t.take_masks(first, chunk);
            }
            if tile != Tile::EMPTY {
                t.set_len(k, tile_len(&tile));
                t.tiles[k] = Rc::new(tile);
            }
        }
        Some(t)
    }

    /// Makes the table hold the (at most 64) bytes `chunk` of vertices
    /// `first..`, and returns the word of masked bits they give. Nearly
    /// always the table holds them already (they are physics): the loops
    /// that find out have no branch, so the compiler vectorizes them.
    fn take_masks(&mut self, first: usize, chunk: &[u8]) -> u64 {
        let masked = chunk.iter().enumerate().fold(0u64, |m, (k, &b)| m | u64::from(b != 0) << k);
        let table = &self.masks[first..first + chunk.len()];
        let differs = chunk.iter().zip(table).fold(false, |d, (&b, c)| d | ((b != 0) & (c.get() != b)));
        if differs {
            for (k, &b) in chunk.iter().enumerate().filter(|(_, &b)| b != 0) {
                self.set_mask(first + k, b);
            }
        }
        masked
    }

    /// Whether a bit is set past the last vertex (a map made in memory).
    pub fn past_end(&self) -> bool {
        let Some(last) = self.tiles.last() else {
            return false;
        };
        let first = self.vertices() - (self.tiles.len() - 1) * TILE;
        (first..TILE).any(|k| last.bit(VISITED, k) || last.bit(KNOWN, k) || last.bit(MASKED, k))
    }

    /// Tiles held by this map alone (for tests of sharing).
    pub fn unshared(&self) -> usize {
        self.tiles.iter().filter(|t| Rc::strong_count(t) == 1).count()
    }

    /// Whether two maps hold the very same tile for vertex `v`.
    pub fn shares(&self, other: &Tiles, v: usize) -> bool {
        Rc::ptr_eq(&self.tiles[v / TILE], &other.tiles[v / TILE])
    }

    /// Whether two maps read their masks from the very same table.
    pub fn shares_masks(&self, other: &Tiles) -> bool {
        Rc::ptr_eq(&self.masks, &other.masks)
    }
}
