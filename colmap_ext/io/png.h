// Writing 8-bit PNG images (zlib deflate), for the rendered demo scenes (`madsfm render_scene`).
//
// In: width x height pixels of `channels` interleaved 8-bit samples, row-major, top row first (1 = grey,
// 2 = grey + alpha, 3 = RGB, 4 = RGBA). Out: a PNG byte stream (signature, IHDR, one IDAT, IEND; non-interlaced;
// each row filtered with the PNG filter among None/Sub/Up/Average/Paeth that minimises the sum of absolute
// residuals, the usual heuristic) or a file. Errors (bad arguments, zlib failure, unwritable file) throw
// std::runtime_error; the file variant names the path.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace madsfm {

std::vector<uint8_t> EncodePng(int width, int height, int channels, const uint8_t* pixels);

void WritePng(const std::string& path, int width, int height, int channels, const uint8_t* pixels);

}  // namespace madsfm
