// The contact ledger of a run: counters the stages add to step by step and the summary reads
// whole (plain data, the data layer).
#pragma once

namespace tc {

/// Contact between bodies over the run (zeros when no contact stage exists).
struct ContactLedger {
  long node_face = 0, candidates = 0, max_per_step = 0, steps_in_contact = 0;
  long edge_edge = 0, edge_candidates = 0;
  double first_time = -1.0, last_time = -1.0, max_force = 0.0;
  double normal_impulse = 0.0;                            // Σ λ over the run, N s
  double broadphase_build = 0.0, broadphase_query = 0.0;  // seconds over the run
  long rebuilds = 0;               // times the broadphase ran (binding lists rebuilt)
  long particle_contacts = 0;      // particle–face and particle–particle contacts that pushed
  long particles_moved_out = 0;    // particle centres found inside a body and moved out
  double particle_move_max = 0.0;  // the largest such move, m
  // Islands of the correction passes (response/islands.hpp), summed over the steps.
  long islands = 0, island_points = 0, largest_island_points = 0;
  // The verification of each step's motion (verify/verify.hpp), summed over the steps:
  // pairs checked, pairs failing after the passes (from apart, from touching; each try of a step
  // taken again shorter counts its own), steps with any.
  long verified_pairs = 0, failed_pairs = 0, failed_touching = 0, steps_failed = 0;
  long failed_edge_edge = 0;    // of failed_pairs, edge–edge pairs
  long extra_rounds = 0;        // rounds of further passes
  long rescue_points = 0;       // contact points made for failing pairs
  long failed_after_extra = 0;  // pairs still failing after them: the zones' work
  // Steps taken again with half the step because pairs still failed after the further passes
  // (Simulation::step; one count per halving), and the shortest step so taken (s; 0: none).
  long step_cuts = 0;
  double cut_step_min = 0.0;
  // The rigid impact zones that removed them (response/impact_zones.hpp): zones made, the
  // largest (nodes), steps that needed zones, zones frozen (and translated), rounds of
  // verification after the first, and steps whose failures outlasted k_zone_rounds (0 unless the
  // start state overlapped).
  long impact_zones = 0, largest_zone_nodes = 0, steps_with_zones = 0, frozen_zones = 0;
  long translated_zones = 0;
  long zone_rounds = 0, unresolved_steps = 0;
};

}  // namespace tc
