#pragma once
// A rawlog as a robot records it: wheel odometry, an IMU, a 2-D laser and two RGB-D
// cameras with their own labels and sensor poses, colour images stored outside the
// rawlog; in the observation-only format or as (actions, sensory frame) pairs.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "gmc/datasets/rawlog.h"
#include "random_frame.h"

namespace gmc::testdata {

inline const mrpt::poses::CPose3D kFrontCameraPose(0.30, 0.05, 0.60, 0.1, -0.2, 0.05);
inline const mrpt::poses::CPose3D kBackCameraPose(-0.25, 0.0, 0.55, 3.1, 0.0, 0.0);

/// One RGB-D scan, labelled and mounted, its colour image stored in `images_dir`.
inline mrpt::obs::CObservation3DRangeScan::Ptr mountedScan(const std::string& label,
                                                          const mrpt::poses::CPose3D& pose,
                                                          double stamp, unsigned seed,
                                                          const std::string& images_dir) {
  const auto f = randomFrame(stamp, seed, 5000, 15000);
  auto scan = gmc::datasets::toObservation(f, label);
  scan->sensorPose = pose;
  const std::string name = label + "_" + std::to_string(seed) + ".png";
  cv::imwrite(images_dir + "/" + name, f.rgb);
  scan->intensityImage.setExternalStorage(name);
  return scan;
}

/// The observations of step `i`, in recording order.
inline std::vector<mrpt::obs::CObservation::Ptr> robotStep(int i, const std::string& images_dir) {
  const double t = 1000.0 + i * 0.1;
  auto odo = std::make_shared<mrpt::obs::CObservationOdometry>();
  odo->sensorLabel = "WHEEL_ODOM";
  odo->timestamp = mrpt::Clock::fromDouble(t);
  odo->odometry = mrpt::poses::CPose2D(0.1 * i, 0.0, 0.01 * i);
  auto imu = std::make_shared<mrpt::obs::CObservationIMU>();
  imu->sensorLabel = "IMU";
  imu->timestamp = mrpt::Clock::fromDouble(t + 0.001);
  imu->set(mrpt::obs::IMU_WZ, 0.1 * i);
  auto laser = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  laser->sensorLabel = "LASER";
  laser->timestamp = mrpt::Clock::fromDouble(t + 0.002);
  laser->resizeScanAndAssign(31, 2.5f + 0.01f * i, true);
  return {odo, imu,
          mountedScan("XTION_FRONT", kFrontCameraPose, t + 0.003, 100 + i, images_dir), laser,
          mountedScan("XTION_BACK", kBackCameraPose, t + 0.004, 200 + i, images_dir)};
}

/// Writes `steps` robot steps to `path` (images in "<stem>_Images/"); returns the objects
/// written, in order.
inline std::vector<mrpt::serialization::CSerializable::Ptr> writeRobotRawlog(const std::string& path,
                                                                             int steps,
                                                                             bool sensory_frames) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const std::string images = (p.parent_path() / (p.stem().string() + "_Images")).string();
  fs::create_directories(images);
  std::vector<mrpt::serialization::CSerializable::Ptr> objects;
  for (int i = 0; i < steps; ++i) {
    const auto step = robotStep(i, images);
    if (!sensory_frames) {
      objects.insert(objects.end(), step.begin(), step.end());
      continue;
    }
    auto actions = std::make_shared<mrpt::obs::CActionCollection>();
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0.01),
                             mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
    actions->insert(move);
    auto sf = std::make_shared<mrpt::obs::CSensoryFrame>();
    for (const auto& o : step) sf->insert(o);
    objects.push_back(actions);
    objects.push_back(sf);
  }
  mrpt::io::CFileGZOutputStream out(path);
  auto archive = mrpt::serialization::archiveFrom(out);
  for (const auto& o : objects) archive << *o;
  return objects;
}

/// Every object of a rawlog, in order.
inline std::vector<mrpt::serialization::CSerializable::Ptr> readAllObjects(const std::string& path) {
  std::vector<mrpt::serialization::CSerializable::Ptr> objects;
  mrpt::io::CFileGZInputStream in(path);
  auto archive = mrpt::serialization::archiveFrom(in);
  while (true) {
    mrpt::serialization::CSerializable::Ptr o;
    try {
      archive >> o;
    } catch (const mrpt::serialization::CExceptionEOF&) {
      break;
    }
    objects.push_back(o);
  }
  return objects;
}

/// The bytes MRPT writes for `object` (equal bytes: equal objects, every field).
inline std::vector<uint8_t> serialized(const mrpt::serialization::CSerializable& object) {
  mrpt::io::CMemoryStream buffer;
  auto archive = mrpt::serialization::archiveFrom(buffer);
  archive << object;
  const auto* data = static_cast<const uint8_t*>(buffer.getRawBufferData());
  return {data, data + buffer.getTotalBytesCount()};
}

}  // namespace gmc::testdata
