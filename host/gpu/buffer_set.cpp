#include "gpu/buffer_set.h"

#include <algorithm>

#include "gpu/gpu_layout.h"

namespace wetdem::gpu {

BufferSet::BufferSet(vk::Context& c, uint32_t num_particles, uint32_t num_cells, uint32_t runs,
                     uint32_t slots, bool events)
    : ctx(c), n(num_particles), cells(num_cells), wall_slots(slots), event_slots(events) {
  const uint64_t N = std::max<uint32_t>(n, 1);
  ctl = vk::Buffer(ctx, ctl::kWords * 4);
  params = vk::Buffer(ctx, uint64_t(std::max<uint32_t>(runs, 1)) * sizeof(GpuParams));
  run_of = vk::Buffer(ctx, N * 4);
  smp = vk::Buffer(ctx, uint64_t(smp::kHead + smp::kRun * std::max<uint32_t>(runs, 1)) * 4);
  table_buf = vk::Buffer(ctx, sizeof(GpuTable));
  for (int s = 0; s < 2; ++s)
    for (uint32_t f = 0; f < kNumParticleFields; ++f)
      pset[s][f] = vk::Buffer(ctx, N * particle_field_bytes(f, wall_slots));
  ref_pos = vk::Buffer(ctx, N * 16);
  cell_key = vk::Buffer(ctx, N * 4);
  sort_val = vk::Buffer(ctx, N * 4);
  cnt_scan = vk::Buffer(ctx, N * 4);
  own_scan = vk::Buffer(ctx, N * 4);
  cell_start = vk::Buffer(ctx, uint64_t(std::max<uint32_t>(cells, 1)) * 4);
  cell_end = vk::Buffer(ctx, uint64_t(std::max<uint32_t>(cells, 1)) * 4);
  p_share = vk::Buffer(ctx, N * 8);
  p_gain = vk::Buffer(ctx, N * 8);
  p_full = vk::Buffer(ctx, N * 8);
  p_offer = vk::Buffer(ctx, N * 8);

  VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 2};
  VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pi.maxSets = 1;
  pi.poolSizeCount = 1;
  pi.pPoolSizes = &ps;
  WETDEM_VK(vkCreateDescriptorPool(ctx.device(), &pi, nullptr, &pool_));
  VkDescriptorSetLayout layout = ctx.set_layout();
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pool_;
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &layout;
  WETDEM_VK(vkAllocateDescriptorSets(ctx.device(), &ai, &descriptors));
  VkDescriptorBufferInfo bi[2] = {{table_buf.handle(), 0, sizeof(GpuTable)},
                                  {params.handle(), 0, sizeof(GpuParams)}};
  VkWriteDescriptorSet w[2]{};
  for (uint32_t k = 0; k < 2; ++k) {
    w[k].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    w[k].dstSet = descriptors;
    w[k].dstBinding = k;
    w[k].descriptorCount = 1;
    w[k].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    w[k].pBufferInfo = &bi[k];
  }
  vkUpdateDescriptorSets(ctx.device(), 2, w, 0, nullptr);
}

BufferSet::~BufferSet() {
  if (pool_) vkDestroyDescriptorPool(ctx.device(), pool_, nullptr);
}

void BufferSet::grow_scratch(uint32_t entries) {
  if (entries <= scratch_capacity_) return;
  const uint64_t E = std::max<uint32_t>(entries, 1);
  pair_f = vk::Buffer(ctx, E * 16);                             // (F, T.x) per entry
  pair_t = vk::Buffer(ctx, E * 8);                              // (T.y, T.z)
  ev = vk::Buffer(ctx, event_slots ? E * kEventSlotBytes : 0);  // (16 bytes when unused)
  partner = vk::Buffer(ctx, E * 4);
  owners = vk::Buffer(ctx, E * 4);
  scratch_capacity_ = entries;
}

void BufferSet::grow_entries(uint32_t set, uint32_t entries) {
  const uint64_t E = std::max<uint32_t>(entries, 1);
  for (uint32_t f = 0; f < kNumEntryFields; ++f) eset[set][f] = vk::Buffer(ctx, E * kEntryFieldBytes[f]);
  capacity_[set] = entries;
  grow_scratch(entries);
}

void BufferSet::grow_sample_pairs(uint32_t pairs) {
  if (pairs <= smp_pair_capacity_) return;
  smp_pairs = vk::Buffer(ctx, uint64_t(std::max<uint32_t>(pairs, 1)) * 16);
  smp_pair_capacity_ = pairs;
  upload_table();
}

GpuTable BufferSet::table() const {
  GpuTable t{};
  t.ctl = ctl.address();
  t.params = params.address();
  for (int s = 0; s < 2; ++s) {
    for (uint32_t f = 0; f < kNumParticleFields; ++f) t.pset[s][f] = pset[s][f].address();
    for (uint32_t f = 0; f < kNumEntryFields; ++f) t.eset[s][f] = eset[s][f].address();
  }
  t.ref_pos = ref_pos.address();
  t.cell_key = cell_key.address();
  t.sort_val = sort_val.address();
  t.cell_start = cell_start.address();
  t.cell_end = cell_end.address();
  t.cnt_scan = cnt_scan.address();
  t.pair_f = pair_f.address();
  t.pair_t = pair_t.address();
  t.ev = ev.address();
  t.partner = partner.address();
  t.p_share = p_share.address();
  t.p_gain = p_gain.address();
  t.p_full = p_full.address();
  t.p_offer = p_offer.address();
  t.own_scan = own_scan.address();
  t.owners = owners.address();
  t.run_of = run_of.address();
  t.smp = smp.address();
  t.smp_pairs = smp_pairs.address();
  return t;
}

void BufferSet::upload_table() {
  GpuTable t = table();
  table_buf.upload(&t, sizeof(t));
}

}  // namespace wetdem::gpu
