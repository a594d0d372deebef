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

void parseCommandLine(TCLAP::CmdLine& cmd, const std::string& program, const std::vector<std::string>& args,
                      const std::string& usage) {
  std::vector<std::string> argv;
  argv.reserve(args.size() + 1);
  argv.push_back(program);
  argv.insert(argv.end(), args.begin(), args.end());
  cmd.setExceptionHandling(false);
  try {
    cmd.parse(argv);
  } catch (const TCLAP::ArgException& e) {
    // TCLAP names the argument as "Argument: (--out)" and may end its text with a newline.
    std::string what = e.error();
    while (!what.empty() && (what.back() == '\n' || what.back() == ' ')) what.pop_back();
    std::string id = e.argId().rfind("Argument: ", 0) == 0 ? e.argId().substr(10) : "";
    if (id.size() > 2 && id.front() == '(' && id.back() == ')') id = id.substr(1, id.size() - 2);
    throw AppError((id.empty() ? "" : id + ": ") + what + "; " + usage, 2);
  }
}

}  // namespace gmc::apps
