// Phase "write", during the run: timeseries.csv (exactly the samples so far; rewritten on resume, then
// appended) and the glTF/VTK frames the case asks for. summary.json is written by the driver at the end.
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include "app/case/case.h"
#include "app/output/gltf_writer.h"
#include "app/output/summary.h"
#include "app/output/vtk_writer.h"
#include "wetdem/state.h"

namespace wetdem::app {

class RunOutputs {
 public:
  // color_max: one colour scale for the whole run (frames compare); liquid_unit_m3 converts liquid units.
  RunOutputs(const std::filesystem::path& dir, const Case& c, const std::vector<Sample>& samples_so_far,
             double color_max, double liquid_unit_m3);
  void append(const Sample& s);
  bool has_frames() const { return gltf_ || vtk_; }
  void frame(const SystemState& st);  // st.time and st.step set

 private:
  std::ofstream ts_;
  std::unique_ptr<GltfSeries> gltf_;
  std::unique_ptr<PvdSeries> vtk_;
  double unit_;
};

// The largest initial film (m³): the top of the snapshots' colour scale.
double film_color_max(const SystemState& s, double liquid_unit_m3);

}  // namespace wetdem::app
