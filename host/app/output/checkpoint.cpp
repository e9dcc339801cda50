#include "app/output/checkpoint.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "app/output/summary.h"

namespace fs = std::filesystem;

namespace wetdem::app {

std::string bytes_hash(const void* data, size_t n) {
  uint64_t h = 1469598103934665603ull;
  const auto* b = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  return fmt::format("{:016x}", h);
}

void save_checkpoint(const std::string& run_dir, const Checkpoint& c) {
  const fs::path dir = fs::path(run_dir) / "checkpoint", tmp = fs::path(run_dir) / "checkpoint.tmp",
                 old = fs::path(run_dir) / "checkpoint.old";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  nlohmann::json host = c.host;
  host["system_bytes"] = c.system.size();
  host["system_hash"] = bytes_hash(c.system.data(), c.system.size());
  write_file_atomic((tmp / "system.bin").string(), std::string(c.system.begin(), c.system.end()));
  write_file_atomic((tmp / "host.json").string(), host.dump(1) + "\n");
  // Swap: checkpoint -> checkpoint.old, checkpoint.tmp -> checkpoint, drop old. Between the renames only
  // checkpoint.old is complete, and load_checkpoint falls back to it.
  fs::remove_all(old);
  if (fs::exists(dir)) fs::rename(dir, old);
  fs::rename(tmp, dir);
  fs::remove_all(old);
}

namespace {

bool read_all(const fs::path& p, std::string& out) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return true;
}

bool try_load(const fs::path& dir, Checkpoint& c, std::string& why) {
  std::string host, blob;
  if (!read_all(dir / "host.json", host) || !read_all(dir / "system.bin", blob)) {
    why = "missing files in " + dir.string();
    return false;
  }
  try {
    c.host = nlohmann::json::parse(host);
  } catch (const std::exception& e) {
    why = dir.string() + "/host.json: " + e.what();
    return false;
  }
  if (c.host.value("system_bytes", uint64_t(0)) != blob.size() ||
      c.host.value("system_hash", std::string()) != bytes_hash(blob.data(), blob.size())) {
    why = dir.string() + "/system.bin does not match host.json (damaged checkpoint)";
    return false;
  }
  c.system.assign(blob.begin(), blob.end());
  return true;
}

}  // namespace

bool has_checkpoint(const std::string& run_dir) {
  return fs::exists(fs::path(run_dir) / "checkpoint" / "host.json") ||
         fs::exists(fs::path(run_dir) / "checkpoint.old" / "host.json");
}

Checkpoint load_checkpoint(const std::string& run_dir) {
  Checkpoint c;
  std::string why, why_old;
  if (try_load(fs::path(run_dir) / "checkpoint", c, why)) return c;
  if (try_load(fs::path(run_dir) / "checkpoint.old", c, why_old)) return c;
  throw std::runtime_error("no usable checkpoint in " + run_dir + ": " + why);
}

}  // namespace wetdem::app
