//! The end of a run: whether the search completed, which waiters never
//! declared the failed robot they waited on, and the [`RunResult`]; and
//! whether a run past a stated bound has stalled (`past_bound`).

use super::{Body, Kernel};
use crate::grid::VertexId;
use crate::outcome::{RunMetrics, RunResult};
use crate::params::Situation;
use crate::sim::{Framed, Time};

impl<'w, P: Clone + Framed> Kernel<'w, P> {
    /// Whether the run is past a stated bound and stalled there, past a
    /// bound in each of the slots counted and no fault due that could
    /// change it: robots searched and none moved for [`STALL_ROUNDS`]
    /// slots, or none visited a vertex first for [`AIMLESS_ROUNDS`] (robots
    /// that swap between vertices they know for ever). The world ends the
    /// record of such a run, as it does at its round limit; it tells the
    /// robots nothing. Inside every bound the counts never start. Notes
    /// why in `past_bound` when it ends the run.
    ///
    /// [`STALL_ROUNDS`]: crate::bounds::STALL_ROUNDS
    /// [`AIMLESS_ROUNDS`]: crate::bounds::AIMLESS_ROUNDS
    pub(super) fn stalled(&mut self, moved: u64) -> bool {
        let visits = self.referee.visits();
        let fresh = std::mem::replace(&mut self.visits, visits) < visits;
        let past = if super::searching_left(&self.bots) { self.past_bound() } else { None };
        let Some(why) = past else {
            (self.stall, self.aimless) = (0, 0);
            return false;
        };
        self.stall = if moved > 0 { 0 } else { self.stall + 1 };
        self.aimless = if fresh { 0 } else { self.aimless + 1 };
        if self.cfg.faults.iter().any(|f| f.round >= self.round) {
            return false;
        }
        let said = if self.stall >= crate::bounds::STALL_ROUNDS {
            format!("no robot moved for {} rounds, {why}", self.stall)
        } else if self.aimless >= crate::bounds::AIMLESS_ROUNDS {
            format!("no vertex visited for the first time in {} rounds, {why}", self.aimless)
        } else {
            return false;
        };
        self.stats.past_bound = Some(said);
        true
    }

    /// The liveness bound the run is past now, from its radio and the
    /// slowness of its running robots, if any.
    pub(super) fn past_bound(&self) -> Option<String> {
        let slow: Vec<(usize, Time)> = (self.bots.iter().enumerate())
            .filter(|(_, b)| b.body == Body::Running && b.slow > 0)
            .map(|(k, b)| (k, b.slow))
            .collect();
        let running = self.bots.iter().filter(|b| b.body == Body::Running && !b.halted).count();
        self.bounds.past(&self.cfg.radio, &slow, running)
    }

    pub(super) fn finish(mut self) -> RunResult {
        let world = self.world;
        let ended = self.ended.unwrap_or("max_rounds");
        let dead: Vec<VertexId> = (0..self.bots.len())
            .filter(|&k| self.bots[k].body != Body::Running)
            .map(|k| self.referee.position(k))
            .collect();
        // Whether some vertex a running robot could reach, around the
        // bodies, was never visited. Only asked of runs that ended `stop`
        // or `cut_off`, so the sweeps' fault-free runs pay for no search.
        let unvisited_left = || {
            let live: Vec<VertexId> = (0..self.bots.len())
                .filter(|&k| self.bots[k].body == Body::Running)
                .map(|k| self.referee.position(k))
                .collect();
            let va = if dead.is_empty() {
                world.reachable_from(&self.starts)
            } else {
                world.reachable_avoiding(&live, &dead)
            };
            (0..world.grid.len()).any(|v| va[v] && !self.referee.visited().get(v))
        };
        let cut_off_early = ended == "cut_off" && unvisited_left();
        let complete = match self.cfg.situation {
            Situation::One => self.stats.stop_round.is_some() && self.referee.found_count() == world.targets.len(),
            Situation::Two if ended == "cut_off" => !cut_off_early,
            Situation::Two if ended == "stop" => !unvisited_left(),
            Situation::Two => false,
        };
        // A stop ends the search as complete only when it is: one that
        // knew targets unfound says so, and any other on an incomplete
        // search is a false stop, a fault of the protocol.
        self.stats.ended_by = match ended {
            "stop" if self.stop_exhausted => "exhausted",
            "stop" if !complete => "false_stop",
            e => e,
        }
        .to_string();
        // Robots that waited on a failed robot and kept searching long
        // enough to declare it, but never did.
        let grace = world.params.suspect_rounds + 1;
        for &(i, w, round) in &self.waiters {
            let rec = &self.stats.failures[i];
            // Searching at the end of every round up to `round + grace`.
            let (from, to) = (round + 1, round + grace);
            let kept_on = self.round > to && !self.bots[w as usize].idle.iter().any(|&(a, b)| a <= to && b >= from);
            if kept_on && !rec.declared_by.contains(&w) && rec.thawed_s.is_none() && !rec.unaware.contains(&w) {
                self.stats.failures[i].unaware.push(w);
            }
        }
        // The cells `World::detected_fraction_of` counts, marked as the run went.
        let coverage = self.coverage.as_ref().map(|c| c.fraction());
        let a = world.params.a;
        let metrics = RunMetrics {
            coverage_s: self.coverage.map(|c| c.curve()).unwrap_or_default(),
            targets_s: self.targets_s,
            distance_m: self.referee.legs().iter().map(|&l| f64::from(l) * a).collect(),
            rotations: self.referee.turns().to_vec(),
            frames: self.bots.iter().map(|b| b.frames).collect(),
            bytes: self.bots.iter().map(|b| b.bytes).collect(),
        };
        let search_time_s = self.stats.stop_s.unwrap_or_else(|| self.round_end_times.last().copied().unwrap_or(0.0));
        RunResult {
            algorithm: self.cfg.policy,
            robots: self.bots.len(),
            seed: self.cfg.seed,
            situation: self.cfg.situation.number(),
            rounds: self.round,
            search_time_s,
            targets_found: self.referee.found_count(),
            targets_total: world.targets.len(),
            collisions: self.collisions,
            coverage,
            complete,
            cut_off_early,
            robot_rounds: self.robot_rounds,
            trajectories: self.trajectories,
            round_end_times_s: self.round_end_times,
            round_collisions: self.round_collisions,
            protocol: self.stats,
            metrics,
        }
    }
}
