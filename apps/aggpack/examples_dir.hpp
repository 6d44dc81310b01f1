#pragma once
#include <filesystem>

// The folder of the shipped scenarios and the paper's tables that `aggpack reproduce` reads
// unless given --examples: the checkout's examples/ for the binary of the build tree that
// compiled it, else share/aggpack/examples beside the running binary (an install moved to
// another prefix still finds its own). `argv0` is used only where /proc/self/exe is missing;
// empty when the binary's own path cannot be told.
std::filesystem::path default_examples_dir(const char* argv0);
