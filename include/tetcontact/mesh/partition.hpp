// Decomposition of the mesh for distributed runs: the tets cut into one piece per
// rank by METIS (src/mesh/partition.cpp only) on the element graph (tets joined across the
// faces they share), with two balance constraints per tet: its element work (1: every tet
// costs the same in the element stage) and its contact work (its boundary faces: each carries
// a face, three edges and three nodes into the contact search, the passes and the
// verification). So a piece with much surface gets fewer tets, and contact-heavy regions are
// balanced too, not only the element stage.
//
// Nodes: a rank holds every node of its tets. A node held by more than one rank is shared; it
// is owned by the lowest of those ranks, and is a ghost on the others (their copy is filled
// from the owner). The report counts, per rank, its tets, boundary faces, nodes held, shared
// nodes and ghost nodes, and the imbalance of each constraint: the largest piece's work over
// the mean.
#pragma once

#include <string>
#include <vector>

#include "tetcontact/mesh/mesh.hpp"
#include "tetcontact/mesh/surface.hpp"

namespace tc {

struct PartitionSettings {
  int ranks = 1;
  /// Balance the contact work (boundary faces) as well as the element work. Off: METIS
  /// balances the tets alone (the comparison the tests and the report make).
  bool balance_contact = true;
  /// The largest piece may carry this factor of the mean work of each constraint (METIS's
  /// `ubvec`): 1.05 allows 5 %.
  double tolerance = 1.05;
  /// METIS's random seed: the same mesh, ranks and seed give the same pieces.
  int seed = 1;
};

struct RankPiece {
  long tets = 0;
  long boundary_faces = 0;
  long nodes = 0;         // held: the nodes of its tets
  long shared_nodes = 0;  // held, and held by another rank too
  long ghost_nodes = 0;   // held, owned by a lower rank
};

struct Partition {
  int ranks = 1;
  std::vector<int> tet_rank;    // per tet
  std::vector<int> node_owner;  // per node: the lowest rank holding it
  std::vector<RankPiece> pieces;
  long cut_faces = 0;           // faces shared by tets of two ranks
  double tet_imbalance = 1.0;   // max tets over the mean
  double face_imbalance = 1.0;  // max boundary faces over the mean
};

struct PartitionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Throws PartitionError for ranks < 1, more ranks than tets, or a METIS failure.
Partition partition_mesh(const Mesh& mesh, const std::vector<Surface>& surfaces,
                         const PartitionSettings& settings);

}  // namespace tc
