#include "support/lockstep.h"

namespace wetdem::test {

StepPair step_both(ref::ReferenceSystem& ref_sys, System& gpu_sys, const SystemState& s) {
  ref_sys.set_state(s);
  gpu_sys.upload(s);
  ref_sys.step();
  gpu_sys.step(1);
  return {ref_sys.state(), gpu_sys.download()};
}

std::vector<BridgeRow> bridges_and_flags(const SystemState& s) {
  std::vector<BridgeRow> out;
  for (const auto& p : s.pairs)
    if (p.bridge > 0 || p.flags) out.emplace_back(p.id_i, p.id_j, p.bridge, p.flags);
  return out;
}

}  // namespace wetdem::test
