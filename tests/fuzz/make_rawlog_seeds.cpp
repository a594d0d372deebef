// Writes the rawlog seeds of corpus/rawlog/ (tiny 8x6 frames, a few hundred bytes each):
//   make_rawlog_seeds <dir>
// plain.rawlog (uncompressed, so mutations hit object fields, not deflate data),
// gz.rawlog (what RawlogWriter writes), sf_odometry.rawlog (sensory-frame format with an
// odometry observation) and external.rawlog (image stored outside, as --externalize does).
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <string>

#include "gmc/datasets/rawlog.h"

namespace {
gmc::datasets::RgbdFrame tinyFrame(double stamp) {
  gmc::datasets::RgbdFrame f;
  f.stamp = stamp;
  f.rgb = cv::Mat(6, 8, CV_8UC3, cv::Scalar(10, 120, 230));
  f.depth = cv::Mat(6, 8, CV_16UC1, cv::Scalar(10000));
  f.camera.fx = f.camera.fy = 7.0;
  f.camera.cx = 3.5, f.camera.cy = 2.5;
  f.camera.width = 8, f.camera.height = 6;
  return f;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_rawlog_seeds <dir>\n");
    return 2;
  }
  const std::string dir = argv[1];
  {
    mrpt::io::CFileOutputStream out(dir + "/plain.rawlog");
    auto archive = mrpt::serialization::archiveFrom(out);
    for (int i = 0; i < 2; ++i) archive << *gmc::datasets::toObservation(tinyFrame(1000.0 + i));
  }
  {
    gmc::datasets::RawlogWriter w(dir + "/gz.rawlog");
    w.write(tinyFrame(1000.0));
    w.close();
  }
  {
    mrpt::io::CFileOutputStream out(dir + "/sf_odometry.rawlog");
    auto archive = mrpt::serialization::archiveFrom(out);
    mrpt::obs::CActionCollection actions;
    mrpt::obs::CSensoryFrame sf;
    auto odo = std::make_shared<mrpt::obs::CObservationOdometry>();
    odo->timestamp = mrpt::Clock::fromDouble(1000.0);
    sf.insert(odo);
    sf.insert(gmc::datasets::toObservation(tinyFrame(1000.0)));
    archive << actions << sf;
  }
  {
    auto obs = gmc::datasets::toObservation(tinyFrame(1000.0));
    obs->intensityImage.setExternalStorage("RGBD_1000.000000.png");
    mrpt::io::CFileOutputStream out(dir + "/external.rawlog");
    auto archive = mrpt::serialization::archiveFrom(out);
    archive << *obs;
  }
  return 0;
}
