#include "gmc/apps/command_line.h"

namespace gmc::apps {

CommandLine::CommandLine(std::string app_name, std::string usage)
    : app_name_(std::move(app_name)),
      usage_(std::move(usage)),
      cmd_(usage_, ' ', "", /*helpAndVersion=*/false),
      help_("h", "help", "print the usage and stop", cmd_, false) {
  cmd_.setExceptionHandling(false);
}

void CommandLine::parse(const std::vector<std::string>& args) {
  std::vector<std::string> argv{app_name_};
  argv.insert(argv.end(), args.begin(), args.end());
  try {
    cmd_.parse(argv);
  } catch (const TCLAP::ArgException& e) {
    fail(e.error() + (e.argId().empty() || e.argId() == " " ? "" : " (" + e.argId() + ")"));
  }
  if (help_.getValue()) throw AppError(usage_, 2);
}

void CommandLine::fail(const std::string& what) const { throw AppError(what + "\n" + usage_, 2); }

}  // namespace gmc::apps
