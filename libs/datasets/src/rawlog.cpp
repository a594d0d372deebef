#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/pixel_labels.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace gmc::datasets {
namespace fs = std::filesystem;
namespace {
/// MRPT keeps rangeUnits as a float: give back 1/n exactly (TUM's 1/5000, millimetres'
/// 1/1000) when the float is the nearest one to 1/n, so metres = raw / n exactly.
double depthUnitsOf(float range_units) {
  const double n = std::round(1.0 / range_units);
  if (n >= 1 && static_cast<float>(1.0 / n) == range_units) return 1.0 / n;
  return range_units;
}

/// A bool member as MRPT deserialised it: MRPT reads the file's byte straight into the bool,
/// so a corrupt file can leave a value other than 0 or 1 there, and reading that as a bool
/// is undefined behaviour. Read its byte instead; anything but 0 or 1 is a corrupt observation.
bool flag(const bool& member, const char* name) {
  static_assert(sizeof(bool) == 1);
  unsigned char byte = 0;
  std::memcpy(&byte, &member, 1);
  if (byte > 1)
    throw std::runtime_error(std::string(name) + " holds " + std::to_string(byte) + ", not a bool (corrupt observation)");
  return byte == 1;
}
}  // namespace

mrpt::obs::CObservation3DRangeScan::Ptr toObservation(const RgbdFrame& frame,
                                                      const std::string& sensor_label) {
  auto obs = std::make_shared<mrpt::obs::CObservation3DRangeScan>();
  obs->sensorLabel = sensor_label;
  obs->timestamp = mrpt::Clock::fromDouble(frame.stamp);
  mrpt::img::TCamera cam;
  cam.ncols = static_cast<uint32_t>(frame.depth.cols);
  cam.nrows = static_cast<uint32_t>(frame.depth.rows);
  cam.fx(frame.camera.fx);
  cam.fy(frame.camera.fy);
  cam.cx(frame.camera.cx);
  cam.cy(frame.camera.cy);
  obs->cameraParams = cam;
  obs->cameraParamsIntensity = cam;  // registered pair: same intrinsics, same centre
  obs->range_is_depth = true;
  obs->rangeUnits = static_cast<float>(frame.depth_units);
  for (const auto& [name, mask] : frame.pixel_labels) obs->pixelLabels = withLabel(obs->pixelLabels, mask, name);
  obs->hasRangeImage = true;
  obs->rangeImage.resize(frame.depth.rows, frame.depth.cols);
  for (int r = 0; r < frame.depth.rows; ++r) {
    const auto* row = frame.depth.ptr<std::uint16_t>(r);
    for (int c = 0; c < frame.depth.cols; ++c) obs->rangeImage(r, c) = row[c];
  }
  obs->hasIntensityImage = true;
  obs->intensityImage = mrpt::img::CImage(frame.rgb, mrpt::img::DEEP_COPY);
  obs->intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
  return obs;
}

RgbdFrame fromObservation(const mrpt::obs::CObservation3DRangeScan& obs) {
  const bool has_range = flag(obs.hasRangeImage, "hasRangeImage");
  const bool has_intensity = flag(obs.hasIntensityImage, "hasIntensityImage");
  const bool is_depth = flag(obs.range_is_depth, "range_is_depth");
  // Externally stored image whose file is gone: name the file (MRPT's message does not).
  if (has_intensity && obs.intensityImage.isExternallyStored()) {
    const std::string image = obs.intensityImage.getExternalStorageFileAbsolutePath();
    if (!fs::is_regular_file(image)) throw std::runtime_error("external image " + image + " is missing");
  }
  obs.load();  // externally stored images
  if (!has_range) throw std::runtime_error("observation has no range image");
  if (!has_intensity) throw std::runtime_error("observation has no intensity image");
  if (!is_depth)
    throw std::runtime_error("observation holds ranges, not depth (range_is_depth = false)");
  if (!(std::isfinite(obs.rangeUnits) && obs.rangeUnits > 0))
    throw std::runtime_error("rangeUnits " + std::to_string(obs.rangeUnits) + " is not a positive number");
  const auto& cam = obs.cameraParamsIntensity;
  if (!(std::isfinite(cam.fx()) && cam.fx() > 0 && std::isfinite(cam.fy()) && cam.fy() > 0 &&
        std::isfinite(cam.cx()) && std::isfinite(cam.cy())))
    throw std::runtime_error("no valid intensity camera intrinsics");
  const auto& ri = obs.rangeImage;
  const cv::Mat& img = obs.intensityImage.asCvMatRef();
  if (ri.rows() == 0 || ri.cols() == 0) throw std::runtime_error("empty range image");
  if (img.rows != static_cast<int>(ri.rows()) || img.cols != static_cast<int>(ri.cols()))
    throw std::runtime_error("intensity image is " + std::to_string(img.cols) + "x" +
                             std::to_string(img.rows) + ", range image is " +
                             std::to_string(ri.cols()) + "x" + std::to_string(ri.rows()) +
                             " (a registered RGB-D pair has one size)");
  if (img.depth() != CV_8U || (img.channels() != 1 && img.channels() != 3))
    throw std::runtime_error("intensity image must be 8-bit grey or colour");
  RgbdFrame f;
  f.stamp = mrpt::Clock::toDouble(obs.timestamp);
  f.depth_units = depthUnitsOf(obs.rangeUnits);
  f.depth.create(static_cast<int>(ri.rows()), static_cast<int>(ri.cols()), CV_16UC1);
  for (int r = 0; r < f.depth.rows; ++r) {
    auto* row = f.depth.ptr<std::uint16_t>(r);
    for (int c = 0; c < f.depth.cols; ++c) row[c] = ri(r, c);
  }
  if (img.channels() == 1)
    cv::cvtColor(img, f.rgb, cv::COLOR_GRAY2BGR);
  else
    f.rgb = img;  // shared, read-only use
  f.camera.fx = cam.fx();
  f.camera.fy = cam.fy();
  f.camera.cx = cam.cx();
  f.camera.cy = cam.cy();
  f.camera.width = f.depth.cols;
  f.camera.height = f.depth.rows;
  return f;
}

mrpt::obs::CObservation3DRangeScan::Ptr observationOf(const RgbdFrame& frame) {
  if (frame.observation && mrpt::Clock::toDouble(frame.observation->timestamp) == frame.stamp)
    return frame.observation;
  return toObservation(frame, frame.sensor_label.empty() ? "RGBD" : frame.sensor_label);
}

RawlogWriter::RawlogWriter(const std::string& path, bool externalize_images)
    : path_(path), externalize_(externalize_images), file_(path) {
  const fs::path p(path);
  images_dir_ = (p.parent_path() / (p.stem().string() + "_Images")).string();
  if (externalize_) ensureImagesDir();
  out_ = std::make_unique<mrpt::io::CFileGZOutputStream>();
  if (!out_->open(file_.tempPath(), 1))
    throw std::runtime_error(path + ": cannot create rawlog");
}

RawlogWriter::~RawlogWriter() {
  if (!out_) return;  // closed
  out_.reset();
  std::error_code ec;
  if (created_images_dir_) fs::remove_all(images_dir_, ec);
}

void RawlogWriter::ensureImagesDir() {
  if (!fs::is_directory(images_dir_)) created_images_dir_ = fs::create_directories(images_dir_);
}

void RawlogWriter::write(const RgbdFrame& frame, const std::string& sensor_label) {
  auto obs = toObservation(frame, sensor_label);
  write(*obs);
}

void RawlogWriter::write(mrpt::obs::CObservation3DRangeScan& obs) {
  if (!out_) throw std::runtime_error(path_ + ": rawlog already closed");
  const size_t queued = queuedIndexOf(obs);
  if (queued < queue_.size()) return flushBefore(queued);
  if (externalize_ && obs.hasIntensityImage && !obs.intensityImage.isExternallyStored()) {
    char name[64];
    std::snprintf(name, sizeof name, "%s_%.6f.png", obs.sensorLabel.c_str(),
                  mrpt::Clock::toDouble(obs.timestamp));
    if (!obs.intensityImage.saveToFile((fs::path(images_dir_) / name).string()))
      throw std::runtime_error(images_dir_ + "/" + name + ": cannot write image");
    obs.intensityImage.setExternalStorage(name);
  }
  writeObject(obs);
}

void RawlogWriter::drop(const mrpt::obs::CObservation3DRangeScan& obs) {
  const size_t queued = queuedIndexOf(obs);
  if (queued == queue_.size()) return;
  auto& entry = queue_[queued];
  if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(entry.object)) {
    for (auto it = sf->begin(); it != sf->end(); ++it)
      if (it->get() == &obs) {
        sf->erase(it);
        break;
      }
  } else {
    entry.dropped = true;
  }
  flushBefore(queued);
}

void RawlogWriter::objectRead(const mrpt::serialization::CSerializable::Ptr& object) {
  if (!out_) throw std::runtime_error(path_ + ": rawlog already closed");
  queue_.push_back({object});
}

size_t RawlogWriter::queuedIndexOf(const mrpt::obs::CObservation3DRangeScan& obs) const {
  for (size_t i = 0; i < queue_.size(); ++i)
    for (const auto& scan : rgbdScansOf(queue_[i].object))
      if (scan.get() == &obs) return i;
  return queue_.size();
}

void RawlogWriter::flushBefore(size_t index) {
  for (size_t i = 0; i < index && !queue_.empty(); ++i) {
    const Queued entry = std::move(queue_.front());
    queue_.pop_front();
    if (entry.dropped || !entry.object) continue;
    copyExternalImages(entry.object);
    writeObject(*entry.object);
  }
}

void RawlogWriter::writeObject(const mrpt::serialization::CSerializable& object) {
  auto archive = mrpt::serialization::archiveFrom(*out_);
  archive << object;
  ++count_;
}

namespace {
/// The images an observation may keep in files of its own.
std::vector<const mrpt::img::CImage*> imagesOf(const mrpt::obs::CObservation& obs) {
  if (auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs))
    return {&scan->intensityImage, &scan->confidenceImage};
  if (auto* image = dynamic_cast<const mrpt::obs::CObservationImage*>(&obs)) return {&image->image};
  if (auto* stereo = dynamic_cast<const mrpt::obs::CObservationStereoImages*>(&obs))
    return {&stereo->imageLeft, &stereo->imageRight, &stereo->imageDisparity};
  return {};
}
}  // namespace

void RawlogWriter::copyExternalImages(const mrpt::serialization::CSerializable::Ptr& object) {
  std::vector<mrpt::obs::CObservation::Ptr> observations;
  if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object))
    observations.assign(sf->begin(), sf->end());
  else if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object))
    observations.push_back(obs);
  for (const auto& obs : observations) {
    if (!obs) continue;
    for (const auto* image : imagesOf(*obs)) {
      if (!image->isExternallyStored()) continue;
      const fs::path relative = image->getExternalStorageFile();
      if (relative.is_absolute()) continue;  // found wherever this rawlog goes
      const fs::path from = image->getExternalStorageFileAbsolutePath();
      const fs::path to = fs::path(images_dir_) / relative;
      if (fs::exists(to) || !fs::exists(from)) continue;  // a missing file stays missing
      ensureImagesDir();
      fs::create_directories(to.parent_path());
      fs::copy_file(from, to);
    }
  }
}

void RawlogWriter::close() {
  if (!out_) return;
  flushBefore(queue_.size());
  out_->close();
  out_.reset();
  file_.commit();
}

}  // namespace gmc::datasets
