// Everything the solver needs from a case, as plain data: the data layer below every stage
// (ARCHITECTURE.md, "Folder order"). Built once by the setup and never changed during a run;
// what a run changes (positions, stresses, cells turned into particles, the surfaces they
// expose) lives in State and in the stages that own it.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tetcontact/material/material.hpp"
#include "tetcontact/mesh/mesh.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/model/names.hpp"

namespace tc {

enum class FrictionMode { slip, stick, coulomb };
inline constexpr NameTable<FrictionMode, 3> k_friction_names{{{FrictionMode::slip, "slip"},
                                                              {FrictionMode::stick, "stick"},
                                                              {FrictionMode::coulomb, "coulomb"}}};

// The names of the material's enumerations (material/ stands below this layer's names.hpp).
inline constexpr NameTable<EosKind, 3> k_eos_names{{{EosKind::linear, "linear"},
                                                    {EosKind::mie_gruneisen, "mie_gruneisen"},
                                                    {EosKind::tillotson, "tillotson"}}};
inline constexpr NameTable<StrengthModel, 3> k_strength_names{
    {{StrengthModel::bilinear, "bilinear"},
     {StrengthModel::johnson_cook, "johnson_cook"},
     {StrengthModel::steinberg_guinan, "steinberg_guinan"}}};

/// Friction of one body pair (case file `contact.pairs`).
struct PairFriction {
  Index body_a = 0, body_b = 0;
  FrictionMode mode = FrictionMode::slip;
  double coefficient = 0.0;
};

struct ContactSettings {
  std::string broadphase = "fcl_tree";
  double margin = 0.0;  // m, added to every swept box
  int passes = 3;       // sequential correction passes per step
  enum class Order { input, lighter_first } order = Order::lighter_first;
  /// face: the normal of the penetrated face (default); node: minus the averaged normal of
  /// the faces around the penetrating node (the contact-boundary notes).
  enum class Normal { face, node } normal = Normal::face;
  static constexpr NameTable<Order, 2> k_order_names{
      {{Order::lighter_first, "lighter_first"}, {Order::input, "input"}}};
  static constexpr NameTable<Normal, 2> k_normal_names{
      {{Normal::face, "face"}, {Normal::node, "node"}}};
  FrictionMode mode = FrictionMode::slip;  // for body pairs not listed in `pairs`
  double coefficient = 0.0;
  std::vector<PairFriction> pairs;
  /// The contact-boundary notes' binding lists (broadphase/binding_lists.hpp): candidates from
  /// boxes enlarged by a reach r = 0.2·dx (half of the 0.4·dx the notes leave between Rs and
  /// 0.75·Rmax; dx the smallest mean tet edge of the bodies), reused until a surface node has
  /// moved r from where the lists were built. Off: the exact swept boxes of every step.
  bool binding_lists = true;
  /// Dobritsa et al.'s edge–edge contact on top of node–face: surface edges of different bodies
  /// that cross during the step (exact CCD) get the reaction of eqs. (11)–(12). On by default;
  /// off (`contact.edge_edge: false`) for studies of node–face contact alone.
  bool edge_edge = true;
  /// Verify every step's motion with the exact CCD (verify/verify.hpp); pairs that fail
  /// get further passes, then a shorter step (`step_cuts`), then rigid impact zones
  /// (response/impact_zones.hpp). On by default:
  /// with it no edge crosses a face and no node ends inside a cell at any step's end
  /// (docs/design/verification.md); off (`contact.verify: false`) for studies.
  bool verify = true;
  /// With `verify`: how many times a step whose pairs still fail after the further passes is
  /// taken again with half the step before rigid impact zones take them (0: zones at once).
  /// The passes linearize each pair's constraint over the step; halving the step quarters what
  /// that misses (second order in the motion) and leaves the bodies' relative motion as it is,
  /// where a rigid zone takes it away (docs/design/verification.md).
  int step_cuts = 4;
  /// The stand-off contacts aim at (m), beyond the rounding margin: a pair closing within a
  /// step stops this far apart; an edge pair already closer is pushed back to it
  /// (ContactPoint::push_speed), a node–face pair or a rescued pair held. Below 0: 1e-5 of the
  /// smallest mean tet edge of the bodies (k_separation_fraction). The stand-off takes up the
  /// second-order error of the step's linearized contacts (faces that turn, edges that slide onto
  /// the next face): aimed at exactly touching, with `verify`, the bars' conforming faces failed on
  /// 380 of 581 steps. With a stand-off of 1e-6 of an edge and every pair held, the cylinders'
  /// interface drifted to touching and needed impact zones on 485 of 584 steps
  /// (docs/design/verification.md).
  double separation = -1.0;
  static constexpr double k_separation_fraction = 1e-5;
  /// Edge pairs within the stand-off are pushed back to it at most at this fraction of the
  /// bodies' fastest wave speed (ContactPoint::push_speed): 0.63 m/s in aluminium, a stand-off
  /// of 1e-5 of an edge restored within a step. In trials at a tenth of it, the cylinders needed
  /// a zone that took 22 to 28 J of their 1,054; pushed at the stand-off over the run's first
  /// step instead, two blocks pressed at 10 m/s with the step forced down to 1e-12 s
  /// (stability/tiny-step) ended at 1,567 m/s.
  static constexpr double k_push_fraction = 1e-4;
  /// The kinetic energy each exchange between bodies or particles dissipates becomes internal
  /// energy of the cells and particles at its nodes (response/heat.hpp); off (the default until
  /// the validation tables are measured with it): it is only booked, as the contact work.
  bool heat = false;
};

struct RigidWall {
  std::string name;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, pointing to the side the bodies are on
  double friction = 0.0;        // Coulomb coefficient k (0: ideal slip)
  /// A symmetry plane's wall: what strikes it meets its mirror image (its exchanges heat as a
  /// contact between bodies does, response/heat.hpp).
  bool mirror = false;
};

/// Options of the element formulation, from the case's `solver` section.
struct ElementOptions {
  double viscosity_linear = 0.06;            // C1 of bulk_viscosity
  double viscosity_quadratic = 1.5;          // C2 of bulk_viscosity
  std::vector<char> average_nodal_pressure;  // per material: pressure averaged at nodes
  /// α of the average nodal pressure's stabilization: a tet's pressure gains α K (J̄ − J) / J,
  /// J its volume ratio, J̄ the mean of its nodes' (element.cpp, pass 3).
  double anp_stabilization = 0.02;
  bool fracture = false;  // spall damage and loosening (Dobritsa et al.)
  /// Erosion (a safeguard, fracture.erosion_step_ratio): a tet t whose stable step squared
  /// falls below its body's limit, erode_dt2[tet_body[t]], is listed in ForceResult::eroding
  /// (empty: off). tet_body is the mesh's (ElementStage::set_erosion_limits).
  std::vector<double> erode_dt2;
  std::span<const Index> tet_body;
};

/// Prescribed velocity components on a set of nodes (a fixed node prescribes zero).
struct VelocityConstraint {
  std::string name;  // e.g. "boundary_conditions.0"
  std::vector<Index> nodes;
  std::array<bool, 3> components{true, true, true};
  Vec3 velocity = Vec3::Zero();
  bool mirror = false;  // a symmetry plane's: each of its nodes stands for 2 of the whole's
};

/// SPH debris (fracture.debris: sph; sph/sph.hpp): the smoothing length h of a particle made
/// from a cell is `smoothing` times the cell's size V0^(1/3); Monaghan's viscosity (α, β) and
/// artificial stress (ε); the particles' stable step is `step_factor` h / (c + 1.2 (α c + β μ)),
/// times the solver's cfl (sph::Options::step_factor).
struct SphSettings {
  double smoothing = 1.3;
  double alpha = 1.0;
  double beta = 2.0;
  double artificial_stress = 0.3;
  double step_factor = 0.6;
  bool faces = true;  // particles meet the bodies' faces through their kernel (else by contact)
};

struct Model {
  Mesh mesh;
  std::vector<Surface> surfaces;     // one per body
  std::vector<Material> materials;   // distinct materials used
  std::vector<Index> body_material;  // body → materials index
  std::vector<VelocityConstraint> constraints;
  std::vector<RigidWall> walls;
  std::optional<ContactSettings> contact;  // the contact stage, when the case enables it
  std::vector<Vec3> initial_velocity;      // per node
  ElementOptions element;                  // viscosity, average nodal pressure per material
  bool particles = false;  // destroyed boundary cells become particles (fracture.particles)
  /// Erosion (with particles): a cell whose stable step falls below this fraction of the
  /// first step's becomes a particle wherever it is (fracture.erosion_step_ratio; 0: off).
  double erosion_step_ratio = 0.0;
  /// fracture.erosion_reference: body — the first step is the cell's own body's (its
  /// smallest cell's); false (model): the whole model's.
  bool erosion_per_body = false;
  /// fracture.fragments: clusters — a converted cell joins the particle of a neighbour that
  /// coheres with it (fracture/particles.hpp); false: each cell its own particle.
  bool fragment_clusters = false;
  /// fracture.debris: sph — a converted cell becomes an SPH particle that keeps its material
  /// and state (sph/); false: a point mass (Dobritsa et al.'s particles).
  bool sph_debris = false;
  SphSettings sph;
  /// Contact heat (contact.heat, response/heat.hpp): also with contact between bodies off, for
  /// the particles' exchanges.
  bool contact_heat = false;
};

/// Surface nodes of every body, sorted (the nodes that can touch a wall or another body).
std::vector<Index> all_surface_nodes(const std::vector<Surface>& surfaces);

struct SolverSettings {
  double end_time = 0.0;
  /// The run ends earlier, once no wall (symmetry planes aside) and no contact between bodies or
  /// particles has pushed for this long (s) after the first push; 0: only at end_time.
  double end_when_released = 0.0;
  double cfl = 0.5;
  long max_steps = 10'000'000;
  int threads = 0;  // threads of the parallel loops; 0: all cores (results do not depend on it)
};

}  // namespace tc
