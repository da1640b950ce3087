#include "hmt/islands/distinctiveness.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include "hmt/islands/surface_normals.h"

namespace hmt::islands {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The axis histogram that finds the reference surface: 1-degree bins over
// [0, 180). The window slides bin by bin, and the reference direction is the
// mean axis of the hits inside it, not a bin's centre.
constexpr int kBins = 180;

// An axis (a direction up to sign) with what the reference search needs.
struct Axis {
  float ux = 1.0f, uy = 0.0f;  // unit vector
  float c2 = 1.0f, s2 = 0.0f;  // cos and sin of twice its angle
  int bin = 0;
};

Axis axis_of(double ux, double uy) {
  double a = std::atan2(uy, ux);
  if (a < 0) a += kPi;
  if (a >= kPi) a -= kPi;
  Axis ax;
  ax.ux = static_cast<float>(std::cos(a));
  ax.uy = static_cast<float>(std::sin(a));
  ax.c2 = static_cast<float>(std::cos(2 * a));
  ax.s2 = static_cast<float>(std::sin(2 * a));
  ax.bin = std::min(kBins - 1, static_cast<int>(a / kPi * kBins));
  return ax;
}

struct Entry {
  Axis axis;
  float magnitude = 0.0f;
};

// Eq. 9-10 over `entries`, the reference the window of `window_bins` bins
// that holds the most influence.
Constraints constrain(const Entry* entries, size_t n, int window_bins) {
  double mag[kBins] = {}, c2[kBins] = {}, s2[kBins] = {};
  for (size_t k = 0; k < n; ++k) {
    const Entry& e = entries[k];
    if (e.magnitude <= 0) continue;
    mag[e.axis.bin] += e.magnitude;
    c2[e.axis.bin] += e.magnitude * e.axis.c2;
    s2[e.axis.bin] += e.magnitude * e.axis.s2;
  }
  Constraints c;
  const int w = std::min(window_bins, kBins);
  double sum = 0.0;
  for (int b = 0; b < w; ++b) sum += mag[b];
  double best = sum;
  int best_start = 0;
  for (int s = 1; s < kBins; ++s) {
    sum += mag[(s + w - 1) % kBins] - mag[s - 1];
    if (sum > best) {
      best = sum;
      best_start = s;
    }
  }
  if (!(best > 0)) return c;
  double sc = 0.0, ss = 0.0;
  for (int b = 0; b < w; ++b) {
    sc += c2[(best_start + b) % kBins];
    ss += s2[(best_start + b) % kBins];
  }
  const double beta = 0.5 * std::atan2(ss, sc);
  c.ref_x = std::cos(beta);
  c.ref_y = std::sin(beta);
  for (size_t k = 0; k < n; ++k) {
    const Entry& e = entries[k];
    c.parallel += e.magnitude * std::abs(e.axis.ux * c.ref_x + e.axis.uy * c.ref_y);
    c.perp += e.magnitude * std::abs(e.axis.ux * c.ref_y - e.axis.uy * c.ref_x);
  }
  return c;
}

// Everything per map and options, shared by the cells.
class Evaluator {
 public:
  Evaluator(const OccupancyRaster& map, const IslandsOptions& opt)
      : map_(map), opt_(opt), normals_(surface_normals(map, std::max(1.0, opt.normal_radius / map.resolution))) {
    axes_.resize(map.cells.size());
    for (size_t k = 0; k < map.cells.size(); ++k)
      if (map.cells[k] == CellState::kOccupied) axes_[k] = axis_of(normals_.nx[k], normals_.ny[k]);
    const int n = opt.rays;
    dtheta_ = 2 * kPi / n;
    for (int k = 0; k < n; ++k) {
      const double a = k * dtheta_;
      cx_.push_back(std::cos(a));
      cy_.push_back(std::sin(a));
      ray_axes_.push_back(axis_of(cx_.back(), cy_.back()));
    }
    max_cells_ = opt.max_range / map.resolution;
    window_bins_ = std::max(1, static_cast<int>(std::lround(opt.reference_window)));
    // The rays each heading's field of view holds.
    const bool full = opt.field_of_view >= 360.0;
    const int headings = full ? 1 : opt.headings;
    const double half_fov = opt.field_of_view * kPi / 360.0;
    for (int h = 0; h < headings; ++h) {
      std::vector<int> rays;
      const double phi = 2 * kPi * h / headings;
      for (int k = 0; k < n; ++k) {
        const double d = std::remainder(k * dtheta_ - phi, 2 * kPi);
        if (full || std::abs(d) <= half_fov + 1e-9) rays.push_back(k);
      }
      heading_rays_.push_back(std::move(rays));
    }
  }

  CellTerms terms(int i, int j, std::vector<Entry>& per_ray, std::vector<Entry>& visible) const {
    const int n = opt_.rays;
    per_ray.assign(2 * static_cast<size_t>(n), Entry{});
    for (int k = 0; k < n; ++k) cast(i, j, k, &per_ray[2 * k]);
    CellTerms best;
    bool first = true;
    for (const std::vector<int>& rays : heading_rays_) {
      visible.clear();
      for (int k : rays) {
        visible.push_back(per_ray[2 * k]);
        visible.push_back(per_ray[2 * k + 1]);
      }
      const Constraints c = constrain(visible.data(), visible.size(), window_bins_);
      const double sp = sigmoid(c.parallel, opt_.cutoff, opt_.rate);
      const double sq = sigmoid(c.perp, opt_.cutoff, opt_.rate);
      CellTerms t;
      t.c_parallel = static_cast<float>(c.parallel);
      t.c_perp = static_cast<float>(c.perp);
      t.f = static_cast<float>(std::min(sp, sq));
      t.q = static_cast<float>(quality(sp, sq));
      if (first || t.term() > best.term()) best = t;
      first = false;
    }
    return best;
  }

 private:
  // Walks ray k from the centre of cell (i, j) (Amanatides & Woo's DDA);
  // at its first occupied cell writes the hit's influences into out[0]
  // (along the surface normal, for the wall-like part of the hit, 1 -
  // isotropy) and out[1] (along the view, for the rest).
  void cast(int i, int j, int k, Entry* out) const {
    const double dx = cx_[k], dy = cy_[k];
    const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const double delta_x = dx != 0 ? 1.0 / std::abs(dx) : inf;
    const double delta_y = dy != 0 ? 1.0 / std::abs(dy) : inf;
    double t_x = 0.5 * delta_x, t_y = 0.5 * delta_y;
    int x = i, y = j;
    for (;;) {
      double t;
      // A ray through a cell corner (to rounding) has both side cells as
      // candidates: the first occupied one of them is hit.
      if (std::abs(t_x - t_y) < 1e-9) {
        t = t_x;
        if (t > max_cells_) return;
        for (const auto& c : {std::pair<int, int>{x + step_x, y}, {x, y + step_y}}) {
          if (!map_.inside(c.first, c.second)) return;
          const CellState s = map_.at(c.first, c.second);
          if (s == CellState::kOccupied) return hit(c.first, c.second, k, t, out);
          if (s == CellState::kUnknown) return;
        }
        x += step_x;
        y += step_y;
        t_x += delta_x;
        t_y += delta_y;
      } else if (t_x < t_y) {
        t = t_x;
        x += step_x;
        t_x += delta_x;
      } else {
        t = t_y;
        y += step_y;
        t_y += delta_y;
      }
      if (t > max_cells_ || !map_.inside(x, y)) return;
      const CellState s = map_.at(x, y);
      if (s == CellState::kOccupied) return hit(x, y, k, t, out);
      if (s == CellState::kUnknown) return;
    }
  }

  void hit(int x, int y, int k, double t_cells, Entry* out) const {
    const size_t c = map_.index(x, y);
    // Eq. 8 times the ray's share of the sweep of Eq. 7.
    const double w = std::exp(-opt_.decay * t_cells * map_.resolution) * dtheta_;
    const double iso = normals_.isotropy[c];
    const double proj = std::abs(normals_.nx[c] * cx_[k] + normals_.ny[c] * cy_[k]);
    out[0].axis = axes_[c];
    out[0].magnitude = static_cast<float>((1.0 - iso) * w * proj);
    out[1].axis = ray_axes_[k];
    out[1].magnitude = static_cast<float>(iso * w);
  }

  const OccupancyRaster& map_;
  const IslandsOptions& opt_;
  SurfaceNormals normals_;
  std::vector<Axis> axes_;
  std::vector<double> cx_, cy_;
  std::vector<Axis> ray_axes_;
  double dtheta_ = 0.0;
  double max_cells_ = 0.0;
  int window_bins_ = 1;
  std::vector<std::vector<int>> heading_rays_;
};

}  // namespace

double sigmoid(double value, double cutoff, double rate) {
  if (!(value > 0)) return 0.0;
  // C^m / (c^m + C^m) = 1 / (1 + (c / C)^m), which does not overflow.
  return 1.0 / (1.0 + std::pow(cutoff / value, rate));
}

double quality(double a, double b) {
  const double hi = std::max(a, b), lo = std::min(a, b);
  return hi > 0 ? lo / hi : 0.0;
}

Constraints constraints(const std::vector<Influence>& influences, double window) {
  std::vector<Entry> entries;
  for (const Influence& v : influences) {
    Entry e;
    e.axis = axis_of(v.ux, v.uy);
    e.magnitude = static_cast<float>(v.magnitude);
    entries.push_back(e);
  }
  const int bins = std::max(1, static_cast<int>(std::lround(window * kBins / kPi)));
  return constrain(entries.data(), entries.size(), bins);
}

CellTerms cell_terms(const OccupancyRaster& map, int i, int j, const IslandsOptions& options) {
  const Evaluator ev(map, options);
  std::vector<Entry> a, b;
  return ev.terms(i, j, a, b);
}

DistinctivenessMap distinctiveness(const OccupancyRaster& map, const IslandsOptions& opt) {
  DistinctivenessMap out;
  out.width = map.width;
  out.height = map.height;
  out.stride = opt.stride;
  const int s = opt.stride;
  for (int j = 0; j < map.height; j += s)
    for (int i = 0; i < map.width; i += s)
      if (map.at(i, j) == CellState::kFree) out.evaluated.push_back(map.index(i, j));
  out.terms.resize(out.evaluated.size());

  const Evaluator ev(map, opt);
  // Rows of evaluated cells handed out one at a time: each cell is written
  // by one thread only, so the result does not depend on the threads.
  std::vector<size_t> row_start;  // first evaluated cell of each lattice row
  for (size_t k = 0; k < out.evaluated.size(); ++k)
    if (k == 0 || out.evaluated[k] / map.width != out.evaluated[k - 1] / map.width)
      row_start.push_back(k);
  row_start.push_back(out.evaluated.size());
  std::atomic<size_t> next_row{0};
  const auto work = [&] {
    std::vector<Entry> per_ray, visible;
    for (size_t r; (r = next_row.fetch_add(1)) + 1 < row_start.size();)
      for (size_t k = row_start[r]; k < row_start[r + 1]; ++k) {
        const size_t c = out.evaluated[k];
        out.terms[k] = ev.terms(static_cast<int>(c % map.width),
                                static_cast<int>(c / map.width), per_ray, visible);
      }
  };
  unsigned threads = opt.threads > 0 ? static_cast<unsigned>(opt.threads)
                                     : std::max(1u, std::thread::hardware_concurrency());
  threads = std::min<unsigned>(threads, std::max<size_t>(1, row_start.size() - 1));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();

  // Eq. 4 and 6: the mean of the terms over the evaluated free cells of the
  // square, from summed-area tables of the terms and of their count.
  const int W = map.width, H = map.height;
  std::vector<double> sum(static_cast<size_t>(W + 1) * (H + 1), 0.0);
  std::vector<int> count(sum.size(), 0);
  std::vector<float> term(map.cells.size(), std::numeric_limits<float>::quiet_NaN());
  for (size_t k = 0; k < out.evaluated.size(); ++k) term[out.evaluated[k]] = out.terms[k].term();
  const auto at = [W](int i, int j) { return static_cast<size_t>(j) * (W + 1) + i; };
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const float v = term[map.index(i, j)];
      const bool has = !std::isnan(v);
      sum[at(i + 1, j + 1)] = (has ? v : 0.0) + sum[at(i, j + 1)] + sum[at(i + 1, j)] - sum[at(i, j)];
      count[at(i + 1, j + 1)] = (has ? 1 : 0) + count[at(i, j + 1)] + count[at(i + 1, j)] - count[at(i, j)];
    }
  const int e = std::max(static_cast<int>(std::lround(opt.epsilon / map.resolution)), s / 2);
  out.r.assign(map.cells.size(), std::numeric_limits<float>::quiet_NaN());
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      if (map.at(i, j) != CellState::kFree) continue;
      const int x0 = std::max(0, i - e), x1 = std::min(W, i + e + 1);
      const int y0 = std::max(0, j - e), y1 = std::min(H, j + e + 1);
      const int n = count[at(x1, y1)] - count[at(x0, y1)] - count[at(x1, y0)] + count[at(x0, y0)];
      if (n == 0) continue;
      const double v = sum[at(x1, y1)] - sum[at(x0, y1)] - sum[at(x1, y0)] + sum[at(x0, y0)];
      out.r[map.index(i, j)] = static_cast<float>(std::clamp(v / n, 0.0, 1.0));
    }
  return out;
}

}  // namespace hmt::islands
