// madsfm command-line entry point: dispatches `madsfm <command> [--options]` COLMAP-style.
#include <cstdio>
#include <cstdlib>
#include <cstring>

int main(int argc, char** argv) {
  std::fprintf(stderr, "madsfm: no commands yet\n");
  return EXIT_FAILURE;
}
