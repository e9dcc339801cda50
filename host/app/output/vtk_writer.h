// VTK XML PolyData (.vtp) particle snapshots and a ParaView collection (.pvd) of them.
//
// A .vtp holds N points (Float64 centres, m) with one vertex cell each (so ParaView draws them without a
// filter), point data "radius" (Float64, m), "liquid_volume" (Float64, m³, physics.md §5 liquid per
// particle), "velocity" (Float32 ×3, m/s), "id" (UInt32), "cluster" and "cluster_size" (UInt32, the bridge
// cluster's label and particle count, app/observe/clusters.h; when the frame has them), "color" (UInt8 ×3,
// sRGB of liquid_color_srgb; only when color_max_m3 > 0), and field data "TimeValue" (Float64, s) and "Step"
// (UInt64) ParaView reads. Axes as in the drum frame (y up, z the drum axis). Encodings: ASCII, or binary
// appended data in base64 (header_type UInt64: each array's block is the byte count as a little-endian UInt64
// followed by the raw little-endian values, base64-encoded on its own; offsets count characters after the '_'
// marker), as vtkXMLWriter writes for encoding="base64".
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "colormap.h"
#include "frame_index.h"

namespace wetdem {

enum class VtkEncoding { kAscii, kBase64 };

struct VtkOptions {
  VtkEncoding encoding = VtkEncoding::kBase64;
  double color_max_m3 = 0.0;  // > 0: also write the "color" array (liquid_color_srgb)
};

void write_vtp(const std::string& path, const ParticleFrame& f, const VtkOptions& opt = {});

// <dir>/<prefix>_<step, 10 digits>.vtp and <dir>/<prefix>s.pvd (rewritten after each frame; an existing
// collection is read and frames with step ≥ the new step are dropped, as GltfSeries).
class PvdSeries {
 public:
  PvdSeries(std::string dir, std::string prefix = "frame", VtkOptions opt = {});
  std::string write(const ParticleFrame& f);  // returns the .vtp path
  const std::string& collection_path() const { return pvd_path_; }
  size_t frames() const { return index_.entries().size(); }

 private:
  void write_collection() const;
  std::string dir_, pvd_path_;
  VtkOptions opt_;
  FrameIndex index_;
};

// Minimal reader for what write_vtp writes (both encodings): tests and tools. Arrays converted to double.
struct VtpData {
  size_t points = 0, verts = 0;
  std::vector<double> x;  // 3 per point
  std::map<std::string, std::vector<double>> point_data;
  std::map<std::string, int> components;     // per point-data array
  std::map<std::string, std::string> types;  // VTK type name per point-data array ("Float64", ...)
  std::map<std::string, double> field_data;  // first value of each field-data array
};
VtpData read_vtp(const std::string& path);

// The (time, file) entries of a .pvd collection, in file order.
std::vector<std::pair<double, std::string>> read_pvd(const std::string& path);

}  // namespace wetdem
