// System::device_memory(): the sizes of the buffers a System owns, by role (benchmarks, resource estimates).
// Kept apart from system.cpp so the step code and this bookkeeping change independently.
#include "gpu/system_impl.h"

namespace wetdem {

DeviceMemory System::device_memory() const {
  const BufferSet& b = *impl_->B;
  DeviceMemory m;
  for (int s = 0; s < 2; ++s) {
    for (const vk::Buffer& f : b.pset[s]) m.particle_sets += f.size();
    for (const vk::Buffer& f : b.eset[s]) m.entry_sets += f.size();
    m.entry_capacity += b.capacity(uint32_t(s));
  }
  for (const vk::Buffer* f : {&b.ref_pos, &b.cell_key, &b.sort_val, &b.cnt_scan, &b.own_scan, &b.p_share,
                              &b.p_gain, &b.p_full, &b.p_offer})
    m.particle_scratch += f->size();
  for (const vk::Buffer* f : {&b.pair_f, &b.pair_t, &b.partner, &b.owners}) m.entry_scratch += f->size();
  if (b.event_slots) m.entry_scratch += b.ev.size();
  m.grid = b.cell_start.size() + b.cell_end.size();
  m.control = b.ctl.size() + b.params.size() + b.table_buf.size() + b.smp.size() + b.smp_pairs.size();
  return m;
}

}  // namespace wetdem
