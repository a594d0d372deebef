#pragma once
// A rawlog that holds no RGB-D observation: a laser scan, odometry, another scan (the
// "wrong observation class" case of doc/robustness.md).
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <string>

namespace gmc::testdata {

inline std::string writeWrongClassRawlog(const std::string& path) {
  mrpt::io::CFileGZOutputStream out(path);
  auto archive = mrpt::serialization::archiveFrom(out);
  mrpt::obs::CObservation2DRangeScan scan;
  scan.resizeScan(180);
  mrpt::obs::CObservationOdometry odo;
  archive << scan << odo << scan;
  return path;
}

}  // namespace gmc::testdata
