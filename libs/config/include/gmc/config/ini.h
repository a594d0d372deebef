#pragma once
// Strict INI sections for option structs that describe themselves with visit()
// (see gmc/gmc/options.h). Unknown keys, malformed numbers and out-of-range values
// are errors naming the file, section and key.
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <initializer_list>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace gmc::cfg {

/// One-line, user-facing configuration error.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Visitor that fills an options struct from one INI section.
/// Keys absent from the section keep the struct's default.
class SectionReader {
 public:
  SectionReader(const mrpt::config::CConfigFileBase& file, std::string section,
                std::string source_name = "");

  void operator()(const char* key, double& value, double lo, double hi, const char* doc = "");
  void operator()(const char* key, float& value, double lo, double hi, const char* doc = "");
  void operator()(const char* key, int& value, double lo, double hi, const char* doc = "");
  void operator()(const char* key, bool& value, const char* doc = "");
  void operator()(const char* key, std::string& value, const char* doc = "");
  /// String restricted to a set of choices.
  void choice(const char* key, std::string& value, std::initializer_list<const char*> allowed,
              const char* doc = "");

  /// Throws ConfigError when the section holds a key that no field claimed.
  void rejectUnknownKeys() const;

  const std::string& section() const { return section_; }

 private:
  bool raw(const char* key, std::string& text);
  [[noreturn]] void fail(const char* key, const std::string& what) const;

  const mrpt::config::CConfigFileBase& file_;
  std::string section_;
  std::string source_;
  std::set<std::string> known_;
};

/// Visitor that writes an options struct as one INI section, with doc comments.
class SectionWriter {
 public:
  SectionWriter(mrpt::config::CConfigFileBase& file, std::string section);

  void operator()(const char* key, const double& value, double lo, double hi, const char* doc = "");
  void operator()(const char* key, const float& value, double lo, double hi, const char* doc = "");
  void operator()(const char* key, const int& value, double lo, double hi, const char* doc = "");
  void operator()(const char* key, const bool& value, const char* doc = "");
  void operator()(const char* key, const std::string& value, const char* doc = "");
  void choice(const char* key, const std::string& value, std::initializer_list<const char*> allowed,
              const char* doc = "");

 private:
  mrpt::config::CConfigFileBase& file_;
  std::string section_;
};

/// Loads `options` from [section]: reads every field, rejects unknown keys, then
/// range-checks the whole struct. Throws ConfigError.
template <class Options>
void loadSection(const mrpt::config::CConfigFileBase& file, const std::string& section,
                 Options& options, const std::string& source_name = "") {
  SectionReader reader(file, section, source_name);
  options.visit(reader);
  reader.rejectUnknownKeys();
}

/// Writes `options` as [section].
template <class Options>
void saveSection(mrpt::config::CConfigFileBase& file, const std::string& section,
                 Options& options) {
  SectionWriter writer(file, section);
  options.visit(writer);
}

/// Reads an INI file into memory; throws ConfigError naming the file when it is
/// missing or unreadable.
mrpt::config::CConfigFileMemory loadIniFile(const std::string& path);

/// Applies "Section.key=value" overrides (the apps' --set option). Throws ConfigError
/// on a malformed override.
void applyOverrides(mrpt::config::CConfigFileMemory& file,
                    const std::vector<std::string>& overrides);

/// Sections of `file` that are not in `known` (for apps that own the whole file).
std::vector<std::string> unknownSections(const mrpt::config::CConfigFileBase& file,
                                         const std::set<std::string>& known);

}  // namespace gmc::cfg
