// Case files: YAML, SI units. The full schema with an example of every key is in
// data/cases/README.md. load_case validates everything before anything runs.
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tetcontact/diagnostics/gauges.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/diagnostics/shield_equation.hpp"
#include "tetcontact/io/vtk.hpp"
#include "tetcontact/material/material.hpp"
#include "tetcontact/mesh/mesh.hpp"
#include "tetcontact/model/model.hpp"
#include "tetcontact/model/names.hpp"

namespace tc {

/// Bad input in a case file or an override: the message reads
/// "FILE:LINE:COL: key 'a.b.c': what is wrong" (or "--set a.b.c: ..." for an override).
struct CaseError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct MeshSpec {
  enum class Kind { box, plate, cylinder, sphere, file };
  Kind kind = Kind::box;
  Vec3 size = Vec3::Zero();           // box, plate
  std::array<int, 3> cells{1, 1, 1};  // box
  int cells_through_thickness = 0;    // plate
  double core = 0.0;                  // plate: > 0, graded outside a core this wide (m)
  double core_growth = 1.2;           // plate: the graded cells' ratio (the key `growth`)
  double radius = 0.0;                // cylinder, sphere
  double height = 0.0;                // cylinder
  int cells_across = 0;               // cylinder, sphere
  int cells_axial = 0;                // cylinder
  int split = 6;                      // 5, 6 or 12
  Vec3 refine_toward = Vec3::Zero();  // sphere: grading toward a pole (±x, ±y, ±z)
  double refine_factor = 1.0;
  double cell_size = 0.0;  // sphere by Delaunay refinement (> 0) instead of the lattice
  double refine_size = 0.0;
  double growth = 0.15;
  std::string file;      // file: path resolved against the case file's folder
  std::string physical;  // file: physical volume name ("" = all tets)
};

struct TransformOp {
  enum class Kind { translate, rotate, scale };
  Kind kind = Kind::translate;
  Vec3 vector = Vec3::Zero();  // translate offset or rotation axis
  double value = 0.0;          // rotation angle (degrees) or scale factor
};

struct Region {  // axis-aligned box, inclusive
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
};

struct VelocityRegion {
  Region region;
  Vec3 velocity = Vec3::Zero();
};

struct BodySpec {
  std::string name;
  std::string material;
  MeshSpec mesh;
  std::vector<TransformOp> transform;
  Vec3 velocity = Vec3::Zero();
  /// Rigid rotation added to `velocity`: ω × (x − c), c the centre of the body's bounding box
  /// after its transform (rad/s).
  Vec3 angular_velocity = Vec3::Zero();
  std::vector<VelocityRegion> velocity_regions;
};

struct BoundarySpec {
  std::string key;  // "boundary_conditions.N", for messages
  std::string body;
  std::optional<Region> region;
  bool fixed = true;  // type: fixed (all listed components zero) or velocity
  Vec3 velocity = Vec3::Zero();
  std::array<bool, 3> components{true, true, true};
};

struct OutputSpec {
  double interval = 0.0;  // simulated seconds between frames
  /// `gauges:`: the points recorded to gauges.csv (diagnostics/gauges.hpp), a row at the first
  /// step at or after each multiple of gauge_interval (0: every step) and at the end.
  std::vector<GaugeSpec> gauges;
  double gauge_interval = 0.0;
  std::vector<std::string> fields;
  long history_every = 1;                    // steps between history rows
  VtuFormat format = VtuFormat::compressed;  // how the frames' arrays are stored
  /// diagnostics.every_step: the penetration measured at every step (history columns
  /// nodes_inside, crossings), not only at the frames.
  bool penetration_every_step = false;
  /// `output.checkpoint`: the complete state written every `checkpoint_interval` simulated
  /// seconds or every `checkpoint_steps` steps (one of them; 0: no checkpoints), keeping the
  /// newest `checkpoint_keep` (io/checkpoint.hpp).
  double checkpoint_interval = 0.0;
  long checkpoint_steps = 0;
  int checkpoint_keep = 2;
};

/// Average nodal pressure (anti-locking): on for plastic materials (auto), all, or none.
enum class AnpMode { automatic, on, off };
inline constexpr NameTable<AnpMode, 3> k_anp_mode_names{
    {{AnpMode::automatic, "auto"}, {AnpMode::on, "true"}, {AnpMode::off, "false"}}};

/// `campaign:`: how `tetcontact campaign` runs the case once per row of a table of experiments
/// (app/campaign.hpp): which column sets which parameter, which columns name a library material
/// for which material slot, and which summary measure is compared with which column.
struct CampaignSpec {
  struct Parameter {
    std::string name;    // a parameter the case declares
    std::string column;  // its value: the column's number times `factor`
    double factor = 1.0;
  };
  struct MaterialSlot {
    std::string slot;                  // a material of the case: its `from` is set
    std::vector<std::string> columns;  // the key: these columns' values joined by " | "
    /// Table key → library entry; a row's key is looked up whole, then without its last
    /// column, and so on (so "Steel 4340 | Gust 1982" may have an entry of its own and
    /// "Steel 4340" one for the rest).
    std::vector<std::pair<std::string, std::string>> names;
  };
  struct Comparison {
    std::string predicted;   // a `reference:` measure's name in the summary
    std::string column;      // the measured value (absent from a table: predictions only)
    double factor = 1.0;     // measured = column × factor (numbers)
    double tolerance = 0.0;  // |predicted / measured − 1| counted as within it (0: not counted)
    /// Categories (P: 1, NP: 0): the column holds a category, the prediction is the category
    /// whose value is nearest the measure's. Empty: the column holds a number.
    std::vector<std::pair<std::string, double>> categories;
  };
  bool declared = false;
  bool units_row = false;  // a row of units under the header row
  std::vector<Parameter> parameters;
  std::vector<MaterialSlot> materials;
  std::vector<Comparison> compare;
  std::vector<std::string> group_by;  // columns whose values split the statistics
};

/// `shield_equation:`: Christiansen's equation for the case's Whipple-shield shot
/// (diagnostics/shield_equation.hpp), printed at the start of a run and written to its summary
/// beside the verdict of the `reference:` entry it names, with a note when the two disagree.
struct ShieldEquationSpec {
  bool declared = false;
  WhippleShot shot;  // the densities are the named bodies' materials'
  std::string projectile_body, bumper_body;
  std::string verdict;  // a `reference:` entry of measure perforated
};

/// `mesh_study:`: what a mesh study measured moving on cells coarser than the case's own, said
/// by a run whose cells are coarser. Each `cells_across` entry (a name and an expression, as
/// "cells through the bumper: = tb / hb") is evaluated with the run's parameters and with the
/// file's own (no override); the run is coarser when any has fewer with the run's.
struct MeshStudySpec {
  struct Resolution {
    std::string name;
    double run = 0.0, file = 0.0;  // cells across, with the run's parameters and the file's
    bool coarser() const { return run < file * (1.0 - 1e-9); }
  };
  std::vector<Resolution> cells_across;
  std::string note;
  bool coarser() const {
    for (const Resolution& r : cells_across)
      if (r.coarser()) return true;
    return false;
  }
};

struct Case {
  std::string file;  // path as given
  std::string name;
  std::string description;
  double end_time = 0.0;
  /// `end_when_released`: the run ends once no wall and no contact has pushed on any body for
  /// this long (s) after the first push, or at end_time; 0 (the default): at end_time.
  double end_when_released = 0.0;
  double cfl = 0.5;
  long max_steps = 10'000'000;
  int threads = 0;  // solver.threads; 0: all cores (auto)
  double viscosity_linear = 0.06;
  double viscosity_quadratic = 1.5;
  AnpMode average_nodal_pressure = AnpMode::automatic;
  double anp_stabilization = 0.02;  // solver.anp_stabilization (ElementOptions)
  std::string material_library;     // resolved path of the library used ("" if none)
  // `parameters:`: the values a case's expressions ("= ...") use, in file order.
  std::vector<std::pair<std::string, double>> parameters;
  std::vector<Material> materials;
  std::vector<RigidWall> walls;
  /// `symmetry`: the planes the bodies are cut along (the model is the part on their positive
  /// side; mesh/symmetry.hpp).
  std::vector<SymmetryPlane> symmetry;
  std::vector<BodySpec> bodies;
  std::vector<BoundarySpec> boundary_conditions;
  OutputSpec output;
  std::vector<ReferenceSpec> references;
  bool contact = false;
  /// contact.initial_overlap: bodies that overlap at t = 0 stop the setup (error, the
  /// default) or run as given (allow).
  bool allow_initial_overlap = false;
  ContactSettings contact_settings;  // pairs' body indices are resolved by the setup
  std::vector<std::array<std::string, 2>> contact_pair_bodies;  // parallel to its pairs
  bool fracture = false;
  bool particles = true;  // fracture.particles: destroyed boundary cells become particles
  double erosion_step_ratio = 0.01;  // fracture.erosion_step_ratio (0: off)
  bool erosion_per_body = false;     // fracture.erosion_reference: body (true) or model
  bool fragment_clusters = false;    // fracture.fragments: clusters (true) or cells
  bool sph_debris = false;           // fracture.debris: sph (true) or points
  SphSettings sph;                   // fracture.sph
  /// `expect`: bounds the run must hold (run --check exits 1 otherwise), by summary figure:
  /// momentum_error, energy_balance (balance_error_max), max_depth_over_h, particles_inside
  /// (at the end), in the order given.
  std::vector<std::pair<std::string, double>> expect;
  CampaignSpec campaign;
  ShieldEquationSpec shield_equation;
  MeshStudySpec mesh_study;

  const Material& material(const std::string& name) const;
};

/// Output fields a case may ask for.
const std::vector<std::string>& known_output_fields();

/// The material library shipped with tetcontact (data/materials.yaml).
std::string default_material_library();

/// Reads and validates a material library: name → material, each validated like a case's
/// material (the message names the library file).
std::vector<Material> load_material_library(const std::string& path);

/// The case file's content re-emitted as YAML: its keys and values in order, without its
/// comments and layout (what a run's key holds of the case: an edited comment changes no run).
std::string canonical_case_text(const std::string& path);

/// Reads and validates a case file, applying `overrides` ("path.to.key=value", the value in
/// YAML syntax; list entries are addressed by index: bodies.0.velocity=[1,0,0]) first.
Case load_case(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace tc
