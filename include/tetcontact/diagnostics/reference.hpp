// Reference values a case declares (`reference:` in the case file) and their measurement
// from a run: the validation cases carry their published or analytical numbers with them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/names.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

class Archive;

struct ReferenceSpec {
  enum class Measure {
    length,         // extent of a body's bounding box along `axis`
    radius,         // half the largest bounding-box extent across `axis`
    mean_stress,    // mean over the tets centred in `region` of −σ_component (compression > 0)
    mean_pressure,  // mean over the tets centred in `region` of the EOS pressure p
    velocity,       // component `axis` of a body's mass-averaged velocity at the end
    contact_duration,       // last − first time with a contact force between bodies
    contact_max_force,      // largest total normal contact force of a step
    contact_mean_pressure,  // total normal contact impulse / (duration · `area`)
    hole_diameter,          // twice the distance from the line along `axis` through the centre of
                            // `region` to the nearest centre of a cell of `body` in `region`
    // Beyond a `plane` (shields), counting the debris of `body`'s plane: every
    // particle beyond it, and every cell of another body whose centre is beyond it (the
    // body's own cells are not debris: a bulging wall is not perforated); with `debris_of`,
    // only the particles and cells of those bodies.
    mass_through,          // the debris' mass, kg
    momentum_through,      // the debris' momentum along the plane's normal, kg m/s
    perforated,            // 1 when any debris is beyond the plane, else 0
    debris_speed,          // the leading edge's speed along the normal: of the debris item
                           // farthest beyond the plane, m/s
    debris_cone_angle,     // half-angle (degrees) about the normal through the plane's point of
                           // the cone holding 95 % of the mass of the cloud's front half (the
                           // debris beyond half the leading edge's distance from the plane)
    debris_particle_mass,  // the mass of the particles beyond the plane, kg
    largest_fragment,      // the largest debris fragment's mass: cells beyond the plane joined
                           // through shared nodes, or one particle, kg
    // Of `body` itself, a plate whose front face the plane is (its normal across the plate):
    thickness_left,  // the smallest share of the plate's thickness still in it along a line
                     // across it: columns along the normal, each the cells whose reference
                     // centre lies in one square of side h (the median of (6 V0)^(1/3) over the
                     // cells centred within `within` of the normal through the plane's point: a
                     // cube's edge when it is split into six tets), the squares centred within
                     // `within`; a column's share is the reference volume of its cells still in
                     // the body (not destroyed, not particles; a scab of intact cells counts
                     // until it is particles) over that of all its cells; 1 untouched, 0 holed
    bulge,           // how far the plate's rear face has moved along the normal: the largest
                     // (x − X)·n over its nodes (the nodes farthest along n in reference
                     // positions) within `within` of the normal through the plane's point, of a
                     // cell still in the body (not destroyed, not particles: a plug or scab of
                     // intact cells that has come off counts until it is particles), m; the
                     // plane's point on the symmetry planes (mirror images are not searched)
  };
  /// Each measure's name in a case file and a summary, and its unit (SI; "" for a verdict or a
  /// ratio).
  static constexpr NameTable<Measure, 18> k_measure_names{
      {{Measure::length, "length"},
       {Measure::radius, "radius"},
       {Measure::mean_stress, "mean_stress"},
       {Measure::mean_pressure, "mean_pressure"},
       {Measure::velocity, "velocity"},
       {Measure::contact_duration, "contact_duration"},
       {Measure::contact_max_force, "contact_max_force"},
       {Measure::contact_mean_pressure, "contact_mean_pressure"},
       {Measure::hole_diameter, "hole_diameter"},
       {Measure::mass_through, "mass_through"},
       {Measure::momentum_through, "momentum_through"},
       {Measure::perforated, "perforated"},
       {Measure::debris_speed, "debris_speed"},
       {Measure::debris_cone_angle, "debris_cone_angle"},
       {Measure::debris_particle_mass, "debris_particle_mass"},
       {Measure::largest_fragment, "largest_fragment"},
       {Measure::thickness_left, "thickness_left"},
       {Measure::bulge, "bulge"}}};
  static constexpr NameTable<Measure, 18> k_measure_units{{{Measure::length, "m"},
                                                           {Measure::radius, "m"},
                                                           {Measure::mean_stress, "Pa"},
                                                           {Measure::mean_pressure, "Pa"},
                                                           {Measure::velocity, "m/s"},
                                                           {Measure::contact_duration, "s"},
                                                           {Measure::contact_max_force, "N"},
                                                           {Measure::contact_mean_pressure, "Pa"},
                                                           {Measure::hole_diameter, "m"},
                                                           {Measure::mass_through, "kg"},
                                                           {Measure::momentum_through, "kg m/s"},
                                                           {Measure::perforated, ""},
                                                           {Measure::debris_speed, "m/s"},
                                                           {Measure::debris_cone_angle, "deg"},
                                                           {Measure::debris_particle_mass, "kg"},
                                                           {Measure::largest_fragment, "kg"},
                                                           {Measure::thickness_left, ""},
                                                           {Measure::bulge, "m"}}};
  std::string name;  // shown in tables
  Measure measure = Measure::length;
  std::string body;   // length, radius, velocity, hole_diameter, the debris measures
  int axis = 2;       // 0, 1, 2 for x, y, z
  int component = 2;  // mean_stress: 0..5 in the order xx yy zz xy yz xz
  Vec3 region_min = Vec3::Zero(), region_max = Vec3::Zero();      // mean_stress, mean_pressure
  Vec3 plane_point = Vec3::Zero(), plane_normal = Vec3::UnitZ();  // the debris measures (unit n)
  std::vector<std::string> debris_of;  // the debris measures: only these bodies (empty: all)
  double within = 0.0;     // the debris measures: > 0, only within this distance of the normal
                           // through the plane's point (a wall's footprint), m
  double area = 0.0;       // contact_mean_pressure
  double time = 0.0;       // > 0: measured at the first step at or after this time, s; 0: the end
  double value = 0.0;      // the reference; NaN: measured and reported, not judged
  double tolerance = 0.0;  // allowed relative error
  std::string source;      // where the reference comes from
  /// physical: an analytical solution, a published experiment or converged result; regression:
  /// the program's own earlier answer (another case, a finer run), which guards against
  /// change but proves nothing about the physics.
  std::string kind = "physical";
};

struct ReferenceResult {
  const ReferenceSpec* spec = nullptr;
  double measured = 0.0;
  double relative_error = 0.0;  // (measured − value) / |value|
  bool pass = false;            // true for a measure without a reference value once measured
  bool judged = true;           // false: the spec has no reference value (relative_error is NaN)
  std::string error;            // why it could not be measured (then measured is NaN, pass false)
};

/// Figures of the whole run that some references measure.
struct RunFigures {
  double contact_first_time = -1.0, contact_last_time = -1.0;
  double contact_max_force = 0.0;
  double contact_impulse = 0.0;     // Σ of normal contact impulses over the run, N s
  std::vector<Vec3> body_velocity;  // mass-averaged, at the end
};

/// Measures each reference on the final state and the run's figures. A reference with
/// nothing to measure (unknown body, empty region, no contact) is reported as missed, with
/// the reason in `error`.
std::vector<ReferenceResult> evaluate_references(const std::vector<ReferenceSpec>& refs,
                                                 const Model& model, const State& st,
                                                 const RunFigures& run = {});

/// The references of a run as it goes: those with a `time` measured at the first step at or
/// after it (`measure_due` after each step), the rest at the end (`finish`), in the case's order.
class ReferenceRecorder {
 public:
  explicit ReferenceRecorder(const std::vector<ReferenceSpec>& refs);
  /// Whether a timed reference not yet measured is due at time t (a distributed run gathers its
  /// state first).
  bool due(double t) const;
  void measure_due(double t, const Model& model, const State& st, const RunFigures& run);
  std::vector<ReferenceResult> finish(const Model& model, const State& st,
                                      const RunFigures& run = {});
  /// What a checkpoint holds of it: the references measured so far.
  void persist(Archive& ar);

 private:
  const std::vector<ReferenceSpec>& refs_;
  std::vector<std::optional<ReferenceResult>> done_;
};

}  // namespace tc
