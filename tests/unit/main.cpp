// Catch2's main, compiled once into bpm_test_support for both test executables.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
