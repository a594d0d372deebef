#pragma once
// The main() of the bench/ diagnostic tools: bad arguments exit 2, any other error 1,
// each as one line on stderr naming the tool.
#include <cstdio>
#include <exception>
#include <stdexcept>

template <class Args>
int toolMain(const char* name, int argc, char** argv, Args (*parse)(int, char**), int (*run)(const Args&)) {
  try {
    return run(parse(argc, argv));
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
    return 1;
  }
}
