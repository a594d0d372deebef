#include "gmc/apps/app.h"

#include <exception>
#include <iostream>

namespace gmc::apps {

int runMain(App& app, const char* app_name, int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    app.initialize(args);
    return app.run();
  } catch (const AppError& e) {
    std::cerr << app_name << ": error: " << e.what() << "\n";
    return e.exitCode();
  } catch (const std::exception& e) {
    std::cerr << app_name << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace gmc::apps
