#include <gtest/gtest.h>

#include <filesystem>

#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "mixed_rawlog.h"
#include "test_data.h"

namespace {

using namespace gmc::datasets;
using gmc::Isometry;
namespace fs = std::filesystem;

std::vector<std::string> labelsRead(const std::string& path, const SensorSelection& sensors) {
  auto source = openRgbdSource(path, {}, sensors);
  std::vector<std::string> labels;
  RgbdFrame f;
  while (source->next(f)) labels.push_back(f.sensor_label);
  return labels;
}

TEST(RawlogStream, CamerasAreSelectedByLabelInBothFormats) {
  for (bool sf : {false, true}) {
    const auto dir = gmc::testdata::scratchDir("stream_select");
    const std::string path = dir + "/robot.rawlog";
    gmc::testdata::writeRobotRawlog(path, 3, sf);
    using L = std::vector<std::string>;
    const L both = {"XTION_FRONT", "XTION_BACK", "XTION_FRONT", "XTION_BACK", "XTION_FRONT", "XTION_BACK"};
    EXPECT_EQ(labelsRead(path, {}), both) << "sensory frames " << sf;
    EXPECT_EQ(labelsRead(path, {{"XTION_BACK"}, false}), L(3, "XTION_BACK"));
    EXPECT_EQ(labelsRead(path, {{}, true}), L(3, "XTION_FRONT")) << "single camera: the first met";
    EXPECT_EQ(labelsRead(path, {{"XTION_BACK", "XTION_FRONT"}, true}), L(3, "XTION_BACK"));
    try {
      labelsRead(path, {{"KINECT"}, false});
      FAIL() << "no camera has that label";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("no CObservation3DRangeScan labelled KINECT (the rawlog's "
                                           "RGB-D sensors: 'XTION_FRONT', 'XTION_BACK')"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(RawlogStream, FrameCarriesTheObservationAndItsMounting) {
  const auto dir = gmc::testdata::scratchDir("stream_mount");
  gmc::testdata::writeRobotRawlog(dir + "/r.rawlog", 1, false);
  auto source = openRgbdSource(dir + "/r.rawlog", {});
  RgbdFrame f;
  ASSERT_TRUE(source->next(f));
  ASSERT_TRUE(f.observation);
  EXPECT_EQ(f.observation->sensorLabel, "XTION_FRONT");
  EXPECT_EQ(observationOf(f), f.observation) << "same stamp: the rawlog's own object";
  ASSERT_TRUE(f.base_camera.has_value());
  ASSERT_TRUE(source->baseCamera().has_value());
  // The optical axis (z) is the MRPT camera's forward axis (x); the origin is the pose's.
  const auto M = gmc::testdata::kFrontCameraPose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
  const Eigen::Matrix4d T = M.asEigen();
  EXPECT_LT((f.base_camera->linear().col(2) - T.block<3, 1>(0, 0)).norm(), 1e-12);
  EXPECT_LT((f.base_camera->linear().col(0) + T.block<3, 1>(0, 1)).norm(), 1e-12) << "x right = -y left";
  EXPECT_LT((f.base_camera->linear().col(1) + T.block<3, 1>(0, 2)).norm(), 1e-12) << "y down = -z up";
  EXPECT_LT((f.base_camera->translation() - T.block<3, 1>(0, 3)).norm(), 1e-12);
  RgbdFrame shifted = f;
  shifted.stamp += 10;
  EXPECT_NE(observationOf(shifted), f.observation) << "a new stamp needs a new observation";
}

TEST(RawlogStream, WriterAsSinkPassesEveryObjectOnAndDropsWhatItIsTold) {
  for (bool sf : {false, true}) {
    const auto dir = gmc::testdata::scratchDir("stream_sink");
    const auto in = gmc::testdata::writeRobotRawlog(dir + "/in.rawlog", 3, sf);
    fs::create_directories(dir + "/out");
    {
      auto source = openRgbdSource(dir + "/in.rawlog", {}, {{"XTION_FRONT", "XTION_BACK"}, false});
      RawlogWriter writer(dir + "/out/copy.rawlog");
      source->setObjectSink(&writer);
      RgbdFrame f;
      while (source->next(f)) {
        if (f.sensor_label == "XTION_BACK" && f.observation->timestamp == mrpt::Clock::fromDouble(1000.104))
          writer.drop(*f.observation);  // step 1's back camera
        else if (f.sensor_label == "XTION_FRONT")
          writer.write(*f.observation);
        // other back scans: never settled, passed on as read
      }
      writer.close();
    }
    const auto out = gmc::testdata::readAllObjects(dir + "/out/copy.rawlog");
    ASSERT_EQ(out.size(), sf ? in.size() : in.size() - 1) << "sensory frames " << sf;
    size_t j = 0;
    for (size_t i = 0; i < in.size(); ++i) {
      auto expected = in[i];
      if (sf && i == 3) {  // step 1's sensory frame, without its back camera
        auto copy = std::make_shared<mrpt::obs::CSensoryFrame>(*std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(in[i]));
        copy->eraseByLabel("XTION_BACK");
        expected = copy;
      } else if (!sf && i == 9) {
        continue;  // the dropped observation
      }
      EXPECT_EQ(gmc::testdata::serialized(*out[j++]), gmc::testdata::serialized(*expected)) << "object " << i;
    }
    // The external images of the scans written went along, under the same names.
    size_t images = 0;
    for (const auto& o : out)
      for (const auto& scan : rgbdScansOf(o)) {
        EXPECT_TRUE(fs::exists(dir + "/out/copy_Images/" + scan->intensityImage.getExternalStorageFile()));
        ++images;
      }
    EXPECT_EQ(images, 5u);
  }
}

TEST(BaseTrajectory, ConjugatesByTheMounting) {
  Isometry T_bc = Isometry::Identity();
  T_bc.translation() = Eigen::Vector3d(0.5, 0, 1.0);
  T_bc.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  // The camera moves 1 m along its optical axis (z) and turns 90 degrees about it.
  StampedPose cam{1.0, Isometry::Identity()};
  cam.pose.translation() = Eigen::Vector3d(0, 0, 1);
  cam.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto base = baseTrajectory({{0.0, Isometry::Identity()}, cam}, T_bc);
  ASSERT_EQ(base.size(), 2u);
  EXPECT_TRUE(base[0].pose.isApprox(Isometry::Identity()));
  // By hand: R_x(-90) maps the camera's z to the base's y, so the base turns 90 degrees
  // about y and moves 1 m along y, plus the swing of its origin about the camera:
  // t = R_bc t_c + t_bc - R_y t_bc.
  const Eigen::Matrix3d R_y = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d lever(0.5, 0, 1.0);
  const Eigen::Vector3d expected_t = Eigen::Vector3d(0, 1, 0) + lever - R_y * lever;
  EXPECT_LT((base[1].pose.translation() - expected_t).norm(), 1e-12);
  EXPECT_TRUE(base[1].pose.linear().isApprox(R_y));
  EXPECT_EQ(base[1].stamp, 1.0);
}

}  // namespace
