// gmc-sim run in-process: file layout, determinism, overrides and user errors.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "gmc/apps/sim_app.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "gmc/sim/simulator.h"
#include "run_app.h"
#include "test_data.h"

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int runSim(std::vector<std::string> args) {
  return gmc::testdata::runApp<gmc::apps::SimApp>("gmc-sim", std::move(args));
}

/// A quarter-resolution configuration (fr3 intrinsics scaled), `frames` long.
std::string writeSmallIni(const std::string& path, int frames, int threads) {
  std::ofstream(path) << "[Simulator]\nframes = " << frames << "\nthreads = " << threads
                      << "\n[Camera]\nwidth = 160\nheight = 120\n"
                         "fx = 133.85\nfy = 134.8\ncx = 79.9\ncy = 61.8\n"
                         "[People]\nwalkers = 3\n";
  return path;
}

TEST(SimApp, SameSeedGivesByteIdenticalOutput) {
  const auto root = gmc::testdata::scratchDir("sim_determinism");
  // Different thread counts: the output must not depend on how rows are shared out.
  ASSERT_EQ(runSim({writeSmallIni(root + "/s.ini", 3, 2), "--out", root + "/a", "--seed", "7"}), 0);
  ASSERT_EQ(runSim({writeSmallIni(root + "/t.ini", 3, 1), "--out", root + "/b", "--seed", "7"}), 0);
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(root + "/a")) {
    if (!e.is_regular_file()) continue;
    const auto rel = fs::relative(e.path(), root + "/a");
    EXPECT_EQ(slurp(e.path()), slurp(fs::path(root + "/b") / rel)) << rel;
    ++files;
  }
  EXPECT_EQ(files, 3u * 3u + 5u);  // rgb, depth, masks per frame; lists, gt, rawlog, scene
  ASSERT_EQ(runSim({root + "/s.ini", "--out", root + "/c", "--seed", "8"}), 0);
  const std::string first = fs::directory_iterator(root + "/a/rgb")->path().filename();
  EXPECT_NE(slurp(fs::path(root + "/a/rgb") / first), slurp(fs::path(root + "/c/rgb") / first));
}

TEST(SimApp, WritesTumLayoutMasksRawlogAndScene) {
  const auto root = gmc::testdata::scratchDir("sim_layout");
  const std::string ini = writeSmallIni(root + "/s.ini", 40, 2);
  ASSERT_EQ(runSim({ini, "--out", root + "/o", "--frames", "4", "--seed", "3", "--preview", "2"}), 0);
  const std::string dir = root + "/o";

  gmc::sim::SimOptions options;
  options.simulator.frames = 4, options.simulator.seed = 3;
  options.camera = {133.85, 134.8, 79.9, 61.8, 160, 120};
  const gmc::sim::Simulator sim(options);

  const auto rgb = gmc::datasets::readTumList(dir + "/rgb.txt");
  const auto depth = gmc::datasets::readTumList(dir + "/depth.txt");
  const auto gt = gmc::datasets::readTumTrajectory(dir + "/groundtruth.txt");
  ASSERT_EQ(rgb.size(), 4u);  // --frames overrides the INI's 40
  ASSERT_EQ(depth.size(), 4u);
  ASSERT_EQ(gt.size(), 4u);
  EXPECT_EQ(rgb[1].path, "rgb/1000000000.033333.png");
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(rgb[i].stamp, sim.stamp(i), 1e-6);
    EXPECT_NEAR(gt[i].stamp, rgb[i].stamp, 1e-9);
    EXPECT_LT((gt[i].pose.matrix() - sim.cameraPose(i).matrix()).cwiseAbs().maxCoeff(), 1e-6);
    const auto truth = sim.renderFrame(i);
    const cv::Mat d = cv::imread(dir + "/" + depth[i].path, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(d.type(), CV_16UC1) << depth[i].path;
    EXPECT_EQ(cv::norm(d, truth.frame.depth, cv::NORM_INF), 0.0);
    const std::string mask_path = dir + "/masks/" + fs::path(rgb[i].path).filename().string();
    const cv::Mat m = cv::imread(mask_path, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(m.type(), CV_8UC1) << mask_path;
    EXPECT_EQ(cv::norm(m, truth.mask, cv::NORM_INF), 0.0);
  }

  // preview.png: frame 2's RGB | depth | mask.
  const cv::Mat preview = cv::imread(dir + "/preview.png", cv::IMREAD_COLOR);
  ASSERT_EQ(preview.cols, 3 * 160);
  ASSERT_EQ(preview.rows, 120);
  EXPECT_EQ(cv::norm(preview.colRange(0, 160), sim.renderFrame(2).frame.rgb, cv::NORM_INF), 0.0);

  // The rawlog holds the same frames.
  const auto source = gmc::datasets::openRgbdSource(dir + "/sequence.rawlog", {});
  gmc::datasets::RgbdFrame f;
  int n = 0;
  while (source->next(f)) {
    const auto truth = sim.renderFrame(n);
    EXPECT_NEAR(f.stamp, truth.frame.stamp, 1e-6);
    EXPECT_EQ(cv::norm(f.depth, truth.frame.depth, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(f.rgb, truth.frame.rgb, cv::NORM_INF), 0.0);
    EXPECT_DOUBLE_EQ(f.camera.fx, 133.85);
    ++n;
  }
  EXPECT_EQ(n, 4);

  // scene.xyz: a header line, then the static samples, one "x y z" per line.
  std::ifstream xyz(dir + "/scene.xyz");
  std::string header;
  std::getline(xyz, header);
  EXPECT_EQ(header.rfind("#", 0), 0u);
  size_t points = 0;
  for (double x, y, z; xyz >> x >> y >> z;) ++points;
  EXPECT_EQ(points, sim.staticSurfaceSamples(0.02).size());
  for (const auto& e : fs::directory_iterator(root))  // no temporary folder left behind
    EXPECT_EQ(e.path().filename().string().find(".o.partial"), std::string::npos) << e.path();
}

TEST(SimApp, BadConfigurationIsNamed) {
  const auto root = gmc::testdata::scratchDir("sim_bad");
  std::ofstream(root + "/a.ini") << "[People]\nwalkerz = 2\n";
  EXPECT_EQ(runSim({root + "/a.ini", "--out", root + "/o"}), 1);
  std::ofstream(root + "/b.ini") << "[Trajectory]\nstyle = loop\n";
  EXPECT_EQ(runSim({root + "/b.ini", "--out", root + "/o"}), 1);
  std::ofstream(root + "/c.ini") << "[Lights]\nsun = 1\n";
  EXPECT_EQ(runSim({root + "/c.ini", "--out", root + "/o"}), 1);
  std::ofstream(root + "/d.ini") << "[People]\nspeed_min = 1.5\nspeed_max = 0.5\n";
  EXPECT_EQ(runSim({root + "/d.ini", "--out", root + "/o"}), 1);
  // Overrides are range-checked like INI values.
  std::ofstream(root + "/ok.ini") << "[Simulator]\nframes = 1\n";
  EXPECT_EQ(runSim({root + "/ok.ini", "--out", root + "/o", "--seed", "2100000000"}), 1);
  EXPECT_EQ(runSim({root + "/a.ini"}), 2);
  EXPECT_EQ(runSim({root + "/a.ini", "--out", root + "/o", "--frames", "x"}), 2);
  EXPECT_EQ(runSim({root + "/a.ini", "--out", root + "/o", "--frames", "0"}), 2);
  EXPECT_EQ(runSim({root + "/ok.ini", "--out", root + "/o", "--preview", "1"}), 2);
  EXPECT_EQ(runSim({root + "/missing.ini", "--out", root + "/o"}), 1);
  EXPECT_FALSE(fs::exists(root + "/o"));
  // A folder that is not an earlier gmc-sim output is never replaced.
  fs::create_directories(root + "/keep");
  std::ofstream(root + "/keep/notes.txt") << "mine";
  EXPECT_EQ(runSim({root + "/ok.ini", "--out", root + "/keep"}), 1);
  EXPECT_EQ(slurp(root + "/keep/notes.txt"), "mine");
}

}  // namespace
