#include "tetcontact/app/partition.hpp"

#include <cstdio>
#include <iostream>

#include "tetcontact/app/setup.hpp"

namespace tc {

Json partition_json(const Partition& p) {
  Json j = Json::object();
  j["ranks"] = p.ranks;
  j["cut_faces"] = p.cut_faces;
  j["tet_imbalance"] = p.tet_imbalance;
  j["face_imbalance"] = p.face_imbalance;
  Json pieces = Json::array();
  for (const RankPiece& r : p.pieces) {
    Json x = Json::object();
    x["tets"] = r.tets;
    x["boundary_faces"] = r.boundary_faces;
    x["nodes"] = r.nodes;
    x["shared_nodes"] = r.shared_nodes;
    x["ghost_nodes"] = r.ghost_nodes;
    pieces.push_back(x);
  }
  j["pieces"] = pieces;
  return j;
}

int partition_command(const PartitionOptions& o) {
  try {
    const Model model = build_model(load_case(o.case_path, o.overrides));
    PartitionSettings settings;
    settings.ranks = o.ranks;
    settings.balance_contact = !o.tets_only;
    const Partition p = partition_mesh(model.mesh, model.surfaces, settings);
    if (o.json) {
      std::cout << partition_json(p).dump(2) << "\n";
      return 0;
    }
    std::printf("%6s %10s %15s %10s %13s %12s\n", "rank", "tets", "boundary faces", "nodes",
                "shared nodes", "ghost nodes");
    for (int r = 0; r < p.ranks; ++r) {
      const RankPiece& x = p.pieces[r];
      std::printf("%6d %10ld %15ld %10ld %13ld %12ld\n", r, x.tets, x.boundary_faces, x.nodes,
                  x.shared_nodes, x.ghost_nodes);
    }
    std::printf(
        "%ld faces cut; imbalance (largest piece over the mean): tets %.3f, boundary faces "
        "%.3f (METIS, %s)\n",
        p.cut_faces, p.tet_imbalance, p.face_imbalance,
        o.tets_only ? "tets alone" : "tets and boundary faces balanced");
    return 0;
  } catch (const CaseError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const SetupError& e) {
    std::cerr << "tetcontact: error: " << e.what() << "\n";
  } catch (const PartitionError& e) {
    std::cerr << "tetcontact: error: " << o.case_path << ": " << e.what() << "\n";
  }
  return 2;
}

}  // namespace tc
