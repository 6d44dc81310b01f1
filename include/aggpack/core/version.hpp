#pragma once

namespace aggpack {
// The build's name: the release and the commit it was built from (cmake/aggpack_version.cmake
// writes it into the build's version.cpp at every build), "0.1.0+git.<commit>[.dirty]". Every
// output, checkpoint and cache records it; a cache is never reused by another build. Defined in
// one generated file, so that a new commit recompiles that file alone.
extern const char* const kVersion;
}  // namespace aggpack
