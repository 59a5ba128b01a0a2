// Gauges: points of a run at which velocity, stress, pressure, plastic strain, temperature and
// damage are recorded over time (the case's `gauges:`, written to gauges.csv by io/output).
// A gauge that follows the material is a material point: the cell holding it in the reference
// configuration and its barycentric coordinates there, fixed for the run, so that its position
// and velocity are those weights of the cell's nodes' (x = Σ b_i x_i, v = Σ b_i v_i). A gauge
// fixed in space reads the cell that holds its point at each reading (none: empty space), the
// velocity interpolated there the same way. The cell's own fields are uniform over it (linear
// tetrahedra): stress, pressure, plastic strain, temperature and damage are the cell's.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/model/state.hpp"

namespace tc {

class Archive;

struct GaugeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct GaugeSpec {
  std::string name;
  Vec3 position = Vec3::Zero();  // m: in the reference configuration (material) or in space
  bool follows_material = true;
};

/// What a gauge reads at one time level; `cell` < 0: no cell holds a space gauge's point (the
/// other fields are then not measured).
struct GaugeReading {
  Index cell = -1;
  Vec3 x = Vec3::Zero(), v = Vec3::Zero();
  Mat3 stress = Mat3::Zero();  // s − p I as the frames' stress (q apart), Pa (tension positive)
  double pressure = 0.0;       // the EOS's, Pa (compression positive)
  double plastic_strain = 0.0, temperature = 0.0;
  Damage damage = Damage::intact;
};

/// The barycentric coordinates of p in the tet (a, b, c, d), and whether p lies in it (each
/// coordinate ≥ −tol).
std::array<double, 4> barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                  const Vec3& p);

class Gauges {
 public:
  /// Places the gauges: a material gauge in the reference cell that holds it (GaugeError naming
  /// the gauge when no cell does: outside every body, or on the cut-away side of a symmetry
  /// plane).
  Gauges(const Mesh& mesh, std::vector<GaugeSpec> specs);
  const std::vector<GaugeSpec>& specs() const { return specs_; }
  /// Every gauge's reading at the state's time level.
  std::vector<GaugeReading> read(const State& st);
  /// What a checkpoint holds of them: each gauge's cell.
  void persist(Archive& ar);

 private:
  // The cell of `positions` that holds p best (the largest smallest barycentric coordinate,
  // ≥ −tol), trying `hint` first; −1 when none does. Particles' cells are skipped.
  Index locate(const std::vector<Vec3>& positions, const State* st, const Vec3& p,
               Index hint) const;
  const Mesh& mesh_;
  std::vector<GaugeSpec> specs_;
  std::vector<Index> cell_;                     // material gauges: their cell; space: the last
  std::vector<std::array<double, 4>> weights_;  // material gauges: their coordinates
};

}  // namespace tc
