// Agglomerates (app/observe/clusters.h): chains and rings of bridged particles give their sizes, labels do
// not depend on the order of the pairs, a random network agrees with a breadth-first search, and snapshots
// carry the cluster of every particle (glTF _CLUSTER/_CLUSTER_SIZE, VTK cluster/cluster_size, read back).
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <queue>
#include <random>

#include "app/observe/clusters.h"
#include "app/output/colormap.h"
#include "app/output/gltf_writer.h"
#include "app/output/vtk_writer.h"

#include "support/numbers.h"
#include "support/tiny_gltf_quiet.h"

namespace wetdem::test {
namespace {

SystemState particles(size_t n, double r = 1e-3) {
  SystemState s;
  s.p.resize(n);
  for (size_t k = 0; k < n; ++k) set_sphere(s.p, k, {0.003 * double(k), -0.05, 0.0}, r, 900.0);
  return s;
}

void bridge(SystemState& s, uint32_t a, uint32_t b, int64_t v = 10) {
  PairRecord r;
  r.id_i = std::min(a, b), r.id_j = std::max(a, b), r.bridge = v;
  s.pairs.push_back(r);
}

TEST(ObserveClusters, ChainRingAndSingletons) {
  // 20 particles: a chain 3-7-1-9-4 (5), a ring 10-12-15-11-10 (4), a touching pair 5-6 with springs but no
  // bridge (not connected), the rest alone.
  SystemState s = particles(20);
  const uint32_t chain[] = {3, 7, 1, 9, 4};
  for (int i = 0; i + 1 < 5; ++i) bridge(s, chain[i], chain[i + 1]);
  const uint32_t ring[] = {10, 12, 15, 11};
  for (int i = 0; i < 4; ++i) bridge(s, ring[i], ring[(i + 1) % 4]);
  PairRecord dry;
  dry.id_i = 5, dry.id_j = 6, dry.flags = kFlagWasInContact, dry.spring_t = {1e-6, 0, 0};
  s.pairs.push_back(dry);
  s.canonicalize();

  const observe::Clusters c = observe::bridge_clusters(s);
  for (uint32_t k : chain) {
    EXPECT_EQ(c.id[k], 1u);
    EXPECT_EQ(c.size[k], 5u);
  }
  for (uint32_t k : ring) {
    EXPECT_EQ(c.id[k], 10u);
    EXPECT_EQ(c.size[k], 4u);
  }
  EXPECT_EQ(c.id[5], 5u);
  EXPECT_EQ(c.id[6], 6u);
  EXPECT_EQ(c.size[6], 1u);
  EXPECT_EQ(c.count, 20u - 4u - 3u);
  EXPECT_EQ(c.largest, 5u);
  // Equal masses: Σ n_c² / N = (25 + 16 + 11) / 20.
  EXPECT_DOUBLE_EQ(c.size_mean, 52.0 / 20.0);
  const double v1 = 4.0 / 3.0 * kPi * 1e-9;
  EXPECT_NEAR(c.volume_mean_m3 / v1, 52.0 / 20.0, 1e-12);
  EXPECT_NEAR(c.equivalent_diameter_m, 2e-3 * std::cbrt(52.0 / 20.0), 1e-15);

  // The same network listed in another order gives the same labels.
  SystemState r = s;
  std::reverse(r.pairs.begin(), r.pairs.end());
  EXPECT_EQ(observe::bridge_clusters(r).id, c.id);
}

TEST(ObserveClusters, MassWeightedMeanWithUnequalParticles) {
  // A heavy particle (radius 2 mm, 8 m) bridged to one light one, and two light singletons:
  // Σ M_c n_c / Σ M_c = (9 m · 2 + m + m) / (11 m).
  SystemState s = particles(4);
  set_sphere(s.p, 0, {0.0, -0.05, 0.0}, 2e-3, 900.0);
  bridge(s, 0, 1);
  const observe::Clusters c = observe::bridge_clusters(s);
  EXPECT_NEAR(c.size_mean, 20.0 / 11.0, 1e-12);
  EXPECT_EQ(c.size[1], 2u);
}

TEST(ObserveClusters, RandomNetworkAgreesWithBreadthFirstSearch) {
  const size_t n = 3000;
  SystemState s = particles(n);
  std::mt19937 rng(11);
  std::uniform_int_distribution<uint32_t> pick(0, n - 1);
  std::vector<std::vector<uint32_t>> adj(n);
  for (int e = 0; e < 2400; ++e) {
    const uint32_t a = pick(rng), b = pick(rng);
    if (a == b) continue;
    bridge(s, a, b);
    adj[a].push_back(b), adj[b].push_back(a);
  }
  const observe::Clusters c = observe::bridge_clusters(s);
  std::vector<int64_t> label(n, -1);
  for (uint32_t k = 0; k < n; ++k) {  // ascending start: the label is the smallest member
    if (label[k] >= 0) continue;
    std::vector<uint32_t> members{k};
    std::queue<uint32_t> q;
    q.push(k);
    label[k] = k;
    while (!q.empty()) {
      const uint32_t a = q.front();
      q.pop();
      for (uint32_t b : adj[a])
        if (label[b] < 0) label[b] = k, q.push(b), members.push_back(b);
    }
    for (uint32_t m : members) {
      ASSERT_EQ(c.id[m], k);
      ASSERT_EQ(c.size[m], members.size());
    }
  }
}

std::filesystem::path scratch(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() /
                 ("wetdem_test_" + name + "_" + std::to_string(static_cast<long>(::getpid())));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

TEST(ObserveClusters, SnapshotsCarryTheClusterOfEveryParticle) {
  SystemState s = particles(8);
  bridge(s, 2, 5), bridge(s, 5, 7), bridge(s, 0, 1);
  const ParticleFrame f = frame_from_state(s, {});
  const std::vector<uint32_t> id = {0, 0, 2, 3, 4, 2, 6, 2}, size = {2, 2, 3, 1, 1, 3, 1, 3};
  ASSERT_EQ(f.cluster, id);
  ASSERT_EQ(f.cluster_size, size);
  const auto dir = scratch("clusters");

  write_glb((dir / "c.glb").string(), f);
  tinygltf::Model m;
  tinygltf::TinyGLTF io;
  std::string err, warn;
  ASSERT_TRUE(io.LoadBinaryFromFile(&m, &err, &warn, (dir / "c.glb").string())) << err;
  const tinygltf::Primitive& p = m.meshes[0].primitives[0];
  for (const char* name : {"_CLUSTER", "_CLUSTER_SIZE"}) {
    ASSERT_TRUE(p.attributes.count(name)) << name;
    const tinygltf::Accessor& a = m.accessors[size_t(p.attributes.at(name))];
    EXPECT_EQ(a.type, TINYGLTF_TYPE_SCALAR);
    EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
    ASSERT_EQ(a.count, 8u);
    const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
    const float* x = reinterpret_cast<const float*>(m.buffers[0].data.data() + v.byteOffset + a.byteOffset);
    const std::vector<uint32_t>& want = std::string(name) == "_CLUSTER" ? id : size;
    for (size_t i = 0; i < 8; ++i) EXPECT_EQ(x[i], float(want[i])) << name << i;
  }

  for (VtkEncoding enc : {VtkEncoding::kAscii, VtkEncoding::kBase64}) {
    VtkOptions o;
    o.encoding = enc;
    write_vtp((dir / "c.vtp").string(), f, o);
    const VtpData d = read_vtp((dir / "c.vtp").string());
    ASSERT_TRUE(d.point_data.count("cluster"));
    ASSERT_TRUE(d.point_data.count("cluster_size"));
    EXPECT_EQ(d.types.at("cluster"), "UInt32");
    for (size_t i = 0; i < 8; ++i) {
      EXPECT_EQ(d.point_data.at("cluster")[i], double(id[i]));
      EXPECT_EQ(d.point_data.at("cluster_size")[i], double(size[i]));
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace wetdem::test
#endif  // WETDEM_HAVE_APP
