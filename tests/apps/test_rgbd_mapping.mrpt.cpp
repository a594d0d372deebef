// gmc-rawlog-filter and gmc-rgbd-mapping as parts of an MRPT rawlog tool chain: nothing
// they do not filter is lost, cameras are chosen by label, the robot base is followed,
// the configuration is found and printed.
#include <gtest/gtest.h>

#include <mrpt/obs/CObservationIMU.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include "gmc/apps/config_files.h"
#include "gmc/apps/rawlog_filter_app.h"
#include "gmc/apps/rgbd_mapping_app.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "mixed_rawlog.h"
#include "run_app.h"
#include "test_data.h"
#include "wall_sequence.h"

namespace {

namespace fs = std::filesystem;
using gmc::testdata::readAllObjects;
using gmc::testdata::serialized;

int runFilter(std::vector<std::string> args) {
  return gmc::testdata::runApp<gmc::apps::RawlogFilterApp>("gmc-rawlog-filter", std::move(args));
}
int runMapping(std::vector<std::string> args) {
  return gmc::testdata::runApp<gmc::apps::RgbdMappingApp>("gmc-rgbd-mapping", std::move(args));
}

/// What `rawlog-edit --info` says about the content (format, objects, sensors and counts).
std::string rawlogInfo(const std::string& path) {
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(("rawlog-edit --info -i '" + path + "' 2>&1").c_str(), "r"), pclose);
  std::array<char, 512> line{};
  while (pipe && fgets(line.data(), line.size(), pipe.get())) {
    const std::string l = line.data();
    for (const char* key : {"Overall number", "Actions/SensoryFrame", "Observations format", "timestamp",
                            "All sensor labels", "Sensor ("})
      if (l.find(key) != std::string::npos) out += l;
  }
  return out;
}

/// Every object of `out` equals the one of `in` at the same place, except that the scans
/// labelled as in `labelled` carry pixel labels (compared without them).
void expectSameExceptLabels(const std::string& in, const std::string& out, const std::set<std::string>& labelled) {
  const auto a = readAllObjects(in), b = readAllObjects(out);
  ASSERT_EQ(a.size(), b.size());
  size_t labelled_scans = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const auto scans_in = gmc::datasets::rgbdScansOf(a[i]), scans_out = gmc::datasets::rgbdScansOf(b[i]);
    ASSERT_EQ(scans_in.size(), scans_out.size());
    for (size_t k = 0; k < scans_out.size(); ++k) {
      const bool selected = labelled.count(scans_out[k]->sensorLabel) > 0;
      EXPECT_EQ(scans_out[k]->hasPixelLabels(), selected) << "object " << i << " " << scans_out[k]->sensorLabel;
      labelled_scans += selected ? 1 : 0;
      if (selected) {
        EXPECT_EQ(scans_out[k]->pixelLabels->getLabelName(0), "dynamic");
      }
      scans_out[k]->pixelLabels.reset();  // the one difference allowed
      EXPECT_EQ(serialized(*scans_out[k]), serialized(*scans_in[k])) << "object " << i;
    }
    EXPECT_EQ(serialized(*b[i]), serialized(*a[i])) << "object " << i << " " << a[i]->GetRuntimeClass()->className;
  }
  EXPECT_GT(labelled_scans, 0u);
}

TEST(RawlogFilterApp, EveryCameraIsFilteredWhenNoLabelIsGiven) {
  const auto root = gmc::testdata::scratchDir("filter_every_camera");
  gmc::testdata::writeRobotRawlog(root + "/robot.rawlog", 3, true);
  std::ofstream(root + "/f.ini") << "[Filters]\nchain = gmc\n";
  ASSERT_EQ(runFilter({root + "/f.ini", root + "/robot.rawlog", root + "/out.rawlog"}), 0);
  expectSameExceptLabels(root + "/robot.rawlog", root + "/out.rawlog", {"XTION_FRONT", "XTION_BACK"});
}

TEST(RawlogFilterApp, PassesEveryObjectOnUnchangedInBothRawlogFormats) {
  for (bool sf : {false, true}) {
    const auto root = gmc::testdata::scratchDir("filter_lossless");
    gmc::testdata::writeRobotRawlog(root + "/robot.rawlog", 4, sf);
    std::ofstream(root + "/f.ini") << "[Filters]\nchain = depth_range@Everything, gmc\nsensor_label = XTION_FRONT\n"
                                      "[Everything]\nmin_depth = 0\nmax_depth = 100\n";
    fs::create_directories(root + "/out");
    ASSERT_EQ(runFilter({root + "/f.ini", root + "/robot.rawlog", root + "/out/robot.rawlog"}), 0);
    expectSameExceptLabels(root + "/robot.rawlog", root + "/out/robot.rawlog", {"XTION_FRONT"});
    for (const auto& image : fs::directory_iterator(root + "/robot_Images"))
      EXPECT_TRUE(fs::exists(root + "/out/robot_Images/" + image.path().filename().string())) << image.path();
    const std::string info = rawlogInfo(root + "/out/robot.rawlog");
    EXPECT_NE(info.find("XTION_BACK"), std::string::npos) << info;
    EXPECT_EQ(info, rawlogInfo(root + "/robot.rawlog")) << "sensory frames " << sf;
  }
}

TEST(RgbdMappingApp, FilteredRawlogPassesEveryObjectOn) {
  const auto root = gmc::testdata::scratchDir("mapping_lossless");
  gmc::testdata::writeRobotRawlog(root + "/robot.rawlog", 4, true);
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", root + "/robot.rawlog", "--out", root + "/out",
                        "--set", "Output.filtered_rawlog=true", "--set", "Output.map=false",
                        "--set", "Filters.sensor_label=XTION_FRONT"}),
            0);
  expectSameExceptLabels(root + "/robot.rawlog", root + "/out/filtered.rawlog", {"XTION_FRONT"});
  for (const auto& image : fs::directory_iterator(root + "/robot_Images"))
    EXPECT_TRUE(fs::exists(root + "/out/filtered_Images/" + image.path().filename().string())) << image.path();
}

// Issue #18: a chain the odometry cannot use was found per frame, after the outputs were opened.
TEST(RgbdMappingApp, ChainWithoutTheOdometryFailsBeforeAnyOutput) {
  const auto root = gmc::testdata::scratchDir("mapping_chain_check");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 2);
  testing::internal::CaptureStderr();
  EXPECT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", root + "/out", "--set",
                        "Filters.chain=depth_range, decimate"}),
            1);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("[Filters] chain must contain a filter that provides 'tracking' (gmc)"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(root + "/out")) << "no output opened";
}

/// The wall sequence as a robot's rawlog: the camera "XTION_FRONT" mounted at `mount`, a
/// second camera and wheel odometry interleaved.
void writeMountedWallRawlog(const std::string& seq, const std::string& path, const mrpt::poses::CPose3D& mount) {
  auto source = gmc::datasets::openRgbdSource(seq, gmc::PinholeCamera{535.4, 539.2, 320.1, 247.6, 640, 480});
  gmc::datasets::RawlogWriter writer(path);
  gmc::datasets::RgbdFrame frame;
  while (source->next(frame)) {
    mrpt::obs::CObservationIMU imu;
    imu.sensorLabel = "IMU";
    imu.timestamp = mrpt::Clock::fromDouble(frame.stamp);
    writer.objectRead(std::make_shared<mrpt::obs::CObservationIMU>(imu));
    auto front = gmc::datasets::toObservation(frame, "XTION_FRONT");
    front->sensorPose = mount;
    writer.objectRead(front);
    gmc::datasets::RgbdFrame other = frame;  // another view: the picture upside down
    cv::flip(frame.rgb, other.rgb, -1);
    auto back = gmc::datasets::toObservation(other, "XTION_BACK");
    back->sensorPose = gmc::testdata::kBackCameraPose;
    writer.objectRead(back);
  }
  writer.close();
}

TEST(RgbdMappingApp, RobotBaseTrajectoryOfAMountedCameraMatchesTheGroundTruth) {
  const auto root = gmc::testdata::scratchDir("mapping_robot");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 30);
  const mrpt::poses::CPose3D mount(0.20, -0.10, 0.80, 0.3, 0.0, 0.0);  // yawed 17 degrees
  writeMountedWallRawlog(seq, root + "/robot.rawlog", mount);
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", root + "/robot.rawlog", "--out", root + "/out",
                        "--set", "Filters.sensor_label=XTION_FRONT", "--set", "Output.map=false"}),
            0);
  const auto camera = gmc::datasets::readTumTrajectory(root + "/out/trajectory_tum.txt");
  const auto base = gmc::datasets::readTumTrajectory(root + "/out/trajectory_base_tum.txt");
  const auto gt = gmc::datasets::readTumTrajectory(seq + "/groundtruth.txt");
  ASSERT_EQ(base.size(), 30u);
  ASSERT_EQ(camera.size(), 30u);
  // Ground truth of the base, by hand: the camera slides along its x (right), which on a
  // base yawed by 0.3 rad is the direction (sin 0.3, -cos 0.3, 0); the base turns not.
  double worst_position = 0, worst_angle = 0;
  for (size_t i = 0; i < base.size(); ++i) {
    const double s = gt[i].pose.translation().x() - gt[0].pose.translation().x();
    const Eigen::Vector3d expected(s * std::sin(0.3), -s * std::cos(0.3), 0.0);
    worst_position = std::max(worst_position, (base[i].pose.translation() - expected).norm());
    worst_angle = std::max(worst_angle, Eigen::AngleAxisd(base[i].pose.linear()).angle());
  }
  std::printf("  mounted camera: base trajectory off the ground truth by at most %.4f m, %.4f rad\n",
              worst_position, worst_angle);
  EXPECT_LT(worst_position, 0.01);
  EXPECT_LT(worst_angle, 0.01);
  EXPECT_NEAR(camera.back().pose.translation().x(), 0.29, 0.01) << "camera trajectory stays optical";
}

TEST(RgbdMappingApp, ShippedConfigurationIsFoundByName) {
  const auto found = gmc::apps::findConfig("default");
  EXPECT_EQ(fs::path(found).filename(), "default.ini");
  EXPECT_EQ(fs::path(found).parent_path().filename(), "config");
  EXPECT_NE(found.find("share/gmc-rgbd/config"), std::string::npos) << found;
  EXPECT_NE(gmc::apps::findConfig("bonn").find("bonn.ini"), std::string::npos);
  const auto p = gmc::apps::invocationPaths({"seq"}, "", false);
  EXPECT_EQ(p.config, found) << "no configuration named: the shipped default";
  EXPECT_EQ(p.input, "seq");
  EXPECT_FALSE(gmc::apps::invocationPaths({"a.ini", "seq"}, "bonn", false).error.empty());
  EXPECT_THROW(gmc::apps::findConfig("no_such_preset"), gmc::apps::AppError);
}

/// Keys per section of an INI text (comments and blank lines ignored).
std::set<std::string> iniKeys(std::istream& in) {
  std::set<std::string> keys;
  std::string line, section;
  while (std::getline(in, line)) {
    const auto b = line.find_first_not_of(" \t");
    if (b == std::string::npos || line[b] == ';' || line[b] == '#') continue;
    if (line[b] == '[') {
      section = line.substr(b + 1, line.find(']') - b - 1);
      continue;
    }
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    std::string key = line.substr(b, eq - b);
    key.erase(key.find_last_not_of(" \t") + 1);
    keys.insert(section + "." + key);
  }
  return keys;
}

TEST(RgbdMappingApp, PrintConfigListsExactlyTheKeysDocumentedInDefaultIni) {
  std::ifstream documented_file(GMC_SOURCE_DIR "/config/default.ini");
  const auto documented = iniKeys(documented_file);
  std::istringstream printed_text(gmc::apps::effectiveConfigText(GMC_SOURCE_DIR "/config/default.ini", {}));
  const auto printed = iniKeys(printed_text);
  for (const auto& k : printed) EXPECT_TRUE(documented.count(k)) << k << " is not documented in config/default.ini";
  for (const auto& k : documented) EXPECT_TRUE(printed.count(k)) << k << " is documented but not read";
  EXPECT_GT(printed.size(), 60u);
  std::istringstream lines(gmc::apps::effectiveConfigText(GMC_SOURCE_DIR "/config/default.ini", {}));
  for (std::string line; std::getline(lines, line);)  // every key with its comment
    if (line.find(" = ") != std::string::npos) {
      EXPECT_NE(line.find(" ; "), std::string::npos) << line;
    }
  testing::internal::CaptureStdout();
  EXPECT_EQ(runMapping({"--print-config", "--config", "bonn", "--set", "GMC.grid_cols=16"}), 0);
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_NE(out.find("camera = bonn"), std::string::npos) << out;
  EXPECT_NE(out.find("grid_cols = 16"), std::string::npos) << out;
}

}  // namespace
