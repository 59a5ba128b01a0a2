#include "tetcontact/solver/run_loop.hpp"

namespace tc {

std::string run_to_end(Simulation& sim, const RunHooks& hooks) {
  try {
    for (long steps = 0; !sim.done(); ++steps) {
      if (hooks.max_steps >= 0 && steps >= hooks.max_steps) return "stopped";
      sim.step();
      if (hooks.references && hooks.references->due(sim.state().t)) {
        sim.gather_state();  // distributed: every tet's fields, as the measures read them
        hooks.references->measure_due(sim.state().t, sim.model(), sim.state(), sim.run_figures());
      }
      if (hooks.each_step) hooks.each_step(sim);
      if (hooks.stop && hooks.stop()) return "interrupted";
    }
    sim.finish();
  } catch (const RunFailure& e) {  // in a distributed run: on every rank alike
    return std::string("failed: ") + e.what();
  }
  return "ok";
}

}  // namespace tc
