#include "app/run/outputs.h"

#include <algorithm>

#include "wetdem/observables.h"

namespace fs = std::filesystem;

namespace wetdem::app {

RunOutputs::RunOutputs(const fs::path& dir, const Case& c, const std::vector<Sample>& samples_so_far,
                       double color_max, double liquid_unit_m3)
    : unit_(liquid_unit_m3) {
  const fs::path ts_path = dir / "timeseries.csv";
  std::string all = timeseries_header();
  for (const Sample& s : samples_so_far) all += timeseries_row(s);
  write_file_atomic(ts_path.string(), all);
  ts_.open(ts_path, std::ios::app);
  for (const std::string& f : c.output.formats) {
    fs::create_directories(dir / "frames");
    if (f == "gltf")
      gltf_ = std::make_unique<GltfSeries>((dir / "frames").string(), "frame", GltfOptions{color_max, false});
    if (f == "vtk")
      vtk_ = std::make_unique<PvdSeries>((dir / "frames").string(), "frame",
                                         VtkOptions{VtkEncoding::kBase64, color_max});
  }
}

void RunOutputs::append(const Sample& s) {
  ts_ << timeseries_row(s);
  ts_.flush();
}

void RunOutputs::frame(const SystemState& st) {
  if (!has_frames()) return;
  std::vector<double> liquid = liquid_per_particle(st);
  for (double& x : liquid) x *= unit_;
  const ParticleFrame fr = frame_from_state(st, liquid);
  if (gltf_) gltf_->write(fr);
  if (vtk_) vtk_->write(fr);
}

double film_color_max(const SystemState& s, double liquid_unit_m3) {
  double m = 0;
  for (int64_t f : s.p.film) m = std::max(m, double(f) * liquid_unit_m3);
  return m;
}

}  // namespace wetdem::app
