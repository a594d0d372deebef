#include "gmc/datasets/atomic_file.h"

#include <opencv2/imgcodecs.hpp>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace gmc::datasets {
namespace fs = std::filesystem;

AtomicFile::AtomicFile(std::string final_path) : final_(std::move(final_path)) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(final_);
  // Same folder (rename is atomic only within a file system); keep the extension so
  // writers that pick a format from it (OpenCV) still work.
  temp_ = (p.parent_path() / ("." + p.stem().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                              std::to_string(counter++) + p.extension().string()))
              .string();
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void AtomicFile::commit() {
  std::error_code ec;
  fs::rename(temp_, final_, ec);
  if (ec) throw std::runtime_error(final_ + ": cannot write (" + ec.message() + ")");
  committed_ = true;
}

void writeTextAtomic(const std::string& path, const std::string& text) {
  AtomicFile file(path);
  {
    std::ofstream out(file.tempPath(), std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(path + ": cannot write");
  }
  file.commit();
}

void writeImageAtomic(const std::string& path, const cv::Mat& image) {
  AtomicFile file(path);
  bool ok = false;
  try {
    ok = cv::imwrite(file.tempPath(), image);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": cannot write image (" + e.what() + ")");
  }
  if (!ok) throw std::runtime_error(path + ": cannot write image");
  file.commit();
}

}  // namespace gmc::datasets
