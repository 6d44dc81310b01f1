#pragma once
// The bodies of the fuzz targets, one per reader of user files. Each feeds arbitrary bytes to
// the reader and what it leads to before any work (the checks of a run); an InputError is the
// right answer to bad bytes, anything else (a crash, another exception, a sanitizer report,
// an exhausted memory or time) is a defect. The libFuzzer mains (fuzz_main.cpp) and the
// regression test that replays every input once found (tests/fuzz/test_fuzz_regressions.cpp)
// call the same functions.
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace aggpack::fuzz {

void scenario_reader(std::string_view bytes);
void grading_reader(std::string_view bytes);
void particle_file_reader(std::string_view bytes);
void calibration_reader(std::string_view bytes);
void checkpoint_reader(std::string_view bytes);
void material_reader(std::string_view bytes);
void shape_reader(std::string_view bytes);
void material_file_reader(std::string_view bytes);

}  // namespace aggpack::fuzz
