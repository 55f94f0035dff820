// Every test program starts as the command does: occsweep's own methods registered (docs/methods.md).
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "occsweep/methods/builtin_methods.hpp"

int main(int argc, char** argv) {
  occsweep::registerBuiltinMethods();
  return Catch::Session().run(argc, argv);
}
