// The list of frames of a series on disk (GltfSeries, PvdSeries): <prefix>_<step, 10 digits>.<ext> files and
// their (time, step, file) entries in step order. A frame at step n first drops the entries at steps >= n: a
// run restarted from a checkpoint re-lists the frames after it once (their files are overwritten as the same
// steps are written again). Each series writes the list in its own index format.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace wetdem {

struct FrameEntry {
  double time = 0.0;
  uint64_t step = 0;
  std::string file;  // relative to the series directory
};

class FrameIndex {
 public:
  FrameIndex(std::string prefix, std::string ext) : prefix_(std::move(prefix)), ext_(std::move(ext)) {}
  std::string file_for(uint64_t step) const { return fmt::format("{}_{:010d}.{}", prefix_, step, ext_); }
  // Drops the entries at steps >= step, then lists the frame; returns its file name.
  std::string add(double time, uint64_t step) {
    entries_.erase(
        std::remove_if(entries_.begin(), entries_.end(), [&](const FrameEntry& e) { return e.step >= step; }),
        entries_.end());
    entries_.push_back({time, step, file_for(step)});
    return entries_.back().file;
  }
  void load(FrameEntry e) { entries_.push_back(std::move(e)); }  // from an index already on disk
  const std::vector<FrameEntry>& entries() const { return entries_; }

 private:
  std::string prefix_, ext_;
  std::vector<FrameEntry> entries_;
};

}  // namespace wetdem
