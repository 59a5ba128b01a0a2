#include "tetcontact/mesh/partition.hpp"

#include <metis.h>

#include <algorithm>
#include <string>

namespace tc {

namespace {

// Boundary faces per tet: the contact work a tet brings.
std::vector<long> faces_per_tet(const Mesh& mesh, const std::vector<Surface>& surfaces) {
  std::vector<long> faces(mesh.tets.size(), 0);
  for (const Surface& s : surfaces)
    for (const Index t : s.face_tet) ++faces[t];
  return faces;
}

double imbalance(const std::vector<long>& work) {
  long total = 0, most = 0;
  for (const long w : work) total += w, most = std::max(most, w);
  if (total == 0) return 1.0;
  return static_cast<double>(most) * static_cast<double>(work.size()) / static_cast<double>(total);
}

// The per-rank counts, shared and ghost nodes, cut and imbalances of an assignment of tets to
// ranks (`faces`: boundary faces per tet; `across`: the tet across each face).
Partition describe(const Mesh& mesh, const std::vector<long>& faces, const TetNeighbours& across,
                   int ranks, std::vector<int> tet_rank) {
  Partition p;
  p.ranks = ranks;
  p.tet_rank = std::move(tet_rank);
  p.pieces.assign(ranks, RankPiece{});
  // Tets grouped by rank (counting sort, tet order kept within a rank).
  std::vector<std::size_t> begin(ranks + 1, 0), order(mesh.tets.size());
  for (const int r : p.tet_rank) ++begin[r + 1];
  for (int r = 0; r < ranks; ++r) begin[r + 1] += begin[r];
  std::vector<std::size_t> next(begin.begin(), begin.end() - 1);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) order[next[p.tet_rank[t]]++] = t;
  // The ranks holding each node: how many, and the lowest (ranks are visited in order).
  const std::size_t n = mesh.x.size();
  std::vector<int> stamp(n, -1), holders(n, 0);
  p.node_owner.assign(n, -1);
  for (int r = 0; r < ranks; ++r)
    for (std::size_t k = begin[r]; k < begin[r + 1]; ++k) {
      const std::size_t t = order[k];
      ++p.pieces[r].tets;
      p.pieces[r].boundary_faces += faces[t];
      for (const Index v : mesh.tets[t]) {
        if (stamp[v] == r) continue;
        stamp[v] = r;
        ++holders[v];
        ++p.pieces[r].nodes;
        if (p.node_owner[v] < 0) p.node_owner[v] = r;
      }
    }
  std::fill(stamp.begin(), stamp.end(), -1);
  for (int r = 0; r < ranks; ++r)
    for (std::size_t k = begin[r]; k < begin[r + 1]; ++k)
      for (const Index v : mesh.tets[order[k]]) {
        if (stamp[v] == r) continue;
        stamp[v] = r;
        p.pieces[r].shared_nodes += holders[v] > 1;
        p.pieces[r].ghost_nodes += p.node_owner[v] < r;
      }
  for (std::size_t t = 0; t < across.size(); ++t)
    for (const Index u : across[t])
      p.cut_faces += u > static_cast<Index>(t) && p.tet_rank[u] != p.tet_rank[t];
  std::vector<long> tets(ranks), face_work(ranks);
  for (int r = 0; r < ranks; ++r)
    tets[r] = p.pieces[r].tets, face_work[r] = p.pieces[r].boundary_faces;
  p.tet_imbalance = imbalance(tets);
  p.face_imbalance = imbalance(face_work);
  return p;
}

}  // namespace

Partition partition_mesh(const Mesh& mesh, const std::vector<Surface>& surfaces,
                         const PartitionSettings& settings) {
  const int ranks = settings.ranks;
  const long tets = static_cast<long>(mesh.tets.size());
  if (ranks < 1) throw PartitionError("ranks must be at least 1, got " + std::to_string(ranks));
  if (ranks > tets)
    throw PartitionError("cannot cut " + std::to_string(tets) + " tets into " +
                         std::to_string(ranks) + " pieces");
  const TetNeighbours across = tet_neighbours(mesh);
  const std::vector<long> faces = faces_per_tet(mesh, surfaces);
  if (ranks == 1) return describe(mesh, faces, across, 1, std::vector<int>(tets, 0));
  // The element graph in CSR form: tets joined across shared faces.
  std::vector<idx_t> xadj{0}, adjncy;
  adjncy.reserve(4 * mesh.tets.size() + 1);  // never null, even with no shared face
  for (const auto& nb : across) {
    for (const Index u : nb)
      if (u >= 0) adjncy.push_back(u);
    xadj.push_back(static_cast<idx_t>(adjncy.size()));
  }
  // Two constraints a tet: element work 1, contact work its boundary faces.
  long total_faces = 0;
  for (const long f : faces) total_faces += f;
  idx_t ncon = settings.balance_contact && total_faces > 0 ? 2 : 1;
  std::vector<idx_t> vwgt;
  for (long t = 0; t < tets; ++t) {
    vwgt.push_back(1);
    if (ncon == 2) vwgt.push_back(static_cast<idx_t>(faces[t]));
  }
  std::vector<real_t> ubvec(ncon, static_cast<real_t>(settings.tolerance));
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = settings.seed;
  options[METIS_OPTION_NUMBERING] = 0;
  idx_t nvtxs = static_cast<idx_t>(tets), nparts = ranks, cut = 0;
  std::vector<idx_t> part(tets, 0);
  const int status =
      METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adjncy.data(), vwgt.data(), nullptr, nullptr,
                          &nparts, nullptr, ubvec.data(), options, &cut, part.data());
  if (status != METIS_OK)
    throw PartitionError("METIS could not cut the mesh into " + std::to_string(ranks) +
                         " pieces (status " + std::to_string(status) + ")");
  return describe(mesh, faces, across, ranks, std::vector<int>(part.begin(), part.end()));
}

}  // namespace tc
