#pragma once
#include <cstddef>
#include <string>

namespace aggpack {

// Appends `size` bytes to `out` compressed as VTK's XML files hold appended data with
// compressor="vtkZLibDataCompressor" and header_type="UInt64": the block header, then each
// block of 32 KiB one zlib stream (the .vtp's arrays, the specimen's .vti).
void append_vtk_zlib_blocks(std::string& out, const void* data, std::size_t size);

}  // namespace aggpack
