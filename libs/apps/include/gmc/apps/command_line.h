#pragma once
// TCLAP for the apps' command lines: errors become AppError (exit code 2) with the usage.
#include <tclap/CmdLine.h>

#include <string>
#include <vector>

#include "gmc/apps/app.h"

namespace gmc::apps {

/// A command line whose errors throw instead of exiting; `-h/--help` is added and, when
/// given, parseCommandLine() throws AppError(usage, 2).
class CommandLine {
 public:
  CommandLine(std::string app_name, std::string usage);
  TCLAP::CmdLine& cmd() { return cmd_; }
  /// Parses `args` (without the program name). Throws AppError (exit code 2) naming the
  /// bad argument, followed by the usage line.
  void parse(const std::vector<std::string>& args);
  /// AppError(what + usage, 2), for checks TCLAP does not make.
  [[noreturn]] void fail(const std::string& what) const;
  const std::string& usage() const { return usage_; }

 private:
  std::string app_name_, usage_;
  TCLAP::CmdLine cmd_;
  TCLAP::SwitchArg help_;
};

}  // namespace gmc::apps
