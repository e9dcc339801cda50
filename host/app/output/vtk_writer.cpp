#include "vtk_writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace wetdem {

namespace {

static_assert(sizeof(double) == 8 && sizeof(float) == 4, "IEEE 754 types expected");

bool little_endian() {
  const uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

const char kB64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64_encode(const std::vector<unsigned char>& in) {
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = (uint32_t{in[i]} << 16) | (uint32_t{in[i + 1]} << 8) | in[i + 2];
    out += kB64[(v >> 18) & 63];
    out += kB64[(v >> 12) & 63];
    out += kB64[(v >> 6) & 63];
    out += kB64[v & 63];
  }
  if (i < in.size()) {
    const bool two = i + 1 < in.size();
    const uint32_t v = (uint32_t{in[i]} << 16) | (two ? uint32_t{in[i + 1]} << 8 : 0u);
    out += kB64[(v >> 18) & 63];
    out += kB64[(v >> 12) & 63];
    out += two ? kB64[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// Decodes `nchars` base64 characters from s at pos (whitespace skipped, '=' ends a group).
std::vector<unsigned char> base64_decode(const std::string& s, size_t pos, size_t nchars) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  int quad[4], q = 0, pad = 0;
  for (size_t k = 0; k < nchars && pos < s.size(); ++pos) {
    const char c = s[pos];
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    ++k;
    if (c == '=') {
      quad[q++] = 0;
      ++pad;
    } else {
      const int v = val(c);
      if (v < 0) throw std::runtime_error("read_vtp: bad base64 character");
      quad[q++] = v;
    }
    if (q == 4) {
      const uint32_t v = (uint32_t(quad[0]) << 18) | (uint32_t(quad[1]) << 12) | (uint32_t(quad[2]) << 6) |
                         uint32_t(quad[3]);
      out.push_back(static_cast<unsigned char>(v >> 16));
      if (pad < 2) out.push_back(static_cast<unsigned char>(v >> 8));
      if (pad < 1) out.push_back(static_cast<unsigned char>(v));
      q = pad = 0;
    }
  }
  return out;
}

// One data array to write: values already in their on-disk type, little-endian.
struct Array {
  std::string name, type;
  int components = 1;
  std::vector<unsigned char> bytes;  // raw values
  std::string ascii;                 // the same values as text (ASCII encoding)
};

template <class T>
Array make_array(std::string name, std::string type, int comps, const std::vector<T>& v, bool ascii) {
  Array a{std::move(name), std::move(type), comps, {}, {}};
  if (ascii) {
    std::string s;
    s.reserve(v.size() * 12);
    for (size_t i = 0; i < v.size(); ++i) {
      if constexpr (std::is_same_v<T, double>)
        s += fmt::format("{:.17g}", v[i]);  // round-trips every double
      else if constexpr (std::is_same_v<T, float>)
        s += fmt::format("{:.9g}", v[i]);  // round-trips every float
      else
        s += fmt::format("{}", +v[i]);
      s += (i + 1) % 12 == 0 ? '\n' : ' ';
    }
    a.ascii = std::move(s);
  } else {
    a.bytes.resize(v.size() * sizeof(T));
    if (!v.empty()) std::memcpy(a.bytes.data(), v.data(), a.bytes.size());
  }
  return a;
}

std::string type_size_check(const std::string& t, size_t& size) {
  if (t == "Float64" || t == "Int64" || t == "UInt64")
    size = 8;
  else if (t == "Float32" || t == "Int32" || t == "UInt32")
    size = 4;
  else if (t == "Int16" || t == "UInt16")
    size = 2;
  else if (t == "Int8" || t == "UInt8")
    size = 1;
  else
    throw std::runtime_error("read_vtp: unsupported type " + t);
  return t;
}

double read_value(const unsigned char* p, const std::string& t) {
  auto get = [p](auto x) {
    std::memcpy(&x, p, sizeof(x));
    return static_cast<double>(x);
  };
  if (t == "Float64") return get(double{});
  if (t == "Float32") return get(float{});
  if (t == "Int64") return get(int64_t{});
  if (t == "UInt64") return get(uint64_t{});
  if (t == "Int32") return get(int32_t{});
  if (t == "UInt32") return get(uint32_t{});
  if (t == "Int16") return get(int16_t{});
  if (t == "UInt16") return get(uint16_t{});
  if (t == "Int8") return get(int8_t{});
  return get(uint8_t{});
}

std::string attr(const std::string& tag, const std::string& key) {
  const std::string k = " " + key + "=\"";
  const size_t p = tag.find(k);
  if (p == std::string::npos) return {};
  const size_t b = p + k.size(), e = tag.find('"', b);
  return tag.substr(b, e - b);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

// Step from "<prefix>_<digits>.vtp".
uint64_t step_of_file(const std::string& file) {
  const size_t us = file.rfind('_'), dot = file.rfind('.');
  if (us == std::string::npos || dot == std::string::npos || dot <= us + 1) return 0;
  try {
    return std::stoull(file.substr(us + 1, dot - us - 1));
  } catch (const std::exception&) {
    return 0;
  }
}

}  // namespace

void write_vtp(const std::string& path, const ParticleFrame& f, const VtkOptions& opt) {
  const size_t n = f.size();
  auto ok = [n](size_t m) { return m == 0 || m == n; };
  if (f.radius.size() != n || !ok(f.v.size()) || !ok(f.liquid_m3.size()) || !ok(f.id.size()) ||
      !ok(f.cluster.size()) || f.cluster_size.size() != f.cluster.size())
    throw std::invalid_argument(
        "ParticleFrame: radius must have one entry per particle; v, liquid_m3, id, cluster (with "
        "cluster_size) one or none");
  if (!little_endian()) throw std::runtime_error("write_vtp: big-endian hosts are not supported");
  const bool ascii = opt.encoding == VtkEncoding::kAscii;

  std::vector<double> pos(3 * n), rad(f.radius), liq(n, 0.0);
  std::vector<float> vel(3 * n, 0.0f);
  std::vector<uint32_t> ids(n);
  std::vector<uint8_t> col;
  std::vector<int64_t> conn(n), offs(n);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      pos[3 * i + k] = f.x[i][k];
      if (!f.v.empty()) vel[3 * i + k] = static_cast<float>(f.v[i][k]);
    }
    if (!f.liquid_m3.empty()) liq[i] = f.liquid_m3[i];
    ids[i] = f.id.empty() ? static_cast<uint32_t>(i) : f.id[i];
    conn[i] = static_cast<int64_t>(i);
    offs[i] = static_cast<int64_t>(i + 1);  // one vertex per cell
  }
  if (opt.color_max_m3 > 0.0) {
    col.resize(3 * n);
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec3 c = liquid_color_srgb(liq[i], opt.color_max_m3);
      for (int k = 0; k < 3; ++k) col[3 * i + k] = static_cast<uint8_t>(std::lround(c[k] * 255.0));
    }
  }

  std::vector<Array> pd;
  pd.push_back(make_array("radius", "Float64", 1, rad, ascii));
  pd.push_back(make_array("liquid_volume", "Float64", 1, liq, ascii));
  pd.push_back(make_array("velocity", "Float32", 3, vel, ascii));
  pd.push_back(make_array("id", "UInt32", 1, ids, ascii));
  if (!f.cluster.empty()) {
    pd.push_back(make_array("cluster", "UInt32", 1, f.cluster, ascii));
    pd.push_back(make_array("cluster_size", "UInt32", 1, f.cluster_size, ascii));
  }
  if (!col.empty()) pd.push_back(make_array("color", "UInt8", 3, col, ascii));
  Array points = make_array("Points", "Float64", 3, pos, ascii);
  Array connectivity = make_array("connectivity", "Int64", 1, conn, ascii);
  Array offsets = make_array("offsets", "Int64", 1, offs, ascii);

  std::string appended;  // base64 text after '_'
  auto data_array = [&](const Array& a, const std::string& indent) {
    std::string head = fmt::format("{}<DataArray type=\"{}\" Name=\"{}\"", indent, a.type, a.name);
    if (a.components != 1) head += fmt::format(" NumberOfComponents=\"{}\"", a.components);
    if (ascii) return head + " format=\"ascii\">\n" + a.ascii + "\n" + indent + "</DataArray>\n";
    // Block = UInt64 byte count + raw values, base64-encoded as one stream (vtkXMLWriter, uncompressed).
    std::vector<unsigned char> block(8 + a.bytes.size());
    const uint64_t nbytes = a.bytes.size();
    std::memcpy(block.data(), &nbytes, 8);
    if (!a.bytes.empty()) std::memcpy(block.data() + 8, a.bytes.data(), a.bytes.size());
    head += fmt::format(" format=\"appended\" offset=\"{}\"/>\n", appended.size());
    appended += base64_encode(block);
    return head;
  };

  std::string x = "<?xml version=\"1.0\"?>\n";
  x += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  x += "  <PolyData>\n";
  x += "    <FieldData>\n";
  x += fmt::format(
      "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
      "format=\"ascii\">{:.17g}</DataArray>\n",
      f.time);
  x += fmt::format(
      "      <DataArray type=\"UInt64\" Name=\"Step\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n",
      f.step);
  x += "    </FieldData>\n";
  x += fmt::format(
      "    <Piece NumberOfPoints=\"{0}\" NumberOfVerts=\"{0}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"0\">\n",
      n);
  x += "      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
  for (const Array& a : pd) x += data_array(a, "        ");
  x += "      </PointData>\n      <Points>\n";
  x += data_array(points, "        ");
  x += "      </Points>\n      <Verts>\n";
  x += data_array(connectivity, "        ");
  x += data_array(offsets, "        ");
  x += "      </Verts>\n    </Piece>\n  </PolyData>\n";
  if (!ascii) x += "  <AppendedData encoding=\"base64\">\n   _" + appended + "\n  </AppendedData>\n";
  x += "</VTKFile>\n";
  write_atomically(path, x);
}

VtpData read_vtp(const std::string& path) {
  const std::string s = slurp(path);
  VtpData d;
  size_t appended_at = std::string::npos;
  {
    const size_t a = s.find("<AppendedData");
    if (a != std::string::npos) {
      if (attr(s.substr(a, s.find('>', a) - a), "encoding") != "base64")
        throw std::runtime_error("read_vtp: only base64 appended data is supported");
      appended_at = s.find('_', a) + 1;
    }
  }
  const size_t end = std::min(s.size(), s.find("<AppendedData"));
  std::string section;  // FieldData, PointData, Points, Verts
  for (size_t p = s.find('<'); p < end; p = s.find('<', p + 1)) {
    const size_t q = s.find('>', p);
    const std::string tag = s.substr(p, q - p + 1);
    for (const char* sec : {"FieldData", "PointData", "Points", "Verts"})
      if (tag.rfind(std::string("<") + sec, 0) == 0 &&
          (tag[1 + std::strlen(sec)] == ' ' || tag[1 + std::strlen(sec)] == '>'))
        section = sec;
    if (tag.rfind("<Piece", 0) == 0) {
      d.points = std::stoull(attr(tag, "NumberOfPoints"));
      d.verts = std::stoull(attr(tag, "NumberOfVerts"));
    }
    if (tag.rfind("<DataArray", 0) != 0) continue;
    const std::string type = attr(tag, "type"), name = attr(tag, "Name"), format = attr(tag, "format");
    const std::string nc = attr(tag, "NumberOfComponents");
    const int comps = nc.empty() ? 1 : std::stoi(nc);
    size_t wsize = 0;
    type_size_check(type, wsize);
    std::vector<double> values;
    if (format == "ascii") {
      const size_t e = s.find("</DataArray>", q);
      std::istringstream in(s.substr(q + 1, e - q - 1));
      double v;
      while (in >> v) values.push_back(v);
    } else if (format == "appended") {
      if (appended_at == std::string::npos) throw std::runtime_error("read_vtp: appended array without data");
      const size_t off = appended_at + std::stoull(attr(tag, "offset"));
      const std::vector<unsigned char> hdr = base64_decode(s, off, 12);  // 12 chars hold the 8-byte header
      uint64_t nbytes = 0;
      std::memcpy(&nbytes, hdr.data(), 8);
      const std::vector<unsigned char> block = base64_decode(s, off, (8 + nbytes + 2) / 3 * 4);
      if (block.size() < 8 + nbytes) throw std::runtime_error("read_vtp: truncated appended block");
      for (size_t i = 0; i < nbytes / wsize; ++i)
        values.push_back(read_value(block.data() + 8 + i * wsize, type));
    } else {
      throw std::runtime_error("read_vtp: unsupported format " + format);
    }
    if (section == "FieldData") {
      d.field_data[name] = values.empty() ? 0.0 : values[0];
    } else if (section == "Points") {
      d.x = std::move(values);
    } else if (section == "PointData") {
      d.point_data[name] = std::move(values);
      d.components[name] = comps;
      d.types[name] = type;
    } else if (section == "Verts") {
      d.point_data["verts." + name] = std::move(values);  // connectivity/offsets, for completeness checks
      d.types["verts." + name] = type;
      d.components["verts." + name] = 1;
    }
  }
  return d;
}

std::vector<std::pair<double, std::string>> read_pvd(const std::string& path) {
  const std::string s = slurp(path);
  std::vector<std::pair<double, std::string>> out;
  for (size_t p = s.find("<DataSet"); p != std::string::npos; p = s.find("<DataSet", p + 1)) {
    const std::string tag = s.substr(p, s.find('>', p) - p + 1);
    out.emplace_back(std::stod(attr(tag, "timestep")), attr(tag, "file"));
  }
  return out;
}

PvdSeries::PvdSeries(std::string dir, std::string prefix, VtkOptions opt)
    : dir_(std::move(dir)), opt_(opt), index_(prefix, "vtp") {
  std::filesystem::create_directories(dir_);
  pvd_path_ = (std::filesystem::path(dir_) / (prefix + "s.pvd")).string();
  if (std::filesystem::exists(pvd_path_))
    for (const auto& [t, file] : read_pvd(pvd_path_)) index_.load({t, step_of_file(file), file});
}

std::string PvdSeries::write(const ParticleFrame& f) {
  const std::string path = (std::filesystem::path(dir_) / index_.file_for(f.step)).string();
  write_vtp(path, f, opt_);
  index_.add(f.time, f.step);
  write_collection();
  return path;
}

void PvdSeries::write_collection() const {
  std::string x =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  x += "  <Collection>\n";
  for (const FrameEntry& e : index_.entries())
    x += fmt::format("    <DataSet timestep=\"{:.17g}\" group=\"\" part=\"0\" file=\"{}\"/>\n", e.time,
                     e.file);
  x += "  </Collection>\n</VTKFile>\n";
  write_atomically(pvd_path_, x);
}

}  // namespace wetdem
