#include "gltf_writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

// tinygltf's header is third-party code: keep its warnings out of our -Werror build. Debian ships the
// implementation as libtinygltf.so (README.Debian), so TINYGLTF_IMPLEMENTATION is not defined here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

namespace wetdem {

namespace {

void check_sizes(const ParticleFrame& f) {
  const size_t n = f.x.size();
  auto ok = [n](size_t m) { return m == 0 || m == n; };
  if (f.radius.size() != n || !ok(f.v.size()) || !ok(f.liquid_m3.size()) || !ok(f.id.size()) ||
      !ok(f.cluster.size()) || f.cluster_size.size() != f.cluster.size())
    throw std::invalid_argument(
        "ParticleFrame: radius must have one entry per particle; v, liquid_m3, id, cluster (with "
        "cluster_size) one or none");
}

std::vector<float> as_float(const std::vector<uint32_t>& v) {
  return std::vector<float>(v.begin(), v.end());
}

// Appends float data as its own buffer view + accessor; returns the accessor index.
int add_float_accessor(tinygltf::Model& m, std::vector<unsigned char>& buf, const std::vector<float>& data,
                       size_t count, int type, bool with_min_max) {
  const size_t comps = data.size() / std::max<size_t>(count, 1);
  while (buf.size() % 4) buf.push_back(0);  // accessor offsets must be multiples of the component size
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.byteLength = data.size() * sizeof(float);
  view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  const size_t at = buf.size();
  buf.resize(at + view.byteLength);
  std::memcpy(buf.data() + at, data.data(), view.byteLength);
  m.bufferViews.push_back(view);

  tinygltf::Accessor acc;
  acc.bufferView = static_cast<int>(m.bufferViews.size() - 1);
  acc.byteOffset = 0;
  acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  acc.count = count;
  acc.type = type;
  if (with_min_max) {
    // min/max of the stored float32 values (the spec compares them with the data as stored).
    acc.minValues.assign(comps, std::numeric_limits<double>::infinity());
    acc.maxValues.assign(comps, -std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < count; ++i)
      for (size_t c = 0; c < comps; ++c) {
        const double v = data[i * comps + c];
        acc.minValues[c] = std::min(acc.minValues[c], v);
        acc.maxValues[c] = std::max(acc.maxValues[c], v);
      }
  }
  m.accessors.push_back(acc);
  return static_cast<int>(m.accessors.size() - 1);
}

tinygltf::Value frame_extras(const ParticleFrame& f, double color_max) {
  tinygltf::Value::Object o;
  o["time"] = tinygltf::Value(f.time);
  // JSON numbers: an integer when it fits tinygltf's int, else a double (exact to 2^53 steps).
  o["step"] = f.step <= static_cast<uint64_t>(std::numeric_limits<int>::max())
                  ? tinygltf::Value(static_cast<int>(f.step))
                  : tinygltf::Value(static_cast<double>(f.step));
  o["particles"] = tinygltf::Value(static_cast<double>(f.size()));
  o["color_max_m3"] = tinygltf::Value(color_max);
  o["units"] = tinygltf::Value(std::string("m"));
  o["up"] = tinygltf::Value(std::string("+y"));
  o["axis"] = tinygltf::Value(std::string("+z"));
  return tinygltf::Value(o);
}

}  // namespace

void write_glb(const std::string& path, const ParticleFrame& f, const GltfOptions& opt) {
  check_sizes(f);
  const size_t n = f.size();
  double color_max = opt.color_max_m3;
  if (!(color_max > 0.0))
    for (double l : f.liquid_m3) color_max = std::max(color_max, l);

  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = std::string("wetdem ") + WETDEM_VERSION;
  m.asset.extras = frame_extras(f, color_max);
  tinygltf::Scene scene;
  scene.name = "particles";
  scene.extras = frame_extras(f, color_max);

  if (n > 0) {
    // Drum frame -> glTF: identity (both right-handed, y up, metres; z is the drum axis).
    std::vector<float> pos(3 * n), col((opt.color_alpha ? 4 : 3) * n), rad(n), vel(3 * n, 0.0f), liq(n, 0.0f),
        ids(n);
    const size_t cc = opt.color_alpha ? 4 : 3;
    for (size_t i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) {
        pos[3 * i + k] = static_cast<float>(f.x[i][k]);
        if (!f.v.empty()) vel[3 * i + k] = static_cast<float>(f.v[i][k]);
      }
      const double l = f.liquid_m3.empty() ? 0.0 : f.liquid_m3[i];
      liq[i] = static_cast<float>(l);
      const glm::dvec3 c = liquid_color_linear(l, color_max);
      for (int k = 0; k < 3; ++k) col[cc * i + k] = static_cast<float>(c[k]);
      if (cc == 4) col[cc * i + 3] = 1.0f;
      rad[i] = static_cast<float>(f.radius[i]);
      ids[i] = static_cast<float>(f.id.empty() ? i : f.id[i]);
    }
    std::vector<unsigned char> buf;
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_POINTS;
    prim.attributes["POSITION"] = add_float_accessor(m, buf, pos, n, TINYGLTF_TYPE_VEC3, true);
    prim.attributes["COLOR_0"] =
        add_float_accessor(m, buf, col, n, opt.color_alpha ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, false);
    prim.attributes["_RADIUS"] = add_float_accessor(m, buf, rad, n, TINYGLTF_TYPE_SCALAR, false);
    prim.attributes["_VELOCITY"] = add_float_accessor(m, buf, vel, n, TINYGLTF_TYPE_VEC3, false);
    prim.attributes["_LIQUID_VOLUME"] = add_float_accessor(m, buf, liq, n, TINYGLTF_TYPE_SCALAR, false);
    prim.attributes["_ID"] = add_float_accessor(m, buf, ids, n, TINYGLTF_TYPE_SCALAR, false);
    if (!f.cluster.empty()) {
      prim.attributes["_CLUSTER"] =
          add_float_accessor(m, buf, as_float(f.cluster), n, TINYGLTF_TYPE_SCALAR, false);
      prim.attributes["_CLUSTER_SIZE"] =
          add_float_accessor(m, buf, as_float(f.cluster_size), n, TINYGLTF_TYPE_SCALAR, false);
    }
    tinygltf::Buffer b;
    b.data = std::move(buf);
    m.buffers.push_back(std::move(b));
    tinygltf::Mesh mesh;
    mesh.name = "particles";
    mesh.primitives.push_back(prim);
    m.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = "particles";
    node.mesh = 0;
    m.nodes.push_back(node);
    scene.nodes.push_back(0);
  }
  m.scenes.push_back(scene);
  m.defaultScene = 0;

  tinygltf::TinyGLTF io;
  // embedImages, embedBuffers (into the GLB BIN chunk), prettyPrint, writeBinary.
  if (!io.WriteGltfSceneToFile(&m, path, false, true, false, true))
    throw std::runtime_error("write_glb: cannot write " + path);
}

GltfSeries::GltfSeries(std::string dir, std::string prefix, GltfOptions opt)
    : dir_(std::move(dir)), opt_(opt), index_(prefix, "glb") {
  std::filesystem::create_directories(dir_);
  index_path_ = (std::filesystem::path(dir_) / (prefix + "s.json")).string();
  std::ifstream in(index_path_);
  if (in) {
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_object() && j.contains("frames") && j["frames"].is_array())
      for (const auto& e : j["frames"])
        index_.load({e.value("time", 0.0), e.value("step", uint64_t{0}), e.value("file", std::string())});
  }
}

std::string GltfSeries::write(const ParticleFrame& f) {
  const std::string path = (std::filesystem::path(dir_) / index_.file_for(f.step)).string();
  write_glb(path, f, opt_);
  clusters_ = !f.cluster.empty();
  index_.add(f.time, f.step);
  write_index();
  return path;
}

void GltfSeries::write_index() const {
  nlohmann::json j;
  j["format"] = "wetdem-frames";
  j["version"] = 1;
  j["units"] = "m";
  j["up"] = "+y";
  j["axis"] = "+z";
  j["attributes"] = {"POSITION", "COLOR_0", "_RADIUS", "_VELOCITY", "_LIQUID_VOLUME", "_ID"};
  if (clusters_) j["attributes"].push_back("_CLUSTER"), j["attributes"].push_back("_CLUSTER_SIZE");
  j["frames"] = nlohmann::json::array();
  for (const FrameEntry& e : index_.entries())
    j["frames"].push_back({{"time", e.time}, {"step", e.step}, {"file", e.file}});
  // Write then rename, so a reader never sees a half-written index.
  const std::string tmp = index_path_ + ".tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(1) << '\n';
    if (!out) throw std::runtime_error("GltfSeries: cannot write " + tmp);
  }
  std::filesystem::rename(tmp, index_path_);
}

}  // namespace wetdem
