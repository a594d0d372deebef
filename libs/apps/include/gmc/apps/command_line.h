#pragma once
// TCLAP for the apps' command lines: errors become AppError (exit code 2) with the usage.
// Two forms: the CommandLine class (usage on its own line, -h/--help) and
// parseCommandLine() on a TCLAP::CmdLine (one line, no --help).
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

/// Parses `args` (without the program name). Throws AppError (exit code 2) naming the
/// argument and ending with `usage`, on one line.
void parseCommandLine(TCLAP::CmdLine& cmd, const std::string& program, const std::vector<std::string>& args,
                      const std::string& usage);

/// --camera PRESET|fx,fy,cx,cy, shared by the apps that read TUM folders
/// (datasets::cameraPreset() checks the value).
class CameraArg : public TCLAP::ValueArg<std::string> {
 public:
  CameraArg(TCLAP::CmdLine& cmd, const std::string& default_preset)
      : TCLAP::ValueArg<std::string>("", "camera", "intrinsics preset or fx,fy,cx,cy", false, default_preset,
                                     "fr1|fr2|fr3|bonn|fx,fy,cx,cy", cmd) {}
};

}  // namespace gmc::apps
