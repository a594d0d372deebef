#include "gmc/apps/app.h"

#include <malloc.h>

#include <exception>
#include <iostream>

namespace gmc::apps {

void tuneAllocator() {
  // Image-sized buffers (0.3-1.2 MB) are above glibc's mmap threshold, so every frame
  // would map and unmap them; page faults are expensive on virtual machines (measured
  // here: GFTT on a 640x480 frame 20 ms with per-frame mmap, 2.2 ms without). Keep
  // them on the heap instead. See doc/performance.md.
  mallopt(M_MMAP_THRESHOLD, 256 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
}

int runMain(App& app, const char* app_name, int argc, char** argv) {
  tuneAllocator();
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
