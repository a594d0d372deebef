#include "gmc/apps/command_line.h"

namespace gmc::apps {

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
