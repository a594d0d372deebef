#pragma once
// "Write to a temporary name, rename when complete": no output is ever half-written.
#include <opencv2/core.hpp>

#include <string>

namespace gmc::datasets {

/// A temporary path next to `final_path`; commit() renames it into place, the
/// destructor removes it when commit() was never called.
class AtomicFile {
 public:
  explicit AtomicFile(std::string final_path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& tempPath() const { return temp_; }
  const std::string& finalPath() const { return final_; }
  /// Renames the temporary file to the final path; throws std::runtime_error naming it.
  void commit();

 private:
  std::string final_, temp_;
  bool committed_ = false;
};

/// Writes `text` atomically; throws std::runtime_error naming the file.
void writeTextAtomic(const std::string& path, const std::string& text);
/// Writes an image (format from the extension) atomically; throws naming the file.
void writeImageAtomic(const std::string& path, const cv::Mat& image);

}  // namespace gmc::datasets
