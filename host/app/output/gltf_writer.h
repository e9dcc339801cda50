// glTF 2.0 binary (.glb) point clouds, one file per frame, plus a JSON index of the frames.
//
// Axes and units: glTF is right-handed, metres, +Y up. The drum frame is also right-handed with y up (gravity
// -y) and z along the drum axis, so positions are written unchanged (identity mapping): glTF x = drum x,
// glTF y = drum y (up), glTF z = drum z (axis).
//
// Each .glb holds one scene > one node > one mesh with one primitive of mode POINTS (no indices) and the
// attributes (all FLOAT, one interleaved-free buffer view each):
//   POSITION        VEC3  centre (m), with the accessor min/max the glTF spec requires for POSITION
//   COLOR_0         VEC3 (or VEC4 with alpha 1) linear RGB of liquid_color_linear(liquid, color_max)
//   _RADIUS         SCALAR radius (m)
//   _VELOCITY       VEC3  velocity (m/s)
//   _LIQUID_VOLUME  SCALAR liquid per particle (m³), physics.md §5
//   _ID             SCALAR stable id (exact in float32 up to 2^24 = 16.7 M particles)
//   _CLUSTER        SCALAR agglomerate label: smallest stable id of the particle's bridge cluster (when
//   given) _CLUSTER_SIZE   SCALAR particles in that cluster (when given)
// asset.extras and scene.extras carry {"time": s, "step": n, "particles": N, "color_max_m3": v}.
#pragma once

#include <string>
#include <vector>

#include "colormap.h"
#include "frame_index.h"

namespace wetdem {

struct GltfOptions {
  double color_max_m3 = 0.0;  // liquid volume drawn darkest blue; ≤ 0: the frame's largest liquid volume
  bool color_alpha = false;   // COLOR_0 as VEC4 (alpha 1) instead of VEC3
};

// Writes one frame. Throws std::runtime_error when the file cannot be written, std::invalid_argument on
// inconsistent array sizes.
void write_glb(const std::string& path, const ParticleFrame& f, const GltfOptions& opt = {});

// A directory of frames <dir>/<prefix>_<step, 10 digits>.glb and the index <dir>/<prefix>s.json:
//   {"format": "wetdem-frames", "version": 1, "units": "m", "up": "+y", "axis": "+z",
//    "frames": [{"time": t, "step": n, "file": "frame_0000000100.glb"}, ...]}
// The index is rewritten after every frame, so it is valid if the run stops. An existing index in dir is read
// on construction; a frame with step n drops the entries with step ≥ n first (a run restarted from a
// checkpoint re-lists the frames after it once; their old files are overwritten as the same steps are
// written).
class GltfSeries {
 public:
  GltfSeries(std::string dir, std::string prefix = "frame", GltfOptions opt = {});
  std::string write(const ParticleFrame& f);  // returns the .glb path
  const std::string& index_path() const { return index_path_; }
  size_t frames() const { return index_.entries().size(); }

 private:
  void write_index() const;
  std::string dir_, index_path_;
  GltfOptions opt_;
  FrameIndex index_;
  bool clusters_ = false;  // the last frame carried _CLUSTER
};

}  // namespace wetdem
