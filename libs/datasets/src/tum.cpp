#include "gmc/datasets/tum.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/camera.h"

namespace gmc::datasets {
namespace {

constexpr double kMaxTrajectoryCoordinate = 1e9;  ///< m, see readTumTrajectory

/// Splits a line on spaces, tabs and commas.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
      if (!cur.empty()) out.push_back(std::move(cur)), cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(std::move(cur));
  return out;
}

bool parseDouble(const std::string& s, double& v) {
  char* end = nullptr;
  errno = 0;
  v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0' && errno != ERANGE && std::isfinite(v);
}

std::ifstream openOrThrow(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  return in;
}

/// Calls f(fields, line_number) for every non-comment, non-empty line.
template <class F>
void forEachRecord(const std::string& path, F&& f) {
  auto in = openOrThrow(path);
  std::string line;
  size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos || line[b] == '#') continue;
    f(fields(line), number);
  }
  if (in.bad()) throw InputError(path + ": read error");
}

}  // namespace

std::vector<TumListEntry> readTumList(const std::string& path) {
  std::vector<TumListEntry> out;
  forEachRecord(path, [&](const std::vector<std::string>& f, size_t line) {
    TumListEntry e;
    if (f.size() != 2 || !parseDouble(f[0], e.stamp))
      throw InputError(path + ":" + std::to_string(line) + ": expected 'timestamp filename'");
    e.path = f[1];
    e.line = line;
    if (!out.empty() && e.stamp < out.back().stamp)
      throw InputError(path + ":" + std::to_string(line) + ": timestamps go backwards");
    out.push_back(std::move(e));
  });
  return out;
}

void writeTumList(const std::string& path, const std::vector<TumListEntry>& entries,
                  const std::string& header_comment) {
  std::ostringstream os;
  os << "# " << header_comment << "\n# timestamp filename\n";
  char buf[64];
  for (const auto& e : entries) {
    std::snprintf(buf, sizeof buf, "%.6f", e.stamp);
    os << buf << ' ' << e.path << '\n';
  }
  writeTextAtomic(path, os.str());
}

std::vector<StampedPose> readTumTrajectory(const std::string& path) {
  std::vector<StampedPose> out;
  forEachRecord(path, [&](const std::vector<std::string>& f, size_t line) {
    double v[8];
    bool ok = f.size() == 8;
    for (size_t k = 0; ok && k < 8; ++k) ok = parseDouble(f[k], v[k]);
    if (!ok)
      throw InputError(path + ":" + std::to_string(line) +
                       ": expected 'timestamp tx ty tz qx qy qz qw'");
    // Beyond this the squares in the ATE alignment overflow (NaN errors); Earth-referenced
    // coordinates (UTM northings, about 1e7 m) stay far below it.
    for (size_t k = 1; k < 4; ++k)
      if (std::abs(v[k]) > kMaxTrajectoryCoordinate)
        throw InputError(path + ":" + std::to_string(line) + ": position beyond 1e9 m");
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-2)
      throw InputError(path + ":" + std::to_string(line) + ": quaternion is not unit length");
    StampedPose p;
    p.stamp = v[0];
    p.pose.linear() = q.normalized().toRotationMatrix();
    p.pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    out.push_back(p);
  });
  std::stable_sort(out.begin(), out.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.stamp < b.stamp; });
  return out;
}

void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  std::ostringstream os;
  os << "# timestamp tx ty tz qx qy qz qw\n";
  char buf[256];
  for (const auto& p : poses) {
    const Eigen::Quaterniond q(p.pose.linear());
    const Eigen::Vector3d t = p.pose.translation();
    std::snprintf(buf, sizeof buf, "%.6f %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", p.stamp, t.x(),
                  t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
    os << buf;
  }
  writeTextAtomic(path, os.str());
}

std::vector<std::pair<size_t, size_t>> associate(const std::vector<double>& first,
                                                 const std::vector<double>& second,
                                                 double max_dt) {
  struct Candidate {
    double diff;
    size_t a, b;
  };
  // Candidates within max_dt: second sorted by stamp, window found by binary search.
  std::vector<size_t> order(second.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return second[x] < second[y]; });
  std::vector<Candidate> candidates;
  for (size_t a = 0; a < first.size(); ++a) {
    auto it = std::lower_bound(order.begin(), order.end(), first[a] - max_dt,
                               [&](size_t idx, double v) { return second[idx] < v; });
    for (; it != order.end() && second[*it] < first[a] + max_dt; ++it) {
      const double diff = std::abs(first[a] - second[*it]);
      if (diff < max_dt) candidates.push_back({diff, a, *it});
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return x.diff != y.diff ? x.diff < y.diff : (x.a != y.a ? x.a < y.a : x.b < y.b);
  });
  std::vector<char> used_a(first.size(), 0), used_b(second.size(), 0);
  std::vector<std::pair<size_t, size_t>> out;
  for (const auto& c : candidates) {
    if (used_a[c.a] || used_b[c.b]) continue;
    used_a[c.a] = used_b[c.b] = 1;
    out.emplace_back(c.a, c.b);
  }
  std::sort(out.begin(), out.end(), [&](const auto& x, const auto& y) { return first[x.first] < first[y.first]; });
  return out;
}

TumFolderPairs pairTumFolder(const std::string& dir, double max_dt) {
  const auto rgb = readTumList(dir + "/rgb.txt");
  const auto depth = readTumList(dir + "/depth.txt");
  std::vector<double> rs, ds;
  for (const auto& e : rgb) rs.push_back(e.stamp);
  for (const auto& e : depth) ds.push_back(e.stamp);
  TumFolderPairs out;
  std::vector<char> paired(rgb.size(), 0);
  for (const auto& [a, b] : associate(rs, ds, max_dt)) {
    out.pairs.emplace_back(rgb[a], depth[b]);
    paired[a] = 1;
  }
  for (size_t a = 0; a < rgb.size(); ++a)
    if (!paired[a]) out.unpaired_rgb.push_back(rgb[a]);
  return out;
}

std::optional<Isometry> interpolatePose(const std::vector<StampedPose>& trajectory, double stamp,
                                        double max_gap) {
  if (trajectory.empty()) return std::nullopt;
  auto it = std::lower_bound(trajectory.begin(), trajectory.end(), stamp,
                             [](const StampedPose& p, double s) { return p.stamp < s; });
  if (it != trajectory.end() && std::abs(it->stamp - stamp) < 1e-9) return it->pose;
  if (it == trajectory.begin() || it == trajectory.end()) {
    // Allow a small extrapolation-free tolerance at the ends.
    const auto& end = it == trajectory.end() ? trajectory.back() : trajectory.front();
    if (std::abs(end.stamp - stamp) <= max_gap / 2) return end.pose;
    return std::nullopt;
  }
  const StampedPose& b = *it;
  const StampedPose& a = *(it - 1);
  if (b.stamp - a.stamp > max_gap) return std::nullopt;
  const double f = (stamp - a.stamp) / (b.stamp - a.stamp);
  Isometry T = Isometry::Identity();
  T.linear() = Eigen::Quaterniond(a.pose.linear())
                   .slerp(f, Eigen::Quaterniond(b.pose.linear()))
                   .toRotationMatrix();
  T.translation() = (1 - f) * a.pose.translation() + f * b.pose.translation();
  return T;
}

PinholeCamera cameraPreset(const std::string& name) {
  PinholeCamera c;  // 640 x 480
  if (name == "fr1") {
    c.fx = 517.3, c.fy = 516.5, c.cx = 318.6, c.cy = 255.3;
  } else if (name == "fr2") {
    c.fx = 520.9, c.fy = 521.0, c.cx = 325.1, c.cy = 249.7;
  } else if (name == "fr3") {
    c.fx = 535.4, c.fy = 539.2, c.cx = 320.1, c.cy = 247.6;
  } else if (name == "bonn") {
    c.fx = 542.822841, c.fy = 542.576870, c.cx = 315.593520, c.cy = 237.756098;
  } else {
    const auto f = fields(name);
    double v[4];
    bool ok = f.size() == 4;
    for (size_t k = 0; ok && k < 4; ++k) ok = parseDouble(f[k], v[k]) && v[k] > 0;
    if (!ok)
      throw std::invalid_argument("camera '" + name +
                                  "': expected fr1, fr2, fr3, bonn or fx,fy,cx,cy (positive numbers)");
    c.fx = v[0], c.fy = v[1], c.cx = v[2], c.cy = v[3];
  }
  return c;
}

LensDistortion presetDistortion(const std::string& name) {
  if (name == "fr1") return {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  if (name == "fr2") return {0.2312, -0.7849, -0.0033, -0.0001, 0.9172};
  return {};
}

namespace {
/// The Bonn dataset's published marker-to-camera transform, rotation made orthonormal
/// (the nearest rotation in the Frobenius norm: U·Vᵀ of its SVD).
Isometry bonnMarkerToCamera() {
  Eigen::Matrix4d m;
  m << 1.0157, 0.1828, -0.2389, 0.0113,  //
      0.0009, -0.8431, -0.6413, -0.0098,  //
      -0.3009, 0.6147, -0.8085, 0.0111,   //
      0, 0, 0, 1;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m.topLeftCorner<3, 3>(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
  if (r.determinant() < 0) {
    Eigen::Matrix3d u = svd.matrixU();
    u.col(2) *= -1;
    r = u * svd.matrixV().transpose();
  }
  Isometry t = Isometry::Identity();
  t.linear() = r;
  t.translation() = m.topRightCorner<3, 1>();
  return t;
}
}  // namespace

std::vector<StampedPose> bonnBodyToCamera(const std::vector<StampedPose>& body_poses) {
  Isometry ros = Isometry::Identity();
  ros.linear() << -1, 0, 0,  //
      0, 0, 1,               //
      0, 1, 0;
  const Isometry marker = bonnMarkerToCamera();
  std::vector<StampedPose> camera;
  camera.reserve(body_poses.size());
  for (const auto& p : body_poses) camera.push_back({p.stamp, ros * p.pose * ros * marker});
  return camera;
}

std::vector<StampedPose> readGroundTruth(const std::string& path, const std::string& frame) {
  if (frame == "camera") return readTumTrajectory(path);
  if (frame == "bonn") return bonnBodyToCamera(readTumTrajectory(path));
  throw std::invalid_argument("ground-truth frame '" + frame + "' is not camera or bonn");
}

std::vector<StampedPose> baseTrajectory(const std::vector<StampedPose>& camera_trajectory,
                                        const Isometry& T_base_camera) {
  std::vector<StampedPose> base;
  base.reserve(camera_trajectory.size());
  for (const auto& p : camera_trajectory)
    base.push_back({p.stamp, T_base_camera * p.pose * T_base_camera.inverse()});
  return base;
}

void writeBaseTrajectory(const std::string& path, const std::vector<StampedPose>& camera_trajectory,
                         const std::optional<Isometry>& T_base_camera) {
  if (T_base_camera) writeTumTrajectory(path, baseTrajectory(camera_trajectory, *T_base_camera));
}

}  // namespace gmc::datasets
