#include "hmt/grouping/topology.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <utility>

namespace hmt::grouping {

PoseSample average_poses(const std::vector<Pose2D>& samples) {
  if (samples.empty()) throw std::invalid_argument("average_poses: no sample");
  PoseSample out;
  out.n = samples.size();
  double sx = 0, sy = 0, ss = 0, sc = 0;
  for (const Pose2D& p : samples) {
    sx += p.x;
    sy += p.y;
    ss += std::sin(p.theta);
    sc += std::cos(p.theta);
  }
  const double n = static_cast<double>(out.n);
  out.mean = Pose2D(sx / n, sy / n, std::atan2(ss, sc));
  if (out.n >= 2) {
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    for (const Pose2D& p : samples) {
      const Eigen::Vector3d d(p.x - out.mean.x, p.y - out.mean.y,
                              wrap_angle(p.theta - out.mean.theta));
      c += d * d.transpose();
    }
    out.cov = c / (n - 1.0);
    out.has_cov = true;
  }
  return out;
}

std::vector<TopologyArc> build_topology(const std::vector<Pose2D>& global,
                                        const std::vector<Pose2D>& local,
                                        const std::vector<int>& label,
                                        const area::WeightMatrix& W) {
  const int n = static_cast<int>(label.size());
  if (global.size() != label.size() || local.size() != label.size() ||
      W.rows() != n || W.cols() != n)
    throw std::invalid_argument("build_topology: size mismatch");
  struct Acc {
    std::map<std::pair<int, int>, char> pairs;  // (i, j), i in from; bit 1
                                                // route, bit 2 overlap
    double cut = 0.0;
  };
  std::map<std::pair<int, int>, Acc> acc;  // by (from, to)
  const auto add = [&](int i, int j, char kind, double w) {
    if (label[i] > label[j]) std::swap(i, j);
    Acc& a = acc[{label[i], label[j]}];
    a.pairs[{i, j}] |= kind;
    a.cut += w;
  };
  for (int k = 0; k + 1 < n; ++k)
    if (label[k] != label[k + 1]) add(k, k + 1, 1, 0.0);
  for (int c = 0; c < W.outerSize(); ++c)
    for (area::WeightMatrix::InnerIterator it(W, c); it; ++it) {
      const int r = static_cast<int>(it.row());
      if (r < c && it.value() > 0.0 && label[r] != label[c])
        add(r, c, 2, it.value());
    }

  std::vector<TopologyArc> arcs;
  for (const auto& [key, a] : acc) {
    TopologyArc arc;
    arc.from = key.first;
    arc.to = key.second;
    arc.sso_cut = a.cut;
    std::vector<Pose2D> samples;
    for (const auto& [ij, kind] : a.pairs) {
      const auto [i, j] = ij;
      arc.route_pairs += (kind & 1) != 0;
      arc.overlap_pairs += (kind & 2) != 0;
      samples.push_back(local[i] + (global[j] - global[i]) + local[j].inverse());
    }
    arc.transform = average_poses(samples);
    arcs.push_back(std::move(arc));
  }
  return arcs;
}

std::string topology_dot(const std::vector<TopologyNode>& nodes,
                         const std::vector<TopologyArc>& arcs) {
  std::string s =
      "// Metric-topological map from hmt-partition: nodes are groups (local\n"
      "// maps), an edge g -> h carries the pose of h's frame in g's frame\n"
      "// (x, y in metres, theta in degrees) averaged over n keyframe pairs.\n"
      "// Nodes are placed at their reference positions: neato -n -Tpng.\n"
      "digraph topology {\n  node [shape=box, fontname=\"Helvetica\"];\n"
      "  edge [fontname=\"Helvetica\", fontsize=10];\n";
  char buf[512];
  for (const TopologyNode& n : nodes) {
    std::snprintf(buf, sizeof buf,
                  "  g%d [label=\"G%d\\n%zu keyframes\\n%s\", pos=\"%.1f,%.1f\"];\n",
                  n.id, n.id, n.keyframes, n.local_map.c_str(),
                  n.reference_pose.x * 72.0, n.reference_pose.y * 72.0);
    s += buf;
  }
  for (const TopologyArc& a : arcs) {
    const Pose2D& m = a.transform.mean;
    std::snprintf(buf, sizeof buf,
                  "  g%d -> g%d [label=\"(%.2f, %.2f, %.1f)\\nn=%zu%s%s\"];\n",
                  a.from, a.to, m.x, m.y, m.theta * 180.0 / M_PI,
                  a.transform.n, a.route_pairs ? " route" : "",
                  a.overlap_pairs ? " overlap" : "");
    s += buf;
  }
  s += "}\n";
  return s;
}

}  // namespace hmt::grouping
