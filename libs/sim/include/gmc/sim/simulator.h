#pragma once
// Synthetic dynamic RGB-D sequences with exact ground truth: a textured room with
// furniture, walking (or seated, gesturing) people, a moving Kinect-like camera.
// Pure computation: renderFrame() returns images, mask and pose; the app writes files.
#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gmc/datasets/frame.h"

namespace gmc::sim {
namespace detail {
struct Rng;
struct PathState;
}  // namespace detail

/// [Simulator]
struct SimulatorOptions {
  int frames = 300;
  double fps = 30.0;
  int seed = 1;
  double start_stamp = 1000000000.0;  ///< s, first frame's timestamp
  int threads = 2;                     ///< rendering threads (output does not depend on it)
  template <class V>
  void visit(V& v) {
    v("frames", frames, 1, 10000000, "frames to render");
    v("fps", fps, 1.0, 1000.0, "frame rate (Hz)");
    v("seed", seed, 0, 2000000000, "random seed: scene, people, noise");
    v("start_stamp", start_stamp, 0.0, 1e10, "timestamp of the first frame (s)");
    v("threads", threads, 1, 64, "rendering threads");
  }
};

/// [Camera] (TUM fr3 defaults)
struct CameraOptions {
  double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;
  int width = 640, height = 480;
  template <class V>
  void visit(V& v) {
    v("fx", fx, 1.0, 1e5, "focal length x (px)");
    v("fy", fy, 1.0, 1e5, "focal length y (px)");
    v("cx", cx, 0.0, 1e5, "principal point x (px)");
    v("cy", cy, 0.0, 1e5, "principal point y (px)");
    v("width", width, 16, 10000, "image width (px)");
    v("height", height, 16, 10000, "image height (px)");
  }
};

/// [Trajectory]
struct TrajectoryOptions {
  std::string style = "xyz";     ///< static | xyz | rpy | halfsphere | handheld | follow | walk
  double amplitude = 0.25;       ///< m, translation amplitude (xyz, handheld, follow's shake)
  double rotation = 15.0;        ///< deg, rotation amplitude (rpy, handheld, follow's shake)
  double period = 8.0;           ///< s, main period of the motion
  double radius = 2.8;           ///< m, halfsphere radius around the room centre
  double height = 1.4;           ///< m, camera height
  double tilt = 0;               ///< deg, optical axis pointed down (all styles but halfsphere)
  double follow_distance = 1.5;  ///< m, follow: camera behind the first walker's path
  double walk_span = 4.0;        ///< m, walk: the camera walks back and forth along x over this
  double walk_speed = 1.0;       ///< m/s, walk: the camera's walking speed
  template <class V>
  void visit(V& v) {
    v.choice("style", style, {"static", "xyz", "rpy", "halfsphere", "handheld", "follow", "walk"},
             "camera motion");
    v("amplitude", amplitude, 0.0, 5.0, "translation amplitude (m)");
    v("rotation", rotation, 0.0, 90.0, "rotation amplitude (deg)");
    v("period", period, 0.5, 1000.0, "main period (s)");
    v("radius", radius, 0.5, 10.0, "halfsphere radius (m)");
    v("height", height, 0.3, 2.5, "camera height (m)");
    v("tilt", tilt, -45.0, 45.0, "camera pointed down by this (deg; not halfsphere)");
    v("follow_distance", follow_distance, 0.5, 4.0, "follow: distance behind the followed walker's path (m)");
    v("walk_span", walk_span, 0.0, 7.0, "walk: length of the camera's back-and-forth walk (m)");
    v("walk_speed", walk_speed, 0.0, 3.0, "walk: camera speed (m/s)");
  }
};

/// [People]
struct PeopleOptions {
  int walkers = 3;
  double speed_min = 0.5, speed_max = 1.5;  ///< m/s
  double distance_min = 1.0, distance_max = 4.0;  ///< m in front of the camera
  double path_slant = 0.8;                  ///< m, change of distance along a path
  bool sitting = false;                     ///< a seated person who only gestures
  double path_span = 6.4;                   ///< m, walking paths' length, centred on the view
  int group = 0;                            ///< walkers in step with the camera (style walk)
  bool articulated = false;                 ///< knees and elbows bend (else straight limbs)
  std::string clothes = "checker";          ///< checker | plain (solid cloth, seams, folds)
  double pause_min = 0, pause_max = 0;      ///< s a walker stands still on every pass (0 = never)
  bool fidget = false;                      ///< standing walkers sway, turn and gesture
  template <class V>
  void visit(V& v) {
    v("walkers", walkers, 0, 20, "people walking across the view");
    v("speed_min", speed_min, 0.0, 5.0, "slowest walker (m/s)");
    v("speed_max", speed_max, 0.0, 5.0, "fastest walker (m/s)");
    v("distance_min", distance_min, 0.3, 6.0, "nearest walking line (m from the camera)");
    v("distance_max", distance_max, 0.3, 6.0, "farthest walking line (m from the camera)");
    v("path_slant", path_slant, 0.0, 3.0,
      "how much a walker's distance from the camera changes along its path (m), 0 = parallel paths");
    v("sitting", sitting, "add a seated person who gestures");
    v("path_span", path_span, 0.5, 6.4, "length of the walking paths, centred in front of the camera (m)");
    v("group", group, 0, 10, "walkers moving in step with the camera (needs [Trajectory] style = walk)");
    v("articulated", articulated, "knees and elbows bend while walking");
    v.choice("clothes", clothes, {"checker", "plain"}, "clothing texture");
    v("pause_min", pause_min, 0.0, 60.0, "shortest stand on every pass (s); the stop is in view");
    v("pause_max", pause_max, 0.0, 60.0, "longest stand on every pass (s), 0 = walkers never stop");
    v("fidget", fidget, "standing people sway, turn and gesture instead of freezing");
  }
};

/// [Sensor]
struct SensorOptions {
  bool depth_noise = true;        ///< sigma(z) = 1.2 mm + 1.9 mm (z - 0.4)^2
  bool quantize = true;           ///< Kinect disparity steps (1/8 px)
  double disparity_step = 0.0015; ///< 1/m, step of the quantised 1/z: depth steps of z^2 times this
  double max_range = 6.0;         ///< m, no depth beyond
  double grazing_angle = 80.0;    ///< deg, no depth above this incidence angle
  bool edge_dropout = true;       ///< no depth next to depth discontinuities
  double image_noise = 2.0;       ///< grey-level sigma of RGB noise
  double projector_baseline = 0;  ///< m, IR projector right of the camera: shadows (0 = off)
  double exposure = 0;            ///< s, motion blur: colour integrated over this (0 = off)
  int blur_samples = 4;           ///< renders averaged over the exposure
  double depth_radial_bias = 0;   ///< k: depth read as z (1 + k r^2), r the normalised image
                                  ///< radius (Bonn's Xtion: -0.14; doc/datasets.md)
  double disparity_distortion = 0;  ///< 1/m, amplitude of a fixed, smooth pattern of disparity
                                  ///< offsets over the image (structured-light sensors' depth
                                  ///< distortion: a surface reads differently from each view;
                                  ///< 0.002 = 1.8 cm at 3 m)
  template <class V>
  void visit(V& v) {
    v("depth_noise", depth_noise, "Kinect-like depth noise");
    v("quantize", quantize, "disparity quantisation");
    v("disparity_step", disparity_step, 0.0001, 0.01,
      "1/m, quantisation step of 1/z (Kinect 0.0015: 6 mm at 2 m; Bonn's Xtion 0.003: 12 mm at 2 m)");
    v("max_range", max_range, 0.5, 100.0, "no depth beyond (m)");
    v("grazing_angle", grazing_angle, 0.0, 90.0, "no depth above this incidence (deg)");
    v("edge_dropout", edge_dropout, "no depth at depth discontinuities");
    v("image_noise", image_noise, 0.0, 50.0, "RGB noise sigma (grey levels)");
    v("projector_baseline", projector_baseline, 0.0, 0.5,
      "m, projector offset: no depth where the projector's pattern is shadowed (0 = off)");
    v("exposure", exposure, 0.0, 0.1, "s, motion blur exposure (0 = sharp)");
    v("blur_samples", blur_samples, 2, 32, "renders averaged over the exposure");
    v("depth_radial_bias", depth_radial_bias, -0.5, 0.5,
      "k of a radial depth bias: depth read as z (1 + k r^2), r the normalised image radius (Bonn's Xtion -0.14)");
    v("disparity_distortion", disparity_distortion, 0.0, 0.05,
      "1/m, amplitude of a fixed smooth pattern of disparity offsets over the image (0 = off)");
  }
};

/// [Room]
struct RoomOptions {
  std::string style = "tiles";  ///< tiles (textured walls, posters) | office (white walls)
  std::string floor = "speckle";  ///< office floor: speckle | plain
  template <class V>
  void visit(V& v) {
    v.choice("style", style, {"tiles", "office"},
             "tiles: textured walls; office: bare white walls, texture on furniture below 1.1 m");
    v.choice("floor", floor, {"speckle", "plain"},
             "office floor: speckle (flecks a near camera tracks) or plain (linoleum, as Bonn's)");
  }
};

struct SimOptions {
  SimulatorOptions simulator;
  CameraOptions camera;
  TrajectoryOptions trajectory;
  PeopleOptions people;
  SensorOptions sensor;
  RoomOptions room;
  /// Noise-free settings for exact geometric tests.
  static SimOptions exact();
};

struct SimFrame {
  datasets::RgbdFrame frame;            ///< BGR, depth in 1/5000 m units
  cv::Mat mask;                         ///< CV_8UC1: 255 where a person is the nearest surface
  Isometry T_world_camera;              ///< optical frame; world z up
  cv::Mat true_depth;                   ///< CV_64FC1 noise-free depth (m), 0 = no surface
};

/// One picture of a frame for people: RGB | depth (colour map, 0 to max_depth metres,
/// black = no reading) | ground-truth mask, side by side (CV_8UC3).
cv::Mat sideBySide(const SimFrame& frame, double max_depth = 6.0);

class Simulator {
 public:
  explicit Simulator(const SimOptions& options);
  ~Simulator();
  const SimOptions& options() const { return options_; }
  int frameCount() const { return options_.simulator.frames; }
  double stamp(int index) const;
  Isometry cameraPose(int index) const;
  /// Camera pose at any time (s since the first frame); cameraPose(i) = cameraPoseAt(i / fps).
  Isometry cameraPoseAt(double time) const;
  /// Where each walker stands at `time` (feet on the floor, world frame), walkers first,
  /// then the camera's group, then the seated person: the ground truth of their motion.
  std::vector<Eigen::Vector3d> peoplePositions(double time) const;
  SimFrame renderFrame(int index) const;
  /// Points on all static surfaces (room, furniture), about `spacing` apart, world frame.
  std::vector<Eigen::Vector3d> staticSurfaceSamples(double spacing) const;

 private:
  struct Scene;
  struct View;
  void addWalkers(detail::Rng& rng);
  detail::PathState cameraWalk(double time) const;
  Eigen::Vector3d handheldShake(double time, bool rotation) const;
  View renderView(double time, const Isometry& T_world_camera) const;
  int renderThreads() const;
  cv::Mat addImageNoise(const cv::Mat& colour, int index) const;
  cv::Mat projectorShadows(const cv::Mat& depth) const;
  cv::Mat sensorDepth(const View& view, int index) const;
  SimOptions options_;
  std::unique_ptr<Scene> scene_;
};

}  // namespace gmc::sim
