#include "hmt/islands/islands_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hmt/common/files.h"
#include "hmt/grid/png.h"
#include "hmt/islands/distinctiveness.h"
#include "hmt/islands/heat_map.h"
#include "hmt/islands/map_input.h"

namespace hmt::islands {
namespace {

void write_r_pgm_yaml(const grid::MapImage& map, const DistinctivenessMap& d,
                      const std::string& base) {
  const int w = d.width, h = d.height;
  write_file_atomically(base + ".pgm", [&](std::ostream& os) {
    os << "P5\n# HMT-SLAM distinctiveness R: level round(254 R), 255 none\n"
       << w << " " << h << "\n255\n";
    std::string row(static_cast<size_t>(w), '\0');
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const float r = d.r[static_cast<size_t>(h - 1 - y) * w + x];
        row[x] = static_cast<char>(std::isnan(r) ? 255 : std::lround(254.0 * r));
      }
      os.write(row.data(), w);
    }
  });
  char yaml[512];
  std::snprintf(yaml, sizeof yaml,
                "image: %s\nresolution: %.6f\norigin: [%.6f, %.6f, 0.0]\n",
                std::filesystem::path(base + ".pgm").filename().c_str(), map.resolution,
                map.origin_x, map.origin_y);
  write_text_atomically(base + ".yaml", yaml);
}

void write_terms_csv(const OccupancyRaster& map, const DistinctivenessMap& d,
                     const std::string& path) {
  write_file_atomically(path, [&](std::ostream& os) {
    os << "x,y,c_parallel,c_perp,F,Q,term,R\n";
    char line[256];
    for (size_t k = 0; k < d.evaluated.size(); ++k) {
      const size_t c = d.evaluated[k];
      const CellTerms& t = d.terms[k];
      std::snprintf(line, sizeof line, "%.3f,%.3f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f\n",
                    map.x_of(static_cast<int>(c % map.width)),
                    map.y_of(static_cast<int>(c / map.width)), t.c_parallel, t.c_perp, t.f,
                    t.q, t.term(), d.r[c]);
      os << line;
    }
  });
}

}  // namespace

IslandsSummary run_islands_job(const std::string& map_path, const IslandsOptions& opt,
                               const std::string& out_dir, const CheckSetup* check) {
  const LoadedMap loaded = load_map(map_path);
  const OccupancyRaster raster = loaded.raster(opt.wall_probability);
  make_directories(out_dir);

  IslandsSummary sum;
  sum.map_description = loaded.description;
  sum.width = raster.width;
  sum.height = raster.height;
  for (CellState s : raster.cells) sum.free_cells += s == CellState::kFree;
  const auto t0 = std::chrono::steady_clock::now();
  const DistinctivenessMap d = distinctiveness(raster, opt);
  sum.compute_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sum.evaluated_cells = d.evaluated.size();
  double total = 0.0;
  size_t n = 0;
  for (float r : d.r)
    if (!std::isnan(r)) {
      total += r;
      ++n;
    }
  sum.mean_r = n ? total / n : 0.0;
  sum.islands = choose_islands(raster, d, opt.threshold, opt.min_distance);

  grid::write_png_file(heat_map_image(loaded.image, d, sum.islands, opt.threshold),
                       out_dir + "/distinctiveness.png");
  grid::write_png_file(islands_image(loaded.image, sum.islands), out_dir + "/islands.png");
  write_r_pgm_yaml(loaded.image, d, out_dir + "/distinctiveness");
  write_terms_csv(raster, d, out_dir + "/distinctiveness.csv");
  std::ostringstream csv;
  csv << "id,x,y,R\n";
  char line[128];
  nlohmann::json islands = nlohmann::json::array();
  for (const Island& is : sum.islands) {
    std::snprintf(line, sizeof line, "%d,%.3f,%.3f,%.5f\n", is.id, is.x, is.y, is.r);
    csv << line;
    islands.push_back({{"id", is.id}, {"x", is.x}, {"y", is.y}, {"R", is.r}});
  }
  write_text_atomically(out_dir + "/islands.csv", csv.str());
  nlohmann::json j = {{"map", loaded.description},
                      {"width", sum.width},
                      {"height", sum.height},
                      {"resolution", raster.resolution},
                      {"origin", {raster.origin_x, raster.origin_y}},
                      {"free_cells", sum.free_cells},
                      {"evaluated_cells", sum.evaluated_cells},
                      {"stride", opt.stride},
                      {"compute_time_s", sum.compute_time_s},
                      {"mean_r", sum.mean_r},
                      {"threshold", opt.threshold},
                      {"min_distance", opt.min_distance},
                      {"islands", islands}};
  if (check) {
    sum.checked = true;
    sum.check = localization_check(raster, d, check->options, check->matcher, check->insertion);
    write_check_csv(out_dir + "/localization_check.csv", sum.check);
    std::vector<double> e;
    for (const CheckSample& cs : sum.check.samples) e.push_back(cs.error_xy);
    std::sort(e.begin(), e.end());
    const auto q = [&](double p) {
      return e.empty() ? 0.0 : e[std::min(e.size() - 1, static_cast<size_t>(p * e.size()))];
    };
    j["check"] = {{"samples", sum.check.samples.size()},
                  {"spearman_r_error", sum.check.spearman},
                  {"error_median", q(0.5)},
                  {"error_p90", q(0.9)},
                  {"offset_min", check->options.offset_min},
                  {"offset_max", check->options.offset_max},
                  {"angle_offset_deg", check->options.angle_offset}};
  }
  write_text_atomically(out_dir + "/islands.json", j.dump(2) + "\n");
  return sum;
}

}  // namespace hmt::islands
