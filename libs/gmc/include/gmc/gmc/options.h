#pragma once
// Option structs across GMC-RGBD describe their fields once, through a visitor:
//
//   template <class Visitor> void visit(Visitor& v) {
//     v("grid_cols", grid_cols, 1, 1000, "cells across the image");
//   }
//
// The same description validates values here (no I/O), and loads/saves INI sections
// in libs/config (gmc::cfg::SectionReader / SectionWriter), so every tunable has one
// key name, one range and one doc string.
#include <sstream>
#include <string>
#include <initializer_list>
#include <type_traits>

namespace gmc {

/// Visitor that records the first field outside its [lo, hi] range.
class RangeValidator {
 public:
  explicit RangeValidator(std::string section = "") : section_(std::move(section)) {}

  template <class T, class L, class H>
  void operator()(const char* key, const T& value, L lo, H hi, const char* /*doc*/ = "") {
    static_assert(std::is_arithmetic_v<T>, "ranged fields must be numbers");
    if (!error_.empty()) return;
    if (!(value >= static_cast<T>(lo) && value <= static_cast<T>(hi))) {
      std::ostringstream os;
      os << keyName(key) << " = " << value << " is out of range [" << lo << ", " << hi << "]";
      error_ = os.str();
    }
  }
  // Fields without a range (bool, string, enums by name) are always valid here.
  template <class T>
  void operator()(const char* /*key*/, const T& /*value*/, const char* /*doc*/ = "") {}

  /// A string restricted to a set of choices.
  void choice(const char* key, const std::string& value,
              std::initializer_list<const char*> allowed, const char* /*doc*/ = "") {
    if (!error_.empty()) return;
    for (const char* a : allowed)
      if (value == a) return;
    error_ = keyName(key) + " = '" + value + "' is not one of the allowed values";
  }

  /// Empty when every field is in range, else a message naming the key.
  const std::string& error() const { return error_; }

 private:
  std::string keyName(const char* key) const {
    return section_.empty() ? std::string(key) : "[" + section_ + "] " + key;
  }
  std::string section_;
  std::string error_;
};

/// Returns "" when all fields of `options` are in range, else a message naming the key.
template <class Options>
std::string validateOptions(Options& options, const std::string& section = "") {
  RangeValidator v(section);
  options.visit(v);
  return v.error();
}

}  // namespace gmc
