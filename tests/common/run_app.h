#pragma once
// Runs an app class in-process exactly as its main() would, returning the exit code.
#include <string>
#include <vector>

#include "gmc/apps/app.h"

namespace gmc::testdata {

template <class AppT>
int runApp(const char* name, std::vector<std::string> args) {
  args.insert(args.begin(), name);
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  AppT app;
  return gmc::apps::runMain(app, name, static_cast<int>(argv.size()), argv.data());
}

}  // namespace gmc::testdata
