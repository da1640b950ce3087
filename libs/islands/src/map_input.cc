#include "hmt/islands/map_input.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/global_map/global_grid.h"
#include "hmt/global_map/global_poses.h"
#include "hmt/topology/topology_file.h"

namespace hmt::islands {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void bad(const std::string& path, const std::string& what) {
  throw InputError(path + ": " + what);
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r\n");
  return s.substr(a, b - a + 1);
}

std::string unquote(std::string s) {
  if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front())
    s = s.substr(1, s.size() - 2);
  return s;
}

double parse_number(const std::string& path, const std::string& key, const std::string& v) {
  try {
    size_t used = 0;
    const double d = std::stod(v, &used);
    if (trim(v.substr(used)).empty() && std::isfinite(d)) return d;
  } catch (const std::exception&) {
  }
  bad(path, key + ": '" + v + "' is not a finite number");
}

// The next token of a PGM header, skipping white space and # comments.
std::string pgm_token(std::istream& in) {
  std::string tok;
  int c;
  while ((c = in.get()) != EOF) {
    if (c == '#') {
      while ((c = in.get()) != EOF && c != '\n') {
      }
      continue;
    }
    if (std::isspace(c)) {
      if (!tok.empty()) return tok;
      continue;
    }
    tok.push_back(static_cast<char>(c));
  }
  return tok;
}

bool starts_with(const std::string& bytes, const char (&magic)[8]) {
  return bytes.size() >= 8 && std::memcmp(bytes.data(), magic, 8) == 0;
}

}  // namespace

grid::Image read_pgm(const std::string& path) {
  require_readable_file(path, "map image");
  std::ifstream in(path, std::ios::binary);
  const std::string magic = pgm_token(in);
  if (magic != "P5" && magic != "P2") bad(path, "not a PGM image (P5 or P2)");
  long w = 0, h = 0, maxval = 0;
  try {
    w = std::stol(pgm_token(in));
    h = std::stol(pgm_token(in));
    maxval = std::stol(pgm_token(in));
  } catch (const std::exception&) {
    bad(path, "malformed PGM header");
  }
  if (w <= 0 || h <= 0 || w > 100000 || h > 100000) bad(path, "PGM size out of range");
  if (maxval <= 0 || maxval > 255) bad(path, "PGM maximum value must be in [1, 255]");
  grid::Image img(static_cast<int>(w), static_cast<int>(h), 1);
  const double scale = 255.0 / static_cast<double>(maxval);
  for (int y = 0; y < h; ++y) {
    uint8_t* row = img.row(y);
    for (int x = 0; x < w; ++x) {
      long v;
      if (magic == "P5") {
        const int c = in.get();
        if (c == EOF) bad(path, "PGM truncated at row " + std::to_string(y));
        v = c;
      } else {
        const std::string t = pgm_token(in);
        if (t.empty()) bad(path, "PGM truncated at row " + std::to_string(y));
        v = std::strtol(t.c_str(), nullptr, 10);
      }
      if (v > maxval) bad(path, "PGM value above its maximum");
      row[x] = static_cast<uint8_t>(std::lround(v * scale));
    }
  }
  return img;
}

LoadedMap read_map_yaml(const std::string& path) {
  require_readable_file(path, "map");
  std::ifstream in(path);
  std::string line, image;
  LoadedMap m;
  bool have_res = false, have_origin = false;
  while (std::getline(in, line)) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line = line.substr(0, hash);
    if (trim(line).empty()) continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) bad(path, "not 'key: value': '" + trim(line) + "'");
    const std::string key = trim(line.substr(0, colon));
    const std::string value = trim(line.substr(colon + 1));
    if (key == "image") {
      image = unquote(value);
    } else if (key == "resolution") {
      m.image.resolution = parse_number(path, key, value);
      have_res = true;
    } else if (key == "origin") {
      if (value.size() < 2 || value.front() != '[' || value.back() != ']')
        bad(path, "origin must be [x, y, yaw]");
      std::stringstream ss(value.substr(1, value.size() - 2));
      std::string part;
      std::vector<double> o;
      while (std::getline(ss, part, ',')) o.push_back(parse_number(path, key, trim(part)));
      if (o.size() != 3) bad(path, "origin must be [x, y, yaw]");
      if (o[2] != 0.0) bad(path, "a rotated origin (yaw != 0) is not supported");
      m.image.origin_x = o[0];
      m.image.origin_y = o[1];
      have_origin = true;
    } else if (key == "negate") {
      m.thresholds.negate = parse_number(path, key, value) != 0.0;
    } else if (key == "occupied_thresh") {
      m.thresholds.occupied = parse_number(path, key, value);
    } else if (key == "free_thresh") {
      m.thresholds.free = parse_number(path, key, value);
    } else if (key != "mode") {
      bad(path, "unknown key '" + key + "'");
    }
  }
  if (image.empty()) bad(path, "no image: key");
  if (!have_res || !(m.image.resolution > 0)) bad(path, "resolution must be given and > 0");
  if (!have_origin) bad(path, "no origin: key");
  if (!(m.thresholds.free >= 0 && m.thresholds.free <= m.thresholds.occupied &&
        m.thresholds.occupied <= 1))
    bad(path, "need 0 <= free_thresh <= occupied_thresh <= 1");
  fs::path img = image;
  if (img.is_relative()) img = fs::path(path).parent_path() / img;
  m.image.image = read_pgm(img.string());
  m.description = "map " + path + " (" + std::to_string(m.image.image.width()) + " x " +
                  std::to_string(m.image.image.height()) + " cells)";
  return m;
}

LoadedMap read_hmt_map(const std::string& path) {
  const topology::Session s = topology::load_session(path);
  if (s.hypotheses.empty()) bad(path, "the file holds no hypothesis");
  // The most probable hypothesis (the lowest id among equals): the one a
  // run draws its global map from.
  const topology::SessionHypothesis* best = &s.hypotheses.front();
  for (const auto& h : s.hypotheses)
    if (h.topo.log_weight > best->topo.log_weight) best = &h;
  const topology::HmtMap& map = best->map;
  double resolution = 0.0;
  topology::AreaId root = topology::kNoArea;
  for (topology::AreaId id : map.area_ids()) {
    if (root == topology::kNoArea) root = id;
    if (map.area(id).map && resolution == 0.0) resolution = map.area(id).map->resolution();
  }
  if (resolution <= 0.0) bad(path, "no area of the most probable hypothesis has a map");
  global_map::GlobalPoses poses;
  try {
    poses = global_map::optimize_poses(map, root);
  } catch (const std::exception&) {
    poses = global_map::shortest_path_poses(map, root);
  }
  const grid::OccupancyGrid global = global_map::render_global_grid(map, poses, resolution);
  LoadedMap m;
  m.image = grid::render(global);
  m.description = "HMT map " + path + ": hypothesis " + std::to_string(best->id) + ", " +
                  std::to_string(map.area_count()) + " areas at their global poses (" +
                  std::to_string(m.image.image.width()) + " x " +
                  std::to_string(m.image.image.height()) + " cells)";
  return m;
}

LoadedMap load_map(const std::string& path) {
  require_readable_file(path, "map");
  std::string head(8, '\0');
  {
    std::ifstream in(path, std::ios::binary);
    in.read(head.data(), 8);
    head.resize(static_cast<size_t>(in.gcount()));
  }
  if (starts_with(head, topology::kSessionMagic)) return read_hmt_map(path);
  if (head.rfind("P5", 0) == 0 || head.rfind("P2", 0) == 0) {
    const fs::path yaml = fs::path(path).replace_extension(".yaml");
    if (!fs::exists(yaml))
      bad(path, "a PGM image needs its map_server .yaml beside it (" + yaml.string() +
                    ") for the resolution and origin");
    return read_map_yaml(yaml.string());
  }
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".yaml" || ext == ".yml") return read_map_yaml(path);
  bad(path, "not a map: expected a run's hmt_map.bin, a map_server .yaml or its .pgm");
}

}  // namespace hmt::islands
