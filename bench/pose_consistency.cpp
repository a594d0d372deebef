// How well a trajectory explains the images themselves: for frame pairs (i, i+lag), ORB
// matches of frame i with depth are moved by the trajectory's relative pose into frame j
// and compared with where frame j saw them. Relative poses only, so no alignment and no
// world frame is involved: the ground truth (camera frame, `gmc-eval --gt-out`) and an
// estimate are judged on the same matches, under the same intrinsics. Walkers' matches
// have large residuals under any camera pose, so each pair is summarised by low
// percentiles of its residuals (the background), and by the share within 2 px.
//
//   pose_consistency <tum_dir> <poses.txt> [--camera P] [--lag K] [--focal-scales a,b,...]
//                    [--rotation-from other_poses.txt]
//
// --focal-scales re-runs the comparison with fx, fy multiplied by each factor (backprojection
// and projection alike): the factor that fits a trajectory best is the focal length that
// trajectory implies. Each line is followed by a fit of the depth ratio (measured in frame
// i+lag against predicted from frame i) to the change of the normalised image radius^2
// between the two views: a radial depth bias k of the sensor (z (1 + k r^2)) shows as the
// slope. --rotation-from takes the relative rotations from another trajectory
// (translations stay from <poses.txt>); on a hovering camera rotation and sideways
// translation trade against each other, so such a mix fits worse than either (Bonn:
// 4-11 px) and does not single out the part that is wrong. Diagnostic for
// doc/odometry.md (the Bonn over-turn), not a benchmark.
#include <Eigen/Geometry>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "gmc/datasets/camera.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "tool_main.h"

namespace {

struct Args {
  std::string input, poses, camera = "fr3", rotation_from;
  int lag = 10;
  std::vector<double> focal_scales{1.0};
};

const char* kUsage =
    "usage: pose_consistency <tum_dir> <poses.txt> [--camera P] [--lag K] [--focal-scales a,b,...] "
    "[--rotation-from other_poses.txt]";

Args parseArgs(int argc, char** argv) {
  Args a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if ((s == "--camera" || s == "--lag" || s == "--focal-scales" || s == "--rotation-from") && i + 1 < argc) {
      const std::string v = argv[++i];
      if (s == "--rotation-from") {
        a.rotation_from = v;
      } else if (s == "--camera") {
        a.camera = v;
      } else if (s == "--lag") {
        a.lag = std::stoi(v);
      } else {
        a.focal_scales.clear();
        std::stringstream list(v);
        for (std::string item; std::getline(list, item, ',');) a.focal_scales.push_back(std::stod(item));
      }
    } else if (!s.empty() && s[0] == '-') {
      throw std::invalid_argument("unknown or incomplete option '" + s + "'\n" + kUsage);
    } else {
      positional.push_back(s);
    }
  }
  if (positional.size() != 2 || a.lag < 1 || a.focal_scales.empty()) throw std::invalid_argument(kUsage);
  a.input = positional[0], a.poses = positional[1];
  return a;
}

struct Frame {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors, depth;
  double depth_units = 0;
  std::optional<gmc::Isometry> pose, rotation_pose;
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(p / 100.0 * static_cast<double>(v.size() - 1))];
}

int run(const Args& args) {
  const gmc::PinholeCamera camera = gmc::datasets::cameraPreset(args.camera);
  const auto trajectory = gmc::datasets::readTumTrajectory(args.poses);
  const auto rotation_trajectory =
      args.rotation_from.empty() ? trajectory : gmc::datasets::readTumTrajectory(args.rotation_from);
  auto source = gmc::datasets::openRgbdSource(args.input, camera);
  auto orb = cv::ORB::create(1500);
  std::vector<Frame> frames;
  gmc::datasets::RgbdFrame rgbd;
  cv::Mat gray;
  while (source->next(rgbd)) {
    cv::cvtColor(rgbd.rgb, gray, cv::COLOR_BGR2GRAY);
    Frame f;
    orb->detectAndCompute(gray, cv::noArray(), f.keypoints, f.descriptors);
    f.depth = rgbd.depth.clone();
    f.depth_units = rgbd.depth_units;
    f.pose = gmc::datasets::interpolatePose(trajectory, rgbd.stamp);
    f.rotation_pose = gmc::datasets::interpolatePose(rotation_trajectory, rgbd.stamp);
    frames.push_back(std::move(f));
  }
  cv::BFMatcher matcher(cv::NORM_HAMMING, true);
  std::printf("%-8s %8s %10s %10s %10s %12s\n", "focal", "pairs", "p20 px", "p40 px", "<2px", "depth p40 m");
  for (const double scale : args.focal_scales) {
    gmc::PinholeCamera cam = camera;
    cam.fx *= scale, cam.fy *= scale;
    std::vector<double> p20, p40, within, depth40;
    // Depth against where in the image a point is seen: z_measured = z (1 + k r^2) makes
    // z_b / z_b(predicted from a) - 1 = c + k (r_b^2 - r_a^2) on consistent matches.
    double sxx = 0, sx = 0, sy = 0, sxy = 0, n_fit = 0;
    auto radius2 = [&](const cv::Point2f& p) {
      const double x = (p.x - cam.cx) / cam.fx, y = (p.y - cam.cy) / cam.fy;
      return x * x + y * y;
    };
    for (size_t i = 0; i + args.lag < frames.size(); ++i) {
      const Frame &a = frames[i], &b = frames[i + args.lag];
      if (!a.pose || !b.pose || !a.rotation_pose || !b.rotation_pose || a.descriptors.empty() ||
          b.descriptors.empty())
        continue;
      gmc::Isometry T_b_a = b.pose->inverse() * *a.pose;
      T_b_a.linear() = (b.rotation_pose->inverse() * *a.rotation_pose).linear();
      std::vector<cv::DMatch> matches;
      matcher.match(a.descriptors, b.descriptors, matches);
      std::vector<double> px, dz;
      for (const auto& m : matches) {
        const cv::Point2f ua = a.keypoints[m.queryIdx].pt, ub = b.keypoints[m.trainIdx].pt;
        const double za = a.depth.at<std::uint16_t>(cvRound(ua.y), cvRound(ua.x)) * a.depth_units;
        if (za < 0.3 || za > 6) continue;
        const Eigen::Vector3d in_b = T_b_a * cam.unproject(ua.x, ua.y, za);
        if (in_b.z() < 0.1) continue;
        px.push_back((cam.project(in_b) - Eigen::Vector2d(ub.x, ub.y)).norm());
        const double zb = b.depth.at<std::uint16_t>(cvRound(ub.y), cvRound(ub.x)) * b.depth_units;
        if (zb <= 0.3) continue;
        dz.push_back(std::abs(zb - in_b.z()));
        const double ratio = zb / in_b.z() - 1;
        if (px.back() > 3 || std::abs(ratio) > 0.1) continue;  // walkers, wrong matches
        const double x = radius2(ub) - radius2(ua);
        sxx += x * x, sx += x, sy += ratio, sxy += x * ratio, ++n_fit;
      }
      if (px.size() < 30) continue;
      p20.push_back(percentile(px, 20));
      p40.push_back(percentile(px, 40));
      within.push_back(std::count_if(px.begin(), px.end(), [](double r) { return r < 2; }) /
                       static_cast<double>(px.size()));
      depth40.push_back(percentile(dz, 40));
    }
    std::printf("%-8.3f %8zu %10.3f %10.3f %10.3f %12.4f\n", scale, p20.size(), percentile(p20, 50),
                percentile(p40, 50), percentile(within, 50), percentile(depth40, 50));
    const double det = n_fit * sxx - sx * sx;
    if (n_fit > 100 && det > 0)
      std::printf("         depth vs image radius: z_b / z_b(predicted) - 1 = %.4f + %.4f (r_b^2 - r_a^2), %.0f matches\n",
                  (sy * sxx - sx * sxy) / det, (n_fit * sxy - sx * sy) / det, n_fit);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return toolMain("pose_consistency", argc, argv, parseArgs, run); }
