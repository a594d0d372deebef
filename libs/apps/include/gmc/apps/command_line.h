#pragma once
// Command lines through TCLAP (libtclap-dev): each app declares its arguments on a
// `TCLAP::CmdLine cmd(description, ' ', "", false)` (no --help/--version: the documented
// options are the whole interface) and calls parseCommandLine(), which turns TCLAP's
// errors into one-line usage errors (AppError, exit code 2).
#include <tclap/CmdLine.h>

#include <string>
#include <vector>

#include "gmc/apps/app.h"

namespace gmc::apps {

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
