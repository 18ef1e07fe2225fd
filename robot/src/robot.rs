//! The decision core: one robot's side of a round (docs/paper.md "One round"),
//! as a state machine with no I/O and no clock. The robot's radio protocol
//! ([`crate::peer`]) drives it the same way in both engines:
//!
//! 1. [`Robot::sense`] with what the robot's own sensors report (steps 1-2);
//! 2. [`Robot::receive_map`] for each map heard (step 3): the sender becomes
//!    a communication neighbour for this round; [`Robot::stop_rule`] is the
//!    stop test (rules 3/4) once the exchange is over;
//! 3. [`Robot::receive_choice`] for each announced choice; [`Robot::suspect`]
//!    for a neighbour that did not choose in time, [`Robot::declare_failed`]
//!    for one that will never answer; once [`Robot::ready`], [`Robot::choose`]
//!    decides (steps 4-5);
//! 4. [`Robot::moved`] once the robot knows where it stands (step 6).
//!
//! A decision depends only on the set of inputs received, never on their
//! arrival order: maps merge by union, choices wait for every higher-priority
//! neighbour, and the repulsion centre is summed in exact lattice coordinates.

use rand_chacha::ChaCha8Rng;

use crate::choice::paths::Paths;
use crate::choice::{self, ChoiceRule, NeighbourView, View};
use crate::geometry::swept_min_distance;
use crate::grid::{Grid, VertexId, NONE};
use crate::lattice::MAX_DEGREE;
use crate::map::sightings::Sighting;
use crate::map::{Map, RobotId, SENSED};
use crate::params::{Order, Situation, VisitedChoice};
use crate::policy::Policy;
use crate::rng::robot_rng;
use crate::spot::Spot;
use crate::trail::Trail;

/// What a robot needs to know about itself and the run.
#[derive(Clone, Copy, Debug)]
pub struct RobotConfig {
    pub id: RobotId,
    pub policy: Policy,
    pub situation: Situation,
    /// `|T|` in situation 1; 0 in situation 2, where nobody knows it.
    pub targets_total: usize,
    pub r_safe: f64,
    pub seed: u64,
    /// Reading "choices update maps" (docs/paper.md): a received choice marks
    /// its vertex visited in the receiver's map at once.
    pub choices_update_maps: bool,
    /// Reading "survivors" ([`crate::params::Params::survivor_step`]):
    /// whether, failures known, the core may step a robot towards the
    /// nearest unvisited vertex instead of its rule's choice.
    pub survivor_step: bool,
    /// Step 4's order ([`Order`]): the paper's, or a local one.
    pub order: Order,
    /// Rule (2) over visited candidates ([`VisitedChoice`]).
    pub visited_choice: VisitedChoice,
    /// Robots in the team, this one included (0: not known). A robot
    /// knows its team's roster before the start, as it knows its own id.
    pub team: usize,
}

impl RobotConfig {
    /// A robot of `policy` with the default readings.
    pub fn new(
        id: RobotId,
        policy: Policy,
        situation: Situation,
        targets_total: usize,
        r_safe: f64,
        seed: u64,
    ) -> Self {
        RobotConfig {
            id,
            policy,
            situation,
            targets_total,
            r_safe,
            seed,
            choices_update_maps: true,
            survivor_step: true,
            order: Order::Paper,
            visited_choice: VisitedChoice::Farthest,
            team: 0,
        }
    }
}

/// One round's readings from the robot's own sensors.
#[derive(Clone, Copy, Debug)]
pub struct Sensing<'a> {
    /// Adjacency slots whose edge is free of obstacles and boundary (sonar).
    pub open: u8,
    /// Adjacency slots whose vertex holds another robot (sonar).
    pub occupied: u8,
    /// Targets within `r_st`, each where it is (laser).
    pub targets: &'a [Spot],
}

/// Why a robot stops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Rule (3): every target is known.
    AllTargets,
    /// Rule (4): the map has no unvisited accessible vertex. In situation 1
    /// this also ends the search (nothing is left to find), incomplete.
    MapComplete,
    /// Every unvisited vertex the robot knows lies behind failed robots: it
    /// stops on its own, but its knowledge does not end the search for others.
    CutOff,
}

impl Stop {
    /// Whether what the robot knows leaves nothing undetected anywhere, so
    /// its stop may end the search for everyone (step 8).
    pub fn ends_search(self) -> bool {
        self != Stop::CutOff
    }

    /// Whether the robot ends the search knowing it incomplete: in
    /// situation 1 nothing is left to visit, yet targets are unfound.
    pub fn exhausted(self, situation: Situation) -> bool {
        self == Stop::MapComplete && situation == Situation::One
    }
}

#[derive(Clone, Copy, Debug)]
struct Neighbour {
    id: RobotId,
    at: VertexId,
    key: (i64, i64),
    /// Its map of this round arrived.
    map_in: bool,
    choice: Option<VertexId>,
    /// It did not choose in time this round: not waited for any more, and
    /// treated as standing still. (A robot heard this round is alive,
    /// whatever failure others declared of it.)
    suspected: bool,
    /// It stopped searching: it stands still and chooses nothing.
    halted: bool,
}

pub struct Robot<'g> {
    grid: &'g Grid,
    cfg: RobotConfig,
    rng: ChaCha8Rng,
    pos: VertexId,
    round: u32,
    map: Map,
    nbrs: Vec<Neighbour>,
    open_now: u8,
    occupied_now: u8,
    next: Option<VertexId>,
    /// Neighbours whose announced choices the last choice avoided.
    accounted: Vec<RobotId>,
    /// Neighbours whose maps say they halted cut off, and where they stand.
    /// They block moves, not the cut-off test: each would search again
    /// once it is no longer cut off itself, and counting them made robots
    /// halted next to each other cut each other off for good.
    parked: Vec<(RobotId, VertexId)>,
    /// The policy's choice rule (step 5).
    rule: Box<dyn ChoiceRule>,
    /// For the stop rule's reachability test.
    paths: Paths,
    /// Vertices this round's choices heard marked visited, and nothing
    /// else did ([`Robot::receive_choice`]).
    /// With whether the claim made the vertex known too.
    claims: Vec<(VertexId, bool)>,
    /// Per robot whose map this one merged (sorted by robot), the round of
    /// the latest: this map holds all of that map, so the sender's next
    /// map needs merging only where it changed since ([`Map::merge_changes`]).
    /// Forgotten when the map may have lost some of it (below), and after
    /// a round unheard: a sender's next copy counts from its last, so only
    /// last round's are of use (and the list stays as short as the
    /// neighbourhood in a long run).
    merged: Vec<(RobotId, u32)>,
    /// A map was merged while claims were held: dropping them may take
    /// away what that map said too, and then `merged` no longer holds.
    merged_over_claims: bool,
    /// Scratch for the rule's view, kept so choosing never allocates.
    views: Vec<NeighbourView>,
    blocked_now: Vec<VertexId>,
    /// Where it stood, to tell bodies that were itself.
    trail: Trail,
}

impl std::fmt::Debug for Robot<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Robot")
            .field("cfg", &self.cfg)
            .field("pos", &self.pos)
            .field("round", &self.round)
            .finish_non_exhaustive()
    }
}

impl<'g> Robot<'g> {
    /// A robot of a grid policy. Its rule must be runnable here: engines
    /// check with [`choice::registry::runnable`] before building robots, so
    /// an unknown policy is a usage error there, never a panic here.
    pub fn new(grid: &'g Grid, cfg: RobotConfig, start: VertexId) -> Self {
        let rule = match choice::rule_for(cfg.policy) {
            Ok(r) => r,
            Err(e) => panic!("robot {}: {e}", cfg.id),
        };
        Robot {
            grid,
            rng: robot_rng(cfg.seed, cfg.id),
            cfg,
            pos: start,
            round: 0,
            map: Map::new(grid.len()),
            nbrs: Vec::with_capacity(16),
            open_now: 0,
            occupied_now: 0,
            next: None,
            accounted: Vec::with_capacity(8),
            parked: Vec::new(),
            rule,
            claims: Vec::new(),
            merged: Vec::new(),
            merged_over_claims: false,
            paths: Paths::default(),
            views: Vec::with_capacity(16),
            blocked_now: Vec::new(),
            trail: Trail::default(),
        }
    }

    pub fn id(&self) -> RobotId {
        self.cfg.id
    }

    pub fn config(&self) -> &RobotConfig {
        &self.cfg
    }

    pub fn grid(&self) -> &'g Grid {
        self.grid
    }

    pub fn position(&self) -> VertexId {
        self.pos
    }

    pub fn round(&self) -> u32 {
        self.round
    }

    pub fn map(&self) -> &Map {
        &self.map
    }

    /// The map, for the protocol's bookkeeping of failures and rejoins.
    pub fn map_mut(&mut self) -> &mut Map {
        &mut self.map
    }

    /// The choice made this round, once [`Robot::choose`] has run.
    pub fn choice(&self) -> Option<VertexId> {
        self.next
    }

    /// The neighbours whose announced choices the choice of this round avoided.
    pub fn accounted(&self) -> &[RobotId] {
        &self.accounted
    }

    /// The sonar's occupied slots of this round.
    pub fn occupied(&self) -> u8 {
        self.occupied_now
    }

    /// A claim lasts one round: by the next the chooser's own map, sensed
    /// on the vertex, says it was visited. A claim nobody sensed (the
    /// chooser crashed, was refused, or is out of range) is dropped, so the
    /// vertex is unvisited again: kept, it would stop robots by rule (4)
    /// on a map that ends at a vertex no one has seen around (in situation
    /// 1 ending the search with targets unfound), and a crashed chooser's
    /// claim would keep the others from ever going there.
    fn drop_claims(&mut self) {
        let mut dropped = false;
        for (v, new) in self.claims.drain(..) {
            if self.map.open(v) & SENSED == 0 {
                dropped = true;
                self.map.set_visited(v, false);
                // Known only through the claim, unless a map merged since
                // sensed an open edge to it: forgetting that would leave
                // the frontier behind it closed, and rule (4) would stop
                // the search on a map that ends at a wall nobody sensed.
                if new && !self.map.reached(self.grid, v) {
                    self.map.set_known(v, false);
                }
            }
        }
        if dropped && std::mem::take(&mut self.merged_over_claims) {
            self.merged.clear();
        }
    }

    /// Steps 1-2: start round `round` with this round's readings. Nobody is
    /// a neighbour until its map or choice is heard.
    pub fn sense(&mut self, round: u32, s: &Sensing) {
        self.round = round;
        self.next = None;
        self.accounted.clear();
        self.open_now = s.open;
        self.occupied_now = s.occupied;
        self.drop_claims();
        self.merged.retain(|m| m.1 + 1 >= round);
        self.map.record_sensing(self.grid, self.pos, s.open);
        self.trail.record(round, self.pos);
        self.learn_targets(s.targets);
        self.nbrs.clear();
        if !(self.map.bodies.is_empty() && self.parked.is_empty()) || self.map.any_failed() {
            self.map.free_body(self.pos, round);
            self.look_around(s.occupied);
        }
        if self.faults_known() {
            self.map.sightings.add(Sighting { robot: self.cfg.id, at: self.pos, round });
        }
    }

    /// What the sonar says of robots thought to stand still nearby. Nobody
    /// stands where it finds free: no body, no halted robot (a halted robot,
    /// which senses but has no exchange, learns it here), and no failed
    /// robot, whose declaration that refutes (it went unheard, and moved
    /// on). A failed robot's vertex found occupied is its body, seen.
    fn look_around(&mut self, occupied: u8) {
        for (d, &v) in self.grid.neighbors(self.pos)[..self.grid.degree()].iter().enumerate() {
            if v == crate::grid::NONE {
                continue;
            }
            let free = occupied >> d & 1 == 0;
            if free {
                self.clear_body(v);
            }
            loop {
                let found = self.map.failures_now().find(|f| f.at == v && (free || !f.seen));
                let Some(f) = found else { break };
                if free {
                    self.map.revive(f.robot, self.round);
                } else {
                    self.map.see_failed(f.robot);
                }
            }
        }
    }

    /// Targets others found (a flood, step 1).
    pub fn learn_targets(&mut self, targets: &[Spot]) {
        for &t in targets {
            self.map.targets.insert(t);
        }
    }

    /// The neighbour entry of `from`, added if it was not heard yet this round.
    fn neighbour(&mut self, from: RobotId, at: VertexId) -> Option<&mut Neighbour> {
        if from == self.cfg.id || (at as usize) >= self.grid.len() {
            return None;
        }
        let k = match self.nbrs.iter().position(|n| n.id == from) {
            Some(k) => k,
            None => {
                // Heard, so alive, whatever others declared.
                if self.map.is_failed(from) {
                    self.map.revive(from, self.round);
                }
                let key = self.key_of(at);
                let n = Neighbour { id: from, at, key, map_in: false, choice: None, suspected: false, halted: false };
                // Sorted by id so every later pass visits neighbours in one fixed order.
                let k = self.nbrs.partition_point(|m| m.id < from);
                self.nbrs.insert(k, n);
                k
            }
        };
        Some(&mut self.nbrs[k])
    }

    /// Step 3: a neighbour's map as it was when it sensed this round, where
    /// it stands, and whether it has stopped searching. Returns false (and
    /// changes nothing) for a map from this robot itself or a bad vertex.
    pub fn receive_map(&mut self, from: RobotId, at: VertexId, map: &Map, halted: bool) -> bool {
        let Some(n) = self.neighbour(from, at) else {
            return false;
        };
        n.at = at;
        n.map_in = true;
        n.halted |= halted;
        self.parked.retain(|p| p.0 != from);
        if halted {
            // A robot that stopped searching stands still until it is heard
            // searching again.
            self.parked.push((from, at));
        } else {
            self.clear_body(at);
        }
        let k = self.merged.binary_search_by_key(&from, |m| m.0);
        let holds_base = map.base.is_some_and(|b| k.is_ok_and(|k| self.merged[k].1 == b));
        if holds_base {
            self.map.merge_changes(map);
        } else {
            self.map.merge(map);
        }
        match k {
            Ok(k) => self.merged[k].1 = self.round,
            Err(k) => self.merged.insert(k, (from, self.round)),
        }
        self.merged_over_claims |= !self.claims.is_empty();
        if self.map.is_failed(self.cfg.id) {
            // Declared failed while it was frozen or unheard: it knows
            // better, and its map now says so to everyone it meets.
            self.map.revive(self.cfg.id, self.round);
        }
        // Likewise found as a silent body where it stands, or stood.
        self.map.free_body(self.pos, self.round);
        self.free_own_bodies();
        self.refresh_failed();
        if map.sightings.of(from).is_none() && self.faults_known() {
            // It has heard of no failure, so it does not say where it is:
            // those that have, and hear it, do.
            self.map.sightings.add(Sighting { robot: from, at, round: self.round });
        }
        true
    }

    /// The bodies its map holds where it stood itself when they were found
    /// were this robot, silent (frozen, or unheard), and it has moved on:
    /// they are freed as of the last round it stood there. Nobody else can
    /// tell such a body from a crash, and each would wall off what lies
    /// behind it until a sonar came by. A robot found there later is
    /// another body, found in a later round, and stays.
    fn free_own_bodies(&mut self) {
        if self.map.bodies.is_empty() {
            return;
        }
        let own = |(v, t): (VertexId, u32)| self.trail.stood(v, t).map(|last| (v, last));
        let freed: Vec<(VertexId, u32)> = self.map.bodies_found_now().filter_map(own).collect();
        for (v, last) in freed {
            self.map.free_body(v, last);
        }
    }

    /// A merged map may declare failed a robot heard this round: what this
    /// robot heard itself wins.
    fn refresh_failed(&mut self) {
        for k in 0..self.nbrs.len() {
            let id = self.nbrs[k].id;
            if self.map.is_failed(id) {
                self.map.revive(id, self.round);
            }
        }
    }

    /// Steps 7 (rules 3/4), evaluated once the maps are exchanged, on what
    /// was sensed: this round's claims still unconfirmed count as unvisited.
    /// A claim says only that a neighbour means to go there; a robot late
    /// to its exchange (slow, thawed) hears its neighbours' choices before
    /// its stop test, and with the claims counted it stopped the search on
    /// vertices nobody had seen around (docs/paper.md, "choices update maps").
    pub fn stop_rule(&mut self) -> Option<Stop> {
        if self.claims.is_empty() {
            // On time: no choice is out yet.
            return self.stop_rule_sensed();
        }
        self.set_unsensed_claims(false);
        let stop = self.stop_rule_sensed();
        self.set_unsensed_claims(true);
        stop
    }

    /// Marks the claimed vertices nobody sensed yet visited or not (they
    /// stay known: a claim shows there is something to visit). Until the
    /// next sensing drops them, every claimed vertex is visited.
    fn set_unsensed_claims(&mut self, visited: bool) {
        for &(v, _) in &self.claims {
            if self.map.open(v) & SENSED == 0 {
                self.map.set_visited(v, visited);
            }
        }
    }

    fn stop_rule_sensed(&mut self) -> Option<Stop> {
        if self.cfg.situation == Situation::One && self.map.targets.count() >= self.cfg.targets_total {
            return Some(Stop::AllTargets);
        }
        if !self.map.has_unvisited() {
            return Some(Stop::MapComplete);
        }
        // Sec. 4.2: a failed robot blocks its vertex for good, so it can cut
        // unvisited vertices off; those can never be visited and must not
        // keep this robot going. Only with failures, so a failure-free run
        // decides exactly as before.
        if self.faults_known() {
            self.collect_blocked(false, false);
            if self.paths.step_to_unvisited(self.grid, &self.map, self.pos, &self.blocked_now).is_none() {
                return Some(Stop::CutOff);
            }
        }
        None
    }

    /// The silent bodies no robot of the team can be. A body
    /// found on `v` in round `t` is some robot that stood there silent
    /// then; not one known to be elsewhere later: heard since, on another
    /// vertex, failed on another vertex with its body seen, or the only
    /// robot a body found later on another vertex can be (bodies are
    /// taken latest first, so that one is known before). Such a body is a
    /// robot that thawed, or was heard again, and moved on, where no sonar
    /// came by to find the vertex free; kept, it would cut off what lies
    /// behind it for good. If a robot does stand there, the next sonar to
    /// pass finds it again, later. Only with the team's roster known.
    fn phantoms(&self) -> Vec<VertexId> {
        let (team, me) = (self.cfg.team, self.cfg.id);
        let mut out = Vec::new();
        if team == 0 {
            return out;
        }
        let mut bodies: Vec<(VertexId, u32)> = self.map.bodies_found_now().collect();
        bodies.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        // Where each robot is known to be, and from which round on.
        let mut placed: Vec<Option<(VertexId, u32)>> = (0..team as RobotId)
            .map(|r| match self.map.failure(r) {
                Some(f) if f.seen => Some((f.at, u32::MAX)),
                Some(_) => None,
                None => self.map.sightings.of(r).map(|s| (s.at, s.round)),
            })
            .collect();
        for (v, found) in bodies {
            let can_be = |r: usize| r != me as usize && placed[r].is_none_or(|(at, t)| at == v || t < found);
            let mut cands = (0..team).filter(|&r| can_be(r));
            match (cands.next(), cands.next()) {
                (None, _) => out.push(v),
                (Some(r), None) if placed[r].is_none_or(|(_, t)| t < found) => placed[r] = Some((v, found)),
                _ => {}
            }
        }
        out
    }

    /// Sec. 4.2: robot `id`, standing on `at`, will never answer (declared
    /// in `round`). It is no longer waited for and its vertex stays blocked.
    pub fn declare_failed(&mut self, id: RobotId, at: VertexId, round: u32) {
        if id == self.cfg.id || (at as usize) >= self.grid.len() {
            return;
        }
        self.map.add_failed(id, at, round);
        if let Some(n) = self.nbrs.iter_mut().find(|n| n.id == id) {
            n.suspected = true;
        }
    }

    /// A silent robot stands on `v` (the sonar finds it, nobody hears it):
    /// it blocks `v` like a failed robot until the sonar finds `v` free.
    pub fn mark_body(&mut self, v: VertexId) {
        if (v as usize) < self.grid.len() {
            self.map.add_body(v, self.round);
        }
    }

    /// Whether it knows of a failed robot or a silent body: the rules for
    /// survivors apply. Never in a failure-free run.
    fn faults_known(&self) -> bool {
        self.map.any_failed() || self.map.bodies_now().next().is_some()
    }

    /// Whether the survivor step applies: failures or bodies known now; or,
    /// under rules that walk visited vertices at random (the paper's two,
    /// and escape's around them), ever known to its map, revived or freed
    /// since. A freeze that thawed still split the team's knowledge (the
    /// thawed robot missed slots, the others' maps went on without it), and
    /// walking visited vertices to mend that took thousands of rounds
    /// (issue 37, point 4: 2,631 against 304). Frontier rules head for
    /// what is left themselves. Never in a failure-free run.
    fn survivors(&self) -> bool {
        let walks = matches!(self.cfg.policy, Policy::Repulsive | Policy::Sequential | Policy::Escape);
        self.faults_known() || (walks && !(self.map.failed.is_empty() && self.map.bodies.is_empty()))
    }

    /// The sonar finds `v` free.
    pub fn clear_body(&mut self, v: VertexId) {
        self.map.free_body(v, self.round);
        self.parked.retain(|p| p.1 != v);
    }

    /// `blocked_now` := the vertices blocked for good: silent bodies',
    /// failed robots' whose body was seen, with `unseen` the other failed
    /// robots' too, and with `parked` halted neighbours' (they block moves
    /// until they search again). The cut-off test takes neither: a robot
    /// cut off only by unseen failures goes and looks.
    fn collect_blocked(&mut self, unseen: bool, parked: bool) {
        let mut b = std::mem::take(&mut self.blocked_now);
        b.clear();
        b.extend(self.map.failures_now().filter(|f| unseen || f.seen).map(|f| f.at));
        let phantoms = if self.map.bodies_now().next().is_some() { self.phantoms() } else { Vec::new() };
        b.extend(self.map.bodies_now().filter(|v| !phantoms.contains(v)));
        if parked {
            b.extend(self.parked.iter().map(|p| p.1));
        }
        self.blocked_now = b;
    }

    /// Robot `id` was heard alive in `round`: a failure declared of it no
    /// longer counts, and it is a neighbour like any other.
    pub fn revive(&mut self, id: RobotId, round: u32) {
        self.map.revive(id, round);
    }

    /// Robot `id` did not choose in time this round: it is no longer waited
    /// for, and treated as standing still where it was heard.
    pub fn suspect(&mut self, id: RobotId) {
        if let Some(n) = self.nbrs.iter_mut().find(|n| n.id == id) {
            n.suspected = true;
        }
    }

    /// Step 5 of a neighbour: its announced next vertex, from `at`. A robot
    /// heard first through its choice becomes a neighbour.
    pub fn receive_choice(&mut self, from: RobotId, at: VertexId, next: VertexId) -> bool {
        if (next as usize) >= self.grid.len() {
            return false;
        }
        match self.neighbour(from, at) {
            Some(n) => {
                n.choice = Some(next);
                if self.cfg.choices_update_maps && self.cfg.policy.sequential() && !self.map.visited(next) {
                    // "the receivers will update their maps": the vertex
                    // counts as visited for the rest of the round.
                    let new = !self.map.known(next);
                    self.map.set_visited(next, true);
                    self.map.set_known(next, true);
                    self.claims.push((next, new));
                }
                true
            }
            None => false,
        }
    }

    fn sequential(&self) -> bool {
        self.cfg.policy.sequential()
    }

    /// Step 4's priority of a robot on `v`: higher chooses first. The
    /// paper's key orders by position; the local order's is the vertex's
    /// class, the first class first.
    fn key_of(&self, v: VertexId) -> (i64, i64) {
        match self.cfg.order {
            Order::Paper => self.grid.priority_key(v),
            Order::Local => (-(self.grid.class(v) as i64), 0),
        }
    }

    /// Higher-priority neighbours this robot still waits for (sequential
    /// policies only): heard, not failed or suspected, not halted, and
    /// without an announced choice.
    pub fn waiting_for(&self) -> impl Iterator<Item = RobotId> + '_ {
        // Equal keys: under the paper's order, robots stacked on one vertex
        // (after a collision under loss), where the higher id goes first;
        // under the local order also robots of one class, more than `2a`
        // apart, which cannot collide and wait for nobody of their class.
        let (key, pos, id) = (self.key_of(self.pos), self.pos, self.cfg.id);
        let seq = self.sequential();
        let ahead = move |n: &Neighbour| n.key > key || (n.key == key && n.at == pos && n.id > id);
        self.nbrs
            .iter()
            .filter(move |n| seq && !n.suspected && !n.halted && ahead(n) && n.choice.is_none())
            .map(|n| n.id)
    }

    /// Whether neighbour `id` comes after this robot in step 4's order (it
    /// waits for this robot's choice: [`Robot::waiting_for`]'s rule, the
    /// other way round). Sequential policies only.
    pub fn precedes(&self, id: RobotId) -> bool {
        let (key, pos, me) = (self.key_of(self.pos), self.pos, self.cfg.id);
        let behind = |n: &Neighbour| n.key < key || (n.key == key && n.at == pos && n.id < me);
        self.sequential() && self.nbrs.iter().any(|n| n.id == id && behind(n))
    }

    /// Whether every input step 5 needs has arrived.
    pub fn ready(&self) -> bool {
        self.next.is_none() && self.waiting_for().next().is_none()
    }

    /// Whether `nb`'s announced move is to be avoided: its choice is known
    /// (in a failure-free round, only higher-priority neighbours' are).
    fn moving(&self, nb: &Neighbour) -> Option<VertexId> {
        if !self.sequential() || nb.suspected || nb.halted {
            return None;
        }
        nb.choice
    }

    /// Steps 4-5: the next vertex (the current one to stay). `None` while
    /// [`Robot::ready`] is false.
    pub fn choose(&mut self) -> Option<VertexId> {
        if !self.ready() {
            return None;
        }
        let grid = self.grid;
        let here = grid.position(self.pos);
        let two_safe = 2.0 * self.cfg.r_safe;
        // Failed robots (seen or not: they may stand there) and bodies.
        self.collect_blocked(true, false);
        let mut cands = [NONE; MAX_DEGREE];
        let mut nc = 0;
        'slot: for (d, &n) in grid.neighbors(self.pos)[..grid.degree()].iter().enumerate() {
            if n == NONE || self.open_now >> d & 1 == 0 {
                continue;
            }
            if !self.sequential() {
                // Particles: RU ignores other robots altogether.
                cands[nc] = n;
                nc += 1;
                continue;
            }
            let there = grid.position(n);
            for &at in &self.blocked_now {
                let p = grid.position(at);
                if at == n || swept_min_distance(here, there, p, p) < two_safe {
                    continue 'slot;
                }
            }
            let mut vacated = false;
            for nb in &self.nbrs {
                let from = grid.position(nb.at);
                if let Some(c) = self.moving(nb) {
                    if c == n || swept_min_distance(here, there, from, grid.position(c)) < two_safe {
                        continue 'slot;
                    }
                    vacated |= nb.at == n && c != n;
                } else if nb.at == n || (nb.at != self.pos && swept_min_distance(here, there, from, from) < two_safe) {
                    // (A robot on this very vertex, after a collision under
                    // loss, is left behind: moving off is what parts them.)
                    continue 'slot;
                }
            }
            // A robot on that vertex that has not announced leaving it blocks it.
            if self.occupied_now >> d & 1 == 1 && !vacated {
                continue;
            }
            cands[nc] = n;
            nc += 1;
        }
        let next = self.pick(&cands[..nc]).unwrap_or(self.pos);
        self.next = Some(next);
        self.accounted.clear();
        for i in 0..self.nbrs.len() {
            if self.moving(&self.nbrs[i]).is_some() {
                self.accounted.push(self.nbrs[i].id);
            }
        }
        Some(next)
    }

    /// Steps 4-5 skipped: the robot stays this round, whatever it heard.
    /// Always safe: nobody moves onto a vertex whose robot has not
    /// announced leaving it, and every move chosen treats a robot that has
    /// not chosen as standing still.
    pub fn stay(&mut self) {
        self.next = Some(self.pos);
        self.accounted.clear();
    }

    /// Step 5 proper: the policy's rule picks among `cands`; anything but
    /// a candidate is staying.
    fn pick(&mut self, cands: &[VertexId]) -> Option<VertexId> {
        if self.cfg.survivor_step && (!self.rule.passes_unvisited() || self.stuck_behind_unseen()) {
            if let Some(step) = self.survivor_step(cands) {
                return Some(step);
            }
        }
        self.collect_blocked(true, true);
        let mut views = std::mem::take(&mut self.views);
        views.clear();
        views.extend(self.nbrs.iter().map(|n| NeighbourView {
            id: n.id,
            at: n.at,
            choice: self.moving(n),
            searching: !n.suspected && !n.halted && n.map_in,
        }));
        let view = View {
            grid: self.grid,
            map: &self.map,
            position: self.pos,
            round: self.round,
            candidates: cands,
            neighbours: &views,
            blocked: &self.blocked_now,
            visited_choice: self.cfg.visited_choice,
        };
        let c = self.rule.choose(&view, &mut self.rng).filter(|c| cands.contains(c));
        self.views = views;
        c
    }

    /// Once failures are known, a robot with no unvisited vertex next to it
    /// steps towards the nearest one it can reach, past failures nobody
    /// has seen, instead of the paper's walk over visited vertices: the
    /// walk could take thousands of rounds to find the few vertices the
    /// bodies' lost maps leave, and a declaration nobody checks (a live
    /// robot unheard under loss) would cut robots off for good. Failure-free
    /// runs never get here, so they follow the paper exactly; with
    /// `survivor_step` off (the paper's rules under failure) nobody does.
    fn survivor_step(&mut self, cands: &[VertexId]) -> Option<VertexId> {
        if !self.survivors() || cands.iter().any(|&c| !self.map.visited(c)) {
            return None;
        }
        // Around the neighbours standing still if it can (one slow for good
        // may stand in a corridor for ever), through them if it must.
        self.collect_blocked(false, true);
        let mut blocked = std::mem::take(&mut self.blocked_now);
        let all = blocked.len();
        for n in &self.nbrs {
            if self.moving(n).is_none_or(|c| c == n.at) {
                blocked.push(n.at);
            }
        }
        let mut step = self.paths.step_to_unvisited(self.grid, &self.map, self.pos, &blocked);
        if step.is_none() {
            blocked.truncate(all);
            step = self.paths.step_to_unvisited(self.grid, &self.map, self.pos, &blocked);
        }
        self.blocked_now = blocked;
        step.filter(|s| cands.contains(s))
    }

    /// Whether, failures known, nothing unvisited is reachable for the rule
    /// (every failure and halted neighbour in the way), though the cut-off
    /// test, which counts only failures whose body was seen, finds the
    /// robot not cut off: a rule that passes unvisited vertices, left to
    /// itself, would walk visited ones for ever instead of going to look.
    fn stuck_behind_unseen(&mut self) -> bool {
        if !self.faults_known() || self.map.failures_now().all(|f| f.seen) {
            return false;
        }
        self.collect_blocked(true, true);
        self.paths.step_to_unvisited(self.grid, &self.map, self.pos, &self.blocked_now).is_none()
    }

    /// Step 6 done: the world moved this robot to `to`.
    pub fn moved(&mut self, to: VertexId) {
        self.pos = to;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::lattice::{Coord, Lattice, LatticeKind};

    #[test]
    fn vertices_cut_off_by_failed_robots_do_not_keep_the_search_going() {
        let lattice = Lattice::new(LatticeKind::Triangular, 1.0);
        let g = &Grid::new(lattice, Point::new(-5.0, -5.0), Point::new(5.0, 5.0));
        let v = g.id_of(Coord::new(0, 0)).unwrap();
        let cfg = RobotConfig::new(0, Policy::Repulsive, Situation::Two, 0, 0.3, 1);
        let mut r = Robot::new(g, cfg, v);
        // Only the edge in slot 0 is open: its far end is the one unvisited vertex.
        r.sense(0, &Sensing { open: 1, occupied: 0, targets: &[] });
        assert_eq!(r.stop_rule(), None);
        // A failed robot elsewhere changes nothing.
        r.declare_failed(4, g.neighbors(v)[3], 0);
        assert_eq!(r.stop_rule(), None);
        // One declared on that vertex: until its body is seen there, the
        // robot goes and looks.
        r.declare_failed(5, g.neighbors(v)[0], 0);
        assert_eq!(r.stop_rule(), None);
        // The sonar finds it there: it blocks the vertex for good, nothing
        // is left this robot can reach, which ends its own search only.
        r.sense(1, &Sensing { open: 1, occupied: 1, targets: &[] });
        assert!(r.map().failure(5).is_some_and(|f| f.seen));
        assert_eq!(r.stop_rule(), Some(Stop::CutOff));
        assert!(!Stop::CutOff.ends_search());
        // Heard alive again: the vertex is free once more.
        r.map_mut().revive(5, 2);
        assert_eq!(r.stop_rule(), None);
        // Declared again, and the sonar finds the vertex free: nobody
        // stands there, so the declaration was wrong.
        r.declare_failed(5, g.neighbors(v)[0], 3);
        r.sense(4, &Sensing { open: 1, occupied: 0, targets: &[] });
        assert!(!r.map().is_failed(5));
        assert_eq!(r.stop_rule(), None);
    }

    #[test]
    fn a_dropped_claim_keeps_what_a_merged_map_sensed() {
        let lattice = Lattice::new(LatticeKind::Triangular, 1.0);
        let g = &Grid::new(lattice, Point::new(-5.0, -5.0), Point::new(5.0, 5.0));
        let v = g.id_of(Coord::new(0, 0)).unwrap();
        let a = g.neighbors(v)[0];
        let w = g.neighbors(a)[0];
        let cfg = RobotConfig::new(0, Policy::Sequential, Situation::Two, 0, 0.3, 1);
        let mut r = Robot::new(g, cfg, v);
        r.sense(0, &Sensing { open: 1, occupied: 1, targets: &[] });
        assert!(r.map().known(a) && !r.map().known(w));
        // Robot 1, on `a`, claims `w`, which this robot has never heard of.
        assert!(r.receive_choice(1, a, w));
        assert!(r.map().visited(w) && r.map().known(w));
        // A map comes in whose sender sensed at `a`, edge to `w` open.
        let mut m = Map::new(g.len());
        m.record_sensing(g, a, 1);
        assert!(r.receive_map(2, g.neighbors(v)[3], &m, false));
        // Robot 1 never went: the claim goes, but `w` stays known, unvisited.
        r.sense(1, &Sensing { open: 1, occupied: 1, targets: &[] });
        assert!(!r.map().visited(w));
        assert!(r.map().known(w), "the merged map's sensing was forgotten with the claim");
        assert!(r.map().has_unvisited());
    }
}
