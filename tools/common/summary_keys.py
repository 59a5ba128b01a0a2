"""The names the tools read from the program's output files, in one place: summary.json (a
run), history.csv (a run, one row per sampled step), sweep.csv (`tetcontact sweep`),
limit.csv (`tetcontact limit`), `stress --json` and `profile --json`, and the measures the
shipped cases name. The program writes them in src/app/ (run.cpp's summary_json, sweep.cpp,
limit.cpp, stress.cpp, profile.cpp) and src/io/output.cpp (history.csv); a renamed key is
renamed here once (tests/tools/test_summary_keys.py runs small cases and checks that every
path below is in their summaries).

A key of a JSON document is a path: the tuple of names from the top, `("energy",
"balance_error_max")` for summary["energy"]["balance_error_max"]. `get(doc, PATH)` follows one
and names the missing key and the file when it is not there; list items (bodies, expect,
references, ...) are read by their item keys (NAME, MEASURED, ...)."""


class MissingKey(KeyError):
    """A path that is not in the document; str() says which key of which file."""

    def __str__(self):
        return self.args[0]


def get(doc, path, source="summary.json"):
    """doc[path[0]][path[1]]...; MissingKey naming the path and `source` when a name is not
    there."""
    value = doc
    for k, name in enumerate(path):
        if not isinstance(value, dict) or name not in value:
            raise MissingKey(f"{source}: no key {'.'.join(path[:k + 1])}")
        value = value[name]
    return value


def has(doc, path):
    """Whether the path is in the document (and not null)."""
    try:
        return get(doc, path) is not None
    except MissingKey:
        return False


# summary.json: every run ----------------------------------------------------------------------
CASE = ("case",)
CASE_FILE = ("case_file",)
STATUS = ("status",)
STEPS = ("steps",)
TIME = ("time",)
END_BY = ("end", "by")
END_WHEN_RELEASED = ("end", "when_released")
END_LAST_PUSH = ("end", "last_push")
WALL_SECONDS = ("wall_seconds",)
MODULES = ("modules",)               # the stages the run made ("broadphase:grid", ...)
MESH_NODES = ("mesh", "nodes")
MESH_TETS = ("mesh", "tets")
MESH_MULTIPLICITY = ("mesh", "multiplicity")  # parts that make the whole (symmetry planes)
TIMINGS = ("timings",)               # seconds per stage, by the stage's name (below)
ENERGY_BALANCE_ERROR = ("energy", "balance_error")
ENERGY_BALANCE_ERROR_MAX = ("energy", "balance_error_max")
MOMENTUM_ERROR = ("momentum", "relative_error")
MASS_ERROR = ("mass", "relative_error")
BODIES = ("bodies",)                 # a list of items: NAME, MASS, VELOCITY, BBOX_MIN, BBOX_MAX
TIME_STEP_MIN = ("time_step", "min")
TIME_STEP_FIRST = ("time_step", "first")
TIME_STEP_COLLAPSES = ("time_step", "collapses")  # a list, one item per reported fall
PENETRATION = ("penetration",)
MAX_DEPTH_OVER_H = ("penetration", "max_depth_over_h")  # null where not measured
MAX_NODES_INSIDE = ("penetration", "max_nodes_inside")
MAX_CROSSINGS = ("penetration", "max_crossings")
PENETRATION_MEASURED_AT = ("penetration", "measured_at")  # "every step" or "output frames"
PENETRATION_SAMPLES = ("penetration", "samples")
FRACTURE_ENABLED = ("fracture", "enabled")    # fracture on: frames always carry "damage"
FRACTURE_PARTICLES = ("fracture", "particles")
FRACTURE_MASS_TO_PARTICLES = ("fracture", "mass_to_particles")
SAFEGUARDS_ERODED = ("safeguards", "eroded")                   # null without erosion
SAFEGUARDS_PARTICLES_MOVED_OUT = ("safeguards", "particles_moved_out")  # null without particles
CONTACT = ("contact",)

# summary.json: some runs (the condition after each) -------------------------------------------
PARAMETERS = ("parameters",)         # a case with `parameters:` (by their names)
EXPECT = ("expect",)                 # a case with `expect:` (items NAME, BOUND, MEASURED, PASS)
EXPECT_PASS = ("expect_pass",)       # idem
REFERENCES = ("references",)         # a case with `reference:` (items NAME, MEASURED, PASS)
PARTICLES_INSIDE_AT_END = ("penetration", "particles_inside_at_end")  # fracture particles
FRACTURE_DEBRIS = ("fracture", "debris")  # particles: "points" or "sph"
FRACTURE_SPH_NEIGHBOURS = ("fracture", "sph", "neighbours_per_particle")  # debris sph
ENERGY_CONTACT_WORK = ("energy", "contact_work")  # null without contact or particles
ENERGY_TOTAL_INITIAL = ("energy", "total_initial")
FRACTURE_FROM_BODIES = ("fracture", "from_bodies")  # particles (items NAME, PARTICLES, MASS)
FRACTURE_DUCTILE_FAILED = ("fracture", "ductile_failed")  # a material with ductile failure
# Of those, the cells whose damage accrued mostly with the failure strain at its floor; each
# FRACTURE_FROM_BODIES item then has DUCTILE_FAILED and DUCTILE_FAILED_AT_FLOOR, its cells'.
FRACTURE_DUCTILE_FAILED_AT_FLOOR = ("fracture", "ductile_failed_at_floor")
DUCTILE_FAILED = "ductile_failed"
DUCTILE_FAILED_AT_FLOOR = "ductile_failed_at_floor"
VERIFICATION = ("contact", "verification")  # contact.verify on; its keys below
VERIFY_FAILED_AFTER_PASSES = VERIFICATION + ("failed_after_passes",)
VERIFY_STEPS_FAILED = VERIFICATION + ("steps_failed",)
VERIFY_STEP_CUTS = VERIFICATION + ("step_cuts",)  # steps taken again with half their step
VERIFY_STEPS_WITH_ZONES = VERIFICATION + ("steps_with_zones",)
VERIFY_IMPACT_ZONES = VERIFICATION + ("impact_zones",)
VERIFY_TRANSLATED_ZONES = VERIFICATION + ("translated_zones",)
VERIFY_FROZEN_ZONES = VERIFICATION + ("frozen_zones",)
COMMUNICATION_SECONDS = ("parallel", "communication_seconds")  # a run under mpirun

# The top-level blocks of results a distributed run must reproduce (tools/docs/tables.py mpi).
RESULT_BLOCKS = ["steps", "energy", "momentum", "bodies", "contact"]

# Keys of list items (bodies, expect, references, fracture.from_bodies, stress scenes).
NAME = "name"
MASS = "mass"
VELOCITY = "velocity"
BBOX_MIN = "bbox_min"
BBOX_MAX = "bbox_max"
BOUND = "bound"
MEASURED = "measured"
PASS = "pass"
PARTICLES = "particles"

# Stage names in summary.json's timings (seconds) and history.csv's seconds_<stage>.
STAGE_ELEMENTS = "elements"
STAGE_VERIFY = "verify"
CONTACT_STAGES = ["broadphase", "narrowphase", "response"]
PARTICLE_STAGES = ["particles", "fracture"]
STAGE_OUTPUT = "output"
STAGE_BALANCE = "balance"

# Bound names of `expect:` (summary.json's expect items, `stress --json` scenes' expect).
EXPECT_DEPTH = "max_depth_over_h"
EXPECT_ENERGY = "energy_balance"

# Measures the shipped cases name (their `reference:` entries, summary.json's references).
HOLE_DIAMETER = "bumper hole diameter"              # whipple.yaml
DEBRIS_SPEED = "debris leading-edge speed"
DEBRIS_CONE_ANGLE = "debris cone half-angle"
DEBRIS_MASS = "debris mass"
DEBRIS_PARTICLE_MASS = "debris mass in particles"
LARGEST_FRAGMENT = "largest fragment"
WALL_PERFORATED = "wall perforated"
MASS_THROUGH_WALL = "mass through the wall"
WALL_THICKNESS_LEFT = "wall thickness left"
WALL_BULGE = "wall bulge"
HEL = "elastic precursor (HEL)"                     # plate-impact-1d.yaml

# history.csv: one column per stage's wall-clock seconds, this prefix and the stage's name.
HISTORY_SECONDS_PREFIX = "seconds_"

# sweep.csv: the varied keys, then these columns (then error:<reference> columns, then the rest).
SWEEP_STATUS = "status"              # "ok" or why not
SWEEP_WALL_SECONDS = "wall_seconds"
SWEEP_STEPS = "steps"
SWEEP_TETS = "tets"
SWEEP_ERROR = "error"
SWEEP_ENERGY_BALANCE_MAX = "energy_balance_max"

# limit.csv: the varied key (when --vary), then these.
LIMIT_KEY = "key"
LIMIT_LO = "lo"                      # the largest value found not meeting the criterion
LIMIT_HI = "hi"                      # the smallest found meeting it
LIMIT_STATUS = "status"              # "ok" or why not

# `stress --json`: {"scenes": [...]}, each scene with these.
STRESS_SCENES = "scenes"
SCENE_STEPS = "steps"
SCENE_PASS = "pass"
SCENE_MOMENTUM_ERROR = "momentum_error"
SCENE_BALANCE_ERROR = "balance_error"
SCENE_DEPTH_OVER_H = "max_depth_over_h"
SCENE_NODES_INSIDE = "nodes_inside"
SCENE_CROSSINGS = "crossings"
SCENE_EXPECT = "expect"

# `profile --json`: a list of methods, each with these.
PROFILE_METHOD = "method"
PROFILE_PRIMITIVES = "primitives"
PROFILE_CANDIDATES = "candidates_per_step"
PROFILE_CONTACTS = "contacts_per_step"
PROFILE_PRUNING = "pruning_ratio"
PROFILE_SECONDS = "seconds_per_step"  # {PROFILE_BUILD, PROFILE_QUERY, PROFILE_STEP}
PROFILE_BUILD, PROFILE_QUERY, PROFILE_STEP = "build", "query", "step"
PROFILE_BROADPHASE_SHARE = "broadphase_share"
PROFILE_CONTACT_SHARE = "contact_share"

# `ccd --json`: {"ee": {...}, "vf": {...}}, each with these (false positives and negatives with
# ground truth only; "fcl" with --fcl: its collisions, errors and mean time).
CCD_QUERIES = "queries"
CCD_COLLISIONS = "collisions"
CCD_MEAN_NS = "mean_ns"
CCD_FALSE_POSITIVES = "false_positives"
CCD_FALSE_NEGATIVES = "false_negatives"
CCD_FCL = "fcl"

# The paths every run's summary.json holds (tests/tools/test_summary_keys.py checks them).
ALWAYS = [CASE, CASE_FILE, STATUS, STEPS, TIME, END_BY, END_WHEN_RELEASED, END_LAST_PUSH,
          WALL_SECONDS, MODULES, MESH_NODES, MESH_TETS, TIMINGS, ENERGY_BALANCE_ERROR, ENERGY_BALANCE_ERROR_MAX, MOMENTUM_ERROR, MASS_ERROR,
          BODIES, TIME_STEP_MIN, TIME_STEP_FIRST, TIME_STEP_COLLAPSES, PENETRATION,
          MAX_DEPTH_OVER_H, PENETRATION_SAMPLES, FRACTURE_ENABLED, FRACTURE_PARTICLES,
          FRACTURE_MASS_TO_PARTICLES, SAFEGUARDS_ERODED, SAFEGUARDS_PARTICLES_MOVED_OUT, CONTACT]
