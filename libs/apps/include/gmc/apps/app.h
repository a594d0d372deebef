#pragma once
// Every app is a class: initialize() parses arguments and loads inputs, run() does the
// work. main() is `return gmc::apps::runApp<MyApp>(argc, argv);`, and tests drive the
// same classes in-process.
#include <stdexcept>
#include <string>
#include <vector>

namespace gmc::apps {

/// A user-facing error: printed as one line, exit code 1 (2 for usage errors).
class AppError : public std::runtime_error {
 public:
  explicit AppError(const std::string& what, int exit_code = 1)
      : std::runtime_error(what), exit_code_(exit_code) {}
  int exitCode() const { return exit_code_; }

 private:
  int exit_code_;
};

class App {
 public:
  virtual ~App() = default;
  /// Parses the command line; throws AppError (exit code 2) on usage errors.
  virtual void initialize(const std::vector<std::string>& args) = 0;
  /// Runs; returns the process exit code. Throws AppError on failure.
  virtual int run() = 0;
};

/// Keeps image-sized allocations off mmap (expensive page faults); called by runMain().
void tuneAllocator();

/// Runs an app from main(): "<app>: error: <message>" on stderr and a non-zero exit
/// code for any exception.
int runMain(App& app, const char* app_name, int argc, char** argv);

template <class AppT>
int runApp(const char* app_name, int argc, char** argv) {
  AppT app;
  return runMain(app, app_name, argc, argv);
}

}  // namespace gmc::apps
