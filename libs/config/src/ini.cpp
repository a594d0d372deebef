#include "gmc/config/ini.h"

#include <mrpt/config/CConfigFile.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace gmc::cfg {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

/// A comment ('#', ';' or '//') starts at the beginning of the value or after whitespace,
/// as in MRPT; inside a value (`/data/run#2/gt.txt`, `http://...`) it is part of the value.
std::string stripComment(const std::string& text) {
  for (size_t pos = 0; pos < text.size(); ++pos) {
    const bool marker = text[pos] == '#' || text[pos] == ';' || text.compare(pos, 2, "//") == 0;
    if (marker && (pos == 0 || std::isspace(static_cast<unsigned char>(text[pos - 1]))))
      return trim(text.substr(0, pos));
  }
  return text;
}

std::string formatNumber(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

}  // namespace

SectionReader::SectionReader(const mrpt::config::CConfigFileBase& file, std::string section,
                             std::string source_name)
    : file_(file), section_(std::move(section)), source_(std::move(source_name)) {}

void SectionReader::fail(const char* key, const std::string& what) const {
  std::string where = source_.empty() ? "" : source_ + ": ";
  throw ConfigError(where + "[" + section_ + "] " + key + ": " + what);
}

bool SectionReader::raw(const char* key, std::string& text) {
  known_.insert(key);
  if (!file_.keyExists(section_, key)) return false;
  text = stripComment(trim(file_.read_string(section_, key, "", false)));
  return true;
}

void SectionReader::operator()(const char* key, double& value, double lo, double hi,
                               const char*) {
  std::string text;
  if (!raw(key, text)) return;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    fail(key, "'" + text + "' is not a number");
  if (v < lo || v > hi)
    fail(key, text + " is out of range [" + formatNumber(lo) + ", " + formatNumber(hi) + "]");
  value = v;
}

void SectionReader::operator()(const char* key, float& value, double lo, double hi,
                               const char* doc) {
  double v = value;
  (*this)(key, v, lo, hi, doc);
  value = static_cast<float>(v);
}

void SectionReader::operator()(const char* key, int& value, double lo, double hi, const char*) {
  std::string text;
  if (!raw(key, text)) return;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end == text.c_str() || *end != '\0' || errno == ERANGE)
    fail(key, "'" + text + "' is not an integer");
  if (v < lo || v > hi)
    fail(key, text + " is out of range [" + formatNumber(lo) + ", " + formatNumber(hi) + "]");
  value = static_cast<int>(v);
}

void SectionReader::operator()(const char* key, bool& value, const char*) {
  std::string text;
  if (!raw(key, text)) return;
  if (text == "true" || text == "1" || text == "yes" || text == "on") {
    value = true;
  } else if (text == "false" || text == "0" || text == "no" || text == "off") {
    value = false;
  } else {
    fail(key, "'" + text + "' is not a boolean (true/false)");
  }
}

void SectionReader::operator()(const char* key, std::string& value, const char*) {
  std::string text;
  if (raw(key, text)) value = text;
}

void SectionReader::choice(const char* key, std::string& value,
                           std::initializer_list<const char*> allowed, const char*) {
  std::string text;
  if (!raw(key, text)) return;
  std::string list;
  for (const char* a : allowed) {
    if (text == a) {
      value = text;
      return;
    }
    list += (list.empty() ? "" : ", ") + std::string(a);
  }
  fail(key, "'" + text + "' is not one of: " + list);
}

void SectionReader::rejectUnknownKeys() const {
  std::vector<std::string> keys;
  file_.getAllKeys(section_, keys);
  for (const auto& k : keys) {
    if (!known_.count(k)) {
      std::string where = source_.empty() ? "" : source_ + ": ";
      throw ConfigError(where + "[" + section_ + "] " + k + ": unknown key");
    }
  }
}

SectionWriter::SectionWriter(mrpt::config::CConfigFileBase& file, std::string section)
    : file_(file), section_(std::move(section)) {}

void SectionWriter::operator()(const char* key, const double& value, double, double,
                               const char* doc) {
  file_.write(section_, key, formatNumber(value), 0, 0, doc);
}
void SectionWriter::operator()(const char* key, const float& value, double lo, double hi,
                               const char* doc) {
  (*this)(key, static_cast<double>(value), lo, hi, doc);
}
void SectionWriter::operator()(const char* key, const int& value, double, double,
                               const char* doc) {
  file_.write(section_, key, std::to_string(value), 0, 0, doc);
}
void SectionWriter::operator()(const char* key, const bool& value, const char* doc) {
  file_.write(section_, key, std::string(value ? "true" : "false"), 0, 0, doc);
}
void SectionWriter::operator()(const char* key, const std::string& value, const char* doc) {
  file_.write(section_, key, value, 0, 0, doc);
}
void SectionWriter::choice(const char* key, const std::string& value,
                           std::initializer_list<const char*>, const char* doc) {
  file_.write(section_, key, value, 0, 0, doc);
}

mrpt::config::CConfigFileMemory loadIniFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open INI file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw ConfigError(path + ": read error");
  // MRPT's parser expands @define, ${...}, $env{...} and $eval{...} and throws
  // std::runtime_error on a malformed one: report it as ours, naming the file.
  try {
    return mrpt::config::CConfigFileMemory(buffer.str());
  } catch (const std::exception& e) {
    const std::string what = e.what();
    throw ConfigError(path + ": " + trim(what.substr(0, what.find('\n'))));
  }
}

void applyOverrides(mrpt::config::CConfigFileMemory& file,
                    const std::vector<std::string>& overrides) {
  for (const auto& o : overrides) {
    const auto eq = o.find('=');
    const auto dot = o.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 >= eq)
      throw ConfigError("--set " + o + ": expected Section.key=value");
    const std::string section = trim(o.substr(0, dot));
    const std::string key = trim(o.substr(dot + 1, eq - dot - 1));
    file.write(section, key, trim(o.substr(eq + 1)));
  }
}

std::vector<std::string> unknownSections(const mrpt::config::CConfigFileBase& file,
                                         const std::set<std::string>& known) {
  std::vector<std::string> sections, unknown;
  file.getAllSections(sections);
  for (const auto& s : sections)
    if (!s.empty() && !known.count(s)) unknown.push_back(s);
  return unknown;
}

}  // namespace gmc::cfg
